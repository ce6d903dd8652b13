//! `softnc path` output: one JSON object per segment, alarms as records (docs/path-format.md).
//! Written by hand: it is on the path of long programs, and the format is small.

use crate::alarm::Alarm;
use crate::frontend::block::{AxisMove, Pos, AXIS_NAMES};
use crate::json::{num_point as num, string};
use crate::machine_data::AuxOutput;
use crate::prep::s_points::{AuxFunction, Prepared, Stop};
use crate::segment::{Segment, Shape, Source};
use std::io::{self, Write};

fn pos(out: &mut impl Write, p: &Pos) -> io::Result<()> {
    crate::json::pos(out, p, num)
}

/// One segment as a JSON object and a newline.
pub fn write_segment(out: &mut impl Write, s: &Segment) -> io::Result<()> {
    let kind = if s.is_arc() { "arc" } else { "line" };
    write!(out, "{{\"type\":\"{kind}\",\"block\":")?;
    block(out, &s.source)?;
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
        center_end,
        ccw,
        r0,
        r1,
        ..
    } = s.shape
    {
        out.write_all(b",\"center\":")?;
        pos(out, &center)?;
        if center_end != center {
            out.write_all(b",\"center_end\":")?;
            pos(out, &center_end)?;
        }
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
    if s.per_rev {
        out.write_all(b",\"feed_per_rev\":true")?;
    }
    if s.thread {
        out.write_all(b",\"thread\":true")?;
    }
    if s.exact_stop {
        writeln!(out, ",\"rapid\":{},\"exact_stop\":true}}", s.rapid)
    } else {
        writeln!(out, ",\"rapid\":{}}}", s.rapid)
    }
}

fn block(out: &mut impl Write, s: &Source) -> io::Result<()> {
    match s.number {
        Some(n) => write!(out, "\"{n}\""),
        None => out.write_all(b"null"),
    }
}

/// Any prepared record: segment, auxiliary functions, stop or program end.
pub fn write_prepared(out: &mut impl Write, p: &Prepared) -> io::Result<()> {
    match p {
        Prepared::Segment(s) => write_segment(out, s),
        Prepared::Axes(m, s) => write_axes(out, m, s),
        Prepared::Aux(a) => write_aux(out, a),
        Prepared::Stop(s) => write_stop(out, "stop", s),
        Prepared::End(s) => write_stop(out, "end", s),
        Prepared::Warning(a) => write_record(out, "warning", a),
    }
}

/// `{"type":"axes","block":"N20","line":3,"from":{"A":0.0,"C":90.0},"to":{"A":-30.0,"C":350.0}}`:
/// the additional axes that move with the next segment.
pub fn write_axes(out: &mut impl Write, m: &AxisMove, s: &Source) -> io::Result<()> {
    out.write_all(b"{\"type\":\"axes\",\"block\":")?;
    block(out, s)?;
    write!(out, ",\"line\":{}", s.line)?;
    for (key, values) in [("from", &m.from), ("to", &m.to)] {
        write!(out, ",\"{key}\":{{")?;
        let moving = (0..values.len()).filter(|&k| m.from[k] != m.to[k]);
        for (n, k) in moving.enumerate() {
            let sep = if n == 0 { "" } else { "," };
            write!(out, "{sep}\"{}\":", AXIS_NAMES[k + 3])?;
            num(out, values[k])?;
        }
        out.write_all(b"}")?;
    }
    out.write_all(b"}\n")
}

/// `{"type":"aux","block":"N25","line":14,"at":"S1","words":["M3","S2000","H2"],"pos":[..],"timing":"before"}`
pub fn write_aux(out: &mut impl Write, a: &AuxFunction) -> io::Result<()> {
    out.write_all(b"{\"type\":\"aux\",\"block\":")?;
    block(out, &a.source)?;
    write!(
        out,
        ",\"line\":{},\"at\":\"S{}\",\"words\":[",
        a.source.line, a.at
    )?;
    for (i, w) in a.words.iter().enumerate() {
        if i > 0 {
            out.write_all(b",")?;
        }
        write!(out, "\"{w}\"")?;
    }
    out.write_all(b"],\"pos\":")?;
    pos(out, &a.pos)?;
    let timing = match a.timing {
        AuxOutput::BeforeMotion => "before",
        AuxOutput::DuringMotion => "during",
    };
    write!(out, ",\"timing\":\"{timing}\"")?;
    if let Some(t) = &a.tech {
        let sp = &t.spindle;
        write!(
            out,
            ",\"tech\":{{\"spindle\":{{\"dir\":\"{}\",\"speed\":",
            sp.dir.name()
        )?;
        num(out, sp.speed)?;
        write!(out, ",\"css\":{},\"limit\":", sp.css)?;
        num(out, sp.limit)?;
        write!(
            out,
            "}},\"tool\":{},\"d\":{},\"work_offset\":{}}}",
            t.tool, t.d, t.work_offset
        )?;
    }
    writeln!(out, "}}")
}

/// `{"type":"stop","block":"N40","line":9,"code":"M0","at":"S5","pos":[..]}`, and the same
/// with `"type":"end"` for M02/M30.
pub fn write_stop(out: &mut impl Write, kind: &str, s: &Stop) -> io::Result<()> {
    write!(out, "{{\"type\":\"{kind}\",\"block\":")?;
    block(out, &s.source)?;
    write!(
        out,
        ",\"line\":{},\"code\":\"{}\",\"at\":\"S{}\",\"pos\":",
        s.source.line,
        s.code.code(),
        s.at
    )?;
    pos(out, &s.pos)?;
    out.write_all(b"}\n")
}

/// An alarm as a record.
pub fn write_alarm(out: &mut impl Write, a: &Alarm) -> io::Result<()> {
    write_record(out, "alarm", a)
}

/// An alarm or a warning as a record of that type.
fn write_record(out: &mut impl Write, kind: &str, a: &Alarm) -> io::Result<()> {
    write!(
        out,
        "{{\"type\":\"{kind}\",\"code\":{},\"block\":",
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
