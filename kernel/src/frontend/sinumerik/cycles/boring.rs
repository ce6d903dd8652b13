//! Boring (Cycles, "CYCLE85 … CYCLE89"): in at the feed to the depth; then out at a feed
//! (CYCLE85, CYCLE89), lifted off the wall after an oriented stop (CYCLE86), or after a
//! programmed stop for the operator (CYCLE87, CYCLE88).

use super::super::super::block::{ProgramStop, SpindleDir};
use super::super::super::build::Step;
use super::super::super::fault::R;
use super::{feed_needed, CycleName, CycleRun, DTB};

/// CYCLE85: the feeds in and out.
const FFR: usize = 6;
const RFF: usize = 7;
/// CYCLE86: spindle direction after the cycle, the lift-off in abscissa, ordinate and
/// applicate.
const SDIR86: usize = 6;
const RPA: usize = 7;
const RPO: usize = 8;
const RPAP: usize = 9;
/// CYCLE87 has no dwell: its SDIR stands where the others keep DTB.
const SDIR87: usize = 5;
const SDIR88: usize = 6;

/// CYCLE85 … CYCLE89: one pass.
pub(super) fn bore(r: &mut CycleRun) -> R<u64> {
    let h = r.hole;
    let given = |k: usize| h.p.given(k).then(|| h.p.get(k) * h.unit);
    let feed_in = match h.name {
        CycleName::Bore85 => given(FFR).map_or_else(|| feed_needed(&h), Ok)?,
        _ => feed_needed(&h)?,
    };
    r.along(h.safety, None);
    r.along(h.bottom, Some(feed_in));
    if h.name != CycleName::Bore87 {
        if let Some(s) = h.dwell(DTB)? {
            r.push(Step::Dwell(s));
        }
    }
    match h.name {
        CycleName::Bore85 => {
            r.along(h.safety, Some(given(RFF).unwrap_or(feed_in)));
            r.along(h.rtp, None);
        }
        CycleName::Bore89 => {
            r.along(h.safety, Some(feed_in));
            r.along(h.rtp, None);
        }
        CycleName::Bore86 => lift_off(r)?,
        _ => {
            // CYCLE87, CYCLE88: M5, M0; after NC start out at rapid.
            r.push(Step::Spindle(SpindleDir::Stop));
            r.push(Step::Stop(ProgramStop::Stop));
            r.along(h.rtp, None);
            let sdir = if h.name == CycleName::Bore87 {
                SDIR87
            } else {
                SDIR88
            };
            r.spindle_after(sdir)?;
        }
    }
    Ok(1)
}

/// CYCLE86 at the depth: the spindle oriented (POSS), lifted off the wall by RPA RPO
/// RPAP at rapid, out to the retraction plane, the lift-off undone in the plane.
fn lift_off(r: &mut CycleRun) -> R<()> {
    let h = r.hole;
    r.push(Step::Spindle(SpindleDir::Orient));
    let (a, o) = (h.plane.abscissa as usize, h.plane.ordinate as usize);
    let mut off = [0.0; 3];
    off[a] += h.p.get(RPA) * h.unit;
    off[o] += h.p.get(RPO) * h.unit;
    off[h.n] += h.p.get(RPAP) * h.unit;
    let mut to = r.at;
    for (t, d) in to.iter_mut().zip(off) {
        *t += d;
    }
    r.go(to, None);
    r.along(h.rtp, None);
    let mut back = r.at;
    back[a] -= off[a];
    back[o] -= off[o];
    r.go(back, None);
    r.spindle_after(SDIR86)
}
