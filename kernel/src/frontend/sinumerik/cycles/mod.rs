//! SINUMERIK drilling cycles CYCLE81 … CYCLE89 and CYCLE840 (808D / 828D / 840D sl
//! Programming Manual Cycles, "Drilling cycles"; docs/research/sinumerik-language.md §12). A
//! call machines one hole where the tool stands, along the tool axis, between the planes its
//! parameters give (all absolute, in workpiece coordinates):
//!
//! ```text
//!   RTP ─────────── retraction plane: the tool leaves the hole to here at rapid
//!   RFP + SDIS ──── the safety plane: rapid from where the tool stands down to here
//!   RFP ─────────── reference plane (the workpiece surface)
//!   DP ──────────── final depth; or RFP − DPR when DPR is given (DPR wins)
//! ```
//!
//! One module per family says what a hole does between the safety plane and the retraction:
//! [`drilling`] (CYCLE81 82 83), [`tapping`] (CYCLE84 840), [`boring`] (CYCLE85 … 89). The
//! moves stream out of the [`CycleRun`] one block each, every move at its own feed; the feed
//! in force before the call is in force again after it.

mod boring;
mod contour;
mod drilling;
mod grooving;
mod lathe;
mod stock_removal;
mod tapping;
mod threading;

pub use lathe::SinumerikPasses;
pub use stock_removal::StockRemovalRun;

use super::super::block::*;
use super::super::build::Step;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use crate::alarm::AlarmCode;
use crate::dialect::MEffect;

/// The drilling cycles by name, and how many parameters each takes (Cycles, "Drilling").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleName {
    Drill81,
    Drill82,
    DeepHole83,
    Tap84,
    Tap840,
    Bore85,
    Bore86,
    Bore87,
    Bore88,
    Bore89,
    /// The turning cycles (cycles/lathe.rs).
    Groove93,
    Thread97,
}

const CYCLES: &[(&str, CycleName, usize)] = &[
    ("CYCLE81", CycleName::Drill81, 5),
    ("CYCLE82", CycleName::Drill82, 6),
    ("CYCLE83", CycleName::DeepHole83, 17),
    ("CYCLE84", CycleName::Tap84, 18),
    ("CYCLE840", CycleName::Tap840, 14),
    ("CYCLE85", CycleName::Bore85, 8),
    ("CYCLE86", CycleName::Bore86, 11),
    ("CYCLE87", CycleName::Bore87, 6),
    ("CYCLE88", CycleName::Bore88, 7),
    ("CYCLE89", CycleName::Bore89, 6),
    ("CYCLE93", CycleName::Groove93, 18),
    ("CYCLE97", CycleName::Thread97, 17),
];

/// The longest parameter list (CYCLE84, CYCLE93).
const MAX_PARAMS: usize = 18;

impl CycleName {
    /// The cycle named `name` (any case).
    pub fn of(name: &[u8]) -> Option<CycleName> {
        CYCLES
            .iter()
            .find(|c| c.0.as_bytes().eq_ignore_ascii_case(name))
            .map(|c| c.1)
    }

    fn entry(self) -> &'static (&'static str, CycleName, usize) {
        // Every name has its row.
        CYCLES.iter().find(|c| c.1 == self).unwrap_or(&CYCLES[0])
    }

    pub fn text(self) -> &'static str {
        self.entry().0
    }

    /// A turning cycle (cuts in the Z-X plane) rather than a hole.
    fn turns(self) -> bool {
        matches!(self, CycleName::Groove93 | CycleName::Thread97)
    }
}

/// A call's parameters as written: position k is `None` where it was left empty (`, ,`) or
/// beyond the last one written; an empty position counts as 0 (Job planning, "Subprograms
/// with parameter transfer").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    v: [Option<f64>; MAX_PARAMS],
    /// Where each parameter stands (for alarms).
    at: [usize; MAX_PARAMS],
    /// Where the call's name stands.
    pub call: usize,
}

impl Params {
    pub fn get(&self, k: usize) -> f64 {
        self.v[k].unwrap_or(0.0)
    }

    fn given(&self, k: usize) -> bool {
        self.v[k].is_some_and(|v| v != 0.0)
    }

    /// Where parameter k stands, or the call's name where it was left out.
    fn at(&self, k: usize) -> usize {
        if self.v[k].is_some() {
            self.at[k]
        } else {
            self.call
        }
    }
}

/// The parameter positions every drilling cycle shares.
const RTP: usize = 0;
const RFP: usize = 1;
const SDIS: usize = 2;
const DP: usize = 3;
const DPR: usize = 4;
/// The dwell at the bottom (all but CYCLE81, CYCLE83 and CYCLE87).
const DTB: usize = 5;

/// One hole along the tool axis `n`, its planes in machine coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Hole {
    pub name: CycleName,
    pub n: usize,
    pub rtp: f64,
    pub rfp: f64,
    pub safety: f64,
    pub bottom: f64,
    /// +1 where the hole goes towards larger coordinates.
    pub dir: f64,
    /// The feed in force at the call, and whether it is per revolution.
    pub feed: f64,
    pub per_rev: bool,
    /// The spindle's speed and direction at the call.
    pub speed: f64,
    pub spindle: SpindleDir,
    /// The working plane at the call.
    pub plane: Plane,
    /// The dialect's table (the spindle functions SDAC and SDIR name by number).
    pub dialect: &'static crate::dialect::Dialect,
    /// mm per program unit (25.4 under G70/G700).
    pub unit: f64,
    /// A level on the tool axis (workpiece coordinates, mm) in machine coordinates:
    /// `scale · v + shift` (the frame and the zero).
    scale: f64,
    shift: f64,
    pub p: Params,
}

impl Hole {
    /// A level of the tool axis (workpiece coordinates, mm) in machine coordinates.
    fn map(&self, v: f64) -> f64 {
        self.scale * v + self.shift
    }

    /// The depth of `level` below the reference plane (mm, positive into the part).
    fn depth_of(&self, level: f64) -> f64 {
        (level - self.rfp) * self.dir
    }

    /// The level `depth` below the reference plane.
    fn level(&self, depth: f64) -> f64 {
        self.rfp + self.dir * depth
    }

    /// A dwell parameter in seconds (negative: spindle revolutions, Cycles "DTB").
    fn dwell(&self, k: usize) -> R<Option<f64>> {
        let v = self.p.get(k);
        if v > 0.0 {
            return Ok(Some(v));
        }
        if v == 0.0 {
            return Ok(None);
        }
        if self.speed <= 0.0 {
            return Err(fault(
                AlarmCode::CycleParameter,
                self.p.at(k),
                format!("a dwell in revolutions ({v}) needs the spindle speed S"),
            ));
        }
        Ok(Some(-v * 60.0 / self.speed))
    }
}

/// The moves of one cycle call still to hand out.
#[derive(Clone, Debug)]
pub struct CycleRun {
    hole: Hole,
    /// Where the steps handed out so far end.
    at: Pos,
    queue: heapless::Deque<Step, 12>,
    /// The spindle speed the steps so far leave.
    speed_now: f64,
    /// CYCLE83: the infeeds still to come.
    deep: Option<drilling::Deep>,
}

impl CycleRun {
    pub fn next(&mut self) -> Option<Step> {
        if self.done() {
            None
        } else {
            self.queue.pop_front()
        }
    }

    /// No step is left (works out the next infeed if it must).
    pub fn done(&mut self) -> bool {
        while self.queue.is_empty() {
            let Some(mut deep) = self.deep.take() else {
                return true;
            };
            if drilling::infeed(self, &mut deep) {
                self.deep = Some(deep);
            }
        }
        false
    }

    /// A move to `to` at rapid or at `feed` (left out where the tool stands).
    fn go(&mut self, to: Pos, feed: Option<f64>) {
        if to != self.at {
            self.push(Step::Move {
                to,
                rapid: feed.is_none(),
                axes: None,
                feed: Some(feed.unwrap_or(self.hole.feed)),
            });
            self.at = to;
        }
    }

    /// Along the tool axis to `level`, at rapid (`None`) or at a feed.
    fn along(&mut self, level: f64, feed: Option<f64>) {
        let mut to = self.at;
        to[self.hole.n] = level;
        self.go(to, feed);
    }

    fn push(&mut self, s: Step) {
        // A family pushes at most eleven steps into an empty queue.
        let _ = self.queue.push_back(s);
    }

    /// The spindle's direction an SDAC/SDIR/SDR parameter names by the number of its
    /// spindle function in the dialect's table; `None` for 0 or empty.
    fn spindle_code(&self, k: usize) -> R<Option<SpindleDir>> {
        let v = self.hole.p.get(k);
        if v == 0.0 {
            return Ok(None);
        }
        let dir = self
            .hole
            .dialect
            .mcodes
            .iter()
            .find_map(|m| match m.effect {
                MEffect::Spindle(d) if f64::from(m.code) == v && d != SpindleDir::Orient => Some(d),
                _ => None,
            });
        match dir {
            Some(d) => Ok(Some(d)),
            None => Err(fault(
                AlarmCode::CycleParameter,
                self.hole.p.at(k),
                format!("spindle direction {v}: the number of a spindle function (clockwise, counter-clockwise, stop)"),
            )),
        }
    }

    /// The spindle after the cycle as parameter k says (empty: as at the call).
    fn spindle_after(&mut self, k: usize) -> R<()> {
        let dir = self.spindle_code(k)?.unwrap_or(self.hole.spindle);
        self.push(Step::Spindle(dir));
        Ok(())
    }
}

impl Interpreter<'_> {
    /// A drilling cycle call `CYCLE8x(…)` at the cursor (its name): the hole where the tool
    /// stands, its first step into the block being built.
    pub(in crate::frontend) fn drilling_cycle(&mut self, c: &mut Cursor, at: usize) -> R<()> {
        if stock_removal::is_cycle95(c) {
            return self.stock_removal_cycle(c, at);
        }
        let (name, p) = self.cycle_call(c, at)?;
        let new = self.block.modal;
        let expansion = if name.turns() {
            self.sinumerik_lathe_cycle(name, p, &new)?
        } else {
            super::super::build::Expansion::cycle(self.cycle_run(name, p, &new)?)
        };
        self.start_cycle(at, expansion, new);
        Ok(())
    }

    /// The cycle called at `at` begins: its first step into the block being built, the
    /// rest from `expansion`.
    fn start_cycle(
        &mut self,
        at: usize,
        expansion: super::super::build::Expansion,
        mut new: ModalState,
    ) {
        let col = super::super::lexer::column(self.src, self.blk_line_start, at);
        let (line, number, program) = (self.blk_line, self.blk_number, self.block.program);
        self.empty_block_at(line, col, number);
        self.block.program = program;
        self.expansion = Some(expansion);
        self.expand_first(&mut new);
        self.block.modal = new;
    }

    /// A cycle's name and parameters at the cursor (`MCALL CYCLE81(…)` reads them once).
    pub(in crate::frontend) fn cycle_call(
        &mut self,
        c: &mut Cursor,
        at: usize,
    ) -> R<(CycleName, Params)> {
        let name = CycleName::of(super::expr::identifier_span(c)).ok_or_else(|| {
            fault(
                AlarmCode::UndefinedName,
                at,
                "a cycle CYCLE81 … CYCLE89, CYCLE840, CYCLE93 or CYCLE97",
            )
        })?;
        Ok((name, self.cycle_params(c, name, at)?))
    }

    /// MCALL of a cycle after a block that moved: the hole where the block ended, its steps
    /// after the block (Job planning, "Modal subprogram call").
    pub(in crate::frontend) fn modal_cycle(&mut self, name: CycleName, p: Params) -> R<()> {
        if name.turns() {
            let m = format!("{} as a modal call (MCALL)", name.text());
            return Err(fault(AlarmCode::NotSupported, p.call, m));
        }
        let modal = self.block.modal;
        let run = self.cycle_run(name, p, &modal)?;
        self.expansion = Some(super::super::build::Expansion::cycle(run));
        self.sinumerik.modal_cycle_running = true;
        Ok(())
    }

    /// The moves of cycle `name` from where the tool stands, checked; its infeeds counted.
    fn cycle_run(&mut self, name: CycleName, p: Params, new: &ModalState) -> R<CycleRun> {
        if new.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                p.call,
                format!(
                    "{} cannot run while tool radius compensation is active",
                    name.text()
                ),
            ));
        }
        let hole = self.hole_of(name, p, new)?;
        let mut run = CycleRun {
            hole,
            at: self.cur,
            queue: heapless::Deque::new(),
            speed_now: hole.speed,
            deep: None,
        };
        let passes = match name {
            CycleName::Drill81 | CycleName::Drill82 => drilling::drill(&mut run)?,
            CycleName::DeepHole83 => drilling::deep_hole(&mut run)?,
            CycleName::Tap84 | CycleName::Tap840 => tapping::tap(&mut run)?,
            _ => boring::bore(&mut run)?,
        };
        // Every infeed after the first is a loop pass (cycles in loops stay bounded).
        self.add_passes(passes.saturating_sub(1), p.call)?;
        Ok(run)
    }

    /// `(p1, , p3 …)`: each an expression or empty; more than the cycle takes is an alarm.
    fn cycle_params(&mut self, c: &mut Cursor, name: CycleName, at: usize) -> R<Params> {
        let mut p = Params {
            v: [None; MAX_PARAMS],
            at: [at; MAX_PARAMS],
            call: at,
        };
        c.skip_blanks();
        if c.peek() != Some(b'(') {
            return Err(fault(
                AlarmCode::Syntax,
                c.i,
                format!("{}( expected", name.text()),
            ));
        }
        c.i += 1;
        self.param_list(c, name.text(), name.entry().2, 0, &mut p)?;
        Ok(p)
    }

    /// The parameters from position `first` on, after the `(` or the `,` before it, up to
    /// and with the `)`: each an expression or empty.
    fn param_list(
        &mut self,
        c: &mut Cursor,
        name: &str,
        max: usize,
        first: usize,
        p: &mut Params,
    ) -> R<()> {
        for k in first.. {
            c.skip_blanks();
            if !matches!(c.peek(), Some(b',' | b')')) {
                if k >= max {
                    let m = format!("{name} takes {max} parameters");
                    return Err(fault(AlarmCode::Syntax, c.i, m));
                }
                p.at[k] = c.i;
                p.v[k] = Some(super::expr::eval(c, &self.sinumerik.store)?);
                c.skip_blanks();
            }
            match c.peek() {
                Some(b',') => c.i += 1,
                Some(b')') => {
                    c.i += 1;
                    return Ok(());
                }
                _ => return Err(fault(AlarmCode::Syntax, c.i, "',' or ')' expected")),
            }
        }
        Ok(())
    }

    /// The hole's planes in machine coordinates, checked against each other.
    fn hole_of(&self, name: CycleName, p: Params, new: &ModalState) -> R<Hole> {
        let n = self.tool_axis(new, p.call)?;
        let unit = if new.units == crate::machine_data::Units::Inch {
            25.4
        } else {
            1.0
        };
        let (scale, shift) = self.cycle_levels(n, new);
        let level = |v: f64| scale * v * unit + shift;
        let (rtp, rfp) = (level(p.get(RTP)), level(p.get(RFP)));
        // DPR (unsigned, below RFP) wins over DP where both are given.
        let bottom = if p.given(DPR) {
            rfp - p.get(DPR).abs() * unit
        } else {
            level(p.get(DP))
        };
        let bad = |k: usize, m: &str| Err(fault(AlarmCode::CycleParameter, p.at(k), m.to_string()));
        if (bottom - rfp).abs() < 1e-9 {
            return bad(DP, "the final depth lies on the reference plane: no hole");
        }
        let dir = (bottom - rfp).signum();
        let safety = rfp - dir * p.get(SDIS).abs() * unit;
        if (rtp - safety) * dir > 1e-9 {
            return bad(
                RTP,
                "the retraction plane lies below the safety plane (RFP + SDIS)",
            );
        }
        Ok(Hole {
            name,
            n,
            rtp,
            rfp,
            safety,
            bottom,
            dir,
            feed: new.feed,
            per_rev: new.feed_per_rev,
            speed: new.spindle,
            spindle: new.spindle_dir,
            plane: new.plane,
            dialect: self.d,
            unit,
            scale,
            shift,
            p,
        })
    }

    /// The tool axis: the plane's normal; on a machine without it (a lathe in G18) Z, the
    /// spindle axis the lathe drills along on its centre line (808D turning).
    fn tool_axis(&self, new: &ModalState, at: usize) -> R<usize> {
        let n = new.plane.normal as usize;
        let n = if self.md.axes.get(n).is_some() { n } else { 2 };
        let f = &self.coords.frame;
        if f.active() && !f.keeps_plane(new.plane) {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "a drilling cycle under a frame that turns the tool axis",
            ));
        }
        Ok(n)
    }

    /// How a level of tool axis `n` (workpiece coordinates, mm) maps into machine
    /// coordinates: (scale, shift), through the frame (which keeps the plane) and the zero.
    fn cycle_levels(&self, n: usize, new: &ModalState) -> (f64, f64) {
        let f = &self.coords.frame;
        let (mut unit, origin) = ([0.0; 3], f.apply([0.0; 3]));
        unit[n] = 1.0;
        let scale = f.apply(unit)[n] - origin[n];
        (scale, origin[n] + self.zero(new.work_offset)[n])
    }
}

/// The feed of a G1 move in the cycle: the active one, which must exist.
fn feed_needed(h: &Hole) -> R<f64> {
    if h.feed > 0.0 {
        Ok(h.feed)
    } else {
        Err(fault(
            AlarmCode::NoFeed,
            h.p.call,
            format!("{} needs a feed F", h.name.text()),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::frontend::block::{Block, MotionKind, SpindleDir};

    const START: &str = "G17 G90 G0 X10 Y20 Z50 F100 S1000 M3\n";

    fn blocks(cycle: &str) -> Vec<Block> {
        run("siemens-840d", &format!("{START}{cycle}\nG1 X30\n")).unwrap_or_else(|a| panic!("{a}"))
    }

    /// (Z end, rapid, feed) of the moves after the start block and before the last one.
    fn moves(cycle: &str) -> Vec<(f64, bool, f64)> {
        let b = blocks(cycle);
        b[1..b.len() - 1]
            .iter()
            .filter_map(|b| {
                b.motion
                    .map(|m| (m.end[2], m.kind == MotionKind::Rapid, b.modal.feed))
            })
            .collect()
    }

    fn zs(cycle: &str) -> Vec<f64> {
        moves(cycle).iter().map(|m| m.0).collect()
    }

    fn near(got: &[f64], want: &[f64]) {
        assert_eq!(got.len(), want.len(), "{got:?} / {want:?}");
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-9, "{got:?} / {want:?}");
        }
    }

    fn alarm(cycle: &str) -> (AlarmCode, u32, u32) {
        let a = run("siemens-840d", &format!("{START}{cycle}\n")).unwrap_err();
        (a.code, a.line, a.col)
    }

    #[test]
    fn cycle81_goes_to_the_safety_plane_drills_and_leaves_to_rtp() {
        // RFP 0 + SDIS 2 = Z2 at rapid, Z-15 at F100, Z10 at rapid; the next block's feed
        // is the programmed one again.
        let m = moves("CYCLE81(10, 0, 2, -15)");
        assert_eq!(
            m,
            [
                (2.0, true, 100.0),
                (-15.0, false, 100.0),
                (10.0, true, 100.0)
            ]
        );
        let b = blocks("CYCLE81(10, 0, 2, -15)");
        assert!(b.iter().all(|b| b
            .motion
            .is_none_or(|m| m.end[0] == 10.0 || m.end[0] == 30.0)));
        assert_eq!(b.last().map(|b| b.modal.feed), Some(100.0));
    }

    #[test]
    fn dpr_counts_from_the_reference_plane_and_wins_over_dp() {
        // RFP 3, DPR 5: the bottom is Z-2 (DP -30 is not used); CYCLE82 dwells 0.5 s there.
        let b = blocks("CYCLE82(20, 3, 1, -30, 5, 0.5)");
        let dwell: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
        assert_eq!(dwell, [0.5]);
        near(&zs("CYCLE82(20, 3, 1, -30, 5, 0.5)"), &[4.0, -2.0, 20.0]);
    }

    #[test]
    fn cycle83_breaks_chips_with_degression_and_a_slower_first_infeed() {
        // FDEP -8, DAM 3, FRF 0.5: infeeds 8, 5, 3, 3, 1 → depths 8 13 16 19 20; after each
        // but the last 1 mm back at F100; the first infeed at F50.
        let m = moves("CYCLE83(10, 0, 1, -20, , -8, , 3, , , 0.5, 0)");
        let z: Vec<f64> = m.iter().map(|m| m.0).collect();
        near(
            &z,
            &[
                1.0, -8.0, -7.0, -13.0, -12.0, -16.0, -15.0, -19.0, -18.0, -20.0, 10.0,
            ],
        );
        assert_eq!((m[1].2, m[2].2, m[3].2), (50.0, 100.0, 100.0));
        assert!(m[0].1 && !m[1].1 && !m[2].1 && m[10].1);
    }

    #[test]
    fn cycle83_removes_chips_back_to_the_safety_plane() {
        // FDPR 8, DAM 0: infeeds 8, 8, 4; out to Z1 after each, back down at rapid to 0.6 mm
        // above the depth reached (a hole up to 30 mm deep).
        near(
            &zs("CYCLE83(10, 0, 1, -20, , , 8, 0, , , , 1)"),
            &[1.0, -8.0, 1.0, -7.4, -16.0, 1.0, -15.4, -20.0, 10.0],
        );
    }

    #[test]
    fn cycle84_taps_at_lead_times_speed_and_reverses_the_spindle() {
        // MPIT 8: lead 1.25 mm; S500: 625 mm/min in and out; SDAC 3: M3 after the cycle.
        let p = "S500\nCYCLE84(10, 0, 2, -12, , 0, 3, 8)";
        let m = moves(p);
        let z: Vec<(f64, bool, f64)> = m[1..].to_vec();
        assert_eq!(
            z,
            [
                (-12.0, false, 625.0),
                (2.0, false, 625.0),
                (10.0, true, 100.0)
            ]
        );
        let b = blocks(p);
        let dirs: Vec<SpindleDir> = b
            .windows(2)
            .filter(|w| w[0].modal.spindle_dir != w[1].modal.spindle_dir)
            .map(|w| w[1].modal.spindle_dir)
            .collect();
        assert_eq!(dirs, [SpindleDir::CounterClockwise, SpindleDir::Clockwise]);
    }

    #[test]
    fn cycle86_lifts_off_the_wall_and_comes_back_in_the_plane() {
        let b = blocks("CYCLE86(10, 0, 2, -20, , 0, 3, -1, 0.5, 1)");
        let ends: Vec<[f64; 3]> = b[1..b.len() - 1]
            .iter()
            .filter_map(|b| b.motion.map(|m| m.end))
            .collect();
        assert_eq!(
            ends,
            [
                [10.0, 20.0, 2.0],
                [10.0, 20.0, -20.0],
                [9.0, 20.5, -19.0],
                [9.0, 20.5, 10.0],
                [10.0, 20.0, 10.0]
            ]
        );
        assert!(b.iter().any(|b| b.modal.spindle_dir == SpindleDir::Orient));
    }

    #[test]
    fn cycle87_stops_for_the_operator_at_the_bottom() {
        let b = blocks("CYCLE87(10, 0, 2, -20, , 4)");
        let stop = b.iter().position(|b| b.stop.is_some()).expect("M0");
        assert_eq!(b[stop - 1].modal.spindle_dir, SpindleDir::Stop);
        assert_eq!(
            b.last().map(|b| b.modal.spindle_dir),
            Some(SpindleDir::CounterClockwise)
        );
    }

    #[test]
    fn bad_parameters_are_alarms_at_their_place() {
        // RTP 0 below the safety plane Z2: at RTP (column 9).
        assert_eq!(
            alarm("CYCLE81(0, 0, 2, -10)"),
            (AlarmCode::CycleParameter, 2, 9)
        );
        assert_eq!(
            alarm("CYCLE81(10, 0, 2, 0)"),
            (AlarmCode::CycleParameter, 2, 19)
        );
        assert_eq!(
            alarm("CYCLE81(1, 0, 0, -1, 0, 7)"),
            (AlarmCode::Syntax, 2, 25)
        );
        assert_eq!(
            alarm("CYCLE84(10, 0, 2, -12, , 0, 3, 7)"),
            (AlarmCode::CycleParameter, 2, 32)
        );
        assert_eq!(
            alarm("CYCLE83(10, 0, 1, -20, , , , , , , , 2)"),
            (AlarmCode::CycleParameter, 2, 38)
        );
        let trc = "T1 D1\nG41 G1 X0 Y0\nCYCLE81(10, 0, 2, -15)";
        assert_eq!(alarm(trc).0, AlarmCode::ForbiddenWithTrc);
    }

    #[test]
    fn tiny_infeeds_end_on_the_loop_budget() {
        let a = run(
            "siemens-840d",
            &format!("{START}CYCLE83(10, 0, 1, -20000, , , 0.0001, 0, , , , 0)\n"),
        )
        .unwrap_err();
        assert_eq!(a.code, AlarmCode::LoopLimit);
    }
}
