//! Turning tools: the setpoint addresses the theoretical tool tip P, not the nose centre S
//! (840C 11.13, `trc::cutting_edge`). The compensation and its checks work on S; the path
//! leaves preparation shifted to P:
//!
//! - with TRC off, P runs on the programmed contour (no shift);
//! - with TRC on, every point gets the active position's vector P − S;
//! - the approach goes from P (TRC off) to the first S + vector, the retract back to P on the
//!   programmed point: the shift changes along these lines, as it does along a line whose
//!   block changes the cutting edge (840C 11.7: D1 in position 3, D2 in position 4; the new
//!   edge is traversed over the block like a new tool length). Over an arc (808D: a D change
//!   traversed continuously over a circle) the arc's centre moves with it
//!   (`Shape::Arc::center_end`).

use crate::frontend::block::Plane;
use crate::segment::{Role, Segment, Shape};
use crate::trc::geom::{v2, V2};

/// Blocks whose cutting edge changed, as far back as a segment in the bottleneck window can
/// reach.
const CHANGES: usize = crate::prep::bottleneck::MAX_WINDOW + 16;

pub struct ToolTip {
    /// (first block, P − S from it on), oldest first.
    changes: heapless::Deque<(u32, V2), CHANGES>,
    /// The vector of the last block read.
    now: V2,
    /// The shift at the end of the last segment out (the next one starts with it).
    end: V2,
}

impl ToolTip {
    pub fn new() -> Self {
        ToolTip {
            changes: heapless::Deque::new(),
            now: v2(0.0, 0.0),
            end: v2(0.0, 0.0),
        }
    }

    /// A block was read (number `seq` in execution order); `v` is its cutting edge's
    /// nose centre → tip vector (`trc::cutting_edge::tip_vector`).
    #[inline]
    pub fn block(&mut self, v: V2, seq: u32) {
        if v != self.now {
            self.now = v;
            if self.changes.is_full() {
                self.changes.pop_front();
            }
            let _ = self.changes.push_back((seq, v));
        }
    }

    /// Nothing to shift: no turning tool with a cutting edge position in sight.
    #[inline]
    pub fn idle(&self) -> bool {
        self.changes.is_empty() && self.now == v2(0.0, 0.0) && self.end == v2(0.0, 0.0)
    }

    /// Shifts `seg` from nose centre to tool tip.
    pub fn shift(&mut self, seg: &mut Segment) {
        let seq = seg.source.seq;
        // The vector of the segment's block: the last change at or before it.
        while self.changes.len() >= 2
            && self
                .changes
                .iter()
                .nth(1)
                .is_some_and(|&(s, _)| (seq.wrapping_sub(s) as i32) >= 0)
        {
            self.changes.pop_front();
        }
        let of_block = match self.changes.front() {
            Some(&(s, v)) if (seq.wrapping_sub(s) as i32) >= 0 => v,
            // Before the first change: no cutting edge yet.
            Some(_) => v2(0.0, 0.0),
            None => self.now,
        };
        let end = match seg.role {
            Role::Retract | Role::Uncompensated => v2(0.0, 0.0),
            _ => of_block,
        };
        let start = self.end;
        if let Shape::Arc {
            center, center_end, ..
        } = &mut seg.shape
        {
            add(center, start);
            add(center_end, end);
        }
        add(&mut seg.from, start);
        add(&mut seg.to, end);
        self.end = end;
    }
}

impl Default for ToolTip {
    fn default() -> Self {
        Self::new()
    }
}

fn add(p: &mut crate::frontend::block::Pos, v: V2) {
    p[Plane::ZX.abscissa as usize] += v.x;
    p[Plane::ZX.ordinate as usize] += v.y;
}
