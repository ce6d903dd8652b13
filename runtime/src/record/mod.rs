//! Record and replay (docs/interfaces.md, "Record and replay"): every input the live kernel
//! took, with its cycle, in a JSON Lines file; `softnc simulate --replay` feeds them to the
//! same cycle ([`Cyclic`](nc_kernel::cycle::Cyclic)) and gets the live setpoints bit for bit.
//!
//! ```text
//!  IPO thread: commands, PLC signals, acks, records taken ─► [ArrayQueue] ─┐
//!              setpoints ─────────────────────────────────► [ArrayQueue] ─┤
//!  control thread: program loads, resumes, offset edits ──────────────────┴─► Writer ─► file
//! ```
//!
//! The IPO thread only copies into preallocated queues (never allocates, blocks or writes);
//! the control thread drains them into the file. A queue that overflowed marks the record
//! incomplete (`lost`), and a replay refuses it.

mod format;
mod replay;

pub use format::{axes, Cmd, Header, Line, F, VERSION};
pub use replay::replay;

use crossbeam::queue::ArrayQueue;
use nc_kernel::cycle::{AuxOut, Bus, ChannelAlarm, PlcInput, Status};
use nc_kernel::ipo::Setpoint;
use nc_kernel::MachineData;
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// What the IPO thread hands over, per cycle.
#[derive(Clone, Copy, Debug)]
enum Event {
    Plc(u64, PlcInput),
    /// Cycles `from..to` without PLC signals.
    NoPlc(u64, u64),
    Ack(u64, u64, Option<ChannelAlarm>),
    AuxFull(u64),
    Prep(u64, u32),
    Command(u64, Cmd, bool),
    End(u64),
}

/// Events in flight between the threads (a few seconds' worth at 1 ms).
const EVENTS: usize = 1 << 16;
/// Setpoints in flight.
const SETPOINTS: usize = 1 << 12;

/// The queues both threads share.
struct Queues {
    events: ArrayQueue<Event>,
    setpoints: Option<ArrayQueue<Setpoint>>,
    lost: AtomicBool,
}

/// The IPO thread's side: every input of a cycle goes through here.
pub struct IpoRecorder {
    q: Arc<Queues>,
    /// The PLC signals last taken.
    plc: Option<PlcInput>,
    /// The first cycle of the current run without PLC signals.
    gap: Option<u64>,
}

impl IpoRecorder {
    fn push(&self, e: Event) {
        if self.q.events.push(e).is_err() {
            self.q.lost.store(true, Ordering::Relaxed);
        }
    }

    /// A command the cycle took before cycle `k` (`ok`: it was not refused).
    pub fn command(&mut self, k: u64, cmd: Cmd, ok: bool) {
        self.push(Event::Command(k, cmd, ok));
    }

    /// The records cycle `k` took from preparation.
    pub fn prep(&mut self, k: u64, records: u32) {
        if records > 0 {
            self.push(Event::Prep(k, records));
        }
    }

    /// The run's last cycle was `k`.
    pub fn end(&mut self, k: u64) {
        if let Some(from) = self.gap.take() {
            self.push(Event::NoPlc(from, k + 1));
        }
        self.push(Event::End(k));
    }

    /// `bus` with every input it gives cycle `k` recorded.
    pub fn wrap<'a, B: Bus>(&'a mut self, bus: &'a mut B, k: u64) -> Recording<'a, B> {
        Recording { rec: self, bus, k }
    }
}

/// A [`Bus`] whose inputs are recorded.
pub struct Recording<'a, B: Bus> {
    rec: &'a mut IpoRecorder,
    bus: &'a mut B,
    k: u64,
}

impl<B: Bus> Bus for Recording<'_, B> {
    fn plc(&mut self) -> Option<PlcInput> {
        let s = self.bus.plc();
        let (k, rec) = (self.k, &mut *self.rec);
        match s {
            None => {
                rec.gap.get_or_insert(k);
            }
            Some(s) => {
                if let Some(from) = rec.gap.take() {
                    rec.push(Event::NoPlc(from, k));
                }
                if rec.plc != Some(s) {
                    rec.plc = Some(s);
                    rec.push(Event::Plc(k, s));
                }
            }
        }
        s
    }

    fn setpoint(&mut self, sp: &Setpoint) {
        if let Some(q) = &self.rec.q.setpoints {
            if q.push(sp.clone()).is_err() {
                self.rec.q.lost.store(true, Ordering::Relaxed);
            }
        }
        self.bus.setpoint(sp);
    }

    fn aux(&mut self, out: &AuxOut<'_>) -> bool {
        let sent = self.bus.aux(out);
        if !sent {
            self.rec.push(Event::AuxFull(self.k));
        }
        sent
    }

    fn acks(&mut self, f: &mut dyn FnMut(u64, Option<ChannelAlarm>)) {
        let (k, rec) = (self.k, &mut *self.rec);
        self.bus.acks(&mut |id, a| {
            rec.push(Event::Ack(k, id, a));
            f(id, a);
        });
    }

    fn status(&mut self, st: &Status) {
        self.bus.status(st);
    }
}

/// The control thread's side: writes the record (and the live setpoints, if asked for).
pub struct Writer {
    q: Arc<Queues>,
    file: std::io::BufWriter<std::fs::File>,
    setpoints: Option<std::io::BufWriter<std::fs::File>>,
    extra: Vec<usize>,
    cycle_us: u64,
    row: String,
    path: std::path::PathBuf,
}

/// Opens the record `path` (and the live setpoint CSV `setpoints`) with its header; the
/// recorder goes to the IPO thread.
pub fn open(
    path: &std::path::Path,
    setpoints: Option<&std::path::Path>,
    header: &Header,
    md: &MachineData,
) -> Result<(Writer, IpoRecorder), String> {
    let create = |p: &std::path::Path| {
        std::fs::File::create(p)
            .map(std::io::BufWriter::new)
            .map_err(|e| format!("{}: {e}", p.display()))
    };
    let q = Arc::new(Queues {
        events: ArrayQueue::new(EVENTS),
        setpoints: setpoints.map(|_| ArrayQueue::new(SETPOINTS)),
        lost: AtomicBool::new(false),
    });
    let extra = nc_kernel::simulate::extra_axes(md);
    let mut sp_file = setpoints.map(create).transpose()?;
    if let Some(f) = &mut sp_file {
        writeln!(f, "{}", nc_kernel::simulate::csv_header(&extra)).map_err(|e| e.to_string())?;
    }
    let mut w = Writer {
        q: q.clone(),
        file: create(path)?,
        setpoints: sp_file,
        extra,
        cycle_us: u64::from(md.ipo.cycle_us),
        row: String::with_capacity(256),
        path: path.to_path_buf(),
    };
    w.line(&Line::Header(header.clone()));
    let rec = IpoRecorder {
        q,
        plc: None,
        gap: None,
    };
    Ok((w, rec))
}

impl Writer {
    /// One line of the control thread's own (a load, a resume, an offset edit).
    pub fn line(&mut self, l: &Line) {
        if let Ok(text) = serde_json::to_string(l) {
            if writeln!(self.file, "{text}").is_err() {
                self.q.lost.store(true, Ordering::Relaxed);
            }
        }
    }

    /// Writes what the IPO thread recorded since the last call.
    pub fn drain(&mut self) {
        while let Some(e) = self.q.events.pop() {
            let l = match e {
                Event::Plc(k, s) => Line::plc(k, &s),
                Event::NoPlc(from, to) => Line::NoPlc {
                    k: from,
                    cycles: to - from,
                },
                Event::Ack(k, id, a) => Line::Ack {
                    k,
                    id,
                    alarm: ChannelAlarm::wire(a),
                },
                Event::AuxFull(k) => Line::AuxFull { k },
                Event::Prep(k, records) => Line::Prep { k, records },
                Event::Command(k, command, ok) => Line::Command { k, command, ok },
                Event::End(k) => Line::End {
                    cycles: k + 1,
                    lost: self.q.lost.load(Ordering::Relaxed),
                },
            };
            self.line(&l);
        }
        let Some(q) = &self.q.setpoints else {
            return;
        };
        while let Some(sp) = q.pop() {
            nc_kernel::simulate::setpoint_row(&mut self.row, &sp, &self.extra, self.cycle_us);
            if let Some(f) = &mut self.setpoints {
                let _ = f.write_all(self.row.as_bytes());
            }
        }
    }

    /// The last lines, after the IPO thread ended; an error names what could not be written.
    pub fn finish(mut self) -> Result<(), String> {
        self.drain();
        let path = self.path.display().to_string();
        self.file.flush().map_err(|e| format!("{path}: {e}"))?;
        if let Some(f) = &mut self.setpoints {
            f.flush().map_err(|e| format!("setpoints: {e}"))?;
        }
        if self.q.lost.load(Ordering::Relaxed) {
            return Err(format!(
                "{path}: the record is incomplete (its queue overflowed): a replay refuses it"
            ));
        }
        Ok(())
    }
}

/// FNV-1a, 64 bits, as 16 hex digits: the header's fingerprints of program, machine data
/// and tables (to tell a mismatch, not to resist forgery).
pub fn fingerprint(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The fingerprints of the machine data, the tool table and the work offsets a run starts
/// with: (machine, tools, work offsets).
pub fn fingerprints(md: &MachineData, tools: &nc_kernel::ToolTable) -> (String, String, String) {
    let machine = toml::to_string(md).unwrap_or_default();
    let table = toml::to_string(tools).unwrap_or_default();
    let tools = format!("{table}{:?}", tools.radius_overrides);
    let work = format!("{:?}", md.work_offsets);
    (
        fingerprint(machine.as_bytes()),
        fingerprint(tools.as_bytes()),
        fingerprint(work.as_bytes()),
    )
}
