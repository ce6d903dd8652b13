//! The turning cycles of the 808D lathe that cut along the Z-X plane (808D Turning
//! "Cycles"; 840D sl Cycles "Turning cycles"): [`threading`](super::threading) (CYCLE97) and
//! [`grooving`](super::grooving) (CYCLE93). Their parameters are workpiece coordinates of the
//! plane: the face axis X as programmed (a diameter under DIAMON, a radius under DIAMOF), the
//! longitudinal axis Z; depths and lengths are unsigned radii. The passes stream out of the
//! lathe cycles' run one pass at a time, as the Fanuc lathe cycles' do.

use super::super::super::block::{ModalState, Pos};
use super::super::super::build::{Expansion, LatheRun, Step};
use super::super::super::fault::{fault, Fault, R};
use super::super::super::interpreter::Interpreter;
use super::{grooving, threading, CycleName, Params};
use crate::alarm::AlarmCode;
use crate::machine_data::Units;

/// A turning cycle's passes still to come.
#[derive(Clone, Debug)]
pub enum SinumerikPasses {
    Thread(threading::Thread),
    Groove(grooving::Groove),
}

impl SinumerikPasses {
    /// The next pass's steps into the empty queue (none when the cycle is done).
    pub(in crate::frontend) fn refill(&mut self, q: &mut heapless::Deque<Step, 8>) {
        match self {
            SinumerikPasses::Thread(t) => t.refill(q),
            SinumerikPasses::Groove(g) => g.refill(q),
        }
    }

    fn count(&self) -> u32 {
        match self {
            SinumerikPasses::Thread(t) => t.passes(),
            SinumerikPasses::Groove(g) => g.passes(),
        }
    }
}

/// A call's parameters and how its plane values map into machine coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lathe {
    pub p: Params,
    /// X: a programmed value times `x.0` plus `x.1`; Z likewise.
    x: (f64, f64),
    z: (f64, f64),
    /// mm per program unit.
    unit: f64,
    /// Where the tool stands at the call.
    pub at: Pos,
    /// The feed at the call (per revolution under G95).
    pub feed: f64,
    /// The spindle speed at the call.
    pub speed: f64,
}

impl Lathe {
    /// The point whose Z is parameter `z` and whose X is parameter `x`.
    pub fn point(&self, z: usize, x: usize) -> Pos {
        [
            self.x.0 * self.p.get(x) + self.x.1,
            self.at[1],
            self.z.0 * self.p.get(z) + self.z.1,
        ]
    }

    /// An unsigned length (mm) at parameter `k` ("enter without sign").
    pub fn len(&self, k: usize) -> f64 {
        self.p.get(k).abs() * self.unit
    }

    /// mm per program unit.
    pub fn unit(&self) -> f64 {
        self.unit
    }

    /// Parameter `k` as a whole number in `lo ..= hi` (empty: 0).
    pub fn whole(&self, k: usize, lo: u32, hi: u32, name: &str) -> R<u32> {
        let v = self.p.get(k);
        if v.fract() != 0.0 || v < f64::from(lo) || v > f64::from(hi) {
            return Err(self.bad(k, format!("{name}={v}: a whole number {lo} … {hi}")));
        }
        Ok(v as u32)
    }

    /// The machining type VARI at `k`, a whole number `lo` … `hi`: else alarm 61002, as for
    /// CYCLE95.
    pub fn machining_type(&self, k: usize, lo: u32, hi: u32) -> R<u32> {
        self.whole(k, lo, hi, "VARI").map_err(|mut f| {
            f.code = AlarmCode::CycleMachiningType;
            f
        })
    }

    /// Alarm 61101 at parameter `k`.
    pub fn bad(&self, k: usize, m: impl Into<String>) -> Box<Fault> {
        fault(AlarmCode::CycleParameter, self.p.at(k), m.into())
    }

    /// Alarm 12580 at parameter `k`: a value the cycle has but softnc does not build.
    pub fn not_built(&self, k: usize, m: impl Into<String>) -> Box<Fault> {
        fault(AlarmCode::NotSupported, self.p.at(k), m.into())
    }
}

/// A rapid move.
pub(super) fn rapid(to: Pos) -> Step {
    Step::Move {
        to,
        rapid: true,
        axes: None,
        feed: None,
    }
}

/// A move at the feed in force.
pub(super) fn cut(to: Pos) -> Step {
    Step::Move {
        to,
        rapid: false,
        axes: None,
        feed: None,
    }
}

impl Interpreter<'_> {
    /// The passes of turning cycle `name`, checked; every pass after the first counts
    /// against the loop budget.
    pub(super) fn sinumerik_lathe_cycle(
        &mut self,
        name: CycleName,
        p: Params,
        new: &ModalState,
    ) -> R<Expansion> {
        self.lathe_allowed(new, p.call, name.text())?;
        let unit = if new.units == Units::Inch { 25.4 } else { 1.0 };
        let zero = self.zero(new.work_offset);
        let dia = if new.diameter { 0.5 } else { 1.0 };
        let l = Lathe {
            p,
            x: (dia * unit, zero[0]),
            z: (unit, zero[2]),
            unit,
            at: self.cur,
            feed: new.feed,
            speed: new.spindle,
        };
        let passes = match name {
            CycleName::Thread97 => SinumerikPasses::Thread(threading::thread(&l)?),
            _ => SinumerikPasses::Groove(grooving::groove(&l, self.tool_width(new, &p)?)?),
        };
        self.add_passes(u64::from(passes.count()).saturating_sub(1), p.call)?;
        Ok(Expansion::lathe(LatheRun::sinumerik(passes)))
    }

    /// A grooving tool's width: the difference of the lengths of its edges D and D+1, or
    /// the edge parameter `_DN` names [unconfirmed].
    fn tool_width(&self, new: &ModalState, p: &Params) -> R<f64> {
        let dn = p.get(DN);
        let second = if dn > 0.0 && dn.fract() == 0.0 && dn < 1e6 {
            dn as u32
        } else {
            new.d.saturating_add(1)
        };
        let table = self.tool_table();
        let length = |d: u32| table.resolve(new.tool, d).map(|r| r.1);
        match (new.d, length(new.d), length(second)) {
            (1.., Some(a), Some(b)) => Ok((b - a).abs()),
            _ => Err(fault(
                AlarmCode::CycleParameter,
                p.call,
                format!(
                    "CYCLE93 needs a grooving tool: edges D{} and D{second}",
                    new.d
                ),
            )),
        }
    }
}

/// CYCLE93's _DN: the grooving tool's second edge.
const DN: usize = 17;

#[cfg(test)]
pub(super) mod tests {
    use crate::alarm::{Alarm, AlarmCode};
    use crate::frontend::{interpret, Block, MotionKind};
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    pub fn lathe(src: &str) -> Result<Vec<Block>, Alarm> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/siemens-808d.toml");
        let md = MachineData::load(Some(std::path::Path::new(path)), &[]).unwrap();
        interpret("p.mpf", src, &md, &ToolTable::builtin())
    }

    /// How a move goes: rapid, fed at a feed, or a thread at its path feed per revolution.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub enum How {
        R,
        F(f64),
        T(f64),
    }

    pub fn r6(v: f64) -> f64 {
        (v * 1e6).round() / 1e6
    }

    /// (how, X radius, Z) of every move, rounded to 1e-6.
    pub fn moves(src: &str) -> Vec<(How, f64, f64)> {
        lathe(src)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| {
                let m = b.motion?;
                let how = match (b.thread, m.kind) {
                    (Some(f), _) => How::T(r6(f)),
                    (None, MotionKind::Rapid) => How::R,
                    _ => How::F(r6(b.modal.feed)),
                };
                Some((how, r6(m.end[0]), r6(m.end[2])))
            })
            .collect()
    }

    /// (code, line, column) of the alarm.
    pub fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        let a = lathe(src).unwrap_err();
        (a.code, a.line, a.col)
    }
}
