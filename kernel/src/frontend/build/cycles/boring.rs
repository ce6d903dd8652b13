//! Boring (Fanuc 0i-MF, G85 G86 G89 G76 G87): feed in; then out at feed (G85, G89 after a
//! dwell), at rapid with the spindle stopped (G86), or with the spindle oriented and the
//! tool shifted off the wall by Q (G76). Back boring (G87) enters from below: oriented and
//! shifted down to the R point, back on the axis, spindle on, feed up to Z.

use super::super::super::block::SpindleDir;
use super::super::expand::Step;
use super::{CycleKind, Drilling};

/// Back boring, operations 1–2 after the positioning: orient, shift, rapid down to R,
/// shift back, spindle on.
pub(super) fn back_bore_entry(d: &mut Drilling) {
    let h = d.hole;
    d.push(Step::Spindle(SpindleDir::Orient));
    d.shift(1.0);
    d.along(h.r, true);
    d.shift(-1.0);
    d.push(Step::Spindle(h.spindle));
}

pub(super) fn machine(d: &mut Drilling) -> bool {
    let h = d.hole;
    d.along(h.bottom, false);
    match h.kind {
        CycleKind::BoreDwell => d.push(Step::Dwell(h.dwell)),
        CycleKind::BoreSpindleStop => d.push(Step::Spindle(SpindleDir::Stop)),
        CycleKind::FineBore | CycleKind::BackBore => {
            if h.dwell > 0.0 {
                d.push(Step::Dwell(h.dwell));
            }
            d.push(Step::Spindle(SpindleDir::Orient));
            d.shift(1.0);
        }
        _ => {}
    }
    true
}

pub(super) fn retract(d: &mut Drilling) {
    let h = d.hole;
    match h.kind {
        CycleKind::Bore | CycleKind::BoreDwell => {
            d.along(h.r, false);
            d.along(h.return_level(), true);
        }
        CycleKind::BoreSpindleStop => {
            d.along(h.return_level(), true);
            d.push(Step::Spindle(h.spindle));
        }
        _ => {
            d.along(h.return_level(), true);
            d.shift(-1.0);
            d.push(Step::Spindle(h.spindle));
        }
    }
}
