//! SINUMERIK 840C programs in the 840C's own language (config/siemens-840c.toml: R0 … R1299,
//! `@` commands, G17, mm) in tests/corpus/siemens-840c/. Every move's end point is compared
//! with values worked out by hand; each program's header comment shows the arithmetic. The end
//! points are the programmed ones (no zero offset is active, tool centre offsets are not
//! applied to them). Subprograms (`L41.SPF`: the l programs) stand beside the programs and are
//! found as `softnc` finds them. Programs that run cleanly also pass `softnc check`; programs
//! that must stop name their alarm's code, line and column, and the moves made before it.

#[path = "support/corpus.rs"]
mod corpus;

use corpus::*;
use nc_kernel::{AlarmCode, Block, MotionKind, TrcSide};

const CORPUS: Corpus = Corpus {
    dir: "tests/corpus/siemens-840c",
    machine: "config/siemens-840c.toml",
};

fn clean(file: &str, want: &[P]) -> Vec<Block> {
    CORPUS.clean(file, want)
}

fn stops(file: &str, want: &[P], code: AlarmCode, line: u32, col: u32) -> nc_kernel::Alarm {
    CORPUS.stops(file, want, code, line, col)
}

fn numbers(b: &[Block]) -> Vec<u32> {
    b.iter().filter_map(|b| b.number.map(|n| n.value)).collect()
}

#[test]
fn k01_r_parameter_arithmetic() {
    let f = "k01_r_parameter_arithmetic.mpf";
    let b = clean(
        f,
        &[
            [12.5, 25.0, 5.0],  // N30: R1, R2 = 12.5·2
            [22.0, -22.0, 5.0], // N50: −R4 = 22 (R4 = −22.5 + 0.5), R5 = 12.5·4/10
            [60.0, 60.0, -7.5], // N70: R6 = 12.5 + 50 − 2.5, −R7, R8 = 60/8 assigned first
            [67.0, 53.0, -0.5], // N90: G91 by R9 = 2·2·2 − 1 = 7
            [0.0, 0.0, 5.0],    // N100: R0 never written
            [7.0, 0.0, 5.0],    // N110
        ],
    );
    // Blocks of assignments alone are statements: they hand out no block.
    assert_eq!(numbers(&b), [10, 30, 50, 70, 90, 100, 110, 120], "{f}");
    assert!(
        block(f, &b, 70).calculation,
        "N70 assigns R8 among its words"
    );
    assert_eq!(block(f, &b, 110).modal.feed, 25.0, "{f}: F R2");
}

#[test]
fn k02_counted_loop() {
    let f = "k02_counted_loop.mpf";
    let mut want = vec![[-20.0, 0.0, 5.0]];
    for z in [-1.5, -3.0, -4.5, -6.0] {
        want.extend([
            [-20.0, 0.0, z],
            [120.0, 0.0, z],
            [120.0, 0.0, 5.0],
            [-20.0, 0.0, 5.0],
        ]);
    }
    want.push([-20.0, 0.0, 50.0]);
    let b = clean(f, &want);
    // The main block :60 carries its number like an N block, once per pass.
    let passes = b.iter().filter(|b| b.number.is_some_and(|n| n.value == 60));
    assert_eq!(passes.count(), 4, "{f}");
}

#[test]
fn k03_hole_pattern_trig() {
    let f = "k03_hole_pattern_trig.mpf";
    let h = 15.0 * 3f64.sqrt(); // 30·cos 30
    let holes = [
        [50.0 + h, 55.0],
        [50.0, 70.0],
        [50.0 - h, 55.0],
        [50.0 - h, 25.0],
        [50.0, 10.0],
        [50.0 + h, 25.0],
    ];
    let mut want = vec![[0.0, 0.0, 5.0]];
    for [x, y] in holes {
        want.extend([[x, y, 5.0], [x, y, -8.0], [x, y, 5.0]]);
    }
    want.push([50.0 + h, 25.0, 50.0]);
    let b = clean(f, &want);
    let drills = b.iter().filter(|b| b.number.is_some_and(|n| n.value == 90));
    assert!(
        drills
            .clone()
            .all(|b| b.motion.unwrap().kind == MotionKind::Linear),
        "{f}"
    );
    assert_eq!(drills.count(), 6, "{f}");
}

#[test]
fn k04_feed_and_cutting_speed() {
    let f = "k04_feed_and_cutting_speed.mpf";
    let b = clean(
        f,
        &[
            [50.0, 0.0, 5.0],
            [50.0, 0.0, 0.0],  // N40 G94
            [40.0, 0.0, 0.0],  // N50 G95
            [30.0, 0.0, 0.0],  // N70 G96
            [10.0, 0.0, 0.0],  // N90
            [20.0, 0.0, 0.0],  // N100 G97
            [20.0, 10.0, 0.0], // N110 G94
        ],
    );
    let m = |n: u32| block(f, &b, n).modal;
    assert_eq!((m(40).feed_per_rev, m(40).feed), (false, 500.0));
    assert_eq!((m(50).feed_per_rev, m(50).feed), (true, 0.2), "F R6");
    assert_eq!((m(50).css, m(50).spindle), (false, 1000.0));
    assert_eq!(m(60).spindle_limit, 2500.0, "G92 S");
    assert!(block(f, &b, 60).motion.is_none());
    assert_eq!(
        (m(70).css, m(70).spindle, m(70).feed),
        (true, 200.0, 0.2),
        "S R5"
    );
    assert_eq!(m(80).spindle_limit, 1800.0, "G26 S");
    assert_eq!(
        (m(80).css, m(80).spindle),
        (true, 200.0),
        "G26's S is no speed"
    );
    assert!(block(f, &b, 80).motion.is_none());
    assert_eq!(
        (m(100).css, m(100).spindle, m(100).spindle_limit),
        (false, 800.0, 1800.0)
    );
    assert_eq!((m(110).feed_per_rev, m(110).feed), (false, 300.0));
}

#[test]
fn k05_contour_g41_from_r() {
    let f = "k05_contour_g41_from_r.mpf";
    let b = clean(
        f,
        &[
            [-2.0, -7.0, 2.0], // R8 = R1 − R6, R9 = R2 − R6
            [-2.0, -7.0, -3.0],
            [10.0, 5.0, -3.0],  // G41 to (R1, R2)
            [10.0, 45.0, -3.0], // R4 = 5 + 40
            [72.0, 45.0, -3.0], // R10 = R3 − R7 = 80 − 8
            [80.0, 37.0, -3.0], // G2 CR=R7 to (R3, R11)
            [80.0, 5.0, -3.0],
            [10.0, 5.0, -3.0],
            [-2.0, -7.0, -3.0], // G40
            [-2.0, -7.0, 20.0],
        ],
    );
    let arc = block(f, &b, 90);
    let m = arc.motion.unwrap();
    assert_eq!(m.kind, MotionKind::ArcCw);
    assert!((m.center[0] - 72.0).abs() <= TOL && (m.center[1] - 37.0).abs() <= TOL);
    assert_eq!(
        (arc.modal.tool, arc.modal.d, arc.modal.radius),
        (Some(5), 2, 5.0)
    );
    for n in [60, 70, 80, 90, 100, 110] {
        assert_eq!(block(f, &b, n).modal.trc, TrcSide::Left, "{f}: N{n}");
    }
    assert_eq!(block(f, &b, 120).modal.trc, TrcSide::Off);
}

#[test]
fn k06_alarm_endless_jump() {
    let a = stops(
        "k06_alarm_endless_jump.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::LoopLimit,
        11,
        5,
    );
    assert!(a.message.contains("max_loop_iterations"), "{a}");
    assert_eq!(a.block.as_deref(), Some("N60"));
}

#[test]
fn k07_alarm_missing_block() {
    let a = stops(
        "k07_alarm_missing_block.mpf",
        &[[10.0, 10.0, 5.0]],
        AlarmCode::JumpTarget,
        7,
        16,
    );
    assert!(a.message.contains("N100"), "{a}");
}

#[test]
fn k08_case_block_main_blocks() {
    let f = "k08_case_block_main_blocks.mpf";
    let b = clean(f, &[[0.0, 0.0, 5.0], [0.0, 0.0, -4.0], [0.0, 0.0, 50.0]]);
    assert_eq!(
        numbers(&b),
        [10, 30, 200, 400, 410],
        "{f}: the branch taken"
    );
}

#[test]
fn l01_840c_l_calls() {
    clean(
        "l01_l_calls.mpf",
        &[
            [0.0, 0.0, 5.0],
            [10.0, 5.0, 5.0],
            [20.0, 10.0, 5.0],
            [0.0, 0.0, 5.0],
            [-5.0, 0.0, 5.0],
            [5.0, 5.0, 5.0],
            [5.0, 5.0, 50.0],
        ],
    );
}

#[test]
fn l02_840c_alarm_missing() {
    let a = stops(
        "l02_alarm_missing.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::MissingProgram,
        4,
        5,
    );
    assert!(a.message.contains("L99.SPF"), "{a}");
}
