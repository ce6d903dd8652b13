//! Thread cutting and the simple lathe cycles of the Fanuc 0i-TF (G-code system A):
//!
//! ```text
//! G32 X(U) Z(W) F(L)                      thread cutting, lead L along the longer axis
//! G90 X(U) Z(W) R(r) F                    outer/inner diameter cutting cycle   (modal)
//! G92 X(U) Z(W) R(r) F(L)                 threading cycle                     (modal)
//! G94 X(U) Z(W) R(r) F                    end face cutting cycle              (modal)
//! G76 P(m)(r)(a) Q(Δdmin) R(d)            multiple threading cycle: its data
//! G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L)      … and its thread
//! G74 R(e) / G74 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F   end face peck drilling
//! G75 R(e) / G75 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F   outer/inner diameter grooving
//! ```
//!
//! One module per family: [`thread`] (G32), [`simple`] (the boxes of G90, G92, G94),
//! [`threading`] (G76's passes and the thread pass G92 shares), [`grooving`] (G74, G75).
//! Every cycle starts and ends at the start point A, the tool's position at the block.

mod grooving;
mod simple;
mod thread;
mod threading;

pub use thread::thread_feed;
pub(in crate::frontend) use threading::thread_pass;

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{Val, Words};
use super::expand::{Expansion, Step};
use crate::alarm::AlarmCode;
use crate::dialect::LatheCycle;
use crate::frontend::sinumerik::cycles::SinumerikPasses;
use crate::machine_data::Units;

/// The lathe cycles' stored data: kept from block to block until written again.
#[derive(Clone, Copy, Debug)]
pub struct LatheData {
    /// G76 first block and G92's chamfer.
    pub thread: ThreadData,
    /// G74/G75 `R(e)`: the return after each peck.
    pub peck_return: f64,
    /// The box cycle in force and its end point and taper (the box's X, Z, R are modal).
    pub boxed: Option<(BoxCycle, Pos, f64)>,
}

/// `G76 P(m)(r)(a) Q(Δdmin) R(d)`: the finishing passes, the chamfer (tenths of the lead),
/// the tool's angle (degrees), the minimum depth of cut and the finishing allowance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThreadData {
    pub finishing: u32,
    pub chamfer: u32,
    pub angle: f64,
    pub min_depth: f64,
    pub allowance: f64,
}

impl Default for LatheData {
    /// The 0i-TF's parameters as softnc ships them (5142 m = 1, 5130 r = 0, 5143 a = 60,
    /// 5140 Δdmin = 0, 5141 d = 0, 5139 e = 0) [unconfirmed: the parameters' defaults].
    fn default() -> Self {
        LatheData {
            thread: ThreadData {
                finishing: 1,
                chamfer: 0,
                angle: 60.0,
                min_depth: 0.0,
                allowance: 0.0,
            },
            peck_return: 0.0,
            boxed: None,
        }
    }
}

/// A lathe cycle's remaining passes, one pass's moves at a time.
#[derive(Clone, Debug)]
pub struct LatheRun {
    queue: heapless::Deque<Step, 8>,
    passes: Passes,
}

#[derive(Clone, Debug)]
enum Passes {
    Threading(threading::Passes),
    Pecking(grooving::Pecks),
    /// A SINUMERIK turning cycle's passes (CYCLE93, CYCLE97).
    Sinumerik(SinumerikPasses),
}

impl LatheRun {
    fn new(passes: Passes) -> Self {
        LatheRun {
            queue: heapless::Deque::new(),
            passes,
        }
    }

    /// The passes of a SINUMERIK turning cycle.
    pub(in crate::frontend) fn sinumerik(passes: SinumerikPasses) -> Self {
        Self::new(Passes::Sinumerik(passes))
    }

    pub fn next(&mut self) -> Option<Step> {
        if self.queue.is_empty() {
            self.refill();
        }
        self.queue.pop_front()
    }

    pub fn done(&mut self) -> bool {
        if self.queue.is_empty() {
            self.refill();
        }
        self.queue.is_empty()
    }

    fn refill(&mut self) {
        match &mut self.passes {
            Passes::Threading(p) => p.refill(&mut self.queue),
            Passes::Pecking(p) => p.refill(&mut self.queue),
            Passes::Sinumerik(p) => p.refill(&mut self.queue),
        }
    }
}

/// Puts the steps of one pass (at most eight) into an empty queue.
pub(in crate::frontend) fn push_all(q: &mut heapless::Deque<Step, 8>, steps: &[Step]) {
    for &s in steps {
        let _ = q.push_back(s);
    }
}

/// A rapid move.
fn rapid(to: Pos) -> Step {
    Step::Move {
        to,
        rapid: true,
        axes: None,
        feed: None,
    }
}

/// A move at the modal feed.
fn cut(to: Pos) -> Step {
    Step::Move {
        to,
        rapid: false,
        axes: None,
        feed: None,
    }
}

/// (X radius, Z) as a position; Y stays at `y`.
fn at(x: f64, z: f64, y: f64) -> Pos {
    [x, y, z]
}

/// −1, 0 or 1 by the sign of `v` beyond a micrometre's thousandth.
fn sign(v: f64) -> f64 {
    if v > 1e-9 {
        1.0
    } else if v < -1e-9 {
        -1.0
    } else {
        0.0
    }
}

impl Interpreter<'_> {
    /// Step 8 of a block in a lathe motion mode (G32, G90, G92, G94); false for the others.
    pub(in crate::frontend::build) fn lathe_motion(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        at: usize,
    ) -> R<bool> {
        match new.motion {
            MotionMode::Thread => self.thread_cut(w, new, at)?,
            MotionMode::BoxCycle(kind) => self.box_cycle(w, new, kind, at)?,
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Step 8 of a G74, G75 or G76 block.
    pub(in crate::frontend::build) fn lathe_cycle(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        kind: LatheCycle,
        at: usize,
    ) -> R<()> {
        self.lathe.boxed = None;
        match kind {
            LatheCycle::Threading => self.multiple_threading(w, new, at),
            LatheCycle::FacePecking | LatheCycle::Grooving => self.pecking(w, new, kind, at),
        }
    }

    /// No nose radius compensation, frame or hole cycle mode, and the Z-X plane: the
    /// cycles cut the tool tip's path.
    pub(in crate::frontend) fn lathe_allowed(
        &self,
        new: &ModalState,
        at: usize,
        what: &str,
    ) -> R<()> {
        if new.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                at,
                format!("{what} cannot be programmed while nose radius compensation is active"),
            ));
        }
        if self.coords.frame.active() || new.plane != Plane::ZX || self.cycle.is_some() {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("{what} runs in the Z-X plane without a frame or hole cycle"),
            ));
        }
        Ok(())
    }

    /// Words a thread or box block has no use for: I and K (no circle), and P and Q where
    /// the block takes none (G32 and G92's Q, the start angle of a multiple-start thread,
    /// is not built).
    fn no_other_words(&self, w: &Words, pq: bool) -> R<()> {
        if let Some(v) = w.centre.iter().flatten().next() {
            return Err(fault(
                AlarmCode::Syntax,
                v.at,
                "I and K have no meaning in a thread or lathe cycle block",
            ));
        }
        if pq {
            return Ok(());
        }
        if let Some(q) = w.q {
            return Err(fault(
                AlarmCode::NotSupported,
                q.at,
                "Q (the start angle of a multiple-start thread) is not supported",
            ));
        }
        if let Some(p) = w.p {
            return Err(fault(
                AlarmCode::Syntax,
                p.at,
                "P has no meaning in this block",
            ));
        }
        Ok(())
    }

    /// A P or Q amount of a lathe cycle: least input increments, no decimal point (0i-TF:
    /// "specify without a decimal point"), in mm; `None` if not written.
    fn increments(&self, v: Option<Val>, units: Units, what: &str) -> R<Option<f64>> {
        let Some(v) = v else { return Ok(None) };
        if v.has_point || v.value < 0.0 || v.value.fract() != 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                v.at,
                format!("{what} is a whole number of least input increments without a decimal point, not negative"),
            ));
        }
        let p = &self.md.program;
        Ok(Some(match units {
            Units::Mm => v.value * p.least_input_increment_mm,
            Units::Inch => v.value * p.least_input_increment_inch * 25.4,
        }))
    }

    /// A cycle that feeds needs F.
    fn cycle_feed(&self, new: &ModalState, at: usize, what: &str) -> R<()> {
        if new.feed > 0.0 {
            return Ok(());
        }
        Err(fault(AlarmCode::NoFeed, at, format!("{what} needs F")))
    }

    /// The expansion of a cycle: its first step into the block.
    fn expand(&mut self, e: Expansion, new: &mut ModalState) {
        self.expansion = Some(e);
        self.expand_first(new);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::alarm::{Alarm, AlarmCode};
    use crate::frontend::{interpret, Block, MotionKind};
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    pub fn lathe_with(src: &str, radius: bool) -> Result<Vec<Block>, Alarm> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-lathe.toml");
        let ov: Vec<String> = if radius {
            vec!["program.diameter_programming=false".into()]
        } else {
            vec![]
        };
        let md = MachineData::load(Some(std::path::Path::new(path)), &ov).unwrap();
        interpret("l.nc", src, &md, &ToolTable::builtin())
    }

    /// How a move goes: rapid, fed, or a thread at its path feed per revolution.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub enum How {
        R,
        F,
        T(f64),
    }

    fn r9(v: f64) -> f64 {
        (v * 1e9).round() / 1e9
    }

    /// (how, X radius, Z) of every move, rounded to 1e-9; `radius`: X programmed as a radius.
    pub fn moves_with(src: &str, radius: bool) -> Vec<(How, f64, f64)> {
        lathe_with(src, radius)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| {
                let m = b.motion?;
                let how = match (b.thread, m.kind) {
                    (Some(f), _) => How::T(r9(f)),
                    (None, MotionKind::Rapid) => How::R,
                    _ => How::F,
                };
                Some((how, r9(m.end[0]), r9(m.end[2])))
            })
            .collect()
    }

    pub fn moves(src: &str) -> Vec<(How, f64, f64)> {
        moves_with(src, false)
    }

    /// (code, line, column) of the alarm.
    pub fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        let a = lathe_with(src, false).unwrap_err();
        (a.code, a.line, a.col)
    }
}
