//! Software limit switches in preparation: a segment that would take an axis past its
//! limit (machine data `axes.<name>.software_limits`) is an alarm before it is handed to
//! the path, so the machine never starts a move it cannot finish (840D 10720 checks the
//! block in preparation; plc-sim's limit switches stay as the last line).
//!
//! A segment's extent is exact for lines and circular arcs (the ends, and the arc's points
//! on the plane axes' extremes within its sweep); a spiral of the compensation (a radius
//! or centre that changes over the block) is sampled finely, and its rounding is far below
//! the tolerance of a limit switch. An arc whose whole circle stays inside the limits (the
//! common case) needs neither: no trigonometry per block for the check.

use crate::frontend::block::{AxisMove, Plane, Pos, AXIS_NAMES};
use crate::machine_data::{MachineData, AXES};
use crate::segment::{Curve, Segment, Shape};

/// Samples of a spiral's extent.
const SPIRAL_SAMPLES: usize = 64;

#[derive(Clone, Copy, Debug)]
pub struct SoftLimits {
    lo: [f64; AXES],
    hi: [f64; AXES],
}

/// An axis past its limit: which, where, and the limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overrun {
    pub axis: usize,
    pub value: f64,
    pub limit: f64,
}

impl Overrun {
    pub fn message(&self) -> String {
        format!(
            "axis {} would reach {:.4}, beyond its software limit {:.4}",
            AXIS_NAMES[self.axis], self.value, self.limit
        )
    }
}

impl SoftLimits {
    /// The limits of `md`; `None` where no axis has any.
    pub fn new(md: &MachineData) -> Option<Self> {
        let mut l = SoftLimits {
            lo: [f64::NEG_INFINITY; AXES],
            hi: [f64::INFINITY; AXES],
        };
        let mut any = false;
        for (i, a) in md.axes.configured() {
            if let Some([lo, hi]) = a.software_limits {
                // Rounding of the path's own arithmetic is not a limit violation.
                l.lo[i] = lo - 1e-9;
                l.hi[i] = hi + 1e-9;
                any = true;
            }
        }
        any.then_some(l)
    }

    /// The first of axes `0..n` whose range `lo`…`hi` leaves its limits.
    fn first_past(&self, lo: &[f64; AXES], hi: &[f64; AXES], n: usize) -> Option<Overrun> {
        (0..n).find_map(|i| {
            if lo[i] < self.lo[i] {
                Some(Overrun {
                    axis: i,
                    value: lo[i],
                    limit: self.lo[i] + 1e-9,
                })
            } else if hi[i] > self.hi[i] {
                Some(Overrun {
                    axis: i,
                    value: hi[i],
                    limit: self.hi[i] - 1e-9,
                })
            } else {
                None
            }
        })
    }

    /// The first axis `seg` (with the additional axes' move `axes` beside it) takes past a
    /// limit.
    #[inline]
    pub fn check(&self, seg: &Segment, axes: Option<&AxisMove>) -> Result<(), Overrun> {
        if axes.is_none() && self.holds(seg) {
            return Ok(());
        }
        self.exact(seg, axes)
    }

    /// `check` by the segment's exact extent.
    fn exact(&self, seg: &Segment, axes: Option<&AxisMove>) -> Result<(), Overrun> {
        let (mut lo, mut hi) = ends(seg);
        if let Some((blo, bhi)) = circle_box(seg) {
            if self.first_past(&blo, &bhi, 3).is_some() {
                arc_extent(seg, &mut lo, &mut hi);
            }
        }
        let mut axes_checked = 3;
        if let Some(m) = axes {
            // Linear in the path: its ends are its extremes. Additional axes that stand
            // still were checked when they moved there.
            for k in 0..m.from.len() {
                lo[k + 3] = m.from[k].min(m.to[k]);
                hi[k + 3] = m.from[k].max(m.to[k]);
            }
            axes_checked = AXES;
        }
        self.first_past(&lo, &hi, axes_checked).map_or(Ok(()), Err)
    }
}

impl SoftLimits {
    /// Whether the geometry axes' limits hold all of `seg` by its ends and, for an arc, its
    /// whole circle (the box `check` tries first): the common case, settled without the
    /// per-axis arrays.
    #[inline]
    fn holds(&self, seg: &Segment) -> bool {
        // Plain comparisons, and-ed without short cuts: the common segment passes all of them
        // (a NaN fails one and goes to `exact`, which decides as before).
        let inside = |i: usize, v: f64| (v >= self.lo[i]) & (v <= self.hi[i]);
        let ends = (0..3).fold(true, |ok, i| {
            ok & inside(i, seg.from[i]) & inside(i, seg.to[i])
        });
        if !ends {
            return false;
        }
        let Some((center, center_end, plane)) = centres(seg) else {
            return true;
        };
        // |dx| + |dy| bounds the distance, with a margin far above rounding: a box at least
        // as large as `circle_box`'s, without a square root.
        let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
        let l1 = |p: &Pos, c: &Pos| (p[a] - c[a]).abs() + (p[o] - c[o]).abs();
        let (r0, r1) = (l1(&seg.from, &center), l1(&seg.to, &center_end));
        let r = if r0 >= r1 { r0 } else { r1 } * (1.0 + 1e-12) + 1e-9;
        let circle = |i: usize| {
            let (c, d) = (center[i], center_end[i]);
            inside(i, c - r) & inside(i, c + r) & inside(i, d - r) & inside(i, d + r)
        };
        circle(a) & circle(o)
    }
}

/// The smallest and largest value of every geometry axis at the ends of `seg` (the
/// additional axes' entries at 0).
fn ends(seg: &Segment) -> ([f64; AXES], [f64; AXES]) {
    let mut lo = [0.0; AXES];
    let mut hi = [0.0; AXES];
    for i in 0..3 {
        lo[i] = seg.from[i].min(seg.to[i]);
        hi[i] = seg.from[i].max(seg.to[i]);
    }
    (lo, hi)
}

/// For an arc, a box that holds all of it: its circle (both centres, the larger radius of
/// its two ends) in the plane, its ends along the normal.
fn circle_box(seg: &Segment) -> Option<([f64; AXES], [f64; AXES])> {
    let (center, center_end, plane) = centres(seg)?;
    let r = circle_radius(seg, &center, &center_end, plane);
    let (mut lo, mut hi) = ends(seg);
    for (i, l, h) in about_centres(&center, &center_end, plane, r) {
        (lo[i], hi[i]) = (l, h);
    }
    Some((lo, hi))
}

/// An arc's centres (start and end) and plane; `None` for a line.
fn centres(seg: &Segment) -> Option<(Pos, Pos, Plane)> {
    match seg.shape {
        Shape::Arc {
            center,
            center_end,
            plane,
            ..
        } => Some((center, center_end, plane)),
        Shape::Line => None,
    }
}

/// The range of each plane axis (axis, low, high) that circles of radius `r` about both
/// centres cover.
fn about_centres(center: &Pos, center_end: &Pos, plane: Plane, r: f64) -> [(usize, f64, f64); 2] {
    [plane.abscissa as usize, plane.ordinate as usize].map(|i| {
        let (c, d) = (center[i], center_end[i]);
        (i, c.min(d) - r, c.max(d) + r)
    })
}

/// The radius of the circle that holds the arc `seg` about either centre (the larger of its
/// ends' distances), with the rounding margin.
#[inline]
fn circle_radius(seg: &Segment, center: &Pos, center_end: &Pos, plane: Plane) -> f64 {
    let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
    let r0 = (seg.from[a] - center[a]).hypot(seg.from[o] - center[o]);
    let r1 = (seg.to[a] - center_end[a]).hypot(seg.to[o] - center_end[o]);
    r0.max(r1) + 1e-9
}

/// Grows `lo`/`hi` (the ends) to the exact extent of the arc `seg`.
fn arc_extent(seg: &Segment, lo: &mut [f64; AXES], hi: &mut [f64; AXES]) {
    let Shape::Arc {
        center,
        center_end,
        r0,
        r1,
        plane,
        ..
    } = seg.shape
    else {
        return;
    };
    let mut grow = |i: usize, v: f64| {
        lo[i] = lo[i].min(v);
        hi[i] = hi[i].max(v);
    };
    let Some(curve) = Curve::new(seg) else {
        return;
    };
    if center == center_end && r0 == r1 {
        // A circle reaches its plane extremes where θ is a multiple of 90° within the sweep.
        if let Curve::Arc { th0, sweep, .. } = curve {
            for q in quarter_angles(th0, sweep) {
                let p = curve.point((q - th0) / sweep);
                grow(plane.abscissa as usize, p[plane.abscissa as usize]);
                grow(plane.ordinate as usize, p[plane.ordinate as usize]);
            }
        }
        return;
    }
    for k in 1..SPIRAL_SAMPLES {
        let p = curve.point(k as f64 / SPIRAL_SAMPLES as f64);
        for (i, v) in p.iter().enumerate() {
            grow(i, *v);
        }
    }
}

/// The multiples of 90° (in radians) strictly between th0 and th0 + sweep.
fn quarter_angles(th0: f64, sweep: f64) -> impl Iterator<Item = f64> {
    let q = std::f64::consts::FRAC_PI_2;
    let (a, b) = if sweep >= 0.0 {
        (th0, th0 + sweep)
    } else {
        (th0 + sweep, th0)
    };
    let first = (a / q).floor() as i64 + 1;
    (first..)
        .map(move |k| k as f64 * q)
        .take_while(move |&t| t < b)
        .take(5)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontend::block::Plane;
    use crate::segment::{Role, Source};
    use proptest::prelude::*;

    fn seg(from: [f64; 3], to: [f64; 3], shape: Shape) -> Segment {
        Segment {
            source: Source::default(),
            role: Role::Uncompensated,
            shape,
            from,
            to,
            feed: 100.0,
            per_rev: false,
            thread: false,
            rapid: false,
            exact_stop: false,
        }
    }

    /// The exact extent of a segment.
    fn extent(s: &Segment) -> ([f64; AXES], [f64; AXES]) {
        let (mut lo, mut hi) = ends(s);
        arc_extent(s, &mut lo, &mut hi);
        (lo, hi)
    }

    #[test]
    fn a_half_circle_bulges_past_its_ends() {
        // (10,0) → (−10,0) about the origin counter-clockwise: Y reaches 10 at 90°.
        let c = [0.0; 3];
        let s = seg(
            [10.0, 0.0, 0.0],
            [-10.0, 0.0, 0.0],
            Shape::Arc {
                center: c,
                center_end: c,
                ccw: true,
                r0: 10.0,
                r1: 10.0,
                plane: Plane::XY,
            },
        );
        let (lo, hi) = extent(&s);
        assert!(
            (hi[1] - 10.0).abs() < 1e-12 && lo[1].abs() < 1e-12,
            "{lo:?} {hi:?}"
        );
        assert_eq!((lo[0], hi[0]), (-10.0, 10.0));
        // Clockwise the other half: Y down to −10.
        let mut cw = s;
        if let Shape::Arc { ccw, .. } = &mut cw.shape {
            *ccw = false;
        }
        let (lo, _) = extent(&cw);
        assert!((lo[1] + 10.0).abs() < 1e-12);
    }

    fn arc() -> impl Strategy<Value = Segment> {
        let p = || prop::array::uniform3(-30.0..30.0f64);
        (p(), p(), p(), any::<bool>(), 0usize..3).prop_map(|(from, to, c, ccw, k)| {
            let plane = [Plane::XY, Plane::ZX, Plane::YZ][k];
            let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
            let r = |q: [f64; 3]| (q[a] - c[a]).hypot(q[o] - c[o]);
            let shape = Shape::Arc {
                center: c,
                center_end: c,
                ccw,
                r0: r(from),
                r1: r(to),
                plane,
            };
            seg(from, to, shape)
        })
    }

    proptest! {
        /// The quick test by ends and circle only ever says what the exact extent says: on
        /// lines and arcs (spirals among them) near limits of every size.
        #[test]
        fn the_quick_test_agrees_with_the_exact_one(
            s in prop_oneof![
                (prop::array::uniform3(-30.0..30.0f64), prop::array::uniform3(-30.0..30.0f64))
                    .prop_map(|(a, b)| seg(a, b, Shape::Line)),
                arc(),
            ],
            limits in prop::array::uniform3((-40.0..5.0f64, -5.0..40.0f64)),
        ) {
            let mut l = SoftLimits { lo: [f64::NEG_INFINITY; AXES], hi: [f64::INFINITY; AXES] };
            for (i, (lo, hi)) in limits.iter().enumerate() {
                l.lo[i] = *lo;
                l.hi[i] = *hi;
            }
            prop_assert_eq!(l.check(&s, None), l.exact(&s, None));
        }
    }

    #[test]
    fn limits_name_the_axis_and_the_value() {
        let md = MachineData::default();
        let l = SoftLimits::new(&md).unwrap();
        // Default Z limits ±500.
        let ok = seg([0.0; 3], [0.0, 0.0, -500.0], Shape::Line);
        assert_eq!(l.check(&ok, None), Ok(()));
        let bad = seg([0.0; 3], [0.0, 0.0, -500.5], Shape::Line);
        let o = l.check(&bad, None).unwrap_err();
        assert_eq!((o.axis, o.value, o.limit), (2, -500.5, -500.0));
        assert!(o.message().contains("axis Z"), "{}", o.message());
    }

    #[test]
    fn an_additional_axis_standing_still_is_not_checked_again() {
        // A's limits exclude 0; a segment without a move of A says nothing of where A is.
        let md = MachineData::load(
            Some(std::path::Path::new(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../config/fanuc-5axis.toml"
            ))),
            &["axes.A.software_limits=[-120, -5]".into()],
        )
        .unwrap();
        let l = SoftLimits::new(&md).unwrap();
        let s = seg([0.0; 3], [10.0, 0.0, 0.0], Shape::Line);
        assert_eq!(l.check(&s, None), Ok(()));
        let mut m = AxisMove {
            from: [0.0, 0.0, 0.0, -50.0, 0.0, 0.0],
            to: [0.0, 0.0, 0.0, -60.0, 0.0, 0.0],
        };
        assert_eq!(l.check(&s, Some(&m)), Ok(()));
        m.to[3] = -1.0;
        assert_eq!(l.check(&s, Some(&m)).map_err(|o| o.axis), Err(6));
    }
}
