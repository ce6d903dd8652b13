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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trc::geom::v2;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, FRAC_PI_6, TAU};

    /// A line from (0,0) to (10,0) whose equidistant y = 2 was trimmed: forwards from x = 2
    /// to x = 8, backwards from 8 to 2; back by 1e-8 mm is within the 1e-7 mm allowance
    /// (the test compares (1e-8·10)² = 1e-14 with 1e-14·10² = 1e-12), by 1e-6 mm it is not;
    /// a move across the line does not run backwards.
    #[test]
    fn a_trimmed_line_reverses_when_its_ends_swap_places() {
        let (a, b) = (v2(0.0, 0.0), v2(10.0, 0.0));
        assert!(!line_reverses(a, b, v2(2.0, 2.0), v2(8.0, 2.0)));
        assert!(line_reverses(a, b, v2(8.0, 2.0), v2(2.0, 2.0)));
        assert!(!line_reverses(a, b, v2(5.0, 2.0), v2(5.0 - 1e-8, 2.0)));
        assert!(line_reverses(a, b, v2(5.0, 2.0), v2(5.0 - 1e-6, 2.0)));
        assert!(!line_reverses(a, b, v2(5.0, 2.0), v2(5.0, -2.0)));
    }

    /// The point at `deg` degrees on the circle of radius `r` about the origin.
    fn at(r: f64, deg: f64) -> V2 {
        let t = deg.to_radians();
        v2(r * libm::cos(t), r * libm::sin(t))
    }

    fn changed(t: ArcTravel) -> f64 {
        match t {
            ArcTravel::Changed(s) => s,
            other => panic!("{other:?}"),
        }
    }

    /// A counter-clockwise quarter circle r 10 from 0° to 90° about the origin, and its
    /// equidistant at r 12 cut at other angles.
    #[test]
    fn an_arc_turns_its_programmed_sweep_less_what_the_start_lost_plus_what_the_end_gained() {
        let q = Elem::Arc {
            a: at(10.0, 0.0),
            b: at(10.0, 90.0),
            c: v2(0.0, 0.0),
            ccw: true,
        };
        // Ends on their radii (at 0° and 90°, r 12): the programmed sweep, no atan2.
        assert_eq!(
            arc_travel(&q, at(12.0, 0.0), at(12.0, 90.0)),
            ArcTravel::Programmed
        );
        // Start trimmed to 30°: 90° − 30° = 60°.
        let s = changed(arc_travel(&q, at(12.0, 30.0), at(12.0, 90.0)));
        assert!((s - FRAC_PI_3).abs() < 1e-12, "{s}");
        // End lengthened to 120°: 90° + 30°.
        let s = changed(arc_travel(&q, at(12.0, 0.0), at(12.0, 120.0)));
        assert!((s - (FRAC_PI_2 + FRAC_PI_6)).abs() < 1e-12, "{s}");
        // Start trimmed to 60°, end to 30°: 90° − 60° − 60° = −30°, backwards (11.12).
        let t = arc_travel(&q, at(12.0, 60.0), at(12.0, 30.0));
        assert_eq!(t, ArcTravel::Reversed);
    }

    /// Clockwise, angles count the other way: the quarter from 90° down to 0°, its end
    /// lengthened to −30°, turns 90° + 30° = 120°.
    #[test]
    fn a_clockwise_arc_gains_where_its_end_moves_on_clockwise() {
        let q = Elem::Arc {
            a: at(10.0, 90.0),
            b: at(10.0, 0.0),
            c: v2(0.0, 0.0),
            ccw: false,
        };
        let s = changed(arc_travel(&q, at(10.0, 90.0), at(10.0, -30.0)));
        assert!((s - 2.0 * FRAC_PI_3).abs() < 1e-12, "{s}");
    }

    /// A full circle (start = end at 0°) runs as programmed while its ends stay; its end
    /// moved on to 30° makes it 360° + 30° (11.14: lengthened past a full turn); its start
    /// moved on to 30° leaves 330°.
    #[test]
    fn a_full_circle_keeps_its_turn_or_goes_past_it() {
        let full = Elem::Arc {
            a: at(10.0, 0.0),
            b: at(10.0, 0.0),
            c: v2(0.0, 0.0),
            ccw: true,
        };
        let t = arc_travel(&full, at(10.0, 0.0), at(10.0, 0.0));
        assert_eq!(t, ArcTravel::Programmed);
        let s = changed(arc_travel(&full, at(10.0, 0.0), at(10.0, 30.0)));
        assert!((s - (TAU + FRAC_PI_6)).abs() < 1e-12, "{s}");
        let s = changed(arc_travel(&full, at(10.0, 30.0), at(10.0, 0.0)));
        assert!((s - (TAU - FRAC_PI_6)).abs() < 1e-12, "{s}");
    }
}
