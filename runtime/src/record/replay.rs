//! `softnc simulate --replay FILE`: the recorded inputs fed to the live kernel's own cycle
//! ([`Cyclic`]) at their recorded cycles, on a simulated clock. Each cycle takes exactly the
//! prepared records the live cycle took (waiting for them), so the lookahead, and with it
//! every setpoint, is the live run's.

use super::format::{axis_pos, Cmd, Header, Line, VERSION};
use super::{fingerprint, fingerprints};
use nc_kernel::cycle::{AuxOut, Bus, ChannelAlarm, Control, Cyclic, PlcInput, Program, Status};
use nc_kernel::handover::{Handover, Spawned};
use nc_kernel::ipo::{Channel, Setpoint};
use nc_kernel::{AxisPos, MachineData, ToolTable, WorkOffsets};
use std::collections::HashMap;
use std::io::Write;
use std::sync::Arc;

/// How a program of the record is built, with the tables in force then.
struct Desc {
    kind: Kind,
    tools: ToolTable,
    work: WorkOffsets,
}

enum Kind {
    Load {
        path: String,
        fingerprint: String,
        at: Option<AxisPos>,
    },
    Resume {
        of: u32,
        at: nc_kernel::Interruption,
        pos: AxisPos,
    },
}

/// What a built program was prepared from (a resume of it prepares the same text again).
#[derive(Clone)]
struct Origin {
    path: String,
    source: String,
    at: Option<AxisPos>,
    programs: Arc<nc_kernel::ProgramLibrary>,
}

/// A record, read.
#[derive(Default)]
struct Record {
    plc: Vec<(u64, PlcInput)>,
    gaps: Vec<(u64, u64)>,
    acks: Vec<(u64, u64, u32)>,
    aux_full: Vec<u64>,
    prep: HashMap<u64, u32>,
    commands: Vec<(u64, Cmd, bool)>,
    programs: HashMap<u32, Desc>,
    cycles: Option<u64>,
}

/// Replays `file` for program `name` (text `source`) on machine data `md` with `tools`,
/// writing the setpoint CSV to `out`; the number of cycles replayed.
pub fn replay(
    file: &std::path::Path,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
    out: &mut dyn Write,
) -> Result<u64, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let (header, rec) =
        read(&text, source, md, tools).map_err(|e| format!("{}: {e}", file.display()))?;
    let cycles = rec.cycles.unwrap_or(0);
    let mut r = Replay {
        md,
        rec: &rec,
        origins: HashMap::new(),
        threads: Vec::new(),
    };
    let res = r.run(&header, cycles, out);
    r.stop();
    res.map(|()| cycles)
}

/// Reads and checks the record: the header against the program, machine data and tables
/// given, every line, and that it is complete.
fn read(
    text: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
) -> Result<(Header, Record), String> {
    let mut lines = text.lines().enumerate();
    let header = match lines.next().map(|(_, l)| serde_json::from_str::<Line>(l)) {
        Some(Ok(Line::Header(h))) => h,
        _ => return Err("line 1: not the header of a softnc record".into()),
    };
    check_header(&header, source, md, tools)?;
    let mut rec = Record::default();
    let (mut tools, mut work) = (tools.clone(), md.work_offsets.clone());
    for (i, l) in lines {
        let line = serde_json::from_str::<Line>(l).map_err(|e| format!("line {}: {e}", i + 1))?;
        rec.take(line, md, &mut tools, &mut work)
            .map_err(|e| format!("line {}: {e}", i + 1))?;
    }
    if rec.cycles.is_none() {
        return Err("the record has no end line: the run was cut short".into());
    }
    Ok((header, rec))
}

fn check_header(
    h: &Header,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
) -> Result<(), String> {
    if h.version != VERSION {
        return Err(format!(
            "record version {} (this softnc reads {VERSION})",
            h.version
        ));
    }
    let (machine, tool_table, work) = fingerprints(md, tools);
    let checks = [
        (
            "program",
            &h.program_fingerprint,
            fingerprint(source.as_bytes()),
        ),
        ("machine data", &h.machine_fingerprint, machine),
        ("tool table", &h.tools_fingerprint, tool_table),
        ("work offsets", &h.work_offsets_fingerprint, work),
    ];
    for (what, recorded, here) in checks {
        // A run started without a program loads its programs later: each `load` line is
        // checked against its file when the replay loads it.
        if *recorded != here && !(what == "program" && recorded.is_empty()) {
            return Err(format!(
                "{what} other than the recorded run's (fingerprint {here}, recorded {recorded}): give the run's"
            ));
        }
    }
    if h.cycle_us != md.ipo.cycle_us {
        return Err(format!("recorded with an IPO cycle of {} µs", h.cycle_us));
    }
    Ok(())
}

impl Record {
    /// One line after the header; `tools` and `work` follow the edits in order.
    fn take(
        &mut self,
        line: Line,
        md: &MachineData,
        tools: &mut ToolTable,
        work: &mut WorkOffsets,
    ) -> Result<(), String> {
        let desc = |kind, tools: &ToolTable, work: &WorkOffsets| Desc {
            kind,
            tools: tools.clone(),
            work: work.clone(),
        };
        match line {
            Line::Header(_) => return Err("a second header".into()),
            Line::Plc {
                k,
                feed_hold,
                read_in_disable,
                drives_ready,
                emergency_stop,
                alarm,
                spindle_rpm,
            } => {
                let s = PlcInput {
                    feed_hold,
                    read_in_disable,
                    drives_ready,
                    emergency_stop,
                    alarm: ChannelAlarm::new(alarm),
                    spindle_rpm: spindle_rpm.0,
                };
                self.plc.push((k, s));
            }
            Line::NoPlc { k, cycles } => self.gaps.push((k, k + cycles)),
            Line::Ack { k, id, alarm } => self.acks.push((k, id, alarm)),
            Line::AuxFull { k } => self.aux_full.push(k),
            Line::Prep { k, records } => {
                self.prep.insert(k, records);
            }
            Line::Command { k, command, ok } => self.commands.push((k, command, ok)),
            Line::Load {
                id,
                path,
                program_fingerprint,
                at,
            } => {
                let at = at.as_ref().map(axis_pos);
                let d = desc(
                    Kind::Load {
                        path,
                        fingerprint: program_fingerprint,
                        at,
                    },
                    tools,
                    work,
                );
                self.programs.insert(id, d);
            }
            Line::Resume {
                id,
                of,
                seq,
                role,
                nth,
                along,
                pos,
            } => {
                let role = nc_kernel::Role::from_code(role).ok_or("unknown segment role")?;
                let at = nc_kernel::Interruption {
                    seq,
                    role,
                    nth,
                    along: along.0,
                };
                let d = desc(
                    Kind::Resume {
                        of,
                        at,
                        pos: axis_pos(&pos),
                    },
                    tools,
                    work,
                );
                self.programs.insert(id, d);
            }
            Line::ToolEdit {
                t,
                d,
                wear,
                value,
                running,
            } => {
                if running {
                    return Err("an offset edit while the program ran: preparation takes it at a block the record does not hold, so the run cannot be replayed".into());
                }
                tools.edit(t, d, wear, value.0, md.hmi.offset_limit(wear))?;
            }
            Line::WorkEdit { name, values } => {
                let values: Vec<(usize, f64)> = values.iter().map(|(a, v)| (*a, v.0)).collect();
                work.edit(md, &name, &values, md.hmi.max_work_offset)
                    .map_err(|e| e.to_string())?;
            }
            Line::End { cycles, lost } => {
                if lost {
                    return Err("the record is incomplete (it lost inputs during the run)".into());
                }
                self.cycles = Some(cycles);
            }
        }
        Ok(())
    }
}

/// A replay under way: the programs built so far and their preparation threads.
struct Replay<'a> {
    md: &'a MachineData,
    rec: &'a Record,
    origins: HashMap<u32, Origin>,
    threads: Vec<(Arc<Handover>, std::thread::JoinHandle<()>)>,
}

impl Replay<'_> {
    fn run(&mut self, header: &Header, cycles: u64, out: &mut dyn Write) -> Result<(), String> {
        let md = self.md;
        let mut cyclic = Box::new(Cyclic::new(md, axis_pos(&header.start)));
        let extra = nc_kernel::simulate::extra_axes(md);
        let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
        writeln!(w, "{}", nc_kernel::simulate::csv_header(&extra)).map_err(|e| e.to_string())?;
        let mut bus = ReplayBus {
            rec: self.rec,
            k: 0,
            plc: None,
            next: [0; 3],
            aux_full: 0,
            out: &mut w,
            row: String::with_capacity(256),
            extra,
            cycle_us: u64::from(md.ipo.cycle_us),
            failed: None,
        };
        let mut ci = 0;
        for k in 0..cycles {
            while let Some(&(_, cmd, ok)) = self.rec.commands.get(ci).filter(|c| c.0 == k) {
                ci += 1;
                let c = self.control(cmd)?;
                let taken = cyclic.command(c);
                drop(cyclic.take_released());
                if taken.is_ok() != ok {
                    return Err(format!(
                        "cycle {k}: the command {cmd:?} was {} live but {} in the replay",
                        taken_word(ok),
                        taken_word(taken.is_ok())
                    ));
                }
            }
            cyclic.replay_preparation(self.rec.prep.get(&k).copied().unwrap_or(0));
            bus.k = k;
            cyclic.cycle(k, &mut bus);
            drop(cyclic.take_released());
            if let Some(e) = bus.failed.take() {
                return Err(format!("writing setpoints: {e}"));
            }
        }
        w.flush().map_err(|e| format!("writing setpoints: {e}"))
    }

    /// The command the IPO took, with the program it installs built as the live run built it.
    fn control(&mut self, cmd: Cmd) -> Result<Control, String> {
        Ok(match cmd {
            Cmd::Start => Control::Start,
            Cmd::Stop => Control::Stop,
            Cmd::Reset => Control::Reset,
            Cmd::SingleBlock(on) => Control::SingleBlock(on),
            Cmd::Override(f) => Control::Override(f.0),
            Cmd::Shutdown => Control::Shutdown,
            Cmd::Load(id) => Control::Load(self.build(id)?),
            Cmd::Resume(id) => Control::Resume(self.build(id)?),
        })
    }

    /// Program `id` of the record, its preparation started.
    fn build(&mut self, id: u32) -> Result<Box<Program>, String> {
        let d = self
            .rec
            .programs
            .get(&id)
            .ok_or_else(|| format!("program {id} is taken but not described"))?;
        let mut md = self.md.clone();
        md.work_offsets = d.work.clone();
        let mut tools = d.tools.clone();
        tools.live = Some(nc_kernel::LiveEdits::default());
        let (origin, spawned) = match &d.kind {
            Kind::Load {
                path,
                fingerprint: f,
                at,
            } => {
                let source = crate::read_program(std::path::Path::new(path))
                    .map_err(|e| format!("{path}: {e}"))?;
                if fingerprint(source.as_bytes()) != *f {
                    return Err(format!("{path} differs from the text the run loaded"));
                }
                let lib =
                    crate::program_library(std::path::Path::new(path), &md.program.search_path)?;
                md.programs = Arc::new(lib);
                let o = Origin {
                    path: path.clone(),
                    source,
                    at: *at,
                    programs: md.programs.clone(),
                };
                let s = nc_kernel::handover::spawn_preparation(
                    o.path.clone(),
                    o.source.clone(),
                    md.clone(),
                    tools,
                    o.at,
                );
                (o, s)
            }
            Kind::Resume { of, at, pos } => {
                let o = self
                    .origins
                    .get(of)
                    .cloned()
                    .ok_or("resume of a program not built")?;
                md.programs = o.programs.clone();
                let s = nc_kernel::handover::spawn_resume(
                    o.path.clone(),
                    o.source.clone(),
                    md.clone(),
                    tools,
                    o.at,
                    *at,
                    *pos,
                );
                (o, s)
            }
        };
        let s: Spawned = spawned
            .map_err(|e| format!("cannot start preparation: {e}"))?
            .map_err(|a| format!("program {id} refused in the replay: {}", a.message))?;
        self.origins.insert(id, origin);
        let program = Box::new(Program {
            id,
            channel: Box::new(Channel::new(&md, s.start)),
            hand: s.hand.clone(),
            start: s.start,
        });
        self.threads.push((s.hand, s.thread));
        Ok(program)
    }

    /// Ends every preparation thread.
    fn stop(&mut self) {
        for (hand, thread) in self.threads.drain(..) {
            hand.cancel
                .store(true, std::sync::atomic::Ordering::Relaxed);
            let _ = thread.join();
        }
    }
}

fn taken_word(ok: bool) -> &'static str {
    if ok {
        "taken"
    } else {
        "refused"
    }
}

/// The recorded PLC and the setpoint CSV as the cycle's transport.
struct ReplayBus<'a> {
    rec: &'a Record,
    k: u64,
    plc: Option<PlcInput>,
    /// Next unread entry of the PLC changes, gaps and acknowledgements.
    next: [usize; 3],
    /// Next unread entry of `aux_full`.
    aux_full: usize,
    out: &'a mut dyn Write,
    row: String,
    extra: Vec<usize>,
    cycle_us: u64,
    failed: Option<std::io::Error>,
}

impl Bus for ReplayBus<'_> {
    fn plc(&mut self) -> Option<PlcInput> {
        let (k, r) = (self.k, self.rec);
        while let Some(&(at, s)) = r.plc.get(self.next[0]).filter(|p| p.0 <= k) {
            debug_assert!(at <= k);
            self.plc = Some(s);
            self.next[0] += 1;
        }
        while r.gaps.get(self.next[1]).is_some_and(|g| g.1 <= k) {
            self.next[1] += 1;
        }
        let in_gap = r.gaps.get(self.next[1]).is_some_and(|g| g.0 <= k);
        if in_gap {
            None
        } else {
            self.plc
        }
    }

    fn setpoint(&mut self, sp: &Setpoint) {
        nc_kernel::simulate::setpoint_row(&mut self.row, sp, &self.extra, self.cycle_us);
        if let Err(e) = self.out.write_all(self.row.as_bytes()) {
            self.failed.get_or_insert(e);
        }
    }

    fn aux(&mut self, _out: &AuxOut<'_>) -> bool {
        let full = self.rec.aux_full.get(self.aux_full) == Some(&self.k);
        self.aux_full += usize::from(full);
        !full
    }

    fn acks(&mut self, f: &mut dyn FnMut(u64, Option<ChannelAlarm>)) {
        while let Some(&(_, id, alarm)) = self.rec.acks.get(self.next[2]).filter(|a| a.0 <= self.k)
        {
            self.next[2] += 1;
            f(id, ChannelAlarm::new(alarm));
        }
    }

    fn status(&mut self, _st: &Status) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record of an empty run with `lines` after its header.
    fn record(md: &MachineData, tools: &ToolTable, lines: &str) -> String {
        let (machine, t, work) = fingerprints(md, tools);
        let h = Header {
            version: VERSION,
            program: String::new(),
            program_fingerprint: String::new(),
            machine_fingerprint: machine,
            tools_fingerprint: t,
            work_offsets_fingerprint: work,
            cycle_us: md.ipo.cycle_us,
            start: super::super::axes(&AxisPos::default()),
        };
        format!(
            "{}\n{lines}",
            serde_json::to_string(&Line::Header(h)).unwrap()
        )
    }

    fn refusal(md: &MachineData, tools: &ToolTable, text: &str) -> String {
        match read(text, "", md, tools) {
            Err(e) => e,
            Ok(_) => panic!("taken: {text}"),
        }
    }

    #[test]
    fn incomplete_or_unreplayable_records_are_refused() {
        let md = MachineData::load(None, &[]).unwrap();
        let tools = ToolTable::builtin();
        let end = "{\"end\":{\"cycles\":3,\"lost\":false}}\n";
        assert!(read(&record(&md, &tools, end), "", &md, &tools).is_ok());
        let e = refusal(&md, &tools, &record(&md, &tools, ""));
        assert!(e.contains("no end line"), "{e}");
        let lost = "{\"end\":{\"cycles\":3,\"lost\":true}}\n";
        let e = refusal(&md, &tools, &record(&md, &tools, lost));
        assert!(e.contains("line 2") && e.contains("incomplete"), "{e}");
        let running = "{\"tool_edit\":{\"t\":null,\"d\":1,\"wear\":false,\"value\":\"6.5\",\"running\":true}}\n";
        let e = refusal(
            &md,
            &tools,
            &record(&md, &tools, &format!("{running}{end}")),
        );
        assert!(e.contains("while the program ran"), "{e}");
        let mut other = tools.clone();
        other.apply_set("D1=3").unwrap();
        let e = refusal(&md, &other, &record(&md, &tools, end));
        assert!(e.contains("tool table other than"), "{e}");
        let e = refusal(&md, &tools, "{}\n");
        assert!(e.contains("not the header"), "{e}");
    }
}
