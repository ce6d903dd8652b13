//! Tapping (Cycles, "CYCLE84 tapping without compensating chuck", "CYCLE840 tapping with
//! compensating chuck"): in at the feed the lead and the speed make, dwell, the spindle
//! reversed, out to the safety plane, rapid to the retraction plane, the spindle as SDAC
//! says.

use super::super::super::block::SpindleDir;
use super::super::super::build::Step;
use super::super::super::fault::{fault, R};
use super::{CycleName, CycleRun, Hole, Params, DTB};
use crate::alarm::AlarmCode;

/// Metric coarse threads (ISO 261): the lead of each size MPIT names.
const COARSE: &[(f64, f64)] = &[
    (3.0, 0.5),
    (4.0, 0.7),
    (5.0, 0.8),
    (6.0, 1.0),
    (8.0, 1.25),
    (10.0, 1.5),
    (12.0, 1.75),
    (14.0, 2.0),
    (16.0, 2.0),
    (18.0, 2.5),
    (20.0, 2.5),
    (22.0, 2.5),
    (24.0, 3.0),
    (27.0, 3.0),
    (30.0, 3.5),
    (33.0, 3.5),
    (36.0, 4.0),
    (39.0, 4.0),
    (42.0, 4.5),
    (45.0, 4.5),
    (48.0, 5.0),
];

/// Where each cycle keeps SDAC, MPIT, PIT and its spindle speeds (SST, SST1).
struct Layout {
    sdac: usize,
    mpit: usize,
    pit: usize,
    speeds: Option<(usize, usize)>,
}

fn layout(name: CycleName) -> Layout {
    if name == CycleName::Tap84 {
        Layout {
            sdac: 6,
            mpit: 7,
            pit: 8,
            speeds: Some((10, 11)),
        }
    } else {
        Layout {
            sdac: 7,
            mpit: 9,
            pit: 10,
            speeds: None,
        }
    }
}

/// CYCLE840's direction for the retraction (0: the spindle reversed automatically).
const SDR: usize = 6;

/// The thread's lead (mm, signed: negative is left-hand) from MPIT or PIT; `None` where
/// neither is given.
fn lead(h: &Hole, l: &Layout) -> R<Option<f64>> {
    pitch(&h.p, l.mpit, l.pit, h.unit)
}

/// A lead from the metric size at parameter `mpit` or the pitch at `pit` (program units
/// times `unit`), which must agree where both are given; `None` where neither is.
pub(super) fn pitch(p: &Params, mpit: usize, pit: usize, unit: f64) -> R<Option<f64>> {
    let (size, lead) = (p.get(mpit), p.get(pit) * unit);
    let from_size = if size != 0.0 {
        let row = COARSE.iter().find(|c| c.0 == size.abs()).ok_or_else(|| {
            fault(
                AlarmCode::CycleParameter,
                p.at(mpit),
                format!("MPIT={size}: a metric coarse thread size 3 … 48"),
            )
        })?;
        Some(row.1 * size.signum())
    } else {
        None
    };
    match (from_size, lead) {
        (Some(a), v) if v != 0.0 && (a - v).abs() > 1e-9 => Err(fault(
            AlarmCode::CycleParameter,
            p.at(pit),
            format!("PIT={v} contradicts MPIT (lead {a})"),
        )),
        (Some(a), _) => Ok(Some(a)),
        (None, v) if v != 0.0 => Ok(Some(v)),
        _ => Ok(None),
    }
}

/// The feed of a tapping move at `speed` for `lead`: the lead per revolution under G95,
/// lead × speed per minute otherwise.
fn tap_feed(h: &Hole, lead: f64, speed: f64) -> R<f64> {
    if h.per_rev {
        return Ok(lead.abs());
    }
    if speed <= 0.0 {
        return Err(fault(
            AlarmCode::CycleParameter,
            h.p.call,
            format!("{} needs the spindle speed S (or SST)", h.name.text()),
        ));
    }
    Ok(lead.abs() * speed)
}

/// CYCLE84 and CYCLE840: one pass.
pub(super) fn tap(r: &mut CycleRun) -> R<u64> {
    let h = r.hole;
    let l = layout(h.name);
    let lead = lead(&h, &l)?;
    let (sst, sst1) = match l.speeds {
        Some((a, b)) if h.p.given(a) => (
            h.p.get(a),
            if h.p.given(b) { h.p.get(b) } else { h.p.get(a) },
        ),
        _ => (h.speed, h.speed),
    };
    let (feed_in, feed_out) = match lead {
        Some(p) => (tap_feed(&h, p, sst)?, tap_feed(&h, p, sst1)?),
        None if h.name == CycleName::Tap840 => (super::feed_needed(&h)?, h.feed),
        None => {
            return Err(fault(
                AlarmCode::CycleParameter,
                h.p.call,
                "CYCLE84 needs the thread's lead: MPIT or PIT",
            ))
        }
    };
    let left = lead.is_some_and(|p| p < 0.0)
        || (lead.is_none() && h.spindle == SpindleDir::CounterClockwise);
    let (ahead, back) = if left {
        (SpindleDir::CounterClockwise, SpindleDir::Clockwise)
    } else {
        (SpindleDir::Clockwise, SpindleDir::CounterClockwise)
    };
    r.along(h.safety, None);
    speed(r, sst);
    r.push(Step::Spindle(ahead));
    r.along(h.bottom, Some(feed_in));
    if let Some(s) = h.dwell(DTB)? {
        r.push(Step::Dwell(s));
    }
    r.push(Step::Spindle(reverse_for(r, back)?));
    speed(r, sst1);
    r.along(h.safety, Some(feed_out));
    r.along(h.rtp, None);
    r.spindle_after(l.sdac)?;
    speed(r, h.speed);
    Ok(1)
}

/// The spindle's speed to `s` where it is not already.
fn speed(r: &mut CycleRun, s: f64) {
    if s != r.speed_now {
        r.speed_now = s;
        r.push(Step::Speed(s));
    }
}

/// CYCLE840's retraction direction (SDR; 0: reversed), CYCLE84's reversal.
fn reverse_for(r: &CycleRun, back: SpindleDir) -> R<SpindleDir> {
    if r.hole.name != CycleName::Tap840 {
        return Ok(back);
    }
    Ok(r.spindle_code(SDR)?.unwrap_or(back))
}
