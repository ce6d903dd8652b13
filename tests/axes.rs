//! The machine's axes beyond X Y Z: additional linear and rotary axes from machine data
//! (docs/axes.md), through the front end, preparation and interpolation. Expected values are
//! worked out by hand in the comments.

#[path = "support/sim.rs"]
mod sim;

use nc_kernel::{interpret, AlarmCode, MachineData, ToolTable};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A shipped configuration with `--md` overrides.
fn config(name: &str, extra: &[&str]) -> MachineData {
    let path = root().join("config").join(format!("{name}.toml"));
    let ov: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    MachineData::load(Some(Path::new(&path)), &ov).expect("machine data")
}

/// Where the additional axes stand after each block: their slots U V W A B C.
fn additional(md: &MachineData, text: &str) -> Vec<[f64; 6]> {
    let blocks = interpret("t.nc", text, md, &ToolTable::builtin()).expect("no alarm");
    let mut here = [0.0; 6];
    blocks
        .iter()
        .map(|b| {
            if let Some(m) = b.axes {
                assert_eq!(m.from, here, "a move starts where the axes stand");
                here = m.to;
            }
            here
        })
        .collect()
}

/// A and C after each block.
fn a_c(md: &MachineData, text: &str) -> Vec<(f64, f64)> {
    additional(md, text).iter().map(|a| (a[3], a[5])).collect()
}

#[test]
fn rotary_words_absolute_incremental_and_modulo() {
    let md = config("fanuc-5axis", &[]);
    let got = a_c(
        &md,
        // Fanuc increment input: a value without a point is in 0.001° steps.
        "G90 G0 A10. C350.\n\
         C10.\n\
         G91 C-400.\n\
         G90 C0.\n\
         A-20. C90\n",
    );
    // C is a modulo axis reached the shorter way: 0 → 350 is −10; shown 350 → 10 is +20
    // (to 10); incremental −400 counts on (−390, shown 330); absolute 0 from 330 is +30
    // (−360); C90 without a point is 0.09°: from 0 shown, +0.09. A is not modulo.
    let want = [
        (10.0, -10.0),
        (10.0, 10.0),
        (10.0, -390.0),
        (10.0, -360.0),
        (-20.0, -359.91),
    ];
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9,
            "{got:?}"
        );
    }
}

#[test]
fn a_modulo_axis_without_the_shorter_way_goes_by_the_sign() {
    let md = config("fanuc-5axis", &["axes.C.shortest_way=false"]);
    // 0 → 350: +350; shown 350 → 10: −340 (to 10), as a linear axis within one turn.
    let got = a_c(&md, "G0 C350.\nC10.\n");
    assert_eq!(got, [(0.0, 350.0), (0.0, 10.0)]);
}

#[test]
fn inch_programs_leave_degrees_alone() {
    let md = config("fanuc-5axis", &[]);
    let blocks = interpret("t.nc", "G20 G91 G0 X1. A1.\n", &md, &ToolTable::builtin()).unwrap();
    let m = blocks[0].motion.unwrap();
    assert!((m.end[0] - 25.4).abs() < 1e-12);
    assert_eq!(blocks[0].axes.unwrap().to[3], 1.0);
}

#[test]
fn axis_letters_the_machine_lacks_or_the_dialect_uses_are_refused() {
    let tools = ToolTable::builtin();
    // B is no axis of the 5-axis machine: an unknown address, pointing at the B.
    let md = config("fanuc-5axis", &[]);
    let a = interpret("t.nc", "G0 X1. B10.\n", &md, &tools).unwrap_err();
    assert_eq!((a.code, a.line, a.col), (AlarmCode::UnknownAddress, 1, 8));
    // The 3-axis Fanuc machine has no A.
    let md3 = config("fanuc", &[]);
    let a = interpret("t.nc", "G0 A10.\n", &md3, &tools).unwrap_err();
    assert_eq!((a.code, a.col), (AlarmCode::UnknownAddress, 4));
    // The 840C reads A as the polar angle: machine data may not name an axis A there.
    let e = MachineData::from_toml_str(
        "[axes.A]\nkind = \"rotary\"\nmax_velocity = 1e3\nmax_acceleration = 1e2\n\
         max_jerk = 1e3\n",
        "m.toml",
    )
    .unwrap_err();
    assert_eq!(e.key, "axes.A");
    assert!(e.reason.contains("another word"), "{e}");
}

#[test]
fn additional_axes_do_not_move_while_compensation_is_active() {
    let md = config("fanuc-5axis", &[]);
    let tools = ToolTable::builtin();
    let a = interpret(
        "t.nc",
        "G0 X0 Y0\nG41 D1 G1 X10. F100.\nX20. C45.\n",
        &md,
        &tools,
    )
    .unwrap_err();
    assert_eq!((a.code, a.line, a.col), (AlarmCode::ForbiddenWithTrc, 3, 6));
    // Nor in the deselection block, whose retract the compensation shapes.
    let a = interpret(
        "t.nc",
        "G0 X0 Y0\nG41 D1 G1 X10. F100.\nG40 X20. A5.\n",
        &md,
        &tools,
    )
    .unwrap_err();
    assert_eq!(a.code, AlarmCode::ForbiddenWithTrc);
    // After it, freely.
    let ok = interpret(
        "t.nc",
        "G0 X0 Y0\nG41 D1 G1 X10. F100.\nG40 X20.\nA5. C45.\n",
        &md,
        &tools,
    );
    assert!(ok.is_ok(), "{ok:?}");
}

/// One CSV row of `softnc simulate` on the 5-axis machine.
#[derive(Debug, Clone, Copy)]
struct Row {
    t: f64,
    /// X Y Z A C
    p: [f64; 5],
    v: f64,
}

fn simulate(md: &MachineData, text: &str) -> (Vec<Row>, nc_kernel::simulate::Summary) {
    let (text, s) = sim::csv(md, text);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("cycle,time,X,Y,Z,A,C,S1,v_path,block,events")
    );
    let rows = lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').take(9).map(|x| x.parse().unwrap()).collect();
            Row {
                t: f[1],
                p: [f[2], f[3], f[4], f[5], f[6]],
                v: f[8],
            }
        })
        .collect();
    (rows, s)
}

#[test]
fn simultaneous_rotary_moves_share_the_feed_and_keep_each_axis_limit() {
    let md = config("fanuc-5axis", &[]);
    let (rows, s) = simulate(
        &md,
        "G90 G0 X0 Y0 Z0 A0 C0\n\
         G1 X30. A-40. C120. F1200.\n\
         X0 A0. C0.\n\
         M30\n",
    );
    assert!(s.alarms.is_empty(), "{:?}", s.alarms);
    let last = rows.last().unwrap();
    assert_eq!(last.p, [0.0; 5]);
    // Block 2: the feed applies over all axes, len = √(30² + 40² + 120²) = 130 (deg as mm);
    // the path speed never exceeds F1200 = 20/s, and every axis keeps its share:
    // X : A : C = 30 : −40 : 120 all along the line.
    let peak = rows.iter().map(|r| r.v).fold(0.0, f64::max);
    assert!(peak <= 1200.0 + 1e-6 && peak > 1199.0, "{peak}");
    for r in rows.iter().filter(|r| r.p[0] > 0.0 && r.t < 10.0) {
        let u = r.p[0] / 30.0;
        assert!(
            (r.p[3] + 40.0 * u).abs() < 1e-9 && (r.p[4] - 120.0 * u).abs() < 1e-9,
            "{r:?}"
        );
    }
    // Every axis within its own velocity (rotary: °/min) and acceleration, by finite
    // differences of the setpoints (1 ms cycle), with rounding's margin.
    let limits = [15000.0, 15000.0, 10000.0, 5400.0, 7200.0];
    let acc = [3000.0, 3000.0, 2000.0, 600.0, 900.0];
    let dt = 0.001;
    for w in rows.windows(3) {
        for i in 0..5 {
            let v1 = (w[1].p[i] - w[0].p[i]) / dt;
            let v2 = (w[2].p[i] - w[1].p[i]) / dt;
            assert!(
                v2.abs() * 60.0 <= limits[i] * (1.0 + 1e-6),
                "axis {i} v {v2}"
            );
            assert!(
                (v2 - v1).abs() / dt <= acc[i] * 1.02 + 1.0,
                "axis {i} a {}",
                (v2 - v1) / dt
            );
        }
    }
    assert_eq!(s.end_state, Some(nc_kernel::ipo::ChannelState::End));
}

#[test]
fn a_move_past_a_software_limit_is_refused_before_anything_moves() {
    let md = config("fanuc-5axis", &[]);
    // A's limits are −120° … 30°: the third block would take it to −121°.
    let text = "G0 X0 Y0 Z0 A0\nG1 X10. F1000.\nA-121.\nX20.\nM30\n";
    let (rows, s) = simulate(&md, text);
    let a = &s.alarms[0];
    assert_eq!((a.number(), a.line), (10720, 3), "{a}");
    assert!(
        a.message.contains("axis A") && a.message.contains("-120"),
        "{a}"
    );
    assert!(rows.iter().all(|r| r.p == [0.0; 5]), "something moved");
    // The kernel refuses the load in the same way, naming the place.
    let spawned = nc_kernel::handover::spawn_preparation(
        "t.nc".into(),
        text.into(),
        md.clone(),
        ToolTable::builtin(),
        None,
    )
    .unwrap();
    let refused = spawned.err().expect("refused at load");
    assert_eq!((refused.number(), refused.line), (10720, 3));
    // An arc that bulges past a limit between its ends (Y's limit is ±400): radius 20 about
    // (0, 390) from (20, 390) to (−20, 390) counter-clockwise reaches Y 410 at 90°.
    let (_, s) = simulate(&md, "G0 X20. Y390.\nG3 X-20. Y390. I-20. J0 F1000.\nM30\n");
    assert_eq!(s.alarms.first().map(|a| a.number()), Some(10720));
}

#[test]
fn a_lathe_with_a_c_axis_positions_the_spindle() {
    let md = config("siemens-808d-c", &[]);
    let text = "G0 X40 Z2 C0\nC270\nG91 C100\nG90 C0\n";
    // Shortest way: 0 → 270 is −90; incremental +100 → 10; absolute 0 from 10 is −10 → 0.
    let c: Vec<f64> = additional(&md, text).iter().map(|a| a[5]).collect();
    assert_eq!(c, [0.0, -90.0, 10.0, 0.0]);
    // X is a diameter: 40 → 20 radius.
    let blocks = interpret("t.mpf", text, &md, &ToolTable::builtin()).unwrap();
    assert_eq!(blocks[0].motion.unwrap().end[0], 20.0);
}

#[test]
fn half_a_turn_goes_positive_on_the_shorter_way() {
    let md = config("fanuc-5axis", &[]);
    // 180 → 0 (360) is half a turn either way: +180. 0 shown → 180 likewise: +180.
    let got = a_c(&md, "G0 C180.\nC360.\nC180.\n");
    assert_eq!(got, [(0.0, 180.0), (0.0, 360.0), (0.0, 540.0)]);
}

#[test]
fn words_of_additional_axes_in_blocks_that_move_nothing_are_refused() {
    let md = config("fanuc-5axis", &[]);
    let a = interpret("t.nc", "G04 X1. C90.\n", &md, &ToolTable::builtin()).unwrap_err();
    assert_eq!((a.code, a.col), (AlarmCode::Syntax, 9), "{a}");
    assert!(a.message.contains("axis C"), "{a}");
}

#[test]
fn a_deselection_waiting_for_its_plane_move_keeps_additional_axes_still() {
    // 840C G40 alone: the retract waits for the next move in the plane (11.5). A C move
    // before it is refused, as inside the run.
    let md = MachineData::from_toml_str(
        "[axes.X]\nmax_velocity = 1e4\nmax_acceleration = 2e3\nmax_jerk = 5e4\n\
         [axes.Y]\nmax_velocity = 1e4\nmax_acceleration = 2e3\nmax_jerk = 5e4\n\
         [axes.Z]\nmax_velocity = 8e3\nmax_acceleration = 1.5e3\nmax_jerk = 4e4\n\
         [axes.C]\nkind = \"rotary\"\nmodulo = true\nmax_velocity = 7200\n\
         max_acceleration = 900\nmax_jerk = 15000\n",
        "840c-c.toml",
    )
    .unwrap();
    let text = "N10 G0 X0 Y0 Z0 C0\nN20 G1 G41 D1 X10 Y10 F1000\nN30 X50\nN40 G40\n\
                N50 Z10\nN55 C90\nN60 X0 Y0 C270\nM30\n";
    let a = nc_kernel::prepare("t.mpf", text, &md, &ToolTable::builtin()).unwrap_err();
    assert_eq!((a.number(), a.line), (10754, 6), "{a}");
}

#[test]
fn a_helix_beside_a_rotary_axis_keeps_the_tool_axis_in_its_limits() {
    // X and Y and C made fast, so that Z (10000 mm/min, 2000 mm/s²) is the axis that limits
    // the helix: its share of the path speed must count the rotary axis's part of the length.
    let md = config(
        "fanuc-5axis",
        &[
            "axes.X.max_velocity=1e6",
            "axes.Y.max_velocity=1e6",
            "axes.X.max_acceleration=1e5",
            "axes.Y.max_acceleration=1e5",
            "axes.C.max_velocity=1e6",
            "axes.C.max_acceleration=1e5",
            "axes.X.max_jerk=1e8",
            "axes.Y.max_jerk=1e8",
            "axes.C.max_jerk=1e8",
        ],
    );
    let (rows, s) = simulate(
        &md,
        "G90 G0 X100. Y0 Z0 A0 C0\nG91 G2 X0 Y0 I-100. J0 Z-400. C1000. F100000.\nM30\n",
    );
    assert!(s.alarms.is_empty(), "{:?}", s.alarms);
    let dt = 0.001;
    let top = rows
        .windows(2)
        .map(|w| (w[1].p[2] - w[0].p[2]).abs() / dt * 60.0)
        .fold(0.0, f64::max);
    assert!(top > 9990.0, "Z limits the helix: {top} mm/min");
    for w in rows.windows(3) {
        let v1 = (w[1].p[2] - w[0].p[2]) / dt;
        let v2 = (w[2].p[2] - w[1].p[2]) / dt;
        assert!(
            v2.abs() * 60.0 <= 10000.0 * (1.0 + 1e-6),
            "Z at {} mm/min",
            v2 * 60.0
        );
        assert!(
            (v2 - v1).abs() / dt <= 2000.0 * 1.02 + 1.0,
            "Z at {} mm/s²",
            (v2 - v1) / dt
        );
    }
}

#[test]
fn a_resume_after_an_offset_change_starts_from_where_the_rotary_axes_stand() {
    // Loaded with C at 0, C turned to 90 before the compensation run; stopped in N40.
    let md = config("fanuc-5axis", &["axes.Z.software_limits=[-500, 500]"]);
    let text = "N10 G90 G0 X0. Y0. Z0. C0.\nN20 C90.\nN30 G41 D1 G1 X10. Y10. F1000.\n\
                N40 X50.\nN50 X60. Y40.\nN60 G40 G0 X100. Y0.\nM30\n";
    let tools = ToolTable::builtin();
    let mut here = nc_kernel::AxisPos {
        geo: [30.0, 0.0, 100.0],
        ..Default::default()
    };
    here.add[5] = 90.0;
    let r = nc_kernel::Preparation::resume(
        "t.nc",
        text,
        &md,
        &tools,
        None,
        nc_kernel::Interruption::contour(4, 0.5),
        here,
    )
    .unwrap();
    // The reposition move says where the additional axes stand and stay: C at 90, not the
    // 0 the program was loaded at.
    match &r.first[0] {
        nc_kernel::Prepared::Axes(m, _) => {
            assert_eq!((m.from[5], m.to[5]), (90.0, 90.0));
        }
        other => panic!("an axes record first, not {other:?}"),
    }
}
