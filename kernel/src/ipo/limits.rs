//! From the axes' limits (machine data) to the path's: the speed cap and the acceleration and
//! jerk of each segment, and the speed allowed through each block transition (corner).
//!
//! Every axis keeps its own velocity, acceleration and jerk limit at every IPO cycle, measured
//! as finite differences of its setpoints — transitions included. The budget per axis:
//!
//! - along a line: the path's acceleration and 3/4 of its jerk, projected on the axis;
//! - on an arc: 3/4 of the acceleration along the path and 1/4 for the centripetal v²κ;
//!   1/2 of the jerk along the path and 1/4 for the terms of the turning direction
//!   (v³κ² + 3·v·a·κ);
//! - 1/4 of the jerk is kept for the steps at block transitions. The path's acceleration is
//!   0 there (every segment's plan ends with a = 0), so a transition at speed v steps each
//!   axis's velocity by v·Δt (the change of the unit tangent) and its acceleration by v²·Δ(κn);
//!   in one IPO cycle T these count as jerk Δv/T² and Δa/T, so the corner speed is
//!   v ≤ ¼·j·T²/|Δt| and v ≤ √(¼·j·T/|Δ(κn)|) for each axis.
//!
//! The consequence: a sharp corner is passed at a crawl (fractions of a mm/s at the default
//! limits); tangent transitions and transition circles (G450) keep their speed. docs/ipo.md.

use super::path::{Piece, V3};
use super::profile::{cubic_root, Dynamics};
use crate::frontend::block::Additional;
use crate::machine_data::{MachineData, AXES};

/// Share of the jerk kept for transition steps.
const STEP_SHARE: f64 = 0.25;

/// The axes' limits in mm/s, mm/s², mm/s³; `None` for an axis without machine data.
#[derive(Clone, Copy, Debug)]
pub struct AxisLimits {
    /// Per axis of [`crate::machine_data::AXIS_NAMES`] (rotary axes in degrees).
    v: [Option<f64>; AXES],
    a: [f64; AXES],
    j: [f64; AXES],
    /// The IPO cycle, s.
    cycle: f64,
}

/// What a segment may do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentLimits {
    /// Highest path speed from the axes (mm/s): the rapid rate for G0, a cap on the feed.
    pub v_cap: f64,
    pub dynamics: Dynamics,
}

impl AxisLimits {
    pub fn new(md: &MachineData) -> Self {
        let mut l = AxisLimits {
            v: [None; AXES],
            a: [f64::INFINITY; AXES],
            j: [f64::INFINITY; AXES],
            cycle: f64::from(md.ipo.cycle_us) * 1e-6,
        };
        for i in 0..AXES {
            if let Some(ax) = md.axes.get(i) {
                l.v[i] = Some(ax.max_velocity / 60.0);
                l.a[i] = ax.max_acceleration;
                l.j[i] = ax.max_jerk;
            }
        }
        l
    }

    pub fn cycle(&self) -> f64 {
        self.cycle
    }

    /// The limits of a segment; `Err(axis)` if it moves an axis without machine data.
    pub fn segment(&self, p: &Piece) -> Result<SegmentLimits, usize> {
        // How much of the path speed each axis can see: a line's direction cosines; on an
        // arc the whole of it in the plane (the tangent turns) and the lead along the normal;
        // an additional axis its constant share.
        let mut share = [0.0f64; AXES];
        for (s, d) in share[3..].iter_mut().zip(&p.add_dir) {
            *s = d.abs();
        }
        match p.plane() {
            None => {
                for (i, s) in share[..3].iter_mut().enumerate() {
                    *s = p.tangent[0][i].abs();
                }
            }
            Some(plane) => {
                // The curve runs at curve_share of the path speed; normal_share is of the
                // whole path already.
                share[plane.abscissa as usize] = p.stretch * p.curve_share;
                share[plane.ordinate as usize] = p.stretch * p.curve_share;
                share[plane.normal as usize] = p.normal_share() * p.stretch;
            }
        }
        let line = p.plane().is_none();
        let (mut v, mut a, mut j) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        for (i, &sh) in share.iter().enumerate() {
            if sh <= 1e-12 {
                continue;
            }
            let Some(vi) = self.v[i] else {
                return Err(i);
            };
            v = v.min(vi / sh);
            a = a.min(self.a[i] / sh);
            j = j.min(self.j[i] / sh);
        }
        if line {
            return Ok(SegmentLimits {
                v_cap: v,
                dynamics: Dynamics {
                    a,
                    j: (1.0 - STEP_SHARE) * j,
                },
            });
        }
        // The turning direction acts in the plane: the plane axes' own limits.
        let (a_plane, j_plane) = match p.plane() {
            Some(plane) => {
                let (ia, io) = (plane.abscissa as usize, plane.ordinate as usize);
                (self.a[ia].min(self.a[io]), self.j[ia].min(self.j[io]))
            }
            None => (a, j),
        };
        let k = p.kappa;
        let at = 0.75 * a;
        // Centripetal: v²κ ≤ ¼·a; turning-direction jerk: κ²v³ + 3·a_t·κ·v ≤ ¼·j.
        let v_centripetal = (0.25 * a_plane / k).sqrt();
        let v_jerk = cubic_root(3.0 * at / k, 0.25 * j_plane / (k * k));
        Ok(SegmentLimits {
            v_cap: v.min(v_centripetal).min(v_jerk),
            dynamics: Dynamics { a: at, j: 0.5 * j },
        })
    }

    /// The highest speed through the transition from `a`'s end to `b`'s start.
    pub fn corner(&self, a: &Piece, b: &Piece) -> f64 {
        let v = self.transition(a.tangent[1], b.tangent[0], a.curvature[1], b.curvature[0]);
        v.min(self.additional_step(&a.add_dir, &b.add_dir))
    }

    /// The additional axes' velocity step (they do not curve): v ≤ ¼·j·T²/|Δshare|.
    fn additional_step(&self, d1: &Additional, d2: &Additional) -> f64 {
        let t = self.cycle;
        let mut v = f64::INFINITY;
        for (k, (a, b)) in d1.iter().zip(d2).enumerate() {
            let du = (b - a).abs();
            if du > 0.0 {
                v = v.min(STEP_SHARE * self.j[k + 3] * t * t / du);
            }
        }
        v
    }

    fn transition(&self, t1: V3, t2: V3, k1: V3, k2: V3) -> f64 {
        let mut v = f64::INFINITY;
        let t = self.cycle;
        for i in 0..3 {
            let du = (t2[i] - t1[i]).abs();
            if du > 0.0 {
                v = v.min(STEP_SHARE * self.j[i] * t * t / du);
            }
            let dk = (k2[i] - k1[i]).abs();
            if dk > 0.0 {
                v = v.min((STEP_SHARE * self.j[i] * t / dk).sqrt());
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontend::block::Plane;
    use crate::segment::{Segment, Shape};

    fn md() -> MachineData {
        MachineData::load(None, &[]).unwrap()
    }

    fn line(from: [f64; 3], to: [f64; 3]) -> Piece {
        Piece::new(&crate::ipo::path::tests::seg(from, to, Shape::Line)).unwrap()
    }

    #[test]
    fn a_diagonal_line_by_hand() {
        // Default 840C data: X and Y 10000 mm/min, 2000 mm/s², 50000 mm/s³. At 45° each axis
        // sees 1/√2 of the path: the path may go √2 times as fast.
        let l = AxisLimits::new(&md());
        let s = l.segment(&line([0.0; 3], [10.0, 10.0, 0.0])).unwrap();
        let r2 = 2f64.sqrt();
        assert!((s.v_cap - 10000.0 / 60.0 * r2).abs() < 1e-9);
        assert!((s.dynamics.a - 2000.0 * r2).abs() < 1e-9);
        assert!((s.dynamics.j - 0.75 * 50000.0 * r2).abs() < 1e-6);
        // Along Z: Z's own limits.
        let z = l.segment(&line([0.0; 3], [0.0, 0.0, -5.0])).unwrap();
        assert!((z.v_cap - 8000.0 / 60.0).abs() < 1e-9);
    }

    #[test]
    fn a_right_angle_corner_crawls() {
        // +X then +Y: the tangent steps by 1 on both axes; ¼·50000·0.001² = 0.0125 mm/s.
        let l = AxisLimits::new(&md());
        let a = line([0.0; 3], [10.0, 0.0, 0.0]);
        let b = line([10.0, 0.0, 0.0], [10.0, 10.0, 0.0]);
        assert!((l.corner(&a, &b) - 0.0125).abs() < 1e-12);
        // Straight on: no limit.
        let c = line([10.0, 0.0, 0.0], [20.0, 0.0, 0.0]);
        assert_eq!(l.corner(&a, &c), f64::INFINITY);
    }

    #[test]
    fn a_line_into_a_tangent_arc_limits_by_the_curvature_step() {
        // Into a circle of radius 10: κ steps by 0.1; v ≤ √(¼·50000·0.001/0.1) = √125.
        let l = AxisLimits::new(&md());
        let a = line([0.0; 3], [10.0, 0.0, 0.0]);
        let arc = Piece::new(&Segment {
            shape: Shape::Arc {
                center: [10.0, 10.0, 0.0],
                center_end: [10.0, 10.0, 0.0],
                ccw: true,
                r0: 10.0,
                r1: 10.0,
                plane: Plane::XY,
            },
            from: [10.0, 0.0, 0.0],
            to: [20.0, 10.0, 0.0],
            ..a.seg
        })
        .unwrap();
        assert!((l.corner(&a, &arc) - 125f64.sqrt()).abs() < 1e-9);
        let s = l.segment(&arc).unwrap();
        // Centripetal ¼·2000 = 500 mm/s² at r 10: v ≤ √5000 = 70.7 mm/s; the jerk share
        // (κ²v³ + 3·1500·κ·v ≤ 12500) is lower: v = 26.17… mm/s.
        let v = s.v_cap;
        assert!((0.01 * v * v * v + 450.0 * v - 12500.0).abs() < 1e-6, "{v}");
    }
}
