//! Contour violation (840C 11.12, alarm 3021).
//!
//! The seed's rule: the equidistants of elements 1 and 3 meet at P; if the perpendicular L
//! from element 2 to P is longer than R, the tool cannot cut element 2 without cutting into 1
//! or 3. softnc checks the same thing where it shows: element 2's compensated path runs from
//! its intersection with 1's equidistant to its intersection with 3's. When L > R these two
//! points have swapped places along element 2 — the trimmed equidistant runs backwards. So
//! the check is "does the trimmed element still run forwards?", for lines and arcs alike
//! (the seed's special case "intermediate block < compensation value").

use super::geom::{Elem, V2};

/// A line from `a` to `b` whose compensated path now runs from `start` to `end`: true if it
/// runs backwards by more than 1e-7 mm.
pub fn line_reverses(a: V2, b: V2, start: V2, end: V2) -> bool {
    // (end − start)·(b − a) < −1e-7 |b − a|, without a square root.
    let back = (end - start).dot(b - a);
    back < 0.0 && back * back > 1e-14 * (b - a).dot(b - a)
}

/// How far an arc's compensated path turns once its ends are trimmed or lengthened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ArcTravel {
    /// Both ends stayed on their radius: the programmed sweep.
    Programmed,
    /// An end moved: the total sweep (may exceed 2π when a corner lengthened the arc, 11.14).
    Changed(f64),
    /// The trimmed arc runs backwards: contour violation.
    Reversed,
}

/// The programmed arc `prog` (start `a`, end `b`, centre `c`) now runs from `start` to `end`.
pub fn arc_travel(prog: &Elem, start: V2, end: V2) -> ArcTravel {
    let Elem::Arc { a, b, c, ccw } = *prog else {
        return ArcTravel::Programmed;
    };
    // The angle an end moved along the arc, as (sin, cos)·r²; untrimmed ends lie on their
    // radius (sin ≈ 0, cos > 0) and need no atan2.
    let moved = |from: V2, to: V2| {
        let (u, v) = (from - c, to - c);
        let y = u.cross(v);
        (if ccw { y } else { -y }, u.dot(v))
    };
    let (y0, x0) = moved(a, start);
    let (y1, x1) = moved(b, end);
    let on_radius = |y: f64, x: f64| x > 0.0 && y.abs() <= 1e-12 * x;
    if on_radius(y0, x0) && on_radius(y1, x1) {
        return ArcTravel::Programmed;
    }
    // Angle travelled: the programmed sweep, less what the start lost, plus what the end gained.
    let total = prog.sweep() + libm::atan2(y1, x1) - libm::atan2(y0, x0);
    if total < -1e-9 {
        ArcTravel::Reversed
    } else {
        ArcTravel::Changed(total)
    }
}
