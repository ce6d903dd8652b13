//! Blocks that set data instead of moving (Fanuc 0i-MF): G92 (the position now gets the
//! values written: the zero shifts), G52 (a local coordinate system: the values are its
//! zero in the workpiece coordinates; 0 cancels it) and G10 (programmable data input: work
//! offsets L2 P1…P6 for G54…G59 and L20 P1…P48 for G54.1, tool offsets L10…L13 P with R as
//! memory C's H geometry, H wear, D geometry, D wear; G90 writes the value, G91 adds it).
//! A written offset acts from the next block that uses it, as on the control: a work offset
//! at the next absolute position, an H or D value at its next H or D word.

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{int_value, Val, Words};
use crate::alarm::AlarmCode;
use crate::dialect::GName;
use crate::machine_data::{AxisKind, AXES};
use crate::tools::OffsetValue;
use crate::work_offsets::MAX_WORK_OFFSET;

/// Which setting a block makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    /// G92.
    Position,
    /// G52.
    Local,
    /// G10 (its code, for messages).
    Data(u16),
}

impl Interpreter<'_> {
    /// Step 8 of a setting block.
    pub(super) fn setting(
        &mut self,
        w: &Words,
        new: &ModalState,
        s: Setting,
        block_col: usize,
    ) -> R<()> {
        if matches!(s, Setting::Position | Setting::Local) && new.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::ForbiddenWithTrc,
                block_col,
                "the zero cannot shift while tool radius compensation is active",
            ));
        }
        match s {
            Setting::Position => {
                // G92 also ends the local coordinate system of the axes it names.
                let set = new.work_offset;
                for (i, v) in self.axis_values(w, new)? {
                    self.coords.g52[i] = 0.0;
                    let base = self.work_offset_table().get(set)[i];
                    self.coords.g92[i] = self.axis_position().axis(i) - base - v;
                }
                Ok(())
            }
            Setting::Local => {
                for (i, v) in self.axis_values(w, new)? {
                    self.coords.g52[i] = v;
                }
                Ok(())
            }
            Setting::Data(code) => self.data_input(w, new, code, block_col),
        }
    }

    /// The axis words of a setting block as (axis, mm or degrees).
    fn axis_values(&self, w: &Words, new: &ModalState) -> R<heapless::Vec<(usize, f64), AXES>> {
        let mut out = heapless::Vec::new();
        let words = w.axis.iter().chain(w.additional.iter()).enumerate();
        for (i, a) in words {
            let Some(a) = a else { continue };
            if !self.md.has_axis(i) {
                return Err(fault(
                    AlarmCode::UnknownAddress,
                    a.at,
                    "axis not configured on this machine",
                ));
            }
            let rotary = self
                .md
                .axes
                .get(i)
                .is_some_and(|ax| ax.kind == AxisKind::Rotary);
            let units = if rotary {
                crate::machine_data::Units::Mm
            } else {
                new.units
            };
            // A diameter-programmed X is a diameter here too (G50 X100: radius 50).
            let half = if i == 0 && new.diameter { 0.5 } else { 1.0 };
            let v = self.length(*a, units) * half;
            if !v.is_finite() || v.abs() > MAX_WORK_OFFSET {
                return Err(fault(AlarmCode::BadNumber, a.at, "value out of range"));
            }
            let _ = out.push((i, v));
        }
        Ok(out)
    }

    /// G10: L selects the table, P the entry.
    fn data_input(&mut self, w: &Words, new: &ModalState, code: u16, at: usize) -> R<()> {
        let name = GName(code);
        let l = w.l.ok_or_else(|| {
            fault(
                AlarmCode::MissingValue,
                at,
                format!("{name} needs L (which data)"),
            )
        })?;
        let p = w.p.ok_or_else(|| {
            fault(
                AlarmCode::MissingValue,
                at,
                format!("{name} needs P (which entry)"),
            )
        })?;
        let pn = int_value(p.value, p.at, "P")?;
        match int_value(l.value, l.at, "L")? {
            2 | 20 => {
                let set = self.written_set(l.value as u32, pn, p)?;
                for (i, v) in self.axis_values(w, new)? {
                    let old = self.work_offset_table().get(set)[i];
                    let value = if new.distance == Distance::Incremental {
                        old + v
                    } else {
                        v
                    };
                    self.work_offset_table_mut().set(set, i, value);
                }
                Ok(())
            }
            10..=13 => self.tool_input(w, new, l.value as u32, pn, at),
            other => Err(fault(
                AlarmCode::NotSupported,
                l.at,
                format!("{name} L{other} is not supported (L2, L10…L13, L20 are)"),
            )),
        }
    }

    /// The work offset set G10 L2 P (G54…G59 as P1…P6) or L20 P (G54.1 P) names.
    fn written_set(&self, l: u32, p: u32, at: Val) -> R<u8> {
        let set = if l == 2 {
            // P1 … P6: the sets with a G code of their own (G54 … G59).
            (1..=self.d.coded_work_offsets() as u32)
                .contains(&p)
                .then_some(p as u8)
        } else {
            self.d.numbered_work_offset(p)
        };
        set.ok_or_else(|| {
            fault(
                AlarmCode::UnknownOffset,
                at.at,
                format!("P{p} names no work offset of this control"),
            )
        })
    }

    /// G10 L10…L13 P R: a tool offset value.
    fn tool_input(&mut self, w: &Words, new: &ModalState, l: u32, p: u32, at: usize) -> R<()> {
        let r = w
            .radius
            .ok_or_else(|| fault(AlarmCode::MissingValue, at, "the offset value R is missing"))?;
        if p == 0 {
            return Err(fault(
                AlarmCode::UnknownOffset,
                at,
                "offset number 0 cannot be written",
            ));
        }
        let which = match l {
            10 => OffsetValue::Length,
            11 => OffsetValue::LengthWear,
            12 => OffsetValue::Radius,
            _ => OffsetValue::RadiusWear,
        };
        let v = self.length(r, new.units);
        if !v.is_finite() || v.abs() > MAX_WORK_OFFSET {
            return Err(fault(
                AlarmCode::BadNumber,
                r.at,
                "offset value out of range",
            ));
        }
        let value = if new.distance == Distance::Incremental {
            let old = self
                .tool_table()
                .find(None, p)
                .map_or(0.0, |o| o.value(which));
            old + v
        } else {
            v
        };
        self.tool_table_mut().write_value(p, which, value);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;

    fn xs(src: &str) -> Vec<f64> {
        super::super::super::end_xs("fanuc", src)
    }

    #[test]
    fn g92_and_g52_shift_the_zero() {
        // G92 X0 at X10: the zero moves to 10, so X5 is 15.
        assert_eq!(xs("G0 X10. Y0.\nG92 X0.\nG0 X5.\n"), [10.0, 15.0]);
        // G92 X0 again at 15 after a G92: the zero moves to 15 (not by 15 more).
        assert_eq!(
            xs("G0 X10.\nG92 X0.\nG0 X5.\nG92 X0.\nG0 X1.\n"),
            [10.0, 15.0, 16.0]
        );
        // G52 X20: X5 is 25; G52 X0 takes it back.
        assert_eq!(xs("G52 X20.\nG0 X5.\nG52 X0.\nG0 X5.\n"), [25.0, 5.0]);
        // G92 ends the local system of its axes: after G92 X0 at 25, G52 X0 changes nothing.
        assert_eq!(
            xs("G52 X20.\nG0 X5.\nG92 X0.\nG52 X0.\nG0 X1.\n"),
            [25.0, 26.0]
        );
        let a = run("fanuc", "G0 X0. Y0.\nG41 D1 G1 X10. F100.\nG92 X0.\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::ForbiddenWithTrc);
    }

    #[test]
    fn g10_writes_offsets_that_act_from_their_next_use() {
        // L2 P1 is G54: absolute writes the value, incremental adds to it.
        let src = "G54 G0 X5.\nG10 L2 P1 X100.\nG0 X5.\nG91 G10 L2 P1 X-10.\nG90 G0 X5.\n";
        assert_eq!(xs(src), [5.0, 105.0, 95.0]);
        // L20 P2 is G54.1 P2.
        assert_eq!(xs("G10 L20 P2 X7.\nG54.1 P2 G0 X1.\n"), [8.0]);
        // L10 and L12: H20's length and D20's radius, taken at the next H and D words.
        let b = run(
            "fanuc",
            "G10 L10 P20 R50.\nG10 L12 P20 R4.\nG43 H20 G0 Z10.\nG41 D20 G1 X10. Y0. F100.\n",
        )
        .unwrap();
        assert_eq!((b[2].modal.length, b[3].modal.radius), (50.0, 4.0));
        let a = run("fanuc", "G10 L2 P7 X1.\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::UnknownOffset, 8));
        let a = run("fanuc", "G10 L3 P1 X1.\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::NotSupported);
    }
}
