//! The machine's axes on the wire: the configured path axes in the machine's order
//! (protocol's `AxisList`), and the mapping between a wire position array and the kernel's
//! [`AxisPos`] (geometry axes and additional-axis slots). Every process builds it from the
//! same machine data, so they agree on the order without asking each other.

use nc_kernel::{AxisKind, AxisPos, MachineData, AXIS_NAMES};
use softnc_protocol::{AxisList, MAX_AXES};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WireAxes {
    pub list: AxisList,
    /// Wire entry n is axis `index[n]` of [`AXIS_NAMES`].
    pub index: [usize; MAX_AXES],
}

impl WireAxes {
    pub fn new(md: &MachineData) -> Self {
        let mut list = AxisList::default();
        let mut index = [0; MAX_AXES];
        for (n, (i, a)) in md.axes.configured().take(MAX_AXES).enumerate() {
            list.names[n] = AXIS_NAMES[i] as u8;
            index[n] = i;
            if a.kind == AxisKind::Rotary {
                list.kinds |= 1 << n;
            }
            if a.modulo {
                list.kinds |= 1 << (8 + n);
            }
            list.count += 1;
        }
        WireAxes { list, index }
    }

    pub fn count(&self) -> usize {
        usize::from(self.list.count)
    }

    /// The axes of `p` in wire order, 0 past the count.
    pub fn to_wire(&self, p: &AxisPos) -> [f64; MAX_AXES] {
        let mut w = [0.0; MAX_AXES];
        for (n, x) in w.iter_mut().enumerate().take(self.count()) {
            *x = p.axis(self.index[n]);
        }
        w
    }

    /// The axis number ([`AXIS_NAMES`] index) of wire slot `slot`, if configured.
    pub fn axis_of_slot(&self, slot: usize) -> Option<usize> {
        (slot < self.count()).then(|| self.index[slot])
    }

    /// Values per axis number ([`AXIS_NAMES`] order) in wire order, 0 past the count.
    pub fn to_wire_all(&self, v: &[f64; nc_kernel::AXES]) -> [f64; MAX_AXES] {
        let mut w = [0.0; MAX_AXES];
        for (n, x) in w.iter_mut().enumerate().take(self.count()) {
            *x = v[self.index[n]];
        }
        w
    }

    /// A wire position array as the kernel's position (axes not configured at 0).
    pub fn from_wire(&self, w: &[f64; MAX_AXES]) -> AxisPos {
        let mut p = AxisPos::default();
        for (n, x) in w.iter().enumerate().take(self.count()) {
            p.set_axis(self.index[n], *x);
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lathe_with_c_lists_x_z_c() {
        let md = MachineData::from_toml_str(
            "dialect = \"siemens-808d\"\nmachine = \"turning\"\n[program]\ninitial_plane = \"zx\"\n\
             [axes.X]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n\
             [axes.Z]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n\
             [axes.C]\nkind = \"rotary\"\nmodulo = true\n\
             max_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n",
            "lathe.toml",
        )
        .unwrap();
        let w = WireAxes::new(&md);
        assert_eq!(w.list.names().collect::<String>(), "XZC");
        assert!(w.list.rotary(2) && w.list.modulo(2) && !w.list.rotary(1));
        let mut p = AxisPos {
            geo: [10.0, 0.0, -5.0],
            ..Default::default()
        };
        p.add[5] = 370.0;
        let wire = w.to_wire(&p);
        assert_eq!(&wire[..4], &[10.0, -5.0, 370.0, 0.0]);
        assert_eq!(w.from_wire(&wire), p);
    }
}
