//! Differential test: the Fanuc lathe's G71 and G72 (type I; G71 type II by the stretches
//! each level cuts) and G70 against LinuxCNC 2.9's
//! `rs274`, which implements them with its own words (the shape in an `o… sub`, `G71 Q<sub> X Z I<depth>
//! R<retract>`). On shapes whose first element after A' runs along Z and without finishing
//! allowances, the two controls cut the same: every feed move (the roughing cuts, the run
//! along the shape, G70's path, each arc's centre and direction) and every 45° retract point
//! agree to 2e-4 mm (rs274 prints four decimals). Where they differ by design
//! (docs/turning.md, "G71/G72/G70 and LinuxCNC"):
//! - rs274 makes a first cut at the start point's X (G72: Z), which removes nothing: left
//!   out here;
//! - its return after a retract goes to the start's Z less R, then in; softnc (a Fanuc) goes
//!   back to the start's Z, then in: the rapids differ and are not compared;
//! - its stock allowance D is an equidistant, not Fanuc's U/W shift: no allowances here;
//! - a Fanuc returns to the start point after G70, rs274 stays at the shape's end.
//!
//! Threads: Fanuc G32 (and G92's thread) against LinuxCNC's G33 on straight threads and
//! tapers whose longer axis is Z: both synchronise Z at the lead per revolution; every end
//! point and the lead agree (rs274's G33 K is along Z; softnc's path feed per revolution
//! times Δz over the path's length gives it back). Fanuc G76 is compared in docs/turning.md
//! only: rs274's G76 has another format and infeed rule. SINUMERIK CYCLE97 at a constant
//! cross-section cuts at the depths of rs274's G76 with degression 2: their cuts agree.
//! The 808D's CYCLE95 (longitudinal, complete machining) is compared the same way: its S is
//! rs274's start point and MID divides the stock into rs274's depth I; its FAL (the
//! contour's equidistant) against rs274's stock allowance D; its transverse machining
//! (VARI 10) against rs274's G72/G70, and its undercuts by the stretches each level cuts
//! against rs274's G71 over pockets.
//!
//! Without `rs274` on the PATH the test says so and passes, unless SOFTNC_REQUIRE_ORACLES is
//! set.

#[path = "support/rs274.rs"]
mod rs274;

use nc_kernel::{interpret, MachineData, MotionKind, ToolTable};
use std::path::Path;

const TOL: f64 = 2e-4;

/// A move in (X radius, Z): its end, and an arc's centre and direction (0 for a line).
#[derive(Clone, Copy, Debug)]
struct Move {
    end: [f64; 2],
    centre: [f64; 2],
    turn: i8,
    rapid: bool,
}

/// The moves of `text` on the machine of data file `machine` (relative to the repository).
fn softnc_on(machine: &str, text: &str) -> Vec<Move> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(machine);
    let md = MachineData::load(Some(&path), &[]).unwrap();
    let blocks =
        interpret("g71.nc", text, &md, &ToolTable::builtin()).unwrap_or_else(|a| panic!("{a}"));
    blocks
        .iter()
        .filter_map(|b| b.motion)
        .map(|m| Move {
            end: [m.end[0], m.end[2]],
            centre: [m.center[0], m.center[2]],
            turn: match m.kind {
                MotionKind::ArcCw => -1,
                MotionKind::ArcCcw => 1,
                _ => 0,
            },
            rapid: m.kind == MotionKind::Rapid,
        })
        .collect()
}

fn oracle(ngc: &str, tag: &str) -> Vec<Move> {
    let (text, status) = rs274::output(ngc, tag, None);
    let mut out = Vec::new();
    for line in text.lines() {
        let call = line.split_whitespace().nth(2).unwrap_or("");
        if call.starts_with("STRAIGHT_FEED") || call.starts_with("STRAIGHT_TRAVERSE") {
            let n = rs274::numbers(line);
            out.push(Move {
                end: [n[0], n[2]],
                centre: [n[0], n[2]],
                turn: 0,
                rapid: call.starts_with("STRAIGHT_TRAVERSE"),
            });
        } else if call.starts_with("ARC_FEED") {
            // In G18: end Z, end X, centre Z, centre X, rotation.
            let n = rs274::numbers(line);
            out.push(Move {
                end: [n[1], n[0]],
                centre: [n[3], n[2]],
                turn: n[4].signum() as i8,
                rapid: false,
            });
        }
    }
    assert!(!out.is_empty(), "rs274 gave no moves:\n{text}\n{status}");
    out
}

fn near(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() <= TOL && (a[1] - b[1]).abs() <= TOL
}

/// The feed moves, and the retract points (a rapid right after a straight feed). `depth` is
/// the axis the passes step along (0: X for G71, 1: Z for G72), `start` the start's value
/// on it.
fn cuts(moves: &[Move], depth: usize, start: f64) -> (Vec<Move>, Vec<[f64; 2]>) {
    let mut feeds = Vec::new();
    let mut retracts = Vec::new();
    let mut prev: Option<Move> = None;
    for m in moves {
        if !m.rapid {
            // rs274's first cut at the start's X removes nothing (module comment).
            let along_start = prev.is_some_and(|p| (p.end[depth] - start).abs() <= TOL)
                && (m.end[depth] - start).abs() <= TOL
                && m.turn == 0;
            if !along_start {
                feeds.push(*m);
            }
        } else if let Some(p) = prev.filter(|p| !p.rapid && p.turn == 0) {
            if (m.end[0] - p.end[0] - (m.end[1] - p.end[1])).abs() <= TOL && m.end[0] != p.end[0] {
                retracts.push(m.end);
            }
        }
        prev = Some(*m);
    }
    (feeds, retracts)
}

fn compare(tag: &str, fanuc: &str, ngc: &str, depth: usize, start: f64) {
    compare_on("config/fanuc-lathe.toml", tag, fanuc, ngc, depth, start);
}

fn compare_on(machine: &str, tag: &str, ours: &str, ngc: &str, depth: usize, start: f64) {
    if !rs274::present() {
        return;
    }
    let (ours, theirs) = (softnc_on(machine, ours), oracle(ngc, tag));
    let (f1, r1) = cuts(&ours, depth, start);
    let (f2, r2) = cuts(&theirs, depth, start);
    assert_eq!(
        f1.len(),
        f2.len(),
        "{tag}: feeds\nsoftnc {f1:?}\nrs274 {f2:?}"
    );
    for (k, (a, b)) in f1.iter().zip(&f2).enumerate() {
        let same =
            near(a.end, b.end) && a.turn == b.turn && (a.turn == 0 || near(a.centre, b.centre));
        assert!(same, "{tag}: feed {k}: softnc {a:?}, rs274 {b:?}");
    }
    for r in &r1 {
        assert!(
            r2.iter().any(|q| near(*q, *r)),
            "{tag}: retract {r:?} not in rs274's {r2:?}"
        );
    }
    assert!(!r1.is_empty(), "{tag}: no retracts found");
    eprintln!("{tag}: {} feeds, {} retracts agree", f1.len(), r1.len());
}

#[test]
fn g71_g70_over_a_fillet_agree_with_rs274() {
    let fanuc = "G18 G21 G99 S500 M3\nG0 X50. Z1.\nG71 U3. R0.5\nG71 P30 Q40 F0.3\n\
        N30 G0 X20.\nG1 Z-10.\nG2 X40. Z-20. R10.\nG1 Z-35.\nN40 X50.\n\
        G70 P30 Q40\nM30\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X50 Z1\no100 sub\nG0 X20 Z1\nG1 Z-10\n\
        G2 X40 Z-20 R10\nG1 Z-35\nG1 X50\no100 endsub\nG71 Q100 X50 Z1 I3 R0.5 F0.3\n\
        G70 Q100 X50 Z1 F0.3\nM2\n";
    compare("fillet", fanuc, ngc, 0, 25.0);
}

#[test]
fn g71_g70_over_a_taper_agree_with_rs274() {
    // Depth 1.5 into 10 on the radius: levels 18.5 … 11 (9.5 of them would reach 10).
    let fanuc = "G18 G21 G99 S500 M3\nG0 X40. Z2.\nG71 U1.5 R1.\nG71 P10 Q20 F0.25\n\
        N10 G0 X20.\nG1 Z-10.\nX30. Z-20.\nG3 X36. Z-23. R3.\nG1 Z-30.\nN20 X40.\n\
        G70 P10 Q20\nM30\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X40 Z2\no100 sub\nG0 X20 Z2\nG1 Z-10\n\
        X30 Z-20\nG3 X36 Z-23 R3\nG1 Z-30\nX40\no100 endsub\nG71 Q100 X40 Z2 I1.5 R1 F0.25\n\
        G70 Q100 X40 Z2 F0.25\nM2\n";
    compare("taper", fanuc, ngc, 0, 20.0);
}

#[test]
fn g72_g70_over_a_rounded_face_agree_with_rs274() {
    // Facing from (radius 20, Z 2) in passes of 2.5 along Z: levels -0.5, -3, -5.5 above A'
    // at Z -6; the face's rounding is a quarter circle about (radius 20, Z 0). The shape
    // ends at the start's Z (rs274 feeds from B to the start's Z, a Fanuc returns at rapid).
    let fanuc = "G18 G21 G99 S500 M3\nG0 X40. Z2.\nG72 W2.5 R0.5\nG72 P10 Q20 F0.2\n\
        N10 G0 Z-6.\nG3 X28. Z0. R6.\nG1 X0.\nN20 Z2.\nG70 P10 Q20\nM30\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X40 Z2\no100 sub\nG0 X40 Z-6\n\
        G3 X28 Z0 R6\nG1 X0\nZ2\no100 endsub\nG72 Q100 X40 Z2 I2.5 R0.5 F0.2\n\
        G70 Q100 X40 Z2 F0.2\nM2\n";
    compare("face", fanuc, ngc, 1, 2.0);
}

#[test]
fn g72_g70_over_a_convex_corner_and_a_taper_agree_with_rs274() {
    // Facing from (radius 30, Z 2), depth 2: levels 0, -2, -4, -6 above A' at Z -8. The
    // shape: along the back face to radius 20, a convex quarter circle G2 R6 about (14, -8)
    // up to (14, -2), a taper to (5, 0), the face to the centre, out to the start's Z.
    let fanuc = "G18 G21 G99 S500 M3\nG0 X60. Z2.\nG72 W2. R0.5\nG72 P10 Q20 F0.2\n\
        N10 G0 Z-8.\nG1 X40.\nG2 X28. Z-2. R6.\nG1 X10. Z0.\nX0.\nN20 Z2.\nG70 P10 Q20\nM30\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X60 Z2\no100 sub\nG0 X60 Z-8\nG1 X40\n\
        G2 X28 Z-2 R6\nG1 X10 Z0\nX0\nZ2\no100 endsub\nG72 Q100 X60 Z2 I2 R0.5 F0.2\n\
        G70 Q100 X60 Z2 F0.2\nM2\n";
    compare("corner", fanuc, ngc, 1, 2.0);
}

/// The stretches cut along Z at each level X of `levels`: the feeds parallel to Z there,
/// merged where they join, as (level, [(from Z, to Z)]) in the order cut.
fn level_cuts(moves: &[Move], levels: &[f64]) -> Vec<(f64, Vec<(f64, f64)>)> {
    let mut out: Vec<(f64, Vec<(f64, f64)>)> = levels.iter().map(|&l| (l, Vec::new())).collect();
    let mut at = [f64::NAN; 2];
    for m in moves {
        let along_z = !m.rapid && m.turn == 0 && (m.end[0] - at[0]).abs() <= TOL;
        if let Some((_, cuts)) = out
            .iter_mut()
            .find(|(l, _)| along_z && (l - m.end[0]).abs() <= TOL)
        {
            match cuts.last_mut() {
                Some(last) if (last.1 - at[1]).abs() <= TOL => last.1 = m.end[1],
                _ if (m.end[1] - at[1]).abs() > TOL => cuts.push((at[1], m.end[1])),
                _ => {}
            }
        }
        at = m.end;
    }
    out
}

/// Every level cuts something, and the same stretches in both.
fn same_stretches(ours: &[(f64, Vec<(f64, f64)>)], theirs: &[(f64, Vec<(f64, f64)>)]) {
    for ((level, a), (_, b)) in ours.iter().zip(theirs) {
        assert!(!a.is_empty(), "level {level}: nothing cut");
        let same = a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(p, q)| (p.0 - q.0).abs() <= TOL && (p.1 - q.1).abs() <= TOL);
        assert!(same, "level {level}: softnc {a:?}, rs274 {b:?}");
    }
}

#[test]
fn g71_type_ii_cuts_the_same_stretches_as_rs274() {
    // Two pockets (a cone and a half circle about (12, -22)), depth 3 from radius 20:
    // levels 17, 14, 11, 8, 5. rs274 cuts pocket by pocket and follows the contour into
    // and out of a pocket; softnc level by level (docs/turning.md, "Type II"). What each
    // level cuts along Z agrees; the ways between the stretches are not compared.
    if !rs274::present() {
        return;
    }
    let fanuc = "G18 G21 G99 S500 M3\nG0 X40. Z2.\nG71 U3. R0.5\nG71 P10 Q20 F0.2\n\
        N10 G0 X20. Z2.\nG1 Z-4.\nX8. Z-8.\nZ-12.\nX24. Z-16.\nZ-18.\nG2 Z-26. R4.\n\
        G1 X32. Z-30.\nN20 X40.\nM30\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X40 Z2\no100 sub\nG0 X20 Z2\nG1 Z-4\n\
        X8 Z-8\nZ-12\nX24 Z-16\nZ-18\nG2 X24 Z-26 R4\nG1 X32 Z-30\nX40\no100 endsub\n\
        G71 Q100 X40 Z2 I3 R0.5 F0.2\nM2\n";
    let levels = [17.0, 14.0, 11.0, 8.0, 5.0];
    let ours = level_cuts(&softnc_on("config/fanuc-lathe.toml", fanuc), &levels);
    let theirs = level_cuts(&oracle(ngc, "pockets"), &levels);
    same_stretches(&ours, &theirs);
    eprintln!("pockets: {ours:?}");
}

/// (end (X radius, Z), rapid, lead along Z for a thread) of every move.
type ThreadMove = ([f64; 2], bool, Option<f64>);

fn softnc_threads(text: &str) -> Vec<ThreadMove> {
    softnc_threads_on("config/fanuc-lathe.toml", text)
}

fn softnc_threads_on(machine: &str, text: &str) -> Vec<ThreadMove> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(machine);
    let md = MachineData::load(Some(&path), &[]).unwrap();
    let blocks =
        interpret("g32.nc", text, &md, &ToolTable::builtin()).unwrap_or_else(|a| panic!("{a}"));
    blocks
        .iter()
        .filter_map(|b| {
            let m = b.motion?;
            let d: [f64; 3] = std::array::from_fn(|i| m.end[i] - m.start[i]);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let lead = b.thread.map(|f| f * d[2].abs() / len);
            Some(([m.end[0], m.end[2]], m.kind == MotionKind::Rapid, lead))
        })
        .collect()
}

/// rs274's moves of `ngc`, its files named by `tag` (one per test: the tests run at once).
fn rs274_threads(ngc: &str, tag: &str) -> Vec<ThreadMove> {
    let (text, status) = rs274::output(ngc, tag, None);
    let mut out = Vec::new();
    let mut sync = None;
    for line in text.lines() {
        let call = line.split_whitespace().nth(2).unwrap_or("");
        if call.starts_with("START_SPEED_FEED_SYNC") {
            sync = rs274::numbers(call).first().copied();
        } else if call.starts_with("STOP_SPEED_FEED_SYNCH") {
            sync = None;
        } else if call.starts_with("STRAIGHT_FEED") || call.starts_with("STRAIGHT_TRAVERSE") {
            let n = rs274::numbers(line);
            let rapid = call.starts_with("STRAIGHT_TRAVERSE");
            out.push(([n[0], n[2]], rapid, if rapid { None } else { sync }));
        }
    }
    assert!(!out.is_empty(), "rs274 gave no moves:\n{text}\n{status}");
    out
}

#[test]
fn g32_and_g92_threads_agree_with_rs274_g33() {
    if !rs274::present() {
        return;
    }
    // A straight thread at 1.5, a taper (ΔX 3 on the radius over ΔZ 8) at 2, and a G92 box
    // at 1.25 from A (X34, Z5) written out with G33 for rs274.
    let fanuc = "G18 G21 G99 S600 M3\nG0 X30. Z3.\nG32 Z-20. F1.5\nG0 X40.\n\
        G32 X34. Z-28. F2.\nG0 Z5.\nG92 X36. Z-25. F1.25\nM30\n";
    let ngc = "G18 G7 G21 G90 S600 M3\nG0 X30 Z3\nG33 Z-20 K1.5\nG0 X40\n\
        G33 X34 Z-28 K2\nG0 Z5\nG0 X36\nG33 Z-25 K1.25\nG0 X34\nG0 Z5\nM2\n";
    let (ours, theirs) = (softnc_threads(fanuc), rs274_threads(ngc, "g33"));
    // rs274 starts its listing at the first move; softnc from machine zero alike.
    assert_eq!(
        ours.len(),
        theirs.len(),
        "softnc {ours:?}\nrs274 {theirs:?}"
    );
    for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        let lead_same = match (a.2, b.2) {
            (Some(x), Some(y)) => (x - y).abs() <= 1e-9,
            (None, None) => true,
            _ => false,
        };
        assert!(
            near(a.0, b.0) && a.1 == b.1 && lead_same,
            "move {k}: softnc {a:?}, rs274 {b:?}"
        );
    }
    assert_eq!(ours.iter().filter(|m| m.2.is_some()).count(), 3);
}

#[test]
fn cycle95_over_a_fillet_agrees_with_rs274() {
    // The 808D's CYCLE95 (complete machining, VARI 9) on the fillet shape with its start A'
    // at Z0: S = (the contour's largest X 25, 0 + _VRT 1) is rs274's start point; stock 15
    // in five equal cuts of MID 3 = rs274's I3: passes at 22, 19, 16, 13 lifted off by 1 =
    // R1. rs274 moves each in-feed along the line from its start to A' (Z 0.8, 0.6 …),
    // CYCLE95 in at S's Z 1: only the rapids differ (docs/turning.md, "CYCLE95 and
    // LinuxCNC").
    let sinumerik = "G18 G90 G95 S500 M3\nG0 X50 Z1\n\
        CYCLE95(\"C_A:C_E\", 3, , , , 0.3, , 0.1, 9, , , 1)\nM30\n\
        C_A: G1 X20 Z0\nZ-10\nG2 X40 Z-20 CR=10\nG1 Z-35\nC_E: X50\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X50 Z1\no100 sub\nG0 X20 Z0\nG1 Z-10\n\
        G2 X40 Z-20 R10\nG1 Z-35\nG1 X50\no100 endsub\nG71 Q100 X50 Z1 I3 R1 F0.3\n\
        G70 Q100 X50 Z1 F0.1\nM2\n";
    compare_on(
        "config/siemens-808d.toml",
        "cycle95",
        sinumerik,
        ngc,
        0,
        25.0,
    );
}

#[test]
fn cycle95_fal_agrees_with_rs274_stock_allowance() {
    // FAL is an equidistant as rs274's D (arcs about convex corners, concave ones trimmed):
    // roughing only (VARI 1) a taper shape, FAL 0.5 = D0.5; the shifted A' (10, 0) lies
    // 15 below S's X 25: five cuts of MID 3 = I3.
    let sinumerik = "G18 G90 G95 S500 M3\nG0 X50 Z1\n\
        CYCLE95(\"C_A:C_E\", 3, , , 0.5, 0.3, , , 1, , , 1)\nM30\n\
        C_A: G1 X19 Z0\nZ-10\nX40 Z-20\nZ-35\nC_E: X50\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X50 Z1\no100 sub\nG0 X19 Z0\nG1 Z-10\n\
        G1 X40 Z-20\nG1 Z-35\nG1 X50\no100 endsub\nG71 Q100 X50 Z1 I3 R1 D0.5 F0.3\nM2\n";
    compare_on(
        "config/siemens-808d.toml",
        "cycle95 FAL",
        sinumerik,
        ngc,
        0,
        25.0,
    );
}

#[test]
fn cycle95_face_machining_agrees_with_rs274_g72() {
    // The 808D's CYCLE95 transverse outside (VARI 10) on G72's rounded face, written from
    // the outer diameter at the deepest Z towards the centre: A' (radius 20, Z −6), the
    // quarter circle to (14, 0), the face to the centre. S = (A''s X + _VRT 0.5, the largest
    // Z 0) = (20.5, 0) is rs274's start point; stock 6 in Z in three equal cuts of MID 2 =
    // rs274's I2: passes at Z −2, −4, lifted off by 0.5 = R0.5 (Z up, X out).
    let sinumerik = "G18 G90 G95 S500 M3\nG0 X41 Z0\n\
        CYCLE95(\"C_A:C_E\", 2, , , , 0.3, , 0.1, 10, , , 0.5)\nM30\n\
        C_A: G1 X40 Z-6\nG3 X28 Z0 CR=6\nC_E: G1 X0\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X41 Z0\no100 sub\nG0 X40 Z-6\n\
        G3 X28 Z0 R6\nG1 X0\no100 endsub\nG72 Q100 X41 Z0 I2 R0.5 F0.3\n\
        G70 Q100 X41 Z0 F0.1\nM2\n";
    compare_on(
        "config/siemens-808d.toml",
        "cycle95 face",
        sinumerik,
        ngc,
        1,
        0.0,
    );
}

#[test]
fn cycle95_undercuts_cut_the_same_stretches_as_rs274() {
    // CYCLE95 (VARI 1) on the two pockets of the type II test, A' at Z 0 and the cone's
    // bottom at radius 5: S = (the largest X 20, 0 + _VRT 0.5); the deepest point lies 15
    // below S: five cuts of MID 3 = rs274's I3 from its start (20, 0.5), levels 17, 14,
    // 11, 8. Both bound the stock by the line from the start point to A'. What each level
    // cuts along Z agrees; the ways between the stretches differ (docs/turning.md).
    if !rs274::present() {
        return;
    }
    let sinumerik = "G18 G90 G95 S500 M3\nG0 X40 Z2\n\
        CYCLE95(\"C_A:C_E\", 3, , , , 0.2, , , 1, , , 0.5)\nM30\n\
        C_A: G1 X20 Z0\nZ-4\nX10 Z-8\nZ-12\nX24 Z-16\nZ-18\nG2 Z-26 CR=4\n\
        G1 X32 Z-30\nC_E: X40\n";
    let ngc = "G18 G7 G21 G90 G95 S500 M3\nG0 X40 Z0.5\no100 sub\nG0 X20 Z0\nG1 Z-4\n\
        X10 Z-8\nZ-12\nX24 Z-16\nZ-18\nG2 X24 Z-26 R4\nG1 X32 Z-30\nX40\no100 endsub\n\
        G71 Q100 X40 Z0.5 I3 R0.5 F0.2\nM2\n";
    let levels = [17.0, 14.0, 11.0, 8.0];
    let ours = level_cuts(&softnc_on("config/siemens-808d.toml", sinumerik), &levels);
    let theirs = level_cuts(&oracle(ngc, "cycle95 pockets"), &levels);
    same_stretches(&ours, &theirs);
    eprintln!("cycle95 pockets: {ours:?}");
}

/// (start, end, lead) of every thread move: its start is the end of the move before it.
fn thread_cuts(m: &[ThreadMove]) -> Vec<([f64; 2], [f64; 2], f64)> {
    m.windows(2)
        .filter_map(|w| w[1].2.map(|lead| (w[0].0, w[1].0, lead)))
        .collect()
}

#[test]
fn cycle97_constant_section_cuts_where_rs274_g76_cuts() {
    if !rs274::present() {
        return;
    }
    // SINUMERIK CYCLE97 VARI 3 (constant cross-section), TDEP 0.8, NRC 4, no allowance, no
    // idle pass: depths 0.8·√(n/4) = 0.4·√n. rs274's G76 with degression R2 cuts at J·√n up
    // to K; under G7 J and K are diameters (J0.8: 0.4, K1.6: 0.8 on the radius). Crest radius
    // 12 (rs274: X26 with I-2, a diameter), from Z6 to Z-43 at pitch 3: both cut at radius
    // 11.6, 11.434315, 11.307180, 11.2. The moves between the cuts differ (rs274 lifts to its
    // drive line, CYCLE97 to 1 mm over the crest): only the cuts are compared.
    let sinumerik = "G18 G90 G95 S400 M3\nG0 X26 Z6\n\
        CYCLE97(3, , 6, -43, 24, 24, 0, 0, 0.8, 0, 0, 0, 4, 0, 3)\nM30\n";
    let ngc = "G18 G7 G21 G90 S400 M3\nG0 X26 Z6\nG76 P3 Z-43 I-2 J0.8 R2 K1.6 Q0 H0 L0\nM2\n";
    let ours = thread_cuts(&softnc_threads_on("config/siemens-808d.toml", sinumerik));
    let theirs = thread_cuts(&rs274_threads(ngc, "g76"));
    assert_eq!(ours.len(), 4, "softnc {ours:?}");
    assert_eq!(
        ours.len(),
        theirs.len(),
        "softnc {ours:?}\nrs274 {theirs:?}"
    );
    for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        assert!(
            near(a.0, b.0) && near(a.1, b.1) && (a.2 - b.2).abs() <= 1e-9,
            "cut {k}: softnc {a:?}, rs274 {b:?}"
        );
    }
}
