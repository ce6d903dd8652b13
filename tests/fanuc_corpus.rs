//! A corpus of Fanuc Custom Macro B programs (tests/corpus/fanuc/), each shaped like a shop
//! or CAM program, interpreted on the shipped Fanuc machine (config/fanuc.toml: increment
//! input, so an axis word without a decimal point counts micrometres) with the shipped tool
//! table. The programmed end point (X Y Z in mm, machine coordinates = workpiece + work
//! offset, no tool centre offsets) of every move is compared with values worked out by hand
//! from the 0i-MF manual's semantics — the arithmetic stands next to each value. A program
//! that runs cleanly must also pass `softnc check`; one that must stop names its alarm, line
//! and column, and the end points reached before it.
//!
//! The m programs use macros and subprograms; the c programs are what CAM posts and shop
//! floors write without them (cycles, cutter compensation, arcs in every plane, inch, the
//! coordinate settings, the frame). A program whose `O` line says `(RS274)` runs in
//! tests/fanuc_rs274.rs too, against LinuxCNC's rs274, with rs274's peck distances; here it
//! runs with the machine data's own (1 mm).

use nc_kernel::{
    AlarmCode, Block, Distance, Interpreter, MachineData, MotionKind, MotionMode, Preparation,
    Role, ToolTable, TrcSide, WorkOffsets,
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
// Programs shaped like CAM posts and shop programs, without macros (c01 …): cycles, cutter
// compensation, arcs in every plane, inch, the coordinate settings and the frame. Those
// marked `(RS274)` also run in tests/fanuc_rs274.rs, against LinuxCNC's rs274 (with its
// peck distances there; here the machine data's 1 mm).
// ---------------------------------------------------------------------------------------

/// What a block does, in the order the channel sees it: its M words, its move, its dwell.
#[derive(Clone, Copy, Debug)]
enum Act {
    M(u32),
    Rapid(P),
    Feed(P),
    Dwell(f64),
}

fn acts(b: &[Block]) -> Vec<Act> {
    let mut out = Vec::new();
    for b in b {
        for w in b.words.iter().filter(|w| w.address == b'M') {
            out.push(Act::M(w.value as u32));
        }
        if let Some(m) = b.motion {
            out.push(if m.kind == MotionKind::Rapid {
                Act::Rapid(m.end)
            } else {
                Act::Feed(m.end)
            });
        }
        if let Some(d) = b.dwell {
            out.push(Act::Dwell(d));
        }
    }
    out
}

fn same_act(a: Act, b: Act) -> bool {
    match (a, b) {
        (Act::M(x), Act::M(y)) => x == y,
        (Act::Rapid(p), Act::Rapid(q)) | (Act::Feed(p), Act::Feed(q)) => close(p, q, EXACT),
        (Act::Dwell(x), Act::Dwell(y)) => (x - y).abs() <= EXACT,
        _ => false,
    }
}

/// The acts of the blocks with sequence number `n` (a cycle's expanded blocks keep it).
fn assert_acts_of(file: &str, b: &[Block], n: u32, want: &[Act]) {
    let of: Vec<Block> = b
        .iter()
        .filter(|b| b.number.is_some_and(|k| k.value == n))
        .cloned()
        .collect();
    let got = acts(&of);
    assert!(
        got.len() == want.len() && got.iter().zip(want).all(|(g, w)| same_act(*g, *w)),
        "{file}: N{n}: got {got:?}\nwant {want:?}"
    );
}

/// The M functions of the whole program in order.
fn m_words(b: &[Block]) -> Vec<u32> {
    acts(b)
        .into_iter()
        .filter_map(|a| match a {
            Act::M(m) => Some(m),
            _ => None,
        })
        .collect()
}

fn dwells(b: &[Block]) -> Vec<f64> {
    b.iter().filter_map(|b| b.dwell).collect()
}

/// Every arc's centre and direction (counter-clockwise: true), in program order.
fn arcs(b: &[Block]) -> Vec<(P, bool)> {
    b.iter()
        .filter_map(|b| b.motion.filter(|m| m.kind.is_arc()))
        .map(|m| (m.center, m.kind == MotionKind::ArcCcw))
        .collect()
}

fn assert_arcs(file: &str, got: &[(P, bool)], want: &[(P, bool)], tol: f64) {
    assert_eq!(got.len(), want.len(), "{file}: arcs {got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            close(g.0, w.0, tol) && g.1 == w.1,
            "{file}: arc {k}: centre {:?} ccw {}, want {:?} ccw {}",
            g.0,
            g.1,
            w.0,
            w.1
        );
    }
}

/// (side after the block, D) of every block that programs G40/G41/G42.
fn sides(b: &[Block]) -> Vec<(TrcSide, u32)> {
    b.iter()
        .filter(|b| b.trc.is_some())
        .map(|b| (b.modal.trc, b.modal.d))
        .collect()
}

fn block_n(b: &[Block], n: u32) -> &Block {
    b.iter()
        .find(|b| b.number.is_some_and(|k| k.value == n))
        .unwrap_or_else(|| panic!("no block N{n}"))
}

#[test]
fn c01_cam_drilling_spot_peck_chipbreak() {
    let mut want = vec![
        // N20 G91 G28 Z0. at the start: through Z 0 + 0 to the reference 0 (no length yet).
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [15.0, 10.0, 0.0],  // N60
        [15.0, 10.0, 25.0], // N70 G43 H1 Z25.
        [15.0, 10.0, 15.0], // N90: the initial level of the G81 series
    ];
    // T1, G98 G81 R5 Z-2: over the hole at 15 (the first is there already), R, bottom, back
    // to the initial level 15.
    want.extend([[15.0, 10.0, 5.0], [15.0, 10.0, -2.0], [15.0, 10.0, 15.0]]);
    for [x, y] in [[45.0, 10.0], [45.0, 30.0], [15.0, 30.0]] {
        want.extend([[x, y, 15.0], [x, y, 5.0], [x, y, -2.0], [x, y, 15.0]]);
    }
    // N160 G91 G28 Z0.: through Z 15 + 0, then the reference 0 minus H1's 100.
    want.extend([[15.0, 30.0, 15.0], [15.0, 30.0, -100.0]]);
    want.extend([[15.0, 10.0, -100.0], [15.0, 10.0, 25.0]]); // N200, N210 G43 H2 Z25.

    // T2, G99 G83 R3 Z-17 Q6: 20 below R in pecks to 6, 12, 18 and 20 (the last 2 < Q)
    // = 3 − 6 = −3, −9, −15, −17; out to R 3 after each, down again to 1 mm
    // (program.peck_clearance) above the depth reached: 3 − 6 + 1 = −2, −8, −14; G99: back
    // to R.
    let peck = |x: f64, y: f64| {
        [
            [x, y, -3.0],
            [x, y, 3.0],
            [x, y, -2.0],
            [x, y, -9.0],
            [x, y, 3.0],
            [x, y, -8.0],
            [x, y, -15.0],
            [x, y, 3.0],
            [x, y, -14.0],
            [x, y, -17.0],
            [x, y, 3.0],
        ]
    };
    want.push([15.0, 10.0, 3.0]); // over the first hole already: straight down to R
    want.extend(peck(15.0, 10.0));
    for [x, y] in [[45.0, 10.0], [45.0, 30.0], [15.0, 30.0]] {
        want.push([x, y, 3.0]); // over the hole at R, which it is at
        want.extend(peck(x, y));
    }
    want.push([15.0, 30.0, 25.0]); // N280
    want.extend([[15.0, 30.0, 25.0], [15.0, 30.0, -80.0]]); // N300: 0 − H2's 80
    want.extend([[30.0, 20.0, -80.0], [30.0, 20.0, 25.0]]); // N340, N350 G43 H7 Z25.

    // T7, G98 G73 R2 Z-9 Q4: 11 below R in pecks to 4, 8, 11 = −2, −6, −9 (the last 3 < Q),
    // back by 1 mm (program.peck_retract) after each but the last: −1, −5; G98: 25.
    want.extend([
        [30.0, 20.0, 2.0],
        [30.0, 20.0, -2.0],
        [30.0, 20.0, -1.0],
        [30.0, 20.0, -6.0],
        [30.0, 20.0, -5.0],
        [30.0, 20.0, -9.0],
        [30.0, 20.0, 25.0],
    ]);
    // N410: 0 − H7's 90. N420 G28 X0. Y0. (still G91): through where X Y are, to 0 0.
    want.extend([
        [30.0, 20.0, 25.0],
        [30.0, 20.0, -90.0],
        [30.0, 20.0, -90.0],
        [0.0, 0.0, -90.0],
    ]);
    let b = run_clean(
        "c01_cam_drilling_spot_peck_chipbreak.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
    // G43 H: config/tools.toml's lengths of offsets 1, 2, 7.
    for (n, h, length) in [(70, 1, 100.0), (210, 2, 80.0), (350, 7, 90.0)] {
        let m = block_n(&b, n).modal;
        assert_eq!((m.h, m.length), (h, length), "N{n}");
    }
    assert_eq!(
        m_words(&b),
        [6, 3, 8, 9, 6, 3, 8, 9, 6, 3, 8, 5, 9, 30],
        "T M6, S M3, M8 … M9 per tool"
    );
}

#[test]
fn c02_hole_rows_g91_k_pecks() {
    let mut want = vec![[0.0, 0.0, 30.0]]; // N20

    // N40 G91 G99 G81 X12. Z-9. R-27. K5: initial level 30, R 30 − 27 = 3, bottom 3 − 9 = −6;
    // X steps of 12 from 0: 12, 24, 36, 48, 60. The first hole is reached at 30 and goes
    // down to R; the others are reached at R (G99), where the move to R goes nowhere.
    want.extend([[12.0, 0.0, 30.0], [12.0, 0.0, 3.0]]);
    for k in 1..=5 {
        let x = 12.0 * k as f64;
        if k > 1 {
            want.push([x, 0.0, 3.0]);
        }
        want.extend([[x, 0.0, -6.0], [x, 0.0, 3.0]]);
    }
    want.extend([[60.0, 0.0, 30.0], [0.0, 20.0, 30.0]]); // N60, N70

    // N80 G91 G98 G83 X15. Z-14. R-28. Q5. K3: R 30 − 28 = 2, bottom 2 − 14 = −12; 14 below R
    // in pecks to 5, 10, 14 (the last 4 < Q) = −3, −8, −12; out to R 2 after each, down to
    // 1 mm above the depth reached: 2 − 5 + 1 = −2, 2 − 10 + 1 = −7; G98: back to 30 each time.
    for x in [15.0, 30.0, 45.0] {
        want.extend([
            [x, 20.0, 30.0],
            [x, 20.0, 2.0],
            [x, 20.0, -3.0],
            [x, 20.0, 2.0],
            [x, 20.0, -2.0],
            [x, 20.0, -8.0],
            [x, 20.0, 2.0],
            [x, 20.0, -7.0],
            [x, 20.0, -12.0],
            [x, 20.0, 30.0],
        ]);
    }
    want.push([0.0, 40.0, 30.0]); // N100

    // N110 G91 G99 G73 X10. Y5. Z-7. R-28. Q3. K2: R 2, bottom 2 − 7 = −5; pecks to 3, 6, 7
    // below R (the last 1 < Q) = −1, −4, −5, back by 1 mm after each but the last: 0, −3;
    // G99: to R 2. Holes at (0 + 10, 40 + 5) and (20, 50).
    want.extend([[10.0, 45.0, 30.0], [10.0, 45.0, 2.0]]);
    for (k, [x, y]) in [[10.0, 45.0], [20.0, 50.0]].into_iter().enumerate() {
        if k > 0 {
            want.push([x, y, 2.0]);
        }
        want.extend([
            [x, y, -1.0],
            [x, y, 0.0],
            [x, y, -4.0],
            [x, y, -3.0],
            [x, y, -5.0],
            [x, y, 2.0],
        ]);
    }
    want.extend([[20.0, 50.0, 30.0], [0.0, 0.0, 30.0]]); // N130, N140
    run_clean(
        "c02_hole_rows_g91_k_pecks.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn c03_tapping_g84_g74_spindle() {
    let file = "c03_tapping_g84_g74_spindle.nc";
    let want = [
        [20.0, 20.0, 0.0],  // N30
        [20.0, 20.0, 20.0], // N50: the initial level
        // N70 G98 G84 R5 Z-15: down to R, feed to the bottom, feed out to R, up to 20.
        [20.0, 20.0, 5.0],
        [20.0, 20.0, -15.0],
        [20.0, 20.0, 5.0],
        [20.0, 20.0, 20.0],
        // N80 X50.
        [50.0, 20.0, 20.0],
        [50.0, 20.0, 5.0],
        [50.0, 20.0, -15.0],
        [50.0, 20.0, 5.0],
        [50.0, 20.0, 20.0],
        // N110 G91 G28 Z0.: 0 − H6's 120.
        [50.0, 20.0, 20.0],
        [50.0, 20.0, -120.0],
        [35.0, 40.0, -120.0], // N140
        [35.0, 40.0, 20.0],   // N160
        // N180 G99 G74 R3 Z-12: back to R only.
        [35.0, 40.0, 3.0],
        [35.0, 40.0, -12.0],
        [35.0, 40.0, 3.0],
        [35.0, 40.0, 20.0], // N200
        // N220: 0 − H7's 90.
        [35.0, 40.0, 20.0],
        [35.0, 40.0, -90.0],
    ];
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // G84 under M3: at the bottom the dwell P200 (0.2 s), M4, feed out, M3 again at R, then
    // the return; the spindle words come in their own blocks, between the moves.
    let tap = |x: f64, first: bool| {
        let mut v = Vec::new();
        if !first {
            v.push(Act::Rapid([x, 20.0, 20.0]));
        }
        v.extend([
            Act::Rapid([x, 20.0, 5.0]),
            Act::Feed([x, 20.0, -15.0]),
            Act::Dwell(0.2),
            Act::M(4),
            Act::Feed([x, 20.0, 5.0]),
            Act::M(3),
            Act::Rapid([x, 20.0, 20.0]),
        ]);
        v
    };
    assert_acts_of(file, &b, 70, &tap(20.0, true));
    assert_acts_of(file, &b, 80, &tap(50.0, false));
    // G74 under M4: M3 at the bottom after P100, M4 at R; G99 stays at R.
    assert_acts_of(
        file,
        &b,
        180,
        &[
            Act::Rapid([35.0, 40.0, 3.0]),
            Act::Feed([35.0, 40.0, -12.0]),
            Act::Dwell(0.1),
            Act::M(3),
            Act::Feed([35.0, 40.0, 3.0]),
            Act::M(4),
        ],
    );
    // The whole program: T6 M6, M3, M8, two holes (M4 M3), M9, T7 M6, M4, M8, one hole
    // (M3 M4), M5 M9, M30.
    assert_eq!(
        m_words(&b),
        [6, 3, 8, 4, 3, 4, 3, 9, 6, 4, 8, 3, 4, 5, 9, 30]
    );
}

#[test]
fn c04_boring_g85_g86_g89() {
    let want = [
        [0.0, 0.0, 40.0], // N20
        // N40 G99 G85 R2 Z-10: feed in, feed out to R (the return to R goes nowhere).
        [20.0, 15.0, 40.0],
        [20.0, 15.0, 2.0],
        [20.0, 15.0, -10.0],
        [20.0, 15.0, 2.0],
        [40.0, 15.0, 2.0], // N50, at R
        [40.0, 15.0, -10.0],
        [40.0, 15.0, 2.0],
        [40.0, 15.0, 40.0], // N70
        // N80 G98 G86 R2 Z-12: feed in, M5, rapid out to the initial level 40, M3.
        [20.0, 35.0, 40.0],
        [20.0, 35.0, 2.0],
        [20.0, 35.0, -12.0],
        [20.0, 35.0, 40.0],
        [40.0, 35.0, 40.0], // N90
        [40.0, 35.0, 2.0],
        [40.0, 35.0, -12.0],
        [40.0, 35.0, 40.0],
        // N110 G99 G89 R2 Z-6 P500: feed in, dwell, feed out to R.
        [60.0, 25.0, 40.0],
        [60.0, 25.0, 2.0],
        [60.0, 25.0, -6.0],
        [60.0, 25.0, 2.0],
        [60.0, 45.0, 2.0], // N120, at R
        [60.0, 45.0, -6.0],
        [60.0, 45.0, 2.0],
        [60.0, 45.0, 40.0], // N140
        [0.0, 0.0, 40.0],   // N150
    ];
    let b = run_clean(
        "c04_boring_g85_g86_g89.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
    // M3; G86: M5 at each bottom, M3 at the top (twice); M5, M30.
    assert_eq!(m_words(&b), [3, 5, 3, 5, 3, 5, 30]);
    // G89 P500: 500 ms at each bottom; G86 P0 and G85 dwell nothing.
    assert_eq!(dwells(&b), [0.5, 0.5]);
    let feeds_out = acts(&b)
        .windows(2)
        .filter(|w| matches!(w, [Act::Dwell(_), Act::Feed(p)] if p[2] == 2.0))
        .count();
    assert_eq!(feeds_out, 2, "G89 feeds out to R after the dwell");
}

#[test]
fn c05_fine_boring_g76_back_boring_g87() {
    let file = "c05_fine_boring_g76_back_boring_g87.nc";
    let want = [
        [30.0, 30.0, 0.0],  // N30
        [30.0, 30.0, 30.0], // N50: the initial level
        // N60 G98 G76 R3 Z-20 Q0.4: in, shift +X by 0.4 (30.4) at the bottom, out at rapid
        // to 30, shift back.
        [30.0, 30.0, 3.0],
        [30.0, 30.0, -20.0],
        [30.4, 30.0, -20.0],
        [30.4, 30.0, 30.0],
        [30.0, 30.0, 30.0],
        // N70 X70.: 70 + 0.4 = 70.4
        [70.0, 30.0, 30.0],
        [70.0, 30.0, 3.0],
        [70.0, 30.0, -20.0],
        [70.4, 30.0, -20.0],
        [70.4, 30.0, 30.0],
        [70.0, 30.0, 30.0],
        // N90 G98 G87 Z-5 R-25 Q2: over the hole at 30, shift +2 (52), rapid down to R −25
        // below the part, back on the axis, feed up to Z −5, shift, rapid to the initial
        // level 30, back.
        [50.0, 60.0, 30.0],
        [52.0, 60.0, 30.0],
        [52.0, 60.0, -25.0],
        [50.0, 60.0, -25.0],
        [50.0, 60.0, -5.0],
        [52.0, 60.0, -5.0],
        [52.0, 60.0, 30.0],
        [50.0, 60.0, 30.0],
        // N120 G91 G28 Z0.: 0 − H6's 120.
        [50.0, 60.0, 30.0],
        [50.0, 60.0, -120.0],
    ];
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // G76: after the dwell P300 at the bottom the spindle orients (M19) before the shift and
    // turns again (M3, as before the hole) after the shift back.
    assert_acts_of(
        file,
        &b,
        60,
        &[
            Act::Rapid([30.0, 30.0, 3.0]),
            Act::Feed([30.0, 30.0, -20.0]),
            Act::Dwell(0.3),
            Act::M(19),
            Act::Rapid([30.4, 30.0, -20.0]),
            Act::Rapid([30.4, 30.0, 30.0]),
            Act::Rapid([30.0, 30.0, 30.0]),
            Act::M(3),
        ],
    );
    // G87: oriented for the way down and the way out, turning (M3) for the cut upwards; no
    // dwell (G80 cleared N60's P).
    assert_acts_of(
        file,
        &b,
        90,
        &[
            Act::Rapid([50.0, 60.0, 30.0]),
            Act::M(19),
            Act::Rapid([52.0, 60.0, 30.0]),
            Act::Rapid([52.0, 60.0, -25.0]),
            Act::Rapid([50.0, 60.0, -25.0]),
            Act::M(3),
            Act::Feed([50.0, 60.0, -5.0]),
            Act::M(19),
            Act::Rapid([52.0, 60.0, -5.0]),
            Act::Rapid([52.0, 60.0, 30.0]),
            Act::Rapid([50.0, 60.0, 30.0]),
            Act::M(3),
        ],
    );
    assert_eq!(m_words(&b), [6, 3, 19, 3, 19, 3, 19, 3, 19, 3, 5, 30]);
    assert_eq!(dwells(&b), [0.3, 0.3]);
}

const C06: &str = "c06_cam_contour_g41_arc_lead.nc";

#[test]
fn c06_cam_contour_g41_arc_lead() {
    let text = source(C06);
    let b = blocks(C06, &text, &machine(None));
    let want = [
        [50.0, -25.0, 0.0],   // N40
        [50.0, -25.0, 15.0],  // N50
        [50.0, -25.0, 3.0],   // N70
        [50.0, -25.0, -5.0],  // N80
        [50.0, -10.0, -5.0],  // N90 G41 D2: the lead-in line
        [40.0, 0.0, -5.0],    // N100 G3 R10: lead-in arc
        [0.0, 0.0, -5.0],     // N110
        [0.0, 40.0, -5.0],    // N120
        [10.0, 50.0, -5.0],   // N130 G2 R10
        [60.0, 50.0, -5.0],   // N140
        [80.0, 30.0, -5.0],   // N150 G2 I0 J-20
        [80.0, 0.0, -5.0],    // N160
        [40.0, 0.0, -5.0],    // N170
        [30.0, -10.0, -5.0],  // N180 G3 I0 J-10: lead-out arc
        [30.0, -25.0, -5.0],  // N190 G40
        [30.0, -25.0, 15.0],  // N200
        [30.0, -25.0, 15.0],  // N230 G91 G28 Z0.: through Z 15,
        [30.0, -25.0, -80.0], // to 0 − H2's 80
    ];
    assert_ends(C06, &ends(&b), &want, EXACT);
    // N100: from (50, −10) to (40, 0), R10 < 180°: the centre 10 from both, left of the chord
    // (−10, 10) for G3: (45, −5) + (−5, −5) = (40, −10). N130: chord (10, 10), right of it
    // for G2: (5, 45) + (5, −5) = (10, 40). N150: (60, 50) + (0, −20). N180: (40, 0) + (0, −10).
    assert_arcs(
        C06,
        &arcs(&b),
        &[
            ([40.0, -10.0, -5.0], true),
            ([10.0, 40.0, -5.0], false),
            ([60.0, 30.0, -5.0], false),
            ([40.0, -10.0, -5.0], true),
        ],
        EXACT,
    );
    // N10's G40; G41 D2 in the lead-in line (radius 5), G40 in the last line.
    assert_eq!(
        sides(&b),
        [(TrcSide::Off, 0), (TrcSide::Left, 2), (TrcSide::Off, 2)]
    );
    assert_eq!(block_n(&b, 90).modal.radius, 5.0);
}

/// The same program through `softnc check`. The tool path of the bottom edge (N110, N170)
/// passes over the lead arcs (N180, N100): the whole-program check takes them for contour
/// and reports a gouge, where they are air moves a Fanuc runs without alarm (its
/// interference check looks three blocks ahead, and at directions, not distances).
#[test]
fn c06_cam_contour_g41_arc_lead_passes_check() {
    assert_check_passes(&path_of(C06), None);
}

#[test]
fn c07_helix_bore_g41() {
    let want = [
        [50.0, 40.0, 0.0],   // N40
        [50.0, 40.0, 10.0],  // N50
        [50.0, 40.0, 1.0],   // N60
        [50.0, 40.0, 0.0],   // N70
        [70.0, 40.0, 0.0],   // N80 G41 D2: radially out to the wall, 50 + 20
        [70.0, 40.0, -3.0],  // N90 helix turn, 0 − 3
        [70.0, 40.0, -6.0],  // N100
        [70.0, 40.0, -9.0],  // N110
        [70.0, 40.0, -9.0],  // N120 full circle at the bottom
        [50.0, 40.0, -9.0],  // N130 G40 back to the centre
        [50.0, 40.0, 10.0],  // N140
        [50.0, 40.0, 10.0],  // N160 G91 G28 Z0.
        [50.0, 40.0, -80.0], // 0 − H2's 80
    ];
    let b = run_clean("c07_helix_bore_g41.nc", Tape::AsWritten, None, &want, EXACT);
    // Four turns counter-clockwise about (70 − 20, 40 + 0); the centre's Z is the turn's
    // start (0, −3, −6, −9).
    assert_arcs(
        "c07_helix_bore_g41.nc",
        &arcs(&b),
        &[
            ([50.0, 40.0, 0.0], true),
            ([50.0, 40.0, -3.0], true),
            ([50.0, 40.0, -6.0], true),
            ([50.0, 40.0, -9.0], true),
        ],
        EXACT,
    );
    assert_eq!(
        sides(&b),
        [(TrcSide::Off, 0), (TrcSide::Left, 2), (TrcSide::Off, 2)]
    );
}

#[test]
fn c08_g18_g19_arcs_lead_arcs() {
    let want = [
        [-40.0, 10.0, 20.0],  // N20
        [-40.0, 10.0, -30.0], // N40
        [-30.0, 10.0, -30.0], // N50
        [-25.0, 10.0, -25.0], // N60 lead-in
        [25.0, 10.0, -25.0],  // N70 dome
        [30.0, 10.0, -30.0],  // N80 lead-out
        [40.0, 10.0, -30.0],  // N90
        [40.0, 10.0, 20.0],   // N100
        [50.0, -25.0, 20.0],  // N110
        [50.0, -25.0, 5.0],   // N120
        [50.0, -15.0, -5.0],  // N130 lead-in
        [50.0, 15.0, -5.0],   // N140 groove
        [50.0, 25.0, 5.0],    // N150 lead-out
        [50.0, 35.0, 5.0],    // N160
        [55.0, 25.0, 15.0],   // N165 helix: X 50 + 5 beside the quarter circle
        [55.0, 25.0, 20.0],   // N170
    ];
    let file = "c08_g18_g19_arcs_lead_arcs.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // G18 works in (Z, X), counter-clockwise from +Z towards +X (G03). N60 G2 R5 from
    // (z, x) = (−30, −30) to (−25, −25): chord (5, 5), centre right of it, (−27.5, −27.5) +
    // (2.5, −2.5) = (−25, −30), X−30 Z−25. N70: I25 K0 from X−25 Z−25: X0 Z−25; it goes from
    // −90° to +90° through the top (Z0): counter-clockwise. N80 G2 R5 from (−25, 25) to
    // (−30, 30): chord (−5, 5), right of it (−27.5, 27.5) + (2.5, 2.5) = (−25, 30), X30 Z−25.
    // G19 works in (Y, Z). N130 G2 R10 from (−25, 5) to (−15, −5): chord (10, −10), right
    // of it (−20, 0) + (−5, −5) = (−25, −5). N140: J15 K0 from Y−15 Z−5: (0, −5), through
    // the bottom Z−20: from 180° to 360°, counter-clockwise. N150 G2 R10 from (15, −5) to
    // (25, 5): chord (10, 10), right of it (20, 0) + (5, −5) = (25, −5). N165: J−10 K0 from
    // Y35 Z5: (25, 5), from 0° to 90°: counter-clockwise; the centre's X is the start's, 50.
    assert_arcs(
        file,
        &arcs(&b),
        &[
            ([-30.0, 10.0, -25.0], false),
            ([0.0, 10.0, -25.0], true),
            ([30.0, 10.0, -25.0], false),
            ([50.0, -25.0, -5.0], false),
            ([50.0, 0.0, -5.0], true),
            ([50.0, 25.0, -5.0], false),
            ([50.0, 25.0, 5.0], true),
        ],
        EXACT,
    );
}

#[test]
fn c09_r_arcs_over_180_full_circles() {
    let want = [
        [0.0, 0.0, 5.0],    // N20
        [0.0, 0.0, -1.0],   // N40
        [20.0, 0.0, -1.0],  // N50
        [36.0, 0.0, -1.0],  // N60 G2 R-10
        [50.0, 0.0, -1.0],  // N70
        [50.0, 24.0, -1.0], // N80 G3 R-13
        [20.0, 24.0, -1.0], // N90
        [20.0, 24.0, -1.0], // N100 full circle
        [8.0, 24.0, -1.0],  // N110 G91 X−12: 20 − 12
        [8.0, 24.0, -1.0],  // N120 full circle in G91
        [0.0, 0.0, -1.0],   // N130
        [0.0, 0.0, 5.0],    // N140
    ];
    let file = "c09_r_arcs_over_180_full_circles.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // N60: chord (20, 0) → (36, 0) of 16, R 10: the centre √(10² − 8²) = 6 off the middle
    // (28, 0); negative R (over 180°) puts it on the other side than a short G2 arc would
    // (right of the chord, −Y): left, (28, 6). 10 from (20, 0): √(8² + 6²).
    // N80: chord (50, 0) → (50, 24) of 24, R 13: √(13² − 12²) = 5 off (50, 12); a short G3
    // would have it left (−X), −13 puts it right: (55, 12).
    // N100: (20, 24) + (0, −8). N110: chord (20, 24) → (8, 24) of 12, R 10: √(10² − 6²) = 8
    // off (14, 24); G3 short: left of −X is −Y, so −10: +Y, (14, 32).
    // N120: (8, 24) + (0, −5).
    assert_arcs(
        file,
        &arcs(&b),
        &[
            ([28.0, 6.0, -1.0], false),
            ([55.0, 12.0, -1.0], true),
            ([20.0, 16.0, -1.0], false),
            ([14.0, 32.0, -1.0], true),
            ([8.0, 19.0, -1.0], false),
        ],
        EXACT,
    );
}

#[test]
fn c10_inch_spot_drill_and_slot() {
    // G20: 1 in = 25.4 mm. Z1 = 25.4, R0.1 = 2.54, Z−0.1 = −2.54, 0.5 = 12.7, 1.5 = 38.1,
    // 1.25 = 31.75, 2.5 = 63.5, 0.25 = 6.35, −0.125 = −3.175, 3.5 = 88.9, 0.75 = 19.05.
    let want = [
        [0.0, 0.0, 25.4], // N20
        // N40 G99 G81: initial level 25.4, R 2.54, bottom −2.54.
        [12.7, 12.7, 25.4],
        [12.7, 12.7, 2.54],
        [12.7, 12.7, -2.54],
        [12.7, 12.7, 2.54],
        [38.1, 12.7, 2.54], // N50 X1.5
        [38.1, 12.7, -2.54],
        [38.1, 12.7, 2.54],
        [38.1, 31.75, 2.54], // N60 Y1.25
        [38.1, 31.75, -2.54],
        [38.1, 31.75, 2.54],
        [38.1, 31.75, 12.7],   // N80 Z0.5
        [63.5, 6.35, 12.7],    // N90
        [63.5, 6.35, -3.175],  // N100
        [88.9, 6.35, -3.175],  // N110
        [88.9, 31.75, -3.175], // N120 G3 J0.5
        [63.5, 31.75, -3.175], // N130
        [63.5, 6.35, -3.175],  // N140 G3 J−0.5
        [63.5, 6.35, 12.7],    // N150
        // N160 G91 X−0.75 Y0.25: 2.5 − 0.75 = 1.75 in = 44.45, 0.25 + 0.25 = 0.5 in = 12.7.
        [44.45, 12.7, 12.7],
        [44.45, 12.7, 25.4], // N170
        [0.0, 0.0, 25.4],    // N180
    ];
    let file = "c10_inch_spot_drill_and_slot.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // Centres: (3.5, 0.25 + 0.5) in = (88.9, 19.05), (2.5, 1.25 − 0.5) in = (63.5, 19.05).
    assert_arcs(
        file,
        &arcs(&b),
        &[([88.9, 19.05, -3.175], true), ([63.5, 19.05, -3.175], true)],
        EXACT,
    );
}

#[test]
fn c11_local_coordinates_g52_and_g92() {
    // G54 = (100, 50, 0) from N20's G10 L2 P1. Machine = workpiece + G54 + G52 (+ G92).
    let want = [
        [100.0, 50.0, 10.0], // N30 (0, 0, 10)
        // G52 X20. Y10.: part 1's zero at (120, 60).
        [125.0, 65.0, 10.0], // N60 (5, 5)
        [125.0, 65.0, -2.0], // N70
        [135.0, 65.0, -2.0], // N80 X15
        [135.0, 75.0, -2.0], // N90 Y15
        [135.0, 75.0, 10.0], // N100
        // G52 X60. Y10. (not added to the last): part 2's zero at (160, 60).
        [165.0, 65.0, 10.0], // N120
        [165.0, 65.0, -2.0], // N130
        [175.0, 75.0, -2.0], // N140 G91 X10 Y10
        [175.0, 75.0, 10.0], // N150
        [100.0, 50.0, 10.0], // N170 after G52 X0 Y0: G54's zero
        // N180 G92 X-10. Y-20. at (100, 50): the zero moves to (100 + 10, 50 + 20).
        [110.0, 70.0, 10.0], // N190
        [115.0, 75.0, 10.0], // N200
        [115.0, 75.0, 20.0], // N210
    ];
    run_clean(
        "c11_local_coordinates_g52_and_g92.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn c12_g10_l2_l20_g55_g54_1() {
    // m13's offsets file: G54 (100, 50, −20), G55 (−30, 10, −5). N20 writes G55 = (−150, −80,
    // −30) over the file's; N30 G54.1 P2 = (200, 100, −50).
    let want = [
        [-140.0, -70.0, -10.0], // N40 G55 (10, 10, 20): 10 − 150, 10 − 80, 20 − 30
        [-140.0, -70.0, -35.0], // N50 Z−5 − 30
        [-140.0, -70.0, -10.0], // N60
        // N70 G54.1 P2 X10 Y10: 210, 110; Z not written stays where it is (machine −10).
        [210.0, 110.0, -10.0],
        [210.0, 110.0, -30.0], // N80 Z 20 − 50
        // N90 G91 G10 L20 P2 X5. Y-5. adds: P2 = (205, 95, −50), used from N100 on.
        [215.0, 105.0, -30.0], // N100 10 + 205, 10 + 95
        // N110 G91 G10 L2 P2 Z2.: G55 Z −30 + 2 = −28.
        [-150.0, -80.0, -8.0], // N120 G55 (0, 0, 20)
        [100.0, 50.0, 30.0],   // N130 G54 (0, 0, 50): the file's G54
    ];
    let b = run_clean(
        "c12_g10_l2_l20_g55_g54_1.nc",
        Tape::AsWritten,
        Some(OFFSETS),
        &want,
        EXACT,
    );
    // The sets in force: G55 is the second, G54.1 P2 comes after G54 … G59 (6 + 2).
    let sets: Vec<(u32, u8)> = [40, 70, 120, 130]
        .into_iter()
        .map(|n| (n, block_n(&b, n).modal.work_offset))
        .collect();
    assert_eq!(sets, [(40, 2), (70, 8), (120, 2), (130, 1)]);
}

#[test]
fn c13_g10_l12_radius_then_g41_pocket() {
    let want = [
        [30.0, 20.0, 0.0],   // N60
        [30.0, 20.0, 10.0],  // N70
        [30.0, 20.0, -4.0],  // N90
        [30.0, 10.0, -4.0],  // N100 G41 D11
        [45.0, 10.0, -4.0],  // N110
        [50.0, 15.0, -4.0],  // N120 G3 R5
        [50.0, 25.0, -4.0],  // N130
        [45.0, 30.0, -4.0],  // N140
        [15.0, 30.0, -4.0],  // N150
        [10.0, 25.0, -4.0],  // N160
        [10.0, 15.0, -4.0],  // N170
        [15.0, 10.0, -4.0],  // N180
        [30.0, 10.0, -4.0],  // N190
        [30.0, 20.0, -4.0],  // N200 G40
        [30.0, 20.0, 10.0],  // N210
        [30.0, 20.0, 10.0],  // N230 G91 G28 Z0.
        [30.0, 20.0, -75.0], // 0 − H11's 75 (G10 L10)
    ];
    let file = "c13_g10_l12_radius_then_g41_pocket.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // The corners, G3 R5 < 180°: the centre left of each chord. (45, 10) → (50, 15): (47.5,
    // 12.5) + (−2.5, 2.5); (50, 25) → (45, 30): (47.5, 27.5) + (−2.5, −2.5); (15, 30) → (10,
    // 25): (12.5, 27.5) + (2.5, −2.5); (10, 15) → (15, 10): (12.5, 12.5) + (2.5, 2.5).
    assert_arcs(
        file,
        &arcs(&b),
        &[
            ([45.0, 15.0, -4.0], true),
            ([45.0, 25.0, -4.0], true),
            ([15.0, 25.0, -4.0], true),
            ([15.0, 15.0, -4.0], true),
        ],
        EXACT,
    );
    // D11: L12 geometry 4 + L13 wear −0.05 = 3.95; H11: L10 75.
    let m = block_n(&b, 100).modal;
    assert_eq!((m.trc, m.d), (TrcSide::Left, 11));
    assert!((m.radius - 3.95).abs() <= EXACT, "radius {}", m.radius);
    assert_eq!(
        (block_n(&b, 70).modal.h, block_n(&b, 70).modal.length),
        (11, 75.0)
    );
}

#[test]
fn c14_g68_rotated_slot_pattern() {
    // O1401 in program terms: G0 X65 Y50 (Z as it is), Z2, G1 Z−3, G91 X20 (to X85), G0 Z10.
    // G68 turns (x, y) by a about (50, 50): (50 + (x − 50)·cos a − (y − 50)·sin a, 50 +
    // (x − 50)·sin a + (y − 50)·cos a); here y = 50: (50 + r·cos a, 50 + r·sin a), r = 15, 35.
    let slot = |a: f64| {
        let (p, q) = (
            [50.0 + 15.0 * cosd(a), 50.0 + 15.0 * sind(a)],
            [50.0 + 35.0 * cosd(a), 50.0 + 35.0 * sind(a)],
        );
        [
            [p[0], p[1], 10.0],
            [p[0], p[1], 2.0],
            [p[0], p[1], -3.0],
            [q[0], q[1], -3.0],
            [q[0], q[1], 10.0],
        ]
    };
    // 30°: (50 + 15·√3/2, 50 + 7.5) = (62.990 381…, 57.5), (50 + 35·√3/2, 67.5) =
    // (80.310 889…, 67.5); 120°: (50 − 7.5, 62.990 381…) = (42.5, …), (50 − 17.5, 80.310 889…).
    let s30 = slot(30.0);
    assert!((s30[0][0] - (50.0 + 7.5 * 3f64.sqrt())).abs() < 1e-12);
    assert!((s30[0][1] - 57.5).abs() < 1e-12 && (s30[3][1] - 67.5).abs() < 1e-12);
    let s120 = slot(120.0);
    assert!((s120[3][0] - 32.5).abs() < 1e-12);
    assert!((s120[3][1] - (50.0 + 17.5 * 3f64.sqrt())).abs() < 1e-12);
    let mut want = vec![[50.0, 50.0, 10.0]]; // N20
    for a in [0.0, 30.0, 120.0] {
        want.extend(slot(a));
    }
    want.push([50.0, 50.0, 50.0]); // N110 after G69
    run_clean(
        "c14_g68_rotated_slot_pattern.nc",
        Tape::AsWritten,
        None,
        &want,
        TRIG,
    );
}

#[test]
fn c15_g51_scaling_obround() {
    // O1501 in program terms: G0 (20, 20), G1 Z−2, X60, G3 to (60, 40) about (60, 30), X20,
    // G3 to (20, 20) about (20, 30), G0 Z5.
    let mut want = vec![[0.0, 0.0, 5.0]]; // N20
    want.extend([
        [20.0, 20.0, 5.0], // N40: as written
        [20.0, 20.0, -2.0],
        [60.0, 20.0, -2.0],
        [60.0, 40.0, -2.0],
        [20.0, 40.0, -2.0],
        [20.0, 20.0, -2.0],
        [20.0, 20.0, 5.0],
    ]);
    // N50 G51 X40. Y30. P500: every axis by 0.5 about (40, 30, 5) (Z: where it is):
    // (20, 20, 5) → (30, 25, 5); Z−2 → 5 + 0.5·(−2 − 5) = 1.5; (60, 20) → (50, 25); (60, 40)
    // → (50, 35); (20, 40) → (30, 35).
    want.extend([
        [30.0, 25.0, 5.0],
        [30.0, 25.0, 1.5],
        [50.0, 25.0, 1.5],
        [50.0, 35.0, 1.5],
        [30.0, 35.0, 1.5],
        [30.0, 25.0, 1.5],
        [30.0, 25.0, 5.0],
    ]);
    // N80 I1500 J1500: X and Y by 1.5 about (40, 30), Z as written: (20, 20) → (40 − 30,
    // 30 − 15) = (10, 15); (60, 20) → (70, 15); (60, 40) → (70, 45); (20, 40) → (10, 45).
    want.extend([
        [10.0, 15.0, 5.0],
        [10.0, 15.0, -2.0],
        [70.0, 15.0, -2.0],
        [70.0, 45.0, -2.0],
        [10.0, 45.0, -2.0],
        [10.0, 15.0, -2.0],
        [10.0, 15.0, 5.0],
    ]);
    // N110 I2000 J500, O1502's square (30, 20) (50, 20) (50, 40) (30, 40): X by 2, Y by 0.5
    // about (40, 30): (20, 25), (60, 25), (60, 35), (20, 35); Z as written (−1).
    want.extend([
        [20.0, 25.0, 5.0],
        [20.0, 25.0, -1.0],
        [60.0, 25.0, -1.0],
        [60.0, 35.0, -1.0],
        [20.0, 35.0, -1.0],
        [20.0, 25.0, -1.0],
        [20.0, 25.0, 5.0],
    ]);
    want.push([0.0, 0.0, 5.0]); // N140 after G50
    let file = "c15_g51_scaling_obround.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // The arc centres scale with the points: (60, 30), (20, 30); at 0.5 (50, 30), (30, 30);
    // at 1.5 (70, 30), (10, 30). Counter-clockwise throughout (no factor is negative).
    assert_arcs(
        file,
        &arcs(&b),
        &[
            ([60.0, 30.0, -2.0], true),
            ([20.0, 30.0, -2.0], true),
            ([50.0, 30.0, 1.5], true),
            ([30.0, 30.0, 1.5], true),
            ([70.0, 30.0, -2.0], true),
            ([10.0, 30.0, -2.0], true),
        ],
        EXACT,
    );
}

#[test]
fn c16_g51_1_mirror_contour_g41() {
    // O1601: G41 to (10, 10), (10, 25), G2 to (25, 40) about (25, 25), (40, 10), (10, 10),
    // G40 to (0, 0); mirrored about X0 and/or Y0: (sx·x, sy·y).
    let mut want = vec![[0.0, 0.0, 5.0], [0.0, 0.0, -2.0]]; // N20, N40
    let mut want_arcs = Vec::new();
    for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
        want.extend([
            [sx * 10.0, sy * 10.0, -2.0],
            [sx * 10.0, sy * 25.0, -2.0],
            [sx * 25.0, sy * 40.0, -2.0],
            [sx * 40.0, sy * 10.0, -2.0],
            [sx * 10.0, sy * 10.0, -2.0],
            [0.0, 0.0, -2.0],
        ]);
        // One mirrored axis turns the plane over: G2 runs as G3. Two turn it back.
        want_arcs.push(([sx * 25.0, sy * 25.0, -2.0], sx * sy < 0.0));
    }
    want.push([0.0, 0.0, 5.0]); // N130
    let file = "c16_g51_1_mirror_contour_g41.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    assert_arcs(file, &arcs(&b), &want_arcs, EXACT);
    // G41 as programmed, G42 under one mirror (the tool stays outside), G41 under two.
    let mut want_sides = vec![(TrcSide::Off, 0)];
    for side in [TrcSide::Left, TrcSide::Right, TrcSide::Left, TrcSide::Right] {
        want_sides.extend([(side, 2), (TrcSide::Off, 2)]);
    }
    assert_eq!(sides(&b), want_sides);
}

#[test]
fn c17_g28_intermediate_g53_g30() {
    // G54 = (200, 100, −50) from N20; the reference positions of config/fanuc.toml are 0.
    let want = [
        [210.0, 120.0, -20.0],  // N30 (10, 20, 30)
        [250.0, 120.0, -20.0],  // N40 G28: through (50, 20) of G54, Z stays
        [0.0, 0.0, -20.0],      // to X Y's reference 0
        [210.0, 110.0, -20.0],  // N50
        [210.0, 110.0, -5.0],   // N60 G91 G28 Z15.: through −20 + 15,
        [210.0, 110.0, 0.0],    // to Z's reference 0
        [-100.0, -50.0, 0.0],   // N70 G53: machine coordinates
        [-100.0, -50.0, -10.0], // N80 G53 Z-10.
        [200.0, 100.0, -10.0],  // N90 G54 again (G53 is one block only)
        [220.0, 100.0, -10.0],  // N100 G30: through X20 of G54,
        [0.0, 100.0, -10.0],    // to X's second reference 0
        [0.0, 100.0, -20.0],    // N110 Z 30 − 50
    ];
    run_clean(
        "c17_g28_intermediate_g53_g30.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn c18_side_drilling_g18_g19_cycles() {
    let mut want = vec![[0.0, 30.0, 10.0]]; // N20

    // N40 G18 G98 G81: the drilling axis is Y, the holes are placed in Z X. Initial level
    // Y30, R Y3, bottom Y−12; over each hole at Y30 (moving X and Z), down to R, feed, back.
    for [x, z] in [[10.0, -5.0], [30.0, -5.0], [30.0, -15.0]] {
        want.extend([[x, 30.0, z], [x, 3.0, z], [x, -12.0, z], [x, 30.0, z]]);
    }
    want.extend([[30.0, 30.0, 10.0], [30.0, 20.0, 10.0]]); // N80, N90

    // N100 G19 G99 G83: the drilling axis is X, initial level X30, R X3, bottom X−10: 13 in
    // pecks to 4, 8, 12, 13 (the last 1 < Q) = −1, −5, −9, −10; out to R after each, back to
    // 1 mm above the depth reached: 3 − 4 + 1 = 0, 3 − 8 + 1 = −4, 3 − 12 + 1 = −8.
    let peck = |y: f64| {
        [
            [-1.0, y, -5.0],
            [3.0, y, -5.0],
            [0.0, y, -5.0],
            [-5.0, y, -5.0],
            [3.0, y, -5.0],
            [-4.0, y, -5.0],
            [-9.0, y, -5.0],
            [3.0, y, -5.0],
            [-8.0, y, -5.0],
            [-10.0, y, -5.0],
            [3.0, y, -5.0],
        ]
    };
    want.extend([[30.0, 20.0, -5.0], [3.0, 20.0, -5.0]]); // over the hole at X30, R
    want.extend(peck(20.0));
    want.push([3.0, 40.0, -5.0]); // N110 Y40. at R (G99)
    want.extend(peck(40.0));
    want.extend([[30.0, 40.0, -5.0], [30.0, 40.0, 10.0], [0.0, 0.0, 10.0]]); // N130 … N160
    run_clean(
        "c18_side_drilling_g18_g19_cycles.nc",
        Tape::AsWritten,
        None,
        &want,
        EXACT,
    );
}

#[test]
fn c19_cam_circular_pocket_helical_ramp() {
    let want = [
        [55.0, 40.0, 0.0],   // N40: 5 from the centre (50, 40)
        [55.0, 40.0, 10.0],  // N50
        [55.0, 40.0, 2.0],   // N60
        [55.0, 40.0, 0.5],   // N70
        [55.0, 40.0, -1.5],  // N80 ramp turn: 0.5 − 2
        [55.0, 40.0, -3.0],  // N90 ramp turn: −1.5 − 1.5
        [55.0, 40.0, -3.0],  // N100 flat circle
        [60.0, 40.0, -3.0],  // N110 out to 10 from the centre
        [60.0, 40.0, -3.0],  // N120
        [65.0, 40.0, -3.0],  // N130 out to 15 = 20 − the tool's 5
        [65.0, 40.0, -3.0],  // N140
        [55.0, 50.0, -3.0],  // N150 G3 R10 off the wall
        [50.0, 40.0, -3.0],  // N160
        [50.0, 40.0, 10.0],  // N170
        [50.0, 40.0, 10.0],  // N190 G91 G28 Z0.
        [50.0, 40.0, -80.0], // 0 − H2's 80
    ];
    let file = "c19_cam_circular_pocket_helical_ramp.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // Every ring about (50, 40) (start − I), counter-clockwise; N150: chord (65, 40) → (55,
    // 50), left of it for G3: (60, 45) + (−5, −5) = (55, 40).
    assert_arcs(
        file,
        &arcs(&b),
        &[
            ([50.0, 40.0, 0.5], true),
            ([50.0, 40.0, -1.5], true),
            ([50.0, 40.0, -3.0], true),
            ([50.0, 40.0, -3.0], true),
            ([50.0, 40.0, -3.0], true),
            ([55.0, 40.0, -3.0], true),
        ],
        EXACT,
    );
}

/// A post that retracts with G53 G0 Z0. under G43 (to the tool change height) and parks with
/// G53 X Y. Fanuc 0i-MB operator's manual (B-63844EN/02) 14.1.2, "G53, G28, and G30
/// commands in tool length offset mode": with G53 the length vector of the tool length axis
/// is "canceled upon movement being performed according to a specified value" — the
/// spindle, not the tool tip, goes to the position written, as softnc does for G28 already
/// (and as LinuxCNC's rs274 does). softnc keeps the length in a G53 block: N100 puts the
/// tool tip on machine Z0, the spindle 100 mm above the reference.
#[test]
fn c20_cam_g53_retract_under_g43() {
    // m13's offsets: G54 (100, 50, −20).
    let want = [
        [0.0, 0.0, 0.0],         // N20 G53 Z0. before any length
        [120.0, 70.0, 0.0],      // N50 (20, 20) + (100, 50); Z stays at machine 0
        [120.0, 70.0, -10.0],    // N60 G43 H1 Z10.: 10 − 20
        [120.0, 70.0, -22.0],    // N70 −2 − 20
        [160.0, 70.0, -22.0],    // N80 60 + 100
        [160.0, 70.0, -10.0],    // N90
        [160.0, 70.0, -100.0],   // N100 G53 Z0.: the spindle on 0, the tool tip 0 − H1's 100
        [160.0, 90.0, -100.0],   // N120 (60, 40) + (100, 50)
        [160.0, 90.0, -10.0],    // N130 G43 H2 Z10.
        [160.0, 90.0, -23.0],    // N140 −3 − 20
        [120.0, 90.0, -23.0],    // N150 20 + 100
        [120.0, 90.0, -10.0],    // N160
        [120.0, 90.0, -80.0],    // N170 G53 Z0.: 0 − H2's 80
        [-200.0, -100.0, -80.0], // N180 G53 X Y: no length axis, as written; Z stays
    ];
    run_clean(
        "c20_cam_g53_retract_under_g43.nc",
        Tape::AsWritten,
        Some(OFFSETS),
        &want,
        EXACT,
    );
}

#[test]
fn c21_cam_contour_g41_line_lead() {
    // c06's profile; the lead-in is the G41 line itself, the lead-out the G40 line, so no
    // air move stands among the contour elements that the gouge check compares.
    let want = [
        [40.0, -20.0, 0.0],   // N40
        [40.0, -20.0, 15.0],  // N50
        [40.0, -20.0, 3.0],   // N70
        [40.0, -20.0, -5.0],  // N80
        [40.0, 0.0, -5.0],    // N90 G41 D2
        [0.0, 0.0, -5.0],     // N100
        [0.0, 40.0, -5.0],    // N110
        [10.0, 50.0, -5.0],   // N120 G2 R10
        [60.0, 50.0, -5.0],   // N130
        [80.0, 30.0, -5.0],   // N140 G2 I0 J-20
        [80.0, 0.0, -5.0],    // N150
        [35.0, 0.0, -5.0],    // N160 5 past the start 40
        [35.0, -20.0, -5.0],  // N170 G40
        [35.0, -20.0, 15.0],  // N180
        [35.0, -20.0, 15.0],  // N210 G91 G28 Z0.
        [35.0, -20.0, -80.0], // 0 − H2's 80
    ];
    let file = "c21_cam_contour_g41_line_lead.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    // As in c06: (0, 40) → (10, 50) R10 about (10, 40); (60, 50) + (0, −20).
    assert_arcs(
        file,
        &arcs(&b),
        &[([10.0, 40.0, -5.0], false), ([60.0, 30.0, -5.0], false)],
        EXACT,
    );
    assert_eq!(
        sides(&b),
        [(TrcSide::Off, 0), (TrcSide::Left, 2), (TrcSide::Off, 2)]
    );
}

#[test]
fn c22_g40_exit_vector() {
    // c21's profile in two depth passes, each cancelled by G40 with an exit vector I J.
    let mut want = vec![
        [-20.0, -10.0, 0.0],  // N40
        [-20.0, -10.0, 15.0], // N50
        [-20.0, -10.0, 3.0],  // N70
    ];
    for z in [-5.0, -10.0] {
        want.extend([
            [-20.0, -10.0, z], // N80 / N180
            [0.0, 0.0, z],     // N90 G41 D2
            [0.0, 40.0, z],    // N100
            [10.0, 50.0, z],   // N110 G2 R10
            [60.0, 50.0, z],   // N120
            [80.0, 30.0, z],   // N130 G2 I0 J-20
            [80.0, 0.0, z],    // N140
            [10.0, 0.0, z],    // N150
            [-20.0, -10.0, z], // N160 G40 I J: the vector moves no axis
        ]);
        want.push([-20.0, -10.0, if z == -5.0 { 3.0 } else { 15.0 }]); // N170 / N270
    }
    want.extend([
        [-20.0, -10.0, 15.0],  // N300 G91 G28 Z0.
        [-20.0, -10.0, -80.0], // 0 − H2's 80
    ]);
    let file = "c22_g40_exit_vector.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, EXACT);
    let vectors: Vec<_> = b.iter().filter_map(|b| b.exit_vector.as_deref()).collect();
    assert_eq!(vectors, [&[-10.0, -10.0, 0.0], &[-10.0, 10.0, 0.0]]);
    // The tool centre (D2, R 5): N150 runs west on y = −5. The virtual block leaves (10, 0)
    // along the vector v, its equidistant through (10, 0) + 5·left(v/|v|).
    // N160, I−10 J−10 (a left turn, towards the tool: inner): through
    // (10 + 2.5√2, −2.5√2) along (−1, −1), y = −5 at x = 5 + 5√2 ≈ 12.071, short of the
    // normal position (10, −5).
    // N260, I−10 J10 (a right turn: outer, and still the intersection): through
    // (10 − 2.5√2, −2.5√2) along (−1, 1), y = −5 at x = 15 − 5√2 ≈ 7.929, past it.
    let r2 = std::f64::consts::SQRT_2;
    let path = tool_path(file);
    let seg = |line: u32, role: Role| {
        let s = path.iter().rfind(|s| s.0 == line && s.1 == role);
        *s.unwrap_or_else(|| panic!("{file}: no {role:?} on line {line}: {path:?}"))
    };
    for (line, x) in [(18, 5.0 + 5.0 * r2), (29, 15.0 - 5.0 * r2)] {
        let end = seg(line, Role::Contour).3;
        assert!(
            close([end[0], end[1], 0.0], [x, -5.0, 0.0], EXACT),
            "{file}: line {line} ends at {end:?}, want ({x}, -5)"
        );
        // The cancel block starts there and runs uncompensated to (−20, −10).
        let (_, _, from, to) = seg(line + 1, Role::Retract);
        assert!(from == end && close([to[0], to[1], 0.0], [-20.0, -10.0, 0.0], EXACT));
    }
}

/// The tool-centre path of a corpus program (`Preparation`, as `softnc path`): (line, role,
/// from, to) of every segment.
fn tool_path(file: &str) -> Vec<(u32, Role, P, P)> {
    let (text, md, tools) = (source(file), machine(None), ToolTable::builtin());
    let mut p = Preparation::new(file, &text, &md, &tools);
    let mut out = Vec::new();
    while let Some(s) = p
        .next_segment()
        .unwrap_or_else(|a| panic!("{}", a.render(&text)))
    {
        out.push((s.source.line, s.role, s.from, s.to));
    }
    out
}

#[test]
fn c23_chamfer_corner_r() {
    // A plate 80 × 40 (and the arc over its top left) milled clockwise under G41 with ,C and
    // ,R at its corners (0i-MF "Optional angle chamfering and corner rounding"). Each
    // corner word puts its element between its block's move and the next, and both moves
    // end and start at the element's ends.
    let r5 = 5f64.sqrt();
    let r35 = 35f64.sqrt();
    let want = [
        [40.0, -20.0, 0.0],  // N40
        [40.0, -20.0, 15.0], // N50
        [40.0, -20.0, 3.0],  // N60
        [40.0, -20.0, -5.0], // N70
        [40.0, 0.0, -5.0],   // N80 G41 D2
        [5.0, 0.0, -5.0],    // N90 X0 ,C5: 5 before the corner (0, 0) …
        [0.0, 5.0, -5.0],    // … the chamfer to 5 after it, up the left side
        // N100 Y40 ,R10 into the arc N110 (about (20, 25), radius 25; its tangent at
        // (0, 40) is (0.6, 0.8): a right turn). The R10 centre is 10 right of X0 and
        // 25 − 10 from (20, 25): (10, 25 + √125) = (10, 25 + 5√5).
        [0.0, 25.0 + 5.0 * r5, -5.0], // touches the line at its foot
        // … and the arc 25 from (20, 25) towards the centre: (20, 25) + 25/15·(−10, 5√5).
        [20.0 - 50.0 / 3.0, 25.0 + 25.0 * r5 / 3.0, -5.0],
        // N110 G2 … ,R8 into N120 (along +X: a left turn, concave). The R8 centre is 8
        // above Y40 and 25 + 8 from (20, 25): x = 20 + √(33² − 23²) = 20 + 4√35.
        [20.0 + 100.0 * r35 / 33.0, 25.0 + 575.0 / 33.0, -5.0], // (20, 25) + 25/33·(4√35, 23)
        [20.0 + 4.0 * r35, 40.0, -5.0],                         // its foot on Y40
        [76.0, 40.0, -5.0],                                     // N120 X80 ,C4
        [80.0, 36.0, -5.0],                                     // the chamfer
        [80.0, 6.0, -5.0],                                      // N130 Y0 ,R6: centre (74, 6)
        [74.0, 0.0, -5.0],                                      // the rounding
        [35.0, 0.0, -5.0],                                      // N140
        [35.0, -20.0, -5.0],                                    // N150 G40
        [35.0, -20.0, 15.0],                                    // N160
        [35.0, -20.0, 15.0],                                    // N180 G91 G28 Z0.
        [35.0, -20.0, -80.0],                                   // 0 − H2's 80
    ];
    let file = "c23_chamfer_corner_r.nc";
    let b = run_clean(file, Tape::AsWritten, None, &want, TRIG);
    // The roundings: R10 clockwise (a right turn), the arc N110, R8 counter-clockwise, R6.
    assert_arcs(
        file,
        &arcs(&b),
        &[
            ([10.0, 25.0 + 5.0 * r5, -5.0], false),
            ([20.0, 25.0, -5.0], false),
            ([20.0 + 4.0 * r35, 48.0, -5.0], true),
            ([74.0, 6.0, -5.0], false),
        ],
        TRIG,
    );
    // Each inserted element is a block of the line that asks for it, at that block's feed:
    // N130's F600 from its rounding on.
    let lines: Vec<(u32, f64)> = b
        .iter()
        .filter(|b| b.motion.is_some())
        .map(|b| (b.line, b.modal.feed))
        .collect();
    assert_eq!(
        &lines[5..16],
        &[
            (11, 800.0),
            (11, 800.0),
            (12, 800.0),
            (12, 800.0),
            (13, 800.0),
            (13, 800.0),
            (14, 800.0),
            (14, 800.0),
            (15, 600.0),
            (15, 600.0),
            (16, 600.0),
        ]
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
