//! Reference point return (Fanuc 0i-MF, G28 and G30): the axes written go at rapid to the
//! intermediate point the words give, then to the reference position of machine data
//! (`axes.<A>.reference_positions`: the first for G28, P2…P4 for G30). The reference is a
//! machine position of the spindle: with a tool length offset in force, the programmed
//! point goes to the reference minus the length, so that the spindle stands on it.

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::Words;
use super::expand::{Expansion, Step};
use crate::alarm::AlarmCode;
use crate::dialect::GName;

impl Interpreter<'_> {
    /// Step 8 of a G28/G30 block (`code`): the two moves.
    pub(super) fn reference_return(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        code: u16,
        second: bool,
        block_col: usize,
    ) -> R<()> {
        if new.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                block_col,
                format!(
                    "{} cannot run while tool radius compensation is active",
                    GName(code)
                ),
            ));
        }
        if self.coords.frame.active() {
            return Err(fault(
                AlarmCode::NotSupported,
                block_col,
                format!("{} under a frame (mirror, scaling, rotation)", GName(code)),
            ));
        }
        if w.axis.iter().chain(&w.additional).all(Option::is_none) {
            return Err(fault(
                AlarmCode::MissingValue,
                block_col,
                format!("{} needs the axes that return", GName(code)),
            ));
        }
        let k = if second { self.reference_number(w)? } else { 0 };
        let mid = self.end_point(w, new, self.cur)?;
        let mut reference = mid;
        let normal = new.plane.normal as usize;
        for (i, a) in w.axis.iter().enumerate() {
            if a.is_some() {
                let r = self
                    .md
                    .axes
                    .get(i)
                    .map_or(0.0, |ax| ax.reference_positions[k]);
                reference[i] = r - if i == normal { new.length } else { 0.0 };
            }
        }
        let (mid_axes, reference_axes) = self.additional_reference(w, new, k)?;
        self.expansion = Some(Expansion::of(&[
            Step::Move {
                to: mid,
                rapid: true,
                axes: Some(mid_axes),
                feed: None,
            },
            Step::Move {
                to: reference,
                rapid: true,
                axes: Some(reference_axes),
                feed: None,
            },
        ]));
        self.expand_first(new);
        Ok(())
    }

    /// The additional axes written (A, C …): their intermediate point and reference `k`
    /// (a modulo axis the way its machine data says, within the turn).
    fn additional_reference(
        &self,
        w: &Words,
        new: &ModalState,
        k: usize,
    ) -> R<(
        [f64; crate::machine_data::ADDITIONAL],
        [f64; crate::machine_data::ADDITIONAL],
    )> {
        let mid = self.additional_end(w, new)?;
        let mut reference = mid;
        for (j, a) in w.additional.iter().enumerate() {
            if let (Some(_), Some(ax)) = (a, self.md.axes.get(j + 3)) {
                reference[j] = ax.absolute_target(mid[j], ax.reference_positions[k]);
            }
        }
        Ok((mid, reference))
    }

    /// G30 P2…P4 (P2 if not written): the index into the reference positions.
    fn reference_number(&self, w: &Words) -> R<usize> {
        match w.p {
            None => Ok(1),
            Some(p) if matches!(p.value, 2.0 | 3.0 | 4.0) => Ok(p.value as usize - 1),
            Some(p) => Err(fault(
                AlarmCode::BadNumber,
                p.at,
                format!("P{} is not a reference position (P2, P3 or P4)", p.value),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    fn ends(md: &MachineData, src: &str) -> Vec<[f64; 3]> {
        crate::frontend::interpret("r.nc", src, md, &ToolTable::builtin())
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion.map(|m| m.end))
            .collect()
    }

    #[test]
    fn g28_goes_through_the_intermediate_point_to_the_reference() {
        let md = MachineData::load(
            None,
            &[
                "dialect=fanuc".into(),
                "axes.Z.reference_positions=[400.0, 300.0, 0.0, 0.0]".into(),
            ],
        )
        .unwrap();
        // G91 G28 Z0: the intermediate point is where Z is; then Z to 400. X stays.
        let e = ends(&md, "G90 G0 X10. Y5. Z20.\nG91 G28 Z0.\n");
        assert_eq!(e[1..], [[10.0, 5.0, 20.0], [10.0, 5.0, 400.0]]);
        // G90 G28 X0 Y0: through the work's X0 Y0 (G54 zero) to the machine's reference 0.
        let e = ends(&md, "G90 G0 X10. Y5. Z20.\nG28 X0. Y0.\n");
        assert_eq!(e[1..], [[0.0, 0.0, 20.0], [0.0, 0.0, 20.0]]);
        // G30 P3 is the third reference; under G43 H1 the tool tip stays the length below it.
        let (_, length, _) = ToolTable::builtin().resolve(None, 1).unwrap();
        let e = ends(&md, "G0 G43 H1 Z50.\nG91 G30 P3 Z0.\n");
        assert_eq!(e[2], [0.0, 0.0, -length]);
        let a = crate::frontend::interpret("r.nc", "G30 P5 Z0.\n", &md, &ToolTable::builtin())
            .unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::BadNumber, 5));
    }

    #[test]
    fn rotary_axes_return_too_the_modulo_one_the_short_way() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-5axis.toml");
        let md = MachineData::load(Some(std::path::Path::new(path)), &[]).unwrap();
        let b = crate::frontend::interpret(
            "r.nc",
            "G90 G0 X10. Y5. Z20. A-30. C270.\nG91 G28 A0. C0.\n",
            &md,
            &ToolTable::builtin(),
        )
        .unwrap();
        // A (slot 3 of U V W A B C) and C (slot 5): the intermediate point is where they
        // stand, so the second move takes them: A to 0; C, at 270 reached the short way as
        // −90, turns the 90° on to 0.
        let m = b[2].axes.expect("the axes move");
        assert_eq!((m.from[3], m.to[3]), (-30.0, 0.0));
        assert_eq!((m.from[5], m.to[5]), (-90.0, 0.0));
        assert!(b[1].axes.is_none());
        assert_eq!(b[2].motion.unwrap().end, [10.0, 5.0, 20.0]);
    }

    #[test]
    fn g28_needs_axes_and_no_compensation() {
        let a = run("fanuc", "G28\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::MissingValue);
        let a = run("fanuc", "G0 X0. Y0.\nG41 D1 G1 X10. F100.\nG28 Z0.\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::ForbiddenWithTrc);
    }
}
