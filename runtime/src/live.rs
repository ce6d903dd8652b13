//! The kernel on the live clock: the IPO thread wakes at absolute deadlines one IPO cycle
//! apart (clock_nanosleep TIMER_ABSTIME), runs the channel's cycle and hands the setpoint to
//! a sink (the IPC publisher in the process; a recorder in tests and benchmarks).
//!
//! Measured per cycle, into histograms allocated before the loop: the wake-up latency (how
//! late after its deadline the thread ran) and the compute time of the cycle.

use crate::os::{self, RtReport};
use hdrhistogram::Histogram;
use nc_kernel::handover::{with_preparation, Handover, Job, Report};
use nc_kernel::ipo::Input;
use nc_kernel::ipo::{Channel, ChannelState, Setpoint};
use nc_kernel::{MachineData, ToolTable};
use std::time::Duration;

#[derive(Clone, Debug)]
pub struct LiveOptions {
    /// SCHED_FIFO priority asked for (1–99).
    pub priority: i32,
    /// Timer slack asked for, ns (1 = the smallest the kernel allows).
    pub slack_ns: u64,
    /// Stop after this long even if the program has not ended (None: run to the end).
    pub limit: Option<Duration>,
    /// Path override, 0–1.2.
    pub override_: f64,
    /// Say on stderr what the IPO thread got (scheduling, locked memory, timer slack) before
    /// its first cycle.
    pub announce: bool,
}

impl Default for LiveOptions {
    fn default() -> Self {
        LiveOptions {
            priority: 80,
            slack_ns: 1,
            limit: None,
            override_: 1.0,
            announce: false,
        }
    }
}

/// What a live run measured.
pub struct LiveStats {
    pub rt: RtReport,
    pub cycles: u64,
    /// Wake-up latency after each deadline, ns.
    pub wakeup: Histogram<u64>,
    /// Work per cycle (taking input, the channel's cycle, the sink), ns.
    pub compute: Histogram<u64>,
    /// Cycles whose work ended after the next cycle's start.
    pub overruns: u64,
    /// Periods skipped because a cycle started a period or more late (runtime/clock.rs).
    pub skipped: u64,
    /// Cycles that found the lookahead not full while preparation was still running.
    pub starved: u64,
    pub end_state: ChannelState,
    pub reports: Vec<Report>,
}

fn histogram() -> Histogram<u64> {
    // 1 ns .. 10 s at 3 significant digits: allocated once, recording never allocates.
    Histogram::new_with_bounds(1, 10_000_000_000, 3).expect("valid histogram bounds")
}

/// Runs the program on the live clock. `sink` gets every setpoint in the IPO thread: it
/// must not block or allocate either. An error: a thread could not be started.
pub fn run(
    name: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
    opts: &LiveOptions,
    sink: &mut (dyn FnMut(&Setpoint) + Send),
) -> std::io::Result<LiveStats> {
    let job = Job {
        name,
        source,
        md,
        tools,
        at: None,
    };
    let cycle_ns = u64::from(md.ipo.cycle_us) * 1000;
    let (stats, reports) = with_preparation(job, Duration::ZERO, |start, hand| {
        std::thread::scope(|scope| {
            std::thread::Builder::new()
                .name("ipo".into())
                .spawn_scoped(scope, move || {
                    ipo_thread(md, start, hand, opts, cycle_ns, sink)
                })
                .map_err(std::io::Error::other)?
                .join()
                .map_err(|_| std::io::Error::other("the IPO thread panicked"))
        })
    })?;
    let mut stats = stats?;
    stats.reports = reports;
    Ok(stats)
}

fn ipo_thread(
    md: &MachineData,
    start: nc_kernel::AxisPos,
    hand: &Handover,
    opts: &LiveOptions,
    cycle_ns: u64,
    sink: &mut (dyn FnMut(&Setpoint) + Send),
) -> LiveStats {
    // Everything the loop needs is made here, before the real-time part starts.
    let mut ch = Box::new(Channel::new(md, start));
    ch.set_override(opts.override_);
    let mut sp = Box::new(Setpoint::new(start));
    let mut wakeup = histogram();
    let mut compute = histogram();
    let (rt, _latency_request) = os::setup_cyclic_thread(opts.priority, opts.slack_ns);
    if opts.announce {
        eprintln!("IPO thread: {rt}; cycle {} µs", cycle_ns / 1000);
    }
    let mut pending: Option<Input> = None;
    let (mut overruns, mut starved) = (0u64, 0u64);
    let limit_cycles = opts
        .limit
        .map_or(u64::MAX, |d| (d.as_nanos() as u64 / cycle_ns).max(1));
    ch.start();
    let mut spindle =
        nc_kernel::ipo::SpindleModel::new(md.plc.spindle_acceleration, cycle_ns as f64 * 1e-9);
    let mut clock = crate::clock::CycleClock::new(cycle_ns);
    let mut k: u64 = 0;
    loop {
        let tick = clock.wait();
        let woke = tick.woke;
        let _ = wakeup.record(woke.saturating_sub(tick.start).max(1));
        // Take what is there, never wait.
        ch.fill(&mut pending, || hand.pop());
        if !ch.input_done() && pending.is_none() && ch.planner().room() > 0 {
            starved += 1;
        }
        while ch.acks_due() > 0 {
            // No PLC in this process: acknowledged at once.
            ch.ack();
        }
        ch.cycle(k, &mut sp);
        // No PLC in this process: its spindle drive is the kernel's model.
        ch.set_spindle_actual(spindle.follow(sp.spindle));
        sink(&sp);
        let done = os::now_ns();
        let _ = compute.record(done.saturating_sub(woke).max(1));
        if done > tick.deadline {
            overruns += 1;
        }
        k += 1;
        match sp.state {
            ChannelState::End => break,
            ChannelState::Stopped if ch.has_alarm() => break,
            ChannelState::Stopped => ch.start(),
            _ => {}
        }
        if k >= limit_cycles {
            break;
        }
    }
    LiveStats {
        rt,
        cycles: k,
        wakeup,
        compute,
        overruns,
        skipped: clock.skipped(),
        starved,
        end_state: sp.state,
        reports: Vec::new(),
    }
}
