//! The system variables softnc binds (0i-MF operator's manual, "System variables"), read
//! from the interpreter's state. Numbers of axes count X, Y, Z, then the machine's other
//! axes in their order (U V W A B C): `#5001+k-1` is axis k.
//!
//! ```text
//! #10001…  H wear   #11001…  H geometry   #12001…  D wear   #13001…  D geometry
//!          (tool compensation memory C, offsets 1…999; #2001…#2200 and #2201…#2400 are
//!          the H values of offsets 1…200 again)
//! #3000 (write)  alarm with the message in ( )     #3006 (write)  stop with message
//! #4001…#4022    modal G codes of the block before  #4107 D #4109 F #4111 H #4114 N
//!                (#4201… the same)                    #4115 O #4119 S #4120 T
//! #5001+k-1  end point of the block before, workpiece coordinates
//! #5021+k-1  present position, machine coordinates    (preprocessing stop)
//! #5041+k-1  present position, workpiece coordinates  (preprocessing stop)
//! #5081+k-1  tool length offset along axis k
//! #5221+20(n-1)+k-1  G54…G59 (n = 1…6)    #7001+20(p-1)+k-1, #14001+…  G54.1 P1…P48
//! ```
//!
//! softnc prepares ahead of the motion, so a variable of the present position reads the
//! end point of the block before and marks its block a preprocessing stop: preparation
//! hands out nothing after it until motion has caught up (docs/macros.md).

use super::super::block::LengthComp;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::expr::{Store, Value};
use super::{slot, Slot};
use crate::alarm::AlarmCode;
use crate::dialect::GEffect;
use crate::machine_data::{Units, AXES};
use crate::tools::OffsetValue;

impl Store for Interpreter<'_> {
    fn read(&self, n: i64, at: usize) -> R<Value> {
        match slot(n) {
            Slot::System(n) => self.system_variable(n, at),
            s => Ok(self.macros.program(s)),
        }
    }
}

impl Interpreter<'_> {
    fn system_variable(&self, n: i64, at: usize) -> R<Value> {
        let v = match n {
            2001..=2400 => {
                let (k, i) = ((n - 2001) / 200, (n - 2001) % 200 + 1);
                self.tool_register(k, i as u32)
            }
            10001..=13999 => {
                let (k, i) = ((n - 10000) / 1000, (n - 10000) % 1000);
                if i == 0 {
                    None
                } else {
                    self.tool_register(k, i as u32)
                }
            }
            4001..=4022 | 4201..=4222 => self.modal_group(((n - 1) % 200) as u8 + 1),
            4107 | 4307 => Some(self.block.modal.d as f64),
            4109 | 4309 => Some(self.block.modal.feed / self.unit()),
            4111 | 4311 => Some(self.block.modal.h as f64),
            4114 | 4314 => self.blk_number.map(|b| b.value as f64),
            4115 | 4315 => self.calls.program_number().map(|o| o as f64),
            4119 | 4319 => Some(self.block.modal.spindle),
            4120 | 4320 => Some(self.block.modal.tool.unwrap_or(0) as f64),
            5001..=5009 => self.workpiece(n - 5001),
            5021..=5029 => {
                self.present_state();
                self.machine(n - 5021)
            }
            5041..=5049 => {
                self.present_state();
                self.workpiece(n - 5041)
            }
            5081..=5089 => self.length_along(n - 5081),
            5221..=5340 => self.work_offset_value(((n - 5221) / 20 + 1) as u8, (n - 5221) % 20),
            7001..=7960 => self.numbered_offset(n - 7001),
            14001..=14960 => self.numbered_offset(n - 14001),
            _ => {
                return Err(fault(
                    AlarmCode::UndefinedName,
                    at,
                    format!("#{n} is not a variable softnc provides (docs/macros.md)"),
                ))
            }
        };
        Ok(v)
    }

    /// A variable of the present position was read: its block stops preprocessing.
    fn present_state(&self) {
        self.present_state_read.set(true);
    }

    /// Millimetres per program unit.
    fn unit(&self) -> f64 {
        match self.block.modal.units {
            Units::Mm => 1.0,
            Units::Inch => 25.4,
        }
    }

    /// Axis `k` (0: X) as the machine configures it: X Y Z, then its other axes in order.
    fn axis_slot(&self, k: i64) -> Option<usize> {
        match k {
            0..=2 => Some(k as usize),
            _ => self
                .md
                .axes
                .configured()
                .map(|(i, _)| i)
                .filter(|&i| i >= 3)
                .nth(k as usize - 3),
        }
    }

    fn machine(&self, k: i64) -> Value {
        let i = self.axis_slot(k)?;
        let p = self.axis_position().axis(i);
        Some(p * self.diameter_factor(i) / self.unit())
    }

    fn workpiece(&self, k: i64) -> Value {
        let i = self.axis_slot(k)?;
        let o = self.zero(self.block.modal.work_offset)[i];
        let p = self.axis_position().axis(i);
        Some((p - o) * self.diameter_factor(i) / self.unit())
    }

    /// A position of X reads as a diameter where X is programmed as one (a lathe).
    fn diameter_factor(&self, i: usize) -> f64 {
        if i == 0 && self.block.modal.diameter {
            2.0
        } else {
            1.0
        }
    }

    /// #5081…: the tool length offset acts along the plane's normal.
    fn length_along(&self, k: i64) -> Value {
        let normal = self.block.modal.plane.normal as i64;
        let on = self.block.modal.length_comp != LengthComp::Off;
        let v = if on && k == normal {
            self.block.modal.length
        } else {
            0.0
        };
        Some(v / self.unit())
    }

    fn work_offset_value(&self, set: u8, k: i64) -> Value {
        let i = self.axis_slot(k)?;
        if set == 0 || set > self.d.work_offset_count() {
            return None;
        }
        Some(self.work_offset_table().get(set)[i] / self.unit())
    }

    fn numbered_offset(&self, n: i64) -> Value {
        let set = self.d.numbered_work_offset((n / 20 + 1) as u32)?;
        self.work_offset_value(set, n % 20)
    }

    fn tool_register(&self, kind: i64, number: u32) -> Value {
        // Memory C: H wear, H geometry, D wear, D geometry.
        let which = match kind {
            0 => OffsetValue::LengthWear,
            1 => OffsetValue::Length,
            2 => OffsetValue::RadiusWear,
            _ => OffsetValue::Radius,
        };
        // Every offset number exists on the control: one not in the table reads 0.
        let v = self
            .tool_table()
            .find(None, number)
            .map_or(0.0, |o| o.value(which));
        Some(v / self.unit())
    }

    /// #4001…#4022: the G code in force in modal group `group` (0i-MF numbering), as the
    /// program writes it (54.1 for G54.1).
    fn modal_group(&self, group: u8) -> Value {
        let m = &self.block.modal;
        let effect = match group {
            1 => GEffect::Motion(m.motion),
            2 => GEffect::Plane(m.plane),
            3 => GEffect::Distance(m.distance),
            5 => GEffect::FeedPerRevolution(m.feed_per_rev),
            6 => GEffect::Units(m.units),
            7 => GEffect::Trc(m.trc),
            8 => GEffect::ToolLength(m.length_comp),
            9 => self
                .cycle
                .map_or(GEffect::CycleCancel, |c| GEffect::Cycle(c.kind)),
            13 => GEffect::ConstantSurfaceSpeed(m.css),
            14 => return self.work_offset_code(),
            15 => GEffect::ExactStopModal(m.exact_stop),
            17 => GEffect::PolarCoordinates(self.coords.polar.is_some()),
            _ => return None,
        };
        let def = self.d.gcodes.iter().find(|def| def.effect == effect)?;
        Some(g_value(def.code))
    }

    fn work_offset_code(&self) -> Value {
        let name = self.d.work_offset_name(self.block.modal.work_offset)?;
        let code = name.trim_start_matches('G');
        code.split_whitespace().next()?.parse().ok()
    }
}

/// A table code as the value #4001 gives: 54.1 for G54.1.
fn g_value(code: u16) -> f64 {
    let c = code as usize;
    if c < crate::dialect::G_CODES {
        c as f64
    } else {
        let t = (c - crate::dialect::G_CODES) as f64;
        libm::floor(t / 10.0) + (t % 10.0) / 10.0
    }
}

const _: () = assert!(AXES <= 9, "#5001…#5009 bind nine axes");
