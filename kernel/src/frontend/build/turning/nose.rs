//! Nose radius compensation in the roughing cycles G71–G73: G41/G42 written in the shape
//! (`N100 G42 G0 X…` … `N200 G40 X…`) make the passes cut against the shape as the
//! compensated tool sees it. The roughing moves are uncompensated blocks that describe the
//! tool tip P on the compensated path (the nose centre S on the equidistant at the nose
//! radius R, shifted by the cutting edge position's P − S), so the nose touches the
//! programmed shape (plus the allowances) at every pass's end and on the last run along it;
//! G70 then runs the shape with the compensation as programmed (docs/turning.md, "Nose
//! radius compensation in the cycles").

use super::super::super::block::*;
use super::super::super::fault::{fault, R};
use super::super::super::interpreter::Interpreter;
use super::contour::{Contour, Element};
use super::equidistant::{tip_path, Nose};
use crate::alarm::AlarmCode;
use crate::dialect::GEffect;

/// Where the shape's compensation is on: selected with element `on` on `side`, deselected
/// with element `off` (the shape's length: not in it).
struct Stretch {
    on: usize,
    side: TrcSide,
    off: usize,
}

impl Interpreter<'_> {
    /// The shape the roughing passes work on: as programmed, or under G41/G42 in it the tool
    /// tip's compensated path with the active offset's nose radius and cutting edge.
    pub(super) fn rough_shape(&mut self, contour: &Contour, new: &ModalState) -> R<Vec<Element>> {
        let Some(st) = self.compensated_stretch(contour)? else {
            return Ok(contour.elements.clone());
        };
        let nose = Nose {
            side: st.side,
            radius: new.radius.abs(),
            edge: new.edge,
            exchanged: false,
        };
        tip_path(&contour.elements, nose, st.on, st.off).map_err(|k| {
            let arc = contour.elements.get(k).is_some_and(|e| e.mode.is_arc());
            let (code, what) = match arc {
                true => (
                    AlarmCode::ArcRadiusTooSmall,
                    "the arc's radius is not larger than the nose radius on the nose's side",
                ),
                false => (
                    AlarmCode::ContourViolation,
                    "the element is shorter than the nose radius's trim at its corners",
                ),
            };
            let m = format!(
                "nose radius {} does not fit element {} of the shape: {what}, its equidistant turns inside out",
                nose.radius,
                k + 1
            );
            self.element_fault(contour, k, code, m)
        })
    }

    /// The one stretch of compensation in the shape: its first G41/G42 and the G40 after it;
    /// a second selection after that G40 is refused (one compensated stretch per shape).
    fn compensated_stretch(&mut self, contour: &Contour) -> R<Option<Stretch>> {
        let n = contour.elements.len();
        let mut found: Option<Stretch> = None;
        for &(i, side) in &contour.compensation {
            match (&mut found, side) {
                (None, TrcSide::Off) => {}
                (None, s) => {
                    found = Some(Stretch {
                        on: i,
                        side: s,
                        off: n,
                    })
                }
                (Some(st), TrcSide::Off) if st.off == n => st.off = i.max(st.on + 1).min(n),
                (Some(_), TrcSide::Off) => {}
                (Some(st), s) if st.off == n && s == st.side => {}
                (Some(_), _) => {
                    let m = "a roughing cycle's shape takes one compensated stretch (a selection and its deselection) in softnc".to_string();
                    return Err(self.element_fault(contour, i, AlarmCode::NotSupported, m));
                }
            }
        }
        if let Some(st) = &found {
            let arc = contour
                .elements
                .get(st.off)
                .is_some_and(|e| e.mode.is_arc());
            if arc {
                let codes = self.d.codes_of(&[
                    GEffect::Motion(MotionMode::Rapid),
                    GEffect::Motion(MotionMode::Linear),
                ]);
                let m = format!("the shape's compensation ends in a block that moves at {codes}");
                return Err(self.element_fault(contour, st.off, self.d.trc_not_linear, m));
            }
        }
        Ok(found.filter(|st| st.on < n))
    }

    /// A fault at the start of element `k`'s block (its line and column).
    fn element_fault(
        &mut self,
        contour: &Contour,
        k: usize,
        code: AlarmCode,
        m: String,
    ) -> Box<super::super::super::fault::Fault> {
        match contour
            .blocks
            .get(k.min(contour.blocks.len().saturating_sub(1)))
        {
            Some(&(pos, line, line_start)) => {
                let f = fault(code, pos, m);
                self.fault_at_line(f, line, line_start)
            }
            None => fault(code, 0usize, m),
        }
    }
}
