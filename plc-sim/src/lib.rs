//! plc-sim: the simulated PLC and axes of a softnc instance (issue 6).
//!
//! Woken by the kernel's setpoint event, it runs one drive cycle per setpoint (axis.rs),
//! answers auxiliary functions (tool change and spindle ramp take their time), publishes the
//! PLC interface signals (its sign of life for the kernel) and the actual values, and writes
//! a CSV trace. When setpoints stay away for `plc.watchdog_cycles` cycles of its own clock,
//! its watchdog brakes the axes and raises PLC alarm 700000; setpoints from a kernel in RESET
//! acknowledge it.
//!
//! Scripted PLC inputs, as from a machine's control panel, for tests and demonstrations:
//! `--estop-at C`, `--feed-hold C:N`, `--read-in-disable C:N`, `--drives-off-at C` act at
//! kernel cycle C (for N cycles).

pub mod args;
pub mod axis;

pub use args::PlcArgs;

use args::Window;
use axis::Axis;
use nc_kernel::MachineData;
use nc_runtime::os::now_ns;
use nc_runtime::Failure;
use softnc_protocol::iceoryx2::port::server::Server;
use softnc_protocol::iceoryx2::prelude::ipc;
use softnc_protocol::{state, ActualValues, AuxAck, AuxRequest, PlcSignals, SetpointMsg};
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// PLC alarms (the 840D's range for user PLC alarms starts at 700000).
mod plc_alarm {
    /// Setpoints missing for `plc.watchdog_cycles`: the axes were braked.
    pub const WATCHDOG: u32 = 700_000;
    /// A setpoint beyond a software limit switch: the axis stops at the limit.
    pub const SOFTWARE_LIMIT: u32 = 700_001;
}

struct Script {
    estop_at: Option<u64>,
    feed_hold: Option<Window>,
    read_in_disable: Option<Window>,
    drives_off_at: Option<u64>,
}

fn within(w: Option<Window>, c: u64) -> bool {
    w.is_some_and(|w| w.contains(c))
}

/// The plc-sim process.
pub fn main(args: PlcArgs) -> Result<(), Failure> {
    run(args).map_err(Failure::Error)
}

struct Pending {
    due_ns: u64,
    req: softnc_protocol::iceoryx2::active_request::ActiveRequest<
        ipc::Service,
        AuxRequest,
        (),
        AuxAck,
        (),
    >,
    id: u64,
    text: String,
}

fn run(args: PlcArgs) -> Result<(), String> {
    let instance = args.control.instance.clone();
    let md = nc_runtime::process::args::machine(args.control.machine.as_deref())?;
    let script = Script {
        estop_at: args.estop_at,
        feed_hold: args.feed_hold,
        read_in_disable: args.read_in_disable,
        drives_off_at: args.drives_off_at,
    };
    let priority = args.priority;
    let mut trace = match &args.trace {
        Some(p) => Some(std::io::BufWriter::new(
            std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()))?,
        )),
        None => None,
    };
    if let Some(t) = &mut trace {
        writeln!(
            t,
            "time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,v_path,line,state,events"
        )
        .map_err(|e| e.to_string())?;
    }

    let term = Arc::new(AtomicBool::new(false));
    {
        let term = term.clone();
        ctrlc::set_handler(move || term.store(true, Ordering::SeqCst))
            .map_err(|e| format!("cannot install the signal handler: {e}"))?;
    }
    let (cleaned, _) = instance.cleanup_dead_nodes();
    if cleaned > 0 {
        eprintln!(
            "plc-sim: removed what {cleaned} dead process(es) of instance '{}' left behind",
            instance.name()
        );
    }
    let node = instance.node("plc-sim").map_err(|e| e.to_string())?;
    let e = |w: &str, x: &dyn std::fmt::Debug| format!("cannot create the {w}: {x:?}");
    let setpoints = instance
        .setpoints(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .create()
        .map_err(|x| e("setpoint subscriber", &x))?;
    let listener = instance
        .setpoint_event(&node)
        .map_err(|e| e.to_string())?
        .listener_builder()
        .create()
        .map_err(|x| e("setpoint listener", &x))?;
    let server: Server<ipc::Service, AuxRequest, (), AuxAck, ()> = instance
        .aux(&node)
        .map_err(|e| e.to_string())?
        .server_builder()
        .create()
        .map_err(|x| e("aux server", &x))?;
    let signals = instance
        .plc_signals(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .create()
        .map_err(|x| e("signal publisher", &x))?;
    let actuals = instance
        .actual_values(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .create()
        .map_err(|x| e("actual-value publisher", &x))?;
    // Opened so that the instance's services exist whoever starts first.
    instance.status(&node).map_err(|e| e.to_string())?;
    instance.commands(&node).map_err(|e| e.to_string())?;

    let cycle_ns = u64::from(md.ipo.cycle_us) * 1000;
    let t = cycle_ns as f64 * 1e-9;
    let n_watch = u64::from(md.plc.watchdog_cycles);
    eprintln!(
        "plc-sim: instance '{}' ready; kv {}/s, dead time {} cycles, watchdog {} cycles",
        instance.name(),
        md.plc.kv,
        md.plc.dead_time_cycles,
        n_watch
    );

    // SCHED_FIFO for the drive cycle, as a PLC's cyclic task runs: one below the kernel's
    // IPO thread (80) unless --priority says otherwise.
    let (rt, _keep) = nc_runtime::os::setup_cyclic_thread(priority, 1);
    eprintln!("plc-sim: {rt}");
    let mut axes: Option<[Axis; 3]> = None;
    let mut last: Option<SetpointMsg> = None;
    // Own cycles (waits that timed out) since the last setpoint: the watchdog counts these,
    // not wall time, so a hold-up of the whole machine is not taken for a dead kernel.
    let mut missed: u64 = 0;
    let mut braking = false;
    let mut alarm: u32 = 0;
    let mut estop = false;
    let mut drives_ready = true;
    let mut lost: u64 = 0;
    let mut late: u64 = 0;
    let mut samples: u64 = 0;
    let mut latency = hdrhistogram::Histogram::<u64>::new_with_bounds(1, 10_000_000_000, 3)
        .map_err(|e| e.to_string())?;
    let mut pending: Vec<Pending> = Vec::new();
    let mut aux_acked: u32 = 0;
    let mut tool: u32 = 0;
    let mut spindle_rpm = 0.0f64;
    let mut spindle_target = 0.0f64;
    let mut sig_seq: u64 = 0;
    let mut act_seq: u64 = 0;
    let mut events = String::new();
    let start_ns = now_ns();

    while !term.load(Ordering::SeqCst) {
        // Wake on the kernel's event, or after one cycle without it.
        let mut event = false;
        let _ = listener.timed_wait(|_| event = true, Duration::from_nanos(cycle_ns));
        let mut got = false;
        while let Ok(Some(sample)) = setpoints.receive() {
            let sp = *sample.payload();
            drop(sample);
            let now = now_ns();
            samples += 1;
            let _ = latency.record(now.saturating_sub(sp.sent_ns).max(1));
            if now > sp.deadline_ns {
                late += 1;
            }
            match last {
                // A new kernel counts from 1 again.
                Some(l) if sp.seq > l.seq + 1 => {
                    lost += sp.seq - l.seq - 1;
                    events.push_str(&format!("lost {};", sp.seq - l.seq - 1));
                }
                _ => {}
            }
            got = true;
            missed = 0;
            if braking && sp.state == state::RESET {
                // The kernel was reset (or restarted): the watchdog alarm is acknowledged,
                // the drives follow the setpoints again from where they stand.
                braking = false;
                if alarm == plc_alarm::WATCHDOG {
                    alarm = 0;
                }
                axes = None;
                events.push_str("watchdog acknowledged;");
            }
            // At or after the cycle: a PLC that connects late still acts.
            if script.estop_at.is_some_and(|c| sp.cycle >= c) && !estop {
                estop = true;
                events.push_str("emergency stop;");
            }
            if script.drives_off_at.is_some_and(|c| sp.cycle >= c) && drives_ready {
                drives_ready = false;
                events.push_str("drives off;");
            }
            let (target, limited) = limit(&md, sp.pos);
            if limited && alarm == 0 {
                alarm = plc_alarm::SOFTWARE_LIMIT;
                events.push_str("software limit;");
            }
            let ax = axes.get_or_insert_with(|| new_axes(&md, t, target));
            let mut actual = [0.0; 3];
            if braking {
                for (a, x) in ax.iter_mut().zip(actual.iter_mut()) {
                    *x = a.brake();
                }
            } else {
                for i in 0..3 {
                    actual[i] = ax[i].step(target[i]);
                }
            }
            let fe = [
                ax[0].following_error,
                ax[1].following_error,
                ax[2].following_error,
            ];
            // Spindle ramp.
            let ds = md.plc.spindle_acceleration * t;
            spindle_rpm += (spindle_target - spindle_rpm).clamp(-ds, ds);
            if let Some(tr) = &mut trace {
                row(
                    tr,
                    (now - start_ns) as f64 * 1e-9,
                    sp.cycle,
                    sp.seq,
                    &sp.pos,
                    &actual,
                    &fe,
                    sp.v_path,
                    sp.line,
                    sp.state,
                    &events,
                );
            }
            events.clear();
            act_seq += 1;
            let _ = actuals.send_copy(ActualValues {
                seq: act_seq,
                cycle: sp.cycle,
                pos: actual,
                following_error: fe,
                spindle_rpm,
                tool,
                aux_acked,
                plc_alarm: alarm,
                _pad: 0,
            });
            last = Some(sp);
        }
        if !got && !event {
            let now = now_ns();
            if let (Some(ax), Some(l)) = (axes.as_mut(), last) {
                missed += 1;
                if missed >= n_watch && !braking {
                    braking = true;
                    if alarm == 0 {
                        alarm = plc_alarm::WATCHDOG;
                    }
                    events.push_str(&format!("watchdog: no setpoint for {missed} cycles;"));
                    eprintln!(
                            "plc-sim: alarm {}: no setpoint for {missed} cycles after cycle {}: braking the axes",
                            plc_alarm::WATCHDOG,
                            l.cycle
                        );
                }
                if braking {
                    let mut actual = [0.0; 3];
                    for (a, x) in ax.iter_mut().zip(actual.iter_mut()) {
                        *x = a.brake();
                    }
                    if let Some(tr) = &mut trace {
                        row(
                            tr,
                            (now - start_ns) as f64 * 1e-9,
                            l.cycle + missed,
                            0,
                            &l.pos,
                            &actual,
                            &[0.0; 3],
                            0.0,
                            l.line,
                            l.state,
                            &events,
                        );
                    }
                    events.clear();
                }
            }
        }
        // Auxiliary functions: take new requests, answer those whose time has come.
        while let Ok(Some(req)) = server.receive() {
            let r = *req.payload();
            let mut wait_ns = 0u64;
            let mut text = String::new();
            for w in r.words() {
                let v = w.value;
                text.push_str(&format!("{}{} ", w.address as char, v));
                match (w.address, v as i64) {
                    (b'M', 6) => {
                        wait_ns = wait_ns.max(u64::from(md.plc.tool_change_ms) * 1_000_000)
                    }
                    (b'T', n) => tool = n.max(0) as u32,
                    (b'M', 3) | (b'M', 4) => {}
                    (b'M', 5) => spindle_target = 0.0,
                    _ => {}
                }
            }
            // Spindle: M3/M4 at the programmed S (or the last one), acknowledged at speed.
            let s_word = r
                .words()
                .iter()
                .find(|w| w.address == b'S')
                .map(|w| w.value);
            let turns = r
                .words()
                .iter()
                .any(|w| w.address == b'M' && (w.value == 3.0 || w.value == 4.0));
            if turns {
                let target = s_word.unwrap_or(spindle_target.abs());
                spindle_target = target;
                let ramp = (target - spindle_rpm).abs() / md.plc.spindle_acceleration;
                wait_ns = wait_ns.max((ramp * 1e9) as u64);
            } else if let Some(s) = s_word {
                if spindle_rpm != 0.0 {
                    spindle_target = s;
                }
            }
            pending.push(Pending {
                due_ns: now_ns() + wait_ns,
                req,
                id: r.id,
                text: text.trim_end().to_string(),
            });
        }
        let now = now_ns();
        let mut i = 0;
        while i < pending.len() {
            if pending[i].due_ns <= now {
                let p = pending.swap_remove(i);
                let _ = p.req.send_copy(AuxAck {
                    id: p.id,
                    alarm: 0,
                    _pad: 0,
                });
                aux_acked += 1;
                events.push_str(&format!("ack {};", p.text));
            } else {
                i += 1;
            }
        }
        // Sign of life and interface signals, every cycle something happened.
        let c = last.map_or(0, |l| l.cycle);
        sig_seq += 1;
        let _ = signals.send_copy(PlcSignals {
            seq: sig_seq,
            echo_cycle: c,
            feed_hold: within(script.feed_hold, c) as u8,
            read_in_disable: within(script.read_in_disable, c) as u8,
            drives_ready: (drives_ready && !braking) as u8,
            emergency_stop: estop as u8,
            alarm,
        });
    }
    if let Some(mut tr) = trace {
        tr.flush().map_err(|e| e.to_string())?;
    }
    let q = |p: f64| latency.value_at_quantile(p) as f64 / 1000.0;
    eprintln!(
        "plc-sim: {samples} setpoints, {lost} lost, {late} after their deadline, {aux_acked} aux functions acknowledged; latency µs p50 {:.1} p99 {:.1} p99.9 {:.1} max {:.1}",
        q(0.5),
        q(0.99),
        q(0.999),
        latency.max() as f64 / 1000.0
    );
    if let Some(path) = &args.histogram {
        let text = nc_runtime::histogram_text(
            "plc-sim setpoint latency (kernel send to plc-sim receive)",
            &latency,
            &[("samples", samples), ("lost", lost), ("late", late)],
        );
        std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

fn new_axes(md: &MachineData, t: f64, at: [f64; 3]) -> [Axis; 3] {
    let mk = |i: usize| {
        let (v, a) = md
            .axes
            .get(i)
            .map_or((1.0, 1.0), |d| (d.max_velocity / 60.0, d.max_acceleration));
        Axis::new(md.plc.kv, t, v, a, md.plc.dead_time_cycles as usize, at[i])
    };
    [mk(0), mk(1), mk(2)]
}

/// The setpoint within the software limit switches, and whether it had to be cut.
fn limit(md: &MachineData, p: [f64; 3]) -> ([f64; 3], bool) {
    let mut out = p;
    let mut cut = false;
    for i in 0..3 {
        let (lo, hi) = (md.plc.software_limit_min[i], md.plc.software_limit_max[i]);
        if p[i] < lo || p[i] > hi {
            out[i] = p[i].clamp(lo, hi);
            cut = true;
        }
    }
    (out, cut)
}

#[allow(clippy::too_many_arguments)]
fn row(
    w: &mut impl Write,
    time: f64,
    cycle: u64,
    seq: u64,
    sp: &[f64; 3],
    act: &[f64; 3],
    fe: &[f64; 3],
    v: f64,
    line: u32,
    st: u8,
    events: &str,
) {
    let _ = writeln!(
        w,
        "{time:.6},{cycle},{seq},{},{},{},{},{},{},{},{},{},{},{line},{},{}",
        sp[0],
        sp[1],
        sp[2],
        act[0],
        act[1],
        act[2],
        fe[0],
        fe[1],
        fe[2],
        v * 60.0,
        state::name(st),
        events.trim_end_matches(';')
    );
}
