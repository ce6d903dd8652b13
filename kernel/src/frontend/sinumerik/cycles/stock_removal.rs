//! Stock removal CYCLE95 (808D Turning / 840D Cycles, "Stock removal – CYCLE95"):
//!
//! ```text
//! CYCLE95(NPP, MID, FALZ, FALX, FAL, FF1, FF2, FF3, VARI, DT, DAM, _VRT)
//!   NPP   the contour: a subprogram's name, or "START:END" labels of this program (contour.rs)
//!   MID   the largest infeed (radius, no sign); the cuts are equal and at most MID deep
//!   FALZ  FALX  the finishing allowances along Z and X (X a radius); FAL along the contour
//!         (build/turning/equidistant.rs: the contour's equidistant), the three add up
//!   FF1   the roughing feed; FF2 into undercuts; FF3 the finishing feed
//!   VARI  1 … 12: roughing (1 … 4), finishing (5 … 8), complete (9 … 12); within each,
//!         longitudinal outside, transverse outside, longitudinal inside, transverse inside
//!   DT    DAM  a dwell after every DAM of a roughing cut (chip breaking)
//!   _VRT  the lift-off from the contour after a roughing cut (0: 1 mm)
//! ```
//!
//! In (X radius, Z): the cycle's start point S lies at the allowance-shifted contour's
//! outermost X (innermost inside), _VRT in front of its start in Z. The tool goes there at
//! rapid; roughing cuts along Z at equal depths from S's X down to the shifted contour's
//! start, each lifted off by _VRT at 45° and back to S's Z at rapid; a last cut along the
//! shifted contour; back to S (X first). Finishing: from S to the contour's start at rapid,
//! along the contour at FF3, back to S. Transverse machining is the same with X and Z
//! exchanged; a contour with undercut elements (its depth axis turns back) is roughed level
//! by level, every cut deeper into the stock at FF2. The passes are the Fanuc lathe's
//! engine (build/turning: `Passes`, `TurningRun`, its exchange and its pockets); this
//! module gives it the contour, S, the depth and the feeds (docs/turning.md, "CYCLE95").

use super::super::super::block::*;
use super::super::super::build::{
    deepest, equidistant, non_monotonic, sign, tip_path, z_turns, Expansion, Nose, Passes, Step,
    TurningElement as Element, TurningRun, EPS,
};
use super::super::super::fault::{fault, R};
use super::super::super::interpreter::Interpreter;
use super::super::super::lexer::Cursor;
use super::{Params, MAX_PARAMS};
use crate::alarm::AlarmCode;

/// The parameter positions (NPP is position 0, read as a string).
const MID: usize = 1;
const FALZ: usize = 2;
const FALX: usize = 3;
const FAL: usize = 4;
const FF1: usize = 5;
const FF2: usize = 6;
const FF3: usize = 7;
const VARI: usize = 8;
const DT: usize = 9;
const DAM: usize = 10;
const VRT: usize = 11;
const COUNT: usize = 12;

/// The lift-off where _VRT is left out or 0 (mm) **[unconfirmed]**.
const VRT_DEFAULT: f64 = 1.0;

/// What VARI asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Machining {
    Roughing,
    Finishing,
    Complete,
}

#[derive(Clone, Copy, Debug)]
struct Vari {
    machining: Machining,
    inside: bool,
    /// Transverse (face) machining: passes along X, levels in Z.
    transverse: bool,
}

/// Whether the cycle name at the cursor is CYCLE95.
pub fn is_cycle95(c: &Cursor) -> bool {
    let mut probe = *c;
    super::super::expr::identifier_span(&mut probe).eq_ignore_ascii_case(b"CYCLE95")
}

/// The machining type VARI (Cycles, "CYCLE95", VARI 1 … 12).
fn vari(p: &Params) -> R<Vari> {
    let v = p.get(VARI);
    if v.fract() != 0.0 || !(1.0..=12.0).contains(&v) {
        return Err(fault(
            AlarmCode::CycleMachiningType,
            p.at(VARI),
            format!("VARI {v}: the machining type is 1 … 12"),
        ));
    }
    let k = v as u32 - 1;
    let machining = match k / 4 {
        0 => Machining::Roughing,
        1 => Machining::Finishing,
        _ => Machining::Complete,
    };
    // Within each kind: longitudinal outside, transverse outside, longitudinal inside,
    // transverse inside.
    Ok(Vari {
        machining,
        inside: k % 4 >= 2,
        transverse: k % 2 == 1,
    })
}

/// The cycle's values in mm, checked.
#[derive(Clone, Copy, Debug)]
struct Setup {
    vari: Vari,
    mid: f64,
    falz: f64,
    falx: f64,
    fal: f64,
    vrt: f64,
    rough_feed: f64,
    /// FF2: into undercut elements (left out: FF1) **[unconfirmed]**.
    plunge_feed: f64,
    finish_feed: f64,
    chip: Option<ChipBreak>,
}

/// Chip breaking: a roughing cut stops every `every` mm and dwells `dwell` s (DAM, DT).
#[derive(Clone, Copy, Debug)]
struct ChipBreak {
    every: f64,
    dwell: f64,
}

impl Interpreter<'_> {
    /// `CYCLE95(…)` at the cursor (its name): the passes and the finishing from S, the
    /// first step into the block being built.
    pub(super) fn stock_removal_cycle(&mut self, c: &mut Cursor, at: usize) -> R<()> {
        let (npp, npp_at, p) = self.cycle95_params(c, at)?;
        let new = self.block.modal;
        let s = self.cycle95_setup(&p, &new)?;
        let contour = self.cycle_contour(&npp, npp_at, &new, s.rough_feed.max(s.finish_feed))?;
        let run = self.stock_removal_run(&s, contour, &p, &new)?;
        self.start_cycle(at, Expansion::stock_removal(run), new);
        Ok(())
    }

    /// `("NPP", MID, …)`: the contour's name (a string expression) and the numbers.
    fn cycle95_params(&mut self, c: &mut Cursor, at: usize) -> R<(String, usize, Params)> {
        super::super::expr::identifier_span(c);
        c.skip_blanks();
        if c.peek() != Some(b'(') {
            return Err(fault(AlarmCode::Syntax, c.i, "CYCLE95( expected"));
        }
        c.i += 1;
        c.skip_blanks();
        let npp_at = c.i;
        let npp = match c.peek() {
            Some(b',' | b')') | None => String::new(),
            _ => self.string_expr(c)?,
        };
        let mut p = Params {
            v: [None; MAX_PARAMS],
            at: [at; MAX_PARAMS],
            call: at,
        };
        c.skip_blanks();
        match c.peek() {
            Some(b',') => {
                c.i += 1;
                self.param_list(c, "CYCLE95", COUNT, 1, &mut p)?;
            }
            Some(b')') => c.i += 1,
            _ => return Err(fault(AlarmCode::Syntax, c.i, "',' or ')' expected")),
        }
        Ok((npp, npp_at, p))
    }

    /// The parameters in mm, checked against each other and the modal state.
    fn cycle95_setup(&self, p: &Params, new: &ModalState) -> R<Setup> {
        self.cycle95_allowed(p, new)?;
        let vari = vari(p)?;
        let bad = |k: usize, m: String| Err(fault(AlarmCode::CycleParameter, p.at(k), m));
        for (k, name) in [
            (MID, "MID"),
            (FALZ, "FALZ"),
            (FALX, "FALX"),
            (FAL, "FAL"),
            (FF1, "FF1"),
            (FF2, "FF2"),
            (FF3, "FF3"),
            (DT, "DT"),
            (DAM, "DAM"),
            (VRT, "_VRT"),
        ] {
            if p.get(k) < 0.0 {
                return bad(k, format!("{name} {} is entered without sign", p.get(k)));
            }
        }
        if vari.machining != Machining::Finishing && p.get(MID) <= 0.0 {
            return bad(MID, "roughing needs the infeed depth MID > 0".into());
        }
        let unit = if new.units == crate::machine_data::Units::Inch {
            25.4
        } else {
            1.0
        };
        let feed = |k: usize| -> R<f64> {
            let f = if p.given(k) { p.get(k) } else { new.feed };
            if f > 0.0 {
                Ok(f)
            } else {
                let m = format!(
                    "CYCLE95 needs a feed: parameter {} or F before the call",
                    ["FF1", "FF3"][(k == FF3) as usize]
                );
                Err(fault(AlarmCode::NoFeed, p.at(k), m))
            }
        };
        let roughs = vari.machining != Machining::Finishing;
        let finishes = vari.machining != Machining::Roughing;
        let chip = (roughs && p.given(DAM)).then(|| ChipBreak {
            every: p.get(DAM) * unit,
            dwell: p.get(DT),
        });
        let vrt = if p.given(VRT) {
            p.get(VRT) * unit
        } else {
            VRT_DEFAULT
        };
        let rough_feed = if roughs { feed(FF1)? } else { 0.0 };
        Ok(Setup {
            vari,
            mid: p.get(MID) * unit,
            falz: p.get(FALZ) * unit,
            falx: p.get(FALX) * unit,
            fal: p.get(FAL) * unit,
            vrt,
            rough_feed,
            plunge_feed: if p.get(FF2) > 0.0 {
                p.get(FF2)
            } else {
                rough_feed
            },
            finish_feed: if finishes { feed(FF3)? } else { 0.0 },
            chip,
        })
    }

    /// No compensation, no frame, and the Z-X plane (as the Fanuc lathe's cycles).
    fn cycle95_allowed(&self, p: &Params, new: &ModalState) -> R<()> {
        if new.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                p.call,
                "CYCLE95 cannot run while tool nose radius compensation is active (the cycle cuts the tool tip's path)",
            ));
        }
        if self.coords.frame.active() || new.plane != Plane::ZX {
            return Err(fault(
                AlarmCode::NotSupported,
                p.call,
                "CYCLE95 runs in the Z-X plane without a frame",
            ));
        }
        Ok(())
    }

    /// S, the passes and the finishing of `contour` (its first element the move to its
    /// start), checked. Transverse machining runs in the frame with X and Z exchanged (as
    /// the Fanuc G72 runs G71); a contour whose depth axis turns back (undercut elements)
    /// is roughed as the engine's pockets, level by level.
    fn stock_removal_run(
        &mut self,
        s: &Setup,
        contour: Vec<Element>,
        p: &Params,
        new: &ModalState,
    ) -> R<StockRemovalRun> {
        let face = s.vari.transverse;
        let frame: Vec<Element> = match face {
            true => contour.iter().map(Element::exchanged).collect(),
            false => contour,
        };
        let (sx, sz) = directions(s.vari, &frame, p)?;
        // The allowances along the frame's depth axis and along its cut.
        let (depth_fal, cut_fal) = if face {
            (s.falz, s.falx)
        } else {
            (s.falx, s.falz)
        };
        // The cycle selects the nose radius compensation itself, on the side away from the
        // material (outside towards the chuck: G42): the passes work on the tool tip's
        // compensated path, the finishing run carries the side to preparation. The side
        // here is the frame's; the exchange of X and Z mirrors it.
        let nose = Nose {
            side: if sx * sz < 0.0 {
                TrcSide::Right
            } else {
                TrcSide::Left
            },
            radius: new.radius.abs(),
            edge: new.edge,
            exchanged: face,
        };
        let allowed = self.along_contour(&frame, s.fal * sx * sz, p)?;
        let moved: Vec<Element> = self
            .compensated(&allowed, nose, p)?
            .iter()
            .map(|e| e.shifted([sx * depth_fal, -sz * cut_fal]))
            .collect();
        let start = cycle_start(&moved, sx, sz, s.vrt);
        let undercut = non_monotonic(&frame, sx, sz).is_some();
        let total = match undercut {
            true => deepest(start, &moved, sx),
            false => sx * (start[0] - moved[0].to[0]),
        };
        check_stock(s.vari, &frame, start, &moved, sx, sz, p)?;
        let rough = match s.vari.machining {
            Machining::Finishing => None,
            _ => Some(self.roughing(s, moved, start, total, undercut, p)?),
        };
        let finish = (s.vari.machining != Machining::Roughing).then(|| {
            let mut shape = frame;
            shape[0].mode = MotionMode::Rapid;
            // Selected with the approach to the contour's start, deselected with the return;
            // in machine axes (the frame's side mirrored for a face contour).
            let side = match (face, nose.side) {
                (true, TrcSide::Left) => TrcSide::Right,
                (true, TrcSide::Right) => TrcSide::Left,
                (_, side) => side,
            };
            let sides = match nose.radius > 0.0 {
                true => vec![(0, side), (shape.len(), TrcSide::Off)],
                false => Vec::new(),
            };
            let run = TurningRun::new(start, shape, None).compensated(sides);
            if face {
                run.exchanged()
            } else {
                run
            }
        });
        let real = |mut q: Pos| {
            if face {
                q.swap(0, 2);
            }
            q
        };
        Ok(StockRemovalRun {
            approach: Some(real(start)),
            rough,
            finish,
            rough_feed: s.rough_feed,
            plunge_feed: s.plunge_feed,
            finish_feed: s.finish_feed,
            feed: new.feed,
            chip: s.chip,
            deeper: if face { (2, -sx) } else { (0, -sx) },
            cut: None,
            at: self.cur,
        })
    }

    /// The contour with FAL on the side `fal`'s sign gives (+: the left of travel in (Z, X)).
    fn along_contour(&self, contour: &[Element], fal: f64, p: &Params) -> R<Vec<Element>> {
        if fal == 0.0 {
            return Ok(contour.to_vec());
        }
        equidistant(contour, fal.abs(), fal.signum()).map_err(|k| {
            let m = format!(
                "FAL {} is too large for element {k} of the contour: its parallel vanishes",
                fal.abs()
            );
            fault(AlarmCode::CycleContour, p.at(FAL), m)
        })
    }

    /// The tool tip's path with the nose centre on the equidistant of `allowed` (the contour
    /// with FAL) at the nose radius; an element the nose does not fit is an alarm at the
    /// cycle (61605), naming the element.
    fn compensated(&self, allowed: &[Element], nose: Nose, p: &Params) -> R<Vec<Element>> {
        tip_path(allowed, nose, 0, allowed.len()).map_err(|k| {
            let arc = allowed.get(k).is_some_and(|e| e.mode.is_arc());
            let what = match arc {
                true => "an arc not larger than the nose radius on the tool's side",
                false => "an element shorter than the nose radius's trim at its corners",
            };
            let m = format!(
                "the tool nose radius {} does not fit the contour (with FAL) at element {k}: {what}",
                nose.radius
            );
            fault(AlarmCode::CycleContour, p.call, m)
        })
    }

    /// The roughing passes (in the frame: transverse exchanged): `total` (from S's X to
    /// the shifted contour's start, with undercuts to its deepest point) in equal cuts of
    /// at most MID; the last cut is the run along the shifted contour.
    fn roughing(
        &mut self,
        s: &Setup,
        moved: Vec<Element>,
        start: Pos,
        total: f64,
        undercut: bool,
        p: &Params,
    ) -> R<TurningRun> {
        let cuts = libm::ceil((total - EPS) / s.mid).max(1.0);
        let count = cuts - 1.0;
        self.add_passes(count as u64, p.call)?;
        if let Some(chip) = s.chip {
            // Every interruption counts as a pass (a tiny DAM stays bounded).
            let length = (moved[moved.len() - 1].to[2] - start[2]).abs();
            let pieces = libm::ceil(length / chip.every.max(EPS)).min(1e12);
            self.add_passes((pieces * cuts) as u64, p.at(DAM))?;
        }
        let passes = Passes {
            depth: total / cuts,
            retract: s.vrt,
            sx: depth_sign(s.vari),
            sz: sign(moved[moved.len() - 1].to[2] - moved[0].to[2]),
            rapid_in: true,
            count: count as u32,
        };
        let mut run = TurningRun::new(start, moved, Some(passes));
        if undercut {
            run = run.pockets();
        }
        Ok(if s.vari.transverse {
            run.exchanged()
        } else {
            run
        })
    }
}

/// S (in the frame): the shifted contour's outermost X (`sx` +1; innermost for −1; an
/// arc's top included), `vrt` before its start in Z (against the cut's direction `sz`).
fn cycle_start(moved: &[Element], sx: f64, sz: f64, vrt: f64) -> Pos {
    let mut s = moved[0].to;
    let ends = moved
        .iter()
        .map(|e| sx * e.to[0])
        .fold(f64::NEG_INFINITY, f64::max);
    // The highest point above A' is the deepest below it, seen from the other side: an
    // arc's top counts where it lies above every end point (else the end point, exactly).
    let top = sx * s[0] + deepest(s, &moved[1..], -sx);
    s[0] = sx * if top > ends + EPS { top } else { ends };
    s[2] -= sz * vrt;
    s
}

/// The frame's depth direction (+1: the passes go towards smaller X): longitudinal, from
/// VARI's side; transverse, always towards smaller Z (the stock in front of the faces)
/// **[unconfirmed]**.
fn depth_sign(v: Vari) -> f64 {
    if v.inside && !v.transverse {
        -1.0
    } else {
        1.0
    }
}

/// The directions of the passes (`sx`) and of the cut (`sz`) in the frame (transverse: X and
/// Z exchanged): a longitudinal contour runs along Z either way; a transverse one along X
/// towards the centre (outside) or away from it (inside) **[unconfirmed]**.
fn directions(v: Vari, frame: &[Element], p: &Params) -> R<(f64, f64)> {
    let (a1, b) = (frame[0].to, frame[frame.len() - 1].to);
    let sz = sign(b[2] - a1[2]);
    let bad = |m: &str| Err(fault(AlarmCode::CycleContour, p.call, m));
    if !v.transverse {
        if sz == 0.0 {
            return bad("the contour's start and end lie at the same Z: a longitudinal contour runs along Z");
        }
        return Ok((depth_sign(v), sz));
    }
    if sz == 0.0 {
        return bad(
            "the contour's start and end lie at the same X: a transverse contour runs along X",
        );
    }
    match (v.inside, sz > 0.0) {
        (false, true) => bad("a transverse contour outside runs towards the centre (from its largest X to its smallest), or VARI names the wrong side"),
        (true, false) => bad("a transverse contour inside runs away from the centre (from its smallest X to its largest), or VARI names the wrong side"),
        _ => Ok((1.0, sz)),
    }
}

/// The stock the roughing removes lies between S and the contour: the contour must not
/// start at S's depth, and along the cut it must go one way (the depth axis may turn
/// back: undercut elements).
fn check_stock(
    v: Vari,
    frame: &[Element],
    start: Pos,
    moved: &[Element],
    sx: f64,
    sz: f64,
    p: &Params,
) -> R<()> {
    let (depth_axis, cut_axis) = if v.transverse { ("Z", "X") } else { ("X", "Z") };
    let bad = |m: String| Err(fault(AlarmCode::CycleContour, p.call, m));
    if sx * (start[0] - moved[0].to[0]) <= EPS {
        let (at, other) = match (v.transverse, v.inside) {
            (true, _) => ("largest", "smallest"),
            (false, false) => ("largest", "smallest"),
            (false, true) => ("smallest", "largest"),
        };
        return bad(format!(
            "the contour starts at its {at} {depth_axis}: nothing to remove along {cut_axis} (program it from its end at the {other} {depth_axis}, or check VARI)"
        ));
    }
    if non_monotonic(frame, sx, sz).is_some() {
        if let Some(i) = z_turns(start, moved, sz) {
            return bad(format!(
                "element {} of the contour turns back along {cut_axis}, the direction of the cut: undercut elements may turn back in {depth_axis} only",
                i + 1
            ));
        }
    }
    Ok(())
}

/// CYCLE95's moves still to come: to S, the roughing run, the finishing run; every cut at
/// its feed, every rapid with the feed in force at the call (which is in force again after
/// the cycle).
#[derive(Clone, Debug)]
pub struct StockRemovalRun {
    approach: Option<Pos>,
    rough: Option<TurningRun>,
    finish: Option<TurningRun>,
    rough_feed: f64,
    plunge_feed: f64,
    finish_feed: f64,
    feed: f64,
    chip: Option<ChipBreak>,
    /// The depth axis (0 X, 2 Z) and the sign of a move deeper into the stock along it: a
    /// roughing move that goes deeper is an insertion into an undercut (FF2).
    deeper: (usize, f64),
    /// The roughing cut being interrupted for chip breaking: its end, and whether a dwell
    /// comes next.
    cut: Option<(Pos, bool)>,
    at: Pos,
}

impl StockRemovalRun {
    pub fn next(&mut self) -> Option<Step> {
        if let Some(s) = self.piece() {
            return Some(s);
        }
        if let Some(to) = self.approach.take() {
            if to != self.at {
                self.at = to;
                return Some(Step::Move {
                    to,
                    rapid: true,
                    axes: None,
                    feed: Some(self.feed),
                });
            }
        }
        let (step, rough) = self.inner()?;
        let plunge = rough && self.plunges(&step);
        let step = self.with_feed(step, rough, plunge);
        match step {
            Step::Move {
                to, rapid: false, ..
            } if rough && !plunge && self.chip.is_some() => {
                self.cut = Some((to, false));
                self.piece()
            }
            Step::Move { to, .. } | Step::Path { to, .. } | Step::Arc { to, .. } => {
                self.at = to;
                Some(step)
            }
            _ => Some(step),
        }
    }

    /// No step is left.
    pub fn done(&mut self) -> bool {
        self.cut.is_none()
            && self.approach.is_none_or(|to| to == self.at)
            && self.rough.as_mut().is_none_or(TurningRun::done)
            && self.finish.as_mut().is_none_or(TurningRun::done)
    }

    /// The next step of the roughing run, then of the finishing run; true for roughing.
    fn inner(&mut self) -> Option<(Step, bool)> {
        if let Some(r) = self.rough.as_mut() {
            if let Some(s) = r.next() {
                return Some((s, true));
            }
            self.rough = None;
        }
        self.finish.as_mut()?.next().map(|s| (s, false))
    }

    /// Whether a cut goes deeper into the stock: the insertion into an undercut element,
    /// in a pass or along the contour (Cycles, "CYCLE95": FF2).
    fn plunges(&self, step: &Step) -> bool {
        let (axis, deeper) = self.deeper;
        let to = match step {
            Step::Move {
                to, rapid: false, ..
            }
            | Step::Path {
                to, rapid: false, ..
            }
            | Step::Arc { to, .. } => to,
            _ => return false,
        };
        deeper * (to[axis] - self.at[axis]) > EPS
    }

    /// The step with its feed: the cycle's for a cut (FF2 for an insertion into an
    /// undercut), the caller's for a rapid.
    fn with_feed(&self, step: Step, rough: bool, plunge: bool) -> Step {
        let cut = match (rough, plunge) {
            (true, true) => self.plunge_feed,
            (true, false) => self.rough_feed,
            _ => self.finish_feed,
        };
        let of = |rapid: bool| Some(if rapid { self.feed } else { cut });
        match step {
            Step::Move {
                to, rapid, axes, ..
            } => Step::Move {
                to,
                rapid,
                axes,
                feed: of(rapid),
            },
            Step::Path { to, rapid, .. } => Step::Path {
                to,
                rapid,
                feed: of(rapid),
            },
            Step::Arc {
                to, centre, ccw, ..
            } => Step::Arc {
                to,
                centre,
                ccw,
                feed: of(false),
            },
            s => s,
        }
    }

    /// The next piece of a roughing cut interrupted every DAM, or the dwell DT between two
    /// (Cycles, "CYCLE95": DT, DAM).
    fn piece(&mut self) -> Option<Step> {
        let ((end, dwell_next), chip) = (self.cut?, self.chip?);
        if dwell_next {
            self.cut = Some((end, false));
            return Some(Step::Dwell(chip.dwell));
        }
        let d = libm::sqrt((0..3).map(|i| (end[i] - self.at[i]).powi(2)).sum());
        let to = if d <= chip.every + EPS {
            self.cut = None;
            end
        } else {
            let k = chip.every / d;
            self.cut = Some((end, chip.dwell > 0.0));
            std::array::from_fn(|i| self.at[i] + (end[i] - self.at[i]) * k)
        };
        self.at = to;
        Some(Step::Move {
            to,
            rapid: false,
            axes: None,
            feed: Some(self.rough_feed),
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::alarm::{Alarm, AlarmCode};
    use crate::frontend::{interpret, Block, MotionKind};
    use crate::{MachineData, ProgramLibrary, ToolTable};

    /// `main` on the 808D lathe (config/siemens-808d.toml: G18, DIAMON) with the program
    /// files `files` beside it.
    fn lathe(main: &str, files: &[(&str, &str)]) -> Result<Vec<Block>, Alarm> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/siemens-808d.toml");
        let mut md = MachineData::load(Some(std::path::Path::new(path)), &[]).expect("md");
        let mut library = ProgramLibrary::default();
        for (file, text) in files {
            assert!(library.add(file, format!("lib/{file}"), text.to_string()));
        }
        md.programs = std::sync::Arc::new(library);
        interpret("main.mpf", main, &md, &ToolTable::builtin())
    }

    /// (X radius, Z) of every move's end, rounded to 1e-9.
    /// The feed of every move that is no rapid traverse, in order.
    fn cut_feeds(b: &[Block]) -> Vec<f64> {
        b.iter()
            .filter(|b| b.motion.is_some_and(|m| m.kind != MotionKind::Rapid))
            .map(|b| b.modal.feed)
            .collect()
    }

    fn ends(b: &[Block]) -> Vec<(f64, f64)> {
        let r = |v: f64| (v * 1e9).round() / 1e9;
        b.iter()
            .filter_map(|b| b.motion.map(|m| (r(m.end[0]), r(m.end[2]))))
            .collect()
    }

    /// A roughing pass at `level` from S's Z `zs` to `z`, lifted off by `vrt` (outside:
    /// up in X, back in Z).
    fn pass(level: f64, z: f64, zs: f64, vrt: f64, sx: f64) -> [(f64, f64); 4] {
        let up = level + sx * vrt;
        [(level, zs), (level, z), (up, z + vrt), (up, zs)]
    }

    /// `got` and `want` the same moves to 1e-9.
    fn assert_near(got: &[(f64, f64)], want: &[(f64, f64)]) {
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9,
                "{got:?}"
            );
        }
    }

    fn run(main: &str, files: &[(&str, &str)]) -> Vec<Block> {
        lathe(main, files).unwrap_or_else(|a| panic!("{a}"))
    }

    /// The tests of the passes' geometry run with D0 (no offset: nose radius 0, the cycle's
    /// compensation moves nothing); `nose_radius_*` with D1 (R 0.8, edge position 3).
    const HEAD: &str = "G18 G90 G95 T1 D0 S1000 M3 F0.25\nG0 X60 Z5\n";

    #[test]
    fn nose_radius_compensates_the_passes_and_the_finishing() {
        // T1 D1: nose R 0.8, edge position 3; outside towards the chuck: the cycle's G42.
        // Contour (radius, Z): A' (10, 0), (10, −20), (20, −20), (20, −40), B (25, −40).
        // Nose centre: X 10.8 from Z 0 to the face's parallel Z −19.2 (concave corner
        // trimmed), the face to X 20, an arc of 0.8 about the edge (20, −20) to (20.8, −20),
        // X 20.8 to the next face's parallel Z −39.2, up to X 25. The tip (−0.8, −0.8 from
        // the centre): A' (10, −0.8), (10, −20), (19.2, −20), the arc about (19.2, −20.8) to
        // (20, −20.8), (20, −40), (24.2, −40). S = (24.2, −0.8 + 0.5). Stock 14.2, MID 2.5:
        // 6 cuts of 14.2/6; passes at 24.2 − 14.2k/6: 21.8333 meets the last face (Z −40),
        // 19.4667 the edge's arc at Z −20.8 + √(0.64 − (19.4667 − 19.2)²), the lower three
        // the face at Z −20.
        let main = "G18 G90 G95 T1 D1 S1000 M3 F0.25\nG0 X60 Z5\nCYCLE95(\"START:END\", 2.5, , , , 0.3, , 0.1, 9, , , 0.5)\nM30\nSTART: G0 X20 Z0\nG1 Z-20\nX40\nZ-40\nEND: X50\n";
        let b = run(main, &[]);
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let zs = -0.3;
        let mut want = vec![(30.0, 5.0), (24.2, zs)];
        for k in 1..=5 {
            let level = 24.2 - 14.2 * k as f64 / 6.0;
            let z = match k {
                1 => -40.0,
                2 => -20.8 + (0.64 - (level - 19.2f64).powi(2)).sqrt(),
                _ => -20.0,
            };
            want.extend(pass(r(level), r(z), zs, 0.5, 1.0));
        }
        want.extend([(10.0, -0.8), (10.0, -20.0), (19.2, -20.0), (20.0, -20.8)]);
        want.extend([(20.0, -40.0), (24.2, -40.0), (24.2, zs)]);
        // Finishing: the contour as programmed, G42 with the G0 to A', G40 with the return.
        want.extend([(10.0, 0.0), (10.0, -20.0), (20.0, -20.0), (20.0, -40.0)]);
        want.extend([(25.0, -40.0), (24.2, -40.0), (24.2, zs)]);
        let got = ends(&b);
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g.0 - w.0).abs() < 1e-8 && (g.1 - w.1).abs() < 1e-8,
                "{got:?}"
            );
        }
        let sides: Vec<_> = b.iter().filter_map(|b| b.trc).collect();
        assert_eq!(sides, [crate::TrcSide::Right, crate::TrcSide::Off]);
        // A nose of 0.8 in a concave R0.5 of the contour: 61605 at the call.
        let a = lathe(
            "G18 G90 G95 T1 D1 S1000 M3 F0.25\nG0 X60 Z5\nCYCLE95(\"START:END\", 2.5, , , , 0.3, , 0.1, 9)\nM30\nSTART: G0 X20 Z0\nG1 Z-20\nG2 X21 Z-20.5 CR=0.5\nG1 X40\nEND: Z-40\n",
            &[],
        )
        .unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::CycleContour, 3, 1));
    }

    #[test]
    fn complete_machining_of_a_label_section() {
        // Contour (radius, Z): A' (10, 0), (10, −20), (20, −20), (20, −40), B (25, −40).
        // FALX 0.2, FALZ 0.1 shift it by (+0.2, +0.1): (10.2, 0.1) … (25.2, −39.9).
        // S = (the shifted contour's largest X 25.2, 0.1 + _VRT 0.5 = 0.6). The stock from
        // S's X to A' is 15: MID 2 gives ⌈7.5⌉ = 8 equal cuts of 1.875; seven passes at
        // 25.2 − 1.875k (k = 1 … 7), the eighth is the run along the shifted contour.
        // Levels above 20.2 meet the face at Z −39.9, those below it the one at −19.9.
        let main = format!(
            "{HEAD}CYCLE95(\"START:END\", 2, 0.1, 0.2, , 0.3, 0.2, 0.1, 9, , , 0.5)\nG1 X70\nM30\nSTART: G0 X20 Z0\nG1 Z-20\nX40\nZ-40\nEND: X50\n"
        );
        let b = run(&main, &[]);
        let mut want = vec![(30.0, 5.0), (25.2, 0.6)];
        for k in 1..=7 {
            let level = 25.2 - 1.875 * k as f64;
            let z = if level > 20.2 { -39.9 } else { -19.9 };
            want.extend(pass((level * 1e9).round() / 1e9, z, 0.6, 0.5, 1.0));
        }
        // The last roughing cut along the shifted contour, back to S (X is there).
        want.extend([
            (10.2, 0.1),
            (10.2, -19.9),
            (20.2, -19.9),
            (20.2, -39.9),
            (25.2, -39.9),
            (25.2, 0.6),
        ]);
        // Finishing: the contour itself from S, back to S (X first, then Z).
        want.extend([
            (10.0, 0.0),
            (10.0, -20.0),
            (20.0, -20.0),
            (20.0, -40.0),
            (25.0, -40.0),
            (25.2, -40.0),
            (25.2, 0.6),
            (35.0, 0.6),
        ]);
        let got = ends(&b);
        assert_near(&got, &want);
        // Cuts at FF1 0.3, the finishing at FF3 0.1, the rapids and the next block at F0.25.
        let feeds: Vec<(MotionKind, f64)> = b
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.kind, b.modal.feed)))
            .collect();
        assert_eq!(feeds[3], (MotionKind::Linear, 0.3));
        assert_eq!(feeds[4], (MotionKind::Rapid, 0.25));
        assert_eq!(feeds[31], (MotionKind::Linear, 0.3));
        assert_eq!(feeds[37], (MotionKind::Linear, 0.1));
        assert_eq!(feeds.last(), Some(&(MotionKind::Linear, 0.25)));
    }

    #[test]
    fn fal_offsets_the_contour_normal_to_its_elements() {
        // The contour of the first test with FAL 0.5 instead of FALZ/FALX, on the outside
        // (the right of travel in (Z, X)): A' (10.5, 0), X 10.5 to the first face's parallel
        // at Z −19.5, that face to X 20, an arc of 0.5 about the edge (20, −20) to
        // (20.5, −20), X 20.5 to the last face's parallel at Z −39.5, B (25, −39.5).
        // S = (25, 0 + 1) (_VRT left out). Stock 14.5, MID 5: 3 cuts of 14.5/3; passes at
        // 20.1667, which meets the edge's arc at Z −20 + √(0.25 − (1/6)²) = −20 + √2/3, and
        // 15.3333, which meets the face at Z −19.5.
        let main = format!(
            "{HEAD}CYCLE95(\"START:END\", 5, , , 0.5, 0.3, , , 1)\nM30\nSTART: G0 X20 Z0\nG1 Z-20\nX40\nZ-40\nEND: X50\n"
        );
        let b = run(&main, &[]);
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let mut want = vec![(30.0, 5.0), (25.0, 1.0)];
        want.extend(pass(
            r(25.0 - 14.5 / 3.0),
            r(-20.0 + 2f64.sqrt() / 3.0),
            1.0,
            1.0,
            1.0,
        ));
        want.extend(pass(r(25.0 - 29.0 / 3.0), -19.5, 1.0, 1.0, 1.0));
        want.extend([
            (10.5, 0.0),
            (10.5, -19.5),
            (20.0, -19.5),
            (20.5, -20.0),
            (20.5, -39.5),
            (25.0, -39.5),
            (25.0, 1.0),
        ]);
        let got = ends(&b);
        assert_near(&got, &want);
    }

    const SHAFT: &str = "PROC SHAFT\nG1 X10 Z0\nZ-10 RND=2\nX30\nZ-20\nX36 Z-26\nM17\n";

    #[test]
    fn roughing_a_subprogram_contour_with_a_rounding_and_a_taper() {
        // SHAFT.SPF (radius, Z): A' (5, 0), (5, −10) rounded by RND=2 into the face to
        // (15, −10): the line ends at (5, −8), the arc about (7, −8) at (7, −10); then
        // (15, −20) and the taper to B (18, −26). No allowances, _VRT left out: 1 mm.
        // S = (18, 1). Stock 13, MID 3: ⌈4.33⌉ = 5 cuts of 2.6: passes at 15.4, 12.8, 10.2,
        // 7.6. 15.4 meets the taper at Z = −20 − (15.4 − 15)·6/3 = −20.8; the others the
        // face at Z −10.
        let b = run(
            &format!("{HEAD}CYCLE95(\"SHAFT\", 3, , , , 0.3, , , 1)\nG0 X60 Z10\n"),
            &[("SHAFT.SPF", SHAFT)],
        );
        let mut want = vec![(30.0, 5.0), (18.0, 1.0)];
        want.extend(pass(15.4, -20.8, 1.0, 1.0, 1.0));
        for level in [12.8, 10.2, 7.6] {
            want.extend(pass(level, -10.0, 1.0, 1.0, 1.0));
        }
        want.extend([
            (5.0, 0.0),
            (5.0, -8.0),
            (7.0, -10.0),
            (15.0, -10.0),
            (15.0, -20.0),
            (18.0, -26.0),
            (18.0, 1.0),
            (30.0, 10.0),
        ]);
        assert_eq!(ends(&b), want);
        let arcs: Vec<[f64; 3]> = b
            .iter()
            .filter_map(|b| b.motion.filter(|m| m.kind.is_arc()).map(|m| m.center))
            .collect();
        assert_eq!(arcs, [[7.0, 0.0, -8.0]]);
        // Radius programming (DIAMOF in the caller, the contour in radii, RND= a radius as
        // always): the same passes; the block after the cycle X30 is a radius too.
        let radii = "G1 X5 Z0\nZ-10 RND=2\nX15\nZ-20\nX18 Z-26\n";
        let r = run(
            &format!("{HEAD}DIAMOF\nCYCLE95(\"R\", 3, , , , 0.3, , , 1)\nG0 X30 Z10\n"),
            &[("R.SPF", radii)],
        );
        assert_eq!(ends(&r), want);
    }

    #[test]
    fn inside_roughing_breaks_chips_every_dam() {
        // A bore (radius, Z): A' (20, 0), (20, −10), (15, −10), (15, −20), B (10, −20).
        // Inside: FALX 0.5 moves X down, FALZ 0.1 moves Z up: (19.5, 0.1) … (9.5, −19.9).
        // S = (9.5, 0.6); stock 10, MID 2.5: 4 cuts, passes at 12, 14.5, 17. 12 meets the
        // face at −19.9, the others the face at −9.9. DAM 4: each cut stops 4 mm at a time
        // (from Z 0.6: −3.4, −7.4, …) with DT 0.5 s between; the lift-off goes down in X.
        let b = run(
            "G18 G90 G95 T1 D0 S1000 M3 F0.25\nG0 X10 Z5\nCYCLE95(\"BORE\", 2.5, 0.1, 0.5, , 0.3, , , 3, 0.5, 4, 0.5)\n",
            &[("BORE.SPF", "G0 X40 Z0\nG1 Z-10\nX30\nZ-20\nX20\n")],
        );
        let mut want = vec![(5.0, 5.0), (9.5, 0.6), (12.0, 0.6)];
        want.extend([-3.4, -7.4, -11.4, -15.4, -19.4, -19.9].map(|z| (12.0, z)));
        want.extend([(11.5, -19.4), (11.5, 0.6)]);
        for level in [14.5, 17.0] {
            want.push((level, 0.6));
            want.extend([-3.4, -7.4, -9.9].map(|z| (level, z)));
            want.extend([(level - 0.5, -9.4), (level - 0.5, 0.6)]);
        }
        want.extend([
            (19.5, 0.1),
            (19.5, -9.9),
            (14.5, -9.9),
            (14.5, -19.9),
            (9.5, -19.9),
            (9.5, 0.6),
        ]);
        assert_eq!(ends(&b), want);
        let dwells: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
        assert_eq!(dwells, [0.5; 9]);
    }

    /// The bore of `inside_roughing_breaks_chips_every_dam`, in diameters and in radii:
    /// A' (radius 20, Z 0), (20, −10), (15, −10), (15, −20), B (10, −20).
    const BORE_DIAMETERS: &str = "G0 X40 Z0\nG1 Z-10\nX30\nZ-20\nX20\n";
    const BORE_RADII: &str = "G0 X20 Z0\nG1 Z-10\nX15\nZ-20\nX10\n";

    /// The bore's finishing from S (9.5, 0.6): G0 to A', the contour, G0 back to S with X
    /// first (in to S's X at B's Z, then out along Z), then the block after the cycle.
    const BORE_FINISHING: [(f64, f64); 8] = [
        (20.0, 0.0),
        (20.0, -10.0),
        (15.0, -10.0),
        (15.0, -20.0),
        (10.0, -20.0),
        (9.5, -20.0),
        (9.5, 0.6),
        (5.0, 10.0),
    ];

    /// `CYCLE95("BORE", …, vari, …)` on the bore from (radius 5, Z 5), with X a diameter
    /// (DIAMON) or a radius (DIAMOF) in the program and the contour alike.
    fn bore(vari: u32, diamof: bool) -> Vec<Block> {
        let (mode, start, spf) = match diamof {
            true => ("DIAMOF", "X5", BORE_RADII),
            false => ("DIAMON", "X10", BORE_DIAMETERS),
        };
        let cycle = format!("CYCLE95(\"BORE\", 2, 0.1, 0.5, , 0.3, , 0.1, {vari}, , , 0.5)");
        let main = format!(
            "G18 G90 G95 T1 D0 S1000 M3 F0.25\n{mode}\nG0 {start} Z5\n{cycle}\nG0 {start} Z10\n"
        );
        run(&main, &[("BORE.SPF", spf)])
    }

    #[test]
    fn inside_complete_machining_roughs_the_bore_then_finishes_it() {
        // VARI 11 (complete, longitudinal inside). FALX 0.5 moves X in (towards the
        // centre), FALZ 0.1 towards the cut's start: A'm (19.5, 0.1), (19.5, −9.9),
        // (14.5, −9.9), (14.5, −19.9), Bm (9.5, −19.9). S = (the smallest X 9.5, 0.1 +
        // _VRT 0.5). Stock 19.5 − 9.5 = 10, MID 2: 5 cuts of 2, passes at 9.5 + 2k: 11.5 and
        // 13.5 meet the face at −19.9 (the wall 14.5 lies outside them), 15.5 and 17.5 the
        // face at −9.9. Each lifted off 0.5 at 45° (X in, Z back) and back to Z 0.6.
        let mut want = vec![(5.0, 5.0), (9.5, 0.6)];
        for (level, z) in [(11.5, -19.9), (13.5, -19.9), (15.5, -9.9), (17.5, -9.9)] {
            want.extend(pass(level, z, 0.6, 0.5, -1.0));
        }
        // The moved contour from A'm at FF1, home X first (there), then Z.
        want.extend([(19.5, 0.1), (19.5, -9.9), (14.5, -9.9), (14.5, -19.9)]);
        want.extend([(9.5, -19.9), (9.5, 0.6)]);
        want.extend(BORE_FINISHING);
        for diamof in [false, true] {
            let b = bore(11, diamof);
            assert_near(&ends(&b), &want);
            // Four passes and the moved contour's four moves at FF1, the contour at FF3.
            let feeds = cut_feeds(&b);
            assert_eq!(feeds, [[0.3; 8].as_slice(), &[0.1; 4]].concat());
        }
    }

    #[test]
    fn inside_finishing_alone_goes_from_s_to_the_contour_and_back() {
        // VARI 7 with the same parameters: S as for roughing (the allowances still place
        // it), then the finishing only; MID is not needed.
        let mut want = vec![(5.0, 5.0), (9.5, 0.6)];
        want.extend(BORE_FINISHING);
        for diamof in [false, true] {
            assert_eq!(ends(&bore(7, diamof)), want);
        }
    }

    #[test]
    fn an_inside_undercut_is_roughed_level_by_level_outwards() {
        // VARI 3 (roughing, longitudinal inside), an inner groove (radius, Z): A' (16, 0),
        // (16, −5), a 45° taper out into the groove to (22, −11), (22, −13), its back face
        // in to (18, −13), (18, −20), B (12, −20). X turns back (goes out again): an
        // undercut. No allowances, _VRT 1: S = (the smallest X 12, 0 + 1). The deepest
        // point is the groove's X 22, 10 beyond S: MID 2.5 gives 4 cuts of 2.5, levels at
        // X 14.5, 17, 19.5; the boundary runs from S to A' first (X = 12 + 4t, Z = 1 − t).
        // 14.5: from that line (t = 0.625: Z 0.375), in at rapid, to the face at −20;
        //   lift-off 1 (X in, Z back) to (13.5, −19).
        // 17: the taper (X = 11 − Z) passes it at Z −6, the stretch ends at the face −20;
        //   the way there passes only the level 14.5 cut (the stretch's start lies on 17):
        //   along Z at 14.5 − 1, G0 out to 14.5, in to 17 at FF2; lift-off to (16, −19).
        // 19.5: the taper at Z −8.5 to the groove's back face at −13; over the bore X 18
        //   (6 beyond S: two levels cut) at 17 − 1, G0 out to 17, in at FF2; lift-off to
        //   (18.5, −12), the Z part 1 within the stretch.
        // Back over the stock to S's X (the way passes the S–A' line), to S; the contour
        // from S, its taper out into the groove at FF2; home X first (there).
        let want = [
            (5.0, 5.0),
            (12.0, 1.0),
            (12.0, 0.375),
            (14.5, 0.375),
            (14.5, -20.0),
            (13.5, -19.0),
            (13.5, -6.0),
            (14.5, -6.0),
            (17.0, -6.0),
            (17.0, -20.0),
            (16.0, -19.0),
            (16.0, -8.5),
            (17.0, -8.5),
            (19.5, -8.5),
            (19.5, -13.0),
            (18.5, -12.0),
            (12.0, -12.0),
            (12.0, 1.0),
            (16.0, 0.0),
            (16.0, -5.0),
            (22.0, -11.0),
            (22.0, -13.0),
            (18.0, -13.0),
            (18.0, -20.0),
            (12.0, -20.0),
            (12.0, 1.0),
        ];
        let cycle = "CYCLE95(\"I\", 2.5, , , , 0.3, 0.1, , 3, , , 1)";
        let diameters = "G1 X32 Z0\nZ-5\nX44 Z-11\nZ-13\nX36\nZ-20\nX24\n";
        let radii = "G1 X16 Z0\nZ-5\nX22 Z-11\nZ-13\nX18\nZ-20\nX12\n";
        for (mode, start, spf) in [("DIAMON", "X10", diameters), ("DIAMOF", "X5", radii)] {
            let main = format!("G18 G90 G95 T1 D0 S1000 M3\n{mode}\nG0 {start} Z5\n{cycle}\n");
            let b = run(&main, &[("I.SPF", spf)]);
            assert_eq!(ends(&b), want, "{mode}");
            // The in-feeds at 17 and 19.5 and the taper along the contour at FF2 0.1.
            let slow: Vec<(f64, f64)> = b
                .iter()
                .filter(|b| {
                    b.modal.feed == 0.1 && b.motion.is_some_and(|m| m.kind != MotionKind::Rapid)
                })
                .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[2])))
                .collect();
            assert_eq!(slow, [(17.0, -6.0), (19.5, -8.5), (22.0, -11.0)], "{mode}");
        }
    }

    /// An inside face (a counterbore's bottom and wall), from its smallest X at its
    /// deepest Z outwards (radius, Z): A' (6, −5), (12, −5), the wall to (12, −2), a 45°
    /// chamfer to (14, 0), the front face to B (25, 0).
    const COUNTERBORE_DIAMETERS: &str = "G1 X12 Z-5\nX24\nZ-2\nX28 Z0\nX50\n";
    const COUNTERBORE_RADII: &str = "G1 X6 Z-5\nX12\nZ-2\nX14 Z0\nX25\n";

    /// `CYCLE95("H", …, vari, …)` on the counterbore from (radius 4, Z 5).
    fn counterbore(vari: u32, diamof: bool) -> Vec<Block> {
        let (mode, start, spf) = match diamof {
            true => ("DIAMOF", "X4", COUNTERBORE_RADII),
            false => ("DIAMON", "X8", COUNTERBORE_DIAMETERS),
        };
        let cycle = format!("CYCLE95(\"H\", 1.5, 0.2, 0.1, , 0.25, , 0.08, {vari}, , , 1)");
        let main = format!("G18 G90 G95 T1 D0 S1000 M3 F0.25\n{mode}\nG0 {start} Z5\n{cycle}\n");
        run(&main, &[("H.SPF", spf)])
    }

    /// The counterbore's finishing from S (4.9, 0.2): G0 to A', the contour, G0 back to S
    /// with Z first (out of the face to S's Z at B's X, then in along X).
    const COUNTERBORE_FINISHING: [(f64, f64); 7] = [
        (6.0, -5.0),
        (12.0, -5.0),
        (12.0, -2.0),
        (14.0, 0.0),
        (25.0, 0.0),
        (25.0, 0.2),
        (4.9, 0.2),
    ];

    #[test]
    fn inside_face_machining_cuts_outwards_in_levels_of_z_then_finishes() {
        // VARI 12 (complete, transverse inside). FALZ 0.2 moves the faces to +Z, FALX 0.1
        // the wall against the cut (in, −X): A'm (5.9, −4.8), (11.9, −4.8), (11.9, −1.8),
        // (13.9, 0.2), Bm (24.9, 0.2). S = (A'm's X − _VRT 1 = 4.9, the largest Z 0.2).
        // Stock 0.2 − (−4.8) = 5 along Z, MID 1.5: 4 cuts of 1.25, levels at Z −1.05, −2.3,
        // −3.55. Each: G0 in along Z at X 4.9, G1 along +X to the moved contour (−1.05 the
        // chamfer at X 11.9 + (−1.05 + 1.8) = 12.65, the others the wall X 11.9), lift-off
        // 1 (Z up, X back in), G0 back to X 4.9.
        let mut want = vec![(4.0, 5.0), (4.9, 0.2)];
        for (z, x) in [(-1.05, 12.65), (-2.3, 11.9), (-3.55, 11.9)] {
            let r = |v: f64| (v * 1e9).round() / 1e9;
            want.extend([
                (4.9, z),
                (x, z),
                (r(x - 1.0), r(z + 1.0)),
                (4.9, r(z + 1.0)),
            ]);
        }
        // The moved contour at FF1; home Z first (there), then X.
        want.extend([(5.9, -4.8), (11.9, -4.8), (11.9, -1.8), (13.9, 0.2)]);
        want.extend([(24.9, 0.2), (4.9, 0.2)]);
        want.extend(COUNTERBORE_FINISHING);
        for diamof in [false, true] {
            let b = counterbore(12, diamof);
            assert_near(&ends(&b), &want);
            let feeds = cut_feeds(&b);
            assert_eq!(feeds, [[0.25; 7].as_slice(), &[0.08; 4]].concat());
        }
        // VARI 8: the finishing alone, from the same S.
        let mut want = vec![(4.0, 5.0), (4.9, 0.2)];
        want.extend(COUNTERBORE_FINISHING);
        for diamof in [false, true] {
            assert_near(&ends(&counterbore(8, diamof)), &want);
        }
    }

    #[test]
    fn finishing_runs_the_contour_from_s_and_back() {
        // VARI 5: from (30, 5) to S (18, 1) at rapid, to A' (5, 0) at rapid, along the
        // contour at FF3, back to S; MID may be left out.
        let b = run(
            &format!("{HEAD}CYCLE95(\"SHAFT\", , , , , , , 0.1, 5)\nG1 X40\n"),
            &[("SHAFT.SPF", SHAFT)],
        );
        assert_eq!(
            ends(&b),
            [
                (30.0, 5.0),
                (18.0, 1.0),
                (5.0, 0.0),
                (5.0, -8.0),
                (7.0, -10.0),
                (15.0, -10.0),
                (15.0, -20.0),
                (18.0, -26.0),
                (18.0, 1.0),
                (20.0, 1.0)
            ]
        );
        let f: Vec<f64> = b.iter().map(|b| b.modal.feed).collect();
        assert_eq!((f[4], f[f.len() - 1]), (0.1, 0.25));
    }

    #[test]
    fn under_diamof_the_contour_is_read_in_radii() {
        // SHAFT.SPF's contour written with X as a radius after DIAMOF in the caller: the
        // same finishing as under DIAMON (the contour's interpreter starts in the
        // caller's modal state).
        let radii = "G1 X5 Z0\nZ-10 RND=2\nX15\nZ-20\nX18 Z-26\n";
        let b = run(
            &format!("{HEAD}DIAMOF\nCYCLE95(\"R\", , , , , , , 0.1, 5)\n"),
            &[("R.SPF", radii)],
        );
        let d = run(
            &format!("{HEAD}CYCLE95(\"SHAFT\", , , , , , , 0.1, 5)\n"),
            &[("SHAFT.SPF", SHAFT)],
        );
        assert_eq!(ends(&b), ends(&d));
        assert_eq!(ends(&b)[2..4], [(5.0, 0.0), (5.0, -8.0)]);
    }

    /// A shaft with an undercut (diameters): A' (radius 5, Z 0), (5, −10), the face to
    /// (15, −10), (15, −15), the taper down into the undercut to (10, −20), (10, −25), the
    /// face up to (15, −25), (15, −30), B (20, −30).
    const UNDERCUT: &str = "G1 X10 Z0\nZ-10\nX30\nZ-15\nX20 Z-20\nZ-25\nX30\nZ-30\nX40\n";

    #[test]
    fn undercuts_are_roughed_level_by_level_with_ff2_into_them() {
        // No allowances, _VRT 1: S = (B's X 20, 0 + 1). The stock reaches down to A' (depth
        // 15 below S): MID 4 gives ⌈3.75⌉ = 4 cuts of 3.75, levels at X 16.25, 12.5, 8.75;
        // the boundary runs from S to A' first (X = 20 − 15t, Z = 1 − t).
        // Level 16.25: one stretch, from the S–A' line at Z 0.75 to the last face at −30;
        //   lift-off to (17.25, −29).
        // Level 12.5: stretches (0.5 → the face at −10) and (the taper at −17.5 → the
        //   face at −25). Over the stock the shallowest point is X 15 (depth 5), so the
        //   deepest level cut over the way is 3.75, less e: X 17.25. The second stretch: up
        //   to 17.25, along Z, down at rapid to the level above (16.25), in to 12.5 at FF2.
        // Level 8.75: one stretch (0.25 → −10); X 10 of the undercut stays above it.
        // Back over the stock to X 20 (S's X: the way passes the S–A' line), to S; the
        // shifted contour from S, its falling taper at FF2; home X first.
        let main = format!("{HEAD}CYCLE95(\"U\", 4, , , , 0.3, 0.1, , 1, , , 1)\nM30\n");
        let b = run(&main, &[("U.SPF", UNDERCUT)]);
        let want = [
            (30.0, 5.0),
            (20.0, 1.0),
            (20.0, 0.75),
            (16.25, 0.75),
            (16.25, -30.0),
            (17.25, -29.0),
            (17.25, 0.5),
            (12.5, 0.5),
            (12.5, -10.0),
            (13.5, -9.0),
            (17.25, -9.0),
            (17.25, -17.5),
            (16.25, -17.5),
            (12.5, -17.5),
            (12.5, -25.0),
            (13.5, -24.0),
            (17.25, -24.0),
            (17.25, 0.25),
            (8.75, 0.25),
            (8.75, -10.0),
            (9.75, -9.0),
            (20.0, -9.0),
            (20.0, 1.0),
            (5.0, 0.0),
            (5.0, -10.0),
            (15.0, -10.0),
            (15.0, -15.0),
            (10.0, -20.0),
            (10.0, -25.0),
            (15.0, -25.0),
            (15.0, -30.0),
            (20.0, -30.0),
            (20.0, 1.0),
        ];
        assert_eq!(ends(&b), want);
        // The cuts: FF1 0.3, the insertions into the undercut (the in-feed at Z −17.5, the
        // taper along the contour) FF2 0.1.
        let cuts: Vec<((f64, f64), f64)> = b
            .iter()
            .filter_map(|b| b.motion.map(|m| (m, b.modal.feed)))
            .filter(|(m, _)| m.kind != MotionKind::Rapid)
            .map(|(m, f)| ((m.end[0], m.end[2]), f))
            .collect();
        let slow: Vec<(f64, f64)> = cuts.iter().filter(|c| c.1 == 0.1).map(|c| c.0).collect();
        assert_eq!(slow, [(12.5, -17.5), (10.0, -20.0)]);
        assert!(cuts.iter().all(|c| c.1 == 0.1 || c.1 == 0.3), "{cuts:?}");
        assert_eq!(cuts.len(), 5 + 8);
        // Radius programming (DIAMOF, the contour in radii): the same moves.
        let radii = "G1 X5 Z0\nZ-10\nX15\nZ-15\nX10 Z-20\nZ-25\nX15\nZ-30\nX20\n";
        let r = run(
            &format!("{HEAD}DIAMOF\nCYCLE95(\"U\", 4, , , , 0.3, 0.1, , 1, , , 1)\n"),
            &[("U.SPF", radii)],
        );
        assert_eq!(ends(&r), want);
    }

    /// A face contour outside, from the outer diameter towards the centre (diameters):
    /// A' (radius 30, Z −10), (20, −10), (20, −5), (10, −5), (10, 0), B (0, 0).
    const FACE: &str = "G1 X60 Z-10\nX40\nZ-5\nX20\nZ0\nX0\n";

    #[test]
    fn transverse_machining_cuts_along_x_in_levels_of_z() {
        // VARI 10 (complete, transverse outside). FALZ 0.2 moves the faces to +Z, FALX 0.1
        // the diameters out: A'm (30.1, −9.8), (20.1, −9.8), (20.1, −4.8), (10.1, −4.8),
        // (10.1, 0.2), Bm (0.1, 0.2). S = (A'm's X + _VRT 1 = 31.1, the largest Z 0.2).
        // Stock 0.2 − (−9.8) = 10 in Z, MID 3: 4 cuts of 2.5, levels at Z −2.3, −4.8, −7.3.
        // Each: G0 in along Z at X 31.1, G1 along −X to the contour (−2.3 meets the wall
        // X 10.1, −4.8 and −7.3 the wall X 20.1), lift-off 1 in Z and X (Z up, X out), G0
        // back to X 31.1.
        let mut want = vec![(30.0, 5.0), (31.1, 0.2)];
        for (z, x) in [(-2.3, 10.1), (-4.8, 20.1), (-7.3, 20.1)] {
            let r = |v: f64| (v * 1e9).round() / 1e9;
            want.extend([(31.1, z), (x, z), (x + 1.0, r(z + 1.0)), (31.1, r(z + 1.0))]);
        }
        // The shifted contour at FF1; home Z first (there), then X.
        want.extend([
            (30.1, -9.8),
            (20.1, -9.8),
            (20.1, -4.8),
            (10.1, -4.8),
            (10.1, 0.2),
            (0.1, 0.2),
            (31.1, 0.2),
        ]);
        // Finishing: G0 to A', the contour at FF3, G0 home Z first, then X.
        want.extend([
            (30.0, -10.0),
            (20.0, -10.0),
            (20.0, -5.0),
            (10.0, -5.0),
            (10.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.2),
            (31.1, 0.2),
        ]);
        let cycle = "CYCLE95(\"F\", 3, 0.2, 0.1, , 0.3, , 0.1, 10, , , 1)";
        let b = run(&format!("{HEAD}{cycle}\nM30\n"), &[("F.SPF", FACE)]);
        let got = ends(&b);
        assert_near(&got, &want);
        // The cuts along X at FF1, the finishing at FF3.
        let feeds = cut_feeds(&b);
        assert_eq!(feeds, [[0.3; 8].as_slice(), &[0.1; 5]].concat());
        // Radius programming: the same moves.
        let radii = "G1 X30 Z-10\nX20\nZ-5\nX10\nZ0\nX0\n";
        let r = run(
            &format!("{HEAD}DIAMOF\n{cycle}\nM30\n"),
            &[("F.SPF", radii)],
        );
        assert_eq!(ends(&r), got);
    }

    #[test]
    fn fal_on_a_face_lies_on_the_stock_side() {
        // Transverse outside, roughing (VARI 2), FAL 0.5: A' (30, −10), (20, −10), (20, 0),
        // B (0, 0). The equidistant on the stock's side: the back face to Z −9.5, the wall
        // to X 20.5 (the concave corner trimmed at (20.5, −9.5)), the front face to Z 0.5,
        // the convex corner (20, 0) rounded by an arc of 0.5 about it. S = (30 + _VRT 1,
        // 0.5); the stock 10 in one cut of MID 10: no pass, only the run along it.
        let b = run(
            &format!("{HEAD}CYCLE95(\"F\", 10, , , 0.5, 0.3, , , 2)\nM30\n"),
            &[("F.SPF", "G1 X60 Z-10\nX40\nZ0\nX0\n")],
        );
        assert_eq!(
            ends(&b),
            [
                (30.0, 5.0),
                (31.0, 0.5),
                (30.0, -9.5),
                (20.5, -9.5),
                (20.5, 0.0),
                (20.0, 0.5),
                (0.0, 0.5),
                (31.0, 0.5)
            ]
        );
        let arcs: Vec<[f64; 3]> = b
            .iter()
            .filter_map(|b| b.motion.filter(|m| m.kind.is_arc()).map(|m| m.center))
            .collect();
        assert_eq!(arcs, [[20.0, 0.0, 0.0]]);
    }

    #[test]
    fn a_face_undercut_is_roughed_as_pockets_in_z() {
        // Transverse inside (VARI 4): the passes cut along +X, from the bore outwards.
        // Radius: A' (5, −6), (10, −6), (10, −2), a flank down into the face to (14, −4),
        // (18, −4), (18, 0), B (25, 0): Z turns back (an undercut in the face), X goes one
        // way. No allowances, _VRT 1: S = (A''s X − 1 = 4, the largest Z 0). The deepest
        // point is A' (6 below S): MID 2.5 gives ⌈2.4⌉ = 3 cuts of 2, levels at Z −2, −4.
        // The boundary runs from S to A' first (X = 4 + t, Z = −6t).
        // Z −2: from that line at X 13/3 out along +X; the wall X 10 comes up to −2 and the
        //   flank goes down again at once (a ridge touching the level): one stretch to the
        //   wall X 18; lift-off 1 (Z up, X back) to (17, −1).
        // Z −4: up to Z 0 (the ridge's top lies on the level cut, nothing deeper is cut
        //   over the whole way), along Z 0 to X 14/3, in at rapid, along +X to the wall X 10
        //   (the groove's bottom lies on the level: the contour's own), lift-off to (9, −3).
        // Back to S over Z 0; the contour from S, its flank into the groove at FF2; home
        // Z first (there), then X.
        let spf = "G1 X10 Z-6\nX20\nZ-2\nX28 Z-4\nX36\nZ0\nX50\n";
        let b = run(
            &format!("{HEAD}G0 X8 Z5\nCYCLE95(\"G\", 2.5, , , , 0.3, 0.1, , 4, , , 1)\nM30\n"),
            &[("G.SPF", spf)],
        );
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let want = [
            (30.0, 5.0),
            (4.0, 5.0),
            (4.0, 0.0),
            (r(13.0 / 3.0), 0.0),
            (r(13.0 / 3.0), -2.0),
            (18.0, -2.0),
            (17.0, -1.0),
            (17.0, 0.0),
            (r(14.0 / 3.0), 0.0),
            (r(14.0 / 3.0), -4.0),
            (10.0, -4.0),
            (9.0, -3.0),
            (9.0, 0.0),
            (4.0, 0.0),
            (5.0, -6.0),
            (10.0, -6.0),
            (10.0, -2.0),
            (14.0, -4.0),
            (18.0, -4.0),
            (18.0, 0.0),
            (25.0, 0.0),
            (4.0, 0.0),
        ];
        assert_eq!(ends(&b), want);
        let slow: Vec<(f64, f64)> = b
            .iter()
            .filter(|b| {
                b.modal.feed == 0.1 && b.motion.is_some_and(|m| m.kind != MotionKind::Rapid)
            })
            .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[2])))
            .collect();
        assert_eq!(slow, [(14.0, -4.0)]);
        // Radius programming (DIAMOF, the contour and the start in radii): the same moves.
        let radii = "G1 X5 Z-6\nX10\nZ-2\nX14 Z-4\nX18\nZ0\nX25\n";
        let r = run(
            &format!("{HEAD}DIAMOF\nG0 X4 Z5\nCYCLE95(\"G\", 2.5, , , , 0.3, 0.1, , 4, , , 1)\n"),
            &[("G.SPF", radii)],
        );
        assert_eq!(ends(&r), want);
    }

    /// The alarm of cycle `cycle` (line 3) with SHAFT.SPF beside it: code, program, line,
    /// column.
    fn alarm(cycle: &str, files: &[(&str, &str)]) -> (AlarmCode, String, u32, u32) {
        let a = lathe(&format!("{HEAD}{cycle}\nM30\n"), files).unwrap_err();
        (a.code, a.program, a.line, a.col)
    }

    fn main_at(code: AlarmCode, col: u32) -> (AlarmCode, String, u32, u32) {
        (code, "main.mpf".into(), 3, col)
    }

    #[test]
    fn bad_parameters_are_alarms_at_their_place() {
        let shaft = [("SHAFT.SPF", SHAFT)];
        // (parameters after the contour's name, the alarm, its column in line 3)
        let cases = [
            // VARI 13; VARI 2 (face outside) on SHAFT, which runs away from the centre (at
            // the cycle's name); MID 0 and MID left out for roughing.
            (" 3, , , , 0.3, , , 13)", AlarmCode::CycleMachiningType, 36),
            (" 3, , , , 0.3, , , 2)", AlarmCode::CycleContour, 1),
            (" 0, , , , 0.3, , , 9)", AlarmCode::CycleParameter, 18),
            (" , , , , 0.3, , , 1)", AlarmCode::CycleParameter, 1),
            // A signed allowance, FAL as large as the fillet RND=2 (its parallel vanishes),
            // a thirteenth parameter.
            (" 3, -0.1, , , 0.3, , , 1)", AlarmCode::CycleParameter, 21),
            (" 3, , , 2, 0.3, , , 1)", AlarmCode::CycleContour, 25),
            (" 3, , , , 0.3, , , 1, , , 1, 7)", AlarmCode::Syntax, 46),
        ];
        for (rest, code, col) in cases {
            let cycle = format!("CYCLE95(\"SHAFT\",{rest}");
            assert_eq!(alarm(&cycle, &shaft), main_at(code, col), "{cycle}");
        }
        // Under nose radius compensation.
        let a = lathe(
            &format!("{HEAD}G42 G1 X50\nCYCLE95(\"SHAFT\", 3, , , , 0.3, , , 1)\n"),
            &shaft,
        )
        .unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::ForbiddenWithTrc, 4, 1));
        // Under a frame.
        let a = lathe(
            &format!("{HEAD}TRANS Z5\nCYCLE95(\"SHAFT\", 3, , , , 0.3, , , 1)\n"),
            &shaft,
        )
        .unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::NotSupported, 4, 1));
    }

    #[test]
    fn cycle95_is_no_modal_cycle() {
        // MCALL takes the drilling cycles only: 12550 at the name (column 7).
        let a = alarm("MCALL CYCLE95(\"SHAFT\", 3, , , , 0.3, , , 1)", &[]);
        assert_eq!(a, main_at(AlarmCode::UndefinedName, 7));
    }

    #[test]
    fn no_feed_is_an_alarm_at_the_feed_parameter() {
        let a = lathe(
            "G18 G95 S1000 M3\nG0 X60 Z5\nCYCLE95(\"SHAFT\", 3, , , , , , , 1)\n",
            &[("SHAFT.SPF", SHAFT)],
        )
        .unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::NoFeed, 3, 1));
    }

    #[test]
    fn a_missing_or_unusable_contour_is_an_alarm() {
        let shaft = [("SHAFT.SPF", SHAFT)];
        // No NPP; no file; no label (at NPP, column 9).
        assert_eq!(
            alarm("CYCLE95(\"\", 3, , , , 0.3, , , 1)", &shaft),
            main_at(AlarmCode::CycleContour, 9)
        );
        assert_eq!(
            alarm("CYCLE95(\"AXLE\", 3, , , , 0.3, , , 1)", &shaft),
            main_at(AlarmCode::MissingProgram, 9)
        );
        assert_eq!(
            alarm("CYCLE95(\"A1:B1\", 3, , , , 0.3, , , 1)", &shaft),
            main_at(AlarmCode::JumpTarget, 9)
        );
        // Z turns back (from −10 to −5), against the cut along Z: no undercut the passes
        // can reach, at the call. The same shape along X for face machining: X turns back.
        let back_z = [("P.SPF", "G1 X10 Z0\nZ-10\nX20 Z-5\nZ-20\nX40\n")];
        assert_eq!(
            alarm("CYCLE95(\"P\", 3, , , , 0.3, , , 1)", &back_z),
            main_at(AlarmCode::CycleContour, 1)
        );
        let back_x = [("P.SPF", "G1 X60 Z-20\nX40\nX50 Z-10\nX20\nZ0\n")];
        assert_eq!(
            alarm("CYCLE95(\"P\", 3, , , , 0.3, , , 2)", &back_x),
            main_at(AlarmCode::CycleContour, 1)
        );
        // A face contour outside that starts at its largest Z (nothing in front of it), one
        // whose start and end lie at the same X, and a face contour inside that runs
        // towards the centre.
        for (spf, vari) in [
            ("G1 X60 Z0\nX40\nZ-5\nX20\n", 2),
            ("G1 X60 Z-10\nX20\nZ0\nX60\n", 2),
            ("G1 X60 Z-10\nX20\nZ0\nX0\n", 4),
        ] {
            let cycle = format!("CYCLE95(\"F\", 3, , , , 0.3, , , {vari})");
            assert_eq!(
                alarm(&cycle, &[("F.SPF", spf)]),
                main_at(AlarmCode::CycleContour, 1),
                "{spf}"
            );
        }
        // A contour programmed from the chuck towards the face starts at its largest X.
        let back = [("B.SPF", "G1 X40 Z-20\nX20\nZ0\n")];
        assert_eq!(
            alarm("CYCLE95(\"B\", 3, , , , 0.3, , , 1)", &back),
            main_at(AlarmCode::CycleContour, 1)
        );
        // Start and end at the same Z: no longitudinal contour.
        let face = [("F.SPF", "G1 X10 Z0\nX40\n")];
        assert_eq!(
            alarm("CYCLE95(\"F\", 3, , , , 0.3, , , 1)", &face),
            main_at(AlarmCode::CycleContour, 1)
        );
        // One move only.
        let one = [("O.SPF", "G1 X10 Z0\n")];
        assert_eq!(
            alarm("CYCLE95(\"O\", 3, , , , 0.3, , , 1)", &one),
            main_at(AlarmCode::CycleContour, 9)
        );
    }

    #[test]
    fn faults_in_the_contour_name_its_file_and_line() {
        let at = |spf: &str| alarm("CYCLE95(\"C\", 3, , , , 0.3, , , 1)", &[("C.SPF", spf)]);
        // A word the 808D does not know, at its column in C.SPF.
        assert_eq!(
            at("G1 X10 Z0\nZ-10 Q5\nX40\n"),
            (AlarmCode::UnknownAddress, "lib/C.SPF".into(), 2, 6)
        );
        // Compensation in the contour, at its block.
        assert_eq!(
            at("G1 X10 Z0\nG42 Z-10\nX40\n"),
            (AlarmCode::NotSupported, "lib/C.SPF".into(), 2, 1)
        );
        // A dwell in the contour.
        assert_eq!(
            at("G1 X10 Z0\nZ-10\nG4 F1\nX40\n"),
            (AlarmCode::NotSupported, "lib/C.SPF".into(), 3, 1)
        );
        // A contour that calls the cycle again.
        assert_eq!(
            at("G1 X10 Z0\nCYCLE95(\"C\", 3, , , , 0.3, , , 1)\nX40\n"),
            (AlarmCode::CycleContour, "lib/C.SPF".into(), 2, 9)
        );
    }
}
