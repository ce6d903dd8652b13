//! SINUMERIK arithmetic (Programming Manual Job planning, "Arithmetic parameters", "Operators
//! and arithmetic functions"; docs/research/sinumerik-language.md §4).
//!
//! Priority, highest first: NOT B_NOT and the sign; `*` `/` DIV MOD; `+` `-`; B_AND; B_XOR;
//! B_OR; AND; XOR; OR; the comparisons `==` `<>` `>` `<` `>=` `<=`. The comparisons bind
//! weakest, so a compound condition is written `(R1>0) AND (R2<5)`, as the manuals do.
//! Brackets are `( )`; angles are degrees; a value is true when it is not 0.

use super::super::expr::finite;
use super::super::fault::{fault, R};
use super::super::lexer::Cursor;
use super::system::{Index, SystemName};
use super::Store;
use crate::alarm::AlarmCode;

/// Evaluates a full expression.
pub fn eval(c: &mut Cursor, store: &Store) -> R<f64> {
    Parser { store, depth: 0 }.comparison(c)
}

/// An arithmetic expression without comparisons: a term of a string concatenation, which
/// ends at `<<`.
pub fn eval_term(c: &mut Cursor, store: &Store) -> R<f64> {
    Parser { store, depth: 0 }.level(c, 0)
}

/// An array element's indices `[i]`, `[i, j]` or `[i, j, k]` (the cursor on `[`).
pub fn indices(c: &mut Cursor, store: &Store) -> R<heapless::Vec<f64, 3>> {
    Parser { store, depth: 0 }.indices(c)
}

pub fn truthy(v: f64) -> bool {
    v != 0.0
}

fn bool_value(b: bool) -> f64 {
    b as u8 as f64
}

/// The binary operators below the comparisons, weakest first: each level's words and
/// what it does.
type Apply = fn(f64, f64, usize) -> R<f64>;
const LEVELS: &[&[(&str, Apply)]] = &[
    &[("OR", |a, b, _| Ok(bool_value(truthy(a) || truthy(b))))],
    &[("XOR", |a, b, _| Ok(bool_value(truthy(a) != truthy(b))))],
    &[("AND", |a, b, _| Ok(bool_value(truthy(a) && truthy(b))))],
    &[("B_OR", |a, b, at| bits(a, b, at, |x, y| x | y))],
    &[("B_XOR", |a, b, at| bits(a, b, at, |x, y| x ^ y))],
    &[("B_AND", |a, b, at| bits(a, b, at, |x, y| x & y))],
    &[
        ("+", |a, b, at| finite(a + b, at, "sum")),
        ("-", |a, b, at| finite(a - b, at, "difference")),
    ],
    &[
        ("*", |a, b, at| finite(a * b, at, "product")),
        ("/", divide),
        ("DIV", |a, b, at| divide(a, b, at).map(f64::trunc)),
        ("MOD", |a, b, at| {
            if b == 0.0 {
                return Err(fault(AlarmCode::Arithmetic, at, "MOD by 0"));
            }
            Ok(a % b)
        }),
    ],
];

fn divide(a: f64, b: f64, at: usize) -> R<f64> {
    if b == 0.0 {
        return Err(fault(AlarmCode::Arithmetic, at, "division by 0"));
    }
    finite(a / b, at, "quotient")
}

/// A bit operation on two whole numbers (INT).
fn bits(a: f64, b: f64, at: usize, f: fn(i64, i64) -> i64) -> R<f64> {
    Ok(f(whole(a, at)?, whole(b, at)?) as f64)
}

fn whole(v: f64, at: usize) -> R<i64> {
    if v.fract() != 0.0 || v.abs() > 2_147_483_647.0 {
        return Err(fault(
            AlarmCode::Arithmetic,
            at,
            format!("{v} is no INT value for a bit operation"),
        ));
    }
    Ok(v as i64)
}

struct Parser<'s> {
    store: &'s Store,
    depth: u32,
}

impl Parser<'_> {
    fn enter(&mut self, c: &Cursor) -> R<()> {
        super::super::expr::deeper(&mut self.depth, c.i)
    }

    /// `a == b`, … (left to right); two strings compare with `==` and `<>`.
    fn comparison(&mut self, c: &mut Cursor) -> R<f64> {
        c.skip_blanks();
        let start = c.i;
        if let Some(l) = self.text(c)? {
            return self.text_comparison(c, l, start);
        }
        let mut l = self.level(c, 0)?;
        loop {
            c.skip_blanks();
            let op: &[u8] = match (c.peek(), c.peek_at(1)) {
                (Some(b'='), Some(b'=')) => b"==",
                (Some(b'<'), Some(b'>')) => b"<>",
                (Some(b'<'), Some(b'=')) => b"<=",
                (Some(b'>'), Some(b'=')) => b">=",
                (Some(b'<'), Some(b'<')) => {
                    return Err(fault(
                        AlarmCode::Syntax,
                        c.i,
                        "<< joins strings: only in MSG(…) and STRING assignments",
                    ))
                }
                (Some(b'<'), _) => b"<",
                (Some(b'>'), _) => b">",
                _ => return Ok(l),
            };
            c.i += op.len();
            let r = self.level(c, 0)?;
            l = bool_value(match op {
                b"==" => l == r,
                b"<>" => l != r,
                b"<=" => l <= r,
                b">=" => l >= r,
                b"<" => l < r,
                _ => l > r,
            });
        }
    }

    /// A string operand at the cursor (a text of more than one character or a STRING
    /// variable), the cursor moved past it; `None` (the cursor left) for anything else.
    fn text(&mut self, c: &mut Cursor) -> R<Option<String>> {
        c.skip_blanks();
        let mut probe = *c;
        if probe.peek() == Some(b'"') {
            let close = c.b[c.i + 1..c.end].iter().position(|&b| b == b'"');
            return match close {
                // One character in quotes is a CHAR: a number.
                Some(1) => Ok(None),
                Some(k) => {
                    let t = String::from_utf8_lossy(&c.b[c.i + 1..c.i + 1 + k]).into_owned();
                    c.i += k + 2;
                    Ok(Some(t))
                }
                None => Err(fault(AlarmCode::Syntax, c.i, "string not closed with '\"'")),
            };
        }
        let name = identifier(&mut probe);
        Ok(self.store.string(&name).map(|t| {
            *c = probe;
            t.to_string()
        }))
    }

    /// `text == text` or `text <> text` (Job planning, "String operations: comparison").
    fn text_comparison(&mut self, c: &mut Cursor, l: String, start: usize) -> R<f64> {
        c.skip_blanks();
        let equal = match (c.peek(), c.peek_at(1)) {
            (Some(b'='), Some(b'=')) => true,
            (Some(b'<'), Some(b'>')) => false,
            _ => {
                let m = "a text is no number: a string only compares with == or <> (or joins with << in MSG and STRING assignments)";
                return Err(fault(AlarmCode::Syntax, start, m));
            }
        };
        c.i += 2;
        let Some(r) = self.text(c)? else {
            return Err(fault(
                AlarmCode::Syntax,
                c.i,
                "a string to compare with expected",
            ));
        };
        Ok(bool_value((l == r) == equal))
    }

    /// The binary operators of `LEVELS[k]` and those above it.
    fn level(&mut self, c: &mut Cursor, k: usize) -> R<f64> {
        let Some(ops) = LEVELS.get(k) else {
            return self.unary(c);
        };
        let mut v = self.level(c, k + 1)?;
        'more: loop {
            c.skip_blanks();
            for (word, apply) in ops.iter() {
                if self.operator(c, word) {
                    let at = c.i;
                    c.i += word.len();
                    let r = self.level(c, k + 1)?;
                    v = apply(v, r, at)?;
                    continue 'more;
                }
            }
            return Ok(v);
        }
    }

    /// Whether operator `word` stands at the cursor (a word operator as a whole word).
    fn operator(&self, c: &Cursor, word: &str) -> bool {
        let w = word.as_bytes();
        if !w[0].is_ascii_alphabetic() {
            return c.peek() == Some(w[0]);
        }
        c.keyword(word) && !matches!(c.peek_at(w.len()), Some(b'_' | b'0'..=b'9'))
    }

    /// A sign, NOT or B_NOT, then a primary.
    fn unary(&mut self, c: &mut Cursor) -> R<f64> {
        c.skip_blanks();
        self.enter(c)?;
        let v = match c.peek() {
            Some(b'-') => {
                c.i += 1;
                -self.unary(c)?
            }
            Some(b'+') => {
                c.i += 1;
                self.unary(c)?
            }
            _ if self.operator(c, "NOT") => {
                c.i += 3;
                bool_value(!truthy(self.unary(c)?))
            }
            _ if self.operator(c, "B_NOT") => {
                let at = c.i;
                c.i += 5;
                !whole(self.unary(c)?, at)? as f64
            }
            _ => self.primary(c)?,
        };
        self.depth -= 1;
        Ok(v)
    }

    /// A number, a bracket, a function, an R parameter or a variable.
    fn primary(&mut self, c: &mut Cursor) -> R<f64> {
        c.skip_blanks();
        let at = c.i;
        match c.peek() {
            Some(b'(') => {
                c.i += 1;
                let v = self.comparison(c)?;
                close(c, at)?;
                Ok(v)
            }
            Some(b'0'..=b'9' | b'.') => number(c, at),
            Some(b'"') => character(c, at),
            Some(ch) if ch.is_ascii_alphabetic() || ch == b'_' || ch == b'$' => self.named(c, at),
            _ => Err(fault(AlarmCode::Syntax, at, "operand expected")),
        }
    }

    /// What starts with a name: a function call, an R parameter, TRUE/FALSE or a variable.
    fn named(&mut self, c: &mut Cursor, at: usize) -> R<f64> {
        let name = identifier(c);
        if name.starts_with('$') {
            return self.system(c, &name, at);
        }
        c.skip_blanks();
        if c.peek() == Some(b'(') {
            if let Some(f) = FUNCTIONS.iter().find(|f| f.0 == name) {
                c.i += 1;
                let args = self.arguments(c, at)?;
                return (f.1)(&args, at, &name);
            }
        }
        match name.as_str() {
            "TRUE" => return Ok(1.0),
            "FALSE" => return Ok(0.0),
            _ => {}
        }
        if let Some(n) = r_number(&name) {
            return self.store.r(n, at);
        }
        if c.peek() == Some(b'[') && self.store.is_array(&name) {
            let idx = self.indices(c)?;
            return self.store.element(&name, &idx, at);
        }
        if name == "R" && c.peek() == Some(b'[') {
            c.i += 1;
            let n = self.comparison(c)?;
            c.skip_blanks();
            if c.peek() != Some(b']') {
                return Err(fault(AlarmCode::Syntax, c.i, "']' expected"));
            }
            c.i += 1;
            return self.store.r(index(n, at)?, at);
        }
        self.store.get(&name, at)
    }

    /// A system variable `name` with its indices (`$AA_IW[X]`, `$TC_DP6[1,1]`).
    fn system(&mut self, c: &mut Cursor, name: &str, at: usize) -> R<f64> {
        let Some(v) = SystemName::of(name) else {
            return Err(fault(
                AlarmCode::UndefinedName,
                at,
                format!("system variable {name} is not provided (docs/sinumerik.md, \"System variables\")"),
            ));
        };
        let mut idx: heapless::Vec<Index, 2> = heapless::Vec::new();
        if v.indices() > 0 {
            c.skip_blanks();
            if c.peek() != Some(b'[') {
                return Err(fault(AlarmCode::Syntax, c.i, format!("{name}[…] expected")));
            }
            c.i += 1;
            for k in 0..v.indices() {
                if k > 0 {
                    expect(c, b',')?;
                }
                let _ = idx.push(self.index_value(c)?);
            }
            expect(c, b']')?;
        }
        let Some(sys) = self.store.system.as_deref() else {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("{name} cannot be read here"),
            ));
        };
        if v.main_run() {
            self.store.main_run_read.set(true);
        }
        sys.read(v, name, &idx, at)
    }

    /// An index: an axis letter alone, or an expression.
    fn index_value(&mut self, c: &mut Cursor) -> R<Index> {
        c.skip_blanks();
        let mut probe = *c;
        let name = identifier(&mut probe);
        if let Some(axis) = self.store.axis_of(&name) {
            let at = c.i;
            *c = probe;
            return axis.map(Index::Axis).ok_or_else(|| {
                fault(
                    AlarmCode::UndefinedName,
                    at,
                    format!("{name} names no axis yet"),
                )
            });
        }
        let letter = c.peek().map(|b| b.to_ascii_uppercase());
        let alone = !c
            .peek_at(1)
            .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_');
        if let Some(l @ (b'A'..=b'C' | b'U'..=b'Z')) = letter.filter(|_| alone) {
            c.i += 1;
            return Ok(Index::Axis(l));
        }
        Ok(Index::Number(self.comparison(c)?))
    }

    /// `[e1, e2, …]` (the cursor on `[`): at most three indices.
    fn indices(&mut self, c: &mut Cursor) -> R<heapless::Vec<f64, 3>> {
        c.i += 1;
        let mut idx = heapless::Vec::new();
        loop {
            let at = c.i;
            let v = self.comparison(c)?;
            if idx.push(v).is_err() {
                return Err(fault(AlarmCode::Syntax, at, "more than three indices"));
            }
            c.skip_blanks();
            match c.peek() {
                Some(b',') => c.i += 1,
                Some(b']') => {
                    c.i += 1;
                    return Ok(idx);
                }
                _ => return Err(fault(AlarmCode::Syntax, c.i, "',' or ']' expected")),
            }
        }
    }

    /// Arguments up to the closing bracket (the opening one is read).
    fn arguments(&mut self, c: &mut Cursor, at: usize) -> R<heapless::Vec<f64, 3>> {
        let mut args = heapless::Vec::new();
        loop {
            let v = self.comparison(c)?;
            if args.push(v).is_err() {
                return Err(fault(AlarmCode::Syntax, c.i, "too many arguments"));
            }
            c.skip_blanks();
            match c.peek() {
                Some(b',') => c.i += 1,
                Some(b')') => {
                    c.i += 1;
                    return Ok(args);
                }
                _ => return Err(fault(AlarmCode::Syntax, at, "')' expected")),
            }
        }
    }
}

fn expect(c: &mut Cursor, ch: u8) -> R<()> {
    c.skip_blanks();
    if c.peek() == Some(ch) {
        c.i += 1;
        Ok(())
    } else {
        Err(fault(
            AlarmCode::Syntax,
            c.i,
            format!("'{}' expected", ch as char),
        ))
    }
}

fn close(c: &mut Cursor, open: usize) -> R<()> {
    c.skip_blanks();
    if c.peek() == Some(b')') {
        c.i += 1;
        Ok(())
    } else {
        Err(fault(AlarmCode::Syntax, open, "'(' is not closed"))
    }
}

/// `"A"` in a number: the character's code (a CHAR constant; Job planning, "Variable types").
fn character(c: &mut Cursor, at: usize) -> R<f64> {
    let (ch, close) = (c.peek_at(1), c.peek_at(2));
    match (ch, close) {
        (Some(b), Some(b'"')) if b != b'"' => {
            c.i += 3;
            Ok(f64::from(b))
        }
        _ => Err(fault(
            AlarmCode::Syntax,
            at,
            "a text is no number: one character in quotes (\"A\") is a CHAR",
        )),
    }
}

fn number(c: &mut Cursor, at: usize) -> R<f64> {
    match crate::frontend::number::parse(c.b, c.i).filter(|(_, e)| *e <= c.end) {
        Some((n, next)) => {
            c.i = next;
            // `1.5EX3`: an exponent (840D).
            let upper = |b: Option<u8>| b.map(|b| b.to_ascii_uppercase());
            if (upper(c.peek()), upper(c.peek_at(1))) == (Some(b'E'), Some(b'X')) {
                c.i += 2;
                let (e, next) = crate::frontend::number::parse(c.b, c.i)
                    .filter(|(_, e)| *e <= c.end)
                    .ok_or_else(|| fault(AlarmCode::Syntax, c.i, "exponent expected after EX"))?;
                c.i = next;
                return finite(n.value * libm::pow(10.0, e.value), at, "number");
            }
            Ok(n.value)
        }
        None => Err(fault(AlarmCode::Syntax, at, "number expected")),
    }
}

/// A name: letters, digits and `_` (a system variable starts with `$`), upper-cased.
pub fn identifier(c: &mut Cursor) -> String {
    let span = identifier_span(c);
    String::from_utf8_lossy(span).to_ascii_uppercase()
}

/// The bytes of the name at the cursor, as written (nothing allocated): the cursor moves past.
pub fn identifier_span<'a>(c: &mut Cursor<'a>) -> &'a [u8] {
    let start = c.i;
    if c.peek() == Some(b'$') {
        c.i += 1;
    }
    while let Some(ch) = c.peek() {
        if ch.is_ascii_alphanumeric() || ch == b'_' {
            c.i += 1;
        } else {
            break;
        }
    }
    &c.b[start..c.i]
}

/// A function's or a constant's name: no variable may take it.
pub fn is_reserved(name: &str) -> bool {
    matches!(
        name,
        "TRUE" | "FALSE" | "NOT" | "AND" | "OR" | "XOR" | "DIV" | "MOD" | "TO"
    ) || name.starts_with("B_")
        || FUNCTIONS.iter().any(|f| f.0 == name)
        || super::words::is_path_word(name)
}

/// `R12` → 12 (`R01` is R1).
pub fn r_number(name: &str) -> Option<usize> {
    let digits = name.strip_prefix('R')?;
    if digits.is_empty() || digits.len() > 6 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// A value used as an index or number: whole and not negative.
pub fn index(v: f64, at: usize) -> R<usize> {
    if v < 0.0 || v.fract() != 0.0 || v > 1e6 {
        return Err(fault(AlarmCode::BadNumber, at, format!("{v} is no index")));
    }
    Ok(v as usize)
}

type Function = fn(&[f64], usize, &str) -> R<f64>;

fn one(args: &[f64], at: usize, name: &str) -> R<f64> {
    match args {
        [a] => Ok(*a),
        _ => Err(fault(
            AlarmCode::Syntax,
            at,
            format!("{name} takes one argument"),
        )),
    }
}

fn domain(ok: bool, v: f64, at: usize, name: &str) -> R<f64> {
    if ok && v.is_finite() {
        Ok(v)
    } else {
        Err(fault(
            AlarmCode::Arithmetic,
            at,
            format!("{name}: argument out of range"),
        ))
    }
}

/// The arithmetic functions (Job planning, "Arithmetic functions"); angles in degrees.
static FUNCTIONS: &[(&str, Function)] = &[
    ("SIN", |a, at, n| Ok(libm::sin(one(a, at, n)?.to_radians()))),
    ("COS", |a, at, n| Ok(libm::cos(one(a, at, n)?.to_radians()))),
    ("TAN", |a, at, n| {
        let v = libm::tan(one(a, at, n)?.to_radians());
        domain(v.abs() < 1e15, v, at, n)
    }),
    ("ASIN", |a, at, n| {
        let x = one(a, at, n)?;
        domain(x.abs() <= 1.0, libm::asin(x).to_degrees(), at, n)
    }),
    ("ACOS", |a, at, n| {
        let x = one(a, at, n)?;
        domain(x.abs() <= 1.0, libm::acos(x).to_degrees(), at, n)
    }),
    ("ATAN2", |a, at, n| match a {
        [y, x] => Ok(libm::atan2(*y, *x).to_degrees()),
        _ => Err(fault(
            AlarmCode::Syntax,
            at,
            format!("{n} takes two arguments"),
        )),
    }),
    ("SQRT", |a, at, n| {
        let x = one(a, at, n)?;
        domain(x >= 0.0, libm::sqrt(x), at, n)
    }),
    ("ABS", |a, at, n| Ok(one(a, at, n)?.abs())),
    ("POT", |a, at, n| {
        let x = one(a, at, n)?;
        domain(true, x * x, at, n)
    }),
    ("TRUNC", |a, at, n| Ok(one(a, at, n)?.trunc())),
    ("ROUND", |a, at, n| Ok(libm::round(one(a, at, n)?))),
    ("ROUNDUP", |a, at, n| Ok(libm::ceil(one(a, at, n)?))),
    ("LN", |a, at, n| {
        let x = one(a, at, n)?;
        domain(x > 0.0, libm::log(x), at, n)
    }),
    ("EXP", |a, at, n| {
        let x = one(a, at, n)?;
        domain(true, libm::exp(x), at, n)
    }),
    ("MINVAL", |a, at, n| match a {
        [x, y] => Ok(x.min(*y)),
        _ => Err(fault(
            AlarmCode::Syntax,
            at,
            format!("{n} takes two arguments"),
        )),
    }),
    ("MAXVAL", |a, at, n| match a {
        [x, y] => Ok(x.max(*y)),
        _ => Err(fault(
            AlarmCode::Syntax,
            at,
            format!("{n} takes two arguments"),
        )),
    }),
    ("BOUND", |a, at, n| match a {
        [lo, hi, x] if lo <= hi => Ok(x.clamp(*lo, *hi)),
        [_, _, _] => Err(fault(
            AlarmCode::Arithmetic,
            at,
            format!("{n}: minimum above maximum"),
        )),
        _ => Err(fault(
            AlarmCode::Syntax,
            at,
            format!("{n} takes three arguments"),
        )),
    }),
];
