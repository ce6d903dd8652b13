//! The programmable frame: a programmed point (workpiece coordinates, before the zero is
//! added) is mapped by an affine map `p ↦ m·p + t`. Two languages build it:
//!
//! - Fanuc (0i-MF "Programmable mirror image", "Scaling", "Coordinate system rotation"):
//!   parts in a fixed order, whatever order they were programmed in — mirrored (G51.1),
//!   scaled (G51), rotated (G68) — rebuilt by [`Frame::update`]:
//!
//!   ```text
//!   p  →  mirror: m_i − (p_i − m_i) on the mirrored axes
//!      →  scale:  c + s·(p − c) per axis (s < 0 mirrors too)
//!      →  rotate: about the centre in the plane of G68, by its angle
//!   ```
//!
//! - SINUMERIK (Fundamentals, "Coordinate transformations (frames)"): a chain in program
//!   order. TRANS, ROT, SCALE, MIRROR replace the map ([`Frame::set`]); ATRANS, AROT,
//!   ASCALE, AMIRROR act in the coordinates the map has made so far ([`Frame::chain`]).
//!
//! The tool radius is never scaled (compensation works on the mapped contour with the
//! table's radius). A map that mirrors the plane an odd number of times turns G02 into G03
//! and G41 into G42, as on both controls. Arcs need a map that keeps their plane and scales
//! both of its axes alike.

use super::block::{Plane, Pos};

/// An affine map of workpiece coordinates, `p ↦ m·p + t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    pub m: [[f64; 3]; 3],
    pub t: Pos,
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Below this a matrix entry counts as 0 (a rotation by 90° leaves cos 90° = 6e-17).
const EPS: f64 = 1e-12;

impl Affine {
    pub const IDENTITY: Affine = Affine {
        m: IDENTITY,
        t: [0.0; 3],
    };

    /// `p ↦ p + v`.
    pub fn translation(v: Pos) -> Affine {
        Affine { m: IDENTITY, t: v }
    }

    /// `p ↦ (s_0·p_0, s_1·p_1, s_2·p_2)` (a factor −1 mirrors that axis).
    pub fn scaling(s: Pos) -> Affine {
        let mut m = IDENTITY;
        for (i, row) in m.iter_mut().enumerate() {
            row[i] = s[i];
        }
        Affine { m, t: [0.0; 3] }
    }

    /// A right-handed rotation by `deg` degrees about axis `k` (X 0, Y 1, Z 2): it turns the
    /// next axis towards the one after (Z: X towards Y; Y: Z towards X; X: Y towards Z), so
    /// about a plane's normal it turns the abscissa towards the ordinate.
    pub fn rotation(k: usize, deg: f64) -> Affine {
        let (a, o) = ((k + 1) % 3, (k + 2) % 3);
        let (sin, cos) = (libm::sin(deg.to_radians()), libm::cos(deg.to_radians()));
        let mut m = IDENTITY;
        m[a][a] = cos;
        m[a][o] = -sin;
        m[o][a] = sin;
        m[o][o] = cos;
        Affine { m, t: [0.0; 3] }
    }

    /// `self` after `inner`: `p ↦ self(inner(p))`.
    pub fn after(&self, inner: &Affine) -> Affine {
        let m = std::array::from_fn(|i| {
            std::array::from_fn(|k| (0..3).map(|j| self.m[i][j] * inner.m[j][k]).sum())
        });
        let v = self.turn(inner.t);
        Affine {
            m,
            t: std::array::from_fn(|i| v[i] + self.t[i]),
        }
    }

    pub fn apply(&self, p: Pos) -> Pos {
        std::array::from_fn(|i| {
            self.m[i][0] * p[0] + self.m[i][1] * p[1] + self.m[i][2] * p[2] + self.t[i]
        })
    }

    /// The linear part alone: a direction, a vector between two points.
    pub fn turn(&self, v: Pos) -> Pos {
        std::array::from_fn(|i| self.m[i][0] * v[0] + self.m[i][1] * v[1] + self.m[i][2] * v[2])
    }

    fn is_identity(&self) -> bool {
        self.m == IDENTITY && self.t == [0.0; 3]
    }
}

/// The frame in force: its map, and Fanuc's parts as programmed.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// G51.1: the mirror axis position per axis, if mirrored.
    pub mirror: [Option<f64>; 3],
    /// G51: the scale factors per axis and the centre.
    pub scale: Option<([f64; 3], Pos)>,
    /// G68: the plane, the centre (in it) and the angle in degrees.
    pub rotation: Option<(Plane, Pos, f64)>,
    map: Affine,
    active: bool,
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            mirror: [None; 3],
            scale: None,
            rotation: None,
            map: Affine::IDENTITY,
            active: false,
        }
    }
}

impl Frame {
    /// Anything but the identity is programmed.
    #[inline(always)]
    pub fn active(&self) -> bool {
        self.active
    }

    /// Fanuc: rebuilds the map from the parts.
    pub fn update(&mut self) {
        let (mut m, mut t) = (IDENTITY, [0.0; 3]);
        for i in 0..3 {
            if let Some(c) = self.mirror[i] {
                // p ↦ 2c − p
                m[i][i] = -1.0;
                t[i] = 2.0 * c;
            }
        }
        if let Some((s, c)) = self.scale {
            for i in 0..3 {
                // p ↦ c + s(p − c) after the mirror
                for v in &mut m[i] {
                    *v *= s[i];
                }
                t[i] = c[i] + s[i] * (t[i] - c[i]);
            }
        }
        if let Some((plane, c, deg)) = self.rotation {
            let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
            let (sin, cos) = (libm::sin(deg.to_radians()), libm::cos(deg.to_radians()));
            let (ra, ro) = (m[a], m[o]);
            for k in 0..3 {
                m[a][k] = cos * ra[k] - sin * ro[k];
                m[o][k] = sin * ra[k] + cos * ro[k];
            }
            let (ta, to) = (t[a] - c[a], t[o] - c[o]);
            t[a] = c[a] + cos * ta - sin * to;
            t[o] = c[o] + sin * ta + cos * to;
        }
        self.set(Affine { m, t });
    }

    /// SINUMERIK TRANS, ROT, SCALE, MIRROR: `map` replaces the frame.
    pub fn set(&mut self, map: Affine) {
        self.map = map;
        self.active = !map.is_identity();
    }

    /// SINUMERIK ATRANS, AROT, ASCALE, AMIRROR: `step` acts first, in the coordinates the
    /// frame has made so far.
    pub fn chain(&mut self, step: &Affine) {
        self.set(self.map.after(step));
    }

    /// A programmed point (workpiece coordinates) in the frame.
    pub fn apply(&self, p: Pos) -> Pos {
        self.map.apply(p)
    }

    /// A direction (a vector between two programmed points) in the frame: its linear part.
    pub fn turn(&self, v: Pos) -> Pos {
        self.map.turn(v)
    }

    /// The programmed point that the frame takes to `q` (a position back into program
    /// terms, for incremental words). `None` if a scale factor is 0.
    pub fn invert(&self, q: Pos) -> Option<Pos> {
        let m = &self.map.m;
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        if det.abs() < 1e-12 {
            return None;
        }
        let d: Pos = std::array::from_fn(|i| q[i] - self.map.t[i]);
        // Cramer's rule: column k replaced by d.
        let col = |k: usize| {
            let mut a = *m;
            for (row, v) in a.iter_mut().zip(d) {
                row[k] = v;
            }
            (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
                - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
                + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
                / det
        };
        Some([col(0), col(1), col(2)])
    }

    /// The frame turns the `plane` over (an odd number of mirrorings in it): G02 ↔ G03,
    /// G41 ↔ G42.
    pub fn flips(&self, plane: Plane) -> bool {
        let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
        let m = &self.map.m;
        m[a][a] * m[o][o] - m[a][o] * m[o][a] < 0.0
    }

    /// The frame maps `plane` onto itself (its normal stays its normal).
    pub fn keeps_plane(&self, plane: Plane) -> bool {
        let (a, o, n) = (
            plane.abscissa as usize,
            plane.ordinate as usize,
            plane.normal as usize,
        );
        let m = &self.map.m;
        [m[n][a], m[n][o], m[a][n], m[o][n]]
            .iter()
            .all(|v| v.abs() < EPS)
    }

    /// The frame leaves axis `n` alone (a hole's depth under a frame in its plane; an axis
    /// the machine does not have).
    pub fn keeps_axis(&self, n: usize) -> bool {
        let m = &self.map.m;
        (0..3).all(|k| {
            m[n][k] == if k == n { 1.0 } else { 0.0 } && m[k][n] == if k == n { 1.0 } else { 0.0 }
        }) && self.map.t[n] == 0.0
    }

    /// The frame maps circles in `plane` to circles: the same scale on both of its axes.
    pub fn keeps_circles(&self, plane: Plane) -> bool {
        self.plane_scale(plane).is_some()
    }

    /// The factor by which the frame scales lengths in `plane`, if it maps the plane onto
    /// itself and its circles to circles (a rotation or a mirror: exactly 1).
    pub fn plane_scale(&self, plane: Plane) -> Option<f64> {
        if !self.keeps_plane(plane) {
            return None;
        }
        let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
        let m = &self.map.m;
        let (la, lo) = (
            m[a][a] * m[a][a] + m[o][a] * m[o][a],
            m[a][o] * m[a][o] + m[o][o] * m[o][o],
        );
        let dot = m[a][a] * m[a][o] + m[o][a] * m[o][o];
        let size = la.max(lo);
        if (la - lo).abs() > EPS * size || dot.abs() > EPS * size {
            return None;
        }
        Some(match self.scale {
            // Fanuc's own factor, exact.
            Some((s, _)) => s[a].abs(),
            None if (la - 1.0).abs() < EPS => 1.0,
            None => la.sqrt(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: Pos, b: Pos) {
        for i in 0..3 {
            assert!((a[i] - b[i]).abs() < 1e-12, "{a:?} != {b:?}");
        }
    }

    #[test]
    fn mirror_then_scale_then_rotate() {
        let mut f = Frame::default();
        f.update();
        assert!(!f.active());
        f.mirror[0] = Some(10.0);
        f.update();
        // X mirrored about 10: 12 ↦ 8.
        near(f.apply([12.0, 3.0, 1.0]), [8.0, 3.0, 1.0]);
        assert!(f.flips(Plane::XY) && !f.flips(Plane::YZ));
        f.mirror[0] = None;
        f.scale = Some(([2.0, 2.0, 1.0], [10.0, 0.0, 0.0]));
        f.rotation = Some((Plane::XY, [10.0, 0.0, 0.0], 90.0));
        f.update();
        // (12, 0) scaled about (10, 0) to (14, 0), rotated 90° about (10, 0) to (10, 4).
        let q = f.apply([12.0, 0.0, 5.0]);
        near(q, [10.0, 4.0, 5.0]);
        near(f.invert(q).unwrap(), [12.0, 0.0, 5.0]);
        assert!(f.keeps_circles(Plane::XY) && !f.keeps_circles(Plane::ZX));
        assert_eq!(f.plane_scale(Plane::XY), Some(2.0));
    }

    #[test]
    fn a_chain_acts_in_program_order() {
        // TRANS X10, AROT RPL=90 (G17), ATRANS X5: the second shift is along the turned X,
        // which is the old +Y: the zero lands at (10, 5). A program point (2, 3): turned to
        // (−3, 2), plus the zero: (7, 7).
        let mut f = Frame::default();
        f.set(Affine::translation([10.0, 0.0, 0.0]));
        f.chain(&Affine::rotation(2, 90.0));
        f.chain(&Affine::translation([5.0, 0.0, 0.0]));
        near(f.apply([0.0, 0.0, 0.0]), [10.0, 5.0, 0.0]);
        near(f.apply([2.0, 3.0, 1.0]), [7.0, 7.0, 1.0]);
        assert!(f.active() && !f.flips(Plane::XY));
        // The same steps the other way round: ATRANS X5 first, then the turn, then X10 along
        // the turned X (+Y): (5, 10).
        let mut g = Frame::default();
        g.set(Affine::translation([5.0, 0.0, 0.0]));
        g.chain(&Affine::rotation(2, 90.0));
        g.chain(&Affine::translation([10.0, 0.0, 0.0]));
        near(g.apply([0.0, 0.0, 0.0]), [5.0, 10.0, 0.0]);
        // MIRROR X0, then AROT RPL=90: the turn acts first, in the mirrored system. (1, 0)
        // turns to (0, 1), which the mirror keeps; (0, 1) turns to (−1, 0), mirrored (1, 0).
        let mut h = Frame::default();
        h.set(Affine::scaling([-1.0, 1.0, 1.0]));
        h.chain(&Affine::rotation(2, 90.0));
        near(h.apply([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0]);
        near(h.apply([0.0, 1.0, 0.0]), [1.0, 0.0, 0.0]);
        assert!(h.flips(Plane::XY) && h.keeps_circles(Plane::XY));
        // Mirrored twice: not turned over. Unequal scale: no circles.
        h.chain(&Affine::scaling([1.0, -1.0, 1.0]));
        assert!(!h.flips(Plane::XY));
        h.chain(&Affine::scaling([2.0, 3.0, 1.0]));
        assert!(!h.keeps_circles(Plane::XY));
        // A turn about X tilts the XY plane and keeps YZ; a turn about Y keeps ZX.
        let mut r = Frame::default();
        r.set(Affine::rotation(0, 30.0));
        assert!(!r.keeps_plane(Plane::XY) && r.keeps_plane(Plane::YZ));
        r.set(Affine::rotation(1, 30.0));
        assert!(r.keeps_plane(Plane::ZX) && r.plane_scale(Plane::ZX) == Some(1.0));
        r.set(Affine::IDENTITY);
        assert!(!r.active());
    }

    #[test]
    fn rotations_turn_the_abscissa_towards_the_ordinate() {
        // Z: X → Y; Y: Z → X; X: Y → Z.
        near(
            Affine::rotation(2, 90.0).apply([1.0, 0.0, 0.0]),
            [0.0, 1.0, 0.0],
        );
        near(
            Affine::rotation(1, 90.0).apply([0.0, 0.0, 1.0]),
            [1.0, 0.0, 0.0],
        );
        near(
            Affine::rotation(0, 90.0).apply([0.0, 1.0, 0.0]),
            [0.0, 0.0, 1.0],
        );
    }
}
