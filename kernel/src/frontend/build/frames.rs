//! The frame in the block build (frame.rs holds the map): the blocks that program it on
//! Fanuc (G51.1/G50.1 mirror, G51/G50 scaling, G68/G69 rotation; SINUMERIK's statements are
//! sinumerik/frames.rs) and the motion of a block while it is active, computed in program
//! coordinates and then mapped.

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{Val, Words};
use crate::alarm::AlarmCode;

/// Which part of the frame a block programs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FramePart {
    /// G51.1 (true) / G50.1 (false).
    Mirror(bool),
    /// G51 (true) / G50 (false).
    Scale(bool),
    /// G68 (true) / G69 (false).
    Rotation(bool),
}

impl Interpreter<'_> {
    /// Step 8 of a block that programs the frame: its axis words are centres or mirror
    /// positions and nothing moves; after G50 and G69 (true) the block moves as written.
    /// Not while compensation is active (its side or shape would change).
    pub(super) fn frame_block(
        &mut self,
        w: &Words,
        new: &ModalState,
        part: FramePart,
        block_col: usize,
    ) -> R<bool> {
        if new.trc != TrcSide::Off || self.block.modal.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                block_col,
                "the frame (mirror, scaling, rotation) cannot change while tool radius compensation is active",
            ));
        }
        if matches!(part, FramePart::Scale(false) | FramePart::Rotation(false)) {
            let f = &mut self.coords.frame;
            if part == FramePart::Scale(false) {
                f.scale = None;
            } else {
                f.rotation = None;
            }
            f.update();
            return Ok(true);
        }
        self.no_additional_axes(w, "a frame block (X Y Z only)")?;
        let here = self.program_position(new, block_col)?;
        let words = self.frame_words(w, new);
        let f = &mut self.coords.frame;
        match part {
            FramePart::Mirror(on) => {
                for (i, v) in words.iter().enumerate() {
                    if v.is_some() {
                        f.mirror[i] = if on { *v } else { None };
                    }
                }
            }
            FramePart::Scale(false) | FramePart::Rotation(false) => {}
            FramePart::Scale(true) => {
                let factors = self.scale_factors(w)?;
                let centre = std::array::from_fn(|i| words[i].unwrap_or(here[i]));
                self.coords.frame.scale = Some((factors, centre));
            }
            FramePart::Rotation(true) => {
                let r = w.radius.ok_or_else(|| {
                    fault(
                        AlarmCode::MissingValue,
                        block_col,
                        "the rotation angle R is missing",
                    )
                })?;
                let old = self.coords.frame.rotation.map_or(0.0, |(_, _, a)| a);
                // Degrees, in the least input increment without a decimal point.
                let r = self.in_program_units(r, crate::machine_data::Units::Mm);
                let angle = match new.distance {
                    Distance::Absolute => r,
                    Distance::Incremental => old + r,
                };
                let centre = std::array::from_fn(|i| words[i].unwrap_or(here[i]));
                self.coords.frame.rotation = Some((new.plane, centre, angle));
            }
        }
        self.coords.frame.update();
        Ok(false)
    }

    /// X Y Z of a frame block in mm, workpiece coordinates (always absolute).
    fn frame_words(&self, w: &Words, new: &ModalState) -> [Option<f64>; 3] {
        std::array::from_fn(|i| w.axis[i].map(|v| self.length(v, new.units)))
    }

    /// G51's factors: P for every axis, or I J K per axis (without a decimal point in
    /// 0.001, the control's scale unit, whatever the decimal-input switch).
    fn scale_factors(&self, w: &Words) -> R<[f64; 3]> {
        let factor = |v: Val| -> R<f64> {
            let f = if v.has_point {
                v.value
            } else {
                v.value * 0.001
            };
            if f == 0.0 || f.abs() > 1e4 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    v.at,
                    "scale factor out of range",
                ));
            }
            Ok(f)
        };
        match (w.p, w.centre.iter().any(Option::is_some)) {
            (Some(p), _) => Ok([factor(p)?; 3]),
            (None, true) => {
                let mut s = [1.0; 3];
                for (k, v) in w.centre.iter().enumerate() {
                    if let Some(v) = v {
                        s[k] = factor(*v)?;
                    }
                }
                Ok(s)
            }
            (None, false) => Ok([1.0; 3]),
        }
    }

    /// Where the tool stands in workpiece terms: the program's coordinates under a frame,
    /// else the position less the zero.
    pub(in crate::frontend) fn workpiece_position(&self, new: &ModalState, at: usize) -> R<Pos> {
        if self.coords.frame.active() && !self.machine_coordinates {
            return self.program_position(new, at);
        }
        let offset = self.work_offset(new);
        Ok(std::array::from_fn(|i| self.cur[i] - offset[i]))
    }

    /// Where the tool stands in program coordinates: back through the zero and the frame.
    pub(in crate::frontend) fn program_position(&self, new: &ModalState, at: usize) -> R<Pos> {
        let zero = self.zero(new.work_offset);
        let rel = std::array::from_fn(|i| self.cur[i] - zero[i]);
        self.coords.frame.invert(rel).ok_or_else(|| {
            fault(
                AlarmCode::Arithmetic,
                at,
                "the frame scales by 0: no way back",
            )
        })
    }

    /// Start and end point of a move under the frame, in program coordinates: the start is
    /// where the tool stands, taken back through the zero and the frame; each axis word is
    /// absolute or incremental by G90/G91 or its own AC()/IC() (U/W), a diameter halved.
    pub(super) fn framed_points(
        &self,
        w: &Words,
        new: &ModalState,
        block_col: usize,
    ) -> R<(Pos, Pos)> {
        let start = self.program_position(new, block_col)?;
        let mut end = start;
        for (i, a) in w.axis.iter().enumerate() {
            if let Some(a) = a {
                let half = if i == 0 && new.diameter { 0.5 } else { 1.0 };
                let v = self.length(*a, new.units) * half;
                let bit = 1 << i;
                let incremental = w.incremental & bit != 0
                    || (new.distance == Distance::Incremental && w.absolute & bit == 0);
                end[i] = if incremental { start[i] + v } else { v };
            }
        }
        Ok((start, end))
    }

    /// A circle under the frame: its plane must stay itself, scaled alike on both axes.
    pub(super) fn frame_keeps_circles(&self, new: &ModalState, block_col: usize) -> R<()> {
        let frame = &self.coords.frame;
        if !frame.keeps_plane(new.plane) {
            return Err(fault(
                AlarmCode::NotSupported,
                block_col,
                "a circle in a plane the frame turns out of itself (rotation about another plane)",
            ));
        }
        if !frame.keeps_circles(new.plane) {
            return Err(fault(
                AlarmCode::NotSupported,
                block_col,
                "a circle under scaling with different factors on the plane's axes",
            ));
        }
        Ok(())
    }

    /// The move to `end` (about `centre`), both in program coordinates, mapped by the frame
    /// and the zero; a frame that turns the plane over turns the arc's direction.
    pub(super) fn set_framed_motion(
        &mut self,
        new: &ModalState,
        end: Pos,
        centre: Pos,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        let frame = self.coords.frame;
        let zero = self.zero(new.work_offset);
        let map = |p: Pos| -> Pos {
            let q = frame.apply(p);
            std::array::from_fn(|i| q[i] + zero[i])
        };
        let (end, centre) = (map(end), map(centre));
        if !end.iter().all(|&x| super::motion::in_range(x)) {
            return Err(fault(
                AlarmCode::BadNumber,
                block_col,
                "the end point under the frame is out of range",
            ));
        }
        let start = self.cur;
        self.set_motion(new, start, end, centre, programmed, block_col)?;
        if let (true, Some(m)) = (frame.flips(new.plane), self.block.motion.as_mut()) {
            m.kind = match m.kind {
                MotionKind::ArcCw => MotionKind::ArcCcw,
                MotionKind::ArcCcw => MotionKind::ArcCw,
                k => k,
            };
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::frontend::{Block, MotionKind, TrcSide};

    fn blocks(src: &str) -> Vec<Block> {
        run("fanuc", src).unwrap_or_else(|a| panic!("{a}"))
    }

    fn near(a: [f64; 3], b: [f64; 3]) {
        for i in 0..3 {
            assert!((a[i] - b[i]).abs() < 1e-9, "{a:?} != {b:?}");
        }
    }

    #[test]
    fn rotation_turns_positions_about_its_centre() {
        // G68 about (10, 0) by 90°: X20 Y0 → (10, 10); G91 X5 moves along the turned X.
        let b = blocks("G0 X0. Y0.\nG68 X10. Y0. R90.\nG0 X20. Y0.\nG91 X5.\nG90 G69 X0. Y0.\n");
        let ends: Vec<[f64; 3]> = b.iter().filter_map(|b| b.motion.map(|m| m.end)).collect();
        near(ends[1], [10.0, 10.0, 0.0]);
        near(ends[2], [10.0, 15.0, 0.0]);
        near(ends[3], [0.0, 0.0, 0.0]);
    }

    #[test]
    fn the_rotation_angle_takes_the_increment_and_keeps_its_plane() {
        // Increment input: R90000 without a decimal point is 90°.
        let md = crate::machine_data::MachineData::load(
            None,
            &[
                "dialect=fanuc".into(),
                "program.decimal_input=increment".into(),
            ],
        )
        .unwrap();
        let b = crate::frontend::interpret(
            "r.nc",
            "G0 X0. Y0.\nG68 X0. Y0. R90000\nG0 X10. Y0.\n",
            &md,
            &crate::tools::ToolTable::builtin(),
        )
        .unwrap();
        near(b[2].motion.unwrap().end, [0.0, 10.0, 0.0]);
        // A circle in G18 under a G17 rotation would leave its plane.
        let a = run(
            "fanuc",
            "G17 G0 X0. Y0. Z0.\nG68 X0. Y0. R90.\nG18 G2 X10. Z0. I5. K0. F100.\n",
        )
        .unwrap_err();
        assert_eq!(a.code, AlarmCode::NotSupported);
    }

    #[test]
    fn holes_of_a_cycle_turn_with_the_frame() {
        // G68 R90 about the zero: the hole at X10 is drilled at Y10; G91 K2 steps turn too.
        let b = blocks("G0 X0. Y0. Z10.\nG68 X0. Y0. R90.\nG91 G99 G81 X10. Z-7. R-8. K2 F100.\n");
        let holes: Vec<[f64; 3]> = b
            .iter()
            .filter_map(|b| b.motion)
            .filter(|m| m.kind == MotionKind::Linear)
            .map(|m| m.end)
            .collect();
        near(holes[0], [0.0, 10.0, -5.0]);
        near(holes[1], [0.0, 20.0, -5.0]);
    }

    #[test]
    fn scaling_scales_the_contour_about_its_centre() {
        // G51 P2000 (factor 2) about (0, 0): X10 Y5 → (20, 10); an arc of radius 5 becomes 10.
        let b = blocks(
            "G0 X0. Y0.\nG51 X0. Y0. P2000\nG1 X10. Y0. F100.\nG3 X0. Y10. R10.\nG50 G0 X0.\n",
        );
        let m: Vec<_> = b.iter().filter_map(|b| b.motion).collect();
        near(m[1].end, [20.0, 0.0, 0.0]);
        near(m[2].end, [0.0, 20.0, 0.0]);
        near(m[2].center, [0.0, 0.0, 0.0]);
        let a = run("fanuc", "G51 I2000 J1000 X0. Y0.\nG2 X10. Y0. R5. F100.\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::NotSupported);
    }

    #[test]
    fn a_mirror_turns_arcs_and_the_compensation_side() {
        // Mirror about X10: X15 → 5; G02 becomes G03; G41 becomes G42.
        let b = blocks(
            "G0 X0. Y0.\nG51.1 X10.\nG41 D1 G1 X15. Y0. F100.\nG2 X20. Y5. R5.\nG40 G1 X20. Y20.\nG50.1 X0.\n",
        );
        let m: Vec<_> = b.iter().filter_map(|b| b.motion).collect();
        near(m[1].end, [5.0, 0.0, 0.0]);
        assert_eq!(b[2].modal.trc, TrcSide::Right);
        assert_eq!(m[2].kind, MotionKind::ArcCcw);
        near(m[2].end, [0.0, 5.0, 0.0]);
        let a = run("fanuc", "G0 X0. Y0.\nG41 D1 G1 X10. F100.\nG68 R30.\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::ForbiddenWithTrc);
    }
}
