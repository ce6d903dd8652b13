//! The baseline for the setpoint latency bench (issue 6): the plainest wake-up of one
//! process by another, a pipe. The sender runs the IPO thread's timing (SCHED_FIFO, absolute
//! clock_nanosleep per cycle) and writes `seq, sent_ns, deadline_ns` every cycle; a child
//! process blocks in read(2) on the pipe and records, as plc-sim does for a setpoint, the
//! time from send to receive and whether it came after the cycle's deadline.
//!
//! `wake_baseline --seconds S [--cycle-us C] [--priority P] [--receiver-priority P]
//!  --histogram FILE` (FILE gets the receiver's histogram, in plc-sim's format).

use clap::Parser;
use nc_runtime::os::{now_ns, setup_cyclic_thread, sleep_until};
use nc_runtime::Failure;
use std::io::{Read, Write};
use std::path::PathBuf;
use std::process::{Command, ExitCode, Stdio};

/// A pipe's wake-up latency between two processes, the baseline of the setpoint latency.
#[derive(Parser, Debug)]
#[command(name = "wake_baseline")]
struct Args {
    /// Seconds to send for.
    #[arg(long, default_value_t = 10)]
    seconds: u64,
    /// The cycle, µs.
    #[arg(long = "cycle-us", default_value_t = 1000)]
    cycle_us: u64,
    /// The sender's SCHED_FIFO priority (the receiver's with --receive).
    #[arg(long, value_parser = nc_runtime::process::args::priority)]
    priority: Option<i32>,
    /// The receiver's SCHED_FIFO priority.
    #[arg(long, default_value_t = 79, value_parser = nc_runtime::process::args::priority)]
    receiver_priority: i32,
    /// Where the receiver writes its histogram.
    #[arg(long, value_name = "FILE")]
    histogram: PathBuf,
    /// Be the receiver (the sender starts it so).
    #[arg(long, hide = true)]
    receive: bool,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let r = if args.receive {
        receive(&args)
    } else {
        send(&args)
    };
    nc_runtime::exit(Some("wake_baseline"), r.map_err(Failure::Error))
}

fn send(args: &Args) -> Result<(), String> {
    let cycle_ns = args.cycle_us * 1000;
    let rprio = args.receiver_priority;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut child = Command::new(exe)
        .args(["--receive", "--priority", &rprio.to_string()])
        .arg("--histogram")
        .arg(&args.histogram)
        .stdin(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start the receiver: {e}"))?;
    let mut pipe = child.stdin.take().ok_or("no pipe to the receiver")?;
    let (rt, _keep) = setup_cyclic_thread(args.priority.unwrap_or(80), 1);
    eprintln!("wake_baseline sender: {rt}");
    let cycles = args.seconds * 1_000_000_000 / cycle_ns;
    let t0 = now_ns() + 100 * cycle_ns;
    for k in 0..cycles {
        sleep_until(t0 + k * cycle_ns);
        let mut msg = [0u8; 24];
        msg[..8].copy_from_slice(&(k + 1).to_ne_bytes());
        msg[8..16].copy_from_slice(&now_ns().to_ne_bytes());
        msg[16..].copy_from_slice(&(t0 + (k + 1) * cycle_ns).to_ne_bytes());
        pipe.write_all(&msg)
            .map_err(|e| format!("the receiver went away: {e}"))?;
    }
    drop(pipe);
    let status = child.wait().map_err(|e| e.to_string())?;
    if !status.success() {
        return Err(format!("the receiver ended with {status}"));
    }
    Ok(())
}

fn receive(args: &Args) -> Result<(), String> {
    let hist = &args.histogram;
    let (rt, _keep) = setup_cyclic_thread(args.priority.unwrap_or(79), 1);
    eprintln!("wake_baseline receiver: {rt}");
    let mut latency = hdrhistogram::Histogram::<u64>::new_with_bounds(1, 10_000_000_000, 3)
        .map_err(|e| e.to_string())?;
    let (mut samples, mut lost, mut late, mut last) = (0u64, 0u64, 0u64, 0u64);
    let mut input = std::io::stdin().lock();
    let mut msg = [0u8; 24];
    while input.read_exact(&mut msg).is_ok() {
        let now = now_ns();
        let word =
            |i: usize| u64::from_ne_bytes(msg[i * 8..i * 8 + 8].try_into().unwrap_or([0; 8]));
        let (seq, sent, deadline) = (word(0), word(1), word(2));
        samples += 1;
        let _ = latency.record(now.saturating_sub(sent).max(1));
        if now > deadline {
            late += 1;
        }
        lost += seq.saturating_sub(last + 1);
        last = seq;
    }
    let text = nc_runtime::histogram_text(
        "pipe wake-up latency (write to read)",
        &latency,
        &[("samples", samples), ("lost", lost), ("late", late)],
    );
    std::fs::write(hist, text).map_err(|e| format!("{}: {e}", hist.display()))
}
