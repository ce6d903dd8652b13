//! Subprograms in files of their own: Fanuc M98/G65 find `O1000.nc` (docs/fanuc.md), SINUMERIK
//! calls find `NAME.SPF` in any case (docs/sinumerik.md, "Subprograms"), in the program's
//! folder, then in `program.search_path`; alarms inside such a file name it, with its line and
//! column, whether the front end or preparation raises them.

use std::path::{Path, PathBuf};
use std::process::Command;

fn folder(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softnc-subfiles-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("lib")).unwrap();
    d
}

fn write(p: &Path, text: &str) {
    std::fs::write(p, text).unwrap();
}

const FANUC: &str = "config/fanuc.toml";
const SIEMENS_840D: &str = "config/siemens-840d.toml";

/// `softnc check` on `main` with the machine data file `machine` and extra `--md` settings.
fn check(main: &Path, machine: &str, md: &[&str]) -> (Option<i32>, String) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_softnc"));
    cmd.arg("check")
        .arg(main)
        .arg("--machine")
        .arg(root.join(machine));
    for m in md {
        cmd.arg("--md").arg(m);
    }
    let out = cmd.output().unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.code(), text)
}

#[test]
fn calls_find_files_in_the_folder_and_the_search_path() {
    let d = folder("find");
    write(
        &d.join("main.nc"),
        "O0001\nG90 G17 G0 X0. Y0. Z10.\nM98 P2000 L2\nG65 P3000 A5.\nG0 X0. Y0.\nM30\n",
    );
    write(&d.join("O2000.nc"), "O2000\nG91 G1 X10. F100.\nG90\nM99\n");
    write(&d.join("lib/O3000.nc"), "O3000\nG0 X#1 Y#1\nM99\n");
    // Without the search path, O3000 is missing: alarm 14011 at the G65 of the main program.
    let (code, text) = check(&d.join("main.nc"), FANUC, &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("main.nc:4:1: alarm 14011"), "{text}");
    let lib = format!("program.search_path=[\"{}\"]", d.join("lib").display());
    let (code, text) = check(&d.join("main.nc"), FANUC, &[&lib]);
    assert_eq!(code, Some(0), "{text}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn alarms_in_a_subprogram_file_name_that_file() {
    let d = folder("alarms");
    write(
        &d.join("main.nc"),
        "O0001\nG90 G0 X0. Y0. Z0.\nM98 P2000\nM98 P2001\nM30\n",
    );
    // Line 3 col 8: X twice (the front end).
    write(
        &d.join("O2000.nc"),
        "O2000\nG1 X1. F100.\nG1 X2. X3.\nM99\n",
    );
    let (code, text) = check(&d.join("main.nc"), FANUC, &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("O2000.nc:3:8: alarm 12040"), "{text}");
    assert!(
        text.contains("3 | G1 X2. X3."),
        "the line shown is the subprogram's: {text}"
    );
    // M99 P to a sequence number the caller lacks: the alarm is at the M99 of the file.
    write(&d.join("O2000.nc"), "O2000\n(sub)\nG1 X1. F100.\nM99 P77\n");
    let (code, text) = check(&d.join("main.nc"), FANUC, &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("O2000.nc:4:1: alarm 14080"), "{text}");
    // A software limit (preparation) in a subprogram file names it too.
    write(&d.join("O2000.nc"), "O2000\nG1 X1. F100.\nM99\n");
    write(
        &d.join("O2001.nc"),
        "O2001\nG1 X10. F100.\nG1 X5000.\nM99\n",
    );
    let (code, text) = check(&d.join("main.nc"), FANUC, &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("O2001.nc:3:1: alarm 10720"), "{text}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn calls_find_spf_files_in_the_folder_and_the_search_path() {
    let d = folder("spf-find");
    write(
        &d.join("main.mpf"),
        "G17 G90 G0 X0 Y0 Z5 F200\nStep_X(10) P2\nL7\nG0 Z50\nM30\n",
    );
    write(
        &d.join("step_x.spf"),
        "PROC STEP_X(REAL DX)\nG91 G1 X=DX\nG90\nM17\n",
    );
    write(&d.join("lib/L7.SPF"), "G1 Y7\n");
    // Without the search path, L7 is missing: alarm 14011 at its name in the main program.
    let (code, text) = check(&d.join("main.mpf"), SIEMENS_840D, &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("main.mpf:3:1: alarm 14011"), "{text}");
    assert!(text.contains("L7.SPF or L7.MPF"), "{text}");
    let lib = format!("program.search_path=[\"{}\"]", d.join("lib").display());
    let (code, text) = check(&d.join("main.mpf"), SIEMENS_840D, &[&lib]);
    assert_eq!(code, Some(0), "{text}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn alarms_in_a_spf_file_name_that_file() {
    let d = folder("spf-alarms");
    write(&d.join("main.mpf"), "G0 X0 Y0 Z0\nBAD_SUB\nM30\n");
    // Line 3 col 10: R1/0 at run time, in the subprogram.
    write(
        &d.join("BAD_SUB.SPF"),
        "; divides\nG1 X1 F100\nR2=5 R3=R2/0\n",
    );
    let (code, text) = check(&d.join("main.mpf"), SIEMENS_840D, &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("BAD_SUB.SPF:3:11: alarm 14000"), "{text}");
    assert!(
        text.contains("3 | R2=5 R3=R2/0"),
        "the line shown is the subprogram's: {text}"
    );
    // A software limit (preparation) in a subprogram names it too.
    write(&d.join("BAD_SUB.SPF"), "G1 X10 F100\nG1 X5000\n");
    let (code, text) = check(&d.join("main.mpf"), SIEMENS_840D, &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("BAD_SUB.SPF:2:1: alarm 10720"), "{text}");
    let _ = std::fs::remove_dir_all(&d);
}
