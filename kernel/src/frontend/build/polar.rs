//! Polar coordinates (Fanuc 0i-MF, "Polar coordinate command G15, G16"): under G16 the
//! plane's first axis word is the radius and its second the angle in degrees,
//! counter-clockwise from the first axis, about the workpiece zero (G90). A word left out
//! keeps its last value. The words are turned into the Cartesian ones before the block's
//! motion or hole is computed, so everything after (cycles, the frame) works unchanged.

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{Val, Words};
use crate::alarm::AlarmCode;
use crate::machine_data::Units;

impl Interpreter<'_> {
    /// The block's words with the plane's two words Cartesian.
    pub(super) fn polar_words(&mut self, w: &Words, new: &ModalState, at: usize) -> R<Words> {
        let (a, o) = (new.plane.abscissa as usize, new.plane.ordinate as usize);
        let (Some((mut r, mut angle)), true) = (
            self.coords.polar,
            w.axis[a].is_some() || w.axis[o].is_some(),
        ) else {
            return Ok(w.clone());
        };
        if new.distance == Distance::Incremental {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "polar coordinates with incremental distances (the pole at the position now)",
            ));
        }
        if let Some(v) = w.axis[a] {
            r = self.in_program_units(v, new.units);
        }
        if let Some(v) = w.axis[o] {
            angle = self.in_program_units(v, Units::Mm);
        }
        self.coords.polar = Some((r, angle));
        let (sin, cos) = (libm::sin(angle.to_radians()), libm::cos(angle.to_radians()));
        let mut out = w.clone();
        let at_word = |v: Option<Val>| v.map_or(at as u32, |v| v.at);
        out.axis[a] = Some(Val {
            value: r * cos,
            at: at_word(w.axis[a]),
            has_point: true,
        });
        out.axis[o] = Some(Val {
            value: r * sin,
            at: at_word(w.axis[o]),
            has_point: true,
        });
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::frontend::MotionKind;

    #[test]
    fn radius_and_angle_about_the_zero_also_for_holes() {
        // A bolt circle: radius 50 at 30°, 150°, 270° (the radius kept).
        let b = run(
            "fanuc",
            "G17 G90 G0 X0. Y0. Z10.\nG16\nG99 G81 X50. Y30. Z-5. R2. F100.\nY150.\nY270.\nG15 G80\nG0 X0. Y0.\n",
        )
        .unwrap();
        let holes: Vec<[f64; 3]> = b
            .iter()
            .filter_map(|b| b.motion)
            .filter(|m| m.kind == MotionKind::Linear)
            .map(|m| m.end)
            .collect();
        let s3 = 3f64.sqrt();
        let want = [
            [25.0 * s3, 25.0, -5.0],
            [-25.0 * s3, 25.0, -5.0],
            [0.0, -50.0, -5.0],
        ];
        for (h, w) in holes.iter().zip(want) {
            assert!((0..3).all(|i| (h[i] - w[i]).abs() < 1e-9), "{h:?} != {w:?}");
        }
        assert_eq!(holes.len(), 3);
        let a = run("fanuc", "G91 G16 X10. Y45.\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::NotSupported);
    }
}
