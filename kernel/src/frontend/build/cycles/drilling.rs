//! Drilling (Fanuc 0i-MF, G81 G82 G73 G83): feed to the bottom in one go or in pecks of Q,
//! then rapid out to the return level.

use super::super::expand::Step;
use super::{CycleKind, Drilling};

/// Operations 3 and 4. A peck cycle makes one peck per call (false until the bottom).
pub(super) fn machine(d: &mut Drilling) -> bool {
    let h = d.hole;
    if matches!(h.kind, CycleKind::HighSpeedPeck | CycleKind::Peck) {
        return peck(d);
    }
    d.along(h.bottom, false);
    if h.kind == CycleKind::SpotDrill && h.dwell > 0.0 {
        d.push(Step::Dwell(h.dwell));
    }
    true
}

/// One peck: G73 retracts by the machine data's `peck_retract` and goes on from there;
/// G83 goes out to the R point and back down at rapid to `peck_clearance` above the depth
/// reached.
fn peck(d: &mut Drilling) -> bool {
    let h = d.hole;
    let total = (h.bottom - h.r).abs();
    let dir = h.dir();
    if h.kind == CycleKind::Peck && d.depth > 0.0 {
        d.along(h.r + dir * (d.depth - h.peck_clearance).max(0.0), true);
    }
    let next = (d.depth + h.q).min(total);
    d.along(h.r + dir * next, false);
    d.depth = next;
    if next >= total {
        return true;
    }
    match h.kind {
        CycleKind::HighSpeedPeck => d.along(h.r + dir * (next - h.peck_retract).max(0.0), true),
        _ => d.along(h.r, true),
    }
    false
}

/// Operations 5 and 6: rapid out to the return level.
pub(super) fn retract(d: &mut Drilling) {
    let level = d.hole.return_level();
    d.along(level, true);
}
