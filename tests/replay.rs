//! Record and replay (docs/interfaces.md): a live run with kernel, plc-sim and hmi-bridge
//! records every input the kernel takes; `softnc simulate --replay` feeds them to the same
//! cycle and writes the live run's setpoints bit for bit (the CSV files are equal byte for
//! byte: every number is written in the shortest form that reads back to its bits).

#[path = "support/control.rs"]
mod control;
#[path = "support/station.rs"]
mod station;

use control::*;
use serde_json::json;
use station::*;
use std::path::Path;
use std::time::{Duration, Instant};

/// A square 100 mm wide drawn in G54 from its corner, the spindle turning (M3 and M5 wait
/// for the PLC's acknowledgement: acknowledgements are recorded inputs too).
const SQUARE: &str =
    "N10 G54 G0 X0 Y0 Z0 M3 S1000\nN20 G1 X100 F3000\nN30 Y100\nN40 X0\nN50 Y0\nN60 M5\nN70 M30\n";

/// `softnc simulate PROGRAM ARGS… --replay RECORD -o OUT`: its exit status and stderr.
fn replay(program: &Path, args: &[&str], record: &Path, out: &Path) -> (bool, String) {
    let o = std::process::Command::new(EXE)
        .current_dir(root())
        .arg("simulate")
        .arg(program)
        .args(args)
        .arg("--replay")
        .arg(record)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Waits until the record's last line is its end (the kernel writes it as it ends).
fn ended(record: &Path) -> String {
    let t = Instant::now();
    loop {
        let text = std::fs::read_to_string(record).unwrap_or_default();
        if text
            .lines()
            .last()
            .is_some_and(|l| l.starts_with("{\"end\""))
        {
            return text;
        }
        assert!(t.elapsed() < Duration::from_secs(20), "no end line: {text}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The first differing line of two setpoint files, for the message.
fn first_difference(a: &str, b: &str) -> String {
    match a.lines().zip(b.lines()).position(|(x, y)| x != y) {
        Some(i) => format!(
            "line {}:\n live   {}\n replay {}",
            i + 1,
            a.lines().nth(i).unwrap(),
            b.lines().nth(i).unwrap()
        ),
        None => format!(
            "{} live lines, {} replayed",
            a.lines().count(),
            b.lines().count()
        ),
    }
}

#[test]
fn a_replay_gives_the_live_setpoints_after_nc_stop_override_and_offset_edit() {
    let prog = write("rp-square.mpf", SQUARE);
    let start = "[G54]\nX = 10.0\nY = 20.0\n";
    let offsets = write("rp-offsets.toml", start);
    // The edit below is saved to `offsets`: the replay starts from the run's start.
    let offsets_at_start = write("rp-offsets-start.toml", start);
    // Tool edits are saved to the table too: a copy, and one as it was at the start.
    let table = std::fs::read_to_string(root().join("config/tools.toml")).unwrap();
    let tools = write("rp-tools.toml", &table);
    let tools_at_start = write("rp-tools-start.toml", &table);
    let (record, live) = (scratch("rp.record"), scratch("rp-live.csv"));
    let mut st = station(
        "replay",
        Some(&prog),
        &[
            "--offsets",
            offsets.to_str().unwrap(),
            "--tools",
            tools.to_str().unwrap(),
            "--record",
            record.to_str().unwrap(),
            "--setpoints",
            live.to_str().unwrap(),
        ],
        &[],
    );
    // On N20 at speed: override 60 %; on N30: NC stop, G54 edited, NC start.
    st.watch(Duration::from_secs(30), |s| {
        s["line"] == json!(2) && f(&s["feed_mm_min"]) > 2400.0
    });
    let (code, r) = st.post("/api/override", json!({ "percent": 60 }));
    assert_eq!(code, 200, "{r}");
    st.watch(Duration::from_secs(30), |s| {
        s["line"] == json!(3) && f(&s["feed_mm_min"]) > 1000.0
    });
    st.nc_stop();
    let edit = json!({ "set": "G54", "values": { "X": 15.0, "Y": 18.0 } });
    let (code, r) = st.post("/api/work-offset", edit);
    assert_eq!(code, 200, "{r}");
    let (code, r) = st.post("/api/offset", json!({ "d": 2, "radius": 6.5 }));
    assert_eq!(code, 200, "{r}");
    let (code, r) = st.post("/api/start", json!({}));
    assert_eq!(code, 200, "{r}");
    st.until_end(Duration::from_secs(30));
    // The kernel ends (SIGTERM): it writes the record's end.
    terminate(&mut st.kids[1]);
    let text = ended(&record);
    let kinds = [
        "\"stop\"",
        "\"override\"",
        "\"work_edit\"",
        "\"tool_edit\"",
        "\"resume\"",
        "\"ack\"",
    ];
    for kind in kinds {
        assert!(text.contains(kind), "{kind} not recorded:\n{text}");
    }

    let out = scratch("rp-replay.csv");
    let args = [
        "--offsets",
        offsets_at_start.to_str().unwrap(),
        "--tools",
        tools_at_start.to_str().unwrap(),
    ];
    let (ok, said) = replay(&prog, &args, &record, &out);
    assert!(ok, "{said}");
    let (a, b) = (
        std::fs::read_to_string(&live).unwrap(),
        std::fs::read_to_string(&out).unwrap(),
    );
    assert!(a.lines().count() > 3000, "{} live rows", a.lines().count());
    assert!(a == b, "{}", first_difference(&a, &b));

    // Other work offsets than the run started with: refused, nothing written.
    let (ok, said) = replay(
        &prog,
        &[
            "--offsets",
            offsets.to_str().unwrap(),
            "--tools",
            tools_at_start.to_str().unwrap(),
        ],
        &record,
        &scratch("rp-wrong.csv"),
    );
    assert!(!ok && said.contains("work offsets other than"), "{said}");
}

#[test]
fn softnc_run_records_and_the_replay_gives_its_setpoints() {
    let prog = line_program("rp-line.mpf", 'X', 60.0);
    let tools = root().join("config/tools.toml");
    let (record, live) = (scratch("rp-run.record"), scratch("rp-run-live.csv"));
    let inst = instance("rprun");
    let r = softnc_run(
        &prog,
        &inst,
        &scratch("rp-run-trace.csv"),
        &[
            "--tools",
            tools.to_str().unwrap(),
            "--record",
            record.to_str().unwrap(),
            "--setpoints",
            live.to_str().unwrap(),
            "--svg",
            scratch("rp-run.svg").to_str().unwrap(),
        ],
    );
    assert!(r.success(), "{}", r.said());
    ended(&record);
    let out = scratch("rp-run-replay.csv");
    let (ok, said) = replay(&prog, &["--tools", tools.to_str().unwrap()], &record, &out);
    assert!(ok, "{said}");
    let (a, b) = (
        std::fs::read_to_string(&live).unwrap(),
        std::fs::read_to_string(&out).unwrap(),
    );
    assert!(a.lines().count() > 1000, "{} live rows", a.lines().count());
    assert!(a == b, "{}", first_difference(&a, &b));
}
