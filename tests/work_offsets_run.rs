//! A work offset edited at the machine through the HMI's JSON API, end to end with kernel,
//! plc-sim and hmi-bridge (docs/work-offsets.md): while the program runs the edit is refused
//! and nothing changes; in NC stop it is taken and saved, NC start repositions, and every
//! setpoint of the rest of the program is shifted by exactly the edit (from plc-sim's trace).

#[path = "support/control.rs"]
mod control;
#[path = "support/station.rs"]
mod station;

use control::*;
use serde_json::json;
use station::*;
use std::time::Duration;

/// A square 100 mm wide drawn in G54 from its corner (0, 0), the spindle turning.
const SQUARE: &str =
    "N10 G54 G0 X0 Y0 Z0 M3 S1000\nN20 G1 X100 F3000\nN30 Y100\nN40 X0\nN50 Y0\nN60 M5\nN70 M30\n";

/// Distance from `p` to the outline of the square with its corner at `o`.
fn off_outline(p: [f64; 3], o: [f64; 2]) -> f64 {
    let c = |x: f64, y: f64| [o[0] + x, o[1] + y, 0.0];
    let corners = [c(0.0, 0.0), c(100.0, 0.0), c(100.0, 100.0), c(0.0, 100.0)];
    (0..4)
        .map(|k| dist_to_segment(p, corners[k], corners[(k + 1) % 4]))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn g54_edited_in_nc_stop_shifts_the_rest_of_the_program_by_exactly_the_edit() {
    let prog = write("wo-square.mpf", SQUARE);
    let offsets = write("wo-offsets.toml", "[G54]\nX = 10.0\nY = 20.0\n");
    let mut st = station(
        "workoff",
        Some(&prog),
        &["--offsets", offsets.to_str().unwrap()],
        &[],
    );
    let table = st.bridge.get("/api/work-offsets").unwrap().json();
    assert_eq!(table["version"], json!(1), "{table}");
    // On N30 (line 3), at speed: the edit is refused, nothing changes.
    st.watch(Duration::from_secs(30), |s| {
        s["line"] == json!(3) && f(&s["feed_mm_min"]) > 2400.0
    });
    let edit = json!({ "set": "G54", "values": { "X": 15.0, "Y": 18.0 } });
    let (code, r) = st.post("/api/work-offset", edit.clone());
    assert_eq!(code, 409, "{r}");
    assert!(r["error"].as_str().unwrap().contains("running"), "{r}");
    let stopped = st.nc_stop();
    assert_eq!(
        stopped["work_offsets_version"],
        json!(1),
        "refused: unchanged"
    );
    assert!(off_outline(pos(&stopped), [10.0, 20.0]) < 1e-6);
    // The status names the set in force and the spindle turning.
    assert_eq!(stopped["work_offset"], json!("G54"), "{stopped}");
    assert_eq!(stopped["spindle_setpoint"], json!(1000.0), "{stopped}");
    assert_eq!(
        std::fs::read_to_string(&offsets).unwrap(),
        "[G54]\nX = 10.0\nY = 20.0\n",
        "the refused edit is not saved"
    );
    // In NC stop: taken, saved, version 2.
    let (code, r) = st.post("/api/work-offset", edit);
    assert_eq!(code, 200, "{r}");
    assert_eq!(r["work_offsets_version"], json!(2), "{r}");
    let saved = std::fs::read_to_string(&offsets).unwrap();
    assert!(
        saved.contains("X = 15.0") && saved.contains("Y = 18.0"),
        "{saved}"
    );
    let (code, r) = st.post("/api/start", json!({}));
    assert_eq!(code, 200, "{r}");
    let end = st.until_end(Duration::from_secs(30));
    let p = pos(&end);
    assert!(
        (p[0] - 15.0).abs() < 1e-9 && (p[1] - 18.0).abs() < 1e-9,
        "{p:?}"
    );

    let rows = st.trace();
    let stop = rows
        .iter()
        .position(|r| r.state == "STOPPED")
        .expect("NC stop in the trace");
    let at_stop = rows[stop].sp;
    // Before the stop every contour setpoint lies on the square in the old G54.
    let contour = |r: &&TraceRow| (2..=5).contains(&r.line);
    let before = rows[..stop].iter().filter(contour).count();
    for r in rows[..stop].iter().filter(contour) {
        assert!(off_outline(r.sp, [10.0, 20.0]) < 1e-6, "{:?}", r.sp);
    }
    // The reposition: a straight move from where the path stood to the same point of N30
    // in the new G54, i.e. shifted by the edit (+5, -2).
    let target = [at_stop[0] + 5.0, at_stop[1] - 2.0, 0.0];
    let on_new = stop
        + rows[stop..]
            .iter()
            .position(|r| norm(sub(r.sp, target)) < 1e-6)
            .expect("the reposition reaches the shifted point");
    for r in &rows[stop..on_new] {
        assert!(dist_to_segment(r.sp, at_stop, target) < 1e-6, "{:?}", r.sp);
    }
    // From there on, every setpoint is the old program's shifted by exactly the edit.
    let after: Vec<&TraceRow> = rows[on_new..].iter().filter(contour).collect();
    for r in &after {
        assert!(off_outline(r.sp, [15.0, 18.0]) < 1e-6, "{:?}", r.sp);
    }
    assert!(
        before > 1000 && after.len() > 4000,
        "{before} {}",
        after.len()
    );
    // The spindle turns on through the stop and the resume: the re-prepared program goes on
    // with the spindle in force where it stopped (its M3 lies before the interruption).
    // (M5 goes out at N50's end, with the path there at rest.)
    let moving = rows[stop..]
        .iter()
        .filter(|r| r.v > 0.0 && (2..=5).contains(&r.line));
    for r in moving {
        assert_eq!(r.spindle[0][0], 1000.0, "line {}", r.line);
    }
}

/// An edit in reset reaches the program loaded before it: NC start prepares it again with
/// the new set first.
#[test]
fn an_edit_in_reset_reaches_the_program_loaded_before_it() {
    let prog = write("wo-reset.mpf", "N10 G54 G0 X10 Y0 Z0\nN20 M30\n");
    let offsets = write("wo-reset.toml", "[G54]\nX = 1.0\n");
    let folder = prog.parent().unwrap().to_str().unwrap().to_string();
    let st = station(
        "woreset",
        None,
        &["--offsets", offsets.to_str().unwrap()],
        &["--programs", &folder],
    );
    let (code, r) = st.post("/api/load", json!({ "program": "wo-reset.mpf" }));
    assert_eq!(code, 200, "{r}");
    let (code, r) = st.post(
        "/api/work-offset",
        json!({ "set": "G54", "values": { "X": 7.0 } }),
    );
    assert_eq!(code, 200, "{r}");
    let (code, r) = st.post("/api/start", json!({}));
    assert_eq!(code, 200, "{r}");
    assert!(
        r["message"].as_str().unwrap().contains("prepared again"),
        "{r}"
    );
    let end = st.until_end(Duration::from_secs(30));
    assert_eq!(pos(&end)[0], 17.0, "X10 in the new G54 (X7)");
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
