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

/// Where the path stopped: the block (its execution number, [`crate::segment::Source::seq`])
/// and how far along its contour segment, 0 at the start to 1 at the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interruption {
    pub seq: u32,
    pub along: f64,
}

/// The re-prepared program: the first records to run (the reposition move and the rest of
/// the interrupted block), then `rest` goes on from there.
pub struct Resumed<'a> {
    pub first: [Segment; 2],
    pub rest: Preparation<'a>,
}

impl<'a> Preparation<'a> {
    /// Prepares the program again with `tools` and positions it at `at`; `axes` is where the
    /// axes stand (tool centre, workpiece coordinates). Records before the interruption were
    /// already executed and are not handed out again.
    pub fn resume(
        name: &'a str,
        source: &'a str,
        md: &'a MachineData,
        tools: &'a ToolTable,
        at: Interruption,
        axes: Pos,
    ) -> Result<Resumed<'a>, Alarm> {
        let mut rest = Preparation::new(name, source, md, tools);
        loop {
            let item = rest.next_item()?;
            let seg = match item {
                Some(Prepared::Segment(s)) => s,
                Some(_) => continue,
                None => break,
            };
            let d = seg.source.seq.wrapping_sub(at.seq) as i32;
            if d > 0 {
                break;
            }
            if d < 0 || seg.role != Role::Contour {
                continue;
            }
            let q = point_at(&seg, at.along.clamp(0.0, 1.0));
            let reposition = Segment {
                role: Role::Approach,
                shape: Shape::Line,
                from: axes,
                to: q,
                rapid: false,
                exact_stop: true,
                ..seg
            };
            let mut remainder = seg;
            remainder.from = q;
            if let Shape::Arc { r0, r1, .. } = &mut remainder.shape {
                // The radius where the rest starts, on the same linear ramp.
                *r0 += (*r1 - *r0) * at.along.clamp(0.0, 1.0);
            }
            return Ok(Resumed {
                first: [reposition, remainder],
                rest,
            });
        }
        Err(Alarm {
            code: AlarmCode::NotSupported,
            program: name.to_string(),
            line: 0,
            col: 0,
            block: None,
            message: format!(
                "cannot resume: block number {} of the run has no contour segment with the new offsets",
                at.seq
            ),
        })
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
