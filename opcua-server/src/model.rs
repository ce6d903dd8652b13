//! The machine as OPC 40501-1 (OPC UA for Machine Tools) shows it, the subset softnc can
//! fill from what the kernel publishes: what the variables say, computed from a
//! [`Snapshot`] of the bridge's link. No OPC UA types here: `space.rs` builds the nodes and
//! writes these values into them. docs/opcua.md has the node tree and the mapping.

use hmi_bridge::link::Snapshot;
use nc_kernel::cycle::ChannelAlarm;
use softnc_protocol::{state, ToolEntry};

/// OPC 40501-1 12.1 ChannelState.
pub mod channel_state {
    pub const ACTIVE: i32 = 0;
    pub const INTERRUPTED: i32 = 1;
    pub const RESET: i32 = 2;
}

/// OPC 40501-1 12.2 ChannelMode: softnc's channel runs programs only.
pub const CHANNEL_MODE_AUTOMATIC: i32 = 0;

/// The ProductionStateMachine's states (OPC 40501-1 8.4.5) as `CurrentState` names them.
pub mod production_state {
    pub const INITIALIZING: &str = "Initializing";
    pub const RUNNING: &str = "Running";
    pub const ENDED: &str = "Ended";
    pub const INTERRUPTED: &str = "Interrupted";
    pub const ABORTED: &str = "Aborted";
}

/// The channel's state as OPC 40501-1 counts it: NC stop interrupts (the program can go
/// on), a program at its end or in reset leaves the channel idle (Reset).
pub fn channel_state(kernel_state: u8) -> i32 {
    match kernel_state {
        state::ACTIVE => channel_state::ACTIVE,
        state::STOPPED => channel_state::INTERRUPTED,
        _ => channel_state::RESET,
    }
}

/// The active program's production state: running while the channel runs it, interrupted
/// in NC stop, ended at its end, aborted when an alarm or a reset ended it early, and
/// initializing while loaded and not yet started.
pub fn production_state(kernel_state: u8, alarm: u32, started: bool) -> &'static str {
    match kernel_state {
        state::ACTIVE => production_state::RUNNING,
        state::STOPPED => production_state::INTERRUPTED,
        state::END => production_state::ENDED,
        _ if alarm != 0 || started => production_state::ABORTED,
        _ => production_state::INITIALIZING,
    }
}

/// The program's name: its file name without folders (the kernel's path is absolute).
pub fn program_name(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
}

/// One standing alarm as Notification shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct AlarmView {
    pub number: u32,
    pub text: String,
    pub program: String,
    pub line: u32,
}

/// What the channel's variables say at one moment.
#[derive(Clone, Debug, PartialEq)]
pub struct Values {
    /// The kernel's status arrived within the bridge's alive time.
    pub connected: bool,
    pub channel_state: i32,
    pub channel_mode: i32,
    /// Percent.
    pub feed_override: f64,
    /// mm/min.
    pub feed_rate: f64,
    pub program_name: String,
    pub program_path: String,
    pub line: u32,
    /// The text of the running line, from the program's file.
    pub block: String,
    pub production_state: &'static str,
    /// rev/min, negative counter-clockwise.
    pub spindle_setpoint: f64,
    pub spindle_actual: f64,
    pub spindle_rotating: bool,
    pub tool: u32,
    pub edge: u32,
    /// The channel's alarm and the PLC's, those standing.
    pub alarms: Vec<AlarmView>,
}

/// A speed below this counts as standing still, rev/min.
const ROTATING: f64 = 0.5;

impl Values {
    /// The values for `snap`; `block` the running line's text, `started` whether the
    /// program has been seen running since its load.
    pub fn new(snap: &Snapshot, block: &str, started: bool) -> Values {
        let st = snap.status.unwrap_or_default();
        let path = snap.program_path.clone().unwrap_or_default();
        let name = program_name(&path).to_string();
        let actual = snap.actual.map_or(0.0, |a| a.spindle_rpm[0]);
        let mut alarms = Vec::new();
        for number in [st.alarm, snap.actual.map_or(0, |a| a.plc_alarm)] {
            if let Some(a) = ChannelAlarm::new(number) {
                alarms.push(AlarmView {
                    number: a.number(),
                    text: a.title().to_string(),
                    program: name.clone(),
                    line: st.line,
                });
            }
        }
        Values {
            connected: snap.connected(),
            channel_state: channel_state(st.state),
            channel_mode: CHANNEL_MODE_AUTOMATIC,
            feed_override: st.override_ * 100.0,
            feed_rate: st.v_path * 60.0,
            program_name: name,
            program_path: path,
            line: st.line,
            block: block.to_string(),
            production_state: production_state(st.state, st.alarm, started),
            spindle_setpoint: st.spindle[0],
            spindle_actual: actual,
            spindle_rotating: actual.abs() >= ROTATING,
            tool: st.tool,
            edge: st.edge,
            alarms,
        }
    }
}

/// A tool offset's node name: `T1 D2` where D numbers count per tool, `D3` otherwise.
pub fn tool_name(e: &ToolEntry) -> String {
    if e.t == 0 {
        format!("D{}", e.d)
    } else {
        format!("T{} D{}", e.t, e.d)
    }
}

/// The text of line `line` (1-based) of `text`, trimmed; empty past its end or for 0.
pub fn line_text(text: &str, line: u32) -> &str {
    let Some(i) = (line as usize).checked_sub(1) else {
        return "";
    };
    text.lines().nth(i).map_or("", str::trim)
}

#[cfg(test)]
mod tests {
    use super::*;
    use softnc_protocol::{ActualValues, KernelStatus};
    use std::time::Duration;

    fn snapshot(st: KernelStatus, path: &str) -> Snapshot {
        Snapshot {
            status: Some(st),
            status_age: Some(Duration::from_millis(10)),
            program_path: Some(path.into()),
            ..Snapshot::default()
        }
    }

    /// A program running at 80 % override, 1200 mm/min path speed (20 mm/s × 60), in line 7
    /// with T1 D1, the spindle at 1500 rev/min set and 1498 actual.
    #[test]
    fn a_running_program() {
        let mut st = KernelStatus {
            state: state::ACTIVE,
            override_: 0.8,
            v_path: 20.0,
            line: 7,
            tool: 1,
            edge: 1,
            ..KernelStatus::default()
        };
        st.spindle[0] = 1500.0;
        let mut snap = snapshot(st, "/shop/programs/part.mpf");
        let mut a = ActualValues::default();
        a.spindle_rpm[0] = 1498.0;
        snap.actual = Some(a);
        let v = Values::new(&snap, "N70 X10 Y5", true);
        assert!(v.connected);
        assert_eq!(v.channel_state, channel_state::ACTIVE);
        assert_eq!(v.channel_mode, 0);
        assert!((v.feed_override - 80.0).abs() < 1e-9);
        assert!((v.feed_rate - 1200.0).abs() < 1e-9);
        assert_eq!(v.program_name, "part.mpf");
        assert_eq!(v.line, 7);
        assert_eq!(v.block, "N70 X10 Y5");
        assert_eq!(v.production_state, production_state::RUNNING);
        assert_eq!((v.spindle_setpoint, v.spindle_actual), (1500.0, 1498.0));
        assert!(v.spindle_rotating);
        assert_eq!((v.tool, v.edge), (1, 1));
        assert!(v.alarms.is_empty());
    }

    /// NC stop interrupts; the end leaves the channel in Reset with the program Ended; a
    /// reset after a start aborts it; loaded and never started it is initializing.
    #[test]
    fn states_follow_the_channel() {
        assert_eq!(channel_state(state::STOPPED), channel_state::INTERRUPTED);
        assert_eq!(channel_state(state::END), channel_state::RESET);
        assert_eq!(channel_state(state::RESET), channel_state::RESET);
        assert_eq!(production_state(state::STOPPED, 0, true), "Interrupted");
        assert_eq!(production_state(state::END, 0, true), "Ended");
        assert_eq!(production_state(state::RESET, 0, true), "Aborted");
        assert_eq!(production_state(state::RESET, 14040, false), "Aborted");
        assert_eq!(production_state(state::RESET, 0, false), "Initializing");
    }

    /// The channel's alarm carries the program and the line it stands at; a PLC alarm too.
    #[test]
    fn standing_alarms() {
        let st = KernelStatus {
            state: state::RESET,
            alarm: 14040,
            line: 3,
            ..KernelStatus::default()
        };
        let mut snap = snapshot(st, "c:\\nc\\arc.mpf");
        let a = ActualValues {
            plc_alarm: 3000,
            ..ActualValues::default()
        };
        snap.actual = Some(a);
        let v = Values::new(&snap, "", true);
        let numbers: Vec<u32> = v.alarms.iter().map(|a| a.number).collect();
        assert_eq!(numbers, [14040, 3000]);
        assert_eq!(v.alarms[0].program, "arc.mpf");
        assert_eq!(v.alarms[0].line, 3);
        assert!(!v.alarms[0].text.is_empty());
    }

    #[test]
    fn without_a_kernel_nothing_is_connected() {
        let v = Values::new(&Snapshot::default(), "", false);
        assert!(!v.connected);
        assert_eq!(v.channel_state, channel_state::RESET);
        assert_eq!(v.program_name, "");
    }

    #[test]
    fn names_and_lines() {
        let per_tool = ToolEntry {
            t: 1,
            d: 2,
            ..ToolEntry::default()
        };
        let global = ToolEntry {
            d: 3,
            ..ToolEntry::default()
        };
        assert_eq!(tool_name(&per_tool), "T1 D2");
        assert_eq!(tool_name(&global), "D3");
        let text = "N10 X0\n  N20 X5 Y1  \n";
        assert_eq!(line_text(text, 2), "N20 X5 Y1");
        assert_eq!(line_text(text, 0), "");
        assert_eq!(line_text(text, 9), "");
    }
}
