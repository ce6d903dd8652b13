//! The co-simulation library from C: cosim/examples/step.c, compiled here with `cc` against
//! cosim/include/softnc_cosim.h and the library cargo built (softnc-cosim is a
//! dev-dependency, so its cdylib is in this test's target directory), steps sample programs
//! cycle by cycle; every row it prints equals `softnc simulate`'s for the same program and
//! machine data, every number bit for bit (the example prints IEEE-754 bit patterns; the
//! CSV's shortest decimal forms read back to the same bits, -0 written as 0).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The directory holding libsoftnc_cosim.so: this test's `deps`, where cargo built the
/// dev-dependency with it, or the profile directory above.
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    let name = "libsoftnc_cosim.so";
    for d in [deps, deps.parent().unwrap()] {
        if d.join(name).exists() {
            return d.to_path_buf();
        }
    }
    // Not built with this test (a filtered build): build it now.
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let ok = Command::new(cargo)
        .args(["build", "-p", "softnc-cosim"])
        .current_dir(root())
        .status()
        .unwrap();
    assert!(ok.success(), "cargo build -p softnc-cosim failed");
    deps.parent().unwrap().to_path_buf()
}

/// The C example, compiled once per test run.
fn example() -> PathBuf {
    static BUILT: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    BUILT
        .get_or_init(|| {
            let lib = library_dir();
            let out =
                std::env::temp_dir().join(format!("softnc-cosim-step-{}", std::process::id()));
            let r = Command::new("cc")
                .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-o"])
                .arg(&out)
                .arg(root().join("cosim/examples/step.c"))
                .arg("-I")
                .arg(root().join("cosim/include"))
                .arg(format!("-L{}", lib.display()))
                .arg("-lsoftnc_cosim")
                .arg(format!("-Wl,-rpath,{}", lib.display()))
                .output()
                .expect("cc");
            assert!(
                r.status.success(),
                "cc: {}",
                String::from_utf8_lossy(&r.stderr)
            );
            out
        })
        .clone()
}

/// What a command wrote to stdout, and its exit code.
fn run(cmd: &mut Command) -> (String, Option<i32>) {
    let r = cmd.output().unwrap();
    (String::from_utf8(r.stdout).unwrap(), r.status.code())
}

/// A `softnc simulate` row with its numbers as the example prints them.
fn as_bits(row: &str, numbers: std::ops::Range<usize>) -> String {
    let f: Vec<String> = row
        .split(',')
        .enumerate()
        .map(|(i, s)| {
            if numbers.contains(&i) {
                let x: f64 = s.parse().unwrap_or_else(|_| panic!("{s} in {row}"));
                format!("0x{:016x}", x.to_bits())
            } else {
                s.to_string()
            }
        })
        .collect();
    f.join(",")
}

/// The example's row with -0.0 as 0.0 (the CSV cannot tell them apart).
fn zero_signless(row: &str, numbers: std::ops::Range<usize>) -> String {
    let f: Vec<String> = row
        .split(',')
        .enumerate()
        .map(|(i, s)| match s.strip_prefix("0x") {
            Some(h) if numbers.contains(&i) && u64::from_str_radix(h, 16) == Ok(1 << 63) => {
                "0x0000000000000000".to_string()
            }
            _ => s.to_string(),
        })
        .collect();
    f.join(",")
}

/// Steps `program` with the example and simulates it with `softnc simulate`; asserts the
/// streams are equal and returns the number of rows and the example's exit code.
fn compare(machine: Option<&str>, program: &str, tools: Option<&str>) -> (usize, Option<i32>) {
    let prog = root().join(program);
    let md = machine.map(|m| root().join(m));
    let tools = tools.map(|t| root().join(t));
    let mut c = Command::new(example());
    c.arg(md.as_deref().unwrap_or(Path::new("-"))).arg(&prog);
    if let Some(t) = &tools {
        c.arg(t);
    }
    let (ours, code) = run(&mut c);
    let mut s = Command::new(env!("CARGO_BIN_EXE_softnc"));
    s.arg("simulate").arg(&prog);
    if let Some(m) = &md {
        s.arg("--machine").arg(m);
    }
    if let Some(t) = &tools {
        s.arg("--tools").arg(t);
    }
    let (theirs, _) = run(&mut s);
    let (ours, theirs): (Vec<&str>, Vec<&str>) = (ours.lines().collect(), theirs.lines().collect());
    assert_eq!(ours.first(), theirs.first(), "{program}: header");
    let columns = theirs[0].split(',').count();
    let numbers = 2..columns - 2;
    assert_eq!(ours.len(), theirs.len(), "{program}: rows");
    for (i, (o, t)) in ours.iter().zip(&theirs).enumerate().skip(1) {
        assert_eq!(
            zero_signless(o, numbers.clone()),
            as_bits(t, numbers.clone()),
            "{program}: row {i}\n  simulate: {t}"
        );
    }
    (ours.len() - 1, code)
}

#[test]
fn c_example_steps_840c_aux_functions_as_simulate() {
    let (rows, code) = compare(None, "programs/siemens-840c/11_10_aux_functions.mpf", None);
    assert_eq!(code, Some(0), "ended");
    assert!(rows > 10_000, "{rows} rows");
}

#[test]
fn c_example_steps_five_axis_program_with_its_rotary_columns() {
    let (rows, code) = compare(
        Some("config/fanuc-5axis.toml"),
        "programs/fanuc-5axis/five_axis_faces_and_sweep.nc",
        Some("config/tools.toml"),
    );
    assert_eq!(code, Some(0));
    assert!(rows > 10_000, "{rows} rows");
}

#[test]
fn c_example_steps_isg_star_as_simulate() {
    let (_, code) = compare(Some("config/isg.toml"), "programs/isg/g238_star.nc", None);
    assert_eq!(code, Some(0));
}

#[test]
fn c_example_stops_with_the_alarm_simulate_stops_with() {
    let (_, code) = compare(
        None,
        "programs/siemens-840c/11_11_four_blocks_outside_plane_alarm.mpf",
        None,
    );
    assert_eq!(code, Some(1), "stopped with an alarm");
}

#[test]
fn c_example_reports_a_missing_program() {
    let r = Command::new(example())
        .args(["-", "/nonexistent/softnc-cosim.mpf"])
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(2));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("/nonexistent/softnc-cosim.mpf"), "{err}");
}
