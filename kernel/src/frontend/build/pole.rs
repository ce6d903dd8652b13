//! SINUMERIK polar coordinates (Fundamentals, "Travel commands with polar coordinates"): the
//! pole is defined by G110 (from the last programmed position), G111 (from the workpiece
//! zero) or G112 (from the last pole), with the plane's axes or with AP= RP=; an end point is
//! given by the polar angle AP= (degrees, counter-clockwise from the plane's abscissa) and
//! the radius RP= about it, for G0/G1 (a line) or G2/G3 (a circle about the pole). Pole,
//! angle and radius are modal; a new pole or another plane asks for angle and radius anew.
//! Without a pole the workpiece zero is the pole. docs/sinumerik.md, "Polar coordinates".

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{Val, Words};
use super::motion::{arc_fault, diameter_factor, feed_programmed, in_range};
use crate::alarm::AlarmCode;
use crate::dialect::GEffect;

/// The polar state of the program.
#[derive(Clone, Copy, Debug, Default)]
pub struct Polar {
    /// The pole in workpiece coordinates (without the zero offset); `None`: the zero.
    pole: Option<Pos>,
    /// Angle (degrees) and radius of the last polar point, in `plane`.
    angle: Option<f64>,
    radius: Option<f64>,
    plane: Option<Plane>,
}

impl Interpreter<'_> {
    /// Step 8, a pole definition: the pole from the block's plane axes or AP= RP=; nothing
    /// moves (Fundamentals, "Defining the pole (G110, G111, G112)": absolute or incremental
    /// dimensions do not change its meaning).
    pub(super) fn pole_block(
        &mut self,
        w: &Words,
        new: &ModalState,
        origin: PoleOrigin,
        at: u32,
    ) -> R<()> {
        self.no_additional_axes(w, "a pole definition")?;
        if let Some(v) = w.radius.or(w.centre.iter().flatten().next().copied()) {
            return Err(fault(
                AlarmCode::Syntax,
                v.at,
                "a pole definition moves nothing",
            ));
        }
        let base = match origin {
            PoleOrigin::LastPosition => self.workpiece_position(new, at as usize)?,
            PoleOrigin::WorkZero => [0.0; 3],
            PoleOrigin::LastPole => self.polar.pole.unwrap_or([0.0; 3]),
        };
        let pole = if w.path.polar() {
            self.polar_pole(w, new, base, at)?
        } else {
            self.cartesian_pole(w, new, base, origin, at)?
        };
        self.polar = Polar {
            pole: Some(pole),
            angle: None,
            radius: None,
            plane: Some(new.plane),
        };
        Ok(())
    }

    /// The pole at AP= RP= from `base`.
    fn polar_pole(&self, w: &Words, new: &ModalState, base: Pos, at: u32) -> R<Pos> {
        let p = new.plane;
        if let Some(v) = [w.axis[p.abscissa as usize], w.axis[p.ordinate as usize]]
            .into_iter()
            .flatten()
            .next()
        {
            return Err(fault(
                AlarmCode::Syntax,
                v.at,
                "a pole is given by the plane's axes or by AP= RP=, not both",
            ));
        }
        let (Some(a), Some(r)) = (w.path.ap, w.path.rp) else {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "a pole in polar coordinates needs AP= and RP=",
            ));
        };
        let r = self.polar_radius(r, new)?;
        let mut pole = base;
        let rad = a.value.to_radians();
        pole[p.abscissa as usize] += r * libm::cos(rad);
        pole[p.ordinate as usize] += r * libm::sin(rad);
        Ok(pole)
    }

    /// The pole at the axis words: from `base`, or (G111) absolute; an axis not written
    /// keeps `base`'s coordinate.
    fn cartesian_pole(
        &self,
        w: &Words,
        new: &ModalState,
        base: Pos,
        origin: PoleOrigin,
        at: u32,
    ) -> R<Pos> {
        let p = new.plane;
        if w.axis[p.abscissa as usize].is_none() && w.axis[p.ordinate as usize].is_none() {
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                format!(
                    "a pole definition needs an axis of the {} plane, or AP= RP=",
                    p.name()
                ),
            ));
        }
        let distance = match origin {
            PoleOrigin::WorkZero => Distance::Absolute,
            _ => Distance::Incremental,
        };
        let mut pole = base;
        for (i, a) in w.axis.iter().enumerate() {
            if let Some(a) = a {
                let v = self.length(*a, new.units) * diameter_factor(i, new, distance);
                pole[i] = if distance == Distance::Absolute {
                    v
                } else {
                    base[i] + v
                };
                if !in_range(pole[i]) {
                    return Err(fault(AlarmCode::BadNumber, a.at, "pole out of range"));
                }
            }
        }
        Ok(pole)
    }

    /// A polar radius in mm: not negative (Fundamentals: "always in absolute positive values").
    fn polar_radius(&self, r: Val, new: &ModalState) -> R<f64> {
        let v = self.length(r, new.units);
        if v < 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                r.at,
                "the polar radius RP= is not negative",
            ));
        }
        Ok(v)
    }

    /// Step 8, a block with AP= or RP=: its end point about the pole; a line under G0/G1, a
    /// circle about the pole under G2/G3. The normal axis moves as written.
    pub(super) fn polar_move(
        &mut self,
        w: &Words,
        new: &ModalState,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        let at = w.path.ap.or(w.path.rp).map_or(block_col, Val::pos);
        self.polar_words_fit(w, new, at)?;
        let p = new.plane;
        let (a, o) = (p.abscissa as usize, p.ordinate as usize);
        // Under a frame the point is worked out in program coordinates, then mapped.
        let framed = self.coords.frame.active() && !self.machine_coordinates;
        let offset = if framed {
            [0.0; crate::machine_data::AXES]
        } else {
            self.work_offset(new)
        };
        let pole_wcs = self.polar.pole.unwrap_or([0.0; 3]);
        let mut pole: Pos = std::array::from_fn(|i| pole_wcs[i] + offset[i]);
        let (start, mut end) = if framed {
            self.framed_points(w, new, block_col)?
        } else {
            (self.cur, self.end_point(w, new, self.cur)?)
        };
        pole[p.normal as usize] = start[p.normal as usize];
        let arc = new.motion.is_arc();
        let r_start = libm::hypot(start[a] - pole[a], start[o] - pole[o]);
        let (angle, r) = self.polar_end(w, new, arc.then_some(r_start), at)?;
        end[a] = pole[a] + r * libm::cos(angle.to_radians());
        end[o] = pole[o] + r * libm::sin(angle.to_radians());
        if !in_range(end[a]) || !in_range(end[o]) {
            return Err(fault(AlarmCode::BadNumber, at, "coordinate out of range"));
        }
        feed_programmed(new, block_col)?;
        if arc {
            let tol = self.md.program.arc_endpoint_tolerance;
            if r_start <= 1e-9 {
                return Err(arc_fault(super::super::arc::ArcError::ZeroRadius, tol, at));
            }
            if (r - r_start).abs() > tol {
                let e = super::super::arc::ArcError::EndPointOff { r_start, r_end: r };
                return Err(arc_fault(e, tol, w.path.rp.map_or(at, Val::pos)));
            }
        }
        let centre = if arc { pole } else { end };
        let programmed = programmed | 1 << a | 1 << o;
        if framed {
            if arc {
                self.frame_keeps_circles(new, block_col)?;
            }
            self.set_framed_motion(new, end, centre, programmed, block_col)?;
        } else {
            self.set_motion(new, start, end, centre, programmed, block_col)?;
        }
        self.polar.angle = Some(angle);
        self.polar.radius = Some(r);
        self.polar.plane = Some(p);
        Ok(())
    }

    /// AP= RP= need both axes of the plane on the machine, no plane-axis or centre words
    /// beside them, and a line or a circle about the pole.
    fn polar_words_fit(&self, w: &Words, new: &ModalState, at: usize) -> R<()> {
        let p = new.plane;
        for i in [p.abscissa as usize, p.ordinate as usize] {
            if !self.md.has_axis(i) {
                return Err(fault(
                    AlarmCode::UnknownAddress,
                    at,
                    format!(
                        "AP=/RP= need both axes of the {} plane: {} is not configured",
                        p.name(),
                        AXIS_NAMES[i]
                    ),
                ));
            }
            if let Some(v) = w.axis[i] {
                return Err(fault(
                    AlarmCode::Syntax,
                    v.at,
                    format!(
                        "{} beside AP=/RP=: the point is given about the pole",
                        AXIS_NAMES[i]
                    ),
                ));
            }
        }
        if let Some(v) = w.radius.or(w.centre.iter().flatten().next().copied()) {
            return Err(fault(
                AlarmCode::Syntax,
                v.at,
                "a circle in polar coordinates is centred on the pole",
            ));
        }
        if !new.motion.is_plain() {
            let motions = self.d.codes_of(&[
                GEffect::Motion(MotionMode::Rapid),
                GEffect::Motion(MotionMode::Linear),
                GEffect::Motion(MotionMode::ArcCw),
                GEffect::Motion(MotionMode::ArcCcw),
            ]);
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("AP=/RP= take {motions}"),
            ));
        }
        Ok(())
    }

    /// Angle (degrees) and radius of the end point. A word not written keeps the last polar
    /// point's value in this plane and about this pole; a circle without RP= keeps its start
    /// radius (`circle`). AP= is incremental (from the last angle) under G91 or with IC().
    fn polar_end(
        &self,
        w: &Words,
        new: &ModalState,
        circle: Option<f64>,
        at: usize,
    ) -> R<(f64, f64)> {
        let fresh = self.polar.plane != Some(new.plane);
        let (last_angle, last_radius) = if fresh {
            (None, None)
        } else {
            (self.polar.angle, self.polar.radius)
        };
        let missing = |what: &str| {
            fault(
                AlarmCode::MissingValue,
                at,
                format!("{what}: none is programmed for this pole and plane"),
            )
        };
        let angle = match w.path.ap {
            Some(v) => {
                let incremental = w
                    .path
                    .ap_incremental
                    .unwrap_or(new.distance == Distance::Incremental);
                if incremental {
                    last_angle.ok_or_else(|| missing("AP= adds to the last polar angle"))? + v.value
                } else {
                    v.value
                }
            }
            None => last_angle.ok_or_else(|| missing("AP= (polar angle)"))?,
        };
        let radius = match w.path.rp {
            Some(v) => self.polar_radius(v, new)?,
            None => circle
                .or(last_radius)
                .ok_or_else(|| missing("RP= (polar radius)"))?,
        };
        Ok((angle, radius))
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::near;
    use crate::alarm::AlarmCode;
    use crate::frontend::MotionKind;

    fn moves(src: &str) -> Vec<(MotionKind, [f64; 3], [f64; 3])> {
        super::super::super::moves("siemens-840d", src)
    }

    fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        super::super::super::alarm_at("siemens-840d", src)
    }

    #[test]
    fn polar_points_are_worked_out_in_program_coordinates_under_a_frame() {
        use MotionKind::*;
        // TRANS X10 then AROT RPL=90: p ↦ (10, 0) + R90·p. RP=10 AP=0: (10, 0) → (10, 10);
        // AP=90: (0, 10) → (0, 0); G3 AP=180: (−10, 0) → (10, −10) about the pole (0, 0) →
        // (10, 0), counter-clockwise. G110 X5 under the frame: from the program position.
        let got = moves(
            "TRANS X10\nAROT RPL=90\nG111 X0 Y0\nG1 F100 RP=10 AP=0\nAP=90\nG3 AP=180\nG1 X5 Y0\nG110 X5\nG1 RP=5 AP=90\n",
        );
        let want = [
            (Linear, [10.0, 10.0, 0.0]),
            (Linear, [0.0, 0.0, 0.0]),
            (ArcCcw, [10.0, -10.0, 0.0]),
            (Linear, [10.0, 5.0, 0.0]),
            (Linear, [5.0, 10.0, 0.0]),
        ];
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(g.0 == w.0 && near(g.1, w.1), "{got:?}");
        }
        assert!(near(got[2].2, [10.0, 0.0, 0.0]), "{got:?}");
    }

    #[test]
    fn poles_from_the_zero_the_position_and_the_last_pole() {
        // G111 X10 Y5: pole (10, 5); RP=20 AP=90: (10, 25). AP=IC(90): 180° → (−10, 5);
        // G91 AP=-90: back to 90° → (10, 25). G110 X5: pole (10, 25) + (5, 0) = (15, 25);
        // G90 RP=10 AP=0: (25, 25). G112 Y-10: pole (15, 15); RP=10 AP=270: (15, 5), Z5
        // as written (cylinder coordinates).
        let got = moves(
            "G111 X10 Y5\nG1 RP=20 AP=90 F100\nAP=IC(90)\nG91 AP=-90\nG110 X5\nG90 RP=10 AP=0\nG112 Y-10\nRP=10 AP=270 Z5\n",
        );
        let want = [
            [10.0, 25.0, 0.0],
            [-10.0, 5.0, 0.0],
            [10.0, 25.0, 0.0],
            [25.0, 25.0, 0.0],
            [15.0, 5.0, 5.0],
        ];
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(g.0 == MotionKind::Linear && near(g.1, w), "{got:?}");
        }
    }

    #[test]
    fn a_polar_circle_runs_about_the_pole() {
        // Pole (0, 0); from (10, 0) G3 AP=90 keeps the start radius: (0, 10) about (0, 0).
        // G111 RP=10 AP=90: the pole at (0, 10) in polar coordinates; RP=5 AP=0: (5, 10).
        let got = moves("G111 X0 Y0\nG1 X10 Y0 F100\nG3 AP=90\nG111 RP=10 AP=90\nG1 RP=5 AP=0\n");
        assert_eq!(got[1].0, MotionKind::ArcCcw);
        assert!(
            near(got[1].1, [0.0, 10.0, 0.0]) && near(got[1].2, [0.0; 3]),
            "{got:?}"
        );
        assert!(near(got[2].1, [5.0, 10.0, 0.0]), "{got:?}");
        // A radius that is not the start's is no circle about the pole.
        assert_eq!(
            alarm("G1 X10 Y0 F100\nG2 RP=12 AP=0\n"),
            (AlarmCode::ArcEndPoint, 2, 4)
        );
    }

    #[test]
    fn what_polar_words_refuse() {
        // Angle and radius are asked for anew after a new pole or plane.
        assert_eq!(
            alarm("G1 RP=10 AP=0 F1\nG111 X1 Y1\nAP=30\n"),
            (AlarmCode::MissingValue, 3, 1)
        );
        assert_eq!(
            alarm("G1 RP=10 AP=0 F1\nG18\nAP=30\n"),
            (AlarmCode::MissingValue, 3, 1)
        );
        // A plane axis beside AP=, a pole without a plane axis, a centre, CIP.
        assert_eq!(alarm("G1 X5 AP=10 RP=5 F1\n"), (AlarmCode::Syntax, 1, 4));
        assert_eq!(alarm("G111 Z5\n"), (AlarmCode::MissingValue, 1, 1));
        assert_eq!(alarm("G111 AP=5\n"), (AlarmCode::MissingValue, 1, 1));
        assert_eq!(alarm("G2 AP=10 RP=5 CR=5 F1\n"), (AlarmCode::Syntax, 1, 15));
        assert_eq!(
            alarm("CIP AP=10 RP=5 F1\n"),
            (AlarmCode::NotSupported, 1, 5)
        );
        assert_eq!(alarm("G1 AP=10 RP=-5 F1\n"), (AlarmCode::BadNumber, 1, 10));
        assert_eq!(
            alarm("G1 AP=10 RP=IC(5) F1\n"),
            (AlarmCode::NotSupported, 1, 10)
        );
    }
}
