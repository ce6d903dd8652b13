//! Tool radius compensation, rule by rule (840C chapter 11, 808D, ISG, Fanuc C).
//!
//! Every expected coordinate is worked out in this file from the program text: by hand (the
//! arithmetic is in the comments) or with the small vector helpers below, never copied from
//! softnc's output. Tolerance 1e-9 mm unless stated.

use nc_kernel::{prepare, AlarmCode, AxisPos, MachineData, ToolTable};
use nc_kernel::{Role, Segment, Shape};
use std::path::PathBuf;

const TOL: f64 = 1e-9;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn machine(config: &str, md: &[&str]) -> MachineData {
    let path = root().join("config").join(config);
    let over: Vec<String> = md.iter().map(|s| s.to_string()).collect();
    MachineData::load(Some(&path), &over).unwrap_or_else(|e| panic!("{e}"))
}

/// The ISG control's own bottleneck checking (none outside G141): its feature examples draw
/// contours that touch themselves, which the shipped 64-block window reports.
const ISG_OWN: &[&str] = &["trc.bottleneck_window=0"];

fn tools(set: &[(u32, f64)]) -> ToolTable {
    let mut t = ToolTable::builtin();
    for &(d, r) in set {
        t.set_radius(d, r).expect("offset exists");
    }
    t
}

fn path(config: &str, md: &[&str], set: &[(u32, f64)], src: &str) -> Vec<Segment> {
    prepare("test", src, &machine(config, md), &tools(set))
        .unwrap_or_else(|a| panic!("alarm {a}\n{src}"))
}

fn program(dir: &str, file: &str) -> String {
    std::fs::read_to_string(root().join("programs").join(dir).join(file)).expect("program")
}

fn alarm(config: &str, set: &[(u32, f64)], src: &str) -> (AlarmCode, u32) {
    match prepare("test", src, &machine(config, &[]), &tools(set)) {
        Ok(p) => panic!("expected an alarm, got {} segments\n{src}", p.len()),
        Err(a) => (a.code, a.line),
    }
}

#[track_caller]
fn at(what: &str, got: [f64; 3], x: f64, y: f64) {
    assert!(
        (got[0] - x).abs() < TOL && (got[1] - y).abs() < TOL,
        "{what}: got ({}, {}), expected ({x}, {y})",
        got[0],
        got[1]
    );
}

fn of_block(p: &[Segment], n: u32) -> Vec<&Segment> {
    p.iter()
        .filter(|s| s.source.number.map(|b| b.value) == Some(n))
        .collect()
}

fn roles(segs: &[&Segment]) -> Vec<Role> {
    segs.iter().map(|s| s.role).collect()
}

/// The path must be continuous: every segment starts where the last one ended.
#[track_caller]
fn continuous(p: &[Segment]) {
    for w in p.windows(2) {
        let d = (0..3)
            .map(|i| (w[0].to[i] - w[1].from[i]).abs())
            .fold(0.0, f64::max);
        assert!(d < TOL, "gap of {d} mm between {:?} and {:?}", w[0], w[1]);
    }
}

// ---------------------------------------------------------------------------------------
// 840C 11.15: the complete workpiece, G41 G450, D1 = radius 10.

#[test]
fn workpiece_11_15_tool_centre_path() {
    let p = path(
        "siemens-840c.toml",
        &[],
        &[],
        &program("siemens-840c", "11_15_workpiece.mpf"),
    );
    continuous(&p);
    let s5 = 5f64.sqrt();
    // N10 selects from P0 (15,60) towards (30,60); N20 runs (1,2)/√5, a left turn: with G41
    // the tool is inside the turn, α ≥ 180°, so N10 ends in the normal position of N20's
    // start: (30,60) + 10·(−2,1)/√5.
    let n10 = of_block(&p, 10);
    assert_eq!(roles(&n10), [Role::Approach]);
    at("N10 end", n10[0].to, 30.0 - 20.0 / s5, 60.0 + 10.0 / s5);
    // N20 → N30 (G2 from (40,80) about (40,55): starts heading +X): a right turn, outer
    // corner: a transition circle about (40,80) from (40,80)+10·(−2,1)/√5 to (40,90).
    let n30 = of_block(&p, 30);
    assert_eq!(roles(&n30), [Role::Corner, Role::Contour]);
    at(
        "N30 corner start",
        n30[0].from,
        40.0 - 20.0 / s5,
        80.0 + 10.0 / s5,
    );
    at("N30 corner end", n30[0].to, 40.0, 90.0);
    match n30[0].shape {
        Shape::Arc {
            center,
            ccw,
            r0,
            r1,
            ..
        } => {
            at("N30 corner centre", center, 40.0, 80.0);
            assert!(!ccw, "G41 outer corner turns clockwise");
            assert!((r0 - 10.0).abs() < TOL && (r1 - 10.0).abs() < TOL);
        }
        Shape::Line => panic!("corner must be a circle"),
    }
    // N30 compensated: radius 25 + 10 = 35 about (40,55) (left of a cw arc is outside);
    // N40 (+X from (65,55)) turns left at the arc end: inner corner, the circle r 35 meets
    // the line y = 65 at x = 40 + √(35² − 10²).
    let x30 = 40.0 + (35f64 * 35.0 - 100.0).sqrt();
    at("N30 end", n30[1].to, x30, 65.0);
    // N50 G2 about (110,55), r 15, starts heading +Y: left turn after N40, inner corner at
    // x = 110 − √(25² − 10²) on y = 65.
    let n50 = of_block(&p, 50);
    assert_eq!(roles(&n50), [Role::Contour]);
    at(
        "N50 start",
        n50[0].from,
        110.0 - (625f64 - 100.0).sqrt(),
        65.0,
    );
    at("N50 end", n50[0].to, 110.0, 80.0);
    // N60 (110,70) → (105,55), direction (−1,−3)/√10: outer corner after N50 (which ends
    // heading +X): circle about (110,70) to (110,70) + 10·(3,−1)/√10.
    let s10 = 10f64.sqrt();
    let n60 = of_block(&p, 60);
    assert_eq!(roles(&n60), [Role::Corner, Role::Contour]);
    at(
        "N60 corner end",
        n60[0].to,
        110.0 + 30.0 / s10,
        70.0 - 10.0 / s10,
    );
    // N110 (40,40) → (30,60) ends in its normal position for G40 (N120 heads −X, a left
    // turn: inner, α ≥ 180°): (30,60) + 10·(−2,−1)/√5, then N120 retracts to P0.
    let n110 = of_block(&p, 110);
    at(
        "N110 end",
        n110.last().unwrap().to,
        30.0 - 20.0 / s5,
        60.0 - 10.0 / s5,
    );
    let n120 = of_block(&p, 120);
    assert_eq!(roles(&n120), [Role::Retract]);
    at("N120 end", n120[0].to, 15.0, 60.0);
    // Tool length: D1 (length 100) becomes active with the next move of Z (N130 G0 Z50).
    let last = p.last().unwrap();
    assert!(
        (last.to[2] - 150.0).abs() < TOL,
        "Z with tool length: {}",
        last.to[2]
    );
    // Every contour segment lies at exactly 10 mm from its programmed element: checked
    // for the lines here, 35/25 for the arcs above.
    for s in p.iter().filter(|s| s.role == Role::Contour && !s.is_arc()) {
        assert!(s.feed == 400.0);
    }
}

// ---------------------------------------------------------------------------------------
// 840C 11.10: G451 inserts two intermediate blocks at the 45° corner, G450 one circle; the
// block outside the plane (N25 Z-5) runs at S1, the end of N20; the blocks take N30's feed.

#[test]
fn intermediate_blocks_11_10() {
    let src = program("siemens-840c", "11_10_aux_functions.mpf");
    // N20 is the selection block (0,0) → (50,50) with G41; N30 runs (50,50) → (50,0): a
    // right turn of 135° (material angle 45°), outer: α < 180° with G455 (default), so the
    // corner mode applies. S1 = (50,50) + 10·(−1,1)/√2.
    let r2 = 2f64.sqrt();
    let s1 = (50.0 - 10.0 / r2, 50.0 + 10.0 / r2);
    let p = path("siemens-840c.toml", &[], &[], &src);
    continuous(&p);
    at("S1", of_block(&p, 20)[0].to, s1.0, s1.1);
    let n25 = of_block(&p, 25);
    assert_eq!(n25.len(), 1);
    at("N25 runs at S1", n25[0].from, s1.0, s1.1);
    assert!(
        (n25[0].to[2] - n25[0].from[2] + 7.0).abs() < TOL,
        "Z2 → Z-5"
    );
    let n30 = of_block(&p, 30);
    assert_eq!(
        roles(&n30),
        [Role::Intermediate, Role::Intermediate, Role::Contour],
        "G451: S1 → S2 → S3, then N30"
    );
    // S2: the tangents through S1 along (1,1)/√2 and through S3 = (60,50) along −Y meet at
    // x = 60: S1 + t·(1,1)/√2 with 50 − 10/√2 + t/√2 = 60, so y = 50 + 10/√2 + 10 + 10/√2.
    at("S2", n30[0].to, 60.0, 60.0 + 20.0 / r2);
    at("S3", n30[1].to, 60.0, 50.0);
    assert!(n30.iter().all(|s| s.feed == 2000.0), "N30's feed F2000");

    let g450 = src.replace("N5  G451", "N5  G450");
    let p = path("siemens-840c.toml", &[], &[], &g450);
    let n30 = of_block(&p, 30);
    assert_eq!(
        roles(&n30),
        [Role::Corner, Role::Contour],
        "G450: S1 → S2, then N30"
    );
    at("S2 (G450)", n30[0].to, 60.0, 50.0);
}

// ---------------------------------------------------------------------------------------
// 840C 11.3/11.2: selection angle ranges.

fn selection_840c(n10: &str, n20: &str, to: (f64, f64)) -> Vec<Segment> {
    // Selection block N20 from (0,0) to (50,0) heading +X, then N30 to `to`; G41, D1 = 10.
    let src = format!(
        "N1 G0 G17 G90 D1 X0 Y0 Z0\nN10 G1 F100 {n10}\nN20 G41 {n20} X50 Y0\nN30 X{} Y{}\nN40 G40 X{} Y{}\nN50 M30\n",
        to.0,
        to.1,
        to.0,
        to.1 + 50.0
    );
    path("siemens-840c.toml", &[], &[], &src)
}

#[test]
fn selection_alpha_at_least_180_ends_in_the_normal_position() {
    // N30 heads +Y: a left turn, G41 inside: α = 270° ≥ 180°. N20 ends at (50,0) + 10·(−1,0)
    // whatever G455/G456 and G450/G451 say.
    for (n10, n20) in [
        ("G450", ""),
        ("G451", ""),
        ("G450", "G455"),
        ("G451", "G456"),
    ] {
        let p = selection_840c(n10, n20, (50.0, 100.0));
        continuous(&p);
        let n20s = of_block(&p, 20);
        assert_eq!(roles(&n20s), [Role::Approach], "{n10} {n20}");
        at(n10, n20s[0].to, 40.0, 0.0);
        at(n10, of_block(&p, 30)[0].from, 40.0, 0.0);
    }
}

#[test]
fn selection_alpha_below_180_follows_g455_g456() {
    // N30 heads −Y: a right turn of 90°, G41 outside: α = 90° < 180°.
    // G455 (default) + G450: N20 ends at its own normal position (50,10), circle to (60,0).
    let p = selection_840c("G450", "", (50.0, -100.0));
    continuous(&p);
    at("G455 G450 end of N20", of_block(&p, 20)[0].to, 50.0, 10.0);
    let n30 = of_block(&p, 30);
    assert_eq!(roles(&n30), [Role::Corner, Role::Contour]);
    at("circle end", n30[0].to, 60.0, 0.0);
    // G456: straight to the normal position of N30's start, whatever the corner mode.
    for n10 in ["G450", "G451"] {
        let p = selection_840c(n10, "G456", (50.0, -100.0));
        at("G456 end of N20", of_block(&p, 20)[0].to, 60.0, 0.0);
        assert_eq!(roles(&of_block(&p, 30)), [Role::Contour]);
    }
    // G455 + G451 at 90°, line/line: the intersection (60,10), no intermediate block.
    let p = selection_840c("G451", "G455", (50.0, -100.0));
    at("G451 end of N20", of_block(&p, 20)[0].to, 60.0, 10.0);
    assert_eq!(roles(&of_block(&p, 30)), [Role::Contour]);
}

#[test]
fn selection_takes_effect_with_the_next_plane_move_11_5_2() {
    // N15 G41 D7 without a path; N20 is the selection block; N25 Z is outside the plane.
    let src = "N1 G0 G17 G90 X0 Y0 Z0\nN10 G1 F100\nN15 G41 D7\nN20 X50 Y0\nN25 Z-5\nN30 X50 Y50\nN40 G40 X0 Y50\nN50 M30\n";
    let p = path("siemens-840c.toml", &[], &[], src);
    continuous(&p);
    // D7 = 8. N30 heads +Y after +X: inner, α ≥ 180°: N20 ends at (50,0) + 8·(−1,0).
    at("N20", of_block(&p, 20)[0].to, 42.0, 0.0);
    assert!(of_block(&p, 15).is_empty(), "no motion in N15");
}

// ---------------------------------------------------------------------------------------
// 840C 11.14: circle transitions with obtuse angles: G451 two blocks, G450 one.

#[test]
fn obtuse_circle_transition_11_14() {
    // N30 runs (1,−1)/√2 into (50,0); N40 G2 about (50,−100) starts there heading +X: a
    // left turn of 45° (material angle 135°), outer for G42. D2 = radius 5.
    let src = |g: &str| {
        format!(
            "N1 G0 G17 G90 D2 X-50 Y100 Z0\nN10 G1 F100 {g}\nN20 G42 X0 Y50\nN30 X50 Y0\nN40 G2 X150 Y-100 I0 J-100\nN50 G1 G40 X150 Y-200\nN60 M30\n"
        )
    };
    let r2 = 2f64.sqrt();
    // P1 = (50,0) + 5·right((1,−1)/√2) = (50,0) + 5·(−1,−1)/√2; P2 = (50,0) + 5·(0,−1).
    let p1 = (50.0 - 5.0 / r2, -5.0 / r2);
    let p = path("siemens-840c.toml", &[], &[], &src("G451"));
    continuous(&p);
    let n40 = of_block(&p, 40);
    assert_eq!(
        roles(&n40),
        [Role::Intermediate, Role::Intermediate, Role::Contour]
    );
    at("P1", n40[0].from, p1.0, p1.1);
    // T: the tangent through P1 along (1,−1)/√2 meets y = −5 at x = p1.x + (p1.y + 5).
    at("T", n40[0].to, p1.0 + (p1.1 + 5.0), -5.0);
    at("P2", n40[1].to, 50.0, -5.0);
    let p = path("siemens-840c.toml", &[], &[], &src("G450"));
    assert_eq!(roles(&of_block(&p, 40)), [Role::Corner, Role::Contour]);
}

// ---------------------------------------------------------------------------------------
// 840C 11.7: D change in a linear block; alarms.

#[test]
fn d_change_start_with_old_end_with_new_radius_11_7() {
    // G41 along +X then N30 +Y with D2 (10 → 5), N40 −X with the new radius.
    let src = "N1 G0 G17 G90 D1 X0 Y-50 Z0\nN10 G1 F100 G450\nN20 G41 X0 Y0\nN25 X100 Y0\nN30 D2 X100 Y100\nN40 X0 Y100\nN50 G40 X0 Y150\nN60 M30\n";
    let p = path("siemens-840c.toml", &[], &[], src);
    continuous(&p);
    // N25 → N30 is a left turn (inner) with the old radius 10: (90, 10).
    let n30 = of_block(&p, 30);
    at("N30 start, R10", n30[0].from, 90.0, 10.0);
    // N30 → N40 inner corner with the new radius 5: (95, 95).
    at("N30 end, R5", n30.last().unwrap().to, 95.0, 95.0);
    let bad = "N1 G0 G17 G90 D1 X0 Y-50 Z0\nN10 G1 F100\nN20 G41 X0 Y0\nN25 X100 Y0\nN30 D2 G3 X100 Y100 I0 J50\nN40 G40 X0 Y150\nN60 M30\n";
    assert_eq!(
        alarm("siemens-840c.toml", &[], bad),
        (AlarmCode::RadiusChangeNotLinear, 5)
    );
}

#[test]
fn arc_not_larger_than_the_tool_is_an_alarm() {
    // G41 inside a ccw circle of radius 10 with a radius-10 tool (D1).
    let src = "N1 G0 G17 G90 D1 X0 Y-50 Z0\nN10 G1 F100\nN20 G41 X0 Y0\nN30 G3 X20 Y0 I10 J0\nN40 G1 G40 X20 Y-50\nN50 M30\n";
    assert_eq!(
        alarm("siemens-840c.toml", &[], src),
        (AlarmCode::ArcRadiusTooSmall, 4)
    );
}

#[test]
fn negative_radius_swaps_the_side_11_9() {
    let src = "N1 G0 G17 G90 D1 X0 Y-50 Z0\nN10 G1 F100\nN20 G41 X0 Y0\nN30 X100 Y0\nN40 G40 X100 Y-50\nN50 M30\n";
    let contour = |p: &[Segment]| {
        *of_block(p, 30)
            .into_iter()
            .find(|s| s.role == Role::Contour)
            .unwrap()
    };
    // +X with G41: left is +Y; a negative radius puts the tool on the right.
    let left = path("siemens-840c.toml", &[], &[(1, 3.0)], src);
    let right = path("siemens-840c.toml", &[], &[(1, -3.0)], src);
    assert!((contour(&left).from[1] - 3.0).abs() < TOL);
    assert!((contour(&right).from[1] + 3.0).abs() < TOL);
}

#[test]
fn more_than_three_blocks_outside_the_plane_11_11() {
    let (code, line) = alarm(
        "siemens-840c.toml",
        &[],
        &program("siemens-840c", "11_11_four_blocks_outside_plane_alarm.mpf"),
    );
    assert_eq!(code, AlarmCode::ContourViolation);
    let src = program("siemens-840c", "11_11_four_blocks_outside_plane_alarm.mpf");
    let n45 = src.lines().position(|l| l.starts_with("N45")).unwrap() as u32 + 1;
    assert_eq!(line, n45);
    // Three are fine; with the old software's limit of one they are not.
    let three = program("siemens-840c", "11_11_three_blocks_outside_plane.mpf");
    path("siemens-840c.toml", &[], &[], &three);
    let md = machine("siemens-840c.toml", &["trc.max_blocks_outside_plane=1"]);
    assert!(prepare("t", &three, &md, &ToolTable::builtin()).is_err());
}

// ---------------------------------------------------------------------------------------
// 840C 11.6: repetition and side change.

#[test]
fn repeated_g41_without_g455_g456_is_ignored_11_6_1() {
    let base = "N1 G0 G17 G90 D1 X0 Y-50 Z0\nN10 G1 F100\nN20 G41 X0 Y0\nN30 X100 Y0\nN40 {G} X200 Y0\nN50 G40 X200 Y-50\nN60 M30\n";
    let p = path("siemens-840c.toml", &[], &[], &base.replace("{G}", "G41"));
    let plain = path("siemens-840c.toml", &[], &[], &base.replace("{G}", ""));
    assert_eq!(p.len(), plain.len());
    for (a, b) in p.iter().zip(&plain) {
        assert_eq!((a.from, a.to, a.role), (b.from, b.to, b.role));
    }
}

#[test]
fn side_change_two_contour_sections_11_6_2() {
    // The line-by-line idiom: G42 … G41 … the infeed block changes sides in the normal
    // position at both ends (G456 implied).
    let src = "N10 G0 G17 G90 D1 X0 Y0 Z0\nN15 G1 F100\nN20 G42 X10 Y0\nN30 X100 Y0\nN40 G41 X100 Y30\nN50 X10 Y30\nN60 G40 X0 Y30\nN70 M30\n";
    let p = path("siemens-840c.toml", &[], &[], src);
    continuous(&p);
    // N30 (G42, +X) ends in its normal position (100, −10); N40 runs to the normal
    // position of N50's start with G41 on −X: (100, 30) + 10·(0,−1) = (100, 20).
    at("N30 end", of_block(&p, 30).last().unwrap().to, 100.0, -10.0);
    let n40 = of_block(&p, 40);
    assert_eq!(roles(&n40), [Role::Approach]);
    at("N40 end", n40[0].to, 100.0, 20.0);
}

// ---------------------------------------------------------------------------------------
// 808D: G451 switches to the transition circle above 100° change of direction.

#[test]
fn g451_808d_switches_to_circle_above_100_degrees() {
    // Lathe, G18: Z abscissa, X ordinate (DIAMOF: X as a radius). Travel −Z, then a right
    // turn (seen in the Z/X plane): outer for G41.
    let prog = |x2: f64| {
        format!("N5 G18 G90 DIAMOF T1 D1 G0 X0 Z0\nN10 G1 F100 G451\nN20 G41 Z-50 X0\nN30 Z-100 X0\nN40 Z-100 X{x2}\nN50 G40 Z-150 X{x2}\nN60 M30\n")
    };
    // Turn of 90° (−Z then +X): the intersection, no block.
    let p = path("siemens-808d.toml", &[], &[], &prog(50.0));
    assert_eq!(roles(&of_block(&p, 40)), [Role::Contour]);
    // Reversing back towards +Z at an angle: N40 runs to (Z −60, X 20): a turn of
    // 180° − atan(20/40) ≈ 153° > 100°: circle.
    let p2 = prog(20.0).replace("Z-100 X20\nN50", "Z-60 X20\nN50");
    let p = path("siemens-808d.toml", &[], &[], &p2);
    assert_eq!(roles(&of_block(&p, 40)), [Role::Corner, Role::Contour]);
}

// ---------------------------------------------------------------------------------------
// ISG G25: inserted linear blocks by pair type and angle (TF5200 table).

fn isg_corner(first: &str, second: &str) -> Vec<Role> {
    // Selection N30 heads −Y into (0,0); N50 is the first element, N60 the second.
    let src = format!(
        "N10 G0 G17 G90 D2 X0 Y50 Z0\nN20 G1 F100 G25\nN30 G41 X0 Y0\n{first}\n{second}\nN90 G138 G40 G1 X300 Y300\nN99 M30\n"
    );
    let p = path("isg.toml", &[], &[], &src);
    continuous(&p);
    roles(&of_block(&p, 60))
}

#[test]
fn isg_g25_block_counts() {
    use Role::{Contour as C, Intermediate as I};
    // LIN-LIN: N50 heads +X; N60 −Y is a right turn of 90° (ISG angle 270°), outer for
    // G41: no block; N60 towards (0,−100) turns 135° (ISG 315°): one.
    assert_eq!(isg_corner("N50 X100 Y0", "N60 X100 Y-100"), [C]);
    assert_eq!(isg_corner("N50 X100 Y0", "N60 X0 Y-100"), [I, C]);
    // LIN-CIR: G2 about (50,0) starts at (100,0) heading −Y (90°): one; about (50,50) it
    // starts heading (−1,−1)/√2 (135°): two.
    assert_eq!(isg_corner("N50 X100 Y0", "N60 G2 X0 Y0 I-50 J0"), [I, C]);
    assert_eq!(
        isg_corner("N50 X100 Y0", "N60 G2 X0 Y0 I-50 J50"),
        [I, I, C]
    );
    // CIR-CIR: N50 G3 about (50,0) from (0,0) ends at (100,0) heading +Y. G2 about
    // (100,−50) starts heading +X (90°): two; about (50,−50) heading (1,−1)/√2 (135°): three.
    let ccw = "N50 G3 X100 Y0 I50 J0";
    assert_eq!(isg_corner(ccw, "N60 G2 X150 Y-50 I0 J-50"), [I, I, C]);
    assert_eq!(isg_corner(ccw, "N60 G2 X0 Y0 I-50 J-50"), [I, I, I, C]);
}

#[test]
fn isg_radius_change_is_spread_over_the_next_linear_block() {
    // Grinding-cycle shape: V.G.WZ_AKT.R lowered, the next linear block ramps it.
    let src = "N10 G0 G17 G90 D6 X0 Y0 Z0\nN20 G1 F100 G26\nN30 G41 X0 Y100\nN40 X300 Y100\nN50 V.G.WZ_AKT.R = 8\nN60 X300 Y200\nN70 X0 Y200\nN80 G40 X0 Y300\nN99 M30\n";
    let p = path("isg.toml", &[], &[], src);
    continuous(&p);
    // N40 (+X, G41 above it, r 10) → N60 (+Y): a left turn, inner: (290, 110) with r 10.
    let n60 = of_block(&p, 60);
    at("N60 start", n60[0].from, 290.0, 110.0);
    // N60 → N70 (−X), inner, with the new radius 8: (292, 192).
    at("N60 end", n60.last().unwrap().to, 292.0, 192.0);
    // and N70 runs at 8 below y = 200.
    assert!((of_block(&p, 70)[0].to[1] - 192.0).abs() < TOL);
}

#[test]
fn isg_d_change_example_runs() {
    // The seed's own example selects (N70 G41, no plane move) straight into a full circle
    // (N90): a perpendicular block leads onto it (docs/trc.md).
    let p = path("isg.toml", ISG_OWN, &[], &program("isg", "d_change.nc"));
    continuous(&p);
    // N90: G2 full circle about (−5,10), r 15, from (10,10); G41 is outside a cw circle:
    // radius 15 + 4 (D100). Its start (10,10) + 4·(1,0).
    let n90 = of_block(&p, 90);
    assert_eq!(n90[0].role, Role::Approach);
    at("perpendicular block", n90[0].to, 14.0, 10.0);
    let arc = n90.iter().find(|s| s.is_arc()).expect("N90 circle");
    at("N90 start", arc.from, 14.0, 10.0);
    // It ends where the circle r 19 meets N130's equidistant at the old radius 4 (inner
    // corner, a left turn from −Y to (1,1)/√2): on the circle and 4 from the line y = x.
    let e = arc.to;
    let r = ((e[0] + 5.0).powi(2) + (e[1] - 10.0).powi(2)).sqrt();
    assert!((r - 19.0).abs() < TOL, "on the circle: {r}");
    assert!(
        ((e[1] - e[0]) / 2f64.sqrt() - 4.0).abs() < TOL,
        "4 left of N130"
    );
}

// ---------------------------------------------------------------------------------------
// Fanuc C: start-up on the normal of the next block's start; G41 without coordinates moves
// by the offset only; a circle in start-up is alarm 026.

#[test]
fn fanuc_start_up_and_alarm_026() {
    let src = "G17 G90 G0 X0 Y0 Z0 D1;\nG1 F100;\nG41 X50 Y0;\nX50 Y100;\nG40 X0 Y100;\nM30;\n";
    let p = path(
        "fanuc.toml",
        &["program.decimal_input=calculator"],
        &[],
        src,
    );
    continuous(&p);
    let app = p.iter().find(|s| s.role == Role::Approach).unwrap();
    at("start-up end", app.to, 40.0, 0.0);
    let bad = "G17 G90 G0 X0 Y0 D1;\nG1 F100;\nG41 G2 X50 Y0 R25;\nM30;\n";
    let e = prepare("t", bad, &machine("fanuc.toml", &[]), &ToolTable::builtin()).unwrap_err();
    assert_eq!(e.number(), 26);
}

/// ISG G238 (TF5200 "Selecting inside corner of TRC"), the manual's star: the approach block
/// ends in the inner corner of the tip P2 = (0, 100), where the equidistants of the last block
/// N380 (20,20)→(0,100) and the first N310 (0,100)→(-20,20) meet. Both have slope ±4: the
/// parallels at distance 10 cross x = 0 at 10·√(1 + 4²) = 10√17 below the tip.
#[test]
fn isg_g238_selects_and_deselects_in_the_inner_corner() {
    let p = path("isg.toml", &[], &[], &program("isg", "g238_star.nc"));
    continuous(&p);
    let q = 100.0 - 10.0 * 17f64.sqrt();
    let approach = of_block(&p, 240);
    assert_eq!(roles(&approach), [Role::Approach]);
    at("approach start", approach[0].from, 0.0, 0.0);
    at("approach end: the inner corner", approach[0].to, 0.0, q);
    at(
        "first contour block starts there",
        of_block(&p, 310)[0].from,
        0.0,
        q,
    );
    let last = of_block(&p, 380);
    at(
        "the contour ends there too",
        last.last().unwrap().to,
        0.0,
        q,
    );
    // N390 G40 has no plane move: N400 G0 X0 Y0 leaves straight from the corner.
    let retract = of_block(&p, 400);
    assert_eq!(roles(&retract), [Role::Retract]);
    at("retract start", retract[0].from, 0.0, q);
    at("retract end", retract[0].to, 0.0, 0.0);
}

#[test]
fn isg_g238_refuses_what_the_manual_restricts() {
    let star = program("isg", "g238_star.nc");
    // Not closed: the last block ends 1 mm beside the tip (alarm at N380, line 18).
    let open = star.replace("N380 G01 X0 Y100", "N380 G01 X1 Y100");
    assert_eq!(
        alarm("isg.toml", &[], &open),
        (AlarmCode::InnerCornerSelection, 18)
    );
    // No G40 after the contour.
    let endless = star.replace("N390 G40 (Deselect TRC)", "N390");
    assert_eq!(
        alarm("isg.toml", &[], &endless).0,
        AlarmCode::InnerCornerSelection
    );
    // The first contour block is an arc.
    let arc = star.replace("N310 X-20 Y20", "N310 G2 X-20 Y20 R80\nN315 G1 X-20 Y20");
    assert_eq!(
        alarm("isg.toml", &[], &arc).0,
        AlarmCode::InnerCornerSelection
    );
    // With the tool outside (G42) the tip is an outer corner.
    let outside = star.replace("N230 G41", "N230 G42");
    assert_eq!(
        alarm("isg.toml", &[], &outside).0,
        AlarmCode::InnerCornerSelection
    );
    // The radius may not change while active.
    let d_change = star.replace("N330 X-20 Y-20", "N330 X-20 Y-20 D2");
    assert_eq!(
        alarm("isg.toml", &[], &d_change),
        (AlarmCode::InnerCornerSelection, 13)
    );
    // And G238 cannot be switched on while TRC is active (the front end refuses it).
    let late = star
        .replace("N210 G238", "N210 G139")
        .replace("N320 X-100 Y0", "N320 X-100 Y0 G238");
    assert_eq!(alarm("isg.toml", &[], &late).0, AlarmCode::ForbiddenWithTrc);
}

/// Fanuc C, change in the offset direction in the offset mode: no deselection; the old side's
/// equidistant of block A meets the new side's of block B, or without an intersection A runs
/// to B's normal position at its start. D1 = R10; the start-up ends at (0, 10).
#[test]
fn fanuc_side_change_in_offset_mode() {
    let run = |a: &str, b: &str, c: &str| {
        let src = format!(
            "N1 G17 G90 G0 X0 Y-20 D1;\nN2 G1 G41 X0 Y0 F100;\nN3 {a};\nN4 G42 {b};\nN5 {c};\nN6 G40 X200 Y-50;\nN7 M30;\n"
        );
        let p = path(
            "fanuc.toml",
            &["program.decimal_input=calculator"],
            &[],
            &src,
        );
        continuous(&p);
        p
    };
    // Line → line at 90°: A (0,0)→(50,0) on the left is y = 10; B (50,0)→(50,50) on the
    // right is x = 60. They meet at (60, 10).
    let p = run("X50", "X50 Y50", "X100");
    assert!(p
        .iter()
        .all(|s| s.role != Role::Retract || s.source.line == 6));
    at(
        "A ends at the intersection",
        of_block(&p, 3)[0].to,
        60.0,
        10.0,
    );
    at("B starts there", of_block(&p, 4)[0].from, 60.0, 10.0);
    // B's end: the inner corner (for the right side) with C (50,50)→(100,50), y = 40.
    at("B ends", of_block(&p, 4).last().unwrap().to, 60.0, 40.0);
    // Collinear: y = 10 and y = -10 never meet: A slants to B's normal position (50, -10).
    let p = run("X50", "X100 Y0", "X150");
    let a = of_block(&p, 3);
    assert_eq!(roles(&a), [Role::Contour]);
    at("A from", a[0].from, 0.0, 10.0);
    at("A slants to B's normal position", a[0].to, 50.0, -10.0);
    at("B", of_block(&p, 4)[0].to, 100.0, -10.0);
    // Line → arc: B is G2 (50,0)→(100,0) about (75,0), r 25; on the right of a clockwise arc
    // the tool is inside, r 15. y = 10 meets that circle at x = 75 ± √(15² − 10²); the point
    // nearer the corner is 75 − √125.
    let p = run("X50", "G2 X100 Y0 I25 J0", "G1 X150");
    let x = 75.0 - 125f64.sqrt();
    at("A ends on B's circle", of_block(&p, 3)[0].to, x, 10.0);
    let b = of_block(&p, 4);
    at("B starts there", b[0].from, x, 10.0);
    match b[0].shape {
        Shape::Arc { r0, r1, .. } => {
            assert!(
                (r0 - 15.0).abs() < TOL && (r1 - 15.0).abs() < TOL,
                "{r0} {r1}"
            )
        }
        Shape::Line => panic!("B is an arc"),
    }
}

/// ISG G11 (TF5200 "Adapting feed of TRC"): the programmed F600 acts at the contour. R = 5
/// (D2). N50 is a circle of radius 10 with the tool inside: the centre runs on radius 5 at
/// 600·5/10 = 300. N70, radius 10 with the tool outside: 600·15/10 = 900. The transition
/// circles at the outer corners N40/N50 and N80/N90 go round a contour radius of 0, taken as
/// the minimum radius (machine data, 1 mm): 600·(1 + 5)/1 = 3600. Lines keep 600. With G10
/// everything runs at 600.
#[test]
fn isg_g11_feed_acts_at_the_contour() {
    let src = program("isg", "g11_feed_adaption.nc");
    let feeds = |src: &str| -> Vec<(u32, Role, f64)> {
        path("isg.toml", ISG_OWN, &[], src)
            .iter()
            .filter(|s| s.role != Role::Uncompensated)
            .map(|s| (s.source.number.unwrap().value, s.role, s.feed))
            .collect()
    };
    assert_eq!(
        feeds(&src),
        [
            (30, Role::Approach, 600.0),
            (40, Role::Contour, 600.0),
            (50, Role::Corner, 3600.0),
            (50, Role::Contour, 300.0),
            (60, Role::Contour, 600.0),
            (70, Role::Contour, 900.0),
            (80, Role::Contour, 600.0),
            (90, Role::Corner, 3600.0),
            (90, Role::Contour, 600.0),
            (100, Role::Retract, 600.0),
        ]
    );
    let g10 = feeds(&src.replace("G26 G11", "G26 G10"));
    assert!(g10.iter().all(|&(_, _, f)| f == 600.0), "{g10:?}");
    // Below the minimum radius an arc keeps the programmed feed (#TANGFEED RMIN).
    let p = path(
        "isg.toml",
        &["trc.feed_adaption_rmin=12", ISG_OWN[0]],
        &[],
        &src,
    );
    let n50 = p
        .iter()
        .find(|s| s.source.number.unwrap().value == 50 && s.role == Role::Contour)
        .unwrap();
    assert_eq!(n50.feed, 600.0);
}

/// 840C 11.5.1: deselection with program end. The contour N20..N40 with G41, R = 10: N40 runs
/// up X60 from Y0 to Y40, its equidistant is x = 50 and its normal end position (50, 40).
/// - G40 with a plane axis in the last-but-one block: the deselection move runs.
/// - M30 while TRC is on, or G40 without a plane axis before M30: N40 ends in its normal
///   position and no deselection move follows.
#[test]
fn program_end_with_trc_active_11_5_1() {
    let head = "N10 G0 G17 G90 X0 Y-20 D1\nN20 G41 G1 X20 Y0 F100\nN30 X60 Y0\nN40 X60 Y40";
    let cases = [
        ("\nN50 G40 X80 Y40\nN60 M30\n", true),
        (" M30\n", false),
        ("\nN50 M30\n", false),
        ("\nN50 G40\nN60 M30\n", false),
    ];
    for (tail, deselects) in cases {
        let src = format!("{head}{tail}");
        let p = path("siemens-840c.toml", &[], &[], &src);
        continuous(&p);
        let n40 = of_block(&p, 40);
        let retract: Vec<_> = p.iter().filter(|s| s.role == Role::Retract).collect();
        if deselects {
            // The deselection block runs to its programmed point.
            at("retract end", retract.last().unwrap().to, 80.0, 40.0);
        } else {
            at(
                "N40 ends in its normal position",
                n40.last().unwrap().to,
                50.0,
                40.0,
            );
            assert!(retract.is_empty(), "{tail:?}: no deselection move");
            at("and stays there", p.last().unwrap().to, 50.0, 40.0);
        }
    }
}

/// 840C 11.8: D1 changed from R 10 to R 8 in NC stop, halfway along N40 of the 11.15
/// workpiece (N40 runs X65 → X95 at Y55, tool above). Old path: y = 65 from the inner corner
/// with N30 (circle r 25 + 10 about (40,55): x = 40 + √(35² − 10²)) to the one with N50
/// (circle r 15 + 10 about (110,55): x = 110 − √(25² − 10²)). New path: y = 63, from
/// x = 40 + √(33² − 8²) to x = 110 − √(23² − 8²). The axes stand at the old midpoint; the
/// reposition move goes to the new midpoint, and N40 goes on from there.
#[test]
fn offset_changed_in_nc_stop_resumes_on_the_new_equidistant_11_8() {
    use nc_kernel::Preparation;
    use nc_kernel::{Interruption, Prepared};
    let src = program("siemens-840c", "11_15_workpiece.mpf");
    let md = machine("siemens-840c.toml", &[]);
    let old = tools(&[]);
    // N40's execution number: the block's place in the run.
    let seq = prepare("t", &src, &md, &old)
        .unwrap()
        .iter()
        .find(|s| s.source.number.map(|n| n.value) == Some(40))
        .unwrap()
        .source
        .seq;
    let mid_old =
        0.5 * ((40.0 + (35f64.powi(2) - 100.0).sqrt()) + (110.0 - (25f64.powi(2) - 100.0).sqrt()));
    let (x0, x1) = (
        40.0 + (33f64.powi(2) - 64.0).sqrt(),
        110.0 - (23f64.powi(2) - 64.0).sqrt(),
    );
    let new = tools(&[(1, 8.0)]);
    let r = Preparation::resume(
        "t",
        &src,
        &md,
        &new,
        None,
        Interruption::contour(seq, 0.5),
        AxisPos {
            geo: [mid_old, 65.0, -5.0 + 100.0],
            ..AxisPos::default()
        },
    )
    .unwrap_or_else(|a| panic!("{a}"));
    // The additional axes' record (where they stand; this machine has none moving), then
    // the reposition move and the rest of the interrupted segment.
    let [Prepared::Axes(..), Prepared::Segment(reposition), Prepared::Segment(remainder)] =
        r.first.as_slice()
    else {
        panic!("the axes, then two segments first");
    };
    assert_eq!(reposition.role, Role::Approach);
    at("reposition from the axes", reposition.from, mid_old, 65.0);
    at(
        "to the new equidistant",
        reposition.to,
        0.5 * (x0 + x1),
        63.0,
    );
    at("N40 goes on", remainder.from, 0.5 * (x0 + x1), 63.0);
    at("to its new end", remainder.to, x1, 63.0);
    // Then N50 follows, on the new radius: a circle of 15 + 8 about (110,55).
    let mut rest = r.rest;
    let next = loop {
        match rest.next_item().unwrap() {
            Some(Prepared::Segment(s)) => break s,
            Some(_) => {}
            None => panic!("the program goes on"),
        }
    };
    assert_eq!(next.source.number.unwrap().value, 50);
    match next.shape {
        Shape::Arc { r0, .. } => assert!((r0 - 23.0).abs() < TOL),
        Shape::Line => panic!("N50 is an arc"),
    }
    // A radius that now violates the contour is an alarm before anything moves: with R 30
    // N40 (30 mm between two inner corners) runs backwards, 11.12.
    let huge = tools(&[(1, 30.0)]);
    let e = Preparation::resume(
        "t",
        &src,
        &md,
        &huge,
        None,
        Interruption::contour(seq, 0.5),
        AxisPos {
            geo: [mid_old, 65.0, 95.0],
            ..AxisPos::default()
        },
    )
    .err()
    .expect("alarm 3021");
    assert_eq!(
        (e.code, e.block.as_deref()),
        (AlarmCode::ContourViolation, Some("N40"))
    );
}

/// A full circle selected into (ISG G237 after G42, G25 corners, D2 = R 5) and run as
/// programmed is a full circle on the tool path too: N40 cw about (−8.43, −8.64), radius
/// √(8.43² + 8.64²), the tool inside (G42 on a cw arc), so radius R − 5, from the normal
/// position at (0, 0) moved 5 mm towards the centre, and back to that point to the bit
/// (two corners computed it; one ulp apart, the interpolator took it for an arc of no
/// length and the circle was never cut).
#[test]
fn a_compensated_full_circle_ends_where_it_starts() {
    let src = "N1 G17 G90 G0 X0 Y0 Z0\nN2 G1 F6000\nN10 D2 G1 X0 Y0\nN20 G42\nN30\nN40 G25 G237 G140 G2 X0 Y0 I-8.43 J-8.64\nN50\n";
    let p = path("isg.toml", &["trc.bottleneck_window=3"], &[], src);
    let n40 = of_block(&p, 40);
    let circle = n40.iter().find(|s| s.role == Role::Contour).unwrap();
    let big = (8.43f64 * 8.43 + 8.64 * 8.64).sqrt();
    let k = (big - 5.0) / big;
    at(
        "N40 starts",
        circle.from,
        -8.43 + 8.43 * k,
        -8.64 + 8.64 * k,
    );
    assert_eq!(circle.to, circle.from);
    let len = nc_kernel::ipo::Piece::new(circle).unwrap().len;
    assert!(
        (len - std::f64::consts::TAU * (big - 5.0)).abs() < 1e-9,
        "{len}"
    );
}

/// ISG G05 tangential approach and retract are arcs (TF5200): their records carry their own
/// radius as r0 = r1 (docs/path-format.md), the distance of both ends from the centre. N305
/// of wzkg25 (G41, R 10) runs from (0, 0) to N310's normal position (20, 30) (N315 goes
/// east), tangent to east there: the centre lies on x = 20 with 20² + y² = (30 − y)², so
/// y = 25/3 and the radius 65/3.
#[test]
fn isg_g05_approach_and_retract_arcs_carry_their_radius() {
    let p = path("isg.toml", &[], &[], &program("isg", "wzkg25.nc"));
    let arcs: Vec<&Segment> = p
        .iter()
        .filter(|s| matches!(s.role, Role::Approach | Role::Retract) && s.is_arc())
        .collect();
    assert_eq!(arcs.len(), 2);
    for s in arcs {
        let Shape::Arc { center, r0, r1, .. } = s.shape else {
            unreachable!()
        };
        let d = |q: [f64; 3]| (q[0] - center[0]).hypot(q[1] - center[1]);
        assert!(
            (r0 - d(s.from)).abs() < TOL && (r1 - d(s.to)).abs() < TOL,
            "{s:?}"
        );
    }
    let n305 = of_block(&p, 305)[0];
    at(
        "N305 centre",
        match n305.shape {
            Shape::Arc { center, .. } => center,
            Shape::Line => unreachable!(),
        },
        20.0,
        25.0 / 3.0,
    );
    assert!(matches!(n305.shape, Shape::Arc { r0, .. } if (r0 - 65.0 / 3.0).abs() < TOL));
}

/// A selection block followed at once by a deselection block (no contour element between
/// them): the selection block runs to its programmed point, and the deselection block's
/// own move goes out from there to its end — the path has no gap (840C, 808D, Fanuc lathe).
#[test]
fn deselection_right_after_selection_keeps_its_move() {
    // 840C mill, D1 R10: N20 G41 to (20, 10) — nothing to compensate against, so the
    // programmed point; N30 G40 to (30, 10); N40 on to (30, 40).
    let p = path(
        "siemens-840c.toml",
        &[],
        &[],
        "N10 G17 G90 G0 X0 Y0 D1\nN20 G41 G1 X20 Y10 F1000\nN30 G40 G0 X30\nN40 G1 Y40\nM30\n",
    );
    continuous(&p);
    let n30 = of_block(&p, 30);
    assert_eq!(roles(&n30), [Role::Retract]);
    at("N30 from", n30[0].from, 20.0, 10.0);
    at("N30 to", n30[0].to, 30.0, 10.0);
    // Fanuc lathe, T0101 (nose R0.8, cutting edge 3): G42 to X44 Z2, G40 G0 X40, on along Z.
    let lathe = path(
        "fanuc-lathe.toml",
        &[],
        &[],
        "N10 G18 G99 T0101 S500 M3\nN20 G0 X50. Z5.\nN30 G42 G1 X44. Z2. F0.2\n\
         N40 G40 G0 X40.\nN50 G1 Z-14.\nM30\n",
    );
    continuous(&lathe);
    assert_eq!(roles(&of_block(&lathe, 40)), [Role::Retract]);
}
