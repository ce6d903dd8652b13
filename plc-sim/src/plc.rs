//! The simulated PLC as a state machine: what it does when a setpoint arrives, when a cycle
//! passes without one, when an auxiliary-function request arrives and as time passes, apart
//! from the transport and the clock.
//!
//! ```text
//!  setpoint ─► Plc::setpoint: sequence gaps, watchdog acknowledgement, scripted inputs,
//!              software limits, one drive cycle of the axes and the spindles
//!              ─► trace row, actual values
//!  no setpoint for a cycle ─► Plc::silence: watchdog count, braking ─► trace row
//!  aux request ─► Plc::request: tool, what it waits for (time, spindle)
//!  time ─► Plc::acknowledge_due ─► acknowledgements; Plc::signal ─► PLC interface signals
//! ```
//!
//! The spindles follow the kernel's speed setpoint in every setpoint (spindle.rs); the PLC
//! does not read S words for a speed (under G96 S is a cutting speed in m/min). A request
//! is acknowledged when everything it waits for holds: M6 its `plc.tool_change_ms`; M3, M4,
//! and S while the spindle turns, the main spindle at speed; M5 at rest; M19 oriented. The
//! spindle conditions count from the first setpoint of the request's cycle on (the one that
//! carries the speed the request belongs to) and each is kept once it has held.
//!
//! The transport is a [`Transport`]: iceoryx2 and a CSV file in the process (ice.rs), a mock
//! on a mock clock in tests/plc.rs.

use crate::args::Window;
use crate::drives::{Axes, DriveData, Drives};
use crate::spindle::{self, SpindleDrives, Spindles, Waits};
use nc_kernel::cycle::{alarm, ChannelAlarm};
use nc_kernel::MachineData;
use nc_runtime::WireAxes;
use softnc_protocol::{state, AuxRequest, AxisList, SetpointMsg, MAX_AXES};
use std::time::Duration;

/// plc-sim's side of the world: what it receives, what it sends and the clock. Every method
/// returns at once except [`wait`](Transport::wait).
pub trait Transport {
    /// The clock, ns.
    fn now_ns(&mut self) -> u64;
    /// Waits up to `timeout` for the kernel's setpoint event; whether it came.
    fn wait(&mut self, timeout: Duration) -> bool;
    /// The next setpoint that arrived, oldest first.
    fn setpoint(&mut self) -> Option<SetpointMsg>;
    /// The next auxiliary-function request that arrived, with the ticket its
    /// acknowledgement goes back with.
    fn request(&mut self) -> Option<(u64, AuxRequest)>;
    /// Acknowledges the request of `ticket` (the kernel's request `id`): done.
    fn ack(&mut self, ticket: u64, id: u64);
    /// The PLC interface signals, with the last setpoint cycle consumed (the sign of life).
    fn signals(&mut self, echo_cycle: u64, s: &Signals);
    fn actuals(&mut self, a: &Actual);
    /// A row of the trace.
    fn row(&mut self, r: &Row<'_>);
    /// A line for the operator.
    fn log(&mut self, line: &str);
}

/// The axes' actual values after a drive cycle; positions in wire order (the machine's
/// configured axes, [`Plc::axes`]), 0 past the count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Actual {
    /// The setpoint cycle these follow.
    pub cycle: u64,
    pub pos: Axes,
    /// Setpoint − actual position per axis, mm (rotary: degrees).
    pub following_error: Axes,
    /// Actual speed per spindle, rev/min, signed as the setpoint.
    pub spindle_rpm: Spindles,
    /// The tool in the spindle.
    pub tool: u32,
    /// Auxiliary functions acknowledged so far.
    pub aux_acked: u32,
    pub alarm: Option<ChannelAlarm>,
}

/// One row of the trace: a drive cycle, or a braking cycle of the watchdog (`seq` 0).
#[derive(Clone, Copy, Debug)]
pub struct Row<'a> {
    /// Since the PLC started, s.
    pub time: f64,
    pub cycle: u64,
    pub seq: u64,
    /// The configured axes: the entries of the position arrays that count.
    pub axes: usize,
    pub setpoint: Axes,
    pub actual: Axes,
    pub following_error: Axes,
    /// The spindles the trace has columns for: the entries of the spindle arrays that count.
    pub spindles: usize,
    /// Per spindle the speed setpoint its drive follows and its actual speed, rev/min.
    pub spindle_setpoint: Spindles,
    pub spindle_actual: Spindles,
    /// mm/s.
    pub v_path: f64,
    pub line: u32,
    /// `state::*` of the kernel.
    pub state: u8,
    /// What happened since the last row, `;`-separated.
    pub events: &'a str,
}

/// The PLC interface signals as plc-sim sends them every PLC cycle (ice.rs makes the
/// wire's numbers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Signals {
    pub feed_hold: bool,
    pub read_in_disable: bool,
    pub drives_ready: bool,
    pub emergency_stop: bool,
    pub alarm: Option<ChannelAlarm>,
    /// Actual speed per spindle, rev/min, signed as the setpoint (feed per revolution).
    pub spindle_rpm: Spindles,
}

/// Inputs as from a machine's control panel, at kernel cycles (for tests and
/// demonstrations).
#[derive(Clone, Copy, Debug, Default)]
pub struct Script {
    pub estop_at: Option<u64>,
    pub feed_hold: Option<Window>,
    pub read_in_disable: Option<Window>,
    pub drives_off_at: Option<u64>,
}

/// What plc-sim counts of the setpoint stream.
pub struct Stats {
    pub samples: u64,
    /// Setpoints missing from the sequence.
    pub lost: u64,
    /// Setpoints consumed after their cycle's deadline.
    pub late: u64,
    pub aux_acked: u32,
    /// One-way latency from the kernel's send to the receipt here, ns.
    pub latency: hdrhistogram::Histogram<u64>,
}

impl Stats {
    fn new() -> Stats {
        Stats {
            samples: 0,
            lost: 0,
            late: 0,
            aux_acked: 0,
            latency: hdrhistogram::Histogram::new_with_bounds(1, 10_000_000_000, 3)
                .expect("constant histogram bounds are valid"),
        }
    }

    /// One line for the end of a run.
    pub fn summary(&self) -> String {
        let q = |p: f64| self.latency.value_at_quantile(p) as f64 / 1000.0;
        format!(
            "{} setpoints, {} lost, {} after their deadline, {} aux functions acknowledged; latency µs p50 {:.1} p99 {:.1} p99.9 {:.1} max {:.1}",
            self.samples,
            self.lost,
            self.late,
            self.aux_acked,
            q(0.5),
            q(0.99),
            q(0.999),
            self.latency.max() as f64 / 1000.0
        )
    }

    /// The latency histogram in cyclictest's format.
    pub fn histogram(&self) -> String {
        nc_runtime::histogram_text(
            "plc-sim setpoint latency (kernel send to plc-sim receive)",
            &self.latency,
            &[
                ("samples", self.samples),
                ("lost", self.lost),
                ("late", self.late),
            ],
        )
    }
}

/// A request waiting until it is done.
struct Pending {
    /// Not before then (M6's tool change time).
    due_ns: u64,
    ticket: u64,
    id: u64,
    /// The kernel cycle it was output in: spindle conditions count from its setpoint on.
    cycle: u64,
    /// The spindle conditions that have not held yet.
    waits: Waits,
    text: String,
}

/// The simulated PLC with its drives and spindle.
pub struct Plc {
    md: MachineData,
    cycle: Duration,
    /// The cycle, s.
    t: f64,
    watchdog: u64,
    script: Script,
    start_ns: u64,
    wire: WireAxes,
    drive_data: DriveData,
    /// The position loops, started at the first setpoint (again after a watchdog reset).
    drives: Option<Drives>,
    /// A setpoint with another axis count than the machine data's has been reported.
    told_axes: bool,
    last: Option<SetpointMsg>,
    /// Own cycles (waits that timed out) since the last setpoint: the watchdog counts these,
    /// not wall time, so a hold-up of the whole machine is not taken for a dead kernel.
    missed: u64,
    braking: bool,
    alarm: Option<ChannelAlarm>,
    estop: bool,
    drives_ready: bool,
    pending: Vec<Pending>,
    tool: u32,
    spindles: SpindleDrives,
    /// Spindles the trace has columns for.
    trace_spindles: usize,
    /// Since the last trace row.
    events: String,
    stats: Stats,
}

impl Plc {
    /// The PLC of machine `md`, started at `start_ns` on the transport's clock.
    pub fn new(md: &MachineData, script: Script, start_ns: u64) -> Plc {
        let cycle_ns = u64::from(md.ipo.cycle_us) * 1000;
        let wire = WireAxes::new(md);
        Plc {
            md: md.clone(),
            cycle: Duration::from_nanos(cycle_ns),
            t: cycle_ns as f64 * 1e-9,
            watchdog: u64::from(md.plc.watchdog_cycles),
            script,
            start_ns,
            drive_data: DriveData::new(md, &wire),
            wire,
            drives: None,
            told_axes: false,
            last: None,
            missed: 0,
            braking: false,
            alarm: None,
            estop: false,
            drives_ready: true,
            pending: Vec::new(),
            tool: 0,
            spindles: SpindleDrives::new(md.plc.spindle_acceleration, cycle_ns as f64 * 1e-9),
            trace_spindles: spindle::CONFIGURED,
            events: String::new(),
            stats: Stats::new(),
        }
    }

    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The axes it drives, in the order of every position array (the kernel's wire order).
    pub fn axes(&self) -> &AxisList {
        &self.wire.list
    }

    /// One PLC cycle: woken by the kernel's setpoint event or after one cycle without it,
    /// it drives the axes with every setpoint that came (or counts a silent cycle), takes the
    /// new requests, acknowledges those whose time has come and sends its signals.
    pub fn cycle(&mut self, io: &mut impl Transport) {
        let event = io.wait(self.cycle);
        let mut got = false;
        while let Some(sp) = io.setpoint() {
            let now = io.now_ns();
            self.setpoint(&sp, now, io);
            got = true;
        }
        if !got && !event {
            let now = io.now_ns();
            self.silence(now, io);
        }
        while let Some((ticket, req)) = io.request() {
            let now = io.now_ns();
            self.request(ticket, &req, now);
        }
        let now = io.now_ns();
        self.acknowledge_due(now, io);
        self.signal(io);
    }

    /// A setpoint arrives at `now`: one drive cycle of the axes and the spindles.
    pub fn setpoint(&mut self, sp: &SetpointMsg, now: u64, io: &mut impl Transport) {
        self.count(sp, now);
        self.missed = 0;
        if self.braking && sp.state == state::RESET {
            self.acknowledge_watchdog();
        }
        self.scripted_inputs(sp.cycle);
        self.check_axes(sp, io);
        let (actual, following_error) = self.drive(&sp.pos);
        self.spindles.follow(sp, self.braking);
        self.last = Some(*sp);
        self.settle();
        io.row(&Row {
            time: self.since_start(now),
            cycle: sp.cycle,
            seq: sp.seq,
            axes: self.drive_data.count,
            setpoint: sp.pos,
            actual,
            following_error,
            spindles: self.trace_spindles,
            spindle_setpoint: self.spindles.setpoint(),
            spindle_actual: self.spindles.actual(),
            v_path: sp.v_path,
            line: sp.line,
            state: sp.state,
            events: &self.events,
        });
        self.events.clear();
        io.actuals(&Actual {
            cycle: sp.cycle,
            pos: actual,
            following_error,
            spindle_rpm: self.spindles.actual(),
            tool: self.tool,
            aux_acked: self.stats.aux_acked,
            alarm: self.alarm,
        });
    }

    /// Latency, lateness and gaps in the sequence (a new kernel counts from 1 again).
    fn count(&mut self, sp: &SetpointMsg, now: u64) {
        self.stats.samples += 1;
        let _ = self
            .stats
            .latency
            .record(now.saturating_sub(sp.sent_ns).max(1));
        if now > sp.deadline_ns {
            self.stats.late += 1;
        }
        if let Some(l) = self.last.filter(|l| sp.seq > l.seq + 1) {
            let n = sp.seq - l.seq - 1;
            self.stats.lost += n;
            self.events.push_str(&format!("lost {n};"));
        }
    }

    /// The kernel was reset (or restarted): the watchdog alarm is acknowledged, and the
    /// drives follow the setpoints again from where they stand.
    fn acknowledge_watchdog(&mut self) {
        self.braking = false;
        if self.alarm == Some(alarm::PLC_WATCHDOG) {
            self.alarm = None;
        }
        self.drives = None;
        self.events.push_str("watchdog acknowledged;");
    }

    /// The control panel's inputs due at kernel cycle `cycle`: at or after it, so a PLC that
    /// connects late still acts.
    fn scripted_inputs(&mut self, cycle: u64) {
        if self.script.estop_at.is_some_and(|c| cycle >= c) && !self.estop {
            self.estop = true;
            self.events.push_str("emergency stop;");
        }
        if self.script.drives_off_at.is_some_and(|c| cycle >= c) && self.drives_ready {
            self.drives_ready = false;
            self.events.push_str("drives off;");
        }
    }

    /// A kernel whose machine data has another number of axes sends positions this PLC
    /// maps to other axes: said once, and the PLC drives its own axes on.
    fn check_axes(&mut self, sp: &SetpointMsg, io: &mut impl Transport) {
        if usize::from(sp.axes) == self.drive_data.count || self.told_axes {
            return;
        }
        self.told_axes = true;
        let line = format!(
            "the kernel sends {} axes, the machine data here has {} ({}): check --machine",
            sp.axes,
            self.drive_data.count,
            self.wire.list.names().collect::<String>()
        );
        self.events.push_str("axis count differs;");
        io.log(&line);
    }

    /// One drive cycle towards `pos` within the software limits (braking instead while the
    /// watchdog holds): the positions measured and the following errors.
    fn drive(&mut self, pos: &Axes) -> (Axes, Axes) {
        let (target, limited) = self.drive_data.limit(pos);
        if limited && self.alarm.is_none() {
            self.alarm = Some(alarm::PLC_SOFTWARE_LIMIT);
            self.events.push_str("software limit;");
        }
        let (data, t) = (&self.drive_data, self.t);
        let drives = self.drives.get_or_insert_with(|| data.drives(t, &target));
        if self.braking {
            (drives.brake(), [0.0; MAX_AXES])
        } else {
            drives.step(&target)
        }
    }

    /// A cycle passes without a setpoint: after `plc.watchdog_cycles` of them every axis
    /// brakes at its acceleration limit and every spindle at `plc.spindle_acceleration`
    /// (a PLC does not leave a spindle turning for a control that is gone), with PLC alarm
    /// 700000.
    pub fn silence(&mut self, now: u64, io: &mut impl Transport) {
        let (Some(drives), Some(l)) = (self.drives.as_mut(), self.last) else {
            return;
        };
        self.missed += 1;
        if self.missed >= self.watchdog && !self.braking {
            self.braking = true;
            self.alarm.get_or_insert(alarm::PLC_WATCHDOG);
            let missed = self.missed;
            self.events
                .push_str(&format!("watchdog: no setpoint for {missed} cycles;"));
            io.log(&format!(
                "alarm {}: no setpoint for {missed} cycles after cycle {}: braking axes and spindles",
                alarm::PLC_WATCHDOG,
                l.cycle
            ));
        }
        if !self.braking {
            return;
        }
        let actual = drives.brake();
        self.spindles.brake();
        self.settle();
        io.row(&Row {
            time: self.since_start(now),
            cycle: l.cycle + self.missed,
            seq: 0,
            axes: self.drive_data.count,
            setpoint: l.pos,
            actual,
            following_error: [0.0; MAX_AXES],
            spindles: self.trace_spindles,
            spindle_setpoint: self.spindles.setpoint(),
            spindle_actual: self.spindles.actual(),
            v_path: 0.0,
            line: l.line,
            state: l.state,
            events: &self.events,
        });
        self.events.clear();
    }

    /// An auxiliary-function request arrives at `now`: T takes the tool at once; the
    /// request is done when M6 has taken `plc.tool_change_ms` and the main spindle is at
    /// speed for M3, M4 (and S while it turns), at rest for M5, oriented for M19; anything
    /// else at once. The speed itself comes with the setpoints, not from S.
    pub fn request(&mut self, ticket: u64, r: &AuxRequest, now: u64) {
        let mut wait_ns = 0u64;
        let mut waits = Waits::NONE;
        let mut text = String::new();
        for w in r.words() {
            text.push_str(&format!("{}{} ", w.address as char, w.value));
            match (w.address, whole(w.value)) {
                (b'M', Some(6)) => {
                    wait_ns = wait_ns.max(u64::from(self.md.plc.tool_change_ms) * 1_000_000)
                }
                (b'M', Some(3 | 4)) => waits |= Waits::AT_SPEED,
                (b'M', Some(5)) => waits |= Waits::STOPPED,
                (b'M', Some(19)) => waits |= Waits::ORIENTED,
                (b'S', _) if self.spindles.turning() => waits |= Waits::AT_SPEED,
                // Saturating: a value from the wire out of range names no real tool anyway.
                (b'T', _) => self.tool = w.value.clamp(0.0, f64::from(u32::MAX)) as u32,
                _ => {}
            }
        }
        self.pending.push(Pending {
            due_ns: now + wait_ns,
            ticket,
            id: r.id,
            cycle: r.cycle,
            waits,
            text: text.trim_end().to_string(),
        });
        // What already holds counts: an M5 to a spindle at rest is done at once.
        self.settle();
    }

    /// Drops from the pending requests the spindle conditions that hold now, for those
    /// whose cycle's setpoint has arrived (before it the spindle still follows the speed
    /// of before the request). Called after every drive cycle, so a condition that holds
    /// for a single cycle counts, whenever the acknowledgements go out.
    fn settle(&mut self) {
        let Some(l) = self.last else {
            return;
        };
        let idle = matches!(l.state, state::RESET | state::END);
        for p in self.pending.iter_mut().filter(|p| l.cycle >= p.cycle) {
            p.waits = self.spindles.open(p.waits, idle);
        }
    }

    /// Time has come to `now`: the requests that are done are acknowledged.
    pub fn acknowledge_due(&mut self, now: u64, io: &mut impl Transport) {
        let mut i = 0;
        while i < self.pending.len() {
            if self.pending[i].due_ns <= now && self.pending[i].waits.is_empty() {
                let p = self.pending.swap_remove(i);
                io.ack(p.ticket, p.id);
                self.stats.aux_acked += 1;
                self.events.push_str(&format!("ack {};", p.text));
            } else {
                i += 1;
            }
        }
    }

    /// The interface signals and the sign of life, sent every PLC cycle.
    pub fn signal(&mut self, io: &mut impl Transport) {
        let c = self.last.map_or(0, |l| l.cycle);
        let within = |w: Option<Window>| w.is_some_and(|w| w.contains(c));
        let s = Signals {
            feed_hold: within(self.script.feed_hold),
            read_in_disable: within(self.script.read_in_disable),
            drives_ready: self.drives_ready && !self.braking,
            emergency_stop: self.estop,
            alarm: self.alarm,
            spindle_rpm: self.spindles.actual(),
        };
        io.signals(c, &s);
    }

    fn since_start(&self, now: u64) -> f64 {
        now.saturating_sub(self.start_ns) as f64 * 1e-9
    }
}

/// `v` as a whole number of an M function, if it is one (M3.5 is not M3).
fn whole(v: f64) -> Option<u32> {
    (v.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&v)).then_some(v as u32)
}
