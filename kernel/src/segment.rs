//! Segments: what block preparation hands to interpolation. One segment is one straight or
//! circular piece of the tool path, tagged with the block it belongs to and why it exists.

use crate::frontend::block::{BlockNo, Plane, Pos};

/// Where a segment comes from in the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Source {
    pub number: Option<BlockNo>,
    /// 1-based line and column of the block's first character.
    pub line: u32,
    pub col: u32,
    /// The block's place in execution order (1, 2, …; a loop's blocks get a new one on every
    /// pass; wraps after 2³² blocks, so compare with `wrapping_sub`).
    pub seq: u32,
}

/// Why a segment is in the path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// The selection block's move onto the contour.
    Approach,
    /// A programmed element (compensated when TRC is active).
    Contour,
    /// A transition circle at an outer corner (840C 11.1 G450, ISG G26).
    Corner,
    /// A linear block inserted at an outer corner (840C G451, ISG G25, Fanuc C).
    Intermediate,
    /// The deselection block's move off the contour.
    Retract,
    /// A move with TRC off.
    Uncompensated,
}

impl Role {
    pub fn name(self) -> &'static str {
        match self {
            Role::Approach => "approach",
            Role::Contour => "contour",
            Role::Corner => "corner",
            Role::Intermediate => "intermediate",
            Role::Retract => "retract",
            Role::Uncompensated => "uncompensated",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Line,
    /// An arc about `center` in `plane`; the radius goes linearly from `r0` at the start to
    /// `r1` at the end over the sweep (they differ only while a radius change is spread over
    /// the block). `from == to` in the plane with `r0 == r1` is a full circle. The centre
    /// moves linearly with the sweep from `center` to `center_end` where a turning tool's
    /// cutting edge changes over the block (prep/tool_tip.rs); otherwise they are equal.
    Arc {
        center: Pos,
        center_end: Pos,
        ccw: bool,
        r0: f64,
        r1: f64,
        plane: Plane,
    },
}

/// One piece of the tool-centre path, in mm, [X, Y, Z] workpiece coordinates with the tool
/// length along the tool axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub source: Source,
    pub role: Role,
    pub shape: Shape,
    pub from: Pos,
    pub to: Pos,
    /// Path feed, mm/min.
    pub feed: f64,
    pub rapid: bool,
    /// Exact stop at the end (G09 of the block, or the modal G60/G61; inserted blocks take
    /// the next block's, 840C 11.10).
    pub exact_stop: bool,
}

impl Segment {
    pub fn is_arc(&self) -> bool {
        matches!(self.shape, Shape::Arc { .. })
    }
}
