//! Cutting edge positions of turning tools (840C ch. 11 "use on turning machines", 11.13;
//! 808D tool data): where the theoretical tool tip P lies relative to the nose centre S.
//!
//! A turning tool is measured at P, so P is what the axes address: without compensation P
//! runs on the programmed contour; with G41/G42 the nose centre S runs on the equidistant and
//! the setpoint is S plus the position's vector. The positions, as seen behind the centre of
//! rotation (Z to the right, X up — the 840C's "clockwise coordinate system"):
//!
//! ```text
//!        X
//!        ▲   2   6   1          P relative to S, R = nose radius:
//!        │   7  9=S  5          1 (+R,+R)  2 (−R,+R)  3 (−R,−R)  4 (+R,−R)   as (Z, X)
//!        │   3   8   4          5 (+R, 0)  6 ( 0,+R)  7 (−R, 0)  8 ( 0,−R)   9 (0, 0)
//!        └────────────► Z
//! ```
//!
//! In front of the centre (X mirrored about Z) the same program and offsets give the same
//! part (rotation symmetry); only the operator's view of the picture, and of G41/G42, is
//! mirrored (docs/turning.md). LinuxCNC numbers its orientations in that mirrored view:
//! measured with `rs274` (tests/oracle_rs274.rs), its L is this position with X mirrored.

use super::geom::{v2, V2};
use crate::frontend::block::Plane;

/// P − S in the plane's (abscissa, ordinate) for cutting edge position `edge` and nose radius
/// `r`. Positions are defined in the turning plane Z/X (G18); elsewhere, and for position 9
/// or none (0), P is the nose centre.
pub fn tip_vector(edge: u8, r: f64, plane: Plane) -> V2 {
    if plane != Plane::ZX {
        return v2(0.0, 0.0);
    }
    let r = r.abs();
    let (z, x) = match edge {
        1 => (r, r),
        2 => (-r, r),
        3 => (-r, -r),
        4 => (r, -r),
        5 => (r, 0.0),
        6 => (0.0, r),
        7 => (-r, 0.0),
        8 => (0.0, -r),
        _ => (0.0, 0.0),
    };
    v2(z, x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_one_to_four_are_diagonal_five_to_eight_on_the_axes() {
        for e in 1..=9u8 {
            let v = tip_vector(e, -0.8, Plane::ZX);
            let (az, ax) = (v.x.abs(), v.y.abs());
            match e {
                1..=4 => assert!(az == 0.8 && ax == 0.8),
                5 | 7 => assert!(az == 0.8 && ax == 0.0),
                6 | 8 => assert!(az == 0.0 && ax == 0.8),
                _ => assert!(az == 0.0 && ax == 0.0),
            }
        }
        // Mirrored about Z (a tool in front of the centre, LinuxCNC's numbering): 1 ↔ 4,
        // 2 ↔ 3, 6 ↔ 8; 5, 7 and 9 stay.
        for (e, m) in [(1, 4), (2, 3), (6, 8), (5, 5), (7, 7), (9, 9)] {
            let (v, w) = (tip_vector(e, 0.8, Plane::ZX), tip_vector(m, 0.8, Plane::ZX));
            assert!(w.x == v.x && w.y == -v.y, "{e} ↔ {m}");
        }
        assert_eq!(tip_vector(3, 0.8, Plane::XY), v2(0.0, 0.0));
    }
}
