//! `softnc path` output: one JSON object per segment, alarms as records (docs/path-format.md).
//! Written by hand: it is on the path of long programs, and the format is small.

use crate::alarm::Alarm;
use crate::frontend::block::Pos;
use crate::json::{num_point as num, string};
use crate::segment::{Segment, Shape};
use std::io::{self, Write};

fn pos(out: &mut impl Write, p: &Pos) -> io::Result<()> {
    crate::json::pos(out, p, num)
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
