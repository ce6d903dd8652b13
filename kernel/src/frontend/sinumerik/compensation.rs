//! The SINUMERIK compensation words among a block's words (Fundamentals "Tool radius
//! compensation"): the G functions written as names (NORM, KONT, KONTC, KONTT: the dialect
//! table's `named_codes`), DISC= (the transition circle's overshoot with G450), and the
//! parameters of the smooth approach and retraction, DISR=, DISCL=, DISRP=, FAD=. They are
//! read here and take effect in the block build (build/smooth.rs).

use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::super::words::{checked, Val, Words};
use super::expr;
use crate::alarm::AlarmCode;
use crate::dialect::NamedCodeDef;

/// DISCL=, DISRP=: a distance from the machining plane, or with `=AC(…)` a position.
#[derive(Clone, Copy, Debug)]
pub struct LevelWord {
    pub value: Val,
    pub absolute: bool,
}

/// FAD=: the slow infeed's feed, in the feed type in force or as `=PM(…)` per minute or
/// `=PR(…)` per revolution (NCP19 p.273).
#[derive(Clone, Copy, Debug)]
pub struct FeedWord {
    pub value: Val,
    /// `Some(true)`: per revolution (PR), `Some(false)`: per minute (PM), `None`: as G94/G95.
    pub per_rev: Option<bool>,
}

/// The compensation words of one block (boxed into [`Words`]: rare, and `Words` stays small).
#[derive(Clone, Debug, Default)]
pub struct CompensationWords {
    /// NORM, KONT, … with where they stand.
    pub codes: heapless::Vec<(&'static NamedCodeDef, u32), 4>,
    pub disc: Option<Val>,
    pub disr: Option<Val>,
    pub discl: Option<LevelWord>,
    pub disrp: Option<LevelWord>,
    pub fad: Option<FeedWord>,
}

impl CompensationWords {
    /// A SAR parameter was written (DISR DISCL DISRP FAD), at its offset.
    pub fn sar_parameter(&self) -> Option<(u32, &'static str)> {
        self.disr
            .map(|v| (v.at, "DISR="))
            .or(self.discl.map(|l| (l.value.at, "DISCL=")))
            .or(self.disrp.map(|l| (l.value.at, "DISRP=")))
            .or(self.fad.map(|f| (f.value.at, "FAD=")))
    }
}

/// The value words, as the program writes them.
const VALUE_WORDS: [&str; 5] = ["DISC", "DISR", "DISCL", "DISRP", "FAD"];

impl Interpreter<'_> {
    /// A compensation word at the cursor (a name, not an address): read into `w`, and true;
    /// false if the name is none of them.
    pub(in crate::frontend) fn compensation_word(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        at: usize,
    ) -> R<bool> {
        let mut probe = *c;
        let span = expr::identifier_span(&mut probe);
        if let Some(def) = self
            .d
            .named_codes
            .iter()
            .find(|d| d.text.as_bytes().eq_ignore_ascii_case(span))
        {
            let words = w.compensation.get_or_insert_with(Default::default);
            if words.codes.push((def, at as u32)).is_err() {
                return Err(fault(
                    AlarmCode::TooManyWords,
                    at,
                    "more than 4 named G functions in one block",
                ));
            }
            *c = probe;
            return Ok(true);
        }
        let Some(&name) = VALUE_WORDS
            .iter()
            .find(|n| n.as_bytes().eq_ignore_ascii_case(span))
        else {
            return Ok(false);
        };
        super::words::equals_after(&mut probe, name, at)?;
        *c = probe;
        self.value_word(c, w, name, at)
    }

    /// The value of `name=` (the cursor after the `=`), filed into the block's words.
    fn value_word(&mut self, c: &mut Cursor, w: &mut Words, name: &str, at: usize) -> R<bool> {
        let form = match name {
            "DISCL" | "DISRP" => function_form(c, &["AC"]),
            "FAD" => function_form(c, &["PM", "PR"]),
            _ => None,
        };
        let value = expr::eval(c, &self.sinumerik.store)?;
        let value = checked(Val::computed(value, at))?;
        let words = w.compensation.get_or_insert_with(Default::default);
        let twice = match name {
            "DISC" => words.disc.replace(value).is_some(),
            "DISR" => words.disr.replace(value).is_some(),
            "FAD" => {
                let per_rev = form.map(|f| f == "PR");
                let word = FeedWord { value, per_rev };
                words.fad.replace(word).is_some()
            }
            _ => {
                let word = LevelWord {
                    value,
                    absolute: form.is_some(),
                };
                let slot = if name == "DISCL" {
                    &mut words.discl
                } else {
                    &mut words.disrp
                };
                slot.replace(word).is_some()
            }
        };
        if twice {
            return Err(fault(
                AlarmCode::AddressTwice,
                at,
                format!("{name}= is programmed twice in this block"),
            ));
        }
        Ok(true)
    }
}

/// `AC(`, `PM(`, `PR(` after a value word's `=`: which one, the cursor left on the `(` so
/// that the expression reads the bracket.
fn function_form(c: &mut Cursor, forms: &[&'static str]) -> Option<&'static str> {
    c.skip_blanks();
    let form = forms.iter().copied().find(|f| c.keyword(f))?;
    let mut probe = *c;
    probe.i += form.len();
    probe.skip_blanks();
    (probe.peek() == Some(b'(')).then(|| {
        *c = probe;
        form
    })
}
