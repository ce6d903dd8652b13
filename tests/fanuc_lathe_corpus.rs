//! Turning programs for the Fanuc lathe (config/fanuc-lathe.toml: G-code system A, X as a
//! diameter, U/W incremental, increment input) in tests/corpus/fanuc-lathe/. Every move's
//! end point is compared with values worked out by hand: X in the blocks is the radius
//! (diameter / 2), machine coordinates (the work offset is zero; G50 shifts the zero).
//! Programs that run cleanly also pass `softnc check` (nose radius compensation and the
//! gouge check included).
//!
//! LinuxCNC's rs274 is no oracle here: its U and W are axes of their own, not X and Z
//! incremental, and it has no T aabb offsets.

use nc_kernel::{AlarmCode, Block, Interpreter, MachineData, ToolTable};
use std::path::PathBuf;
use std::process::Command;

type P = [f64; 3];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn path_of(file: &str) -> PathBuf {
    root().join("tests/corpus/fanuc-lathe").join(file)
}

fn machine() -> MachineData {
    MachineData::load(Some(&root().join("config/fanuc-lathe.toml")), &[]).expect("machine data")
}

/// The blocks up to the end or the first alarm.
fn run(file: &str) -> (Vec<Block>, Option<nc_kernel::Alarm>) {
    let text = std::fs::read_to_string(path_of(file)).unwrap();
    let (md, tools) = (machine(), ToolTable::builtin());
    let mut out = Vec::new();
    for item in Interpreter::new(file, &text, &md, &tools) {
        match item {
            Ok(b) => out.push(b),
            Err(a) => return (out, Some(a)),
        }
    }
    (out, None)
}

fn ends(b: &[Block]) -> Vec<P> {
    b.iter().filter_map(|b| b.motion.map(|m| m.end)).collect()
}

fn assert_ends(file: &str, got: &[P], want: &[P]) {
    assert_eq!(got.len(), want.len(), "{file}: {got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (0..3).all(|i| (g[i] - w[i]).abs() <= 1e-9),
            "{file}: move {k}: {g:?}, by hand {w:?}"
        );
    }
}

/// `softnc check` on the lathe machine passes.
fn check(file: &str) {
    check_at(&path_of(file));
}

/// `softnc check` of the program at `path` on the lathe machine passes.
fn check_at(path: &std::path::Path) {
    let file = path.display();
    let out = Command::new(env!("CARGO_BIN_EXE_softnc"))
        .arg("check")
        .arg(path)
        .arg("--machine")
        .arg(root().join("config/fanuc-lathe.toml"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{file}: {stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn clean(file: &str, want: &[P]) -> Vec<Block> {
    let (b, alarm) = run(file);
    if let Some(a) = alarm {
        panic!("{file}: {a}");
    }
    assert_ends(file, &ends(&b), want);
    check(file);
    b
}

#[test]
fn t01_shaft_finish_u_w() {
    let b = clean(
        "t01_shaft_finish_u_w.nc",
        &[
            [13.0, 0.0, 2.0],   // X26 Z2: radius 13
            [6.0, 0.0, 0.0],    // G42 X12 Z0
            [8.0, 0.0, -2.0],   // X16 W-2: chamfer, Z 0 − 2
            [8.0, 0.0, -15.0],  // Z-15
            [12.0, 0.0, -15.0], // U8: radius 8 + 8/2
            [12.0, 0.0, -25.0], // W-10: −15 − 10
            [17.0, 0.0, -30.0], // G2 X34 W-5 R5: radius 17, Z −25 − 5
            [17.0, 0.0, -45.0], // Z-45
            [22.0, 0.0, 2.0],   // G40 U10 Z2: radius 17 + 10/2
        ],
    );
    // T0101: T1 D1 of the tool table, the 0.8 mm nose in edge position 3; G42 in force.
    let contour = &b[6];
    assert_eq!((contour.modal.tool, contour.modal.d), (Some(1), 1));
    assert_eq!((contour.modal.radius, contour.modal.edge), (0.8, 3));
    assert_eq!(contour.modal.trc, nc_kernel::TrcSide::Right);
    assert_eq!(contour.modal.spindle_limit, 3000.0);
}

#[test]
fn t02_facing_passes_while() {
    // Four passes of 0.5 (#1 = 0.5 … 2.0): Z = 2 − #1, across to X−1.6 (radius −0.8),
    // back 1 mm in Z (W1), out to X44 (radius 22).
    let mut want = vec![[22.0, 0.0, 5.0]];
    for z in [1.5, 1.0, 0.5, 0.0] {
        want.extend([
            [22.0, 0.0, z],
            [-0.8, 0.0, z],
            [-0.8, 0.0, z + 1.0],
            [22.0, 0.0, z + 1.0],
        ]);
    }
    let b = clean("t02_facing_passes_while.nc", &want);
    assert!(
        b.iter().any(|b| b.modal.feed_per_rev),
        "G99: feed per revolution"
    );
}

#[test]
fn t03_grooves_m98_repeat() {
    // X32 is radius 16; each pass: U-6 down to radius 13, dwell, U6 back to 16, W-8 on.
    let mut want = vec![[16.0, 0.0, -10.0]];
    for z in [-10.0, -18.0, -26.0] {
        want.extend([[13.0, 0.0, z], [16.0, 0.0, z], [16.0, 0.0, z - 8.0]]);
    }
    want.push([30.0, 0.0, 20.0]); // X60 Z20
    let b = clean("t03_grooves_m98_repeat.nc", &want);
    let dwells: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
    assert_eq!(dwells, [0.3, 0.3, 0.3]);
}

#[test]
fn t04_reference_and_g50() {
    clean(
        "t04_reference_and_g50.nc",
        &[
            [0.0, 0.0, 0.0],    // G28 U0 W0: the intermediate point is where the tool is
            [60.0, 0.0, 100.0], // then the reference: X 60 (radius), Z 100 (machine data)
            [20.0, 0.0, -95.0], // after G50 X120 Z200 there: zero X 60 − 60 = 0, Z 100 − 200 = −100
            [25.0, 0.0, -95.0], // G28 U10: radius 20 + 5 first
            [60.0, 0.0, 100.0], // then the reference again
            [25.0, 0.0, -90.0], // X50 Z10: radius 25, Z 10 − 100
        ],
    );
}

#[test]
fn t05_taper_g65_macro() {
    clean(
        "t05_taper_g65_macro.nc",
        &[
            [10.0, 0.0, 2.0],   // X#1 = A20: radius 10
            [10.0, 0.0, 0.0],   // Z0
            [15.0, 0.0, -25.0], // X#2 = B30 (radius 15), W-#3 = −25
            [20.0, 0.0, -25.0], // U10: radius + 5
            [20.0, 0.0, 2.0],   // Z2
            [30.0, 0.0, 10.0],  // back in the main program: X60 Z10
        ],
    );
}

#[test]
fn t06_chamfer_corner_r() {
    // A shaft turned under G42 with ,C and ,R (0i-TF "Optional angle chamfering and corner
    // rounding"): X is a diameter, the ,C and ,R values are lengths (not halved). Each
    // element comes between its block's move and the next; (X radius, Z) below.
    let r5 = 5f64.sqrt();
    let b = clean(
        "t06_chamfer_corner_r.nc",
        &[
            [5.0, 0.0, 2.0],    // X10 Z2: radius 5
            [5.0, 0.0, 0.0],    // G42 Z0
            [9.0, 0.0, 0.0],    // X20 ,C1: 1 before the corner (10, 0) …
            [10.0, 0.0, -1.0],  // … the chamfer to 1 after it
            [10.0, 0.0, -13.0], // Z-15 ,R2 into X30 (a right turn in the Z-X plane) …
            [12.0, 0.0, -15.0], // … about (12, −13)
            [13.5, 0.0, -15.0], // X30 ,C1.5: radius 15, 1.5 before
            [15.0, 0.0, -16.5], // the chamfer
            // W-15 ,R2 into G3 X40 Z-35 R5 (about (15, −35), leaving the corner (15, −30)
            // along +X: a right turn). The R2 centre is 2 above radius 15 and 5 + 2 from
            // (15, −35): Z = −35 + √(7² − 2²) = −35 + 3√5.
            [15.0, 0.0, -35.0 + 3.0 * r5],
            // It touches the arc at (15, −35) + 5/7·(2, 3√5).
            [15.0 + 10.0 / 7.0, 0.0, -35.0 + 15.0 * r5 / 7.0],
            [20.0, 0.0, -35.0], // G3 X40 Z-35 R5
            [20.0, 0.0, -45.0], // Z-45
            [25.0, 0.0, 2.0],   // G40 U10 Z2
        ],
    );
    // The roundings are blocks of the lines that carry ,R (10 and 12), clockwise in Z-X.
    let rounds: Vec<(u32, [f64; 3])> = b
        .iter()
        .filter_map(|b| {
            b.motion
                .filter(|m| m.kind.is_arc())
                .map(|m| (b.line, m.center))
        })
        .collect();
    assert_eq!(rounds[0], (10, [12.0, 0.0, -13.0]));
    assert_eq!(rounds[1].0, 12);
    assert!((rounds[1].1[2] - (-35.0 + 3.0 * r5)).abs() < 1e-9 && rounds[1].1[0] == 17.0);
}

#[test]
fn t08_g71_arc_increments() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let fillet = |level: f64| -10.0 - (100.0 - (level - 20.0f64).powi(2)).sqrt();
    let mut want = vec![[25.0, 0.0, 1.0]];
    for (level, z) in [
        (22.0, -35.0),
        (19.0, fillet(19.0)),
        (16.0, fillet(16.0)),
        (13.0, fillet(13.0)),
    ] {
        want.extend([
            [level, 0.0, 1.0],           // in at the feed (N30 is G01)
            [level, 0.0, z],             // along Z to the shape
            [level + 0.5, 0.0, z + 0.5], // retract 0.5 at 45°
            [level + 0.5, 0.0, 1.0],     // back to Z 1
        ]);
    }
    want.extend([
        [10.0, 0.0, 1.0],   // A'
        [10.0, 0.0, -10.0], // W-11000: 11 mm
        [20.0, 0.0, -20.0], // the fillet
        [20.0, 0.0, -35.0],
        [25.0, 0.0, -35.0], // U10: 5 on the radius, at the start's X: no X move home
        [25.0, 0.0, 1.0],   // back to A
        [40.0, 0.0, 30.0],  // G0 X80 Z30
    ]);
    let b = clean("t08_g71_arc_increments.nc", &want);
    let arc = b
        .iter()
        .filter_map(|b| b.motion)
        .find(|m| m.kind.is_arc())
        .unwrap();
    assert_eq!(arc.center, [20.0, 0.0, -10.0]);
    assert_eq!(arc.kind, nc_kernel::MotionKind::ArcCw);
}

#[test]
fn a01_lathe_cycle_refused() {
    let (b, alarm) = run("a01_lathe_cycle_refused.nc");
    assert_ends("a01", &ends(&b), &[[20.0, 0.0, 2.0]]);
    // G73 U2. W1. R0: no passes; the alarm points at R (column 13).
    let a = alarm.expect("G73 R0 is refused");
    assert_eq!((a.code, a.line, a.col), (AlarmCode::BadNumber, 6, 13));
}

#[test]
fn t09_g72_g70_face() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let arc = |level: f64| 20.2 - (36.0 - (level - 0.2f64).powi(2)).sqrt();
    let mut want = vec![[22.0, 0.0, 2.0]]; // G0 X44 Z2: the start point A
    for level in [0.0, -2.0, -4.0] {
        let x = arc(level);
        want.extend([
            [22.0, 0.0, level],          // in along Z at rapid (N10 is G00)
            [x, 0.0, level],             // across at F0.2 to the moved arc
            [x + 0.5, 0.0, level + 0.5], // out by R0.5 at 45°
            [22.0, 0.0, level + 0.5],    // back to A's X
        ]);
    }
    want.extend([
        [22.2, 0.0, -5.8], // the moved shape: A'
        [20.2, 0.0, -5.8],
        [14.2, 0.0, 0.2], // the arc about (20.2, 0.2)
        [5.2, 0.0, 0.2],
        [0.2, 0.0, 1.2],
        [0.2, 0.0, 2.0],   // home: Z first (the depth axis of facing) …
        [22.0, 0.0, 2.0],  // … then X
        [22.0, 0.0, -6.0], // G70: the shape as written
        [20.0, 0.0, -6.0],
        [14.0, 0.0, 0.0],
        [5.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [22.0, 0.0, 1.0], // home X first, then Z
        [22.0, 0.0, 2.0],
        [50.0, 0.0, 50.0], // G0 X100 Z50
    ]);
    let b = clean("t09_g72_g70_face.nc", &want);
    let arcs: Vec<(u32, [f64; 3], nc_kernel::MotionKind)> = b
        .iter()
        .filter_map(|b| {
            b.motion
                .filter(|m| m.kind.is_arc())
                .map(|m| (b.line, m.center, m.kind))
        })
        .collect();
    // The roughing's arc is the moved one, G70's the programmed one; both counter-clockwise.
    assert_eq!(arcs.len(), 2);
    assert!((arcs[0].1[0] - 20.2).abs() < 1e-9 && (arcs[0].1[2] - 0.2).abs() < 1e-9);
    assert!((arcs[1].1[0] - 20.0).abs() < 1e-9 && arcs[1].1[2].abs() < 1e-9);
    assert!(arcs.iter().all(|a| a.2 == nc_kernel::MotionKind::ArcCcw));
    assert_eq!((arcs[0].0, arcs[1].0), (18, 24));
}

#[test]
fn t10_g73_g70_forging() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let mut want = vec![[30.0, 0.0, 3.0]]; // G0 X60 Z3: the start point A
    for (sx, sz) in [(3.2, 1.6), (1.7, 0.85), (0.2, 0.1)] {
        want.extend([
            [8.0 + sx, 0.0, 1.0 + sz], // A' moved, at rapid (N10 is G00)
            [8.0 + sx, 0.0, -8.0 + sz],
            [16.0 + sx, 0.0, -16.0 + sz], // the arc, its centre (16, -8) moved with it
            [16.0 + sx, 0.0, -24.0 + sz],
            [13.0 + sx, 0.0, -30.0 + sz],
            [30.0 + sx, 0.0, -30.0 + sz],
            [30.0, 0.0, -30.0 + sz], // home X first …
            [30.0, 0.0, 3.0],        // … then Z
        ]);
    }
    want.extend([
        [8.0, 0.0, 1.0], // G70: the shape as written
        [8.0, 0.0, -8.0],
        [16.0, 0.0, -16.0],
        [16.0, 0.0, -24.0],
        [13.0, 0.0, -30.0],
        [30.0, 0.0, -30.0], // at the start's X: home is Z alone
        [30.0, 0.0, 3.0],
        [50.0, 0.0, 50.0], // G0 X100 Z50
    ]);
    let b = clean("t10_g73_g70_forging.nc", &want);
    let centres: Vec<[f64; 3]> = b
        .iter()
        .filter_map(|b| b.motion.filter(|m| m.kind.is_arc()).map(|m| m.center))
        .collect();
    let by_hand = [(19.2, -6.4), (17.7, -7.15), (16.2, -7.9), (16.0, -8.0)];
    assert_eq!(centres.len(), 4);
    for (c, (x, z)) in centres.iter().zip(by_hand) {
        assert!((c[0] - x).abs() < 1e-9 && (c[2] - z).abs() < 1e-9, "{c:?}");
    }
    // The passes at the cycle's F0.25; G70 at the shape's F0.1.
    let feeds: Vec<(u32, f64)> = b
        .iter()
        .filter(|b| {
            b.motion
                .is_some_and(|m| m.kind != nc_kernel::MotionKind::Rapid)
        })
        .map(|b| (b.line, b.modal.feed))
        .collect();
    assert!(
        feeds
            .iter()
            .all(|&(l, f)| (l == 17 && f == 0.25) || (l == 24 && f == 0.1)),
        "{feeds:?}"
    );
}

#[test]
fn t11_g71_type_ii_pockets() {
    // The arithmetic is in the program's header; (X radius, Z) below. `on(p, q, x)`: the Z
    // of the line p–q at X = x.
    let on = |p: (f64, f64), q: (f64, f64), x: f64| p.1 + (x - p.0) * (q.1 - p.1) / (q.0 - p.0);
    let (down1, rise1) = (((10.2, -4.0), (4.2, -8.0)), ((4.2, -12.0), (12.2, -16.0)));
    let (down2, rise2) = (((12.2, -18.0), (6.2, -22.0)), ((6.2, -26.0), (16.2, -30.0)));
    let z = |l: ((f64, f64), (f64, f64)), x: f64| on(l.0, l.1, x);
    let mut want = vec![[20.0, 0.0, 2.0]]; // G0 X40 Z2: the start point A
                                           // Levels 17 and 14 (in at rapid: the stretch begins on N10's G00 move).
    want.extend([[17.0, 0.0, 2.0], [17.0, 0.0, -30.0], [17.5, 0.0, -29.5]]);
    let e14 = z(rise2, 14.0); // level 14 meets the last rise (it ends at 16.2)
    want.extend([
        [17.5, 0.0, 2.0],
        [14.0, 0.0, 2.0],
        [14.0, 0.0, e14],
        [14.5, 0.0, e14 + 0.5],
    ]);
    // Level 11: back to Z 2 at X 14.5 (the top over the way is the bump, 7.8 below A, and
    // the rise at the retract point: level 6 is cut all along).
    let (e1, a2, e2) = (z(rise1, 11.0), z(down2, 11.0), z(rise2, 11.0));
    want.extend([
        [14.5, 0.0, 2.0],
        [11.0, 0.0, 2.0],
        [11.0, 0.0, e1],
        [11.5, 0.0, e1 + 0.5],
        [14.5, 0.0, e1 + 0.5], // over the bump (7.8 below A: level 6 cut there)
        [14.5, 0.0, a2],
        [14.0, 0.0, a2], // down to the level above at rapid
        [11.0, 0.0, a2], // in by 3 at the feed
        [11.0, 0.0, e2],
        [11.5, 0.0, e2 + 0.5],
    ]);
    // Level 8, both pockets; level 5, the first only (the second's bottom is 6.2).
    for (level, pockets) in [
        (8.0, vec![(down1, rise1), (down2, rise2)]),
        (5.0, vec![(down1, rise1)]),
    ] {
        for (d, r) in pockets {
            let (a, b) = (z(d, level), z(r, level));
            let at = *want.last().unwrap();
            want.extend([
                [14.5, 0.0, at[2]],
                [14.5, 0.0, a],
                [level + 3.0, 0.0, a],
                [level, 0.0, a],
                [level, 0.0, b],
                [level + 0.5, 0.0, b + 0.5],
            ]);
        }
    }
    let last = want.last().unwrap()[2];
    want.extend([
        [11.5, 0.0, last], // back to A over X 11.5 (the top is 9.8 below A: level 9)
        [11.5, 0.0, 2.0],
        [20.0, 0.0, 2.0],
    ]);
    let shape = [
        (10.0, 2.0),
        (10.0, -4.0),
        (4.0, -8.0),
        (4.0, -12.0),
        (12.0, -16.0),
        (12.0, -18.0),
        (6.0, -22.0),
        (6.0, -26.0),
        (16.0, -30.0),
        (20.0, -30.0),
    ];
    want.extend(shape.iter().map(|&(x, z)| [x + 0.2, 0.0, z])); // moved by U0.4
    want.extend([[20.0, 0.0, -30.0], [20.0, 0.0, 2.0]]); // home, X first
    want.extend(shape.iter().map(|&(x, z)| [x, 0.0, z])); // G70
    want.extend([[20.0, 0.0, 2.0], [40.0, 0.0, 50.0]]);
    clean("t11_g71_type_ii_pockets.nc", &want);
}

#[test]
fn t12_g70_nose_radius_compensation() {
    // The arithmetic is in the program's header; (X radius, Z) below. `softnc check`
    // prepares the compensated path (nose 0.8, edge position 3) without a violation.
    let b = clean(
        "t12_g70_nose_radius_compensation.nc",
        &[
            [22.0, 0.0, 2.0],   // G0 X44 Z2: the start point A
            [8.0, 0.0, 2.0],    // N10 G42: A'
            [8.0, 0.0, -10.0],  // Z-10
            [12.0, 0.0, -18.0], // X24 Z-18
            [12.0, 0.0, -30.0], // Z-30
            [22.0, 0.0, -30.0], // N20 G40 X44
            [22.0, 0.0, 2.0],   // back to A: Z alone
            [40.0, 0.0, 50.0],  // G0 X80 Z50
        ],
    );
    let sides: Vec<(Option<nc_kernel::TrcSide>, nc_kernel::TrcSide)> = b
        .iter()
        .filter(|b| b.motion.is_some())
        .map(|b| (b.trc, b.modal.trc))
        .collect();
    let (r, off) = (nc_kernel::TrcSide::Right, nc_kernel::TrcSide::Off);
    assert_eq!(
        sides,
        [
            (None, off),
            (Some(r), r),
            (None, r),
            (None, r),
            (None, r),
            (Some(off), off),
            (None, off),
            (None, off),
        ]
    );
}

#[test]
fn t07_g71_g70_shaft() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let pass = |level: f64, z: f64| {
        [
            [level, 0.0, 2.0],           // in at rapid (N10 is G00) to the level
            [level, 0.0, z],             // along Z to the offset shape
            [level + 1.0, 0.0, z + 1.0], // retract R1 at 45°
            [level + 1.0, 0.0, 2.0],     // back to the start's Z
        ]
    };
    let mut want = vec![[20.0, 0.0, 2.0]]; // G0 X40 Z2: the start point A
    for (level, z) in [(18.0, -29.8), (16.0, -29.8), (14.0, -17.4), (12.0, -13.4)] {
        want.extend(pass(level, z));
    }
    want.extend([
        // along the shape offset by U0.4 (0.2 on the radius) and W0.2
        [10.2, 0.0, 2.2],
        [10.2, 0.0, -9.8],
        [15.2, 0.0, -19.8],
        [15.2, 0.0, -29.8],
        [20.2, 0.0, -29.8],
        // back to A at rapid, X first
        [20.0, 0.0, -29.8],
        [20.0, 0.0, 2.0],
        // G70: the shape as written, then back to A
        [10.0, 0.0, 2.0],
        [10.0, 0.0, -10.0],
        [15.0, 0.0, -20.0],
        [15.0, 0.0, -30.0],
        [20.0, 0.0, -30.0],
        [20.0, 0.0, 2.0],
        [30.0, 0.0, 20.0], // G0 X60 Z20 after G70
    ]);
    let (b, alarm) = run("t07_g71_g70_shaft.nc");
    assert!(alarm.is_none(), "{alarm:?}");
    let got = ends(&b);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(
            (0..3).all(|i| (g[i] - w[i]).abs() <= 1e-9),
            "move {k}: {g:?}, by hand {w:?}"
        );
    }
    check("t07_g71_g70_shaft.nc");
    // Roughing at the G71 block's F0.25; G70 at the shape's F0.1 and S220.
    let feeds: Vec<(u32, f64)> = b
        .iter()
        .filter(|b| {
            b.motion
                .is_some_and(|m| m.kind == nc_kernel::MotionKind::Linear)
        })
        .map(|b| (b.line, b.modal.feed))
        .collect();
    assert!(
        feeds
            .iter()
            .all(|&(l, f)| (l == 17 && f == 0.25) || (l == 23 && f == 0.1)),
        "{feeds:?}"
    );
    let s220 = b.iter().any(|b| {
        b.line == 23
            && b.words
                .iter()
                .any(|w| w.address == b'S' && w.value == 220.0)
    });
    assert!(s220, "G70 gives the shape's S");
    // The passes stop at every corner; the shape runs as a path (the modal G64 decides).
    let stops: Vec<bool> = b
        .iter()
        .filter(|b| {
            b.motion
                .is_some_and(|m| m.kind == nc_kernel::MotionKind::Linear)
        })
        .map(|b| b.exact_stop)
        .collect();
    assert_eq!(stops[..2], [true, true], "{stops:?}");
    assert!(stops[stops.len() - 4..].iter().all(|s| !s), "{stops:?}");
}

#[test]
fn sample_shaft_rough_finish_checks_clean() {
    // programs/fanuc-lathe/shaft_rough_finish.nc: A = X44 Z2 (radius 22), A' = X12 (6) moved
    // by U0.4 to 6.2; depth 2: levels 20, 18 … 8 (15.8 / 2 rounded up less 1 = 7 passes),
    // each ending in a 45° retract of R0.5.
    let file = root().join("programs/fanuc-lathe/shaft_rough_finish.nc");
    let text = std::fs::read_to_string(&file).unwrap();
    let (md, tools) = (machine(), ToolTable::builtin());
    let blocks: Vec<Block> = Interpreter::new("shaft", &text, &md, &tools)
        .collect::<Result<_, _>>()
        .unwrap_or_else(|a| panic!("{a}"));
    let retracts = blocks
        .iter()
        .filter_map(|b| b.motion)
        .filter(|m| {
            let (dx, dz) = (m.end[0] - m.start[0], m.end[2] - m.start[2]);
            m.kind == nc_kernel::MotionKind::Rapid
                && (dx - 0.5).abs() < 1e-9
                && (dz - 0.5).abs() < 1e-9
        })
        .count();
    assert_eq!(retracts, 7);
    check_at(&file);
}

#[test]
fn sample_flange_face_checks_clean() {
    // programs/fanuc-lathe/flange_face_rough_finish.nc: A = X84 Z2 (Z 2), A' at Z -6 moved
    // by W0.1 to -5.9; depth 1.5 along Z: levels 0.5, -1, -2.5, -4, -5.5 (7.9 / 1.5 rounded
    // up less 1 = 5 passes), each ending in a 45° retract of R0.5 (X and Z up).
    let file = root().join("programs/fanuc-lathe/flange_face_rough_finish.nc");
    let text = std::fs::read_to_string(&file).unwrap();
    let (md, tools) = (machine(), ToolTable::builtin());
    let blocks: Vec<Block> = Interpreter::new("flange", &text, &md, &tools)
        .collect::<Result<_, _>>()
        .unwrap_or_else(|a| panic!("{a}"));
    let levels: Vec<f64> = blocks
        .iter()
        .filter_map(|b| b.motion)
        .filter(|m| {
            let (dx, dz) = (m.end[0] - m.start[0], m.end[2] - m.start[2]);
            m.kind == nc_kernel::MotionKind::Rapid
                && (dx - 0.5).abs() < 1e-9
                && (dz - 0.5).abs() < 1e-9
        })
        .map(|m| m.start[2])
        .collect();
    assert_eq!(levels.len(), 5, "{levels:?}");
    for (got, want) in levels.iter().zip([0.5, -1.0, -2.5, -4.0, -5.5]) {
        assert!((got - want).abs() < 1e-9, "{levels:?}");
    }
    check_at(&file);
}

/// The path feed per revolution of each thread block, in order.
fn thread_feeds(b: &[Block]) -> Vec<f64> {
    b.iter().filter_map(|b| b.thread).collect()
}

#[test]
fn t20_g32_threads() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let mut want = vec![[12.0, 0.0, 5.0]];
    for (x0, x1) in [(9.6, 9.6), (9.3, 9.3), (8.9, 9.9)] {
        want.extend([
            [x0, 0.0, 5.0],
            [x1, 0.0, -30.0],
            [12.0, 0.0, -30.0],
            [12.0, 0.0, 5.0],
        ]);
    }
    want.push([30.0, 0.0, 20.0]);
    let b = clean("t20_g32_threads.nc", &want);
    let f = thread_feeds(&b);
    assert_eq!(f[..2], [2.0, 2.0]);
    assert!((f[2] - 2.0 * 1226f64.sqrt() / 35.0).abs() < 1e-12);
    assert!((f[2] - 2.000816).abs() < 1e-6);
}

#[test]
fn t21_g92_thread() {
    let mut want = vec![[17.5, 0.0, 4.0]];
    for x in [14.65, 14.45, 14.25, 14.1, 14.025] {
        want.extend([
            [x, 0.0, 4.0],
            [x, 0.0, -25.0],
            [17.5, 0.0, -25.0],
            [17.5, 0.0, 4.0],
        ]);
    }
    // The spring pass with the chamfer of 1.5.
    want.extend([
        [14.025, 0.0, 4.0],
        [14.025, 0.0, -23.5],
        [15.525, 0.0, -25.0],
        [17.5, 0.0, -25.0],
        [17.5, 0.0, 4.0],
        [30.0, 0.0, 20.0],
    ]);
    let b = clean("t21_g92_thread.nc", &want);
    // Five straight threads at 1.5, the spring pass's thread, its 45° chamfer at 1.5·√2.
    let f = thread_feeds(&b);
    assert_eq!(f.len(), 7);
    assert!(f[..6].iter().all(|&v| v == 1.5));
    assert!((f[6] - 1.5 * 2f64.sqrt()).abs() < 1e-12);
}

#[test]
fn t22_g76_thread() {
    let depths = [
        0.3,
        0.424264069,
        0.524264069,
        0.624264069,
        0.724264069,
        0.824264069,
        0.924264069,
        1.024264069,
        1.124264069,
        1.15,
        1.2,
        1.2,
    ];
    let tan30 = 0.577350269;
    let mut want = vec![[14.0, 0.0, 5.0]];
    for d in depths {
        let (x, s) = (10.8 + (1.2 - d), (1.2 - d) * tan30);
        want.extend([
            [x, 0.0, 5.0 + s],
            [x, 0.0, -20.0 + s],
            [14.0, 0.0, -20.0 + s],
            [14.0, 0.0, 5.0],
        ]);
    }
    want.push([30.0, 0.0, 20.0]);
    // The depths are written to 1e-9 above: compare to 1e-8.
    let (b, alarm) = run("t22_g76_thread.nc");
    assert!(alarm.is_none(), "{alarm:?}");
    let got = ends(&b);
    assert_eq!(got.len(), want.len());
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(
            (0..3).all(|i| (g[i] - w[i]).abs() < 1e-8),
            "move {k}: {g:?} {w:?}"
        );
    }
    check("t22_g76_thread.nc");
    assert_eq!(thread_feeds(&b), [2.0; 12]);
}

#[test]
fn t23_g90_g94_boxes() {
    let mut want = vec![[26.0, 0.0, 2.0]];
    for (start, x) in [(23.0, 23.0), (21.0, 21.0), (18.0, 20.0)] {
        want.extend([
            [start, 0.0, 2.0],
            [x, 0.0, -30.0],
            [26.0, 0.0, -30.0],
            [26.0, 0.0, 2.0],
        ]);
    }
    want.push([27.5, 0.0, 3.0]);
    for (start, z) in [(-1.0, -1.0), (-2.0, -2.0), (-4.0, -3.0)] {
        want.extend([
            [27.5, 0.0, start],
            [10.0, 0.0, z],
            [10.0, 0.0, 3.0],
            [27.5, 0.0, 3.0],
        ]);
    }
    want.push([30.0, 0.0, 20.0]);
    let b = clean("t23_g90_g94_boxes.nc", &want);
    assert!(b.iter().all(|b| b.thread.is_none()));
}

#[test]
fn t24_g74_g75_pecks() {
    let mut want = vec![[21.0, 0.0, -15.0]];
    for (z, next) in [(-15.0, -17.0), (-17.0, -19.0), (-19.0, -15.0)] {
        want.extend([
            [18.0, 0.0, z],
            [18.5, 0.0, z],
            [15.0, 0.0, z],
            [21.0, 0.0, z],
            [21.0, 0.0, next],
        ]);
    }
    want.extend([
        [0.0, 0.0, 2.0],
        [0.0, 0.0, -3.0],
        [0.0, 0.0, -2.0],
        [0.0, 0.0, -8.0],
        [0.0, 0.0, -7.0],
        [0.0, 0.0, -12.0],
        [0.0, 0.0, 2.0],
        [30.0, 0.0, 20.0],
    ]);
    clean("t24_g74_g75_pecks.nc", &want);
}

#[test]
fn t30_g71_g70_nose_radius_compensation() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let arc = |l: f64| -15.7 + (5.8f64 * 5.8 - (l - 14.4) * (l - 14.4)).sqrt();
    let mut want = vec![[22.0, 0.0, 2.0]];
    for l in [20.0, 18.0, 16.0, 14.0, 12.0] {
        let z = if l < 15.0 { -9.9 } else { arc(l) };
        want.extend([
            [l, 0.0, 2.0],
            [l, 0.0, z],
            [l + 1.0, 0.0, z + 1.0],
            [l + 1.0, 0.0, 2.0],
        ]);
    }
    want.extend([
        [10.2, 0.0, 1.3], // the run along the moved tip path
        [10.2, 0.0, -9.9],
        [14.4, 0.0, -9.9],
        [20.2, 0.0, -15.7],
        [20.2, 0.0, -25.7],
        [24.2, 0.0, -24.9],
        [22.0, 0.0, -24.9], // back to A, X first
        [22.0, 0.0, 2.0],
        [10.0, 0.0, 2.0], // G70: the shape as programmed, G42 ... G40
        [10.0, 0.0, -10.0],
        [15.0, 0.0, -10.0],
        [20.0, 0.0, -15.0],
        [20.0, 0.0, -25.0],
        [24.0, 0.0, -25.0],
        [22.0, 0.0, -25.0],
        [22.0, 0.0, 2.0],
        [40.0, 0.0, 50.0],
    ]);
    clean("t30_g71_g70_nose_radius_compensation.nc", &want);
}

#[test]
fn t30_g70_tip_path_is_the_roughing_run_without_the_allowances() {
    // Preparation compensates G70 (nose centre on the equidistant, tip = centre − (0.8,
    // 0.8)); the roughing run of G71 is that tip path moved by U0.4 W0.1 = (0.2, 0.1):
    // the front end's equidistant and preparation's compensation agree on every end point.
    let file = path_of("t30_g71_g70_nose_radius_compensation.nc");
    let text = std::fs::read_to_string(&file).unwrap();
    let segs = nc_kernel::prepare("t30", &text, &machine(), &ToolTable::builtin())
        .unwrap_or_else(|a| panic!("{a}"));
    let ends = |line: u32| -> Vec<[f64; 2]> {
        segs.iter()
            .filter(|s| s.source.line == line)
            .map(|s| [s.to[0], s.to[2]])
            .collect()
    };
    let (rough, finish) = (ends(22), ends(29));
    // The run: the six moves before the return to A; G70: the six after the start point.
    let run = &rough[rough.len() - 8..rough.len() - 2];
    assert_eq!(finish.len(), 8, "{finish:?}");
    for (r, f) in run.iter().zip(&finish[..6]) {
        assert!(
            (r[0] - 0.2 - f[0]).abs() < 1e-9 && (r[1] - 0.1 - f[1]).abs() < 1e-9,
            "roughing {r:?} less (0.2, 0.1) against G70's tip {f:?}"
        );
    }
    // And the tip at the arc's end lies 0.8 below and 0.8 towards −Z of the nose centre
    // on the radius 5.8 about (15, −15): (20.8 − 0.8, −15 − 0.8).
    assert!((finish[3][0] - 20.0).abs() < 1e-9 && (finish[3][1] + 15.8).abs() < 1e-9);
}

#[test]
fn t31_g72_g70_nose_radius_compensation() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let taper = |z: f64| 31.354066 - 2.5 * (z + 6.8);
    let mut want = vec![[42.0, 0.0, 2.0]];
    for z in [0.5, -1.0, -2.5, -4.0, -5.5] {
        let x = if z > -2.0 {
            9.2 + 0.2 * (z + 2.0)
        } else {
            taper(z)
        };
        want.extend([
            [42.0, 0.0, z],
            [x, 0.0, z],
            [x + 0.5, 0.0, z + 0.5],
            [42.0, 0.0, z + 0.5],
        ]);
    }
    want.extend([
        [41.2, 0.0, -6.0], // the run along the tip path
        [29.354066, 0.0, -6.0],
        [19.497113, 0.0, -2.057219],
        [19.2, 0.0, -2.0],
        [9.2, 0.0, -2.0],
        [10.0, 0.0, 2.0],
        [42.0, 0.0, 2.0],  // back to A: Z is there, X
        [42.0, 0.0, -6.0], // G70: the shape as programmed, G41 ... G40
        [30.0, 0.0, -6.0],
        [20.0, 0.0, -2.0],
        [10.0, 0.0, -2.0],
        [10.0, 0.0, 2.0],
        [42.0, 0.0, 2.0],
        [50.0, 0.0, 50.0],
    ]);
    // The header's decimals are rounded to 1e-6.
    let (b, alarm) = run("t31_g72_g70_nose_radius_compensation.nc");
    assert!(alarm.is_none(), "{alarm:?}");
    let got = ends(&b);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        let ok = (0..3).all(|i| (g[i] - w[i]).abs() < 1e-6);
        assert!(ok, "move {k}: {g:?}, by hand {w:?}");
    }
    check("t31_g72_g70_nose_radius_compensation.nc");
}

/// The prepared path of a corpus program: tool tip segments.
fn prepared(file: &str) -> Vec<nc_kernel::Segment> {
    let text = std::fs::read_to_string(path_of(file)).unwrap();
    nc_kernel::prepare(file, &text, &machine(), &ToolTable::builtin())
        .unwrap_or_else(|a| panic!("{a}"))
}

/// (X radius, Z) of each segment's end, and (centre X, Z, counter-clockwise) of an arc.
type Tip = ([f64; 2], Option<(f64, f64, bool)>);

fn tips_of_line(segs: &[nc_kernel::Segment], line: u32) -> Vec<Tip> {
    segs.iter()
        .filter(|s| s.source.line == line)
        .map(|s| {
            let arc = match s.shape {
                nc_kernel::Shape::Arc { center, ccw, .. } => Some((center[0], center[2], ccw)),
                nc_kernel::Shape::Line => None,
            };
            ([s.to[0], s.to[2]], arc)
        })
        .collect()
}

fn assert_tips(file: &str, got: &[Tip], want: &[Tip]) {
    assert_eq!(got.len(), want.len(), "{file}: {got:?}");
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        let arcs = match (g.1, w.1) {
            (Some(a), Some(b)) => near(a.0, b.0) && near(a.1, b.1) && a.2 == b.2,
            (a, b) => a.is_none() && b.is_none(),
        };
        let ok = near(g.0[0], w.0[0]) && near(g.0[1], w.0[1]) && arcs;
        assert!(ok, "{file}: segment {k}: {g:?}, by hand {w:?}");
    }
}

#[test]
fn t31_g70_tip_path_is_the_nose_centre_equidistant_shifted_to_the_tip() {
    // G70 (line 27) prepared with G41, nose 0.8, edge position 3 (tip = centre − (0.8,
    // 0.8)). The nose centre, left of travel: on the face along −X at Z −6 + 0.8; on the
    // taper (30, −6) → (20, −2), direction (Z, X) = (4, −10)/√116, moved along its left
    // normal (10, 4)/√116 by 0.8, which is 0.8·√116/4 = 0.2·√116 in X at a fixed Z: X =
    // 30 + 0.2√116 − 2.5(Z + 6); the concave corner with the face at Z −5.2: X = 28 +
    // 0.2√116; the taper's end (20 + 3.2/√116, −2 + 8/√116); the convex edge (20, −2)
    // rounded at 0.8 (a right turn in (Z, X): clockwise) to (20, −1.2); the face at Z −1.2
    // to X 10; the G40 block from there to the programmed (10, 2); home X first.
    let s = 116f64.sqrt();
    let file = "t31_g72_g70_nose_radius_compensation.nc";
    let want: [Tip; 7] = [
        ([42.0 - 0.8, -6.0], None), // the selection from A to the first S + v
        ([27.2 + 0.2 * s, -6.0], None),
        ([19.2 + 3.2 / s, -2.8 + 8.0 / s], None),
        ([19.2, -2.0], Some((19.2, -2.8, false))),
        ([9.2, -2.0], None),
        ([10.0, 2.0], None),
        ([42.0, 2.0], None),
    ];
    assert_tips(file, &tips_of_line(&prepared(file), 27), &want);
}

/// t32's moved tip path (X radius, Z): q = 0.8/√2, b = 0.8·√2; the header derives it.
fn t32_tip_path(u: f64) -> [[f64; 2]; 9] {
    let (q, b) = (0.8 / 2f64.sqrt(), 0.8 * 2f64.sqrt());
    [
        [12.0 + u, 1.2],
        [12.0 + u, -5.8],
        [11.2 + u + q, -5.8 - q],
        [6.0 + u, -11.0 - b],
        [6.0 + u, -16.6 + b],
        [11.2 + u + q, -21.8 + q],
        [12.0 + u, -21.8],
        [12.0 + u, -25.8],
        [20.0 + u, -25.0],
    ]
}

#[test]
fn t32_g71_type_ii_nose_radius_compensation() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let b = 0.8 * 2f64.sqrt();
    let (c1, c2) = (17.2 + b, -10.4 + b); // the moved tip path's flanks: X − Z, X + Z
    let p = |x: f64, z: f64| [x, 0.0, z];
    let (z15, z13) = (2.0 - 0.8 * 2.0 / 4.8, 2.0 - 0.8 * 4.0 / 4.8); // on N10's move
    let mut want = vec![
        p(17.0, 2.0),
        p(17.0, z15),
        p(15.0, z15), // in at rapid
        p(15.0, -25.52),
        p(15.5, -25.02),
        p(17.0, -25.02), // up to A's X: behind the ramp's end
        p(17.0, z13),
        p(13.0, z13),
        p(13.0, -25.72),
        p(13.5, -25.22),
        p(17.0, -25.22),
    ];
    for (level, over) in [(11.0, 17.0), (9.0, 11.5), (7.0, 9.5)] {
        let (z0, z1) = (level - c1, c2 - level);
        want.extend([
            p(over, z0),
            p(level + 2.0, z0), // down to the level above at rapid
            p(level, z0),       // in at F
            p(level, z1),
            p(level + 0.5, z1 + 0.5),
        ]);
    }
    want.extend([p(17.0, c2 - 7.0 + 0.5), p(17.0, 2.0)]);
    want.extend(t32_tip_path(0.2).map(|[x, z]| p(x, z)));
    want.extend([p(17.0, -25.0), p(17.0, 2.0)]);
    // G70: the shape as programmed, home X first; then G0 X80 Z50.
    want.extend(
        [
            (12.0, 2.0),
            (12.0, -5.0),
            (6.0, -11.0),
            (6.0, -15.0),
            (12.0, -21.0),
            (12.0, -25.0),
            (20.0, -25.0),
            (17.0, -25.0),
            (17.0, 2.0),
            (40.0, 50.0),
        ]
        .map(|(x, z)| p(x, z)),
    );
    clean("t32_g71_type_ii_nose_radius_compensation.nc", &want);
}

#[test]
fn t32_g70_tip_path_is_the_nose_centre_equidistant_shifted_to_the_tip() {
    // G70 (line 41) prepared with G42, nose 0.8, edge position 3: the tip path of the
    // header without the allowance, the convex edges rounded counter-clockwise about the
    // edges less (0.8, 0.8); then home X first.
    let file = "t32_g71_type_ii_nose_radius_compensation.nc";
    let t = t32_tip_path(0.0);
    let mut want: Vec<Tip> = t.iter().map(|&e| (e, None)).collect();
    want[2].1 = Some((11.2, -5.8, true));
    want[6].1 = Some((11.2, -21.8, true));
    want.extend([([17.0, -25.0], None), ([17.0, 2.0], None)]);
    assert_tips(file, &tips_of_line(&prepared(file), 41), &want);
}
