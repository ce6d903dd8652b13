//! The layout rules the code keeps (docs/ARCHITECTURE.md): the portable core has no OS in its
//! dependencies, no function outside tests is longer than 120 lines, and G/M/@ numbers live
//! in the dialect tables only.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The crates' sources: (path, text), test modules cut off.
fn sources(dirs: &[&str]) -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    let mut todo: Vec<PathBuf> = dirs.iter().map(|d| root().join(d)).collect();
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                todo.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                let code = match text.find("#[cfg(test)]\nmod tests") {
                    Some(i) => text[..i].to_string(),
                    None => text,
                };
                out.push((p, code));
            }
        }
    }
    out.sort();
    out
}

const CODE: &[&str] = &[
    "kernel/src",
    "runtime/src",
    "protocol/src",
    "plc-sim/src",
    "hmi-bridge/src",
    "opcua-server/src",
    "src",
];

/// `cargo tree` of the core's normal dependencies: no libc, no iceoryx2, no signal handling,
/// nothing of the runtime (proptest and criterion, test tools, bring libc as dev-dependencies
/// only).
#[test]
fn the_core_has_no_os_in_its_dependencies() {
    let out = std::process::Command::new(env!("CARGO"))
        .current_dir(root())
        .args([
            "tree",
            "-p",
            "nc-kernel",
            "-e",
            "normal",
            "--prefix",
            "none",
        ])
        .output()
        .expect("cargo tree");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let tree = String::from_utf8_lossy(&out.stdout);
    for name in [
        "libc ",
        "iceoryx2",
        "ctrlc",
        "nix ",
        "softnc-protocol",
        "nc-runtime",
        "hdrhistogram",
    ] {
        assert!(
            !tree.lines().any(|l| l.starts_with(name)),
            "nc-kernel depends on {name}:\n{tree}"
        );
    }
}

/// Function lengths, counted as the before-stop hook counts them: from the `fn` line to its
/// closing brace.
fn long_functions(path: &Path, text: &str, limit: usize) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let t = lines[i].trim_start();
        let is_fn = [
            "fn ",
            "pub fn ",
            "pub(crate) fn ",
            "const fn ",
            "pub const fn ",
        ]
        .iter()
        .any(|p| t.starts_with(p))
            || t.starts_with("unsafe fn ")
            || t.starts_with("pub unsafe fn ");
        if !is_fn {
            i += 1;
            continue;
        }
        let (mut depth, mut opened, mut j) = (0i64, false, i);
        while j < lines.len() {
            let code = strip(lines[j]);
            if !opened && code.contains(';') && !code.contains('{') {
                break;
            }
            depth += code.matches('{').count() as i64 - code.matches('}').count() as i64;
            opened |= code.contains('{');
            if opened && depth <= 0 {
                break;
            }
            j += 1;
        }
        if opened && j - i + 1 > limit {
            out.push(format!(
                "{}:{} ({} lines)",
                path.display(),
                i + 1,
                j - i + 1
            ));
        }
        i = if opened { j + 1 } else { i + 1 };
    }
    out
}

/// A line without its comment and string contents.
fn strip(line: &str) -> String {
    let code = line.split("//").next().unwrap_or("");
    let mut out = String::new();
    let mut in_str = false;
    let mut esc = false;
    for c in code.chars() {
        match (in_str, esc, c) {
            (true, true, _) => esc = false,
            (true, false, '\\') => esc = true,
            (true, false, '"') => in_str = false,
            (true, false, _) => {}
            (false, _, '"') => in_str = true,
            (false, _, c) => out.push(c),
        }
    }
    out
}

#[test]
fn no_function_is_longer_than_120_lines() {
    let long: Vec<String> = sources(CODE)
        .iter()
        .flat_map(|(p, t)| long_functions(p.strip_prefix(root()).unwrap(), t, 120))
        .collect();
    assert!(long.is_empty(), "split these:\n{}", long.join("\n"));
}

/// Outside the dialect tables no code names a G, M or @ number: in the front end, preparation
/// and the CLI's picture a word like `G4`, `M30` or `@714` in code (comments aside) would be a
/// rule that belongs to a dialect. Not rules: the program text the synthetic benchmark
/// programs are written in, and the machine data keys that name the settable zero offsets
/// by their codes (docs/machine-data.md).
#[test]
fn g_m_and_at_numbers_live_in_the_dialect_tables() {
    let mut found = Vec::new();
    for (p, text) in sources(CODE) {
        let dialect = p.components().any(|c| c.as_os_str() == "dialect");
        if dialect || p.ends_with("synthetic.rs") {
            continue;
        }
        for (n, line) in text.lines().enumerate() {
            let t = line.trim_start();
            if t.starts_with("//") || t.starts_with("#[serde(rename") {
                continue;
            }
            let code = line.split("//").next().unwrap_or("");
            for word in code.split(|c: char| !(c.is_ascii_alphanumeric() || c == '@')) {
                let mut ch = word.chars();
                let lead = ch.next();
                let rest: String = ch.collect();
                if matches!(lead, Some('G' | 'M' | '@'))
                    && !rest.is_empty()
                    && rest.chars().all(|c| c.is_ascii_digit())
                {
                    found.push(format!(
                        "{}:{}: {}",
                        p.strip_prefix(root()).unwrap().display(),
                        n + 1,
                        line.trim()
                    ));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "G/M/@ numbers outside dialect/:\n{}",
        found.join("\n")
    );
}
