//! A prepared segment as the interpolator sees it: its length, the point at a distance along
//! it, and its tangent and curvature at both ends (for the corner limits).
//!
//! Lines, arcs, helices (an arc with a move along the plane's normal) and the arcs of the TRC
//! core whose radius changes over the block (r0 → r1) or whose centre moves (a turning
//! tool's cutting edge changing, prep/tool_tip.rs) are one parametrisation: with u = s/len,
//! angle θ0 + u·sweep, radius r0 + u·(r1 − r0), centre c0 + u·(c1 − c0), normal coordinate
//! h0 + u·(h1 − h0). Every setpoint is a point of that curve, computed directly (no chords);
//! the end points are the segment's own.

use crate::frontend::block::{Plane, Pos};
use crate::segment::{Segment, Shape};

pub type V3 = [f64; 3];

#[derive(Clone, Copy, Debug)]
enum Geo {
    Line {
        d: V3,
    },
    Arc {
        plane: Plane,
        c0: [f64; 2],
        dc: [f64; 2],
        r0: f64,
        dr: f64,
        th0: f64,
        sweep: f64,
        h0: f64,
        dh: f64,
    },
}

/// A segment ready for interpolation.
#[derive(Clone, Copy, Debug)]
pub struct Piece {
    pub seg: Segment,
    /// Path length, mm.
    pub len: f64,
    geo: Geo,
    /// Unit tangents at the start and the end.
    pub tangent: [V3; 2],
    /// Curvature vectors (1/mm, towards the centre) at the start and the end.
    pub curvature: [V3; 2],
    /// Largest ratio of the axes' speed to the path speed along the parametrisation (1 for
    /// lines, circles and helices; a little more where the radius or the centre moves).
    pub stretch: f64,
    /// Largest curvature, 1/mm (0 for lines).
    pub kappa: f64,
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

const TAU: f64 = std::f64::consts::TAU;

impl Piece {
    /// `None` for a segment without length (nothing to interpolate).
    pub fn new(seg: &Segment) -> Option<Piece> {
        match seg.shape {
            Shape::Line => {
                let d = sub(seg.to, seg.from);
                let len = norm(d);
                if len.is_nan() || len <= 0.0 {
                    return None;
                }
                let t = scale(d, 1.0 / len);
                Some(Piece {
                    seg: *seg,
                    len,
                    geo: Geo::Line { d },
                    tangent: [t, t],
                    curvature: [[0.0; 3]; 2],
                    stretch: 1.0,
                    kappa: 0.0,
                })
            }
            Shape::Arc {
                center,
                center_end,
                ccw,
                plane,
                ..
            } => {
                let (ia, io, ino) = (
                    plane.abscissa as usize,
                    plane.ordinate as usize,
                    plane.normal as usize,
                );
                let c0 = [center[ia], center[io]];
                let c1 = [center_end[ia], center_end[io]];
                let (fa, fo) = (seg.from[ia] - c0[0], seg.from[io] - c0[1]);
                let (ta, to) = (seg.to[ia] - c1[0], seg.to[io] - c1[1]);
                // The radii from the end points themselves: the end is the segment's own.
                let r0 = (fa * fa + fo * fo).sqrt();
                let r1 = (ta * ta + to * to).sqrt();
                if r0.is_nan() || r1.is_nan() || r0 <= 0.0 || r1 <= 0.0 {
                    return None;
                }
                let th0 = libm::atan2(fo, fa);
                let th1 = libm::atan2(to, ta);
                let full = seg.from[ia] == seg.to[ia] && seg.from[io] == seg.to[io];
                let mut sweep = if ccw { th1 - th0 } else { th0 - th1 };
                if full {
                    sweep = TAU;
                } else if sweep < 0.0 {
                    sweep += TAU;
                    // An arc whose ends differ only by rounding is not a full circle.
                    if sweep >= TAU {
                        sweep = 0.0;
                    }
                }
                let sweep = if ccw { sweep } else { -sweep };
                let geo = Geo::Arc {
                    plane,
                    c0,
                    dc: [c1[0] - c0[0], c1[1] - c0[1]],
                    r0,
                    dr: r1 - r0,
                    th0,
                    sweep,
                    h0: seg.from[ino],
                    dh: seg.to[ino] - seg.from[ino],
                };
                let mut p = Piece {
                    seg: *seg,
                    len: 0.0,
                    geo,
                    tangent: [[0.0; 3]; 2],
                    curvature: [[0.0; 3]; 2],
                    stretch: 1.0,
                    kappa: 1.0 / r0.min(r1),
                };
                let uniform = r0 == r1 && c0 == c1;
                let len = if uniform {
                    let h = seg.to[ino] - seg.from[ino];
                    ((r0 * sweep) * (r0 * sweep) + h * h).sqrt()
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
                        sum += w * norm(p.derivatives(k as f64 / N as f64).0);
                    }
                    sum / (3.0 * N as f64)
                };
                if len.is_nan() || len <= 0.0 {
                    return None;
                }
                p.len = len;
                if !uniform {
                    let mut most: f64 = 0.0;
                    for k in 0..=64 {
                        most = most.max(norm(p.derivatives(k as f64 / 64.0).0));
                    }
                    p.stretch = (most / len).max(1.0);
                }
                for (end, u) in [(0, 0.0), (1, 1.0)] {
                    let (d1, d2) = p.derivatives(u);
                    let speed = norm(d1);
                    let t = scale(d1, 1.0 / speed);
                    p.tangent[end] = t;
                    p.curvature[end] = scale(sub(d2, scale(t, dot(d2, t))), 1.0 / (speed * speed));
                }
                Some(p)
            }
        }
    }

    /// dP/du and d²P/du² of an arc (u = s/len).
    fn derivatives(&self, u: f64) -> (V3, V3) {
        let Geo::Arc {
            plane,
            dc,
            r0,
            dr,
            th0,
            sweep,
            dh,
            ..
        } = self.geo
        else {
            return (sub(self.seg.to, self.seg.from), [0.0; 3]);
        };
        let th = th0 + sweep * u;
        let (sn, cs) = (libm::sin(th), libm::cos(th));
        let r = r0 + dr * u;
        let mut d1 = [0.0; 3];
        let mut d2 = [0.0; 3];
        let (ia, io, ino) = (
            plane.abscissa as usize,
            plane.ordinate as usize,
            plane.normal as usize,
        );
        // P = c + r·e(θ); e' = sweep·e⊥, e⊥' = −sweep·e.
        d1[ia] = dc[0] + dr * cs - r * sweep * sn;
        d1[io] = dc[1] + dr * sn + r * sweep * cs;
        d1[ino] = dh;
        d2[ia] = -2.0 * dr * sweep * sn - r * sweep * sweep * cs;
        d2[io] = 2.0 * dr * sweep * cs - r * sweep * sweep * sn;
        (d1, d2)
    }

    /// The point at distance `s` along the segment (clamped to it); the ends exactly.
    pub fn point(&self, s: f64) -> Pos {
        if s <= 0.0 {
            return self.seg.from;
        }
        if s >= self.len {
            return self.seg.to;
        }
        let u = s / self.len;
        match self.geo {
            Geo::Line { d } => [
                self.seg.from[0] + d[0] * u,
                self.seg.from[1] + d[1] * u,
                self.seg.from[2] + d[2] * u,
            ],
            Geo::Arc {
                plane,
                c0,
                dc,
                r0,
                dr,
                th0,
                sweep,
                h0,
                dh,
            } => {
                let th = th0 + sweep * u;
                let r = r0 + dr * u;
                let mut p = self.seg.from;
                p[plane.abscissa as usize] = c0[0] + dc[0] * u + r * libm::cos(th);
                p[plane.ordinate as usize] = c0[1] + dc[1] * u + r * libm::sin(th);
                p[plane.normal as usize] = h0 + dh * u;
                p
            }
        }
    }

    /// The plane and sweep of an arc (for tests and the corner limits).
    pub fn arc(&self) -> Option<(Plane, f64)> {
        match self.geo {
            Geo::Arc { plane, sweep, .. } => Some((plane, sweep)),
            Geo::Line { .. } => None,
        }
    }

    /// Share of the path speed along the plane's normal (a helix's lead).
    pub fn normal_share(&self) -> f64 {
        match self.geo {
            Geo::Arc { dh, .. } => (dh / self.len).abs(),
            Geo::Line { .. } => 0.0,
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::segment::{Role, Source};

    /// A contour segment at F1000 for the tests of this stage.
    pub(crate) fn seg(from: Pos, to: Pos, shape: Shape) -> Segment {
        Segment {
            source: Source {
                number: None,
                line: 1,
                col: 1,
                seq: 1,
            },
            role: Role::Contour,
            shape,
            from,
            to,
            feed: 1000.0,
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
