//! The box cycles of the Fanuc 0i-TF: four moves from the start point A and back, modal in
//! the group of G00 … G03 (a following block with X, Z or R cuts the box again with the
//! others kept; 0i-TF "Canned cycle: G90, G92, G94", the data X(U) Z(W) R modal).
//!
//! ```text
//! G90 (outer/inner diameter)        G92 (thread)                 G94 (end face)
//! 1 rapid X to the cut's start       1 rapid X to the start       1 rapid Z to the cut's start
//! 2 feed to (X, Z)                   2 thread to (X, Z)           2 feed to (X, Z)
//! 3 feed X back to A's X             3 rapid X back (a chamfer    3 feed Z back to A's Z
//! 4 rapid Z back to A                  first where set)           4 rapid X back to A
//!                                    4 rapid Z back to A
//! ```
//!
//! R is the taper: the cut's start lies R (a radius; for G94 along Z) from the end point,
//! at A's Z (G94: A's X). The start may not lie beyond A (0i-TF: |R| ≤ |U/2| where R and U
//! have opposite signs).

use super::super::super::block::*;
use super::super::super::fault::{fault, R};
use super::super::super::interpreter::Interpreter;
use super::super::super::words::Words;
use super::super::expand::{Expansion, Step};
use super::threading::thread_pass;
use super::{at, cut, rapid};
use crate::alarm::AlarmCode;

impl Interpreter<'_> {
    /// Step 8 under G90, G92 or G94: the box, if the block writes X, Z or R.
    pub(super) fn box_cycle(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        kind: BoxCycle,
        col: usize,
    ) -> R<()> {
        if w.axis[0].is_none() && w.axis[2].is_none() && w.radius.is_none() {
            return Ok(());
        }
        self.lathe_allowed(new, col, "a box cycle")?;
        self.no_other_words(w, false)?;
        self.cycle_feed(new, col, "the cycle's cut (or thread lead)")?;
        let a = self.cur;
        let kept = match self.lathe.boxed {
            Some((k, end, r)) if k == kind && self.block.modal.motion == new.motion => {
                Some((end, r))
            }
            _ => None,
        };
        let (mut end, mut taper) = kept.unwrap_or((a, 0.0));
        let written = self.end_point(w, new, a)?;
        for i in [0, 2] {
            if w.axis[i].is_some() {
                end[i] = written[i];
            }
        }
        if let Some(r) = w.radius {
            taper = self.length(r, new.units);
        }
        let at_r = w.radius.map_or(col, |r| r.pos());
        let (axis, start) = match kind {
            BoxCycle::Facing => (2, end[2] + taper),
            _ => (0, end[0] + taper),
        };
        if (a[axis] - start) * (a[axis] - end[axis]) < -1e-12
            || (taper != 0.0 && a[axis] == end[axis])
        {
            return Err(fault(
                AlarmCode::BadNumber,
                at_r,
                "the taper R puts the cut's start beyond the start point",
            ));
        }
        self.lathe.boxed = Some((kind, end, taper));
        let steps = match kind {
            BoxCycle::Turning => turning_box(a, end, taper),
            BoxCycle::Facing => facing_box(a, end, taper),
            BoxCycle::Threading => {
                let gamma = self.chamfer(new.feed, a, end, col)?;
                let from = at(end[0] + taper, a[2], a[1]);
                thread_pass(a, from, end, new.feed, gamma, 0)
            }
        };
        self.expand(Expansion::of(&steps), new);
        Ok(())
    }

    /// The thread chamfer's length along Z: the stored chamfer r in tenths of the lead
    /// (0i-TF parameter 5130, set by G76's P), at 45°; shorter than the thread.
    pub(super) fn chamfer(&self, lead: f64, a: Pos, end: Pos, col: usize) -> R<f64> {
        let gamma = f64::from(self.lathe.thread.chamfer) * 0.1 * lead;
        if gamma > 0.0 && gamma >= (end[2] - a[2]).abs() {
            return Err(fault(
                AlarmCode::BadNumber,
                col,
                format!("the thread chamfer {gamma:.4} is as long as the thread or longer"),
            ));
        }
        Ok(gamma)
    }
}

/// G90: in at rapid, along the taper at the feed, out at the feed, back at rapid.
fn turning_box(a: Pos, end: Pos, taper: f64) -> heapless::Vec<Step, 8> {
    let steps = [
        rapid(at(end[0] + taper, a[2], a[1])),
        cut(end),
        cut(at(a[0], end[2], a[1])),
        rapid(a),
    ];
    steps.into_iter().collect()
}

/// G94: down the face in Z at rapid, across at the feed, back in Z at the feed, out at
/// rapid.
fn facing_box(a: Pos, end: Pos, taper: f64) -> heapless::Vec<Step, 8> {
    let steps = [
        rapid(at(a[0], end[2] + taper, a[1])),
        cut(end),
        cut(at(end[0], a[2], a[1])),
        rapid(a),
    ];
    steps.into_iter().collect()
}

#[cfg(test)]
mod tests {
    use super::super::tests::{alarm, moves, moves_with, How::*};
    use crate::alarm::AlarmCode;

    #[test]
    fn g90_cuts_a_box_and_repeats_it_with_the_next_x() {
        // A (X50 → r25, Z2). G90 X40 Z-20: in to r20 at Z2, feed to (20, -20), out to 25,
        // back to Z2. X36: the same box at r18 (Z-20 kept).
        let m = moves("G0 X50. Z2.\nG90 X40. Z-20. F0.2\nX36.\nG0 X60.\n");
        assert_eq!(
            m,
            [
                (R, 25.0, 2.0),
                (R, 20.0, 2.0),
                (F, 20.0, -20.0),
                (F, 25.0, -20.0),
                (R, 25.0, 2.0),
                (R, 18.0, 2.0),
                (F, 18.0, -20.0),
                (F, 25.0, -20.0),
                (R, 25.0, 2.0),
                (R, 30.0, 2.0),
            ]
        );
    }

    #[test]
    fn g90_taper_starts_r_from_the_end_point() {
        // A (r25, Z2), end X40 (r20) Z-20, R-3: the cut starts at r17 at Z2 and runs to
        // (20, -20) (a taper growing towards the chuck). Radius programming: X20 R-3 alike.
        let want = [
            (R, 25.0, 2.0),
            (R, 17.0, 2.0),
            (F, 20.0, -20.0),
            (F, 25.0, -20.0),
            (R, 25.0, 2.0),
        ];
        assert_eq!(moves("G0 X50. Z2.\nG90 X40. W-22. R-3. F0.2\n"), want);
        assert_eq!(
            moves_with("G0 X25. Z2.\nG90 U-5. Z-20. R-3. F0.2\n", true),
            want
        );
        // R+6 would start the cut at r26, beyond A's r25: alarm at R.
        assert_eq!(
            alarm("G0 X50. Z2.\nG90 X40. Z-20. R6. F0.2\n"),
            (AlarmCode::BadNumber, 2, 16)
        );
    }

    #[test]
    fn g94_faces_along_x() {
        // A (X60 → r30, Z2). G94 X20 Z-2: down to Z-2 at r30, across to r10, back to Z2,
        // out to r30. Then Z-4 with R-1 (the cut starts at Z-5 at A's X, runs to (10, -4)).
        let m = moves("G0 X60. Z2.\nG94 X20. Z-2. F0.2\nZ-4. R-1.\n");
        assert_eq!(
            m,
            [
                (R, 30.0, 2.0),
                (R, 30.0, -2.0),
                (F, 10.0, -2.0),
                (F, 10.0, 2.0),
                (R, 30.0, 2.0),
                (R, 30.0, -5.0),
                (F, 10.0, -4.0),
                (F, 10.0, 2.0),
                (R, 30.0, 2.0),
            ]
        );
    }

    #[test]
    fn g94_in_radius_programming() {
        // X is a radius: A (30, 2), G94 X10 W-4 (Z -2) R-1: in to Z-3 at r30, across to
        // (10, -2), back to Z2, out to r30.
        assert_eq!(
            moves_with("G0 X30. Z2.\nG94 X10. W-4. R-1. F0.2\n", true),
            [
                (R, 30.0, 2.0),
                (R, 30.0, -3.0),
                (F, 10.0, -2.0),
                (F, 10.0, 2.0),
                (R, 30.0, 2.0)
            ]
        );
    }

    #[test]
    fn g92_threads_the_box_at_the_lead() {
        // A (X40 → r20, Z5). G92 X29.2 Z-30 F1.5: in to r14.6, thread to Z-30 at 1.5
        // per revolution, out to r20, back to Z5; X28.6: the next pass at r14.3.
        let m = moves("G0 X40. Z5.\nG92 X29.2 Z-30. F1.5\nX28.6\n");
        assert_eq!(
            m,
            [
                (R, 20.0, 5.0),
                (R, 14.6, 5.0),
                (T(1.5), 14.6, -30.0),
                (R, 20.0, -30.0),
                (R, 20.0, 5.0),
                (R, 14.3, 5.0),
                (T(1.5), 14.3, -30.0),
                (R, 20.0, -30.0),
                (R, 20.0, 5.0),
            ]
        );
    }

    #[test]
    fn g92_taper_and_chamfer() {
        // G76's P: m 01, chamfer 10 (1.0 lead), angle 60. Lead 2: γ = 2 along Z at 45°.
        // A (r20, Z5), end X30 (r15) Z-25, R-1: the thread from (14, 5) to (15, -25), 30
        // long in Z for 1 in X. The chamfer starts 2 before the end, at Z-23: X
        // 14 + 28/30 = 14.933333333; it runs out to (15 + 2, -25) = (17, -25).
        // Feeds: the taper 2·√(900+1)/30 = 2.001110803 up to Z-23 (the same line); the
        // chamfer moves 2.066666667 in X, 2 in Z: X is longer, 2·2.875960·/2.066667 =
        // 2.78318124.
        let m = moves("G76 P011060 Q100 R0.05\nG0 X40. Z5.\nG92 X30. Z-25. R-1. F2.\n");
        assert_eq!(
            m,
            [
                (R, 20.0, 5.0),
                (R, 14.0, 5.0),
                (T(2.001110803), 14.933333333, -23.0),
                (T(2.78318124), 17.0, -25.0),
                (R, 20.0, -25.0),
                (R, 20.0, 5.0),
            ]
        );
    }

    #[test]
    fn g92_taper_and_chamfer_in_radius_programming() {
        // Radius programming. G76's P: m 01, chamfer 05 (0.5 lead), angle 60; lead 2: γ = 1
        // along Z at 45°. A (r20, Z5); X15 is r15 (a diameter would be r7.5), R-1.5 (a
        // radius either way): the thread from (13.5, 5) to (15, −25), 1.5 in X over 30 in Z.
        // The chamfer starts γ before the end, at Z −24: X 13.5 + 1.5·29/30 = 14.95; it runs
        // out to (15 + 1, −25). Rapid out to r20 at Z −25, back to Z5.
        // Feeds: the taper, Z the longer axis, 2·√(1.5² + 30²)/30 = √902.25/15; the chamfer
        // moves 1.05 in X and 1 in Z: X the longer, 2·√(1.05² + 1)/1.05 = 2·1.45/1.05.
        // X14.6: the next pass with Z and R kept, 0.4 lower on the radius: from (13.1, 5),
        // the chamfer from (14.55, −24) to (15.6, −25), the same feeds.
        let m = moves_with(
            "G76 P010560 Q100 R0.05\nG0 X20. Z5.\nG92 X15. Z-25. R-1.5 F2.\nX14.6\n",
            true,
        );
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let (taper, chamfer) = (T(r(902.25f64.sqrt() / 15.0)), T(r(2.0 * 1.45 / 1.05)));
        let mut want = vec![(R, 20.0, 5.0)];
        for x in [15.0, 14.6] {
            want.extend([
                (R, r(x - 1.5), 5.0),
                (taper, r(x - 1.5 + 1.5 * 29.0 / 30.0), -24.0),
                (chamfer, r(x + 1.0), -25.0),
                (R, 20.0, -25.0),
                (R, 20.0, 5.0),
            ]);
        }
        assert_eq!(m, want);
    }

    #[test]
    fn box_cycles_need_feed_and_no_compensation() {
        assert_eq!(
            alarm("G0 X40. Z5.\nG92 X29.2 Z-30.\n"),
            (AlarmCode::NoFeed, 2, 1)
        );
        assert_eq!(
            alarm("T0101 G0 X40. Z5.\nG42 G1 X38. F0.2\nG90 X30. Z-10.\n"),
            (AlarmCode::ForbiddenWithTrc, 3, 1)
        );
    }
}
