//! Chamfers and roundings between two moves, as plane geometry: the first move's end is the
//! virtual corner, where the second starts; a chamfer is the line between the two points at a
//! distance from that corner, one on each element; a rounding is the arc of a radius tangent
//! to both. Both elements are trimmed to the inserted one. Dialect-free: Fanuc ",C" ",R"
//! (0i-MF "Optional angle chamfering and corner rounding") and Sinumerik CHF=/RND= ask for
//! the same elements; the words are the dialect table's, the holding of the move until its
//! successor is known is in [`super::corner_blocks`].

pub use super::super::plane::V;
use super::super::plane::{add, cross, dist, dot, scale, sub, unit};

/// What a corner word asks for between two moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerKind {
    /// A line from the point at the size's distance before the corner to the one after it
    /// (Fanuc `,C`, Sinumerik CHR=: the leg).
    Chamfer,
    /// A chamfer whose own length is the size, its legs equal (Sinumerik CHF=, Fundamentals
    /// "Chamfer, rounding").
    ChamferLength,
    /// An arc of the size as radius, tangent to both elements.
    Round,
}

/// One contour element in the plane, in the direction of travel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Element {
    Line {
        from: V,
        to: V,
    },
    Arc {
        from: V,
        to: V,
        centre: V,
        ccw: bool,
    },
}

/// The two elements trimmed and the element between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cornered {
    /// The new end of the first element.
    pub first_end: V,
    /// The new start of the second element.
    pub second_start: V,
    /// The chamfer (a line) or the rounding (an arc) from `first_end` to `second_start`.
    pub insert: Element,
}

/// Why no corner element fits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CornerError {
    /// The chamfer or the rounding would take up a whole element, or more.
    TooLarge,
    /// No arc of the radius touches both elements (elements that turn back on themselves).
    NoRound,
}

/// Elements meeting at less than this angle (degrees) get no corner element: Fanuc 16i/0i
/// "Travel distance 0" (within ±1°, the chamfer or corner R block moves nothing).
pub const TANGENT_DEG: f64 = 1.0;

/// Lengths below this count as zero (mm).
const EPS: f64 = 1e-9;

/// The corner of `kind` and `size` between `first` and `second` (which starts where `first`
/// ends). `None` where there is nothing to insert: a size of 0, or elements that meet
/// tangentially (within [`TANGENT_DEG`]).
pub fn corner(
    first: Element,
    second: Element,
    kind: CornerKind,
    size: f64,
) -> Result<Option<Cornered>, CornerError> {
    let p = first.end();
    let (t1, t2) = (first.tangent_at(p), second.tangent_at(p));
    let turn = libm::atan2(cross(t1, t2), dot(t1, t2));
    if size <= 0.0 || turn.abs() <= TANGENT_DEG.to_radians() {
        return Ok(None);
    }
    match kind {
        CornerKind::Chamfer => chamfer(first, second, size).map(Some),
        CornerKind::ChamferLength => {
            chamfer(first, second, leg_for(first, second, size)?).map(Some)
        }
        CornerKind::Round => round(first, second, size, turn > 0.0).map(Some),
    }
}

/// The chamfer: on each element the point at the straight distance `c` from the corner (on
/// an arc the chord; Fanuc gives no rule for arcs, ISG TF5200 G301 takes the chord too).
fn chamfer(first: Element, second: Element, c: f64) -> Result<Cornered, CornerError> {
    let a = first.at_distance_from_end(c).ok_or(CornerError::TooLarge)?;
    let b = second
        .at_distance_from_start(c)
        .ok_or(CornerError::TooLarge)?;
    Ok(Cornered {
        first_end: a,
        second_start: b,
        insert: Element::Line { from: a, to: b },
    })
}

/// The leg that gives a chamfer of length `len`: on lines 2·leg·cos(turn / 2) = len; on arcs
/// found by bisection (the chamfer grows with its legs until an element is used up).
fn leg_for(first: Element, second: Element, len: f64) -> Result<f64, CornerError> {
    if let (Element::Line { .. }, Element::Line { .. }) = (first, second) {
        let p = first.end();
        let (t1, t2) = (first.tangent_at(p), second.tangent_at(p));
        let turn = libm::atan2(cross(t1, t2), dot(t1, t2));
        return Ok(len / (2.0 * libm::cos(turn / 2.0)));
    }
    let span = |d: f64| -> Option<f64> {
        Some(dist(
            first.at_distance_from_end(d)?,
            second.at_distance_from_start(d)?,
        ))
    };
    // Too short below `lo`; `hi` too long or past an element's end.
    let (mut lo, mut hi) = (0.0, len);
    while span(hi).is_some_and(|s| s < len) {
        lo = hi;
        hi *= 2.0;
        if hi > 1e9 {
            return Err(CornerError::TooLarge);
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        match span(mid) {
            Some(s) if s < len => lo = mid,
            _ => hi = mid,
        }
        if hi - lo <= 1e-12 * len.max(1.0) {
            break;
        }
    }
    match span(hi) {
        Some(s) if (s - len).abs() <= 1e-9 * len.max(1.0) => Ok(hi),
        _ => Err(CornerError::TooLarge),
    }
}

/// The rounding of radius `r`: its centre is where the two elements' parallels at distance
/// `r` on the inner side of the corner (left where the path turns left) meet, nearest to the
/// corner; it touches each element at the foot of the centre.
fn round(first: Element, second: Element, r: f64, left: bool) -> Result<Cornered, CornerError> {
    let p = first.end();
    let (o1, o2) = (first.offset(r, left), second.offset(r, left));
    let (o1, o2) = (
        o1.ok_or(CornerError::TooLarge)?,
        o2.ok_or(CornerError::TooLarge)?,
    );
    let centre = intersections(o1, o2)
        .into_iter()
        .min_by(|a, b| dist(*a, p).total_cmp(&dist(*b, p)))
        .ok_or(CornerError::NoRound)?;
    let a = first.foot(centre);
    let b = second.foot(centre);
    if !first.inside(a) || !second.inside(b) {
        return Err(CornerError::TooLarge);
    }
    Ok(Cornered {
        first_end: a,
        second_start: b,
        insert: Element::Arc {
            from: a,
            to: b,
            centre,
            ccw: left,
        },
    })
}

/// A line through `p` along the unit vector `d`, or a circle.
#[derive(Clone, Copy, Debug)]
pub enum Curve {
    Line { p: V, d: V },
    Circle { c: V, r: f64 },
}

impl Element {
    pub fn end(self) -> V {
        match self {
            Element::Line { to, .. } | Element::Arc { to, .. } => to,
        }
    }

    /// The unit tangent in the direction of travel at `q` (a point of the element).
    fn tangent_at(self, q: V) -> V {
        match self {
            Element::Line { from, to } => unit(sub(to, from)),
            Element::Arc { centre, ccw, .. } => {
                let r = unit(sub(q, centre));
                if ccw {
                    [-r[1], r[0]]
                } else {
                    [r[1], -r[0]]
                }
            }
        }
    }

    /// The element's parallel at distance `d` on its left (or right) side; `None` where an
    /// arc's parallel shrinks to nothing.
    fn offset(self, d: f64, left: bool) -> Option<Curve> {
        let side = if left { 1.0 } else { -1.0 };
        match self {
            Element::Line { from, to } => {
                let u = unit(sub(to, from));
                let n = [-u[1] * side * d, u[0] * side * d];
                Some(Curve::Line {
                    p: add(from, n),
                    d: u,
                })
            }
            Element::Arc {
                from, centre, ccw, ..
            } => {
                // The centre lies on the left of a counter-clockwise arc.
                let towards_centre = if ccw { side } else { -side };
                let r = dist(from, centre) - towards_centre * d;
                (r > EPS).then_some(Curve::Circle { c: centre, r })
            }
        }
    }

    /// The point of the element's line or circle nearest to `q`.
    fn foot(self, q: V) -> V {
        match self {
            Element::Line { from, to } => {
                let u = unit(sub(to, from));
                add(from, scale(u, dot(sub(q, from), u)))
            }
            Element::Arc { from, centre, .. } => {
                let r = dist(from, centre);
                add(centre, scale(unit(sub(q, centre)), r))
            }
        }
    }

    /// How far along the element `q` (a point of its line or circle) lies: a length on a
    /// line, an angle in the direction of travel on an arc; and the whole element's.
    fn along(self, q: V) -> (f64, f64) {
        match self {
            Element::Line { from, to } => {
                let u = unit(sub(to, from));
                (dot(sub(q, from), u), dist(from, to))
            }
            Element::Arc { from, to, .. } => (self.angle_to(q), self.sweep(from, to)),
        }
    }

    /// The angle from the start to `q` in the direction of travel, in [0, 2π).
    fn angle_to(self, q: V) -> f64 {
        let Element::Arc {
            from, centre, ccw, ..
        } = self
        else {
            return 0.0;
        };
        let (a, b) = (sub(from, centre), sub(q, centre));
        let mut t = libm::atan2(cross(a, b), dot(a, b));
        if !ccw {
            t = -t;
        }
        if t < 0.0 {
            t += std::f64::consts::TAU;
        }
        t
    }

    /// An arc's sweep from `from` to `to`: a full circle where they meet.
    fn sweep(self, from: V, to: V) -> f64 {
        if dist(from, to) <= EPS {
            std::f64::consts::TAU
        } else {
            self.angle_to(to)
        }
    }

    /// `q` lies on the element strictly between its ends: trimming there leaves both parts.
    fn inside(self, q: V) -> bool {
        let (at, whole) = self.along(q);
        let eps = match self {
            Element::Line { .. } => EPS,
            Element::Arc { .. } => 1e-12,
        };
        at > eps && at < whole - eps
    }

    /// The point of the element at the straight distance `c` before its end.
    fn at_distance_from_end(self, c: f64) -> Option<V> {
        let q = match self {
            Element::Line { from, to } => sub(to, scale(unit(sub(to, from)), c)),
            Element::Arc {
                to, centre, ccw, ..
            } => rotate(to, centre, chord_angle(self, c)?, !ccw),
        };
        self.inside(q).then_some(q)
    }

    /// The point of the element at the straight distance `c` after its start.
    fn at_distance_from_start(self, c: f64) -> Option<V> {
        let q = match self {
            Element::Line { from, to } => add(from, scale(unit(sub(to, from)), c)),
            Element::Arc {
                from, centre, ccw, ..
            } => rotate(from, centre, chord_angle(self, c)?, ccw),
        };
        self.inside(q).then_some(q)
    }
}

/// The angle a chord of length `c` spans on the arc's circle; `None` beyond the diameter.
fn chord_angle(arc: Element, c: f64) -> Option<f64> {
    let Element::Arc { from, centre, .. } = arc else {
        return None;
    };
    let half = c / (2.0 * dist(from, centre));
    (half <= 1.0).then(|| 2.0 * libm::asin(half))
}

/// `q` turned about `c` by `angle`, counter-clockwise or clockwise.
fn rotate(q: V, c: V, angle: f64, ccw: bool) -> V {
    let a = if ccw { angle } else { -angle };
    let (s, co) = (libm::sin(a), libm::cos(a));
    let v = sub(q, c);
    [c[0] + v[0] * co - v[1] * s, c[1] + v[0] * s + v[1] * co]
}

/// Where two curves meet: none, one or two points.
pub fn intersections(a: Curve, b: Curve) -> Vec<V> {
    match (a, b) {
        (Curve::Line { p: p1, d: d1 }, Curve::Line { p: p2, d: d2 }) => {
            let den = cross(d1, d2);
            if den.abs() <= EPS {
                return Vec::new();
            }
            vec![add(p1, scale(d1, cross(sub(p2, p1), d2) / den))]
        }
        (Curve::Line { p, d }, Curve::Circle { c, r })
        | (Curve::Circle { c, r }, Curve::Line { p, d }) => line_circle(p, d, c, r),
        (Curve::Circle { c: c1, r: r1 }, Curve::Circle { c: c2, r: r2 }) => {
            circle_circle(c1, r1, c2, r2)
        }
    }
}

/// A line (through `p`, unit direction `d`) and a circle.
fn line_circle(p: V, d: V, c: V, r: f64) -> Vec<V> {
    let f = sub(p, c);
    let b = dot(f, d);
    let disc = b * b - (dot(f, f) - r * r);
    if disc < -EPS {
        return Vec::new();
    }
    let s = libm::sqrt(disc.max(0.0));
    vec![add(p, scale(d, -b - s)), add(p, scale(d, -b + s))]
}

/// Two circles.
fn circle_circle(c1: V, r1: f64, c2: V, r2: f64) -> Vec<V> {
    let dd = dist(c1, c2);
    if dd <= EPS || dd > r1 + r2 + EPS || dd < (r1 - r2).abs() - EPS {
        return Vec::new();
    }
    let a = (r1 * r1 - r2 * r2 + dd * dd) / (2.0 * dd);
    let h = libm::sqrt((r1 * r1 - a * a).max(0.0));
    let u = unit(sub(c2, c1));
    let m = add(c1, scale(u, a));
    let n = [-u[1] * h, u[0] * h];
    vec![add(m, n), sub(m, n)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(from: V, to: V) -> Element {
        Element::Line { from, to }
    }

    fn near(a: V, b: V) -> bool {
        dist(a, b) < 1e-9
    }

    fn assert_cut(got: Cornered, first_end: V, second_start: V) {
        assert!(near(got.first_end, first_end), "{got:?}");
        assert!(near(got.second_start, second_start), "{got:?}");
        assert!(near(got.insert.end(), second_start), "{got:?}");
    }

    #[test]
    fn chamfer_and_round_at_a_right_angle() {
        // (0,0) → (50,0) → (50,30): 5 before and after the corner (50,0).
        let (a, b) = (
            line([0.0, 0.0], [50.0, 0.0]),
            line([50.0, 0.0], [50.0, 30.0]),
        );
        let c = corner(a, b, CornerKind::Chamfer, 5.0).unwrap().unwrap();
        assert_cut(c, [45.0, 0.0], [50.0, 5.0]);
        assert!(matches!(c.insert, Element::Line { .. }));
        // R8 turning left: centre (42, 8), touching at (42, 0) and (50, 8), counter-clockwise.
        let r = corner(a, b, CornerKind::Round, 8.0).unwrap().unwrap();
        assert_cut(r, [42.0, 0.0], [50.0, 8.0]);
        let Element::Arc { centre, ccw, .. } = r.insert else {
            panic!("{r:?}")
        };
        assert!(near(centre, [42.0, 8.0]) && ccw);
        // Turning right instead ((50,0) → (50,−30)): centre (42, −8), clockwise.
        let b = line([50.0, 0.0], [50.0, -30.0]);
        let r = corner(a, b, CornerKind::Round, 8.0).unwrap().unwrap();
        assert!(
            matches!(r.insert, Element::Arc { centre, ccw: false, .. } if near(centre, [42.0, -8.0]))
        );
    }

    #[test]
    fn a_chamfer_of_a_given_length_has_equal_legs() {
        // CHF=6 at a 60° turn: legs 6 / (2 cos 30°) = 2√3; from (40 − 2√3, 0) to
        // (40 + √3, 3), 6 apart.
        let s3 = 3f64.sqrt();
        let (a, b) = (
            line([0.0, 0.0], [40.0, 0.0]),
            line([40.0, 0.0], [50.0, 10.0 * s3]),
        );
        let c = corner(a, b, CornerKind::ChamferLength, 6.0)
            .unwrap()
            .unwrap();
        assert_cut(c, [40.0 - 2.0 * s3, 0.0], [40.0 + s3, 3.0]);
        // Onto an arc (about (60, 0), R20, clockwise from (40, 0) up to (60, 20): a left turn
        // of 90°): the legs are chords, equal, and the chamfer is 6 long.
        let arc = Element::Arc {
            from: [40.0, 0.0],
            to: [60.0, 20.0],
            centre: [60.0, 0.0],
            ccw: false,
        };
        let c = corner(a, arc, CornerKind::ChamferLength, 6.0)
            .unwrap()
            .unwrap();
        let p = [40.0, 0.0];
        assert!(
            (dist(c.first_end, c.second_start) - 6.0).abs() < 1e-9,
            "{c:?}"
        );
        assert!(
            (dist(c.first_end, p) - dist(c.second_start, p)).abs() < 1e-9,
            "{c:?}"
        );
        assert!(
            (dist(c.second_start, [60.0, 0.0]) - 20.0).abs() < 1e-9,
            "{c:?}"
        );
        // Longer than the elements allow.
        assert_eq!(
            corner(a, arc, CornerKind::ChamferLength, 90.0),
            Err(CornerError::TooLarge)
        );
    }

    #[test]
    fn a_sixty_degree_turn() {
        // (0,0) → (40,0), then 20 along 60°: to (50, 10√3).
        let s3 = 3f64.sqrt();
        let (a, b) = (
            line([0.0, 0.0], [40.0, 0.0]),
            line([40.0, 0.0], [50.0, 10.0 * s3]),
        );
        // ,C4: 4 back along X, 4 on along 60°: (40 + 2, 2√3).
        let c = corner(a, b, CornerKind::Chamfer, 4.0).unwrap().unwrap();
        assert_cut(c, [36.0, 0.0], [42.0, 2.0 * s3]);
        // ,R6: the tangent points lie R·tan(60°/2) = 2√3 from the corner; centre 6 above
        // the first one.
        let t = 2.0 * s3;
        let r = corner(a, b, CornerKind::Round, 6.0).unwrap().unwrap();
        assert_cut(r, [40.0 - t, 0.0], [40.0 + t / 2.0, t * s3 / 2.0]);
        assert!(
            matches!(r.insert, Element::Arc { centre, ccw: true, .. } if near(centre, [40.0 - t, 6.0]))
        );
    }

    #[test]
    fn line_then_arc() {
        // (0,0) → (20,0), then counter-clockwise about (30,0) down through (30,−10) to
        // (40,0): a right turn. The R5 centre is 5 below the line and 10 + 5 from (30,0):
        // x = 30 − √(15² − 5²) = 30 − 10√2; it touches the circle at (30,0) + 10/15 of the
        // way to it.
        let a = line([0.0, 0.0], [20.0, 0.0]);
        let b = Element::Arc {
            from: [20.0, 0.0],
            to: [40.0, 0.0],
            centre: [30.0, 0.0],
            ccw: true,
        };
        let x = 30.0 - 10.0 * 2f64.sqrt();
        let r = corner(a, b, CornerKind::Round, 5.0).unwrap().unwrap();
        assert_cut(r, [x, 0.0], [30.0 - 20.0 * 2f64.sqrt() / 3.0, -10.0 / 3.0]);
        assert!(
            matches!(r.insert, Element::Arc { centre, ccw: false, .. } if near(centre, [x, -5.0]))
        );
        // ,C2 on the arc: the chord of 2 from (20,0) spans 2·asin(0.1) about (30,0).
        let c = corner(a, b, CornerKind::Chamfer, 2.0).unwrap().unwrap();
        let t = 2.0 * libm::asin(0.1);
        assert_cut(c, [18.0, 0.0], [30.0 - 10.0 * t.cos(), -10.0 * t.sin()]);
        assert!((dist(c.second_start, [20.0, 0.0]) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn arc_then_line() {
        // Clockwise about (0,0) from (0,10) to (10,0), then on along +X: a left turn. The R2
        // centre is 2 above the line and 10 + 2 from (0,0): (√140, 2).
        let a = Element::Arc {
            from: [0.0, 10.0],
            to: [10.0, 0.0],
            centre: [0.0, 0.0],
            ccw: false,
        };
        let b = line([10.0, 0.0], [30.0, 0.0]);
        let x = 140f64.sqrt();
        let r = corner(a, b, CornerKind::Round, 2.0).unwrap().unwrap();
        assert_cut(r, [x * 10.0 / 12.0, 2.0 * 10.0 / 12.0], [x, 0.0]);
        assert!(
            matches!(r.insert, Element::Arc { centre, ccw: true, .. } if near(centre, [x, 2.0]))
        );
    }

    #[test]
    fn arc_then_arc() {
        // Counter-clockwise about (0,0) from (10,0) to (0,10), then clockwise about
        // (−10,10): tangents (−1,0) then (0,−1), a left turn.
        let a = Element::Arc {
            from: [10.0, 0.0],
            to: [0.0, 10.0],
            centre: [0.0, 0.0],
            ccw: true,
        };
        let b = Element::Arc {
            from: [0.0, 10.0],
            to: [-10.0, 0.0],
            centre: [-10.0, 10.0],
            ccw: false,
        };
        // ,R2: the centre is 10 − 2 from (0,0) and 10 + 2 from (−10,10): the circles meet
        // 3√2 along the line of centres and √46 across it, at (√23 − 3, √23 + 3).
        let s23 = 23f64.sqrt();
        let c = [s23 - 3.0, s23 + 3.0];
        let r = corner(a, b, CornerKind::Round, 2.0).unwrap().unwrap();
        let t2 = [
            -10.0 + (c[0] + 10.0) * 10.0 / 12.0,
            10.0 + (c[1] - 10.0) * 10.0 / 12.0,
        ];
        assert_cut(r, [c[0] * 1.25, c[1] * 1.25], t2);
        assert!(matches!(r.insert, Element::Arc { centre, ccw: true, .. } if near(centre, c)));
        // ,C2: chords of 2 on both circles, 2·asin(0.1) back from (0,10) and on from it.
        let t = 2.0 * libm::asin(0.1);
        let ch = corner(a, b, CornerKind::Chamfer, 2.0).unwrap().unwrap();
        let (s, co) = (10.0 * t.sin(), 10.0 * t.cos());
        assert_cut(ch, [s, co], [-10.0 + co, 10.0 - s]);
    }

    #[test]
    fn tangent_elements_get_nothing_and_too_large_is_refused() {
        // A line into the arc that starts along it: nothing to insert (within 1°).
        let a = line([0.0, 0.0], [20.0, 0.0]);
        let b = Element::Arc {
            from: [20.0, 0.0],
            to: [30.0, 10.0],
            centre: [20.0, 10.0],
            ccw: true,
        };
        assert_eq!(corner(a, b, CornerKind::Round, 3.0), Ok(None));
        let bent = line([20.0, 0.0], [40.0, 0.3]);
        assert_eq!(corner(a, bent, CornerKind::Chamfer, 1.0), Ok(None));
        assert_eq!(
            corner(a, line([20.0, 0.0], [20.0, 5.0]), CornerKind::Chamfer, 0.0),
            Ok(None)
        );
        // Legs longer than an element, or the whole of it.
        let up = line([20.0, 0.0], [20.0, 5.0]);
        assert_eq!(
            corner(a, up, CornerKind::Chamfer, 6.0),
            Err(CornerError::TooLarge)
        );
        assert_eq!(
            corner(a, up, CornerKind::Chamfer, 5.0),
            Err(CornerError::TooLarge)
        );
        assert_eq!(
            corner(a, up, CornerKind::Round, 5.5),
            Err(CornerError::TooLarge)
        );
        // Straight back: no arc touches both.
        let back = line([20.0, 0.0], [10.0, 0.0]);
        assert_eq!(
            corner(a, back, CornerKind::Round, 1.0),
            Err(CornerError::NoRound)
        );
    }
}
