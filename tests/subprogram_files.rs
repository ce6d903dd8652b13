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

/// The folder's files are listed when the program loads and read when it first calls one: a
/// file no call reaches is never read, and one that went since the load is alarm 14011 at
/// the call that needs it, naming the file.
#[test]
fn files_are_read_at_their_first_call() {
    let d = folder("lazy");
    let main = d.join("main.nc");
    write(
        &main,
        "O0001\nG90 G0 X0. Y0. Z0.\nM98 P2000\nM98 P3000\nM30\n",
    );
    write(&d.join("O2000.nc"), "O2000\nG1 X1. F100.\nM99\n");
    write(&d.join("O3000.nc"), "O3000\nG1 X2. F100.\nM99\n");
    write(&d.join("O4000.nc"), "O4000\nnever called\nM99\n");
    // What the program loaded with: O2000 as it was, O3000 gone, O4000 not read at all.
    let (blocks, shown, md) = interpreted_after(&main, FANUC, &d.join("O3000.nc"));
    assert!(blocks >= 2, "O2000 ran first: {blocks} blocks");
    assert!(shown.contains("main.nc:4:5: alarm 14011"), "{shown}");
    assert!(shown.contains("O3000.nc cannot be read"), "{shown}");
    let (_, o4000) = md.programs.find(4000).unwrap();
    assert!(format!("{o4000:?}").contains("read: None"), "{o4000:?}");
    // A SINUMERIK call by name the same way.
    let main = d.join("main.mpf");
    write(&main, "G0 X0 Y0 Z0\nPOCKET\nM30\n");
    write(&d.join("POCKET.SPF"), "G1 X1 F100\nM17\n");
    let (_, shown, _) = interpreted_after(&main, SIEMENS_840D, &d.join("POCKET.SPF"));
    assert!(shown.contains("main.mpf:2:1: alarm 14011"), "{shown}");
    assert!(shown.contains("POCKET.SPF cannot be read"), "{shown}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The blocks `main` gives up to its first alarm (shown as `softnc` shows it), with its
/// program library listed at the load and `gone` deleted after it.
fn interpreted_after(
    main: &Path,
    machine: &str,
    gone: &Path,
) -> (usize, String, nc_kernel::MachineData) {
    use nc_kernel::{Interpreter, MachineData, ToolTable};
    let library = nc_runtime::program_library(main, &[]).unwrap();
    std::fs::remove_file(gone).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut md = MachineData::load(Some(&root.join(machine)), &[]).unwrap();
    md.programs = std::sync::Arc::new(library);
    let tools = ToolTable::builtin();
    let text = std::fs::read_to_string(main).unwrap();
    let name = main.file_name().unwrap().to_str().unwrap();
    let mut blocks = 0;
    for item in Interpreter::new(name, &text, &md, &tools) {
        match item {
            Ok(_) => blocks += 1,
            Err(a) => {
                let shown = md.programs.render(&a, &text);
                return (blocks, shown, md);
            }
        }
    }
    panic!(
        "{} ran to its end without {}",
        main.display(),
        gone.display()
    );
}
