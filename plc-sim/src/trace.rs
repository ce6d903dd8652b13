//! plc-sim's trace: one CSV row per drive cycle (docs/ipc.md).

use crate::plc::Row;
use softnc_protocol::state;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

pub const HEADER: &str = "time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,v_path,line,state,events";

/// A new trace file at `path`, its header written.
pub fn create(path: &Path) -> Result<BufWriter<File>, String> {
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut w = BufWriter::new(File::create(path).map_err(err)?);
    writeln!(w, "{HEADER}").map_err(err)?;
    Ok(w)
}

/// A row: setpoint, actual position, following error, path speed in mm/min.
pub fn write(w: &mut impl Write, r: &Row<'_>) -> std::io::Result<()> {
    let (sp, act, fe) = (r.setpoint, r.actual, r.following_error);
    writeln!(
        w,
        "{:.6},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
        r.time,
        r.cycle,
        r.seq,
        sp[0],
        sp[1],
        sp[2],
        act[0],
        act[1],
        act[2],
        fe[0],
        fe[1],
        fe[2],
        r.v_path * 60.0,
        r.line,
        state::name(r.state),
        r.events.trim_end_matches(';')
    )
}
