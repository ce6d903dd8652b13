//! SINUMERIK programs for the 828D / 840D sl milling machine (config/siemens-840d.toml: the
//! SINUMERIK language, G17, mm, R0 … R99) in tests/corpus/siemens-840d/, and the 840C's
//! L-number subprograms in tests/corpus/siemens-840c/ (config/siemens-840c.toml). Every
//! move's end point is compared with values worked out by hand; each program's header comment
//! shows the arithmetic. The end points are the programmed ones (no zero offset is active,
//! tool centre offsets are not applied to them). Subprogram files (`NAME.SPF`) stand beside
//! the programs and are found as `softnc` finds them (the program's folder). Programs that
//! run cleanly also pass `softnc check`; programs that must stop name their alarm's code,
//! line and column, and the moves made before it.

use nc_kernel::{AlarmCode, Block, Interpreter, MachineData, MotionKind, ToolTable, TrcSide};
use std::path::PathBuf;
use std::process::Command;

type P = [f64; 3];

const CORPUS: &str = "tests/corpus/siemens-840d";
const MACHINE: &str = "config/siemens-840d.toml";
const CORPUS_840C: &str = "tests/corpus/siemens-840c";
const MACHINE_840C: &str = "config/siemens-840c.toml";
/// Hand values agree to this (sums of decimal fractions, and the trigonometry of s02/s16).
const TOL: f64 = 1e-9;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The corpus folder and machine data of a file: `l…` programs are the 840C's.
fn corpus_of(file: &str) -> (&'static str, &'static str) {
    if file.starts_with('l') {
        (CORPUS_840C, MACHINE_840C)
    } else {
        (CORPUS, MACHINE)
    }
}

fn path_of(file: &str) -> PathBuf {
    root().join(corpus_of(file).0).join(file)
}

/// The machine data of `file`'s corpus, with the subprogram files beside it.
fn machine(file: &str) -> MachineData {
    let machine = corpus_of(file).1;
    let mut md = MachineData::load(Some(&root().join(machine)), &[]).expect(machine);
    let library = nc_runtime::program_library(&path_of(file), &md.program.search_path);
    md.programs = std::sync::Arc::new(library.expect("the corpus folder"));
    md
}

/// The blocks up to the end or the first alarm.
fn run(file: &str) -> (Vec<Block>, Option<nc_kernel::Alarm>) {
    let text = std::fs::read_to_string(path_of(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    let (md, tools) = (machine(file), ToolTable::builtin());
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
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (0..3).all(|i| (g[i] - w[i]).abs() <= TOL),
            "{file}: move {k}: {g:?}, by hand {w:?}\nall moves: {got:?}"
        );
    }
    assert_eq!(got.len(), want.len(), "{file}: number of moves: {got:?}");
}

/// `softnc check PROGRAM --machine <the corpus's machine data>` passes (it finds the
/// subprogram files beside the program itself).
fn check(file: &str) {
    let out = Command::new(env!("CARGO_BIN_EXE_softnc"))
        .current_dir(root())
        .arg("check")
        .arg(path_of(file))
        .arg("--machine")
        .arg(corpus_of(file).1)
        .output()
        .expect("softnc runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{file}: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A program that runs to its end: the end points by hand, and `softnc check`.
fn clean(file: &str, want: &[P]) -> Vec<Block> {
    let (b, alarm) = run(file);
    if let Some(a) = alarm {
        panic!("{file}: {a}");
    }
    assert_ends(file, &ends(&b), want);
    check(file);
    b
}

/// A program that stops: the moves before the alarm, and the alarm's code, line and column.
fn stops(file: &str, want: &[P], code: AlarmCode, line: u32, col: u32) -> nc_kernel::Alarm {
    let (b, alarm) = run(file);
    assert_ends(file, &ends(&b), want);
    let a = alarm.unwrap_or_else(|| panic!("{file}: no alarm"));
    assert_eq!(
        (a.code, a.line, a.col),
        (code, line, col),
        "{file}: {} {a}",
        a.number()
    );
    a
}

/// The block of the program's `N` word `n` (the first one produced).
fn block<'a>(file: &str, b: &'a [Block], n: u32) -> &'a Block {
    b.iter()
        .find(|b| b.number.is_some_and(|x| x.value == n))
        .unwrap_or_else(|| panic!("{file}: no block N{n}"))
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
        &[],
        AlarmCode::ControlNesting,
        6,
        5,
    );
    assert_eq!(a.number(), 12640);
    assert!(a.message.contains("ENDIF"), "{a}");
}

#[test]
fn s21_s22_s29_structure_alarms_name_their_block() {
    for (file, n) in [
        ("s21_alarm_if_open.mpf", "N30"),
        ("s22_alarm_endwhile_closes_for.mpf", "N50"),
        ("s29_alarm_label_on_structure.mpf", "N30"),
    ] {
        let a = run(file).1.expect("an alarm");
        assert_eq!(a.block.as_deref(), Some(n), "{file}: {a}");
    }
}

#[test]
fn s22_alarm_endwhile_closes_for() {
    let a = stops(
        "s22_alarm_endwhile_closes_for.mpf",
        &[],
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
        &[],
        AlarmCode::Syntax,
        5,
        12,
    );
    assert_eq!(a.number(), 12080);
}

#[test]
fn s30_alarm_skipped_if() {
    let a = stops("s30_alarm_skipped_if.mpf", &[], AlarmCode::Syntax, 4, 2);
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
    let library = machine(f).programs.clone();
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
