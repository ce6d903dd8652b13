//! SINUMERIK 828D / 840D sl milling: the 808D's G codes and M functions, and the SINUMERIK
//! language (frontend/sinumerik; docs/sinumerik.md). Machine data: config/siemens-840d.toml.

use super::siemens_808d::{G451_LIMIT_DEG, GCODES, MCODES};
use super::{CornerKind, CornerWordDef, Dialect, DwellWords, RadiusWord, Semicolon};
use crate::alarm::AlarmCode;
use crate::frontend::block::{CornerPolicy, MotionMode, SelectionPolicy};
use crate::machine_data::DialectName;
use crate::trc::{ArmedArc, NoPlaneMove, RadiusChange, RepeatRule, SideChange, TrcRules};

/// Chamfer and rounding between two contour blocks (Fundamentals, "Chamfer, rounding"): CHF=
/// the chamfer's length, CHR= its leg, RND= the rounding's radius.
pub(super) static CORNER_WORDS: &[CornerWordDef] = &[
    CornerWordDef {
        text: "CHF=",
        kind: CornerKind::ChamferLength,
    },
    CornerWordDef {
        text: "CHR=",
        kind: CornerKind::Chamfer,
    },
    CornerWordDef {
        text: "RND=",
        kind: CornerKind::Round,
    },
];

pub static DIALECT: Dialect = Dialect {
    name: DialectName::Siemens840D,
    gcodes: GCODES,
    mcodes: MCODES,
    semicolon: Semicolon::Comment,
    radius_word: RadiusWord::CrEquals,
    lf_block_end: false,
    variables: false,
    at_commands: &[],
    corner_words: CORNER_WORDS,
    polar_words: false,
    lims_word: true,
    diameter_words: true,
    o_numbers: false,
    macro_b: false,
    sinumerik: true,
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
    },
    trc_not_linear: AlarmCode::TrcSelectionNotLinear,
    trc_codes_need_linear_mode: false,
    d0_deselects: false,
    initial_motion: MotionMode::Rapid,
    initial_corner_intersection: CornerPolicy::IntersectionLimited {
        limit_deg: G451_LIMIT_DEG,
    },
    initial_selection: SelectionPolicy::NormalPosition,
    // The 808D's rules: one Sinumerik compensation (Fundamentals, "Tool radius compensation").
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
