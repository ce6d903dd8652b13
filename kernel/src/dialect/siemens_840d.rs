//! SINUMERIK 828D / 840D sl milling: the 808D's G codes and M functions, and the SINUMERIK
//! language (frontend/sinumerik; docs/sinumerik.md). Machine data: config/siemens-840d.toml.

use super::{CornerKind, CornerWordDef, Dialect, GEffect, NamedCodeDef};
use crate::frontend::block::SelectionPolicy;
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

/// G group 17, the compensation's approach and retraction (Fundamentals "Approach and
/// retraction NORM, KONT, KONTC, KONTT"; FM W1 "Approach and retraction behavior"): NORM runs
/// straight to the normal position; KONT goes round the start point by the corner mode when
/// the start lies behind the contour, which is the 840C's compensated approach (G455).
pub(super) static NAMED_CODES: &[NamedCodeDef] = &[
    NamedCodeDef {
        text: "NORM",
        effect: GEffect::Selection(SelectionPolicy::NormalPosition),
    },
    NamedCodeDef {
        text: "KONT",
        effect: GEffect::Selection(SelectionPolicy::Compensated),
    },
    NamedCodeDef {
        text: "KONTC",
        effect: GEffect::Unsupported(
            "KONTC (approach and retraction along a curve of constant curvature)",
        ),
    },
    NamedCodeDef {
        text: "KONTT",
        effect: GEffect::Unsupported(
            "KONTT (approach and retraction along a curve of constant tangent)",
        ),
    },
];

/// The 808D's table and rules (one SINUMERIK language, one compensation) under the 840D's
/// name; the machine data make it a mill.
pub static DIALECT: Dialect = Dialect {
    name: DialectName::Siemens840D,
    ..super::siemens_808d::BASE
};
