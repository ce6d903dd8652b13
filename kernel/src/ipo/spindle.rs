//! The spindle's speed setpoint (docs/spindle.md): the channel turns the spindle as
//! programmed into rev/min every cycle — constant surface speed follows the transverse axis
//! — and a feed per revolution follows the spindle's actual speed (the PLC's, or
//! [`SpindleModel`] where no PLC runs).

use crate::frontend::block::{SpindleDir, SpindleProgram};

/// The speed setpoint, rev/min, positive clockwise (M3), negative counter-clockwise (M4), 0
/// stopped or oriented. Under constant surface speed n = v·1000 / (2π·r) with r the
/// transverse axis's distance from the centre (`x`, a radius, mm) and v in m/min. The
/// limit holds for both: the program's (840C G92, 808D LIMS, 840D: "LIMS acts with G96 and
/// G97") if below machine data's `max_speed`, else `max_speed`; under constant surface
/// speed it is also the speed at the centre.
pub fn spindle_setpoint(p: &SpindleProgram, x: f64, max_speed: f64) -> f64 {
    let limit = if p.limit > 0.0 {
        p.limit.min(max_speed)
    } else {
        max_speed
    };
    let n = if p.css {
        let circumference = 2.0 * core::f64::consts::PI * x.abs();
        if circumference * limit <= p.speed * 1000.0 {
            limit
        } else {
            p.speed * 1000.0 / circumference
        }
    } else {
        p.speed.min(limit)
    };
    match p.dir {
        SpindleDir::Clockwise => n,
        SpindleDir::CounterClockwise => -n,
        SpindleDir::Stop | SpindleDir::Orient => 0.0,
    }
}

/// A spindle drive that follows its setpoint at a constant acceleration (machine data
/// `plc.spindle_acceleration`, rev/min per s): the actual speed where no PLC reports one
/// (`softnc simulate`, the kernel alone). The same ramp as plc-sim's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpindleModel {
    rpm: f64,
    /// rev/min per cycle.
    step: f64,
}

impl SpindleModel {
    pub fn new(acceleration: f64, cycle_s: f64) -> Self {
        SpindleModel {
            rpm: 0.0,
            step: acceleration * cycle_s,
        }
    }

    /// One cycle toward `setpoint`; the actual speed after it.
    pub fn follow(&mut self, setpoint: f64) -> f64 {
        self.rpm += (setpoint - self.rpm).clamp(-self.step, self.step);
        self.rpm
    }

    /// The actual speed, rev/min.
    pub fn rpm(&self) -> f64 {
        self.rpm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prog(dir: SpindleDir, speed: f64, css: bool, limit: f64) -> SpindleProgram {
        SpindleProgram {
            dir,
            speed,
            css,
            limit,
        }
    }

    #[test]
    fn rev_per_min_signed_by_direction_and_limited_by_machine_data() {
        let cw = prog(SpindleDir::Clockwise, 1200.0, false, 0.0);
        assert_eq!(spindle_setpoint(&cw, 50.0, 6000.0), 1200.0);
        let ccw = SpindleProgram {
            dir: SpindleDir::CounterClockwise,
            ..cw
        };
        assert_eq!(spindle_setpoint(&ccw, 50.0, 6000.0), -1200.0);
        assert_eq!(spindle_setpoint(&cw, 50.0, 1000.0), 1000.0);
        // The program's limit holds under G97 too (840D: LIMS acts with G96 and G97).
        let limited = SpindleProgram { limit: 800.0, ..cw };
        assert_eq!(spindle_setpoint(&limited, 50.0, 6000.0), 800.0);
        for dir in [SpindleDir::Stop, SpindleDir::Orient] {
            assert_eq!(
                spindle_setpoint(&SpindleProgram { dir, ..cw }, 0.0, 6000.0),
                0.0
            );
        }
    }

    #[test]
    fn constant_surface_speed_follows_the_radius_up_to_the_limit() {
        // 200 m/min at r = 50 mm: 200000 / (2π·50) = 636.6198 rev/min; at r = 10 mm
        // 3183.099; at r = 5 mm 6366 > the program's limit 4000; at the centre the limit.
        let css = prog(SpindleDir::Clockwise, 200.0, true, 4000.0);
        let n = |x| spindle_setpoint(&css, x, 6000.0);
        assert!((n(50.0) - 636.619_772_367_581_4).abs() < 1e-9);
        assert!(
            (n(-10.0) - 3_183.098_861_837_907).abs() < 1e-9,
            "either side of the centre"
        );
        assert_eq!(n(5.0), 4000.0);
        assert_eq!(n(0.0), 4000.0);
        // Without a program limit the machine's maximum holds.
        let free = SpindleProgram { limit: 0.0, ..css };
        assert_eq!(spindle_setpoint(&free, 0.0, 6000.0), 6000.0);
        // A program limit above the machine's is the machine's.
        let high = SpindleProgram {
            limit: 9000.0,
            ..css
        };
        assert_eq!(spindle_setpoint(&high, 1.0, 6000.0), 6000.0);
    }

    #[test]
    fn the_model_ramps_at_its_acceleration() {
        // 6000 rev/min per s, 1 ms cycles: 6 rev/min per cycle; 1200 in 200 cycles.
        let mut m = SpindleModel::new(6000.0, 0.001);
        let mut k = 0;
        while m.follow(1200.0) < 1200.0 {
            k += 1;
        }
        assert_eq!(k, 199);
        assert_eq!(m.follow(-6.0), 1194.0);
    }
}
