//! `softnc path` output: one JSON object per segment, alarms as records (docs/path-format.md).
//! Written by hand: it is on the path of long programs, and the format is small.

use crate::alarm::Alarm;
use crate::frontend::block::Pos;
use crate::segment::{Segment, Shape};
use std::io::{self, Write};

fn num(out: &mut impl Write, v: f64) -> io::Result<()> {
    // Shortest round-trip form with a decimal point (`1000.0`); values are finite.
    let v = if v == 0.0 { 0.0 } else { v };
    if v.is_finite() {
        write!(out, "{v:?}")
    } else {
        out.write_all(b"null")
    }
}

fn pos(out: &mut impl Write, p: &Pos) -> io::Result<()> {
    out.write_all(b"[")?;
    num(out, p[0])?;
    out.write_all(b",")?;
    num(out, p[1])?;
    out.write_all(b",")?;
    num(out, p[2])?;
    out.write_all(b"]")
}

/// A JSON string; block numbers and messages are ASCII or UTF-8 text.
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

/// One segment as a JSON object and a newline.
pub fn write_segment(out: &mut impl Write, s: &Segment) -> io::Result<()> {
    let kind = if s.is_arc() { "arc" } else { "line" };
    write!(out, "{{\"type\":\"{kind}\",\"block\":")?;
    match s.source.number {
        Some(n) => write!(out, "\"{n}\"")?,
        None => out.write_all(b"null")?,
    }
    write!(
        out,
        ",\"line\":{},\"role\":\"{}\",\"from\":",
        s.source.line,
        s.role.name()
    )?;
    pos(out, &s.from)?;
    out.write_all(b",\"to\":")?;
    pos(out, &s.to)?;
    if let Shape::Arc {
        center,
        ccw,
        r0,
        r1,
        ..
    } = s.shape
    {
        out.write_all(b",\"center\":")?;
        pos(out, &center)?;
        write!(
            out,
            ",\"dir\":\"{}\",\"r0\":",
            if ccw { "ccw" } else { "cw" }
        )?;
        num(out, r0)?;
        out.write_all(b",\"r1\":")?;
        num(out, r1)?;
    }
    out.write_all(b",\"feed\":")?;
    num(out, s.feed)?;
    writeln!(out, ",\"rapid\":{}}}", s.rapid)
}

/// An alarm as a record.
pub fn write_alarm(out: &mut impl Write, a: &Alarm) -> io::Result<()> {
    write!(
        out,
        "{{\"type\":\"alarm\",\"code\":{},\"block\":",
        a.number()
    )?;
    match &a.block {
        Some(b) => string(out, b)?,
        None => out.write_all(b"null")?,
    }
    write!(out, ",\"line\":{},\"col\":{},\"message\":", a.line, a.col)?;
    string(out, &a.message)?;
    out.write_all(b"}\n")
}
