//! The block build: a block's collected words become the interpreted block, step by step in
//! the order in which the control executes a block's functions — the way RS274/NGC lists its
//! order of execution — so that a rule that depends on an earlier one (the feed on the units,
//! the motion on the plane and the zero offset, a TRC check on the motion) finds it done.
//! [`Interpreter::build`] is that order; each step lives in the module of its concern:
//! [`gcodes`] (modal groups and their effects), [`technology`] (F S T D), [`flow`] (program
//! stops, `@` commands, dwell) and [`motion`] (end point, polar coordinates, arcs, working
//! area).

mod circles;
mod corner_blocks;
mod corners;
mod cycles;
mod expand;
mod flow;
mod frames;
mod gcodes;
mod lathe;
mod motion;
mod polar;
mod pole;
mod reference;
mod settings;
mod smooth;
mod technology;
mod turning;

pub(super) use corner_blocks::Corners;
pub use corners::CornerKind;
pub(in crate::frontend) use corners::{intersections, Curve, Element};
pub use cycles::CycleKind;
pub(super) use cycles::CycleMode;
pub(super) use expand::{Expansion, Step};
pub(super) use lathe::LatheData;
pub(in crate::frontend) use lathe::{push_all, thread_pass, LatheRun};
pub(super) use motion::{in_range, WorkingArea};
pub(super) use pole::Polar;
pub(super) use smooth::Smooth;
pub(super) use turning::TurningData;
pub(in crate::frontend) use turning::{
    deepest, equidistant, non_monotonic, sign, tip_path, z_turns, Element as TurningElement, Nose,
    Passes, TurningRun, EPS,
};

use super::block::{Block, BlockNo, ModalState};
use super::fault::R;
use super::interpreter::Interpreter;
use super::lexer::column;
use super::words::Words;

impl Interpreter<'_> {
    /// Turns a block's collected words into the block, in the order of execution.
    #[inline]
    pub(in crate::frontend) fn build(&mut self, w: &Words, block_col: usize) -> R<bool> {
        // 1. The block at its place in the text, nothing programmed yet.
        self.begin(w, block_col);
        // 2. G codes looked up and checked against each other and the active TRC (840C 11.4).
        let codes = self.g_codes(w)?;
        // 3. @ commands (840C 11.4).
        self.at_commands(w)?;
        // 4. The G codes' effects, and modal switches written as words (808D DIAMON).
        let mut new = self.block.modal;
        let mut g = self.g_effects(&codes, &mut new)?;
        // SINUMERIK SUPA: as G53, for every zero offset and frame softnc has.
        self.machine_coordinates |= w.suppress;
        if let Some((mode, at)) = w.path.motion {
            self.motion_word(&codes, mode, at, &mut new)?;
        }
        if let Some(at) = g.numbered_at {
            self.numbered_work_offset(w, at, &mut new)?;
        }
        if let Some(kind) = g.cycle {
            let initial = self.cur[new.plane.normal as usize];
            self.cycle = Some(CycleMode::new(kind, initial, self.cycle));
        }
        self.diameter_switch(w, &mut new);
        // SINUMERIK NORM/KONT, DISC= and the corner under it (build/smooth.rs).
        if w.compensation.is_some() || self.smooth.is_some() {
            self.compensation_words(w, &codes, &g, &mut new)?;
        }
        // 5. Feed and spindle speed; a dwell block's F is its time, on SINUMERIK its S may be
        //    revolutions.
        if g.dwell.is_none() {
            self.feed(w, &mut new)?;
        } else if self.d.dwell.s_revolutions {
            g.dwell_revolutions = self.take_s_words();
        }
        self.spindle(w, &mut new, g.spindle_limit, block_col)?;
        // 6. Tool and tool offset (840C 11.5: D0 deselects); the H register's length.
        self.tool_offset(w, &mut new, block_col)?;
        self.length_register(w, &mut new, g.length, block_col)?;
        // 7. Program-flow M functions, acting at block end (840C 11.10); the spindle's.
        self.m_functions(w, &mut new)?;
        // 8. The axis words: a dwell time, the working area's limits, a setting (G92 G52
        //    G10), a reference point return or a canned cycle (expanded into several
        //    moves), a smooth approach or retraction, or the motion.
        match g.sar {
            Some(sar) => self.smooth_block(w, &g, &mut new, sar)?,
            None => self.axis_words(w, &g, &mut new, block_col)?,
        }
        // 9. TRC selected or deselected only in a linear block (840C 11.3/11.5, Fanuc 026);
        //    additional axes move only outside compensation (docs/axes.md).
        self.trc_in_linear_block(&new, g.trc_at)?;
        self.additional_outside_trc(&new, w)?;
        // 10. A chamfer or corner word (Fanuc ,C ,R; SINUMERIK also RNDM): the move waits
        //     for the next one.
        if self.d.sinumerik {
            if w.corner.is_some() || self.corners.is_some() || !w.path.is_empty() {
                self.sinumerik_corners(w, &new)?;
            }
        } else if let Some(word) = w.corner {
            self.corner_request(word, &new, None)?;
        }
        // 11. The block done: position, program end (880 4.2.5: the pole), modal state; a
        //     smooth approach holds it, or blocks go out in its place (build/smooth.rs).
        self.finish(new);
        if self.smooth.is_some() {
            return self.smooth_built();
        }
        Ok(true)
    }

    /// Step 8: what the block's axis words mean.
    fn axis_words(
        &mut self,
        w: &Words,
        g: &gcodes::BlockCodes,
        new: &mut ModalState,
        block_col: usize,
    ) -> R<()> {
        if let Some(code) = g.dwell {
            self.no_additional_axes(w, "a dwell block")?;
            return self.dwell(w, code, g.dwell_revolutions, new, block_col);
        }
        if let Some((origin, at)) = g.pole {
            return self.pole_block(w, new, origin, at);
        }
        if g.limit_only {
            self.no_set_actual_value(w)?;
        }
        if let Some(max) = g.working_area {
            self.no_additional_axes(w, "a working area limit (it bounds X Y Z)")?;
            self.working_area(w, max, new.units);
            return Ok(());
        }
        if let Some(s) = g.setting {
            return self.setting(w, new, s, block_col);
        }
        if let Some(part) = g.frame {
            // G50 and G69 end their part and the block moves as written; the others'
            // axis words are the frame's data.
            if !self.frame_block(w, new, part, block_col)? {
                return Ok(());
            }
        }
        if let Some((code, second)) = g.reference {
            return self.reference_return(w, new, code, second, block_col);
        }
        if let Some((kind, at)) = g.turning {
            return self.turning_cycle(w, new, kind, at as usize);
        }
        if let Some((kind, at)) = g.lathe {
            return self.lathe_cycle(w, new, kind, at as usize);
        }
        if self.lathe_motion(w, new, block_col)? {
            return Ok(());
        }
        let polar;
        let w = if self.coords.polar.is_some() {
            polar = self.polar_words(w, new, block_col)?;
            &polar
        } else {
            w
        };
        if self.cycle.is_some() && cycles::makes_hole(w) {
            return self.canned_cycle(w, new, block_col);
        }
        self.motion(w, new, block_col)?;
        if let Some(turn) = w.path.turn {
            self.helix_turns(turn, new)?;
        }
        Ok(())
    }

    /// Step 4, SINUMERIK CIP or CT: the motion command, in the group of G0 … G3.
    fn motion_word(
        &mut self,
        codes: &gcodes::Codes,
        mode: super::block::MotionMode,
        at: u32,
        new: &mut ModalState,
    ) -> R<()> {
        if let Some((def, _)) = codes
            .iter()
            .find(|(def, _)| matches!(def.effect, crate::dialect::GEffect::Motion(_)))
        {
            return Err(super::fault::fault(
                crate::alarm::AlarmCode::SameGroupTwice,
                at,
                format!(
                    "{} and a circle word (CIP, CT) belong to the same group",
                    crate::dialect::GName(def.code)
                ),
            ));
        }
        self.cycle = None;
        new.motion = mode;
        Ok(())
    }

    /// A dwell block's S words (SINUMERIK `G4 S…`): spindle revolutions, not a speed; they
    /// leave the block's words.
    fn take_s_words(&mut self) -> Option<f64> {
        let words = &mut self.block.words;
        let s = words
            .iter()
            .rev()
            .find(|a| a.address == b'S')
            .map(|a| a.value);
        words.retain(|a| a.address != b'S');
        s
    }

    /// Step 1: the block at its source position with nothing programmed; its words (read
    /// already) and modal state (still the one before the block) stay.
    #[inline(always)]
    fn begin(&mut self, w: &Words, block_col: usize) {
        self.remember_move();
        let col = column(self.src, self.blk_line_start, block_col);
        reset(&mut self.block, self.blk_line, col, self.blk_number);
        self.block.calculation = w.calculation;
    }

    /// Step 11: the position moves to the motion's end; M02/M30 end the program and reset
    /// the pole to the zero offset; the new modal state is the block's.
    #[inline(always)]
    fn finish(&mut self, mut new: ModalState) {
        let blk = &mut self.block;
        if let Some(m) = &blk.motion {
            self.cur = m.end;
            // CT's last element: the next block's start remembers the block handed out,
            // unless corner elements hold blocks back (remember_move).
            if self.d.sinumerik && self.corners.is_some() {
                self.last_move = Some(*m);
            }
        }
        if let Some(a) = &blk.axes {
            self.cur_add = a.to;
        }
        let ends = blk.stop.is_some_and(|s| s.ends_program());
        if ends {
            let o = self.zero(new.work_offset);
            new.pole = [o[0], o[1], o[2]];
            self.finished = true;
        }
        self.block.modal = new;
    }
}

impl Interpreter<'_> {
    /// SINUMERIK CT: the move of the block handed out last (a plain block's too) is the
    /// path element the next tangent circle continues. Called before the block is reset;
    /// while corner elements are in play the blocks built are remembered instead (finish),
    /// and an expansion's moves as they are made (`next_expanded`).
    #[inline(always)]
    pub(in crate::frontend) fn remember_move(&mut self) {
        if self.d.sinumerik && self.corners.is_none() {
            if let Some(m) = self.block.motion {
                self.last_move = Some(m);
            }
        }
    }

    /// A block with nothing programmed at a statement's place (its preprocessing stop).
    pub(in crate::frontend) fn empty_block_at(
        &mut self,
        line: u32,
        col: u32,
        number: Option<BlockNo>,
    ) {
        self.remember_move();
        reset(&mut self.block, line, col, number);
        self.block.words.clear();
    }

    /// After a block is complete: the call or return it asked for (M98, M99, M17), or the
    /// G66 or MCALL modal call after a move.
    #[inline(always)]
    pub(in crate::frontend) fn after_block(&mut self) -> R<()> {
        if self.calls.pending.is_none() {
            if self.calls.modal.is_none() {
                return Ok(());
            }
            return self.modal_call_after_move();
        }
        self.run_pending()
    }

    /// G66 or MCALL: the modal call after a block that moves (not inside the called
    /// program).
    #[inline(never)]
    fn modal_call_after_move(&mut self) -> R<()> {
        let Some(call) = &self.calls.modal else {
            return Ok(());
        };
        if std::mem::take(&mut self.sinumerik.modal_cycle_running) {
            // The end of the cycle an MCALL started: it calls nothing again.
            return Ok(());
        }
        if self.block.motion.is_none() || self.calls.in_modal_call() || self.finished {
            return Ok(());
        }
        use super::calls::{Args, CallKind, Pending};
        let kind = match call.args {
            Args::Params(_) => CallKind::Procedure { modal: true },
            Args::Locals(_) => CallKind::Modal,
        };
        self.calls.pending = Some(Pending::Call {
            target: call.target.clone(),
            repeats: call.repeats,
            kind,
            args: call.args.clone(),
            at: self.blk_line_start,
        });
        self.run_pending()
    }
}

/// Clears everything of `b` but its auxiliary words (collected already) and its modal state
/// (still the state before the block). Destructures, so that a new field is not forgotten.
pub(super) fn reset(b: &mut Block, line: u32, col: u32, number: Option<BlockNo>) {
    let Block {
        line: b_line,
        col: b_col,
        // Set where the block's text is read (the interpreter), kept by the expansion.
        program: _,
        number: b_number,
        motion,
        modal: _,
        words: _,
        trc,
        approach,
        exact_stop,
        thread,
        dwell,
        stop,
        offset_changed,
        calculation,
        preprocess_stop,
        axes,
        message,
        exit_vector,
    } = b;
    *b_line = line;
    *b_col = col;
    *b_number = number;
    *motion = None;
    *trc = None;
    *approach = None;
    *exact_stop = false;
    *thread = None;
    *dwell = None;
    *stop = None;
    *offset_changed = false;
    *calculation = false;
    *preprocess_stop = false;
    *axes = None;
    *message = None;
    *exit_vector = None;
}
