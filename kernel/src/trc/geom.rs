//! Plane geometry for the compensation: vectors in the working plane (abscissa, ordinate),
//! contour elements (lines, arcs), their equidistants and intersections. Transcendentals come
//! from `libm` so that every machine computes the same bits.

use std::ops::{Add, Mul, Neg, Sub};

/// Lengths below this are zero (mm): far below any encoder resolution, far above rounding.
pub const EPS: f64 = 1e-9;
/// Direction changes below this count as tangent (rad).
pub const ANGLE_EPS: f64 = 1e-9;

#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct V2 {
    pub x: f64,
    pub y: f64,
}

pub const fn v2(x: f64, y: f64) -> V2 {
    V2 { x, y }
}

impl Add for V2 {
    type Output = V2;
    fn add(self, o: V2) -> V2 {
        v2(self.x + o.x, self.y + o.y)
    }
}
impl Sub for V2 {
    type Output = V2;
    fn sub(self, o: V2) -> V2 {
        v2(self.x - o.x, self.y - o.y)
    }
}
impl Mul<f64> for V2 {
    type Output = V2;
    fn mul(self, k: f64) -> V2 {
        v2(self.x * k, self.y * k)
    }
}
impl Neg for V2 {
    type Output = V2;
    fn neg(self) -> V2 {
        v2(-self.x, -self.y)
    }
}

impl V2 {
    pub fn dot(self, o: V2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    /// z component of the cross product: > 0 when `o` lies counter-clockwise of `self`.
    pub fn cross(self, o: V2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    pub fn len(self) -> f64 {
        (self.x * self.x + self.y * self.y).sqrt()
    }
    pub fn dist(self, o: V2) -> f64 {
        (self - o).len()
    }
    /// Unit vector; the zero vector stays zero.
    pub fn unit(self) -> V2 {
        let l = self.len();
        if l > 0.0 {
            self * (1.0 / l)
        } else {
            self
        }
    }
    /// Rotated by +90°: the left normal of a direction.
    pub fn left(self) -> V2 {
        v2(-self.y, self.x)
    }
    #[cfg(test)]
    pub fn angle(self) -> f64 {
        libm::atan2(self.y, self.x)
    }
    #[cfg(test)]
    pub fn from_angle(a: f64) -> V2 {
        v2(libm::cos(a), libm::sin(a))
    }
}

/// Signed angle from direction `a` to direction `b`, in (−π, π]: > 0 is a left turn.
pub fn turn(a: V2, b: V2) -> f64 {
    libm::atan2(a.cross(b), a.dot(b))
}

/// A contour element in the plane. An arc with `a == b` is a full circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Elem {
    Line { a: V2, b: V2 },
    Arc { a: V2, b: V2, c: V2, ccw: bool },
}

impl Elem {
    pub fn start(&self) -> V2 {
        match *self {
            Elem::Line { a, .. } | Elem::Arc { a, .. } => a,
        }
    }
    pub fn end(&self) -> V2 {
        match *self {
            Elem::Line { b, .. } | Elem::Arc { b, .. } => b,
        }
    }
    pub fn is_arc(&self) -> bool {
        matches!(self, Elem::Arc { .. })
    }
    pub fn radius(&self) -> f64 {
        match *self {
            Elem::Line { .. } => f64::INFINITY,
            Elem::Arc { a, c, .. } => a.dist(c),
        }
    }
    /// Unit direction of travel at a point of the element.
    fn tangent_at(&self, p: V2) -> V2 {
        self.heading_at(p).unit()
    }
    /// Direction of travel at a point, not normalised (the element's length or radius):
    /// enough to tell a tangent transition, without a square root.
    pub fn heading_at(&self, p: V2) -> V2 {
        match *self {
            Elem::Line { a, b } => b - a,
            Elem::Arc { c, ccw, .. } => {
                let r = (p - c).left();
                if ccw {
                    r
                } else {
                    -r
                }
            }
        }
    }
    pub fn tangent_start(&self) -> V2 {
        self.tangent_at(self.start())
    }
    pub fn tangent_end(&self) -> V2 {
        self.tangent_at(self.end())
    }
    /// Swept angle of an arc, in (0, 2π]; 0 for a line.
    pub fn sweep(&self) -> f64 {
        match *self {
            Elem::Line { .. } => 0.0,
            Elem::Arc { a, b, c, ccw } => sweep(c, a, b, ccw),
        }
    }
    /// The equidistant at `d` (> 0: left of the direction of travel). `None` when an arc
    /// would shrink to a point or turn inside out: the tool does not fit (alarm, never a path).
    #[inline]
    pub fn offset(&self, d: f64) -> Option<Elem> {
        self.equidistant(d).filter(
            |o| !matches!((self, o), (Elem::Arc { ccw, .. }, Elem::Arc { ccw: k, .. }) if ccw != k),
        )
    }
    /// As [`Elem::offset`], but an arc the tool does not fit into turns inside out: the
    /// circle of radius R − r about the same centre, run the other way, from normal position
    /// to normal position (a raw offset, for contour masking to leave out). `None` only where
    /// it shrinks to a point.
    #[inline]
    pub fn equidistant(&self, d: f64) -> Option<Elem> {
        match *self {
            Elem::Line { a, b } => {
                let n = (b - a).unit().left() * d;
                Some(Elem::Line { a: a + n, b: b + n })
            }
            Elem::Arc { a, b, c, ccw } => {
                // Left of a counter-clockwise arc is towards its centre.
                let r = a.dist(c);
                let r2 = if ccw { r - d } else { r + d };
                if r2.abs() <= EPS {
                    return None;
                }
                let k = r2 / r;
                Some(Elem::Arc {
                    a: c + (a - c) * k,
                    b: c + (b - c) * k,
                    c,
                    ccw: ccw == (r2 > 0.0),
                })
            }
        }
    }
    /// The normal position: the point at `d` left of the element's end.
    pub fn normal_end(&self, d: f64) -> V2 {
        self.end() + self.tangent_end().left() * d
    }
    /// The same element with another start point (which must lie on its line or circle).
    pub fn with_start(&self, p: V2) -> Elem {
        match *self {
            Elem::Line { b, .. } => Elem::Line { a: p, b },
            Elem::Arc { b, c, ccw, .. } => Elem::Arc { a: p, b, c, ccw },
        }
    }
    pub fn with_end(&self, p: V2) -> Elem {
        match *self {
            Elem::Line { a, .. } => Elem::Line { a, b: p },
            Elem::Arc { a, c, ccw, .. } => Elem::Arc { a, b: p, c, ccw },
        }
    }
}

/// Swept angle from `a` to `b` about `c`, in (0, 2π] (a == b is a full circle).
pub fn sweep(c: V2, a: V2, b: V2, ccw: bool) -> f64 {
    let tau = std::f64::consts::TAU;
    let (u, w) = (a - c, b - c);
    let mut s = libm::atan2(u.cross(w), u.dot(w));
    if !ccw {
        s = -s;
    }
    if s <= ANGLE_EPS * u.len().max(1.0).recip() {
        s += tau;
    }
    s
}

/// Intersection of the lines through `p` along `u` and through `q` along `w`; `None` when
/// they are parallel.
pub fn line_line(p: V2, u: V2, q: V2, w: V2) -> Option<V2> {
    let den = u.cross(w);
    if den.abs() <= 1e-12 * u.len() * w.len() {
        return None;
    }
    let t = (q - p).cross(w) / den;
    Some(p + u * t)
}

/// Intersections of the line through `p` along `u` with the circle about `c` of radius `r`.
pub fn line_circle(p: V2, u: V2, c: V2, r: f64) -> heapless::Vec<V2, 2> {
    let mut out = heapless::Vec::new();
    let u = u.unit();
    let f = p - c;
    let b = f.dot(u);
    let disc = b * b - (f.dot(f) - r * r);
    let tol = 1e-12 * r.max(1.0) * r.max(1.0);
    if disc < -tol {
        return out;
    }
    if disc <= tol {
        let _ = out.push(p + u * (-b));
        return out;
    }
    let s = disc.sqrt();
    let _ = out.push(p + u * (-b - s));
    let _ = out.push(p + u * (-b + s));
    out
}

/// Intersections of two circles.
pub fn circle_circle(c1: V2, r1: f64, c2: V2, r2: f64) -> heapless::Vec<V2, 2> {
    let mut out = heapless::Vec::new();
    let dv = c2 - c1;
    let d = dv.len();
    if d <= EPS {
        return out;
    }
    let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h2 = r1 * r1 - a * a;
    let tol = 1e-12 * r1.max(1.0) * r1.max(1.0);
    let m = c1 + dv * (a / d);
    if h2 < -tol {
        return out;
    }
    if h2 <= tol {
        let _ = out.push(m);
        return out;
    }
    let h = h2.sqrt();
    let n = dv.left() * (h / d);
    let _ = out.push(m + n);
    let _ = out.push(m - n);
    out
}

/// Where the carriers (infinite line, full circle) of two elements meet.
pub fn intersections(e1: &Elem, e2: &Elem) -> heapless::Vec<V2, 2> {
    match (*e1, *e2) {
        (Elem::Line { a, b }, Elem::Line { a: p, b: q }) => {
            let mut v = heapless::Vec::new();
            if let Some(x) = line_line(a, b - a, p, q - p) {
                let _ = v.push(x);
            }
            v
        }
        (Elem::Line { a, b }, Elem::Arc { a: s, c, .. })
        | (Elem::Arc { a: s, c, .. }, Elem::Line { a, b }) => line_circle(a, b - a, c, s.dist(c)),
        (Elem::Arc { a: s1, c: c1, .. }, Elem::Arc { a: s2, c: c2, .. }) => {
            circle_circle(c1, s1.dist(c1), c2, s2.dist(c2))
        }
    }
}

/// Helpers the tests below use.
#[cfg(test)]
impl Elem {
    /// The element run backwards.
    pub fn reversed(&self) -> Elem {
        match *self {
            Elem::Line { a, b } => Elem::Line { a: b, b: a },
            Elem::Arc { a, b, c, ccw } => Elem::Arc {
                a: b,
                b: a,
                c,
                ccw: !ccw,
            },
        }
    }
    /// Position of `p` (a point on the element's line or circle) along the element, as a
    /// length from the start: negative before the start, beyond its length after the end.
    /// For arcs the angle is measured in the direction of travel from the start; points up
    /// to half a turn behind the start come out negative unless the arc reaches them.
    pub fn param(&self, p: V2) -> f64 {
        match *self {
            Elem::Line { a, b } => (p - a).dot((b - a).unit()),
            Elem::Arc { a, c, ccw, .. } => {
                let r = a.dist(c);
                let mut t = libm::atan2((a - c).cross(p - c), (a - c).dot(p - c));
                if !ccw {
                    t = -t;
                }
                // t in (−π, π]; points past half a turn from the start are "ahead" when
                // the arc is long enough to reach them.
                let s = self.sweep();
                if t < 0.0 && t + std::f64::consts::TAU <= s + ANGLE_EPS && s > std::f64::consts::PI
                {
                    t += std::f64::consts::TAU;
                }
                t * r
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn close(a: V2, b: V2) -> bool {
        a.dist(b) < 1e-12
    }

    fn value() -> impl Strategy<Value = f64> {
        prop_oneof![
            Just(f64::NAN),
            Just(-0.0),
            Just(f64::INFINITY),
            -1e9..1e9f64
        ]
    }

    proptest! {
        /// `max_abs` is `f64::max` over the magnitudes, bit for bit, NaN coordinates passed
        /// over as `f64::max` passes them.
        #[test]
        fn max_abs_is_f64_max_of_the_magnitudes(
            m in 0.0..2.0f64, xs in proptest::collection::vec((value(), value()), 0..4)
        ) {
            let points: Vec<V2> = xs.iter().map(|&(x, y)| v2(x, y)).collect();
            let want = points.iter().fold(m, |m, p| m.max(p.x.abs()).max(p.y.abs()));
            prop_assert_eq!(max_abs(m, &points).to_bits(), want.to_bits());
        }
    }

    #[test]
    fn left_offset_of_a_line_going_east_moves_north() {
        let e = Elem::Line {
            a: v2(0.0, 0.0),
            b: v2(10.0, 0.0),
        };
        let o = e.offset(2.0).unwrap();
        assert!(close(o.start(), v2(0.0, 2.0)) && close(o.end(), v2(10.0, 2.0)));
    }

    #[test]
    fn left_offset_of_a_ccw_arc_shrinks_it() {
        let e = Elem::Arc {
            a: v2(10.0, 0.0),
            b: v2(0.0, 10.0),
            c: v2(0.0, 0.0),
            ccw: true,
        };
        let o = e.offset(3.0).unwrap();
        assert!(close(o.start(), v2(7.0, 0.0)) && close(o.end(), v2(0.0, 7.0)));
        assert!(e.offset(10.0).is_none(), "tool as large as the arc");
        let cw = e.reversed();
        assert!((cw.offset(3.0).unwrap().radius() - 13.0).abs() < 1e-12);
    }

    #[test]
    fn sweep_and_full_circle() {
        let c = v2(0.0, 0.0);
        assert!(
            (sweep(c, v2(1.0, 0.0), v2(0.0, 1.0), true) - std::f64::consts::FRAC_PI_2).abs()
                < 1e-15
        );
        assert!(
            (sweep(c, v2(1.0, 0.0), v2(0.0, 1.0), false) - 1.5 * std::f64::consts::PI).abs()
                < 1e-15
        );
        assert!((sweep(c, v2(1.0, 0.0), v2(1.0, 0.0), true) - std::f64::consts::TAU).abs() < 1e-15);
    }

    #[test]
    fn intersections_of_carriers() {
        let x = line_line(v2(0.0, 1.0), v2(1.0, 0.0), v2(3.0, 0.0), v2(0.0, 1.0)).unwrap();
        assert!(close(x, v2(3.0, 1.0)));
        let pts = line_circle(v2(-5.0, 0.0), v2(1.0, 0.0), v2(0.0, 0.0), 2.0);
        assert_eq!(pts.len(), 2);
        assert!(close(pts[0], v2(-2.0, 0.0)) && close(pts[1], v2(2.0, 0.0)));
        let pts = circle_circle(v2(0.0, 0.0), 5.0, v2(8.0, 0.0), 5.0);
        assert!(close(pts[0], v2(4.0, -3.0)) || close(pts[0], v2(4.0, 3.0)));
    }

    #[test]
    fn param_along_elements() {
        let l = Elem::Line {
            a: v2(0.0, 0.0),
            b: v2(10.0, 0.0),
        };
        assert_eq!(l.param(v2(-2.0, 0.0)), -2.0);
        let a = Elem::Arc {
            a: v2(1.0, 0.0),
            b: v2(-1.0, 0.0),
            c: v2(0.0, 0.0),
            ccw: true,
        };
        assert!((a.param(v2(0.0, 1.0)) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(a.param(v2(0.0, -1.0)) < 0.0, "just before the start");
    }
}

/// Distance from `p` to the element (a segment of a line or of a circle).
pub fn dist_point(e: &Elem, p: V2) -> f64 {
    match *e {
        Elem::Line { a, b } => {
            let d = b - a;
            let l2 = d.dot(d);
            let t = if l2 > 0.0 {
                ((p - a).dot(d) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            p.dist(a + d * t)
        }
        Elem::Arc { a, b, c, .. } => {
            if on_arc(e, p, c) {
                (p.dist(c) - a.dist(c)).abs()
            } else {
                p.dist(a).min(p.dist(b))
            }
        }
    }
}

/// Whether the ray from the arc's centre through `p` meets the arc (p at the centre: no).
fn on_arc(e: &Elem, p: V2, c: V2) -> bool {
    let Elem::Arc { a, b, ccw, .. } = *e else {
        return false;
    };
    if p.dist(c) <= EPS {
        return false;
    }
    // Counter-clockwise from s to t: the arc as seen from its centre, without angles.
    let (s, t) = if ccw { (a - c, b - c) } else { (b - c, a - c) };
    let v = p - c;
    let r = s.len();
    // On a ray through an end point (within rounding): on the arc.
    let near_ray = |w: V2| w.cross(v).abs() <= 1e-12 * r * v.len() && w.dot(v) > 0.0;
    if near_ray(s) || near_ray(t) {
        return true;
    }
    let full = (a - b).len() <= 1e-12 * r.max(1.0);
    full || between(s, t, v)
}

/// Whether direction `v` lies between `s` and `t`, counter-clockwise from `s` (vectors from an
/// arc's centre to its ends, in ccw order): cross products only, no tolerance.
#[inline]
fn between(s: V2, t: V2, v: V2) -> bool {
    let st = s.cross(t);
    if st > 0.0 || (st == 0.0 && s.dot(t) < 0.0) {
        // At most half a turn: between the two rays.
        s.cross(v) >= 0.0 && v.cross(t) >= 0.0
    } else {
        // More than half a turn: anywhere but strictly inside the complement.
        !(t.cross(v) > 0.0 && v.cross(s) > 0.0)
    }
}

/// Whether a point of the element's line or circle lies on the element itself.
pub fn contains(e: &Elem, p: V2) -> bool {
    const TOL: f64 = 1e-9;
    match *e {
        Elem::Line { a, b } => {
            let d = b - a;
            let l2 = d.dot(d);
            if l2 == 0.0 {
                return p.dist(a) <= TOL;
            }
            let t = (p - a).dot(d) / l2;
            (-TOL..=1.0 + TOL).contains(&t)
        }
        Elem::Arc { c, .. } => on_arc(e, p, c),
    }
}

/// Smallest distance between two elements (0 where they cross).
pub fn dist_elems(e1: &Elem, e2: &Elem) -> f64 {
    if intersections(e1, e2)
        .into_iter()
        .any(|x| contains(e1, x) && contains(e2, x))
    {
        return 0.0;
    }
    // Otherwise the closest pair has an end point of one element, or lies on the line
    // through an arc's centre (perpendicular to a line, or joining two centres).
    let mut d = dist_point(e2, e1.start())
        .min(dist_point(e2, e1.end()))
        .min(dist_point(e1, e2.start()))
        .min(dist_point(e1, e2.end()));
    for (x, y) in [(e1, e2), (e2, e1)] {
        if let Elem::Arc { a, c, .. } = *x {
            let r = a.dist(c);
            let dirs: heapless::Vec<V2, 2> = match *y {
                Elem::Line { a: p, b: q } => {
                    // The foot of the centre on the line, and the arc point towards it.
                    let u = (q - p).unit();
                    let foot = p + u * (c - p).dot(u);
                    let mut v = heapless::Vec::new();
                    if contains(y, foot) && foot.dist(c) > EPS {
                        let _ = v.push((foot - c).unit());
                    }
                    v
                }
                Elem::Arc { c: c2, .. } => {
                    let mut v = heapless::Vec::new();
                    if c2.dist(c) > EPS {
                        let _ = v.push((c2 - c).unit());
                        let _ = v.push((c - c2).unit());
                    }
                    v
                }
            };
            for u in dirs {
                let q = c + u * r;
                if contains(x, q) {
                    d = d.min(dist_point(y, q));
                }
            }
        }
    }
    d
}

/// The element's bounding box (x0, y0, x1, y1): an arc's ends and the points of its circle
/// furthest along ±x and ±y that lie within its sweep. Inlined: the element is mostly one
/// just built, which a call would read back from memory before its stores complete.
#[inline(always)]
pub fn bounds(e: &Elem) -> [f64; 4] {
    let (a, b) = (e.start(), e.end());
    let mut bb = [a.x.min(b.x), a.y.min(b.y), a.x.max(b.x), a.y.max(b.y)];
    if let Elem::Arc { a, b, c, .. } = *e {
        // One root: the root of the larger square is the larger root, bit for bit.
        let (u, w) = (a - c, b - c);
        let r = u.dot(u).max(w.dot(w)).sqrt();
        let full = a == b;
        let reach = |w: V2| full || in_sweep(e, w);
        if reach(v2(-1.0, 0.0)) {
            bb[0] = bb[0].min(c.x - r);
        }
        if reach(v2(0.0, -1.0)) {
            bb[1] = bb[1].min(c.y - r);
        }
        if reach(v2(1.0, 0.0)) {
            bb[2] = bb[2].max(c.x + r);
        }
        if reach(v2(0.0, 1.0)) {
            bb[3] = bb[3].max(c.y + r);
        }
    }
    bb
}

/// Whether direction `w` from an arc's centre lies within the arc's sweep, for the cheap
/// tests below: no tolerance (a direction within rounding of an end changes their values by
/// a second-order amount).
#[inline]
fn in_sweep(e: &Elem, w: V2) -> bool {
    let Elem::Arc { a, b, c, ccw } = *e else {
        return false;
    };
    let (s, t) = if ccw { (a - c, b - c) } else { (b - c, a - c) };
    between(s, t, w)
}

/// A path element made ready for [`clear_by_ends`]: its circle's radius worked out once (the
/// test asks for it up to five times, a square root each).
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    pub e: Elem,
    /// The circle's radius (0 for a line).
    r: f64,
    /// Rounding margin: a few 1e-14 of the coordinates (the centre's too).
    eta: f64,
}

impl Measured {
    pub fn new(e: Elem) -> Self {
        let r = match e {
            Elem::Line { .. } => 0.0,
            Elem::Arc { a, c, .. } => a.dist(c),
        };
        Measured {
            e,
            r,
            eta: eta_of(&e),
        }
    }
}

/// What the cheap tests ([`lines_clear`], [`arcs_clear`]) add to a limit for rounding: a few
/// 1e-14 of the pair's coordinates. Their operations round by about 1e-16 of the coordinates,
/// so a pair shown clear with the margin is clear by the exact distance; the margin lies far
/// below the gouge tolerance (1e-9 mm, 1e-12 of the coordinates), so a neighbour at exactly
/// the tool radius is still shown clear. `other_eta`: the other element's [`eta_of`].
#[inline]
pub fn margin(path: &Measured, other_eta: f64) -> f64 {
    4.0 * path.eta.max(other_eta)
}

/// Rounding margin of an element: 1e-14 of its largest coordinate (its centre's too), at
/// least of 1 mm.
#[inline]
pub fn eta_of(e: &Elem) -> f64 {
    let m = match *e {
        Elem::Line { a, b } => max_abs(1.0, &[a, b]),
        Elem::Arc { a, b, c, .. } => max_abs(1.0, &[a, b, c]),
    };
    1e-14 * m
}

/// The largest of `m` (not NaN) and the magnitudes of the points' coordinates: `f64::max`'s
/// value (a NaN coordinate is passed over) by plain comparisons, which it costs several of.
#[inline]
pub fn max_abs(m: f64, points: &[V2]) -> f64 {
    let up = |m: f64, v: f64| if v.abs() > m { v.abs() } else { m };
    points.iter().fold(m, |m, p| up(up(m, p.x), p.y))
}

/// What [`clear_by_ends`] needs of the element a path must keep away from, worked out once
/// when the element enters the bottleneck window (each is tested against several paths).
#[derive(Clone, Copy, Debug)]
pub struct Fence {
    /// Rounding margin: a few 1e-14 of the coordinates.
    eta: f64,
    shape: FenceShape,
}

#[derive(Clone, Copy, Debug)]
enum FenceShape {
    /// Direction `d` (with its length), the margin in units of |d|, a·d and b·d.
    Line {
        d: V2,
        len: f64,
        tol: f64,
        ad: f64,
        bd: f64,
    },
    /// An arc of at most half a turn: directions of travel at the start and the end (with
    /// their lengths, the radius), the margin, c·ts, c·te, and the clearance the centre needs.
    Arc {
        ts: V2,
        te: V2,
        ts_len: f64,
        te_len: f64,
        tol: f64,
        cts: f64,
        cte: f64,
        centre: f64,
    },
    /// Not to be shown clear by its ends (degenerate, or more than half a turn).
    Never,
}

impl Fence {
    pub fn new(other: &Elem) -> Self {
        Self::with_eta(other, eta_of(other))
    }

    /// [`Fence::new`] for an element whose [`eta_of`] is `eta`.
    pub fn with_eta(other: &Elem, eta: f64) -> Self {
        let (a, b) = (other.start(), other.end());
        let shape = match *other {
            Elem::Line { .. } => {
                let d = b - a;
                let dd = d.dot(d);
                if dd <= EPS * EPS {
                    FenceShape::Never
                } else {
                    FenceShape::Line {
                        d,
                        len: d.len(),
                        // Margins in units of |d|: eta·|d| ≤ eta·(|dx| + |dy|).
                        tol: eta * (d.x.abs() + d.y.abs()),
                        ad: a.dot(d),
                        bd: b.dot(d),
                    }
                }
            }
            Elem::Arc { c, ccw, .. } => {
                let (u, w) = (a - c, b - c);
                let r2 = u.dot(u);
                // At most half a turn (within rounding), and not a full circle.
                let turn = if ccw { u.cross(w) } else { w.cross(u) };
                if r2 <= EPS * EPS || a == b || turn < -1e-12 * r2 {
                    FenceShape::Never
                } else {
                    // Directions of travel at the ends: the arc lies behind the end's and
                    // ahead of the start's, so a ray beyond either misses it.
                    // |ts| = |te| = r ≤ |ux|+|uy|.
                    let (ts, te) = if ccw {
                        (u.left(), w.left())
                    } else {
                        (-u.left(), -w.left())
                    };
                    FenceShape::Arc {
                        ts,
                        te,
                        ts_len: ts.len(),
                        te_len: te.len(),
                        tol: eta * (u.x.abs() + u.y.abs()),
                        cts: c.dot(ts),
                        cte: c.dot(te),
                        centre: 1e-3 * r2.sqrt(),
                    }
                }
            }
        };
        Fence { eta, shape }
    }
}

/// Smallest and largest value of `X·w` over the points X of the element (`w_len` = |w|).
#[inline]
fn extent(p: &Measured, w: V2, w_len: f64) -> (f64, f64) {
    let e = &p.e;
    let (s, t) = (e.start().dot(w), e.end().dot(w));
    let (mut lo, mut hi) = (s.min(t), s.max(t));
    if let Elem::Arc { a, b, c, .. } = *e {
        if a == b {
            // A full circle.
            return (f64::NEG_INFINITY, f64::INFINITY);
        }
        let k = p.r * w_len;
        let cw = c.dot(w);
        if in_sweep(e, w) {
            hi = hi.max(cw + k);
        }
        if in_sweep(e, -w) {
            lo = lo.min(cw - k);
        }
    }
    (lo, hi)
}

/// Whether point `q` is at least `limit` (≥ 0) from the element: squared distances, no root.
#[inline]
fn at_least(p: &Measured, q: V2, limit: f64) -> bool {
    let l2 = limit * limit;
    match p.e {
        Elem::Line { a, b } => {
            let d = b - a;
            let (aq, dd) = (q - a, d.dot(d));
            let t = aq.dot(d);
            let q2 = if t <= 0.0 || dd <= 0.0 {
                aq.dot(aq)
            } else if t >= dd {
                (q - b).dot(q - b)
            } else {
                // Squared distance to the line: cross² / |d|².
                let x = aq.cross(d);
                x * x / dd
            };
            q2 >= l2
        }
        Elem::Arc { a, b, c, .. } => {
            let v = q - c;
            if a != b && !in_sweep(&p.e, v) {
                return (q - a).dot(q - a) >= l2 && (q - b).dot(q - b) >= l2;
            }
            let (r, v2) = (p.r, v.dot(v));
            let out = r + limit;
            v2 >= out * out || (r > limit && v2 <= (r - limit) * (r - limit))
        }
    }
}

/// Whether every point of `path` is at least `limit` from `other`, shown by a cheap test
/// that works where the closest points of `other` are its ends: the common case of a path
/// segment and the programmed element it shares a corner with. `false` means "not shown",
/// and the caller computes the exact distance ([`dist_elems`]).
///
/// The test: every point of `path` lies where the nearest point of `other` is one of its
/// ends (for a line: the projection falls outside the line; for an arc of at most half a
/// turn: the ray from the centre misses the arc), and both ends are at least `limit` from
/// `path`. Rounding is covered by a margin of a few 1e-14 of the coordinates (far below the
/// gouge tolerance, so that a tangent neighbour at exactly R still passes).
#[cfg(test)]
pub fn clear_by_ends(path: &Elem, other: &Elem, limit: f64) -> bool {
    clear_by_ends_of(&Measured::new(*path), other, &Fence::new(other), limit)
}

/// Whether two line segments are surely at least `limit` (≥ 0, with the rounding [`margin`]
/// added) apart: they do not cross and every end is that far from the other segment, by
/// squared distances. `false` says nothing (the exact distance decides): the cheap test for
/// the most common pair, two lines that meet at a corner or lie side by side.
#[inline]
pub fn lines_clear(a: V2, b: V2, p: V2, q: V2, limit: f64) -> bool {
    let (d, e) = (b - a, q - p);
    let (s1, s2) = (d.cross(p - a), d.cross(q - a));
    let (s3, s4) = (e.cross(a - p), e.cross(b - p));
    let l2 = limit * limit;
    // One wholly beyond the other's line by the limit (the cross products are the ends'
    // signed distances times the line's length): how a corner's neighbours lie.
    if beyond(s1, s2, l2 * d.dot(d)) || beyond(s3, s4, l2 * e.dot(e)) {
        return true;
    }
    if (s1 <= 0.0 && s2 >= 0.0 || s1 >= 0.0 && s2 <= 0.0)
        && (s3 <= 0.0 && s4 >= 0.0 || s3 >= 0.0 && s4 <= 0.0)
    {
        return false;
    }
    point_seg_sq(p, a, d) >= l2
        && point_seg_sq(q, a, d) >= l2
        && point_seg_sq(a, p, e) >= l2
        && point_seg_sq(b, p, e) >= l2
}

/// Whether two points whose signed distances from a line, times its length, are `s1` and
/// `s2` lie on one side of it, both at least the distance whose square times the length's
/// square is `l2dd`.
#[inline]
fn beyond(s1: f64, s2: f64, l2dd: f64) -> bool {
    let m = s1.abs().min(s2.abs());
    s1 * s2 > 0.0 && m * m >= l2dd
}

/// Squared distance from `x` to the segment from `a` along `d`.
#[inline]
fn point_seg_sq(x: V2, a: V2, d: V2) -> f64 {
    let ax = x - a;
    let (t, dd) = (ax.dot(d), d.dot(d));
    if t <= 0.0 || dd <= 0.0 {
        ax.dot(ax)
    } else if t >= dd {
        let bx = ax - d;
        bx.dot(bx)
    } else {
        let c = ax.cross(d);
        c * c / dd
    }
}

/// Whether `path` and `other` are surely at least `limit` (≥ 0, with the rounding [`margin`]
/// added) apart where one of them is an arc and [`clear_by_ends_of`] could not tell: an arc
/// and a line by the few places their closest points can be ([`arc_line_clear`]), two arcs by
/// their whole circles. `false` says nothing (the exact distance decides).
#[inline]
pub fn arcs_clear(path: &Measured, other: &Elem, limit: f64) -> bool {
    match (path.e, *other) {
        (Elem::Arc { .. }, Elem::Line { a, b }) => arc_line_clear(&path.e, path.r, a, b, limit),
        (Elem::Line { a, b }, Elem::Arc { a: s, c, .. }) => {
            arc_line_clear(other, s.dist(c), a, b, limit)
        }
        (Elem::Arc { c, .. }, Elem::Arc { a, c: c2, .. }) => {
            // Circles apart, or one inside the other, `limit` clear of each other.
            let (r1, r2, d) = (path.r, a.dist(c2), c.dist(c2));
            let (small, big) = (r1.min(r2), r1.max(r2));
            d >= r1 + r2 + limit || d + small + limit <= big
        }
        _ => false,
    }
}

/// Whether the arc `arc` (radius `r`) and the line from `p` to `q` are surely at least `limit`
/// (≥ 0, with the rounding [`margin`] added) apart, by squared distances. Where the line
/// crosses the arc it says `false`; elsewhere the closest points are an end of either, or the
/// arc's point towards (or away from) the foot of its centre on the line: the only places a
/// distance between the two can be least.
#[inline]
pub fn arc_line_clear(arc: &Elem, r: f64, p: V2, q: V2, limit: f64) -> bool {
    let Elem::Arc { a, b, c, .. } = *arc else {
        return false;
    };
    let l2 = limit * limit;
    // A distance δ from the circle along a radius: |ρ − r| ≥ limit, ρ² given.
    let out = (r + limit) * (r + limit);
    let inside = if r > limit {
        (r - limit) * (r - limit)
    } else {
        -1.0
    };
    let off_circle = |rho2: f64| rho2 >= out || rho2 <= inside;
    let (d, pc) = (q - p, c - p);
    let (t, dd) = (pc.dot(d), d.dot(d));
    if dd > 0.0 {
        let x = pc.cross(d);
        let (foot2, at) = (x * x / dd, t / dd);
        let foot = p + d * at;
        // Where the line meets the circle, on the line and on the arc: they cross.
        let w2 = r * r - foot2;
        if w2 >= 0.0 {
            let h = (w2 / dd).sqrt();
            let crosses = |s: f64| (0.0..=1.0).contains(&s) && in_sweep(arc, p + d * s - c);
            if crosses(at - h) || crosses(at + h) {
                return false;
            }
        }
        // The arc's points towards and away from the foot, where the foot is on the line.
        if at > 0.0 && at < 1.0 {
            let u = foot - c;
            if in_sweep(arc, u) && !off_circle(foot2) {
                return false;
            }
            let far = r + foot2.sqrt();
            if in_sweep(arc, -u) && far * far < l2 {
                return false;
            }
        }
    }
    let end_clear = |x: V2| {
        if in_sweep(arc, x - c) {
            off_circle((x - c).dot(x - c))
        } else {
            (x - a).dot(x - a) >= l2 && (x - b).dot(x - b) >= l2
        }
    };
    end_clear(p) && end_clear(q) && point_seg_sq(a, p, d) >= l2 && point_seg_sq(b, p, d) >= l2
}

/// Whether a path piece and an element are surely at least `limit` (≥ 0, with the rounding
/// [`margin`] added) apart by a few products: the tests that settle a tool-centre path against
/// the elements beside its own block. Two lines by [`lines_clear`]; an arc and a line by the
/// arc's disc apart from the line, or by the arc lying behind an end of the line
/// ([`arc_behind_clear`]: how the path goes round a corner against the elements that meet
/// there, and how an element arc leaves a path line's end); two circles apart or one inside
/// the other. `false` says nothing.
#[inline]
pub fn circles_clear(path: &Measured, other: &Elem, limit: f64) -> bool {
    let behind = |arc: &Elem, rho: f64, p: V2, q: V2| {
        arc_behind_clear(arc, rho, p, q - p, limit) || arc_behind_clear(arc, rho, q, p - q, limit)
    };
    // Matched by reference: a copy of the two elements costs more than most of the tests.
    match (&path.e, other) {
        (&Elem::Line { a, b }, &Elem::Line { a: p, b: q }) => lines_clear(a, b, p, q, limit),
        (&Elem::Arc { c, .. }, &Elem::Line { a: p, b: q }) => {
            // Behind an end only as a corner: about that end (a trimmed arc at an inner
            // corner is left to the fence).
            let about = |p: V2, q: V2| c == p && arc_behind_clear(&path.e, path.r, p, q - p, limit);
            let reach = path.r + limit;
            point_seg_sq(c, p, q - p) >= reach * reach || about(p, q) || about(q, p)
        }
        (&Elem::Line { a, b }, &Elem::Arc { a: s, c, .. }) => {
            let rho = s.dist(c);
            let (out, inner) = (rho + limit, rho - limit);
            let far = (a - c).dot(a - c).max((b - c).dot(b - c));
            point_seg_sq(c, a, b - a) >= out * out
                || inner > 0.0 && far <= inner * inner
                || behind(other, rho, a, b)
        }
        (&Elem::Arc { c, .. }, &Elem::Arc { a, c: c2, .. }) => {
            let (r1, r2, d) = (path.r, a.dist(c2), c.dist(c2));
            let (small, big) = (r1.min(r2), r1.max(r2));
            d >= r1 + r2 + limit || d + small + limit <= big
        }
    }
}

/// Whether an arc (radius `rho`) and the line from `p` to `p + u` are at least `limit` (≥ 0)
/// apart because the arc lies behind `p` along `u`. A point of the arc is at least the arc's
/// distance d from `p`, and that is its distance from the line while it lies behind `p`;
/// reaching ahead of `p` by t, it comes to √(d² − t²). t² may take half the room d² − limit²
/// (the rest is for rounding). The arc reaches farthest along `u` at an end, or where its
/// sweep holds `u`'s direction. An end off the circle says `false`.
#[inline]
pub fn arc_behind_clear(arc: &Elem, rho: f64, p: V2, u: V2, limit: f64) -> bool {
    let Elem::Arc { a, b, c, .. } = *arc else {
        return false;
    };
    let (wa, wb, w) = (a - c, b - c, p - c);
    let on_circle = (wb.dot(wb) - rho * rho).abs() <= 1e-9 * rho * rho;
    let ahead = if in_sweep(arc, u) {
        rho * u.len()
    } else {
        wa.dot(u).max(wb.dot(u))
    };
    let t = (ahead - w.dot(u)).max(0.0);
    // The arc's distance from `p` as `dist_point` takes it: its circle's where the sweep holds
    // `p`'s direction, and its two ends (an end may lie off the circle by rounding).
    let ends = (p - a).dot(p - a).min((p - b).dot(p - b));
    let d2 = if in_sweep(arc, w) {
        let off = w.len() - rho;
        ends.min(off * off)
    } else {
        ends
    };
    let room = d2 - limit * limit;
    on_circle && limit >= 0.0 && room > 0.0 && t * t <= 0.5 * room * u.dot(u)
}

/// [`clear_by_ends`] with the path measured and the element's fence worked out beforehand
/// (`fence` is `Fence::new(other)`): the bottleneck window's hot path.
#[inline]
pub fn clear_by_ends_of(path: &Measured, other: &Elem, fence: &Fence, limit: f64) -> bool {
    let (a, b) = (other.start(), other.end());
    let limit = limit.max(0.0) + 4.0 * fence.eta;
    match fence.shape {
        FenceShape::Line {
            d,
            len,
            tol,
            ad,
            bd,
        } => {
            let (lo, hi) = extent(path, d, len);
            if hi - ad <= tol {
                at_least(path, a, limit)
            } else if lo - bd >= -tol {
                at_least(path, b, limit)
            } else {
                false
            }
        }
        FenceShape::Arc {
            ts,
            te,
            ts_len,
            te_len,
            tol,
            cts,
            cte,
            centre,
        } => {
            let Elem::Arc { c, .. } = *other else {
                return false;
            };
            let beyond_end = extent(path, te, te_len).0 - cte >= -tol;
            let before_start = || extent(path, ts, ts_len).1 - cts <= tol;
            (beyond_end || before_start())
                && at_least(path, c, centre)
                && at_least(path, a, limit)
                && at_least(path, b, limit)
        }
        FenceShape::Never => false,
    }
}

#[cfg(test)]
mod clear_tests {
    use super::*;
    use proptest::prelude::*;

    fn line(a: (f64, f64), b: (f64, f64)) -> Elem {
        Elem::Line {
            a: v2(a.0, a.1),
            b: v2(b.0, b.1),
        }
    }

    #[test]
    fn tangent_serpentine_neighbours_are_shown_clear() {
        // Row along +X from (0,0) to (50,0), then a G2 half circle r = 12 about (50,-12),
        // tool left (G41) at R = 10: the arc's path (r 22) and the row's path (Y = 10).
        let row = line((0.0, 0.0), (50.0, 0.0));
        let arc = Elem::Arc {
            a: v2(50.0, 0.0),
            b: v2(50.0, -24.0),
            c: v2(50.0, -12.0),
            ccw: false,
        };
        let row_path = row.offset(10.0).unwrap();
        let arc_path = arc.offset(10.0).unwrap();
        assert!(clear_by_ends(&arc_path, &row, 10.0 - 1e-9));
        assert!(clear_by_ends(&row_path, &arc, 10.0 - 1e-9));
        // The next row goes back along Y = -24 with the tool inside the next bend: its path
        // at Y = -14 against the half circle it leaves.
        let back = line((50.0, -24.0), (0.0, -24.0));
        assert!(clear_by_ends(
            &back.offset(10.0).unwrap(),
            &arc,
            10.0 - 1e-9
        ));
    }

    #[test]
    fn a_path_too_close_is_never_shown_clear() {
        let row = line((0.0, 0.0), (50.0, 0.0));
        // A path 9 mm from the row's end, beyond it.
        let p = line((50.0, 9.0), (60.0, 9.0));
        assert!(!clear_by_ends(&p, &row, 10.0 - 1e-9));
        assert!(clear_by_ends(&p, &row, 9.0 - 1e-9));
        // Over the middle of the row: the nearest point is not an end, not shown.
        let q = line((20.0, 12.0), (30.0, 12.0));
        assert!(!clear_by_ends(&q, &row, 10.0));
        assert!(dist_elems(&q, &row) >= 10.0);
    }

    fn elem() -> impl Strategy<Value = Elem> {
        let p = || (-20.0..20.0f64, -20.0..20.0f64).prop_map(|(x, y)| v2(x, y));
        prop_oneof![
            (p(), p()).prop_map(|(a, b)| Elem::Line { a, b }),
            (p(), 0.5..15.0f64, -3.2..3.2f64, 0.05..6.2f64, any::<bool>()).prop_map(
                |(c, r, t0, s, ccw)| {
                    let t1 = if ccw { t0 + s } else { t0 - s };
                    Elem::Arc {
                        a: c + V2::from_angle(t0) * r,
                        b: c + V2::from_angle(t1) * r,
                        c,
                        ccw,
                    }
                }
            ),
        ]
    }

    #[test]
    fn a_corner_arc_is_shown_clear_of_the_lines_that_meet_it_at_its_centre() {
        // A convex corner at P = (0,0): along +X, then down -Y; tool left at R = 10 goes
        // round P clockwise from (0,10) to (10,0). Both lines are exactly R from the arc.
        let arc = Measured::new(Elem::Arc {
            a: v2(0.0, 10.0),
            b: v2(10.0, 0.0),
            c: v2(0.0, 0.0),
            ccw: false,
        });
        let (first, second) = (
            line((-50.0, 0.0), (0.0, 0.0)),
            line((0.0, 0.0), (0.0, -50.0)),
        );
        let limit = 10.0 - 1e-9;
        assert!(circles_clear(&arc, &first, limit));
        assert!(circles_clear(&arc, &second, limit));
        // Exactly R is no more than R: the arc touches both.
        assert!(!circles_clear(&arc, &second, 10.0));
        // A line that leaves P into the arc's side comes closer.
        let into = line((0.0, 0.0), (30.0, 30.0));
        assert!(!circles_clear(&arc, &into, limit));
        assert!(dist_elems(&arc.e, &into) < 1e-9);
        // Leaving P just ahead of the arc's end by 1e-3 rad: 10·(1 − cos 1e-3) = 5e-6 closer.
        let (s, c) = (1e-3f64.sin(), 1e-3f64.cos());
        let ahead = line((0.0, 0.0), (40.0 * s, -40.0 * c));
        assert!(!circles_clear(&arc, &ahead, limit));
        assert!(circles_clear(&arc, &ahead, limit - 1e-5));
    }

    #[test]
    fn an_arc_end_off_its_circle_counts_where_it_lies() {
        // A quarter circle about the origin whose end lies 4e-9 inside its circle (within
        // rounding), and a line leaving (0,5) away from it: the end, not the circle, is nearest.
        let arc = Elem::Arc {
            a: v2(10.0, 0.0),
            b: v2(0.0, 10.0 - 4e-9),
            c: v2(0.0, 0.0),
            ccw: true,
        };
        let (p, u) = (v2(0.0, 5.0), v2(-3.0, -3.0));
        let line = Elem::Line { a: p, b: p + u };
        assert!(dist_elems(&arc, &line) < 5.0 - 3e-9);
        assert!(!arc_behind_clear(&arc, 10.0, p, u, 5.0 - 2e-9));
        assert!(arc_behind_clear(&arc, 10.0, p, u, 5.0 - 8e-9));
    }

    /// An arc about `p` of less than a half turn, and a line from `p`.
    fn corner() -> impl Strategy<Value = (Elem, Elem)> {
        (
            point(),
            0.5..15.0f64,
            -3.2..3.2f64,
            0.01..3.1f64,
            any::<bool>(),
            -3.2..3.2f64,
            0.0..30.0f64,
        )
            .prop_map(|(p, r, t0, s, ccw, phi, len)| {
                let t1 = if ccw { t0 + s } else { t0 - s };
                let arc = Elem::Arc {
                    a: p + V2::from_angle(t0) * r,
                    b: p + V2::from_angle(t1) * r,
                    c: p,
                    ccw,
                };
                (
                    arc,
                    Elem::Line {
                        a: p,
                        b: p + V2::from_angle(phi) * len,
                    },
                )
            })
    }

    /// `limit` with the cheap tests' rounding margin for the pair.
    fn sure(limit: f64, path: &Elem, other: &Elem) -> f64 {
        limit + margin(&Measured::new(*path), eta_of(other))
    }

    fn point() -> impl Strategy<Value = V2> {
        (-20.0..20.0f64, -20.0..20.0f64).prop_map(|(x, y)| v2(x, y))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        /// Two lines shown clear are as far apart as the exact distance says, and two that
        /// do not cross and lie clearly farther apart than the limit are shown clear.
        #[test]
        fn lines_clear_agrees_with_the_exact_distance(
            a in point(), b in point(), p in point(), q in point(), limit in 0.0..12.0f64
        ) {
            let (path, other) = (Elem::Line { a, b }, Elem::Line { a: p, b: q });
            let d = dist_elems(&path, &other);
            if lines_clear(a, b, p, q, sure(limit, &path, &other)) {
                prop_assert!(d >= limit, "{a:?} {b:?} {p:?} {q:?} limit {limit} dist {d}");
            } else {
                prop_assert!(d <= limit * (1.0 + 1e-6) + 1e-9, "{a:?} {b:?} {p:?} {q:?} limit {limit} dist {d}");
            }
        }

        /// A pair shown clear by its circles is as far apart as the exact distance says.
        #[test]
        fn circles_clear_agrees_with_the_exact_distance(
            p in elem(), o in elem(), limit in 0.0..12.0f64
        ) {
            if circles_clear(&Measured::new(p), &o, sure(limit, &p, &o)) {
                let d = dist_elems(&p, &o);
                prop_assert!(d >= limit, "{p:?} {o:?} limit {limit} dist {d}");
            }
        }

        /// An arc about a line's end shown clear of it is; one that stays behind the line's
        /// start by a clear angle is shown clear at just under its radius, either way round.
        #[test]
        fn a_corner_arc_is_shown_clear_where_it_is((arc, l) in corner(), below in 1e-10..0.5f64) {
            let Elem::Arc { a, b, c, .. } = arc else { unreachable!() };
            let r = a.dist(c);
            let limit = r * (1.0 - below);
            let d = dist_elems(&arc, &l);
            let back = Elem::Line { a: l.end(), b: l.start() };
            for other in [l, back] {
                if circles_clear(&Measured::new(arc), &other, sure(limit, &arc, &other)) {
                    prop_assert!(d >= limit, "{arc:?} {other:?} limit {limit} dist {d}");
                }
            }
            let u = l.end() - l.start();
            let behind = |w: V2| w.dot(u) <= -0.01 * r * u.len();
            if u.len() > 1e-3 && behind(a - c) && behind(b - c) && !in_sweep(&arc, u) {
                for other in [l, back] {
                    prop_assert!(circles_clear(&Measured::new(arc), &other, sure(limit, &arc, &other)));
                }
            }
        }

        /// A line that ends near where an arc starts (a path line beside the next block's
        /// element), shown clear, is as far apart as the exact distance says.
        #[test]
        fn a_line_beside_an_arcs_start_is_clear_where_shown(
            arc in elem(), r in 0.5..12.0f64, dir in -3.2..3.2f64, back in -3.2..3.2f64,
            len in 0.0..30.0f64, below in 1e-10..0.5f64
        ) {
            let end = arc.start() + V2::from_angle(dir) * r;
            let path = Elem::Line { a: end + V2::from_angle(back) * len, b: end };
            let limit = r * (1.0 - below);
            if circles_clear(&Measured::new(path), &arc, sure(limit, &path, &arc)) {
                let d = dist_elems(&path, &arc);
                prop_assert!(d >= limit, "{path:?} {arc:?} limit {limit} dist {d}");
            }
        }

        /// An arc and a line shown clear are as far apart as the exact distance says, and
        /// ones clearly farther apart than the limit are shown clear; two arcs shown clear by
        /// their circles are clear.
        #[test]
        fn arcs_clear_agrees_with_the_exact_distance(
            p in elem(), o in elem(), limit in 0.0..12.0f64
        ) {
            let d = dist_elems(&p, &o);
            let clear = arcs_clear(&Measured::new(p), &o, sure(limit, &p, &o));
            if clear {
                prop_assert!(d >= limit, "{p:?} {o:?} limit {limit} dist {d}");
            } else if matches!((p, o), (Elem::Arc { .. }, Elem::Line { .. }) | (Elem::Line { .. }, Elem::Arc { .. })) {
                prop_assert!(d <= limit * (1.0 + 1e-6) + 1e-9, "{p:?} {o:?} limit {limit} dist {d}");
            }
        }

        /// Never "clear" when the exact distance says otherwise.
        #[test]
        fn shown_clear_means_clear(p in elem(), o in elem(), limit in 0.0..12.0f64) {
            if clear_by_ends(&p, &o, limit) {
                prop_assert!(dist_elems(&p, &o) >= limit - 1e-9,
                    "{p:?} {o:?} limit {limit} dist {}", dist_elems(&p, &o));
            }
        }

    }

    /// Paths beside an element they share an end with, tangent or at a corner, both sides,
    /// lines and arcs: a path (the equidistant of the next element), the element, the radius.
    fn shared_corner_cases() -> Vec<(Elem, Elem, f64)> {
        let mut cases = Vec::new();
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move |lo: f64, hi: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
        };
        for i in 0..40_000 {
            let c = v2(rnd(-20.0, 20.0), rnd(-20.0, 20.0));
            let o = if i % 2 == 0 {
                Elem::Line {
                    a: c,
                    b: v2(rnd(-20.0, 20.0), rnd(-20.0, 20.0)),
                }
            } else {
                let (r, t0, s) = (rnd(0.5, 15.0), rnd(-3.2, 3.2), rnd(0.05, 3.1));
                let ccw = i % 4 == 1;
                let t1 = if ccw { t0 + s } else { t0 - s };
                Elem::Arc {
                    a: c + V2::from_angle(t0) * r,
                    b: c + V2::from_angle(t1) * r,
                    c,
                    ccw,
                }
            };
            let v = o.end();
            // Tangent in a quarter of the cases.
            let turn = if i % 8 < 2 { 0.0 } else { rnd(-3.0, 3.0) };
            let dir = V2::from_angle(o.tangent_end().angle() + turn);
            let next = if (i / 2) % 2 == 0 {
                let (rr, sweep, ccw) = (rnd(0.5, 15.0), rnd(0.05, 3.1), i % 3 == 0);
                let n = if ccw { dir.left() } else { -dir.left() };
                let cc = v + n * rr;
                let t0 = (v - cc).angle();
                let t1 = if ccw { t0 + sweep } else { t0 - sweep };
                Elem::Arc {
                    a: v,
                    b: cc + V2::from_angle(t1) * rr,
                    c: cc,
                    ccw,
                }
            } else {
                Elem::Line {
                    a: v,
                    b: v + dir * rnd(0.1, 30.0),
                }
            };
            let r = rnd(0.1, 12.0);
            let Some(path) = next.offset(if i % 5 < 2 { r } else { -r }) else {
                continue;
            };
            cases.push((path, o, r));
        }
        cases
    }

    /// Paths sharing an end with the element: never wrong, and shown clear often (where it
    /// saves the exact distance).
    #[test]
    fn shown_clear_at_shared_corners() {
        let cases = shared_corner_cases();
        let mut shown = 0;
        for (path, o, r) in &cases {
            if clear_by_ends(path, o, r - 1e-9) {
                shown += 1;
                let d = dist_elems(path, o);
                assert!(d >= r - 2e-9, "{path:?} {o:?} r {r} dist {d}");
            }
        }
        assert!(
            cases.len() > 30_000 && shown * 4 > cases.len(),
            "shown clear {shown} of {}",
            cases.len()
        );
    }

    /// A path line whose end lies at exactly the tool radius from the next element (an outer
    /// corner) is shown clear against the gouge tolerance, near the origin and kilometres
    /// out: the rounding margin stays below the tolerance.
    #[test]
    fn a_neighbour_at_exactly_the_radius_is_shown_clear() {
        for x0 in [0.0, 1234.5, 5.6e6] {
            let r = 10.0;
            let (a, b) = (v2(x0 - 28.0, 3.0 + r), v2(x0, 3.0 + r));
            let (p, q) = (v2(x0, 3.0), v2(x0 + 20.0, -15.0));
            let (path, next) = (Elem::Line { a, b }, Elem::Line { a: p, b: q });
            let tol = 1e-9f64.max(1e-12 * x0);
            assert!(
                lines_clear(a, b, p, q, sure(r - tol, &path, &next)),
                "at {x0}"
            );
            assert!(dist_elems(&path, &next) >= r - tol);
        }
    }

    /// The same pairs where one is an arc: the arcs' test is never wrong either, and shows
    /// most of those the ends' test leaves clear.
    #[test]
    fn arcs_shown_clear_at_shared_corners() {
        let (mut left, mut shown) = (0, 0);
        for (path, o, r) in shared_corner_cases() {
            let limit = r - 1e-9;
            let d = dist_elems(&path, &o);
            if arcs_clear(&Measured::new(path), &o, sure(limit, &path, &o)) {
                assert!(d >= limit, "{path:?} {o:?} r {r} dist {d}");
                shown += 1;
            }
            let arc = matches!(path, Elem::Arc { .. }) || matches!(o, Elem::Arc { .. });
            if arc && !clear_by_ends(&path, &o, limit) && d > limit * (1.0 + 1e-6) {
                left += 1;
            }
        }
        assert!(
            shown * 10 > left * 9,
            "shown clear {shown}, left by the ends' test {left}"
        );
    }
}
