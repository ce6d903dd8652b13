//! LinuxCNC 2.9's `rs274` (Debian linuxcnc-uspace) as an oracle: whether it is there, a run
//! of it on a program, and the numbers of its canonical calls (field notes: four decimals,
//! `STRAIGHT_FEED(x, y, z, a, b, c)` …).

use std::process::Command;

/// Whether `rs274` runs here. Without it a test says so and passes, unless
/// SOFTNC_REQUIRE_ORACLES is set (CI installs linuxcnc-uspace): then it fails.
pub fn present() -> bool {
    let ok = Command::new("rs274").arg("-h").output().is_ok();
    if !ok {
        if std::env::var_os("SOFTNC_REQUIRE_ORACLES").is_some() {
            panic!("rs274 not found, and SOFTNC_REQUIRE_ORACLES is set (install linuxcnc-uspace)");
        }
        eprintln!("rs274 not found: oracle comparison skipped (install linuxcnc-uspace)");
    }
    ok
}

/// rs274 processes started at the same moment sometimes die with SIGBUS (seen here,
/// 2.9.0~pre1): one at a time.
static RS274: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// rs274's canonical calls for a program (with a tool table's text, if given), and its exit
/// status and stderr for messages. `tag` names the run's temporary files.
pub fn output(ngc: &str, tag: &str, tool_table: Option<&str>) -> (String, String) {
    let dir = std::env::temp_dir().join(format!("softnc-rs274-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("p.ngc");
    std::fs::write(&file, ngc).unwrap();
    let table = dir.join("tools.tbl");
    if let Some(t) = tool_table {
        std::fs::write(&table, t).unwrap();
    }
    let guard = RS274.lock().unwrap_or_else(|e| e.into_inner());
    // rs274 now and then dies from a signal on a loaded machine, with no output: that is the
    // oracle failing, not an answer. Up to three tries; its own errors (an exit code) are
    // answers and come back at once.
    let mut tries = 0;
    let out = loop {
        tries += 1;
        let mut cmd = Command::new("rs274");
        // LinuxCNC 2.9 keeps the tool table in $HOME/.tool.mmap: a home of the run's own,
        // or a run may read the table another one left there.
        cmd.env("HOME", &dir);
        if tool_table.is_some() {
            cmd.arg("-t").arg(&table);
        }
        let out = cmd.arg("-g").arg(&file).output().expect("rs274 runs");
        if out.status.code().is_some() || tries == 3 {
            break out;
        }
        eprintln!("rs274 died ({}), trying again", out.status);
    };
    drop(guard);
    let _ = std::fs::remove_dir_all(&dir);
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        format!("{}\n{}", out.status, String::from_utf8_lossy(&out.stderr)),
    )
}

/// The numbers between a canonical call's parentheses.
pub fn numbers(s: &str) -> Vec<f64> {
    let inner = &s[s.find('(').unwrap() + 1..s.rfind(')').unwrap()];
    inner
        .split(',')
        .map(|t| t.trim().parse().unwrap())
        .collect()
}
