//! The control structures and jump labels of a program text, read line by line in text order
//! as far as the program needs them, and to its end when it ends.
//!
//! Job planning ("Control structures") says the control matches IF/ELSE/ENDIF, WHILE/ENDWHILE,
//! FOR/ENDFOR, REPEAT/UNTIL and LOOP/ENDLOOP as it interprets. softnc reads every line of the
//! text once, in order: the lines the interpreter reads itself as plain blocks are taken as
//! read (they hold no structure word and no label); a statement's link or a forward jump's
//! label reads on until it is known; the program's end reads the rest, so a structure left
//! open behind an M30 is an alarm too. Running a structure is then a jump to a known place
//! (nothing to unwind when a GOTO leaves a loop). A block with a structure word cannot be
//! skipped and carries no label (Job planning, "Control structures").

pub use super::super::block_text::Numbered;
use super::super::fault::{fault, Fault};
use super::statements::Keyword;
use crate::alarm::AlarmCode;
use std::collections::HashMap;

/// A place in the text: (byte offset, line number, line start) of a block's start.
pub use super::super::calls::Mark;

/// Where a structure word sends the interpreter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// IF: a false condition goes on after the ELSE, or after the ENDIF.
    If { otherwise: Mark },
    /// ELSE reached at the end of the true branch: on after the ENDIF.
    Else { after_end: Mark },
    /// WHILE and FOR: a loop that does not run goes on after its end.
    Head { after_end: Mark },
    /// ENDWHILE: back to the WHILE, which tests again.
    EndWhile { head: Mark },
    /// ENDFOR: its FOR block (for the variable and the end value) and the body's start.
    EndFor { head: Mark, body: Mark },
    /// UNTIL and ENDLOOP: back to the body's start.
    Back { body: Mark },
}

/// The structures and labels of one program text.
#[derive(Clone, Debug, Default)]
pub struct Structure {
    links: HashMap<usize, Link>,
    /// Label name → the blocks that carry it, in text order.
    labels: HashMap<Box<str>, Vec<Mark>>,
    /// The program's text: its first block, its end. Block numbers are looked for in it
    /// when a jump names one (not indexed: a program numbers every block, and the index
    /// would grow with its length).
    text: (Mark, usize),
    /// Its PROC line, if its first block is one.
    pub proc: Option<super::procs::ProcDecl>,
    /// The matching while lines are still to read; `None` once the whole text is read.
    reading: Option<Reading>,
}

/// The matching state between two reads: the structures open and whether the first block
/// (a PROC line) is still to come.
#[derive(Clone, Debug, Default)]
struct Reading {
    open: Vec<Open>,
    first: bool,
}

/// An opened structure while matching: its word, its block, its body's start, and for IF
/// its ELSE block and what follows it.
#[derive(Clone, Debug)]
struct Open {
    word: Keyword,
    at: Mark,
    body: Mark,
    col: usize,
    otherwise: Option<(Mark, Mark)>,
}

/// A fault of the structure check, with the block it belongs to (line, line start).
pub type Located = (Box<Fault>, u32, usize);

impl Structure {
    pub fn link(&self, block: usize) -> Option<Link> {
        self.links.get(&block).copied()
    }

    pub fn labels(&self, name: &str) -> &[Mark] {
        self.labels.get(name).map_or(&[], Vec::as_slice)
    }

    /// The blocks numbered `n` (`N10` or the main block `:10`) around the block at `here`.
    pub fn numbered(&self, src: &[u8], n: u32, here: usize) -> Numbered {
        let (from, end) = self.text;
        super::super::block_text::numbered(src, from, end, n, here, true)
    }

    /// The structure of `src[start..end]` (first line number `line`), nothing read yet.
    pub fn new(start: usize, end: usize, line: u32) -> Structure {
        Structure {
            text: ((start, line, start), end),
            reading: Some(Reading {
                open: Vec::new(),
                first: true,
            }),
            ..Structure::default()
        }
    }

    /// The whole of `src[start..end]` read (a called program's text, when it is first
    /// called).
    pub fn of(src: &[u8], start: usize, end: usize, line: u32) -> Result<Structure, Located> {
        let mut s = Structure::new(start, end, line);
        s.finish(src, (start, line, start))?;
        Ok(s)
    }

    /// Where the text ends.
    pub fn end(&self) -> usize {
        self.text.1
    }

    /// Whether the whole text is read.
    pub fn complete(&self) -> bool {
        self.reading.is_none()
    }

    /// Reads the lines from `at` (a line's start) whose start is at most `until`; returns
    /// where reading stopped (the text's end at the most).
    pub fn read(&mut self, src: &[u8], mut at: Mark, until: usize) -> Result<Mark, Located> {
        let end = self.text.1;
        let Some(mut r) = self.reading.take() else {
            return Ok(at);
        };
        while at.0 < end && at.0 <= until {
            // Line ends by SIMD search.
            let stop = memchr::memchr(b'\n', &src[at.0..end]).map_or(end, |k| at.0 + k);
            let next: Mark = (stop + 1, at.1 + 1, stop + 1);
            let line = self.line(src, &mut r, at, stop, next);
            if line.is_err() {
                self.reading = Some(r);
                return line.map(|()| at);
            }
            at = next;
        }
        self.reading = Some(r);
        Ok(at)
    }

    /// The line `src[at..stop]` into the matching.
    fn line(
        &mut self,
        src: &[u8],
        r: &mut Reading,
        at: Mark,
        stop: usize,
        next: Mark,
    ) -> Result<(), Located> {
        if r.first && holds_block(&src[at.0..stop]) {
            r.first = false;
            self.proc = proc_line(src, at, stop)?;
            if self.proc.is_some() {
                return Ok(());
            }
        }
        if may_hold_name(&src[at.0..stop]) {
            if let Some((word, col)) = self.block(src, at, stop)? {
                self.structure_word(&mut r.open, word, at, next, col)?;
            }
        }
        Ok(())
    }

    /// Reads from `at` until the first block (a PROC line) is read; returns where it stopped.
    pub fn read_first_block(&mut self, src: &[u8], mut at: Mark) -> Result<Mark, Located> {
        while self.reading.as_ref().is_some_and(|r| r.first) && at.0 < self.text.1 {
            at = self.read(src, at, at.0)?;
        }
        Ok(at)
    }

    /// Reads the rest of the text from `at`: a structure still open is a fault at its
    /// opening statement.
    pub fn finish(&mut self, src: &[u8], at: Mark) -> Result<(), Located> {
        self.read(src, at, usize::MAX)?;
        let Some(mut r) = self.reading.take() else {
            return Ok(());
        };
        match r.open.pop() {
            Some(o) => Err((
                fault(
                    AlarmCode::ControlNesting,
                    o.col,
                    format!("{} is not closed by {}", o.word.text(), closer(o.word)),
                ),
                o.at.1,
                o.at.2,
            )),
            None => Ok(()),
        }
    }

    /// One block: its number and label on record; its structure word, if it has one.
    fn block(
        &mut self,
        src: &[u8],
        at: Mark,
        stop: usize,
    ) -> Result<Option<(Keyword, usize)>, Located> {
        let mut c = super::super::lexer::Cursor::new(src, at.0, stop);
        c.skip_blanks();
        let skipped = c.peek() == Some(b'/');
        if skipped {
            c.i += 1;
            while matches!(c.peek(), Some(b'0'..=b'9')) {
                c.i += 1;
            }
            c.skip_blanks();
        }
        block_number(&mut c);
        // A label or a structure word starts with two letters (or `_`): most blocks
        // (`G1 X…`) are done here.
        let name_char =
            |k: usize| matches!(c.peek_at(k), Some(b) if b.is_ascii_alphabetic() || b == b'_');
        if !(name_char(0) && name_char(1)) {
            return Ok(None);
        }
        let label_at = c.i;
        let label = label(&mut c);
        let col = c.i;
        if Keyword::at(&c) == Some(Keyword::Proc) {
            let message = "PROC must be the program's first block, without a label or skip mark";
            return Err((fault(AlarmCode::Syntax, col, message), at.1, at.2));
        }
        let Some(word) = Keyword::at(&c).filter(|w| w.is_structure() && !is_short_if(*w, &c))
        else {
            if let Some(name) = label {
                let marks = self.labels.entry(name.into()).or_default();
                if let Some(first) = marks.first() {
                    // Names are unique in a program (Fundamentals, "Names").
                    let message = format!("label defined twice (first in line {})", first.1);
                    return Err((fault(AlarmCode::Syntax, label_at, message), at.1, at.2));
                }
                marks.push(at);
            }
            return Ok(None);
        };
        let refuse =
            |what: &str| Err((fault(AlarmCode::Syntax, col, what.to_string()), at.1, at.2));
        if skipped {
            return refuse("a block with a control structure cannot be skipped (/)");
        }
        if label.is_some() {
            return refuse("a block with a control structure carries no label");
        }
        Ok(Some((word, col)))
    }

    /// Structure word `word` in the block at `at` (the next block at `next`).
    fn structure_word(
        &mut self,
        open: &mut Vec<Open>,
        word: Keyword,
        at: Mark,
        next: Mark,
        col: usize,
    ) -> Result<(), Located> {
        let opener = match word {
            Keyword::Else | Keyword::EndIf => Keyword::If,
            Keyword::EndWhile => Keyword::While,
            Keyword::EndFor => Keyword::For,
            Keyword::Until => Keyword::Repeat,
            Keyword::EndLoop => Keyword::Loop,
            _ => {
                open.push(Open {
                    word,
                    at,
                    body: next,
                    col,
                    otherwise: None,
                });
                return Ok(());
            }
        };
        let top = open
            .last_mut()
            .filter(|o| o.word == opener && !(word == Keyword::Else && o.otherwise.is_some()));
        let Some(o) = top else {
            let message = match open.last() {
                Some(o) => format!(
                    "{} does not close {} (line {})",
                    word.text(),
                    o.word.text(),
                    o.at.1
                ),
                None => format!("{} without {}", word.text(), opener.text()),
            };
            return Err((fault(AlarmCode::ControlNesting, col, message), at.1, at.2));
        };
        if word == Keyword::Else {
            o.otherwise = Some((at, next));
            return Ok(());
        }
        let Some(o) = open.pop() else { return Ok(()) };
        match word {
            Keyword::EndIf => {
                let otherwise = o.otherwise.map_or(next, |(_, after_else)| after_else);
                self.links.insert(o.at.0, Link::If { otherwise });
                if let Some((else_at, _)) = o.otherwise {
                    self.links.insert(else_at.0, Link::Else { after_end: next });
                }
            }
            Keyword::EndWhile => {
                self.links.insert(o.at.0, Link::Head { after_end: next });
                self.links.insert(at.0, Link::EndWhile { head: o.at });
            }
            Keyword::EndFor => {
                self.links.insert(o.at.0, Link::Head { after_end: next });
                self.links.insert(
                    at.0,
                    Link::EndFor {
                        head: o.at,
                        body: o.body,
                    },
                );
            }
            _ => {
                self.links.insert(at.0, Link::Back { body: o.body });
            }
        }
        Ok(())
    }
}

fn closer(w: Keyword) -> &'static str {
    match w {
        Keyword::If => "ENDIF",
        Keyword::While => "ENDWHILE",
        Keyword::For => "ENDFOR",
        Keyword::Repeat => "UNTIL",
        _ => "ENDLOOP",
    }
}

/// Whether a block's text may hold a label or a structure word: after blanks, a skip mark,
/// a block number, or two name characters. Most blocks (`G1 X…`) are told by two bytes.
#[inline]
fn may_hold_name(b: &[u8]) -> bool {
    let i = b
        .iter()
        .position(|&c| c != b' ' && c != b'\t')
        .unwrap_or(b.len());
    let name = |c: Option<&u8>| c.is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_');
    match b.get(i) {
        Some(b'/' | b':' | b'N' | b'n') => true,
        c => name(c) && name(b.get(i + 1)),
    }
}

/// Whether a line holds a block: not blank, no comment alone, no `%` header.
fn holds_block(b: &[u8]) -> bool {
    let first = b.iter().find(|&&c| !matches!(c, b' ' | b'\t' | b'\r'));
    !matches!(first, None | Some(b';' | b'%'))
}

/// The program's first block, when it is a PROC line (after its block number, if any).
fn proc_line(src: &[u8], at: Mark, stop: usize) -> Result<Option<super::procs::ProcDecl>, Located> {
    let mut c = super::super::lexer::Cursor::new(src, at.0, stop);
    c.skip_blanks();
    block_number(&mut c);
    if Keyword::at(&c) != Some(Keyword::Proc) {
        return Ok(None);
    }
    c.i += Keyword::Proc.text().len();
    match super::procs::read(&mut c) {
        Ok(decl) => Ok(Some(super::procs::ProcDecl {
            line: (at.1, at.2),
            ..decl
        })),
        Err(f) => Err((f, at.1, at.2)),
    }
}

/// `N10` or `:10` at the cursor: the number.
pub fn block_number(c: &mut super::super::lexer::Cursor) -> Option<u32> {
    if !matches!(c.letter(), Some(b'N')) && c.peek() != Some(b':') {
        return None;
    }
    let digits = c.i + 1;
    let mut k = digits;
    while k < c.end && c.b[k].is_ascii_digit() {
        k += 1;
    }
    if k == digits || k - digits > 9 {
        return None;
    }
    let n = std::str::from_utf8(&c.b[digits..k]).ok()?.parse().ok()?;
    c.i = k;
    c.skip_blanks();
    Some(n)
}

/// A jump label `NAME:` at the cursor (the first two characters letters or `_`): its name.
pub fn label(c: &mut super::super::lexer::Cursor) -> Option<String> {
    let first_two =
        |k: usize| matches!(c.peek_at(k), Some(b) if b.is_ascii_alphabetic() || b == b'_');
    if !(first_two(0) && first_two(1)) {
        return None;
    }
    let mut probe = *c;
    let span = super::expr::identifier_span(&mut probe);
    if probe.peek() != Some(b':') || span.first() == Some(&b'$') {
        return None;
    }
    let name = String::from_utf8_lossy(span).to_ascii_uppercase();
    probe.i += 1;
    probe.skip_blanks();
    *c = probe;
    Some(name)
}

/// `IF cond GOTOF label`: an IF that jumps, with no ENDIF (Job planning, "Program jumps").
fn is_short_if(w: Keyword, c: &super::super::lexer::Cursor) -> bool {
    w == Keyword::If && super::statements::jump_in(c).is_some()
}
