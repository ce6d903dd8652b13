//! The word loop: reads a block's words into [`Words`] (addresses and their values), and
//! skips what is no word: comments, and the end-of-block word `LF`. The common addresses
//! (G X Y Z I J K) go straight to their value; everything else takes
//! [`Interpreter::special`]: comments, `@` commands, a bare dwell time, the multi-letter
//! words of each dialect and unknown addresses (docs/dialects.md, "Lexical rules").

use super::block::AuxWord;
use super::expr;
use super::fault::{fault, Fault, R};
use super::interpreter::Interpreter;
use super::lexer::Cursor;
use super::number;
use super::words::*;
use crate::alarm::AlarmCode;
use crate::dialect::{point_code, CornerWordDef, GEffect, LengthOffset, RadiusWord, G_CODES};

/// How the word loop goes on after [`Interpreter::special`].
enum Next {
    Continue,
    Break,
    /// A one-letter address: read its value.
    Address(u8),
}

impl Interpreter<'_> {
    /// Collects the words of a block.
    pub(super) fn words(&mut self, c: &mut Cursor, w: &mut Words) -> R<()> {
        loop {
            c.skip_blanks();
            let Some(ch) = c.peek() else { break };
            let at = c.i;
            let upper = ch.to_ascii_uppercase();
            // G, X, Y, Z, I, J, K are plain addresses in every dialect and start no longer
            // word: the bulk of any program, so they skip the checks in `special`.
            let letter = if matches!(upper, b'G' | b'I'..=b'K' | b'X'..=b'Z') && !self.long_name(c)
            {
                upper
            } else {
                match self.special(c, w, ch, at)? {
                    Next::Continue => continue,
                    Next::Break => break,
                    Next::Address(letter) => letter,
                }
            };
            c.i += 1;
            if self.d.sinumerik {
                match (c.peek(), letter) {
                    (Some(b'='), _) => {
                        self.sinumerik_word(c, w, letter, at)?;
                        continue;
                    }
                    (Some(b'1'), b'I'..=b'K') if c.peek_at(1) == Some(b'=') => {
                        self.intermediate_word(c, w, letter, at)?;
                        continue;
                    }
                    _ => {}
                }
            }
            let v = self.value(c, at, "")?;
            if v.value.is_nan() {
                // Macro B: a vacant variable leaves its word out.
                continue;
            }
            self.word(w, letter, v, at)?;
        }
        Ok(())
    }

    /// SINUMERIK: a name of more than one letter starts here (`XPOS=`, `GOTOF`), not an
    /// address.
    #[inline(always)]
    fn long_name(&self, c: &Cursor) -> bool {
        self.d.sinumerik && matches!(c.peek_at(1), Some(b) if b.is_ascii_alphabetic() || b == b'_')
    }

    /// Files the word `letter` with its value `v` into its slot.
    #[inline(always)]
    pub(super) fn word(&mut self, w: &mut Words, letter: u8, v: Val, at: usize) -> R<()> {
        let d = self.d;
        match letter {
            b'G' => {
                let code = g_code(v.value, at, d.name.as_str())?;
                push(&mut w.g, (code, at as u32), at)
            }
            b'X' | b'Y' | b'Z' => {
                let i = (letter - b'X') as usize;
                set_once(&mut w.axis[i], v, AXIS_WORDS[i])
            }
            b'I' | b'J' | b'K' => {
                let i = (letter - b'I') as usize;
                set_once(&mut w.centre[i], v, CENTRE_WORDS[i])
            }
            b'U' | b'W' if d.incremental_words => {
                // U and W: X and Z, incremental (Fanuc lathe, G-code system A).
                let i = if letter == b'U' { 0 } else { 2 };
                if w.axis[i].is_some() {
                    return Err(fault(
                        AlarmCode::AddressTwice,
                        at,
                        format!("{} and {} in one block", AXIS_WORDS[i], letter as char),
                    ));
                }
                w.axis[i] = Some(v);
                w.incremental |= 1 << i;
                Ok(())
            }
            b'U'..=b'W' | b'A'..=b'C' if self.md.axes.of_letter(letter).is_some() => {
                let i = self.md.axes.of_letter(letter).map_or(0, |i| i - 3);
                set_once(&mut w.additional[i], v, ADDITIONAL_WORDS[i])
            }
            b'R' if d.radius_word == RadiusWord::R => set_once(&mut w.radius, v, "R"),
            b'A' if d.polar_words => set_once(&mut w.angle, v, "A"),
            b'U' | b'B' if d.polar_words => set_once(&mut w.polar_radius, v, "U/B"),
            b'P' if d.dwell.p_millis => set_once(&mut w.p, v, "P"),
            b'L' if d.macro_b => set_once(&mut w.l, v, "L"),
            b'Q' if d.has_cycles() => set_once(&mut w.q, v, "Q"),
            b'F' => {
                set_once(&mut w.f, v, "F")?;
                self.aux(letter, v, at)
            }
            b'D' => {
                set_once(&mut w.d, v, "D")?;
                self.aux(letter, v, at)
            }
            b'T' => {
                set_once(&mut w.t, v, "T")?;
                self.aux(letter, v, at)
            }
            b'M' => {
                push(&mut w.m, v, at)?;
                self.aux(letter, v, at)
            }
            b'H' if d.length_offset == LengthOffset::HRegister => set_once(&mut w.h, v, "H"),
            b'S' | b'H' => self.aux(letter, v, at),
            b'N' => Err(fault(
                AlarmCode::Syntax,
                at,
                "the block number N must come first in the block",
            )),
            _ => Err(self.unknown_address(letter, at)),
        }
    }

    /// An auxiliary or technology word, in program order into the block being built.
    #[inline(always)]
    fn aux(&mut self, address: u8, v: Val, at: usize) -> R<()> {
        let word = AuxWord {
            address,
            value: v.value,
        };
        push(&mut self.block.words, word, at)
    }

    /// Everything at a word's start but the plain addresses. Says how the word loop goes
    /// on, or returns the address letter for the loop to read.
    #[inline(never)]
    fn special(&mut self, c: &mut Cursor, w: &mut Words, ch: u8, at: usize) -> R<Next> {
        match ch {
            b'(' => return self.comment(c, at),
            // comment (Siemens, ISG); Fanuc's ';' never gets here
            b';' => return Ok(Next::Break),
            _ => {}
        }
        let Some(letter) = c.letter() else {
            return self.not_a_letter(c, w, ch, at);
        };
        if self.d.sinumerik
            && (self.sinumerik_assignment(c, w, at)? || self.sinumerik_path_word(c, w, at)?)
        {
            return Ok(Next::Continue);
        }
        if self.d.sinumerik && letter == b'A' && c.keyword("AX") && c.peek_at(2) == Some(b'[') {
            // Fundamentals, "Axial addresses": AX[axis]=value.
            self.axial_address(c, w, at)?;
            return Ok(Next::Continue);
        }
        if self.d.sinumerik && letter == b'S' && c.keyword("SUPA") {
            // Fundamentals, "Frame suppression": G153's suppression and more, this block.
            c.i += 4;
            w.suppress = true;
            return Ok(Next::Continue);
        }
        if self.d.at_language && letter == b'R' {
            // 840C: `R1=…` (statements/siemens_840c.rs).
            return self.c840_assignment(c, w, at).map(|()| Next::Continue);
        }
        // Multi-letter words: they start with L (LF, LIMS=), C (CR=), D (DIAMON/DIAMOF) or
        // V (V. variables).
        if matches!(letter, b'L' | b'C' | b'D' | b'V') {
            if let Some(next) = self.multi_letter(c, w, letter, at)? {
                return Ok(next);
            }
        }
        if self.long_name(c) {
            if self.compensation_word(c, w, at)? {
                return Ok(Next::Continue);
            }
            if let Some(def) = self
                .d
                .corner_words
                .iter()
                .find(|def| starts_with(c, def.text))
            {
                return self.corner_word(c, w, def, at);
            }
            return Err(self.unknown_name(c, at));
        }
        if !self.known_address(letter) {
            return Err(self.unknown_address(letter, at));
        }
        Ok(Next::Address(letter))
    }

    /// A parenthesised comment at `at`.
    fn comment(&self, c: &mut Cursor, at: usize) -> R<Next> {
        if c.skip_comment() {
            Ok(Next::Continue)
        } else if self.d.variables {
            // ISG: `(` alone comments out the rest of the block.
            Ok(Next::Break)
        } else {
            Err(fault(AlarmCode::Syntax, at, "comment not closed with ')'"))
        }
    }

    /// What starts with no letter: an `@` command, a chamfer or corner word (`,C`), a bare
    /// dwell time, or a syntax error.
    fn not_a_letter(&mut self, c: &mut Cursor, w: &mut Words, ch: u8, at: usize) -> R<Next> {
        if !self.d.at_commands.is_empty() && ch == b'@' {
            return self.at_command(c, w, at);
        }
        if let Some(def) = self.d.corner_words.iter().find(|def| c.keyword(def.text)) {
            return self.corner_word(c, w, def, at);
        }
        if self.d.dwell.bare_seconds && w.bare.is_none() && self.after_dwell_code(w) {
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
        Err(fault(
            AlarmCode::Syntax,
            at,
            format!("unexpected character '{shown}'"),
        ))
    }

    /// A chamfer or corner word of the dialect's table and its value; at most one a block.
    fn corner_word(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        def: &CornerWordDef,
        at: usize,
    ) -> R<Next> {
        c.i += def.text.len();
        let value = self.equals_value(c, at, def.text)?;
        if value.value.is_nan() {
            // Macro B: a vacant variable leaves the word out.
            return Ok(Next::Continue);
        }
        if let Some(first) = w.corner {
            return Err(fault(
                AlarmCode::AddressTwice,
                at,
                format!("{} and {} in one block", first.text, def.text),
            ));
        }
        w.corner = Some(CornerWord {
            kind: def.kind,
            text: def.text,
            value,
        });
        Ok(Next::Continue)
    }

    /// The last G code read is the dwell (ISG `G04 3.0`: a bare number is its time).
    fn after_dwell_code(&self, w: &Words) -> bool {
        w.g.last()
            .and_then(|&(code, _)| self.d.gcode(code))
            .is_some_and(|def| def.effect == GEffect::Dwell)
    }

    /// The multi-letter words of the dialect (`LF`, `CR=`, `DIAMON`/`DIAMOF`/`DIAM90`, `V.` variable
    /// assignments); `None` if the text at the cursor is none of them.
    fn multi_letter(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        letter: u8,
        at: usize,
    ) -> R<Option<Next>> {
        let d = self.d;
        if d.lf_block_end && letter == b'L' && is_lf(c) {
            return lf_block_end(c).map(Some);
        }
        if d.radius_word == RadiusWord::CrEquals
            && letter == b'C'
            && matches!(c.peek_at(1), Some(b'R' | b'r'))
        {
            return self.cr_equals(c, w, at).map(Some);
        }
        if d.diameter_words && (c.keyword("DIAMON") || c.keyword("DIAMOF") || c.keyword("DIAM90")) {
            return diameter_switch(c, w, at).map(Some);
        }
        if d.lims_word && c.keyword("LIMS") {
            return self.lims_equals(c, w, at).map(Some);
        }
        if d.variables && expr::at_variable(c) {
            self.assignment(c, w, at)?;
            return Ok(Some(Next::Continue));
        }
        Ok(None)
    }

    /// Siemens `CR=`: the arc radius.
    fn cr_equals(&mut self, c: &mut Cursor, w: &mut Words, at: usize) -> R<Next> {
        let v = self.keyword_value(c, at, "CR=")?;
        set_once(&mut w.radius, v, "CR=")?;
        Ok(Next::Continue)
    }

    /// Siemens `LIMS=`: the spindle speed limit under constant surface speed.
    fn lims_equals(&mut self, c: &mut Cursor, w: &mut Words, at: usize) -> R<Next> {
        let v = self.keyword_value(c, at, "LIMS=")?;
        set_once(&mut w.lims, v, "LIMS=")?;
        Ok(Next::Continue)
    }

    /// The value of a Siemens `NAME=` word (`word`) whose name starts at the cursor.
    fn keyword_value(&mut self, c: &mut Cursor, at: usize, word: &'static str) -> R<Val> {
        let name = word.trim_end_matches('=');
        c.i += name.len();
        c.skip_blanks();
        if c.peek() != Some(b'=') {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("{name} must be followed by '='"),
            ));
        }
        c.i += 1;
        self.equals_value(c, at, word)
    }

    /// The value after a `NAME=` word: on SINUMERIK a whole expression (`CR=R1*2`), else a
    /// value as any word's.
    fn equals_value(&mut self, c: &mut Cursor, at: usize, word: &'static str) -> R<Val> {
        if !self.d.sinumerik {
            return self.value(c, at, word);
        }
        let value = super::sinumerik::expr::eval(c, &self.sinumerik.store)?;
        checked(Val::computed(value, at))
    }

    /// Whether `letter` is an address of the dialect.
    fn known_address(&self, letter: u8) -> bool {
        let d = self.d;
        matches!(
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
        ) || d.address_taken(letter)
            || self.md.axes.of_letter(letter).is_some()
    }

    /// SINUMERIK: a name that is no variable, no word of the dialect and no statement here.
    #[cold]
    fn unknown_name(&self, c: &Cursor, at: usize) -> Box<Fault> {
        let mut probe = *c;
        let name = super::sinumerik::expr::identifier(&mut probe);
        let message = if super::sinumerik::statements::Keyword::at(c).is_some() {
            format!("{name} must stand at the start of its block")
        } else {
            format!("{name} is not defined: no variable, word or statement of the language (docs/sinumerik.md lists what is not built yet)")
        };
        fault(AlarmCode::UndefinedName, at, message)
    }

    #[cold]
    fn unknown_address(&self, letter: u8, at: usize) -> Box<Fault> {
        fault(
            AlarmCode::UnknownAddress,
            at,
            format!(
                "address {} is not defined in the {} dialect",
                letter as char,
                self.d.name.as_str()
            ),
        )
    }

    /// The value after an address: a number, or in the ISG dialect an expression operand.
    #[inline(always)]
    pub(super) fn value(&mut self, c: &mut Cursor, at: usize, what: &str) -> R<Val> {
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
        if self.d.macro_b && crate::frontend::macro_b::expr::at_operand(c) {
            let v = crate::frontend::macro_b::expr::operand(c, &*self)?;
            return match v {
                // Vacant: the word loop leaves the word out.
                None => Ok(Val::computed(f64::NAN, at)),
                Some(value) => checked(Val::computed(value, at)),
            };
        }
        if self.d.variables && starts_operand(c) {
            let v = expr::eval_operand(c, &self.vars)?;
            return checked(Val::computed(v, at));
        }
        if self.d.at_language {
            if let Some(v) = self.c840_address_value(c, at)? {
                return checked(Val::computed(v, at));
            }
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
}

/// ISG: an expression operand (`[…]`, a function, a variable, a sign before one of them)
/// rather than a signed number.
fn starts_operand(c: &Cursor) -> bool {
    matches!(
        c.peek(),
        Some(b'[') | Some(b'-') | Some(b'+') | Some(b'a'..=b'z') | Some(b'A'..=b'Z')
    ) && !matches!(
        (c.peek(), c.peek_at(1)),
        (Some(b'-' | b'+'), Some(b'0'..=b'9' | b'.'))
    )
}

impl Interpreter<'_> {
    /// An `@` command: its number, looked up in the dialect's table, and in the 840C's
    /// language its operands (docs/sinumerik.md, "The 840C's R parameters and @ commands").
    fn at_command(&mut self, c: &mut Cursor, w: &mut Words, at: usize) -> R<Next> {
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
        let Some(def) = self.d.at_command(code) else {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("@{code} is not supported by softnc"),
            ));
        };
        if self.d.at_language {
            self.c840_at(c, w, def.effect, code, at)?;
        } else {
            push(&mut w.at_codes, (code, at as u32), at)?;
        }
        Ok(Next::Continue)
    }
}

/// `LF` as a word of its own: not followed by a letter, digit, point or sign.
fn is_lf(c: &Cursor) -> bool {
    matches!(c.peek_at(1), Some(b'F' | b'f'))
        && !matches!(c.peek_at(2), Some(x) if x.is_ascii_alphanumeric() || x == b'.' || x == b'-' || x == b'+')
}

/// 840C listings: `LF` ends the block; only comments may follow (docs/dialects.md,
/// "840C LF").
fn lf_block_end(c: &mut Cursor) -> R<Next> {
    c.i += 2;
    loop {
        c.skip_blanks();
        match c.peek() {
            None | Some(b';') => return Ok(Next::Break),
            Some(b'(') => {
                if !c.skip_comment() {
                    return Err(fault(AlarmCode::Syntax, c.i, "comment not closed with ')'"));
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
}

/// 808D `DIAMON` / `DIAMOF` / `DIAM90`: diameter programming on, off, or for absolute
/// dimensions only (808D Turning, "Positional data").
fn diameter_switch(c: &mut Cursor, w: &mut Words, at: usize) -> R<Next> {
    let word = if c.keyword("DIAMON") {
        DiameterWord::On
    } else if c.keyword("DIAMOF") {
        DiameterWord::Off
    } else {
        DiameterWord::Absolute
    };
    c.i += 6;
    if w.diameter.replace(word).is_some() {
        return Err(fault(
            AlarmCode::AddressTwice,
            at,
            "DIAMON/DIAMOF/DIAM90 twice in one block",
        ));
    }
    Ok(Next::Continue)
}

/// A G number as the tables index it: whole below `G_CODES`, or with one decimal (G54.1,
/// [`point_code`]).
fn g_code(v: f64, at: usize, dialect: &str) -> R<u16> {
    let tenths = libm::round(v * 10.0);
    if v < 0.0 || !v.is_finite() {
        Err(fault(
            AlarmCode::BadNumber,
            at,
            format!("a G code must be a whole number, not {v}"),
        ))
    } else if v < G_CODES as f64 && v as u16 as f64 == v {
        Ok(v as u16)
    } else if v < G_CODES as f64 && libm::fabs(v * 10.0 - tenths) < 1e-9 {
        Ok(point_code(0, tenths as u16))
    } else {
        Err(fault(
            AlarmCode::UnknownGCode,
            at,
            format!("G{v} is not a {dialect} G code"),
        ))
    }
}

/// Whether the text at the cursor starts with `text` (ASCII, any case): a word that ends in
/// `=` (`CHF=`), whatever follows it.
fn starts_with(c: &Cursor, text: &str) -> bool {
    text.bytes()
        .enumerate()
        .all(|(k, t)| c.peek_at(k).is_some_and(|b| b.eq_ignore_ascii_case(&t)))
}
