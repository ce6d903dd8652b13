//! plc-sim's command line: one clap definition for its own binary and `softnc plc-sim`.

use nc_runtime::process::args::{priority, ControlArgs};
use std::path::PathBuf;

/// The simulated PLC and axes of a softnc control: position loops, auxiliary functions,
/// the sign of life, a setpoint watchdog and a CSV trace.
///
/// Scripted inputs, as from a machine's control panel, act at kernel cycle CYCLE (for
/// CYCLES cycles).
#[derive(clap::Parser, Debug)]
#[command(name = "plc-sim")]
pub struct PlcArgs {
    #[command(flatten)]
    pub control: ControlArgs,
    /// Write the CSV trace to FILE: setpoint, actual (A…) and following error (F…) of
    /// every configured axis, speed setpoint (S…) and actual speed (AS…) of every spindle
    /// (`time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,S1,AS1,v_path,line,state,events` on a
    /// three-axis mill).
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Press emergency stop at kernel cycle CYCLE.
    #[arg(long, value_name = "CYCLE")]
    pub estop_at: Option<u64>,
    /// Feed hold from kernel cycle CYCLE for CYCLES cycles.
    #[arg(long, value_name = "CYCLE:CYCLES", value_parser = window)]
    pub feed_hold: Option<Window>,
    /// Read-in disable from kernel cycle CYCLE for CYCLES cycles.
    #[arg(long, value_name = "CYCLE:CYCLES", value_parser = window)]
    pub read_in_disable: Option<Window>,
    /// Drop the drives' ready signal at kernel cycle CYCLE.
    #[arg(long, value_name = "CYCLE")]
    pub drives_off_at: Option<u64>,
    /// The drive cycle's SCHED_FIFO priority, 1 to 99: one below the kernel's IPO thread.
    #[arg(long, value_name = "P", value_parser = priority, default_value_t = 79)]
    pub priority: i32,
    /// Write the setpoint latency histogram to FILE, in cyclictest's format.
    #[arg(long, value_name = "FILE")]
    pub histogram: Option<PathBuf>,
}

/// Kernel cycles `from` to `from + cycles` (not included).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    pub from: u64,
    pub cycles: u64,
}

impl Window {
    pub fn contains(self, cycle: u64) -> bool {
        cycle >= self.from && cycle - self.from < self.cycles
    }
}

/// `CYCLE:CYCLES`.
fn window(v: &str) -> Result<Window, String> {
    let bad = || "expected CYCLE:CYCLES".to_string();
    let (a, b) = v.split_once(':').ok_or_else(bad)?;
    match (a.parse::<u64>(), b.parse::<u64>()) {
        (Ok(from), Ok(cycles)) => Ok(Window { from, cycles }),
        _ => Err(bad()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[test]
    fn scripted_inputs_as_tests_and_softnc_run_give_them() {
        let a = PlcArgs::try_parse_from([
            "plc-sim",
            "--instance",
            "t-hold",
            "--trace",
            "t.csv",
            "--feed-hold",
            "2000:1000",
            "--read-in-disable",
            "5000:1500",
            "--estop-at=3000",
            "--drives-off-at",
            "2500",
        ])
        .unwrap();
        assert_eq!(a.control.instance.name(), "t-hold");
        assert_eq!(
            a.feed_hold,
            Some(Window {
                from: 2000,
                cycles: 1000
            })
        );
        assert_eq!(a.read_in_disable.map(|w| w.cycles), Some(1500));
        assert_eq!((a.estop_at, a.drives_off_at), (Some(3000), Some(2500)));
        assert_eq!(a.priority, 79);
        let w = Window {
            from: 10,
            cycles: 2,
        };
        assert_eq!(
            [9, 10, 11, 12].map(|c| w.contains(c)),
            [false, true, true, false]
        );
        let d = PlcArgs::try_parse_from(["plc-sim"]).unwrap();
        assert_eq!(d.control.instance.name(), softnc_protocol::DEFAULT_INSTANCE);
        for bad in ["2000", "2000:", ":5", "a:b", "1:2:3"] {
            assert!(
                PlcArgs::try_parse_from(["plc-sim", "--feed-hold", bad]).is_err(),
                "{bad}"
            );
        }
    }
}
