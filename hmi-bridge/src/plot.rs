//! What the page plots: the programmed contour (from the interpreter) and the compensated
//! tool-centre path (from preparation, with the kernel's current tool table), as polylines
//! in the program's plane, arcs sampled finely enough to look round.

use nc_kernel::geometry::Curve;
use nc_kernel::Prepared;
use nc_kernel::{Interpreter, MachineData, Preparation, ToolOffset, ToolTable};
use nc_kernel::{MotionKind, Plane};
use softnc_protocol::ToolTableMsg;

/// Points kept at most per picture: longer programs are thinned.
const MAX_POINTS: usize = 100_000;

#[derive(Debug, Default, serde::Serialize)]
pub struct Plot {
    /// Abscissa and ordinate of the plane: "X", "Y" (G17), "Z", "X" (G18), "Y", "Z" (G19).
    pub axes: [&'static str; 2],
    /// The same as indices into a position (X 0, Y 1, Z 2): the page draws the actual
    /// position with them.
    pub index: [usize; 2],
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

/// Names of the axes by index.
const AXES: [&str; 3] = ["X", "Y", "Z"];

/// The picture is drawn in the plane of the program's first feed move (where the contour
/// is: a turned part in G18 is a Z/X picture); moves in other planes are drawn projected
/// onto it.
pub fn plot(name: &str, source: &str, md: &MachineData, tools: &ToolTable) -> Plot {
    let plane = contour_plane(name, source, md, tools);
    let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
    let mut out = Plot {
        axes: [AXES[a], AXES[o]],
        index: [a, o],
        ..Default::default()
    };
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
                out.alarm = Some(e.render(source));
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

/// The plane of the first move at feed, else the one the program starts in.
fn contour_plane(name: &str, source: &str, md: &MachineData, tools: &ToolTable) -> Plane {
    let mut interp = Interpreter::new(name, source, md, tools);
    let start = interp.state().plane;
    while let Ok(Some(b)) = interp.next_block() {
        if b.motion
            .as_ref()
            .is_some_and(|m| m.kind != MotionKind::Rapid)
        {
            return b.modal.plane;
        }
    }
    start
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turned_part_is_drawn_in_its_zx_plane() {
        // G18: Z is the abscissa, X the ordinate (840C machine data: X as a radius value).
        // D1 has radius 10 in the built-in table; G42 on the outside of the part while
        // turning towards the chuck puts the tool centre 10 mm above the contour in X.
        let text = "N10 G18 G90 G0 X50 Z10 D1\nN20 G1 G42 X20 Z0 F100\nN30 Z-10\nN40 X30 Z-20\nN50 G40 G0 X50 Z10\nM30\n";
        let md = MachineData::load(None, &[]).unwrap();
        let p = plot("t.mpf", text, &md, &ToolTable::builtin());
        assert_eq!((p.axes, p.index), (["Z", "X"], [2, 0]));
        assert!(p.alarm.is_none(), "{:?}", p.alarm);
        assert_eq!(
            p.programmed,
            vec![vec![
                [10.0, 50.0],
                [0.0, 20.0],
                [-10.0, 20.0],
                [-20.0, 30.0]
            ]]
        );
        // Selection straight to N30's normal position (0, 30); N30's equidistant at X 30 up
        // to the inner corner with N40 (135°): Z −10 + 10·tan 22.5°; N40's end point moved
        // 10 mm along its right-hand normal (1, 1)/√2. The G0 deselection is not drawn.
        let h = 10.0 / 2f64.sqrt();
        let want = [
            [10.0, 50.0],
            [0.0, 30.0],
            [-10.0 + 10.0 * (std::f64::consts::PI / 8.0).tan(), 30.0],
            [-20.0 + h, 30.0 + h],
        ];
        assert_eq!(p.path.len(), 1);
        assert_eq!(p.path[0].len(), want.len());
        for (got, want) in p.path[0].iter().zip(want) {
            assert!((got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9);
        }
    }
}
