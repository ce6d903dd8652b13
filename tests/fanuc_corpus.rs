//! A corpus of Fanuc Custom Macro B programs (tests/corpus/fanuc/), each shaped like a shop
//! or CAM program, interpreted on the shipped Fanuc machine (config/fanuc.toml: increment
//! input, so an axis word without a decimal point counts micrometres) with the shipped tool
//! table. The programmed end point (X Y Z in mm, machine coordinates = workpiece + work
//! offset, no tool centre offsets) of every move is compared with values worked out by hand
//! from the 0i-MF manual's semantics — the arithmetic stands next to each value. A program
//! that runs cleanly must also pass `softnc check`; one that must stop names its alarm, line
//! and column, and the end points reached before it.

use nc_kernel::{
    AlarmCode, Block, Distance, Interpreter, MachineData, MotionMode, ToolTable, TrcSide,
    WorkOffsets,
};
use std::path::{Path, PathBuf};
use std::process::Command;

type P = [f64; 3];

const CORPUS: &str = "tests/corpus/fanuc";
const MACHINE: &str = "config/fanuc.toml";
/// Exact arithmetic (sums of decimal fractions).
const EXACT: f64 = 1e-9;
/// Where trigonometric functions are involved.
const TRIG: f64 = 1e-6;

/// m13's work offsets: G54 (100, 50, -20), G55 (-30, 10, -5).
const OFFSETS: &str =
    "[G54]\nX = 100.0\nY = 50.0\nZ = -20.0\n[G55]\nX = -30.0\nY = 10.0\nZ = -5.0\n";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn path_of(file: &str) -> PathBuf {
    root().join(CORPUS).join(file)
}

fn source(file: &str) -> String {
    std::fs::read_to_string(path_of(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn machine(offsets: Option<&str>) -> MachineData {
    let mut md = MachineData::load(Some(&root().join(MACHINE)), &[]).expect("config/fanuc.toml");
    if let Some(o) = offsets {
        md.work_offsets = WorkOffsets::from_toml_str(o, "offsets.toml", &md).expect("offsets");
    }
    md
}

/// The blocks of a program up to its end or its first alarm.
fn blocks_until_alarm(
    file: &str,
    text: &str,
    md: &MachineData,
) -> (Vec<Block>, Option<nc_kernel::Alarm>) {
    let tools = ToolTable::builtin();
    let mut out = Vec::new();
    for item in Interpreter::new(file, text, md, &tools) {
        match item {
            Ok(b) => out.push(b),
            Err(a) => return (out, Some(a)),
        }
    }
    (out, None)
}

/// The blocks of a program that must run without an alarm.
fn blocks(file: &str, text: &str, md: &MachineData) -> Vec<Block> {
    let (b, alarm) = blocks_until_alarm(file, text, md);
    if let Some(a) = alarm {
        panic!("{}", a.render(text));
    }
    b
}

fn ends(b: &[Block]) -> Vec<P> {
    b.iter().filter_map(|b| b.motion.map(|m| m.end)).collect()
}

fn assert_ends(file: &str, got: &[P], want: &[P], tol: f64) {
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.iter().zip(w).all(|(a, b)| (a - b).abs() <= tol),
            "{file}: move {k}: got {g:?}, want {w:?}\nall moves: {got:?}"
        );
    }
    assert_eq!(
        got.len(),
        want.len(),
        "{file}: number of moves\ngot {got:?}"
    );
}

fn close(a: P, b: P, tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

fn sind(a: f64) -> f64 {
    a.to_radians().sin()
}

fn cosd(a: f64) -> f64 {
    a.to_radians().cos()
}

/// `softnc check PROGRAM --machine config/fanuc.toml [--offsets FILE]`: (exit code, stdout,
/// stderr).
fn softnc_check(program: &Path, offsets: Option<&str>) -> (Option<i32>, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_softnc"));
    cmd.current_dir(root())
        .arg("check")
        .arg(program)
        .arg("--machine")
        .arg(MACHINE);
    if let Some(o) = offsets {
        let f = scratch(&format!("{}.offsets.toml", stem(program)));
        std::fs::write(&f, o).unwrap();
        cmd.arg("--offsets").arg(f);
    }
    let out = cmd.output().expect("softnc runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn stem(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softnc-fanuc-corpus-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn assert_check_passes(program: &Path, offsets: Option<&str>) {
    let (code, stdout, stderr) = softnc_check(program, offsets);
    assert_eq!(code, Some(0), "{}: {stdout}\n{stderr}", program.display());
    assert!(
        stdout.contains(": ok: ") && stdout.contains(" 0 alarms"),
        "{}: {stdout}",
        program.display()
    );
}

/// How a corpus file is run.
#[derive(Clone, Copy, PartialEq)]
enum Tape {
    /// As written.
    AsWritten,
    /// With its leading `%` line taken out: the same path (sequence numbers are found
    /// whatever stands before the program's O line).
    WithoutStartLine,
}

fn text_of(file: &str, tape: Tape) -> String {
    let text = source(file);
    match tape {
        Tape::AsWritten => text,
        Tape::WithoutStartLine => {
            let first = text.lines().next().unwrap_or("");
            assert_eq!(first.trim(), "%", "{file} starts with a % line");
            text[text.find('\n').unwrap() + 1..].to_string()
        }
    }
}

/// Runs a clean corpus program: its end points against the hand values, and `softnc
/// check`. Returns its blocks for further checks.
fn run_clean(file: &str, tape: Tape, offsets: Option<&str>, want: &[P], tol: f64) -> Vec<Block> {
    let text = text_of(file, tape);
    let md = machine(offsets);
    let b = blocks(file, &text, &md);
    assert_ends(file, &ends(&b), want, tol);
    let program = match tape {
        Tape::AsWritten => path_of(file),
        Tape::WithoutStartLine => {
            let p = scratch(file);
            std::fs::write(&p, &text).unwrap();
            p
        }
    };
    assert_check_passes(&program, offsets);
    b
}

/// Runs a corpus program that must stop: its alarm (code, line, column), the end points
/// reached before it, and `softnc check` naming the same place.
fn run_alarm(file: &str, want_before: &[P], code: AlarmCode, line: u32, col: u32) -> String {
    let text = source(file);
    let (b, alarm) = blocks_until_alarm(file, &text, &machine(None));
    let a = alarm.unwrap_or_else(|| panic!("{file}: no alarm; moves {:?}", ends(&b)));
    assert_eq!(
        (a.code, a.line, a.col),
        (code, line, col),
        "{}",
        a.render(&text)
    );
    assert_ends(file, &ends(&b), want_before, EXACT);
    let (exit, stdout, stderr) = softnc_check(&path_of(file), None);
    assert_eq!(exit, Some(1), "{file}: {stdout}\n{stderr}");
    let place = format!("{file}:{line}:{col}: alarm {}", code.number());
    assert!(stderr.contains(&place), "{file}: want {place}\n{stderr}");
    a.message
}

// ---------------------------------------------------------------------------------------
// Programs that run cleanly.
// ---------------------------------------------------------------------------------------

#[test]
fn m01_bolt_circle_g65() {
    // G65 P9010 X50 Y30 R40 A15 H6 Z-8: hole k (k = 0…5) at 15° + k·360°/6 on radius 40
    // about (50, 30): x = 50 + 40·cos a, y = 30 + 40·sin a. Per hole: G0 X Y (Z stays: N20's
    // 25 for the first hole, then the retract plane 2), Z2, G1 Z-8, G0 Z2.
    let hole = |a: f64| [50.0 + 40.0 * cosd(a), 30.0 + 40.0 * sind(a)];
    // Two of them written out: 135° → (50 − 20·√2, 30 + 20·√2); 315° → (50 + 20·√2, 30 − 20·√2).
    assert!((hole(135.0)[0] - 21.715_728_752_538_1).abs() < 1e-9);
    assert!((hole(315.0)[1] - 1.715_728_752_538_1).abs() < 1e-9);
    let mut want = vec![[0.0, 0.0, 25.0]]; // N20
    for (k, a) in [15.0, 75.0, 135.0, 195.0, 255.0, 315.0]
        .into_iter()
        .enumerate()
    {
        let [x, y] = hole(a);
        let above = if k == 0 { 25.0 } else { 2.0 };
        want.extend([[x, y, above], [x, y, 2.0], [x, y, -8.0], [x, y, 2.0]]);
    }
    let [x, y] = hole(315.0);
    want.push([x, y, 25.0]); // N50 G0 Z25
    want.push([0.0, 0.0, 25.0]); // N60
    run_clean("m01_bolt_circle_g65.nc", Tape::AsWritten, None, &want, TRIG);
}

/// m02: passes along X at Y = 0, 8, … 40 (step 8 up to the width 40), alternating
/// X60 / X0 (#3 = 60·(dir + 1)/2); after the pass at Y40 the next Y (48) is past the width
/// and the loop is left by GOTO 100.
const M02: &[P] = &[
    [0.0, 0.0, 5.0],    // N20
    [0.0, 0.0, -3.0],   // N30
    [60.0, 0.0, -3.0],  // pass Y0: 60·(1 + 1)/2
    [60.0, 8.0, -3.0],  // 0 + 8
    [0.0, 8.0, -3.0],   // 60·(−1 + 1)/2
    [0.0, 16.0, -3.0],  // 8 + 8
    [60.0, 16.0, -3.0], //
    [60.0, 24.0, -3.0], // 16 + 8
    [0.0, 24.0, -3.0],  //
    [0.0, 32.0, -3.0],  // 24 + 8
    [60.0, 32.0, -3.0], //
    [60.0, 40.0, -3.0], // 32 + 8 = 40, not past 40
    [0.0, 40.0, -3.0],  // last pass; 40 + 8 = 48 > 40: GOTO 100
    [0.0, 40.0, 5.0],   // N100
    [0.0, 0.0, 5.0],    // N110
];

#[test]
fn m02_pocket_zigzag_while() {
    run_clean(
        "m02_pocket_zigzag_while.nc",
        Tape::AsWritten,
        None,
        M02,
        EXACT,
    );
}

#[test]
fn m02_pocket_zigzag_while_without_tape_start() {
    run_clean(
        "m02_pocket_zigzag_while.nc",
        Tape::WithoutStartLine,
        None,
        M02,
        EXACT,
    );
}

#[test]
fn m03_slots_g91_m98_l() {
    // O1100 in G91 from (x, 10, 5): Z−7 → −2, Y+20 → 30, Z+7 → 5, X+15 Y−20 → (x + 15, 10).
    // Four passes from x = 10: 10, 25, 40, 55. Then N40 G90 Z50, N50 X0 Y0.
    let mut want = vec![[10.0, 10.0, 5.0]]; // N20
    for x in [10.0, 25.0, 40.0, 55.0] {
        want.extend([
            [x, 10.0, -2.0],       // 5 − 7
            [x, 30.0, -2.0],       // 10 + 20
            [x, 30.0, 5.0],        // −2 + 7
            [x + 15.0, 10.0, 5.0], // 30 − 20
        ]);
    }
    want.extend([[70.0, 10.0, 50.0], [0.0, 0.0, 50.0]]); // 55 + 15 = 70
    run_clean(
        "m03_slots_g91_m98_l.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn m04_hole_grid_nested_do() {
    // Holes at X = 20 + 25·column (columns 0…2), Y = 15 + 20·row (rows 0, 1), row by row.
    // Per hole: G0 X Y (Z: N20's 10 first, then the retract 1), pecks k = 1, 2: G1 Z −2.5·k,
    // G0 Z1.
    let mut want = vec![[0.0, 0.0, 10.0]];
    let mut above = 10.0;
    for y in [15.0, 35.0] {
        for x in [20.0, 45.0, 70.0] {
            want.extend([
                [x, y, above],
                [x, y, -2.5], // −2.5·1
                [x, y, 1.0],
                [x, y, -5.0], // −2.5·2
                [x, y, 1.0],
            ]);
            above = 1.0;
        }
    }
    want.extend([[70.0, 35.0, 10.0], [0.0, 0.0, 10.0]]); // N900, N910
    run_clean(
        "m04_hole_grid_nested_do.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

/// m05: pass p = 1, 2, 3 at Z = −p·0.5: down, across to X110, up to 5, back to X−10.
const M05: &[P] = &[
    [-10.0, 0.0, 5.0],  // N20
    [-10.0, 0.0, -0.5], // −1·0.5
    [110.0, 0.0, -0.5], //
    [110.0, 0.0, 5.0],  //
    [-10.0, 0.0, 5.0],  // 1 < 3: GOTO 100
    [-10.0, 0.0, -1.0], // −2·0.5
    [110.0, 0.0, -1.0], //
    [110.0, 0.0, 5.0],  //
    [-10.0, 0.0, 5.0],  // 2 < 3: GOTO 100
    [-10.0, 0.0, -1.5], // −3·0.5
    [110.0, 0.0, -1.5], //
    [110.0, 0.0, 5.0],  //
    [-10.0, 0.0, 5.0],  // 3 < 3 fails: on to N200
    [-10.0, 0.0, 50.0], // N200
];

#[test]
fn m05_face_passes_if_goto() {
    run_clean(
        "m05_face_passes_if_goto.nc",
        Tape::AsWritten,
        None,
        M05,
        EXACT,
    );
}

#[test]
fn m05_face_passes_if_goto_without_tape_start() {
    run_clean(
        "m05_face_passes_if_goto.nc",
        Tape::WithoutStartLine,
        None,
        M05,
        EXACT,
    );
}

#[test]
fn m06_profile_arg_spec_ii() {
    // N30 A4 and four I J K sets: #4 #5 #6 = (10, 5, −1), #7 #8 #9 = (40, 5, −2),
    // #10 #11 #12 = (40, 25, −2), #13 #14 #15 = (10, 25, −1). O9020: G0 to set 1, G1 Z −1,
    // sets 2…4 through #[4 + 3·n], back to set 1, G0 Z5.
    // N40 I5 K8 I7 J9: K before a second I starts set 2, so #4 = 5, #5 vacant, #6 = 8,
    // #7 = 7, #8 = 9, #9 vacant; a vacant variable leaves its address out.
    let want = [
        [0.0, 0.0, 5.0],    // N20
        [10.0, 5.0, 5.0],   // G0 X#4 Y#5
        [10.0, 5.0, -1.0],  // G1 Z#6
        [40.0, 5.0, -2.0],  // #7 #8 #9
        [40.0, 25.0, -2.0], // #10 #11 #12
        [10.0, 25.0, -1.0], // #13 #14 #15
        [10.0, 5.0, -1.0],  // closed: #4 #5 #6
        [10.0, 5.0, 5.0],   // G0 Z5
        [5.0, 5.0, 8.0],    // O9021: X5, Y left out (stays 5), Z8
        [7.0, 9.0, 8.0],    // X7 Y9, Z left out (stays 8)
    ];
    run_clean(
        "m06_profile_arg_spec_ii.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn m07_g66_drill_positions() {
    // After every move from N50 to N90 (not the G66 block itself, not the macro's own
    // moves) O9030 drills: G1 Z−12, G0 Z3 (R). N80 G91 X−20 from X30 → X10; the macro's G90
    // stays afterwards. G67 ends the calls: N110, N120 call nothing.
    let mut want = vec![[0.0, 0.0, 20.0], [0.0, 0.0, 3.0]]; // N20, N30
    for [x, y] in [
        [10.0, 10.0],
        [30.0, 10.0],
        [30.0, 30.0],
        [10.0, 30.0],
        [20.0, 20.0],
    ] {
        want.extend([[x, y, 3.0], [x, y, -12.0], [x, y, 3.0]]);
    }
    want.extend([[20.0, 20.0, 20.0], [0.0, 0.0, 20.0]]);
    run_clean(
        "m07_g66_drill_positions.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

/// m08: O1200 moves to X = 10·#100, Y20 and returns to N100 (M99 P100) for passes 1 and 2;
/// on pass 3 it returns to N300 (N200 is never read). O1201 returns to N330, past N320.
const M08: &[P] = &[
    [0.0, 0.0, 10.0],   // N20
    [10.0, 20.0, 10.0], // pass 1: 1·10
    [20.0, 20.0, 10.0], // pass 2: 2·10
    [30.0, 20.0, 10.0], // pass 3: 3·10, then M99 P300
    [50.0, 0.0, 10.0],  // N300
    [50.0, 0.0, 5.0],   // O1201 G0 Z5, M99 P330
    [50.0, -5.0, 5.0],  // N330
];

#[test]
fn m08_m99_p_return() {
    run_clean("m08_m99_p_return.nc", Tape::AsWritten, None, M08, EXACT);
}

#[test]
fn m08_m99_p_return_without_tape_start() {
    run_clean(
        "m08_m99_p_return.nc",
        Tape::WithoutStartLine,
        None,
        M08,
        EXACT,
    );
}

#[test]
fn m09_macro_calls_subprogram() {
    // O9040 goes to the corner, Z2, G1 to depth; O1300 (M98: the macro's locals) runs the
    // frame incrementally by W (#23) and H (#11); G0 Z10.
    let frame = |x: f64, y: f64, w: f64, h: f64, z: f64| {
        [
            [x, y, 10.0],
            [x, y, 2.0],
            [x, y, z],
            [x + w, y, z],     // X+W
            [x + w, y + h, z], // Y+H
            [x, y + h, z],     // X−W
            [x, y, z],         // Y−H
            [x, y, 10.0],
        ]
    };
    let mut want = vec![[0.0, 0.0, 10.0]];
    want.extend(frame(20.0, 10.0, 30.0, 15.0, -4.0)); // corners 20…50 × 10…25
    want.extend(frame(60.0, 10.0, 20.0, 20.0, -6.0)); // corners 60…80 × 10…30
    want.push([0.0, 0.0, 10.0]);
    run_clean(
        "m09_macro_calls_subprogram.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn m10_common_vars_levels() {
    // Call 1: √(3² + 4²) = 5 into #100, the inner level 2·5 = 10 into #101; the main
    // program's #1 (5) is its own: N40 X5 Y5 Z10. Call 2: √(6² + 8²) = 10, 2·10 = 20:
    // N60 X10 Y5 Z20.
    let want = [[5.0, 5.0, 10.0], [10.0, 5.0, 20.0]];
    run_clean(
        "m10_common_vars_levels.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn m11_vacant_defaults() {
    // Call 1 (X40 Y30 only): Z −0.5, F200, Q 10 by default: passes at Y 0, 10, 20 each
    // ending with the step to the next Y (up to 30). Call 2: Z−1.5, F250, Q0 — zero, not
    // vacant: `#17 EQ #0` fails, `#17 EQ 0` holds, the step is Y (30): one pass.
    let want = [
        [0.0, 0.0, 20.0],   // N20
        [0.0, 0.0, 20.0],   // call 1: G0 X0 Y0
        [0.0, 0.0, -0.5],   // default depth
        [40.0, 0.0, -0.5],  //
        [0.0, 10.0, -0.5],  // 0 + 10
        [40.0, 10.0, -0.5], //
        [0.0, 20.0, -0.5],  // 10 + 10
        [40.0, 20.0, -0.5], //
        [0.0, 30.0, -0.5],  // 20 + 10 = 30 (not past Y)
        [0.0, 30.0, 20.0],  // G0 Z20
        [0.0, 0.0, 20.0],   // call 2: G0 X0 Y0
        [0.0, 0.0, -1.5],   // Z−1.5
        [40.0, 0.0, -1.5],  //
        [0.0, 30.0, -1.5],  // 0 + 30
        [0.0, 30.0, 20.0],  // G0 Z20
        [0.0, 30.0, 20.0],  // N50
    ];
    let b = run_clean(
        "m11_vacant_defaults.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
    // The plunges' feeds: the default 200, then F250 as given.
    let plunges: Vec<f64> = b
        .iter()
        .filter(|b| b.motion.is_some_and(|m| m.end[2] < 0.0 && m.start[2] > 0.0))
        .map(|b| b.modal.feed)
        .collect();
    assert_eq!(plunges, [200.0, 250.0]);
}

#[test]
fn m12_end_point_5001() {
    // N30 G91 from (12.5, −7.25, 30) by (10, 5, −10): (22.5, −2.25, 20) = #1 #2 #3.
    // N50: X 22.5·2 = 45, Y −2.25 − 20 = −22.25, Z 20/4 = 5. N60 G91 X−#5001 = −45 → X0.
    // N70 G90 X#5002 (−22.25) Y#5001 (0), both read before the block moves.
    let want = [
        [12.5, -7.25, 30.0],
        [22.5, -2.25, 20.0],
        [45.0, -22.25, 5.0],
        [0.0, -22.25, 5.0],
        [-22.25, 0.0, 5.0],
    ];
    run_clean("m12_end_point_5001.nc", Tape::AsWritten, None, &want, EXACT);
}

#[test]
fn m13_work_offsets_5221() {
    // G54 = (100, 50, −20), G55 = (−30, 10, −5); machine = workpiece + offset.
    // N20 (0, 0, 10) in G54 → (100, 50, −10).
    // N40 X 100/10 = 10, Y 50/10 = 5 → (110, 55, −10); N50 #4 = #5001 = 110 − 100 = 10.
    // N60 G55 X10 Y0 → (10 − 30, 0 + 10), Z untouched: (−20, 10, −10).
    // N70 #5 = #5003 in G55 = −10 − (−5) = −5.
    // N80 X #5241 − #1 = −30 − 100 = −130 → −160; Y #5242 = 10 → 20;
    //     Z −5 + (−20) + 35 = 10 → 10 − 5 = 5.
    // N90 G54 (0, 0, 10) → (100, 50, −10).
    let want = [
        [100.0, 50.0, -10.0],
        [110.0, 55.0, -10.0],
        [-20.0, 10.0, -10.0],
        [-160.0, 20.0, 5.0],
        [100.0, 50.0, -10.0],
    ];
    run_clean(
        "m13_work_offsets_5221.nc",
        Tape::AsWritten,
        Some(OFFSETS),
        &want,
        EXACT,
    );
}

#[test]
fn m14_tool_offsets_2001() {
    // config/tools.toml: D1 radius 10 length 100, D2 radius 5 length 80, D6 length 120, no
    // wear. #2201 = 100, #2202 = 80, #13001 = 10, #13002 = 5, #2001 + #12001 = 0,
    // #2206 = 120.
    let want = [
        [20.0, 15.0, 50.0], // X 100 − 80, Y 10 + 5, Z 0 + 50
        [35.0, 5.0, 50.0],  // X 40 − 5, Y 5
        [0.0, 0.0, 20.0],   // Z 120 − 100
    ];
    run_clean(
        "m14_tool_offsets_2001.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn m15_boss_g41_passes() {
    // Pass k = 1…3 at Z = −k·2: G0 to (−20, −20) (Z: 5 first, then the last pass's depth),
    // G1 down, G41 D1 to the corner (0, 0), round the 50 × 50 square clockwise, G40 back to
    // (−20, −20). Programmed (contour) points, no tool centre offsets.
    let mut want = vec![[-30.0, -30.0, 5.0]];
    let mut above = 5.0;
    for k in 1..=3 {
        let z = -2.0 * k as f64;
        want.extend([
            [-20.0, -20.0, above], // X 0 − 20, Y 0 − 20
            [-20.0, -20.0, z],
            [0.0, 0.0, z],   // G41
            [0.0, 50.0, z],  // Y 0 + 50
            [50.0, 50.0, z], // X 0 + 50
            [50.0, 0.0, z],
            [0.0, 0.0, z],
            [-20.0, -20.0, z], // G40
        ]);
        above = z;
    }
    want.push([-20.0, -20.0, 50.0]); // N50
    let b = run_clean(
        "m15_boss_g41_passes.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
    let sides: Vec<(TrcSide, u32)> = b
        .iter()
        .filter(|b| b.trc.is_some())
        .map(|b| (b.modal.trc, b.modal.d))
        .collect();
    // N10's G40 of the safe-start line (no D yet), then G41 D1 and G40 once per pass.
    let mut want_sides = vec![(TrcSide::Off, 0)];
    want_sides.extend([(TrcSide::Left, 1), (TrcSide::Off, 1)].repeat(3));
    assert_eq!(sides, want_sides);
}

#[test]
fn m16_inch_slots_g65_l() {
    // G20: 1 in = 25.4 mm. G65 … L3 calls O9080 three times with the same arguments; #100
    // counts the slots. Slot n: X = 1 + 0.5·n in, Y 0.5 → 1.25 in (0.5 + 0.75), Z −0.125 in,
    // retract Z0.1 in.
    let mut want = vec![[0.0, 0.0, 12.7]]; // Z 0.5·25.4
    let mut above = 12.7;
    for x in [25.4, 38.1, 50.8] {
        // 1·25.4, 1.5·25.4, 2·25.4
        want.extend([
            [x, 12.7, above],   // Y 0.5·25.4
            [x, 12.7, -3.175],  // −0.125·25.4
            [x, 31.75, -3.175], // 1.25·25.4
            [x, 31.75, 2.54],   // 0.1·25.4
        ]);
        above = 2.54;
    }
    want.extend([
        [50.8, 31.75, 12.7], // N40 Z0.5
        [50.8, 0.0, 12.7],   // N50 X#5001: 2.0 in (read in inch) → 50.8
        [25.4, 0.0, 12.7],   // N60 G91 X−10000: −10000·0.0001 in = −1 in
        [10.0, 10.0, 12.7],  // N70 G21 X10 Y10 in mm
    ]);
    run_clean(
        "m16_inch_slots_g65_l.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn m17_functions_triangle() {
    // #3 = √(30² + 40²) = 50; #4 = ATAN[40]/[30] = 53.130…° (= ATAN[40,30]); ROUND 53,
    // FIX 53, FUP 54; ABS[−50] = 50; 17 MOD 5 = 2; POW[2,5] = 32.
    let want = [
        [50.0, 53.0, 2.0],  // N20 X#3 Y#5 Z#9
        [30.0, 40.0, 2.0],  // N30 50·cos 53.13° = 30, 50·sin 53.13° = 40
        [54.0, 32.0, 2.0],  // N40 X#7 Y#10
        [-3.0, 1.0, 2.0],   // N50 50 − 53, |53 − 54|
        [17.0, 1.0, 2.0],   // N60 G2 X −3 + 20 R10: a half circle
        [10.0, -1.0, -2.0], // N70 tan 45°·10, FIX[−1.7] = −1, FUP[−1.2] = −2
    ];
    let b = run_clean(
        "m17_functions_triangle.nc",
        Tape::AsWritten,
        None,
        &want,
        TRIG,
    );
    // The half circle's centre: the chord's middle, (−3 + 17)/2 = 7.
    let arc = b
        .iter()
        .find_map(|b| b.motion.filter(|m| m.kind.is_arc()))
        .unwrap();
    assert!(close(arc.center, [7.0, 1.0, 2.0], TRIG), "{:?}", arc.center);
}

#[test]
fn m18_modal_save_restore() {
    // N10 G91 G0 from 0 by 5 → (5, 5, 5). O9090: G90 G1 X40 Y20 → (40, 20, 5), then
    // G#4003 (91) G#4001 (0) F#4109 (321). N40 X1 Y1 is G91 G0 again: (41, 21, 5).
    let want = [
        [5.0, 5.0, 5.0],
        [40.0, 20.0, 5.0],
        [41.0, 21.0, 5.0],
        [0.0, 0.0, 0.0],
    ];
    let b = run_clean(
        "m18_modal_save_restore.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
    let n40 = b.iter().find(|b| b.line == 6).unwrap(); // N40
    assert_eq!(n40.modal.distance, Distance::Incremental);
    assert_eq!(n40.modal.motion, MotionMode::Rapid);
    assert_eq!(n40.modal.feed, 321.0);
}

/// m19: GOTO [2·100] runs pattern 2 ((20, 20), X30), GOTO #5 (900): Z50; #1 = 3 and
/// GOTO [3·100] back to pattern 3 (X40), N900 again, #1 = 4 > 3: the end.
const M19: &[P] = &[
    [0.0, 0.0, 5.0],    // N20
    [20.0, 20.0, 5.0],  // N200
    [30.0, 20.0, 5.0],  // G0 X30
    [30.0, 20.0, 50.0], // N900
    [40.0, 20.0, 50.0], // N300
    [40.0, 20.0, 50.0], // N900
];

#[test]
fn m19_pattern_computed_goto() {
    run_clean(
        "m19_pattern_computed_goto.nc",
        Tape::AsWritten,
        None,
        M19,
        EXACT,
    );
}

#[test]
fn m19_pattern_computed_goto_without_tape_start() {
    run_clean(
        "m19_pattern_computed_goto.nc",
        Tape::WithoutStartLine,
        None,
        M19,
        EXACT,
    );
}

#[test]
fn m20_helical_bore() {
    // Start on the circle at (50 + 12, 40); Z1, G1 Z0; helical turns to Z −1.5, −3, −4.5
    // (0 − 1.5·k, the last not below −4.5), a full circle at −4.5, back to the centre.
    let want = [
        [50.0, 40.0, 5.0],  // N20
        [62.0, 40.0, 5.0],  // X 50 + 12
        [62.0, 40.0, 1.0],  //
        [62.0, 40.0, 0.0],  //
        [62.0, 40.0, -1.5], // turn 1
        [62.0, 40.0, -3.0], // turn 2
        [62.0, 40.0, -4.5], // turn 3: −4.5 is not GT −4.5, the loop ends
        [62.0, 40.0, -4.5], // clean-up circle
        [50.0, 40.0, -4.5], // G1 to the centre
        [50.0, 40.0, 5.0],  // N40
        [50.0, 40.0, 5.0],  // N50
    ];
    let b = run_clean("m20_helical_bore.nc", Tape::AsWritten, None, &want, EXACT);
    // Four full circles about start + (I, J) = (62 − 12, 40 + 0).
    let arcs: Vec<_> = b
        .iter()
        .filter_map(|b| b.motion.filter(|m| m.kind.is_arc()))
        .collect();
    assert_eq!(arcs.len(), 4);
    for a in arcs {
        assert!(close(a.center, [50.0, 40.0, a.start[2]], EXACT), "{a:?}");
    }
}

#[test]
fn m21_nested_m98_count_in_p() {
    // P21400: O1400 twice; in it P31401: O1401 three times, each G0 X+15, G1 Z−15 (10 → −5),
    // G0 Z+15; then X−45 Y+20 to the next row's start. All in N30's G91.
    let mut want = vec![[0.0, 0.0, 10.0]];
    for y in [0.0, 20.0] {
        for x in [15.0, 30.0, 45.0] {
            want.extend([[x, y, 10.0], [x, y, -5.0], [x, y, 10.0]]);
        }
        want.push([0.0, y + 20.0, 10.0]); // 45 − 45, y + 20
    }
    want.push([0.0, 0.0, 10.0]); // N50 G90
    run_clean(
        "m21_nested_m98_count_in_p.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

/// m22: pecks of 3 from 0: −3, −6, −9, then −12 clipped to −10; each followed by G0 Z1;
/// at −10 (LE −10) GOTO 50 leaves the DO loop.
const M22: &[P] = &[
    [25.0, 25.0, 5.0],   // N20
    [25.0, 25.0, -3.0],  // 0 − 3
    [25.0, 25.0, 1.0],   //
    [25.0, 25.0, -6.0],  // −3 − 3
    [25.0, 25.0, 1.0],   //
    [25.0, 25.0, -9.0],  // −6 − 3
    [25.0, 25.0, 1.0],   //
    [25.0, 25.0, -10.0], // −9 − 3 = −12 < −10: −10
    [25.0, 25.0, 1.0],   //
    [25.0, 25.0, 25.0],  // N50
];

#[test]
fn m22_peck_do_loop() {
    run_clean("m22_peck_do_loop.nc", Tape::AsWritten, None, M22, EXACT);
}

#[test]
fn m22_peck_do_loop_without_tape_start() {
    run_clean(
        "m22_peck_do_loop.nc",
        Tape::WithoutStartLine,
        None,
        M22,
        EXACT,
    );
}

#[test]
fn m23_eob_semicolons_kept() {
    // Blocks end at `;`, several to a line. #500 starts vacant (no kept file): 0, then 1.
    // #1 = 100 in X: a variable's value is in mm (100); Y100 without a decimal point is
    // 100·0.001 mm; Z 1·10.
    let want = [
        [100.0, 0.1, 10.0],   // N20
        [120.0, 0.1, 10.0],   // N30 G1 X120
        [120.0, -19.9, 10.0], // G91 Y−20: 0.1 − 20
        [110.0, -19.9, 10.0], // loop pass 1: X −10
        [100.0, -19.9, 10.0], // loop pass 2
        [0.0, 0.0, 10.0],     // N40 G90
    ];
    run_clean(
        "m23_eob_semicolons_kept.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn m24_g66_rows_in_subprogram() {
    // The G66 call comes after every move of O1500 too (a subprogram called by M98, not by
    // G66): holes at X = 8 + 12·k (8, 20, 32), rows at Y = 10 + 15·row (10, 25). O9110 reads
    // its start level #5003 = 10, drills to Z−6 and goes back to 10. O1500's DO 1 is its
    // own, beside the main program's open DO 1.
    let mut want = vec![[0.0, 0.0, 10.0]]; // N20
    for y in [10.0, 25.0] {
        for x in [8.0, 20.0, 32.0] {
            want.extend([[x, y, 10.0], [x, y, -6.0], [x, y, 10.0]]);
        }
    }
    want.extend([[32.0, 25.0, 10.0], [0.0, 0.0, 10.0]]); // N50 (after G67: no call), N60
    run_clean(
        "m24_g66_rows_in_subprogram.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

// ---------------------------------------------------------------------------------------
// Programs that must stop with an alarm.
// ---------------------------------------------------------------------------------------

#[test]
fn a01_alarm_3000_tool_check() {
    // H2's length 80 (#2202) is below Q90: #3000 = 1 (line 11) → MC3001 with the message.
    let m = run_alarm(
        "a01_alarm_3000_tool_check.nc",
        &[[0.0, 0.0, 50.0]],
        AlarmCode::ProgramAlarm,
        11,
        1,
    );
    assert_eq!(m, "MC3001 TOOL TOO SHORT");
}

#[test]
fn a02_missing_subprogram() {
    // "N30 M98 P1234": O1234 is not in the file (O1235 is); the alarm points at P (col 9).
    run_alarm(
        "a02_missing_subprogram.nc",
        &[[0.0, 0.0, 10.0]],
        AlarmCode::MissingProgram,
        5,
        9,
    );
}

#[test]
fn a03_goto_missing_label() {
    // "N30 IF [#1 GT 0] GOTO 250": N250 is only in O2000, not in the running program; the
    // alarm points at GOTO (col 18).
    run_alarm(
        "a03_goto_missing_label.nc",
        &[[5.0, 5.0, 5.0]],
        AlarmCode::JumpTarget,
        6,
        18,
    );
}

#[test]
fn a04_endless_loop_limit() {
    // #1 never changes: WHILE (line 6, col 5 after "N30 ") opens pass 100 001 of
    // program.max_loop_iterations = 100 000.
    run_alarm(
        "a04_endless_loop_limit.nc",
        &[[0.0, 0.0, 5.0]],
        AlarmCode::LoopLimit,
        6,
        5,
    );
}

#[test]
fn a05_end_without_do() {
    // END 2 (line 8) with only DO 1 open; the first pass's move (X 0·10) came before.
    run_alarm(
        "a05_end_without_do.nc",
        &[[0.0, 0.0, 0.0]],
        AlarmCode::ControlNesting,
        8,
        1,
    );
}

#[test]
fn a06_recursive_macro_nesting() {
    // Five macro levels each move G91 X5 (X 5…25); level 5's G65 (line 9) would open a
    // sixth.
    run_alarm(
        "a06_recursive_macro_nesting.nc",
        &[
            [0.0, 0.0, 5.0],
            [5.0, 0.0, 5.0],
            [10.0, 0.0, 5.0],
            [15.0, 0.0, 5.0],
            [20.0, 0.0, 5.0],
            [25.0, 0.0, 5.0],
        ],
        AlarmCode::CallNesting,
        9,
        1,
    );
}

#[test]
fn a07_m99_p_endless() {
    // O1700's M99 P30 returns to N30, which calls O1700 again: every return is a jump back
    // and must count against program.max_loop_iterations (statements/fanuc.rs: "every
    // backward jump … counts"), so pass 100 001 stops at the M99 (line 7, col 1).
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let file = "a07_m99_p_endless.nc";
        let text = source(file);
        let (b, alarm) = blocks_until_alarm(file, &text, &machine(None));
        let _ = tx.send((ends(&b), alarm.map(|a| (a.code, a.line, a.col))));
    });
    let (moves, alarm) = rx
        .recv_timeout(std::time::Duration::from_secs(60))
        .expect("the program ends within a minute");
    assert_eq!(moves, [[0.0, 0.0, 5.0]]);
    assert_eq!(alarm, Some((AlarmCode::LoopLimit, 7, 1)));
}
