//! The machine's feed drives: one [`Axis`] per configured path axis, in wire order (the
//! order of the setpoints' and actual values' position arrays, protocol's `AxisList`), each
//! with its own velocity, acceleration and software limit switches from its machine data.
//!
//! Everything is a fixed array of `MAX_AXES`: a drive cycle allocates nothing.

use crate::axis::Axis;
use nc_kernel::MachineData;
use nc_runtime::WireAxes;
use softnc_protocol::MAX_AXES;

/// Positions, one per wire axis (0 past the count).
pub type Axes = [f64; MAX_AXES];

/// What every drive cycle needs of the machine data, per wire axis.
#[derive(Clone, Copy, Debug)]
pub struct DriveData {
    pub count: usize,
    kv: f64,
    dead: usize,
    /// mm/s (°/s).
    v_max: Axes,
    /// mm/s² (°/s²).
    a_max: Axes,
    limits: [Option<[f64; 2]>; MAX_AXES],
}

impl DriveData {
    pub fn new(md: &MachineData, wire: &WireAxes) -> Self {
        let mut d = DriveData {
            count: wire.count(),
            kv: md.plc.kv,
            dead: md.plc.dead_time_cycles as usize,
            v_max: [1.0; MAX_AXES],
            a_max: [1.0; MAX_AXES],
            limits: [None; MAX_AXES],
        };
        for n in 0..d.count {
            if let Some(a) = md.axes.get(wire.index[n]) {
                d.v_max[n] = a.max_velocity / 60.0;
                d.a_max[n] = a.max_acceleration;
                d.limits[n] = a.software_limits;
            }
        }
        d
    }

    /// The setpoint within each axis's software limit switches (an axis without them is
    /// not cut), and whether any had to be cut.
    pub fn limit(&self, p: &Axes) -> (Axes, bool) {
        let mut out = *p;
        let mut cut = false;
        for (x, l) in out.iter_mut().zip(&self.limits).take(self.count) {
            let Some([lo, hi]) = *l else { continue };
            if *x < lo || *x > hi {
                *x = x.clamp(lo, hi);
                cut = true;
            }
        }
        (out, cut)
    }

    /// The drives standing at `at`, cycle `t` s.
    pub fn drives(&self, t: f64, at: &Axes) -> Drives {
        Drives {
            count: self.count,
            axis: std::array::from_fn(|n| {
                Axis::new(self.kv, t, self.v_max[n], self.a_max[n], self.dead, at[n])
            }),
        }
    }
}

/// The position loops of the configured axes.
#[derive(Clone, Debug)]
pub struct Drives {
    count: usize,
    axis: [Axis; MAX_AXES],
}

impl Drives {
    /// One drive cycle towards `target`: the positions measured and the following errors.
    pub fn step(&mut self, target: &Axes) -> (Axes, Axes) {
        let mut actual = [0.0; MAX_AXES];
        let mut fe = [0.0; MAX_AXES];
        for n in 0..self.count {
            actual[n] = self.axis[n].step(target[n]);
            fe[n] = self.axis[n].following_error;
        }
        (actual, fe)
    }

    /// One cycle braking every axis at its acceleration limit: the positions measured.
    pub fn brake(&mut self) -> Axes {
        let mut actual = [0.0; MAX_AXES];
        for (x, a) in actual.iter_mut().zip(&mut self.axis).take(self.count) {
            *x = a.brake();
        }
        actual
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lathe with a C axis: wire order X, Z, C; each entry is cut at its own axis's
    /// limits, C (modulo, none) never.
    #[test]
    fn each_wire_entry_takes_its_own_axis_data() {
        let md = MachineData::from_toml_str(
            "dialect = \"siemens-808d\"\nmachine = \"turning\"\n[program]\ninitial_plane = \"zx\"\n\
             [axes.X]\nmax_velocity = 6000\nmax_acceleration = 1500\nmax_jerk = 3e4\n\
             software_limits = [-1000.0, 1000.0]\n\
             [axes.Z]\nmax_velocity = 12000\nmax_acceleration = 2000\nmax_jerk = 4e4\n\
             software_limits = [-500.0, 500.0]\n\
             [axes.C]\nkind = \"rotary\"\nmodulo = true\nmax_velocity = 36000\n\
             max_acceleration = 3600\nmax_jerk = 7.2e4\n",
            "lathe.toml",
        )
        .unwrap();
        let d = DriveData::new(&md, &WireAxes::new(&md));
        assert_eq!(d.count, 3);
        assert_eq!(&d.v_max[..3], &[100.0, 200.0, 600.0]);
        assert_eq!(&d.a_max[..3], &[1500.0, 2000.0, 3600.0]);
        let mut p = [0.0; MAX_AXES];
        p[..3].copy_from_slice(&[900.0, -600.0, 1e5]);
        let (cut, limited) = d.limit(&p);
        assert!(limited);
        assert_eq!(&cut[..3], &[900.0, -500.0, 1e5]);
        p[1] = -400.0;
        assert_eq!(d.limit(&p), (p, false));
    }
}
