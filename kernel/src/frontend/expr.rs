//! ISG arithmetic expressions (seed 002, TF5200 "calculation operations"), evaluated against
//! the [`Variables`] store.
//!
//! Grouping with `[ ]` as ISG writes it, and with `( )` where a parenthesis cannot be a
//! comment (right after an operator or a function name). Angles are in degrees. A condition
//! is true when its absolute value is at least 0.5 (TF5200 `$IF`).

use super::fault::{fault, R};
use super::lexer::Cursor;
use super::variables::Variables;
use crate::alarm::AlarmCode;

/// Nesting depth beyond which an expression is refused (keeps the recursion bounded).
const MAX_DEPTH: u32 = 64;

/// True if a variable reference starts at the cursor (`V.`).
pub fn at_variable(c: &Cursor) -> bool {
    matches!(c.letter(), Some(b'V')) && c.peek_at(1) == Some(b'.')
}

pub fn truthy(v: f64) -> bool {
    v.abs() >= 0.5
}

/// Evaluates a full expression (comparisons and logic included).
pub fn eval(c: &mut Cursor, vars: &Variables) -> R<f64> {
    Parser { vars, depth: 0 }.or(c)
}

/// Evaluates one operand (`X[...]`, `X SIN[...]`, `XV.P.A`, `X-V.P.A`): a signed primary.
pub fn eval_operand(c: &mut Cursor, vars: &Variables) -> R<f64> {
    Parser { vars, depth: 0 }.unary(c)
}

struct Parser<'v> {
    vars: &'v Variables,
    depth: u32,
}

impl Parser<'_> {
    fn enter(&mut self, c: &Cursor) -> R<()> {
        deeper(&mut self.depth, c.i)
    }

    fn or(&mut self, c: &mut Cursor) -> R<f64> {
        let mut v = self.and(c)?;
        loop {
            c.skip_blanks();
            if c.keyword("OR") || (c.peek() == Some(b'|') && c.peek_at(1) == Some(b'|')) {
                c.i += 2;
            } else {
                return Ok(v);
            }
            let r = self.and(c)?;
            v = (truthy(v) || truthy(r)) as u8 as f64;
        }
    }

    fn and(&mut self, c: &mut Cursor) -> R<f64> {
        let mut v = self.cmp(c)?;
        loop {
            c.skip_blanks();
            if c.keyword("AND") {
                c.i += 3;
            } else if c.peek() == Some(b'&') && c.peek_at(1) == Some(b'&') {
                c.i += 2;
            } else {
                return Ok(v);
            }
            let r = self.cmp(c)?;
            v = (truthy(v) && truthy(r)) as u8 as f64;
        }
    }

    fn cmp(&mut self, c: &mut Cursor) -> R<f64> {
        let l = self.add(c)?;
        c.skip_blanks();
        let op: &[u8] = match (c.peek(), c.peek_at(1)) {
            (Some(b'='), Some(b'=')) => b"==",
            (Some(b'!'), Some(b'=')) => b"!=",
            (Some(b'<'), Some(b'>')) => b"<>",
            (Some(b'<'), Some(b'=')) => b"<=",
            (Some(b'>'), Some(b'=')) => b">=",
            (Some(b'<'), _) => b"<",
            (Some(b'>'), _) => b">",
            _ => return Ok(l),
        };
        c.i += op.len();
        let r = self.add(c)?;
        let t = match op {
            b"==" => l == r,
            b"!=" | b"<>" => l != r,
            b"<=" => l <= r,
            b">=" => l >= r,
            b"<" => l < r,
            _ => l > r,
        };
        Ok(t as u8 as f64)
    }

    fn add(&mut self, c: &mut Cursor) -> R<f64> {
        let mut v = self.mul(c)?;
        loop {
            c.skip_blanks();
            match c.peek() {
                Some(b'+') => {
                    let at = c.i;
                    c.i += 1;
                    v = finite(v + self.mul(c)?, at, "sum")?;
                }
                Some(b'-') => {
                    let at = c.i;
                    c.i += 1;
                    v = finite(v - self.mul(c)?, at, "difference")?;
                }
                _ => return Ok(v),
            }
        }
    }

    fn mul(&mut self, c: &mut Cursor) -> R<f64> {
        let mut v = self.unary(c)?;
        loop {
            c.skip_blanks();
            let at = c.i;
            match (c.peek(), c.peek_at(1)) {
                (Some(b'*'), Some(b'*')) => return Ok(v),
                (Some(b'*'), _) => {
                    c.i += 1;
                    v = finite(v * self.unary(c)?, at, "product")?;
                }
                (Some(b'/'), _) => {
                    c.i += 1;
                    let r = self.unary(c)?;
                    if r == 0.0 {
                        return Err(fault(AlarmCode::Arithmetic, at, "division by zero"));
                    }
                    v = finite(v / r, at, "quotient")?;
                }
                _ if c.keyword("MOD") => {
                    c.i += 3;
                    let r = self.unary(c)?;
                    if r == 0.0 {
                        return Err(fault(AlarmCode::Arithmetic, at, "MOD by zero"));
                    }
                    v %= r;
                }
                _ => return Ok(v),
            }
        }
    }

    fn unary(&mut self, c: &mut Cursor) -> R<f64> {
        self.enter(c)?;
        c.skip_blanks();
        let v = match c.peek() {
            Some(b'-') => {
                c.i += 1;
                -self.unary(c)?
            }
            Some(b'+') => {
                c.i += 1;
                self.unary(c)?
            }
            Some(b'!') => {
                c.i += 1;
                (!truthy(self.unary(c)?)) as u8 as f64
            }
            _ if c.keyword("NOT") => {
                c.i += 3;
                (!truthy(self.unary(c)?)) as u8 as f64
            }
            _ => self.power(c)?,
        };
        self.depth -= 1;
        Ok(v)
    }

    fn power(&mut self, c: &mut Cursor) -> R<f64> {
        let base = self.primary(c)?;
        c.skip_blanks();
        if c.peek() == Some(b'*') && c.peek_at(1) == Some(b'*') {
            let at = c.i;
            c.i += 2;
            let e = self.unary(c)?;
            let v = libm::pow(base, e);
            return finite(v, at, "power");
        }
        Ok(base)
    }

    fn group(&mut self, c: &mut Cursor, open: u8) -> R<f64> {
        let close = if open == b'[' { b']' } else { b')' };
        let at = c.i;
        c.i += 1;
        let v = self.or(c)?;
        c.skip_blanks();
        if c.peek() != Some(close) {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("'{}' is not closed", open as char),
            ));
        }
        c.i += 1;
        Ok(v)
    }

    fn primary(&mut self, c: &mut Cursor) -> R<f64> {
        c.skip_blanks();
        let at = c.i;
        match c.peek() {
            Some(b'[') => self.group(c, b'['),
            Some(b'(') => self.group(c, b'('),
            Some(ch) if ch.is_ascii_digit() || ch == b'.' => {
                let (n, next) = super::number::parse(c.b, c.i)
                    .filter(|(_, next)| *next <= c.end)
                    .ok_or_else(|| fault(AlarmCode::BadNumber, at, "bad number"))?;
                c.i = next;
                Ok(n.value)
            }
            Some(_) if at_variable(c) => {
                let name = c.name();
                self.vars.get(&name).ok_or_else(|| {
                    fault(
                        AlarmCode::UndefinedName,
                        at,
                        format!("variable {name} is read before it is defined"),
                    )
                })
            }
            Some(ch) if ch.is_ascii_alphabetic() => {
                let name = c.name();
                let f = func(&name).ok_or_else(|| {
                    fault(
                        AlarmCode::Syntax,
                        at,
                        format!("unknown function or name `{name}`"),
                    )
                })?;
                c.skip_blanks();
                match c.peek() {
                    Some(open @ (b'[' | b'(')) => {
                        let arg = self.group(c, open)?;
                        apply(f, arg, at)
                    }
                    _ => Err(fault(
                        AlarmCode::Syntax,
                        c.i,
                        format!("{name} needs an argument in [ ]"),
                    )),
                }
            }
            Some(ch) => Err(fault(
                AlarmCode::Syntax,
                at,
                format!("unexpected '{}' in expression", ch as char),
            )),
            None => Err(fault(AlarmCode::Syntax, at, "expression expected")),
        }
    }
}

#[derive(Clone, Copy)]
enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sqrt,
    Sqr,
    Abs,
    Int,
    Fract,
    Round,
    Exp,
    Ln,
}

fn func(name: &str) -> Option<Func> {
    Some(match name {
        "SIN" => Func::Sin,
        "COS" => Func::Cos,
        "TAN" => Func::Tan,
        "ASIN" => Func::Asin,
        "ACOS" => Func::Acos,
        "ATAN" => Func::Atan,
        "SQRT" => Func::Sqrt,
        "SQR" => Func::Sqr,
        "ABS" => Func::Abs,
        "INT" => Func::Int,
        "FRACT" => Func::Fract,
        "ROUND" => Func::Round,
        "EXP" | "DEXP" => Func::Exp,
        "LN" => Func::Ln,
        _ => return None,
    })
}

/// One nesting level more in an expression parser (any language's): refused beyond
/// `MAX_DEPTH`, which keeps the recursion bounded.
pub(super) fn deeper(depth: &mut u32, at: usize) -> R<()> {
    *depth += 1;
    if *depth > MAX_DEPTH {
        return Err(fault(AlarmCode::Syntax, at, "expression nested too deeply"));
    }
    Ok(())
}

/// `v`, the result `what` of an operation, if it is a finite number (alarm 14000 if not).
pub(super) fn finite(v: f64, at: usize, what: &str) -> R<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(fault(
            AlarmCode::Arithmetic,
            at,
            format!("{what}: result is not a finite number"),
        ))
    }
}

fn apply(f: Func, x: f64, at: usize) -> R<f64> {
    let rad = x.to_radians();
    let v = match f {
        Func::Sin => libm::sin(rad),
        Func::Cos => libm::cos(rad),
        Func::Tan => libm::tan(rad),
        Func::Asin | Func::Acos if !(-1.0..=1.0).contains(&x) => {
            return Err(fault(
                AlarmCode::Arithmetic,
                at,
                format!("argument {x} outside -1..1"),
            ))
        }
        Func::Asin => libm::asin(x).to_degrees(),
        Func::Acos => libm::acos(x).to_degrees(),
        Func::Atan => libm::atan(x).to_degrees(),
        Func::Sqrt if x < 0.0 => {
            return Err(fault(
                AlarmCode::Arithmetic,
                at,
                format!("square root of {x}"),
            ))
        }
        Func::Sqrt => libm::sqrt(x),
        Func::Sqr => x * x,
        Func::Abs => x.abs(),
        Func::Int => libm::trunc(x),
        Func::Fract => x - libm::trunc(x),
        Func::Round => libm::round(x),
        Func::Exp => libm::exp(x),
        Func::Ln if x <= 0.0 => {
            return Err(fault(
                AlarmCode::Arithmetic,
                at,
                format!("logarithm of {x}"),
            ))
        }
        Func::Ln => libm::log(x),
    };
    finite(v, at, "function")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(s: &str) -> R<f64> {
        let mut vars = Variables::default();
        vars.set("V.P.A", 2.0, 0).unwrap();
        vars.tool_radius = 10.0;
        let mut c = Cursor::new(s.as_bytes(), 0, s.len());
        eval(&mut c, &vars)
    }

    #[test]
    fn arithmetic_and_precedence() {
        assert_eq!(ev("1+2*3").unwrap(), 7.0);
        assert_eq!(ev("[1+2]*3").unwrap(), 9.0);
        assert_eq!(ev("(1+2)*3").unwrap(), 9.0);
        assert_eq!(ev("-V.P.A**2").unwrap(), -4.0);
        assert_eq!(ev("V.G.WZ_AKT.R - 0.01").unwrap(), 10.0 - 0.01);
        assert_eq!(ev("-2*COS[60] + 60 + SIN[90]").unwrap(), 60.0);
        assert_eq!(ev("V.P.A >= 2 AND 1 < 0.2").unwrap(), 0.0);
        assert_eq!(ev("V.P.A == 2 || 0").unwrap(), 1.0);
    }

    #[test]
    fn errors() {
        assert_eq!(ev("1/0").unwrap_err().code, AlarmCode::Arithmetic);
        assert_eq!(ev("SQRT[-1]").unwrap_err().code, AlarmCode::Arithmetic);
        assert_eq!(ev("V.P.NOPE").unwrap_err().code, AlarmCode::UndefinedName);
        assert_eq!(ev("[1+2").unwrap_err().code, AlarmCode::Syntax);
        let deep = "[".repeat(200) + "1" + &"]".repeat(200);
        assert_eq!(ev(&deep).unwrap_err().code, AlarmCode::Syntax);
    }
}
