//! The payloads' layout against the definitions for other languages: the C header, the
//! Python module and docs/interfaces.md are read as text and every struct, offset, size,
//! type name and constant in them compared with the Rust types.

use super::*;
use crate::services::PROTOCOL_VERSION;

const HEADER: &str = include_str!("../../clients/c/softnc_ipc.h");
const PYTHON: &str = include_str!("../../clients/python/softnc_ipc.py");
const DOC: &str = include_str!("../../docs/interfaces.md");

/// A struct as a C or Python definition writes it: each field's name, offset (from its
/// comment) and size (from its type).
#[derive(Debug, Default)]
struct Written {
    name: String,
    type_name: String,
    fields: Vec<(String, usize, usize)>,
    size: usize,
    align: usize,
}

fn rust(name: &str) -> Option<PayloadLayout> {
    payloads().into_iter().find(|p| p.rust == name)
}

/// An array length: a number or one of [`LENGTHS`] (in C with its `SOFTNC_` prefix).
fn length(s: &str) -> usize {
    let s = s.trim().trim_start_matches("SOFTNC_");
    s.parse()
        .ok()
        .or_else(|| LENGTHS.iter().find(|(n, _)| *n == s).map(|(_, v)| *v))
        .unwrap_or_else(|| panic!("unknown length {s}"))
}

/// The size of a scalar type or of a nested payload, by the name either language gives it.
fn type_size(t: &str) -> usize {
    let t = t.trim().trim_start_matches("struct softnc_");
    let t = t.trim_start_matches("ctypes.c_");
    match t {
        "uint8_t" | "uint8" => 1,
        "uint16_t" | "uint16" => 2,
        "uint32_t" | "uint32" => 4,
        "uint64_t" | "uint64" | "double" => 8,
        other => rust(other).map_or_else(|| panic!("unknown type {other}"), |p| p.size),
    }
}

/// The number a comment starts with (`/*  40: mm … */`, `# 40: mm …`).
fn leading_number(comment: &str) -> usize {
    let digits: String = comment
        .trim()
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits
        .parse()
        .unwrap_or_else(|_| panic!("no offset in {comment:?}"))
}

/// `uint8_t names[SOFTNC_MAX_AXES]; /*    0: … */` → (name, offset, size).
fn c_field(line: &str) -> (String, usize, usize) {
    let (decl, comment) = line.split_once(';').expect("a declaration");
    let comment = comment.trim().trim_start_matches("/*");
    let (ty, name) = decl.trim().rsplit_once(' ').expect("type and name");
    let (name, count) = match name.split_once('[') {
        Some((n, len)) => (n, length(len.trim_end_matches(']'))),
        None => (name, 1),
    };
    (
        name.to_string(),
        leading_number(comment),
        type_size(ty) * count,
    )
}

fn c_structs(text: &str) -> Vec<Written> {
    let mut out = Vec::new();
    let mut cur = Written::default();
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("/* softnc::") {
            cur.type_name = format!("softnc::{}", rest.split(':').next().unwrap_or(""));
        } else if let Some(rest) = line.strip_prefix("struct softnc_") {
            cur.name = rest.trim_end_matches(" {").to_string();
        } else if let Some(rest) = line.strip_prefix("}; /* size ") {
            let (size, align) = rest.trim_end_matches(" */").split_once(", align ").unwrap();
            cur.size = size.parse().unwrap();
            cur.align = align.parse().unwrap();
            out.push(std::mem::take(&mut cur));
        } else if !cur.name.is_empty() && line.starts_with("    ") {
            cur.fields.push(c_field(line));
        }
    }
    out
}

/// `("pos", ctypes.c_double * MAX_AXES),  # 40: …` → (name, offset, size).
fn py_field(line: &str) -> (String, usize, usize) {
    let (decl, comment) = line.split_once("),  #").expect("a field with its offset");
    let (name, ty) = decl
        .trim()
        .trim_start_matches('(')
        .split_once(", ")
        .unwrap();
    let (ty, count) = match ty.split_once(" * ") {
        Some((t, n)) => (t, length(n)),
        None => (ty, 1),
    };
    let name = name.trim_matches('"').to_string();
    (name, leading_number(comment), type_size(ty) * count)
}

fn py_classes(text: &str) -> Vec<Written> {
    let mut out = Vec::new();
    let mut cur = Written::default();
    for line in text.lines() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("class ") {
            cur.name = rest.trim_end_matches("(ctypes.Structure):").to_string();
        } else if let Some(i) = t.find("Size ").filter(|_| t.starts_with("\"\"\"softnc::")) {
            let (size, align) = t[i + 5..]
                .trim_end_matches(".\"\"\"")
                .split_once(", align ")
                .unwrap();
            cur.size = size.parse().unwrap();
            cur.align = align.parse().unwrap();
        } else if t.starts_with("(\"") {
            cur.fields.push(py_field(t));
        } else if let Some(rest) = t.strip_prefix("return \"softnc::") {
            cur.type_name = format!("softnc::{}", rest.trim_end_matches('"'));
            out.push(std::mem::take(&mut cur));
        }
    }
    out
}

/// Every payload written once in `written`, exactly as Rust lays it out.
fn check(language: &str, written: &[Written]) {
    let all = payloads();
    assert_eq!(
        written.len(),
        all.len(),
        "{language}: one definition per payload"
    );
    for p in &all {
        let w = written
            .iter()
            .find(|w| w.name == p.rust)
            .unwrap_or_else(|| panic!("{language}: {} is missing", p.rust));
        let fields: Vec<(String, usize, usize)> = p
            .fields
            .iter()
            .map(|f| (f.name.to_string(), f.offset, f.size))
            .collect();
        assert_eq!(w.fields, fields, "{language}: {}", p.rust);
        assert_eq!(
            (w.size, w.align),
            (p.size, p.align),
            "{language}: {}",
            p.rust
        );
        assert_eq!(w.type_name, p.type_name, "{language}: {}", p.rust);
    }
}

#[test]
fn every_payload_is_listed_field_by_field_without_hidden_padding() {
    let all = payloads();
    let names: Vec<&str> = all.iter().map(|p| p.rust).collect();
    let abi: Vec<&str> = layouts().iter().map(|l| l.0).collect();
    assert_eq!(names, abi, "the same payloads as the ABI string");
    for p in &all {
        assert_eq!(p.type_name, format!("softnc::{}", p.rust));
        let mut at = 0;
        for f in &p.fields {
            assert_eq!(
                f.offset, at,
                "{}.{}: a field left out, or padding",
                p.rust, f.name
            );
            at += f.size;
        }
        assert_eq!(at, p.size, "{}: the fields fill it", p.rust);
    }
}

/// The sizes docs/interfaces.md gives in its table.
#[test]
fn sizes_are_the_documented_ones() {
    for p in payloads() {
        let row = format!("| `{}` | {} | {} |", p.type_name, p.size, p.align);
        assert!(DOC.contains(&row), "docs/interfaces.md: {row}");
    }
}

#[test]
fn the_c_header_lays_out_every_payload_as_rust_does() {
    check("clients/c/softnc_ipc.h", &c_structs(HEADER));
    for (name, value) in LENGTHS {
        assert!(
            HEADER.contains(&format!("#define SOFTNC_{name} {value}\n")),
            "{name}"
        );
    }
    assert!(HEADER.contains(&format!("#define SOFTNC_ABI \"{}\"\n", crate::abi())));
    let version = format!("#define SOFTNC_PROTOCOL_VERSION {PROTOCOL_VERSION}\n");
    assert!(HEADER.contains(&version));
}

#[test]
fn the_python_classes_lay_out_every_payload_as_rust_does() {
    check("clients/python/softnc_ipc.py", &py_classes(PYTHON));
    for (name, value) in LENGTHS {
        assert!(PYTHON.contains(&format!("\n{name} = {value}\n")), "{name}");
    }
    assert!(PYTHON.contains(&format!("\nABI = \"{}\"\n", crate::abi())));
    assert!(PYTHON.contains(&format!("\nPROTOCOL_VERSION = {PROTOCOL_VERSION}\n")));
}

/// docs/interfaces.md's C and Python definitions are the files' own text, one of each per
/// payload, and it names this build's ABI.
#[test]
fn the_doc_shows_the_files_definitions() {
    let blocks = |lang: &str| -> Vec<&str> {
        let fence = format!("```{lang}\n");
        DOC.split(fence.as_str())
            .skip(1)
            .filter_map(|b| b.split_once("\n```").map(|(code, _)| code))
            .collect()
    };
    let c: Vec<&str> = blocks("c")
        .into_iter()
        // The co-simulation's structs are cosim/include/softnc_cosim.h's (cosim/tests/layout.rs).
        .filter(|b| b.contains("struct softnc_") && !b.contains("softnc_cosim"))
        .collect();
    let py: Vec<&str> = blocks("python")
        .into_iter()
        .filter(|b| b.contains("(ctypes.Structure)"))
        .collect();
    for b in &c {
        assert!(HEADER.contains(b), "not in the header:\n{b}");
    }
    for b in &py {
        assert!(PYTHON.contains(b), "not in the Python module:\n{b}");
    }
    check("docs/interfaces.md (C)", &c_structs(&c.join("\n")));
    check("docs/interfaces.md (Python)", &py_classes(&py.join("\n")));
    assert!(
        DOC.contains(&crate::abi()),
        "docs/interfaces.md names {}",
        crate::abi()
    );
}
