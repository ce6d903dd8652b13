//! Fanuc-style milling control with cutter compensation C (seed 003).

use super::{
    g, m, point_code, CornerKind, CornerWordDef, CycleKind, Dialect, DwellWords, GCodeDef, GEffect,
    MCodeDef, MEffect, RadiusWord, Semicolon,
};
use crate::alarm::AlarmCode;
use crate::frontend::block::{
    CornerPolicy, Distance, LengthComp, MotionMode, Plane, ProgramStop, SelectionPolicy,
    SpindleDir, TrcSide,
};
use crate::machine_data::{DialectName, Units};
use crate::trc::{ArmedArc, NoPlaneMove, RadiusChange, RepeatRule, SideChange, TrcRules};

use GEffect::*;
use MEffect::*;

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
    g(40, Trc(TrcSide::Off)),
    g(41, Trc(TrcSide::Left)),
    g(42, Trc(TrcSide::Right)),
    g(43, ToolLength(LengthComp::Plus)),
    g(44, ToolLength(LengthComp::Minus)),
    g(49, ToolLength(LengthComp::Off)),
    g(53, MachineCoordinates),
    g(54, WorkOffset(1)),
    g(55, WorkOffset(2)),
    g(56, WorkOffset(3)),
    g(57, WorkOffset(4)),
    g(58, WorkOffset(5)),
    g(59, WorkOffset(6)),
    g(61, ExactStopModal(true)),
    g(point_code(54, 1), NumberedWorkOffset),
    g(64, ExactStopModal(false)),
    g(65, MacroCall),
    g(66, ModalMacroCall),
    g(67, ModalMacroCancel),
    g(28, ReferenceReturn(false)),
    g(30, ReferenceReturn(true)),
    g(73, Cycle(CycleKind::HighSpeedPeck)),
    g(74, Cycle(CycleKind::LeftTap)),
    g(76, Cycle(CycleKind::FineBore)),
    g(80, CycleCancel),
    g(81, Cycle(CycleKind::Drill)),
    g(82, Cycle(CycleKind::SpotDrill)),
    g(83, Cycle(CycleKind::Peck)),
    g(84, Cycle(CycleKind::Tap)),
    g(85, Cycle(CycleKind::Bore)),
    g(86, Cycle(CycleKind::BoreSpindleStop)),
    g(87, Cycle(CycleKind::BackBore)),
    g(
        88,
        Unsupported("boring cycle with manual operation at the bottom G88"),
    ),
    g(89, Cycle(CycleKind::BoreDwell)),
    g(98, CycleReturn(true)),
    g(99, CycleReturn(false)),
    g(90, Distance(Distance::Absolute)),
    g(91, Distance(Distance::Incremental)),
    g(94, FeedPerRevolution(false)),
    g(95, FeedPerRevolution(true)),
    g(96, ConstantSurfaceSpeed(true)),
    g(97, ConstantSurfaceSpeed(false)),
    g(92, PositionSetting),
    g(15, PolarCoordinates(false)),
    g(16, PolarCoordinates(true)),
    g(52, LocalCoordinates),
    g(50, Scaling(false)),
    g(51, Scaling(true)),
    g(point_code(50, 1), Mirror(false)),
    g(point_code(51, 1), Mirror(true)),
    g(68, Rotation(true)),
    g(69, Rotation(false)),
    g(10, DataSetting),
];

/// The M functions the front end acts on, the lathe's too.
pub(super) static MCODES: &[MCodeDef] = &[
    m(0, Stop(ProgramStop::Stop)),
    m(1, Stop(ProgramStop::OptionalStop)),
    m(3, Spindle(SpindleDir::Clockwise)),
    m(4, Spindle(SpindleDir::CounterClockwise)),
    m(5, Spindle(SpindleDir::Stop)),
    m(19, Spindle(SpindleDir::Orient)),
    m(2, Stop(ProgramStop::End)),
    m(30, Stop(ProgramStop::EndRewind)),
    m(98, Call),
    m(99, Return),
];

/// Optional angle chamfering and corner rounding (0i-MF, 0i-TF): `,C` the distance from the
/// virtual corner to the chamfer's ends, `,R` the rounding's radius; the lathe's too.
pub(super) static CORNER_WORDS: &[CornerWordDef] = &[
    CornerWordDef {
        text: ",C",
        kind: CornerKind::Chamfer,
    },
    CornerWordDef {
        text: ",R",
        kind: CornerKind::Round,
    },
];

pub static DIALECT: Dialect = Dialect {
    name: DialectName::Fanuc,
    gcodes: GCODES,
    mcodes: MCODES,
    semicolon: Semicolon::EndOfBlock,
    radius_word: RadiusWord::R,
    lf_block_end: false,
    variables: false,
    at_commands: &[],
    at_language: false,
    main_block_colon: false,
    corner_words: CORNER_WORDS,
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
    incremental_words: false,
    t_selects_offset: false,
    decimal_switch: true,
    initial_work_offset: 1,
    numbered_work_offsets: 48,
    length_offset: super::LengthOffset::HRegister,
    tool_edges: false,
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
    trc: TRC,
};

/// Cutter compensation C (seed 003), the lathe's nose radius compensation too.
pub(super) const TRC: TrcRules = TrcRules {
    repeat: RepeatRule::Restart,
    side_change: SideChange::Intersection,
    radius_change: RadiusChange::InBlock,
    armed_arc: ArmedArc::Alarm(AlarmCode::FanucTrcNotLinear),
    no_plane_move: NoPlaneMove::OffsetOnly,
    not_linear: AlarmCode::FanucTrcNotLinear,
    intersection_cap_deg: super::siemens_840c::INTERSECTION_CAP_DEG,
    exit_vector: true,
};
