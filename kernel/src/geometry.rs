//! Geometry for those who draw the path (the SVG of `softnc path` and `softnc run`, the
//! HMI's plot): a segment or a programmed motion as a [`Curve`] of one parameter, sampled as
//! finely as a picture needs, and where a turning tool's tip lies from its nose centre.

use crate::frontend::Plane;
pub use crate::segment::Curve;

/// Where a turning tool's tip P lies from its nose centre S, as (abscissa, ordinate) of
/// `plane`: the cutting edge position `edge` (1–9) at nose radius `radius` (840C 11.13);
/// `[0, 0]` outside the turning plane, for position 9 and for none.
pub fn tip_offset(edge: u8, radius: f64, plane: Plane) -> [f64; 2] {
    let v = crate::trc::cutting_edge::tip_vector(edge, radius, plane);
    [v.x, v.y]
}
