//! Front-end rules checked with hand-computed values: comments, zero offsets, polar
//! coordinates, Fanuc decimal input for dwell times.

use nc_kernel::{interpret, AlarmCode, Block, MachineData, ToolTable, WorkOffsets};

fn run(md: &[&str], src: &str) -> Result<Vec<Block>, nc_kernel::Alarm> {
    let md: Vec<String> = md.iter().map(|s| s.to_string()).collect();
    let md = MachineData::load(None, &md).expect("machine data");
    interpret("rules.nc", src, &md, &ToolTable::builtin())
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-9)
}

#[test]
fn a_line_with_only_a_comment_is_no_block() {
    let b = run(
        &[],
        "(only a comment)\n; and another\nN10 G0 X1 (with comment)\n",
    )
    .unwrap();
    assert_eq!(b.len(), 1);
    assert_eq!(b[0].line, 3);
}

#[test]
fn centre_words_in_a_linear_block_are_an_alarm() {
    // N10 G1 X10 I5 F100: I at column 12.
    let a = run(&[], "N10 G1 X10 I5 F100\n").unwrap_err();
    assert_eq!((a.code, a.line, a.col), (AlarmCode::Syntax, 1, 12), "{a}");
}

#[test]
fn zero_offset_shifts_absolute_coordinates() {
    // G54 = (100, 50, -20): X10 Y5 Z0 lands at (110, 55, -20); G91 X1 then moves by 1.
    let mut md = MachineData::default();
    md.work_offsets =
        WorkOffsets::from_toml_str("[G54]\nX = 100\nY = 50.0\nZ = -20\n", "w.toml", &md).unwrap();
    let b = interpret(
        "rules.nc",
        "G54 G0 X10 Y5 Z0\nG91 X1\nG90 G53 X10\nX20\n",
        &md,
        &ToolTable::builtin(),
    )
    .unwrap();
    assert!(close(b[0].motion.unwrap().end, [110.0, 55.0, -20.0]));
    assert!(close(b[1].motion.unwrap().end, [111.0, 55.0, -20.0]));
    // G53 (840C: the zero offset suppressed in its block): X10 is X10 in the basic system;
    // the next block is in G54 again.
    assert!(close(b[2].motion.unwrap().end, [10.0, 55.0, -20.0]));
    assert!(close(b[3].motion.unwrap().end, [120.0, 55.0, -20.0]));
}

#[test]
fn polar_coordinates_840c() {
    // Pole at (20, 10); radius 10 at 90° → (20, 20); then G91 A-90 keeps radius 10 → (30, 10);
    // then G13 (counter-clockwise about the pole) to A180 → (10, 10), centre (20, 10).
    let b = run(
        &[],
        "N5 G1 F100\nN10 G11 X20 Y10 A90 U10\nN20 G91 A-90\nN30 G90 G13 A180\n",
    )
    .unwrap();
    let m1 = b[1].motion.unwrap();
    assert!(close(m1.end, [20.0, 20.0, 0.0]), "{:?}", m1.end);
    let m2 = b[2].motion.unwrap();
    assert!(close(m2.end, [30.0, 10.0, 0.0]), "{:?}", m2.end);
    let m3 = b[3].motion.unwrap();
    assert!(close(m3.end, [10.0, 10.0, 0.0]), "{:?}", m3.end);
    assert!(close(m3.center, [20.0, 10.0, 0.0]));
}

#[test]
fn fanuc_dwell_without_decimal_point_is_in_milliseconds() {
    // Increment input (config/fanuc.toml): G04 X1000 = 1000 × 0.001 s; X2.5 = 2.5 s; P500 = 0.5 s.
    let md = ["dialect=fanuc", "program.decimal_input=\"increment\""];
    let b = run(&md, "G04 X1000;\nG04 X2.5;\nG04 P500;\n").unwrap();
    let d: Vec<f64> = b.iter().map(|b| b.dwell.unwrap()).collect();
    assert_eq!(d, vec![1.0, 2.5, 0.5]);
}

#[test]
fn inch_programs_are_converted_to_mm() {
    // G70 X1 Y-0.5 F10 → (25.4, -12.7) mm at 254 mm/min.
    let b = run(&[], "G70 G1 X1 Y-0.5 F10\n").unwrap();
    assert!(close(b[0].motion.unwrap().end, [25.4, -12.7, 0.0]));
    assert_eq!(b[0].modal.feed, 254.0);
}

#[test]
fn nested_loops_share_one_pass_budget() {
    // Three nested 100-pass loops would run 10^6 blocks; with a budget of 1000 passes over the
    // whole program the alarm comes long before that.
    let src = "$FOR V.P.A = 0,99,1\n$FOR V.P.B = 0,99,1\n$FOR V.P.C = 0,99,1\nG0 X1\n$ENDFOR\n$ENDFOR\n$ENDFOR\n";
    let a = run(&["dialect=isg", "program.max_loop_iterations=1000"], src).unwrap_err();
    assert_eq!(a.code, AlarmCode::LoopLimit, "{a}");
}
