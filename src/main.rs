//! `softnc`: the user-facing command line of the softnc NC kernel.

use clap::{Args, Parser, Subcommand};
use nc_kernel::jsonl;
use nc_kernel::jsonl as prep_jsonl;
use nc_kernel::Prepared;
use nc_kernel::{Interpreter, Lent, MachineData, Preparation, ToolTable, WholeMode};
use nc_runtime::Failure;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod picture;
mod run;

#[derive(Parser)]
#[command(
    name = "softnc",
    version,
    about = "softnc: a soft NC kernel for part programs in the 840C, ISG, Fanuc and 808D dialects"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Interpret a part program and print its blocks as JSON Lines.
    Parse {
        #[command(flatten)]
        input: ProgramArgs,
        /// Write to FILE instead of standard output.
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: Option<PathBuf>,
    },
    /// Prepare a part program (tool radius and length compensation) and print the tool-centre
    /// path: JSON Lines, one record per segment (docs/path-format.md).
    Path {
        #[command(flatten)]
        input: ProgramArgs,
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Jsonl)]
        format: Format,
        /// Write to FILE instead of standard output.
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: Option<PathBuf>,
    },
    /// Run the same preparation as `path` and print only the alarms and a summary line:
    /// what to run before taking a program to the machine.
    Check {
        #[command(flatten)]
        input: ProgramArgs,
    },
    /// Run the program through the kernel (preparation, lookahead, interpolation, channel)
    /// against a simulated clock and write one CSV row per IPO cycle:
    /// `cycle,time,X,Y,Z,S1,v_path,block,events` (docs/ipo.md). Bit-identical on every run.
    Simulate {
        #[command(flatten)]
        input: ProgramArgs,
        /// Write the setpoints to FILE instead of standard output.
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: Option<PathBuf>,
        /// Path override in percent (above 0, at most 120).
        #[arg(long = "override", value_name = "PERCENT", default_value_t = 100.0)]
        override_percent: f64,
        /// Single-block mode: stop at every S point (the simulation presses NC start again).
        #[arg(long)]
        single_block: bool,
        /// IPO cycles from an auxiliary function's output to the PLC's acknowledgement.
        #[arg(long, value_name = "CYCLES", default_value_t = 1)]
        ack_cycles: u64,
        /// Replay a record of a live run (`softnc run --record FILE`): its HMI commands, PLC
        /// signals and offset edits at their cycles, giving the live run's setpoints bit for
        /// bit (docs/interfaces.md, "Record and replay"). The program, machine data, tools
        /// and work offsets must be the run's.
        #[arg(long, value_name = "FILE", conflicts_with_all = ["override_percent", "single_block", "ack_cycles"])]
        replay: Option<PathBuf>,
    },
    /// Run the program on the control: nc-kernel and plc-sim as processes over shared memory
    /// (iceoryx2), with progress, a summary (time, following error, deviation of the actual
    /// path, aux functions acknowledged) and an SVG of programmed, compensated and actual path.
    Run {
        #[command(flatten)]
        input: ProgramArgs,
        /// Instance name: the prefix of the services and shared memory (default: run-<pid>).
        #[arg(long, value_name = "NAME")]
        instance: Option<String>,
        /// Keep plc-sim's CSV trace in FILE: setpoint, actual (A…) and following error (F…)
        /// of every configured axis
        /// (`time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,S1,AS1,v_path,line,state,events` on a mill).
        #[arg(long, value_name = "FILE")]
        trace: Option<PathBuf>,
        /// Write the picture to FILE (default: <program>.run.svg here).
        #[arg(long, value_name = "FILE")]
        svg: Option<PathBuf>,
        /// Pass an argument to plc-sim, e.g. `--plc=--estop-at --plc=5000`.
        #[arg(long = "plc", value_name = "ARG", allow_hyphen_values = true)]
        plc: Vec<String>,
        /// No progress line.
        #[arg(long)]
        quiet: bool,
        /// Path override in percent from NC start on (above 0, at most 120), as the operator
        /// sets it at the machine.
        #[arg(long = "override", value_name = "PERCENT", default_value_t = 100.0)]
        override_percent: f64,
        /// Also start hmi-bridge (the web page and JSON API, docs/hmi.md) and keep the control
        /// up after the program's end until Ctrl-C.
        #[arg(long)]
        hmi: bool,
        /// The bridge's port (default: machine data hmi.port; 0: any free one).
        #[arg(long, value_name = "PORT", requires = "hmi")]
        hmi_port: Option<u16>,
        // The OPC UA server beside the run (docs/opcua.md); it ends with the run.
        #[command(flatten)]
        opcua: softnc_opcua::ServerOptions,
        /// Record every input the kernel takes (HMI commands, PLC signals, offset edits) with
        /// its cycle to FILE, for `softnc simulate --replay FILE`.
        #[arg(long, value_name = "FILE")]
        record: Option<PathBuf>,
        /// With --record: also write the live setpoints to FILE as `softnc simulate` writes
        /// them.
        #[arg(long, value_name = "FILE", requires = "record")]
        setpoints: Option<PathBuf>,
    },
    /// Show the control's state through hmi-bridge: channel state, block, position, feed,
    /// override, alarm.
    Status {
        #[command(flatten)]
        bridge: BridgeArgs,
        /// Print the status as JSON.
        #[arg(long)]
        json: bool,
    },
    /// NC start through hmi-bridge.
    Start {
        #[command(flatten)]
        bridge: BridgeArgs,
    },
    /// NC stop through hmi-bridge.
    Stop {
        #[command(flatten)]
        bridge: BridgeArgs,
    },
    /// Reset through hmi-bridge.
    Reset {
        #[command(flatten)]
        bridge: BridgeArgs,
    },
    /// Offsets through hmi-bridge: a tool offset, `softnc offset set D1 --radius 10.02
    /// [--wear]` (`T1D2` on a table numbered per tool), or a work offset, `softnc offset set
    /// G54 --x 120.5 --z -310` (`"G54.1 P3"` on a Fanuc).
    Offset {
        #[command(subcommand)]
        action: OffsetAction,
    },
    /// Remove what ended or crashed processes of an instance left in shared memory
    /// (/dev/shm and iceoryx2's folder). Refused while a process of the instance runs.
    Clean {
        /// The instance's name.
        #[arg(long, value_name = "NAME")]
        instance: String,
    },
    // The control's processes (docs/ipc.md, docs/hmi.md): `softnc run` starts itself in
    // these roles. Their arguments and help are the processes' own.
    #[command(hide = true)]
    NcKernel(nc_runtime::process::KernelArgs),
    #[command(hide = true)]
    PlcSim(plc_sim::PlcArgs),
    /// The operator's side of a softnc control: an HTTP JSON API, a live status stream and a
    /// web page (docs/hmi.md), and with --opcua the OPC UA server (docs/opcua.md).
    #[command(hide = true)]
    HmiBridge {
        #[command(flatten)]
        bridge: hmi_bridge::BridgeArgs,
        // The OPC UA server inside the bridge's process, on its link (docs/opcua.md).
        #[command(flatten)]
        opcua: softnc_opcua::ServerOptions,
    },
    /// The OPC UA server: the OPC 40501-1 machine-tool model subset of a running control,
    /// read-only (docs/opcua.md).
    Opcua(softnc_opcua::OpcuaArgs),
}

impl Command {
    /// The process of the control this command runs as, if it is one: its messages carry
    /// the name, as they share a log with the others.
    fn process(&self) -> Option<&'static str> {
        match self {
            Command::NcKernel(_) => Some("nc-kernel"),
            Command::PlcSim(_) => Some("plc-sim"),
            Command::HmiBridge { .. } => Some("hmi-bridge"),
            Command::Opcua(_) => Some("opcua"),
            _ => None,
        }
    }
}

#[derive(Subcommand)]
enum OffsetAction {
    /// Set a tool offset's geometry radius (or its radius wear with --wear), or a work
    /// offset's axis values: in NC stop or reset; while the program runs only if machine
    /// data hmi.edit_while_active allows it.
    Set {
        /// The offset: D1, or T1D2 (also "T1 D2") where D numbers count per tool (808D); or
        /// a work offset as the program selects it: G54, "G54.1 P3".
        name: String,
        /// A tool offset's radius, mm.
        #[arg(long, allow_hyphen_values = true)]
        radius: Option<f64>,
        /// Set the radius wear instead of the geometry radius.
        #[arg(long)]
        wear: bool,
        #[command(flatten)]
        axes: AxisValues,
        #[command(flatten)]
        bridge: BridgeArgs,
    },
}

/// A work offset's new values per axis, mm (degrees for a rotary axis).
#[derive(Args)]
struct AxisValues {
    #[arg(long, allow_hyphen_values = true)]
    x: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    y: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    z: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    u: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    v: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    w: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    a: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    b: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    c: Option<f64>,
}

impl AxisValues {
    /// The values given, by axis letter, as a JSON object.
    fn given(&self) -> serde_json::Map<String, serde_json::Value> {
        let all = [
            ('X', self.x),
            ('Y', self.y),
            ('Z', self.z),
            ('U', self.u),
            ('V', self.v),
            ('W', self.w),
            ('A', self.a),
            ('B', self.b),
            ('C', self.c),
        ];
        all.iter()
            .filter_map(|(n, v)| v.map(|v| (n.to_string(), v.into())))
            .collect()
    }
}

/// Where hmi-bridge listens.
#[derive(Args)]
struct BridgeArgs {
    /// hmi-bridge's address (default: 127.0.0.1 and the port of machine data hmi.port).
    #[arg(long, value_name = "HOST:PORT")]
    bridge: Option<String>,
    /// Machine data file, for hmi.port.
    #[arg(long, value_name = "FILE")]
    machine: Option<PathBuf>,
    /// The bridge's token, if it has one (or SOFTNC_HMI_TOKEN).
    #[arg(long)]
    token: Option<String>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Format {
    /// One JSON object per segment.
    Jsonl,
    /// A picture: programmed contour, tool-centre path, tool circles, labels, alarms.
    Svg,
}

/// What every command that reads a program takes.
#[derive(Args)]
struct ProgramArgs {
    /// The part program.
    program: PathBuf,
    /// Machine data file (TOML); built-in 840C milling machine if not given.
    #[arg(long, value_name = "FILE")]
    machine: Option<PathBuf>,
    /// Override one machine data value, e.g. `--md trc.max_blocks_outside_plane=1`.
    #[arg(long = "md", value_name = "KEY=VALUE")]
    md: Vec<String>,
    /// Tool offset file (TOML); the shipped config/tools.toml if not given.
    #[arg(long, value_name = "FILE")]
    tools: Option<PathBuf>,
    /// Override the radius of offset n, e.g. `--set D1=10.0`.
    #[arg(long = "set", value_name = "Dn=R")]
    set: Vec<String>,
    /// Work-offset file (TOML, docs/work-offsets.md); all work offsets zero if not given.
    #[arg(long, value_name = "FILE")]
    offsets: Option<PathBuf>,
    /// Kept macro variables #500 … #999 (TOML, docs/fanuc.md): the values a program starts
    /// with; `softnc run` also saves what the program leaves there.
    #[arg(long, value_name = "FILE")]
    macro_variables: Option<PathBuf>,
}

struct Loaded {
    name: String,
    source: String,
    md: MachineData,
    tools: ToolTable,
}

/// A usage or configuration error (exit status 2).
fn fail(msg: impl std::fmt::Display) -> Failure {
    Failure::Error(msg.to_string())
}

fn load(a: &ProgramArgs) -> Result<Loaded, Failure> {
    let mut md = MachineData::load(a.machine.as_deref(), &a.md).map_err(fail)?;
    if let Some(p) = &a.offsets {
        md.work_offsets = nc_kernel::WorkOffsets::load(p, &md).map_err(fail)?;
    }
    if let Some(p) = &a.macro_variables {
        md.kept_variables = std::sync::Arc::new(nc_runtime::process::kept::load(p).map_err(fail)?);
    }
    let mut tools = match &a.tools {
        Some(p) => ToolTable::load(p).map_err(fail)?,
        None => ToolTable::builtin(),
    };
    for s in &a.set {
        tools.apply_set(s).map_err(fail)?;
    }
    let name = a.program.display().to_string();
    let source = nc_runtime::read_program(&a.program).map_err(|e| fail(format!("{name}: {e}")))?;
    md.programs = std::sync::Arc::new(
        nc_runtime::program_library(&a.program, &md.program.search_path).map_err(fail)?,
    );
    Ok(Loaded {
        name,
        source,
        md,
        tools,
    })
}

fn parse(input: &ProgramArgs, output: Option<&PathBuf>) -> Result<(), Failure> {
    let l = load(input)?;
    let mut out = open_output(output)?;
    let writing = |e: std::io::Error| fail(format!("writing output: {e}"));
    for item in Interpreter::new(&l.name, &l.source, &l.md, &l.tools) {
        match item {
            Ok(block) => jsonl::write_block(&mut out, &block, l.md.dialect).map_err(writing)?,
            Err(alarm) => {
                let _ = out.flush();
                eprintln!("{}", l.md.programs.render(&alarm, &l.source));
                return Err(Failure::Reported);
            }
        }
    }
    out.flush().map_err(writing)
}

fn open_output(output: Option<&PathBuf>) -> Result<BufWriter<Box<dyn Write>>, Failure> {
    let sink: Box<dyn Write> = match output {
        Some(p) => match std::fs::File::create(p) {
            Ok(f) => Box::new(f),
            Err(e) => return Err(fail(format!("{}: {e}", p.display()))),
        },
        None => Box::new(std::io::stdout().lock()),
    };
    Ok(BufWriter::with_capacity(1 << 16, sink))
}

fn path(input: &ProgramArgs, format: Format, output: Option<&PathBuf>) -> Result<(), Failure> {
    let l = load(input)?;
    let out = open_output(output)?;
    if format == Format::Svg {
        return path_svg(&l, out);
    }
    with_preparation(&l, WholeMode::Reaction, |prep| path_jsonl(&l, prep, out))
}

fn path_jsonl(
    l: &Loaded,
    prep: &mut Preparation,
    mut out: BufWriter<Box<dyn Write>>,
) -> Result<(), Failure> {
    let writing = |e: std::io::Error| fail(format!("writing output: {e}"));
    let outcome = loop {
        match prep.next_item() {
            Ok(Some(item)) => {
                if let Prepared::Warning(w) = &item {
                    eprintln!("{}", render_warning(w, &l.source));
                }
                prep_jsonl::write_prepared(&mut out, &item).map_err(writing)?;
            }
            Ok(None) => break Ok(()),
            Err(alarm) => {
                let _ = prep_jsonl::write_alarm(&mut out, &alarm);
                eprintln!("{}", l.md.programs.render(&alarm, &l.source));
                break Err(Failure::Reported);
            }
        }
    };
    out.flush().map_err(writing)?;
    outcome
}

fn path_svg(l: &Loaded, mut out: BufWriter<Box<dyn Write>>) -> Result<(), Failure> {
    let mut segments = Vec::new();
    let mut alarm = None;
    let prep = Preparation::new(&l.name, &l.source, &l.md, &l.tools);
    for item in checked(prep, &l.md, WholeMode::Reaction) {
        match item {
            Ok(s) => segments.push(s),
            Err(a) => {
                eprintln!("{}", l.md.programs.render(&a, &l.source));
                alarm = Some(a);
            }
        }
    }
    let pic = picture::Picture::new(
        &l.name,
        &l.source,
        &l.md,
        &l.tools,
        &segments,
        alarm.as_ref(),
    );
    svg::write(&mut out, &pic.render())
        .and_then(|()| out.flush())
        .map_err(|e| fail(format!("writing output: {e}")))?;
    match alarm {
        Some(_) => Err(Failure::Reported),
        None => Ok(()),
    }
}

fn check(input: &ProgramArgs) -> Result<(), Failure> {
    let l = load(input)?;
    let t0 = std::time::Instant::now();
    with_preparation(&l, WholeMode::Collect, |prep| check_run(&l, prep, t0))
}

fn check_run(l: &Loaded, prep: &mut Preparation, t0: std::time::Instant) -> Result<(), Failure> {
    let mut segments = 0u64;
    let mut alarms = 0u32;
    let mut warnings = 0u32;
    loop {
        // Segments lent, not copied out: the check only counts them.
        let seen = match prep.next_ref() {
            Ok(Some(Lent::Segment(_) | Lent::Item(Prepared::Segment(_)))) => {
                Ok(Some(Seen::Segment))
            }
            Ok(Some(Lent::Item(Prepared::Warning(w)))) => Ok(Some(Seen::Warning(w))),
            Ok(Some(Lent::Item(_))) => Ok(Some(Seen::Other)),
            Ok(None) => Ok(None),
            Err(a) => Err(a),
        };
        // What the whole-program check found goes on record where it was found.
        let end = !matches!(seen, Ok(Some(_)));
        for v in prep.take_violations(end) {
            alarms += 1;
            eprintln!("{}", l.md.programs.render(&v, &l.source));
        }
        match seen {
            Ok(Some(Seen::Segment)) => segments += 1,
            Ok(Some(Seen::Warning(w))) => {
                warnings += 1;
                eprintln!("{}", render_warning(&w, &l.source));
            }
            Ok(Some(Seen::Other)) => {}
            Ok(None) => break,
            Err(alarm) => {
                alarms += 1;
                eprintln!("{}", l.md.programs.render(&alarm, &l.source));
                break;
            }
        }
    }
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let verdict = if alarms == 0 { "ok" } else { "FAILED" };
    let warned = if warnings > 0 {
        format!(
            ", {warnings} warning{}",
            if warnings == 1 { "" } else { "s" }
        )
    } else {
        String::new()
    };
    println!(
        "{}: {verdict}: {} blocks, {segments} segments, {alarms} alarm{}{warned}, {ms:.1} ms",
        l.name,
        prep.blocks(),
        if alarms == 1 { "" } else { "s" }
    );
    if alarms == 0 {
        Ok(())
    } else {
        Err(Failure::Reported)
    }
}

/// What `softnc check` takes of a record.
enum Seen {
    Segment,
    Warning(nc_kernel::Alarm),
    Other,
}

/// Runs `f` on the program's preparation, with the whole-program check in `whole` mode when
/// the machine data asks for it: for a long program on a machine with a second core, with
/// the interpreter in a thread of its own (the same output, sooner).
fn with_preparation<R>(l: &Loaded, whole: WholeMode, f: impl FnOnce(&mut Preparation) -> R) -> R {
    const LONG: usize = 256 * 1024;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if l.source.len() >= LONG && cores >= 2 {
        std::thread::scope(|s| {
            let prep = Preparation::threaded(s, &l.name, &l.source, &l.md, &l.tools);
            let mut prep = checked(prep, &l.md, whole).with_join(&nc_runtime::Threads);
            f(&mut prep)
        })
    } else {
        let prep = Preparation::new(&l.name, &l.source, &l.md, &l.tools);
        f(&mut checked(prep, &l.md, whole))
    }
}

/// `prep` with the machine's checks: the software limits, and the whole-program check in
/// `mode` where the machine data asks for it.
fn checked<'a>(prep: Preparation<'a>, md: &MachineData, mode: WholeMode) -> Preparation<'a> {
    let prep = prep.with_soft_limits(md);
    if md.trc.whole_program_check {
        prep.checking_whole(mode)
    } else {
        prep
    }
}

/// A warning (an alarm the machine data lets pass) as a diagnostic.
fn render_warning(w: &nc_kernel::Alarm, source: &str) -> String {
    w.render(source).replacen(": alarm ", ": warning ", 1)
}

fn bridge(b: &BridgeArgs) -> Result<hmi_bridge::client::Bridge, Failure> {
    let addr = match &b.bridge {
        Some(a) => a.clone(),
        None => {
            let md = MachineData::load(b.machine.as_deref(), &[]).map_err(fail)?;
            format!("127.0.0.1:{}", md.hmi.port)
        }
    };
    let token = b
        .token
        .clone()
        .or_else(|| std::env::var("SOFTNC_HMI_TOKEN").ok());
    Ok(hmi_bridge::client::Bridge::new(addr, token))
}

/// The bridge's answer: its message printed on success; a refusal fails the command
/// (exit 1), a bridge out of reach is an error (exit 2).
fn report(r: Result<hmi_bridge::client::Answer, String>) -> Result<(), Failure> {
    let a = r?;
    let j = a.json();
    if (200..300).contains(&a.status) {
        println!("{}", j["message"].as_str().unwrap_or("done"));
        return Ok(());
    }
    Err(Failure::Failed(format!(
        "refused ({}): {}",
        a.status,
        j["error"].as_str().unwrap_or(a.body.as_str())
    )))
}

fn simple(b: &BridgeArgs, path: &str) -> Result<(), Failure> {
    report(bridge(b)?.post(path, &serde_json::json!({})))
}

/// `softnc offset set`: a tool offset (D1, T1D2) with --radius, or a work offset with
/// axis values.
fn offset(
    b: &BridgeArgs,
    name: &str,
    radius: Option<f64>,
    wear: bool,
    axes: &AxisValues,
) -> Result<(), Failure> {
    let values = axes.given();
    match (offset_name(name), radius) {
        (Some((t, n)), Some(r)) if values.is_empty() => {
            let mut body = serde_json::json!({ "d": n, "radius": r, "wear": wear });
            if let Some(t) = t {
                body["t"] = t.into();
            }
            report(bridge(b)?.post("/api/offset", &body))
        }
        (Some(_), _) => Err(fail(format!(
            "{name} is a tool offset: give its value with --radius (and --wear for the wear)"
        ))),
        (None, None) if !values.is_empty() && !wear => {
            let body = serde_json::json!({ "set": name, "values": values });
            report(bridge(b)?.post("/api/work-offset", &body))
        }
        (None, _) => Err(fail(format!(
            "{name}: a work offset, named as the program selects it, takes axis values (--x 10 --z -5); a tool offset is D1 or T1D2"
        ))),
    }
}

/// "D1" → (None, 1); "T1D2", "T1 D2", "t1d2" → (Some(1), 2). Numbers from 1.
fn offset_name(s: &str) -> Option<(Option<u32>, u32)> {
    let number = |x: &str| x.trim().parse::<u32>().ok().filter(|n| *n > 0);
    let s = s.trim();
    let (t, rest) = match s.strip_prefix(['T', 't']) {
        Some(r) => {
            let k = r.find(['D', 'd'])?;
            (Some(number(&r[..k])?), &r[k..])
        }
        None => (None, s),
    };
    Some((t, number(rest.strip_prefix(['D', 'd'])?)?))
}

fn status(b: &BridgeArgs, json: bool) -> Result<(), Failure> {
    let a = match bridge(b)?.get("/api/status") {
        Ok(a) if a.status == 200 => a,
        other => return report(other),
    };
    let s = a.json();
    if json {
        println!("{s}");
        return Ok(());
    }
    if s["connected"] != serde_json::Value::Bool(true) {
        println!("kernel: not running (hmi-bridge has no status from it)");
        return Err(Failure::Reported);
    }
    let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
    println!(
        "{:<8} program {}  line {}",
        s["state"].as_str().unwrap_or("?"),
        s["program_path"].as_str().unwrap_or("(none)"),
        s["line"]
    );
    println!(
        "{}F {:.0} mm/min  override {:.0} %  single block {}",
        axis_positions(&s),
        f(&s["feed_mm_min"]),
        f(&s["override_percent"]),
        if s["single_block"] == serde_json::Value::Bool(true) {
            "on"
        } else {
            "off"
        }
    );
    println!(
        "aux functions {} sent, {} acknowledged; tool table version {}; PLC {}",
        s["aux_sent"],
        s["aux_acked"],
        s["tools_version"],
        if s["plc_alive"] == serde_json::Value::Bool(true) {
            "ok"
        } else {
            "missing"
        }
    );
    if let Some(a) = s["alarm"].as_object() {
        println!(
            "alarm {}: {}",
            a.get("number").cloned().unwrap_or_default(),
            a.get("text").and_then(|t| t.as_str()).unwrap_or("")
        );
    }
    Ok(())
}

/// Each axis of the bridge's status with its position (`axes` names them in the order of
/// `pos`): a rotary axis in degrees, a modulo one within 0…360°.
fn axis_positions(s: &serde_json::Value) -> String {
    let (Some(axes), Some(pos)) = (s["axes"].as_array(), s["pos"].as_array()) else {
        return String::new();
    };
    let mut out = String::new();
    for (a, p) in axes.iter().zip(pos) {
        let p = p.as_f64().unwrap_or(f64::NAN);
        let flag = |k: &str| a[k].as_bool().unwrap_or(false);
        let (shown, unit) = match (flag("modulo"), flag("rotary")) {
            (true, _) => (p.rem_euclid(360.0), "°"),
            (false, true) => (p, "°"),
            (false, false) => (p, ""),
        };
        let name = a["name"].as_str().unwrap_or("?");
        out.push_str(&format!("{name} {shown:.3}{unit}  "));
    }
    out
}

fn clean(name: &str) -> Result<(), Failure> {
    let inst = softnc_protocol::Instance::new(name).map_err(fail)?;
    let before = inst.files().len();
    let left = inst
        .remove_when_unused()
        .map_err(|e| Failure::Failed(e.to_string()))?;
    if !left.is_empty() {
        let files: Vec<String> = left.iter().map(|f| format!("  {}", f.display())).collect();
        return Err(Failure::Failed(format!(
            "instance '{name}': could not remove:\n{}",
            files.join("\n")
        )));
    }
    println!("instance '{name}': {before} file(s) removed, none left");
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let process = cli.command.process();
    nc_runtime::exit(process, dispatch(cli.command))
}

fn dispatch(command: Command) -> Result<(), Failure> {
    match command {
        Command::Parse { input, output } => parse(&input, output.as_ref()),
        Command::Path {
            input,
            format,
            output,
        } => path(&input, format, output.as_ref()),
        Command::Check { input } => check(&input),
        Command::Clean { instance } => clean(&instance),
        Command::Status { bridge, json } => status(&bridge, json),
        Command::Start { bridge } => simple(&bridge, "/api/start"),
        Command::Stop { bridge } => simple(&bridge, "/api/stop"),
        Command::Reset { bridge } => simple(&bridge, "/api/reset"),
        Command::Offset {
            action:
                OffsetAction::Set {
                    name,
                    radius,
                    wear,
                    axes,
                    bridge,
                },
        } => offset(&bridge, &name, radius, wear, &axes),
        Command::Run {
            input,
            instance,
            trace,
            svg,
            plc,
            quiet,
            override_percent,
            hmi,
            hmi_port,
            opcua,
            record,
            setpoints,
        } => {
            let override_ = path_override(override_percent)?;
            let l = load(&input)?;
            run::run(run::RunOptions {
                name: &l.name,
                source: &l.source,
                program: &input.program,
                md: &l.md,
                tools: &l.tools,
                tools_file: input.tools.as_deref(),
                offsets_file: input.offsets.as_deref(),
                macro_variables_file: input.macro_variables.as_deref(),
                set: &input.set,
                instance,
                trace,
                svg,
                plc_args: &plc,
                quiet,
                override_,
                hmi: hmi.then_some(hmi_port),
                opcua,
                record: record.as_deref(),
                setpoints: setpoints.as_deref(),
            })
        }
        Command::Simulate {
            input,
            output,
            replay: Some(file),
            ..
        } => replay(&input, &file, output.as_ref()),
        Command::Simulate {
            input,
            output,
            override_percent,
            single_block,
            ack_cycles,
            replay: None,
        } => simulate(
            &input,
            output.as_ref(),
            override_percent,
            single_block,
            ack_cycles,
        ),
        // One executable for the whole control: `softnc run` starts itself in these roles,
        // so one `cargo run` builds everything the run needs.
        Command::NcKernel(args) => nc_runtime::process::main(args),
        Command::PlcSim(args) => plc_sim::main(args),
        Command::HmiBridge { bridge, opcua } => softnc_opcua::bridge_main(bridge, opcua),
        Command::Opcua(args) => softnc_opcua::main(args),
    }
}

/// `softnc simulate --replay FILE`.
fn replay(input: &ProgramArgs, file: &Path, output: Option<&PathBuf>) -> Result<(), Failure> {
    let l = load(input)?;
    let mut out: Box<dyn Write> = match output {
        Some(p) => {
            Box::new(std::fs::File::create(p).map_err(|e| fail(format!("{}: {e}", p.display())))?)
        }
        None => Box::new(std::io::stdout().lock()),
    };
    let cycles =
        nc_runtime::record::replay(file, &l.source, &l.md, &l.tools, &mut out).map_err(fail)?;
    eprintln!(
        "{}: replayed {} cycles of {}",
        l.name,
        cycles,
        file.display()
    );
    Ok(())
}

/// `--override PERCENT` as the fraction the kernel takes. 0 % is refused: it holds the path
/// for ever, and neither a simulation nor a run would end.
fn path_override(percent: f64) -> Result<f64, Failure> {
    nc_kernel::cycle::Override::from_percent(percent)
        .map(|o| o.fraction())
        .ok_or_else(|| {
            fail(format!(
                "--override {percent}: expected a percentage {}",
                nc_kernel::cycle::Override::RANGE
            ))
        })
}

fn simulate(
    input: &ProgramArgs,
    output: Option<&PathBuf>,
    override_percent: f64,
    single_block: bool,
    ack_cycles: u64,
) -> Result<(), Failure> {
    let override_ = path_override(override_percent)?;
    let l = load(input)?;
    let opts = nc_kernel::simulate::Options {
        ack_cycles,
        override_,
        single_block,
        ..Default::default()
    };
    let mut out: Box<dyn Write> = match output {
        Some(p) => {
            Box::new(std::fs::File::create(p).map_err(|e| fail(format!("{}: {e}", p.display())))?)
        }
        None => Box::new(std::io::stdout().lock()),
    };
    let t0 = std::time::Instant::now();
    // A progress line on a terminal, at most five times a second (long programs simulate for
    // minutes: the ISG grinding cycle is 27 h of machine time).
    let cycle_s = f64::from(l.md.ipo.cycle_us) * 1e-6;
    let total_lines = l.source.lines().count().max(1);
    let tty = std::io::stderr().is_terminal();
    let mut shown = t0;
    let mut progress = |p: nc_kernel::simulate::Progress| {
        if tty && shown.elapsed() >= std::time::Duration::from_millis(200) {
            shown = std::time::Instant::now();
            eprint!(
                "\rline {:>6}/{total_lines}  {:.1} s machine time ",
                p.line,
                p.cycles as f64 * cycle_s
            );
        }
    };
    let r = nc_kernel::simulate::run_with_progress(
        &l.name,
        &l.source,
        &l.md,
        &l.tools,
        &opts,
        &mut out,
        &mut progress,
    );
    if tty && shown != t0 {
        eprint!("\r{}\r", " ".repeat(60));
    }
    let s = r.map_err(|e| fail(format!("writing setpoints: {e}")))?;
    for w in &s.warnings {
        eprintln!("{}", render_warning(w, &l.source));
    }
    for a in &s.alarms {
        eprintln!("{}", l.md.programs.render(a, &l.source));
    }
    eprintln!(
        "{}: {}: {} cycles ({:.3} s machine time), {} segments, {} auxiliary functions, top path speed {:.1} mm/min; simulated in {:.0} ms",
        l.name,
        s.end_state.map_or("?", |st| st.name()),
        s.cycles,
        s.cycles as f64 * cycle_s,
        s.segments,
        s.aux,
        s.max_speed,
        t0.elapsed().as_secs_f64() * 1e3
    );
    if s.timed_out {
        return Err(Failure::Failed(format!(
            "the simulation stopped after {} cycles without reaching the end",
            s.cycles
        )));
    }
    if s.alarms.is_empty() {
        Ok(())
    } else {
        Err(Failure::Reported)
    }
}

#[cfg(test)]
mod tests {
    use super::{axis_positions, offset_name};

    #[test]
    fn offset_names() {
        assert_eq!(offset_name("D1"), Some((None, 1)));
        assert_eq!(offset_name("d12"), Some((None, 12)));
        assert_eq!(offset_name("T1D2"), Some((Some(1), 2)));
        assert_eq!(offset_name("T3 D1"), Some((Some(3), 1)));
        assert_eq!(offset_name("t2d4"), Some((Some(2), 4)));
        for bad in [
            "", "D", "D0", "T0D1", "T1", "1", "X1", "D-1", "T1D", "D1.5", "TD1",
        ] {
            assert_eq!(offset_name(bad), None, "{bad}");
        }
    }

    #[test]
    fn status_positions_by_axis_name() {
        let s = serde_json::json!({
            "axes": [
                { "name": "X", "rotary": false, "modulo": false },
                { "name": "Z", "rotary": false, "modulo": false },
                { "name": "A", "rotary": true, "modulo": false },
                { "name": "C", "rotary": true, "modulo": true },
            ],
            "pos": [1.0, -2.5, -30.0, -90.0],
        });
        assert_eq!(
            axis_positions(&s),
            "X 1.000  Z -2.500  A -30.000°  C 270.000°  "
        );
        assert_eq!(axis_positions(&serde_json::json!({})), "");
    }
}
