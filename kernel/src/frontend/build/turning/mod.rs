//! Multiple repetitive turning cycles (Fanuc 0i-TF, G-code system A): the shape is written
//! once between the blocks P and Q; G71 roughs down to it in passes along Z, G72 in passes
//! along X, G73 runs it again and again from an escape towards it, G70 runs it.
//!
//! ```text
//! G71 U(Δd) R(e)                  depth of cut (radius), retract: stored
//! G71 P(ns) Q(nf) U(Δu) W(Δw) F S allowances (U a diameter); F and S for the roughing
//! N(ns) G00/G01 X(U) …            the shape: the first block moves X only (type I), or
//! …                               X and Z (type II: pockets, stock_removal/pockets.rs)
//! N(nf) …
//! G70 P(ns) Q(nf)                 finishing: the shape with its own F, S and G41/G42
//! G72 W(Δd) R(e)  G72 P Q U W F S  facing: G71 with X and Z exchanged (first block: Z only)
//! G73 U(Δi) W(Δk) R(d)             escape (U a radius) and number of passes: stored
//! G73 P(ns) Q(nf) U(Δu) W(Δw) F S  the shape d times, shifted from Δi+Δu/2, Δk+Δw to Δu/2, Δw
//! ```
//!
//! After G71 … G73 the program goes on after block Q; after G70, after the G70 block. All
//! return to the start point at rapid. [`contour`] reads the shape, [`stock_removal`] makes
//! the moves.

mod contour;
mod equidistant;
mod nose;
mod stock_removal;

pub use contour::Element;
pub use equidistant::{equidistant, tip_path, Nose};
pub use stock_removal::{deepest, non_monotonic, z_turns, Passes, TurningRun, EPS};

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{int_value, Val, Words};
use super::expand::Expansion;
use crate::alarm::AlarmCode;
use crate::dialect::TurningCycle;
use stock_removal::{exchange, Repeat};

/// `G71 U R` / `G72 W R`: the depth of cut and the retract; `G73 U W R`: the escape and
/// the number of passes. Kept until written again.
#[derive(Clone, Copy, Debug, Default)]
pub struct TurningData {
    pub depth: f64,
    pub retract: f64,
    /// G73's escape (Δi, Δk): X radius, Z.
    pub escape: [f64; 2],
    /// G73's number of passes (d).
    pub divisions: u32,
}

impl Interpreter<'_> {
    /// Step 8 of a G70 … G73 block.
    pub(super) fn turning_cycle(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        kind: TurningCycle,
        at: usize,
    ) -> R<()> {
        self.turning_allowed(new, at)?;
        let (p, q) = match (w.p, w.q) {
            (None, None) if kind != TurningCycle::Finishing => {
                return self.turning_data(w, new, kind, at)
            }
            (Some(p), Some(q)) => (
                (int_value(p.value, p.at, "P")?, p.pos()),
                (int_value(q.value, q.at, "Q")?, q.pos()),
            ),
            _ => {
                return Err(fault(
                    AlarmCode::MissingValue,
                    at,
                    "a turning cycle needs the shape's first and last block numbers P and Q",
                ))
            }
        };
        let start = self.cur;
        let contour = self.read_contour(p, q, start, new)?;
        let run = match kind {
            TurningCycle::Finishing => {
                TurningRun::new(start, contour.elements, None).compensated(contour.compensation)
            }
            TurningCycle::StockRemoval => self.stock_removal(w, new, &contour, false, at)?,
            TurningCycle::Facing => self.stock_removal(w, new, &contour, true, at)?,
            TurningCycle::PatternRepeating => {
                let shape = self.rough_shape(&contour, new)?;
                self.pattern_repeating(w, new, shape, at)?
            }
        };
        if kind != TurningCycle::Finishing {
            (self.pos, self.line, self.line_start) = contour.after;
        }
        self.expansion = Some(Expansion::turning(run));
        self.expand_first(new);
        Ok(())
    }

    /// No compensation, frame or hole cycle mode, and the Z-X plane.
    fn turning_allowed(&self, new: &ModalState, at: usize) -> R<()> {
        if new.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                at,
                "a turning cycle cannot be called while nose radius compensation is active (not built yet)",
            ));
        }
        if self.coords.frame.active() || new.plane != Plane::ZX {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "a turning cycle runs in the Z-X plane without a frame",
            ));
        }
        Ok(())
    }

    /// The cycle's first block, without P and Q: its data, stored.
    fn turning_data(
        &mut self,
        w: &Words,
        new: &ModalState,
        kind: TurningCycle,
        at: usize,
    ) -> R<()> {
        match kind {
            TurningCycle::PatternRepeating => self.escape_and_divisions(w, new),
            TurningCycle::Facing => self.depth_and_retract(w, new, 2, at),
            _ => self.depth_and_retract(w, new, 0, at),
        }
    }

    /// `G71 U(Δd) R(e)`, `G72 W(Δd) R(e)`: the depth word is U (`axis` 0) or W (2).
    fn depth_and_retract(&mut self, w: &Words, new: &ModalState, axis: usize, at: usize) -> R<()> {
        let no_axes = w.axis[1].is_none() && w.axis[2 - axis].is_none();
        let word = w.axis[axis].filter(|_| no_axes && w.incremental & (1 << axis) != 0);
        let Some(u) = word else {
            let name = if axis == 0 { "U" } else { "W" };
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                format!("the depth of cut block is {name}(depth) R(retract), or give P and Q"),
            ));
        };
        let depth = self.length(u, new.units);
        if depth <= 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                u.pos(),
                "the depth of cut must be greater than 0",
            ));
        }
        self.turning.depth = depth;
        if let Some(r) = w.radius {
            let e = self.non_negative(r, new.units, "the retract R")?;
            self.turning.retract = e;
        }
        Ok(())
    }

    /// `G73 U(Δi) W(Δk) R(d)`: the escape (U a radius, with its sign) and the passes; the
    /// words left out keep their values.
    fn escape_and_divisions(&mut self, w: &Words, new: &ModalState) -> R<()> {
        for i in [0, 2] {
            if let Some(v) = w.axis[i].filter(|_| w.incremental & (1 << i) == 0) {
                return Err(fault(
                    AlarmCode::Syntax,
                    v.pos(),
                    "the escape block is U(X escape, radius) W(Z escape) R(passes)",
                ));
            }
        }
        if let Some(r) = w.radius {
            let d = int_value(r.value, r.at, "the number of passes R")?;
            if d == 0 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    r.pos(),
                    "pattern repeating needs at least one pass (R)",
                ));
            }
            self.turning.divisions = d;
        }
        for (k, i) in [(0, 0), (1, 2)] {
            if let Some(v) = w.axis[i] {
                self.turning.escape[k] = self.length(v, new.units);
            }
        }
        Ok(())
    }
}

impl Interpreter<'_> {
    /// G71 (`facing` false) or G72: the shape offset by the allowances and the passes,
    /// checked. G72 runs G71's cycle with X and Z exchanged.
    fn stock_removal(
        &mut self,
        w: &Words,
        new: &ModalState,
        contour: &contour::Contour,
        facing: bool,
        at: usize,
    ) -> R<TurningRun> {
        if self.turning.depth <= 0.0 {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "no depth of cut: program the block U(depth) R(retract) of the cycle first (W for facing)",
            ));
        }
        let pockets = contour.first_has[0] && contour.first_has[1];
        let (du, dw) = self.allowances(w, new)?;
        let (du, dw) = if facing { (dw, du) } else { (du, dw) };
        let frame = |e: &Element| if facing { e.exchanged() } else { *e };
        let programmed: Vec<Element> = contour.elements.iter().map(frame).collect();
        let a = if facing { exchange(self.cur) } else { self.cur };
        let (sx, sz) = shape_directions(a, &programmed, pockets, facing, at)?;
        // The passes work on the tool tip's path: compensated in machine axes (G72's
        // exchange mirrors the sides), then moved by the allowances.
        let shape: Vec<Element> = self
            .rough_shape(contour, new)?
            .iter()
            .map(|e| frame(e).shifted([du, dw]))
            .collect();
        if sx * du < 0.0 || sz * dw > 0.0 || sx * (a[0] - shape[0].to[0]) <= EPS {
            return Err(fault(
                AlarmCode::BadNumber,
                at,
                "the allowances U and W turn the shape inside out (their signs oppose the cut, or they reach the start point)",
            ));
        }
        let total = match pockets {
            true => stock_removal::deepest(a, &shape, sx),
            false => sx * (a[0] - shape[0].to[0]),
        };
        let count = Passes::count(total, self.turning.depth);
        self.add_passes(count as u64, at)?;
        let passes = Passes {
            depth: self.turning.depth,
            retract: self.turning.retract,
            sx,
            sz,
            rapid_in: contour.elements[0].mode == MotionMode::Rapid,
            count: count as u32,
        };
        let mut run = TurningRun::new(a, shape, Some(passes));
        if pockets {
            run = run.pockets();
        }
        Ok(if facing { run.exchanged() } else { run })
    }

    /// G73: the shape run d times, from the escape plus the allowances to the allowances.
    fn pattern_repeating(
        &mut self,
        w: &Words,
        new: &ModalState,
        shape: Vec<Element>,
        at: usize,
    ) -> R<TurningRun> {
        let d = self.turning.divisions;
        if d == 0 {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "no number of passes: program the block U(escape) W(escape) R(passes) of the cycle first",
            ));
        }
        let (du, dw) = self.allowances(w, new)?;
        let [ei, ek] = self.turning.escape;
        self.add_passes(d as u64, at)?;
        let repeat = Repeat {
            first: [ei + du, ek + dw],
            last: [du, dw],
            count: d,
        };
        Ok(TurningRun::repeating(self.cur, shape, repeat))
    }
}

impl Interpreter<'_> {
    /// Δu/2 and Δw from the block's U and W (X and Z are no words of this block).
    fn allowances(&self, w: &Words, new: &ModalState) -> R<(f64, f64)> {
        let mut out = [0.0; 2];
        for (k, i) in [(0, 0), (1, 2)] {
            let Some(v): Option<Val> = w.axis[i] else {
                continue;
            };
            if w.incremental & (1 << i) == 0 {
                return Err(fault(
                    AlarmCode::Syntax,
                    v.pos(),
                    "the allowances are U and W; X and Z have no meaning here",
                ));
            }
            let f = super::motion::diameter_factor(i, new, Distance::Incremental);
            out[k] = self.length(v, new.units) * f;
        }
        Ok((out[0], out[1]))
    }
}

/// The directions of the passes (`sx`: +1 towards smaller X) and of the cut (`sz`) from the
/// start `a` and the shape (G72: exchanged), checked against the type's rule: type I
/// monotonic in X and Z, type II (`pockets`) in Z.
fn shape_directions(
    a: Pos,
    shape: &[Element],
    pockets: bool,
    facing: bool,
    at: usize,
) -> R<(f64, f64)> {
    let (depth_axis, cut_axis) = if facing { ("Z", "X") } else { ("X", "Z") };
    let a1 = shape.first().map_or(a, |e| e.to);
    let b = shape.last().map_or(a1, |e| e.to);
    let (sx, sz) = (sign(a[0] - a1[0]), sign(b[2] - a1[2]));
    if sx == 0.0 || sz == 0.0 {
        return Err(fault(
            AlarmCode::NotSupported,
            at,
            format!("the shape must start off the start point in {depth_axis} and go on along {cut_axis}"),
        ));
    }
    let broken = match pockets {
        true => stock_removal::z_turns(a, shape, sz).map(|i| (i, "it turns back along the cut")),
        false => stock_removal::non_monotonic(shape, sx, sz),
    };
    if let Some((i, what)) = broken {
        let kind = if pockets { "type II" } else { "type I" };
        return Err(fault(
            AlarmCode::NotSupported,
            at,
            format!(
                "the shape is not monotonic ({kind}), element {}: {what} ({depth_axis} the depth, {cut_axis} the cut)",
                i + 1
            ),
        ));
    }
    Ok((sx, sz))
}

pub fn sign(v: f64) -> f64 {
    if v > EPS {
        1.0
    } else if v < -EPS {
        -1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use crate::alarm::{Alarm, AlarmCode};
    use crate::frontend::block::TrcSide;
    use crate::frontend::{interpret, Block, MotionKind};
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    fn lathe(src: &str) -> Result<Vec<Block>, Alarm> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-lathe.toml");
        let md = MachineData::load(Some(std::path::Path::new(path)), &[]).unwrap();
        interpret("l.nc", src, &md, &ToolTable::builtin())
    }

    /// The blocks of `src` with X programmed as a radius.
    fn lathe_radius(src: &str) -> Vec<Block> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-lathe.toml");
        let ov = ["program.diameter_programming=false".to_string()];
        let md = MachineData::load(Some(std::path::Path::new(path)), &ov).unwrap();
        interpret("r.nc", src, &md, &ToolTable::builtin()).unwrap_or_else(|a| panic!("{a}"))
    }

    /// (X radius, Z) of every move's end, rounded to 1e-9, with X programmed as a radius.
    fn radius_ends(src: &str) -> Vec<(f64, f64)> {
        let b = lathe_radius(src);
        let r = |v: f64| (v * 1e9).round() / 1e9;
        b.iter()
            .filter_map(|b| b.motion.map(|m| (r(m.end[0]), r(m.end[2]))))
            .collect()
    }

    #[test]
    fn radius_programming_takes_x_and_u_as_radii() {
        // X20 is radius 20; U0.2 is 0.2 on the radius. Shape (10, 2), (10, -10), (20, -10)
        // moved by (0.2, 0.2): (10.2, 2.2), (10.2, -9.8), (20.2, -9.8). Levels 20 − 2k above
        // 10.2: 18, 16, 14, 12 (9.8 / 2 rounded up less 1 = 4); each meets the face at
        // Z -9.8 (the last element reaches X 20.2).
        let e = radius_ends(
            "G0 X20. Z2.\nG71 U2. R1.\nG71 P10 Q20 U0.2 W0.2 F0.2\nN10 G0 X10.\nG1 Z-10.\nN20 X20.\n",
        );
        let mut want = vec![(20.0, 2.0)];
        for level in [18.0, 16.0, 14.0, 12.0] {
            want.extend([
                (level, 2.0),
                (level, -9.8),
                (level + 1.0, -8.8),
                (level + 1.0, 2.0),
            ]);
        }
        want.extend([
            (10.2, 2.2),
            (10.2, -9.8),
            (20.2, -9.8),
            (20.0, -9.8),
            (20.0, 2.0),
        ]);
        assert_eq!(e, want);
    }

    /// The alarm of `body` after the start block, as (code, line, column).
    fn alarm(body: &str) -> (AlarmCode, u32, u32) {
        let a = lathe(&format!("G0 X40. Z2.\n{body}")).unwrap_err();
        (a.code, a.line, a.col)
    }

    const SHAPE: &str = "N10 G0 X20.\nG1 Z-10. F0.1\nN20 X40.\n";

    #[test]
    fn the_shape_blocks_must_be_there() {
        // No Q block after P: the alarm points at Q of the cycle block (line 3, column 9).
        let got = alarm(&format!("G71 U2. R1.\nG71 P10 Q99\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::JumpTarget, 3, 9));
        // No P block at all.
        let got = alarm(&format!("G71 U2. R1.\nG71 P11 Q20\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::JumpTarget, 3, 5));
        // P without Q.
        let got = alarm(&format!("G71 U2. R1.\nG71 P10\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::MissingValue, 3, 1));
        // G70 alike.
        let got = alarm("G70 P10 Q20\n");
        assert_eq!(got.0, AlarmCode::JumpTarget);
    }

    #[test]
    fn depth_of_cut_must_be_given_and_not_zero() {
        assert_eq!(alarm("G71 U0 R1.\n"), (AlarmCode::BadNumber, 2, 5));
        let got = alarm(&format!("G71 P10 Q20\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::MissingValue, 2, 1));
    }

    #[test]
    fn type_i_needs_a_monotonic_shape() {
        // X goes up to 30 and back down to 24 (a pocket): alarm at the cycle block.
        let got = alarm(
            "G71 U2. R1.\nG71 P10 Q20\nN10 G0 X20.\nG1 X30. Z-5. F0.1\nX24. Z-10.\nN20 X40.\n",
        );
        assert_eq!(got, (AlarmCode::NotSupported, 3, 1));
        // A half circle turns in X.
        let got = alarm(
            "G71 U2. R1.\nG71 P10 Q20\nN10 G0 X20.\nG1 Z-5. F0.1\nG2 Z-15. R5.\nN20 G1 X40.\n",
        );
        assert_eq!(got, (AlarmCode::NotSupported, 3, 1));
        // Type II (X and Z in the first block): Z turns back.
        let got = alarm(
            "G71 U2. R1.\nG71 P10 Q20\nN10 G0 X20. Z1.\nG1 Z-10. F0.1\nX30. Z-5.\nN20 X40.\n",
        );
        assert_eq!(got, (AlarmCode::NotSupported, 3, 1));
        // A type II arc passing the point where Z turns (a half circle along X).
        let got = alarm(
            "G71 U2. R1.\nG71 P10 Q20\nN10 G0 X20. Z1.\nG1 Z-10. F0.1\nG3 X30. R2.5\nN20 G1 X40.\n",
        );
        assert_eq!(got, (AlarmCode::NotSupported, 3, 1));
    }

    #[test]
    fn allowances_must_not_turn_the_shape_inside_out() {
        // Outer turning with U negative, or U as large as the stock.
        let got = alarm(&format!("G71 U2. R1.\nG71 P10 Q20 U-0.4\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::BadNumber, 3, 1));
        let got = alarm(&format!("G71 U2. R1.\nG71 P10 Q20 U20.\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::BadNumber, 3, 1));
        // W against the cut's direction (towards the chuck: W must not be negative).
        let got = alarm(&format!("G71 U2. R1.\nG71 P10 Q20 W-0.1\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::BadNumber, 3, 1));
    }

    #[test]
    fn unsupported_words_in_the_shape_name_their_block() {
        // A second compensated stretch in a roughing shape: refused at its block.
        let got = alarm(
            "G71 U2. R1.\nG71 P10 Q20\nN10 G42 G0 X20.\nG40 G1 Z-10. F0.1\nG42 X30.\nN20 X40.\n",
        );
        assert_eq!(got, (AlarmCode::NotSupported, 6, 1));
        // A chamfer word, a macro expression.
        let got = alarm("G71 U2. R1.\nG71 P10 Q20\nN10 G0 X20.\nG1 Z-10. ,C1. F0.1\nN20 X40.\n");
        assert_eq!(got, (AlarmCode::NotSupported, 5, 10));
        let got = alarm("G70 P10 Q20\nN10 G0 X#1\nN20 X40.\n");
        assert_eq!(got, (AlarmCode::NotSupported, 3, 9));
        // The first block needs its motion code.
        let got = alarm("G70 P10 Q20\nN10 X20.\nN20 X40.\n");
        assert_eq!(got, (AlarmCode::MissingValue, 3, 1));
        // And G70/G71 under compensation.
        let got = alarm(&format!("G42 G1 X38. F0.1\nG70 P10 Q20\n{SHAPE}"));
        assert_eq!(got, (AlarmCode::ForbiddenWithTrc, 3, 1));
    }

    #[test]
    fn g70_runs_the_shape_of_blocks_ended_by_semicolons_and_returns() {
        // From (20, 2): A' (10, 2) at rapid, (10, -5), (20, -5), back to A: X is there, Z 2.
        let b =
            lathe("G0 X40. Z2.\nG70 P10 Q20\nM30\nN10 G0 X20.; G1 Z-5. F0.1; N20 X40.\n").unwrap();
        let ends: Vec<(f64, f64)> = b
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[2])))
            .collect();
        assert_eq!(
            ends,
            [
                (20.0, 2.0),
                (10.0, 2.0),
                (10.0, -5.0),
                (20.0, -5.0),
                (20.0, 2.0)
            ]
        );
        assert!(
            b.iter().all(|b| b.line <= 3),
            "the shape's line does not run by itself"
        );
    }

    #[test]
    fn inner_turning_goes_up_in_x() {
        // Bore from radius 5 (X10): the shape A' = (15, 2), (15, -10), face down to
        // (12, -10). U-0.4 moves it −0.2 in X: A' = (14.8, 2). Passes up by 3 while below
        // 14.8 (9.8/3 rounded up less 1 = 3): levels 8, 11, 14; each runs to the face at
        // Z -10, then out by R0.5 at 45° (X down, Z up).
        let b = lathe(
            "G0 X10. Z2.\nG71 U3. R0.5\nG71 P10 Q20 U-0.4 F0.2\nN10 G0 X30.\nG1 Z-10.\nN20 X24.\n",
        )
        .unwrap();
        let ends: Vec<(f64, f64)> = b
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[2])))
            .collect();
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let ends: Vec<(f64, f64)> = ends.iter().map(|&(x, z)| (r(x), r(z))).collect();
        assert_eq!(
            ends[1..5],
            [(8.0, 2.0), (8.0, -10.0), (7.5, -9.5), (7.5, 2.0)]
        );
        assert_eq!(ends.len(), 1 + 3 * 4 + 3 + 2);
    }

    /// (X radius, Z) of every move's end, rounded to 1e-9, X programmed as a diameter.
    fn diameter_ends(src: &str) -> Vec<(f64, f64)> {
        let b = lathe(src).unwrap_or_else(|a| panic!("{a}"));
        let r = |v: f64| (v * 1e9).round() / 1e9;
        b.iter()
            .filter_map(|b| b.motion.map(|m| (r(m.end[0]), r(m.end[2]))))
            .collect()
    }

    /// G72's moves by hand (radius, Z). Start A (40, 2); the shape A' (40, -6) at rapid,
    /// (20, -6), (10, -2), B (0, -2); moved by U0.4 (0.2 on the radius) and W0.2: A' (40.2,
    /// -5.8), (20.2, -5.8), (10.2, -1.8), (0.2, -1.8). Levels in Z 2 − 2k above -5.8: 0, -2,
    /// -4 (7.8 / 2 rounded up less 1 = 3). Z 0 lies above the whole shape: across to B's X
    /// 0.2. Z -2 and -4 meet the taper (20.2, -5.8)–(10.2, -1.8), X = 20.2 − 2.5·(level +
    /// 5.8): 10.7 and 15.7. Each pass: in along Z at A's X, across at the feed, out by R0.5
    /// at 45° (Z and X up), back to A's X; then the shape, and home Z first, then X.
    fn g72_by_hand() -> Vec<(f64, f64)> {
        let mut want = vec![(40.0, 2.0)];
        for (level, x) in [(0.0, 0.2), (-2.0, 10.7), (-4.0, 15.7)] {
            want.extend([
                (40.0, level),
                (x, level),
                (x + 0.5, level + 0.5),
                (40.0, level + 0.5),
            ]);
        }
        want.extend([
            (40.2, -5.8),
            (20.2, -5.8),
            (10.2, -1.8),
            (0.2, -1.8),
            (0.2, 2.0),
            (40.0, 2.0),
        ]);
        want
    }

    #[test]
    fn g72_faces_in_passes_along_x() {
        let e = diameter_ends(
            "G0 X80. Z2.\nG72 W2. R0.5\nG72 P10 Q20 U0.4 W0.2 F0.2\nN10 G0 Z-6.\nG1 X40.\nX20. Z-2.\nN20 X0.\n",
        );
        assert_eq!(e, g72_by_hand());
        // Radius programming: X and U are radii, the same moves.
        let e = radius_ends(
            "G0 X40. Z2.\nG72 W2. R0.5\nG72 P10 Q20 U0.2 W0.2 F0.2\nN10 G0 Z-6.\nG1 X20.\nX10. Z-2.\nN20 X0.\n",
        );
        assert_eq!(e, g72_by_hand());
    }

    #[test]
    fn g72_alarms() {
        const FACE: &str = "N10 G0 Z-6.\nG1 X20.\nN20 Z0.\n";
        // No depth of cut yet; W0; U in the depth block.
        assert_eq!(
            alarm(&format!("G72 P10 Q20\n{FACE}")),
            (AlarmCode::MissingValue, 2, 1)
        );
        assert_eq!(alarm("G72 W0 R1.\n"), (AlarmCode::BadNumber, 2, 5));
        assert_eq!(alarm("G72 U2. R1.\n"), (AlarmCode::MissingValue, 2, 1));
        // Z turns back: not monotonic in Z (type I).
        let got =
            alarm("G72 W2. R1.\nG72 P10 Q20\nN10 G0 Z-6.\nG1 X30. Z-2.\nX20. Z-4.\nN20 X0.\n");
        assert_eq!(got, (AlarmCode::NotSupported, 3, 1));
        // Type II (X and Z in the first block): X turns back.
        let got =
            alarm("G72 W2. R1.\nG72 P10 Q20\nN10 G0 X38. Z-6.\nG1 X20.\nX30. Z-3.\nN20 Z0.\n");
        assert_eq!(got, (AlarmCode::NotSupported, 3, 1));
        // W against the cut (the face cut towards the chuck keeps W ≥ 0).
        let got = alarm(&format!("G72 W2. R1.\nG72 P10 Q20 W-0.2\n{FACE}"));
        assert_eq!(got, (AlarmCode::BadNumber, 3, 1));
    }

    /// G73 by hand (radius, Z): A (30, 5); the shape (10, 1) at rapid, (10, -10), (15, -20),
    /// (25, -20). U4 W2 R3 and U0.4 W0.1: the shifts go from (4 + 0.2, 2 + 0.1) to (0.2,
    /// 0.1) in 3 passes: (4.2, 2.1), (2.2, 1.1), (0.2, 0.1). Each pass: the whole shape
    /// shifted, then home at rapid, X first.
    fn g73_by_hand() -> Vec<(f64, f64)> {
        let mut want = vec![(30.0, 5.0)];
        for (sx, sz) in [(4.2, 2.1), (2.2, 1.1), (0.2, 0.1)] {
            want.extend([
                (10.0 + sx, 1.0 + sz),
                (10.0 + sx, -10.0 + sz),
                (15.0 + sx, -20.0 + sz),
                (25.0 + sx, -20.0 + sz),
                (30.0, -20.0 + sz),
                (30.0, 5.0),
            ]);
        }
        let r = |v: f64| (v * 1e9).round() / 1e9;
        want.iter().map(|&(x, z)| (r(x), r(z))).collect()
    }

    #[test]
    fn g73_repeats_the_shape_towards_it() {
        let e = diameter_ends(
            "G0 X60. Z5.\nG73 U4. W2. R3\nG73 P10 Q20 U0.4 W0.1 F0.25\nN10 G0 X20. Z1.\nG1 Z-10.\nX30. Z-20.\nN20 X50.\n",
        );
        assert_eq!(e, g73_by_hand());
        // Radius programming: U4 of the escape stays a radius, U0.2 is the allowance.
        let e = radius_ends(
            "G0 X30. Z5.\nG73 U4. W2. R3\nG73 P10 Q20 U0.2 W0.1 F0.25\nN10 G0 X10. Z1.\nG1 Z-10.\nX15. Z-20.\nN20 X25.\n",
        );
        assert_eq!(e, g73_by_hand());
        // One pass: the allowances only.
        let e = diameter_ends(
            "G0 X60. Z5.\nG73 U4. W2. R1\nG73 P10 Q20 U0.4 W0.1\nN10 G0 X20. Z1.\nN20 G1 X50. Z-10.\n",
        );
        assert_eq!(
            e,
            [
                (30.0, 5.0),
                (10.2, 1.1),
                (25.2, -9.9),
                (30.0, -9.9),
                (30.0, 5.0)
            ]
        );
    }

    #[test]
    fn g73_alarms() {
        const SHAPE3: &str = "N10 G0 X20. Z1.\nN20 G1 X40. Z-10.\n";
        // No passes programmed yet; R0; R not whole; X instead of U.
        assert_eq!(
            alarm(&format!("G73 P10 Q20\n{SHAPE3}")),
            (AlarmCode::MissingValue, 2, 1)
        );
        assert_eq!(alarm("G73 U2. W1. R0\n"), (AlarmCode::BadNumber, 2, 13));
        assert_eq!(alarm("G73 U2. W1. R2.5\n"), (AlarmCode::BadNumber, 2, 13));
        assert_eq!(alarm("G73 X2. R2\n"), (AlarmCode::Syntax, 2, 5));
        // P without Q.
        assert_eq!(
            alarm(&format!("G73 U2. R2\nG73 P10\n{SHAPE3}")),
            (AlarmCode::MissingValue, 3, 1)
        );
    }

    /// Type II by hand (radius, Z), depth 2, retract 0.5. A (20, 2); the boundary A → A'
    /// (12, 2) at rapid, (12, -5), down to (6, -10), (6, -15), up to (14, -20), (14, -25),
    /// B (20, -25). Deepest 14 below A: levels X 18 16 … 8 (14/2 rounded up less 1 = 6).
    /// 18, 16: one stretch from A's Z to B's wall at -25; 14: to where the boundary comes up
    /// to 14, (14, -20). 12: in at (12, -5) (the cone's top), out on the rise from (6, -15)
    /// to (14, -20) at Z = -15 − 5·6/8 = -18.75; 10: the cone at Z = -5 − 5·2/6, the rise at
    /// -15 − 5·4/8 = -17.5; 8: -5 − 5·4/6 and -15 − 5·2/8 = -16.25.
    /// The way to a stretch: up to the deepest level cut over the whole way less 0.5, along
    /// Z; off the first block's G00 move down to the level above at rapid, in by 2 at the
    /// feed. Over (12, -5) … (14.5, -19.5) the boundary's top is 6.8 below A: levels down to
    /// 6 are cut there: across at X 20 − 6 + 0.5 = 14.5; then 8.8: X 12.5; 10.8: X 10.5.
    /// Back to A: the top over the way is 8 (X 12 at the start): X 14.5; then the moved
    /// shape from A and home.
    fn type_ii_by_hand() -> Vec<(f64, f64)> {
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let mut want = vec![(20.0, 2.0)];
        for (level, back, end) in [
            (18.0, 20.0, -25.0),
            (16.0, 18.5, -25.0),
            (14.0, 16.5, -20.0),
        ] {
            if back != 20.0 {
                want.push((back, 2.0)); // along Z, e above the last level
            }
            want.extend([(level, 2.0), (level, end), (level + 0.5, end + 0.5)]);
        }
        let cone = |x: f64| -5.0 - 5.0 * (12.0 - x) / 6.0;
        let rise = |x: f64| -15.0 - 5.0 * (x - 6.0) / 8.0;
        for (level, over) in [(12.0, 14.5), (10.0, 12.5), (8.0, 10.5)] {
            want.extend([
                (over, cone(level)),
                (level + 2.0, cone(level)),
                (level, cone(level)),
                (level, rise(level)),
                (level + 0.5, rise(level) + 0.5),
            ]);
        }
        want.extend([
            (14.5, -15.75),
            (14.5, 2.0),
            (20.0, 2.0),
            (12.0, 2.0),
            (12.0, -5.0),
            (6.0, -10.0),
            (6.0, -15.0),
            (14.0, -20.0),
            (14.0, -25.0),
            (20.0, -25.0),
            (20.0, 2.0),
        ]);
        want.iter().map(|&(x, z)| (r(x), r(z))).collect()
    }

    #[test]
    fn type_ii_cuts_the_pockets_level_by_level() {
        let e = diameter_ends(
            "G0 X40. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.2\nN10 G0 X24. Z2.\nG1 Z-5.\nX12. Z-10.\nZ-15.\nX28. Z-20.\nZ-25.\nN20 X40.\n",
        );
        assert_eq!(e, type_ii_by_hand());
        let e = radius_ends(
            "G0 X20. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.2\nN10 G0 X12. W0\nG1 Z-5.\nX6. Z-10.\nZ-15.\nX14. Z-20.\nZ-25.\nN20 X20.\n",
        );
        assert_eq!(e, type_ii_by_hand());
    }

    #[test]
    fn g72_type_ii_cuts_a_face_groove() {
        // (radius, Z), depth 1.5 along Z, retract 0.5. A (20, 2); the boundary A → A' (20,
        // -1) at rapid, (14, -1), down to (12, -4), (10, -4), up to (8, -1), B (0, -1).
        // Deepest 6 below A's Z: levels Z 0.5, -1, -2.5. Z 0.5: from N10's move to past B
        // (B's X); Z -1 touches the face (not below it): the groove from its edge (14, -1)
        // to (8, -1); Z -2.5: its flanks at X 13 and 9. Between: up to the deepest level
        // cut over the way less 0.5 (Z 1, then -0.5), along X, down to the level above at
        // rapid, in at the feed; retract 0.5 at 45°. Back to A over Z 1; the shape; home Z
        // first.
        let e = diameter_ends(
            "G0 X40. Z2.\nG72 W1.5 R0.5\nG72 P10 Q20 F0.2\nN10 G0 X40. Z-1.\nG1 X28.\nX24. Z-4.\nX20.\nX16. Z-1.\nN20 X0.\n",
        );
        let want = [
            (20.0, 2.0),
            (20.0, 0.5),
            (0.0, 0.5),
            (0.5, 1.0),
            (14.0, 1.0),
            (14.0, 0.5),
            (14.0, -1.0),
            (8.0, -1.0),
            (8.5, -0.5),
            (13.0, -0.5),
            (13.0, -1.0),
            (13.0, -2.5),
            (9.0, -2.5),
            (9.5, -2.0),
            (9.5, 1.0),
            (20.0, 1.0),
            (20.0, 2.0),
            (20.0, -1.0),
            (14.0, -1.0),
            (12.0, -4.0),
            (10.0, -4.0),
            (8.0, -1.0),
            (0.0, -1.0),
            (0.0, 2.0),
            (20.0, 2.0),
        ];
        assert_eq!(e, want);
    }

    #[test]
    fn g70_takes_the_compensation_written_in_its_shape() {
        // G42 in N10 starts the compensation with the move to A' (10, 2); G40 in N20 ends it
        // with the move out to (20, -12); the return to A (X is there: Z only) runs without.
        let b = lathe(
            "G0 X40. Z2.\nG70 P10 Q20\nM30\nN10 G0 G42 X20. Z2.\nG1 Z-10. F0.1\nX30.\nN20 G40 X40. Z-12.\n",
        )
        .unwrap();
        let got: Vec<(f64, f64, Option<TrcSide>, TrcSide)> = b
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[2], b.trc, b.modal.trc)))
            .collect();
        let (r, off) = (TrcSide::Right, TrcSide::Off);
        assert_eq!(
            got,
            [
                (20.0, 2.0, None, off),
                (10.0, 2.0, Some(r), r),
                (10.0, -10.0, None, r),
                (15.0, -10.0, None, r),
                (20.0, -12.0, Some(off), off),
                (20.0, 2.0, None, off),
            ]
        );
        // G41 in an arc block: no start-up there (Fanuc alarm of a start-up in a circle).
        let a =
            lathe("G0 X40. Z2.\nG70 P10 Q20\nN10 G0 X20. Z2.\nG41 G2 X30. Z-3. R5.\nN20 G1 X40.\n")
                .unwrap_err();
        assert_eq!(
            (a.code, a.line, a.col),
            (AlarmCode::FanucTrcNotLinear, 4, 1)
        );
        // G40 alone in a roughing cycle's shape changes nothing.
        let b =
            lathe("G0 X40. Z2.\nG73 U1. R1\nG73 P10 Q20\nN10 G0 X20. Z2.\nN20 G40 G1 X40. Z-5.\n")
                .unwrap();
        assert!(b
            .iter()
            .all(|b| b.modal.trc == TrcSide::Off && b.trc.is_none()));
    }

    #[test]
    fn type_ii_bores_an_inner_groove() {
        // Inner turning (radius, Z), depth 3, retract 0.5: the levels go up in X. A (5, 2);
        // A' (12, 2) at rapid, (12, -5), out to (16, -8), (16, -12), back to (13, -15),
        // (13, -20), B (6, -20). Deepest 11 above A: levels X 8, 11, 14. 8 and 11: from
        // N10's move to the last element (X 13 → 6) at Z -20; 14: the groove's flanks at
        // Z -6.5 and -14. Retract 0.5 at 45° down in X. Between: X 7.5, then 10.5 (the
        // shallowest over the way is 7 above A: level 6 is cut), back to A over X 10.5.
        let e = diameter_ends(
            "G0 X10. Z2.\nG71 U3. R0.5\nG71 P10 Q20 F0.2\nN10 G0 X24. Z2.\nG1 Z-5.\nX32. Z-8.\nZ-12.\nX26. Z-15.\nZ-20.\nN20 X12.\n",
        );
        let want = [
            (5.0, 2.0),
            (8.0, 2.0),
            (8.0, -20.0),
            (7.5, -19.5),
            (7.5, 2.0),
            (11.0, 2.0),
            (11.0, -20.0),
            (10.5, -19.5),
            (10.5, -6.5),
            (11.0, -6.5),
            (14.0, -6.5),
            (14.0, -14.0),
            (13.5, -13.5),
            (10.5, -13.5),
            (10.5, 2.0),
            (5.0, 2.0),
            (12.0, 2.0),
            (12.0, -5.0),
            (16.0, -8.0),
            (16.0, -12.0),
            (13.0, -15.0),
            (13.0, -20.0),
            (6.0, -20.0),
            (5.0, -20.0),
            (5.0, 2.0),
        ];
        assert_eq!(e, want);
    }

    #[test]
    fn type_ii_cuts_a_round_pocket() {
        // (radius, Z), depth 3, retract 0.5. A (20, 2); A' (12, 2), (12, -5), a half circle
        // G2 R5 about (12, -10) down to X 7 and up to (12, -15), (12, -20), B (20, -20).
        // Deepest 13 (the arc's bottom): levels X 17, 14, 11, 8. 17 and 14: to the last
        // element at Z -20. 11 meets the arc where sin = -1/5: Z = -10 ± 5·√0.96; 8 where
        // sin = -4/5: Z = -10 ± 3. The way to 11: over the arc's ends (8 below A): level 6
        // cut, X 14.5; to 8: over the arc from Z -7 to the last retract point -14.399
        // (X 12 − 5·√(1 − 0.879796²) = 9.6232: 10.38 below A): level 9, X 11.5; back to A:
        // over (12, 2 … -5), 8 below A: X 14.5.
        let e = diameter_ends(
            "G0 X40. Z2.\nG71 U3. R0.5\nG71 P10 Q20 F0.2\nN10 G0 X24. Z2.\nG1 Z-5.\nG2 Z-15. R5.\nG1 Z-20.\nN20 X40.\n",
        );
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let w = 5.0 * 0.96f64.sqrt();
        let (z11a, z11b) = (-10.0 + w, -10.0 - w);
        let want = [
            (20.0, 2.0),
            (17.0, 2.0),
            (17.0, -20.0),
            (17.5, -19.5),
            (17.5, 2.0),
            (14.0, 2.0),
            (14.0, -20.0),
            (14.5, -19.5),
            (14.5, z11a),
            (14.0, z11a),
            (11.0, z11a),
            (11.0, z11b),
            (11.5, z11b + 0.5),
            (11.5, -7.0),
            (11.0, -7.0),
            (8.0, -7.0),
            (8.0, -13.0),
            (8.5, -12.5),
            (14.5, -12.5),
            (14.5, 2.0),
            (20.0, 2.0),
            (12.0, 2.0),
            (12.0, -5.0),
            (12.0, -15.0),
            (12.0, -20.0),
            (20.0, -20.0),
            (20.0, 2.0),
        ];
        let want: Vec<(f64, f64)> = want.iter().map(|&(x, z)| (r(x), r(z))).collect();
        assert_eq!(e, want);
    }

    #[test]
    fn type_ii_passes_a_point_that_touches_the_level() {
        // (radius, Z), depth 2. A (20, 2); A' (10, 2), (10, -5), up to a ridge at (14, -8),
        // down to (8, -11), (8, -15), B (20, -15). Level 14 meets the ridge's tip only: one
        // stretch from A's Z to the last element at Z -15, out by 0.5 at 45°.
        let e = diameter_ends(
            "G0 X40. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.2\nN10 G0 X20. Z2.\nG1 Z-5.\nX28. Z-8.\nX16. Z-11.\nZ-15.\nN20 X40.\n",
        );
        let k = e.iter().position(|&p| p == (14.0, 2.0)).expect("level 14");
        assert_eq!(e[k + 1..k + 3], [(14.0, -15.0), (14.5, -14.5)]);
        assert!(!e.contains(&(14.5, -7.5)), "no retract at the ridge: {e:?}");
    }

    /// δ = R − R/√2 for the nose radius 0.8: a 45° taper's compensated tip path lies δ
    /// beside the programmed taper in X and in Z (the nose centre is R/√2 off the taper in
    /// X and Z, the tip R below and R towards −Z of the centre).
    fn delta() -> f64 {
        0.8 - 0.8 / 2f64.sqrt()
    }

    fn close(got: &[(f64, f64)], want: &[(f64, f64)]) {
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (k, (g, w)) in got.iter().zip(want).enumerate() {
            let ok = (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9;
            assert!(ok, "move {k}: {g:?}, by hand {w:?}\n{got:?}");
        }
    }

    /// The moves of G71 at levels `levels`, each ending at the Z given, from A (`a`), with
    /// retract 1 (radius programming).
    fn passes(a: (f64, f64), levels: &[(f64, f64)]) -> Vec<(f64, f64)> {
        passes_by(a, 1.0, levels)
    }

    /// The moves of G71 (outer turning towards the chuck) at `levels`, each ending at the
    /// Z given, from A (`a`): in at A's Z, along Z, out by `e` at 45°, back to A's Z.
    fn passes_by(a: (f64, f64), e: f64, levels: &[(f64, f64)]) -> Vec<(f64, f64)> {
        let mut want = vec![a];
        for &(x, z) in levels {
            want.extend([(x, a.1), (x, z), (x + e, z + e), (x + e, a.1)]);
        }
        want
    }

    #[test]
    fn g71_roughs_a_taper_against_the_compensated_shape() {
        // Radius programming, T0101: nose R 0.8, edge position 3 (P − S = (−0.8, −0.8) in
        // (X, Z)). The shape (10, 2) → (10, −10) → 45° taper to (16, −16) → G40 up to
        // (20, −16), G42 (the nose above the contour). The nose centre: X 10.8 along the
        // diameter; the taper's parallel 0.8/√2 up and to +Z; the concave corner trimmed
        // where X 10.8 meets it, at Z −10 + 0.8(√2 − 1) = −10 + 0.8 − 2δ with δ = 0.8 −
        // 0.8/√2. The tip P = centre − (0.8, 0.8): A' (10, 1.2), (10, −10 − 2δ), the
        // taper's end (16 − δ, −16 − δ), then the G40 ramp to (20, −16) as programmed.
        // U0.2 W0.1 move it all by (0.2, 0.1): A' (10.2, 1.3), (10.2, −9.9 − 2δ),
        // (16.2 − δ, −15.9 − δ), (20.2, −15.9). From A (20, 2) the stock to 10.2 is 9.8:
        // levels 18 16 14 12 (4). Level 12 and 14 meet the taper (Z falls as X rises, 45°):
        // Z = −9.9 − 2δ − (L − 10.2); levels 16 and 18
        // the ramp, from (16.2 − δ, −15.9 − δ) rising 4 + δ in X over δ in Z.
        let d = delta();
        let ramp = |l: f64| -15.9 - d + (l - 16.2 + d) * d / (4.0 + d);
        let taper = |l: f64| -9.9 - 2.0 * d - (l - 10.2);
        let e = radius_ends(
            "T0101\nG0 X20. Z2.\nG71 U2. R1.\nG71 P10 Q20 U0.2 W0.1 F0.2\n\
             N10 G0 G42 X10.\nG1 Z-10.\nX16. Z-16.\nN20 G40 X20.\n",
        );
        let mut want = passes(
            (20.0, 2.0),
            &[
                (18.0, ramp(18.0)),
                (16.0, ramp(16.0)),
                (14.0, taper(14.0)),
                (12.0, taper(12.0)),
            ],
        );
        want.extend([
            (10.2, 1.3),
            (10.2, -9.9 - 2.0 * d),
            (16.2 - d, -15.9 - d),
            (20.2, -15.9),
            (20.0, -15.9),
            (20.0, 2.0),
        ]);
        close(&e, &want);
    }

    #[test]
    fn g71_roughs_a_convex_radius_against_the_compensated_shape() {
        // Radius programming, nose R 0.8, edge 3, G42. The shape (10, 2) → (10, −10) → the
        // face to (15, −10) → G3 R5 about (15, −15) to (20, −15) → (20, −25) → G40 to
        // (24, −25). The nose centre: X 10.8, trimmed at the face's parallel Z −9.2; the
        // face at Z −9.2 up to X 15; the arc at radius 5.8 about (15, −15) to (20.8, −15);
        // X 20.8 to Z −25. The tip, 0.8 lower and 0.8 towards −Z: A' (10, 1.2), (10, −10),
        // (14.2, −10), the arc about (14.2, −15.8) radius 5.8 to (20, −15.8), (20, −25.8),
        // then the ramp to (24, −25). From A (24, 2): stock 14, levels 22 20 … 12 (6).
        // 12, 14 end on the face at Z −10; 16, 18 on the arc, Z = −15.8 + √(5.8² − (L −
        // 14.2)²): 16 → −15.8 + √30.4, 18 → −15.8 + √19.2; 20 at the arc's end −15.8; 22 on
        // the ramp rising 4 over 0.8: −25.8 + 2 · 0.2 = −25.4.
        let arc = |l: f64| -15.8 + (5.8f64 * 5.8 - (l - 14.2) * (l - 14.2)).sqrt();
        let e = radius_ends(
            "T0101\nG0 X24. Z2.\nG71 U2. R1.\nG71 P10 Q20 F0.2\nN10 G0 G42 X10.\n\
             G1 Z-10.\nX15.\nG3 X20. Z-15. R5.\nG1 Z-25.\nN20 G40 X24.\n",
        );
        let mut want = passes(
            (24.0, 2.0),
            &[
                (22.0, -25.4),
                (20.0, -15.8),
                (18.0, arc(18.0)),
                (16.0, arc(16.0)),
                (14.0, -10.0),
                (12.0, -10.0),
            ],
        );
        want.extend([
            (10.0, 1.2),
            (10.0, -10.0),
            (14.2, -10.0),
            (20.0, -15.8),
            (20.0, -25.8),
            (24.0, -25.0),
            (24.0, 2.0),
        ]);
        close(&e, &want);
    }

    #[test]
    fn g73_runs_the_compensated_shape() {
        // One pass (R1) at the allowances 0: the tip path of the taper test above without
        // U and W, from A (20, 2), then back to A (X first).
        let d = delta();
        let e = radius_ends(
            "T0101\nG0 X20. Z2.\nG73 U0 W0 R1\nG73 P10 Q20 F0.2\n\
             N10 G0 G42 X10.\nG1 Z-10.\nX16. Z-16.\nN20 G40 X20.\n",
        );
        let want = [
            (20.0, 2.0),
            (10.0, 1.2),
            (10.0, -10.0 - 2.0 * d),
            (16.0 - d, -16.0 - d),
            (20.0, -16.0),
            (20.0, 2.0),
        ];
        close(&e, &want);
    }

    #[test]
    fn a_shape_the_nose_does_not_fit_is_refused_at_its_block() {
        // A concave fillet R0.5 (diameter programming) under a nose of 0.8: 10758 at the G2
        // block (line 7). A face step of 0.2 (radius) shorter than the nose's trim at the
        // concave corner before it: the equidistant turns inside out, 3021 at its block.
        let got = alarm(
            "T0101\nG71 U2. R1.\nG71 P10 Q20\nN10 G0 G42 X20.\nG1 Z-10. F0.1\n\
             G2 X21. Z-10.5 R0.5\nG1 X30.\nN20 G40 X40.\n",
        );
        assert_eq!(got, (AlarmCode::ArcRadiusTooSmall, 7, 1));
        let got = alarm(
            "T0101\nG71 U2. R1.\nG71 P10 Q20\nN10 G0 G42 X20.\nG1 Z-10. F0.1\nX20.4\n\
             Z-20.\nN20 G40 X40.\n",
        );
        assert_eq!(got, (AlarmCode::ContourViolation, 7, 1));
        // G40 in an arc block of a roughing shape: the lathe's start-up/cancel alarm, at the
        // arc's block (line 7).
        let got = alarm(
            "T0101\nG71 U2. R1.\nG71 P10 Q20\nN10 G0 G42 X20.\nG1 Z-10. F0.1\n\
             N20 G40 G2 X30. Z-15. R5.\n",
        );
        assert_eq!(got, (AlarmCode::FanucTrcNotLinear, 7, 1));
        // The same shapes without a nose radius (T0100: no offset) rough as programmed.
        assert!(lathe(
            "G0 X40. Z2.\nT0100\nG71 U2. R1.\nG71 P10 Q20\nN10 G0 G42 X20.\nG1 Z-10. F0.1\nX20.4\nZ-20.\nN20 G40 X40.\n"
        )
        .is_ok());
    }

    /// (X radius, Z, centre X, centre Z, counter-clockwise) of every arc.
    fn arcs(b: &[Block]) -> Vec<(f64, f64, f64, f64, bool)> {
        let r = |v: f64| (v * 1e9).round() / 1e9;
        b.iter()
            .filter_map(|b| b.motion)
            .filter(|m| m.kind.is_arc())
            .map(|m| {
                let ccw = m.kind == MotionKind::ArcCcw;
                (
                    r(m.end[0]),
                    r(m.end[2]),
                    r(m.center[0]),
                    r(m.center[2]),
                    ccw,
                )
            })
            .collect()
    }

    #[test]
    fn g70_after_g71_finishes_the_shape_in_radius_programming() {
        // Radius programming: X6 is radius 6, U0.3 is 0.3 on the radius. A (15, 2); the
        // shape A' (6, 2) at rapid, (6, −4), G2 R4 (concave, centre (10, −4)) to (10, −8),
        // (10, −14), B (16, −14). Moved by (0.3, 0.1): (6.3, 2.1), (6.3, −3.9), the arc
        // about (10.3, −3.9) to (10.3, −7.9), (10.3, −13.9), (16.3, −13.9). Stock 15 − 6.3
        // = 8.7: levels 13 11 9 7 (8.7/2 rounded up less 1 = 4). 13 and 11 lie above 10.3:
        // they end on the last element, Z −13.9; 9 and 7 on the arc, Z = −3.9 − √(16 −
        // (L − 10.3)²): −3.9 − √14.31, −3.9 − √5.11. Retract 0.5 at 45°, rapid back to Z 2.
        // The run along the moved shape, home X first (B lies beyond A's X). G70: the
        // shape as written at its F0.1, home X first: (15, −14), then Z 2.
        let src = "G0 X15. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.3 W0.1 F0.25\nN10 G0 X6.\n\
                   G1 Z-4. F0.1\nG2 X10. Z-8. R4.\nG1 Z-14.\nN20 X16.\nG70 P10 Q20\n";
        let arc = |l: f64| -3.9 - (16.0 - (l - 10.3f64).powi(2)).sqrt();
        let mut want = passes_by(
            (15.0, 2.0),
            0.5,
            &[
                (13.0, -13.9),
                (11.0, -13.9),
                (9.0, arc(9.0)),
                (7.0, arc(7.0)),
            ],
        );
        want.extend([
            (6.3, 2.1),
            (6.3, -3.9),
            (10.3, -7.9),
            (10.3, -13.9),
            (16.3, -13.9),
            (15.0, -13.9),
            (15.0, 2.0),
            (6.0, 2.0),
            (6.0, -4.0),
            (10.0, -8.0),
            (10.0, -14.0),
            (16.0, -14.0),
            (15.0, -14.0),
            (15.0, 2.0),
        ]);
        close(&radius_ends(src), &want);
        let b = lathe_radius(src);
        assert_eq!(
            arcs(&b),
            [
                (10.3, -7.9, 10.3, -3.9, false),
                (10.0, -8.0, 10.0, -4.0, false)
            ]
        );
        // The roughing cuts at the cycle's F0.25, G70's at the shape's F0.1.
        let feeds: Vec<f64> = b
            .iter()
            .filter(|b| b.motion.is_some_and(|m| m.kind != MotionKind::Rapid))
            .map(|b| b.modal.feed)
            .collect();
        assert_eq!(feeds.len(), 4 + 4 + 4);
        assert!(feeds[..8].iter().all(|&f| f == 0.25), "{feeds:?}");
        assert!(feeds[8..].iter().all(|&f| f == 0.1), "{feeds:?}");
    }

    #[test]
    fn g72_type_ii_cuts_a_face_groove_in_radius_programming() {
        // (radius, Z), depth 1.5 along Z, retract 0.5, U0.2 (radius) W0.5. A (22, 2); the
        // boundary A → A' (20, −1) at rapid, (14, −1), a 45° flank down to (11, −4), (9,
        // −4), a 45° flank up to (6, −1), B (0, −1); moved by (0.2, 0.5): A' (20.2, −0.5),
        // (14.2, −0.5), (11.2, −3.5), (9.2, −3.5), (6.2, −0.5), (0.2, −0.5). Deepest 5.5
        // below A's Z: levels Z 0.5, −1, −2.5 (5.5/1.5 rounded up less 1 = 3).
        // Z 0.5: from N10's move (X = 22 − 1.8·1.5/2.5 = 20.92, in at rapid) to past B (B's
        // X). Z −1 and −2.5: between the flanks, X = 14.2 + (Z + 0.5) and 9.2 − (Z + 3.5):
        // 13.7 to 6.7, 12.2 to 8.2. The way over: the shallowest boundary between is the
        // face at −0.5 (2.5 deep), then the second flank at X 7.2 (Z −1.5, 3.5 deep): the
        // deepest level cut less 0.5, Z 1 and −0.5, where the retract already is; down at
        // rapid to the level above, in at F. Back to A over Z 2 (A's own point is 0 deep);
        // the moved shape from A, home Z first.
        let want = [
            (22.0, 2.0),
            (20.92, 2.0),
            (20.92, 0.5),
            (0.2, 0.5),
            (0.7, 1.0),
            (13.7, 1.0),
            (13.7, 0.5),
            (13.7, -1.0),
            (6.7, -1.0),
            (7.2, -0.5),
            (12.2, -0.5),
            (12.2, -1.0),
            (12.2, -2.5),
            (8.2, -2.5),
            (8.7, -2.0),
            (8.7, 2.0),
            (22.0, 2.0),
            (20.2, -0.5),
            (14.2, -0.5),
            (11.2, -3.5),
            (9.2, -3.5),
            (6.2, -0.5),
            (0.2, -0.5),
            (0.2, 2.0),
            (22.0, 2.0),
        ];
        let e = radius_ends(
            "G0 X22. Z2.\nG72 W1.5 R0.5\nG72 P10 Q20 U0.2 W0.5 F0.2\nN10 G0 X20. Z-1.\n\
             G1 X14.\nX11. Z-4.\nX9.\nX6. Z-1.\nN20 X0.\n",
        );
        close(&e, &want);
        // The same groove in diameters: U0.4 is 0.2 on the radius.
        let e = diameter_ends(
            "G0 X44. Z2.\nG72 W1.5 R0.5\nG72 P10 Q20 U0.4 W0.5 F0.2\nN10 G0 X40. Z-1.\n\
             G1 X28.\nX22. Z-4.\nX18.\nX12. Z-1.\nN20 X0.\n",
        );
        close(&e, &want);
    }

    /// G71 type II under G42, (radius, Z), nose R 0.8 in edge position 3 (P = S − (0.8,
    /// 0.8)), U0.2 on the radius, depth 3, retract 0.5. The shape: A (17, 2), N10 G42 to
    /// A' (12, 2), (12, −5), a 45° flank down to (6, −11), (6, −15), a 45° flank up to
    /// (12, −21), (12, −25), N20 G40 out to (20, −25). With q = 0.8/√2:
    /// - the nose centre S runs 0.8 above: X 12.8 to Z −5; round the convex edge (12, −5)
    ///   (a left turn in (Z, X): counter-clockwise) to (12 + q, −5 − q); the flank's
    ///   parallel X − Z = 17 + 0.8√2 meets X 6.8 at the concave bottom corner, Z = −10.2 −
    ///   0.8√2; the rising flank's X + Z = −9 + 0.8√2 meets it at Z −15.8 + 0.8√2; up to
    ///   (12 + q, −21 + q), round the edge (12, −21) to (12.8, −21), X 12.8 to Z −25;
    /// - the tip P = S − (0.8, 0.8), moved by (0.2, 0): A' (12.2, 1.2), (12.2, −5.8), the
    ///   arc about (11.4, −5.8) to (11.4 + q, −5.8 − q), (6.2, −11 − 0.8√2), (6.2, −16.6 +
    ///   0.8√2), (11.4 + q, −21.8 + q), the arc about (11.4, −21.8) to (12.2, −21.8),
    ///   (12.2, −25.8), then the G40 ramp to (20.2, −25).
    ///
    /// The flanks of the moved tip path: X − Z = c1 = 17.2 + 0.8√2 falling, X + Z = c2 =
    /// −10.4 + 0.8√2 rising. Deepest 17 − 6.2 = 10.8: levels X 14, 11, 8 (10.8/3 rounded up
    /// less 1 = 3). 14: from N10's move (the line (17, 2) → (12.2, 1.2) at X 14: Z 2 − 0.8 ·
    /// 3/4.8 = 1.5, in at rapid) to the G40 ramp at X 14 (Z −25.8 + 0.8 · 1.8/8 = −25.62).
    /// 11 and 8: from the falling flank (Z = L − c1) to the rising one (Z = c2 − L). The
    /// way over to 11 starts at Z −25.12, behind the ramp's end (−25): the ramp turns back
    /// in Z and rises to X 19 there, above A: no level is cut over the whole way, so up to
    /// A's X 17, along Z, down at rapid to the level above (14), in by 3 at F. To 8 the
    /// shallowest boundary between is X 10.5 on the rising flank (6.5 deep): level 11 is
    /// cut, 11.5 is where the retract already is; down to 11, in. Back to A over X 17 (A's
    /// own point); the moved tip path from A, home X first.
    fn type_ii_nose_by_hand() -> Vec<(f64, f64)> {
        let (q, b) = (0.8 / 2f64.sqrt(), 0.8 * 2f64.sqrt());
        let (c1, c2) = (17.2 + b, -10.4 + b);
        let mut want = vec![
            (17.0, 2.0),
            (17.0, 1.5),
            (14.0, 1.5),
            (14.0, -25.62),
            (14.5, -25.12),
            (17.0, -25.12),
        ];
        for (level, over) in [(11.0, 17.0), (8.0, 11.5)] {
            want.extend([
                (over, level - c1),
                (level + 3.0, level - c1),
                (level, level - c1),
                (level, c2 - level),
                (level + 0.5, c2 - level + 0.5),
            ]);
        }
        want.extend([
            (17.0, c2 - 7.5),
            (17.0, 2.0),
            (12.2, 1.2),
            (12.2, -5.8),
            (11.4 + q, -5.8 - q),
            (6.2, -11.0 - b),
            (6.2, -16.6 + b),
            (11.4 + q, -21.8 + q),
            (12.2, -21.8),
            (12.2, -25.8),
            (20.2, -25.0),
            (17.0, -25.0),
            (17.0, 2.0),
        ]);
        want
    }

    #[test]
    fn type_ii_roughs_the_pockets_against_the_compensated_shape() {
        let src = "T0101\nG0 X34. Z2.\nG71 U3. R0.5\nG71 P10 Q20 U0.4 F0.2\n\
                   N10 G0 G42 X24. Z2.\nG1 Z-5.\nX12. Z-11.\nZ-15.\nX24. Z-21.\nZ-25.\nN20 G40 X40.\n";
        close(&diameter_ends(src), &type_ii_nose_by_hand());
        // The nose's arcs round the two convex edges, counter-clockwise.
        let r = |v: f64| (v * 1e9).round() / 1e9;
        let q = r(0.8 / 2f64.sqrt());
        assert_eq!(
            arcs(&lathe(src).unwrap()),
            [
                (r(11.4 + q), r(-5.8 - q), 11.4, -5.8, true),
                (12.2, -21.8, 11.4, -21.8, true)
            ]
        );
        // Radius programming: X and U are radii, the same moves.
        let e = radius_ends(
            "T0101\nG0 X17. Z2.\nG71 U3. R0.5\nG71 P10 Q20 U0.2 F0.2\n\
             N10 G0 G42 X12. Z2.\nG1 Z-5.\nX6. Z-11.\nZ-15.\nX12. Z-21.\nZ-25.\nN20 G40 X20.\n",
        );
        close(&e, &type_ii_nose_by_hand());
    }

    #[test]
    fn g72_roughs_the_compensated_face_in_radius_programming_and_g70_finishes_it() {
        // Radius programming, T0101 (R 0.8, edge 3), G41: travelling along −X the nose
        // stands on the +Z side. The shape: A (30, 2), N10 to A' (30, −6), the face to
        // (20, −6), a 45° taper to (16, −2), the face to (6, −2), N20 G40 out to (6, 1).
        // Nose centre S, q = 0.8/√2: the face at Z −5.2; the concave corner where it meets
        // the taper's parallel X + Z = 14 + 0.8√2: X 19.2 + 0.8√2; the taper to (16 + q,
        // −2 + q); round the convex edge (16, −2) to (16, −1.2); the face at Z −1.2 to X 6.
        // The tip P = S − (0.8, 0.8), moved by U0.2 (radius) W0.1: A' (29.4, −5.9), (18.6 +
        // 0.8√2, −5.9), (15.4 + q, −2.7 + q), the arc about (15.4, −2.7) to (15.4, −1.9),
        // (5.4, −1.9), then the G40 ramp to (6.2, 1.1).
        // Levels Z 2 − 2k above −5.9: 0, −2, −4 (7.9/2 rounded up less 1 = 3). Z 0 meets the
        // ramp, X = 5.4 + 0.8 · 1.9/3; Z −2 the arc, X = 15.4 + √(0.8² − 0.7²); Z −4 the
        // taper X + Z = 12.7 + 0.8√2. Each pass: in along Z at A's X at rapid (N10 is G00),
        // across at F, out 0.5 at 45° (Z and X up), back to X 30. The run along the tip
        // path, home Z first. G70: the shape as written from A, home X first: (30, 1), Z 2.
        let b = 0.8 * 2f64.sqrt();
        let q = 0.8 / 2f64.sqrt();
        let mut want = vec![(30.0, 2.0)];
        for (z, x) in [
            (0.0, 5.4 + 0.8 * 1.9 / 3.0),
            (-2.0, 15.4 + 0.15f64.sqrt()),
            (-4.0, 16.7 + b),
        ] {
            want.extend([(30.0, z), (x, z), (x + 0.5, z + 0.5), (30.0, z + 0.5)]);
        }
        want.extend([
            (29.4, -5.9),
            (18.6 + b, -5.9),
            (15.4 + q, -2.7 + q),
            (15.4, -1.9),
            (5.4, -1.9),
            (6.2, 1.1),
            (6.2, 2.0),
            (30.0, 2.0),
            (30.0, -6.0),
            (20.0, -6.0),
            (16.0, -2.0),
            (6.0, -2.0),
            (6.0, 1.0),
            (30.0, 1.0),
            (30.0, 2.0),
        ]);
        let src = "T0101\nG0 X30. Z2.\nG72 W2. R0.5\nG72 P10 Q20 U0.2 W0.1 F0.2\n\
                   N10 G0 G41 Z-6.\nG1 X20. F0.1\nX16. Z-2.\nX6.\nN20 G40 Z1.\nG70 P10 Q20\n";
        close(&radius_ends(src), &want);
        // The roughing's arc about the edge: the taper turns right into the face in (Z, X),
        // so the nose goes round it clockwise.
        let got = arcs(&lathe_radius(src));
        assert_eq!(got, [(15.4, -1.9, 15.4, -2.7, false)]);
    }
}
