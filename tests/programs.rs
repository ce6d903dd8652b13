//! The seed programs in `programs/`, interpreted with the machine data of their dialect.
//!
//! Every expected value below is worked out by hand from the program text (the arithmetic is
//! in the comments next to it), never copied from softnc's output. Positions are in the basic
//! coordinate system in mm ([X, Y, Z], all zero offsets 0 in the shipped config); on the 808D
//! lathe X is programmed as a diameter and expected here as the radius (diameter / 2).

use nc_kernel::{AlarmCode, Block, MachineData, ToolTable};
use nc_kernel::{CornerPolicy, MotionKind, Plane, SelectionPolicy, TrcSide};
use std::path::PathBuf;

const TOL: f64 = 1e-9;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn source(dir: &str, file: &str) -> String {
    let path = root().join("programs").join(dir).join(file);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn machine(config: &str) -> MachineData {
    let path = root().join("config").join(config);
    MachineData::load(Some(&path), &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// Interprets `programs/<dir>/<file>` with `config/<config>`; panics on an alarm.
fn run(dir: &str, file: &str, config: &str) -> Vec<Block> {
    let src = source(dir, file);
    let md = machine(config);
    let tools = ToolTable::builtin();
    nc_kernel::interpret(file, &src, &md, &tools).unwrap_or_else(|a| panic!("{file}: alarm {a}"))
}

fn motions(blocks: &[Block]) -> Vec<&Block> {
    blocks.iter().filter(|b| b.motion.is_some()).collect()
}

/// End point of the last motion block.
fn final_pos(blocks: &[Block]) -> [f64; 3] {
    motions(blocks)
        .last()
        .expect("no motion")
        .motion
        .unwrap()
        .end
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[track_caller]
fn assert_pos(what: &str, actual: [f64; 3], expected: [f64; 3]) {
    assert!(
        (0..3).all(|i| close(actual[i], expected[i], TOL)),
        "{what}: got {actual:?}, expected {expected:?} (tolerance {TOL})"
    );
}

#[track_caller]
fn assert_f(what: &str, actual: f64, expected: f64, tol: f64) {
    assert!(
        close(actual, expected, tol),
        "{what}: got {actual}, expected {expected} (tolerance {tol})"
    );
}

/// The (first) block labelled `label` (e.g. "N45").
#[track_caller]
fn block<'a>(blocks: &'a [Block], label: &str) -> &'a Block {
    blocks
        .iter()
        .find(|b| b.number.is_some() && b.label() == label)
        .unwrap_or_else(|| panic!("no block {label}"))
}

fn index_of(blocks: &[Block], label: &str) -> usize {
    blocks
        .iter()
        .position(|b| b.number.is_some() && b.label() == label)
        .unwrap_or_else(|| panic!("no block {label}"))
}

#[track_caller]
fn end_of(blocks: &[Block], label: &str) -> [f64; 3] {
    block(blocks, label)
        .motion
        .unwrap_or_else(|| panic!("{label} has no motion"))
        .end
}

#[track_caller]
fn centre_of(blocks: &[Block], label: &str) -> [f64; 3] {
    let m = block(blocks, label)
        .motion
        .unwrap_or_else(|| panic!("{label} has no motion"));
    assert!(m.kind.is_arc(), "{label} is not an arc");
    m.center
}

/// Checks the end point of each listed block.
#[track_caller]
fn assert_ends(blocks: &[Block], expected: &[(&str, [f64; 3])]) {
    for (label, p) in expected {
        assert_pos(label, end_of(blocks, label), *p);
    }
}

/// Blocks strictly between `from` and `to` that do not move in the compensation plane
/// (840C 11.11: auxiliary function blocks, path = 0, infeed outside the plane).
fn outside_plane_between(blocks: &[Block], from: &str, to: &str) -> usize {
    let (a, b) = (index_of(blocks, from), index_of(blocks, to));
    blocks[a + 1..b]
        .iter()
        .filter(|b| b.number.is_some())
        .filter(|b| !b.motion.is_some_and(|m| m.moves_in_plane(TOL)))
        .count()
}

/// 1-based line of the first line of `src` that starts with `prefix` (from the text).
fn line_of(src: &str, prefix: &str) -> u32 {
    src.lines()
        .position(|l| l.trim_start().starts_with(prefix))
        .expect("line not found") as u32
        + 1
}

fn word(b: &Block, address: u8, value: f64) -> bool {
    b.words
        .iter()
        .any(|w| w.address == address && w.value == value)
}

// ---------------------------------------------------------------------------------------
// SINUMERIK 840C (seed 000), config/siemens-840c.toml, tools: D1 R10, D2 R5, D7 R8.
// ---------------------------------------------------------------------------------------

const C840: &str = "siemens-840c";
const C840_MD: &str = "siemens-840c.toml";

#[test]
fn c840_11_15_workpiece() {
    let b = run(C840, "11_15_workpiece.mpf", C840_MD);
    // N1 N5 N10 N20 N30 N40 N50 N60 N70 N80 N90 N100 N110 N120 N130 = 15 motion blocks.
    assert_eq!(motions(&b).len(), 15);
    assert_ends(
        &b,
        &[
            ("N1", [15.0, 60.0, 5.0]),
            ("N5", [15.0, 60.0, -5.0]),
            ("N10", [30.0, 60.0, -5.0]),
            ("N30", [65.0, 55.0, -5.0]),
            ("N50", [110.0, 70.0, -5.0]),
            ("N110", [30.0, 60.0, -5.0]),
            ("N120", [15.0, 60.0, -5.0]),
        ],
    );
    // N30 G2 from (40,80) with I0 J-25: centre (40+0, 80-25) = (40,55); radius 25 to (65,55).
    assert_pos("N30 centre", centre_of(&b, "N30"), [40.0, 55.0, -5.0]);
    assert_eq!(block(&b, "N30").motion.unwrap().kind, MotionKind::ArcCw);
    // N50 G2 from (95,55) with I15 J0: centre (95+15, 55+0) = (110,55); radius 15 to (110,70).
    assert_pos("N50 centre", centre_of(&b, "N50"), [110.0, 55.0, -5.0]);
    // N10: G41 with G450 and D1 (radius 10), F400, S80.
    let n10 = block(&b, "N10");
    assert_eq!(n10.trc, Some(TrcSide::Left));
    assert_eq!(n10.modal.corner, CornerPolicy::TransitionCircle);
    assert_eq!(n10.modal.plane, Plane::XY);
    assert_eq!(n10.modal.d, 1);
    assert_f("N10 radius", n10.modal.radius, 10.0, 1e-12);
    assert_f("N10 feed", n10.modal.feed, 400.0, 1e-12);
    assert_f("N10 spindle", n10.modal.spindle, 80.0, 1e-12);
    assert_eq!(block(&b, "N120").trc, Some(TrcSide::Off));
    assert!(block(&b, "N130").stop.is_some_and(|s| s.ends_program()));
    // N130 G0 Z50 from P0 at depth: (15, 60, 50).
    assert_pos("final", final_pos(&b), [15.0, 60.0, 50.0]);
}

#[test]
fn c840_11_10_aux_functions() {
    let b = run(C840, "11_10_aux_functions.mpf", C840_MD);
    // N1 N10 N20 N25 N30 N35 N40 = 7 motion blocks (N5 G451 has none).
    assert_eq!(motions(&b).len(), 7);
    assert!(block(&b, "N5").motion.is_none());
    assert_eq!(block(&b, "N5").modal.corner, CornerPolicy::Intersection);
    assert_ends(
        &b,
        &[
            ("N1", [-20.0, 0.0, 2.0]),
            ("N10", [0.0, 0.0, 2.0]),
            ("N20", [50.0, 50.0, 2.0]),
            // N25 Z-5: infeed outside the TRC plane at (50,50).
            ("N25", [50.0, 50.0, -5.0]),
            ("N30", [50.0, 0.0, -5.0]),
            ("N35", [50.0, -20.0, -5.0]),
        ],
    );
    assert!(!block(&b, "N25").motion.unwrap().moves_in_plane(TOL));
    let n20 = block(&b, "N20");
    assert!(word(n20, b'H', 1.0));
    assert_eq!(n20.trc, Some(TrcSide::Left));
    let n25 = block(&b, "N25");
    assert!(word(n25, b'M', 3.0) && word(n25, b'S', 2000.0) && word(n25, b'H', 2.0));
    assert_f("N25 feed", n25.modal.feed, 10.0, 1e-12);
    let n30 = block(&b, "N30");
    assert!(word(n30, b'H', 3.0));
    assert_f("N30 feed", n30.modal.feed, 2000.0, 1e-12);
    // N40 G0 Z50: (50, -20, 50).
    assert_pos("final", final_pos(&b), [50.0, -20.0, 50.0]);
}

#[test]
fn c840_11_11_three_blocks_outside_plane() {
    let b = run(C840, "11_11_three_blocks_outside_plane.mpf", C840_MD);
    // N5 N10 N15 N25 N35 N40 N45 N50 N55 = 9 motion blocks (N30 M08 H1 has none).
    assert_eq!(motions(&b).len(), 9);
    assert_ends(
        &b,
        &[
            ("N15", [0.0, 100.0, -5.0]),
            // N25 G91 X200: 0 + 200 = 200.
            ("N25", [200.0, 100.0, -5.0]),
            // N35 X0 (G91): path 0.
            ("N35", [200.0, 100.0, -5.0]),
            // N40 Z-5 (G91): -5 - 5 = -10.
            ("N40", [200.0, 100.0, -10.0]),
            // N45 Y-100 (G91): 100 - 100 = 0.
            ("N45", [200.0, 0.0, -10.0]),
            ("N50", [220.0, -20.0, -10.0]),
        ],
    );
    // N30 (aux), N35 (path 0), N40 (Z only): 3 blocks outside the plane, the maximum.
    let md = machine(C840_MD);
    let n = outside_plane_between(&b, "N25", "N45");
    assert_eq!(n, 3);
    assert!(n as u32 <= md.trc.max_blocks_outside_plane);
    let n30 = block(&b, "N30");
    assert!(n30.motion.is_none() && word(n30, b'M', 8.0) && word(n30, b'H', 1.0));
    assert_eq!(block(&b, "N45").modal.trc, TrcSide::Left);
    // N55 G0 Z50: (220, -20, 50).
    assert_pos("final", final_pos(&b), [220.0, -20.0, 50.0]);
}

#[test]
fn c840_11_11_four_blocks_outside_plane_parses_at_front_end() {
    // Alarm 3021 belongs to the TRC stage; the front end must accept the program.
    let b = run(C840, "11_11_four_blocks_outside_plane_alarm.mpf", C840_MD);
    // N5 N10 N15 N25 N35 N40 N50 N55 N60 = 9 motion blocks (N30 M08 and N45 H2 have none).
    assert_eq!(motions(&b).len(), 9);
    assert_ends(
        &b,
        &[
            ("N25", [200.0, 100.0, -5.0]),
            ("N35", [200.0, 100.0, -5.0]),
            ("N40", [200.0, 100.0, -10.0]),
            // N50 Y-100 (G91): 100 - 100 = 0.
            ("N50", [200.0, 0.0, -10.0]),
            ("N55", [220.0, -20.0, -10.0]),
        ],
    );
    // N30 (aux), N35 (path 0), N40 (Z only), N45 (aux): 4 > 3 blocks outside the plane.
    let md = machine(C840_MD);
    let n = outside_plane_between(&b, "N25", "N50");
    assert_eq!(n, 4);
    assert!(n as u32 > md.trc.max_blocks_outside_plane);
    assert_pos("final", final_pos(&b), [220.0, -20.0, 50.0]);
}

#[test]
fn c840_11_5_2_selection_variant1() {
    let b = run(C840, "11_5_2_selection_variant1.mpf", C840_MD);
    // N5 N10 N15 N20 N25 N30 N35 N40 N45 = 9 motion blocks.
    assert_eq!(motions(&b).len(), 9);
    let n10 = block(&b, "N10");
    assert_eq!(n10.trc, Some(TrcSide::Left));
    assert_eq!(n10.modal.d, 7);
    // D07 = radius 8 in tools.toml.
    assert_f("D07 radius", n10.modal.radius, 8.0, 1e-12);
    assert_ends(
        &b,
        &[
            ("N10", [0.0, 0.0, 5.0]),
            // N15 Z-5: only Z moves.
            ("N15", [0.0, 0.0, -5.0]),
            ("N20", [0.0, 50.0, -5.0]),
            ("N25", [80.0, 50.0, -5.0]),
            ("N30", [80.0, 0.0, -5.0]),
            ("N35", [0.0, 0.0, -5.0]),
            ("N40", [-20.0, -20.0, -5.0]),
        ],
    );
    assert!(!block(&b, "N15").motion.unwrap().moves_in_plane(TOL));
    assert_eq!(block(&b, "N40").trc, Some(TrcSide::Off));
    assert_pos("final", final_pos(&b), [-20.0, -20.0, 50.0]);
}

#[test]
fn c840_11_5_2_selection_variant2() {
    let b = run(C840, "11_5_2_selection_variant2.mpf", C840_MD);
    // N5 N20 N25 N30 N35 N40 N45 N50 N55 = 9 motion blocks (N10 G17, N15 G41 D07 have none).
    assert_eq!(motions(&b).len(), 9);
    let n15 = block(&b, "N15");
    assert!(n15.motion.is_none());
    assert_eq!(n15.trc, Some(TrcSide::Left));
    assert_eq!(n15.modal.d, 7);
    assert_f("D07 radius", n15.modal.radius, 8.0, 1e-12);
    let n20 = block(&b, "N20").motion.unwrap();
    assert_pos("N20 start", n20.start, [-20.0, -20.0, 5.0]);
    assert_pos("N20 end", n20.end, [0.0, 0.0, 5.0]);
    assert_eq!(n20.kind, MotionKind::Linear);
    assert_ends(
        &b,
        &[
            ("N25", [0.0, 0.0, -5.0]),
            ("N45", [0.0, 0.0, -5.0]),
            ("N50", [-20.0, -20.0, -5.0]),
        ],
    );
    assert_pos("final", final_pos(&b), [-20.0, -20.0, 50.0]);
}

#[test]
fn c840_11_6_2_partial_turned_part() {
    let b = run(C840, "11_6_2_partial_turned_part.mpf", C840_MD);
    // N40 N50 N55 N60 N65 N70 N75 N80 = 8 motion blocks.
    assert_eq!(motions(&b).len(), 8);
    for m in motions(&b) {
        assert_eq!(m.motion.unwrap().plane, Plane::ZX, "{}", m.label());
    }
    // Points (X radius on this milling machine data, Y stays 0):
    // A = X30 Z0, B = X30 Z-40, C = X25 Z-40, D = X25 Z-10, E = X20 Z0.
    assert_ends(
        &b,
        &[
            ("N40", [40.0, 0.0, 5.0]),
            ("N50", [30.0, 0.0, 0.0]),
            ("N55", [30.0, 0.0, -40.0]),
            ("N60", [30.0, 0.0, -40.0]),
            ("N65", [25.0, 0.0, -40.0]),
            ("N70", [25.0, 0.0, -10.0]),
            ("N75", [20.0, 0.0, 0.0]),
        ],
    );
    let n50 = block(&b, "N50");
    assert_eq!(n50.trc, Some(TrcSide::Right));
    assert_eq!(n50.motion.unwrap().kind, MotionKind::Rapid);
    // N60: G41 at the same point B: a programmed block with path 0.
    let n60 = block(&b, "N60");
    assert_eq!(n60.trc, Some(TrcSide::Left));
    assert_pos("N60 start", n60.motion.unwrap().start, [30.0, 0.0, -40.0]);
    // D2 = radius 5.
    assert_f("D2 radius", n60.modal.radius, 5.0, 1e-12);
    assert_eq!(block(&b, "N80").trc, Some(TrcSide::Off));
    assert_pos("final", final_pos(&b), [40.0, 0.0, 5.0]);
}

#[test]
fn c840_11_6_2_two_contour_sections() {
    let b = run(C840, "11_6_2_two_contour_sections.mpf", C840_MD);
    // N1 N2 N5 N10 N15 N20 N25 N30 N35 = 9 motion blocks.
    assert_eq!(motions(&b).len(), 9);
    // N15 G3 full circle at P1 = (40,10) with I0 J20: centre (40+0, 10+20) = (40,30).
    let n15 = block(&b, "N15").motion.unwrap();
    assert_eq!(n15.kind, MotionKind::ArcCcw);
    assert_pos("N15 start", n15.start, [40.0, 10.0, -5.0]);
    assert_pos("N15 end", n15.end, [40.0, 10.0, -5.0]);
    assert_pos("N15 centre", n15.center, [40.0, 30.0, -5.0]);
    // N25 G3 full circle at P2 = (100,15) with I0 J15: centre (100+0, 15+15) = (100,30).
    let n25 = block(&b, "N25").motion.unwrap();
    assert_pos("N25 end", n25.end, [100.0, 15.0, -5.0]);
    assert_pos("N25 centre", n25.center, [100.0, 30.0, -5.0]);
    let n20 = block(&b, "N20");
    assert_eq!(n20.trc, Some(TrcSide::Right));
    assert_eq!(n20.approach, Some(SelectionPolicy::NormalPosition));
    assert_eq!(block(&b, "N10").trc, Some(TrcSide::Right));
    assert_ends(&b, &[("N5", [0.0, 0.0, -5.0]), ("N30", [130.0, 0.0, -5.0])]);
    assert_pos("final", final_pos(&b), [130.0, 0.0, 50.0]);
}

#[test]
fn c840_11_6_2_line_by_line_milling() {
    let b = run(C840, "11_6_2_line_by_line_milling.mpf", C840_MD);
    // N1 N10 N15 N20 N30 N40 N50 N60 N70 N80 N90 = 11 motion blocks.
    assert_eq!(motions(&b).len(), 11);
    assert_ends(
        &b,
        &[
            ("N10", [-20.0, 60.0, 5.0]),
            ("N15", [-20.0, 60.0, -2.0]),
            ("N20", [0.0, 50.0, -2.0]),
            ("N30", [100.0, 50.0, -2.0]),
            ("N40", [100.0, 40.0, -2.0]),
            ("N50", [0.0, 40.0, -2.0]),
            ("N60", [0.0, 30.0, -2.0]),
            ("N70", [100.0, 30.0, -2.0]),
            ("N80", [120.0, 20.0, -2.0]),
        ],
    );
    let sides: Vec<_> = ["N20", "N40", "N60", "N80"]
        .iter()
        .map(|l| block(&b, l).trc)
        .collect();
    assert_eq!(
        sides,
        [
            Some(TrcSide::Right),
            Some(TrcSide::Left),
            Some(TrcSide::Right),
            Some(TrcSide::Off)
        ]
    );
    assert_eq!(block(&b, "N70").modal.trc, TrcSide::Right);
    assert_pos("final", final_pos(&b), [120.0, 20.0, 50.0]);
}

#[test]
fn c840_11_7_d_change() {
    let b = run(C840, "11_7_d_change.mpf", C840_MD);
    // N5 N10 N20 N30 N40 N45 N50 N55 N60 = 9 motion blocks.
    assert_eq!(motions(&b).len(), 9);
    let n40 = block(&b, "N40");
    assert_eq!(n40.modal.d, 1);
    assert_f("D1 radius", n40.modal.radius, 10.0, 1e-12);
    let n45 = block(&b, "N45");
    assert!(n45.offset_changed);
    assert_eq!(n45.modal.d, 2);
    assert_f("D2 radius", n45.modal.radius, 5.0, 1e-12);
    let m = n45.motion.unwrap();
    assert_eq!(m.kind, MotionKind::Linear);
    assert_eq!(m.plane, Plane::ZX);
    assert_pos("N45 start", m.start, [25.0, 0.0, -35.0]);
    assert_pos("N45 end", m.end, [30.0, 0.0, -45.0]);
    assert_eq!(block(&b, "N50").modal.trc, TrcSide::Right);
    assert_ends(
        &b,
        &[("N50", [30.0, 0.0, -60.0]), ("N55", [45.0, 0.0, -60.0])],
    );
    // N60 G0 Z10 at X45: (45, 0, 10).
    assert_pos("final", final_pos(&b), [45.0, 0.0, 10.0]);
}

// ---------------------------------------------------------------------------------------
// ISG / TwinCAT CNC (seed 002), config/isg.toml, tools: D1 R10, D2 R5, D6 R10, D100 R4.
// ---------------------------------------------------------------------------------------

const ISG: &str = "isg";
const ISG_MD: &str = "isg.toml";

/// Shared by %WZKG25 and %WZKG26: the contour and the three paths use the same numbers.
/// `p` = first block number of the paths (100/400), `q` (200/500), `r` (300/600).
fn check_wzkg(b: &[Block], p: u32, q: u32, r: u32) {
    // Presentation: N10 N15 N25 N30 N35 N40 N45 = 7; each path 6 motion blocks
    // (x05, x15, x20, x25, x30, x40) = 18; total 25.
    assert_eq!(motions(b).len(), 25);
    assert_f("D1 radius", block(b, "N10").modal.radius, 10.0, 1e-12);
    // Contour under G91 from (20,20): X10 -> (30,20); X5 Y-5 -> (35,15); Y-5 -> (35,10);
    // X-5 Y-3 -> (30,7).
    let contour = |n: [u32; 4]| {
        assert_pos(
            &format!("N{}", n[0]),
            end_of(b, &format!("N{}", n[0])),
            [30.0, 20.0, 0.0],
        );
        assert_pos(
            &format!("N{}", n[1]),
            end_of(b, &format!("N{}", n[1])),
            [35.0, 15.0, 0.0],
        );
        assert_pos(
            &format!("N{}", n[2]),
            end_of(b, &format!("N{}", n[2])),
            [35.0, 10.0, 0.0],
        );
        assert_pos(
            &format!("N{}", n[3]),
            end_of(b, &format!("N{}", n[3])),
            [30.0, 7.0, 0.0],
        );
    };
    assert_pos("N15", end_of(b, "N15"), [20.0, 20.0, 0.0]);
    contour([25, 30, 35, 40]);
    assert_pos("N45", end_of(b, "N45"), [0.0, 0.0, 0.0]);
    for base in [p, q, r] {
        assert_pos(
            "x05",
            end_of(b, &format!("N{}", base + 5)),
            [20.0, 20.0, 0.0],
        );
        contour([base + 15, base + 20, base + 25, base + 30]);
    }
    assert_pos("p40", end_of(b, &format!("N{}", p + 40)), [0.0, 0.0, 0.0]);
    assert_pos("q40", end_of(b, &format!("N{}", q + 40)), [0.0, 0.0, 0.0]);
    // Path 3/6: the last block N340/N640 "G01 X20 Y20" has no G90: still G91 from N315/N615,
    // so it ends at (30+20, 7+20) = (50, 27).
    let last = block(b, &format!("N{}", r + 40)).motion.unwrap();
    assert_pos("r40 start", last.start, [30.0, 7.0, 0.0]);
    assert_pos("r40 end", last.end, [50.0, 27.0, 0.0]);
    // Selection methods: G138 direct, G139 indirect (modal), G05 tangential (block).
    assert_eq!(
        block(b, &format!("N{p}")).modal.selection,
        SelectionPolicy::Direct
    );
    assert_eq!(block(b, &format!("N{p}")).trc, Some(TrcSide::Left));
    assert_eq!(block(b, &format!("N{}", p + 35)).trc, Some(TrcSide::Off));
    assert_eq!(
        block(b, &format!("N{q}")).modal.selection,
        SelectionPolicy::Indirect
    );
    assert_eq!(
        block(b, &format!("N{r}")).approach,
        Some(SelectionPolicy::Tangential)
    );
    assert_eq!(
        block(b, &format!("N{}", r + 35)).approach,
        Some(SelectionPolicy::Tangential)
    );
    assert!(block(b, "N999").stop.is_some_and(|s| s.ends_program()));
    assert_pos("final", final_pos(b), [50.0, 27.0, 0.0]);
}

#[test]
fn isg_wzkg25() {
    let b = run(ISG, "wzkg25.nc", ISG_MD);
    check_wzkg(&b, 100, 200, 300);
    assert_eq!(
        block(&b, "N110").modal.corner,
        CornerPolicy::LinearTransition
    );
}

#[test]
fn isg_wzkg26() {
    let b = run(ISG, "wzkg26.nc", ISG_MD);
    check_wzkg(&b, 400, 500, 600);
    assert_eq!(
        block(&b, "N410").modal.corner,
        CornerPolicy::TransitionCircle
    );
}

#[test]
fn isg_d_change() {
    let b = run(ISG, "d_change.nc", ISG_MD);
    // N30 N40 N50 N60 N80 N90 N100 N110 N120 N130 N140 N150 N170 = 13 motion blocks.
    assert_eq!(motions(&b).len(), 13);
    let n30 = block(&b, "N30");
    assert_eq!(n30.modal.d, 0);
    assert_f("D0 radius", n30.modal.radius, 0.0, 0.0);
    let n40 = block(&b, "N40");
    assert_eq!(n40.modal.d, 100);
    assert_f("D100 radius", n40.modal.radius, 4.0, 1e-12);
    assert_eq!(block(&b, "N70").trc, Some(TrcSide::Left));
    // N90 G2 full circle at (10,10) with I-15: centre (10-15, 10) = (-5, 10).
    let n90 = block(&b, "N90").motion.unwrap();
    assert_eq!(n90.kind, MotionKind::ArcCw);
    assert_pos("N90 start", n90.start, [10.0, 10.0, 0.0]);
    assert_pos("N90 end", n90.end, [10.0, 10.0, 0.0]);
    assert_pos("N90 centre", n90.center, [-5.0, 10.0, 0.0]);
    let n110 = block(&b, "N110");
    assert!(n110.offset_changed);
    assert_eq!(n110.modal.d, 2);
    assert_f("D2 radius", n110.modal.radius, 5.0, 1e-12);
    assert_pos("N110", end_of(&b, "N110"), [10.0, 10.0, 200.0]);
    // N140 G02 full circle at (20,20) with I-15: centre (20-15, 20) = (5, 20).
    assert_pos("N140 end", end_of(&b, "N140"), [20.0, 20.0, 0.0]);
    assert_pos("N140 centre", centre_of(&b, "N140"), [5.0, 20.0, 0.0]);
    assert_eq!(block(&b, "N160").trc, Some(TrcSide::Off));
    // N170 X0 (G0, absolute): (0, 20, 100).
    assert_pos("final", final_pos(&b), [0.0, 20.0, 100.0]);
}

#[test]
fn isg_d_change_as_printed_n140_is_not_a_circle() {
    // The seed prints N140 G02 X10 Y10 I-15 after N130 G1 X20 Y20: centre (20-15, 20) =
    // (5,20), start radius 15, end radius sqrt((10-5)^2 + (10-20)^2) = sqrt(125) = 11.18.
    let src = source(ISG, "d_change.nc");
    let changed = "N140 G02 X20 Y20 I-15";
    assert!(src.contains(changed));
    let printed = src.replacen(changed, "N140 G02 X10 Y10 I-15", 1);
    let md = machine(ISG_MD);
    let err = nc_kernel::interpret(
        "d_change_as_printed.nc",
        &printed,
        &md,
        &ToolTable::builtin(),
    )
    .expect_err("the printed N140 has its end point off the circle");
    assert_eq!(err.code, AlarmCode::ArcEndPoint);
    assert_eq!(err.block.as_deref(), Some("N140"));
}

#[test]
fn isg_grinding_cycle() {
    let src = source(ISG, "grinding_cycle.nc");
    let b = run(ISG, "grinding_cycle.nc", ISG_MD);
    // $FOR V.P.LAUF = 0,100,10: 0, 10, ..., 100 = 100/10 + 1 = 11 passes.
    let passes = 11usize;
    // N00, N20, 11 passes x (N110 N120 N130 N140), N200: 2 + 44 + 1 = 47 motion blocks.
    assert_eq!(motions(&b).len(), 2 + 4 * passes + 1);
    let l110 = line_of(&src, "N110");
    let n110: Vec<_> = b.iter().filter(|x| x.line == l110).collect();
    assert_eq!(n110.len(), passes);
    // Pass k runs N110 with radius 10 - k*0.010 (D6 = 10, reduced at the end of each pass).
    for (k, blk) in n110.iter().enumerate() {
        assert_f(
            &format!("pass {k} radius"),
            blk.modal.radius,
            10.0 - k as f64 * 0.010,
            1e-12,
        );
        assert_pos("N110", blk.motion.unwrap().end, [300.0, 250.0, 0.0]);
    }
    let l140 = line_of(&src, "N140");
    assert_eq!(b.iter().filter(|x| x.line == l140).count(), passes);
    // Radius after the loop: 10 - 11 * 0.010 = 9.89.
    let r_end = 10.0 - 11.0 * 0.010;
    let n200 = block(&b, "N200");
    assert_f("radius after the loop", n200.modal.radius, r_end, 1e-12);
    assert_f("final radius", b.last().unwrap().modal.radius, r_end, 1e-12);
    assert_eq!(n200.trc, Some(TrcSide::Off));
    assert_eq!(
        block(&b, "N10").modal.corner,
        CornerPolicy::TransitionCircle
    );
    assert_f("F5", block(&b, "N00").modal.feed, 5.0, 1e-12);
    assert_ends(&b, &[("N00", [0.0, 0.0, 0.0]), ("N20", [0.0, 250.0, 0.0])]);
    // N200 G40 X300 from (0,250): (300, 250, 0).
    assert_pos("final", final_pos(&b), [300.0, 250.0, 0.0]);
}

// ---------------------------------------------------------------------------------------
// Fanuc (seed 003), config/fanuc.toml: decimal_input = "increment", 0.001 mm per count.
// ---------------------------------------------------------------------------------------

const FANUC: &str = "fanuc";
const FANUC_MD: &str = "fanuc.toml";

#[test]
fn fanuc_example_a_line() {
    let b = run(FANUC, "example_a_line.nc", FANUC_MD);
    // N1 N3 N4 N5 N6 = 5 motion blocks (N2 G17 G01 F200. has no axis).
    assert_eq!(motions(&b).len(), 5);
    assert_f("F200.", block(&b, "N2").modal.feed, 200.0, 1e-12);
    let n3 = block(&b, "N3");
    assert_eq!(n3.trc, Some(TrcSide::Left));
    assert_f("D1 radius", n3.modal.radius, 10.0, 1e-12);
    assert_ends(
        &b,
        &[
            ("N1", [0.0, 0.0, -5.0]),
            ("N3", [50.0, 30.0, -5.0]),
            ("N4", [100.0, 30.0, -5.0]),
            ("N5", [120.0, 0.0, -5.0]),
        ],
    );
    assert_pos("final", final_pos(&b), [120.0, 0.0, 50.0]);
}

#[test]
fn fanuc_example_b_arc_decimal_input_increment() {
    let b = run(FANUC, "example_b_arc.nc", FANUC_MD);
    // No decimal points: every length counts 0.001 mm.
    // N1 N3 N4 N5 N6 = 5 motion blocks.
    assert_eq!(motions(&b).len(), 5);
    assert_ends(
        &b,
        &[
            // X0 Y60000 Z-5000 -> (0, 60000*0.001, -5000*0.001) = (0, 60, -5).
            ("N1", [0.0, 60.0, -5.0]),
            // X50000 Y30000 -> (50, 30).
            ("N3", [50.0, 30.0, -5.0]),
            // X70000 Y10000 -> (70, 10).
            ("N4", [70.0, 10.0, -5.0]),
            // X100000 -> 100.
            ("N5", [100.0, 10.0, -5.0]),
        ],
    );
    // F200 is a feedrate, not a length: 200 mm/min (not 0.2).
    assert_f("F200", block(&b, "N2").modal.feed, 200.0, 1e-12);
    // N4 G02 from (50,30) with J-20000 = -20 mm: centre (50+0, 30-20) = (50, 10);
    // radius 20 both to the start and to the end (70,10).
    let n4 = block(&b, "N4").motion.unwrap();
    assert_eq!(n4.kind, MotionKind::ArcCw);
    assert_pos("N4 centre", n4.center, [50.0, 10.0, -5.0]);
    assert_eq!(block(&b, "N3").trc, Some(TrcSide::Left));
    assert_eq!(block(&b, "N5").trc, Some(TrcSide::Off));
    // N6 G00 Z50000 -> Z50.
    assert_pos("final", final_pos(&b), [100.0, 10.0, 50.0]);
}

#[test]
fn fanuc_example_a_line_g42_decimal_input_increment() {
    let b = run(FANUC, "example_a_line_g42.nc", FANUC_MD);
    // N1 N3 N4 N5 N6 = 5 motion blocks.
    assert_eq!(motions(&b).len(), 5);
    let n3 = block(&b, "N3");
    assert_eq!(n3.trc, Some(TrcSide::Right));
    assert_f("D2 radius", n3.modal.radius, 5.0, 1e-12);
    assert_ends(
        &b,
        &[
            // Y60000 Z-5000 -> 60, -5.
            ("N1", [0.0, 60.0, -5.0]),
            ("N3", [50.0, 30.0, -5.0]),
            // X100000 -> 100.
            ("N4", [100.0, 30.0, -5.0]),
            // X120000 Y60000 -> (120, 60).
            ("N5", [120.0, 60.0, -5.0]),
        ],
    );
    assert_pos("final", final_pos(&b), [120.0, 60.0, 50.0]);
}

#[test]
fn fanuc_example_b_arc_g42() {
    let b = run(FANUC, "example_b_arc_g42.nc", FANUC_MD);
    // N1 N2 N4 N5 N6 N7 = 6 motion blocks.
    assert_eq!(motions(&b).len(), 6);
    assert_ends(
        &b,
        &[
            ("N1", [50.0, 10.0, 2.0]),
            ("N2", [50.0, 10.0, -5.0]),
            ("N4", [50.0, 30.0, -5.0]),
            ("N5", [70.0, 10.0, -5.0]),
            ("N6", [50.0, 10.0, -5.0]),
        ],
    );
    // N5 G02 from (50,30) with J-20.: centre (50, 30-20) = (50, 10).
    assert_pos("N5 centre", centre_of(&b, "N5"), [50.0, 10.0, -5.0]);
    assert_eq!(block(&b, "N4").trc, Some(TrcSide::Right));
    assert_f("D2 radius", block(&b, "N4").modal.radius, 5.0, 1e-12);
    assert_pos("final", final_pos(&b), [50.0, 10.0, 50.0]);
}

// ---------------------------------------------------------------------------------------
// SINUMERIK 808D turning (seed 004), config/siemens-808d.toml: G18, X as diameter.
// Tools: T1 D1 R0.8, T1 D2 R0.4. Expected X values are radii = programmed diameter / 2.
// ---------------------------------------------------------------------------------------

const S808: &str = "siemens-808d";
const S808_MD: &str = "siemens-808d.toml";

#[test]
fn s808d_g40_deselection() {
    let b = run(S808, "g40_deselection.mpf", S808_MD);
    // N20 N30 N40 N50 N60 N70 N80 N90 N100 N110 N120 = 11 motion blocks.
    assert_eq!(motions(&b).len(), 11);
    let n10 = block(&b, "N10");
    assert_eq!(n10.modal.tool, Some(1));
    assert_f("T1 D1 radius", n10.modal.radius, 0.8, 1e-12);
    assert!(n10.modal.diameter);
    for m in motions(&b) {
        assert_eq!(m.motion.unwrap().plane, Plane::ZX, "{}", m.label());
    }
    assert_ends(
        &b,
        &[
            ("N30", [0.0, 0.0, 0.0]),
            // X16 -> radius 8.
            ("N40", [8.0, 0.0, 0.0]),
            // X20 -> radius 10.
            ("N50", [10.0, 0.0, -2.0]),
            ("N60", [10.0, 0.0, -20.0]),
            // X30 -> 15.
            ("N70", [15.0, 0.0, -20.0]),
            ("N80", [15.0, 0.0, -35.0]),
            // X40 -> 20 (P1).
            ("N90", [20.0, 0.0, -40.0]),
            // X50 -> 25 (P2).
            ("N100", [25.0, 0.0, -40.0]),
            // X60 -> 30.
            ("N110", [30.0, 0.0, -40.0]),
        ],
    );
    // N50 G3 CR=2 from (Z0, r8) to (Z-2, r10): chord midpoint (Z-1, r9), half chord sqrt(2),
    // distance of the centre from the chord sqrt(4 - 2) = sqrt(2) on the left (G3): centre
    // (Z-2, r8) — the edge rounding of the face/diameter corner.
    let n50 = block(&b, "N50").motion.unwrap();
    assert_eq!(n50.kind, MotionKind::ArcCcw);
    assert_pos("N50 centre", n50.center, [8.0, 0.0, -2.0]);
    // N90 G2 CR=5 from (Z-35, r15) to (Z-40, r20): midpoint (Z-37.5, r17.5), offset
    // sqrt(25 - 12.5) on the right (G2): centre (Z-35, r20) — the concave fillet.
    let n90 = block(&b, "N90").motion.unwrap();
    assert_eq!(n90.kind, MotionKind::ArcCw);
    assert_pos("N90 centre", n90.center, [20.0, 0.0, -35.0]);
    assert_eq!(block(&b, "N30").trc, Some(TrcSide::Right));
    let n100 = block(&b, "N100");
    assert_eq!(n100.trc, Some(TrcSide::Off));
    assert_eq!(n100.motion.unwrap().kind, MotionKind::Linear);
    // N120 Z5 at X60 (r30).
    assert_pos("final", final_pos(&b), [30.0, 0.0, 5.0]);
}

#[test]
fn s808d_direction_change() {
    let b = run(S808, "direction_change.mpf", S808_MD);
    // N20 N30 N40 N50 N60 N70 N80 N90 N100 N110 N120 = 11 motion blocks.
    assert_eq!(motions(&b).len(), 11);
    assert_ends(
        &b,
        &[
            // X48 -> 24.
            ("N20", [24.0, 0.0, 2.0]),
            ("N30", [24.0, 0.0, 0.0]),
            ("N40", [0.0, 0.0, 0.0]),
            // X16 -> 8.
            ("N50", [8.0, 0.0, 1.0]),
            // X20 -> 10.
            ("N60", [10.0, 0.0, -1.0]),
            ("N70", [10.0, 0.0, -25.0]),
            // X30 -> 15.
            ("N80", [15.0, 0.0, -25.0]),
            ("N90", [15.0, 0.0, -40.0]),
            // X36 -> 18.
            ("N100", [18.0, 0.0, -40.0]),
        ],
    );
    assert_eq!(block(&b, "N30").trc, Some(TrcSide::Left));
    assert_eq!(block(&b, "N40").modal.trc, TrcSide::Left);
    let n50 = block(&b, "N50");
    assert_eq!(n50.trc, Some(TrcSide::Right));
    assert_eq!(n50.modal.trc, TrcSide::Right);
    assert_eq!(block(&b, "N100").trc, Some(TrcSide::Off));
    // N120 Z5 at X60 (r30).
    assert_pos("final", final_pos(&b), [30.0, 0.0, 5.0]);
}

#[test]
fn s808d_repeat_g41() {
    let b = run(S808, "repeat_g41.mpf", S808_MD);
    // N20 N30 N40 N50 N60 N70 N80 N90 N100 = 9 motion blocks.
    assert_eq!(motions(&b).len(), 9);
    assert_ends(
        &b,
        &[
            // X24 -> 12.
            ("N20", [12.0, 0.0, 2.0]),
            ("N30", [12.0, 0.0, 0.0]),
            ("N40", [0.0, 0.0, 0.0]),
            ("N50", [12.0, 0.0, 2.0]),
            // X48 -> 24.
            ("N60", [24.0, 0.0, -18.0]),
            ("N70", [24.0, 0.0, -20.0]),
            // X20 -> 10.
            ("N80", [10.0, 0.0, -20.0]),
            ("N90", [12.0, 0.0, -18.0]),
        ],
    );
    assert_eq!(block(&b, "N30").trc, Some(TrcSide::Left));
    // N60: G41 again while G41 is active: recorded as programmed.
    assert_eq!(block(&b, "N50").modal.trc, TrcSide::Left);
    let n60 = block(&b, "N60");
    assert_eq!(n60.trc, Some(TrcSide::Left));
    assert_eq!(n60.motion.unwrap().kind, MotionKind::Rapid);
    assert_eq!(block(&b, "N90").trc, Some(TrcSide::Off));
    // N100 G0 X60 Z5: (30, 0, 5).
    assert_pos("final", final_pos(&b), [30.0, 0.0, 5.0]);
}

#[test]
fn s808d_d_change() {
    let b = run(S808, "d_change.mpf", S808_MD);
    // N20 N30 N40 N50 N60 N70 N80 N90 N100 N110 N120 = 11 motion blocks.
    assert_eq!(motions(&b).len(), 11);
    let n10 = block(&b, "N10");
    assert!(n10.modal.diameter);
    assert_eq!(n10.modal.tool, Some(1));
    assert_eq!(n10.modal.d, 1);
    assert_f("T1 D1 radius", n10.modal.radius, 0.8, 1e-12);
    assert_ends(
        &b,
        &[
            // X16 -> 8.
            ("N20", [8.0, 0.0, 3.0]),
            ("N30", [8.0, 0.0, 0.0]),
            ("N40", [8.0, 0.0, -10.0]),
            // X24 -> 12.
            ("N50", [12.0, 0.0, -20.0]),
            ("N60", [12.0, 0.0, -30.0]),
            // X34 -> 17.
            ("N70", [17.0, 0.0, -35.0]),
            // X40 -> 20.
            ("N80", [20.0, 0.0, -35.0]),
            ("N90", [20.0, 0.0, -50.0]),
            // X46 -> 23.
            ("N100", [23.0, 0.0, -50.0]),
        ],
    );
    // D change over a line: N50 T1 D2 = radius 0.4.
    let n50 = block(&b, "N50");
    assert!(n50.offset_changed);
    assert_eq!(n50.modal.d, 2);
    assert_f("T1 D2 radius", n50.modal.radius, 0.4, 1e-12);
    assert_eq!(n50.motion.unwrap().kind, MotionKind::Linear);
    // D change over an arc: N70 back to T1 D1 = radius 0.8.
    let n70 = block(&b, "N70");
    assert!(n70.offset_changed);
    assert_eq!(n70.modal.d, 1);
    assert_f("T1 D1 radius", n70.modal.radius, 0.8, 1e-12);
    let arc = n70.motion.unwrap();
    assert_eq!(arc.kind, MotionKind::ArcCw);
    // G2 CR=5 from (Z-30, r12) to (Z-35, r17): midpoint (Z-32.5, r14.5), centre offset
    // sqrt(25 - 12.5) = 3.5355 on the right of the chord (G2): centre (Z-30, r17).
    assert_pos("N70 start", arc.start, [12.0, 0.0, -30.0]);
    assert_pos("N70 centre", arc.center, [17.0, 0.0, -30.0]);
    assert_eq!(block(&b, "N60").modal.trc, TrcSide::Right);
    assert_eq!(block(&b, "N100").trc, Some(TrcSide::Off));
    // N120 Z5 at X60 (r30).
    assert_pos("final", final_pos(&b), [30.0, 0.0, 5.0]);
}
