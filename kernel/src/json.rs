//! The JSON pieces the hand-written JSON Lines writers share (`softnc parse`, `softnc path`).
//! Written by hand: they are on the path of million-block programs.

use crate::frontend::block::Pos;
use std::io::{self, Write};

/// A number in its shortest round-trip form (`1000`); non-finite values as `null`.
pub fn num<W: Write>(out: &mut W, v: f64) -> io::Result<()> {
    // -0.0 prints as 0.
    let v = if v == 0.0 { 0.0 } else { v };
    if v.is_finite() {
        write!(out, "{v}")
    } else {
        out.write_all(b"null")
    }
}

/// As [`num`], but always with a decimal point (`1000.0`), as the path format shows floats.
pub fn num_point<W: Write>(out: &mut W, v: f64) -> io::Result<()> {
    let v = if v == 0.0 { 0.0 } else { v };
    if v.is_finite() {
        write!(out, "{v:?}")
    } else {
        out.write_all(b"null")
    }
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
