//! plc-sim: the simulated PLC and axes of a softnc instance (docs/ipc.md).
//!
//! Woken by the kernel's setpoint event, it runs one drive cycle per setpoint: the axes'
//! position loops (axis.rs) and the spindle drives, which follow the kernel's speed setpoint
//! at `plc.spindle_acceleration` (spindle.rs). It answers auxiliary functions when they are
//! done (M6 after the tool change time, M3/M4 with the spindle at speed, M5 at rest, M19
//! oriented), publishes the PLC interface signals (its sign of life for the kernel, and the
//! spindles' actual speed for feed per revolution) and the actual values, and writes a CSV
//! trace. When setpoints stay away for `plc.watchdog_cycles` cycles of its own clock, its
//! watchdog brakes the axes and the spindles and raises PLC alarm 700000; setpoints from a
//! kernel in RESET acknowledge it.
//!
//! The PLC is a state machine over a transport ([`plc::Plc`], [`plc::Transport`]); the
//! process runs it over iceoryx2 (ice.rs) until SIGINT or SIGTERM.
//!
//! Scripted PLC inputs, as from a machine's control panel, for tests and demonstrations:
//! `--estop-at C`, `--feed-hold C:N`, `--read-in-disable C:N`, `--drives-off-at C` act at
//! kernel cycle C (for N cycles).

pub mod args;
mod axis;
mod drives;
mod ice;
pub mod plc;
pub mod spindle;
mod trace;

pub use args::PlcArgs;

use nc_runtime::Failure;
use plc::{Plc, Script};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The plc-sim process.
pub fn main(args: PlcArgs) -> Result<(), Failure> {
    let instance = &args.control.instance;
    let md = nc_runtime::process::args::machine(args.control.machine.as_deref())?;
    let axes = nc_runtime::WireAxes::new(&md).list;
    let trace = args
        .trace
        .as_deref()
        .map(|p| trace::create(p, &axes, spindle::CONFIGURED))
        .transpose()?;
    let term = Arc::new(AtomicBool::new(false));
    {
        let term = term.clone();
        ctrlc::set_handler(move || term.store(true, Ordering::SeqCst))
            .map_err(|e| format!("cannot install the signal handler: {e}"))?;
    }
    let mut io = ice::Ice::open(instance, trace)?;
    eprintln!(
        "plc-sim: instance '{}' ready; axes {}, kv {}/s, dead time {} cycles, watchdog {} cycles, spindle {} rev/min per s",
        instance.name(),
        axes.names().collect::<String>(),
        md.plc.kv,
        md.plc.dead_time_cycles,
        md.plc.watchdog_cycles,
        md.plc.spindle_acceleration
    );
    // SCHED_FIFO for the drive cycle, as a PLC's cyclic task runs: one below the kernel's
    // IPO thread (80) unless --priority says otherwise.
    let (rt, _keep) = nc_runtime::os::setup_cyclic_thread(args.priority, 1);
    eprintln!("plc-sim: {rt}");
    let script = Script {
        estop_at: args.estop_at,
        feed_hold: args.feed_hold,
        read_in_disable: args.read_in_disable,
        drives_off_at: args.drives_off_at,
    };
    let mut plc = Plc::new(&md, script, nc_runtime::os::now_ns());
    while !term.load(Ordering::SeqCst) {
        plc.cycle(&mut io);
    }
    io.finish()?;
    eprintln!("plc-sim: {}", plc.stats().summary());
    if let Some(path) = &args.histogram {
        std::fs::write(path, plc.stats().histogram())
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}
