//! SINUMERIK 840C (seed 000; polar coordinates as in the 880/840C programming guide 4.2.5).

use super::{
    g, g_no_trc, m, AtCommandDef, AtEffect, AtFunction, Compare, Dialect, DwellWords, GCodeDef,
    GEffect, MCodeDef, MEffect, RadiusWord, Semicolon,
};
use crate::alarm::AlarmCode;
use crate::frontend::block::{
    CornerPolicy, Distance, MotionMode, Plane, ProgramStop, SelectionPolicy, SpindleDir, TrcSide,
};
use crate::machine_data::{DialectName, Units};
use crate::trc::{ArmedArc, NoPlaneMove, RadiusChange, RepeatRule, SideChange, TrcRules};

use GEffect::*;
use MEffect::*;

/// 840C G451: beyond this change of direction the tangent extension is cut off and three
/// intermediate blocks are inserted. The excerpt gives no number; 150° keeps the two blocks
/// the 11.10 figure shows at its 135° corner (docs/trc.md).
pub const INTERSECTION_CAP_DEG: f64 = 150.0;

static GCODES: &[GCodeDef] = &[
    g(0, Motion(MotionMode::Rapid)),
    g(1, Motion(MotionMode::Linear)),
    g(2, Motion(MotionMode::ArcCw)),
    g(3, Motion(MotionMode::ArcCcw)),
    g(4, Dwell),
    g(9, ExactStopBlock),
    // 880/840C polar coordinates (TRC may be selected in G10/G11 blocks, 11.3 and 11.5).
    g(10, Motion(MotionMode::PolarRapid)),
    g(11, Motion(MotionMode::PolarLinear)),
    g(12, Motion(MotionMode::PolarCw)),
    g(13, Motion(MotionMode::PolarCcw)),
    g_no_trc(16, Unsupported("free plane selection G16")),
    g_no_trc(17, Plane(Plane::XY)),
    g_no_trc(18, Plane(Plane::ZX)),
    g_no_trc(19, Plane(Plane::YZ)),
    // Working area limitation (min / max), not with TRC (11.4); G26's S is the spindle speed
    // limit (880 program key: "Maximum working area limitation/spindle speed limitation S").
    g_no_trc(25, WorkingArea { max: false }),
    g_no_trc(26, WorkingArea { max: true }),
    g(40, Trc(TrcSide::Off)),
    g(41, Trc(TrcSide::Left)),
    g(42, Trc(TrcSide::Right)),
    g(53, MachineCoordinates),
    g_no_trc(54, WorkOffset(1)),
    g_no_trc(55, WorkOffset(2)),
    g_no_trc(56, WorkOffset(3)),
    g_no_trc(57, WorkOffset(4)),
    g_no_trc(58, Unsupported("programmable zero offset G58")),
    g_no_trc(59, Unsupported("programmable zero offset G59")),
    g(60, ExactStopModal(true)),
    g(64, ExactStopModal(false)),
    g(70, Units(Units::Inch)),
    g(71, Units(Units::Mm)),
    g_no_trc(74, Unsupported("reference point approach G74")),
    g(90, Distance(Distance::Absolute)),
    g(91, Distance(Distance::Incremental)),
    g(94, FeedPerRevolution(false)),
    g(95, FeedPerRevolution(true)),
    g(96, ConstantSurfaceSpeed(true)),
    g(97, ConstantSurfaceSpeed(false)),
    // With S, the spindle speed limit under G96; not with TRC (11.4).
    g_no_trc(92, SpindleLimit),
    g(110, PoleHere),
    g(111, Unsupported("polar programming G111")),
    g(450, Corner(CornerPolicy::TransitionCircle)),
    g(451, Corner(CornerPolicy::Intersection)),
    g(455, Approach(SelectionPolicy::Compensated)),
    g(456, Approach(SelectionPolicy::NormalPosition)),
];

static MCODES: &[MCodeDef] = &[
    m(0, Stop(ProgramStop::Stop)),
    m(1, Stop(ProgramStop::OptionalStop)),
    m(3, Spindle(SpindleDir::Clockwise)),
    m(4, Spindle(SpindleDir::CounterClockwise)),
    m(5, Spindle(SpindleDir::Stop)),
    m(19, Spindle(SpindleDir::Orient)),
    // End of subprogram (Fundamentals, "Program end"; 840C [unconfirmed]).
    m(17, SubprogramEnd),
    m(2, Stop(ProgramStop::End)),
    // 11.10 lists M18 with M00/M01/M02/M30: a programmed stop at block end.
    m(18, Stop(ProgramStop::StopAtEnd)),
    m(30, Stop(ProgramStop::EndRewind)),
];

/// A row of the @ table that TRC allows.
const fn at(code: u32, effect: AtEffect) -> AtCommandDef {
    AtCommandDef {
        code,
        effect,
        forbidden_with_trc: false,
    }
}

/// The @ commands (docs/sinumerik.md, "The 840C's R parameters and @ commands"). 11.4 lists
/// @714 among the functions TRC forbids; its meaning, "stop decoding until the buffer is
/// empty", is unconfirmed. The codes with operands and their forms follow Beckhoff's
/// emulation of the 880/840C scheme (TwinCAT NC I "@-command overview"); the 840C guide's own
/// tables were not found (docs/research/sinumerik-language.md §13).
static AT_COMMANDS: &[AtCommandDef] = &[
    AtCommandDef {
        code: 714,
        effect: AtEffect::PreprocessStop,
        forbidden_with_trc: true,
    },
    at(100, AtEffect::Jump),
    at(111, AtEffect::Case),
    at(121, AtEffect::JumpIf(Compare::NotEqual)),
    at(122, AtEffect::JumpIf(Compare::Equal)),
    at(123, AtEffect::JumpIf(Compare::LessOrEqual)),
    at(124, AtEffect::JumpIf(Compare::Less)),
    at(125, AtEffect::JumpIf(Compare::GreaterOrEqual)),
    at(126, AtEffect::JumpIf(Compare::Greater)),
    at(610, AtEffect::Function(AtFunction::Abs)),
    at(613, AtEffect::Function(AtFunction::Sqrt)),
    at(614, AtEffect::Function(AtFunction::Hypot)),
    at(620, AtEffect::Function(AtFunction::Increment)),
    at(621, AtEffect::Function(AtFunction::Decrement)),
    at(622, AtEffect::Function(AtFunction::IntegerPart)),
    at(630, AtEffect::Function(AtFunction::Sin)),
    at(631, AtEffect::Function(AtFunction::Cos)),
];

pub static DIALECT: Dialect = Dialect {
    name: DialectName::Siemens840C,
    gcodes: GCODES,
    mcodes: MCODES,
    semicolon: Semicolon::Comment,
    radius_word: RadiusWord::CrEquals,
    lf_block_end: true,
    variables: false,
    at_commands: AT_COMMANDS,
    at_language: true,
    main_block_colon: true,
    corner_words: &[],
    named_codes: &[],
    polar_words: true,
    lims_word: false,
    diameter_words: false,
    o_numbers: false,
    helix_turns: 0,
    macro_b: false,
    sinumerik: false,
    l_calls: true,
    // 840C: the 808D's eight program levels [unconfirmed] (docs/sinumerik.md, "Subprograms").
    program_levels: 8,
    incremental_words: false,
    t_selects_offset: false,
    decimal_switch: false,
    initial_work_offset: 0,
    numbered_work_offsets: 0,
    length_offset: super::LengthOffset::WithD,
    tool_edges: false,
    dwell: DwellWords {
        x_seconds: true,
        f_seconds: true,
        p_millis: false,
        bare_seconds: false,
        s_revolutions: false,
    },
    trc_not_linear: AlarmCode::TrcSelectionNotLinear,
    trc_codes_need_linear_mode: false,
    d0_deselects: true,
    initial_motion: MotionMode::Rapid,
    initial_corner_intersection: CornerPolicy::Intersection,
    initial_selection: SelectionPolicy::Compensated,
    trc: TrcRules {
        repeat: RepeatRule::IgnoreWithoutApproach,
        side_change: SideChange::Reselect(Some(SelectionPolicy::NormalPosition)),
        radius_change: RadiusChange::InBlockLinear,
        armed_arc: ArmedArc::Alarm(AlarmCode::TrcSelectionNotLinear),
        no_plane_move: NoPlaneMove::Wait,
        not_linear: AlarmCode::TrcSelectionNotLinear,
        intersection_cap_deg: INTERSECTION_CAP_DEG,
        exit_vector: false,
    },
};
