//! nc-kernel process: runs a part program on the live clock — preparation thread, lock-free
//! queue, cyclic IPO thread (SCHED_FIFO, locked memory, absolute deadlines) — and reports the
//! IPO thread's wake-up latency and compute time. The IPC services (setpoints to plc-sim,
//! HMI commands) come with issue 6.
//!
//! `nc-kernel PROGRAM [--machine FILE] [--tools FILE] [--seconds S] [--priority P]`

use nc_kernel::runtime::live::{run, LiveOptions};
use nc_kernel::runtime::Report;
use std::process::ExitCode;
use std::time::Duration;

const USAGE: &str =
    "usage: nc-kernel PROGRAM [--machine FILE] [--tools FILE] [--seconds S] [--priority P]";

fn value<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    args.windows(2)
        .find(|w| w[0] == flag)
        .map(|w| w[1].as_str())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() || args.iter().any(|a| a == "--help" || a == "-h") {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    }
    let program = &args[0];
    let fail = |m: String| {
        eprintln!("error: {m}");
        ExitCode::from(2)
    };
    let md = match nc_kernel::MachineData::load(
        value(&args, "--machine").map(std::path::Path::new),
        &[],
    ) {
        Ok(md) => md,
        Err(e) => return fail(e.to_string()),
    };
    let tools = match value(&args, "--tools") {
        Some(p) => match nc_kernel::ToolTable::load(std::path::Path::new(p)) {
            Ok(t) => t,
            Err(e) => return fail(e.to_string()),
        },
        None => nc_kernel::ToolTable::builtin(),
    };
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
    if let Some(p) = value(&args, "--priority") {
        match p.parse::<i32>() {
            Ok(x) if (1..=99).contains(&x) => opts.priority = x,
            _ => return fail(format!("--priority {p}: expected 1 to 99")),
        }
    }
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
            Report::Warning(w) => eprintln!("{}", nc_kernel::alarm::render(w, &source)),
            Report::Alarm(a) => {
                alarms += 1;
                eprintln!("{}", nc_kernel::alarm::render(a, &source));
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
        "cycle work µs:      p50 {:.2}  p99 {:.2}  max {:.1}; overruns {}, cycles short of lookahead {}",
        q(&stats.compute, 0.5),
        q(&stats.compute, 0.99),
        stats.compute.max() as f64 / 1000.0,
        stats.overruns,
        stats.starved
    );
    if let Some(path) = value(&args, "--histogram") {
        // The wake-up latency in cyclictest's histogram format: "<µs> <count>" per line.
        let mut text = String::from("# nc-kernel wake-up latency histogram, µs\n");
        let mut buckets = std::collections::BTreeMap::<u64, u64>::new();
        for v in stats.wakeup.iter_recorded() {
            *buckets.entry(v.value_iterated_to() / 1000).or_default() += v.count_at_value();
        }
        for (us, n) in buckets {
            text.push_str(&format!("{us:06} {n:06}\n"));
        }
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
