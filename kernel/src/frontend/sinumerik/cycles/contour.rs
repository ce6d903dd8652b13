//! The contour a SINUMERIK turning cycle machines (Cycles, "Stock removal – CYCLE95":
//! parameter NPP): the name of a subprogram (`"SHAFT"`: the file SHAFT.SPF, found as a call
//! finds it), or a section of the calling program between two labels (`"START:END"`, both
//! blocks included).
//!
//! The contour's blocks are read by an interpreter of their own, started where the cycle
//! is called with the caller's modal state, position, frames and variables: every word of
//! the language acts as in a programmed block (DIAMON, G90/G91, CR=, I K, AP= RP=, the
//! corners CHF= CHR= RND=, expressions), and the moves it makes become the contour's
//! elements. Nothing of it reaches the machine; a fault in it names its own file and line.

use super::super::super::block::*;
use super::super::super::build::{TurningElement as Element, EPS};
use super::super::super::calls::Mark;
use super::super::super::fault::{fault, Fault, R};
use super::super::super::interpreter::Interpreter;
use super::super::structure::Structure;
use crate::alarm::{Alarm, AlarmCode};

/// More elements than this are refused (a bound on a contour that loops).
const MAX_ELEMENTS: usize = 2000;

/// The text of a contour: its file's name and text (a section ends with the end label's
/// line), and where it starts.
struct ContourText<'a> {
    name: &'a str,
    src: &'a str,
    start: Mark,
}

impl<'a> Interpreter<'a> {
    /// The elements of contour `npp` (written at `at`), from the tool's position: the first
    /// is the move to the contour's start point. The contour is read with `feed` in force
    /// where no F is (its own F words move nothing: the cycle has its feeds).
    pub(super) fn cycle_contour(
        &mut self,
        npp: &str,
        at: usize,
        new: &ModalState,
        feed: f64,
    ) -> R<Vec<Element>> {
        if self.sinumerik.reading_contour {
            let m = "a contour cannot call a turning cycle itself";
            return Err(fault(AlarmCode::CycleContour, at, m));
        }
        let text = self.contour_text(npp, at)?;
        let (md, tools) = (self.md, self.tools);
        let mut sub = Interpreter::new(text.name, text.src, md, tools);
        (sub.pos, sub.line, sub.line_start) = text.start;
        sub.cur = self.cur;
        sub.cur_add = self.cur_add;
        sub.coords = self.coords.clone();
        sub.sinumerik.store = self.sinumerik.store.clone();
        sub.sinumerik.reading_contour = true;
        sub.block.modal = *new;
        if sub.block.modal.feed <= 0.0 {
            sub.block.modal.feed = feed;
        }
        let mut elements: Vec<Element> = Vec::new();
        // Bounded: the interpreter's loops count against its own pass budget, and the
        // elements against MAX_ELEMENTS.
        loop {
            let b = match sub.next_block() {
                Ok(Some(b)) => b.clone(),
                Ok(None) => break,
                Err(a) => return Err(self.foreign(&text, a)),
            };
            if let Some(e) =
                contour_element(&b).map_err(|m| self.foreign(&text, alarm_at(&b, m)))?
            {
                if elements.len() >= MAX_ELEMENTS {
                    let m = format!("more than {MAX_ELEMENTS} contour elements");
                    return Err(self.foreign(&text, alarm_at(&b, (AlarmCode::CycleContour, m))));
                }
                elements.push(e);
            }
            if b.stop.is_some_and(|s| s.ends_program()) {
                break;
            }
        }
        if elements.len() < 2 {
            let m = format!("contour {npp} has fewer than two moves: a start point and at least one element are needed");
            return Err(fault(AlarmCode::CycleContour, at, m));
        }
        Ok(elements)
    }

    /// The text NPP names: a program file, or the labelled section of the running program.
    fn contour_text(&self, npp: &str, at: usize) -> R<ContourText<'a>> {
        let npp = npp.trim().to_ascii_uppercase();
        if npp.is_empty() {
            let m = "no contour: NPP names the contour's subprogram or its labels START:END";
            return Err(fault(AlarmCode::CycleContour, at, m));
        }
        let Some((first, last)) = npp.split_once(':') else {
            return self.contour_file(&npp, at);
        };
        let src: &'a [u8] = self.src;
        let name: &'a str = self.name;
        let text = std::str::from_utf8(src)
            .map_err(|_| fault(AlarmCode::Syntax, at, "the program text is not UTF-8"))?;
        let s = Structure::of(src, 0, src.len(), 1).map_err(|e| e.0)?;
        let find = |label: &str| {
            s.labels(label).first().copied().ok_or_else(|| {
                let m = format!("contour label {label} not found in the program");
                fault(AlarmCode::JumpTarget, at, m)
            })
        };
        let (start, end) = (find(first)?, find(last)?);
        if end.0 < start.0 {
            let m = format!("the contour's end label {last} stands before its start label {first}");
            return Err(fault(AlarmCode::CycleContour, at, m));
        }
        let line_end = super::super::super::lexer::find_byte(src, end.0, [b'\n']);
        Ok(ContourText {
            name,
            src: text.get(..line_end).unwrap_or(text),
            start,
        })
    }

    /// The program file NAME.SPF (else NAME.MPF) of the program library.
    fn contour_file(&self, npp: &str, at: usize) -> R<ContourText<'a>> {
        let library: &'a crate::programs::ProgramLibrary = &self.md.programs;
        let stem = npp.strip_prefix("_N_").unwrap_or(npp);
        let stem = stem.strip_suffix("_SPF").unwrap_or(stem);
        let Some((_, p)) = library.find_named(stem, None) else {
            let m = format!("contour program {stem} not found: no {stem}.SPF or {stem}.MPF in the program's folder or the search path");
            return Err(fault(AlarmCode::MissingProgram, at, m));
        };
        Ok(ContourText {
            name: p.name.as_str(),
            src: super::super::super::calls::file_text(p, at)?,
            start: (0, 1, 0),
        })
    }

    /// An alarm of the contour's own text as a fault of this interpreter: the alarm names
    /// the contour's file, line and column (the interpreter stops with it).
    fn foreign(&mut self, text: &ContourText<'a>, a: Alarm) -> Box<Fault> {
        let src = text.src.as_bytes();
        let line_start = line_start(src, a.line);
        let at = src[line_start..]
            .iter()
            .enumerate()
            .filter(|(_, &c)| (c & 0xC0) != 0x80)
            .nth(a.col.saturating_sub(1) as usize)
            .map_or(src.len(), |(k, _)| line_start + k);
        self.name = text.name;
        self.src = src;
        (self.blk_line, self.blk_line_start, self.blk_number) = (a.line, line_start, None);
        fault(a.code, at, a.message)
    }
}

/// Where line `line` (1 …) of `src` starts.
fn line_start(src: &[u8], line: u32) -> usize {
    if line <= 1 {
        return 0;
    }
    src.iter()
        .enumerate()
        .filter(|(_, &c)| c == b'\n')
        .nth(line as usize - 2)
        .map_or(src.len(), |(k, _)| k + 1)
}

/// An alarm at block `b`'s first character.
fn alarm_at(b: &Block, (code, message): (AlarmCode, String)) -> Alarm {
    Alarm {
        code,
        program: String::new(),
        line: b.line,
        col: b.col,
        block: None,
        message,
    }
}

/// The element block `b` adds to the contour (none for a block that does not move).
fn contour_element(b: &Block) -> Result<Option<Element>, (AlarmCode, String)> {
    let refuse = |what: &str| {
        Err((
            AlarmCode::NotSupported,
            format!("{what} in a turning cycle's contour is not supported by softnc"),
        ))
    };
    if b.modal.trc != TrcSide::Off {
        return refuse("tool nose radius compensation");
    }
    if b.dwell.is_some() {
        return refuse("a dwell");
    }
    if b.axes.is_some() {
        return refuse("a move of an additional axis");
    }
    if b.stop.is_some_and(|s| !s.ends_program()) {
        return refuse("a program stop");
    }
    let Some(m) = b.motion else { return Ok(None) };
    if m.plane != Plane::ZX || (m.end[1] - m.start[1]).abs() > EPS {
        return refuse("a move outside the Z-X plane");
    }
    let mode = match m.kind {
        MotionKind::Rapid => MotionMode::Rapid,
        MotionKind::Linear => MotionMode::Linear,
        MotionKind::ArcCw => MotionMode::ArcCw,
        MotionKind::ArcCcw => MotionMode::ArcCcw,
    };
    let still = (0..3).all(|i| (m.end[i] - m.start[i]).abs() <= EPS);
    if still && !m.kind.is_arc() {
        return Ok(None);
    }
    Ok(Some(Element {
        to: m.end,
        mode,
        centre: m.center,
        feed: None,
        speed: None,
    }))
}
