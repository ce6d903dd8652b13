//! The machine's axes end to end: `softnc run` (nc-kernel and plc-sim over iceoryx2) on the
//! shipped 5-axis milling machine with its sample program, and a program that would drive
//! an axis past its software limit (docs/axes.md).

#[path = "support/control.rs"]
mod control;

use control::*;
use std::path::Path;

#[test]
fn five_axes_run_through_plc_sim_with_every_axis_in_the_trace() {
    let inst = instance("fiveax");
    let tr = scratch("fiveax.csv");
    let run = softnc_run(
        Path::new("programs/fanuc-5axis/five_axis_faces_and_sweep.nc"),
        &inst,
        &tr,
        &["--machine", "config/fanuc-5axis.toml"],
    );
    assert!(run.success(), "{}", run.said());
    assert!(run.stdout.contains("ran to its end"), "{}", run.stdout);
    let header = std::fs::read_to_string(&tr).unwrap();
    assert!(
        header.starts_with("time,cycle,seq,X,Y,Z,A,C,AX,AY,AZ,AA,AC,FX,FY,FZ,FA,FC,S1,AS1,v_path,"),
        "{}",
        header.lines().next().unwrap_or("")
    );
    let rows = trace(&tr);
    assert_eq!(rows.last().unwrap().state, "END");
    assert!(rows.iter().all(|r| r.seq > 0), "no watchdog rows");
    for w in rows.windows(2) {
        assert_eq!(w[1].seq, w[0].seq + 1, "no setpoint lost");
    }
    // As programmed: C the shorter way each time — N230 C0. from 270 +90 (360), N250 C180.
    // +180 (540), N260 C360. half a turn, positive (720), N280 C0. stays (shown 0).
    let last = rows.last().unwrap();
    assert_eq!(last.sp, [-40.0, 0.0, 0.0]);
    assert_eq!(last.axis('A').map(|a| a[0]), Some(0.0));
    assert_eq!(last.axis('C').map(|c| c[0]), Some(720.0));
    // N250 (line 33) moves X, A and C together: X +80 while A −60° and C +180°, the ratio
    // of their setpoints' changes constant along the block. C starts at 360: N230's C0.
    // came from 270 the shorter way (+90).
    let sweep: Vec<&TraceRow> = rows.iter().filter(|r| r.line == 33).collect();
    assert!(sweep.len() > 100, "{}", sweep.len());
    let (x0, a0, c0) = (-40.0, -30.0, 360.0);
    for r in &sweep {
        let u = (r.sp[0] - x0) / 80.0;
        let a = r.axis('A').unwrap()[0];
        let c = r.axis('C').unwrap()[0];
        assert!((a - (a0 - 60.0 * u)).abs() < 1e-9, "{a} at u {u}");
        assert!((c - (c0 + 180.0 * u)).abs() < 1e-9, "{c} at u {u}");
    }
    // The rotary drives follow with an error of their own, in degrees.
    let fe_c = sweep
        .iter()
        .map(|r| r.axis('C').unwrap()[2].abs())
        .fold(0.0, f64::max);
    assert!(fe_c > 0.1, "C's following error {fe_c}°");
}

#[test]
fn a_program_past_a_software_limit_is_refused_before_motion() {
    let inst = instance("softlim");
    let tr = scratch("softlim.csv");
    let prog = scratch("softlim.nc");
    // A's limits are −120° … 30°; N30 would take it to −125°.
    std::fs::write(
        &prog,
        "N10 G90 G0 X0. Y0. Z0. A0. C0.\nN20 G1 X50. F2000.\nN30 A-125.\nN40 M30\n",
    )
    .unwrap();
    let run = softnc_run(&prog, &inst, &tr, &["--machine", "config/fanuc-5axis.toml"]);
    let said = run.said();
    assert_eq!(run.code, Some(1), "{said}");
    assert!(said.contains("alarm 10720"), "{said}");
    assert!(said.contains(":3:"), "the alarm names line 3: {said}");
    assert!(said.contains("axis A would reach -125.0000"), "{said}");
    // Nothing moved: X never left 0.
    if let Ok(text) = std::fs::read_to_string(&tr) {
        if text.lines().count() > 1 {
            assert!(trace(&tr).iter().all(|r| r.sp[0] == 0.0), "something moved");
        }
    }
}

/// The shipped lathe with a C axis and its main spindle, end to end: the sample turns a
/// shoulder at constant surface speed with feed per revolution, stops the spindle and
/// drills four radial holes positioned with C. From plc-sim's trace: every axis and the
/// spindle, no setpoint lost, the final position as programmed; the spindle's setpoint is
/// n = 150000 / (2π·r) (G96 S150) at the turning radius, plc-sim's spindle comes up to it,
/// and the path runs at F × the actual speed (G95).
#[test]
fn the_lathe_with_c_and_spindle_runs_its_sample_through_plc_sim() {
    let inst = instance("lathesp");
    let tr = scratch("lathesp.csv");
    let run = softnc_run(
        Path::new("programs/siemens-808d-c/c_axis_cross_holes.mpf"),
        &inst,
        &tr,
        &["--machine", "config/siemens-808d-c.toml"],
    );
    assert!(run.success(), "{}", run.said());
    let header = std::fs::read_to_string(&tr).unwrap();
    assert!(
        header.starts_with("time,cycle,seq,X,Z,C,AX,AZ,AC,FX,FZ,FC,S1,AS1,v_path,"),
        "{}",
        header.lines().next().unwrap_or("")
    );
    let rows = trace(&tr);
    assert!(rows.iter().all(|r| r.seq > 0), "no watchdog rows");
    for w in rows.windows(2) {
        assert_eq!(w[1].seq, w[0].seq + 1, "no setpoint lost");
    }
    let last = rows.last().unwrap();
    assert_eq!(last.state, "END");
    assert_eq!(last.sp, [40.0, 0.0, 50.0], "X80 (a diameter) Z50");
    assert_eq!(last.axis('C').map(|c| c[0]), Some(360.0));
    assert_eq!(last.spindle, vec![[0.0, 0.0]], "M5: stopped");
    // N30 (line 8): X62 is r = 31 mm: 150000 / (2π·31) = 770.1046 rev/min; the path
    // runs at F0.5 × the actual speed once it is there.
    let n = 150_000.0 / (2.0 * std::f64::consts::PI * 31.0);
    let cut: Vec<&TraceRow> = rows.iter().filter(|r| r.line == 8).collect();
    assert!(cut.len() > 1000, "{}", cut.len());
    for r in &cut {
        assert!((r.spindle[0][0] - n).abs() < 1e-9, "{:?}", r.spindle);
    }
    let steady: Vec<&&TraceRow> = cut
        .iter()
        .filter(|r| (r.spindle[0][1] - n).abs() < 1e-6)
        .collect();
    assert!(
        steady.len() > cut.len() / 2,
        "the spindle is at speed for most of the cut"
    );
    let top = cut.iter().map(|r| r.v * 60.0).fold(0.0, f64::max);
    assert!((top - 0.5 * n).abs() < 1e-6, "{top} mm/min vs {}", 0.5 * n);
    // The holes (lines 17, 20, 23, 26) with the spindle stopped, C at its angle.
    for (line, c) in [(17, 0.0), (20, 90.0), (23, 180.0), (26, 270.0)] {
        let hole: Vec<&TraceRow> = rows.iter().filter(|r| r.line == line).collect();
        assert!(!hole.is_empty(), "line {line}");
        for r in hole {
            assert_eq!(r.spindle[0], [0.0, 0.0], "line {line}");
            assert_eq!(r.axis('C').map(|a| a[0]), Some(c), "line {line}");
        }
    }
}
