//! `softnc parse` output: one JSON object per interpreted block (docs/parse-format.md).
//! Written by hand: it is on the path of million-block programs, and the format is small.

use super::block::*;
use crate::dialect::Dialect;
use crate::json::{num, string};
use crate::machine_data::DialectName;
use crate::machine_data::Units;
use std::io::{self, Write};

fn pos(out: &mut impl Write, p: &Pos) -> io::Result<()> {
    crate::json::pos(out, p, num)
}

/// Writes one block as a JSON object and a newline.
/// `dialect` names the work offset as the program selects it.
pub fn write_block(out: &mut impl Write, b: &Block, dialect: DialectName) -> io::Result<()> {
    write!(out, "{{\"line\":{},\"col\":{},\"block\":", b.line, b.col)?;
    match b.number {
        Some(n) => string(out, &n.to_string())?,
        None => out.write_all(b"null")?,
    }
    out.write_all(b",\"motion\":")?;
    match &b.motion {
        None => out.write_all(b"null")?,
        Some(m) => motion(out, m)?,
    }
    modal(out, &b.modal, Dialect::get(dialect))?;
    out.write_all(b",\"words\":[")?;
    for (i, w) in b.words.iter().enumerate() {
        if i > 0 {
            out.write_all(b",")?;
        }
        write!(out, "\"{w}\"")?;
    }
    out.write_all(b"]")?;
    programmed(out, b)?;
    out.write_all(b"}\n")
}

fn motion(out: &mut impl Write, m: &Motion) -> io::Result<()> {
    write!(
        out,
        "{{\"type\":\"{}\",\"plane\":\"{}\",\"start\":",
        m.kind.name(),
        m.plane.name()
    )?;
    pos(out, &m.start)?;
    out.write_all(b",\"end\":")?;
    pos(out, &m.end)?;
    if m.kind.is_arc() {
        out.write_all(b",\"center\":")?;
        pos(out, &m.center)?;
    }
    out.write_all(b"}")
}

fn modal(out: &mut impl Write, s: &ModalState, d: &Dialect) -> io::Result<()> {
    write!(
        out,
        ",\"modal\":{{\"motion\":\"{}\",\"plane\":\"{}\",\"distance\":\"{}\",\"units\":\"{}\",\"feed\":",
        s.motion.name(),
        s.plane.name(),
        match s.distance {
            Distance::Absolute => "absolute",
            Distance::Incremental => "incremental",
        },
        match s.units {
            Units::Mm => "mm",
            Units::Inch => "inch",
        }
    )?;
    num(out, s.feed)?;
    out.write_all(b",\"spindle\":")?;
    num(out, s.spindle)?;
    write!(
        out,
        ",\"trc\":\"{}\",\"corner\":\"{}\",\"selection\":\"{}\",\"feed_adaption\":\"{}\",\"masking\":{},\"exact_stop\":{},\"work_offset\":",
        s.trc.name(),
        s.corner.name(),
        s.selection.name(),
        match s.feed_adaption {
            FeedAdaption::Centre => "centre",
            FeedAdaption::Contour => "contour",
        },
        s.masking,
        s.exact_stop,
    )?;
    match d.work_offset_name(s.work_offset) {
        Some(name) => write!(out, "\"{name}\"")?,
        None => out.write_all(b"null")?,
    }
    write!(out, ",\"diameter\":{},\"tool\":", s.diameter)?;
    match s.tool {
        Some(t) => write!(out, "{t}")?,
        None => out.write_all(b"null")?,
    }
    write!(out, ",\"d\":{},\"radius\":", s.d)?;
    num(out, s.radius)?;
    out.write_all(b",\"length\":")?;
    num(out, s.length)?;
    out.write_all(b"}")
}

/// What the block programmed besides motion and words; each key only when present.
fn programmed(out: &mut impl Write, b: &Block) -> io::Result<()> {
    if let Some(t) = b.trc {
        write!(out, ",\"trc_programmed\":\"{}\"", t.name())?;
    }
    if let Some(a) = b.approach {
        write!(out, ",\"approach\":\"{}\"", a.name())?;
    }
    if let Some(v) = &b.exit_vector {
        out.write_all(b",\"exit_vector\":")?;
        pos(out, v)?;
    }
    if b.exact_stop {
        out.write_all(b",\"exact_stop\":true")?;
    }
    if let Some(f) = b.thread {
        out.write_all(b",\"thread\":")?;
        num(out, f)?;
    }
    if let Some(dw) = b.dwell {
        out.write_all(b",\"dwell\":")?;
        num(out, dw)?;
    }
    if let Some(st) = b.stop {
        write!(out, ",\"stop\":\"{}\"", st.code())?;
    }
    if let Some(m) = &b.message {
        out.write_all(b",\"message\":")?;
        string(out, m)?;
    }
    if b.offset_changed {
        out.write_all(b",\"offset_changed\":true")?;
    }
    if b.calculation {
        out.write_all(b",\"calculation\":true")?;
    }
    if b.preprocess_stop {
        out.write_all(b",\"preprocess_stop\":true")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fanuc's exit vector appears in its cancel block only (docs/parse-format.md).
    #[test]
    fn the_exit_vector_is_written_with_its_block() {
        let b =
            super::super::run("fanuc", "G41 D1 G1 X0. Y10. F100.\nG40 X0. Y0. I10. J0.\n").unwrap();
        let text = |b: &Block| {
            let mut out = Vec::new();
            write_block(&mut out, b, DialectName::Fanuc).unwrap();
            String::from_utf8(out).unwrap()
        };
        assert!(!text(&b[0]).contains("exit_vector"));
        assert!(
            text(&b[1]).contains(",\"exit_vector\":[10,0,0]"),
            "{}",
            text(&b[1])
        );
    }
}
