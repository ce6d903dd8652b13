//! What the page plots: the programmed contour (from the interpreter) and the compensated
//! tool-centre path (from preparation, with the kernel's current tool table), as polylines
//! in the program's plane, arcs sampled finely enough to look round.

use nc_kernel::frontend::block::MotionKind;
use nc_kernel::prep::Prepared;
use nc_kernel::segment::Curve;
use nc_kernel::{Interpreter, MachineData, Preparation, ToolOffset, ToolTable};
use softnc_protocol::ToolTableMsg;

/// Points kept at most per picture: longer programs are thinned.
const MAX_POINTS: usize = 100_000;

#[derive(Debug, Default, serde::Serialize)]
pub struct Plot {
    /// Abscissa and ordinate of the plane ("X", "Y").
    pub axes: [&'static str; 2],
    pub programmed: Vec<Vec<[f64; 2]>>,
    pub path: Vec<Vec<[f64; 2]>>,
    /// Preparation's first alarm, rendered (the path ends there).
    pub alarm: Option<String>,
}

/// The kernel's table as the preparation reads it.
pub fn table(m: &ToolTableMsg) -> ToolTable {
    ToolTable {
        offset: m
            .entries()
            .iter()
            .map(|e| ToolOffset {
                t: (e.t != 0).then_some(e.t),
                d: e.d,
                radius: e.radius,
                radius_wear: e.radius_wear,
                length: e.length,
                length_wear: e.length_wear,
                edge: None,
            })
            .collect(),
        ..Default::default()
    }
}

pub fn plot(name: &str, source: &str, md: &MachineData, tools: &ToolTable) -> Plot {
    let mut out = Plot {
        axes: ["X", "Y"],
        ..Default::default()
    };
    let (a, o) = (0usize, 1usize);
    let mut interp = Interpreter::new(name, source, md, tools);
    let mut line: Vec<[f64; 2]> = Vec::new();
    // Up to the first alarm: preparation below reports it.
    while let Ok(Some(b)) = interp.next_block() {
        let Some(m) = &b.motion else { continue };
        if m.kind == MotionKind::Rapid {
            flush(&mut out.programmed, &mut line);
            continue;
        }
        let p0 = [m.start[a], m.start[o]];
        if line.last() != Some(&p0) {
            flush(&mut out.programmed, &mut line);
            line.push(p0);
        }
        if m.kind.is_arc() {
            let c = [m.center[a], m.center[o]];
            let r = ((p0[0] - c[0]).powi(2) + (p0[1] - c[1]).powi(2)).sqrt();
            let t0 = (p0[1] - c[1]).atan2(p0[0] - c[0]);
            let t1 = (m.end[o] - c[1]).atan2(m.end[a] - c[0]);
            let ccw = m.kind == MotionKind::ArcCcw;
            let mut sweep = t1 - t0;
            if ccw && sweep <= 0.0 {
                sweep += std::f64::consts::TAU;
            } else if !ccw && sweep >= 0.0 {
                sweep -= std::f64::consts::TAU;
            }
            let n = arc_steps(r, sweep);
            for k in 1..n {
                let t = t0 + sweep * k as f64 / n as f64;
                line.push([c[0] + r * t.cos(), c[1] + r * t.sin()]);
            }
        }
        line.push([m.end[a], m.end[o]]);
    }
    flush(&mut out.programmed, &mut line);

    let mut prep = Preparation::new(name, source, md, tools);
    loop {
        let seg = match prep.next_item() {
            Ok(Some(Prepared::Segment(s))) => s,
            Ok(Some(_)) => continue,
            Ok(None) => break,
            Err(e) => {
                out.alarm = Some(nc_kernel::alarm::render(&e, source));
                break;
            }
        };
        if seg.rapid {
            flush(&mut out.path, &mut line);
            continue;
        }
        let Some(c) = Curve::new(&seg) else { continue };
        let p0 = [seg.from[a], seg.from[o]];
        if line.last() != Some(&p0) {
            flush(&mut out.path, &mut line);
            line.push(p0);
        }
        let n = match c {
            Curve::Line { .. } => 1,
            Curve::Arc { r0, dr, sweep, .. } => arc_steps(r0.max(r0 + dr), sweep),
        };
        for k in 1..=n {
            let p = c.point(k as f64 / n as f64);
            line.push([p[a], p[o]]);
        }
    }
    flush(&mut out.path, &mut line);
    thin(&mut out.programmed);
    thin(&mut out.path);
    out
}

/// Steps for an arc: chords of at most 2° and at most 1 mm.
fn arc_steps(r: f64, sweep: f64) -> usize {
    let by_angle = sweep.abs() / 2f64.to_radians();
    let by_length = (sweep.abs() * r).abs();
    (by_angle.max(by_length).ceil() as usize).clamp(2, 720)
}

fn flush(to: &mut Vec<Vec<[f64; 2]>>, line: &mut Vec<[f64; 2]>) {
    if line.len() >= 2 {
        to.push(std::mem::take(line));
    }
    line.clear();
}

/// Keeps every k-th point (and each line's ends) when there are too many.
fn thin(lines: &mut [Vec<[f64; 2]>]) {
    let total: usize = lines.iter().map(Vec::len).sum();
    if total <= MAX_POINTS {
        return;
    }
    let k = total.div_ceil(MAX_POINTS);
    for l in lines.iter_mut() {
        let last = l.len() - 1;
        let kept: Vec<[f64; 2]> = l
            .iter()
            .enumerate()
            .filter(|(i, _)| i % k == 0 || *i == last)
            .map(|(_, p)| *p)
            .collect();
        *l = kept;
    }
}
