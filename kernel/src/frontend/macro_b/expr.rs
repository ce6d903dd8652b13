//! Custom Macro B expressions (Fanuc 0i-MF operator's manual, "Arithmetic and logic
//! operation"): `[ ]` groups, functions take their argument in brackets, angles are degrees.
//! Precedence from high to low: functions, `* / AND MOD`, `+ - OR XOR`, `EQ NE GT GE LT LE`.
//!
//! A value is `None` when vacant (`#0`, a variable never written). An operation on a vacant
//! value takes it as 0, but a variable passed on as it stands stays vacant (so `X#1` leaves
//! X out), and `EQ`/`NE` tell vacant from 0 while `GT GE LT LE` take it as 0.

use super::super::fault::{fault, R};
use super::super::lexer::Cursor;
use super::super::number;
use crate::alarm::AlarmCode;

/// A macro value; `None` is vacant.
pub type Value = Option<f64>;

/// Brackets nest at most this deep, function brackets included (0i-MF, "Nesting of
/// brackets": five levels).
const MAX_BRACKETS: u32 = 5;

/// Largest magnitude of a macro value (the control's range is about ±10^47; softnc keeps
/// values well inside f64 so that every later computation stays finite).
const MAX_MACRO_VALUE: f64 = 1e30;

/// Two values within this relative distance are equal for EQ/NE (the control compares to
/// its internal precision, not bit for bit: `0.1+0.2 EQ 0.3` holds).
const EQ_TOLERANCE: f64 = 1e-12;

/// Where the values of `#` variables come from.
pub trait Store {
    /// The value of variable `number`; `at` points at its `#` for an alarm.
    fn read(&self, number: i64, at: usize) -> R<Value>;
}

/// A full expression at the cursor: what stands between `[` and `]`, or right of `=`.
pub fn eval<S: Store + ?Sized>(c: &mut Cursor, s: &S) -> R<Value> {
    Parser { s, depth: 0 }.cmp(c)
}

/// An address value (`X#1`, `X-#1`, `X[#1+2]`, `XSIN[30]`): a signed primary.
pub fn operand<S: Store + ?Sized>(c: &mut Cursor, s: &S) -> R<Value> {
    Parser { s, depth: 0 }.unary(c)
}

/// The variable number after a `#` at the cursor (`#12`, `#[#1+100]`); the cursor moves past
/// it. Returns the number and the offset of the `#`.
pub fn variable<S: Store + ?Sized>(c: &mut Cursor, s: &S) -> R<(i64, usize)> {
    Parser { s, depth: 0 }.variable_number(c)
}

/// Whether a macro operand starts at the cursor (after an address or `=`).
pub fn at_operand(c: &Cursor) -> bool {
    match c.peek() {
        Some(b'#' | b'[') => true,
        Some(b'-' | b'+') => matches!(c.peek_at(1), Some(b'#' | b'[')),
        Some(ch) if ch.is_ascii_alphabetic() => FUNCTIONS.iter().any(|f| c.keyword(f.0)),
        _ => false,
    }
}

/// A value as a whole number, for what must be one (a variable number, a label, AND/OR).
pub fn whole(v: f64, at: usize, what: &str) -> R<i64> {
    let r = libm::round(v);
    if (v - r).abs() > 1e-6 || r.abs() > 1e15 {
        return Err(fault(
            AlarmCode::BadNumber,
            at,
            format!("{what} must be a whole number, not {v}"),
        ));
    }
    Ok(r as i64)
}

/// Condition truth (IF, WHILE): a comparison gives 1 or 0; any other value is true unless 0.
pub fn truthy(v: Value) -> bool {
    v.is_some_and(|x| x != 0.0)
}

fn finite(v: f64, at: usize) -> R<Value> {
    if v.is_finite() && v.abs() <= MAX_MACRO_VALUE {
        Ok(Some(v))
    } else {
        Err(fault(AlarmCode::Arithmetic, at, "result out of range"))
    }
}

fn syntax(at: usize, m: impl Into<String>) -> Box<super::super::fault::Fault> {
    fault(AlarmCode::Syntax, at, m)
}

/// A one-argument function: name and what it computes (`None`: the argument is outside its
/// domain).
type Function = (&'static str, fn(f64) -> Option<f64>);

static FUNCTIONS: &[Function] = &[
    ("SIN", |x| Some(libm::sin(x.to_radians()))),
    ("COS", |x| Some(libm::cos(x.to_radians()))),
    ("TAN", |x| {
        let c = libm::cos(x.to_radians());
        (c.abs() > 1e-12).then(|| libm::sin(x.to_radians()) / c)
    }),
    ("ASIN", |x| {
        (-1.0..=1.0)
            .contains(&x)
            .then(|| libm::asin(x).to_degrees())
    }),
    ("ACOS", |x| {
        (-1.0..=1.0)
            .contains(&x)
            .then(|| libm::acos(x).to_degrees())
    }),
    ("ATAN", |x| Some(libm::atan(x).to_degrees())),
    ("SQRT", |x| (x >= 0.0).then(|| libm::sqrt(x))),
    ("ABS", |x| Some(x.abs())),
    // 0i-MF: ROUND rounds half away from zero; FIX drops the fraction, FUP raises it
    // (both toward / away from zero).
    ("ROUND", |x| Some(libm::round(x))),
    ("FIX", |x| Some(libm::trunc(x))),
    ("FUP", |x| {
        let t = libm::trunc(x);
        Some(if t == x { t } else { t + x.signum() })
    }),
    ("LN", |x| (x > 0.0).then(|| libm::log(x))),
    ("EXP", |x| Some(libm::exp(x))),
    ("BIN", bcd_to_binary),
    ("BCD", binary_to_bcd),
    ("POW", |_| None),
];

/// BIN: a BCD-coded number (each decimal digit in four bits) to its value.
fn bcd_to_binary(x: f64) -> Option<f64> {
    if !(0.0..=99_999_999.0).contains(&x) || x.fract() != 0.0 {
        return None;
    }
    let (mut bits, mut v, mut scale) = (x as u64, 0u64, 1u64);
    while bits > 0 {
        let digit = bits & 0xF;
        if digit > 9 {
            return None;
        }
        v += digit * scale;
        scale *= 10;
        bits >>= 4;
    }
    Some(v as f64)
}

/// BCD: a value to its BCD code.
fn binary_to_bcd(x: f64) -> Option<f64> {
    if !(0.0..=99_999_999.0).contains(&x) || x.fract() != 0.0 {
        return None;
    }
    let (mut n, mut v, mut shift) = (x as u64, 0u64, 0);
    while n > 0 {
        v |= (n % 10) << shift;
        n /= 10;
        shift += 4;
    }
    Some(v as f64)
}

struct Parser<'s, S: ?Sized> {
    s: &'s S,
    depth: u32,
}

impl<S: Store + ?Sized> Parser<'_, S> {
    fn cmp(&mut self, c: &mut Cursor) -> R<Value> {
        let l = self.sum(c)?;
        c.skip_blanks();
        const OPS: [&str; 6] = ["EQ", "NE", "GT", "GE", "LT", "LE"];
        let Some(op) = OPS.iter().find(|op| c.keyword(op)) else {
            return Ok(l);
        };
        c.i += 2;
        let r = self.sum(c)?;
        let (a, b) = (l.unwrap_or(0.0), r.unwrap_or(0.0));
        let t = match *op {
            "EQ" => equal(l, r),
            "NE" => !equal(l, r),
            "GT" => a > b,
            "GE" => a >= b || equal(Some(a), Some(b)),
            "LT" => a < b,
            _ => a <= b || equal(Some(a), Some(b)),
        };
        Ok(Some(t as u8 as f64))
    }

    fn sum(&mut self, c: &mut Cursor) -> R<Value> {
        let mut v = self.product(c)?;
        loop {
            c.skip_blanks();
            let at = c.i;
            let op = match c.peek() {
                Some(b'+') => "+",
                Some(b'-') => "-",
                _ if c.keyword("OR") => "OR",
                _ if c.keyword("XOR") => "XOR",
                _ => return Ok(v),
            };
            c.i += op.len();
            let r = self.product(c)?.unwrap_or(0.0);
            let l = v.unwrap_or(0.0);
            v = match op {
                "+" => finite(l + r, at)?,
                "-" => finite(l - r, at)?,
                "OR" => Some((bits(l, at, op)? | bits(r, at, op)?) as f64),
                _ => Some((bits(l, at, op)? ^ bits(r, at, op)?) as f64),
            };
        }
    }

    fn product(&mut self, c: &mut Cursor) -> R<Value> {
        let mut v = self.unary(c)?;
        loop {
            c.skip_blanks();
            let at = c.i;
            let op = match c.peek() {
                Some(b'*') => "*",
                Some(b'/') => "/",
                _ if c.keyword("AND") => "AND",
                _ if c.keyword("MOD") => "MOD",
                _ => return Ok(v),
            };
            c.i += op.len();
            let r = self.unary(c)?.unwrap_or(0.0);
            let l = v.unwrap_or(0.0);
            if r == 0.0 && matches!(op, "/" | "MOD") {
                return Err(fault(AlarmCode::Arithmetic, at, "division by zero"));
            }
            v = match op {
                "*" => finite(l * r, at)?,
                "/" => finite(l / r, at)?,
                "MOD" => finite(l % r, at)?,
                _ => Some((bits(l, at, op)? & bits(r, at, op)?) as f64),
            };
        }
    }

    /// A sign keeps a vacant value vacant (`X-#1` with #1 vacant leaves X out).
    fn unary(&mut self, c: &mut Cursor) -> R<Value> {
        c.skip_blanks();
        match c.peek() {
            Some(b'-') => {
                c.i += 1;
                Ok(self.primary(c)?.map(|v| -v))
            }
            Some(b'+') => {
                c.i += 1;
                self.primary(c)
            }
            _ => self.primary(c),
        }
    }

    fn primary(&mut self, c: &mut Cursor) -> R<Value> {
        c.skip_blanks();
        let at = c.i;
        match c.peek() {
            Some(b'#') => {
                let (n, at) = self.variable_number(c)?;
                self.s.read(n, at)
            }
            Some(b'[') => self.bracket(c),
            Some(b'0'..=b'9' | b'.') => {
                match number::parse(c.b, c.i).filter(|(_, e)| *e <= c.end) {
                    Some((n, next)) => {
                        c.i = next;
                        Ok(Some(n.value))
                    }
                    None => Err(fault(AlarmCode::BadNumber, at, "malformed number")),
                }
            }
            Some(ch) if ch.is_ascii_alphabetic() => self.function(c),
            _ => Err(syntax(at, "a number, #variable, [ or function expected")),
        }
    }

    /// `[ expression ]`.
    fn bracket(&mut self, c: &mut Cursor) -> R<Value> {
        let open = c.i;
        self.depth += 1;
        if self.depth > MAX_BRACKETS {
            return Err(syntax(
                open,
                format!("brackets nested deeper than {MAX_BRACKETS} levels"),
            ));
        }
        c.i += 1;
        let v = self.cmp(c)?;
        c.skip_blanks();
        if c.peek() != Some(b']') {
            return Err(syntax(c.i, "']' expected"));
        }
        c.i += 1;
        self.depth -= 1;
        Ok(v)
    }

    /// `SIN[…]`, `ATAN[a]/[b]`, `ATAN[a,b]`, `POW[a,b]`.
    fn function(&mut self, c: &mut Cursor) -> R<Value> {
        let at = c.i;
        let Some(&(name, f)) = FUNCTIONS.iter().find(|f| c.keyword(f.0)) else {
            let mut probe = *c;
            let word = probe.name();
            return Err(fault(
                AlarmCode::UndefinedName,
                at,
                format!("{word} is not a macro function"),
            ));
        };
        c.i += name.len();
        c.skip_blanks();
        if c.peek() != Some(b'[') {
            return Err(syntax(c.i, format!("{name} takes its argument in [ ]")));
        }
        let (a, second) = self.arguments(c, name == "ATAN")?;
        let a = a.unwrap_or(0.0);
        let v = match (name, second) {
            ("ATAN", Some(b)) => Some(atan2_degrees(a, b)),
            ("POW", Some(b)) => Some(libm::pow(a, b)).filter(|v| v.is_finite()),
            ("POW", None) => return Err(syntax(c.i, "POW takes two arguments: POW[a,b]")),
            (_, Some(_)) => return Err(syntax(at, format!("{name} takes one argument"))),
            (_, None) => f(a),
        };
        match v {
            Some(v) => finite(v, at),
            None => Err(fault(
                AlarmCode::Arithmetic,
                at,
                format!("{name}[{a}] is outside the function's domain"),
            )),
        }
    }

    /// A function's bracket and a second argument: `[a,b]`, or with `slash_form` (ATAN)
    /// `[a]/[b]`.
    fn arguments(&mut self, c: &mut Cursor, slash_form: bool) -> R<(Value, Option<f64>)> {
        self.depth += 1;
        if self.depth > MAX_BRACKETS {
            return Err(syntax(
                c.i,
                format!("brackets nested deeper than {MAX_BRACKETS} levels"),
            ));
        }
        c.i += 1;
        let a = self.cmp(c)?;
        c.skip_blanks();
        let mut second = None;
        if c.peek() == Some(b',') {
            c.i += 1;
            second = Some(self.cmp(c)?.unwrap_or(0.0));
            c.skip_blanks();
        }
        if c.peek() != Some(b']') {
            return Err(syntax(c.i, "']' expected"));
        }
        c.i += 1;
        self.depth -= 1;
        let mut ahead = *c;
        ahead.skip_blanks();
        if slash_form && second.is_none() && ahead.peek() == Some(b'/') {
            ahead.i += 1;
            ahead.skip_blanks();
            if ahead.peek() == Some(b'[') {
                *c = ahead;
                second = Some(self.bracket(c)?.unwrap_or(0.0));
            }
        }
        Ok((a, second))
    }

    fn variable_number(&mut self, c: &mut Cursor) -> R<(i64, usize)> {
        let at = c.i;
        c.i += 1;
        let n = match c.peek() {
            Some(b'[') => {
                let v = self.bracket(c)?.unwrap_or(0.0);
                whole(v, at, "a variable number")?
            }
            Some(b'0'..=b'9') => {
                let mut n: i64 = 0;
                while let Some(d @ b'0'..=b'9') = c.peek() {
                    n = n.saturating_mul(10).saturating_add((d - b'0') as i64);
                    c.i += 1;
                }
                n
            }
            _ => return Err(syntax(at, "# must be followed by a number or [expression]")),
        };
        Ok((n, at))
    }
}

/// EQ: vacant equals only vacant; numbers within [`EQ_TOLERANCE`].
fn equal(a: Value, b: Value) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => (a - b).abs() <= EQ_TOLERANCE * a.abs().max(b.abs()).max(1.0),
        _ => false,
    }
}

/// AND/OR/XOR work on whole numbers bit by bit (on 1 and 0 of comparisons: logically).
fn bits(v: f64, at: usize, op: &str) -> R<i64> {
    whole(v, at, &format!("an operand of {op}"))
}

/// Two-argument ATAN: the angle of the vector (b, a) in 0 … 360° (0i-MF parameter NAT = 0).
fn atan2_degrees(a: f64, b: f64) -> f64 {
    let d = libm::atan2(a, b).to_degrees();
    if d < 0.0 {
        d + 360.0
    } else {
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Vars;
    impl Store for Vars {
        fn read(&self, n: i64, _: usize) -> R<Value> {
            Ok(match n {
                1 => Some(2.0),
                2 => Some(-3.5),
                _ => None,
            })
        }
    }

    fn ev(text: &str) -> R<Value> {
        let mut c = Cursor::new(text.as_bytes(), 0, text.len());
        let v = eval(&mut c, &Vars)?;
        assert_eq!(c.i, text.len(), "{text}: all read");
        Ok(v)
    }

    #[test]
    fn precedence_follows_the_manual() {
        assert_eq!(ev("1+2*3").unwrap(), Some(7.0));
        assert_eq!(ev("[1+2]*3").unwrap(), Some(9.0));
        assert_eq!(ev("#1*#2").unwrap(), Some(-7.0));
        assert_eq!(ev("10 MOD 4 + 1").unwrap(), Some(3.0));
        assert_eq!(ev("#1 EQ 2").unwrap(), Some(1.0));
        assert_eq!(ev("[#1 GT 1] AND [#2 LT 0]").unwrap(), Some(1.0));
        assert_eq!(ev("6 XOR 3").unwrap(), Some(5.0));
        assert_eq!(ev("#[#1-1]").unwrap(), Some(2.0));
    }

    #[test]
    fn vacant_is_zero_in_arithmetic_but_not_for_eq() {
        assert_eq!(ev("#5").unwrap(), None);
        assert_eq!(ev("-#5").unwrap(), None);
        assert_eq!(ev("#5+0").unwrap(), Some(0.0));
        assert_eq!(ev("#5*2").unwrap(), Some(0.0));
        assert_eq!(ev("#5 EQ #0").unwrap(), Some(1.0));
        assert_eq!(ev("#5 EQ 0").unwrap(), Some(0.0));
        assert_eq!(ev("#5 GE 0").unwrap(), Some(1.0));
        assert_eq!(ev("0.1+0.2 EQ 0.3").unwrap(), Some(1.0));
    }

    #[test]
    fn functions_work_in_degrees() {
        let near = |t: &str, want: f64| {
            let v = ev(t).unwrap().unwrap();
            assert!((v - want).abs() < 1e-12, "{t} = {v}, want {want}");
        };
        near("SIN[30]", 0.5);
        near("ATAN[1]/[-1]", 135.0);
        near("ATAN[-1,-1]", 225.0);
        near("SQRT[16]+ABS[-2]", 6.0);
        near("ROUND[-2.5]", -3.0);
        near("FIX[-1.7]", -1.0);
        near("FUP[-1.2]", -2.0);
        near("FUP[3]", 3.0);
        near("POW[2,10]", 1024.0);
        near("BIN[18]", 12.0);
        near("BCD[12]", 18.0);
        near("LN[EXP[2]]", 2.0);
    }

    #[test]
    fn bad_expressions_point_at_their_place() {
        assert_eq!(ev("1/[#1-2]").unwrap_err().at, 1);
        assert_eq!(ev("SQRT[-1]").unwrap_err().code, AlarmCode::Arithmetic);
        assert_eq!(ev("FOO[1]").unwrap_err().code, AlarmCode::UndefinedName);
        assert_eq!(ev("[[[[[[1]]]]]]").unwrap_err().code, AlarmCode::Syntax);
        assert!(ev("[[[[[1]]]]]").is_ok());
        assert_eq!(ev("1.5 AND 1").unwrap_err().code, AlarmCode::BadNumber);
        assert_eq!(ev("[1+2").unwrap_err().at, 4);
    }
}
