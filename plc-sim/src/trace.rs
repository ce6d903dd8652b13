//! plc-sim's trace: one CSV row per drive cycle (docs/ipc.md).
//!
//! The columns name the machine's axes: the setpoint of each configured axis under its
//! letter, its actual position under `A` and the letter, its following error under `F` and
//! the letter, in the machine's order (wire order). Then per spindle of the machine data
//! (1-based number i) its speed setpoint under `S`i and its actual speed under `AS`i, in
//! rev/min, signed (positive clockwise). A three-axis mill's header is
//! `time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,S1,AS1,v_path,line,state,events`; a lathe with a
//! C axis has `X,Z,C,AX,AZ,AC,FX,FZ,FC` in place of the axes' columns. Readers find an axis
//! by its column name; traces from before the spindle columns have none.

use crate::plc::Row;
use softnc_protocol::{state, AxisList, MAX_SPINDLES};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// What a column of an axis holds, by its name's prefix.
pub const SETPOINT: &str = "";
pub const ACTUAL: &str = "A";
pub const FOLLOWING_ERROR: &str = "F";

/// What a column of a spindle holds, by its name's prefix before the spindle's number.
pub const SPINDLE_SETPOINT: &str = "S";
pub const SPINDLE_ACTUAL: &str = "AS";

/// The header line of a machine with `axes` and `spindles` spindles (at most
/// `MAX_SPINDLES`).
pub fn header(axes: &AxisList, spindles: usize) -> String {
    let mut h = String::from("time,cycle,seq");
    for prefix in [SETPOINT, ACTUAL, FOLLOWING_ERROR] {
        for name in axes.names() {
            h.push(',');
            h.push_str(prefix);
            h.push(name);
        }
    }
    for i in 1..=spindles.min(MAX_SPINDLES) {
        h.push_str(&format!(",{SPINDLE_SETPOINT}{i},{SPINDLE_ACTUAL}{i}"));
    }
    h.push_str(",v_path,line,state,events");
    h
}

/// A new trace file at `path` for a machine with `axes` and `spindles` spindles, its
/// header written. Every row has the spindles of `Row::spindles`: pass the same count.
pub fn create(path: &Path, axes: &AxisList, spindles: usize) -> Result<BufWriter<File>, String> {
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut w = BufWriter::new(File::create(path).map_err(err)?);
    writeln!(w, "{}", header(axes, spindles)).map_err(err)?;
    Ok(w)
}

/// A row: setpoint, actual position, following error of every axis, speed setpoint and
/// actual speed of every spindle, path speed in mm/min. Writes straight into `w` (no
/// allocation: it runs every drive cycle).
pub fn write(w: &mut impl Write, r: &Row<'_>) -> std::io::Result<()> {
    write!(w, "{:.6},{},{}", r.time, r.cycle, r.seq)?;
    for values in [&r.setpoint, &r.actual, &r.following_error] {
        for v in values.iter().take(r.axes) {
            write!(w, ",{v}")?;
        }
    }
    let speeds = r.spindle_setpoint.iter().zip(&r.spindle_actual);
    for (set, act) in speeds.take(r.spindles) {
        write!(w, ",{set},{act}")?;
    }
    writeln!(
        w,
        ",{},{},{},{}",
        r.v_path * 60.0,
        r.line,
        state::name(r.state),
        r.events.trim_end_matches(';')
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use softnc_protocol::MAX_AXES;

    fn list(names: &str) -> AxisList {
        let mut l = AxisList::default();
        for (n, c) in names.bytes().enumerate() {
            l.names[n] = c;
        }
        l.count = names.len() as u8;
        l
    }

    #[test]
    fn a_mill_keeps_its_columns_and_other_axes_are_named_after_their_letter() {
        assert_eq!(
            header(&list("XYZ"), 0),
            "time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,v_path,line,state,events"
        );
        assert_eq!(
            header(&list("XZC"), 0),
            "time,cycle,seq,X,Z,C,AX,AZ,AC,FX,FZ,FC,v_path,line,state,events"
        );
    }

    #[test]
    fn each_spindle_has_its_setpoint_and_actual_speed_before_the_path_speed() {
        assert_eq!(
            header(&list("XYZ"), crate::spindle::CONFIGURED),
            "time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,S1,AS1,v_path,line,state,events"
        );
        assert_eq!(
            header(&list("XZC"), 2),
            "time,cycle,seq,X,Z,C,AX,AZ,AC,FX,FZ,FC,S1,AS1,S2,AS2,v_path,line,state,events"
        );
        assert_eq!(header(&list("X"), 5), header(&list("X"), MAX_SPINDLES));
    }

    #[test]
    fn a_row_has_one_value_per_configured_axis_and_column() {
        let mut sp = [0.0; MAX_AXES];
        sp[..3].copy_from_slice(&[1.5, -2.0, 370.25]);
        let mut act = [9.0; MAX_AXES];
        act[..3].copy_from_slice(&[1.0, -1.5, 370.0]);
        let fe = [0.5; MAX_AXES];
        let r = Row {
            time: 0.001,
            cycle: 7,
            seq: 3,
            axes: 3,
            setpoint: sp,
            actual: act,
            following_error: fe,
            spindles: 1,
            spindle_setpoint: [-1200.0, 50.0],
            spindle_actual: [-996.5, 40.0],
            v_path: 1.0,
            line: 4,
            state: state::ACTIVE,
            events: "ack M3;",
        };
        let mut out = Vec::new();
        write(&mut out, &r).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "0.001000,7,3,1.5,-2,370.25,1,-1.5,370,0.5,0.5,0.5,-1200,-996.5,60,4,ACTIVE,ack M3\n"
        );
        let mut out = Vec::new();
        write(&mut out, &Row { spindles: 2, ..r }).unwrap();
        let row = String::from_utf8(out).unwrap();
        assert!(row.contains(",0.5,-1200,-996.5,50,40,60,4,"), "{row}");
    }
}
