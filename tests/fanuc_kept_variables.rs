//! Kept macro variables (#500 … #999, docs/fanuc.md): `softnc run --macro-variables FILE`
//! starts the program with the file's values and saves what it leaves there, so a part
//! counter counts across runs; the kernel's second preparation (the whole-program checker)
//! does not count twice; `softnc check` reads the file and writes nothing.

#[path = "support/control.rs"]
mod control;

use control::*;
use std::path::Path;

fn run_once(prog: &Path, kept: &Path, tag: &str) {
    let inst = instance(tag);
    let _scope = Scope::new(&inst);
    let out = std::process::Command::new(EXE)
        .arg("run")
        .arg(prog)
        .args(["--quiet", "--instance", &inst, "--machine"])
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("config/fanuc.toml"))
        .arg("--macro-variables")
        .arg(kept)
        .arg("--svg")
        .arg(scratch(&format!("{tag}.svg")))
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_part_counter_counts_across_runs() {
    let prog = scratch("counter.nc");
    let kept = scratch("kept.toml");
    let _ = std::fs::remove_file(&kept);
    std::fs::write(
        &prog,
        "O0001 (PART COUNTER)\n#500 = #500 + 1\n#501 = #500 * 10.\nG90 G0 X#500 Y0. Z10.\nM30\n",
    )
    .unwrap();
    run_once(&prog, &kept, "kept1");
    let text = std::fs::read_to_string(&kept).unwrap();
    assert_eq!(
        nc_kernel::parse_kept_variables(&text, "kept").unwrap(),
        [(500, 1.0), (501, 10.0)]
    );
    run_once(&prog, &kept, "kept2");
    let text = std::fs::read_to_string(&kept).unwrap();
    assert_eq!(
        nc_kernel::parse_kept_variables(&text, "kept").unwrap(),
        [(500, 2.0), (501, 20.0)]
    );
    // `softnc check` starts from the file (X3 after two runs) and leaves it alone.
    let out = std::process::Command::new(EXE)
        .arg("check")
        .arg(&prog)
        .arg("--machine")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("config/fanuc.toml"))
        .arg("--macro-variables")
        .arg(&kept)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), text);
    let bad = scratch("kept-bad.toml");
    std::fs::write(&bad, "100 = 1.0\n").unwrap();
    let out = std::process::Command::new(EXE)
        .arg("check")
        .arg(&prog)
        .arg("--macro-variables")
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "a bad file is a usage error");
    assert!(String::from_utf8_lossy(&out.stderr).contains("key `100`"));
}
