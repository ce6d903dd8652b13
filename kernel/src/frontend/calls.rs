//! Subprogram and macro calls (Fanuc 0i-MF, "Subprogram", "Macro call"): a call stack of
//! reading positions. A call saves where the caller reads (its text, the block after the
//! call, its open loops and, for a macro call, its local variables) in a [`Frame`] and goes
//! on reading in the called program; a return takes the frame back.
//!
//! Programs are found by number: first the `O` programs in the main program's file, after
//! the main program (a program's text ends where the next `O` line starts), then the
//! subprogram files of the machine data's program library (the program's folder and the
//! search path, programs.rs). Nesting is bounded as on the control: five macro levels
//! (G65/G66), and the dialect's program levels (Fanuc: fifteen calls in all).
//!
//! SINUMERIK calls (sinumerik/calls.rs) use the same stack: they find their program file by
//! name before the call and hand over its bound parameters, which become the called level's
//! user variables.

use super::fault::{fault, R};
use super::interpreter::Interpreter;
use super::lexer::Cursor;
use super::macro_b::{Value, LOCALS};
use super::sinumerik::Param;
use crate::alarm::AlarmCode;
use std::collections::HashMap;

/// Macro call levels (G65/G66): local variable levels 1…5 (0i-F).
pub const MAX_MACRO_LEVELS: usize = 5;

/// A reading position: (byte offset, line, line start).
pub type Mark = (usize, u32, usize);

/// A program's text to read: its file's name, the text, its library index (`None` where
/// it is the main program's file).
pub(super) type Text<'a> = Option<(&'a str, &'a [u8], u16)>;

/// How a program was called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CallKind {
    /// M98: the caller's local variables stay.
    Subprogram,
    /// G65: a new level of local variables.
    Macro,
    /// G66 after a move: a new level; moves inside call nothing.
    Modal,
    /// SINUMERIK (and 840C `L`): a new level of user variables, the parameters bound;
    /// `modal`: MCALL after a move, moves inside call nothing.
    Procedure { modal: bool },
}

/// The program a call runs.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// Fanuc O number: in the main program's file, else a library file.
    Number(u32),
    /// A file of the program library, found before the call (SINUMERIK names).
    File(u16),
    /// A SINUMERIK drilling cycle with its parameters, evaluated at the MCALL: no program,
    /// its moves are built in.
    Cycle(
        crate::frontend::sinumerik::cycles::CycleName,
        Box<crate::frontend::sinumerik::cycles::Params>,
    ),
}

/// What a call hands the called program.
#[derive(Clone, Debug, PartialEq)]
pub enum Args {
    /// Fanuc: the local variables #1 … #33 of a macro call (M98: unused).
    Locals(Box<[Value; LOCALS]>),
    /// SINUMERIK: the PROC parameters, bound.
    Params(Box<[Param]>),
}

/// An open WHILE … DO m loop: `m`, where its WHILE (or DO) block starts, and its origin for
/// alarms (line, line start, byte offset).
#[derive(Clone, Copy, Debug)]
pub struct DoLoop {
    pub m: u8,
    pub head: Mark,
    /// A DO without WHILE: jumps back to the block after it.
    pub endless: bool,
}

/// The program being read.
#[derive(Clone, Copy, Debug)]
pub struct Running {
    /// Where its O line is and its number, once that was read.
    pub own: Option<(usize, u32)>,
    /// Where it starts (its O line, or the start of the text).
    pub start: Mark,
    /// Its file: 0 the main program's, k the program library's file k.
    pub program: u16,
    /// A block of it has been read: an `O` line from now on begins the next program.
    pub started: bool,
}

/// A caller's saved reading state.
#[derive(Clone, Debug)]
struct Frame<'a> {
    name: &'a str,
    src: &'a [u8],
    ret: Mark,
    running: Running,
    loops: Vec<DoLoop>,
    /// The caller's locals, for a macro call.
    locals: Option<[Value; LOCALS]>,
    kind: CallKind,
    /// Passes still to run after this one (M98 L, P with a count) and where they start.
    repeats: u32,
    start: Mark,
}

/// What a block asks for when it is complete.
#[derive(Clone, Debug)]
pub enum Pending {
    Call {
        target: Target,
        repeats: u32,
        kind: CallKind,
        args: Args,
        at: usize,
    },
    /// M99, with P: the sequence number to go on at.
    Return { to: Option<u32>, at: usize },
}

/// A G66 or MCALL modal call: the program and its arguments.
#[derive(Clone, Debug)]
pub struct ModalCall {
    pub target: Target,
    /// L (P): how often it runs after each move.
    pub repeats: u32,
    pub args: Args,
    /// The calls open when it was set (an MCALL ends with the level that set it: its VAR
    /// parameters are that level's variables).
    pub depth: usize,
}

/// The call stack, the open loops of the level running now, and the label index.
#[derive(Clone, Debug)]
pub struct Calls<'a> {
    /// The main program's whole file (its `O` programs are callable) and its name.
    file: &'a [u8],
    main_name: &'a str,
    frames: Vec<Frame<'a>>,
    pub running: Running,
    pub loops: Vec<DoLoop>,
    pub pending: Option<Pending>,
    pub modal: Option<ModalCall>,
    /// The `O` programs of the file: number → start (read when the first call comes).
    programs: Option<HashMap<u32, Mark>>,
    /// Sequence numbers of each program (by its start offset): N → the blocks' marks.
    labels: HashMap<(usize, usize), HashMap<u32, Vec<Mark>>>,
}

impl<'a> Calls<'a> {
    pub fn new(main_name: &'a str, file: &'a [u8]) -> Self {
        Calls {
            file,
            main_name,
            frames: Vec::new(),
            running: Running {
                own: None,
                start: (0, 1, 0),
                program: 0,
                started: false,
            },
            loops: Vec::new(),
            pending: None,
            modal: None,
            programs: None,
            labels: HashMap::new(),
        }
    }

    /// Calls open (0: the main program runs).
    pub fn depth(&self) -> usize {
        self.frames.len()
    }

    /// The running program's O number.
    pub fn program_number(&self) -> Option<u32> {
        self.running.own.map(|(_, n)| n)
    }

    /// Inside a program called by G66 or MCALL (its moves call nothing).
    pub fn in_modal_call(&self) -> bool {
        self.frames.iter().any(|f| {
            matches!(
                f.kind,
                CallKind::Modal | CallKind::Procedure { modal: true }
            )
        })
    }

    fn macro_levels(&self) -> usize {
        self.frames
            .iter()
            .filter(|f| matches!(f.kind, CallKind::Macro | CallKind::Modal))
            .count()
    }
}

impl<'a> Interpreter<'a> {
    /// Runs the call or return the block just built asked for.
    pub(super) fn run_pending(&mut self) -> R<()> {
        match self.calls.pending.take() {
            Some(Pending::Call {
                target,
                repeats,
                kind,
                args,
                at,
            }) => self.call(target, repeats, kind, args, at),
            Some(Pending::Return { to, at }) => self.ret(to, at),
            None => Ok(()),
        }
    }

    fn call(
        &mut self,
        target: Target,
        repeats: u32,
        kind: CallKind,
        args: Args,
        at: usize,
    ) -> R<()> {
        if repeats == 0 {
            return Ok(());
        }
        let (text, start) = match target {
            Target::Number(number) => self.find_program(number, at)?,
            Target::File(k) => (self.library_text(k), (0, 1, 0)),
            Target::Cycle(name, p) => return self.modal_cycle(name, *p),
        };
        self.check_levels(at)?;
        let macro_call = matches!(kind, CallKind::Macro | CallKind::Modal);
        if macro_call && self.calls.macro_levels() >= MAX_MACRO_LEVELS {
            return Err(nesting(
                at,
                format!("more than {MAX_MACRO_LEVELS} macro call levels nested"),
            ));
        }
        let (locals, params) = match args {
            Args::Locals(a) if macro_call => {
                (Some(std::mem::replace(&mut self.macros.locals, *a)), None)
            }
            Args::Locals(_) => (None, None),
            Args::Params(p) => (None, Some(p)),
        };
        if let Some(p) = &params {
            // The called level's variables: its parameters (before the caller's state goes).
            self.sinumerik.store.push_level(p, at)?;
        }
        let frame = Frame {
            name: self.name,
            src: self.src,
            ret: (self.pos, self.line, self.line_start),
            running: self.calls.running,
            loops: std::mem::take(&mut self.calls.loops),
            locals,
            kind,
            repeats: repeats - 1,
            start,
        };
        self.calls.frames.push(frame);
        self.enter(text, start);
        Ok(())
    }

    /// A call that would open one more program level than the dialect has: alarm 14012.
    pub(super) fn check_levels(&self, at: usize) -> R<()> {
        let levels = self.d.program_levels as usize;
        if self.calls.depth() + 1 < levels {
            return Ok(());
        }
        let message = if self.d.sinumerik || self.d.l_calls {
            format!(
                "more than {levels} program levels (the main program and {} subprograms) nested",
                levels - 1
            )
        } else {
            format!("more than {} calls nested", levels - 1)
        };
        Err(nesting(at, message))
    }

    /// Library file `k` as `enter` takes it.
    pub(super) fn library_text(&self, k: u16) -> Text<'a> {
        let library: &'a crate::programs::ProgramLibrary = &self.md.programs;
        let p = library.find_index(k)?;
        Some((p.name.as_str(), p.text().ok()?.as_bytes(), k))
    }

    /// Starts reading a program at `start` (its O line) in `text` (name, text, library
    /// index; `None`: the main program's file).
    pub(super) fn enter(&mut self, text: Text<'a>, start: Mark) {
        let (name, src, program) = text.unwrap_or((self.calls.main_name, self.calls.file, 0));
        self.name = name;
        self.src = src;
        (self.pos, self.line, self.line_start) = start;
        self.calls.running = Running {
            own: None,
            start,
            program,
            started: false,
        };
    }

    /// M99: back to the caller (or its sequence number `to`); a pass still to run starts
    /// the program again. In the main program M99 starts it again (or goes on at `to`).
    fn ret(&mut self, to: Option<u32>, at: usize) -> R<()> {
        let Some(frame) = self.calls.frames.last_mut() else {
            self.next_pass(at)?;
            let target = match to {
                Some(n) => self.find_label(n, at)?,
                None => self.calls.running.start,
            };
            self.calls.loops.clear();
            (self.pos, self.line, self.line_start) = target;
            return Ok(());
        };
        if frame.repeats > 0 && to.is_none() {
            frame.repeats -= 1;
            let start = frame.start;
            // A repetition is a loop pass: nested repetitions stay bounded too.
            self.next_pass(at)?;
            let text = self.running_text();
            self.calls.loops.clear();
            self.enter(text, start);
            return Ok(());
        }
        // M99 P: the caller's sequence number, found (and a jump back before the call
        // counted) while the alarm can still point at the M99 in this program.
        let target = match to {
            Some(n) => {
                let (src, running, ret) = (frame.src, frame.running, frame.ret);
                let target = self.find_label_in(src, running, ret.0, n, at)?;
                if target.0 < ret.0 {
                    self.next_pass(at)?;
                }
                Some(target)
            }
            None => None,
        };
        let Some(frame) = self.calls.frames.pop() else {
            return Ok(());
        };
        if let Some(locals) = frame.locals {
            self.macros.locals = locals;
        }
        if matches!(frame.kind, CallKind::Procedure { .. }) {
            self.sinumerik.store.pop_level();
            let depth = self.calls.frames.len();
            // An MCALL ends with the level that set it.
            if self
                .calls
                .modal
                .as_ref()
                .is_some_and(|m| m.depth > depth && matches!(m.args, Args::Params(_)))
            {
                self.calls.modal = None;
            }
        }
        self.name = frame.name;
        self.src = frame.src;
        (self.pos, self.line, self.line_start) = target.unwrap_or(frame.ret);
        self.calls.running = frame.running;
        self.calls.loops = frame.loops;
        Ok(())
    }

    /// An `O` line at the cursor while reading (block_text): the running program's own O
    /// line names it; the next one ends its text.
    pub(super) fn o_line(&mut self, c: &Cursor, line_start_at: usize) {
        let running = &mut self.calls.running;
        if running.own.is_some_and(|(at, _)| at == c.i) {
            return;
        }
        if running.own.is_none() && !running.started {
            let n = o_number(c.b, c.i, c.end).unwrap_or(0);
            running.own = Some((c.i, n));
            return;
        }
        // The next program begins: the running one's text ends before its line.
        self.src = &self.src[..line_start_at.min(self.src.len())];
        self.pos = self.src.len();
    }

    /// The running program's text as `enter` takes it (to run it again).
    fn running_text(&self) -> Text<'a> {
        self.library_text(self.calls.running.program)
    }

    /// Program O`number`: in the main program's file, else a file of the library (its
    /// name, text and index), and where it starts.
    fn find_program(&mut self, number: u32, at: usize) -> R<(Text<'a>, Mark)> {
        let file = self.calls.file;
        let programs = self
            .calls
            .programs
            .get_or_insert_with(|| index_programs(file));
        if let Some(&start) = programs.get(&number) {
            return Ok((None, start));
        }
        let library: &'a crate::programs::ProgramLibrary = &self.md.programs;
        match library.find(number) {
            Some((k, p)) => Ok((Some((p.name.as_str(), file_text(p, at)?.as_bytes(), k)), (0, 1, 0))),
            None => Err(fault(
                AlarmCode::MissingProgram,
                at,
                format!(
                    "program O{number:04} is neither in this file nor a subprogram file (O{number:04}.nc) of the program's folder or program.search_path"
                ),
            )),
        }
    }

    /// The block with sequence number `n` in the running program: the first after the
    /// block being read, else the first from the program's start (0i-MF, GOTO).
    pub(super) fn find_label(&mut self, n: u32, at: usize) -> R<Mark> {
        let (src, running, here) = (self.src, self.calls.running, self.pos);
        self.find_label_in(src, running, here, n, at)
    }

    /// Sequence number `n` in the program `running` of `src`: the first at or after
    /// `here`, else the first from its start.
    fn find_label_in(
        &mut self,
        src: &'a [u8],
        running: Running,
        here: usize,
        n: u32,
        at: usize,
    ) -> R<Mark> {
        let (start, own_o_line) = (running.start, running.own.map(|(at, _)| at));
        let labels = self
            .calls
            .labels
            .entry((src.as_ptr() as usize, start.0))
            .or_insert_with(|| index_labels(src, start, own_o_line, self.d.semicolon));
        let marks = labels.get(&n).ok_or_else(|| {
            fault(
                AlarmCode::JumpTarget,
                at,
                format!("sequence number N{n} is not in this program"),
            )
        })?;
        Ok(*marks.iter().find(|m| m.0 >= here).unwrap_or(&marks[0]))
    }
}

fn nesting(at: usize, m: String) -> Box<super::fault::Fault> {
    fault(AlarmCode::CallNesting, at, m)
}

/// The lines of `src` from `from`: (block text start, end, mark of the line).
fn lines(src: &[u8], from: Mark) -> impl Iterator<Item = (usize, usize, Mark)> + '_ {
    let (mut pos, mut line, _) = from;
    std::iter::from_fn(move || {
        if pos >= src.len() {
            return None;
        }
        let start = pos;
        let end = super::lexer::find_byte(src, start, [b'\n']);
        pos = end + 1;
        line += 1;
        Some((start, end, (start, line - 1, start)))
    })
}

/// The first non-blank byte of a line (upper case), and where it is.
fn first(src: &[u8], start: usize, end: usize) -> Option<(u8, usize)> {
    let mut c = Cursor::new(src, start, end);
    c.skip_blanks();
    c.peek().map(|b| (b.to_ascii_uppercase(), c.i))
}

/// The program number of the `O` at `at` (digits up to `end`, no decimal point).
fn o_number(b: &[u8], at: usize, end: usize) -> Option<u32> {
    super::number::parse(b, at + 1)
        .filter(|(n, e)| !n.has_point && *e <= end && n.value <= u32::MAX as f64)
        .map(|(n, _)| n.value as u32)
}

/// Every `O` line of a file: program number → its mark.
fn index_programs(file: &[u8]) -> HashMap<u32, Mark> {
    let mut out = HashMap::new();
    for (s, e, mark) in lines(file, (0, 1, 0)) {
        if let Some((b'O', i)) = first(file, s, e) {
            if let Some(n) = o_number(file, i, e) {
                out.entry(n).or_insert(mark);
            }
        }
    }
    out
}

/// The sequence numbers of the program starting at `start`, up to an `O` line other than
/// its own (at `own_o_line`: lines such as `%` may stand before it); a block after a `;`
/// on the same line counts too (Fanuc end of block).
fn index_labels(
    src: &[u8],
    start: Mark,
    own_o_line: Option<usize>,
    semicolon: crate::dialect::Semicolon,
) -> HashMap<u32, Vec<Mark>> {
    let mut out: HashMap<u32, Vec<Mark>> = HashMap::new();
    for (k, (s, e, mark)) in lines(src, start).enumerate() {
        let o_line = first(src, s, e).filter(|&(b, _)| b == b'O');
        if o_line.is_some_and(|(_, at)| Some(at) != own_o_line && !(k == 0 && own_o_line.is_none()))
        {
            break;
        }
        let mut block_start = s;
        loop {
            // A `;` ends a Fanuc block, but not inside a comment.
            let end = match semicolon {
                crate::dialect::Semicolon::EndOfBlock => {
                    match super::block_text::fanuc_block_end(&src[..e], block_start) {
                        super::block_text::BlockEnd::Semicolon(i) => i,
                        super::block_text::BlockEnd::Line(_) => e,
                    }
                }
                crate::dialect::Semicolon::Comment => e,
            };
            if let Some(n) = super::block_text::block_number(src, block_start, end) {
                out.entry(n.value)
                    .or_default()
                    .push((block_start, mark.1, mark.2));
            }
            if end >= e {
                break;
            }
            block_start = end + 1;
        }
    }
    out
}

/// The text of library file `p`, called at `at`: read now if it was not before, or alarm
/// 14011 where it is listed but cannot be read (it went since the program was loaded, or
/// cannot be opened).
pub(super) fn file_text(p: &crate::programs::LibraryProgram, at: usize) -> R<&str> {
    p.text().map_err(|why| {
        let m = format!("program file {} cannot be read: {why}", p.name);
        fault(AlarmCode::MissingProgram, at, m)
    })
}
