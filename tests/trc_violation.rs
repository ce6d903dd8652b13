//! Contour violation (840C 11.12) with both machine-data reactions, and an arc lengthened
//! past a full turn at an obtuse circle transition (11.14). Expected positions by hand.

use nc_kernel::Prepared;
use nc_kernel::{AlarmCode, MachineData, Preparation, ToolTable};
use nc_kernel::{Role, Segment, Shape};

fn run(src: &str, md: &[&str]) -> (Vec<Prepared>, Option<nc_kernel::Alarm>) {
    let over: Vec<String> = md.iter().map(|s| s.to_string()).collect();
    run_with(src, &MachineData::load(None, &over).unwrap())
}

/// Every record up to the end or the alarm.
fn run_with(src: &str, md: &MachineData) -> (Vec<Prepared>, Option<nc_kernel::Alarm>) {
    let tools = ToolTable::builtin();
    let mut p = Preparation::new("t", src, md, &tools);
    let mut v = Vec::new();
    loop {
        match p.next_item() {
            Ok(Some(x)) => v.push(x),
            Ok(None) => return (v, None),
            Err(a) => return (v, Some(a)),
        }
    }
}

fn segments(items: &[Prepared]) -> Vec<&Segment> {
    items
        .iter()
        .filter_map(|x| match x {
            Prepared::Segment(s) => Some(s),
            _ => None,
        })
        .collect()
}

#[track_caller]
fn at(p: [f64; 3], x: f64, y: f64) {
    assert!(
        (p[0] - x).abs() < 1e-9 && (p[1] - y).abs() < 1e-9,
        "({}, {}) vs ({x}, {y})",
        p[0],
        p[1]
    );
}

/// A step of 5 mm with R = 10 (D1), G41, tool above: "intermediate block < compensation
/// value". N30 (0,0)→(40,0) and N40 up to (40,5) meet at an inner corner: y = 10 and x = 30
/// give (30,10). N40's equidistant would then run from (30,10) down to its normal end (30,5):
/// backwards, so the tool cannot cut N40 without cutting into N30.
const NOTCH: &str = "N10 G0 G17 G90 X-30 Y20 D1\nN20 G1 G41 X0 Y0 F500\nN30 X40\nN40 Y5\nN50 X80\nN60 Y40\nN70 G40 X100 Y60\nN80 M30\n";

#[test]
fn violation_stops_before_the_violating_block_by_default() {
    let (items, alarm) = run(NOTCH, &[]);
    let a = alarm.expect("alarm 3021");
    assert_eq!(a.code, AlarmCode::ContourViolation);
    assert_eq!((a.line, a.col, a.block.as_deref()), (4, 1, Some("N40")));
    // The bottleneck window (3 blocks) still held N30's path, not yet checked against the
    // contour after it: it is not put out. Without the window N30 runs to (30, 10).
    let segs = segments(&items);
    assert_eq!(segs.last().unwrap().role, Role::Approach);
    let (items, _) = run(NOTCH, &["trc.bottleneck_window=0"]);
    let segs = segments(&items);
    let last = segs.last().unwrap();
    assert_eq!(last.source.number.unwrap().value, 30);
    at(last.to, 30.0, 10.0);
}

#[test]
fn violation_warns_and_goes_on_with_the_machine_data_switch() {
    let (items, alarm) = run(NOTCH, &["trc.violation_reaction=warn"]);
    assert!(alarm.is_none());
    let w = items
        .iter()
        .position(|x| matches!(x, Prepared::Warning(a) if a.code == AlarmCode::ContourViolation && a.line == 4))
        .expect("a warning for N40");
    // The warning comes before N40's (reversed) path, which is output as it is.
    let n40 = items
        .iter()
        .position(|x| matches!(x, Prepared::Segment(s) if s.source.number.unwrap().value == 40))
        .expect("N40's path");
    assert!(w < n40);
    let Prepared::Segment(s) = &items[n40] else {
        unreachable!()
    };
    at(s.from, 30.0, 10.0);
    at(s.to, 30.0, 5.0);
    assert!(matches!(items.last(), Some(Prepared::End(_))));
}

/// Arc sweep from `a` to `b` about `c`, counter-clockwise, in (0, 2π].
fn ccw_sweep(c: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let (u, v) = ([a[0] - c[0], a[1] - c[1]], [b[0] - c[0], b[1] - c[1]]);
    let s = (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1]);
    if s <= 0.0 {
        s + std::f64::consts::TAU
    } else {
        s
    }
}

/// 11.14: a circle of radius 20 (G3, almost a full turn: from angle a0 round to angle 0) and a
/// line leaving it with an outer kink of δ. With G42 the tool is outside (r 30), the normal
/// points A and C are ~10δ apart, below the 0.01 mm suppression distance: the intersection is
/// approached, which lengthens the arc by φ past its end — and past a full turn. softnc turns
/// the whole 2π − a0 + φ (the 840C turns only the part above 360°).
#[test]
fn arc_lengthened_past_a_full_turn_is_traversed_in_full() {
    let (a0, d) = (0.00005f64, 0.0006f64);
    let (sx, sy) = (20.0 * a0.cos(), 20.0 * a0.sin());
    let (ex, ey) = (20.0 - 30.0 * d.sin(), 30.0 * d.cos());
    let src = format!(
        "N10 G0 G17 G90 X50 Y-30 D1\nN20 G1 G42 X{sx:.12} Y{sy:.12} F500\nN30 G3 X20 Y0 I{:.12} J{:.12}\nN40 G1 X{ex:.12} Y{ey:.12}\nN50 G40 X60 Y60\nN60 M30\n",
        -sx, -sy
    );
    // The full turn at r 30 passes over N40 (x ≈ 20, y 0..30): a real gouge, which the
    // bottleneck check reports. What is tested here is the path, so the window is off.
    let (_, alarm) = run(&src, &[]);
    assert!(alarm.is_some());
    let (items, alarm) = run(&src, &["trc.bottleneck_window=0"]);
    assert!(alarm.is_none(), "{alarm:?}");
    // The start angle as the program writes it.
    let start = (format!("{sy:.12}").parse::<f64>().unwrap())
        .atan2(format!("{sx:.12}").parse::<f64>().unwrap());
    // φ: the line's equidistant (right of direction (−sin δ, cos δ): + 10·(cos δ, sin δ))
    // meets the circle r = 30 at the root nearest the corner.
    let (dx, dy) = (-d.sin(), d.cos());
    let (px, py) = (20.0 + 10.0 * d.cos(), 10.0 * d.sin());
    let b = px * dx + py * dy;
    let disc = (b * b - (px * px + py * py) + 900.0).sqrt();
    let s = [-b + disc, -b - disc]
        .into_iter()
        .min_by(|x, y| x.abs().total_cmp(&y.abs()))
        .unwrap();
    let phi = (py + s * dy).atan2(px + s * dx);
    assert!(
        phi > start,
        "the test's geometry lengthens the arc past its start"
    );
    let arcs: Vec<_> = segments(&items)
        .into_iter()
        .filter(|s| s.source.number.unwrap().value == 30 && s.role == Role::Contour)
        .collect();
    let total: f64 = arcs
        .iter()
        .map(|s| match s.shape {
            Shape::Arc {
                center, ccw: true, ..
            } => ccw_sweep(center, s.from, s.to),
            _ => panic!("N30 is a counter-clockwise arc: {s:?}"),
        })
        .sum();
    let expected = std::f64::consts::TAU - start + phi;
    assert!(expected > std::f64::consts::TAU);
    assert!(
        (total - expected).abs() < 1e-9,
        "turned {total}, expected {expected}"
    );
    at(arcs.last().unwrap().to, 30.0 * phi.cos(), 30.0 * phi.sin());
}

/// A contour that comes back close to itself (R = 10, G41, tool above N30): N30 runs along
/// y = 0, the contour goes up, left, and N60 comes back down at x = 50 to y = `bottom`. With
/// `bottom` = 8, N60 crosses N30's tool path (y = 10): distance 0. With `bottom` = 15 and
/// N70 running right at y = 15, nothing crosses, but N30's tool path (y = 10) passes 5 mm from
/// N70: the tool circle would cut it. Neither shows in three neighbouring elements.
fn comes_back(bottom: &str) -> String {
    format!(
        "N10 G0 G17 G90 X-20 Y-20 D1\nN20 G1 G41 X0 Y0 F500\nN30 X100\nN40 Y50\nN50 X50\nN60 Y{bottom}\nN70 X90\nN80 G40 X90 Y-30\nN90 M30\n"
    )
}

#[test]
fn bottleneck_found_before_the_tool_gets_there() {
    let (items, alarm) = run(&comes_back("8"), &[]);
    let a = alarm.expect("alarm 3021");
    assert_eq!(a.code, AlarmCode::ContourViolation);
    assert_eq!((a.line, a.block.as_deref()), (3, Some("N30")));
    assert!(
        a.message.contains("within 0.0000 mm of the contour of N60"),
        "{}",
        a.message
    );
    // Nothing of N30 went out: the path stops after the approach.
    let segs = segments(&items);
    assert_eq!(segs.last().unwrap().role, Role::Approach);

    // No crossing: N60 now stops at y = 15, 5 mm above N30's tool path; so does N70.
    let (_, alarm) = run(&comes_back("15"), &[]);
    let a = alarm.expect("alarm 3021 without a crossing");
    assert_eq!(a.line, 3);
    assert!(
        a.message.contains("within 5.0000 mm of the contour of N60"),
        "{}",
        a.message
    );
}

#[test]
fn bottleneck_window_is_machine_data() {
    // Off: no alarm (and the tool would gouge).
    let (_, alarm) = run(&comes_back("8"), &["trc.bottleneck_window=0"]);
    assert!(alarm.is_none(), "{alarm:?}");
    // One block: N30's path has gone on before N60 comes; what is found is later (the
    // deselection corner at (100, 8) touches N40 — this contour gouges in more than one way).
    let (_, alarm) = run(&comes_back("8"), &["trc.bottleneck_window=1"]);
    assert_ne!(alarm.map(|a| a.line), Some(3));
    let (_, alarm) = run(&comes_back("8"), &["trc.bottleneck_window=64"]);
    assert_eq!(alarm.map(|a| a.line), Some(3));
    // Warn: a warning, and the whole path.
    let (items, alarm) = run(&comes_back("8"), &["trc.violation_reaction=warn"]);
    assert!(alarm.is_none());
    assert!(items
        .iter()
        .any(|x| matches!(x, Prepared::Warning(a) if a.line == 3)));
    assert!(matches!(items.last(), Some(Prepared::End(_))));
}

#[test]
fn gouge_free_contours_pass_every_window() {
    let serpentine =
        nc_kernel::synthetic::compensated_program(2000, nc_kernel::synthetic::Header::Softnc);
    let workpiece = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("programs/siemens-840c/11_15_workpiece.mpf"),
    )
    .unwrap();
    for (name, src) in [("serpentine", &serpentine), ("workpiece", &workpiece)] {
        let (plain, _) = run(src, &["trc.bottleneck_window=0"]);
        for w in ["1", "3", "64"] {
            let (items, alarm) = run(src, &[&format!("trc.bottleneck_window={w}")]);
            assert!(alarm.is_none(), "{name}, window {w}: {alarm:?}");
            // The window holds the path back but puts out all of it, unchanged.
            assert_eq!(segments(&items), segments(&plain), "{name}, window {w}");
        }
    }
}

/// ISG contour masking (G141): a notch 8 mm wide under a tool of R = 10 (D1), the tool above
/// N25. Inside the notch the equidistants are x = 10 (N30 down), y = −20 (N40) and
/// x = 8 − 10 = −2 (N50 up): N40's runs backwards. With G141 the blocks that would violate
/// the contour are left out: N25's equidistant y = 10 meets N50's x = −2 at (−2, 10), and the
/// path joins there. N30's M8 is output at that point, in program order.
const NOTCH_ISG: &str = "N10 G17 G90 G00 X-60 Y20 D1\nN15 G141\nN20 G41 G01 X-40 Y0 F1000\nN25 X0 Y0\nN30 X0 Y-30 M8\nN40 X8 Y-30\nN50 X8 Y2\nN60 X50 Y2\nN70 G40 X60 Y30\nN80 M30\n";

fn run_isg(src: &str) -> (Vec<Prepared>, Option<nc_kernel::Alarm>) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("config/isg.toml");
    run_with(src, &MachineData::load(Some(&path), &[]).unwrap())
}

#[test]
fn isg_masking_leaves_out_what_would_violate_and_joins_at_the_intersection() {
    let (items, alarm) = run_isg(NOTCH_ISG);
    assert!(alarm.is_none(), "{alarm:?}");
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    assert!(
        segs.iter().all(|s| block(s) != 30 && block(s) != 40),
        "N30, N40 left out"
    );
    let n25 = segs.iter().rfind(|s| block(s) == 25).unwrap();
    at(n25.to, -2.0, 10.0);
    let n50 = segs.iter().find(|s| block(s) == 50).unwrap();
    at(n50.from, -2.0, 10.0);
    at(n50.to, -2.0, 12.0);
    // M8 of the left-out N30 comes out where the path joins, before N50 moves.
    let m8 = items
        .iter()
        .position(|x| matches!(x, Prepared::Aux(a) if a.source.number.unwrap().value == 30))
        .expect("N30's M8");
    let Prepared::Aux(a) = &items[m8] else {
        unreachable!()
    };
    at(a.pos, -2.0, 10.0);
    let first_n50 = items
        .iter()
        .position(|x| matches!(x, Prepared::Segment(s) if s.source.number.unwrap().value == 50))
        .unwrap();
    assert!(m8 < first_n50);
    // G140: the notch is a contour violation (11.12 at N40).
    let (_, alarm) = run_isg(&NOTCH_ISG.replace("N15 G141", "N15 G140"));
    let a = alarm.expect("alarm 3021");
    assert_eq!((a.code, a.line), (AlarmCode::ContourViolation, 6));
}

/// ISG masking of a step shorter than its inner corner's trim: N30 east along Y0, N40 3 mm up,
/// N50 east along Y3, the tool above (G41, R 10, G26 transition circles). N40's equidistant
/// x = 40 runs backwards (the trim at the inner corner is R·tan 45° = 10 > 3), and N30's was
/// trimmed at their intersection (40, 10), a point that is gone once N40 is left out. The
/// path joins where N30's equidistant y = 10, lengthened, meets the transition circle about
/// N40's end (50, 3): x = 50 − √51. It goes on round that circle to N50's normal position
/// (50, 13), and N40 is not cut. (Found by the cavalier oracle in tests/gouge.rs: before, the
/// window found no crossing to cut at and stopped with 3021.)
#[test]
fn isg_masking_joins_past_a_step_shorter_than_its_trim() {
    let items = masked_step("3");
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    let x = 50.0 - 51f64.sqrt();
    let n30 = segs.iter().rfind(|s| block(s) == 30).unwrap();
    at(n30.to, x, 10.0);
    let (corner, center) = transition_circle(&segs);
    at(corner.from, x, 10.0);
    at(corner.to, 50.0, 13.0);
    at(center, 50.0, 3.0);
    // The transition circle is N50's first piece, its straight line the second.
    assert_eq!(block(corner), 50);
    let n50 = segs
        .iter()
        .find(|s| block(s) == 50 && s.role == Role::Contour)
        .unwrap();
    at(n50.from, 50.0, 13.0);
}

/// The mirror image: N30 east along Y0, N40 3 mm down, N50 east along Y−3, the tool above
/// (G41, R 10, G26). N30→N40 is an outer corner: the transition circle about (50, 0) from
/// (50, 10) to (60, 0) is N40's first piece. N40's equidistant x = 60 meets N50's y = 7 at
/// (60, 7), above where it starts: it runs backwards. Left out, the path joins where the
/// transition circle meets N50's equidistant, lengthened back: x = 50 + √51, y = 7.
#[test]
fn isg_masking_joins_a_transition_circle_before_a_step_down() {
    let items = masked_step("-3");
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    let x = 50.0 + 51f64.sqrt();
    let (corner, center) = transition_circle(&segs);
    assert_eq!(block(corner), 40);
    at(corner.from, 50.0, 10.0);
    at(corner.to, x, 7.0);
    at(center, 50.0, 0.0);
    let n50 = segs.iter().find(|s| block(s) == 50).unwrap();
    at(n50.from, x, 7.0);
    // Along y = 7 to the deselection's inner corner.
    assert!((n50.to[1] - 7.0).abs() < 1e-9 && n50.to[0] > x, "{n50:?}");
}

/// The step of the two tests above under G141 (N40 `rise` mm up or down, the tool above,
/// R 10, G26): prepared without an alarm, nothing of N40 cut but a transition circle; with
/// G140 the step is a contour violation (11.12 at N40).
fn masked_step(rise: &str) -> Vec<Prepared> {
    let items = masked(&format!("N10 G17 G90 G00 X-20 Y20 D1\nN15 G141 G26\nN20 G41 G01 X0 Y0 F1000\nN30 X50\nN40 Y{rise}\nN50 X100\nN60 G40 X120 Y30\nN70 M30\n"));
    assert!(segments(&items)
        .iter()
        .all(|s| s.source.number.unwrap().value != 40 || s.role == Role::Corner));
    items
}

/// An ISG program with G141 (line 2): prepared without an alarm; with G140 instead, a
/// contour violation (11.12) at line 5.
fn masked(src: &str) -> Vec<Prepared> {
    masked_else(src, AlarmCode::ContourViolation, 5)
}

/// As [`masked`], with G140 ending in alarm `code` at `line`.
fn masked_else(src: &str, code: AlarmCode, line: u32) -> Vec<Prepared> {
    let (items, alarm) = run_isg(src);
    assert!(alarm.is_none(), "{alarm:?}");
    let (_, alarm) = run_isg(&src.replace("G141", "G140"));
    assert_eq!(alarm.map(|a| (a.code, a.line)), Some((code, line)));
    items
}

/// The 2 mm step of [`masked_step`] programmed as two blocks on one line: N40 1 mm up, N45
/// 1 mm more, N50 east along Y2 (G41, R 10, G26). N40's equidistant x = 40 runs backwards
/// from the inner corner (40, 10); N45's, from (40, 1) to (40, 2), runs forwards but 1 mm
/// from N30: it lies inside the loop and is left out with N40. The path joins where N30's
/// equidistant y = 10, lengthened, meets the transition circle about N45's end (50, 2):
/// (x − 50)² = 10² − 8², x = 44. Round that circle to N50's normal position (50, 12).
/// (Found by the cavalier oracle in tests/gouge.rs: before, N45 ended the masking with 3021.)
#[test]
fn isg_masking_leaves_out_a_step_split_into_blocks_on_one_line() {
    let src = "N10 G17 G90 G00 X-20 Y20 D1\nN15 G141 G26\nN20 G41 G01 X0 Y0 F1000\nN30 X50\nN40 Y1\nN45 Y2\nN50 X100\nN60 G40 X120 Y30\nN70 M30\n";
    let items = masked(src);
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    assert!(segs.iter().all(|s| block(s) != 40));
    let n30 = segs.iter().rfind(|s| block(s) == 30).unwrap();
    at(n30.to, 44.0, 10.0);
    let (corner, center) = transition_circle(&segs);
    at(corner.from, 44.0, 10.0);
    at(corner.to, 50.0, 12.0);
    at(center, 50.0, 2.0);
    let Shape::Arc { ccw, .. } = corner.shape else {
        unreachable!()
    };
    assert!(!ccw, "clockwise round the step's top");
    let n50 = segs
        .iter()
        .find(|s| block(s) == 50 && s.role == Role::Contour)
        .unwrap();
    at(n50.from, 50.0, 12.0);
    assert!(segs
        .iter()
        .all(|s| block(s) != 45 || s.role == Role::Corner));
}

/// A transition circle left out with a backward run, then cut short by a joint. N30 runs
/// up-left to (0, 45), N40 1 mm up: its equidistant x = 10 starts where it meets N30's,
/// (10, 46.62…), above its own end (10, 46), so it runs backwards. N45 turns left on a
/// clockwise r 5 about (0, 51), smaller than the tool on its inside (G42, R 10, G26); N50 goes
/// up x = −5. The transition circle about N40's end (0, 46), from (10, 46) to (0, 56), comes
/// closer than R to N45's end (−5, 51) past φ ≈ 65.7° (where cos φ − sin φ = −½), so it is
/// left out with the run. The path: N30's equidistant, lengthened to meet that circle, the
/// circle (still counter-clockwise) to where it meets N50's equidistant x = 5 at φ = 60°,
/// (5, 46 + 5√3), then x = 5. (Found by the cavalier oracle in tests/gouge.rs: before, a
/// left-out transition circle offered no joint, and the masking ended with 3021.)
#[test]
fn isg_masking_cuts_a_left_out_transition_circle_short() {
    let src = "N10 G17 G90 G00 X40 Y-20 D1\nN15 G141 G26\nN20 G42 G01 X15 Y0 F1000\nN30 X0 Y45\nN40 Y46\nN45 G02 X-5 Y51 I0 J5\nN50 G01 Y100\nN60 G40 X-30 Y120\nN70 M30\n";
    // Without masking the circle smaller than the tool is the alarm.
    let items = masked_else(src, AlarmCode::ArcRadiusTooSmall, 6);
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    assert!(segs
        .iter()
        .all(|s| block(s) != 40 && (block(s) != 45 || s.role == Role::Corner)));
    // N30's equidistant: (15, 0) + 10·n + t·u, u = (−1, 3)/√10, n = (3, 1)/√10 (right of u).
    // It meets |p − (0, 46)| = 10 at the smaller root of |q + t·u|² = 100, q = its start
    // − (0, 46).
    let s10 = 10f64.sqrt();
    let (u, n) = ([-1.0 / s10, 3.0 / s10], [3.0 / s10, 1.0 / s10]);
    let p0 = [15.0 + 10.0 * n[0], 10.0 * n[1]];
    let q = [p0[0], p0[1] - 46.0];
    let b = q[0] * u[0] + q[1] * u[1];
    let c = q[0] * q[0] + q[1] * q[1] - 100.0;
    let t = -b - (b * b - c).sqrt();
    let (bx, by) = (p0[0] + t * u[0], p0[1] + t * u[1]);
    let n30 = segs.iter().rfind(|s| block(s) == 30).unwrap();
    at(n30.to, bx, by);
    let (corner, center) = transition_circle(&segs);
    assert_eq!(block(corner), 45);
    at(center, 0.0, 46.0);
    at(corner.from, bx, by);
    let j = 46.0 + 5.0 * 3f64.sqrt();
    at(corner.to, 5.0, j);
    let Shape::Arc { ccw, .. } = corner.shape else {
        unreachable!()
    };
    assert!(
        ccw,
        "counter-clockwise round N40's end, as the corner was built"
    );
    let n50 = segs
        .iter()
        .find(|s| block(s) == 50 && s.role == Role::Contour)
        .unwrap();
    at(n50.from, 5.0, j);
    at(n50.to, 5.0, 100.0);
}

/// A pocket narrower than the tool with a shallow wall before it: N30 east along Y0, N40 2 mm
/// down, N50 east along Y−2 for 18 mm, N60 up the far wall X68 (G41, R 10, G26). N40's
/// equidistant x = 60 runs backwards (down from the transition circle, up to the floor's
/// y = 8), and so does the floor's, from (60, 8) back to the far wall's x = 58. The tool
/// cannot reach the floor's corners: the transition circle about (50, 0) runs on until it
/// meets the floor's equidistant, (x − 50)² = 10² − 8², x = 56; the path follows y = 8 to
/// (58, 8) and goes up x = 58. Two joints for one new segment (N60): N50 is bridged.
#[test]
fn isg_masking_bridges_the_floor_of_a_pocket_narrower_than_the_tool() {
    let src = "N10 G17 G90 G00 X-20 Y20 D1\nN15 G141 G26\nN20 G41 G01 X0 Y0 F1000\nN30 X50\nN40 Y-2\nN50 X68\nN60 Y40\nN70 G40 X90 Y60\nN80 M30\n";
    let items = masked(src);
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    let n30 = segs.iter().rfind(|s| block(s) == 30).unwrap();
    at(n30.to, 50.0, 10.0);
    let (corner, center) = transition_circle(&segs);
    assert_eq!(block(corner), 40);
    at(corner.from, 50.0, 10.0);
    at(corner.to, 56.0, 8.0);
    at(center, 50.0, 0.0);
    assert!(segs
        .iter()
        .all(|s| block(s) != 40 || s.role == Role::Corner));
    let floor: Vec<_> = segs.iter().filter(|s| block(s) == 50).collect();
    assert_eq!(floor.len(), 1, "{floor:?}");
    at(floor[0].from, 56.0, 8.0);
    at(floor[0].to, 58.0, 8.0);
    let n60 = segs.iter().find(|s| block(s) == 60).unwrap();
    at(n60.from, 58.0, 8.0);
    at(n60.to, 58.0, 40.0);
}

/// A concave arc at the end of the contour that runs backwards: N30 east along Y0 to (50, 0),
/// N35 1 mm down, N40 counter-clockwise r 30 about (50, 29) from (50, −1) to −65° (the tool
/// inside, G41, R 10, G26), then M30 with compensation on (11.5.2: N40 ends in its normal
/// position) or a G40 retract. N30→N35 is an outer corner: the transition circle about
/// (50, 0). N35's equidistant x = 60 meets N40's, the circle r 20 about (50, 29), at
/// y = 29 − √300, −60° on it, past N40's end at −65°: N35 and N40 both run backwards, and no
/// later element comes to join them. The path joins N40's circle over its programmed sweep:
/// the transition circle x² + y² = 10² (about (50, 0)) meets x² + (y − 29)² = 20² at
/// y = 541/58, x = √(10² − y²); from there N40 runs counter-clockwise, as programmed, to its
/// normal position (50 + 20 cos 65°, 29 − 20 sin 65°). (Found by the cavalier oracle in
/// tests/gouge.rs: before, a last arc that ran backwards joined nothing, and at M30 a run
/// still held was not joined at all: 3021 both ways.)
#[test]
fn isg_masking_joins_a_last_arc_that_runs_backwards_along_its_circle() {
    let phi = 65f64.to_radians();
    let (ex, ey) = (50.0 + 30.0 * phi.cos(), 29.0 - 30.0 * phi.sin());
    let head = format!("N10 G17 G90 G00 X-20 Y20 D1\nN15 G141 G26\nN20 G41 G01 X0 Y0 F1000\nN30 X50\nN35 Y-1\nN40 G03 X{ex:.12} Y{ey:.12} I0 J30\n");
    let y: f64 = 541.0 / 58.0;
    let x = 50.0 + (100.0 - y * y).sqrt();
    for end in ["N60 M30\n", "N50 G01 G40 X80 Y20\nN60 M30\n"] {
        let items = masked(&format!("{head}{end}"));
        let segs = segments(&items);
        let block = |s: &Segment| s.source.number.unwrap().value;
        let (corner, center) = transition_circle(&segs);
        assert_eq!(block(corner), 35);
        at(center, 50.0, 0.0);
        at(corner.from, 50.0, 10.0);
        at(corner.to, x, y);
        assert!(segs
            .iter()
            .all(|s| block(s) != 35 || s.role == Role::Corner));
        let n40: Vec<_> = segs.iter().filter(|s| block(s) == 40).collect();
        assert_eq!(n40.len(), 1, "{n40:?}");
        at(n40[0].from, x, y);
        let Shape::Arc { center, ccw, .. } = n40[0].shape else {
            panic!("{:?}", n40[0]);
        };
        assert!(ccw, "as programmed");
        at(center, 50.0, 29.0);
        if end == "N60 M30\n" {
            at(n40[0].to, 50.0 + 20.0 * phi.cos(), 29.0 - 20.0 * phi.sin());
        }
    }
}

/// A joint into a segment that follows a backward run is a bridge. G42, R 10: N30 north up
/// x = 1 to (1, 0), N40 1 mm west, N50 north up the y axis to (0, 40), N60 back down to
/// (4, 25), N70 east along Y25. N30→N40 is an outer corner: the transition circle about
/// (1, 0) from (11, 0) to (1, 10). N40's equidistant y = 10 meets N50's x = 10 at (10, 10),
/// east of where it starts: it runs backwards. N50 runs into a slot 4 mm wide at most with
/// N60 and is cut back far below its start: it runs backwards too, and so does N60. N70's
/// equidistant y = 15 meets N50's line x = 10 at (10, 15); joined there alone, N50 would
/// still start where N40's backward run ends. So the transition circle must meet N50's line
/// first: (10 − 1)² + y² = 10², y = √19. The path: the circle from (11, 0) to (10, √19), N50
/// up to (10, 15), N70 east; N40 and N60 left out. (Found by the cavalier oracle in
/// tests/gouge.rs: before, the joint at (10, 15) was taken and N40 stayed, 3021.)
#[test]
fn isg_masking_bridges_a_segment_that_follows_a_backward_run() {
    bridged_up_x10("N40 X0", AlarmCode::ContourViolation);
}

/// The segment after a gap is bridged the same way. N40 of the test above is a clockwise arc
/// instead, from (1, 0) to (0, 0) about (½, ½), r √½, smaller than the tool on its inside:
/// left out, its equidistant turned inside out (r 10 − √½ about (½, ½)) never meets N50's
/// x = 10, 9.5 from the centre, and the compensator leaves a gap before N50. The transition
/// circle about (1, 0) (N30 turns left onto the arc) meets N50's line at (10, √19) as above,
/// and the path is the same. (Found by the cavalier oracle: before, the segment after a gap
/// could only be joined from before it, 3021.)
#[test]
fn isg_masking_bridges_the_segment_after_a_gap() {
    bridged_up_x10(
        "N40 G02 X0 Y0 I-0.5 J0.5\nN50 G01",
        AlarmCode::ArcRadiusTooSmall,
    );
}

/// The program of the two tests above with `n40` (G140 ends in `g140` at N40), masked over
/// 8 blocks (N40 is held until N70 comes): the path up x = 10 from (10, √19) to (10, 15).
fn bridged_up_x10(n40: &str, g140: AlarmCode) {
    let src = format!("N10 G17 G90 G00 X20 Y-40 D1\nN15 G141 G26\nN20 G42 G01 X1 Y-30 F1000\nN30 Y0\n{n40}\nN50 G01 Y40\nN60 X4 Y25\nN70 X40\nN80 G40 X60 Y40\nN90 M30\n");
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("config/isg.toml");
    let md = MachineData::load(Some(&path), &["trc.bottleneck_window=8".to_string()]).unwrap();
    let (items, alarm) = run_with(&src, &md);
    assert!(alarm.is_none(), "{alarm:?}");
    let (_, alarm) = run_with(&src.replace("G141", "G140"), &md);
    assert_eq!(alarm.map(|a| (a.code, a.line)), Some((g140, 5)));
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    let y = 19f64.sqrt();
    let n30 = segs.iter().rfind(|s| block(s) == 30).unwrap();
    at(n30.to, 11.0, 0.0);
    let (corner, center) = transition_circle(&segs);
    assert_eq!(block(corner), 40);
    at(center, 1.0, 0.0);
    at(corner.from, 11.0, 0.0);
    at(corner.to, 10.0, y);
    assert!(segs
        .iter()
        .all(|s| block(s) != 60 && (block(s) != 40 || s.role == Role::Corner)));
    let n50: Vec<_> = segs.iter().filter(|s| block(s) == 50).collect();
    assert_eq!(n50.len(), 1, "{n50:?}");
    at(n50[0].from, 10.0, y);
    at(n50[0].to, 10.0, 15.0);
    let n70 = segs.iter().find(|s| block(s) == 70).unwrap();
    at(n70.from, 10.0, 15.0);
    at(n70.to, 40.0, 15.0);
}

/// The path's one transition circle and its centre.
fn transition_circle<'a>(segs: &[&'a Segment]) -> (&'a Segment, [f64; 3]) {
    let corner = *segs.iter().find(|s| s.role == Role::Corner).unwrap();
    let Shape::Arc { center, .. } = corner.shape else {
        panic!("{corner:?}");
    };
    (corner, center)
}

/// A concave circle smaller than the tool: N40 turns 90° left on r 2 about (50, 2), the tool
/// inside it (G41, R 10). Without masking that is alarm 10758. With G141 the circle is left
/// out: N30's equidistant y = 10 meets N50's x = 52 − 10 = 42 at (42, 10), where the tool
/// is 10 from both lines and √(8² + 10²) from the circle's ends; N40's M8 comes out there.
#[test]
fn isg_masking_leaves_out_a_circle_smaller_than_the_tool() {
    let src = "N10 G17 G90 G00 X-20 Y20 D1\nN15 G141 G26\nN20 G41 G01 X0 Y0 F1000\nN30 X50\nN40 G03 X52 Y2 I0 J2 M8\nN50 G01 Y50\nN60 G40 X30 Y70\nN70 M30\n";
    let (items, alarm) = run_isg(src);
    assert!(alarm.is_none(), "{alarm:?}");
    let segs = segments(&items);
    let block = |s: &Segment| s.source.number.unwrap().value;
    assert!(segs.iter().all(|s| block(s) != 40), "N40 left out");
    let n30 = segs.iter().rfind(|s| block(s) == 30).unwrap();
    at(n30.to, 42.0, 10.0);
    let n50 = segs.iter().find(|s| block(s) == 50).unwrap();
    at(n50.from, 42.0, 10.0);
    // Along x = 42 to the deselection's inner corner.
    assert!(
        (n50.to[0] - 42.0).abs() < 1e-9 && n50.to[1] > 10.0,
        "{n50:?}"
    );
    let m8 = items
        .iter()
        .find_map(|x| match x {
            Prepared::Aux(a) if a.source.number.unwrap().value == 40 => Some(a),
            _ => None,
        })
        .expect("N40's M8");
    at(m8.pos, 42.0, 10.0);
    let (_, alarm) = run_isg(&src.replace("G141", "G140"));
    assert_eq!(
        alarm.map(|a| (a.code, a.line)),
        Some((AlarmCode::ArcRadiusTooSmall, 5))
    );
}

#[test]
fn isg_masking_without_a_way_round_is_an_alarm() {
    // The contour that comes back close to itself without crossing (see `comes_back`): no loop
    // to cut out, so no gouge-free path inside the window.
    let src = comes_back("15").replace("N20 G1 G41", "N15 G141\nN20 G1 G41");
    let (_, alarm) = run_isg(&src);
    assert_eq!(alarm.map(|a| a.code), Some(AlarmCode::ContourViolation));
}

/// A D change over a circle (Fanuc: the radius is spread over the block) into a channel:
/// N30 is the clockwise quarter circle r 50 about the origin from (50, 0) to (0, −50), cut
/// outside (G41) while the radius goes from D1 = 10 to D2 = 5, so its path is a spiral from
/// (60, 0) at radius 60 towards radius 55, ending at the inner corner with N40's equidistant
/// X5: (5, −√3000). Three blocks later N60 rises along X68. At the spiral's
/// start the tool circle (R 10 about (60, 0)) reaches X70: 8 mm from the wall, a gouge of
/// 2 mm that the window finds before any motion. The walls later, cut with R 5, are clear;
/// with the wall at X75 (15 mm from (60, 0)) the program passes.
#[test]
fn a_radius_change_over_a_circle_is_checked_with_the_radius_at_each_point() {
    let prog = |wall: &str| {
        format!(
            "N10 G17 G90 G0 X50 Y40\nN20 G41 D1 G1 X50 Y0 F1000\nN30 G2 X0 Y-50 I-50 J0 D2\nN40 G1 Y-70\nN50 X{wall}\nN60 Y10\nN70 G40 X100 Y30\nN80 M30\n"
        )
    };
    let (items, alarm) = run(&prog("68"), &["dialect=fanuc"]);
    let a = alarm.expect("alarm 3021");
    assert_eq!(a.code, AlarmCode::ContourViolation);
    assert_eq!(a.block.as_deref(), Some("N30"));
    assert!(
        a.message
            .contains("the tool path of N30 comes within 8.0000 mm of the contour of N60 (tool radius 10.0000)"),
        "{}",
        a.message
    );
    // N30's spiral was still held in the window: only the approach went out.
    assert!(segments(&items).iter().all(|s| s.source.line < 3));
    let (items, alarm) = run(&prog("75"), &["dialect=fanuc"]);
    assert!(alarm.is_none(), "{alarm:?}");
    // The spiral itself: radius 60 at its start, 55 at its end on N40's equidistant.
    let spiral = segments(&items)
        .into_iter()
        .find(|s| s.source.line == 3)
        .unwrap();
    at(spiral.from, 60.0, 0.0);
    at(spiral.to, 5.0, -(3000f64.sqrt()));
    assert!(
        matches!(spiral.shape, Shape::Arc { r0, r1, .. } if (r0 - 60.0).abs() < 1e-9 && (r1 - 55.0).abs() < 1e-9)
    );
}
