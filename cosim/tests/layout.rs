//! include/softnc_cosim.h against the Rust types: a C program compiled with `cc` prints each
//! struct's size and alignment and each field's offset and size as the C compiler lays them
//! out; they must equal Rust's `#[repr(C)]` layout, and the offsets and sizes written in the
//! header's comments must be the real ones.

use softnc_cosim::{SoftncCosimInfo, SoftncCosimSetpoint, SoftncCosimStatus};
use std::mem::{align_of, offset_of, size_of};
use std::path::PathBuf;
use std::process::Command;

fn field_size<T, F>(_: fn(&T) -> &F) -> usize {
    size_of::<F>()
}

/// `(C struct, Rust size, Rust align, [(field, offset, size)])`.
type Layout = (
    &'static str,
    usize,
    usize,
    Vec<(&'static str, usize, usize)>,
);

macro_rules! layout {
    ($c:literal, $t:ident: $($f:ident),* $(,)?) => {
        ($c, size_of::<$t>(), align_of::<$t>(), vec![$((
            stringify!($f),
            offset_of!($t, $f),
            field_size(|p: &$t| &p.$f),
        )),*])
    };
}

fn layouts() -> Vec<Layout> {
    vec![
        layout!("softnc_cosim_setpoint", SoftncCosimSetpoint: cycle, time_us, pos, spindle, v_path,
            line, col, block_number, block_digits, state, events, _pad),
        layout!("softnc_cosim_status", SoftncCosimStatus: cycle, aux, override_, line, col, alarm,
            alarm_line, alarm_col, acks_due, state, waits_for_start, single_block, operator_, plc,
            over, _pad),
        layout!("softnc_cosim_info", SoftncCosimInfo: cycle_us, columns, column, _pad),
    ]
}

fn header() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("include/softnc_cosim.h")
}

/// A C program printing `struct size align` and `struct.field offset size` lines.
fn c_program(ls: &[Layout]) -> String {
    let mut c = String::from(
        "#include <stddef.h>\n#include <stdio.h>\n#include \"softnc_cosim.h\"\nint main(void) {\n",
    );
    for (s, _, _, fields) in ls {
        c +=
            &format!("    printf(\"{s} %zu %zu\\n\", sizeof(struct {s}), _Alignof(struct {s}));\n");
        for (f, _, _) in fields {
            c += &format!(
                "    printf(\"{s}.{f} %zu %zu\\n\", offsetof(struct {s}, {f}), sizeof(((struct {s} *)0)->{f}));\n"
            );
        }
    }
    c + "    return 0;\n}\n"
}

fn rust_lines(ls: &[Layout]) -> Vec<String> {
    let mut out = Vec::new();
    for (s, size, align, fields) in ls {
        out.push(format!("{s} {size} {align}"));
        for (f, off, sz) in fields {
            out.push(format!("{s}.{f} {off} {sz}"));
        }
    }
    out
}

#[test]
fn c_header_lays_out_the_structs_as_rust_does() {
    let ls = layouts();
    let dir = std::env::temp_dir().join(format!("softnc-cosim-layout-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("layout.c");
    std::fs::write(&src, c_program(&ls)).unwrap();
    let exe = dir.join("layout");
    let cc = Command::new("cc")
        .args(["-std=c11", "-Wall", "-Werror", "-I"])
        .arg(header().parent().unwrap())
        .arg(&src)
        .arg("-o")
        .arg(&exe)
        .output()
        .expect("cc");
    assert!(
        cc.status.success(),
        "{}",
        String::from_utf8_lossy(&cc.stderr)
    );
    let out = Command::new(&exe).output().unwrap();
    let c = String::from_utf8(out.stdout).unwrap();
    let c: Vec<&str> = c.lines().collect();
    assert_eq!(c, rust_lines(&ls));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn header_comments_give_the_real_offsets_and_sizes() {
    let text = std::fs::read_to_string(header()).unwrap();
    for (s, size, align, fields) in layouts() {
        let body = text
            .split(&format!("struct {s} {{"))
            .nth(1)
            .unwrap_or_else(|| panic!("struct {s} in the header"));
        let body = &body[..body.find("};").unwrap()];
        let end = &text[text.find(body).unwrap() + body.len()..];
        assert!(
            end.starts_with(&format!("}}; /* size {size}, align {align} */")),
            "{s}: size {size}, align {align}"
        );
        let lines: Vec<&str> = body.lines().filter(|l| l.contains("/*")).collect();
        assert_eq!(lines.len(), fields.len(), "{s}: one line per field");
        for ((f, off, _), line) in fields.iter().zip(lines) {
            let decl = line.split(';').next().unwrap();
            let name = decl.split_whitespace().last().unwrap();
            let name = name.split('[').next().unwrap();
            assert_eq!(name, *f, "{s}: field order");
            let comment = line.split("/*").nth(1).unwrap().trim_start();
            let at: usize = comment
                .split(':')
                .next()
                .unwrap()
                .trim()
                .trim_end_matches("*/")
                .trim()
                .parse()
                .unwrap();
            assert_eq!(at, *off, "{s}.{f}: offset in the comment");
        }
    }
}

/// docs/interfaces.md's C blocks of the co-simulation: the struct definitions verbatim from
/// the header, the example compiling against it.
#[test]
fn the_doc_shows_the_header_and_an_example_that_compiles() {
    let doc_path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/interfaces.md");
    let doc = std::fs::read_to_string(doc_path).unwrap();
    let text = std::fs::read_to_string(header()).unwrap();
    let blocks: Vec<&str> = doc
        .split("```c\n")
        .skip(1)
        .filter_map(|b| b.split_once("\n```").map(|(code, _)| code))
        .filter(|b| b.contains("softnc_cosim"))
        .collect();
    let (defs, examples): (Vec<&str>, Vec<&str>) =
        blocks.into_iter().partition(|b| b.contains("}; /* size"));
    assert!(!defs.is_empty() && !examples.is_empty());
    for d in defs {
        assert!(text.contains(d), "not in the header:\n{d}");
    }
    let dir = std::env::temp_dir().join(format!("softnc-cosim-doc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (i, e) in examples.iter().enumerate() {
        let src = dir.join(format!("example{i}.c"));
        std::fs::write(&src, e).unwrap();
        let cc = Command::new("cc")
            .args(["-std=c11", "-Wall", "-Werror", "-fsyntax-only", "-I"])
            .arg(header().parent().unwrap())
            .arg(&src)
            .output()
            .expect("cc");
        assert!(
            cc.status.success(),
            "{e}\n{}",
            String::from_utf8_lossy(&cc.stderr)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
