//! The baseline for the setpoint latency bench (issue 6): the plainest wake-up of one
//! process by another, a pipe. The sender runs the IPO thread's timing (SCHED_FIFO, absolute
//! clock_nanosleep per cycle) and writes `seq, sent_ns, deadline_ns` every cycle; a child
//! process blocks in read(2) on the pipe and records, as plc-sim does for a setpoint, the
//! time from send to receive and whether it came after the cycle's deadline.
//!
//! `wake_baseline --seconds S [--cycle-us C] [--priority P] [--receiver-priority P]
//!  --histogram FILE` (FILE gets the receiver's histogram, in plc-sim's format).

use nc_runtime::os::{now_ns, setup_cyclic_thread, sleep_until};
use std::io::{Read, Write};
use std::process::{Command, ExitCode, Stdio};

fn value<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    args.windows(2)
        .find(|w| w[0] == flag)
        .map(|w| w[1].as_str())
}

fn number(args: &[String], flag: &str, default: u64) -> Result<u64, String> {
    value(args, flag).map_or(Ok(default), |v| {
        v.parse()
            .map_err(|_| format!("{flag} {v}: expected a whole number"))
    })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let r = if args.iter().any(|a| a == "--receive") {
        receive(&args)
    } else {
        send(&args)
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("wake_baseline: error: {e}");
            ExitCode::from(2)
        }
    }
}

fn send(args: &[String]) -> Result<(), String> {
    let seconds = number(args, "--seconds", 10)?;
    let cycle_ns = number(args, "--cycle-us", 1000)? * 1000;
    let prio = number(args, "--priority", 80)? as i32;
    let rprio = number(args, "--receiver-priority", 79)? as i32;
    let hist = value(args, "--histogram").ok_or("--histogram FILE is needed")?;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut child = Command::new(exe)
        .args(["--receive", "--priority", &rprio.to_string()])
        .args(["--histogram", hist])
        .stdin(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start the receiver: {e}"))?;
    let mut pipe = child.stdin.take().ok_or("no pipe to the receiver")?;
    let (rt, _keep) = setup_cyclic_thread(prio, 1);
    eprintln!("wake_baseline sender: {rt}");
    let cycles = seconds * 1_000_000_000 / cycle_ns;
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

fn receive(args: &[String]) -> Result<(), String> {
    let prio = number(args, "--priority", 79)? as i32;
    let hist = value(args, "--histogram").ok_or("--histogram FILE is needed")?;
    let (rt, _keep) = setup_cyclic_thread(prio, 1);
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
    std::fs::write(hist, text).map_err(|e| format!("{hist}: {e}"))
}
