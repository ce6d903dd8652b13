//! Bad part programs: every case asserts the alarm number, the line and the column (1-based,
//! counted in characters). The positions are worked out by hand from the program text in each
//! test; the comment above the assertion shows the count.
//!
//! The last tests run the `softnc` binary end to end: exit status, the diagnostic on stderr
//! and machine data errors.

use nc_kernel::{interpret, Alarm, AlarmCode, Block, MachineData, ToolTable};
use nc_kernel::{FeedAdaption, MotionMode};
use std::path::{Path, PathBuf};
use std::process::Command;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// Built-in machine data switched to `dialect`, plus further overrides.
fn md(dialect: &str, extra: &[&str]) -> MachineData {
    let mut ov = vec![format!("dialect={dialect}")];
    ov.extend(extra.iter().map(|s| s.to_string()));
    MachineData::load(None, &ov).expect("machine data")
}

/// The shipped machine data file `config/<name>.toml`.
fn md_file(name: &str) -> MachineData {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("config")
        .join(format!("{name}.toml"));
    MachineData::load(Some(&path), &[]).expect("shipped machine data")
}

fn run(md: &MachineData, src: &str) -> Result<Vec<Block>, Alarm> {
    interpret("test.nc", src, md, &ToolTable::builtin())
}

/// Interprets `src` and returns the alarm it must raise.
fn alarm_with(md: &MachineData, src: &str) -> Alarm {
    match run(md, src) {
        Err(a) => a,
        Ok(blocks) => panic!("expected an alarm, got {} blocks for:\n{src}", blocks.len()),
    }
}

fn alarm(dialect: &str, src: &str) -> Alarm {
    alarm_with(&md(dialect, &[]), src)
}

/// Asserts number, code, line and column of an alarm.
#[track_caller]
fn check(a: &Alarm, code: AlarmCode, number: u32, line: u32, col: u32) {
    assert_eq!(
        code.number(),
        number,
        "test table: {code:?} is not alarm {number}"
    );
    assert_eq!(
        (a.number(), a.line, a.col),
        (number, line, col),
        "wrong alarm or position: {a}"
    );
    assert_eq!(a.code, code, "{a}");
    assert_eq!(a.program, "test.nc");
    assert!(!a.message.is_empty());
}

const C840: &str = "siemens-840c";
const ISG: &str = "isg";
const FANUC: &str = "fanuc";

// ---------------------------------------------------------------------------------------------
// Unknown words, addresses and G codes
// ---------------------------------------------------------------------------------------------

#[test]
fn unknown_address_q_on_840c() {
    // N10 G1 X10 Q5 F100
    // 123456789012
    //            ^ Q at 12
    let a = alarm(C840, "N10 G1 X10 Q5 F100\n");
    check(&a, AlarmCode::UnknownAddress, 12050, 1, 12);
    assert_eq!(a.block.as_deref(), Some("N10"));
    assert!(a.message.contains('Q'), "{a}");
}

#[test]
fn r_radius_word_is_a_parameter_on_840c() {
    // The 840C writes the radius as CR=; R10 there is an R parameter, which needs '='.
    // N20 G2 X10 R10
    // 123456789012
    //            ^ R at 12
    let a = alarm(C840, "N10 G1 X0 Y0 F100\nN20 G2 X10 R10\n");
    check(&a, AlarmCode::Syntax, 12080, 2, 12);
    assert_eq!(a.block.as_deref(), Some("N20"));
    assert!(a.message.contains("CR="), "{a}");
}

#[test]
fn cr_radius_word_is_unknown_on_fanuc() {
    // Fanuc writes the radius as R; `CR=` is a Siemens word, C no Fanuc address.
    // N20 G2 X10. CR=5.
    // 1234567890123
    //             ^ C at 13
    let a = alarm(FANUC, "N10 G1 X0. Y0. F100\nN20 G2 X10. CR=5.\n");
    check(&a, AlarmCode::UnknownAddress, 12050, 2, 13);
}

#[test]
fn g138_is_not_an_840c_code() {
    // G138 (ISG direct selection) does not exist on the 840C.
    // N10 G138
    //     ^ 5
    let a = alarm(C840, "N10 G138\n");
    check(&a, AlarmCode::UnknownGCode, 12470, 1, 5);
    assert!(a.message.contains("G138"), "{a}");
}

#[test]
fn g450_is_not_a_fanuc_code() {
    // N10 G1 X0 F100
    // N20 G450
    //     ^ 5
    let a = alarm(FANUC, "N10 G1 X0 F100\nN20 G450\n");
    check(&a, AlarmCode::UnknownGCode, 12470, 2, 5);
}

#[test]
fn g_code_of_1000_or_more_is_unknown() {
    // N10 G1 G1000
    //        ^ 8
    let a = alarm(ISG, "N10 G1 G1000\n");
    check(&a, AlarmCode::UnknownGCode, 12470, 1, 8);
}

#[test]
fn g10_means_different_things_and_is_fine_on_840c_and_isg() {
    // 840C: polar coordinates, rapid.
    let b = run(&md(C840, &[]), "N10 G10\n").expect("G10 on the 840C");
    assert_eq!(b[0].modal.motion, MotionMode::PolarRapid);
    // ISG: feed adaption at the tool centre; the motion stays as it was.
    let b = run(&md(ISG, &[]), "N10 G11\nN20 G10\n").expect("G10 on the ISG kernel");
    assert_eq!(b[0].modal.feed_adaption, FeedAdaption::Contour);
    assert_eq!(b[1].modal.feed_adaption, FeedAdaption::Centre);
    assert_eq!(b[1].modal.motion, MotionMode::Rapid);
}

// ---------------------------------------------------------------------------------------------
// Bad numbers
// ---------------------------------------------------------------------------------------------

#[test]
fn number_with_two_decimal_points() {
    // `1.2` is read as X's value; the second `.` cannot start a word.
    // N10 G1 X1.2.3 F100
    // 123456789012
    //            ^ second '.' at 12
    let a = alarm(C840, "N10 G1 X1.2.3 F100\n");
    check(&a, AlarmCode::Syntax, 12080, 1, 12);
}

#[test]
fn sign_without_digits() {
    // N10 G1 X- F100
    // 123456789
    //         ^ '-' at 9, where the number should be
    let a = alarm(C840, "N10 G1 X- F100\n");
    check(&a, AlarmCode::BadNumber, 12160, 1, 9);
    assert!(a.message.contains('X'), "{a}");
}

#[test]
fn address_without_value() {
    // N10 G1 X F100
    // 1234567890
    //          ^ the value is missing where F stands (10)
    let a = alarm(C840, "N10 G1 X F100\n");
    check(&a, AlarmCode::BadNumber, 12160, 1, 10);
}

#[test]
fn address_without_value_at_end_of_line() {
    // N10 G1 F100 X
    // 12345678901234
    //              ^ just past the X (14)
    let a = alarm(C840, "N10 G1 F100 X\n");
    check(&a, AlarmCode::BadNumber, 12160, 1, 14);
}

#[test]
fn g_code_with_a_fraction() {
    // N10 G1.5 X1 F100
    //     ^ 5
    // G numbers with a decimal exist (Fanuc G54.1): this one is not in the 840C's table.
    let a = alarm(C840, "N10 G1.5 X1 F100\n");
    check(&a, AlarmCode::UnknownGCode, 12470, 1, 5);
    let a = alarm(C840, "N10 G-1 X1 F100\n");
    check(&a, AlarmCode::BadNumber, 12160, 1, 5);
}

#[test]
fn block_number_too_large() {
    // N99999999999 G1
    // ^ 1
    let a = alarm(C840, "N99999999999 G1\n");
    check(&a, AlarmCode::BadNumber, 12160, 1, 1);
}

#[test]
fn coordinate_out_of_range() {
    // N10 G0 X99999999999999999999
    //        ^ 8
    let a = alarm(C840, "N10 G0 X99999999999999999999\n");
    check(&a, AlarmCode::BadNumber, 12160, 1, 8);
}

// ---------------------------------------------------------------------------------------------
// Circles
// ---------------------------------------------------------------------------------------------

#[test]
fn arc_end_point_off_the_circle() {
    // From (0,0) with centre (5,0): start radius 5, end (10,1) has radius 5.099 > 5 + 0.01.
    // N20 G2 X10 Y1 I5 J0
    // 123456789012345
    //               ^ first centre word I at 15
    let a = alarm(C840, "N10 G1 X0 Y0 F100\nN20 G2 X10 Y1 I5 J0\n");
    check(&a, AlarmCode::ArcEndPoint, 14040, 2, 15);
    assert_eq!(a.block.as_deref(), Some("N20"));
}

#[test]
fn arc_end_point_within_tolerance_is_accepted() {
    // End radius 5.0000025: within arc_endpoint_tolerance = 0.01.
    let b = run(
        &md(C840, &[]),
        "N10 G1 X0 Y0 F100\nN20 G2 X10 Y0.005 I5 J0\n",
    )
    .expect("within tolerance");
    assert!(b[1].motion.is_some());
}

#[test]
fn arc_radius_too_small_for_the_chord() {
    // Chord 20, radius 5.
    // N20 G2 X20 Y0 CR=5
    // 123456789012345
    //               ^ CR at 15
    let a = alarm(C840, "N10 G1 X0 Y0 F100\nN20 G2 X20 Y0 CR=5\n");
    check(&a, AlarmCode::ArcEndPoint, 14040, 2, 15);
}

#[test]
fn arc_radius_too_small_isg_r_word() {
    // N20 G3 X20 R5
    // 12345678901
    //            ^ R at 12
    let a = alarm(ISG, "N10 G1 X0 Y0 F100\nN20 G3 X20 R5\n");
    check(&a, AlarmCode::ArcEndPoint, 14040, 2, 12);
}

// ---------------------------------------------------------------------------------------------
// ISG control structures
// ---------------------------------------------------------------------------------------------

#[test]
fn missing_endfor_is_reported_at_the_for() {
    // N20 $FOR V.P.I = 0,3,1
    //     ^ $ at 5
    let a = alarm(ISG, "N10 G1 X0 F100\nN20 $FOR V.P.I = 0,3,1\nN30 X1\n");
    check(&a, AlarmCode::ControlNesting, 12640, 2, 5);
}

#[test]
fn missing_endfor_of_a_loop_that_never_runs() {
    // The body is skipped (0 > -1), looking for $ENDFOR up to the end of the program.
    // N10 $FOR V.P.I = 0,-1,1
    //     ^ 5
    let a = alarm(ISG, "N10 $FOR V.P.I = 0,-1,1\nN20 G1 X1 F100\n");
    check(&a, AlarmCode::ControlNesting, 12640, 1, 5);
}

#[test]
fn endfor_without_for() {
    // N20 $ENDFOR
    //     ^ 5
    let a = alarm(ISG, "N10 G1 X0 F100\nN20 $ENDFOR\n");
    check(&a, AlarmCode::ControlNesting, 12640, 2, 5);
}

#[test]
fn missing_endif_true_branch() {
    // N10 $IF 1
    //     ^ 5
    let a = alarm(ISG, "N10 $IF 1\nN20 G1 X1 F100\n");
    check(&a, AlarmCode::ControlNesting, 12640, 1, 5);
}

#[test]
fn missing_endif_false_branch() {
    //   N10 $IF 0   (indented by two blanks)
    //       ^ 7
    let a = alarm(ISG, "  N10 $IF 0\nN20 G1 X1 F100\n");
    check(&a, AlarmCode::ControlNesting, 12640, 1, 7);
}

#[test]
fn endfor_closing_an_if() {
    // N20 $ENDFOR
    //     ^ 5
    let a = alarm(ISG, "N10 $IF 1\nN20 $ENDFOR\n");
    check(&a, AlarmCode::ControlNesting, 12640, 2, 5);
    assert!(a.message.contains("$IF"), "{a}");
}

#[test]
fn endless_while_loop_hits_the_iteration_limit() {
    // N30 $ENDWHILE
    //     ^ 5
    let md = MachineData::load(
        None,
        &[
            "dialect=isg".into(),
            "program.max_loop_iterations=1000".into(),
        ],
    )
    .expect("machine data");
    let t = std::time::Instant::now();
    let a = alarm_with(&md, "N10 $WHILE 1\nN20 G1 X1 F100\nN30 $ENDWHILE\n");
    check(&a, AlarmCode::LoopLimit, 12650, 3, 5);
    assert!(
        t.elapsed().as_secs() < 5,
        "the loop limit took {:?}",
        t.elapsed()
    );
}

#[test]
fn endless_for_loop_hits_the_iteration_limit() {
    // The body keeps resetting the counter.
    // N30 $ENDFOR
    //     ^ 5
    let md = MachineData::load(
        None,
        &[
            "dialect=isg".into(),
            "program.max_loop_iterations=1000".into(),
        ],
    )
    .expect("machine data");
    let a = alarm_with(&md, "N10 $FOR V.P.I = 0,3,1\nN20 V.P.I = 0\nN30 $ENDFOR\n");
    check(&a, AlarmCode::LoopLimit, 12650, 3, 5);
}

#[test]
fn alarm_in_a_loop_body_names_the_body_line() {
    // Third pass: V.P.I = 2, division by zero.
    // N20 V.P.X = [1/[V.P.I-2]]
    // 123456789012345
    //               ^ '/' at 15
    let a = alarm(
        ISG,
        "N10 $FOR V.P.I = 0,3,1\nN20 V.P.X = [1/[V.P.I-2]]\nN30 $ENDFOR\n",
    );
    check(&a, AlarmCode::Arithmetic, 14000, 2, 15);
}

#[test]
fn elseif_condition_alarm_names_its_own_block() {
    // The condition of $ELSEIF is read when the $IF branch is skipped; the alarm belongs to
    // the $ELSEIF block (N20), not to the $IF (N10).
    // N20 $ELSEIF [1/0]
    // 123456789012345
    //               ^ '/' at 15
    let a = alarm(ISG, "N10 $IF 0\nN20 $ELSEIF [1/0]\nN30 $ENDIF\n");
    check(&a, AlarmCode::Arithmetic, 14000, 2, 15);
    assert_eq!(a.block.as_deref(), Some("N20"), "{a}");
}

#[test]
fn lines_are_counted_through_a_skipped_if() {
    // N40 Q2
    //     ^ 5
    let a = alarm(ISG, "N10 $IF 0\nN20 Q1\nN30 $ENDIF\nN40 Q2\n");
    check(&a, AlarmCode::UnknownAddress, 12050, 4, 5);
}

// ---------------------------------------------------------------------------------------------
// Tool radius compensation
// ---------------------------------------------------------------------------------------------

#[test]
fn fanuc_trc_selection_in_a_circle_is_alarm_026() {
    // N20 G41 G2 X10. R5. F100
    //     ^ G41 at 5
    let a = alarm(FANUC, "N10 G0 X0 Y0 D1\nN20 G41 G2 X10. R5. F100\n");
    check(&a, AlarmCode::FanucTrcNotLinear, 26, 2, 5);
    assert!(a.to_string().contains("alarm 026:"), "{a}");
}

#[test]
fn c840_trc_selection_in_a_circle_is_alarm_10751() {
    // N20 G41 G2 X10 CR=5 F100
    //     ^ 5
    let a = alarm(C840, "N10 G0 X0 Y0 D1\nN20 G41 G2 X10 CR=5 F100\n");
    check(&a, AlarmCode::TrcSelectionNotLinear, 10751, 2, 5);
}

const TRC_ON: &str = "N10 G0 X0 Y0 D1\nN20 G41 G1 X10 F100\n";

#[test]
fn plane_change_with_trc_on_fanuc() {
    // N30 G18
    //     ^ 5
    let a = alarm(FANUC, &format!("{TRC_ON}N30 G18\n"));
    check(&a, AlarmCode::PlaneChangeWithTrc, 10755, 3, 5);
}

#[test]
fn plane_change_with_trc_on_isg() {
    // N30 G19
    //     ^ 5
    let a = alarm(ISG, &format!("{TRC_ON}N30 G19\n"));
    check(&a, AlarmCode::PlaneChangeWithTrc, 10755, 3, 5);
}

#[test]
fn plane_change_with_trc_on_840c() {
    // An actual plane change is alarm 10755 on every dialect; the 840C additionally refuses a
    // plane code that keeps the plane (10754, test below).
    // N30 G18
    //     ^ 5
    let a = alarm(C840, &format!("{TRC_ON}N30 G18\n"));
    check(&a, AlarmCode::PlaneChangeWithTrc, 10755, 3, 5);
}

#[test]
fn fanuc_same_plane_code_with_trc_is_fine() {
    let b = run(&md(FANUC, &[]), &format!("{TRC_ON}N30 G17 X20\n")).expect("G17 in the XY plane");
    assert_eq!(b.len(), 3);
}

#[test]
fn c840_g17_with_trc_even_in_the_same_plane() {
    // N30 G17 X20
    //     ^ 5
    let a = alarm(C840, &format!("{TRC_ON}N30 G17 X20\n"));
    check(&a, AlarmCode::ForbiddenWithTrc, 10754, 3, 5);
}

#[test]
fn c840_g54_with_trc() {
    // N30 G54 X20
    //     ^ 5
    let a = alarm(C840, &format!("{TRC_ON}N30 G54 X20\n"));
    check(&a, AlarmCode::ForbiddenWithTrc, 10754, 3, 5);
}

#[test]
fn c840_g25_with_trc() {
    // N30 G25 X-100
    //     ^ 5
    let a = alarm(C840, &format!("{TRC_ON}N30 G25 X-100\n"));
    check(&a, AlarmCode::ForbiddenWithTrc, 10754, 3, 5);
}

#[test]
fn c840_at714_with_trc() {
    // N30 X20 @714
    // 123456789
    //         ^ @ at 9
    let a = alarm(C840, &format!("{TRC_ON}N30 X20 @714\n"));
    check(&a, AlarmCode::ForbiddenWithTrc, 10754, 3, 9);
}

#[test]
fn unknown_d_offset() {
    // N10 G0 X0 Y0 D9
    // 1234567890123
    //              ^ D at 14
    let a = alarm(C840, "N10 G0 X0 Y0 D9\n");
    check(&a, AlarmCode::UnknownOffset, 17180, 1, 14);
    assert!(a.message.contains("D9"), "{a}");
}

#[test]
fn unknown_t_d_offset_on_808d() {
    // T1 has D1 and D2 only.
    // N10 T1 D3
    //        ^ 8
    let a = alarm_with(&md_file("siemens-808d"), "N10 T1 D3\n");
    check(&a, AlarmCode::UnknownOffset, 17180, 1, 8);
    assert!(a.message.contains("T1 D3"), "{a}");
}

// ---------------------------------------------------------------------------------------------
// Block structure
// ---------------------------------------------------------------------------------------------

#[test]
fn feed_motion_without_f() {
    // The alarm points at the start of the block.
    let a = alarm(C840, "N10 G1 X10\n");
    check(&a, AlarmCode::NoFeed, 10860, 1, 1);
    //   G2 X10 Y0 I5 (no N word, indented by one blank)
    //  ^ 2
    let a = alarm(C840, " G2 X10 Y0 I5\n");
    check(&a, AlarmCode::NoFeed, 10860, 1, 2);
}

#[test]
fn same_address_twice() {
    // N10 G1 X1 X2 F100
    // 12345678901
    //           ^ second X at 11
    let a = alarm(C840, "N10 G1 X1 X2 F100\n");
    check(&a, AlarmCode::AddressTwice, 12040, 1, 11);
}

#[test]
fn two_g_codes_of_one_group() {
    // N10 G0 G1 X1 F100
    //        ^ G1 at 8
    let a = alarm(C840, "N10 G0 G1 X1 F100\n");
    check(&a, AlarmCode::SameGroupTwice, 12060, 1, 8);
}

#[test]
fn unterminated_comment_840c() {
    // N10 G1 X1 F100 (comment
    // 12345678901234567
    //                ^ '(' at 16
    let a = alarm(C840, "N10 G1 X1 F100 (comment\nN20 X2\n");
    check(&a, AlarmCode::Syntax, 12080, 1, 16);
}

#[test]
fn unterminated_comment_808d() {
    // N10 G1 X1 F100 (a (nested) comment
    //                ^ 16
    let a = alarm_with(
        &md_file("siemens-808d"),
        "N10 G1 X1 F100 (a (nested) comment\n",
    );
    check(&a, AlarmCode::Syntax, 12080, 1, 16);
}

#[test]
fn words_after_lf_on_840c() {
    // N10 G1 X1 F100 LF X2
    // 1234567890123456789
    //                   ^ X at 19
    let a = alarm(C840, "N10 G1 X1 F100 LF X2\n");
    check(&a, AlarmCode::Syntax, 12080, 1, 19);
    // A comment after LF is fine.
    run(&md(C840, &[]), "N10 G1 X1 F100 LF (done) ; and more\n").expect("comment after LF");
}

#[test]
fn block_number_not_first() {
    // G1 N10 X1
    //    ^ 4
    let a = alarm(C840, "G1 N10 X1\n");
    check(&a, AlarmCode::Syntax, 12080, 1, 4);
}

#[test]
fn fanuc_semicolon_ends_a_block_within_a_line() {
    // Two blocks on one line; the column is counted from the start of the line.
    // G0 X0;G1 X1 X2;
    // 1234567890123
    //             ^ second X of the second block at 13
    let a = alarm(FANUC, "G0 X0;G1 X1 X2;\n");
    check(&a, AlarmCode::AddressTwice, 12040, 1, 13);
}

#[test]
fn column_counts_characters_not_bytes() {
    // `ä` is two bytes in UTF-8 but one column.
    // N10 (Fräsen) G1 X1 F100 Q5
    // 1234567890123456789012345
    //                         ^ Q at 25 (byte offset 25, i.e. column 26 if bytes were counted)
    let a = alarm(C840, "N10 (Fräsen) G1 X1 F100 Q5\n");
    check(&a, AlarmCode::UnknownAddress, 12050, 1, 25);
}

#[test]
fn unconfigured_axis_on_the_808d_lathe() {
    // The lathe has X and Z only.
    // N10 G1 Y5 F100
    //        ^ Y at 8
    let a = alarm_with(&md_file("siemens-808d"), "N10 G1 Y5 F100\n");
    check(&a, AlarmCode::UnknownAddress, 12050, 1, 8);
}

// ---------------------------------------------------------------------------------------------
// ISG expressions
// ---------------------------------------------------------------------------------------------

#[test]
fn isg_division_by_zero() {
    // N10 V.P.A = [1/0]
    // 123456789012345
    //               ^ '/' at 15
    let a = alarm(ISG, "N10 V.P.A = [1/0]\n");
    check(&a, AlarmCode::Arithmetic, 14000, 1, 15);
}

#[test]
fn isg_division_by_zero_in_an_axis_word() {
    // N20 G1 X[10/[V.P.A-4]] F100
    // 123456789012
    //            ^ '/' at 12
    let a = alarm(ISG, "N10 V.P.A = 4\nN20 G1 X[10/[V.P.A-4]] F100\n");
    check(&a, AlarmCode::Arithmetic, 14000, 2, 12);
}

#[test]
fn isg_undefined_variable_read() {
    // N10 G1 X[V.P.NOPE*2] F100
    // 1234567890
    //          ^ V at 10
    let a = alarm(ISG, "N10 G1 X[V.P.NOPE*2] F100\n");
    check(&a, AlarmCode::UndefinedName, 12550, 1, 10);
    assert!(a.message.contains("V.P.NOPE"), "{a}");
}

#[test]
fn isg_overflowing_product_is_an_arithmetic_alarm() {
    // 10**200 * 10**200 is not a finite number; `**` alone already reports that.
    // N10 V.P.A = [10**200 * 10**200]
    // 1234567890123456789012
    //                      ^ '*' at 22
    let a = alarm(
        ISG,
        "N10 V.P.A = [10**200 * 10**200]\nN20 G2 X0 Y0 I[V.P.A] F100\n",
    );
    check(&a, AlarmCode::Arithmetic, 14000, 1, 22);
}

// ---------------------------------------------------------------------------------------------
// Values that must not reach block preparation
// ---------------------------------------------------------------------------------------------

#[test]
fn at_command_number_is_not_truncated() {
    // @66250 is not @714 (66250 = 65536 + 714).
    // N10 @66250
    //     ^ 5
    let a = alarm(C840, "N10 @66250\n");
    check(&a, AlarmCode::NotSupported, 12580, 1, 5);
}

#[test]
fn polar_pole_out_of_range() {
    // The same range check as for a Cartesian end point.
    // N10 G10 X99999999999999999999 Y0 A0
    // 123456789
    //         ^ X at 9
    let a = alarm(C840, "N10 G10 X99999999999999999999 Y0 A0\n");
    check(&a, AlarmCode::BadNumber, 12160, 1, 9);
}

#[test]
fn circle_radius_too_large_gives_no_nan_centre() {
    // CR= with 308 digits: the centre must not become NaN or infinite. Either the value is
    // refused as out of range at the CR word (column 15) ...
    let src = format!("N10 G1 X0 Y0 F100\nN20 G2 X10 Y0 CR={}\n", "9".repeat(308));
    match run(&md(C840, &[]), &src) {
        Err(a) => check(&a, AlarmCode::BadNumber, 12160, 2, 15),
        // ... or the circle is computed with a finite centre.
        Ok(b) => {
            let m = b[1].motion.expect("motion");
            assert!(
                m.center.iter().all(|v| v.is_finite()),
                "centre {:?}",
                m.center
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The command line, end to end
// ---------------------------------------------------------------------------------------------

fn tmp_file(name: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("alarms");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn softnc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_softnc"))
        .args(args)
        .output()
        .expect("run softnc")
}

#[test]
fn cli_arc_alarm_exit_1_with_caret() {
    let prog = tmp_file(
        "arc_off.nc",
        "N10 G1 X0 Y0 F100\nN20 G2 X10 Y1 I5 J0\nN30 M30\n",
    );
    let path = prog.to_str().unwrap();
    let out = softnc(&["parse", path]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr:\n{stderr}");
    let head = format!("{path}:2:15: alarm 14040:");
    assert!(
        stderr.starts_with(&head),
        "stderr does not start with `{head}`:\n{stderr}"
    );
    assert!(stderr.lines().next().unwrap().contains("N20: "), "{stderr}");
    // The source line and a caret under column 15.
    assert!(
        stderr.lines().any(|l| l == "2 | N20 G2 X10 Y1 I5 J0"),
        "{stderr}"
    );
    let caret = format!("  | {}^", " ".repeat(14));
    assert!(
        stderr.lines().any(|l| l == caret),
        "no caret line `{caret}`:\n{stderr}"
    );
    // The block before the alarm was written.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
}

#[test]
fn cli_bad_md_override_exit_2_names_the_key() {
    let prog = tmp_file("ok1.nc", "N10 G1 X1 F100\n");
    let out = softnc(&[
        "parse",
        prog.to_str().unwrap(),
        "--md",
        "trc.max_blocks_outside_plane=0",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr:\n{stderr}");
    assert!(stderr.contains("trc.max_blocks_outside_plane"), "{stderr}");
    assert!(out.stdout.is_empty());

    let out = softnc(&[
        "parse",
        prog.to_str().unwrap(),
        "--md",
        "program.no_such_key=1",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr:\n{stderr}");
    assert!(stderr.contains("program.no_such_key"), "{stderr}");
}

#[test]
fn cli_unknown_key_in_machine_file_exit_2_names_file_and_key() {
    let prog = tmp_file("ok2.nc", "N10 G1 X1 F100\n");
    let machine = tmp_file(
        "bad-machine.toml",
        "dialect = \"isg\"\n[trc]\ncolour = \"red\"\n",
    );
    let out = softnc(&[
        "parse",
        prog.to_str().unwrap(),
        "--machine",
        machine.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr:\n{stderr}");
    assert!(
        stderr.contains(machine.to_str().unwrap()),
        "file not named:\n{stderr}"
    );
    assert!(stderr.contains("trc.colour"), "key not named:\n{stderr}");
    assert!(out.stdout.is_empty());
}
