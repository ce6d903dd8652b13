//! Tool registers end to end (`softnc run`: nc-kernel and plc-sim over iceoryx2) on the
//! shipped Fanuc machine: T preselection and M6, which the path waits at until plc-sim has
//! changed the tool (`plc.tool_change_ms`) and acknowledges it, then G43 H with the H
//! register's geometry and wear along the tool axis (docs/offsets.md).

#[path = "support/control.rs"]
mod control;

use control::*;

const PROGRAM: &str = "%\nO0002 (TOOL CHANGE AND LENGTH)\n\
N10 G21 G90 G17 G0 X0. Y0. Z100.\n\
N20 T2 M6\n\
N30 G43 H2 Z10.\n\
N40 G1 X50. F2000.\n\
N50 G49 G0 Z100.\n\
N60 M30\n%\n";

#[test]
fn m6_waits_for_the_plc_and_g43_h_takes_geometry_and_wear() {
    let prog = scratch("tools-run.nc");
    std::fs::write(&prog, PROGRAM).unwrap();
    // Offset number 2: H2 = 80 geometry - 0.25 wear = 79.75 mm.
    let tools = scratch("tools-run.toml");
    std::fs::write(
        &tools,
        "[[offset]]\nd = 2\nradius = 5.0\nlength = 80.0\nlength_wear = -0.25\n",
    )
    .unwrap();
    let tr = scratch("tools-run.csv");
    let run = softnc_run(
        &prog,
        &instance("toolsrun"),
        &tr,
        &[
            "--machine",
            "config/fanuc.toml",
            "--tools",
            tools.to_str().unwrap(),
            "--md",
            "plc.tool_change_ms=1500",
        ],
    );
    assert!(run.success(), "{}", run.said());
    let rows = trace(&tr);
    // The acknowledgement names the tool change; until it came the path stood still at
    // N10's end for the tool change time (1 ms IPO cycles).
    let k = rows
        .iter()
        .position(|r| r.events.contains("ack T2 M6"))
        .expect("plc-sim acknowledged the tool change");
    let at = rows[k].sp;
    assert_eq!(at, [0.0, 0.0, 100.0]);
    let from = rows[..k]
        .iter()
        .rposition(|r| r.sp != at)
        .map_or(0, |j| j + 1);
    // The PLC times the change on its own clock: a kernel cycle the VM's host delayed past
    // its slot is skipped, so the cycle numbers may count fewer than the milliseconds.
    let stood = rows[k].time - rows[from].time;
    assert!(
        (1.45..2.5).contains(&stood),
        "the path stood {stood} s at the tool change (cycles {} to {})",
        rows[from].cycle,
        rows[k].cycle
    );
    // Lines: N10 is line 3. Then N30 (line 5) goes down to Z10 plus H2 (79.75), N40 cuts at that height, N50 takes the
    // length off again.
    let on = |line: u32| rows.iter().filter(move |r| r.line == line);
    let n30 = on(5).next_back().expect("N30 ran").sp;
    assert!((n30[2] - 89.75).abs() < 1e-6, "{n30:?}"); // the last cycle before N40
    assert!(on(6).all(|r| (r.sp[2] - 89.75).abs() < 1e-9));
    assert!(
        (on(6).next_back().unwrap().sp[0] - 50.0).abs() < 1e-5,
        "N40 ends at X50 (blending into N50)"
    );
    // N30 starts only after the acknowledgement.
    assert!(
        rows.iter()
            .position(|r| r.sp[2] < 100.0 && r.line >= 5)
            .unwrap()
            > k
    );
    let last = rows.last().unwrap();
    assert_eq!((last.sp, last.state.as_str()), ([50.0, 0.0, 100.0], "END"));
}
