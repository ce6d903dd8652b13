//! A program's text, block by block: where a block's text ends (the line feed; on Fanuc also
//! `;` outside a comment), what stands before its words (`%` lines, the block-skip mark `/`,
//! Fanuc `O` program numbers) and its block number `N` (docs/dialects.md, "Common rules").

use super::block::BlockNo;
use super::calls::Mark;
use super::fault::{fault, R};
use super::interpreter::Interpreter;
use super::lexer::{find_byte, Cursor};
use crate::alarm::AlarmCode;
use crate::dialect::Semicolon;

impl Interpreter<'_> {
    /// The next block's text `(start, end)`; advances past its terminator and records the
    /// block's line for alarms.
    pub(super) fn next_segment(&mut self) -> Option<(usize, usize)> {
        if self.pos >= self.src.len() {
            return None;
        }
        let start = self.pos;
        self.blk_line = self.line;
        self.blk_line_start = self.line_start;
        let b = self.src;
        let i = if self.d.semicolon == Semicolon::EndOfBlock {
            match fanuc_block_end(b, start) {
                BlockEnd::Semicolon(i) => {
                    self.pos = i + 1;
                    return Some((start, i));
                }
                BlockEnd::Line(i) => i,
            }
        } else {
            find_byte(b, start, [b'\n'])
        };
        self.pos = (i + 1).min(b.len().max(i + 1));
        self.line += 1;
        self.line_start = self.pos;
        Some((start, i))
    }

    /// Skips what stands before a block's words: blanks and a block-skip mark. False if the
    /// text is no block: empty, a `%` line, a block left out by block skip, a Fanuc `O` line.
    #[inline]
    pub(super) fn block_start(&mut self, c: &mut Cursor) -> bool {
        c.skip_blanks();
        // Program header: `%name`, `%` alone (Fanuc tape start/end).
        if matches!(c.peek(), None | Some(b'%')) {
            return false;
        }
        if skip_mark(c) {
            if self.md.program.block_skip {
                return false;
            }
            c.skip_blanks();
        }
        // Fanuc program number line: the program's own, or the next program's (its end).
        if self.d.o_numbers && c.letter() == Some(b'O') && matches!(c.peek_at(1), Some(b'0'..=b'9'))
        {
            let line_start = self.blk_line_start;
            self.o_line(c, line_start);
            return false;
        }
        true
    }
}

/// Where a Fanuc block ends.
pub(super) enum BlockEnd {
    /// At a `;` (outside a comment), which ends the block but not the line.
    Semicolon(usize),
    /// At the line feed or the end of the text.
    Line(usize),
}

/// Fanuc: `;` ends the block, except inside a comment.
pub(super) fn fanuc_block_end(b: &[u8], start: usize) -> BlockEnd {
    let mut depth = 0u32;
    let mut i = start;
    loop {
        i = if depth == 0 {
            find_byte(b, i, [b'\n', b'(', b';'])
        } else {
            find_byte(b, i, [b'\n', b'(', b')'])
        };
        match b.get(i) {
            None | Some(b'\n') => return BlockEnd::Line(i),
            Some(b'(') => depth += 1,
            // only looked for inside a comment, so depth > 0
            Some(b')') => depth -= 1,
            // `;` outside a comment
            Some(_) => return BlockEnd::Semicolon(i),
        }
        i += 1;
    }
}

/// Skips a block-skip mark (`/`, `/0` … `/9`) at the cursor; true if there was one.
fn skip_mark(c: &mut Cursor) -> bool {
    if c.peek() != Some(b'/') {
        return false;
    }
    c.i += 1;
    if matches!(c.peek(), Some(b'0'..=b'9')) {
        c.i += 1;
    }
    true
}

/// Skips blanks and a block-skip mark at the start of a block.
fn skip_block_skip(c: &mut Cursor) {
    c.skip_blanks();
    if skip_mark(c) {
        c.skip_blanks();
    }
}

/// Skips `/`, the block number and blanks at the start of a block.
pub fn skip_prefix(c: &mut Cursor) {
    skip_block_skip(c);
    if c.letter() == Some(b'N') {
        c.i += 1;
        while matches!(c.peek(), Some(b'0'..=b'9')) {
            c.i += 1;
        }
        c.skip_blanks();
    }
}

/// Reads `N<digits>` at the cursor, if there is an N; a fault points at the N.
#[inline]
pub fn read_block_number(c: &mut Cursor) -> R<Option<BlockNo>> {
    // A name that starts with N (SINUMERIK `NORM`, a variable) is no block number.
    let name = matches!(c.peek_at(1), Some(b) if b.is_ascii_alphabetic() || b == b'_');
    if c.letter() != Some(b'N') || name {
        return Ok(None);
    }
    number_after(c)
}

/// Reads `N<digits>`, or `:<digits>` (a main block, 880/840C), at the cursor.
pub fn read_main_or_block_number(c: &mut Cursor) -> R<Option<BlockNo>> {
    if c.peek() == Some(b':') {
        return number_after(c);
    }
    read_block_number(c)
}

/// The digits after the `N` or `:` at the cursor.
#[inline]
fn number_after(c: &mut Cursor) -> R<Option<BlockNo>> {
    let at = c.i;
    c.i += 1;
    let ds = c.i;
    let mut v: u64 = 0;
    while let Some(ch @ b'0'..=b'9') = c.peek() {
        v = v * 10 + (ch - b'0') as u64;
        if v > u32::MAX as u64 {
            return Err(fault(AlarmCode::BadNumber, at, "block number too large"));
        }
        c.i += 1;
    }
    if c.i == ds {
        return Err(fault(
            AlarmCode::Syntax,
            at,
            format!(
                "{} must be followed by the block number",
                (c.b[at] as char).to_ascii_uppercase()
            ),
        ));
    }
    // At least one digit was read (checked above).
    let digits =
        std::num::NonZeroU8::new((c.i - ds).min(10) as u8).unwrap_or(std::num::NonZeroU8::MIN);
    Ok(Some(BlockNo {
        value: v as u32,
        digits,
    }))
}

/// The N number at the start of a block's text, if any.
pub fn block_number(src: &[u8], start: usize, end: usize) -> Option<BlockNo> {
    let mut c = Cursor::new(src, start, end);
    skip_block_skip(&mut c);
    read_block_number(&mut c).ok().flatten()
}

/// The number at the start of a block's text, `N` or (`colon`: 880/840C main block) `:`.
pub fn main_or_block_number(src: &[u8], start: usize, end: usize, colon: bool) -> Option<BlockNo> {
    let mut c = Cursor::new(src, start, end);
    skip_block_skip(&mut c);
    if colon {
        read_main_or_block_number(&mut c).ok().flatten()
    } else {
        read_block_number(&mut c).ok().flatten()
    }
}

/// The blocks numbered n around a place: the first from where the search began, the last at
/// or before the place and the first after it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Numbered {
    pub first: Option<Mark>,
    pub backward: Option<Mark>,
    pub forward: Option<Mark>,
}

/// The blocks numbered `n` (`colon`: a `:` main block's number too) in the lines of
/// `src[from..end]` around the block at `here`; the scan stops at the first after `here`.
/// Block numbers are looked for as a jump needs them, not indexed: a program numbers every
/// block, and an index would grow with its length.
pub fn numbered(src: &[u8], from: Mark, end: usize, n: u32, here: usize, colon: bool) -> Numbered {
    let mut at = from;
    let mut found = Numbered::default();
    while at.0 < end && found.forward.is_none() {
        let stop = memchr::memchr(b'\n', &src[at.0..end]).map_or(end, |k| at.0 + k);
        if main_or_block_number(src, at.0, stop, colon).is_some_and(|b| b.value == n) {
            found.first.get_or_insert(at);
            if at.0 <= here {
                found.backward = Some(at);
            } else {
                found.forward = Some(at);
            }
        }
        at = (stop + 1, at.1 + 1, stop + 1);
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn number(text: &str) -> R<Option<BlockNo>> {
        read_block_number(&mut Cursor::new(text.as_bytes(), 0, text.len()))
    }

    #[test]
    fn block_numbers_keep_their_digits() {
        let n = number("N05 X1").unwrap().unwrap();
        assert_eq!((n.value, n.to_string()), (5, "N05".to_string()));
        assert_eq!(number("X1").unwrap(), None);
        assert_eq!(number("N X1").unwrap_err().code, AlarmCode::Syntax);
        assert_eq!(number("NORM X1").unwrap(), None);
        // u32::MAX + 1
        assert_eq!(
            number("N4294967296").unwrap_err().code,
            AlarmCode::BadNumber
        );
        let text = b"/1 N20 G1";
        assert_eq!(block_number(text, 0, text.len()).unwrap().value, 20);
    }

    #[test]
    fn fanuc_blocks_end_at_a_semicolon_outside_comments() {
        let b = b"G1 (a;b) X1; Y2\n";
        assert!(matches!(fanuc_block_end(b, 0), BlockEnd::Semicolon(11)));
        assert!(matches!(fanuc_block_end(b, 12), BlockEnd::Line(15)));
    }
}
