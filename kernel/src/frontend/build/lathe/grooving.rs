//! End face peck drilling and outer/inner diameter grooving (Fanuc 0i-TF "End face peck
//! drilling cycle (G74)", "Outer diameter/internal diameter drilling cycle (G75)"):
//!
//! ```text
//! G74 R(e)                              the return after each peck: stored
//! G74 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F     pecks of Δk along Z to Z, columns Δi apart in X
//!                                       from A's X to X; relief Δd at the bottom
//! G75 R(e)
//! G75 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F     pecks of Δi along X to X, grooves Δk apart in Z
//! ```
//!
//! One column (groove): from A's level on the peck axis, feed Δ in, rapid back by e, feed
//! on (Δ + e), … to the bottom; relief by Δd along the step axis, rapid back out to A's
//! level, rapid to the next column (the last one ends on X, resp. Z). After the last one,
//! rapid back to A. P and Q are least input increments without a decimal point.

use super::super::super::block::*;
use super::super::super::fault::{fault, R};
use super::super::super::interpreter::Interpreter;
use super::super::super::words::Words;
use super::super::expand::{Expansion, Step};
use super::{cut, rapid, sign, LatheRun};
use crate::alarm::AlarmCode;
use crate::dialect::LatheCycle;

/// The pecks still to come.
#[derive(Clone, Debug)]
pub(super) struct Pecks {
    a: Pos,
    /// The peck axis and the step axis (Z and X for G74, X and Z for G75).
    p: usize,
    s: usize,
    bottom: f64,
    last_column: f64,
    depth: f64,
    step: f64,
    back: f64,
    relief: f64,
    /// The column's place on the step axis; how deep the column is so far; finished.
    column: f64,
    done_depth: f64,
    over: bool,
}

impl Pecks {
    pub(super) fn refill(&mut self, q: &mut heapless::Deque<Step, 8>) {
        if self.over {
            return;
        }
        let (p0, dir) = (self.a[self.p], sign(self.bottom - self.a[self.p]));
        let total = (self.bottom - p0).abs();
        let mut here = self.a;
        here[self.s] = self.column;
        here[self.p] = p0 + dir * self.done_depth;
        // Moves that would not move (no return e, no relief) are left out.
        let mut go = |from: &mut Pos, to: Pos, step: fn(Pos) -> Step| {
            if *from != to {
                let _ = q.push_back(step(to));
                *from = to;
            }
        };
        let mut to = here;
        if self.done_depth > 0.0 {
            to[self.p] = p0 + dir * (self.done_depth - self.back).max(0.0);
            go(&mut here, to, rapid);
        }
        self.done_depth = (self.done_depth + self.depth).min(total);
        to[self.p] = p0 + dir * self.done_depth;
        go(&mut here, to, cut);
        if self.done_depth < total - 1e-9 {
            return;
        }
        // The bottom: relief, out, on to the next column or back to A.
        to[self.s] += self.relief;
        go(&mut here, to, rapid);
        to[self.p] = p0;
        go(&mut here, to, rapid);
        let left = (self.last_column - self.column).abs();
        if left <= 1e-9 {
            go(&mut here, self.a, rapid);
            self.over = true;
            return;
        }
        self.column += sign(self.last_column - self.column) * self.step.min(left);
        to[self.s] = self.column;
        go(&mut here, to, rapid);
        self.done_depth = 0.0;
    }
}

impl Interpreter<'_> {
    /// Step 8 of a G74 or G75 block: the return e (no X Z U W) or the cycle.
    pub(super) fn pecking(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        kind: LatheCycle,
        col: usize,
    ) -> R<()> {
        if w.axis[0].is_none() && w.axis[2].is_none() {
            if let Some(r) = w.radius {
                let e = self.non_negative(r, new.units, "the return R")?;
                self.lathe.peck_return = e;
            }
            return Ok(());
        }
        self.lathe_allowed(new, col, "a peck cycle")?;
        self.no_other_words(w, true)?;
        self.cycle_feed(new, col, "a peck cycle")?;
        let a = self.cur;
        let end = self.end_point(w, new, a)?;
        let di = self.increments(w.p, new.units, "the amount P")?;
        let dk = self.increments(w.q, new.units, "the amount Q")?;
        // G74 pecks Δk along Z with columns Δi apart in X; G75 the other way round.
        let (p, s, depth, step) = match kind {
            LatheCycle::FacePecking => (2, 0, dk, di),
            _ => (0, 2, di, dk),
        };
        let (moves_p, moves_s) = ((end[p] - a[p]).abs() > 1e-9, (end[s] - a[s]).abs() > 1e-9);
        let depth = depth.filter(|d| *d > 0.0);
        let step = if moves_s {
            step.filter(|d| *d > 0.0)
        } else {
            Some(step.unwrap_or(0.0))
        };
        let (Some(depth), Some(step), true) = (depth, step, moves_p) else {
            return Err(fault(
                AlarmCode::MissingValue,
                col,
                "a peck cycle needs a depth along its axis and its amounts P and Q greater than 0",
            ));
        };
        let dd = w.radius.map_or(0.0, |r| self.length(r, new.units));
        // Several columns: the relief goes back towards A's side; one column: as signed.
        let relief = if moves_s {
            -sign(end[s] - a[s]) * dd.abs()
        } else {
            dd
        };
        let columns = if moves_s {
            libm::ceil((end[s] - a[s]).abs() / step) + 1.0
        } else {
            1.0
        };
        let pecks = libm::ceil((end[p] - a[p]).abs() / depth);
        self.add_passes((columns * pecks) as u64 - 1, col)?;
        let pecks = Pecks {
            a,
            p,
            s,
            bottom: end[p],
            last_column: end[s],
            depth,
            step,
            back: self.lathe.peck_return,
            relief,
            column: a[s],
            done_depth: 0.0,
            over: false,
        };
        self.expand(
            Expansion::lathe(LatheRun::new(super::Passes::Pecking(pecks))),
            new,
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{alarm, moves, moves_with, How::*};
    use crate::alarm::AlarmCode;

    #[test]
    fn g74_pecks_along_z_in_columns_along_x() {
        // A (X0, Z1); e 0.5. Holes to Z-5 by 2.5 (Q2500); X goes 0 → X8 (r4) in steps of
        // 3 (P3000): columns at r0, r3, r4; relief 0 (R0 not written).
        // Column: feed to Z-1.5 (2.5 below Z1), back 0.5 to Z-1, feed to -4, back to -3.5,
        // feed to -5 (6 in all); no relief (R not written), out to Z1, on to the next.
        let m = moves("G74 R0.5\nG0 X0. Z1.\nG74 X8. Z-5. P3000 Q2500 F0.1\n");
        let col = |x: f64, next: f64| {
            vec![
                (F, x, -1.5),
                (R, x, -1.0),
                (F, x, -4.0),
                (R, x, -3.5),
                (F, x, -5.0),
                (R, x, 1.0),
                (R, next, 1.0),
            ]
        };
        let mut want = vec![(R, 0.0, 1.0)];
        want.extend(col(0.0, 3.0));
        want.extend(col(3.0, 4.0));
        want.extend(col(4.0, 0.0));
        assert_eq!(m, want);
    }

    #[test]
    fn g75_grooves_along_x_with_relief_in_radius_programming() {
        // Radius programming. A (r22, Z-10); e 1. Grooves down to r18 by 2.5 (P2500),
        // from Z-10 to Z-13 in steps of 2 (Q2000): grooves at Z-10, -12, -13; relief
        // R0.2 back towards A's side (+Z).
        // Groove: feed to r19.5, back to 20.5, feed to 18, relief Z+0.2, out to r22, on.
        let m = moves_with(
            "G75 R1.\nG0 X22. Z-10.\nG75 X18. W-3. P2500 Q2000 R0.2 F0.05\n",
            true,
        );
        let groove = |z: f64, next: f64| {
            vec![
                (F, 19.5, z),
                (R, 20.5, z),
                (F, 18.0, z),
                (R, 18.0, z + 0.2),
                (R, 22.0, z + 0.2),
                (R, 22.0, next),
            ]
        };
        let mut want = vec![(R, 22.0, -10.0)];
        want.extend(groove(-10.0, -12.0));
        want.extend(groove(-12.0, -13.0));
        want.extend(groove(-13.0, -10.0));
        assert_eq!(m, want);
    }

    #[test]
    fn g74_in_radius_programming_takes_x_and_u_as_radii() {
        // Radius programming: A (r10, Z1), e 0.5. U-5 ends the columns at r5 (a diameter
        // would end them at r7.5); P2000 steps 2 on the radius: columns r10, 8, 6 and the
        // last, shorter step, 5. Pecks of 2.5 (Q2500) to Z-6 (7 deep): feed to Z-1.5, back
        // 0.5 to -1, feed to -4, back to -3.5, feed to -6. Relief R0.3 back towards A's side
        // (+X: the columns go towards smaller X), rapid out to Z1, on to the next column;
        // after the last, back to A.
        let m = moves_with(
            "G74 R0.5\nG0 X10. Z1.\nG74 U-5. Z-6. P2000 Q2500 R0.3 F0.1\n",
            true,
        );
        let column = |x: f64, next: f64| {
            vec![
                (F, x, -1.5),
                (R, x, -1.0),
                (F, x, -4.0),
                (R, x, -3.5),
                (F, x, -6.0),
                (R, x + 0.3, -6.0),
                (R, x + 0.3, 1.0),
                (R, next, 1.0),
            ]
        };
        let mut want = vec![(R, 10.0, 1.0)];
        for (x, next) in [(10.0, 8.0), (8.0, 6.0), (6.0, 5.0), (5.0, 10.0)] {
            want.extend(column(x, next));
        }
        assert_eq!(m, want);
    }

    #[test]
    fn a_single_groove_without_p_stepping() {
        // G75 with Z at A's: one groove, Q not needed; diameter programming X30 → r15.
        // No return e: feed to r16, on to r15, out to r20 (A: the return to A is no move).
        let m = moves("G0 X40. Z-8.\nG75 X30. Z-8. P4000 F0.05\n");
        assert_eq!(
            m,
            [
                (R, 20.0, -8.0),
                (F, 16.0, -8.0),
                (F, 15.0, -8.0),
                (R, 20.0, -8.0)
            ]
        );
    }

    #[test]
    fn peck_cycles_need_their_amounts() {
        assert_eq!(
            alarm("G0 X40. Z-8.\nG75 X30. Z-12. P4000 F0.05\n"),
            (AlarmCode::MissingValue, 2, 1)
        );
        assert_eq!(
            alarm("G0 X0. Z1.\nG74 Z-5. Q2.5 F0.1\n"),
            (AlarmCode::BadNumber, 2, 10)
        );
        assert_eq!(alarm("G74 R-1.\n"), (AlarmCode::BadNumber, 1, 5));
    }
}
