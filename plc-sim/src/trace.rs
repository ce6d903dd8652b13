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
use crossbeam::queue::ArrayQueue;
use softnc_protocol::{state, AxisList, MAX_SPINDLES};
use std::fs::File;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

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
/// header written, and its writer thread started (call it before the drive cycle asks for
/// SCHED_FIFO: the writer keeps the normal policy). Every row has the spindles of
/// `Row::spindles`: pass the same count.
pub fn create(path: &Path, axes: &AxisList, spindles: usize) -> Result<Trace, String> {
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    // No BufWriter: the writer thread hands the file whole chunks.
    let mut f = File::create(path).map_err(err)?;
    writeln!(f, "{}", header(axes, spindles)).map_err(err)?;
    Trace::new(f, CHUNKS, CHUNK).map_err(err)
}

/// Bytes a chunk of rows holds, and how many chunks there are: ~25 s of a 1 ms cycle's rows
/// may wait for the disk before rows are lost.
const CHUNK: usize = 64 * 1024;
const CHUNKS: usize = 64;

/// Rows written so far into a preallocated buffer.
struct Chunk {
    buf: Box<[u8]>,
    len: usize,
}

/// The trace as the drive cycle writes it: rows go into preallocated chunks, and a writer
/// thread of normal priority takes full chunks to the file and hands them back. The cycle
/// never waits for the disk: a write(2) blocked by dirty pages draining on a loaded machine
/// would hold the PLC's sign of life past the kernel's watchdog. With no free chunk (the disk
/// behind for seconds) a row is lost and counted; [`Trace::finish`] reports it.
pub struct Trace {
    current: Option<Chunk>,
    full: Arc<ArrayQueue<Chunk>>,
    free: Arc<ArrayQueue<Chunk>>,
    done: Arc<AtomicBool>,
    writer: Option<JoinHandle<std::io::Result<()>>>,
    lost: u64,
}

impl Trace {
    fn new(w: impl Write + Send + 'static, chunks: usize, size: usize) -> std::io::Result<Trace> {
        let full = Arc::new(ArrayQueue::new(chunks));
        let free = Arc::new(ArrayQueue::new(chunks));
        for _ in 0..chunks {
            let _ = free.push(Chunk {
                buf: vec![0; size].into_boxed_slice(),
                len: 0,
            });
        }
        let done = Arc::new(AtomicBool::new(false));
        let (f, e, d) = (full.clone(), free.clone(), done.clone());
        let writer = std::thread::Builder::new()
            .name("trace".into())
            .spawn(move || drain(w, &f, &e, &d))?;
        Ok(Trace {
            current: free.pop(),
            full,
            free,
            done,
            writer: Some(writer),
            lost: 0,
        })
    }

    /// One row, written into the current chunk (a full one goes to the writer first).
    pub fn row(&mut self, r: &Row<'_>) {
        for _ in 0..2 {
            if let Some(c) = &mut self.current {
                let mut at = std::io::Cursor::new(&mut c.buf[c.len..]);
                if write(&mut at, r).is_ok() {
                    c.len += at.position() as usize;
                    return;
                }
                if c.len == 0 {
                    // Longer than a chunk: it can never be written.
                    break;
                }
            }
            self.hand_over();
        }
        self.lost += 1;
    }

    /// The current chunk to the writer, a free one in its place (none while the writer is
    /// behind).
    fn hand_over(&mut self) {
        if let Some(c) = self.current.take() {
            if c.len > 0 {
                // Never full: there are only as many chunks as places.
                let _ = self.full.push(c);
            } else {
                self.current = Some(c);
                return;
            }
        }
        self.current = self.free.pop();
    }

    /// Ends the trace: every row written, the file flushed; an error if the file could not
    /// be written or rows were lost.
    pub fn finish(mut self) -> Result<(), String> {
        self.hand_over();
        self.done.store(true, Ordering::Release);
        let written = match self.writer.take().map(JoinHandle::join) {
            Some(Ok(r)) => r.map_err(|e| e.to_string()),
            Some(Err(_)) => Err("the trace's writer thread failed".into()),
            None => Ok(()),
        };
        written?;
        match self.lost {
            0 => Ok(()),
            n => Err(format!(
                "the trace is incomplete: {n} rows lost, the disk did not keep up"
            )),
        }
    }
}

/// The writer thread: full chunks to `w` in order, each handed back empty; at `done`, what
/// is left, then the flush. After a write error it stops taking chunks (the cycle then
/// loses its rows) and returns the error.
fn drain(
    mut w: impl Write,
    full: &ArrayQueue<Chunk>,
    free: &ArrayQueue<Chunk>,
    done: &AtomicBool,
) -> std::io::Result<()> {
    loop {
        let last = done.load(Ordering::Acquire);
        while let Some(mut c) = full.pop() {
            w.write_all(&c.buf[..c.len])?;
            c.len = 0;
            let _ = free.push(c);
        }
        if last {
            return w.flush();
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
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
    fn row(cycle: u64, events: &str) -> Row<'_> {
        Row {
            time: cycle as f64 * 0.001,
            cycle,
            seq: cycle,
            axes: 1,
            setpoint: [0.0; MAX_AXES],
            actual: [0.0; MAX_AXES],
            following_error: [0.0; MAX_AXES],
            spindles: 0,
            spindle_setpoint: [0.0; 2],
            spindle_actual: [0.0; 2],
            v_path: 0.0,
            line: 1,
            state: state::ACTIVE,
            events,
        }
    }

    /// A writer that shares what it was given, or blocks until `open` while it is shut.
    #[derive(Clone, Default)]
    struct Shared {
        out: Arc<std::sync::Mutex<Vec<u8>>>,
        open: Arc<AtomicBool>,
    }

    impl Write for Shared {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            while !self.open.load(Ordering::Acquire) {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
            self.out.lock().unwrap().extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    fn cycles(out: &[u8]) -> Vec<u64> {
        let text = String::from_utf8(out.to_vec()).unwrap();
        text.lines()
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect()
    }

    #[test]
    fn every_row_reaches_the_file_in_the_order_of_the_cycles() {
        let w = Shared::default();
        w.open.store(true, Ordering::Release);
        let mut t = Trace::new(w.clone(), 3, 100).unwrap();
        for c in 0..1000 {
            // Each chunk is used many times over: a row lost while the writer is behind is
            // offered again.
            while {
                t.row(&row(c, ""));
                t.lost > 0
            } {
                t.lost = 0;
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        }
        t.finish().unwrap();
        assert_eq!(
            cycles(&w.out.lock().unwrap()),
            (0..1000).collect::<Vec<_>>()
        );
    }

    #[test]
    fn a_disk_that_falls_behind_loses_rows_and_the_end_of_the_trace_says_so() {
        let w = Shared::default();
        let mut t = Trace::new(w.clone(), 2, 100).unwrap();
        for c in 0..100 {
            t.row(&row(c, ""));
        }
        w.open.store(true, Ordering::Release);
        let e = t.finish().unwrap_err();
        assert!(e.contains("rows lost"), "{e}");
        let kept = cycles(&w.out.lock().unwrap());
        assert!(!kept.is_empty() && kept.len() < 100, "{kept:?}");
        assert!(kept.windows(2).all(|p| p[0] < p[1]), "{kept:?}");
    }

    #[test]
    fn a_row_longer_than_a_chunk_is_lost_not_split() {
        let w = Shared::default();
        w.open.store(true, Ordering::Release);
        let mut t = Trace::new(w.clone(), 2, 100).unwrap();
        t.row(&row(1, ""));
        t.row(&row(2, &"M".repeat(200)));
        t.row(&row(3, ""));
        assert_eq!(
            t.finish().unwrap_err(),
            "the trace is incomplete: 1 rows lost, the disk did not keep up"
        );
        assert_eq!(cycles(&w.out.lock().unwrap()), [1, 3]);
    }
}
