//! Fanuc-style milling control with cutter compensation C (seed 003).

use super::{
    g, m, point_code, Dialect, DwellWords, GCodeDef, GEffect, MCodeDef, MEffect, RadiusWord,
    Semicolon,
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
    g(80, CycleCancel),
    g(90, Distance(Distance::Absolute)),
    g(91, Distance(Distance::Incremental)),
    g(94, FeedPerRevolution(false)),
    g(95, FeedPerRevolution(true)),
    g(96, ConstantSurfaceSpeed(true)),
    g(97, ConstantSurfaceSpeed(false)),
    g(92, Unsupported("coordinate system setting G92")),
];

static MCODES: &[MCodeDef] = &[
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

pub static DIALECT: Dialect = Dialect {
    name: DialectName::Fanuc,
    gcodes: GCODES,
    mcodes: MCODES,
    semicolon: Semicolon::EndOfBlock,
    radius_word: RadiusWord::R,
    lf_block_end: false,
    variables: false,
    at_commands: &[],
    polar_words: false,
    lims_word: false,
    diameter_words: false,
    o_numbers: true,
    macro_b: true,
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
    },
    trc_not_linear: AlarmCode::FanucTrcNotLinear,
    trc_codes_need_linear_mode: true,
    d0_deselects: false,
    initial_motion: MotionMode::Linear,
    initial_corner_intersection: CornerPolicy::ExtendedIntersection,
    initial_selection: SelectionPolicy::OffsetVector,
    trc: TrcRules {
        repeat: RepeatRule::Restart,
        side_change: SideChange::Intersection,
        radius_change: RadiusChange::InBlock,
        armed_arc: ArmedArc::Alarm(AlarmCode::FanucTrcNotLinear),
        no_plane_move: NoPlaneMove::OffsetOnly,
        not_linear: AlarmCode::FanucTrcNotLinear,
        intersection_cap_deg: super::siemens_840c::INTERSECTION_CAP_DEG,
    },
};
