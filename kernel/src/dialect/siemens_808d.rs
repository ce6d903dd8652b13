//! SINUMERIK 808D turning (seed 004).

use super::{
    g, m, Dialect, DwellWords, GCodeDef, GEffect, MCodeDef, MEffect, RadiusWord, SarContour,
    SarPath, SarSide, Semicolon,
};
use crate::alarm::AlarmCode;
use crate::frontend::block::{
    CornerPolicy, Distance, FeedType, MotionMode, Plane, PoleOrigin, ProgramStop, SelectionPolicy,
    SpindleDir, TrcSide,
};
use crate::machine_data::{DialectName, Units};
use crate::trc::{ArmedArc, NoPlaneMove, RadiusChange, RepeatRule, SideChange, TrcRules};

use GEffect::*;
use MEffect::*;

/// 808D G451 switches to the transition circle above this angle (fixed on the 808D).
pub const G451_LIMIT_DEG: f64 = 100.0;

/// The G codes the 808D and the 840D share (siemens_840d.rs adds its own).
pub(super) const COMMON: &[GCodeDef] = &[
    g(0, Motion(MotionMode::Rapid)),
    g(1, Motion(MotionMode::Linear)),
    g(2, Motion(MotionMode::ArcCw)),
    g(3, Motion(MotionMode::ArcCcw)),
    g(4, Dwell),
    g(9, ExactStopBlock),
    g(17, Plane(Plane::XY)),
    g(18, Plane(Plane::ZX)),
    g(19, Plane(Plane::YZ)),
    g(40, Trc(TrcSide::Off)),
    g(41, Trc(TrcSide::Left)),
    g(42, Trc(TrcSide::Right)),
    g(53, MachineCoordinates),
    // Also the basic frame (none in softnc): as G53 here.
    g(153, MachineCoordinates),
    g(54, WorkOffset(1)),
    g(55, WorkOffset(2)),
    g(56, WorkOffset(3)),
    g(57, WorkOffset(4)),
    g(60, ExactStopModal(true)),
    g(64, ExactStopModal(false)),
    // 808D "Inch and metric dimensioning": G70/G71 the geometry only, G700/G710 the feed too.
    g(70, GeometryUnits(Units::Inch)),
    g(71, GeometryUnits(Units::Mm)),
    g(90, Distance(Distance::Absolute)),
    g(91, Distance(Distance::Incremental)),
    // Fundamentals, "Feedrate control": one group; G96 switches G95 on, G97 keeps the type.
    g(94, FeedType(FeedType::PerMinute)),
    g(95, FeedType(FeedType::PerRevolution)),
    g(96, FeedType(FeedType::CuttingSpeed)),
    g(97, FeedType(FeedType::CuttingSpeedOff)),
    // Fundamentals, "Defining the pole": from the last position, the zero, the last pole.
    g(110, Pole(PoleOrigin::LastPosition)),
    g(111, Pole(PoleOrigin::WorkZero)),
    g(112, Pole(PoleOrigin::LastPole)),
    // Smooth approach and retraction (840D sl Fundamentals "Approach and retraction"): the
    // side (group 43), the contour (non-modal), the infeed (group 44).
    g(140, SmoothSide(SarSide::Compensation)),
    g(141, SmoothSide(SarSide::Left)),
    g(142, SmoothSide(SarSide::Right)),
    g(143, SmoothSide(SarSide::Position)),
    g(147, SmoothApproach(SarContour::Line)),
    g(148, SmoothRetraction(SarContour::Line)),
    g(247, SmoothApproach(SarContour::Quadrant)),
    g(248, SmoothRetraction(SarContour::Quadrant)),
    g(340, SmoothPath(SarPath::Spatial)),
    g(341, SmoothPath(SarPath::AxisFirst)),
    g(347, SmoothApproach(SarContour::Semicircle)),
    g(348, SmoothRetraction(SarContour::Semicircle)),
    g(450, Corner(CornerPolicy::TransitionCircle)),
    g(500, WorkOffset(0)),
    g(
        451,
        Corner(CornerPolicy::IntersectionLimited {
            limit_deg: G451_LIMIT_DEG,
        }),
    ),
    g(700, Units(Units::Inch)),
    g(710, Units(Units::Mm)),
];

/// The 808D's own: two more settable zero offsets.
static GCODES: [GCodeDef; COMMON.len() + 2] =
    super::concat(COMMON, &[g(58, WorkOffset(5)), g(59, WorkOffset(6))]);

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
    m(30, Stop(ProgramStop::EndRewind)),
];

pub static DIALECT: Dialect = BASE;

/// The 808D's table: the 840D's too, under its own name (siemens_840d.rs).
pub(super) const BASE: Dialect = Dialect {
    name: DialectName::Siemens808D,
    gcodes: &GCODES,
    mcodes: MCODES,
    semicolon: Semicolon::Comment,
    radius_word: RadiusWord::CrEquals,
    lf_block_end: false,
    variables: false,
    at_commands: &[],
    at_language: false,
    main_block_colon: false,
    corner_words: super::siemens_840d::CORNER_WORDS,
    named_codes: super::siemens_840d::NAMED_CODES,
    polar_words: false,
    lims_word: true,
    diameter_words: true,
    o_numbers: false,
    // Fundamentals, "Helical interpolation (G2/G3, TURN)": TURN= 0 … 999.
    helix_turns: 999,
    macro_b: false,
    sinumerik: true,
    l_calls: false,
    // 808D: eight program levels including the main program (808D manual, "Subprograms").
    program_levels: 8,
    incremental_words: false,
    t_selects_offset: false,
    decimal_switch: false,
    initial_work_offset: 0,
    numbered_work_offsets: 0,
    length_offset: super::LengthOffset::WithD,
    tool_edges: true,
    dwell: DwellWords {
        x_seconds: false,
        f_seconds: true,
        p_millis: false,
        bare_seconds: false,
        // Fundamentals, "Dwell time (G4)": S is the master spindle's revolutions.
        s_revolutions: true,
    },
    trc_not_linear: AlarmCode::TrcSelectionNotLinear,
    trc_codes_need_linear_mode: false,
    d0_deselects: false,
    initial_motion: MotionMode::Rapid,
    initial_corner_intersection: CornerPolicy::IntersectionLimited {
        limit_deg: G451_LIMIT_DEG,
    },
    initial_selection: SelectionPolicy::NormalPosition,
    trc: TrcRules {
        repeat: RepeatRule::Restart,
        side_change: SideChange::Reselect(Some(SelectionPolicy::NormalPosition)),
        radius_change: RadiusChange::InBlock,
        armed_arc: ArmedArc::Alarm(AlarmCode::TrcSelectionNotLinear),
        no_plane_move: NoPlaneMove::Wait,
        not_linear: AlarmCode::TrcSelectionNotLinear,
        intersection_cap_deg: super::siemens_840c::INTERSECTION_CAP_DEG,
        exit_vector: false,
    },
};
