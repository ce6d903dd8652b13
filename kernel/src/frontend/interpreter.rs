//! The interpreter: reads a program block by block, keeps the modal state and the current
//! position, and hands out interpreted [`Block`]s. It streams: nothing is read ahead except
//! to skip the body of a false `$IF` or a finished loop, and loops jump back in the text.
//!
//! One block goes: its text ([`block_text`](super::block_text)), then either a statement of
//! the dialect's language ([`statements`](super::statements)), the plain-block fast path
//! ([`plain`](super::plain)), or the word loop ([`word_loop`](super::word_loop)) and the block
//! build ([`build`](super::build)).

use super::block::*;
use super::block_text::{read_block_number, read_main_or_block_number};
use super::build::{Corners, CycleMode, Expansion, Smooth, WorkingArea};
use super::calls::Calls;
use super::fault::{fault, Fault, R};
use super::lexer::{column, Cursor};
use super::macro_b::MacroVariables;
use super::statements::isg::Structures;
use super::variables::Variables;
use super::words::Words;
use crate::alarm::{Alarm, AlarmCode};
use crate::dialect::Dialect;
use crate::machine_data::{CornerModeSetting, MachineData, PlaneName};
use crate::segment::Source;
use crate::tools::ToolTable;

/// Streams interpreted blocks out of one part program.
#[derive(Clone)]
pub struct Interpreter<'a> {
    pub(super) name: &'a str,
    pub(super) src: &'a [u8],
    pub(super) d: &'static Dialect,
    pub(super) md: &'a MachineData,
    pub(super) tools: &'a ToolTable,
    /// Start of the next block's text.
    pub(super) pos: usize,
    /// Line number and line start of `pos`.
    pub(super) line: u32,
    pub(super) line_start: usize,
    /// Line, line start and number of the block being interpreted (for alarms).
    pub(super) blk_line: u32,
    pub(super) blk_line_start: usize,
    pub(super) blk_number: Option<BlockNo>,
    /// The position after the last block.
    pub(super) cur: Pos,
    pub(super) cur_add: Additional,
    pub(super) vars: Variables,
    /// Fanuc `#` variables.
    pub(super) macros: MacroVariables,
    /// A Macro B variable of the present position was read in this block.
    pub(super) present_state_read: std::cell::Cell<bool>,
    /// The program's shifts of the zero (G92, G52) and its writes to the tables (G10).
    pub(super) coords: super::coordinates::Coordinates,
    /// The subprogram and macro call stack (Fanuc, SINUMERIK, 840C), the open WHILE … DO
    /// loops, the jump labels.
    pub(super) calls: Calls<'a>,
    /// SINUMERIK R parameters, user variables of each call level, the structures and labels
    /// and the PROC line of each program text.
    pub(super) sinumerik: super::sinumerik::statements::Sinumerik,
    /// 840C R parameters and the jump an `@` command asked for.
    pub(super) c840: super::statements::siemens_840c::Language,
    /// The open `$IF`/`$FOR`/`$WHILE` structures and the program's loop budget.
    pub(super) structures: Structures,
    /// 840C G25/G26.
    pub(super) area: WorkingArea,
    /// The moves still to come of a block that expands into several (G28, a canned cycle).
    pub(super) expansion: Option<Expansion>,
    /// The canned cycle mode in force, and its return level (G98: the initial level).
    pub(super) cycle: Option<CycleMode>,
    pub(super) cycle_to_initial: bool,
    /// The depth of cut and retract of the turning cycles (Fanuc lathe `G71 U R`).
    pub(super) turning: super::build::TurningData,
    /// The lathe cycles' stored data (Fanuc lathe G76 first block, G74/G75 `R(e)`, the box
    /// cycles' modal X Z R).
    pub(super) lathe: super::build::LatheData,
    /// Chamfer and corner words (Fanuc `,C` `,R`): the move that waits for the next one,
    /// and the blocks to hand out before reading on. `None` while no corner word is in play.
    pub(super) corners: Option<Box<Corners<'a>>>,
    /// SINUMERIK compensation words (G140 … G348, DISC): their modal settings, a smooth
    /// approach waiting for its contour element and the blocks it becomes. `None` until a
    /// program uses one (build/smooth.rs).
    pub(super) smooth: Option<Box<Smooth<'a>>>,
    /// The block being built is in machine coordinates: no work offset (G53, this block).
    pub(super) machine_coordinates: bool,
    /// SINUMERIK polar coordinates: the pole, the last polar angle and radius (G110 … G112,
    /// AP=, RP=).
    pub(super) polar: super::build::Polar,
    /// SINUMERIK: the last path element, which CT continues tangentially.
    pub(super) last_move: Option<Motion>,
    pub(super) finished: bool,
    /// SINUMERIK: the program's structures are still to be read (before its first block).
    pub(super) structure_pending: bool,
    /// SINUMERIK: the next line of the main program's text its structure read has not read
    /// (sinumerik/structure.rs); offset `usize::MAX` once all is read, or in other dialects.
    pub(super) frontier: (usize, u32, usize),
    /// Plain motion blocks take [`Self::plain`] (off only to test it against the full path).
    pub(super) plain_path: bool,
    /// The block handed out last, built in place (it is not moved through every layer). Its
    /// `modal` is the interpreter's modal state: it changes only when a block is complete.
    pub(super) block: Block,
}

impl<'a> Interpreter<'a> {
    /// `name` is how alarms name the program (usually its path).
    pub fn new(name: &'a str, source: &'a str, md: &'a MachineData, tools: &'a ToolTable) -> Self {
        let d = Dialect::get(md.dialect);
        Interpreter {
            name,
            src: source.as_bytes(),
            d,
            md,
            tools,
            pos: 0,
            line: 1,
            line_start: 0,
            blk_line: 1,
            blk_line_start: 0,
            blk_number: None,
            cur: [0.0; 3],
            cur_add: [0.0; ADDITIONAL],
            vars: Variables::default(),
            macros: MacroVariables::default().with_kept(&md.kept_variables),
            present_state_read: std::cell::Cell::new(false),
            calls: Calls::new(name, source.as_bytes()),
            coords: Default::default(),
            structures: Structures::default(),
            sinumerik: super::sinumerik::statements::Sinumerik {
                store: super::sinumerik::Store::new(if d.sinumerik {
                    md.program.r_parameters as usize
                } else {
                    0
                }),
                ..Default::default()
            },
            c840: super::statements::siemens_840c::Language {
                r: super::statements::siemens_840c::RParameters::new(if d.at_language {
                    md.program.r_parameters as usize
                } else {
                    0
                }),
                jump: None,
            },
            area: WorkingArea::default(),
            expansion: None,
            cycle: None,
            cycle_to_initial: true,
            turning: Default::default(),
            lathe: Default::default(),
            corners: None,
            smooth: None,
            machine_coordinates: false,
            polar: Default::default(),
            last_move: None,
            finished: false,
            structure_pending: d.sinumerik,
            frontier: (usize::MAX, 0, 0),
            plain_path: true,
            block: Block::new(0, 0, None, initial_state(d, md)),
        }
    }

    /// The next interpreted block, borrowed: the fast way to stream a program. `Ok(None)` at
    /// the end; after an alarm the interpreter stays finished.
    #[inline]
    pub fn next_block(&mut self) -> Result<Option<&Block>, Alarm> {
        if self.step()? {
            Ok(Some(&self.block))
        } else {
            Ok(None)
        }
    }

    /// The last block handed out (what `next_block` returned).
    pub fn current(&self) -> &Block {
        &self.block
    }

    /// The modal state after the last block handed out.
    pub fn state(&self) -> &ModalState {
        &self.block.modal
    }

    /// The same interpreter with the axes standing at `p` (machine coordinates) before the
    /// first block: a kernel loads a program where the last one left the axes, as a control
    /// does (the first motion starts from there).
    pub fn starting_at(mut self, p: AxisPos) -> Self {
        self.cur = p.geo;
        self.cur_add = p.add;
        self
    }

    /// The kept macro variables (#500 … #999) that hold a value, to save after the run.
    pub fn kept_variables(&self) -> Vec<(u32, f64)> {
        crate::macro_variables::KEPT
            .zip(self.macros.kept())
            .filter_map(|(n, v)| v.map(|v| (n, v)))
            .collect()
    }

    /// SINUMERIK: the main program's control structures and labels read through to its
    /// end without running a block (a structure left open, even behind the M30, or a label
    /// twice). The kernel refuses a program with this alarm at load; the interpreter itself
    /// reads the structures as far as it runs and meets the same alarm at the program's end.
    /// `None` in the other dialects.
    pub fn structure_alarm(mut self) -> Option<Alarm> {
        if !self.d.sinumerik {
            return None;
        }
        self.program_structure()
            .err()
            .or_else(|| self.main_program_ends().err())
    }

    /// The position after the last block handed out.
    pub fn position(&self) -> Pos {
        self.cur
    }

    /// Every path axis's position after the last block handed out.
    pub fn axis_position(&self) -> AxisPos {
        AxisPos {
            geo: self.cur,
            add: self.cur_add,
        }
    }

    /// The same interpreter with every block read by the full word loop (tests compare the
    /// two ways of reading a plain motion block).
    #[doc(hidden)]
    pub fn without_plain_path(mut self) -> Self {
        self.plain_path = false;
        self
    }

    /// The one place a fault becomes an alarm: at the block being interpreted, the column
    /// counted from the fault's byte offset.
    #[cold]
    fn alarm(&self, f: Fault) -> Alarm {
        let source = Source {
            number: self.blk_number,
            line: self.blk_line,
            col: column(self.src, self.blk_line_start, f.at),
            // Not read by `Alarm::at`: a block that fails has no place in execution order.
            seq: 0,
            program: self.calls.running.program,
        };
        // `name` is the running program's file (a subprogram file's while one runs).
        Alarm::at(f.code, self.name, &source, f.message)
    }

    /// The next block to hand out: the next one interpreted, unless corner words are in
    /// play (then a move waits for the next one, build/corner_blocks.rs).
    #[inline]
    fn step(&mut self) -> Result<bool, Alarm> {
        loop {
            if self.corners.is_some() {
                if let Some(ready) = self.corner_waiting() {
                    return Ok(ready);
                }
            }
            let produced = self.produce()?;
            if self.finished && self.frontier.0 != usize::MAX {
                self.main_program_ends()?;
            }
            if self.corners.is_none() {
                return Ok(produced);
            }
            if let Some(ready) = self.take_block(produced)? {
                return Ok(ready);
            }
        }
    }

    /// Interprets blocks until one is produced, the program ends, or an alarm is raised.
    #[inline]
    fn produce(&mut self) -> Result<bool, Alarm> {
        loop {
            if self.finished {
                return Ok(false);
            }
            if self.expansion.is_some() {
                match self.next_expanded() {
                    Ok(true) => return Ok(true),
                    Ok(false) => continue,
                    Err(f) => {
                        self.finished = true;
                        return Err(self.alarm(*f));
                    }
                }
            }
            if self.structure_pending {
                self.program_structure()?;
            }
            if self.plain_allowed() && self.plain_line() {
                return Ok(true);
            }
            let Some((start, end)) = self.next_segment() else {
                if self.text_ends()? {
                    continue;
                }
                return Ok(false);
            };
            self.blk_number = None;
            match self.segment(start, end) {
                Ok(true) => return Ok(true),
                Ok(false) => continue,
                Err(f) => {
                    self.finished = true;
                    return Err(self.alarm(*f));
                }
            }
        }
    }

    /// SINUMERIK, at the main program's end: the rest of its text read for structures.
    #[cold]
    #[inline(never)]
    fn main_program_ends(&mut self) -> Result<(), Alarm> {
        self.structure_end().map_err(|f| {
            self.finished = true;
            self.alarm(*f)
        })
    }

    /// SINUMERIK, before the first block: the program's structures and labels.
    #[cold]
    #[inline(never)]
    fn program_structure(&mut self) -> Result<(), Alarm> {
        self.read_structure().map_err(|f| {
            self.finished = true;
            self.alarm(*f)
        })
    }

    /// At the end of the text: a control structure still open, as a fault at its opening
    /// statement (which becomes the block the alarm names).
    #[cold]
    fn unclosed(&mut self) -> Option<Box<Fault>> {
        let f = self.structures.innermost()?;
        let (line, line_start, at) = f.origin();
        let message = format!("{} is not closed by {}", f.opener(), f.closer());
        (self.blk_line, self.blk_line_start, self.blk_number) = (line, line_start, None);
        Some(fault(AlarmCode::ControlNesting, at, message))
    }

    /// Plain motion blocks may take the fast path: not while a modal macro call or a canned
    /// cycle makes a move block more than a move.
    #[inline(always)]
    fn plain_allowed(&self) -> bool {
        self.plain_path
            && self.calls.modal.is_none()
            && self.cycle.is_none()
            && !self.coords.frame.active()
            && self.coords.polar.is_none()
            && self.corners.is_none()
    }

    /// The end of the running program's text: true if reading goes on in the caller (a
    /// SINUMERIK or 840C subprogram returns there); else the program's end, or the alarm of
    /// a called program without M99 or of a structure left open.
    #[cold]
    #[inline(never)]
    fn text_ends(&mut self) -> Result<bool, Alarm> {
        if self.calls.depth() > 0 && self.d.has_subprogram_end() {
            return match self.implicit_return() {
                Ok(()) => Ok(true),
                Err(f) => {
                    self.finished = true;
                    Err(self.alarm(*f))
                }
            };
        }
        self.finished = true;
        if let Some(f) = self.called_program_ends() {
            return Err(self.alarm(*f));
        }
        if let Some(f) = self.smooth_unfinished() {
            return Err(self.alarm(*f));
        }
        match self.unclosed() {
            Some(f) => Err(self.alarm(*f)),
            None => Ok(false),
        }
    }

    /// At the end of a called program's text: it has no M99 (a fault at its O line).
    #[cold]
    fn called_program_ends(&mut self) -> Option<Box<Fault>> {
        if self.calls.depth() == 0 {
            return None;
        }
        let (at, line, line_start) = self.calls.running.start;
        (self.blk_line, self.blk_line_start, self.blk_number) = (line, line_start, None);
        let name = match self.calls.program_number() {
            Some(n) => format!("O{n:04}"),
            None => "the called program".to_string(),
        };
        let ret = self.d.m_name(crate::dialect::MEffect::Return);
        Some(fault(
            AlarmCode::ControlNesting,
            at,
            format!("{name} ends without {ret} (return)"),
        ))
    }

    /// One block's text: what stands before the words, the block number, then a statement,
    /// a plain block or the words and the build.
    #[inline]
    fn segment(&mut self, start: usize, end: usize) -> R<bool> {
        if start >= self.frontier.0 && self.calls.running.program == 0 {
            self.structure_to(start)?;
        }
        let mut c = Cursor::new(self.src, start, end);
        if !self.block_start(&mut c) {
            return Ok(false);
        }
        self.block.program = self.calls.running.program;
        let block_col = c.i;
        // SINUMERIK: `NAME…` is a name (a variable, a program), not the block number N.
        let name = self.d.sinumerik
            && matches!(c.peek_at(1), Some(b) if b.is_ascii_alphabetic() || b == b'_');
        self.blk_number = if name {
            None
        } else if self.d.main_block_colon {
            read_main_or_block_number(&mut c)?
        } else {
            read_block_number(&mut c)?
        };
        c.skip_blanks();
        let mut system = false;
        if self.d.sinumerik {
            // A jump label (`LAB1:`): the jumps found it before the program started.
            super::sinumerik::structure::label(&mut c);
            system = self.reads_system(start, end);
        }
        if self.is_statement(&c) {
            self.calls.running.started = true;
            return self.statement(c, start, block_col);
        }
        if self.plain_allowed() && self.plain(c, block_col).is_some() {
            return Ok(true);
        }
        let mut words = Words::default();
        self.block.words.clear();
        self.present_state_read.set(false);
        self.words(&mut c, &mut words)?;
        if system && self.sinumerik.store.main_run_read.take() {
            self.present_state_read.set(true);
        }
        if self.blk_number.is_none() && words.is_empty() && self.block.words.is_empty() {
            // A line holding only a comment is no block.
            return Ok(false);
        }
        self.calls.running.started = true;
        if words.calculation && self.d.at_language && words.only_calculation() {
            // 840C: a block of the language alone is a statement, not a block.
            if self.block.words.is_empty() {
                return self.c840_block_end().map(|()| false);
            }
        }
        let built = self.build(&words, block_col)?;
        // A word read the present position (#5041 …): the block stops preprocessing.
        self.block.preprocess_stop |= self.present_state_read.get();
        if self.expansion.is_none() {
            self.after_block()?;
        }
        if self.c840.jump.is_some() {
            self.c840_block_end()?;
        }
        Ok(built)
    }
}

/// The modal state at program start: the dialect's initial codes and the machine data.
fn initial_state(d: &Dialect, md: &MachineData) -> ModalState {
    let plane = match md.program.initial_plane {
        PlaneName::Xy => Plane::XY,
        PlaneName::Zx => Plane::ZX,
        PlaneName::Yz => Plane::YZ,
    };
    let corner = match md.trc.corner_mode {
        CornerModeSetting::TransitionCircle => CornerPolicy::TransitionCircle,
        CornerModeSetting::Intersection => d.initial_corner_intersection,
    };
    ModalState {
        motion: d.initial_motion,
        plane,
        distance: Distance::Absolute,
        units: md.program.units,
        feed_units: md.program.units,
        feed: 0.0,
        spindle: 0.0,
        spindle_dir: SpindleDir::Stop,
        css: false,
        spindle_limit: 0.0,
        feed_per_rev: false,
        trc: TrcSide::Off,
        corner,
        selection: d.initial_selection,
        feed_adaption: FeedAdaption::Centre,
        masking: false,
        exact_stop: false,
        work_offset: d.initial_work_offset,
        diameter: md.program.diameter_programming,
        radius_incremental: false,
        tool: None,
        d: 0,
        radius: 0.0,
        length: 0.0,
        length_comp: LengthComp::Off,
        h: 0,
        edge: 0,
        pole: [0.0; 3],
    }
}

#[cfg(test)]
mod tests {
    use super::super::run;
    use crate::alarm::AlarmCode;

    #[test]
    fn a_fault_becomes_an_alarm_at_its_block_in_characters() {
        // N10 (é) Q5: Q is the 9th character, the 10th byte.
        let a = run("siemens-840c", "G1 F100\nN10 (é) Q5\n").unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::UnknownAddress, 2, 9));
        assert_eq!(a.block.as_deref(), Some("N10"));
    }

    #[test]
    fn a_structure_left_open_is_an_alarm_at_its_opening() {
        let a = run("isg", "N5 X1\nN10 $FOR V.P.A = 0,1,1\nN20 X2\n").unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::ControlNesting, 2, 5));
        assert_eq!(a.block, None);
    }
}
