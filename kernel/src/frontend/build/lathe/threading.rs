//! The multiple threading cycle (Fanuc 0i-TF "Multiple threading cycle (G76)") and the
//! thread pass it shares with G92:
//!
//! ```text
//! G76 P(m)(r)(a) Q(Δdmin) R(d)        m finishing passes, chamfer r (0.1 L), tool angle a;
//!                                     minimum depth of cut, finishing allowance: stored
//! G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L)  the thread's end at its root; taper i (radius, start
//!                                     less end); thread height k; first depth Δd; lead L
//! ```
//!
//! Pass n cuts at depth Dₙ below the crest: D₁ = Δd, then Dₙ = Dₙ₋₁ + max(Δd(√n − √(n−1)),
//! Δdmin) (a constant amount of cut per pass, never less than Δdmin), up to k − d; then m
//! passes at k. The tool feeds in along the flank: a pass at depth D is shifted back
//! against the thread's direction by (k − D)·tan(a/2), so the last passes cut on the
//! programmed points. Each pass: rapid from A to its start, the thread (with the chamfer),
//! rapid out to A's X, rapid back to A.

use super::super::super::block::*;
use super::super::super::fault::{fault, R};
use super::super::super::interpreter::Interpreter;
use super::super::super::words::{int_value, Words};
use super::super::expand::{Expansion, Step};
use super::{at, push_all, rapid, sign, LatheRun, ThreadData};
use crate::alarm::AlarmCode;

/// The steps of one thread pass from A: rapid to `from`, the thread to `to` (the last
/// `gamma` of Z as a chamfer out by `gamma` at the lead), rapid out to A's level on axis
/// `out` (X for a longitudinal thread, Z for a face thread), rapid to A.
pub(in crate::frontend) fn thread_pass(
    a: Pos,
    from: Pos,
    to: Pos,
    lead: f64,
    gamma: f64,
    out_axis: usize,
) -> heapless::Vec<Step, 8> {
    let mut q = heapless::Vec::new();
    let mut push = |s| {
        let _ = q.push(s);
    };
    push(rapid(from));
    let out = if gamma > 0.0 {
        let (sx, sz) = (sign(a[0] - to[0]), sign(to[2] - from[2]));
        let zc = to[2] - sz * gamma;
        let t = (zc - from[2]) / (to[2] - from[2]);
        let xc = from[0] + t * (to[0] - from[0]);
        push(Step::Thread {
            to: at(xc, zc, a[1]),
            lead,
            stop: false,
        });
        at(to[0] + sx * gamma, to[2], a[1])
    } else {
        to
    };
    push(Step::Thread {
        to: out,
        lead,
        stop: true,
    });
    let mut lifted = out;
    lifted[out_axis] = a[out_axis];
    push(rapid(lifted));
    push(rapid(a));
    q
}

/// The passes of a G76 cycle still to come.
#[derive(Clone, Debug)]
pub(super) struct Passes {
    a: Pos,
    /// The root at the thread's end, and the taper i.
    end: Pos,
    taper: f64,
    height: f64,
    first: f64,
    data: ThreadData,
    lead: f64,
    gamma: f64,
    /// Outer (1) or inner (−1) thread; the thread's direction along Z.
    sx: f64,
    sz: f64,
    depths: Depths,
}

/// The depths of cut one after the other.
#[derive(Clone, Copy, Debug)]
struct Depths {
    n: u32,
    last: f64,
    rough_done: bool,
    finishing_left: u32,
}

impl Depths {
    fn new(finishing: u32) -> Self {
        Depths {
            n: 0,
            last: 0.0,
            rough_done: false,
            finishing_left: finishing,
        }
    }

    /// The next pass's depth below the crest, if any.
    fn next(&mut self, first: f64, min: f64, rough_end: f64, height: f64) -> Option<f64> {
        if !self.rough_done {
            self.n += 1;
            let n = f64::from(self.n);
            let step = first * (libm::sqrt(n) - libm::sqrt(n - 1.0));
            let mut d = self.last + step.max(min);
            if d >= rough_end - 1e-9 {
                d = rough_end;
                self.rough_done = true;
            }
            self.last = d;
            return Some(d);
        }
        if self.finishing_left == 0 {
            return None;
        }
        self.finishing_left -= 1;
        Some(height)
    }
}

impl Passes {
    fn depth(&mut self) -> Option<f64> {
        let rough_end = self.height - self.data.allowance;
        self.depths
            .next(self.first, self.data.min_depth, rough_end, self.height)
    }

    pub(super) fn refill(&mut self, q: &mut heapless::Deque<Step, 8>) {
        let Some(d) = self.depth() else { return };
        let h = self.height - d;
        let tan = libm::tan(self.data.angle.to_radians() / 2.0);
        let shift = -self.sz * h * tan;
        let (a, end) = (self.a, self.end);
        let from = at(end[0] + self.taper + self.sx * h, a[2] + shift, a[1]);
        let to = at(end[0] + self.sx * h, end[2] + shift, a[1]);
        push_all(q, &thread_pass(a, from, to, self.lead, self.gamma, 0));
    }
}

impl Interpreter<'_> {
    /// Step 8 of a G76 block: its data (no X Z U W) or its thread.
    pub(super) fn multiple_threading(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        col: usize,
    ) -> R<()> {
        if w.axis[0].is_none() && w.axis[2].is_none() {
            return self.thread_data(w, new);
        }
        self.lathe_allowed(new, col, "a threading cycle")?;
        self.no_other_words(w, true)?;
        self.cycle_feed(new, col, "a threading cycle's lead")?;
        let height = self.increments(w.p, new.units, "the thread height P")?;
        let first = self.increments(w.q, new.units, "the first depth of cut Q")?;
        let (Some(height), Some(first)) = (height, first) else {
            return Err(fault(
                AlarmCode::MissingValue,
                col,
                "a threading cycle needs the thread height P and the first depth of cut Q",
            ));
        };
        for (v, word) in [(height, w.p), (first, w.q)] {
            if v <= 0.0 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    word.map_or(col, |x| x.pos()),
                    "the thread height and the depth of cut must be greater than 0",
                ));
            }
        }
        let data = self.lathe.thread;
        if data.allowance >= height {
            return Err(fault(
                AlarmCode::BadNumber,
                col,
                format!(
                    "the finishing allowance {} is not less than the thread height {height}",
                    data.allowance
                ),
            ));
        }
        let a = self.cur;
        let end = self.end_point(w, new, a)?;
        let taper = w.radius.map_or(0.0, |r| self.length(r, new.units));
        let (sx, sz) = (sign(a[0] - end[0]), sign(end[2] - a[2]));
        let crests = [end[0] + taper + sx * height, end[0] + sx * height];
        if sx == 0.0 || sz == 0.0 || crests.iter().any(|c| sx * (a[0] - c) < 0.0) {
            return Err(fault(
                AlarmCode::BadNumber,
                col,
                "the start point must lie outside the thread's crest in X and off its end in Z",
            ));
        }
        let gamma = self.chamfer(new.feed, a, end, col)?;
        let passes = Passes {
            a,
            end,
            taper,
            height,
            first,
            data,
            lead: new.feed,
            gamma,
            sx,
            sz,
            depths: Depths::new(data.finishing),
        };
        self.count_thread_passes(&passes, col)?;
        self.expand(
            Expansion::lathe(LatheRun::new(super::Passes::Threading(passes))),
            new,
        );
        Ok(())
    }

    /// Every pass after the first counts as a loop pass (`program.max_loop_iterations`).
    fn count_thread_passes(&mut self, p: &Passes, col: usize) -> R<()> {
        let max = u64::from(self.md.program.max_loop_iterations);
        let mut probe = p.clone();
        let mut n = 0u64;
        while probe.depth().is_some() {
            n += 1;
            if n > max + 1 {
                break;
            }
        }
        self.add_passes(n.saturating_sub(1), col)
    }

    /// `G76 P(m)(r)(a) Q(Δdmin) R(d)`: the words written replace the stored ones.
    fn thread_data(&mut self, w: &Words, new: &ModalState) -> R<()> {
        let mut data = self.lathe.thread;
        if let Some(p) = w.p {
            let v = int_value(p.value, p.at, "P")?;
            let (m, r, a) = (v / 10000, v / 100 % 100, v % 100);
            if !(1..=99).contains(&m) || v >= 1_000_000 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    p.at,
                    "P is mmrraa: m finishing passes 01 … 99, chamfer rr, angle aa",
                ));
            }
            // 0i-TF: the tool angle is one of 80, 60, 55, 30, 29, 0.
            if ![80, 60, 55, 30, 29, 0].contains(&a) {
                return Err(fault(
                    AlarmCode::BadNumber,
                    p.at,
                    format!("tool angle {a}: one of 80, 60, 55, 30, 29, 0"),
                ));
            }
            (data.finishing, data.chamfer, data.angle) = (m, r, f64::from(a));
        }
        if let Some(q) = self.increments(w.q, new.units, "the minimum depth of cut Q")? {
            data.min_depth = q;
        }
        if let Some(r) = w.radius {
            let d = self.non_negative(r, new.units, "the finishing allowance R")?;
            data.allowance = d;
        }
        self.lathe.thread = data;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{alarm, moves, moves_with, How::*};
    use crate::alarm::AlarmCode;

    /// Depths 0.4, 0.5656854249, then Δdmin 0.15 wins: 0.7156854249, 0.8656854249, then
    /// k − d = 0.9, then k = 1 (m 1). tan 30° = 0.5773502692; the shift back along +Z
    /// (the thread runs to −Z) is (1 − D)·tan 30°.
    const DEPTHS: [f64; 6] = [0.4, 0.565685425, 0.715685425, 0.865685425, 0.9, 1.0];

    #[test]
    fn g76_cuts_constant_amounts_along_the_flank() {
        // A (X40 → r20, Z5); root at the end X34 (r17) Z-30, k 1 (P1000), Δd 0.4 (Q400),
        // Δdmin 0.15 (Q150), d 0.1, lead 2. Pass at depth D: X 17 + (1 − D), Z shifted by
        // (1 − D)·0.5773502692:
        //   D 0.4: X 17.6, shift 0.346410162     D 0.565685425: X 17.434314575, 0.250751
        //   …                                    D 1: X 17, shift 0.
        let m = moves("G76 P010060 Q150 R0.1\nG0 X40. Z5.\nG76 X34. Z-30. P1000 Q400 F2.\n");
        assert_eq!(m.len(), 1 + 6 * 4);
        let tan = 0.5773502692;
        let r = |v: f64| (v * 1e6).round() / 1e6;
        for (k, d) in DEPTHS.iter().enumerate() {
            let pass = &m[1 + 4 * k..5 + 4 * k];
            let (x, s) = (17.0 + (1.0 - d), (1.0 - d) * tan);
            let got: Vec<_> = pass.iter().map(|&(h, x, z)| (h, r(x), r(z))).collect();
            assert_eq!(
                got,
                [
                    (R, r(x), r(5.0 + s)),
                    (T(2.0), r(x), r(-30.0 + s)),
                    (R, 20.0, r(-30.0 + s)),
                    (R, 20.0, 5.0)
                ],
                "pass {k}"
            );
        }
        // The first pass by hand: (17.6, 5.346410) in, (17.6, -29.653590) thread.
        assert_eq!(
            (r(m[1].1), r(m[1].2), r(m[2].2)),
            (17.6, 5.34641, -29.65359)
        );
    }

    #[test]
    fn g76_inner_taper_with_chamfer_in_radius_programming() {
        // Radius programming. A (r10, Z3); an inner thread (X up), root at the end r12
        // Z-10, taper i −0.5 (the root at the start r11.5), k 0.6, Δd 0.6 (one rough pass
        // at k − d = 0.5), d 0.1, m 2, chamfer 05 (0.5 L = 0.5), angle 0: no shift.
        //   rough D 0.5: h 0.1, start X 11.5 − 0.1 = 11.4 at Z3, end X 11.9 at Z-10; the
        //   chamfer from Z-9.5 (X 11.4 + 0.5·12.5/13 = 11.880769231) to (11.9 − 0.5, -10).
        //   finishing (twice) D 0.6: start 11.5, end 12; chamfer from (11.980769231, -9.5)
        //   to (11.5, -10).
        let m = moves_with(
            "G76 P020500 Q0 R0.1\nG0 X10. Z3.\nG76 X12. Z-10. R-0.5 P600 Q600 F1.\n",
            true,
        );
        let pos: Vec<(f64, f64)> = m.iter().map(|&(_, x, z)| (x, z)).collect();
        let pass = |s: f64, xc: f64, e: f64| {
            [
                (s, 3.0),
                (xc, -9.5),
                (e - 0.5, -10.0),
                (10.0, -10.0),
                (10.0, 3.0),
            ]
        };
        let mut want = vec![(10.0, 3.0)];
        want.extend(pass(11.4, 11.880769231, 11.9));
        want.extend(pass(11.5, 11.980769231, 12.0));
        want.extend(pass(11.5, 11.980769231, 12.0));
        assert_eq!(pos, want);
        assert!(matches!(m[2].0, T(_)) && matches!(m[3].0, T(_)) && m[4].0 == R);
    }

    #[test]
    fn g76_alarms() {
        // No height.
        assert_eq!(
            alarm("G0 X40. Z5.\nG76 X34. Z-30. Q400 F2.\n"),
            (AlarmCode::MissingValue, 2, 1)
        );
        // Q with a decimal point.
        assert_eq!(
            alarm("G0 X40. Z5.\nG76 X34. Z-30. P1000 Q0.4 F2.\n"),
            (AlarmCode::BadNumber, 2, 22)
        );
        // A inside the crest: root r17, crest r18 > A's r17.5.
        assert_eq!(
            alarm("G0 X35. Z5.\nG76 X34. Z-30. P1000 Q400 F2.\n"),
            (AlarmCode::BadNumber, 2, 1)
        );
        // The allowance not less than the height; a bad tool angle.
        assert_eq!(
            alarm("G76 P010060 R1.\nG0 X40. Z5.\nG76 X34. Z-30. P1000 Q400 F2.\n"),
            (AlarmCode::BadNumber, 3, 1)
        );
        assert_eq!(alarm("G76 P010045\n"), (AlarmCode::BadNumber, 1, 5));
        // No lead.
        assert_eq!(
            alarm("G0 X40. Z5.\nG76 X34. Z-30. P1000 Q400\n"),
            (AlarmCode::NoFeed, 2, 1)
        );
    }
}
