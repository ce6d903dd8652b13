//! The programmable frame (Fanuc 0i-MF "Programmable mirror image", "Scaling", "Coordinate
//! system rotation"): a programmed point is mirrored (G51.1), scaled (G51) and rotated (G68)
//! in that order, in workpiece coordinates, before the zero is added.
//!
//! ```text
//! p  →  mirror: m_i − (p_i − m_i) on the mirrored axes
//!    →  scale:  c + s·(p − c) per axis (s < 0 mirrors too)
//!    →  rotate: about the centre in the plane of G68, by its angle
//! ```
//!
//! The tool radius is never scaled (compensation works on the transformed contour with the
//! table's radius). A frame that mirrors the plane an odd number of times turns G02 into
//! G03 and G41 into G42, as on the control. Arcs need the same scale on both plane axes.

use super::block::{Plane, Pos};

/// The frame's parts, as programmed, and the affine map they make.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// G51.1: the mirror axis position per axis, if mirrored.
    pub mirror: [Option<f64>; 3],
    /// G51: the scale factors per axis and the centre.
    pub scale: Option<([f64; 3], Pos)>,
    /// G68: the plane, the centre (in it) and the angle in degrees.
    pub rotation: Option<(Plane, Pos, f64)>,
    /// p ↦ m·p + t, kept up to date by [`Frame::update`].
    m: [[f64; 3]; 3],
    t: Pos,
    active: bool,
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            mirror: [None; 3],
            scale: None,
            rotation: None,
            m: IDENTITY,
            t: [0.0; 3],
            active: false,
        }
    }
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Frame {
    /// Anything but the identity is programmed.
    #[inline(always)]
    pub fn active(&self) -> bool {
        self.active
    }

    /// Rebuilds the map from the parts.
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
        self.m = m;
        self.t = t;
        self.active = m != IDENTITY || t != [0.0; 3];
    }

    /// A programmed point (workpiece coordinates) in the frame.
    pub fn apply(&self, p: Pos) -> Pos {
        std::array::from_fn(|i| {
            self.m[i][0] * p[0] + self.m[i][1] * p[1] + self.m[i][2] * p[2] + self.t[i]
        })
    }

    /// A direction (a vector between two programmed points) in the frame: its linear part.
    pub fn turn(&self, v: Pos) -> Pos {
        std::array::from_fn(|i| self.m[i][0] * v[0] + self.m[i][1] * v[1] + self.m[i][2] * v[2])
    }

    /// The programmed point that the frame takes to `q` (a position back into program
    /// terms, for incremental words). `None` if a scale factor is 0.
    pub fn invert(&self, q: Pos) -> Option<Pos> {
        let m = &self.m;
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        if det.abs() < 1e-12 {
            return None;
        }
        let d: Pos = std::array::from_fn(|i| q[i] - self.t[i]);
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
        self.m[a][a] * self.m[o][o] - self.m[a][o] * self.m[o][a] < 0.0
    }

    /// The frame maps `plane` onto itself (its normal stays its normal).
    pub fn keeps_plane(&self, plane: Plane) -> bool {
        let (a, o, n) = (
            plane.abscissa as usize,
            plane.ordinate as usize,
            plane.normal as usize,
        );
        self.m[n][a] == 0.0 && self.m[n][o] == 0.0 && self.m[a][n] == 0.0 && self.m[o][n] == 0.0
    }

    /// The frame leaves axis `n` alone (a hole's depth under a frame in its plane).
    pub fn keeps_axis(&self, n: usize) -> bool {
        (0..3).all(|k| {
            self.m[n][k] == if k == n { 1.0 } else { 0.0 }
                && self.m[k][n] == if k == n { 1.0 } else { 0.0 }
        }) && self.t[n] == 0.0
    }

    /// The frame maps circles in `plane` to circles: the same scale on both of its axes.
    pub fn keeps_circles(&self, plane: Plane) -> bool {
        match self.scale {
            None => true,
            Some((s, _)) => {
                let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
                (s[a].abs() - s[o].abs()).abs() < 1e-12
            }
        }
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
    }
}
