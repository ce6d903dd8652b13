//! Circle centres from centre offsets (I J K) or a radius (`CR=` / `R`), checked against the
//! machine-data end-point tolerance.

use super::block::{Plane, Pos};

/// How the program gave the circle.
#[derive(Clone, Copy, Debug)]
pub enum CentreSpec {
    /// Centre offsets from the start point along X, Y, Z (I, J, K), in mm.
    Offsets([f64; 3]),
    /// Radius; negative selects the arc longer than a half circle.
    Radius(f64),
}

/// Length of a plane vector (coordinates are bounded to 1e9 mm, so no overflow guard).
#[inline]
fn len(x: f64, y: f64) -> f64 {
    libm::sqrt(x * x + y * y)
}

/// Why no circle fits.
#[derive(Clone, Debug, PartialEq)]
pub enum ArcError {
    /// Start and end radius differ by more than the tolerance.
    EndPointOff { r_start: f64, r_end: f64 },
    /// Centre on the start point.
    ZeroRadius,
    /// Radius programming with start = end (a full circle needs a centre).
    FullCircleByRadius,
    /// The chord is longer than the diameter.
    RadiusTooSmall { radius: f64, half_chord: f64 },
}

/// Returns the centre (its normal coordinate that of `start`), placed so that start and end
/// lie at exactly the same distance from it: a centre within tolerance is moved onto the
/// perpendicular bisector of the chord, so the arc ends exactly at the programmed point.
pub fn centre(
    start: Pos,
    end: Pos,
    plane: Plane,
    ccw: bool,
    spec: CentreSpec,
    tol: f64,
) -> Result<Pos, ArcError> {
    let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
    let chord = Chord::new((start[a], start[o]), (end[a], end[o]));
    let (cx, cy) = match spec {
        CentreSpec::Offsets(off) => chord.by_offsets(off[a], off[o], tol)?,
        CentreSpec::Radius(r) => chord.by_radius(r, ccw, tol)?,
    };
    let mut c = start;
    c[a] = cx;
    c[o] = cy;
    Ok(c)
}

/// The chord from the start to the end point, in plane coordinates.
#[derive(Clone, Copy)]
struct Chord {
    sx: f64,
    sy: f64,
    ex: f64,
    ey: f64,
    dx: f64,
    dy: f64,
    len: f64,
}

impl Chord {
    fn new((sx, sy): (f64, f64), (ex, ey): (f64, f64)) -> Chord {
        let (dx, dy) = (ex - sx, ey - sy);
        let len = libm::sqrt(dx * dx + dy * dy);
        Chord {
            sx,
            sy,
            ex,
            ey,
            dx,
            dy,
            len,
        }
    }

    /// The centre at offsets (i, j) from the start, moved onto the chord's bisector.
    fn by_offsets(&self, i: f64, j: f64, tol: f64) -> Result<(f64, f64), ArcError> {
        let Chord {
            sx,
            sy,
            ex,
            ey,
            dx,
            dy,
            len: chord,
        } = *self;
        let (cx, cy) = (sx + i, sy + j);
        let r0 = len(sx - cx, sy - cy);
        let r1 = len(ex - cx, ey - cy);
        if r0 <= 1e-9 {
            return Err(ArcError::ZeroRadius);
        }
        if (r0 - r1).abs() > tol {
            return Err(ArcError::EndPointOff {
                r_start: r0,
                r_end: r1,
            });
        }
        if chord <= 1e-12 || r0 == r1 {
            return Ok((cx, cy));
        }
        // Project onto the bisector: m + ((c - m)·n) n, n the unit normal of the chord.
        let (mx, my) = (sx + 0.5 * dx, sy + 0.5 * dy);
        let (nx, ny) = (-dy / chord, dx / chord);
        let t = (cx - mx) * nx + (cy - my) * ny;
        Ok((mx + t * nx, my + t * ny))
    }

    /// The centre of the arc of radius `r` (negative: the one longer than a half circle).
    fn by_radius(&self, r: f64, ccw: bool, tol: f64) -> Result<(f64, f64), ArcError> {
        let Chord {
            sx,
            sy,
            dx,
            dy,
            len: chord,
            ..
        } = *self;
        if chord <= 1e-12 {
            return Err(ArcError::FullCircleByRadius);
        }
        let half = 0.5 * chord;
        let rr = r.abs();
        let h2 = rr * rr - half * half;
        let h = if h2 >= 0.0 {
            libm::sqrt(h2)
        } else if half - rr <= tol {
            0.0
        } else {
            return Err(ArcError::RadiusTooSmall {
                radius: r,
                half_chord: half,
            });
        };
        // Left normal of the chord; a counter-clockwise arc up to a half circle has its
        // centre on the left, a clockwise one on the right; a negative radius swaps it.
        let (nx, ny) = (-dy / chord, dx / chord);
        let left = ccw == (r > 0.0);
        let s = if left { h } else { -h };
        Ok((sx + 0.5 * dx + s * nx, sy + 0.5 * dy + s * ny))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_and_radius_agree() {
        // 840C 11.15 N30: from (40,80) G2 to (65,55) with I0 J-25: centre (40,55).
        let c = centre(
            [40.0, 80.0, 0.0],
            [65.0, 55.0, 0.0],
            Plane::XY,
            false,
            CentreSpec::Offsets([0.0, -25.0, 0.0]),
            0.01,
        )
        .unwrap();
        assert_eq!(c, [40.0, 55.0, 0.0]);
        let c = centre(
            [40.0, 80.0, 0.0],
            [65.0, 55.0, 0.0],
            Plane::XY,
            false,
            CentreSpec::Radius(25.0),
            0.01,
        )
        .unwrap();
        assert!(
            (c[0] - 40.0).abs() < 1e-12 && (c[1] - 55.0).abs() < 1e-12,
            "{c:?}"
        );
        // Negative radius: the other centre (65,80), the 270° arc.
        let c = centre(
            [40.0, 80.0, 0.0],
            [65.0, 55.0, 0.0],
            Plane::XY,
            false,
            CentreSpec::Radius(-25.0),
            0.01,
        )
        .unwrap();
        assert!(
            (c[0] - 65.0).abs() < 1e-12 && (c[1] - 80.0).abs() < 1e-12,
            "{c:?}"
        );
    }

    #[test]
    fn end_point_off_circle() {
        let e = centre(
            [0.0; 3],
            [10.0, 0.5, 0.0],
            Plane::XY,
            true,
            CentreSpec::Offsets([5.0, 0.0, 0.0]),
            0.01,
        )
        .unwrap_err();
        assert!(matches!(e, ArcError::EndPointOff { .. }));
        let e = centre(
            [0.0; 3],
            [10.0, 0.0, 0.0],
            Plane::XY,
            true,
            CentreSpec::Radius(4.0),
            0.01,
        )
        .unwrap_err();
        assert!(matches!(e, ArcError::RadiusTooSmall { .. }));
    }

    #[test]
    fn zx_plane_orientation() {
        // G18: Z abscissa, X ordinate. CCW quarter from (Z=10,X=0) to (Z=0,X=10) about origin.
        let c = centre(
            [0.0, 0.0, 10.0],
            [10.0, 0.0, 0.0],
            Plane::ZX,
            true,
            CentreSpec::Radius(10.0),
            0.01,
        )
        .unwrap();
        assert!(c[0].abs() < 1e-12 && c[2].abs() < 1e-12, "{c:?}");
    }
}
