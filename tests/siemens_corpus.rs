//! SINUMERIK programs for the 828D / 840D sl milling machine (config/siemens-840d.toml: the
//! SINUMERIK language, G17, mm, R0 … R99) in tests/corpus/siemens-840d/. Every
//! move's end point is compared with values worked out by hand; each program's header comment
//! shows the arithmetic. The end points are the programmed ones (no zero offset is active,
//! tool centre offsets are not applied to them). Subprogram files (`NAME.SPF`) stand beside
//! the programs and are found as `softnc` finds them (the program's folder). Programs that
//! run cleanly also pass `softnc check`; programs that must stop name their alarm's code,
//! line and column, and the moves made before it.

#[path = "support/corpus.rs"]
mod corpus;

use corpus::*;
use nc_kernel::{AlarmCode, Block, MachineData, MotionKind, ToolTable, TrcSide};

const CORPUS: Corpus = Corpus {
    dir: "tests/corpus/siemens-840d",
    machine: "config/siemens-840d.toml",
};

fn path_of(file: &str) -> std::path::PathBuf {
    CORPUS.path_of(file)
}

fn machine() -> MachineData {
    CORPUS.machine()
}

fn machine_for(file: &str) -> MachineData {
    CORPUS.machine_for(file)
}

fn run(file: &str) -> (Vec<Block>, Option<nc_kernel::Alarm>) {
    CORPUS.run(file)
}

fn clean(file: &str, want: &[P]) -> Vec<Block> {
    CORPUS.clean(file, want)
}

fn stops(file: &str, want: &[P], code: AlarmCode, line: u32, col: u32) -> nc_kernel::Alarm {
    CORPUS.stops(file, want, code, line, col)
}

#[test]
fn s01_r_parameter_arithmetic() {
    let f = "s01_r_parameter_arithmetic.mpf";
    let b = clean(
        f,
        &[
            [12.5, 25.0, 5.0],  // N30: R1 = 12.5, R2 = 12.5·2
            [17.5, -23.0, 0.5], // N50: 12.5 + 5, −R2 (R[2] = 22.5 + 0.5), 23 − 22.5
            [56.0, 9.6, -6.56], // N80: (12.5 + 23)·2 − 120/8, 120/12.5, −(56 + 9.6)/10
            [12.5, 0.0, 20.0],  // N100: 120/9.6, R0, 12.5 − 12.5 + 20
        ],
    );
    // An assignment-only block is a block of its own, marked as a calculation.
    assert!(block(f, &b, 20).calculation && block(f, &b, 20).motion.is_none());
    assert!(
        block(f, &b, 80).calculation,
        "N80 assigns R7 among its words"
    );
}

#[test]
fn s02_functions() {
    clean(
        "s02_functions.mpf",
        &[
            [0.0, 0.0, 10.0],
            [5.0, 5.0, 1.0],       // SIN(30)·10, COS(60)·10, TAN(45)
            [30.0, 120.0, -135.0], // ASIN(0.5), ACOS(−0.5), ATAN2(−1, −1)
            [10.0, 7.25, -3.0],    // SQRT(36 + 64), ABS(−7.25), TRUNC(−3.9)
            [3.0, 2.0, 3.0],       // ROUND(2.5), ROUND(2.49), ROUNDUP(2.01)
            [1.5, 1.0, 4.0],       // LN(EXP(1.5)), EXP(0), ROUNDUP(4)
            [-4.0, 3.0, 2.0],      // MINVAL, MAXVAL, BOUND(−2, 2, 5)
            [-2.0, 1.5, 3.0],      // BOUND(−2, 2, −9), BOUND(−2, 2, 1.5), 5·3/5
        ],
    );
}

#[test]
fn s03_def_types() {
    clean(
        "s03_def_types.mpf",
        &[
            [0.0, 3.0, 2.0],    // INT: 0 by default, 2.5 → 3, 2.49 → 2
            [4.0, -1.0, -2.75], // 7/2 = 3.5 → 4, −1.2 → −1, REAL −2.75
            [1.0, 0.0, 0.125],  // BOOL 7 → TRUE, FALSE, 1/8
            [10.0, 1.0, 0.125], // the IF branch: 10·TRUE, 4 DIV 3
            [3.0, 1.0, -2.5],   // ZDEPTH −2.75 + 0.25, CNT = ABS(−2.5) → 3
        ],
    );
}

#[test]
fn s04_operator_priority() {
    clean(
        "s04_operator_priority.mpf",
        &[
            [0.0, 1.0, 12.5], // 3 == (2 OR 1); (3 == 2) OR 1; 2 + 12 − 1.5
            [3.0, 2.0, -3.0], // 17 DIV 5, 17 MOD 5, −17 DIV 5
            [2.0, 13.0, 0.0], // 6 MOD 4; 12 B_OR (3 B_AND 5); (5 + 3) B_AND 6
            [7.0, 11.0, 9.0], // 6 B_XOR 1; 9 B_OR (6 B_XOR 5); (B_NOT 0) + 10
            [0.0, 1.0, 1.0],  // (NOT 0) AND 0; 1 OR (0 AND 0); 1 XOR (0 AND 0)
            [1.0, 0.0, 3.0],  // (1 XOR 1) OR 1; (3 > 2) AND (2 < 2); (10 − 4) − 3
            [-6.0, 0.0, 3.0], // 2·−3
        ],
    );
}

#[test]
fn s05_if_else_nested() {
    let f = "s05_if_else_nested.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 0.0],
            [1.0, 10.0, 0.0],  // odd, PASS == 1: N120
            [2.0, 20.0, 0.0],  // even, not 4: N80
            [3.0, 30.0, 0.0],  // odd, not 1: N140
            [4.0, 40.0, 0.0],  // even, 4: N60
            [20.0, 40.0, 0.0], // N220: R1·5; N200 and N240 do not run
        ],
    );
    let lines: Vec<u32> = b
        .iter()
        .filter(|b| b.motion.is_some())
        .map(|b| b.line)
        .collect();
    assert_eq!(lines, [14, 25, 21, 27, 19, 35], "{f}: the branches taken");
}

#[test]
fn s06_while_gotof_exit() {
    let mut want = vec![[0.0, 0.0, 2.0]];
    for z in [-1.5, -3.0] {
        want.extend([
            [0.0, 0.0, z],
            [40.0, 0.0, z],
            [40.0, 0.0, 2.0],
            [0.0, 0.0, 2.0],
        ]);
    }
    // −4.5 < −4: GOTOF FINISH, the last pass at −4; the second WHILE does not run.
    want.extend([[0.0, 0.0, -4.0], [40.0, 0.0, -4.0], [40.0, 0.0, 2.0]]);
    want.push([-4.5, 0.0, 2.0]); // N170 X = DEPTH
    clean("s06_while_gotof_exit.mpf", &want);
}

#[test]
fn s07_for_loops() {
    let mut want = vec![[0.0, 0.0, 2.0]];
    for row in [1.0, 2.0] {
        for col in [1.0, 2.0, 3.0] {
            let (x, y) = (col * 15.0, row * 10.0);
            want.extend([[x, y, 2.0], [x, y, -1.0], [x, y, 2.0]]);
        }
    }
    want.extend([[5.0, -1.0, 2.0], [10.0, -2.0, 2.0], [15.0, -3.0, 2.0]]); // FOR R1
    want.push([0.0, 0.0, 2.0]); // FOR COL=5 TO 4 ran no pass
    let b = clean("s07_for_loops.mpf", &want);
    assert!(b.iter().all(|b| b.line != 25), "N130 never runs");
}

#[test]
fn s08_repeat_until() {
    clean(
        "s08_repeat_until.mpf",
        &[
            [0.0, 0.0, 0.0],
            [15.0, 0.0, 0.0], // one pass: UNTIL 15 > 0 at once
            [15.0, 11.0, 0.0],
            [15.0, 7.0, 0.0],
            [15.0, 3.0, 0.0], // 3 < 4: GOTOF OUT
            [15.0, 3.0, 10.0],
        ],
    );
}

#[test]
fn s09_loop_gotof() {
    clean(
        "s09_loop_gotof.mpf",
        &[
            [0.0, 0.0, 1.0],
            [10.0, 1.0, 1.0],
            [20.0, 4.0, 1.0],
            [30.0, 9.0, 1.0],
            [40.0, 16.0, 1.0],
            [40.0, 16.0, 50.0],
        ],
    );
}

#[test]
fn s10_gotob_counter() {
    let mut want = vec![[-5.0, 0.0, 0.0]];
    // Passes R1 = 1, 3, 5: along +X at Y (R1 − 1)·8, step 8, back, step 8.
    for y in [0.0, 16.0, 32.0] {
        want.extend([
            [60.0, y, 0.0],
            [60.0, y + 8.0, 0.0],
            [-5.0, y + 8.0, 0.0],
            [-5.0, y + 16.0, 0.0],
        ]);
    }
    want.push([-5.0, 48.0, 20.0]);
    clean("s10_gotob_counter.mpf", &want);
}

#[test]
fn s11_goto_forward_then_start() {
    clean(
        "s11_goto_forward_then_start.mpf",
        &[
            [0.0, 0.0, 5.0],
            [10.0, 0.0, 5.0],
            [20.0, 0.0, 5.0], // GOTO TOP found from the start
            [30.0, 0.0, 5.0], // GOTO FINISH found forward
            [30.0, 20.0, 5.0],
        ],
    );
}

#[test]
fn s12_gotoc_missing_label() {
    clean(
        "s12_gotoc_missing_label.mpf",
        &[
            [0.0, 0.0, 5.0],
            [10.0, 0.0, 5.0],  // after GOTOC NOT_THERE
            [10.0, 10.0, 5.0], // GOTOC SKIP_IT jumped over N50
            [10.0, 10.0, 0.0], // after IF … GOTOC N999
        ],
    );
}

#[test]
fn s13_jump_block_numbers() {
    clean(
        "s13_jump_block_numbers.mpf",
        &[
            [0.0, 0.0, 5.0],
            [5.0, -5.0, 5.0],
            [10.0, -10.0, 5.0],
            [15.0, -15.0, 5.0],
            [15.0, -15.0, 20.0],
        ],
    );
}

#[test]
fn s14_ac_ic() {
    clean(
        "s14_ac_ic.mpf",
        &[
            [10.0, 10.0, 0.0],
            [15.0, 20.0, 0.0],  // X=IC(5) under G90
            [30.0, 20.0, 0.0],  // G90 again
            [35.0, 2.0, -1.0],  // G91 X5, Y=AC(2), Z=AC(−1)
            [36.0, 0.0, -1.0],  // X=IC(1), Y−2 incremental
            [36.0, 10.0, -1.0], // G91 again
            [0.0, 9.0, 2.0],    // G90 X=AC(0), Y=IC(−1), Z=IC(3)
            [5.0, 2.5, 2.0],    // X=IC(2.5·2), Y=AC(2.5)
        ],
    );
}

#[test]
fn s15_rectangle_g41() {
    let f = "s15_rectangle_g41.mpf";
    let b = clean(
        f,
        &[
            [-2.0, -7.0, 2.0], // R1 − R6, R2 − R6
            [-2.0, -7.0, -3.0],
            [10.0, 5.0, -3.0],  // G41 to (R1, R2)
            [10.0, 45.0, -3.0], // R4 = 5 + 40
            [72.0, 45.0, -3.0], // R3 − R7 = 80 − 8
            [80.0, 37.0, -3.0], // G2 CR=8 to (R3, R4 − R7)
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
    // T5 D2: D2 of the tool table (radius 5), TRC left from N60 to N110.
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
fn s16_bolt_circle_for() {
    let r3 = 3f64.sqrt();
    let mut want = vec![[50.0, 40.0, 10.0]];
    let holes = [
        (50.0 + 10.0 * r3, 50.0), // 30°
        (50.0, 60.0),             // 90°
        (50.0 - 10.0 * r3, 50.0), // 150°
        (50.0 - 10.0 * r3, 30.0), // 210°
        (50.0, 20.0),             // 270°
        (50.0 + 10.0 * r3, 30.0), // 330°
    ];
    for (x, y) in holes {
        want.extend([[x, y, 2.0], [x, y, -8.0], [x, y, 2.0]]);
    }
    want.push([50.0 + 10.0 * r3, 30.0, 50.0]);
    let b = clean("s16_bolt_circle_for.mpf", &want);
    let feeds: Vec<MotionKind> = b.iter().filter_map(|b| b.motion.map(|m| m.kind)).collect();
    assert_eq!(
        feeds.iter().filter(|k| **k == MotionKind::Linear).count(),
        6,
        "one G1 per hole"
    );
}

#[test]
fn s17_stopre_msg() {
    let f = "s17_stopre_msg.mpf";
    let b = clean(f, &[[0.0, 0.0, 5.0], [0.0, 0.0, -2.0], [20.0, 0.0, -2.0]]);
    let n10 = block(f, &b, 10);
    assert_eq!(n10.message.as_deref(), Some("Roughing; pass 1"));
    assert_eq!((n10.line, n10.col, n10.preprocess_stop), (12, 5, false));
    let n40 = block(f, &b, 40);
    assert!(n40.preprocess_stop && n40.message.is_none() && n40.motion.is_none());
    assert_eq!(block(f, &b, 60).message.as_deref(), Some("Pass done"));
    let n80 = block(f, &b, 80);
    assert!(n80.message.is_none() && !n80.preprocess_stop);
    // G4 F1.5 dwells 1.5 s and leaves the feed at 200.
    let n90 = block(f, &b, 90);
    assert_eq!((n90.dwell, n90.modal.feed), (Some(1.5), 200.0));
    let stops = b.iter().filter(|b| b.preprocess_stop).count();
    assert_eq!(stops, 1, "{f}: only STOPRE stops preprocessing");
}

#[test]
fn s18_slot_arcs() {
    let f = "s18_slot_arcs.mpf";
    let b = clean(
        f,
        &[
            [0.0, -10.0, 2.0],
            [0.0, -10.0, -1.0],
            [30.0, -10.0, -1.0],
            [30.0, 10.0, -1.0], // G3 CR=10 about (30, 0)
            [0.0, 10.0, -1.0],
            [0.0, -10.0, -1.0], // G3 I=0 J=−R2 about (0, 0)
            [0.0, -10.0, 2.0],
            [10.0, -10.0, -8.0], // G18 G2 CR=10
            [10.0, -10.0, 20.0],
        ],
    );
    let c50 = block(f, &b, 50).motion.unwrap().center;
    let c70 = block(f, &b, 70).motion.unwrap().center;
    assert!(
        (c50[0] - 30.0).abs() <= TOL && c50[1].abs() <= TOL,
        "{c50:?}"
    );
    assert!(c70[0].abs() <= TOL && c70[1].abs() <= TOL, "{c70:?}");
    assert_eq!(block(f, &b, 70).motion.unwrap().kind, MotionKind::ArcCcw);
}

#[test]
fn s19_def_one_letter_name() {
    let a = stops("s19_def_one_letter_name.mpf", &[], AlarmCode::Syntax, 6, 13);
    assert_eq!(a.number(), 12080);
}

#[test]
fn s20_cr_from_r_parameter() {
    clean(
        "s20_cr_from_r_parameter.mpf",
        &[
            [0.0, 0.0, 0.0],
            [20.0, 0.0, 0.0],
            [20.0, 20.0, 0.0], // G3 CR=R1 about (20, 10)
            [10.0, 20.0, 0.0], // G2 CR=R1/2 about (15, 20)
            [0.0, 20.0, 0.0],
        ],
    );
}

#[test]
fn s21_alarm_if_open() {
    let a = stops(
        "s21_alarm_if_open.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::ControlNesting,
        6,
        5,
    );
    assert_eq!(a.number(), 12640);
    assert!(a.message.contains("ENDIF"), "{a}");
}

#[test]
fn s21_s22_s29_structure_alarms_name_their_block_and_refuse_the_load() {
    for (file, n) in [
        ("s21_alarm_if_open.mpf", "N30"),
        ("s22_alarm_endwhile_closes_for.mpf", "N50"),
        ("s29_alarm_label_on_structure.mpf", "N30"),
    ] {
        let a = run(file).1.expect("an alarm");
        assert_eq!(a.block.as_deref(), Some(n), "{file}: {a}");
        // The kernel reads the structures through before anything moves: refused at load.
        let text = std::fs::read_to_string(path_of(file)).unwrap();
        let refused = nc_kernel::handover::spawn_preparation(
            file.into(),
            text,
            machine(),
            ToolTable::builtin(),
            None,
        )
        .expect("thread");
        let Err(at_load) = refused else {
            panic!("{file}: the kernel took the program")
        };
        assert_eq!(
            (at_load.line, at_load.col),
            (a.line, a.col),
            "{file}: {at_load}"
        );
    }
}

#[test]
fn s22_alarm_endwhile_closes_for() {
    let a = stops(
        "s22_alarm_endwhile_closes_for.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::ControlNesting,
        7,
        5,
    );
    assert_eq!(a.number(), 12640);
    assert!(a.message.contains("FOR"), "{a}");
}

#[test]
fn s23_alarm_gotof_missing_label() {
    let a = stops(
        "s23_alarm_gotof_missing_label.mpf",
        &[[0.0, 0.0, 5.0], [10.0, 0.0, 5.0]],
        AlarmCode::JumpTarget,
        6,
        11,
    );
    assert_eq!(a.number(), 14080);
    assert_eq!(a.block.as_deref(), Some("N30"));
}

#[test]
fn s24_alarm_endless_loop() {
    let a = stops(
        "s24_alarm_endless_loop.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::LoopLimit,
        8,
        5,
    );
    assert_eq!(a.number(), 12650);
}

#[test]
fn s25_alarm_r100() {
    let a = stops(
        "s25_alarm_r100.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::UndefinedName,
        5,
        12,
    );
    assert_eq!(a.number(), 12550);
    assert!(a.message.contains("R100"), "{a}");
}

#[test]
fn s26_alarm_undefined_variable() {
    let a = stops(
        "s26_alarm_undefined_variable.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::UndefinedName,
        5,
        10,
    );
    assert_eq!(a.number(), 12550);
    assert!(a.message.contains("DEPHT"), "{a}");
}

#[test]
fn s27_alarm_division_by_zero() {
    let a = stops(
        "s27_alarm_division_by_zero.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::Arithmetic,
        5,
        16,
    );
    assert_eq!(a.number(), 14000);
}

#[test]
fn s28_alarm_setal() {
    let a = stops(
        "s28_alarm_setal.mpf",
        &[[0.0, 0.0, 5.0], [20.0, 0.0, 5.0]],
        AlarmCode::ProgramAlarm,
        7,
        7,
    );
    assert_eq!(a.number(), 65000);
    assert!(a.message.contains("65010"), "{a}");
}

#[test]
fn s29_alarm_label_on_structure() {
    let a = stops(
        "s29_alarm_label_on_structure.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::Syntax,
        5,
        12,
    );
    assert_eq!(a.number(), 12080);
}

#[test]
fn s30_alarm_skipped_if() {
    let a = stops(
        "s30_alarm_skipped_if.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::Syntax,
        4,
        2,
    );
    assert_eq!(a.number(), 12080);
}

#[test]
fn s31_alarm_gotob_label_below() {
    let a = stops(
        "s31_alarm_gotob_label_below.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::JumpTarget,
        4,
        11,
    );
    assert_eq!(a.number(), 14080);
}

#[test]
fn s32_chf_chr_rnd_g41() {
    let f = "s32_chf_chr_rnd_g41.mpf";
    let b = clean(
        f,
        &[
            [-15.0, -15.0, 2.0],
            [-15.0, -15.0, -3.0],
            [0.0, 0.0, -3.0],   // G41
            [0.0, 32.0, -3.0],  // to the rounding: 40 − 8
            [8.0, 40.0, -3.0],  // RND=8, centre (8, 32)
            [55.0, 40.0, -3.0], // to the chamfer: 60 − 5
            [60.0, 35.0, -3.0], // CHF=5√2: legs 5
            [60.0, 4.0, -3.0],  // CHR=4
            [56.0, 0.0, -3.0],
            [0.0, 0.0, -3.0],
            [-15.0, -15.0, -3.0], // G40
            [-15.0, -15.0, 20.0],
        ],
    );
    let round = b
        .iter()
        .filter_map(|b| b.motion)
        .find(|m| m.kind == MotionKind::ArcCw)
        .expect("the rounding");
    assert!((round.center[0] - 8.0).abs() <= TOL && (round.center[1] - 32.0).abs() <= TOL);
}

#[test]
fn s50_drilling_cycles_plate() {
    let z = |z: f64| [70.0, 15.0, z];
    let mut want = vec![
        [20.0, 15.0, 50.0],
        [20.0, 15.0, 2.0], // CYCLE81
        [20.0, 15.0, -12.0],
        [20.0, 15.0, 10.0],
        [45.0, 15.0, 10.0],
        [45.0, 15.0, 2.0], // CYCLE82, DPR 6
        [45.0, 15.0, -6.0],
        [45.0, 15.0, 10.0],
        [70.0, 15.0, 10.0],
    ];
    // CYCLE83: depths 10 16 20 24 25, out to Z1 and back to 0.6 above each.
    for v in [
        1.0, -10.0, 1.0, -9.4, -16.0, 1.0, -15.4, -20.0, 1.0, -19.4, -24.0, 1.0, -23.4, -25.0,
        10.0, 50.0,
    ] {
        want.push(z(v));
    }
    let b = clean("s50_drilling_cycles_plate.mpf", &want);
    let dwells: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
    assert_eq!(dwells, [1.5]);
}

#[test]
fn s51_tapping_and_boring_cycles() {
    let b = clean(
        "s51_tapping_and_boring_cycles.mpf",
        &[
            [0.0, 0.0, 20.0],
            [0.0, 0.0, 2.0], // CYCLE84, PIT 1.5 at S400
            [0.0, 0.0, -15.0],
            [0.0, 0.0, 2.0],
            [0.0, 0.0, 5.0],
            [30.0, 0.0, 5.0],
            [30.0, 0.0, 2.0], // CYCLE85, FFR 60 in, RFF 200 out
            [30.0, 0.0, -20.0],
            [30.0, 0.0, 2.0],
            [30.0, 0.0, 5.0],
            [60.0, 0.0, 5.0],
            [60.0, 0.0, 2.0], // CYCLE89
            [60.0, 0.0, -20.0],
            [60.0, 0.0, 2.0],
            [60.0, 0.0, 5.0],
            [60.0, 0.0, 50.0],
        ],
    );
    let feeds: Vec<f64> = b
        .iter()
        .filter(|b| b.motion.is_some_and(|m| m.kind == MotionKind::Linear))
        .map(|b| b.modal.feed)
        .collect();
    assert_eq!(feeds, [600.0, 600.0, 60.0, 200.0, 80.0, 80.0]);
    let dwells: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
    assert_eq!(dwells, [0.5, 1.0]);
}

#[test]
fn s60_trans_arot_atrans() {
    clean(
        "s60_trans_arot_atrans.mpf",
        &[
            [0.0, 0.0, 5.0],
            [10.0, 5.0, 5.0],  // zero (10, 5)
            [7.0, 7.0, 5.0],   // (2, 3) → (10 − 3, 5 + 2)
            [7.0, 12.0, 5.0],  // G91 X5 along the turned X (+Y)
            [10.0, 12.0, 5.0], // (7, 0) → (10 − 0, 5 + 7)
            [0.0, 0.0, 5.0],   // TRANS alone: no frame
        ],
    );
}

#[test]
fn s61_scale_ascale_arc() {
    let f = "s61_scale_ascale_arc.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 2.0],
            [20.0, 0.0, 2.0], // X10 · 2
            [0.0, 20.0, 2.0], // G3 CR=10 scaled to radius 20
            [10.0, 0.0, 2.0], // ATRANS X5 scaled: zero at 10
            [20.0, 0.0, 2.0], // ASCALE 0.5: p + (10, 0)
            [0.0, 0.0, 20.0],
        ],
    );
    let arc = block(f, &b, 50).motion.unwrap();
    assert_eq!(arc.kind, MotionKind::ArcCcw);
    assert!(arc.center[0].abs() <= TOL && arc.center[1].abs() <= TOL);
}

/// s62's programmed points, mirrored: G41 became G42, G2 became G3.
#[test]
fn s62_mirror_g41_contour() {
    let f = "s62_mirror_g41_contour.mpf";
    let b = clean(
        f,
        &[
            [0.0, -10.0, 2.0],
            [0.0, -10.0, -3.0],
            [-10.0, 0.0, -3.0], // G41 → G42
            [-10.0, 30.0, -3.0],
            [-40.0, 30.0, -3.0],
            [-50.0, 20.0, -3.0], // G2 → G3 about (−40, 20)
            [-50.0, 0.0, -3.0],
            [-10.0, 0.0, -3.0],
            [0.0, -10.0, -3.0], // G40
            [0.0, -10.0, 20.0],
        ],
    );
    for n in [70, 80, 90, 100, 110, 120] {
        assert_eq!(block(f, &b, n).modal.trc, TrcSide::Right, "{f}: N{n}");
    }
    let arc = block(f, &b, 100).motion.unwrap();
    assert_eq!(arc.kind, MotionKind::ArcCcw);
    assert!((arc.center[0] + 40.0).abs() <= TOL && (arc.center[1] - 20.0).abs() <= TOL);
}

/// The tool-centre path of s62 (D2: radius 5), worked out by hand in the program's header:
/// the mirrored contour runs counter-clockwise and G42 keeps the tool outside it, on the
/// exact equidistant: the sides 5 mm out, the arc at radius 15, transition circles of
/// radius 5 about the two outer corners.
#[test]
fn s62_mirror_g41_tool_centre_path() {
    use nc_kernel::{Role, Segment, Shape};
    let f = "s62_mirror_g41_contour.mpf";
    let text = std::fs::read_to_string(path_of(f)).unwrap();
    let path = nc_kernel::prepare(f, &text, &machine(), &ToolTable::builtin())
        .unwrap_or_else(|a| panic!("{a}"));
    let of = |n: u32| -> Vec<Segment> {
        path.iter()
            .filter(|s| s.source.number.map(|b| b.value) == Some(n))
            .copied()
            .collect()
    };
    let xy = |p: P, x: f64, y: f64, what: &str| {
        assert!(
            (p[0] - x).abs() <= TOL && (p[1] - y).abs() <= TOL,
            "{what}: ({}, {}), by hand ({x}, {y})",
            p[0],
            p[1]
        );
    };
    let line = |s: &Segment, a: (f64, f64), b: (f64, f64), what: &str| {
        assert_eq!(s.shape, Shape::Line, "{what}");
        xy(s.from, a.0, a.1, what);
        xy(s.to, b.0, b.1, what);
    };
    let arc = |s: &Segment, a: (f64, f64), b: (f64, f64), c: (f64, f64), r: f64, what: &str| {
        let Shape::Arc {
            center,
            ccw,
            r0,
            r1,
            ..
        } = s.shape
        else {
            panic!("{what}: not an arc: {s:?}");
        };
        assert!(ccw, "{what}: counter-clockwise");
        assert!(
            (r0 - r).abs() <= TOL && (r1 - r).abs() <= TOL,
            "{what}: radius {r0}"
        );
        xy(center, c.0, c.1, what);
        xy(s.from, a.0, a.1, what);
        xy(s.to, b.0, b.1, what);
    };
    let n70 = of(70);
    assert_eq!(n70.len(), 1);
    assert_eq!(n70[0].role, Role::Approach);
    xy(n70[0].to, -5.0, 0.0, "N70: normal position of N80's start");
    let n80 = of(80);
    assert_eq!(n80.len(), 1);
    line(&n80[0], (-5.0, 0.0), (-5.0, 30.0), "N80");
    let n90 = of(90);
    assert_eq!(
        n90.iter().map(|s| s.role).collect::<Vec<_>>(),
        [Role::Corner, Role::Contour]
    );
    arc(
        &n90[0],
        (-5.0, 30.0),
        (-10.0, 35.0),
        (-10.0, 30.0),
        5.0,
        "N90 corner",
    );
    line(&n90[1], (-10.0, 35.0), (-40.0, 35.0), "N90");
    let n100 = of(100);
    assert_eq!(n100.len(), 1, "tangent: no corner");
    arc(
        &n100[0],
        (-40.0, 35.0),
        (-55.0, 20.0),
        (-40.0, 20.0),
        15.0,
        "N100",
    );
    let n110 = of(110);
    assert_eq!(n110.len(), 1, "tangent: no corner");
    line(&n110[0], (-55.0, 20.0), (-55.0, 0.0), "N110");
    let n120 = of(120);
    assert_eq!(
        n120.iter().map(|s| s.role).collect::<Vec<_>>(),
        [Role::Corner, Role::Contour]
    );
    arc(
        &n120[0],
        (-55.0, 0.0),
        (-50.0, -5.0),
        (-50.0, 0.0),
        5.0,
        "N120 corner",
    );
    line(&n120[1], (-50.0, -5.0), (-10.0, -5.0), "N120");
    // The same contour written mirrored by hand, with G42 and G3, gives the same path.
    let by_hand = text
        .replace("N30 MIRROR X0", "")
        .replace("N70 G41 X10", "N70 G42 X-10")
        .replace("N90 X40", "N90 X-40")
        .replace("N100 G2 X50", "N100 G3 X-50")
        .replace("N120 X10", "N120 X-10");
    let other = nc_kernel::prepare(f, &by_hand, &machine(), &ToolTable::builtin())
        .unwrap_or_else(|a| panic!("{a}"));
    assert_eq!(path.len(), other.len());
    for (a, b) in path.iter().zip(&other) {
        assert_eq!(a.role, b.role);
        xy(a.from, b.from[0], b.from[1], "mirrored by hand");
        xy(a.to, b.to[0], b.to[1], "mirrored by hand");
    }
}

#[test]
fn s63_mirror_both_axes() {
    let f = "s63_mirror_both_axes.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 2.0],
            [-20.0, 0.0, 2.0],
            [-30.0, -10.0, 2.0], // a half turn: still CW
            [40.0, -10.0, 2.0],
            [50.0, 0.0, 2.0], // Y mirrored: CCW becomes CW
            [0.0, 0.0, 20.0],
        ],
    );
    let n50 = block(f, &b, 50).motion.unwrap();
    assert_eq!(n50.kind, MotionKind::ArcCw);
    assert!((n50.center[0] + 30.0).abs() <= TOL && n50.center[1].abs() <= TOL);
    let n80 = block(f, &b, 80).motion.unwrap();
    assert_eq!(n80.kind, MotionKind::ArcCw);
    assert!((n80.center[0] - 50.0).abs() <= TOL && (n80.center[1] + 10.0).abs() <= TOL);
}

#[test]
fn s64_rot_pattern_for() {
    let mut want = Vec::new();
    for (cx, cy) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)] {
        // The slot's direction after (k − 1) quarter turns.
        want.extend([
            [20.0 * cx, 20.0 * cy, 2.0],
            [20.0 * cx, 20.0 * cy, -2.0],
            [30.0 * cx, 30.0 * cy, -2.0],
            [30.0 * cx, 30.0 * cy, 2.0],
        ]);
    }
    want.push([0.0, 0.0, 2.0]);
    want.insert(0, [0.0, 0.0, 2.0]);
    clean("s64_rot_pattern_for.mpf", &want);
}

#[test]
fn s65_supa_g53_g153() {
    clean(
        "s65_supa_g53_g153.mpf",
        &[
            [100.0, 50.0, 10.0],
            [100.0, 50.0, 20.0], // SUPA Z20
            [10.0, 10.0, 20.0],  // G53
            [20.0, 10.0, 20.0],  // G153
            [110.0, 50.0, 20.0], // the frame again
            [0.0, 0.0, 20.0],
        ],
    );
}

#[test]
fn s66_alarm_atrans_under_g41() {
    let a = stops(
        "s66_alarm_atrans_under_g41.mpf",
        &[
            [-10.0, -10.0, 2.0],
            [-10.0, -10.0, -3.0],
            [0.0, 0.0, -3.0],
            [0.0, 20.0, -3.0],
        ],
        AlarmCode::ForbiddenWithTrc,
        11,
        5,
    );
    assert_eq!(a.number(), 10754);
    assert!(a.message.contains("ATRANS"), "{a}");
}

#[test]
fn s67_alarm_scale_unequal_arc() {
    let a = stops(
        "s67_alarm_scale_unequal_arc.mpf",
        &[[0.0, 0.0, 2.0], [20.0, 0.0, 2.0]],
        AlarmCode::NotSupported,
        8,
        1,
    );
    assert_eq!(a.number(), 12580);
}

#[test]
fn s68_alarm_g41_tilted_plane() {
    let (s, c) = 20f64.to_radians().sin_cos();
    let a = stops(
        "s68_alarm_g41_tilted_plane.mpf",
        &[[0.0, 0.0, 0.0], [10.0 * c, 0.0, -10.0 * s]],
        AlarmCode::NotSupported,
        9,
        11,
    );
    assert_eq!(a.number(), 12580);
}

#[test]
fn s69_mirror_incremental() {
    clean(
        "s69_mirror_incremental.mpf",
        &[
            [5.0, 5.0, 2.0],
            [10.0, -10.0, 2.0],
            [15.0, -15.0, 2.0], // G91 X5 Y5
            [15.0, -20.0, 2.0], // Y=AC(20)
            [10.0, -20.0, 2.0], // X=IC(−5)
            [0.0, 0.0, 2.0],
        ],
    );
}

/// The moves' kinds and centres, for the circles' checks.
fn arcs(b: &[Block]) -> Vec<(MotionKind, P)> {
    b.iter()
        .filter_map(|b| b.motion)
        .filter(|m| m.kind.is_arc())
        .map(|m| (m.kind, m.center))
        .collect()
}

fn assert_arcs(file: &str, b: &[Block], want: &[(MotionKind, P)]) {
    let got = arcs(b);
    assert_eq!(got.len(), want.len(), "{file}: arcs {got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            g.0 == w.0 && (0..3).all(|i| (g.1[i] - w.1[i]).abs() <= TOL),
            "{file}: arc {g:?}, by hand {w:?}"
        );
    }
}

#[test]
fn s80_polar_poles() {
    let r = 20.0 * 2f64.sqrt();
    let f = "s80_polar_poles.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 2.0],
            [70.0, 20.0, 2.0],         // pole (30, 20), RP 40 at 0°
            [30.0, 60.0, 2.0],         // AP=90, RP kept
            [30.0 - r, 20.0 + r, 2.0], // AP=IC(45): 135°
            [40.0, 20.0, 2.0],         // G91 AP=−135: 0°, RP=10
            [45.0, 5.0, -3.0],         // G110: pole (45, 20); 270°, Z as written
            [10.0, 30.0, -3.0],        // G112: pole (30, 30); 180°
            [0.0, 25.0, -3.0],         // G111 RP=50 AP=90: pole (0, 50); −90°
            [0.0, 25.0, 20.0],
        ],
    );
    // The pole blocks move nothing.
    for n in [30, 80, 100, 120] {
        assert!(block(f, &b, n).motion.is_none(), "{f}: N{n}");
    }
}

#[test]
fn s81_polar_hole_circle() {
    let at = |deg: f64, r: f64| {
        let a = deg.to_radians();
        (50.0 + r * a.cos(), 50.0 + r * a.sin())
    };
    let mut want = vec![[0.0, 0.0, 2.0]];
    for k in 0..6 {
        let (x, y) = at(15.0 + 60.0 * k as f64, 25.0);
        want.extend([[x, y, 2.0], [x, y, -5.0], [x, y, 2.0]]);
    }
    want.extend([
        [90.0, 50.0, 2.0],
        [90.0, 50.0, -2.0],
        [50.0, 90.0, -2.0], // G3 AP=90 about the pole, radius 40
        [10.0, 50.0, -2.0], // AP=IC(90): 180°
        [50.0, 90.0, -4.0], // G2 AP=90 with Z: a helix
        [50.0, 90.0, 20.0],
    ]);
    let f = "s81_polar_hole_circle.mpf";
    let b = clean(f, &want);
    let c = |z: f64| [50.0, 50.0, z];
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCcw, c(-2.0)),
            (MotionKind::ArcCcw, c(-2.0)),
            (MotionKind::ArcCw, c(-2.0)),
        ],
    );
}

#[test]
fn s82_cip() {
    let f = "s82_cip.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 2.0],
            [0.0, 0.0, -2.0],
            [40.0, 0.0, -2.0], // over (20, 20)
            [40.0, -10.0, -2.0],
            [0.0, -10.0, -2.0], // G91: over (20, −30)
            [0.0, 0.0, -2.0],
            [30.0, 30.0, -2.0], // X=IC(30) Y=IC(30) over I1=AC(30) J1=AC(0)
            [30.0, 30.0, 20.0],
        ],
    );
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCw, [20.0, 0.0, -2.0]),
            (MotionKind::ArcCw, [20.0, -10.0, -2.0]),
            (MotionKind::ArcCcw, [15.0, 15.0, -2.0]),
        ],
    );
}

#[test]
fn s83_ct() {
    let f = "s83_ct.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 2.0],
            [0.0, 0.0, -1.0],
            [20.0, 0.0, -1.0],
            [40.0, 20.0, -1.0], // CT about (20, 20)
            [20.0, 40.0, -1.0], // CT about (20, 20) again
            [0.0, 40.0, -1.0],  // on the tangent: a line
            [0.0, 30.0, -1.0],
            [10.0, 20.0, -3.0], // CT about (10, 30) with Z
            [10.0, 20.0, 20.0],
        ],
    );
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCcw, [20.0, 20.0, -1.0]),
            (MotionKind::ArcCcw, [20.0, 20.0, -1.0]),
            (MotionKind::ArcCcw, [10.0, 30.0, -1.0]),
        ],
    );
    assert_eq!(block(f, &b, 70).motion.unwrap().kind, MotionKind::Linear);
}

#[test]
fn s84_helix_turn() {
    let f = "s84_helix_turn.mpf";
    let b = clean(
        f,
        &[
            [50.0, 30.0, 5.0],
            [50.0, 30.0, 0.0],
            [50.0, 30.0, -2.0], // TURN=2 on a full circle: three turns of −2
            [50.0, 30.0, -4.0],
            [50.0, 30.0, -6.0],
            [50.0, 30.0, -8.0], // TURN=1 and a half circle: 3 over 3π, −2 a turn
            [30.0, 30.0, -9.0],
            [40.0, 30.0, -9.0],
            [40.0, 30.0, 20.0],
        ],
    );
    let c = |z: f64| [40.0, 30.0, z];
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCw, c(0.0)),
            (MotionKind::ArcCw, c(-2.0)),
            (MotionKind::ArcCw, c(-4.0)),
            (MotionKind::ArcCcw, c(-6.0)),
            (MotionKind::ArcCcw, c(-8.0)),
        ],
    );
    // Every turn belongs to its programmed block.
    let lines: Vec<u32> = b
        .iter()
        .filter(|b| b.motion.is_some())
        .map(|b| b.line)
        .collect();
    assert_eq!(lines, [13, 14, 15, 15, 15, 16, 16, 17, 18]);
}

#[test]
fn s85_rndm_frc() {
    let f = "s85_rndm_frc.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 2.0],
            [0.0, 0.0, -2.0],
            [55.0, 0.0, -2.0],
            [60.0, 5.0, -2.0], // RNDM=5 about (55, 5)
            [60.0, 32.0, -2.0],
            [52.0, 40.0, -2.0], // RND=8 about (52, 32)
            [3.0, 40.0, -2.0],
            [0.0, 37.0, -2.0], // CHR=3
            [0.0, 0.0, -2.0],  // RNDM=0: no rounding at (0, 0)
            [30.0, 0.0, -2.0],
            [30.0, 0.0, 20.0],
        ],
    );
    let feeds: Vec<f64> = b
        .iter()
        .filter(|b| b.motion.is_some())
        .map(|b| b.modal.feed)
        .collect();
    assert_eq!(
        feeds[1..10],
        [500.0, 500.0, 100.0, 500.0, 60.0, 500.0, 100.0, 500.0, 500.0],
        "{f}: FRCM 100, FRC 60 for N50's element only"
    );
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCcw, [55.0, 5.0, -2.0]),
            (MotionKind::ArcCcw, [52.0, 32.0, -2.0]),
        ],
    );
}

/// The tool-centre path of a program: `softnc path`'s segments.
fn tool_centre(file: &str) -> Vec<nc_kernel::Segment> {
    let text = std::fs::read_to_string(path_of(file)).expect("program");
    nc_kernel::prepare(file, &text, &machine(), &ToolTable::builtin())
        .unwrap_or_else(|a| panic!("{file}: {a}"))
}

#[test]
fn s86_rnd_g41_equidistant() {
    use nc_kernel::{Role, Shape};
    let f = "s86_rnd_g41_equidistant.mpf";
    clean(
        f,
        &[
            [-20.0, -20.0, 2.0],
            [-20.0, -20.0, -3.0],
            [0.0, 0.0, -3.0],
            [0.0, 30.0, -3.0],
            [10.0, 40.0, -3.0], // RND=10 about (10, 30)
            [40.0, 40.0, -3.0],
            [50.0, 30.0, -3.0], // RND=10 about (40, 30)
            [50.0, 0.0, -3.0],
            [0.0, 0.0, -3.0],
            [-20.0, -20.0, -3.0],
            [-20.0, -20.0, 20.0],
        ],
    );
    // The tool centre, by hand (the header): offset 5 to the left; the roundings' equidistants
    // are arcs about their centres with radius 15. (from, to, centre) in X Y; Z is −3 plus
    // the tool length 80.
    type Xy = [f64; 2];
    let want: [(Role, Xy, Xy, Option<Xy>); 9] = [
        (Role::Approach, [-20.0, -20.0], [-5.0, 0.0], None),
        (Role::Contour, [-5.0, 0.0], [-5.0, 30.0], None),
        (
            Role::Contour,
            [-5.0, 30.0],
            [10.0, 45.0],
            Some([10.0, 30.0]),
        ),
        (Role::Contour, [10.0, 45.0], [40.0, 45.0], None),
        (
            Role::Contour,
            [40.0, 45.0],
            [55.0, 30.0],
            Some([40.0, 30.0]),
        ),
        (Role::Contour, [55.0, 30.0], [55.0, 0.0], None),
        (Role::Corner, [55.0, 0.0], [50.0, -5.0], Some([50.0, 0.0])),
        (Role::Contour, [50.0, -5.0], [0.0, -5.0], None),
        (Role::Retract, [0.0, -5.0], [-20.0, -20.0], None),
    ];
    let segs = tool_centre(f);
    let in_plane: Vec<_> = segs
        .iter()
        .filter(|s| s.from[2] == -3.0 + 80.0 && s.to[2] == -3.0 + 80.0)
        .collect();
    assert_eq!(in_plane.len(), want.len(), "{f}: {in_plane:#?}");
    let xy = |p: [f64; 3]| [p[0], p[1]];
    let near = |a: Xy, b: Xy| (a[0] - b[0]).abs() <= TOL && (a[1] - b[1]).abs() <= TOL;
    for (s, (role, from, to, centre)) in in_plane.iter().zip(want) {
        assert!(
            s.role == role && near(xy(s.from), from) && near(xy(s.to), to),
            "{f}: {s:?}, by hand {role:?} {from:?} -> {to:?}"
        );
        match (s.shape, centre) {
            (Shape::Line, None) => {}
            (
                Shape::Arc {
                    center,
                    r0,
                    r1,
                    ccw,
                    ..
                },
                Some(c),
            ) => {
                let r = if role == Role::Corner { 5.0 } else { 15.0 };
                assert!(near(xy(center), c) && !ccw, "{f}: {s:?}");
                assert!((r0 - r).abs() <= TOL && (r1 - r).abs() <= TOL, "{f}: {s:?}");
            }
            _ => panic!("{f}: {s:?}, by hand centre {centre:?}"),
        }
    }
}

#[test]
fn s87_dwell_units_exact_stop() {
    let f = "s87_dwell_units_exact_stop.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 2.0],
            [0.0, 0.0, -1.0],
            [10.0, 0.0, -1.0],
            [20.0, 0.0, -1.0],
            [25.4, 0.0, -1.0],  // G700 X1
            [25.4, 25.4, -1.0], // G70 Y1
            [30.0, 0.0, -1.0],
            [30.0, 0.0, 20.0],
        ],
    );
    assert_eq!(block(f, &b, 40).dwell, Some(1.5));
    assert_eq!(
        block(f, &b, 50).dwell,
        Some(1.5),
        "{f}: 30 rev at 1200 rev/min"
    );
    assert!(block(f, &b, 50).words.is_empty(), "{f}: G4's S is no speed");
    let stops = |n: u32| (block(f, &b, n).exact_stop, block(f, &b, n).modal.exact_stop);
    assert_eq!(
        [stops(60), stops(70), stops(80)],
        [(true, false), (false, true), (false, false)]
    );
    let feed = |n: u32| block(f, &b, n).modal.feed;
    assert_eq!([feed(90), feed(100), feed(110)], [254.0, 10.0, 500.0]);
}

#[test]
fn s88_alarm_cip_collinear() {
    let a = stops(
        "s88_alarm_cip_collinear.mpf",
        &[[0.0, 0.0, 2.0], [0.0, 0.0, -1.0]],
        AlarmCode::ArcEndPoint,
        7,
        17,
    );
    assert_eq!(a.number(), 14040);
}

#[test]
fn s89_alarm_ct_without_element() {
    let a = stops(
        "s89_alarm_ct_without_element.mpf",
        &[],
        AlarmCode::MissingValue,
        5,
        5,
    );
    assert_eq!(a.number(), 14045);
}

/// The square of SQUARE10.SPF from (x, y) at height z.
fn square(x: f64, y: f64, z: f64) -> [P; 4] {
    [
        [x + 10.0, y, z],
        [x + 10.0, y + 10.0, z],
        [x, y + 10.0, z],
        [x, y, z],
    ]
}

#[test]
fn s40_call_by_name() {
    let f = "s40_call_by_name.mpf";
    let mut want = vec![[0.0, 0.0, 5.0]];
    want.extend(square(0.0, 0.0, 5.0));
    want.push([20.0, 0.0, 5.0]);
    want.extend(square(20.0, 0.0, 5.0));
    want.extend(square(20.0, 0.0, 5.0));
    want.push([40.0, 0.0, 5.0]);
    want.extend([[45.0, 5.0, 5.0], [50.0, 10.0, 5.0], [55.0, 15.0, 5.0]]);
    want.push([0.0, 0.0, 50.0]);
    let b = clean(f, &want);
    // The subprograms' blocks name their files (for alarms and the path's sources), and
    // carry their own lines: SQUARE10's N10 is its line 3.
    let library = machine_for(f).programs.clone();
    let first = &b[1];
    let name = library.name(first.program).expect("a library file");
    assert!(name.ends_with("SQUARE10.SPF"), "{name}");
    assert_eq!((first.line, first.number.map(|n| n.value)), (3, Some(10)));
    // N10, N30, N50, N70, N80: the calls make no block of their own.
    assert_eq!(
        b.iter().filter(|b| b.program == 0).count(),
        5,
        "main blocks"
    );
}

#[test]
fn s41_proc_parameters() {
    let mut want = vec![[0.0, 0.0, 10.0], [15.0, 5.0, 2.0]];
    for z in [-1.0, -2.0] {
        want.extend([
            [15.0, 5.0, z],
            [25.0, 5.0, z],
            [25.0, 15.0, z],
            [15.0, 15.0, z],
            [15.0, 5.0, z],
        ]);
    }
    want.push([15.0, 5.0, 2.0]);
    want.extend([
        [37.5, -2.5, 2.0],
        [37.5, -2.5, -3.0],
        [42.5, -2.5, -3.0],
        [42.5, 2.5, -3.0],
        [37.5, 2.5, -3.0],
        [37.5, -2.5, -3.0],
        [37.5, -2.5, 2.0],
    ]);
    want.push([-3.0, 10.0, 50.0]);
    clean("s41_proc_parameters.mpf", &want);
}

#[test]
fn s42_mcall() {
    let mut want = vec![[0.0, 0.0, 2.0]];
    for (x, y) in [(10.0, 0.0), (10.0, 10.0), (0.0, 10.0)] {
        want.extend([[x, y, 2.0], [x, y, -6.0], [x, y, 2.0]]);
    }
    want.extend([[30.0, 30.0, 2.0], [30.0, 30.0, 50.0]]);
    let b = clean("s42_mcall.mpf", &want);
    let feeds: Vec<f64> = b
        .iter()
        .filter(|b| b.motion.is_some_and(|m| m.kind == MotionKind::Linear))
        .map(|b| b.modal.feed)
        .collect();
    assert_eq!(feeds, [80.0; 3], "DRILL_B's feed");
}

#[test]
fn s43_recursion_var() {
    clean(
        "s43_recursion_var.mpf",
        &[
            [0.0, 0.0, 0.0],
            [3.0, 1.0, 0.0],
            [5.0, 2.0, 0.0],
            [6.0, 3.0, 0.0],
            [60.0, 0.0, 0.0], // TOTAL = 3 + 2 + 1
        ],
    );
}

#[test]
fn s44_alarm_missing_subprogram() {
    let a = stops(
        "s44_alarm_missing_subprogram.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::MissingProgram,
        5,
        5,
    );
    assert_eq!(
        (a.number(), a.program.as_str()),
        (14011, "s44_alarm_missing_subprogram.mpf")
    );
    assert_eq!(a.block.as_deref(), Some("N20"));
    assert!(a.message.contains("NOT_THERE.SPF or NOT_THERE.MPF"), "{a}");
    assert!(a.message.contains("program.search_path"), "{a}");
}

#[test]
fn s45_alarm_recursion() {
    let mut want = vec![[0.0, 0.0, 0.0]];
    want.extend((1..=15).map(|x| [x as f64, 0.0, 0.0]));
    let a = stops(
        "s45_alarm_recursion.mpf",
        &want,
        AlarmCode::CallNesting,
        4,
        5,
    );
    assert_eq!(a.number(), 14012);
    assert!(a.program.ends_with("ENDLESS.SPF"), "{a}");
    assert_eq!(a.block.as_deref(), Some("N30"));
}

#[test]
fn s46_alarm_if_in_subprogram() {
    let a = stops(
        "s46_alarm_if_in_subprogram.mpf",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::ControlNesting,
        3,
        5,
    );
    assert_eq!(a.number(), 12640);
    assert!(a.program.ends_with("OPEN_IF.SPF"), "{a}");
    assert_eq!(a.block.as_deref(), Some("N20"));
}

#[test]
fn s47_alarm_var_not_variable() {
    let a = stops(
        "s47_alarm_var_not_variable.mpf",
        &[[0.0, 0.0, 10.0]],
        AlarmCode::ParameterNotVariable,
        6,
        28,
    );
    assert_eq!(
        (a.number(), a.program.as_str()),
        (12320, "s47_alarm_var_not_variable.mpf")
    );
    assert!(a.message.contains("DEPTH"), "{a}");
}

#[test]
fn s48_labels_per_program() {
    let mut want = Vec::new();
    want.push([0.0, 0.0, 0.0]);
    for y in [0.0, 30.0] {
        want.push([0.0, y, 0.0]);
        want.extend(square(0.0, y, 0.0));
        want.push([15.0, y, 0.0]);
        want.extend(square(15.0, y, 0.0));
        want.push([30.0, y, 0.0]);
    }
    want.push([0.0, 0.0, 50.0]);
    clean("s48_labels_per_program.mpf", &want);
}

#[test]
fn s52_mcall_cycle82_row() {
    let mut want = vec![[0.0, 0.0, 50.0]];
    for x in [15.0, 30.0, 45.0] {
        let z = if x == 15.0 { 50.0 } else { 10.0 };
        want.extend([
            [x, 10.0, z],
            [x, 10.0, 2.0],
            [x, 10.0, -8.0],
            [x, 10.0, 10.0],
        ]);
    }
    want.push([45.0, 10.0, 50.0]);
    let b = clean("s52_mcall_cycle82_row.mpf", &want);
    let dwells: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
    assert_eq!(dwells, [0.5, 0.5, 0.5]);
}

#[test]
fn s53_array_hole_table() {
    let mut want = vec![[0.0, 0.0, 20.0]];
    for (k, (x, y)) in [(10.0, 5.0), (25.0, 5.0), (25.0, 20.0)]
        .into_iter()
        .enumerate()
    {
        let z = if k == 0 { 20.0 } else { 10.0 };
        want.extend([[x, y, z], [x, y, 2.0], [x, y, -7.0], [x, y, 10.0]]);
    }
    want.push([25.0, 20.0, 50.0]);
    let b = clean("s53_array_hole_table.mpf", &want);
    let msgs: Vec<&str> = b.iter().filter_map(|b| b.message.as_deref()).collect();
    assert_eq!(msgs, ["Drilling BRACKET"]);
}

/// Compensation words (docs/sinumerik.md "Compensation words"): smooth approach and
/// retraction, NORM/KONT, DISC. The programmed end points by hand, and for s70 … s75 the
/// tool centre's path (the prepared segments, T5 D2: radius 5, length 80 added to Z) by
/// hand; s71's also against cavalier_contours' offset of the programmed chain.
mod compensation_words {
    use super::*;
    use cavalier_contours::core::math::Vector2;
    use cavalier_contours::polyline::{PlineSource, PlineSourceMut, Polyline};
    use nc_kernel::{prepare, Role, Segment, Shape};

    /// The tool length of D2 on Z.
    const L: f64 = 80.0;

    fn tool_path(file: &str) -> Vec<Segment> {
        let text = std::fs::read_to_string(path_of(file)).expect("program");
        prepare(file, &text, &machine(), &ToolTable::builtin()).unwrap_or_else(|a| panic!("{a}"))
    }

    /// One expected tool-centre segment: role, from, to, and an arc's centre and direction.
    type Want = (Role, P, P, Option<([f64; 2], bool)>);

    fn line(role: Role, from: P, to: P) -> Want {
        (role, from, to, None)
    }

    fn arc(role: Role, from: P, to: P, c: [f64; 2], ccw: bool) -> Want {
        (role, from, to, Some((c, ccw)))
    }

    /// Z of a programmed height with the tool length.
    fn z(v: f64) -> f64 {
        v + L
    }

    fn assert_path(file: &str, got: &[Segment], want: &[Want]) {
        let near = |a: P, b: P| (0..3).all(|i| (a[i] - b[i]).abs() <= TOL);
        for (k, (s, w)) in got.iter().zip(want).enumerate() {
            let shape_ok = match (s.shape, w.3) {
                (Shape::Line, None) => true,
                (Shape::Arc { center, ccw, .. }, Some((c, wccw))) => {
                    (center[0] - c[0]).abs() <= TOL
                        && (center[1] - c[1]).abs() <= TOL
                        && ccw == wccw
                }
                _ => false,
            };
            assert!(
                s.role == w.0 && near(s.from, w.1) && near(s.to, w.2) && shape_ok,
                "{file}: segment {k}: {s:?}\nby hand {w:?}"
            );
        }
        assert_eq!(got.len(), want.len(), "{file}: number of segments: {got:?}");
    }

    #[test]
    fn s70_g147_g148_square() {
        let f = "s70_g147_g148_square.mpf";
        clean(
            f,
            &[
                [-30.0, -30.0, 20.0],
                [0.0, -8.0, 20.0], // N30: A = P4 − (DISR + R)·t = (0, 0) − 8·(0, 1)
                [0.0, -8.0, -3.0], // DISCL=2 above Z−5
                [0.0, 0.0, -5.0],  // the approach line to P4
                [0.0, 40.0, -5.0],
                [40.0, 40.0, -5.0],
                [40.0, 0.0, -5.0],
                [0.0, 0.0, -5.0],
                [-8.0, 0.0, -3.0],  // N80: 8 ahead of P4 along −X, up to DISCL
                [-8.0, -5.0, 20.0], // the deselection, tool centre (−8, 0) + 5·(0, −1)
                [-30.0, -30.0, 20.0],
            ],
        );
        // The tool centre: the approach line at x = −5 (R left of +Y) from y = −8, DISR + R
        // long; the square's equidistant with transition circles of R about the corners;
        // the retraction line at y = −5 (R left of −X) to x = −8.
        use Role::*;
        let want = [
            line(Uncompensated, [0.0, 0.0, 0.0], [-30.0, -30.0, z(20.0)]),
            line(Approach, [-30.0, -30.0, z(20.0)], [-5.0, -8.0, z(20.0)]),
            line(Contour, [-5.0, -8.0, z(20.0)], [-5.0, -8.0, z(-3.0)]),
            line(Contour, [-5.0, -8.0, z(-3.0)], [-5.0, 0.0, z(-5.0)]),
            line(Contour, [-5.0, 0.0, z(-5.0)], [-5.0, 40.0, z(-5.0)]),
            arc(
                Corner,
                [-5.0, 40.0, z(-5.0)],
                [0.0, 45.0, z(-5.0)],
                [0.0, 40.0],
                false,
            ),
            line(Contour, [0.0, 45.0, z(-5.0)], [40.0, 45.0, z(-5.0)]),
            arc(
                Corner,
                [40.0, 45.0, z(-5.0)],
                [45.0, 40.0, z(-5.0)],
                [40.0, 40.0],
                false,
            ),
            line(Contour, [45.0, 40.0, z(-5.0)], [45.0, 0.0, z(-5.0)]),
            arc(
                Corner,
                [45.0, 0.0, z(-5.0)],
                [40.0, -5.0, z(-5.0)],
                [40.0, 0.0],
                false,
            ),
            line(Contour, [40.0, -5.0, z(-5.0)], [0.0, -5.0, z(-5.0)]),
            line(Contour, [0.0, -5.0, z(-5.0)], [-8.0, -5.0, z(-3.0)]),
            line(Retract, [-8.0, -5.0, z(-3.0)], [-8.0, -5.0, z(20.0)]),
            line(
                Uncompensated,
                [-8.0, -5.0, z(20.0)],
                [-30.0, -30.0, z(20.0)],
            ),
        ];
        assert_path(f, &tool_path(f), &want);
        // The approach's infeed at the speed before it (G0), its line at F.
        let b = run(f).0;
        let n30: Vec<(MotionKind, f64)> = b
            .iter()
            .filter(|b| b.number.is_some_and(|n| n.value == 30))
            .filter_map(|b| b.motion.map(|m| (m.kind, b.modal.feed)))
            .collect();
        assert_eq!(
            n30,
            [
                (MotionKind::Rapid, 0.0),
                (MotionKind::Rapid, 0.0),
                (MotionKind::Linear, 400.0)
            ]
        );
        assert_eq!(block(f, &b, 30).trc, Some(TrcSide::Left));
    }

    /// The tool path of s71 (hand values in the program's header).
    fn s71_want() -> Vec<Want> {
        use Role::*;
        vec![
            line(Uncompensated, [0.0, 0.0, 0.0], [-40.0, -20.0, z(20.0)]),
            line(Approach, [-40.0, -20.0, z(20.0)], [-15.0, -10.0, z(20.0)]),
            line(Contour, [-15.0, -10.0, z(20.0)], [-15.0, -10.0, z(3.0)]),
            line(Contour, [-15.0, -10.0, z(3.0)], [-15.0, -10.0, z(-5.0)]),
            arc(
                Contour,
                [-15.0, -10.0, z(-5.0)],
                [-5.0, 0.0, z(-5.0)],
                [-15.0, 0.0],
                true,
            ),
            line(Contour, [-5.0, 0.0, z(-5.0)], [-5.0, 40.0, z(-5.0)]),
            arc(
                Corner,
                [-5.0, 40.0, z(-5.0)],
                [0.0, 45.0, z(-5.0)],
                [0.0, 40.0],
                false,
            ),
            line(Contour, [0.0, 45.0, z(-5.0)], [40.0, 45.0, z(-5.0)]),
            arc(
                Corner,
                [40.0, 45.0, z(-5.0)],
                [45.0, 40.0, z(-5.0)],
                [40.0, 40.0],
                false,
            ),
            line(Contour, [45.0, 40.0, z(-5.0)], [45.0, 0.0, z(-5.0)]),
            arc(
                Corner,
                [45.0, 0.0, z(-5.0)],
                [40.0, -5.0, z(-5.0)],
                [40.0, 0.0],
                false,
            ),
            line(Contour, [40.0, -5.0, z(-5.0)], [0.0, -5.0, z(-5.0)]),
            arc(
                Contour,
                [0.0, -5.0, z(-5.0)],
                [-8.0, -13.0, z(-5.0)],
                [0.0, -13.0],
                true,
            ),
            line(Retract, [-8.0, -13.0, z(-5.0)], [-8.0, -13.0, z(3.0)]),
            line(Uncompensated, [-8.0, -13.0, z(3.0)], [-8.0, -13.0, z(20.0)]),
            line(
                Uncompensated,
                [-8.0, -13.0, z(20.0)],
                [-40.0, -20.0, z(20.0)],
            ),
        ]
    }

    #[test]
    fn s71_g247_g248_g341_fad() {
        let f = "s71_g247_g248_g341_fad.mpf";
        let b = clean(
            f,
            &[
                [-40.0, -20.0, 20.0],
                [-15.0, -15.0, 20.0], // A: the quarter's start, 15 below its centre (−15, 0)
                [-15.0, -15.0, 3.0],  // DISCL=AC(3)
                [-15.0, -15.0, -5.0], // G341: down to the plane at FAD
                [0.0, 0.0, -5.0],     // the quarter circle, radius 15
                [0.0, 40.0, -5.0],
                [40.0, 40.0, -5.0],
                [40.0, 0.0, -5.0],
                [0.0, 0.0, -5.0],
                [-13.0, -13.0, -5.0], // N90: radius 13 about (0, −13), in the plane
                [-8.0, -13.0, 3.0],   // the deselection, up at FAD (tool centre)
                [-8.0, -13.0, 20.0],
                [-40.0, -20.0, 20.0],
            ],
        );
        let feeds: Vec<(MotionKind, f64)> = b
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.kind, b.modal.feed)))
            .collect();
        use MotionKind::*;
        assert_eq!(
            feeds[1..5],
            [(Rapid, 0.0), (Rapid, 0.0), (Linear, 100.0), (ArcCcw, 400.0)]
        );
        assert_eq!(
            feeds[9..],
            [
                (ArcCcw, 400.0),
                (Linear, 100.0),
                (Linear, 400.0),
                (Linear, 400.0)
            ]
        );
        let path = tool_path(f);
        assert_path(f, &path, &s71_want());
        same_as_cavalier(f, &path);
    }

    /// cavalier_contours' offset of s71's programmed contour (R 5 to the left) traces
    /// softnc's tool path: the approach quarter with the first two edges, and the last two
    /// edges with the retraction quarter, each as an open chain of its own (together they
    /// would lie closer than R to each other's leads: air, which cavalier cuts away).
    fn same_as_cavalier(file: &str, path: &[Segment]) {
        // Bulge tan(sweep/4): a quarter ccw is tan(22.5°).
        let q = (std::f64::consts::PI / 8.0).tan();
        let approach = [
            (-15.0, -15.0, q),
            (0.0, 0.0, 0.0),
            (0.0, 40.0, 0.0),
            (40.0, 40.0, 0.0),
        ];
        let retraction = [
            (40.0, 40.0, 0.0),
            (40.0, 0.0, 0.0),
            (0.0, 0.0, q),
            (-13.0, -13.0, 0.0),
        ];
        let in_plane: Vec<&Segment> = path
            .iter()
            .filter(|s| matches!(s.role, Role::Contour | Role::Corner))
            .filter(|s| (s.from[0] - s.to[0]).hypot(s.from[1] - s.to[1]) > 1e-9)
            .collect();
        // The approach quarter, N50, its corner, N60 | N70, its corner, N80, the quarter.
        let (first, second) = (&in_plane[..4], &in_plane[5..]);
        for (chain, segs, from, to) in [
            (&approach, first, [-15.0, -10.0], [40.0, 45.0]),
            (&retraction, second, [45.0, 40.0], [-8.0, -13.0]),
        ] {
            let mut pl: Polyline<f64> = Polyline::new();
            for &(x, y, bulge) in chain {
                pl.add(x, y, bulge);
            }
            let cav = pl.parallel_offset(5.0);
            assert_eq!(cav.len(), 1, "{file}: cavalier's offset in one piece");
            let cav = &cav[0];
            for s in segs {
                for p in [s.from, s.to] {
                    let d = cav
                        .closest_point(Vector2::new(p[0], p[1]), 1e-9)
                        .map_or(f64::INFINITY, |c| c.distance);
                    assert!(
                        d < 1e-5,
                        "{file}: {p:?} of {s:?} is {d} mm off cavalier's offset"
                    );
                }
            }
            let (a, b) = (cav.at(0).pos(), cav.at(cav.vertex_count() - 1).pos());
            let near = |v: Vector2<f64>, w: [f64; 2]| (v.x - w[0]).hypot(v.y - w[1]) < 1e-5;
            assert!(
                near(a, from) && near(b, to),
                "{file}: cavalier from {a:?} to {b:?}"
            );
            assert!(near(Vector2::new(segs[0].from[0], segs[0].from[1]), from));
            let last = segs[segs.len() - 1];
            assert!(near(Vector2::new(last.to[0], last.to[1]), to));
        }
    }

    #[test]
    fn s72_g347_g348_circle_helix() {
        let f = "s72_g347_g348_circle_helix.mpf";
        let b = clean(
            f,
            &[
                [50.0, -20.0, 10.0],
                [42.0, 0.0, 10.0], // A, opposite P4 across the centre (31, 0)
                [42.0, 0.0, -2.0], // DISCL=4 above −6
                [20.0, 0.0, -6.0], // the half circle (a helix down 4)
                [20.0, 0.0, -6.0], // N40: the full circle
                [46.0, 0.0, 12.0], // N50: radius 13 about (33, 0), rising to Z12
                [60.0, 10.0, 12.0],
            ],
        );
        let approach = b
            .iter()
            .filter_map(|b| b.motion.map(|m| (m, b.modal.feed)))
            .nth(3)
            .unwrap();
        assert_eq!(approach.0.kind, MotionKind::ArcCw);
        assert_eq!(
            (approach.0.center[0], approach.0.center[1], approach.1),
            (31.0, 0.0, 150.0)
        );
        use Role::*;
        let want = [
            line(Uncompensated, [0.0, 0.0, 0.0], [50.0, -20.0, z(10.0)]),
            line(Approach, [50.0, -20.0, z(10.0)], [37.0, 0.0, z(10.0)]),
            line(Contour, [37.0, 0.0, z(10.0)], [37.0, 0.0, z(-2.0)]),
            // The tool centre's half circle: radius DISR = 6 about (31, 0), 5 off the boss.
            arc(
                Contour,
                [37.0, 0.0, z(-2.0)],
                [25.0, 0.0, z(-6.0)],
                [31.0, 0.0],
                false,
            ),
            arc(
                Contour,
                [25.0, 0.0, z(-6.0)],
                [25.0, 0.0, z(-6.0)],
                [0.0, 0.0],
                true,
            ),
            // Radius 8 about (33, 0) from (25, 0) over the top to (41, 0).
            arc(
                Contour,
                [25.0, 0.0, z(-6.0)],
                [41.0, 0.0, z(12.0)],
                [33.0, 0.0],
                false,
            ),
            line(Retract, [41.0, 0.0, z(12.0)], [60.0, 10.0, z(12.0)]),
        ];
        assert_path(f, &tool_path(f), &want);
    }

    /// Behind the contour: KONT goes round the start point by the transition circle, NORM
    /// straight to the normal position (the programs' headers).
    #[test]
    fn s73_s74_kont_and_norm_behind_the_contour() {
        let ends = [
            [20.0, -20.0, -5.0],
            [0.0, 0.0, -5.0],
            [0.0, 40.0, -5.0],
            [40.0, 40.0, -5.0],
            [40.0, 0.0, -5.0],
            [0.0, 0.0, -5.0],
            [20.0, -20.0, -5.0],
            [20.0, -20.0, 20.0],
        ];
        let h = 5.0 / 2f64.sqrt(); // (0, 0) + 5·(−1, −1)/√2
        for (f, kont) in [
            ("s73_kont_behind_the_contour.mpf", true),
            ("s74_norm_behind_the_contour.mpf", false),
        ] {
            clean(f, &ends);
            let p = tool_path(f);
            let of = |n: u32| -> Vec<&Segment> {
                p.iter()
                    .filter(|s| s.source.number.is_some_and(|b| b.value == n))
                    .collect()
            };
            let (n30, n40) = (of(30), of(40));
            let near = |a: P, x: f64, y: f64| (a[0] - x).abs() <= TOL && (a[1] - y).abs() <= TOL;
            assert!(near(n30[0].from, 20.0, -20.0), "{f}: {n30:?}");
            if kont {
                assert!(near(n30[0].to, -h, -h), "{f}: {n30:?}");
                assert!(
                    matches!(n40[0].shape, Shape::Arc { ccw: false, center, .. } if center[0] == 0.0 && center[1] == 0.0)
                );
                assert!(
                    near(n40[0].to, -5.0, 0.0) && n40[0].role == Role::Corner,
                    "{f}: {n40:?}"
                );
            } else {
                assert!(near(n30[0].to, -5.0, 0.0), "{f}: {n30:?}");
                assert_eq!(n40[0].role, Role::Contour, "{f}: no corner");
            }
            assert!(near(n40.last().unwrap().to, -5.0, 40.0), "{f}: {n40:?}");
        }
    }

    #[test]
    fn s75_disc_intersection() {
        let f = "s75_disc_intersection.mpf";
        let sq = [
            [0.0, 40.0, -5.0],
            [40.0, 40.0, -5.0],
            [40.0, 0.0, -5.0],
            [0.0, 0.0, -5.0],
        ];
        let mut want = vec![[-20.0, 0.0, -5.0], [0.0, 0.0, -5.0]];
        want.extend(sq);
        want.extend(sq);
        want.push([-20.0, 0.0, -5.0]);
        clean(f, &want);
        // First lap: the corners are the intersections of the equidistants x = −5, y = 45,
        // x = 45, y = −5; the second (DISC=0) has transition circles again.
        let p = tool_path(f);
        let ends: Vec<[f64; 2]> = p[2..6].iter().map(|s| [s.to[0], s.to[1]]).collect();
        assert_eq!(
            ends,
            [[-5.0, 45.0], [45.0, 45.0], [45.0, -5.0], [0.0, -5.0]]
        );
        assert!(p[2..6].iter().all(|s| s.role == Role::Contour));
        let circles = p.iter().filter(|s| s.role == Role::Corner).count();
        assert_eq!(
            circles, 4,
            "{f}: N80 … N110 start with a transition circle each"
        );
    }

    #[test]
    fn s76_alarm_disc_50() {
        stops(
            "s76_alarm_disc_50.mpf",
            &[[0.0, 0.0, 5.0]],
            AlarmCode::NotSupported,
            7,
            9,
        );
    }

    #[test]
    fn s77_alarm_g247_without_disr() {
        let a = stops(
            "s77_alarm_g247_without_disr.mpf",
            &[[0.0, 0.0, 5.0]],
            AlarmCode::SarDistance,
            6,
            12,
        );
        assert_eq!(a.number(), 10742);
    }

    #[test]
    fn s78_alarm_sar_empty_blocks() {
        let a = stops(
            "s78_alarm_sar_empty_blocks.mpf",
            &[[0.0, 0.0, 5.0]],
            AlarmCode::SarBlocks,
            5,
            9,
        );
        assert_eq!(a.number(), 10740);
    }

    #[test]
    fn s79_alarm_sar_contour_along_z() {
        let a = stops(
            "s79_alarm_sar_contour_along_z.mpf",
            &[[0.0, 0.0, 5.0]],
            AlarmCode::SarDirection,
            5,
            12,
        );
        assert_eq!(a.number(), 10744);
    }
}
