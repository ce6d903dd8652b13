//! ISG kernel / Beckhoff TwinCAT CNC (seed 002; TF5200 programming manual).

use super::{
    g, m, Dialect, DwellWords, GCodeDef, GEffect, MCodeDef, MEffect, RadiusWord, Semicolon,
};
use crate::alarm::AlarmCode;
use crate::frontend::block::{
    CornerPolicy, Distance, FeedAdaption, MotionMode, Plane, ProgramStop, SelectionPolicy,
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
    // G05: tangential selection/deselection, non-modal.
    g(5, Approach(SelectionPolicy::Tangential)),
    // G09: deceleration at block end; G60: exact stop for this block end.
    g(9, ExactStopBlock),
    // G10/G11: feed adaption with TRC (not polar coordinates as on the 840C).
    g(10, FeedAdaption(FeedAdaption::Centre)),
    g(11, FeedAdaption(FeedAdaption::Contour)),
    g(17, Plane(Plane::XY)),
    g(18, Plane(Plane::ZX)),
    g(19, Plane(Plane::YZ)),
    // G25/G26: TRC transition type (not the working area as on the 840C).
    g(25, Corner(CornerPolicy::LinearTransition)),
    g(26, Corner(CornerPolicy::TransitionCircle)),
    g(40, Trc(TrcSide::Off)),
    g(41, Trc(TrcSide::Left)),
    g(42, Trc(TrcSide::Right)),
    g(53, WorkOffset(0)),
    g(54, WorkOffset(1)),
    g(55, WorkOffset(2)),
    g(56, WorkOffset(3)),
    g(57, WorkOffset(4)),
    g(58, WorkOffset(5)),
    g(59, WorkOffset(6)),
    g(60, ExactStopBlock),
    g(70, Units(Units::Inch)),
    g(71, Units(Units::Mm)),
    g(90, Distance(Distance::Absolute)),
    g(91, Distance(Distance::Incremental)),
    g(94, FeedPerRevolution(false)),
    g(95, FeedPerRevolution(true)),
    g(96, ConstantSurfaceSpeed(true)),
    g(97, ConstantSurfaceSpeed(false)),
    g(138, Selection(SelectionPolicy::Direct)),
    g(139, Selection(SelectionPolicy::Indirect)),
    g(140, Masking(false)),
    g(141, Masking(true)),
    g(237, Selection(SelectionPolicy::Perpendicular)),
    g(238, Selection(SelectionPolicy::InnerCorner)),
    g(239, Selection(SelectionPolicy::WithoutBlock)),
    g(359, ExactStopModal(false)),
    g(360, ExactStopModal(true)),
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
];

pub static DIALECT: Dialect = Dialect {
    name: DialectName::Isg,
    gcodes: GCODES,
    mcodes: MCODES,
    semicolon: Semicolon::Comment,
    radius_word: RadiusWord::R,
    lf_block_end: false,
    variables: true,
    at_commands: &[],
    at_language: false,
    main_block_colon: false,
    corner_words: &[],
    named_codes: &[],
    polar_words: false,
    lims_word: false,
    diameter_words: false,
    o_numbers: false,
    helix_turns: 0,
    macro_b: false,
    sinumerik: false,
    l_calls: false,
    // No calls in the language built here; the bound of the others.
    program_levels: 16,
    incremental_words: false,
    t_selects_offset: false,
    decimal_switch: false,
    initial_work_offset: 0,
    numbered_work_offsets: 0,
    length_offset: super::LengthOffset::WithD,
    tool_edges: false,
    dwell: DwellWords {
        x_seconds: true,
        f_seconds: false,
        p_millis: false,
        bare_seconds: true,
        s_revolutions: false,
    },
    trc_not_linear: AlarmCode::TrcSelectionNotLinear,
    trc_codes_need_linear_mode: false,
    d0_deselects: false,
    initial_motion: MotionMode::Rapid,
    initial_corner_intersection: CornerPolicy::LinearTransition,
    initial_selection: SelectionPolicy::Indirect,
    trc: TrcRules {
        repeat: RepeatRule::IgnoreWithoutApproach,
        side_change: SideChange::Reselect(None),
        radius_change: RadiusChange::NextLinear,
        armed_arc: ArmedArc::Perpendicular,
        no_plane_move: NoPlaneMove::Wait,
        not_linear: AlarmCode::TrcSelectionNotLinear,
        intersection_cap_deg: super::siemens_840c::INTERSECTION_CAP_DEG,
        exit_vector: false,
    },
};
