//! Geometry for those who draw the path (the SVG of `softnc path` and `softnc run`, the
//! HMI's plot): a segment or a programmed motion as a [`Curve`] of one parameter, sampled as
//! finely as a picture needs, and where a turning tool's tip lies from its nose centre.
//!
//! Drawings take their arcs from here, so a picture shows the sweep the interpolator runs:
//! `from == to` in the plane is a full circle (the segment's rule, [`crate::Shape`]).

use crate::frontend::{Motion, MotionKind, Plane};
pub use crate::segment::Curve;
use crate::segment::{Role, Segment, Shape, Source};

/// Where a turning tool's tip P lies from its nose centre S, as (abscissa, ordinate) of
/// `plane`: the cutting edge position `edge` (1–9) at nose radius `radius` (840C 11.13);
/// `[0, 0]` outside the turning plane, for position 9 and for none.
pub fn tip_offset(edge: u8, radius: f64, plane: Plane) -> [f64; 2] {
    let v = crate::trc::cutting_edge::tip_vector(edge, radius, plane);
    [v.x, v.y]
}

/// How far apart a drawing's points on an arc may lie: at most `max_angle` (radians) of
/// its sweep and at most `max_length` mm along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fineness {
    pub max_angle: f64,
    pub max_length: f64,
}

/// More pieces than this per curve show nothing more on any screen.
pub const MAX_PIECES: usize = 720;

impl Curve {
    /// A programmed motion (a block's start, end, centre, plane and kind) as a curve: a
    /// line, or an arc about its centre in its plane, a helix where the normal axis moves.
    /// `None` for an arc with an end on its centre.
    pub fn of_motion(m: &Motion) -> Option<Curve> {
        Curve::new(&Segment {
            source: Source::default(),
            role: Role::Contour,
            shape: Shape::of_motion(m),
            from: m.start,
            to: m.end,
            feed: 0.0,
            per_rev: false,
            thread: false,
            rapid: m.kind == MotionKind::Rapid,
            exact_stop: false,
        })
    }

    /// Pieces of equal parameter whose ends lie no further apart than `f` allows: 1 for a
    /// line; for an arc at least 2 and at most [`MAX_PIECES`].
    pub fn pieces(&self, f: Fineness) -> usize {
        let Curve::Arc { r0, dr, sweep, .. } = *self else {
            return 1;
        };
        let sweep = sweep.abs();
        let by_angle = sweep / f.max_angle;
        let by_length = sweep * r0.max(r0 + dr) / f.max_length;
        let n = by_angle.max(by_length).ceil();
        if n.is_nan() {
            return 2;
        }
        (n.min(MAX_PIECES as f64) as usize).clamp(2, MAX_PIECES)
    }

    /// The points between the curve's ends, in order, as finely as `f` asks (none for a
    /// line). The ends are left to the caller, who has them exactly.
    pub fn interior(&self, f: Fineness) -> impl Iterator<Item = crate::Pos> {
        let c = *self;
        let n = self.pieces(f);
        (1..n).map(move |k| c.point(k as f64 / n as f64))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn arc(start: [f64; 3], end: [f64; 3], kind: MotionKind) -> Motion {
        Motion {
            kind,
            plane: Plane::XY,
            start,
            end,
            center: [0.0; 3],
            programmed: 0b11,
        }
    }

    fn sweep(c: Option<Curve>) -> f64 {
        match c {
            Some(Curve::Arc { sweep, .. }) => sweep,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn sweep_of_quarter_and_full_circles() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let ccw = Curve::of_motion(&arc(x, y, MotionKind::ArcCcw));
        let Some(Curve::Arc { th0, .. }) = ccw else {
            panic!("{ccw:?}")
        };
        assert!(th0.abs() < 1e-12 && (sweep(ccw) - TAU / 4.0).abs() < 1e-12);
        let cw = Curve::of_motion(&arc(x, y, MotionKind::ArcCw));
        assert!((sweep(cw) + 3.0 * TAU / 4.0).abs() < 1e-12);
        let full = Curve::of_motion(&arc(x, x, MotionKind::ArcCw));
        assert!((sweep(full) + TAU).abs() < 1e-12);
    }

    #[test]
    fn points_lie_no_further_apart_than_asked() {
        // A half circle of radius 100: 180 pieces by 1°, 315 by 1 mm of arc.
        let m = arc([100.0, 0.0, 0.0], [-100.0, 0.0, 0.0], MotionKind::ArcCcw);
        let c = Curve::of_motion(&m).unwrap();
        let deg = Fineness {
            max_angle: 1f64.to_radians(),
            max_length: f64::INFINITY,
        };
        assert_eq!(c.pieces(deg), 180);
        let mm = Fineness {
            max_angle: 1f64.to_radians(),
            max_length: 1.0,
        };
        assert_eq!(c.pieces(mm), 315);
        let pts: Vec<_> = c.interior(mm).collect();
        assert_eq!(pts.len(), 314);
        for p in &pts {
            assert!(
                (p[0].hypot(p[1]) - 100.0).abs() < 1e-9 && p[1] > 0.0,
                "{p:?}"
            );
        }
        // A line is one piece: nothing between its ends.
        let line = Motion {
            kind: MotionKind::Linear,
            ..m
        };
        assert_eq!(Curve::of_motion(&line).unwrap().interior(mm).count(), 0);
        // A huge arc gets no more than the cap.
        let big = Motion {
            start: [1e6, 0.0, 0.0],
            end: [-1e6, 0.0, 0.0],
            ..m
        };
        assert_eq!(Curve::of_motion(&big).unwrap().pieces(mm), MAX_PIECES);
    }
}
