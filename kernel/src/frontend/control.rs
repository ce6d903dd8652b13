//! ISG control structures (seed 002, TF5200): `$FOR var = start, end, step … $ENDFOR`,
//! `$IF … [$ELSEIF …] [$ELSE] $ENDIF`, `$WHILE … $ENDWHILE`. One statement per block, only
//! the block number and `/` before it. The end value of `$FOR` is inclusive; a condition is
//! true when its absolute value is at least 0.5.

use super::block::BlockNo;
use super::expr;
use super::fault::{fault, R};
use super::lexer::Cursor;
use super::variables::Variables;
use crate::alarm::AlarmCode;

/// A statement as read. Byte offsets point at the `$`.
#[derive(Debug)]
pub enum ControlStmt {
    For {
        var: String,
        var_at: usize,
        start: f64,
        end: f64,
        step: f64,
        at: usize,
    },
    EndFor {
        at: usize,
    },
    While {
        cond: f64,
        cond_range: (usize, usize),
        at: usize,
    },
    EndWhile {
        at: usize,
    },
    If {
        cond: f64,
        at: usize,
    },
    /// The condition is evaluated only when the branch is reached.
    ElseIf {
        at: usize,
    },
    Else {
        at: usize,
    },
    EndIf {
        at: usize,
    },
}

/// Where to jump back to: (byte offset, line number, line start).
pub type Mark = (usize, u32, usize);

/// An open control structure. `origin` is (line, line start, byte offset) of its opening.
#[derive(Clone, Debug)]
pub enum Frame {
    For {
        var: String,
        end: f64,
        step: f64,
        body: Mark,
        origin: (u32, usize, usize),
    },
    While {
        cond: (usize, usize),
        body: Mark,
        origin: (u32, usize, usize),
    },
    If {
        origin: (u32, usize, usize),
    },
}

impl Frame {
    pub fn origin(&self) -> (u32, usize, usize) {
        match self {
            Frame::For { origin, .. } | Frame::While { origin, .. } | Frame::If { origin } => {
                *origin
            }
        }
    }
    pub fn opener(&self) -> &'static str {
        match self {
            Frame::For { .. } => "$FOR",
            Frame::While { .. } => "$WHILE",
            Frame::If { .. } => "$IF",
        }
    }
    pub fn closer(&self) -> &'static str {
        match self {
            Frame::For { .. } => "$ENDFOR",
            Frame::While { .. } => "$ENDWHILE",
            Frame::If { .. } => "$ENDIF",
        }
    }
}

/// Whether a `$FOR` loop runs another pass with the variable at `v`. A tolerance of 1e-9 of a
/// step keeps decimal steps (0.1) from losing their last pass to rounding.
pub fn for_continues(v: f64, end: f64, step: f64) -> bool {
    let eps = 1e-9 * step.abs();
    if step > 0.0 {
        v <= end + eps
    } else {
        v >= end - eps
    }
}

fn syntax(at: usize, m: impl Into<String>) -> Box<super::fault::Fault> {
    fault(AlarmCode::Syntax, at, m)
}

fn keyword(c: &mut Cursor) -> String {
    let start = c.i;
    while matches!(c.peek(), Some(ch) if ch.is_ascii_alphabetic()) {
        c.i += 1;
    }
    String::from_utf8_lossy(&c.b[start..c.i]).to_ascii_uppercase()
}

/// After a statement only a comment may follow.
fn end_of_statement(c: &mut Cursor) -> R<()> {
    loop {
        c.skip_blanks();
        match c.peek() {
            None | Some(b';') => return Ok(()),
            Some(b'(') => {
                if !c.skip_comment() {
                    return Ok(()); // ISG: an unclosed `(` comments out the rest
                }
            }
            Some(_) => {
                return Err(syntax(
                    c.i,
                    "a control statement must stand alone in its block",
                ))
            }
        }
    }
}

fn expect(c: &mut Cursor, ch: u8, what: &str) -> R<()> {
    c.skip_blanks();
    if c.peek() == Some(ch) {
        c.i += 1;
        Ok(())
    } else {
        Err(syntax(c.i, format!("'{}' expected {what}", ch as char)))
    }
}

/// Parses a statement; the cursor stands on the `$`.
pub fn parse(c: &mut Cursor, vars: &Variables) -> R<ControlStmt> {
    let at = c.i;
    c.i += 1;
    let kw = keyword(c);
    let stmt = match kw.as_str() {
        "FOR" => {
            c.skip_blanks();
            if !expr::at_variable(c) {
                return Err(syntax(
                    c.i,
                    "$FOR needs a V.P., V.L. or V.S. counting variable",
                ));
            }
            let var_at = c.i;
            let var = c.name();
            expect(c, b'=', "after the $FOR variable")?;
            let start = expr::eval(c, vars)?;
            expect(c, b',', "between start and end value")?;
            let end = expr::eval(c, vars)?;
            expect(c, b',', "between end value and step")?;
            let step = expr::eval(c, vars)?;
            ControlStmt::For {
                var,
                var_at,
                start,
                end,
                step,
                at,
            }
        }
        "ENDFOR" => ControlStmt::EndFor { at },
        "WHILE" => {
            let s = c.i;
            let cond = expr::eval(c, vars)?;
            ControlStmt::While {
                cond,
                cond_range: (s, c.i),
                at,
            }
        }
        "ENDWHILE" => ControlStmt::EndWhile { at },
        "IF" => ControlStmt::If {
            cond: expr::eval(c, vars)?,
            at,
        },
        "ELSEIF" | "ELSIF" => {
            // Condition read later (only if the branch is reached); skip the text now.
            c.i = c.end;
            ControlStmt::ElseIf { at }
        }
        "ELSE" => ControlStmt::Else { at },
        "ENDIF" => ControlStmt::EndIf { at },
        "" => return Err(syntax(at, "$ must be followed by a keyword")),
        other => {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("${other} is not supported by softnc"),
            ))
        }
    };
    end_of_statement(c)?;
    Ok(stmt)
}

/// Skips blanks and a block-skip mark (`/`, `/1`) at the start of a block.
fn skip_block_skip(c: &mut Cursor) {
    c.skip_blanks();
    if c.peek() == Some(b'/') {
        c.i += 1;
        if matches!(c.peek(), Some(b'0'..=b'9')) {
            c.i += 1;
        }
        c.skip_blanks();
    }
}

/// Skips `/`, the block number and blanks at the start of a block.
fn skip_prefix(c: &mut Cursor) {
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
pub fn read_block_number(c: &mut Cursor) -> R<Option<BlockNo>> {
    if c.letter() != Some(b'N') {
        return Ok(None);
    }
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
            "N must be followed by the block number",
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

/// The control keyword of a block's text, if it is a control statement.
pub fn keyword_of(src: &[u8], start: usize, end: usize) -> Option<String> {
    let mut c = Cursor::new(src, start, end);
    skip_prefix(&mut c);
    if c.peek() != Some(b'$') {
        return None;
    }
    c.i += 1;
    Some(keyword(&mut c))
}

/// Evaluates the condition of a `$ELSEIF` block. Returns the value and the `$` offset.
pub fn elseif_condition(src: &[u8], start: usize, end: usize, vars: &Variables) -> R<(f64, usize)> {
    let mut c = Cursor::new(src, start, end);
    skip_prefix(&mut c);
    let at = c.i;
    c.i += 1;
    keyword(&mut c);
    let v = expr::eval(&mut c, vars)?;
    end_of_statement(&mut c)?;
    Ok((v, at))
}
