//! G codes in the block build: each looked up in the dialect's table, checked (one code per
//! modal group, the codes TRC forbids, codes softnc does not implement), then applied as its
//! dialect-free effect to the modal state or the block. Also the TRC rule that needs the
//! block's motion: selection and deselection only in a linear block.

use super::super::block::*;
use super::super::fault::{fault, Fault, Offset, R};
use super::super::interpreter::Interpreter;
use super::super::words::{int_value, DiameterWord, Words};
use crate::alarm::AlarmCode;
use crate::dialect::{Dialect, GCodeDef, GEffect, GName};
use crate::trc::SideChange;

/// A block's G codes as their table rows (not copies: the common block has one or two), with
/// the offsets of their words.
pub(super) type Codes = heapless::Vec<(&'static GCodeDef, u32), 16>;

/// What a block's G codes ask of the block beyond its modal state.
pub(super) struct BlockCodes {
    /// The dwell code's number, as written.
    pub dwell: Option<u16>,
    /// 840C G25 (false) / G26 (true): the axis words are working-area limits.
    pub working_area: Option<bool>,
    /// Where a G40/G41/G42 was written.
    pub trc_at: Option<u32>,
    /// Where a numbered work offset's G code was written (Fanuc G54.1: the set is P).
    pub numbered_at: Option<u32>,
    /// A tool length compensation code was written (Fanuc G43/G44/G49).
    pub length: bool,
    /// The block's S is the spindle speed limit (840C G92, G26).
    pub spindle_limit: bool,
    /// A spindle limit code (840C G92): the block sets the limit and nothing else.
    pub limit_only: bool,
    /// A canned cycle code was written (Fanuc G81 …).
    pub cycle: Option<super::cycles::CycleKind>,
    /// A reference point return (its code; true for the second reference, G30).
    pub reference: Option<(u16, bool)>,
    /// A data-setting block (G92, G52, G10).
    pub setting: Option<super::settings::Setting>,
    /// A block that programs the frame (G51.1 G50.1 G51 G50 G68 G69).
    pub frame: Option<super::frames::FramePart>,
    /// A pole definition (SINUMERIK G110 G111 G112), with where its code stands.
    pub pole: Option<(PoleOrigin, u32)>,
    /// The spindle revolutions of a dwell (SINUMERIK `G4 S…`).
    pub dwell_revolutions: Option<f64>,
    /// A smooth approach or retraction (SINUMERIK G147 … G348) and where it was written.
    pub sar: Option<(GEffect, u32)>,
    /// A multiple repetitive turning cycle (Fanuc lathe G70, G71) and where it was written.
    pub turning: Option<(crate::dialect::TurningCycle, u32)>,
    /// A one-shot lathe cycle (Fanuc lathe G74, G75, G76) and where it was written.
    pub lathe: Option<(crate::dialect::LatheCycle, u32)>,
}

impl Interpreter<'_> {
    /// Step 2: every G code looked up and checked against the others and the active TRC.
    #[inline(always)]
    pub(super) fn g_codes(&self, w: &Words) -> R<Codes> {
        let mut codes = Codes::new();
        for &(code, at) in &w.g {
            let def = self.d.gcode(code).ok_or_else(|| self.unknown_g(code, at))?;
            if let Some((other, _)) = codes
                .iter()
                .find(|(e, _)| Dialect::same_group(e.effect, def.effect))
            {
                return Err(fault(
                    AlarmCode::SameGroupTwice,
                    at,
                    format!(
                        "{} and {} belong to the same group",
                        GName(code),
                        GName(other.code)
                    ),
                ));
            }
            self.check_with_trc(def, at)?;
            if let GEffect::Unsupported(what) = def.effect {
                return Err(fault(
                    AlarmCode::NotSupported,
                    at,
                    format!("{what} is not supported by softnc"),
                ));
            }
            let _ = codes.push((def, at));
        }
        Ok(codes)
    }

    #[cold]
    fn unknown_g(&self, code: u16, at: u32) -> Box<Fault> {
        fault(
            AlarmCode::UnknownGCode,
            at,
            format!("{} is not a {} G code", GName(code), self.d.name.as_str()),
        )
    }

    /// With TRC active, no plane change (alarm 10755) and none of the codes the dialect
    /// forbids (840C 11.4, alarm 10754).
    #[inline(always)]
    fn check_with_trc(&self, def: &GCodeDef, at: u32) -> R<()> {
        let old = &self.block.modal;
        if old.trc == TrcSide::Off {
            return Ok(());
        }
        let code = def.code;
        if matches!(def.effect, GEffect::Plane(p) if p != old.plane) {
            return Err(fault(
                AlarmCode::PlaneChangeWithTrc,
                at,
                format!(
                    "{}: the plane cannot be changed while TRC is active",
                    GName(code)
                ),
            ));
        }
        if def.forbidden_with_trc {
            return Err(self.forbidden_with_trc(&GName(code).to_string(), at));
        }
        Ok(())
    }

    /// `what` (a code as written) may not stand in a block while TRC is active.
    #[cold]
    pub(in crate::frontend) fn forbidden_with_trc(
        &self,
        what: &str,
        at: impl Offset,
    ) -> Box<Fault> {
        let trc_on = self
            .d
            .codes_of(&[GEffect::Trc(TrcSide::Left), GEffect::Trc(TrcSide::Right)]);
        fault(
            AlarmCode::ForbiddenWithTrc,
            at,
            format!(
                "{what} may not be programmed while TRC ({trc_on}) is active; deselect TRC first"
            ),
        )
    }

    /// Step 4: the G codes' effects, on the modal state `new` or on the block.
    #[inline(always)]
    pub(super) fn g_effects(&mut self, codes: &Codes, new: &mut ModalState) -> R<BlockCodes> {
        let mut g = BlockCodes {
            dwell: None,
            working_area: None,
            trc_at: None,
            numbered_at: None,
            cycle: None,
            reference: None,
            setting: None,
            frame: None,
            sar: None,
            turning: None,
            lathe: None,
            length: false,
            spindle_limit: false,
            limit_only: false,
            pole: None,
            dwell_revolutions: None,
        };
        self.machine_coordinates = false;
        for &(&GCodeDef { code, effect, .. }, at) in codes {
            match effect {
                GEffect::Motion(m) => {
                    // A motion code ends the canned cycle mode (0i-MF: group 01 cancels 09).
                    self.cycle = None;
                    new.motion = m
                }
                GEffect::Dwell => g.dwell = Some(code),
                GEffect::ExactStopBlock => self.block.exact_stop = true,
                GEffect::ExactStopModal(on) => new.exact_stop = on,
                // A change while TRC is active was refused in step 2.
                GEffect::Plane(p) => new.plane = p,
                GEffect::Units(u) => {
                    new.units = u;
                    new.feed_units = u;
                }
                GEffect::GeometryUnits(u) => {
                    // F is in the basic system (808D "Inch and metric dimensioning").
                    new.units = u;
                    new.feed_units = self.md.program.units;
                }
                GEffect::Distance(x) => new.distance = x,
                GEffect::Trc(side) => {
                    // A frame that turns the plane over turns G41 into G42 (frame.rs).
                    let side = match side {
                        TrcSide::Left if self.coords.frame.flips(new.plane) => TrcSide::Right,
                        TrcSide::Right if self.coords.frame.flips(new.plane) => TrcSide::Left,
                        s => s,
                    };
                    self.block.trc = Some(side);
                    new.trc = side;
                    g.trc_at = Some(at);
                }
                GEffect::Corner(cp) => new.corner = cp,
                GEffect::Approach(sp) => self.block.approach = Some(sp),
                GEffect::Selection(sp) => {
                    new.selection = selection(&self.block.modal, sp, code, at)?
                }
                GEffect::FeedAdaption(fa) => new.feed_adaption = fa,
                GEffect::Masking(on) => new.masking = on,
                GEffect::WorkOffset(i) => new.work_offset = i,
                GEffect::NumberedWorkOffset => g.numbered_at = Some(at),
                GEffect::MachineCoordinates => self.machine_coordinates = true,
                GEffect::FeedPerRevolution(on) => feed_per_revolution(new, on),
                GEffect::FeedType(t) => {
                    let (per_rev, css) = match t {
                        FeedType::PerMinute => (Some(false), false),
                        FeedType::PerRevolution => (Some(true), false),
                        FeedType::CuttingSpeed => (Some(true), true),
                        FeedType::CuttingSpeedOff => (None, false),
                    };
                    if let Some(on) = per_rev {
                        feed_per_revolution(new, on);
                    }
                    new.css = css;
                }
                GEffect::Pole(origin) => g.pole = Some((origin, at)),
                GEffect::ConstantSurfaceSpeed(on) => new.css = on,
                GEffect::SpindleLimit => {
                    g.spindle_limit = true;
                    g.limit_only = true;
                }
                GEffect::ToolLength(c) => {
                    new.length_comp = c;
                    g.length = true;
                }
                GEffect::WorkingArea { max } => {
                    g.working_area = Some(max);
                    // 880: "maximum working area limitation/spindle speed limitation S".
                    g.spindle_limit |= max;
                }
                GEffect::PoleHere => new.pole = self.cur,
                GEffect::Unsupported(_) => {}
                other => self.program_effect(other, code, at, &mut g)?,
            }
        }
        Ok(g)
    }

    /// Step 4, the codes that change how the program runs or what the block's axis words
    /// mean: canned cycles, reference return, settings, the frame, polar coordinates,
    /// macro calls.
    fn program_effect(&mut self, effect: GEffect, code: u16, at: u32, g: &mut BlockCodes) -> R<()> {
        use super::frames::FramePart;
        use super::settings::Setting;
        match effect {
            GEffect::Cycle(kind) => g.cycle = Some(kind),
            GEffect::CycleReturn(initial) => self.cycle_to_initial = initial,
            GEffect::CycleCancel => self.cycle = None,
            GEffect::ReferenceReturn(second) => g.reference = Some((code, second)),
            GEffect::TurningCycle(kind) => g.turning = Some((kind, at)),
            GEffect::LatheCycle(kind) => g.lathe = Some((kind, at)),
            GEffect::PositionSetting => {
                // Its S is the spindle speed limit (Fanuc G92 S, lathe G50 S).
                g.setting = Some(Setting::Position);
                g.spindle_limit = true;
            }
            GEffect::LocalCoordinates => g.setting = Some(Setting::Local),
            GEffect::DataSetting => g.setting = Some(Setting::Data(code)),
            GEffect::PolarCoordinates(on) => {
                let last = self.coords.polar.unwrap_or((0.0, 0.0));
                self.coords.polar = on.then_some(last);
            }
            GEffect::Mirror(on) => g.frame = Some(FramePart::Mirror(on)),
            GEffect::Scaling(on) => g.frame = Some(FramePart::Scale(on)),
            GEffect::Rotation(on) => g.frame = Some(FramePart::Rotation(on)),
            GEffect::ModalMacroCancel => self.calls.modal = None,
            GEffect::SmoothApproach(_) | GEffect::SmoothRetraction(_) => g.sar = Some((effect, at)),
            GEffect::SmoothSide(side) => self.smooth_state().side = side,
            GEffect::SmoothPath(path) => self.smooth_state().path = path,
            GEffect::MacroCall | GEffect::ModalMacroCall => {
                return Err(fault(
                    AlarmCode::Syntax,
                    at,
                    format!("{} must stand first in its block", GName(code)),
                ))
            }
            _ => {}
        }
        Ok(())
    }

    /// Step 4, a numbered work offset: the set is P (Fanuc G54.1 P1…P48).
    pub(super) fn numbered_work_offset(&self, w: &Words, at: u32, new: &mut ModalState) -> R<()> {
        let p = w.p.ok_or_else(|| {
            fault(
                AlarmCode::MissingValue,
                at,
                "a numbered work offset needs its number P",
            )
        })?;
        let n = int_value(p.value, p.at, "P")?;
        new.work_offset = self.d.numbered_work_offset(n).ok_or_else(|| {
            fault(
                AlarmCode::BadNumber,
                p.at,
                format!(
                    "P{n}: the control has numbered work offsets P1 … P{}",
                    self.d.numbered_work_offsets
                ),
            )
        })?;
        Ok(())
    }

    /// Step 4, words that switch a modal state: 808D `DIAMON`/`DIAMOF`/`DIAM90`.
    #[inline(always)]
    pub(super) fn diameter_switch(&self, w: &Words, new: &mut ModalState) {
        if let Some(word) = w.diameter {
            new.diameter = word != DiameterWord::Off;
            new.radius_incremental = word == DiameterWord::Absolute;
        }
    }

    /// Step 9: TRC selected or deselected only in a linear block (840C 11.3/11.5, Fanuc 026).
    /// Fanuc changes sides in offset mode in any block, circles included (no new start-up).
    #[inline(always)]
    pub(super) fn trc_in_linear_block(&self, new: &ModalState, trc_at: Option<u32>) -> R<()> {
        let d = self.d;
        let blk = &self.block;
        let old_trc = blk.modal.trc;
        let fanuc_side_change = d.trc.side_change == SideChange::Intersection
            && old_trc != TrcSide::Off
            && new.trc != TrcSide::Off
            && new.trc != old_trc;
        if let (Some(side), Some(at)) = (blk.trc, trc_at) {
            let frame = &self.coords.frame;
            if side != TrcSide::Off && frame.active() && !frame.keeps_plane(new.plane) {
                return Err(tilted_plane(new.plane, at));
            }
            let arc = new.motion.is_arc();
            if arc && !fanuc_side_change && (blk.motion.is_some() || d.trc_codes_need_linear_mode) {
                return Err(self.trc_not_linear(at));
            }
        }
        Ok(())
    }
}

impl Interpreter<'_> {
    #[cold]
    fn trc_not_linear(&self, at: u32) -> Box<Fault> {
        let linear = self.d.codes_of(&[
            GEffect::Motion(MotionMode::Rapid),
            GEffect::Motion(MotionMode::Linear),
        ]);
        fault(
            self.d.trc_not_linear,
            at,
            format!(
                "tool radius compensation can only be selected or deselected in a {linear} block"
            ),
        )
    }
}

/// Compensation works in its plane; a frame that tilts it (a rotation about another axis)
/// leaves no plane to compensate in (docs/sinumerik.md, "Frames").
#[cold]
fn tilted_plane(plane: Plane, at: u32) -> Box<Fault> {
    fault(
        AlarmCode::NotSupported,
        at,
        format!(
            "tool radius compensation in the {} plane while the frame tilts it",
            plane.name()
        ),
    )
}

/// Feed per revolution on or off. A change of the feed's unit deletes F: the next move needs
/// its own (840D feeds "F is deleted when switching G93/G94/G95"; Fanuc likewise).
fn feed_per_revolution(new: &mut ModalState, on: bool) {
    if new.feed_per_rev != on {
        new.feed = 0.0;
    }
    new.feed_per_rev = on;
}

/// A modal selection method; ISG inner-corner selection cannot be switched on while TRC is
/// active (TF5200 G238).
fn selection(old: &ModalState, sp: SelectionPolicy, code: u16, at: u32) -> R<SelectionPolicy> {
    if sp == SelectionPolicy::InnerCorner && old.trc != TrcSide::Off && old.selection != sp {
        return Err(fault(
            AlarmCode::ForbiddenWithTrc,
            at,
            format!("G{code}: inner-corner selection cannot be switched on while TRC is active"),
        ));
    }
    Ok(sp)
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use super::*;

    #[test]
    fn one_code_per_group_and_the_codes_trc_forbids() {
        let a = run("isg", "G0 G1\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::SameGroupTwice, 4));
        assert_eq!(a.message, "G1 and G0 belong to the same group");
        let trc = "G41 D1 G1 X0 Y0 F100\n";
        let a = run("siemens-840c", &format!("{trc}G18\n")).unwrap_err();
        assert_eq!(a.code, AlarmCode::PlaneChangeWithTrc);
        // 840C 11.4: G17 is forbidden with TRC even when it keeps the plane.
        let a = run("siemens-840c", &format!("{trc}G17\n")).unwrap_err();
        assert_eq!(a.code, AlarmCode::ForbiddenWithTrc);
        assert!(run("isg", &format!("{trc}G17\n")).is_ok());
        let a = run("siemens-840c", "G16\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::NotSupported);
    }

    #[test]
    fn trc_codes_only_in_linear_blocks() {
        let a = run("siemens-840c", "G2 G41 D1 X10 Y0 I5 F100\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::TrcSelectionNotLinear, 4));
        // Fanuc 026: also in circular mode without a motion.
        let a = run("fanuc", "G2 F100\nG41 D1\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::FanucTrcNotLinear);
        assert!(run("isg", "G2 F100\nG41 D1\n").is_ok());
    }
}
