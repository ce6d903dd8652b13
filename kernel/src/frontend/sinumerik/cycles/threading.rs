//! Thread cutting (808D Turning "Thread cutting - CYCLE97"; 840D sl Cycles "Thread cutting -
//! CYCLE97"):
//!
//! ```text
//! CYCLE97(PIT, MPIT, SPL, FPL, DM1, DM2, APP, ROP, TDEP, FAL, IANG, NSP, NRC, NID, VARI,
//!         NUMT, _VRT)
//! ```
//!
//! The thread runs from (SPL, DM1) to (FPL, DM2): along Z where its taper is 45° or less (a
//! longitudinal thread), along X beyond (a face thread). The run-in APP brings its start
//! forward and the run-out ROP its end back, along the thread. The cycle's start point lies
//! at the run-in point, lifted _VRT (1 mm where empty) off the crest, outside the thread.
//! TDEP less FAL is cut in NRC roughing passes: of a constant depth (VARI 1, 2), or of a
//! constant cross-section (VARI 3, 4: after pass n the depth is (TDEP − FAL)·√(n/NRC)); FAL
//! in one pass; then NID idle passes at TDEP. VARI 1 and 3 cut an outside thread, 2 and 4 an
//! inside one. With IANG the tool feeds along the flank: a pass at depth D lies (TDEP − D)·
//! tan|IANG| back against the thread's direction (IANG < 0: on alternate flanks). Each pass
//! is the Fanuc lathe's thread pass: rapid in, the thread, rapid out to the lift-off level,
//! rapid back to the start point, where the cycle ends.

use super::super::super::block::Pos;
use super::super::super::build::{push_all, thread_pass, Step};
use super::super::super::fault::R;
use super::lathe::{rapid, Lathe};
use super::tapping::pitch;

const PIT: usize = 0;
const MPIT: usize = 1;
const SPL: usize = 2;
const FPL: usize = 3;
const DM1: usize = 4;
const DM2: usize = 5;
const APP: usize = 6;
const ROP: usize = 7;
const TDEP: usize = 8;
const FAL: usize = 9;
const IANG: usize = 10;
const NSP: usize = 11;
const NRC: usize = 12;
const NID: usize = 13;
const VARI: usize = 14;
const NUMT: usize = 15;
const VRT: usize = 16;

/// The lift-off off the crest where _VRT is empty (808D Turning: "always by 1 mm above the
/// programmed thread diameter").
const LIFT_OFF: f64 = 1.0;

/// A CYCLE97 thread and the passes handed out so far.
#[derive(Clone, Debug)]
pub struct Thread {
    /// The crest at the run-in and the run-out point (machine coordinates).
    start: Pos,
    end: Pos,
    /// The cycle's start point: the run-in point lifted off the crest.
    home: Pos,
    /// Whether the tool must first go to `home`.
    approach: bool,
    /// The axis the thread runs along, the axis of its depth, and the way into the part
    /// along that axis (+1 or −1).
    along: usize,
    across: usize,
    into: f64,
    lead: f64,
    depth: f64,
    allowance: f64,
    /// tan |IANG|, and whether the flanks alternate (IANG < 0).
    tan: f64,
    alternate: bool,
    rough: u32,
    idle: u32,
    /// VARI 3, 4: a constant cross-section.
    section: bool,
    /// Passes handed out so far.
    done: u32,
}

impl Thread {
    /// Every pass: roughing, the finishing pass where FAL is given, the idle passes.
    pub(super) fn passes(&self) -> u32 {
        self.rough + u32::from(self.allowance > 0.0) + self.idle
    }

    /// The depth below the crest of pass `k` (1 …).
    fn depth_of(&self, k: u32) -> Option<f64> {
        if k == 0 || k > self.passes() {
            return None;
        }
        if k > self.rough {
            return Some(self.depth);
        }
        let part = f64::from(k) / f64::from(self.rough);
        let rough = self.depth - self.allowance;
        Some(if self.section {
            rough * libm::sqrt(part)
        } else {
            rough * part
        })
    }

    pub(super) fn refill(&mut self, q: &mut heapless::Deque<Step, 8>) {
        if self.approach {
            self.approach = false;
            let _ = q.push_back(rapid(self.home));
        }
        self.done = self.done.saturating_add(1);
        let Some(d) = self.depth_of(self.done) else {
            return;
        };
        let dir = (self.end[self.along] - self.start[self.along]).signum();
        // 840D sl Cycles, IANG: "+" along one flank, "−" on alternate flanks.
        let side = if self.alternate && self.done.is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        let shift = side * dir * (self.depth - d) * self.tan;
        let place = |mut p: Pos| {
            p[self.across] += self.into * d;
            p[self.along] += shift;
            p
        };
        let pass = thread_pass(
            self.home,
            place(self.start),
            place(self.end),
            self.lead,
            0.0,
            self.across,
        );
        push_all(q, &pass);
    }
}

/// The thread of a CYCLE97 call, its parameters checked.
pub(super) fn thread(l: &Lathe) -> R<Thread> {
    let vari = l.machining_type(VARI, 1, 4)?;
    // PIT and MPIT are entered without sign: the spindle's direction makes a left-hand thread.
    let lead = pitch(&l.p, MPIT, PIT, l.unit())?
        .map(f64::abs)
        .ok_or_else(|| l.bad(PIT, "CYCLE97 needs the thread's pitch: PIT or MPIT"))?;
    if l.p.get(NSP) != 0.0 {
        return Err(l.not_built(NSP, "NSP (the start angle of the thread) is not supported"));
    }
    if l.whole(NUMT, 0, 1, "NUMT").is_err() {
        return Err(l.not_built(NUMT, "NUMT: multiple-start threads are not supported"));
    }
    let (depth, allowance) = (l.len(TDEP), l.len(FAL));
    if depth <= 0.0 {
        return Err(l.bad(TDEP, "the thread depth TDEP must be greater than 0"));
    }
    if allowance >= depth {
        return Err(l.bad(FAL, "the finishing allowance FAL is not less than TDEP"));
    }
    let iang = l.p.get(IANG);
    if iang.abs() >= 90.0 {
        return Err(l.bad(
            IANG,
            "the infeed angle IANG lies between -90 and 90 degrees",
        ));
    }
    let rough = l.whole(NRC, 1, 9999, "NRC")?;
    let idle = l.whole(NID, 0, 9999, "NID")?;
    let mut t = geometry(l, vari)?;
    (t.lead, t.depth, t.allowance) = (lead, depth, allowance);
    (t.tan, t.alternate) = (libm::tan(iang.abs().to_radians()), iang < 0.0);
    (t.rough, t.idle, t.section) = (rough, idle, vari >= 3);
    Ok(t)
}

/// The thread's line, run-in and run-out, and the start point.
fn geometry(l: &Lathe, vari: u32) -> R<Thread> {
    let (p1, p2) = (l.point(SPL, DM1), l.point(FPL, DM2));
    let d: [f64; 3] = std::array::from_fn(|i| p2[i] - p1[i]);
    if d[0].abs() < 1e-9 && d[2].abs() < 1e-9 {
        return Err(l.bad(FPL, "the thread has no length (SPL, DM1 = FPL, DM2)"));
    }
    // 840D sl Cycles, CYCLE97: up to 45° a longitudinal thread, beyond a face thread.
    let (along, across) = if d[2].abs() >= d[0].abs() {
        (2, 0)
    } else {
        (0, 2)
    };
    // VARI 1, 3: outside; on a face thread into the face from +Z [unconfirmed].
    let into = if vari % 2 == 1 { -1.0 } else { 1.0 };
    let step =
        |p: Pos, by: f64| -> Pos { std::array::from_fn(|i| p[i] + by * d[i] / d[along].abs()) };
    let (start, end) = (step(p1, -l.len(APP)), step(p2, l.len(ROP)));
    let lift = if l.p.given(VRT) { l.len(VRT) } else { LIFT_OFF };
    let outer = if into < 0.0 {
        start[across].max(end[across])
    } else {
        start[across].min(end[across])
    };
    let mut home = start;
    home[across] = outer - into * lift;
    Ok(Thread {
        start,
        end,
        home,
        approach: home != l.at,
        along,
        across,
        into,
        lead: 0.0,
        depth: 0.0,
        allowance: 0.0,
        tan: 0.0,
        alternate: false,
        rough: 1,
        idle: 0,
        section: false,
        done: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::super::lathe::tests::{alarm, moves, r6, How::*};
    use crate::alarm::AlarmCode;

    const START: &str = "N10 G18 G90 G95 T1 D1 S500 M3\nN20 G0 X50 Z10\n";

    fn cycle(call: &str) -> Vec<(super::super::lathe::tests::How, f64, f64)> {
        let m = moves(&format!("{START}{call}\nG0 X60\n"));
        m[1..m.len() - 1].to_vec()
    }

    /// One pass at radius `x` from Z `z0` to `z1`, lifted to `lift`, back to `home`.
    fn pass(
        x: f64,
        z0: f64,
        z1: f64,
        lead: f64,
        lift: f64,
        home: f64,
    ) -> Vec<(super::super::lathe::tests::How, f64, f64)> {
        vec![
            (R, r6(x), r6(z0)),
            (T(lead), r6(x), r6(z1)),
            (R, lift, r6(z1)),
            (R, lift, home),
        ]
    }

    #[test]
    fn constant_depth_outside_thread_in_diameter() {
        // M20x1.5: PIT 1.5, SPL 0, FPL -30, DM1 = DM2 = 20 (radius 10), APP 3, ROP 2,
        // TDEP 0.92, FAL 0.12, NRC 4, NID 1, VARI 1. Rough depth 0.8 in 4: 0.2 0.4 0.6 0.8,
        // then FAL to 0.92, then one idle pass at 0.92. Run-in Z3, run-out Z-32; start point
        // radius 10 + 1 = 11 at Z3.
        let m = cycle("CYCLE97(1.5, , 0, -30, 20, 20, 3, 2, 0.92, 0.12, 0, 0, 4, 1, 1)");
        let mut want = vec![(R, 11.0, 3.0)];
        for d in [0.2, 0.4, 0.6, 0.8, 0.92, 0.92] {
            want.extend(pass(10.0 - d, 3.0, -32.0, 1.5, 11.0, 3.0));
        }
        assert_eq!(m, want);
    }

    #[test]
    fn constant_section_inside_thread_in_radius_along_the_flank() {
        // DIAMOF: DM1 = DM2 = 15 is a radius. Inside thread VARI 4, TDEP 0.6, FAL 0, NRC 3:
        // depths 0.6·√(1/3) = 0.346410162, 0.6·√(2/3) = 0.489897949, 0.6. IANG 30: the pass
        // at depth D lies (0.6 − D)·tan 30° back against the thread (which runs to −Z), i.e.
        // towards +Z: 0.146410162 and 0.063397460, then 0. Run-in APP 2: Z2, ROP 0: Z-20.
        // Start point: radius 15 − 1 = 14 at Z2; the passes at radius 15 + D.
        let m = cycle("DIAMOF\nCYCLE97(2, , 0, -20, 15, 15, 2, 0, 0.6, 0, 30, 0, 3, 0, 4)");
        let tan = (30f64).to_radians().tan();
        let mut want = vec![(R, 14.0, 2.0)];
        for d in [
            0.6 * (1.0f64 / 3.0).sqrt(),
            0.6 * (2.0f64 / 3.0).sqrt(),
            0.6,
        ] {
            let s = (0.6 - d) * tan;
            want.extend(pass(15.0 + d, 2.0 + s, -20.0 + s, 2.0, 14.0, 2.0));
        }
        assert_eq!(m, want);
        // By hand: the first pass at radius 15.346410 from Z 2 + (0.6 − 0.346410)·0.577350
        // = 2.146410.
        assert_eq!((m[1].1, m[1].2), (15.34641, 2.14641));
    }

    #[test]
    fn alternating_flanks_swap_sides_from_pass_to_pass() {
        // IANG −30, constant depth, TDEP 0.9, NRC 3: depths 0.3 0.6 0.9; shifts against the
        // thread's direction (−Z, so towards +Z) on pass 1, with it on pass 2:
        // +0.6·tan 30° = +0.346410, −0.3·tan 30° = −0.173205, 0.
        let m = cycle("CYCLE97(1, , 0, -10, 20, 20, 0, 0, 0.9, 0, -30, 0, 3, 0, 1)");
        let zs: Vec<f64> = m.iter().skip(1).step_by(4).map(|p| p.2).collect();
        assert_eq!(zs, [0.34641, -0.173205, 0.0]);
        let xs: Vec<f64> = m.iter().skip(1).step_by(4).map(|p| p.1).collect();
        assert_eq!(xs, [9.7, 9.4, 9.1]);
    }

    #[test]
    fn a_face_thread_runs_along_x_and_lifts_off_in_z() {
        // SPL = FPL = 0, DM1 40 → DM2 10 (radius 20 → 5): a face thread along −X, pitch 2
        // (MPIT 14), APP 1 (radius), ROP 0; TDEP 0.5 in 1 pass, VARI 1: into the face
        // towards −Z. Start point X radius 21, Z 0 + 1 = 1; the pass at Z −0.5 from X 21
        // to 5, out to Z1, back to X21.
        let m = cycle("CYCLE97(, 14, 0, 0, 40, 10, 1, 0, 0.5, 0, 0, 0, 1, 0, 1)");
        assert_eq!(
            m,
            [
                (R, 21.0, 1.0),
                (R, 21.0, -0.5),
                (T(2.0), 5.0, -0.5),
                (R, 5.0, 1.0),
                (R, 21.0, 1.0)
            ]
        );
    }

    #[test]
    fn a_taper_thread_extends_its_line_by_the_run_in() {
        // DM1 20 → DM2 24 over Z0 → Z-20 (radius +2 over 20): APP 5 goes back along the
        // line to Z5, radius 10 − 0.5 = 9.5; ROP 0. Outside: lift 1 mm over the larger crest
        // (radius 12): 13. TDEP 0.5, NRC 1: the pass from (9, 5) to (11.5, -20); the thread
        // feed per revolution along the path: 1·√(2.5² + 25²)/25 = 1.004987562.
        let m = cycle("CYCLE97(1, , 0, -20, 20, 24, 5, 0, 0.5, 0, 0, 0, 1, 0, 1)");
        assert_eq!(
            m,
            [
                (R, 13.0, 5.0),
                (R, 9.0, 5.0),
                (T(1.004988), 11.5, -20.0),
                (R, 13.0, -20.0),
                (R, 13.0, 5.0)
            ]
        );
    }

    #[test]
    fn the_modal_state_after_the_call_is_the_one_before() {
        // G0 and F0.1 before the call: a bare X after it is a rapid, a G1 feeds at 0.1 (not
        // at the pitch 1.5).
        let m = moves(&format!(
            "{START}F0.1\nCYCLE97(1.5, , 0, -30, 20, 20, 3, 2, 0.92, 0, 0, 0, 2, 0, 1)\nX60\nG1 X70\n"
        ));
        assert_eq!(m[m.len() - 2..], [(R, 30.0, 3.0), (F(0.1), 35.0, 3.0)]);
    }

    #[test]
    fn bad_parameters_are_alarms_at_their_place() {
        let at = |call: &str| alarm(&format!("{START}{call}\n"));
        // VARI 5 (column 56 on line 3): the machining type, 61002 as for CYCLE95.
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 0, 1, 0, 5)"),
            (AlarmCode::CycleMachiningType, 3, 56)
        );
        // PIT contradicts MPIT 10 (1.5).
        assert_eq!(
            at("CYCLE97(1, 10, 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 0, 1, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 9)
        );
        // No pitch; FAL not less than TDEP; NRC 0; a thread without length.
        assert_eq!(
            at("CYCLE97(, , 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 0, 1, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 1)
        );
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0.5, 0, 0, 1, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 41)
        );
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 50)
        );
        assert_eq!(
            at("CYCLE97(1, , 0, 0, 20, 20, 0, 0, 0.5, 0, 0, 0, 1, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 17)
        );
        // TDEP 0; IANG 90; a fractional NID.
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0, 0, 0, 0, 1, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 36)
        );
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0, 90, 0, 1, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 44)
        );
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 0, 1, 1.5, 1)"),
            (AlarmCode::CycleParameter, 3, 53)
        );
        // A start angle and two starts are not built.
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 90, 1, 0, 1)"),
            (AlarmCode::NotSupported, 3, 47)
        );
        assert_eq!(
            at("CYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 0, 1, 0, 1, 2)"),
            (AlarmCode::NotSupported, 3, 59)
        );
        // Under nose radius compensation.
        assert_eq!(
            at("G42 G1 X40 F0.2\nCYCLE97(1, , 0, -20, 20, 20, 0, 0, 0.5, 0, 0, 0, 1, 0, 1)").0,
            AlarmCode::ForbiddenWithTrc
        );
    }
}
