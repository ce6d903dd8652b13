//! nc-kernel process: the NC kernel on the live clock — preparation thread, lock-free
//! queue, cyclic IPO thread (SCHED_FIFO, locked memory, absolute deadlines).
//!
//! `nc-kernel --instance NAME [PROGRAM] [--start] [--machine FILE] [--tools FILE]`: a process
//! of the control, talking to plc-sim and the HMI over iceoryx2 (serve.rs).
//!
//! `nc-kernel PROGRAM [--machine FILE] [--tools FILE] [--seconds S] [--priority P]`: the
//! program alone, no PLC (auxiliary functions acknowledged at once), with the IPO thread's
//! wake-up latency and compute time (the latency benchmark).

pub mod args;
mod bus;
mod serve;

use args::value;

use crate::live::{run, LiveOptions};
use nc_kernel::handover::Report;
use std::process::ExitCode;
use std::time::Duration;

const USAGE: &str = "usage: nc-kernel --instance NAME [PROGRAM] [--start] [--machine FILE] [--tools FILE] [--set Dn=R]... [--priority P]
       nc-kernel PROGRAM [--machine FILE] [--tools FILE] [--seconds S] [--priority P] [--histogram FILE]";

/// The nc-kernel process with its arguments (after the program name).
pub fn main(args: Vec<String>) -> ExitCode {
    if args.is_empty() || args.iter().any(|a| a == "--help" || a == "-h") {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    }
    let fail = |m: String| {
        eprintln!("error: {m}");
        ExitCode::from(2)
    };
    // Flags and their values; the one other argument is the program.
    let with_value = [
        "--instance",
        "--machine",
        "--tools",
        "--seconds",
        "--priority",
        "--histogram",
        "--set",
    ];
    let mut program = None;
    let mut i = 0;
    while i < args.len() {
        let a = &args[i];
        if with_value.contains(&a.as_str()) {
            if i + 1 >= args.len() {
                return fail(format!("{a} needs a value\n{USAGE}"));
            }
            i += 2;
            continue;
        }
        if a.starts_with("--") && a != "--start" {
            return fail(format!("unknown option {a}\n{USAGE}"));
        }
        if !a.starts_with("--") {
            if program.is_some() {
                return fail(format!("one program only\n{USAGE}"));
            }
            program = Some(a.clone());
        }
        i += 1;
    }
    let md = match args::machine(&args) {
        Ok(md) => md,
        Err(e) => return fail(e),
    };
    let tools = match value(&args, "--tools") {
        Some(p) => match nc_kernel::ToolTable::load(std::path::Path::new(p)) {
            Ok(t) => t,
            Err(e) => return fail(e.to_string()),
        },
        None => nc_kernel::ToolTable::builtin(),
    };
    let mut tools = tools;
    for w in args.windows(2).filter(|w| w[0] == "--set") {
        if let Err(e) = tools.apply_set(&w[1]) {
            return fail(e);
        }
    }
    let mut opts = LiveOptions {
        announce: true,
        ..Default::default()
    };
    if let Some(s) = value(&args, "--seconds") {
        match s.parse::<f64>() {
            Ok(x) if x > 0.0 && x.is_finite() => opts.limit = Some(Duration::from_secs_f64(x)),
            _ => return fail(format!("--seconds {s}: expected a positive number")),
        }
    }
    match args::priority(&args) {
        Ok(Some(p)) => opts.priority = p,
        Ok(None) => {}
        Err(e) => return fail(e),
    }
    if let Some(instance) = value(&args, "--instance") {
        return serve::run(serve::ServeOptions {
            instance: instance.to_string(),
            program,
            start: args.iter().any(|a| a == "--start"),
            md,
            tools,
            tools_path: value(&args, "--tools").map(std::path::PathBuf::from),
            priority: opts.priority,
        });
    }
    let Some(program) = program else {
        return fail(format!("no program given\n{USAGE}"));
    };
    let program = &program;
    let source = match std::fs::read_to_string(program) {
        Ok(s) => s,
        Err(e) => return fail(format!("{program}: {e}")),
    };
    let mut setpoints = 0u64;
    let stats = match run(program, &source, &md, &tools, &opts, &mut |_sp| {
        setpoints += 1
    }) {
        Ok(s) => s,
        Err(e) => return fail(format!("cannot start the kernel's threads: {e}")),
    };
    let mut alarms = 0;
    for r in &stats.reports {
        match r {
            Report::Warning(w) => eprintln!("{}", w.render(&source)),
            Report::Alarm(a) => {
                alarms += 1;
                eprintln!("{}", a.render(&source));
            }
        }
    }
    let q = |h: &hdrhistogram::Histogram<u64>, p: f64| h.value_at_quantile(p) as f64 / 1000.0;
    println!(
        "{program}: {} after {} cycles ({setpoints} setpoints); {}",
        stats.end_state.name(),
        stats.cycles,
        stats.rt
    );
    println!(
        "wake-up latency µs: p50 {:.1}  p99 {:.1}  p99.9 {:.1}  max {:.1}",
        q(&stats.wakeup, 0.5),
        q(&stats.wakeup, 0.99),
        q(&stats.wakeup, 0.999),
        stats.wakeup.max() as f64 / 1000.0
    );
    println!(
        "cycle work µs:      p50 {:.2}  p99 {:.2}  max {:.1}; overruns {}, periods skipped {}, cycles short of lookahead {}",
        q(&stats.compute, 0.5),
        q(&stats.compute, 0.99),
        stats.compute.max() as f64 / 1000.0,
        stats.overruns,
        stats.skipped,
        stats.starved
    );
    if let Some(path) = value(&args, "--histogram") {
        let text = crate::histogram_text("nc-kernel wake-up latency", &stats.wakeup, &[]);
        if let Err(e) = std::fs::write(path, text) {
            return fail(format!("{path}: {e}"));
        }
    }
    if alarms > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
