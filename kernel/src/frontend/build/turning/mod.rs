//! Multiple repetitive turning cycles (Fanuc 0i-TF, G-code system A): the shape is written
//! once between the blocks P and Q; G71 roughs down to it in passes along Z, G70 runs it.
//!
//! ```text
//! G71 U(Δd) R(e)                  depth of cut (radius), retract: stored
//! G71 P(ns) Q(nf) U(Δu) W(Δw) F S allowances (U a diameter); F and S for the roughing
//! N(ns) G00/G01 X(U) …            the shape: the first block moves X only (type I)
//! N(nf) …
//! G70 P(ns) Q(nf)                 finishing: the shape with its own F and S
//! ```
//!
//! After G71 the program goes on after block Q; after G70, after the G70 block. Both
//! return to the start point at rapid. [`contour`] reads the shape, [`stock_removal`] makes
//! the moves.

mod contour;
mod stock_removal;

pub use contour::Element;
pub use stock_removal::{non_monotonic, Passes, TurningRun, EPS};

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{int_value, Val, Words};
use super::expand::Expansion;
use crate::alarm::AlarmCode;
use crate::dialect::TurningCycle;

/// `G71 U R`: the depth of cut and the retract, kept until written again.
#[derive(Clone, Copy, Debug, Default)]
pub struct TurningData {
    pub depth: f64,
    pub retract: f64,
}

impl Interpreter<'_> {
    /// Step 8 of a G70/G71 block.
    pub(super) fn turning_cycle(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        kind: TurningCycle,
        at: usize,
    ) -> R<()> {
        self.turning_allowed(new, at)?;
        let (p, q) = match (w.p, w.q) {
            (None, None) if kind == TurningCycle::StockRemoval => {
                return self.depth_and_retract(w, new, at)
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
        let passes = match kind {
            TurningCycle::StockRemoval => {
                let (shape, passes) = self.stock_removal(w, new, &contour, at)?;
                (self.pos, self.line, self.line_start) = contour.after;
                Some((shape, passes))
            }
            TurningCycle::Finishing => None,
        };
        let run = match passes {
            Some((shape, p)) => TurningRun::new(start, shape, Some(p)),
            None => TurningRun::new(start, contour.elements, None),
        };
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

    /// `G71 U(Δd) R(e)`: stored for the cycles that follow.
    fn depth_and_retract(&mut self, w: &Words, new: &ModalState, at: usize) -> R<()> {
        let no_axes = w.axis[1].is_none() && w.axis[2].is_none();
        let Some(u) = w.axis[0].filter(|_| no_axes && w.incremental & 1 != 0) else {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "the depth of cut block is U(depth) R(retract), or give P and Q",
            ));
        };
        let depth = self.length(u, new.units);
        if depth <= 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                u.pos(),
                "the depth of cut U must be greater than 0",
            ));
        }
        self.turning.depth = depth;
        if let Some(r) = w.radius {
            let e = self.length(r, new.units);
            if e < 0.0 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    r.pos(),
                    "the retract R must not be negative",
                ));
            }
            self.turning.retract = e;
        }
        Ok(())
    }
}

impl Interpreter<'_> {
    /// G71 type I: the shape offset by the allowances and the passes, checked.
    fn stock_removal(
        &mut self,
        w: &Words,
        new: &ModalState,
        contour: &contour::Contour,
        at: usize,
    ) -> R<(Vec<Element>, Passes)> {
        if self.turning.depth <= 0.0 {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "no depth of cut: program the block U(depth) R(retract) of the cycle first",
            ));
        }
        if contour.first_has_z {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "stock removal type II (Z in the shape's first block: pockets) is not built yet",
            ));
        }
        let (du, dw) = self.allowances(w, new)?;
        let shape = &contour.elements;
        let (a, a1) = (self.cur, shape.first().map_or(self.cur, |e| e.to));
        let b = shape.last().map_or(a1, |e| e.to);
        let sx = sign(a[0] - a1[0]);
        let sz = sign(b[2] - a1[2]);
        if sx == 0.0 || sz == 0.0 {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "the shape must start below (or above) the start point in X and go on along Z",
            ));
        }
        if let Some((i, what)) = stock_removal::non_monotonic(shape, sx, sz) {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!(
                    "the shape is not monotonic (type I), element {}: {what}",
                    i + 1
                ),
            ));
        }
        let shape: Vec<Element> = shape.iter().map(|e| shifted(e, du, dw)).collect();
        let total = sx * (a[0] - shape[0].to[0]);
        if sx * du < 0.0 || sz * dw > 0.0 || total <= EPS {
            return Err(fault(
                AlarmCode::BadNumber,
                at,
                "the allowances U and W turn the shape inside out (their signs oppose the cut, or they reach the start point)",
            ));
        }
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
        Ok((shape, passes))
    }

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

pub fn sign(v: f64) -> f64 {
    if v > EPS {
        1.0
    } else if v < -EPS {
        -1.0
    } else {
        0.0
    }
}

/// The element moved by the allowances (its centre with it).
pub fn shifted(e: &Element, du: f64, dw: f64) -> Element {
    let mv = |mut p: Pos| {
        p[0] += du;
        p[2] += dw;
        p
    };
    Element {
        to: mv(e.to),
        centre: mv(e.centre),
        ..*e
    }
}

#[cfg(test)]
mod tests {
    use crate::alarm::{Alarm, AlarmCode};
    use crate::frontend::{interpret, Block};
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    fn lathe(src: &str) -> Result<Vec<Block>, Alarm> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-lathe.toml");
        let md = MachineData::load(Some(std::path::Path::new(path)), &[]).unwrap();
        interpret("l.nc", src, &md, &ToolTable::builtin())
    }

    /// (X radius, Z) of every move's end, rounded to 1e-9, with X programmed as a radius.
    fn radius_ends(src: &str) -> Vec<(f64, f64)> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-lathe.toml");
        let ov = ["program.diameter_programming=false".to_string()];
        let md = MachineData::load(Some(std::path::Path::new(path)), &ov).unwrap();
        let b =
            interpret("r.nc", src, &md, &ToolTable::builtin()).unwrap_or_else(|a| panic!("{a}"));
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
        // Z in the first block: type II, not built.
        let got = alarm("G71 U2. R1.\nG71 P10 Q20\nN10 G0 X20. Z1.\nG1 Z-10. F0.1\nN20 X40.\n");
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
        // Nose radius compensation inside the shape: not built yet, alarm at its G41.
        let got = alarm("G71 U2. R1.\nG71 P10 Q20\nN10 G0 X20.\nG41 G1 Z-10. F0.1\nN20 X40.\n");
        assert_eq!(got, (AlarmCode::NotSupported, 5, 1));
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
}
