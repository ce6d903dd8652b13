//! The JSON pieces the hand-written JSON Lines writers share (`softnc parse`, `softnc path`).
//! Written by hand: they are on the path of million-block programs.

use crate::frontend::block::Pos;
use std::io::{self, Write};

/// A number in its shortest round-trip form (`1000`, `0.5`, `1e-7`); non-finite values as
/// `null`. Formatting floats is most of the cost of a million-line output: ryu, not `fmt`.
pub fn num<W: Write>(out: &mut W, v: f64) -> io::Result<()> {
    if !v.is_finite() {
        return out.write_all(b"null");
    }
    let mut buf = ryu::Buffer::new();
    // -0.0 prints as 0; an integral value without the ".0".
    let s = buf.format_finite(if v == 0.0 { 0.0 } else { v });
    out.write_all(s.strip_suffix(".0").unwrap_or(s).as_bytes())
}

/// As [`num`], but integral values keep a decimal point (`1000.0`), as the path format shows
/// floats.
pub fn num_point<W: Write>(out: &mut W, v: f64) -> io::Result<()> {
    if !v.is_finite() {
        return out.write_all(b"null");
    }
    let mut buf = ryu::Buffer::new();
    out.write_all(buf.format_finite(if v == 0.0 { 0.0 } else { v }).as_bytes())
}

/// `[x,y,z]` with each coordinate written by `num`.
pub fn pos<W: Write>(
    out: &mut W,
    p: &Pos,
    num: fn(&mut W, f64) -> io::Result<()>,
) -> io::Result<()> {
    out.write_all(b"[")?;
    num(out, p[0])?;
    out.write_all(b",")?;
    num(out, p[1])?;
    out.write_all(b",")?;
    num(out, p[2])?;
    out.write_all(b"]")
}

/// A JSON string with `"`, `\` and control characters escaped.
pub fn string(out: &mut impl Write, s: &str) -> io::Result<()> {
    out.write_all(b"\"")?;
    for ch in s.chars() {
        match ch {
            '"' => out.write_all(b"\\\"")?,
            '\\' => out.write_all(b"\\\\")?,
            c if (c as u32) < 0x20 => write!(out, "\\u{:04x}", c as u32)?,
            c => write!(out, "{c}")?,
        }
    }
    out.write_all(b"\"")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(f: fn(&mut Vec<u8>, f64) -> io::Result<()>, v: f64) -> String {
        let mut out = Vec::new();
        f(&mut out, v).unwrap();
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn numbers_are_shortest_round_trip() {
        assert_eq!(s(num, 1000.0), "1000");
        assert_eq!(s(num_point, 1000.0), "1000.0");
        assert_eq!(s(num, -0.0), "0");
        assert_eq!(s(num_point, -0.0), "0.0");
        assert_eq!(s(num, 0.1 + 0.2), "0.30000000000000004");
        assert_eq!(s(num, -12.5), "-12.5");
        assert_eq!(s(num, f64::NAN), "null");
        assert_eq!(s(num_point, f64::INFINITY), "null");
        for v in [1e-7, 31.055728090000844, -1e300, 5e-324, 123456789.0] {
            for f in [num, num_point] {
                let t = s(f, v);
                assert_eq!(t.parse::<f64>().unwrap(), v, "{t}");
                assert!(serde_json::from_str::<f64>(&t).is_ok(), "{t} is JSON");
            }
        }
    }
}
