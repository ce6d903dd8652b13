//! SINUMERIK path words of more than one letter (Fundamentals, "Motion commands" and
//! "Feedrate control"; docs/sinumerik.md "Path geometry"): the motion commands CIP and CT,
//! the polar words AP= and RP=, the intermediate point I1= J1= K1=, TURN=, and the modal
//! rounding RNDM= with the corner feeds FRC= and FRCM=. They are read into
//! [`PathWords`](super::super::words::PathWords); the block build gives them their meaning.

use super::super::block::MotionMode;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::super::words::{checked, set_once, Val, Words};
use super::expr;
use crate::alarm::AlarmCode;

#[derive(Clone, Copy, PartialEq, Eq)]
enum PathWord {
    Motion(MotionMode),
    Ap,
    Rp,
    Turn,
    Rndm,
    Frc,
    Frcm,
}

/// The words as written; those with a value take `=`.
const PATH_WORDS: &[(&str, PathWord)] = &[
    ("CIP", PathWord::Motion(MotionMode::ArcThrough)),
    ("CT", PathWord::Motion(MotionMode::ArcTangent)),
    ("AP", PathWord::Ap),
    ("RP", PathWord::Rp),
    ("TURN", PathWord::Turn),
    ("RNDM", PathWord::Rndm),
    ("FRC", PathWord::Frc),
    ("FRCM", PathWord::Frcm),
];

/// The `=` after a value word `name` (standing at `at`), the cursor past it.
pub fn equals_after(c: &mut Cursor, name: &str, at: usize) -> R<()> {
    c.skip_blanks();
    if c.peek() != Some(b'=') {
        return Err(fault(
            AlarmCode::Syntax,
            at,
            format!("{name} must be followed by '='"),
        ));
    }
    c.i += 1;
    Ok(())
}

/// Whether `name` (upper case) is one of the path words: no variable may take it.
pub fn is_path_word(name: &str) -> bool {
    PATH_WORDS.iter().any(|(w, _)| *w == name)
}

/// `AC(` (b'A') or `IC(` (b'I') at the cursor: the cursor is moved past the bracket's
/// opening name, onto `(`, and the letter returned; else the cursor stays.
pub fn dimension_mode(c: &mut Cursor) -> Option<u8> {
    if !(c.keyword("AC") || c.keyword("IC")) {
        return None;
    }
    let m = c.letter();
    let mut probe = *c;
    probe.i += 2;
    probe.skip_blanks();
    if probe.peek() != Some(b'(') {
        return None;
    }
    *c = probe;
    m
}

impl Interpreter<'_> {
    /// A path word at the cursor: read into `w`, and true; false if the name is none.
    pub(in crate::frontend) fn sinumerik_path_word(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        at: usize,
    ) -> R<bool> {
        let mut probe = *c;
        let span = expr::identifier_span(&mut probe);
        let Some(&(text, word)) = PATH_WORDS
            .iter()
            .find(|(t, _)| t.as_bytes().eq_ignore_ascii_case(span))
        else {
            return Ok(false);
        };
        *c = probe;
        let p = &mut w.path;
        if let PathWord::Motion(mode) = word {
            if let Some((first, _)) = p.motion {
                return Err(fault(
                    AlarmCode::SameGroupTwice,
                    at,
                    format!("{text} and {} in one block", motion_name(first)),
                ));
            }
            p.motion = Some((mode, at as u32));
            return Ok(true);
        }
        equals_after(c, text, at)?;
        c.skip_blanks();
        let mode = dimension_mode(c);
        let v = checked(Val::computed(expr::eval(c, &self.sinumerik.store)?, at))?;
        if mode.is_some() && word != PathWord::Ap {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("{text}= takes no AC()/IC(): it is always absolute"),
            ));
        }
        let p = &mut w.path;
        match word {
            PathWord::Ap => {
                p.ap_incremental = mode.map(|m| m == b'I');
                set_once(&mut p.ap, v, "AP=")
            }
            PathWord::Rp => set_once(&mut p.rp, v, "RP="),
            PathWord::Turn => set_once(&mut p.turn, v, "TURN="),
            PathWord::Rndm => set_once(&mut p.rndm, v, "RNDM="),
            PathWord::Frc => set_once(&mut p.frc, v, "FRC="),
            PathWord::Frcm => set_once(&mut p.frcm, v, "FRCM="),
            PathWord::Motion(_) => Ok(()),
        }?;
        Ok(true)
    }

    /// `I1=`, `J1=`, `K1=` (the cursor on the `1`): a coordinate of CIP's intermediate point,
    /// `AC()`/`IC()` allowed (Fundamentals, "Circular interpolation through intermediate
    /// point (CIP)").
    pub(in crate::frontend) fn intermediate_word(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        letter: u8,
        at: usize,
    ) -> R<()> {
        c.i += 2;
        c.skip_blanks();
        let mode = dimension_mode(c);
        let v = checked(Val::computed(expr::eval(c, &self.sinumerik.store)?, at))?;
        let i = (letter - b'I') as usize;
        match mode {
            Some(b'A') => w.path.inter_absolute |= 1 << i,
            Some(_) => w.path.inter_incremental |= 1 << i,
            None => {}
        }
        set_once(&mut w.path.inter[i], v, INTER_WORDS[i])
    }
}

static INTER_WORDS: [&str; 3] = ["I1=", "J1=", "K1="];

fn motion_name(mode: MotionMode) -> &'static str {
    PATH_WORDS
        .iter()
        .find(|(_, w)| *w == PathWord::Motion(mode))
        .map_or("?", |(t, _)| t)
}
