//! nc-kernel process: the NC kernel on the live clock — preparation thread, lock-free
//! queue, cyclic IPO thread (SCHED_FIFO, locked memory, absolute deadlines).
//!
//! `nc-kernel --instance NAME [PROGRAM] [--start] [--machine FILE] [--tools FILE]
//! [--offsets FILE] [--record FILE [--setpoints FILE]]`: a process
//! of the control, talking to plc-sim and the HMI over iceoryx2 (serve.rs).
//!
//! `nc-kernel PROGRAM [--machine FILE] [--tools FILE] [--seconds S] [--priority P]`: the
//! program alone, no PLC (auxiliary functions acknowledged at once), with the IPO thread's
//! wake-up latency and compute time (the latency benchmark). The arguments: [`KernelArgs`].

pub mod args;
mod bus;
pub mod kept;
mod serve;

pub use args::KernelArgs;

use crate::live::{run, LiveOptions, LiveStats};
use crate::Failure;
use nc_kernel::handover::Report;
use std::path::Path;
use std::time::Duration;

/// The nc-kernel process.
pub fn main(args: KernelArgs) -> Result<(), Failure> {
    let mut md = args::machine(args.machine.as_deref())?;
    if let Some(p) = &args.offsets {
        md.work_offsets = nc_kernel::WorkOffsets::load(p, &md).map_err(|e| e.to_string())?;
    }
    if let Some(p) = &args.macro_variables {
        md.kept_variables = std::sync::Arc::new(kept::load(p)?);
    }
    let tools = args.tool_table()?;
    if let Some(instance) = args.instance {
        return serve::run(serve::ServeOptions {
            instance,
            program: args.program.map(|p| p.display().to_string()),
            start: args.start,
            md,
            tools,
            tools_path: args.tools,
            offsets_path: args.offsets,
            kept_path: args.macro_variables,
            priority: args.priority,
            record: args.record,
            setpoints: args.setpoints,
        });
    }
    let Some(program) = &args.program else {
        return Err(
            "no program given (or --instance NAME to run as a process of the control)".into(),
        );
    };
    let opts = LiveOptions {
        announce: true,
        priority: args.priority,
        limit: args.seconds.map(Duration::from_secs_f64),
        ..Default::default()
    };
    let name = program.display().to_string();
    let source = crate::read_program(program).map_err(|e| format!("{name}: {e}"))?;
    md.programs = std::sync::Arc::new(crate::program_library(program, &md.program.search_path)?);
    let mut setpoints = 0u64;
    let stats = run(&name, &source, &md, &tools, &opts, &mut |_sp| {
        setpoints += 1
    })
    .map_err(|e| format!("cannot start the kernel's threads: {e}"))?;
    let mut alarms = 0;
    for r in &stats.reports {
        match r {
            Report::Warning(w) => eprintln!("{}", md.programs.render(w, &source)),
            Report::Alarm(a) => {
                alarms += 1;
                eprintln!("{}", md.programs.render(a, &source));
            }
            Report::KeptVariables(k) => {
                if let Some(path) = &args.macro_variables {
                    kept::save(path, k)?;
                }
            }
        }
    }
    print_latency(&name, setpoints, &stats);
    if let Some(path) = &args.histogram {
        write_histogram(path, &stats)?;
    }
    if alarms > 0 {
        return Err(Failure::Reported);
    }
    Ok(())
}

fn print_latency(program: &str, setpoints: u64, stats: &LiveStats) {
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
}

fn write_histogram(path: &Path, stats: &LiveStats) -> Result<(), Failure> {
    let text = crate::histogram_text("nc-kernel wake-up latency", &stats.wakeup, &[]);
    std::fs::write(path, text).map_err(|e| Failure::Error(format!("{}: {e}", path.display())))
}
