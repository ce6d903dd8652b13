//! Tool offsets changed in NC stop (840C 11.8: "if the changes are to become active
//! immediately, the compensation values can only be entered in the NC stop state").
//!
//! The program is prepared again from its start with the new offsets — every check runs again,
//! so a radius that now violates the contour is an alarm before anything moves — up to the
//! interrupted block. There the path goes on from the point of the new equidistant that
//! corresponds to the interruption point, reached by a straight reposition move from wherever
//! the axes stand.

use super::{Preparation, Prepared};
use crate::alarm::{Alarm, AlarmCode};
use crate::frontend::block::Pos;
use crate::machine_data::MachineData;
use crate::segment::{Curve, Role, Segment, Shape};
use crate::tools::ToolTable;

/// Where the path stopped: the block (its execution number, [`crate::segment::Source::seq`]),
/// which of its segments — the `nth` one with length, of role `role` — and how far along it,
/// 0 at the start to 1 at the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interruption {
    pub seq: u32,
    pub role: Role,
    pub nth: u32,
    pub along: f64,
}

impl Interruption {
    /// On the block's (first) programmed element.
    pub fn contour(seq: u32, along: f64) -> Self {
        Interruption {
            seq,
            role: Role::Contour,
            nth: 0,
            along,
        }
    }
}

/// The re-prepared program: the records to run first (the reposition move, the rest of the
/// interrupted segment, and what preparation had to read past to find it), then `rest`
/// goes on from there.
pub struct Resumed<'a> {
    pub first: Vec<Prepared>,
    pub rest: Preparation<'a>,
}

impl<'a> Preparation<'a> {
    /// Prepares the program again with `tools` (the axes at `start` before its first block,
    /// as when it was loaded) and positions it at `at`; `axes` is where the axes stand (tool
    /// centre, workpiece coordinates). Records before the interruption were already executed
    /// and are not handed out again.
    ///
    /// The interrupted segment is found again by block, role and place in the block. Where
    /// the new radius changed the block's pieces (an inserted corner became an intersection,
    /// say), it is not there: the path then goes on from the start of the block's first
    /// piece, which the old path had reached.
    #[allow(clippy::too_many_arguments)]
    pub fn resume(
        name: &'a str,
        source: &'a str,
        md: &'a MachineData,
        tools: &'a ToolTable,
        start: Option<Pos>,
        at: Interruption,
        axes: Pos,
    ) -> Result<Resumed<'a>, Alarm> {
        let mut rest = Preparation::starting_at(name, source, md, tools, start);
        let along = at.along.clamp(0.0, 1.0);
        // The block's pieces with length, in order, and what follows them (the fallback).
        let mut block: Vec<Prepared> = Vec::new();
        let mut nth = 0u32;
        loop {
            let item = rest.next_item()?;
            let seg = match item {
                Some(Prepared::Segment(s)) => s,
                Some(other) => {
                    if !block.is_empty() {
                        block.push(other);
                    }
                    continue;
                }
                None => break,
            };
            let d = seg.source.seq.wrapping_sub(at.seq) as i32;
            if d < 0 || Curve::new(&seg).is_none() {
                continue;
            }
            if d > 0 {
                block.push(Prepared::Segment(seg));
                break;
            }
            if nth == at.nth && seg.role == at.role {
                let q = point_at(&seg, along);
                let mut remainder = seg;
                remainder.from = q;
                if let Shape::Arc { r0, r1, .. } = &mut remainder.shape {
                    // The radius where the rest starts, on the same linear ramp.
                    *r0 += (*r1 - *r0) * along;
                }
                return Ok(Resumed {
                    first: vec![
                        Prepared::Segment(reposition(&seg, axes, q)),
                        Prepared::Segment(remainder),
                    ],
                    rest,
                });
            }
            nth += 1;
            block.push(Prepared::Segment(seg));
        }
        // Not found: from the start of the block's first piece.
        if let Some(Prepared::Segment(first)) = block.first() {
            if first.source.seq == at.seq {
                let mut out = vec![Prepared::Segment(reposition(first, axes, first.from))];
                out.extend(block);
                return Ok(Resumed { first: out, rest });
            }
        }
        Err(Alarm {
            code: AlarmCode::NotSupported,
            program: name.to_string(),
            line: 0,
            col: 0,
            block: None,
            message: format!(
                "cannot resume: block number {} of the run has no segment with the new offsets",
                at.seq
            ),
        })
    }
}

/// The straight move from where the axes stand onto `q` of `seg`, with `seg`'s feed and
/// block, ending in an exact stop.
fn reposition(seg: &Segment, axes: Pos, q: Pos) -> Segment {
    Segment {
        role: Role::Approach,
        shape: Shape::Line,
        from: axes,
        to: q,
        rapid: false,
        exact_stop: true,
        ..*seg
    }
}

/// The point `t` (0..=1) along a segment: on its [`Curve`], the parametrisation the
/// interpolator runs along (by angle on an arc, the radius, centre and tool axis linearly).
fn point_at(s: &Segment, t: f64) -> Pos {
    match Curve::new(s) {
        Some(c) if t > 0.0 && t < 1.0 => c.point(t),
        _ if t >= 1.0 => s.to,
        _ => s.from,
    }
}
