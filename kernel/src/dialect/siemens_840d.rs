//! SINUMERIK 828D / 840D sl milling: the 808D's G codes and M functions, and the SINUMERIK
//! language (frontend/sinumerik; docs/sinumerik.md). Machine data: config/siemens-840d.toml.

use super::{CornerKind, CornerWordDef, Dialect};
use crate::machine_data::DialectName;

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

/// The 808D's table and rules (one SINUMERIK language, one compensation) under the 840D's
/// name; the machine data make it a mill.
pub static DIALECT: Dialect = Dialect {
    name: DialectName::Siemens840D,
    // 16 program levels, the main program level 0 (Job planning 828D/840D sl, "Nesting
    // depth"; the two more of interrupt routines are not built).
    program_levels: 16,
    ..super::siemens_808d::BASE
};
