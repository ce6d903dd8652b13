//! Drilling (Cycles, "CYCLE81 drilling, centring", "CYCLE82 drilling, counterboring",
//! "CYCLE83 deep-hole drilling"): rapid to the safety plane, feed to the depth (CYCLE83 in
//! infeeds that break or remove the chips), rapid out to the retraction plane.

use super::super::super::build::Step;
use super::super::super::fault::{fault, R};
use super::{feed_needed, CycleName, CycleRun, DTB};
use crate::alarm::AlarmCode;

// CYCLE83's own parameters after RTP RFP SDIS DP DPR.
const FDEP: usize = 5;
const FDPR: usize = 6;
const DAM: usize = 7;
const DTB83: usize = 8;
const DTS: usize = 9;
const FRF: usize = 10;
const VARI: usize = 11;
const MDEP: usize = 13;
const VRT: usize = 14;
const DTD: usize = 15;
const DIS1: usize = 16;

/// CYCLE81 and CYCLE82 (a dwell DTB at the depth): one pass.
pub(super) fn drill(r: &mut CycleRun) -> R<u64> {
    let h = r.hole;
    let feed = feed_needed(&h)?;
    r.along(h.safety, None);
    r.along(h.bottom, Some(feed));
    if h.name == CycleName::Drill82 {
        if let Some(s) = h.dwell(DTB)? {
            r.push(Step::Dwell(s));
        }
    }
    r.along(h.rtp, None);
    Ok(1)
}

/// CYCLE83's infeeds: how deep the tool has gone below the reference plane and the next
/// infeed's length.
#[derive(Clone, Copy, Debug)]
pub struct Deep {
    plan: Plan,
    reached: f64,
    infeed: f64,
    first: bool,
}

/// The constant infeed data of a CYCLE83 call, read once.
#[derive(Clone, Copy, Debug)]
struct Plan {
    total: f64,
    first: f64,
    dam: f64,
    min: f64,
}

fn plan(r: &CycleRun) -> R<Plan> {
    let h = &r.hole;
    let total = h.depth_of(h.bottom);
    // FDPR (relative to RFP) wins over FDEP, as DPR does over DP; neither: one infeed.
    let first = if h.p.given(FDPR) {
        h.p.get(FDPR).abs() * h.unit
    } else if h.p.given(FDEP) {
        h.depth_of(h.map(h.p.get(FDEP) * h.unit))
    } else {
        total
    };
    if first <= 0.0 {
        return Err(fault(
            AlarmCode::CycleParameter,
            h.p.at(if h.p.given(FDPR) { FDPR } else { FDEP }),
            "the first drilling depth lies above the reference plane",
        ));
    }
    let dam = h.p.get(DAM) * h.unit;
    if dam < 0.0 {
        return Err(fault(
            AlarmCode::CycleParameter,
            h.p.at(DAM),
            "a negative degression DAM (a percentage) is not supported",
        ));
    }
    Ok(Plan {
        total,
        first: first.min(total),
        dam,
        min: h.p.get(MDEP).abs() * h.unit,
    })
}

/// The infeed after one of `last` (Cycles, CYCLE83 DAM): less by the degression, not below
/// it nor below the minimum depth _MDEP.
fn next_infeed(p: &Plan, last: f64) -> f64 {
    if p.dam > 0.0 {
        (last - p.dam).max(p.dam).max(p.min)
    } else {
        last.max(p.min)
    }
}

/// How many infeeds the plan makes (bounded: a plan beyond `cap` answers `cap + 1`).
fn infeeds(p: &Plan, cap: u64) -> u64 {
    let (mut reached, mut infeed, mut n) = (0.0, p.first, 0u64);
    while reached < p.total && n <= cap {
        reached = (reached + infeed).min(p.total);
        infeed = next_infeed(p, infeed);
        n += 1;
    }
    n
}

/// CYCLE83: to the safety plane, then the infeeds stream from [`infeed`].
pub(super) fn deep_hole(r: &mut CycleRun) -> R<u64> {
    let h = r.hole;
    feed_needed(&h)?;
    let vari = h.p.get(VARI);
    if vari != 0.0 && vari != 1.0 {
        return Err(fault(
            AlarmCode::CycleParameter,
            h.p.at(VARI),
            format!("VARI={vari}: 0 (chip breaking) or 1 (chip removal)"),
        ));
    }
    let frf = h.p.get(FRF);
    if !(frf == 0.0 || (0.001..=1.0).contains(&frf)) {
        return Err(fault(
            AlarmCode::CycleParameter,
            h.p.at(FRF),
            format!("feed factor FRF={frf}: 0.001 … 1"),
        ));
    }
    // Every dwell is read here, where a bad one can still be an alarm.
    for k in [DTB83, DTS, DTD] {
        h.dwell(k)?;
    }
    let p = plan(r)?;
    // The count is only a bound for the loop budget: a plan of tiny infeeds stops there.
    let n = infeeds(&p, 1 << 32);
    r.along(h.safety, None);
    r.deep = Some(Deep {
        plan: p,
        reached: 0.0,
        infeed: p.first,
        first: true,
    });
    Ok(n)
}

/// One infeed of CYCLE83 into the queue; false after the last (with the retraction).
pub(super) fn infeed(r: &mut CycleRun, d: &mut Deep) -> bool {
    let (h, p) = (r.hole, d.plan);
    let frf = if h.p.given(FRF) { h.p.get(FRF) } else { 1.0 };
    let feed = if d.first { h.feed * frf } else { h.feed };
    let removal = h.p.get(VARI) == 1.0;
    if removal && !d.first {
        // Chip removal: back down at rapid to the anticipation distance above the depth.
        let lead = anticipation(r, p.total);
        r.along(h.level((d.reached - lead).max(0.0)), None);
    }
    d.reached = (d.reached + d.infeed).min(p.total);
    d.infeed = next_infeed(&p, d.infeed);
    d.first = false;
    r.along(h.level(d.reached), Some(feed));
    if d.reached >= p.total {
        if let Some(s) = dwell(r, DTD).or(dwell(r, DTB83)) {
            r.push(Step::Dwell(s));
        }
        r.along(h.rtp, None);
        return false;
    }
    if let Some(s) = dwell(r, DTB83) {
        r.push(Step::Dwell(s));
    }
    if removal {
        r.along(h.safety, None);
        if let Some(s) = dwell(r, DTS) {
            r.push(Step::Dwell(s));
        }
    } else {
        // Chip breaking: back by _VRT (1 mm where not given) at the feed.
        let back = if h.p.given(VRT) {
            h.p.get(VRT).abs() * h.unit
        } else {
            1.0
        };
        r.along(h.level((d.reached - back).max(0.0)), Some(h.feed));
    }
    true
}

/// A dwell parameter checked at the call (see [`deep_hole`]).
fn dwell(r: &CycleRun, k: usize) -> Option<f64> {
    r.hole.dwell(k).ok().flatten()
}

/// Chip removal's anticipation distance: _DIS1, else 0.6 mm up to a 30 mm deep hole and
/// depth / 50 beyond it, at most 7 mm (Cycles, CYCLE83).
fn anticipation(r: &CycleRun, total: f64) -> f64 {
    let h = &r.hole;
    if h.p.given(DIS1) {
        return h.p.get(DIS1).abs() * h.unit;
    }
    if total <= 30.0 {
        0.6
    } else {
        (total / 50.0).min(7.0)
    }
}
