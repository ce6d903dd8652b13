//! Technology words in the block build: the feed F, the spindle speed S, the tool T and its
//! offset D (radius, length, cutting edge from the tool table), and the ISG variables that
//! mirror the active tool (V.G.WZ_AKT.R/L).

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{int_value, Val, Words};
use crate::alarm::AlarmCode;
use crate::dialect::LengthOffset;
use crate::machine_data::Units;

impl Interpreter<'_> {
    /// Step 5: the feed, in mm/min (inch per minute converted).
    #[inline(always)]
    pub(super) fn feed(&self, w: &Words, new: &mut ModalState) -> R<()> {
        if let Some(f) = w.f {
            if f.value <= 0.0 || !f.value.is_finite() {
                return Err(fault(
                    AlarmCode::BadNumber,
                    f.at,
                    "the feed F must be positive",
                ));
            }
            new.feed = self.feed_value(f.value, new);
        }
        Ok(())
    }

    /// A feed value in mm/min or mm/rev: inch converted where F is in inch (G700 on
    /// SINUMERIK, the inch code elsewhere).
    pub(super) fn feed_value(&self, f: f64, new: &ModalState) -> f64 {
        if new.feed_units == Units::Inch {
            f * 25.4
        } else {
            f
        }
    }

    /// Step 5: the spindle speed, from the S words collected into the block: rev/min, the
    /// cutting speed under constant surface speed (m/min, ft/min in inch converted), or the
    /// speed limit in a limit block (840C G92); Siemens `LIMS=` is a limit too.
    #[inline(always)]
    pub(super) fn spindle(
        &self,
        w: &Words,
        new: &mut ModalState,
        limit_block: bool,
        block_col: usize,
    ) -> R<()> {
        let mut s_written = false;
        for a in &self.block.words {
            if a.address == b'S' {
                s_written |= !limit_block;
                if a.value < 0.0 || !a.value.is_finite() {
                    return Err(fault(
                        AlarmCode::BadNumber,
                        block_col,
                        "the spindle speed S must not be negative",
                    ));
                }
                if limit_block {
                    new.spindle_limit = a.value;
                } else if new.css && new.units == Units::Inch {
                    new.spindle = a.value * 0.3048;
                } else {
                    new.spindle = a.value;
                }
            }
        }
        if let Some(l) = w.lims {
            if l.value <= 0.0 || !l.value.is_finite() {
                return Err(fault(
                    AlarmCode::BadNumber,
                    l.at,
                    "the spindle speed limit LIMS must be positive",
                ));
            }
            new.spindle_limit = l.value;
        }
        if self.block.modal.css && !new.css && !s_written {
            new.spindle = self.css_speed_here(new);
        }
        Ok(())
    }

    /// G97 without S after G96 keeps the speed the spindle turns at where the block starts
    /// (840D, TF5200: "the last speed remains").
    fn css_speed_here(&self, new: &ModalState) -> f64 {
        let css = crate::frontend::block::SpindleProgram {
            dir: crate::frontend::block::SpindleDir::Clockwise,
            speed: self.block.modal.spindle,
            css: true,
            limit: new.spindle_limit,
        };
        crate::ipo::spindle_setpoint(&css, self.cur[0], self.md.spindle.max_speed)
    }

    /// Step 6: the tool and its offset. A written tool radius (ISG) overrides the table's.
    #[inline(always)]
    pub(super) fn tool_offset(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        block_col: usize,
    ) -> R<()> {
        if let (Some(t), true) = (w.t, self.d.t_selects_offset) {
            return self.turret_tool(t, new);
        }
        if let Some(t) = w.t {
            new.tool = Some(int_value(t.value, t.at, "T")?);
            self.block.offset_changed = true;
        }
        if let Some((dn, at)) = self.d_number(w, new, block_col)? {
            if dn == 0 {
                self.no_offset(new);
            } else {
                self.offset(dn, at, new)?;
            }
            self.block.offset_changed = true;
        }
        self.vars.tool_length = new.length;
        if w.radius_written.is_some() {
            new.radius = self.vars.tool_radius;
            self.block.offset_changed = true;
        }
        self.vars.tool_radius = new.radius;
        Ok(())
    }

    /// Fanuc lathe: T aabb is tool aa with offset bb (looked up as T aa D bb, else D bb);
    /// offset 00 cancels it.
    fn turret_tool(&mut self, t: Val, new: &mut ModalState) -> R<()> {
        let v = int_value(t.value, t.at, "T")?;
        let (tool, offset) = (v / 100, v % 100);
        new.tool = Some(tool);
        if offset == 0 {
            self.no_offset(new);
        } else {
            self.offset(offset, t.pos(), new)?;
        }
        self.block.offset_changed = true;
        self.vars.tool_length = new.length;
        self.vars.tool_radius = new.radius;
        Ok(())
    }

    /// The D number to look up, with where it points: the D word, or on controls with
    /// cutting edges per tool the active D again under a new T (docs/dialects.md, "Tools on
    /// the 808D").
    fn d_number(&self, w: &Words, new: &ModalState, block_col: usize) -> R<Option<(u32, usize)>> {
        Ok(match w.d {
            Some(v) => Some((int_value(v.value, v.at, "D")?, v.pos())),
            None if self.d.tool_edges && w.t.is_some() && new.d != 0 => Some((new.d, block_col)),
            None => None,
        })
    }

    /// D0: no offset; on the 840C it also deselects TRC (840C 11.5).
    fn no_offset(&mut self, new: &mut ModalState) {
        new.d = 0;
        new.radius = 0.0;
        if self.d.length_offset == LengthOffset::WithD {
            new.length = 0.0;
        }
        new.edge = 0;
        let blk = &mut self.block;
        if self.d.d0_deselects && blk.modal.trc != TrcSide::Off && blk.trc.is_none() {
            blk.trc = Some(TrcSide::Off);
            new.trc = TrcSide::Off;
        }
    }

    /// Offset `dn` from the tool table (under the active tool where tools have edges).
    fn offset(&self, dn: u32, at: usize, new: &mut ModalState) -> R<()> {
        let tool = if self.d.tool_edges { new.tool } else { None };
        let (radius, length, edge) = self.tool_table().resolve(tool, dn).ok_or_else(|| {
            let what = crate::tools::offset_label(tool, dn);
            fault(
                AlarmCode::UnknownOffset,
                at,
                format!("tool offset {what} is not in the tool table"),
            )
        })?;
        new.d = dn;
        new.radius = radius;
        if self.d.length_offset == LengthOffset::WithD {
            new.length = length;
        }
        new.edge = edge.unwrap_or(0);
        Ok(())
    }

    /// Step 6 on controls with H registers (Fanuc G43/G44/G49): the length of H, signed,
    /// taken when a length code or H is written (an H edited in the table acts at the next
    /// H, as a D does). H0 is no length.
    pub(super) fn length_register(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        code: bool,
        block_col: usize,
    ) -> R<()> {
        if self.d.length_offset != LengthOffset::HRegister || !(code || w.h.is_some()) {
            return Ok(());
        }
        if let Some(h) = w.h {
            new.h = int_value(h.value, h.at, "H")?;
        }
        let sign = match new.length_comp {
            LengthComp::Off => 0.0,
            LengthComp::Plus => 1.0,
            LengthComp::Minus => -1.0,
        };
        new.length = if sign == 0.0 || new.h == 0 {
            0.0
        } else {
            let at = w.h.map_or(block_col, |h| h.pos());
            let (_, length, _) = self.tool_table().resolve(None, new.h).ok_or_else(|| {
                fault(
                    AlarmCode::UnknownOffset,
                    at,
                    format!("tool length offset H{} is not in the tool table", new.h),
                )
            })?;
            sign * length
        };
        self.vars.tool_length = new.length;
        self.block.offset_changed = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use super::*;

    #[test]
    fn feed_in_inch_is_converted_and_spindle_speed_kept() {
        let b = run("siemens-840c", "G70 F10 S1200\n").unwrap();
        assert_eq!((b[0].modal.feed, b[0].modal.spindle), (254.0, 1200.0));
        let a = run("siemens-840c", "N5 S-1\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::BadNumber, 1));
    }

    #[test]
    fn sinumerik_inch_codes_switch_the_feed_only_with_g700() {
        // 808D "Inch and metric dimensioning": G70 lengths in inch, F in the machine's
        // mm/min; G700 both. X1 is 25.4 mm either way; G71 F10 is 10 mm/min again.
        let b = run("siemens-840d", "G70 F10 G1 X1\nG700 F10 X2\nG71 F10\n").unwrap();
        let got: Vec<(f64, f64)> = b
            .iter()
            .map(|b| (b.modal.feed, b.motion.map_or(0.0, |m| m.end[0])))
            .collect();
        assert_eq!(got, [(10.0, 25.4), (254.0, 50.8), (10.0, 0.0)]);
    }

    #[test]
    fn sinumerik_feed_type_and_cutting_speed_are_one_group() {
        // G96 switches G95 on and deletes F; G97 keeps G95; G94 switches both off.
        let b = run(
            "siemens-808d",
            "G94 F100\nG96 S180 LIMS=2000\nG97 S800\nF0.2 G94\n",
        )
        .unwrap();
        let got: Vec<(bool, bool, f64)> = b
            .iter()
            .map(|b| (b.modal.feed_per_rev, b.modal.css, b.modal.feed))
            .collect();
        assert_eq!(
            got,
            [
                (false, false, 100.0),
                (true, true, 0.0),
                (true, false, 0.0),
                (false, false, 0.2)
            ]
        );
        assert_eq!(b[1].modal.spindle_limit, 2000.0);
        let a = run("siemens-808d", "G95 G96 S100\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::SameGroupTwice, 5));
    }

    #[test]
    fn d0_deselects_trc_on_the_840c_only() {
        let src = "G41 D1 G1 X0 Y0 F100\nD0\n";
        let b = run("siemens-840c", src).unwrap();
        assert_eq!(
            (b[1].trc, b[1].modal.trc),
            (Some(TrcSide::Off), TrcSide::Off)
        );
        assert_eq!((b[1].modal.radius, b[1].modal.length), (0.0, 0.0));
        let b = run("isg", src).unwrap();
        assert_eq!((b[1].trc, b[1].modal.trc), (None, TrcSide::Left));
        // D1 from the shipped table: radius 10, length 100.
        assert_eq!((b[0].modal.radius, b[0].modal.length), (10.0, 100.0));
        let a = run("isg", "D99\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::UnknownOffset);
    }
}
