//! SINUMERIK 828D / 840D sl milling: the 808D's G codes (with G54 … G57, G505 … G599 as the
//! settable zero offsets) and M functions, and the SINUMERIK language (frontend/sinumerik;
//! docs/sinumerik.md). Machine data: config/siemens-840d.toml.

use super::siemens_808d::COMMON;
use super::{concat, g, CornerKind, CornerWordDef, Dialect, GCodeDef, GEffect, NamedCodeDef};
use crate::frontend::block::SelectionPolicy;
use crate::machine_data::DialectName;

/// G505 … G599: the settable frames after G54 … G57 (Fundamentals, "Settable zero offset"),
/// work offsets 5 … 99.
const SETTABLE_FRAMES: [GCodeDef; 95] = {
    let mut t = [g(505, GEffect::WorkOffset(5)); 95];
    let mut k = 0;
    while k < t.len() {
        t[k] = g(505 + k as u16, GEffect::WorkOffset(5 + k as u8));
        k += 1;
    }
    t
};

/// The 840D's G58/G59 replace the coarse / fine translation of the programmable frame,
/// axis by axis: not built (docs/sinumerik.md, "Frames").
const AXIAL_OFFSETS: [GCodeDef; 2] = [
    g(
        58,
        GEffect::Unsupported("the axial programmable offset G58"),
    ),
    g(
        59,
        GEffect::Unsupported("the axial programmable offset G59"),
    ),
];

static GCODES: [GCodeDef; COMMON.len() + 2 + 95] = concat(
    &concat::<{ COMMON.len() + 2 }>(COMMON, &AXIAL_OFFSETS),
    &SETTABLE_FRAMES,
);

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

/// The 808D's rules (one SINUMERIK language, one compensation) under the 840D's name, with
/// its own zero offsets; the machine data make it a mill.
pub static DIALECT: Dialect = Dialect {
    name: DialectName::Siemens840D,
    gcodes: &GCODES,
    // 16 program levels, the main program level 0 (Job planning 828D/840D sl, "Nesting
    // depth"; the two more of interrupt routines are not built).
    program_levels: 16,
    ..super::siemens_808d::BASE
};
