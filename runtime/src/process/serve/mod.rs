//! nc-kernel as a process of the control: the IPO thread runs the cycle with the
//! PLC over iceoryx2, this (control) thread answers HMI commands, loads programs and tells
//! the user about alarms.
//!
//! ```text
//!  control thread (this)                         IPO thread (SCHED_FIFO)
//!  commands server ─► Control ─► [ArrayQueue 4] ─► Cyclic::command
//!  reply ◄─────────── Result ◄── [ArrayQueue 4] ◄─┘      Cyclic::cycle ─► IceBus
//!  frees programs ◄── Box<Program> ◄ [ArrayQueue 4] ◄── take_released
//! ```
//!
//! Programs are built (preparation thread started, channel allocated) here and handed over
//! boxed, so the IPO thread never allocates or frees.

mod work_offsets;

use super::bus::IceBus;
use crate::clock::CycleClock;
use crate::os;
use crate::record;
use crate::Failure;
use crossbeam::queue::ArrayQueue;
use nc_kernel::cycle::{alarm, ChannelAlarm, Control, Cyclic, Override, Program, Refusal};
use nc_kernel::handover::{spawn_preparation, Report};
use nc_kernel::ipo::Channel;
use nc_kernel::{MachineData, ToolTable};
use softnc_protocol::iceoryx2::port::update_connections::UpdateConnections;
use softnc_protocol::{command, receive_each, state, Command, Instance, KernelStatus, Reply};
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub struct ServeOptions {
    pub instance: Instance,
    pub program: Option<String>,
    pub start: bool,
    pub md: MachineData,
    pub tools: ToolTable,
    /// Where offset edits are saved (atomically); `None`: the built-in table, not saved.
    pub tools_path: Option<std::path::PathBuf>,
    /// Where work-offset edits are saved (`md.work_offsets` was read from it); `None`: not
    /// saved.
    pub offsets_path: Option<std::path::PathBuf>,
    /// Where the kept macro variables are saved when a program's preparation ends
    /// (`md.kept_variables` was read from it); `None`: not saved.
    pub kept_path: Option<std::path::PathBuf>,
    pub priority: i32,
    /// Record every input to this file (docs/interfaces.md, "Record and replay").
    pub record: Option<std::path::PathBuf>,
    /// With `record`: the live setpoints as `softnc simulate` writes them.
    pub setpoints: Option<std::path::PathBuf>,
}

/// What the control thread keeps of a loaded program.
struct Loaded {
    name: String,
    source: String,
    /// The subprogram files it calls (read at load; a resume prepares with the same).
    programs: std::sync::Arc<nc_kernel::ProgramLibrary>,
    /// The kept macro variables it started with (a resume prepares again from them, so that
    /// what it writes is not counted twice).
    kept: Arc<Vec<(u32, f64)>>,
    /// Where the axes stood when it was loaded (its interpretation starts there).
    at: Option<nc_kernel::AxisPos>,
    /// Offset edits made while it runs, taken by its preparation at the next D.
    live: nc_kernel::LiveEdits,
    /// The tool and work-offset tables' versions it was prepared with.
    versions: (u32, u32),
    reports: crossbeam::channel::Receiver<Report>,
    thread: Option<std::thread::JoinHandle<()>>,
}

struct Shared {
    ctrl: ArrayQueue<Control>,
    answers: ArrayQueue<Result<(), Refusal>>,
    garbage: ArrayQueue<Box<Program>>,
    /// Set by the IPO thread when it has ended.
    done: AtomicBool,
    /// The tool table's version, shown in the status.
    tools_version: std::sync::atomic::AtomicU32,
    /// The work-offset table's version, shown in the status.
    work_offsets_version: std::sync::atomic::AtomicU32,
}

/// The control thread's own state besides the ports.
struct Desk<'a> {
    shared: &'a Shared,
    md: &'a MachineData,
    tools: ToolTable,
    tools_path: Option<std::path::PathBuf>,
    /// The work offsets programs are loaded with (edited here), and their file.
    work: nc_kernel::WorkOffsets,
    work_path: Option<std::path::PathBuf>,
    /// The kept macro variables, and their file.
    kept: Kept,
    programs: HashMap<u32, Loaded>,
    next_id: u32,
    /// Offsets changed in NC stop since the program stopped: NC start resumes with them.
    changed_in_stop: bool,
    /// The record of the run's inputs, if asked for.
    record: Option<record::Writer>,
}

pub fn run(opts: ServeOptions) -> Result<(), Failure> {
    let instance = opts.instance;
    let (cleaned, _) = instance.cleanup_dead_nodes();
    if cleaned > 0 {
        eprintln!(
            "nc-kernel: removed what {cleaned} dead process(es) of instance '{}' left behind",
            instance.name()
        );
    }
    let term = Arc::new(AtomicBool::new(false));
    {
        let term = term.clone();
        // SIGINT and SIGTERM: brake, then end (ctrlc's "termination" feature).
        ctrlc::set_handler(move || term.store(true, Ordering::SeqCst))
            .map_err(|e| format!("cannot install the signal handler: {e}"))?;
    }
    let md = Arc::new(opts.md);
    let tools = opts.tools;
    let mut programs: HashMap<u32, Loaded> = HashMap::new();
    let mut next_id = 1u32;
    // The first program, if any, fixes where the axes stand at start-up; without one they
    // stand where an empty program would start.
    let mut first = None;
    if let Some(path) = &opts.program {
        let (p, mut l) = load(path, &md, &tools, next_id, None).map_err(|(a, m)| match a {
            0 => Failure::Error(m),
            _ => Failure::Failed(m),
        })?;
        // The tables' versions start at 1.
        l.versions = (1, 1);
        programs.insert(next_id, l);
        first = Some(p);
        next_id += 1;
    }
    let start = first.as_ref().map_or_else(
        || nc_kernel::Interpreter::new("", "", &md, &tools).axis_position(),
        |p| p.start,
    );
    let shared = Arc::new(Shared {
        ctrl: ArrayQueue::new(4),
        answers: ArrayQueue::new(4),
        garbage: ArrayQueue::new(4),
        done: AtomicBool::new(false),
        tools_version: std::sync::atomic::AtomicU32::new(1),
        work_offsets_version: std::sync::atomic::AtomicU32::new(1),
    });
    let (writer, recorder) = match &opts.record {
        Some(path) => {
            let first = programs.get(&1);
            let (w, r) = open_record(path, opts.setpoints.as_deref(), first, &md, &tools, start)?;
            (Some(w), Some(r))
        }
        None => (None, None),
    };
    let ipo = start_ipo(&instance, &md, start, opts.priority, &shared, recorder)?;
    let mut desk = Desk {
        shared: &shared,
        md: &md,
        tools,
        tools_path: opts.tools_path,
        work: md.work_offsets.clone(),
        work_path: opts.offsets_path,
        kept: Kept {
            values: md.kept_variables.clone(),
            path: opts.kept_path,
        },
        programs,
        next_id,
        changed_in_stop: false,
        record: writer,
    };
    let outcome = control(&instance, &mut desk, first, opts.start, &term);
    if outcome.is_err() {
        // The IPO thread brakes and ends.
        let _ = shared.ctrl.push(Control::Shutdown);
    }
    let joined = ipo.join();
    if let Some(w) = desk.record.take() {
        if let Err(e) = w.finish() {
            eprintln!("nc-kernel: {e}");
        }
    }
    while let Some(g) = shared.garbage.pop() {
        drop(g);
    }
    for (_, mut l) in desk.programs {
        if let Some(t) = l.thread.take() {
            let _ = t.join();
        }
        // What a program wrote into the kept variables is saved even at shutdown.
        print_reports(&l, &mut desk.kept);
    }
    outcome?;
    joined.map_err(|_| {
        Failure::Error("the IPO thread failed (internal error): the kernel ends".into())
    })
}

/// Starts the IPO thread and waits until its ports are open and its scheduling is set.
fn start_ipo(
    instance: &Instance,
    md: &Arc<MachineData>,
    start: nc_kernel::AxisPos,
    priority: i32,
    shared: &Arc<Shared>,
    recorder: Option<record::IpoRecorder>,
) -> Result<std::thread::JoinHandle<()>, String> {
    let (ready_tx, ready_rx) = crossbeam::channel::bounded::<Result<String, String>>(1);
    let ipo = {
        let (shared, md, instance) = (shared.clone(), md.clone(), instance.clone());
        std::thread::Builder::new()
            .name("ipo".into())
            .spawn(move || {
                let ports = (&instance, &*md, &*shared);
                ipo_thread(ports, start, priority, recorder, ready_tx)
            })
            .map_err(|e| format!("cannot start the IPO thread: {e}"))?
    };
    match ready_rx.recv() {
        Ok(Ok(rt)) => {
            eprintln!(
                "nc-kernel: instance '{}' ready; IPO cycle {} µs; {rt}",
                instance.name(),
                md.ipo.cycle_us
            );
            Ok(ipo)
        }
        Ok(Err(e)) => {
            let _ = ipo.join();
            Err(e)
        }
        Err(_) => {
            let _ = ipo.join();
            Err("the IPO thread ended before it was ready".into())
        }
    }
}

/// Opens the record of the run with its header and the first program's load.
fn open_record(
    path: &std::path::Path,
    setpoints: Option<&std::path::Path>,
    first: Option<&Loaded>,
    md: &MachineData,
    tools: &ToolTable,
    start: nc_kernel::AxisPos,
) -> Result<(record::Writer, record::IpoRecorder), String> {
    let (machine, tools_f, work) = record::fingerprints(md, tools);
    let header = record::Header {
        version: record::VERSION,
        program: first.map_or(String::new(), |l| l.name.clone()),
        program_fingerprint: first
            .map_or(String::new(), |l| record::fingerprint(l.source.as_bytes())),
        machine_fingerprint: machine,
        tools_fingerprint: tools_f,
        work_offsets_fingerprint: work,
        cycle_us: md.ipo.cycle_us,
        start: record::axes(&start),
    };
    let (mut w, r) = record::open(path, setpoints, &header, md)?;
    if let Some(l) = first {
        w.line(&l.load_line(1));
    }
    Ok((w, r))
}

/// Reads and starts preparing a program with the axes at `at` (`None`: the machine zero);
/// the channel is built here, at the program's start.
/// A refusal names the alarm (0: none) and says why; an alarm is rendered and also logged.
fn load(
    path: &str,
    md: &MachineData,
    tools: &ToolTable,
    id: u32,
    at: Option<nc_kernel::AxisPos>,
) -> Result<(Box<Program>, Loaded), (u32, String)> {
    let source =
        crate::read_program(std::path::Path::new(path)).map_err(|e| (0, format!("{path}: {e}")))?;
    let mut md = md.clone();
    md.programs = std::sync::Arc::new(
        crate::program_library(std::path::Path::new(path), &md.program.search_path)
            .map_err(|e| (0, e))?,
    );
    let md = &md;
    let (tools, live) = run_table(tools);
    let s = spawn_preparation(path.to_string(), source.clone(), md.clone(), tools, at)
        .map_err(|e| (0, format!("cannot start the preparation thread: {e}")))?
        .map_err(|a| {
            let text = md.programs.render(&a, &source);
            eprintln!("{text}");
            (
                a.number(),
                format!("program refused, nothing moved (the whole-program check): {text}"),
            )
        })?;
    Ok(Loaded::running(
        s,
        md,
        id,
        path.to_string(),
        source,
        at,
        live,
    ))
}

/// The table a program runs with: `tools` and a list of its own for edits made while it
/// runs.
fn run_table(tools: &ToolTable) -> (ToolTable, nc_kernel::LiveEdits) {
    let live = nc_kernel::LiveEdits::default();
    let mut tools = tools.clone();
    tools.live = Some(live.clone());
    (tools, live)
}

impl Loaded {
    /// The record's line for this program's load as number `id`.
    fn load_line(&self, id: u32) -> record::Line {
        record::Line::Load {
            id,
            path: self.name.clone(),
            program_fingerprint: record::fingerprint(self.source.as_bytes()),
            at: self.at.as_ref().map(record::axes),
        }
    }

    /// The program `s` prepares, with its channel at the program's start, and what this
    /// thread keeps of it.
    fn running(
        s: nc_kernel::handover::Spawned,
        md: &MachineData,
        id: u32,
        name: String,
        source: String,
        at: Option<nc_kernel::AxisPos>,
        live: nc_kernel::LiveEdits,
    ) -> (Box<Program>, Loaded) {
        let program = Box::new(Program {
            id,
            channel: Box::new(Channel::new(md, s.start)),
            hand: s.hand,
            start: s.start,
        });
        let loaded = Loaded {
            name,
            source,
            programs: md.programs.clone(),
            kept: md.kept_variables.clone(),
            at,
            live,
            versions: (0, 0),
            reports: s.reports,
            thread: Some(s.thread),
        };
        (program, loaded)
    }
}

fn ipo_thread(
    (instance, md, shared): (&Instance, &MachineData, &Shared),
    start: nc_kernel::AxisPos,
    priority: i32,
    mut rec: Option<record::IpoRecorder>,
    ready: crossbeam::channel::Sender<Result<String, String>>,
) {
    // However this thread ends (a panic included), the control thread learns it and ends.
    let _done = Done(&shared.done);
    let cycle_ns = u64::from(md.ipo.cycle_us) * 1000;
    let mut bus = match IceBus::open(instance, cycle_ns, crate::WireAxes::new(md)) {
        Ok(b) => b,
        Err(e) => {
            let _ = ready.send(Err(e.to_string()));
            return;
        }
    };
    let mut cyclic = Box::new(Cyclic::new(md, start));
    let (rt, _latency) = os::setup_cyclic_thread(priority, 1);
    let _ = ready.send(Ok(rt.to_string()));
    let mut released: Option<Box<Program>> = None;
    let mut clock = CycleClock::new(cycle_ns);
    let mut k: u64 = 0;
    loop {
        let tick = clock.wait();
        bus.deadline_ns = tick.deadline;
        bus.skipped = clock.skipped();
        bus.tools_version = shared.tools_version.load(Ordering::Relaxed);
        bus.work_offsets_version = shared.work_offsets_version.load(Ordering::Relaxed);
        // Every input the cycle takes passes here: the record keeps it with the cycle.
        while let Some(c) = shared.ctrl.pop() {
            let cmd = record::Cmd::of(&c);
            let r = cyclic.command(c);
            if let Some(rec) = &mut rec {
                rec.command(k, cmd, r.is_ok());
            }
            let _ = shared.answers.push(r);
        }
        match &mut rec {
            Some(rec) => {
                cyclic.cycle(k, &mut rec.wrap(&mut bus, k));
                rec.prep(k, cyclic.taken());
            }
            None => cyclic.cycle(k, &mut bus),
        }
        if released.is_none() {
            released = cyclic.take_released();
        }
        if let Some(g) = released.take() {
            if let Err(back) = shared.garbage.push(g) {
                released = Some(back);
            }
        }
        if cyclic.may_exit() {
            break;
        }
        k += 1;
    }
    if let Some(rec) = &mut rec {
        rec.end(k);
    }
    // Hand everything back to be freed on the control thread.
    if let Some(g) = cyclic.take_released().or(released) {
        let _ = shared.garbage.push(g);
    }
}

/// Sets its flag when dropped.
struct Done<'a>(&'a AtomicBool);

impl Drop for Done<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// Sends a command to the IPO thread and waits for its answer.
fn ask(shared: &Shared, c: Control) -> Result<(), Refusal> {
    // Only this thread asks, one command at a time: the queue always has room, and the
    // IPO thread answers at its next cycle unless it has ended.
    if shared.ctrl.push(c).is_err() {
        return Err(Refusal::Ending);
    }
    let t = Instant::now();
    loop {
        if let Some(a) = shared.answers.pop() {
            return a;
        }
        if t.elapsed() > Duration::from_secs(2) || shared.done.load(Ordering::Acquire) {
            return Err(Refusal::Ending);
        }
        std::thread::sleep(Duration::from_micros(200));
    }
}

fn refusal_text(r: Refusal) -> (u32, String) {
    match r {
        Refusal::NotInReset(s) => (0, format!("the channel is {}: reset it first", s.name())),
        Refusal::NotStopped(s) => (
            0,
            format!("the channel is {}: this needs NC stop, at rest", s.name()),
        ),
        Refusal::NoProgram => (0, "no program is loaded (or it has ended): load one".into()),
        Refusal::Alarm(a) => (a.number(), format!("alarm {a} stands: reset first")),
        Refusal::NoPlc => (
            alarm::PLC_SIGN_OF_LIFE.number(),
            "no PLC: plc-sim is not running for this instance".into(),
        ),
        Refusal::DrivesNotReady => (0, "the drives are not ready (PLC)".into()),
        Refusal::EmergencyStop => (
            alarm::EMERGENCY_STOP.number(),
            "emergency stop is pressed: release it, then reset".into(),
        ),
        Refusal::StartsElsewhere { axis, start, here } => (
            0,
            format!(
                "the program starts with {} at {start:.3} but the axis stands at {here:.3}: move it there first",
                nc_kernel::AXIS_NAMES.get(axis).copied().unwrap_or('?')
            ),
        ),
        Refusal::Ending => (0, "the kernel is ending".into()),
        Refusal::BadOverride => (0, format!("override must be {}", Override::RANGE)),
    }
}

#[allow(clippy::too_many_arguments)]
fn control(
    instance: &Instance,
    desk: &mut Desk<'_>,
    first: Option<Box<Program>>,
    start: bool,
    term: &AtomicBool,
) -> Result<(), String> {
    let shared = desk.shared;
    let node = instance.node("nc-kernel-hmi").map_err(|e| e.to_string())?;
    let server = instance
        .commands(&node)
        .map_err(|e| e.to_string())?
        .server_builder()
        .create()
        .map_err(|e| format!("cannot create the command server: {e:?}"))?;
    let status = instance
        .status(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .create()
        .map_err(|e| format!("cannot subscribe to the status: {e:?}"))?;
    let tools_pub = instance
        .tools(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .create()
        .map_err(|e| format!("cannot publish the tool table: {e:?}"))?;
    let _ = tools_pub.send_copy(desk.table_msg(1));
    let mut published = 1u32;
    let work_pub = instance
        .work_offsets(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .create()
        .map_err(|e| format!("cannot publish the work offsets: {e:?}"))?;
    let _ = work_pub.send_copy(desk.work_offsets_msg(1));
    let mut work_published = 1u32;
    let mut tools_seen = Instant::now();
    if let Some(p) = first {
        if let Err(r) = ask(shared, Control::Load(p)) {
            return Err(refusal_text(r).1);
        }
    }
    let mut want_start = start;
    let mut last = KernelStatus::default();
    let mut shutting_down = false;
    loop {
        if shared.done.load(Ordering::Acquire) {
            break;
        }
        if term.load(Ordering::SeqCst) && !shutting_down {
            shutting_down = true;
            eprintln!("nc-kernel: terminating: the path brakes, then the process ends");
            let _ = ask(shared, Control::Shutdown);
        }
        // A late subscriber gets the table kept in the history when the publisher looks
        // for new subscribers: now and then, not only when the table changes.
        if tools_seen.elapsed() > Duration::from_millis(50) {
            let _ = tools_pub.update_connections();
            let _ = work_pub.update_connections();
            tools_seen = Instant::now();
        }
        while let Ok(Some(req)) = server.receive() {
            let c: Command = *req.payload();
            // The newest status first: a program loads where the axes stand now.
            receive_each(&status, |s| last = report_status(s, &last));
            let mut reply = desk.handle(&c, &last);
            // The new table goes out before the reply: who reads after the reply reads it.
            let version = shared.tools_version.load(Ordering::Acquire);
            if version != published {
                let _ = tools_pub.send_copy(desk.table_msg(version));
                published = version;
            }
            reply.tools_version = version;
            let work = shared.work_offsets_version.load(Ordering::Acquire);
            if work != work_published {
                let _ = work_pub.send_copy(desk.work_offsets_msg(work));
                work_published = work;
            }
            reply.work_offsets_version = work;
            let _ = req.send_copy(reply);
        }
        receive_each(&status, |s| last = report_status(s, &last));
        if let Some(w) = &mut desk.record {
            w.drain();
        }
        // NC start once the PLC is there (--start).
        if want_start && last.plc_alive != 0 {
            match ask(shared, Control::Start) {
                Ok(()) => want_start = false,
                Err(Refusal::NoPlc | Refusal::DrivesNotReady) => {}
                Err(r) => {
                    eprintln!("nc-kernel: NC start refused: {}", refusal_text(r).1);
                    want_start = false;
                }
            }
        }
        while let Some(g) = shared.garbage.pop() {
            if let Some(mut l) = desk.programs.remove(&g.id) {
                drop(g);
                if let Some(t) = l.thread.take() {
                    let _ = t.join();
                }
                print_reports(&l, &mut desk.kept);
            }
        }
        for l in desk.programs.values() {
            print_reports(l, &mut desk.kept);
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    Ok(())
}

/// Tells the user about a new alarm or state; returns `s` as the new last status.
fn report_status(s: KernelStatus, last: &KernelStatus) -> KernelStatus {
    if let Some(a) = ChannelAlarm::new(s.alarm).filter(|_| s.alarm != last.alarm) {
        eprintln!(
            "nc-kernel: alarm {a} at cycle {} (line {}): {}; PLC sign of life last at cycle {}",
            s.cycle,
            s.line,
            a.title(),
            s.plc_cycle
        );
    }
    if s.state != last.state {
        eprintln!("nc-kernel: {} at cycle {}", state::name(s.state), s.cycle);
    }
    s
}

/// The kept macro variables (#500 …) the next program starts with, and their file.
struct Kept {
    values: Arc<Vec<(u32, f64)>>,
    path: Option<std::path::PathBuf>,
}

/// A program's reports: alarms and warnings printed, kept variables taken and saved.
fn print_reports(l: &Loaded, kept: &mut Kept) {
    for r in l.reports.try_iter() {
        match r {
            Report::Warning(w) | Report::Alarm(w) => {
                eprintln!("{}", l.programs.render(&w, &l.source))
            }
            Report::KeptVariables(v) => {
                if *kept.values != v {
                    if let Some(path) = &kept.path {
                        if let Err(e) = super::kept::save(path, &v) {
                            eprintln!("nc-kernel: {e}");
                        }
                    }
                    kept.values = Arc::new(v);
                }
            }
        }
    }
}

impl Desk<'_> {
    fn handle(&mut self, c: &Command, last: &KernelStatus) -> Reply {
        let shared = self.shared;
        match c.kind {
            command::START if self.changed_in_stop && last.state == state::STOPPED => {
                self.resume(last)
            }
            command::START if last.state == state::RESET && self.stale(last.program) => {
                self.reload_and_start(last)
            }
            command::START => answer(ask(shared, Control::Start), "NC start"),
            command::STOP => answer(ask(shared, Control::Stop), "NC stop"),
            command::RESET => {
                let r = ask(shared, Control::Reset);
                if r.is_ok() {
                    self.changed_in_stop = false;
                }
                answer(r, "reset")
            }
            command::SINGLE_BLOCK => answer(
                ask(shared, Control::SingleBlock(c.value != 0.0)),
                if c.value != 0.0 {
                    "single block on"
                } else {
                    "single block off"
                },
            ),
            command::OVERRIDE => answer(ask(shared, Control::Override(c.value)), "override set"),
            command::SHUTDOWN => answer(ask(shared, Control::Shutdown), "shutting down"),
            command::LOAD => self.load_command(c.text(), last),
            command::SET_OFFSET => self.set_offset(c, last),
            command::SET_WORK_OFFSET => self.set_work_offset(c, last),
            command::PROGRAM_INFO => match self.programs.get(&c.d) {
                Some(l) => Reply::new(true, 0, &l.name),
                None => Reply::new(false, 0, &format!("no program number {}", c.d)),
            },
            k => Reply::new(false, 0, &format!("unknown command {k}")),
        }
    }

    /// LOAD: the program at `path` prepared from where the axes stand.
    fn load_command(&mut self, path: &str, last: &KernelStatus) -> Reply {
        let id = self.next_id;
        let md = self.program_md();
        match load(
            path,
            &md,
            &self.tools,
            id,
            Some(crate::WireAxes::new(self.md).from_wire(&last.pos)),
        ) {
            Ok((p, mut l)) => {
                l.versions = self.versions();
                if let Some(w) = &mut self.record {
                    w.line(&l.load_line(id));
                }
                self.programs.insert(id, l);
                self.next_id += 1;
                let r = ask(self.shared, Control::Load(p));
                if r.is_ok() {
                    self.changed_in_stop = false;
                }
                self.settle(id, r.is_ok(), last.program);
                answer(r, &format!("program {path} loaded (number {id})"))
            }
            Err((a, m)) => Reply::new(false, a, &m),
        }
    }

    /// The tool and work-offset tables' versions now.
    fn versions(&self) -> (u32, u32) {
        (
            self.shared.tools_version.load(Ordering::Acquire),
            self.shared.work_offsets_version.load(Ordering::Acquire),
        )
    }

    /// Program `id` was prepared with offsets edited since.
    fn stale(&self, id: u32) -> bool {
        self.programs
            .get(&id)
            .is_some_and(|l| l.versions != self.versions())
    }

    /// NC start in reset of a program prepared before an offset edit: prepared again with
    /// the offsets now in force (every check before anything moves), then started.
    fn reload_and_start(&mut self, last: &KernelStatus) -> Reply {
        let Some(path) = self.programs.get(&last.program).map(|l| l.name.clone()) else {
            return Reply::new(false, 0, "no program is loaded: load one");
        };
        let loaded = self.load_command(&path, last);
        if loaded.ok == 0 {
            return loaded;
        }
        answer(
            ask(self.shared, Control::Start),
            "NC start: the program was prepared again with the offsets edited since its load",
        )
    }

    /// An operator's offset edit (840C 11.8): taken at once in RESET, END and NC stop (from
    /// NC stop, NC start resumes on the new equidistant); while the program runs refused, or
    /// with `hmi.edit_while_active` stored to act when the program next programs that D.
    /// Saved atomically before it counts; the reply names the table version now active.
    fn set_offset(&mut self, c: &Command, last: &KernelStatus) -> Reply {
        let wear = c.flag != 0;
        let what = if wear { "radius wear" } else { "radius" };
        let t = c.tool();
        let name = nc_kernel::offset_label(t, c.d);
        let running = last.state == state::ACTIVE;
        if running && !self.md.hmi.edit_while_active {
            return Reply::new(
                false,
                0,
                &format!(
                    "the program is running: {name} {what} can be changed in NC stop or reset only (840C 11.8); nothing changed"
                ),
            );
        }
        let limit = self.md.hmi.offset_limit(wear);
        let before = self.tools.clone();
        if let Err(e) = self.tools.edit(t, c.d, wear, c.value, limit) {
            return Reply::new(false, 0, &format!("{e}; nothing changed"));
        }
        let saved = self
            .tools_path
            .as_ref()
            .map(|path| (path, self.tools.save_atomic(path)));
        if let Some(refusal) = unsaved(saved) {
            self.tools = before;
            return refusal;
        }
        let version = bump(&self.shared.tools_version);
        if let Some(w) = &mut self.record {
            w.line(&record::Line::ToolEdit {
                t,
                d: c.d,
                wear,
                value: record::F(c.value),
                running,
            });
        }
        let when = if running {
            if let Some(l) = self.programs.get(&last.program) {
                l.live.push(nc_kernel::LiveEdit {
                    t,
                    d: c.d,
                    wear,
                    value: c.value,
                });
            }
            "the running program takes it when it next programs this D in a block not yet prepared (840C 11.8), the path it runs now does not change"
        } else if last.state == state::STOPPED && last.program != 0 {
            self.changed_in_stop = true;
            "acts at NC start: the tool moves onto the new equidistant at the interruption point"
        } else {
            "acts at the next NC start (a loaded program is prepared again with it) or program load"
        };
        let saved = if self.tools_path.is_some() {
            "saved"
        } else {
            "not saved: built-in table"
        };
        Reply::new(
            true,
            0,
            &format!(
                "{name} {what} = {} mm; tool table version {version} ({saved}); {when}",
                c.value
            ),
        )
    }

    /// Program `id` went to the IPO thread: if it was taken, it and the one the last status
    /// names (an HMI may still ask for that one's path) are kept, and the earlier ones
    /// dropped; if refused, it is dropped. (Every load and resume stayed before, source text
    /// included, for as long as the kernel ran.)
    fn settle(&mut self, id: u32, taken: bool, current: u32) {
        if taken {
            self.programs.retain(|k, _| *k == id || *k == current);
        } else {
            self.programs.remove(&id);
        }
    }

    /// NC start after an offset change in NC stop: the program is prepared again with the
    /// new offsets from the interruption point; an alarm (the new radius violates the
    /// contour) refuses the start and nothing moves.
    fn resume(&mut self, last: &KernelStatus) -> Reply {
        let Some(l) = self.programs.get(&last.program) else {
            return Reply::new(false, 0, "no program is loaded: load one");
        };
        let Some(role) = nc_kernel::Role::from_code(last.role) else {
            return Reply::new(false, 0, "the stopped program has no segment to resume on");
        };
        let at = nc_kernel::Interruption {
            seq: last.block_seq,
            role,
            nth: last.piece,
            along: last.along,
        };
        let (tools, live) = run_table(&self.tools);
        let mut md = self.program_md();
        md.programs = l.programs.clone();
        md.kept_variables = l.kept.clone();
        let programs = l.programs.clone();
        let spawned = nc_kernel::handover::spawn_resume(
            l.name.clone(),
            l.source.clone(),
            md.clone(),
            tools,
            l.at,
            at,
            crate::WireAxes::new(self.md).from_wire(&last.pos),
        );
        let s = match spawned {
            Ok(Ok(s)) => s,
            Ok(Err(alarm)) => {
                let text = programs.render(&alarm, &l.source);
                eprintln!("{text}");
                return Reply::new(
                    false,
                    alarm.number(),
                    &format!("NC start refused with the new offsets, nothing moved: {text}"),
                );
            }
            Err(e) => return Reply::new(false, 0, &format!("cannot prepare: {e}")),
        };
        let id = self.next_id;
        self.next_id += 1;
        if let Some(w) = &mut self.record {
            w.line(&record::Line::Resume {
                id,
                of: last.program,
                seq: at.seq,
                role: last.role,
                nth: at.nth,
                along: record::F(at.along),
                pos: record::axes(&crate::WireAxes::new(self.md).from_wire(&last.pos)),
            });
        }
        let (name, source, load_at) = (l.name.clone(), l.source.clone(), l.at);
        let (program, mut loaded) = Loaded::running(s, &md, id, name, source, load_at, live);
        loaded.versions = self.versions();
        self.programs.insert(id, loaded);
        let r = ask(self.shared, Control::Resume(program));
        self.settle(id, r.is_ok(), last.program);
        match r {
            Ok(()) => {
                self.changed_in_stop = false;
                Reply::new(
                    true,
                    0,
                    "NC start with the new offsets: repositioning onto the new equidistant",
                )
            }
            Err(r) => {
                let (a, m) = refusal_text(r);
                Reply::new(false, a, &m)
            }
        }
    }

    /// The table as HMIs get it.
    fn table_msg(&self, version: u32) -> softnc_protocol::ToolTableMsg {
        crate::tool_table_msg(&self.tools, version, self.tools_path.is_some())
    }
}

/// A refusal when an edited table could not be saved (the caller puts the old one back).
fn unsaved(saved: Option<(&std::path::PathBuf, std::io::Result<()>)>) -> Option<Reply> {
    match saved {
        Some((path, Err(e))) => Some(Reply::new(
            false,
            0,
            &format!("cannot save {}: {e}; nothing changed", path.display()),
        )),
        _ => None,
    }
}

/// The reply to a command the IPO thread took or refused.
fn answer(r: Result<(), Refusal>, ok: &str) -> Reply {
    match r {
        Ok(()) => Reply::new(true, 0, ok),
        Err(r) => {
            let (a, m) = refusal_text(r);
            Reply::new(false, a, &m)
        }
    }
}

/// One more on a table's version; the new version.
fn bump(version: &std::sync::atomic::AtomicU32) -> u32 {
    version.fetch_add(1, Ordering::AcqRel) + 1
}
