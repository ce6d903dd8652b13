//! Canned cycles for hole machining (Fanuc 0i-MF operator's manual, "Canned cycle for
//! drilling"): a cycle code makes every following block with a position (or Z, R) machine a
//! hole there, until G80 or a motion code cancels it. Each hole runs the six operations of
//! the manual:
//!
//! ```text
//! 1 positioning in the plane at rapid      4 at the hole bottom (dwell, spindle)
//! 2 rapid to the R point                   5 retraction (to the R point)
//! 3 machining to the hole bottom           6 rapid to the return level (G98: the initial
//!                                            level, G99: the R point)
//! ```
//!
//! The drilling axis is the plane's normal (Z in G17). Z (the bottom) and R are absolute
//! under G90; under G91 R counts from the initial level and Z from the R point. Z, R, Q
//! and P stay as modal data while the cycle mode lasts; K repeats the hole (under G91 each
//! repetition moves by the programmed increments; K0 stores the data and drills nothing).
//!
//! One module per family says what a hole does between the R point and the return:
//! [`drilling`] (G81 G82 G73 G83), [`tapping`] (G84 G74), [`boring`] (G85 G86 G89 G76 G87).

mod boring;
mod drilling;
mod tapping;

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::Words;
use super::expand::{Expansion, Step};
use crate::alarm::AlarmCode;
use crate::machine_data::BoringShift;

/// What a hole cycle does, independent of its G number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleKind {
    /// Feed to the bottom, rapid out (Fanuc G81).
    Drill,
    /// Feed, dwell at the bottom, rapid out (G82).
    SpotDrill,
    /// Pecks of Q with a short retraction between them (G73).
    HighSpeedPeck,
    /// Pecks of Q, out to the R point after each (G83).
    Peck,
    /// Tapping: feed in with the spindle forward, reverse at the bottom, feed out (G84).
    Tap,
    /// Left-hand tapping: the spindle the other way round (G74).
    LeftTap,
    /// Feed in, feed out (G85).
    Bore,
    /// Feed in, spindle stop at the bottom, rapid out (G86).
    BoreSpindleStop,
    /// Feed in, dwell, feed out (G89).
    BoreDwell,
    /// Feed in, orient the spindle, shift off the wall, rapid out (G76).
    FineBore,
    /// Back boring from below, upwards (G87).
    BackBore,
}

/// The cycle mode in force: its kind and modal data.
#[derive(Clone, Copy, Debug)]
pub struct CycleMode {
    pub kind: CycleKind,
    /// The drilling axis' position when the cycle mode began (machine coordinates).
    pub initial: f64,
    /// Z and R as written (mm) with the distance mode they were written in.
    z: Option<(f64, Distance)>,
    r: Option<(f64, Distance)>,
    /// Peck depth or shift amount Q (mm), dwell P (s).
    q: f64,
    dwell: f64,
}

impl CycleMode {
    pub fn new(kind: CycleKind, initial: f64, old: Option<CycleMode>) -> Self {
        match old {
            // A change of cycle keeps the modal data (and the initial level).
            Some(o) => CycleMode { kind, ..o },
            None => CycleMode {
                kind,
                initial,
                z: None,
                r: None,
                q: 0.0,
                dwell: 0.0,
            },
        }
    }
}

/// One hole's geometry along the drilling axis `n` (machine coordinates).
#[derive(Clone, Copy, Debug)]
pub struct Hole {
    pub kind: CycleKind,
    pub n: usize,
    pub initial: f64,
    pub r: f64,
    pub bottom: f64,
    pub q: f64,
    pub dwell: f64,
    /// Return to the initial level (G98) or the R point (G99).
    pub to_initial: bool,
    /// The boring cycles' shift off the wall, in the plane.
    pub shift: Pos,
    pub peck_retract: f64,
    pub peck_clearance: f64,
    /// The spindle's direction before the hole (the taps reverse it and turn it back).
    pub spindle: SpindleDir,
}

impl Hole {
    /// +1 if the hole goes towards larger coordinates from R to the bottom.
    fn dir(&self) -> f64 {
        if self.bottom >= self.r {
            1.0
        } else {
            -1.0
        }
    }

    fn return_level(&self) -> f64 {
        if self.to_initial || self.kind == CycleKind::BackBore {
            self.initial
        } else {
            self.r
        }
    }
}

/// Where a cycle's expansion stands.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    Position,
    Machining,
    Retract,
    Done,
}

/// The holes still to machine of one cycle block, streamed step by step.
#[derive(Clone, Debug)]
pub struct Drilling {
    hole: Hole,
    /// Where the steps handed out so far end.
    at: Pos,
    /// The next hole's position in the plane (the drilling axis' value is ignored).
    target: Pos,
    /// Added to `target` for each repetition (G91 K).
    step: Pos,
    holes_left: u32,
    phase: Phase,
    /// How deep the pecks have gone below the R point (mm, positive).
    depth: f64,
    queue: heapless::Deque<Step, 8>,
}

impl Drilling {
    pub fn next(&mut self) -> Option<Step> {
        if self.done() {
            None
        } else {
            self.queue.pop_front()
        }
    }

    /// No step is left (works out the next ones if it must).
    pub fn done(&mut self) -> bool {
        loop {
            if !self.queue.is_empty() {
                return false;
            }
            if !self.refill() {
                return true;
            }
        }
    }

    fn refill(&mut self) -> bool {
        match self.phase {
            Phase::Position => {
                self.position();
                self.phase = Phase::Machining;
                self.depth = 0.0;
            }
            Phase::Machining => {
                if self.machine() {
                    self.phase = Phase::Retract;
                }
            }
            Phase::Retract => {
                self.retract();
                self.holes_left -= 1;
                self.phase = if self.holes_left == 0 {
                    Phase::Done
                } else {
                    for i in 0..3 {
                        self.target[i] += self.step[i];
                    }
                    Phase::Position
                };
            }
            Phase::Done => return false,
        }
        true
    }

    /// Operations 1 and 2: over the hole at the level the tool is at, then down to R
    /// (back boring first orients and shifts, and goes down to R below the part).
    fn position(&mut self) {
        let n = self.hole.n;
        let mut over = self.target;
        over[n] = self.at[n];
        self.go(over, true);
        if self.hole.kind == CycleKind::BackBore {
            boring::back_bore_entry(self);
        } else {
            self.along(self.hole.r, true);
        }
    }

    /// Operations 3 and 4; true when the tool is at the bottom and done there.
    fn machine(&mut self) -> bool {
        match self.hole.kind {
            CycleKind::Drill
            | CycleKind::SpotDrill
            | CycleKind::HighSpeedPeck
            | CycleKind::Peck => drilling::machine(self),
            CycleKind::Tap | CycleKind::LeftTap => tapping::machine(self),
            _ => boring::machine(self),
        }
    }

    /// Operations 5 and 6.
    fn retract(&mut self) {
        match self.hole.kind {
            CycleKind::Tap | CycleKind::LeftTap => tapping::retract(self),
            CycleKind::Drill
            | CycleKind::SpotDrill
            | CycleKind::HighSpeedPeck
            | CycleKind::Peck => drilling::retract(self),
            _ => boring::retract(self),
        }
    }

    /// A move to `to`, left out if the tool is there.
    fn go(&mut self, to: Pos, rapid: bool) {
        if to != self.at {
            self.push(Step::Move {
                to,
                rapid,
                axes: None,
                feed: None,
            });
            self.at = to;
        }
    }

    /// A move along the drilling axis to `level`.
    fn along(&mut self, level: f64, rapid: bool) {
        let mut to = self.at;
        to[self.hole.n] = level;
        self.go(to, rapid);
    }

    /// The boring cycles' shift off the wall (`sign` 1) or back (-1), at rapid.
    fn shift(&mut self, sign: f64) {
        let mut to = self.at;
        for (t, s) in to.iter_mut().zip(self.hole.shift) {
            *t += sign * s;
        }
        self.go(to, true);
    }

    fn push(&mut self, s: Step) {
        // Refills push at most four steps into an empty queue of eight.
        let _ = self.queue.push_back(s);
    }
}

impl Interpreter<'_> {
    /// Step 8 in a cycle mode: the hole (or holes) at the block's position.
    pub(in crate::frontend::build) fn canned_cycle(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        block_col: usize,
    ) -> R<()> {
        let Some(mut mode) = self.cycle else {
            return Ok(());
        };
        if new.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                block_col,
                "a canned cycle cannot run while tool radius compensation is active",
            ));
        }
        self.no_additional_axes(w, "a canned cycle block")?;
        let n = new.plane.normal as usize;
        self.cycle_data(w, new, n, &mut mode)?;
        self.cycle = Some(mode);
        let repeats = self.repeats(w)?;
        if repeats == 0 {
            return Ok(());
        }
        let hole = self.hole(&mode, new, n, block_col)?;
        // Every peck and every repetition after the first is a loop pass (nested in loops
        // and calls, they stay bounded).
        let pecks = match hole.kind {
            CycleKind::HighSpeedPeck | CycleKind::Peck => {
                libm::ceil((hole.bottom - hole.r).abs() / hole.q).max(1.0) as u64
            }
            _ => 1,
        };
        self.add_passes(repeats as u64 * pecks - 1, block_col)?;
        feed_for_cycle(new, block_col)?;
        let (target, step) = if self.coords.frame.active() {
            self.framed_hole_position(w, new, n, block_col)?
        } else {
            self.hole_position(w, new, n)
        };
        self.expansion = Some(Expansion::drilling(Drilling {
            hole,
            at: self.cur,
            target,
            step,
            holes_left: repeats,
            phase: Phase::Position,
            depth: 0.0,
            queue: heapless::Deque::new(),
        }));
        self.expand_first(new);
        Ok(())
    }

    /// Z, R, Q and P of the block into the cycle's modal data.
    fn cycle_data(&self, w: &Words, new: &ModalState, n: usize, mode: &mut CycleMode) -> R<()> {
        if let Some(v) = w.axis[n] {
            mode.z = Some((self.length(v, new.units), new.distance));
        }
        if let Some(v) = w.radius {
            mode.r = Some((self.length(v, new.units), new.distance));
        }
        if let Some(v) = w.q {
            let q = self.length(v, new.units);
            if q <= 0.0 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    v.at,
                    "Q must be greater than 0",
                ));
            }
            mode.q = q;
        }
        if let Some(p) = w.p {
            if !(0.0..=1e9).contains(&p.value) {
                return Err(fault(AlarmCode::BadNumber, p.at, "dwell P out of range"));
            }
            mode.dwell = p.value / 1000.0;
        }
        if let Some(v) = w.centre[0].or(w.centre[1]) {
            return Err(fault(
                AlarmCode::Syntax,
                v.at,
                "I and J have no meaning in a canned cycle block (the shift is Q)",
            ));
        }
        Ok(())
    }

    /// K: how often the hole is machined (1 if not written).
    fn repeats(&self, w: &Words) -> R<u32> {
        let Some(k) = w.centre[2] else { return Ok(1) };
        let v = k.value;
        if !(0.0..=9999.0).contains(&v) || v.fract() != 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                k.at,
                format!("repeat count K{v} is not a whole number 0…9999"),
            ));
        }
        Ok(v as u32)
    }

    /// The hole's levels in machine coordinates from the modal data.
    fn hole(&self, mode: &CycleMode, new: &ModalState, n: usize, at: usize) -> R<Hole> {
        let offset = self.zero(new.work_offset)[n];
        let (Some((z, zd)), Some((r, rd))) = (mode.z, mode.r) else {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "a canned cycle needs the hole bottom and the R point (Z and R)",
            ));
        };
        let r = match rd {
            Distance::Absolute => r + offset,
            Distance::Incremental => mode.initial + r,
        };
        let bottom = match zd {
            Distance::Absolute => z + offset,
            Distance::Incremental => r + z,
        };
        let needs_q = matches!(mode.kind, CycleKind::HighSpeedPeck | CycleKind::Peck);
        if needs_q && mode.q <= 0.0 {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "a peck cycle needs the depth of cut Q",
            ));
        }
        let max = self.md.program.max_loop_iterations as f64;
        if needs_q && (bottom - r).abs() / mode.q > max {
            return Err(fault(
                AlarmCode::LoopLimit,
                at,
                format!("more than {max} pecks (machine data program.max_loop_iterations)"),
            ));
        }
        Ok(Hole {
            kind: mode.kind,
            n,
            initial: mode.initial,
            r,
            bottom,
            q: mode.q,
            dwell: mode.dwell,
            to_initial: self.cycle_to_initial,
            shift: self.boring_shift(new.plane, mode.q),
            peck_retract: self.md.program.peck_retract,
            peck_clearance: self.md.program.peck_clearance,
            spindle: new.spindle_dir,
        })
    }

    /// The shift vector of G76/G87: Q in the machine data's direction within the plane.
    fn boring_shift(&self, plane: Plane, q: f64) -> Pos {
        let mut v = [0.0; 3];
        let (axis, sign) = match self.md.program.boring_shift {
            BoringShift::PlusX => (plane.abscissa, 1.0),
            BoringShift::MinusX => (plane.abscissa, -1.0),
            BoringShift::PlusY => (plane.ordinate, 1.0),
            BoringShift::MinusY => (plane.ordinate, -1.0),
        };
        v[axis as usize] = sign * q;
        v
    }

    /// The first hole's position (plane axes from the words, the rest where they are) and,
    /// under G91, the step to each further hole.
    fn hole_position(&self, w: &Words, new: &ModalState, n: usize) -> (Pos, Pos) {
        let offset = self.zero(new.work_offset);
        let (mut target, mut step) = (self.cur, [0.0; 3]);
        for i in (0..3).filter(|&i| i != n) {
            if let Some(a) = w.axis[i] {
                target[i] = self.axis_target(a, i, new, self.cur[i], offset[i]);
                if new.distance == Distance::Incremental {
                    step[i] = target[i] - self.cur[i];
                }
            }
        }
        (target, step)
    }
}

impl Interpreter<'_> {
    /// [`Interpreter::hole_position`] under a frame: the position in program coordinates,
    /// mapped; the frame may not touch the drilling axis.
    fn framed_hole_position(
        &self,
        w: &Words,
        new: &ModalState,
        n: usize,
        at: usize,
    ) -> R<(Pos, Pos)> {
        let frame = self.coords.frame;
        if !frame.keeps_axis(n) {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "a canned cycle under a frame that mirrors, scales or turns the drilling axis",
            ));
        }
        let start = self.program_position(new, at)?;
        let (mut prog, mut delta) = (start, [0.0; 3]);
        for i in (0..3).filter(|&i| i != n) {
            if let Some(a) = w.axis[i] {
                let v = self.length(a, new.units);
                prog[i] = match new.distance {
                    Distance::Absolute => v,
                    Distance::Incremental => {
                        delta[i] = v;
                        start[i] + v
                    }
                };
            }
        }
        let zero = self.zero(new.work_offset);
        let q = frame.apply(prog);
        let mut target: Pos = std::array::from_fn(|i| q[i] + zero[i]);
        target[n] = self.cur[n];
        let (a, b) = (frame.apply(delta), frame.apply([0.0; 3]));
        let step = std::array::from_fn(|i| a[i] - b[i]);
        Ok((target, step))
    }
}

/// A cycle feeds: an F must be in force.
fn feed_for_cycle(new: &ModalState, at: usize) -> R<()> {
    if new.feed > 0.0 {
        Ok(())
    } else {
        Err(fault(
            AlarmCode::NoFeed,
            at,
            "a canned cycle needs a feed F",
        ))
    }
}

/// Whether a block in cycle mode machines a hole: it has a position, Z or R.
pub fn makes_hole(w: &Words) -> bool {
    w.axis.iter().any(Option::is_some) || w.radius.is_some()
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::frontend::{Block, MotionKind};

    /// (rapid?, end) of every move, dwells as (false, [dwell, -1, -1]), M words as
    /// (true, [M, -2, -2]).
    fn steps(src: &str) -> Vec<(bool, [f64; 3])> {
        let blocks = run("fanuc", src).unwrap_or_else(|a| panic!("{a}"));
        blocks.iter().flat_map(step_of).collect()
    }

    fn step_of(b: &Block) -> Vec<(bool, [f64; 3])> {
        let mut out = Vec::new();
        for w in b.words.iter().filter(|w| w.address == b'M') {
            out.push((true, [w.value, -2.0, -2.0]));
        }
        if let Some(m) = b.motion {
            out.push((m.kind == MotionKind::Rapid, m.end));
        }
        if let Some(d) = b.dwell {
            out.push((false, [d, -1.0, -1.0]));
        }
        out
    }

    const START: &str = "G90 G17 G0 X0. Y0. Z50.\n";

    #[test]
    fn drilling_goes_to_r_feeds_and_returns_to_the_level_of_g98_or_g99() {
        let s = steps(&format!(
            "{START}G99 G81 X10. Y10. Z-5. R2. F100.\nX20.\nG98 Y20.\nG80\n"
        ));
        let want = [
            (true, [0.0, 0.0, 50.0]),
            // hole 1: over it at the initial level 50, R 2, bottom -5, back to R (G99)
            (true, [10.0, 10.0, 50.0]),
            (true, [10.0, 10.0, 2.0]),
            (false, [10.0, 10.0, -5.0]),
            (true, [10.0, 10.0, 2.0]),
            // hole 2 from the R level
            (true, [20.0, 10.0, 2.0]),
            (false, [20.0, 10.0, -5.0]),
            (true, [20.0, 10.0, 2.0]),
            // hole 3, G98: back to the initial level 50
            (true, [20.0, 20.0, 2.0]),
            (false, [20.0, 20.0, -5.0]),
            (true, [20.0, 20.0, 50.0]),
        ];
        assert_eq!(s, want);
    }

    #[test]
    fn pecks_follow_q_and_the_machine_data_distances() {
        // G83, Q4 to a bottom 12 below R: pecks to 4, 8, 12 below R = -2, -6, -10; out to R
        // after each and down again to 1 mm (peck_clearance) above the depth reached.
        let s = steps(&format!("{START}G98 G83 X5. Z-10. R2. Q4. F100.\nG80\n"));
        let z: Vec<f64> = s.iter().skip(1).map(|(_, p)| p[2]).collect();
        assert_eq!(
            z,
            [50.0, 2.0, -2.0, 2.0, -1.0, -6.0, 2.0, -5.0, -10.0, 50.0]
        );
        // G73: pecks to 4 and 8 below R (-2, -6), back by 1 mm (peck_retract) after each,
        // the last to the bottom -7.
        let s = steps(&format!("{START}G99 G73 X5. Z-7. R2. Q4. F100.\nG80\n"));
        let z: Vec<f64> = s.iter().skip(1).map(|(_, p)| p[2]).collect();
        assert_eq!(z, [50.0, 2.0, -2.0, -1.0, -6.0, -5.0, -7.0, 2.0]);
    }

    #[test]
    fn incremental_r_and_z_and_k_repeat_the_hole_along_the_increment() {
        // G91: R 48 below the initial level 50 (R = 2), Z 7 below R (bottom -5); K3 moves
        // by X10 before each hole.
        let s = steps(&format!(
            "{START}G91 G99 G81 X10. Z-7. R-48. K3 F100.\nG80\n"
        ));
        let holes: Vec<[f64; 3]> = s.iter().filter(|(r, _)| !r).map(|(_, p)| *p).collect();
        assert_eq!(
            holes,
            [[10.0, 0.0, -5.0], [20.0, 0.0, -5.0], [30.0, 0.0, -5.0]]
        );
        // K0 stores the data and drills nothing; the next position drills with it.
        let s = steps(&format!("{START}G81 X10. Z-5. R2. K0 F100.\nX20.\nG80\n"));
        assert_eq!(s.iter().filter(|(r, _)| !r).count(), 1);
    }

    /// The steps after the hole's bottom (X5 Z-8) of a cycle block run with the spindle on.
    fn after_bottom(cycle: &str) -> Vec<(bool, [f64; 3])> {
        let s = steps(&format!("{START}M3 S500\n{cycle}\nG80\n"));
        let bottom = s
            .iter()
            .position(|p| *p == (false, [5.0, 0.0, -8.0]))
            .unwrap();
        s[bottom + 1..].to_vec()
    }

    #[test]
    fn taps_and_boring_cycles_work_the_spindle_at_the_bottom() {
        assert_eq!(
            after_bottom("G98 G84 X5. Z-8. R2. P500 F100."),
            [
                (false, [0.5, -1.0, -1.0]),
                (true, [4.0, -2.0, -2.0]),
                (false, [5.0, 0.0, 2.0]),
                (true, [3.0, -2.0, -2.0]),
                (true, [5.0, 0.0, 50.0]),
            ]
        );
        // G76: orient, shift +X by Q, out at rapid, shift back, spindle on again.
        assert_eq!(
            after_bottom("G98 G76 X5. Z-8. R2. Q0.5 F100."),
            [
                (true, [19.0, -2.0, -2.0]),
                (true, [5.5, 0.0, -8.0]),
                (true, [5.5, 0.0, 50.0]),
                (true, [5.0, 0.0, 50.0]),
                (true, [3.0, -2.0, -2.0]),
            ]
        );
    }

    #[test]
    fn a_cycle_needs_its_data_and_no_compensation() {
        let a = run("fanuc", "G0 Z10.\nG81 X1. R2. F100.\n").unwrap_err();
        assert_eq!((a.code, a.line), (AlarmCode::MissingValue, 2));
        let a = run("fanuc", "G0 Z10.\nG83 X1. Z-5. R2. F100.\n").unwrap_err();
        assert_eq!(a.message, "a peck cycle needs the depth of cut Q");
        let src = "G17 G0 X0. Y0. Z10.\nG41 D1 G1 X10. F100.\nG81 X20. Z-5. R2.\n";
        assert_eq!(
            run("fanuc", src).unwrap_err().code,
            AlarmCode::ForbiddenWithTrc
        );
        // A motion code ends the cycle mode: X moves again.
        let s = steps(&format!("{START}G81 X10. Z-5. R2. F100.\nG0 X30.\n"));
        assert_eq!(s.last(), Some(&(true, [30.0, 0.0, 50.0])));
    }
}
