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
use crate::frontend::block::{Additional, AxisMove, AxisPos, Pos};
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
        start: Option<AxisPos>,
        at: Interruption,
        axes: AxisPos,
    ) -> Result<Resumed<'a>, Alarm> {
        let mut rest =
            Preparation::starting_at(name, source, md, tools, start).with_soft_limits(md);
        let along = at.along.clamp(0.0, 1.0);
        // The block's pieces with length, in order, and what follows them (the fallback);
        // the additional axes where they stand before the segment, and their move with it.
        let mut block: Vec<Prepared> = Vec::new();
        let mut nth = 0u32;
        let mut here = rest.start().add;
        let mut moving: Option<AxisMove> = None;
        loop {
            let item = rest.next_item()?;
            let seg = match item {
                Some(Prepared::Segment(s)) => s,
                Some(Prepared::Axes(m, src)) => {
                    moving = Some(m);
                    if !block.is_empty() {
                        block.push(Prepared::Axes(m, src));
                    }
                    continue;
                }
                Some(other) => {
                    if !block.is_empty() {
                        block.push(other);
                    }
                    continue;
                }
                None => break,
            };
            let axes_of = moving.take();
            let d = seg.source.seq.wrapping_sub(at.seq) as i32;
            if d < 0 || Curve::new(&seg).is_none() {
                here = axes_of.map_or(here, |m| m.to);
                continue;
            }
            if d > 0 {
                block.push(Prepared::Segment(seg));
                break;
            }
            if nth == at.nth && seg.role == at.role {
                let q = point_at(&seg, axes_of.as_ref(), &here, along);
                let mut remainder = seg;
                remainder.from = q.geo;
                if let Shape::Arc { r0, r1, .. } = &mut remainder.shape {
                    // The radius where the rest starts, on the same linear ramp.
                    *r0 += (*r1 - *r0) * along;
                }
                let mut first = reposition(&seg, axes, q);
                if let Some(m) = axes_of {
                    first.push(Prepared::Axes(
                        AxisMove {
                            from: q.add,
                            to: m.to,
                        },
                        seg.source,
                    ));
                }
                first.push(Prepared::Segment(remainder));
                return Ok(Resumed { first, rest });
            }
            nth += 1;
            if let Some(m) = axes_of {
                block.push(Prepared::Axes(m, seg.source));
            }
            block.push(Prepared::Segment(seg));
            here = axes_of.map_or(here, |m| m.to);
        }
        // Not found: from the start of the block's first piece.
        let first_piece = block.iter().find_map(|p| match p {
            Prepared::Segment(s) => Some(*s),
            _ => None,
        });
        if let Some(first) = first_piece.filter(|f| f.source.seq == at.seq) {
            let start = AxisPos {
                geo: first.from,
                add: block_start(&block, &here),
            };
            let mut out = reposition(&first, axes, start);
            out.extend(block);
            return Ok(Resumed { first: out, rest });
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
/// block, ending in an exact stop: the segment, with the additional axes' move before it —
/// always, even where they stand still: it tells the hand-over where they stand, which
/// need not be where the program was loaded.
fn reposition(seg: &Segment, axes: AxisPos, q: AxisPos) -> Vec<Prepared> {
    let mut out = Vec::with_capacity(3);
    let m = AxisMove {
        from: axes.add,
        to: q.add,
    };
    out.push(Prepared::Axes(m, seg.source));
    out.push(Prepared::Segment(Segment {
        role: Role::Approach,
        shape: Shape::Line,
        from: axes.geo,
        to: q.geo,
        rapid: false,
        exact_stop: true,
        thread: false,
        ..*seg
    }));
    out
}

/// Where the additional axes stand at the start of the block's first piece: the start of
/// its move if one comes before it, else `here`.
fn block_start(block: &[Prepared], here: &Additional) -> Additional {
    match block.first() {
        Some(Prepared::Axes(m, _)) => m.from,
        _ => *here,
    }
}

/// The point `t` (0..=1) along a segment: on its [`Curve`], the parametrisation the
/// interpolator runs along (by angle on an arc, the radius, centre and tool axis linearly).
/// The additional axes move linearly in t beside it (`axes`), or stand at `here`.
fn point_at(s: &Segment, axes: Option<&AxisMove>, here: &Additional, t: f64) -> AxisPos {
    let geo: Pos = match Curve::new(s) {
        Some(c) if t > 0.0 && t < 1.0 => c.point(t),
        _ if t >= 1.0 => s.to,
        _ => s.from,
    };
    let mut add = *here;
    if let Some(m) = axes {
        for (k, a) in add.iter_mut().enumerate() {
            *a = m.from[k] + (m.to[k] - m.from[k]) * t.clamp(0.0, 1.0);
        }
    }
    AxisPos { geo, add }
}
