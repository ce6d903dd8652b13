//! A prepared segment as the interpolator sees it: its length, the point at a distance along
//! it, and its tangent and curvature at both ends (for the corner limits).
//!
//! Lines, arcs, helices (an arc with a move along the plane's normal) and the arcs of the TRC
//! core whose radius changes over the block (r0 → r1) or whose centre moves (a turning
//! tool's cutting edge changing, prep/tool_tip.rs) are one parametrisation, the segment's
//! [`Curve`], with u = s/len. Every setpoint is a point of that curve, computed directly
//! (no chords); the end points are the segment's own.
//!
//! Additional axes (U V W A B C) move linearly in u beside the curve, and the path length
//! counts them: len = √(curve length² + Σ Δ²), degrees of a rotary axis as mm (the feed
//! applies over all axes, docs/ipo.md).

use crate::frontend::block::{Additional, AxisMove, AxisPos, Plane, Pos, ADDITIONAL};
use crate::segment::{Curve, Segment};

pub type V3 = [f64; 3];

/// A segment ready for interpolation.
#[derive(Clone, Copy, Debug)]
pub struct Piece {
    pub seg: Segment,
    /// Path length, mm.
    pub len: f64,
    curve: Curve,
    /// Unit tangents at the start and the end.
    pub tangent: [V3; 2],
    /// Curvature vectors (1/mm, towards the centre) at the start and the end.
    pub curvature: [V3; 2],
    /// Largest ratio of the axes' speed to the curve's speed along the parametrisation (1
    /// for lines, circles and helices; a little more where the radius or the centre moves).
    pub stretch: f64,
    /// Largest curvature, 1/mm (0 for lines).
    pub kappa: f64,
    /// The curve's share of the path speed, L/len (1 without additional axes moving).
    pub curve_share: f64,
    /// The additional axes at the start and the end, and each one's share of the path speed
    /// (signed; constant over the segment).
    pub add_from: Additional,
    pub add_to: Additional,
    pub add_dir: Additional,
}

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn norm(a: V3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
fn scale(a: V3, k: f64) -> V3 {
    [a[0] * k, a[1] * k, a[2] * k]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Piece {
    /// `None` for a segment without length (nothing to interpolate); the additional axes at 0.
    pub fn new(seg: &Segment) -> Option<Piece> {
        Piece::with_axes(seg, None, &[0.0; ADDITIONAL])
    }

    /// As [`Piece::new`], with the additional axes' move `axes` beside the segment; without
    /// one they stand at `at`.
    pub fn with_axes(seg: &Segment, axes: Option<&AxisMove>, at: &Additional) -> Option<Piece> {
        let curve = Curve::new(seg)?;
        let mut p = Piece {
            seg: *seg,
            len: 0.0,
            curve,
            tangent: [[0.0; 3]; 2],
            curvature: [[0.0; 3]; 2],
            stretch: 1.0,
            kappa: 0.0,
            curve_share: 1.0,
            add_from: axes.map_or(*at, |m| m.from),
            add_to: axes.map_or(*at, |m| m.to),
            add_dir: [0.0; ADDITIONAL],
        };
        p.measure_curve()?;
        p.add_additional();
        (p.len > 0.0).then_some(p)
    }

    /// Length, tangents and curvatures of the curve alone; `None` for a length that is not
    /// a number.
    fn measure_curve(&mut self) -> Option<()> {
        let (seg, curve) = (self.seg, self.curve);
        let p = self;
        let Curve::Arc {
            r0,
            dr,
            dc,
            sweep,
            dh,
            ..
        } = curve
        else {
            let d = sub(seg.to, seg.from);
            p.len = norm(d);
            if p.len.is_nan() {
                return None;
            }
            if p.len > 0.0 {
                let t = scale(d, 1.0 / p.len);
                p.tangent = [t, t];
            }
            return Some(());
        };
        let r1 = r0 + dr;
        p.kappa = 1.0 / r0.min(r1);
        let uniform = dr == 0.0 && dc == [0.0, 0.0];
        p.len = if uniform {
            ((r0 * sweep) * (r0 * sweep) + dh * dh).sqrt()
        } else {
            // Simpson over the speed |dP/du|: the parametrisation is not by length.
            const N: usize = 64;
            let mut sum = 0.0;
            for k in 0..=N {
                let w = if k == 0 || k == N {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                sum += w * norm(curve.derivatives(k as f64 / N as f64).0);
            }
            sum / (3.0 * N as f64)
        };
        if p.len.is_nan() || p.len <= 0.0 {
            return None;
        }
        if !uniform {
            let mut most: f64 = 0.0;
            for k in 0..=64 {
                most = most.max(norm(curve.derivatives(k as f64 / 64.0).0));
            }
            p.stretch = (most / p.len).max(1.0);
        }
        for (end, u) in [(0, 0.0), (1, 1.0)] {
            let (d1, d2) = curve.derivatives(u);
            let speed = norm(d1);
            let t = scale(d1, 1.0 / speed);
            p.tangent[end] = t;
            p.curvature[end] = scale(sub(d2, scale(t, dot(d2, t))), 1.0 / (speed * speed));
        }
        Some(())
    }

    /// The additional axes into the length: with k = curve length / path length the
    /// curve's tangents scale by k, its curvatures by k² (d²P/ds² = κ·(ds_curve/ds)²).
    fn add_additional(&mut self) {
        if self.add_from == self.add_to {
            return;
        }
        let mut sq = self.len * self.len;
        for (a, b) in self.add_from.iter().zip(&self.add_to) {
            sq += (b - a) * (b - a);
        }
        let len = sq.sqrt();
        if len.is_nan() || len <= 0.0 {
            return;
        }
        let k = self.len / len;
        for i in 0..ADDITIONAL {
            self.add_dir[i] = (self.add_to[i] - self.add_from[i]) / len;
        }
        for end in 0..2 {
            self.tangent[end] = scale(self.tangent[end], k);
            self.curvature[end] = scale(self.curvature[end], k * k);
        }
        self.curve_share = k;
        self.kappa *= k * k;
        self.len = len;
    }

    /// The point at distance `s` along the segment (clamped to it); the ends exactly.
    pub fn point(&self, s: f64) -> Pos {
        if s <= 0.0 {
            return self.seg.from;
        }
        if s >= self.len {
            return self.seg.to;
        }
        self.curve.point(s / self.len)
    }

    /// Every axis at distance `s` along the segment; the ends exactly.
    pub fn axes_at(&self, s: f64) -> AxisPos {
        if s <= 0.0 {
            return AxisPos {
                geo: self.seg.from,
                add: self.add_from,
            };
        }
        if s >= self.len {
            return AxisPos {
                geo: self.seg.to,
                add: self.add_to,
            };
        }
        let mut add = self.add_from;
        for (x, d) in add.iter_mut().zip(&self.add_dir) {
            *x += d * s;
        }
        AxisPos {
            geo: self.curve.point(s / self.len),
            add,
        }
    }

    /// The plane of an arc; `None` for a line.
    pub fn plane(&self) -> Option<Plane> {
        match self.curve {
            Curve::Arc { plane, .. } => Some(plane),
            Curve::Line { .. } => None,
        }
    }

    /// Share of the path speed along the plane's normal (a helix's lead).
    pub fn normal_share(&self) -> f64 {
        match self.curve {
            Curve::Arc { dh, .. } => (dh / self.len).abs(),
            Curve::Line { .. } => 0.0,
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::segment::{Role, Shape, Source};

    /// A contour segment at F1000 for the tests of this stage.
    pub(crate) fn seg(from: Pos, to: Pos, shape: Shape) -> Segment {
        Segment {
            source: Source {
                number: None,
                line: 1,
                col: 1,
                seq: 1,
                program: 0,
            },
            role: Role::Contour,
            shape,
            from,
            to,
            feed: 1000.0,
            per_rev: false,
            thread: false,
            rapid: false,
            exact_stop: false,
        }
    }

    fn arc(c: Pos, ccw: bool) -> Shape {
        Shape::Arc {
            center: c,
            center_end: c,
            ccw,
            r0: 0.0,
            r1: 0.0,
            plane: Plane::XY,
        }
    }

    #[test]
    fn a_quarter_circle_by_hand() {
        // (10,0) → (0,10) about the origin, counter-clockwise: length 5π, tangent +Y then −X,
        // curvature 1/10 towards the centre.
        let p = Piece::new(&seg(
            [10.0, 0.0, 0.0],
            [0.0, 10.0, 0.0],
            arc([0.0; 3], true),
        ))
        .unwrap();
        assert!((p.len - 5.0 * std::f64::consts::PI).abs() < 1e-12);
        assert!((p.tangent[0][1] - 1.0).abs() < 1e-15 && (p.tangent[1][0] + 1.0).abs() < 1e-15);
        assert!((p.curvature[0][0] + 0.1).abs() < 1e-15);
        assert!((p.curvature[1][1] + 0.1).abs() < 1e-15);
        let m = p.point(p.len / 2.0);
        let h = 10.0 / 2f64.sqrt();
        assert!((m[0] - h).abs() < 1e-14 && (m[1] - h).abs() < 1e-14);
        assert_eq!(p.point(p.len), [0.0, 10.0, 0.0]);
        // Clockwise the long way round: three quarters.
        let q = Piece::new(&seg(
            [10.0, 0.0, 0.0],
            [0.0, 10.0, 0.0],
            arc([0.0; 3], false),
        ))
        .unwrap();
        assert!((q.len - 15.0 * std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn a_helix_and_a_full_circle() {
        let p = Piece::new(&seg(
            [10.0, 0.0, 0.0],
            [10.0, 0.0, -5.0],
            arc([0.0; 3], true),
        ))
        .unwrap();
        let c = 20.0 * std::f64::consts::PI;
        assert!((p.len - (c * c + 25.0).sqrt()).abs() < 1e-12);
        let m = p.point(p.len / 4.0);
        assert!((m[0]).abs() < 1e-12 && (m[1] - 10.0).abs() < 1e-12 && (m[2] + 1.25).abs() < 1e-12);
        assert!((p.normal_share() - 5.0 / p.len).abs() < 1e-15);
    }

    #[test]
    fn a_radius_change_runs_linearly_with_the_angle() {
        // r 10 → 12 over a half circle about the origin (a radius change spread over the block).
        let p = Piece::new(&seg(
            [10.0, 0.0, 0.0],
            [-12.0, 0.0, 0.0],
            arc([0.0; 3], true),
        ))
        .unwrap();
        let m = p.point(p.len / 2.0);
        assert!((m[0]).abs() < 1e-12 && (m[1] - 11.0).abs() < 1e-12);
        // Uniform in the angle, so faster where the radius is larger: at the end about
        // r1/r̄ = 12/11 of the mean speed.
        assert!((p.stretch - 12.0 / 11.0).abs() < 2e-3, "{}", p.stretch);
        // Its length lies between the two half circles.
        assert!(p.len > 10.0 * std::f64::consts::PI && p.len < 12.0 * std::f64::consts::PI);
    }
}
