//! The interpreter: reads a program block by block, keeps the modal state and the current
//! position, and hands out interpreted [`Block`]s. It streams: nothing is read ahead except
//! to skip the body of a false `$IF` or a finished loop, and loops jump back in the text.

use super::arc::{self, ArcError, CentreSpec};
use super::block::*;
use super::control::{self, ControlStmt, Frame};
use super::expr;
use super::fault::{fault, Fault, Offset, R};
use super::lexer::{column, find_byte, Cursor};
use super::number::{self, Number};
use super::variables::{Variables, Written};
use crate::alarm::{Alarm, AlarmCode};
use crate::dialect::{Dialect, GCodeDef, GEffect, RadiusWord, Semicolon};
use crate::machine_data::{DecimalInput, MachineData, PlaneName, Units};
use crate::segment::Source;
use crate::tools::ToolTable;
use crate::trc::SideChange;

/// A value as written, with the byte offset of its address letter. Flat rather than holding
/// a [`Number`], so that it packs into 16 bytes and `Option<Val>` stays 16 bytes too.
#[derive(Clone, Copy, Debug)]
struct Val {
    value: f64,
    at: u32,
    /// A decimal point was written.
    has_point: bool,
}

impl Val {
    fn new(n: Number, at: usize) -> Self {
        Val {
            value: n.value,
            at: at as u32,
            has_point: n.has_point,
        }
    }
    fn pos(self) -> usize {
        self.at as usize
    }
}

/// The words of one block, collected before they are interpreted (a G code may follow the
/// axis words it governs). The auxiliary words go straight into the block being built.
#[derive(Default)]
struct Words {
    g: heapless::Vec<(u16, u32), 16>,
    axis: [Option<Val>; 3],
    centre: [Option<Val>; 3],
    radius: Option<Val>,
    angle: Option<Val>,
    polar_radius: Option<Val>,
    f: Option<Val>,
    p: Option<Val>,
    bare: Option<Val>,
    d: Option<Val>,
    t: Option<Val>,
    m: heapless::Vec<Val, 8>,
    at_codes: heapless::Vec<(u32, u32), 4>,
    diameter: Option<bool>,
    radius_written: Option<u32>,
    calculation: bool,
}

impl Words {
    /// No word at all besides the auxiliary ones (which the caller checks).
    fn is_empty(&self) -> bool {
        self.g.is_empty()
            && self.axis.iter().all(Option::is_none)
            && self.centre.iter().all(Option::is_none)
            && self.radius.is_none()
            && self.angle.is_none()
            && self.polar_radius.is_none()
            && self.p.is_none()
            && self.bare.is_none()
            && self.at_codes.is_empty()
            && self.diameter.is_none()
            && !self.calculation
    }
}

/// How the word loop goes on after [`Interpreter::special`].
enum Next {
    Continue,
    Break,
    /// A one-letter address: read its value.
    Address(u8),
}

/// Streams interpreted blocks out of one part program.
#[derive(Clone)]
pub struct Interpreter<'a> {
    name: &'a str,
    src: &'a [u8],
    d: &'static Dialect,
    md: &'a MachineData,
    tools: &'a ToolTable,
    /// Start of the next block's text.
    pos: usize,
    /// Line number and line start of `pos`.
    line: u32,
    line_start: usize,
    /// Line, line start and number of the block being interpreted (for alarms).
    blk_line: u32,
    blk_line_start: usize,
    blk_number: Option<BlockNo>,
    cur: Pos,
    vars: Variables,
    frames: Vec<Frame>,
    work_min: Pos,
    work_max: Pos,
    /// A G25/G26 limit has been programmed (saves the check on every block otherwise).
    work_limited: bool,
    /// Loop passes of the whole program: bounds nested loops too (their product would not be).
    loop_passes: u32,
    finished: bool,
    /// The block text where the last `skip_to` stopped.
    last_skip: (usize, usize),
    /// Plain motion blocks take [`Self::plain`] (off only to test it against the full path).
    plain_path: bool,
    /// The block handed out last, built in place (it is not moved through every layer). Its
    /// `modal` is the interpreter's modal state: it changes only when a block is complete.
    block: Block,
}

impl<'a> Interpreter<'a> {
    /// `name` is how alarms name the program (usually its path).
    pub fn new(name: &'a str, source: &'a str, md: &'a MachineData, tools: &'a ToolTable) -> Self {
        let d = Dialect::get(md.dialect);
        let plane = match md.program.initial_plane {
            PlaneName::Xy => Plane::XY,
            PlaneName::Zx => Plane::ZX,
            PlaneName::Yz => Plane::YZ,
        };
        let corner = match md.trc.corner_mode {
            crate::machine_data::CornerModeSetting::TransitionCircle => {
                CornerPolicy::TransitionCircle
            }
            crate::machine_data::CornerModeSetting::Intersection => d.initial_corner_intersection,
        };
        let state = ModalState {
            motion: d.initial_motion,
            plane,
            distance: Distance::Absolute,
            units: md.program.units,
            feed: 0.0,
            spindle: 0.0,
            trc: TrcSide::Off,
            corner,
            selection: d.initial_selection,
            feed_adaption: FeedAdaption::Centre,
            masking: false,
            exact_stop: false,
            work_offset: 0,
            diameter: md.program.diameter_programming,
            tool: None,
            d: 0,
            radius: 0.0,
            length: 0.0,
            edge: 0,
            pole: [0.0; 3],
        };
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
            vars: Variables::default(),
            frames: Vec::new(),
            work_min: [f64::NEG_INFINITY; 3],
            work_max: [f64::INFINITY; 3],
            work_limited: false,
            loop_passes: 0,
            finished: false,
            last_skip: (0, 0),
            plain_path: true,
            block: Block::new(0, 0, None, state),
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
    pub fn starting_at(mut self, p: Pos) -> Self {
        self.cur = p;
        self
    }

    /// The position after the last block handed out.
    pub fn position(&self) -> Pos {
        self.cur
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
        };
        Alarm::at(f.code, self.name, &source, f.message)
    }

    /// Next block's text: `(start, end)`; advances past its terminator.
    fn next_segment(&mut self) -> Option<(usize, usize)> {
        if self.pos >= self.src.len() {
            return None;
        }
        let start = self.pos;
        self.blk_line = self.line;
        self.blk_line_start = self.line_start;
        let b = self.src;
        let mut i = start;
        if self.d.semicolon == Semicolon::EndOfBlock {
            // Fanuc: `;` ends the block, except inside a comment.
            let mut depth = 0u32;
            loop {
                i = if depth == 0 {
                    find_byte(b, i, [b'\n', b'(', b';'])
                } else {
                    find_byte(b, i, [b'\n', b'(', b')'])
                };
                match b.get(i) {
                    None | Some(b'\n') => break,
                    Some(b'(') => depth += 1,
                    // only looked for inside a comment, so depth > 0
                    Some(b')') => depth -= 1,
                    Some(_) => {
                        // `;` outside a comment
                        self.pos = i + 1;
                        return Some((start, i));
                    }
                }
                i += 1;
            }
        } else {
            i = find_byte(b, start, [b'\n']);
        }
        self.pos = (i + 1).min(b.len().max(i + 1));
        self.line += 1;
        self.line_start = self.pos;
        Some((start, i))
    }

    /// A plain block (see [`Self::plain`]) that is a line of its own, read without looking
    /// for the line's end first: it starts with one of the plain block's words and stops at
    /// the line feed. Anything else is left to [`Self::next_segment`], nothing changed but
    /// the block's line fields, which it sets again.
    #[inline]
    fn plain_line(&mut self) -> bool {
        let b = self.src;
        let mut i = self.pos;
        while matches!(b.get(i), Some(b' ' | b'\t' | b'\r')) {
            i += 1;
        }
        if b.get(i).is_none_or(|&c| PLAIN_BYTE[c as usize] > G_WORD) {
            return false;
        }
        self.blk_line = self.line;
        self.blk_line_start = self.line_start;
        self.blk_number = None;
        let Some(end) = self.plain(Cursor::new(b, i, b.len()), i) else {
            return false;
        };
        // As `next_segment` leaves it after a line.
        self.pos = end + 1;
        self.line += 1;
        self.line_start = self.pos;
        true
    }

    /// Interprets blocks until one is produced, the program ends, or an alarm is raised.
    #[inline]
    fn step(&mut self) -> Result<bool, Alarm> {
        loop {
            if self.finished {
                return Ok(false);
            }
            if self.plain_path && self.plain_line() {
                return Ok(true);
            }
            let Some((start, end)) = self.next_segment() else {
                self.finished = true;
                if let Some(f) = self.frames.last() {
                    // The alarm points at the statement left open.
                    let (line, line_start, at) = f.origin();
                    let message = format!("{} is not closed by {}", f.opener(), f.closer());
                    (self.blk_line, self.blk_line_start, self.blk_number) =
                        (line, line_start, None);
                    return Err(self.alarm(*fault(AlarmCode::ControlNesting, at, message)));
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

    /// One block's text: header, skip, number, control statement or words.
    #[inline]
    fn segment(&mut self, start: usize, end: usize) -> R<bool> {
        let mut c = Cursor::new(self.src, start, end);
        c.skip_blanks();
        match c.peek() {
            None => return Ok(false),
            // Program header: `%name`, `%` alone (Fanuc tape start/end).
            Some(b'%') => return Ok(false),
            Some(b'/') => {
                c.i += 1;
                if matches!(c.peek(), Some(b'0'..=b'9')) {
                    c.i += 1;
                }
                if self.md.program.block_skip {
                    return Ok(false);
                }
                c.skip_blanks();
            }
            _ => {}
        }
        if self.d.o_numbers && c.letter() == Some(b'O') && matches!(c.peek_at(1), Some(b'0'..=b'9'))
        {
            // Fanuc program number line.
            return Ok(false);
        }
        let block_col = c.i;
        self.blk_number = control::read_block_number(&mut c)?;
        c.skip_blanks();
        if self.d.variables && c.peek() == Some(b'$') {
            return self.control(c).map(|()| false);
        }
        if self.plain_path && self.plain(c, block_col).is_some() {
            return Ok(true);
        }
        let mut words = Words::default();
        self.block.words.clear();
        self.words(&mut c, &mut words)?;
        if self.blk_number.is_none() && words.is_empty() && self.block.words.is_empty() {
            // A line holding only a comment is no block.
            return Ok(false);
        }
        self.build(&words, block_col)
    }

    /// The common block — at most one motion G code (not polar), axis and centre words with
    /// their numbers written out, nothing else — read and built in one pass, without the
    /// word loop's collection and the general build. For anything else, and for anything an
    /// alarm would come from, it returns `None` with the block untouched, and the full path
    /// reads the block from the same place: both ways give the same block (tested below).
    /// Otherwise it returns where it stopped: the end of the cursor's text or a line feed.
    #[inline]
    fn plain(&mut self, c: Cursor, block_col: usize) -> Option<usize> {
        if self.work_limited {
            return None;
        }
        let d = self.d;
        let mut mode = self.block.modal.motion;
        // X Y Z I J K; bit k of `seen`: word k written, bit `G_WORD`: a G code.
        let mut vals = [Val {
            value: 0.0,
            at: 0,
            has_point: false,
        }; 6];
        let mut seen = 0u8;
        // The block's text alone: a number cannot run past its end.
        let text = c.b.get(..c.end)?;
        let mut i = c.i;
        while let Some(&ch) = text.get(i) {
            let k = PLAIN_BYTE[ch as usize];
            if k > G_WORD {
                match k {
                    BLANK => {
                        i += 1;
                        continue;
                    }
                    LINE_FEED => break,
                    _ => return None,
                }
            }
            if seen & (1 << k) != 0 {
                return None;
            }
            seen |= 1 << k;
            let at = i;
            let (n, next) = number::parse(text, at + 1)?;
            if n.value.abs() > MAX_VALUE {
                return None;
            }
            i = next;
            if k == G_WORD {
                let v = n.value;
                if !((0.0..1000.0).contains(&v) && v as u16 as f64 == v) {
                    return None;
                }
                match d.gcode(v as u16) {
                    Some(GCodeDef {
                        effect: GEffect::Motion(m),
                        forbidden_with_trc: false,
                        ..
                    }) => mode = *m,
                    _ => return None,
                }
            } else {
                vals[k as usize] = Val::new(n, at);
            }
        }
        let programmed = seen & 7;
        let arc = mode.is_arc();
        if mode.is_polar() || programmed == 0 || (seen & 0x38 != 0) != arc {
            return None;
        }
        let modal = &self.block.modal;
        if mode != MotionMode::Rapid && modal.feed <= 0.0 {
            return None;
        }
        let offset = self.md.zero_offsets.get(modal.work_offset);
        let start = self.cur;
        let mut end = start;
        for i in 0..3 {
            if programmed & (1 << i) != 0 {
                if !self.md.has_axis(i) {
                    return None;
                }
                end[i] = self.axis_target(vals[i], i, modal, start[i], offset[i]);
                if !in_range(end[i]) {
                    return None;
                }
            }
        }
        let plane = modal.plane;
        let mut centre = end;
        if arc {
            let mut off = [0.0; 3];
            for i in 0..3 {
                if seen & (8 << i) != 0 {
                    if !plane.contains(i) {
                        return None;
                    }
                    off[i] = self.length(vals[3 + i], modal.units);
                }
            }
            let tol = self.md.program.arc_endpoint_tolerance;
            let ccw = mode == MotionMode::ArcCcw;
            match arc::centre(start, end, plane, ccw, CentreSpec::Offsets(off), tol) {
                Ok(c) => centre = c,
                Err(_) => return None,
            }
        }
        // Nothing fails from here on.
        let col = column(self.src, self.blk_line_start, block_col);
        reset(&mut self.block, self.blk_line, col, self.blk_number);
        let blk = &mut self.block;
        blk.words.clear();
        blk.modal.motion = mode;
        self.vars.tool_length = blk.modal.length;
        self.vars.tool_radius = blk.modal.radius;
        blk.motion = Some(Motion {
            kind: mode.kind(),
            plane,
            start,
            end,
            center: centre,
            programmed,
        });
        self.cur = end;
        Some(i)
    }

    /// Collects the words of a block.
    fn words(&mut self, c: &mut Cursor, w: &mut Words) -> R<()> {
        let d = self.d;
        loop {
            c.skip_blanks();
            let Some(ch) = c.peek() else { break };
            let at = c.i;
            let upper = ch.to_ascii_uppercase();
            // G, X, Y, Z, I, J, K are plain addresses in every dialect and start no longer
            // word: the bulk of any program, so they skip the checks in `special`.
            let letter = if matches!(upper, b'G' | b'I'..=b'K' | b'X'..=b'Z') {
                upper
            } else {
                match self.special(c, w, ch, at)? {
                    Next::Continue => continue,
                    Next::Break => break,
                    Next::Address(letter) => letter,
                }
            };
            c.i += 1;
            let v = self.value(c, at, "")?;
            let name = letter as char;
            match letter {
                b'G' => {
                    let code = int_value(v.value, at, "G code")?;
                    if code >= 1000 {
                        return Err(fault(
                            AlarmCode::UnknownGCode,
                            at,
                            format!("G{code} is not a {} G code", d.name.as_str()),
                        ));
                    }
                    push(&mut w.g, (code as u16, at as u32), at)?;
                }
                b'X' | b'Y' | b'Z' => {
                    let i = (letter - b'X') as usize;
                    set_once(&mut w.axis[i], v, AXIS_WORDS[i])?;
                }
                b'I' | b'J' | b'K' => {
                    let i = (letter - b'I') as usize;
                    set_once(&mut w.centre[i], v, CENTRE_WORDS[i])?;
                }
                b'R' if d.radius_word == RadiusWord::R => set_once(&mut w.radius, v, "R")?,
                b'A' if d.polar_words => set_once(&mut w.angle, v, "A")?,
                b'U' | b'B' if d.polar_words => set_once(&mut w.polar_radius, v, "U/B")?,
                b'P' if d.dwell.p_millis => set_once(&mut w.p, v, "P")?,
                b'F' => {
                    set_once(&mut w.f, v, "F")?;
                    push(
                        &mut self.block.words,
                        AuxWord {
                            address: b'F',
                            value: v.value,
                        },
                        at,
                    )?;
                }
                b'D' => {
                    set_once(&mut w.d, v, "D")?;
                    push(
                        &mut self.block.words,
                        AuxWord {
                            address: b'D',
                            value: v.value,
                        },
                        at,
                    )?;
                }
                b'T' => {
                    set_once(&mut w.t, v, "T")?;
                    push(
                        &mut self.block.words,
                        AuxWord {
                            address: b'T',
                            value: v.value,
                        },
                        at,
                    )?;
                }
                b'M' => {
                    push(&mut w.m, v, at)?;
                    push(
                        &mut self.block.words,
                        AuxWord {
                            address: b'M',
                            value: v.value,
                        },
                        at,
                    )?;
                }
                b'S' | b'H' => push(
                    &mut self.block.words,
                    AuxWord {
                        address: letter,
                        value: v.value,
                    },
                    at,
                )?,
                b'N' => {
                    return Err(fault(
                        AlarmCode::Syntax,
                        at,
                        "the block number N must come first in the block",
                    ))
                }
                _ => {
                    return Err(fault(
                        AlarmCode::UnknownAddress,
                        at,
                        format!(
                            "address {name} is not defined in the {} dialect",
                            d.name.as_str()
                        ),
                    ))
                }
            }
        }
        Ok(())
    }

    /// Everything at a word's start but the plain addresses: comments, `@` commands, an ISG
    /// bare dwell time, multi-letter words and unknown addresses. Says how the word loop goes
    /// on, or returns the address letter for the loop to read.
    #[inline(never)]
    fn special(&mut self, c: &mut Cursor, w: &mut Words, ch: u8, at: usize) -> R<Next> {
        let d = self.d;
        match ch {
            b'(' => {
                if !c.skip_comment() {
                    if d.variables {
                        // ISG: `(` alone comments out the rest of the block.
                        return Ok(Next::Break);
                    }
                    return Err(fault(AlarmCode::Syntax, at, "comment not closed with ')'"));
                }
                return Ok(Next::Continue);
            }
            // comment (Siemens, ISG); Fanuc's ';' never gets here
            b';' => return Ok(Next::Break),
            _ => {}
        }
        let Some(letter) = c.letter() else {
            if d.at_commands && ch == b'@' {
                c.i += 1;
                let (n, next) = number::parse(c.b, c.i)
                    .filter(|(n, e)| *e <= c.end && !n.has_point)
                    .ok_or_else(|| {
                        fault(
                            AlarmCode::Syntax,
                            at,
                            "@ must be followed by a command number",
                        )
                    })?;
                c.i = next;
                let code = int_value(n.value, at, "@ command")?;
                push(&mut w.at_codes, (code, at as u32), at)?;
                return Ok(Next::Continue);
            }
            if d.dwell.bare_seconds && w.bare.is_none() && matches!(w.g.last(), Some((4, _))) {
                if let Some((n, next)) = number::parse(c.b, c.i).filter(|(_, e)| *e <= c.end) {
                    c.i = next;
                    w.bare = Some(Val::new(n, at));
                    return Ok(Next::Continue);
                }
            }
            let shown = std::str::from_utf8(&c.b[at..c.end])
                .ok()
                .and_then(|s| s.chars().next())
                .unwrap_or('?');
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("unexpected character '{shown}'"),
            ));
        };
        // Multi-letter words: they start with L (LF), C (CR=), D (DIAMON/DIAMOF) or
        // V (V. variables).
        if matches!(letter, b'L' | b'C' | b'D' | b'V') {
            if d.lf_block_end
                && letter == b'L'
                && matches!(c.peek_at(1), Some(b'F' | b'f'))
                && !matches!(c.peek_at(2), Some(x) if x.is_ascii_alphanumeric() || x == b'.' || x == b'-' || x == b'+')
            {
                // 840C listings: `LF` ends the block; only comments may follow.
                c.i += 2;
                loop {
                    c.skip_blanks();
                    match c.peek() {
                        None | Some(b';') => break,
                        Some(b'(') => {
                            if !c.skip_comment() {
                                return Err(fault(
                                    AlarmCode::Syntax,
                                    c.i,
                                    "comment not closed with ')'",
                                ));
                            }
                        }
                        Some(_) => {
                            return Err(fault(
                                AlarmCode::Syntax,
                                c.i,
                                "nothing but a comment may follow LF (end of block)",
                            ))
                        }
                    }
                }
                return Ok(Next::Break);
            }
            if d.radius_word == RadiusWord::CrEquals
                && letter == b'C'
                && matches!(c.peek_at(1), Some(b'R' | b'r'))
            {
                c.i += 2;
                c.skip_blanks();
                if c.peek() != Some(b'=') {
                    return Err(fault(AlarmCode::Syntax, at, "CR must be followed by '='"));
                }
                c.i += 1;
                let v = self.value(c, at, "CR=")?;
                set_once(&mut w.radius, v, "CR=")?;
                return Ok(Next::Continue);
            }
            if d.diameter_words && (c.keyword("DIAMON") || c.keyword("DIAMOF")) {
                let on = c.keyword("DIAMON");
                c.i += 6;
                if w.diameter.replace(on).is_some() {
                    return Err(fault(
                        AlarmCode::AddressTwice,
                        at,
                        "DIAMON/DIAMOF twice in one block",
                    ));
                }
                return Ok(Next::Continue);
            }
            if d.variables && expr::at_variable(c) {
                let name = c.name();
                c.skip_blanks();
                if c.peek() != Some(b'=') || c.peek_at(1) == Some(b'=') {
                    return Err(fault(
                        AlarmCode::Syntax,
                        c.i,
                        format!("'=' expected after {name}"),
                    ));
                }
                c.i += 1;
                let value = expr::eval(c, &self.vars)?;
                let written = self.vars.set(&name, value, at)?;
                if written == Written::ToolRadius {
                    w.radius_written = Some(at as u32);
                }
                w.calculation = true;
                return Ok(Next::Continue);
            }
        }
        let known = matches!(
            letter,
            b'G' | b'X'
                | b'Y'
                | b'Z'
                | b'I'
                | b'J'
                | b'K'
                | b'F'
                | b'D'
                | b'T'
                | b'M'
                | b'S'
                | b'H'
                | b'N'
        ) || (letter == b'R' && d.radius_word == RadiusWord::R)
            || (matches!(letter, b'A' | b'U' | b'B') && d.polar_words)
            || (letter == b'P' && d.dwell.p_millis);
        if !known {
            return Err(fault(
                AlarmCode::UnknownAddress,
                at,
                format!(
                    "address {} is not defined in the {} dialect",
                    letter as char,
                    d.name.as_str()
                ),
            ));
        }
        Ok(Next::Address(letter))
    }

    /// The value after an address: a number, or in the ISG dialect an expression operand.
    #[inline(always)]
    fn value(&mut self, c: &mut Cursor, at: usize, what: &str) -> R<Val> {
        // The common case: an in-range number right after the address.
        if let Some((n, next)) = number::parse(c.b, c.i) {
            if next <= c.end && n.value.abs() <= MAX_VALUE {
                c.i = next;
                return Ok(Val::new(n, at));
            }
        }
        self.value_slow(c, at, what)
    }

    /// [`Self::value`] for everything but the common case, alarms included.
    #[inline(never)]
    fn value_slow(&mut self, c: &mut Cursor, at: usize, what: &str) -> R<Val> {
        if let Some((n, next)) = number::parse(c.b, c.i).filter(|(_, e)| *e <= c.end) {
            // A number right after the address, out of range if it got here: `checked` says so.
            c.i = next;
            return checked(Val::new(n, at));
        }
        c.skip_blanks();
        if self.d.variables
            && matches!(
                c.peek(),
                Some(b'[') | Some(b'-') | Some(b'+') | Some(b'a'..=b'z') | Some(b'A'..=b'Z')
            )
            && !matches!(
                (c.peek(), c.peek_at(1)),
                (Some(b'-' | b'+'), Some(b'0'..=b'9' | b'.'))
            )
        {
            let v = expr::eval_operand(c, &self.vars)?;
            return checked(Val {
                value: v,
                at: at as u32,
                has_point: true,
            });
        }
        match number::parse(c.b, c.i).filter(|(_, e)| *e <= c.end) {
            Some((n, next)) => {
                c.i = next;
                checked(Val::new(n, at))
            }
            None => {
                let shown = if what.is_empty() {
                    (c.b[at] as char).to_ascii_uppercase().to_string()
                } else {
                    what.to_string()
                };
                Err(fault(
                    AlarmCode::BadNumber,
                    c.i,
                    format!("{shown} must be followed by a number"),
                ))
            }
        }
    }

    /// A length value in mm: decimal-input switch, inch conversion.
    fn length(&self, v: Val, units: Units) -> f64 {
        let mut x = v.value;
        if self.d.decimal_switch
            && !v.has_point
            && self.md.program.decimal_input == DecimalInput::Increment
        {
            x *= match units {
                Units::Mm => self.md.program.least_input_increment_mm,
                Units::Inch => self.md.program.least_input_increment_inch,
            };
        }
        if units == Units::Inch {
            x * 25.4
        } else {
            x
        }
    }

    /// Where axis `i` goes for its word `a`: in mm, a diameter halved, absolute (plus the zero
    /// offset) or incremental.
    #[inline(always)]
    fn axis_target(&self, a: Val, i: usize, new: &ModalState, start: f64, offset: f64) -> f64 {
        let v = self.length(a, new.units) * if i == 0 && new.diameter { 0.5 } else { 1.0 };
        match new.distance {
            Distance::Absolute => v + offset,
            Distance::Incremental => start + v,
        }
    }

    /// Turns collected words into a block.
    #[inline]
    fn build(&mut self, w: &Words, block_col: usize) -> R<bool> {
        let d = self.d;
        let mut new = self.block.modal;
        let (old_trc, old_plane, old_selection) = (new.trc, new.plane, new.selection);
        let col = column(self.src, self.blk_line_start, block_col);
        reset(&mut self.block, self.blk_line, col, self.blk_number);
        self.block.calculation = w.calculation;
        let blk = &mut self.block;

        // G codes: look up, check groups and TRC restrictions, then apply.
        // Table rows, not copies of them: the common block has one or two G codes.
        let mut effects: heapless::Vec<(&'static GCodeDef, u32), 16> = heapless::Vec::new();
        for &(code, at) in &w.g {
            let def = d.gcode(code).ok_or_else(|| {
                fault(
                    AlarmCode::UnknownGCode,
                    at,
                    format!("G{code} is not a {} G code", d.name.as_str()),
                )
            })?;
            if let Some((other, _)) = effects
                .iter()
                .find(|(e, _)| Dialect::same_group(e.effect, def.effect))
            {
                return Err(fault(
                    AlarmCode::SameGroupTwice,
                    at,
                    format!("G{code} and G{} belong to the same group", other.code),
                ));
            }
            if let (GEffect::Plane(p), true) = (def.effect, old_trc != TrcSide::Off) {
                if p != old_plane {
                    return Err(fault(
                        AlarmCode::PlaneChangeWithTrc,
                        at,
                        format!("G{code}: the plane cannot be changed while TRC is active"),
                    ));
                }
            }
            if def.forbidden_with_trc && old_trc != TrcSide::Off {
                return Err(fault(
                    AlarmCode::ForbiddenWithTrc,
                    at,
                    format!("G{code} may not be programmed while TRC (G41/G42) is active; deselect TRC first"),
                ));
            }
            if let GEffect::Unsupported(what) = def.effect {
                return Err(fault(
                    AlarmCode::NotSupported,
                    at,
                    format!("{what} is not supported by softnc"),
                ));
            }
            let _ = effects.push((def, at));
        }
        for &(code, at) in &w.at_codes {
            if code != 714 {
                return Err(fault(
                    AlarmCode::NotSupported,
                    at,
                    format!("@{code} is not supported by softnc"),
                ));
            }
            if old_trc != TrcSide::Off {
                return Err(fault(
                    AlarmCode::ForbiddenWithTrc,
                    at,
                    "@714 may not be programmed while TRC (G41/G42) is active; deselect TRC first",
                ));
            }
            blk.preprocess_stop = true;
        }

        let mut dwell = false;
        let mut working_area: Option<bool> = None;
        let mut trc_code_at = None;
        for &(&GCodeDef { code, effect, .. }, at) in &effects {
            match effect {
                GEffect::Motion(m) => new.motion = m,
                GEffect::Dwell => dwell = true,
                GEffect::ExactStopBlock => blk.exact_stop = true,
                GEffect::ExactStopModal(on) => new.exact_stop = on,
                GEffect::Plane(p) => {
                    if old_trc != TrcSide::Off && p != old_plane {
                        return Err(fault(
                            AlarmCode::PlaneChangeWithTrc,
                            at,
                            format!("G{code}: the plane cannot be changed while TRC is active"),
                        ));
                    }
                    new.plane = p;
                }
                GEffect::Units(u) => new.units = u,
                GEffect::Distance(x) => new.distance = x,
                GEffect::Trc(side) => {
                    blk.trc = Some(side);
                    new.trc = side;
                    trc_code_at = Some(at);
                }
                GEffect::Corner(cp) => new.corner = cp,
                GEffect::Approach(sp) => blk.approach = Some(sp),
                GEffect::Selection(sp) => {
                    if sp == SelectionPolicy::InnerCorner
                        && old_trc != TrcSide::Off
                        && old_selection != sp
                    {
                        return Err(fault(
                            AlarmCode::ForbiddenWithTrc,
                            at,
                            format!("G{code}: inner-corner selection cannot be switched on while TRC is active"),
                        ));
                    }
                    new.selection = sp;
                }
                GEffect::FeedAdaption(fa) => new.feed_adaption = fa,
                GEffect::Masking(on) => new.masking = on,
                GEffect::WorkOffset(i) => new.work_offset = i,
                GEffect::WorkingArea { max } => working_area = Some(max),
                GEffect::PoleHere => new.pole = self.cur,
                GEffect::Unsupported(_) => {}
            }
        }
        if let Some(on) = w.diameter {
            new.diameter = on;
        }
        let units = new.units;
        let scale = if units == Units::Inch { 25.4 } else { 1.0 };

        // Technology words.
        if !dwell {
            if let Some(f) = w.f {
                if f.value <= 0.0 || !f.value.is_finite() {
                    return Err(fault(
                        AlarmCode::BadNumber,
                        f.at,
                        "the feed F must be positive",
                    ));
                }
                new.feed = f.value * scale;
            }
        }
        for a in &blk.words {
            if a.address == b'S' {
                if a.value < 0.0 {
                    return Err(fault(
                        AlarmCode::BadNumber,
                        block_col,
                        "the spindle speed S must not be negative",
                    ));
                }
                new.spindle = a.value;
            }
        }
        if let Some(t) = w.t {
            new.tool = Some(int_value(t.value, t.at, "T")?);
            blk.offset_changed = true;
        }
        let d_word = match w.d {
            Some(v) => Some((int_value(v.value, v.at, "D")?, v.pos())),
            None if d.tool_edges && w.t.is_some() && new.d != 0 => Some((new.d, block_col)),
            None => None,
        };
        if let Some((dn, at)) = d_word {
            if dn == 0 {
                new.d = 0;
                new.radius = 0.0;
                new.length = 0.0;
                new.edge = 0;
                if d.d0_deselects && old_trc != TrcSide::Off && blk.trc.is_none() {
                    blk.trc = Some(TrcSide::Off);
                    new.trc = TrcSide::Off;
                }
            } else {
                let tool = if d.tool_edges { new.tool } else { None };
                let (radius, length, edge) = self.tools.resolve(tool, dn).ok_or_else(|| {
                    let what = crate::tools::offset_label(tool, dn);
                    fault(
                        AlarmCode::UnknownOffset,
                        at,
                        format!("tool offset {what} is not in the tool table"),
                    )
                })?;
                new.d = dn;
                new.radius = radius;
                new.length = length;
                new.edge = edge.unwrap_or(0);
            }
            blk.offset_changed = true;
        }
        self.vars.tool_length = new.length;
        if w.radius_written.is_some() {
            new.radius = self.vars.tool_radius;
            blk.offset_changed = true;
        }
        self.vars.tool_radius = new.radius;

        // Program flow M functions.
        for m in &w.m {
            let stop = match m.value {
                0.0 => Some(ProgramStop::Stop),
                1.0 => Some(ProgramStop::OptionalStop),
                2.0 => Some(ProgramStop::End),
                30.0 => Some(ProgramStop::EndRewind),
                v if v == 18.0 && d.m18_stops => Some(ProgramStop::StopAtEnd),
                _ => None,
            };
            if let Some(s) = stop {
                if blk.stop.is_some_and(|prev| prev != s) {
                    return Err(fault(
                        AlarmCode::SameGroupTwice,
                        m.at,
                        "two program-flow M functions in one block",
                    ));
                }
                blk.stop = Some(s);
            }
        }

        // Dwell, working area: the axis words carry times or limits, not positions.
        if dwell {
            let secs = if let (true, Some(mut x)) = (d.dwell.x_seconds, w.axis[0]) {
                // Fanuc increment input: X1000 without a decimal point is 1000 ms.
                if d.decimal_switch
                    && !x.has_point
                    && self.md.program.decimal_input == DecimalInput::Increment
                {
                    x.value *= 0.001;
                }
                Some(x)
            } else if let (true, Some(f)) = (d.dwell.f_seconds, w.f) {
                Some(f)
            } else if let (true, Some(p)) = (d.dwell.p_millis, w.p) {
                Some(Val {
                    value: p.value / 1000.0,
                    at: p.at,
                    has_point: true,
                })
            } else {
                w.bare
            };
            let secs = secs.ok_or_else(|| {
                fault(AlarmCode::MissingValue, block_col, "G4 needs a dwell time")
            })?;
            if secs.value < 0.0 || secs.value > 1e6 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    secs.at,
                    "dwell time out of range",
                ));
            }
            let axis_used_as_time = d.dwell.x_seconds && w.axis[0].is_some();
            for (i, a) in w.axis.iter().enumerate() {
                if let Some(a) = a {
                    if !(i == 0 && axis_used_as_time) {
                        return Err(fault(
                            AlarmCode::Syntax,
                            a.at,
                            "a dwell block (G4) cannot move axes",
                        ));
                    }
                }
            }
            blk.dwell = Some(secs.value);
        } else if let Some(max) = working_area {
            self.work_limited = true;
            for (i, a) in w.axis.iter().enumerate() {
                if let Some(a) = a {
                    let v = self.length(*a, units);
                    if max {
                        self.work_max[i] = v;
                    } else {
                        self.work_min[i] = v;
                    }
                }
            }
        } else {
            self.motion(w, &mut new, block_col)?;
        }

        let blk = &mut self.block;
        // TRC selection/deselection only in linear blocks (840C 11.3/11.5, Fanuc 026).
        // Fanuc changes sides in offset mode in any block, circles included (no new start-up).
        let fanuc_side_change = d.trc.side_change == SideChange::Intersection
            && old_trc != TrcSide::Off
            && new.trc != TrcSide::Off
            && new.trc != old_trc;
        if let (Some(_), Some(at)) = (blk.trc, trc_code_at) {
            let arc = new.motion.is_arc();
            if arc
                && !fanuc_side_change
                && (blk.motion.is_some() || d.trc_not_linear == AlarmCode::FanucTrcNotLinear)
            {
                return Err(fault(
                    d.trc_not_linear,
                    at,
                    "tool radius compensation can only be selected or deselected in a G0/G1 block",
                ));
            }
        }

        if let Some(m) = &blk.motion {
            self.cur = m.end;
        }
        if blk.stop.is_some_and(|s| s.ends_program()) {
            new.pole = self.md.zero_offsets.get(new.work_offset);
            self.finished = true;
        }
        blk.modal = new;
        Ok(true)
    }

    /// Sets the block's motion, if it has one (written in place: `Motion` is large).
    fn motion(&mut self, w: &Words, new: &mut ModalState, block_col: usize) -> R<()> {
        let units = new.units;
        let offset = self.md.zero_offsets.get(new.work_offset);
        let plane = new.plane;
        let (pa, po) = (plane.abscissa as usize, plane.ordinate as usize);
        let mut programmed = 0u8;
        for (i, a) in w.axis.iter().enumerate() {
            if let Some(a) = a {
                if !self.md.has_axis(i) {
                    return Err(fault(
                        AlarmCode::UnknownAddress,
                        a.at,
                        format!("axis {} is not configured on this machine", AXIS_NAMES[i]),
                    ));
                }
                programmed |= 1 << i;
            }
        }
        let start = self.cur;
        let mut end = start;
        let diameter_factor = |i: usize| if i == 0 && new.diameter { 0.5 } else { 1.0 };
        let mode = new.motion;
        let feed_needed = !matches!(mode, MotionMode::Rapid | MotionMode::PolarRapid);

        if mode.is_polar() {
            // 880/840C: plane-axis words give the pole, A the angle, U or B the radius.
            for i in [pa, po] {
                if let Some(a) = w.axis[i] {
                    let v = self.length(a, units) * diameter_factor(i);
                    new.pole[i] = match new.distance {
                        Distance::Absolute => v + offset[i],
                        Distance::Incremental => new.pole[i] + v,
                    };
                }
            }
            let normal = plane.normal as usize;
            if let Some(a) = w.axis[normal] {
                let v = self.length(a, units);
                end[normal] = match new.distance {
                    Distance::Absolute => v + offset[normal],
                    Distance::Incremental => start[normal] + v,
                };
            }
            if w.angle.is_none() && w.polar_radius.is_none() && w.axis[normal].is_none() {
                return Ok(());
            }
            let (rx, ry) = (start[pa] - new.pole[pa], start[po] - new.pole[po]);
            let r_now = libm::hypot(rx, ry);
            let ang_now = libm::atan2(ry, rx).to_degrees();
            let ang = match w.angle {
                Some(a) if new.distance == Distance::Incremental => ang_now + a.value,
                Some(a) => a.value,
                None => ang_now,
            };
            let r = match w.polar_radius {
                Some(u) => {
                    let r = self.length(u, units);
                    if r < 0.0 {
                        return Err(fault(
                            AlarmCode::BadNumber,
                            u.at,
                            "the polar radius U/B is written without sign",
                        ));
                    }
                    r
                }
                None => r_now,
            };
            let arc = mode.is_arc();
            if arc {
                if r_now <= 1e-9 {
                    return Err(fault(
                        AlarmCode::ArcEndPoint,
                        block_col,
                        "polar circle: the start point lies on the pole",
                    ));
                }
                if (r - r_now).abs() > self.md.program.arc_endpoint_tolerance {
                    return Err(fault(
                        AlarmCode::ArcEndPoint,
                        w.polar_radius.map_or(block_col, Val::pos),
                        format!(
                            "polar circle: radius {r:.4} differs from the start radius {r_now:.4}"
                        ),
                    ));
                }
            }
            let rr = if arc { r_now } else { r };
            let rad = ang.to_radians();
            end[pa] = new.pole[pa] + rr * libm::cos(rad);
            end[po] = new.pole[po] + rr * libm::sin(rad);
            let mut centre = start;
            centre[pa] = new.pole[pa];
            centre[po] = new.pole[po];
            if feed_needed && new.feed <= 0.0 {
                return Err(fault(
                    AlarmCode::NoFeed,
                    block_col,
                    "no feed programmed (F)",
                ));
            }
            self.check_area(&end, block_col)?;
            self.block.motion = Some(Motion {
                kind: mode.kind(),
                plane,
                start,
                end,
                center: if arc { centre } else { end },
                programmed,
            });
            return Ok(());
        }

        for (i, a) in w.axis.iter().enumerate() {
            if let Some(a) = a {
                end[i] = self.axis_target(*a, i, new, start[i], offset[i]);
                if !in_range(end[i]) {
                    return Err(fault(AlarmCode::BadNumber, a.at, "coordinate out of range"));
                }
            }
        }
        let arc = mode.is_arc();
        let has_centre = w.centre.iter().any(Option::is_some) || w.radius.is_some();
        if has_centre && !arc {
            let at = w
                .centre
                .iter()
                .flatten()
                .map(|v| v.pos())
                .chain(w.radius.map(Val::pos))
                .next()
                .unwrap_or(block_col);
            return Err(fault(
                AlarmCode::Syntax,
                at,
                "circle parameters without a circular motion",
            ));
        }
        if programmed == 0 && !(arc && has_centre) {
            return Ok(());
        }
        if feed_needed && new.feed <= 0.0 {
            return Err(fault(
                AlarmCode::NoFeed,
                block_col,
                "no feed programmed (F)",
            ));
        }
        let mut centre = end;
        if arc {
            for (i, v) in w.centre.iter().enumerate() {
                if let (Some(v), false) = (v, plane.contains(i)) {
                    return Err(fault(
                        AlarmCode::Syntax,
                        v.at,
                        format!(
                            "{} is not a centre coordinate in the {} plane",
                            ['I', 'J', 'K'][i],
                            plane.name()
                        ),
                    ));
                }
            }
            let spec = match (w.radius, w.centre.iter().any(Option::is_some)) {
                (Some(r), false) => CentreSpec::Radius(self.length(r, units)),
                (None, true) => {
                    let mut off = [0.0; 3];
                    for (i, v) in w.centre.iter().enumerate() {
                        if let Some(v) = v {
                            off[i] = self.length(*v, units);
                        }
                    }
                    CentreSpec::Offsets(off)
                }
                (Some(r), true) => {
                    return Err(fault(
                        AlarmCode::Syntax,
                        r.at,
                        "a circle takes either a centre or a radius, not both",
                    ))
                }
                (None, false) => {
                    return Err(fault(
                        AlarmCode::MissingValue,
                        block_col,
                        "a circle needs its centre (I, J, K) or its radius",
                    ))
                }
            };
            let at = w
                .radius
                .map(Val::pos)
                .or_else(|| w.centre.iter().flatten().next().map(|v| v.pos()))
                .unwrap_or(block_col);
            let tol = self.md.program.arc_endpoint_tolerance;
            let ccw = mode == MotionMode::ArcCcw;
            centre = arc::centre(start, end, plane, ccw, spec, tol).map_err(|e| {
                let msg = match e {
                    ArcError::EndPointOff { r_start, r_end } => format!(
                        "end point not on the circle: start radius {r_start:.4}, end radius {r_end:.4} (tolerance {tol})"
                    ),
                    ArcError::ZeroRadius => "the centre lies on the start point".to_string(),
                    ArcError::FullCircleByRadius => {
                        "a full circle cannot be programmed with a radius; give the centre".to_string()
                    }
                    ArcError::RadiusTooSmall { radius, half_chord } => format!(
                        "radius {:.4} is smaller than half the distance to the end point ({half_chord:.4})",
                        radius.abs()
                    ),
                };
                fault(AlarmCode::ArcEndPoint, at, msg)
            })?;
        }
        self.check_area(&end, block_col)?;
        self.block.motion = Some(Motion {
            kind: mode.kind(),
            plane,
            start,
            end,
            center: centre,
            programmed,
        });
        Ok(())
    }

    /// 840C G25/G26: end points must stay inside the working area.
    fn check_area(&self, p: &Pos, at: usize) -> R<()> {
        if !self.work_limited {
            return Ok(());
        }
        for i in 0..3 {
            if p[i] < self.work_min[i] || p[i] > self.work_max[i] {
                return Err(fault(
                    AlarmCode::WorkingArea,
                    at,
                    format!(
                        "{} {:.4} lies outside the working area limitation {} .. {}",
                        AXIS_NAMES[i], p[i], self.work_min[i], self.work_max[i]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `$FOR`, `$IF`, `$WHILE` and their closing statements (ISG).
    fn control(&mut self, mut c: Cursor) -> R<()> {
        let stmt = control::parse(&mut c, &self.vars)?;
        let origin = (self.blk_line, self.blk_line_start, c.i);
        match stmt {
            ControlStmt::For {
                var,
                var_at,
                start,
                end,
                step,
                at,
            } => {
                if step == 0.0 {
                    return Err(fault(
                        AlarmCode::BadNumber,
                        at,
                        "$FOR with step 0 would never end",
                    ));
                }
                self.vars.set(&var, start, var_at)?;
                if control::for_continues(start, end, step) {
                    // The first pass counts against the program's loop budget too.
                    self.loop_passes = self.loop_passes.saturating_add(1);
                    self.frames.push(Frame::For {
                        var,
                        end,
                        step,
                        body: (self.pos, self.line, self.line_start),
                        origin: (origin.0, origin.1, at),
                    });
                } else {
                    self.skip_to(&["ENDFOR"], at)?;
                }
            }
            ControlStmt::EndFor { at } => match self.frames.pop() {
                Some(Frame::For {
                    var,
                    end,
                    step,
                    body,
                    origin,
                }) => {
                    let v = self.vars.get(&var).unwrap_or(end) + step;
                    // It was written at the $FOR already, so it is a program variable.
                    let _ = self.vars.set(&var, v, origin.2);
                    if control::for_continues(v, end, step) {
                        self.next_pass(at)?;
                        (self.pos, self.line, self.line_start) = body;
                        self.frames.push(Frame::For {
                            var,
                            end,
                            step,
                            body,
                            origin,
                        });
                    }
                }
                other => return Err(self.mismatch(other, "$ENDFOR", at)),
            },
            ControlStmt::While {
                cond,
                cond_range,
                at,
            } => {
                if expr::truthy(cond) {
                    // The first pass counts against the program's loop budget too.
                    self.loop_passes = self.loop_passes.saturating_add(1);
                    self.frames.push(Frame::While {
                        cond: cond_range,
                        body: (self.pos, self.line, self.line_start),
                        origin: (origin.0, origin.1, at),
                    });
                } else {
                    self.skip_to(&["ENDWHILE"], at)?;
                }
            }
            ControlStmt::EndWhile { at } => match self.frames.pop() {
                Some(Frame::While { cond, body, origin }) => {
                    let mut cc = Cursor::new(self.src, cond.0, cond.1);
                    // A fault in the condition points at the $ENDWHILE that evaluates it.
                    let v = expr::eval(&mut cc, &self.vars).map_err(|mut f| {
                        f.at = at;
                        f
                    })?;
                    if expr::truthy(v) {
                        self.next_pass(at)?;
                        (self.pos, self.line, self.line_start) = body;
                        self.frames.push(Frame::While { cond, body, origin });
                    }
                }
                other => return Err(self.mismatch(other, "$ENDWHILE", at)),
            },
            ControlStmt::If { cond, at } => {
                let mut taken = expr::truthy(cond);
                let mut at_kw = at;
                // Walk $ELSEIF / $ELSE until a branch is taken.
                while !taken {
                    let kw = self.skip_to(&["ELSEIF", "ELSE", "ENDIF"], at_kw)?;
                    match kw.as_str() {
                        "ENDIF" => return Ok(()),
                        "ELSE" => {
                            taken = true;
                        }
                        _ => {
                            // The $ELSEIF line was consumed by skip_to; evaluate its condition.
                            let (s, e) = self.last_skip;
                            let (cond, cat) =
                                control::elseif_condition(self.src, s, e, &self.vars)?;
                            taken = expr::truthy(cond);
                            at_kw = cat;
                        }
                    }
                }
                self.frames.push(Frame::If {
                    origin: (origin.0, origin.1, at),
                });
            }
            ControlStmt::Else { at } | ControlStmt::ElseIf { at } => match self.frames.pop() {
                Some(Frame::If { .. }) => {
                    // The taken branch ends here: skip the rest up to $ENDIF.
                    self.skip_to(&["ENDIF"], at)?;
                }
                other => return Err(self.mismatch(other, "$ELSE", at)),
            },
            ControlStmt::EndIf { at } => match self.frames.pop() {
                Some(Frame::If { .. }) => {}
                other => return Err(self.mismatch(other, "$ENDIF", at)),
            },
        }
        Ok(())
    }

    /// Counts one more loop pass; the budget covers the whole program, so nested loops are
    /// bounded by it too.
    fn next_pass(&mut self, at: usize) -> R<()> {
        let max = self.md.program.max_loop_iterations;
        if self.loop_passes >= max {
            return Err(fault(
                AlarmCode::LoopLimit,
                at,
                format!("loops ran {max} passes (machine data program.max_loop_iterations, counted over the whole program)"),
            ));
        }
        self.loop_passes += 1;
        Ok(())
    }

    fn mismatch(&self, open: Option<Frame>, close: &str, at: usize) -> Box<Fault> {
        match open {
            Some(f) => fault(
                AlarmCode::ControlNesting,
                at,
                format!(
                    "{close} does not close {} (line {})",
                    f.opener(),
                    f.origin().0
                ),
            ),
            None => fault(
                AlarmCode::ControlNesting,
                at,
                format!("{close} without an opening statement"),
            ),
        }
    }

    /// Skips blocks up to the `$keyword` (one of `targets`) that matches at this nesting level;
    /// returns the keyword found. Leaves `pos` after that line. Used for false conditions and
    /// finished loops.
    fn skip_to(&mut self, targets: &[&str], at: usize) -> R<String> {
        let origin = (self.blk_line, self.blk_line_start);
        let mut depth = 0u32;
        while let Some((s, e)) = self.next_segment() {
            let Some(kw) = control::keyword_of(self.src, s, e) else {
                continue;
            };
            match kw.as_str() {
                "FOR" | "WHILE" | "IF" => depth += 1,
                "ENDFOR" | "ENDWHILE" | "ENDIF" if depth > 0 => depth -= 1,
                k if depth == 0 && targets.contains(&k) => {
                    self.last_skip = (s, e);
                    self.blk_number = control::block_number(self.src, s, e);
                    return Ok(kw);
                }
                _ => {}
            }
        }
        self.blk_line = origin.0;
        self.blk_line_start = origin.1;
        Err(fault(
            AlarmCode::ControlNesting,
            at,
            format!(
                "missing ${} for this statement",
                targets.last().copied().unwrap_or("END")
            ),
        ))
    }
}

/// Largest magnitude of any programmed value (mm, mm/min, s, ...): beyond it a value is a
/// typing error, and keeping values bounded keeps every later computation finite.
pub const MAX_VALUE: f64 = 1e9;

/// What a byte is to [`Interpreter::plain`]: 0..=5 the words X Y Z I J K (either case),
/// `G_WORD`, or one of the marks below; one table lookup instead of a chain of tests per byte.
const G_WORD: u8 = 6;
const BLANK: u8 = 7;
const LINE_FEED: u8 = 8;
const OTHER: u8 = 9;
static PLAIN_BYTE: [u8; 256] = {
    let mut t = [OTHER; 256];
    let words = *b"XYZIJKG";
    let mut k = 0;
    while k < words.len() {
        t[words[k] as usize] = k as u8;
        t[words[k].to_ascii_lowercase() as usize] = k as u8;
        k += 1;
    }
    t[b' ' as usize] = BLANK;
    t[b'\t' as usize] = BLANK;
    t[b'\r' as usize] = BLANK;
    t[b'\n' as usize] = LINE_FEED;
    t
};

/// A coordinate the control takes (bounded like the words, with room for offsets).
#[inline(always)]
fn in_range(x: f64) -> bool {
    x.is_finite() && x.abs() <= 1e9
}

fn checked(v: Val) -> R<Val> {
    if v.value.is_finite() && v.value.abs() <= MAX_VALUE {
        Ok(v)
    } else {
        Err(fault(
            AlarmCode::BadNumber,
            v.at,
            format!("value {} is out of range (±{MAX_VALUE})", v.value),
        ))
    }
}

fn push<T, const N: usize>(v: &mut heapless::Vec<T, N>, x: T, at: usize) -> R<()> {
    v.push(x).map_err(|_| {
        fault(
            AlarmCode::TooManyWords,
            at,
            format!("more than {N} words of this kind in one block"),
        )
    })
}

/// Word names for alarms, as statics: an array literal at the call would be built on the
/// stack for every word.
static AXIS_WORDS: [&str; 3] = ["X", "Y", "Z"];
static CENTRE_WORDS: [&str; 3] = ["I", "J", "K"];

/// `name` is `&'static` so that callers pass a constant, not a string built for every word.
#[inline(always)]
fn set_once(slot: &mut Option<Val>, v: Val, name: &'static str) -> R<()> {
    if slot.is_some() {
        return Err(fault(
            AlarmCode::AddressTwice,
            v.at,
            format!("{name} is programmed twice in this block"),
        ));
    }
    *slot = Some(v);
    Ok(())
}

/// Clears everything of `b` but its auxiliary words (collected already) and its modal state
/// (still the state before the block). Destructures, so that a new field is not forgotten.
fn reset(b: &mut Block, line: u32, col: u32, number: Option<BlockNo>) {
    let Block {
        line: b_line,
        col: b_col,
        number: b_number,
        motion,
        modal: _,
        words: _,
        trc,
        approach,
        exact_stop,
        dwell,
        stop,
        offset_changed,
        calculation,
        preprocess_stop,
    } = b;
    *b_line = line;
    *b_col = col;
    *b_number = number;
    *motion = None;
    *trc = None;
    *approach = None;
    *exact_stop = false;
    *dwell = None;
    *stop = None;
    *offset_changed = false;
    *calculation = false;
    *preprocess_stop = false;
}

/// A value that must be a non-negative integer (G, M, T, D numbers).
fn int_value(v: f64, at: impl Offset, what: &str) -> R<u32> {
    // `v as u32 as f64 == v` tests for a whole number without a call to `trunc`.
    if v >= 0.0 && v <= u32::MAX as f64 && v as u32 as f64 == v {
        Ok(v as u32)
    } else {
        Err(fault(
            AlarmCode::BadNumber,
            at,
            format!("{what} must be a whole number, not {v}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Every block and the alarm that ends a program, read with and without the plain path.
    fn both(
        src: &str,
        md: &MachineData,
        tools: &ToolTable,
    ) -> [Vec<Result<(Block, Pos), Alarm>>; 2] {
        let run = |mut it: Interpreter| {
            let mut got = Vec::new();
            loop {
                match it.next_block() {
                    Ok(Some(b)) => {
                        let b = b.clone();
                        got.push(Ok((b, it.position())));
                    }
                    Ok(None) => break,
                    Err(a) => {
                        got.push(Err(a));
                        break;
                    }
                }
            }
            got
        };
        [
            run(Interpreter::new("p", src, md, tools)),
            run(Interpreter::new("p", src, md, tools).without_plain_path()),
        ]
    }

    /// Words near the plain block's edges: what it takes, and what must send a block to the
    /// full path (other words, comments, doubled words, odd G codes, numbers out of range,
    /// expressions, lower case, no blank between words).
    fn word() -> impl Strategy<Value = String> {
        let num = prop_oneof![
            (-300i32..300, 0u32..10000).prop_map(|(i, f)| format!("{i}.{f:04}")),
            (-300i32..300).prop_map(|i| format!("{i}")),
            Just("2000000000".to_string()),
            Just("-.5".to_string()),
            Just("1.".to_string()),
            Just("".to_string()),
            Just("=5".to_string()),
            Just("0000000000000000012.5".to_string()),
        ];
        let letter = prop_oneof![
            8 => prop::sample::select(vec!["X", "Y", "Z", "I", "J", "K", "x", "y", "i"]),
            1 => prop::sample::select(vec!["F", "R", "M", "S", "D", "A", "U", "N", "P", "T"]),
        ];
        prop_oneof![
            8 => (letter, num).prop_map(|(l, n)| format!("{l}{n}")),
            3 => prop::sample::select(vec![0u32, 1, 2, 3, 1, 2, 3, 4, 17, 18, 19, 40, 41, 42, 90,
                91, 20, 21, 70, 71, 10, 12, 25, 26, 110, 141, 999, 1000])
                .prop_map(|g| format!("G{g}")),
            1 => prop::sample::select(vec!["G1.5", "g01", "(c)", ";c", "X[1+2]", "$IF", "@714"])
                .prop_map(str::to_string),
        ]
    }

    fn line() -> impl Strategy<Value = String> {
        (
            prop::collection::vec(
                (word(), prop::sample::select(vec![" ", "", "  ", "\t"])),
                0..6,
            ),
            prop::option::of(0u32..100),
            prop::sample::select(vec!["", " ", "\t", "/"]),
            prop::sample::select(vec!["", "\r", ";", " "]),
        )
            .prop_map(|(words, n, lead, tail)| {
                let mut l = lead.to_string();
                if let Some(n) = n {
                    l.push_str(&format!("N{n} "));
                }
                for (w, sep) in words {
                    l.push_str(&w);
                    l.push_str(sep);
                }
                l.push_str(tail);
                l
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]
        /// The plain path is a shortcut, not a second interpreter: blocks, positions and
        /// alarms are the same with it and without it, in every dialect.
        #[test]
        fn plain_path_reads_as_the_word_loop(
            lines in prop::collection::vec(line(), 1..12),
            header in prop::sample::select(vec!["G1 F500", "G90 F100 G17", "G91 G1 F100", "G18 F10", "G0", "G70 F1", "G2 F7", "G12 F100", "G26 X100 Y100 Z100 F9"]),
            dialect in prop::sample::select(vec!["siemens-840c", "isg", "fanuc", "siemens-808d"]),
            diameter in any::<bool>(),
        ) {
            let mut set = vec![format!("dialect={dialect}")];
            if diameter {
                set.push("program.diameter_programming=true".into());
            }
            let md = MachineData::load(None, &set).unwrap();
            let tools = ToolTable::builtin();
            let src = format!("{header}\n{}\nM30\n", lines.join("\n"));
            let [fast, full] = both(&src, &md, &tools);
            prop_assert_eq!(fast, full, "{}", src);
        }
    }

    #[test]
    fn plain_blocks_take_the_plain_path() {
        // Guards the test above against a plain path that never runs: the serpentine's
        // blocks are all plain, and reading them that way gives the same blocks.
        let md = MachineData::default();
        let tools = ToolTable::builtin();
        let src = "G1 F100\nG1 X10 Y0\nG2 X10 Y-20 I0 J-10\ng1 x0 y-20\nG3 X0 Y-40 I0.0 J-10.0\n";
        let mut it = Interpreter::new("p", src, &md, &tools);
        it.next_block().unwrap();
        let mut plain = 0;
        for _ in 0..4 {
            let mut probe = it.clone();
            let (start, end) = probe.next_segment().unwrap();
            if probe
                .plain(Cursor::new(probe.src, start, end), start)
                .is_some()
            {
                plain += 1;
            }
            let mut full = it.clone().without_plain_path();
            let b = full.next_block().unwrap().unwrap().clone();
            assert_eq!(it.next_block().unwrap().unwrap(), &b);
        }
        assert_eq!(plain, 4);
    }
}
