//! Tapping (Fanuc 0i-MF, G84 and G74): feed in with the spindle turning forward (G84: M3,
//! G74: M4), dwell P, reverse the spindle, feed out to the R point, turn it forward again.

use super::super::super::block::SpindleDir;
use super::super::expand::Step;
use super::{CycleKind, Drilling};

fn forward(kind: CycleKind) -> (SpindleDir, SpindleDir) {
    if kind == CycleKind::LeftTap {
        (SpindleDir::CounterClockwise, SpindleDir::Clockwise)
    } else {
        (SpindleDir::Clockwise, SpindleDir::CounterClockwise)
    }
}

pub(super) fn machine(d: &mut Drilling) -> bool {
    let h = d.hole;
    let (_, reverse) = forward(h.kind);
    d.along(h.bottom, false);
    if h.dwell > 0.0 {
        d.push(Step::Dwell(h.dwell));
    }
    d.push(Step::Spindle(reverse));
    true
}

pub(super) fn retract(d: &mut Drilling) {
    let h = d.hole;
    let (ahead, _) = forward(h.kind);
    d.along(h.r, false);
    d.push(Step::Spindle(ahead));
    d.along(h.return_level(), true);
}
