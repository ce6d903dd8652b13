//! Fanuc-style lathe (0i-TF, G-code system A): X is a diameter, U and W are the incremental
//! words of X and Z (there is no G90/G91), G98/G99 are feed per minute / per revolution,
//! G50 sets the coordinate system and, with S, the spindle speed limit, and T aabb selects
//! tool aa with offset bb. Custom Macro B and the subprograms are the milling control's.

use super::{g, Dialect, DwellWords, GCodeDef, GEffect, RadiusWord, Semicolon};
use crate::alarm::AlarmCode;
use crate::frontend::block::{BoxCycle, CornerPolicy, MotionMode, Plane, SelectionPolicy, TrcSide};
use crate::machine_data::{DialectName, Units};

use GEffect::*;

static GCODES: &[GCodeDef] = &[
    g(0, Motion(MotionMode::Rapid)),
    g(1, Motion(MotionMode::Linear)),
    g(2, Motion(MotionMode::ArcCw)),
    g(3, Motion(MotionMode::ArcCcw)),
    g(4, Dwell),
    g(9, ExactStopBlock),
    g(17, Plane(Plane::XY)),
    g(18, Plane(Plane::ZX)),
    g(19, Plane(Plane::YZ)),
    g(20, Units(Units::Inch)),
    g(21, Units(Units::Mm)),
    g(28, ReferenceReturn(false)),
    g(30, ReferenceReturn(true)),
    g(32, Motion(MotionMode::Thread)),
    g(40, Trc(TrcSide::Off)),
    g(41, Trc(TrcSide::Left)),
    g(42, Trc(TrcSide::Right)),
    g(50, PositionSetting),
    g(52, LocalCoordinates),
    g(53, MachineCoordinates),
    g(54, WorkOffset(1)),
    g(55, WorkOffset(2)),
    g(56, WorkOffset(3)),
    g(57, WorkOffset(4)),
    g(58, WorkOffset(5)),
    g(59, WorkOffset(6)),
    g(61, ExactStopModal(true)),
    g(64, ExactStopModal(false)),
    g(65, MacroCall),
    g(66, ModalMacroCall),
    g(67, ModalMacroCancel),
    g(70, TurningCycle(super::TurningCycle::Finishing)),
    g(71, TurningCycle(super::TurningCycle::StockRemoval)),
    g(72, TurningCycle(super::TurningCycle::Facing)),
    g(73, TurningCycle(super::TurningCycle::PatternRepeating)),
    g(74, LatheCycle(super::LatheCycle::FacePecking)),
    g(75, LatheCycle(super::LatheCycle::Grooving)),
    g(76, LatheCycle(super::LatheCycle::Threading)),
    g(90, Motion(MotionMode::BoxCycle(BoxCycle::Turning))),
    g(92, Motion(MotionMode::BoxCycle(BoxCycle::Threading))),
    g(94, Motion(MotionMode::BoxCycle(BoxCycle::Facing))),
    g(96, ConstantSurfaceSpeed(true)),
    g(97, ConstantSurfaceSpeed(false)),
    g(98, FeedPerRevolution(false)),
    g(99, FeedPerRevolution(true)),
];

pub static DIALECT: Dialect = Dialect {
    name: DialectName::FanucLathe,
    gcodes: GCODES,
    mcodes: super::fanuc::MCODES,
    semicolon: Semicolon::EndOfBlock,
    radius_word: RadiusWord::R,
    lf_block_end: false,
    variables: false,
    at_commands: &[],
    at_language: false,
    main_block_colon: false,
    corner_words: super::fanuc::CORNER_WORDS,
    named_codes: &[],
    polar_words: false,
    lims_word: false,
    diameter_words: false,
    o_numbers: true,
    helix_turns: 0,
    macro_b: true,
    sinumerik: false,
    l_calls: false,
    // Fifteen calls open at once (0i-F; docs/fanuc.md).
    program_levels: 16,
    incremental_words: true,
    t_selects_offset: true,
    decimal_switch: true,
    initial_work_offset: 1,
    numbered_work_offsets: 0,
    length_offset: super::LengthOffset::WithD,
    tool_edges: true,
    dwell: DwellWords {
        x_seconds: true,
        f_seconds: false,
        p_millis: true,
        bare_seconds: false,
        s_revolutions: false,
    },
    trc_not_linear: AlarmCode::FanucTrcNotLinear,
    trc_codes_need_linear_mode: true,
    d0_deselects: false,
    initial_motion: MotionMode::Linear,
    initial_corner_intersection: CornerPolicy::ExtendedIntersection,
    initial_selection: SelectionPolicy::OffsetVector,
    trc: super::fanuc::TRC,
};

#[cfg(test)]
mod tests {
    use crate::alarm::AlarmCode;
    use crate::frontend::{interpret, Block};
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    fn lathe(src: &str) -> Result<Vec<Block>, crate::alarm::Alarm> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-lathe.toml");
        let md = MachineData::load(Some(std::path::Path::new(path)), &[]).unwrap();
        interpret("l.nc", src, &md, &ToolTable::builtin())
    }

    /// (X as a radius, Z) of every move's end.
    fn ends(src: &str) -> Vec<(f64, f64)> {
        lathe(src)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[2])))
            .collect()
    }

    #[test]
    fn x_is_a_diameter_and_u_w_are_incremental() {
        // X30 is radius 15; U-4 takes 2 off the radius; W-5 goes 5 along Z.
        let e = ends("G0 X30. Z2.\nG1 Z-10. F0.2\nU-4. W-5.\nX40.\n");
        assert_eq!(
            e,
            [(15.0, 2.0), (15.0, -10.0), (13.0, -15.0), (20.0, -15.0)]
        );
        let a = lathe("G0 X30. U2.\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::AddressTwice, 9));
    }

    #[test]
    fn t_selects_tool_and_offset_and_g98_g99_set_the_feed_mode() {
        let b = lathe("T0101\nG99 G1 X10. F0.2\nT0100\nG98 G1 X12. F100.\n").unwrap();
        // T1 D1 of the table: the 0.8 mm nose in edge position 3.
        assert_eq!(
            (b[0].modal.tool, b[0].modal.d, b[0].modal.radius),
            (Some(1), 1, 0.8)
        );
        assert_eq!(b[0].modal.edge, 3);
        assert!(b[1].modal.feed_per_rev);
        // T0100: tool 1 without its offset.
        assert_eq!((b[2].modal.d, b[2].modal.radius), (0, 0.0));
        assert!(!b[3].modal.feed_per_rev);
    }

    #[test]
    fn position_variables_read_x_as_a_diameter() {
        // #5001 after X40 is 40 (the diameter), so X#1 stays at radius 20.
        let e = ends("G0 X40. Z2.\n#1=#5001\nG0 X#1 Z5.\n");
        assert_eq!(e, [(20.0, 2.0), (20.0, 5.0)]);
    }

    #[test]
    fn g50_sets_the_position_and_the_speed_limit() {
        // G50 X100 at X radius 20: the zero moves so that here reads diameter 100.
        let b = lathe("G0 X40. Z0.\nG50 X100. Z10. S2000\nG0 X90. Z5.\n").unwrap();
        assert_eq!(b[1].modal.spindle_limit, 2000.0);
        let m = b[2].motion.unwrap();
        // X90 is 5 radius below the 50 that reads here; Z5 is 5 below the Z10 here.
        assert_eq!((m.end[0], m.end[2]), (15.0, -5.0));
    }
}
