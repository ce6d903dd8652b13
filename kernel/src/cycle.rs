//! The kernel's cycle with the PLC and the HMI around it: what one IPO cycle does
//! between waking up and sleeping again, apart from the clock and the transport.
//!
//! ```text
//!  commands (HMI) ─► Cyclic::command ─┐
//!  PLC signals ─► sign of life, feed hold, read-in disable, drives, E-stop ─► Channel
//!  preparation ─► Channel::fill ──────┴─► Channel::cycle ─► setpoint, aux requests, status
//!  aux acknowledgements ─► Channel::ack
//! ```
//!
//! The transport is a [`Bus`]: iceoryx2 in the nc-kernel process, a mock PLC on a mock clock
//! in tests/cyclic.rs (every reaction below checked cycle by cycle, in one thread).
//! Nothing here allocates, frees or blocks; a new program arrives built and boxed, and the
//! one it replaces goes back to the caller to be freed outside the IPO thread.

use crate::frontend::block::{Additional, AxisPos, Pos, ADDITIONAL};
use crate::handover::Handover;
use crate::ipo::Input;
use crate::ipo::{Channel, ChannelState, Event, Setpoint};
use crate::prep::AuxFunction;
use crate::MachineData;
use std::num::NonZeroU32;
use std::sync::Arc;

/// An alarm standing on the channel: one of the program's (from preparation or the path),
/// of the interface to the PLC ([`alarm`]) or raised by the PLC itself. On the wire (crate
/// softnc-protocol) it is its number, 0 for none; here "none" is `Option::None`, so no
/// number 0 can stand for an alarm.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ChannelAlarm(NonZeroU32);

impl ChannelAlarm {
    /// The alarm with this number; `None` for 0, the wire's "no alarm".
    pub const fn new(number: u32) -> Option<ChannelAlarm> {
        match NonZeroU32::new(number) {
            Some(n) => Some(ChannelAlarm(n)),
            None => None,
        }
    }

    /// A number known to be one (the constants below).
    const fn known(number: u32) -> ChannelAlarm {
        match ChannelAlarm::new(number) {
            Some(a) => a,
            None => panic!("alarm numbers start at 1"),
        }
    }

    pub const fn number(self) -> u32 {
        self.0.get()
    }

    /// The number as the wire carries it: 0 for none.
    pub fn wire(a: Option<ChannelAlarm>) -> u32 {
        a.map_or(0, ChannelAlarm::number)
    }

    /// What the alarm stands for, in a few words (docs/alarms.md has the reactions).
    pub fn title(self) -> &'static str {
        match self {
            alarm::PLC_SIGN_OF_LIFE => "PLC sign of life lost: the path brakes",
            alarm::EMERGENCY_STOP => {
                "emergency stop: the path brakes on its contour, reset after release"
            }
            alarm::AUX_NOT_DELIVERED => "auxiliary functions could not be handed to the PLC",
            alarm::DRIVES_NOT_READY => "drives not ready while the path moved",
            alarm::PLC_WATCHDOG => "PLC: no setpoints, the axes were braked (watchdog)",
            alarm::PLC_SOFTWARE_LIMIT => "PLC: software limit switch",
            _ => match self.number() {
                700_002..=799_999 => "PLC alarm",
                3021 => "contour violation with tool radius compensation",
                1011 => {
                    "internal error in block preparation: the path stopped where the prepared part ends"
                }
                _ => "program alarm (see the program's diagnostics)",
            },
        }
    }
}

impl std::fmt::Display for ChannelAlarm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.number().fmt(f)
    }
}

/// Alarms of the interface between NC and PLC (docs/alarms.md), numbered as on an 840D, and
/// those the simulated PLC raises (the 840D's range for user PLC alarms starts at 700000).
pub mod alarm {
    use super::ChannelAlarm;

    /// The PLC's sign of life stayed away for `plc.watchdog_cycles` cycles.
    pub const PLC_SIGN_OF_LIFE: ChannelAlarm = ChannelAlarm::known(2000);
    /// Emergency stop from the PLC.
    pub const EMERGENCY_STOP: ChannelAlarm = ChannelAlarm::known(3000);
    /// Auxiliary functions could not be handed to the PLC (its request queue stayed full).
    pub const AUX_NOT_DELIVERED: ChannelAlarm = ChannelAlarm::known(2011);
    /// The drives dropped their ready signal while the path moved.
    pub const DRIVES_NOT_READY: ChannelAlarm = ChannelAlarm::known(21612);
    /// The PLC's setpoint watchdog: setpoints missing for `plc.watchdog_cycles`, the axes
    /// were braked.
    pub const PLC_WATCHDOG: ChannelAlarm = ChannelAlarm::known(700_000);
    /// A setpoint beyond a software limit switch: the PLC stopped the axis at the limit.
    pub const PLC_SOFTWARE_LIMIT: ChannelAlarm = ChannelAlarm::known(700_001);
}

/// A path override an operator may set: above 0 (0 would hold the path for ever) and at
/// most 120 %. The one definition of the range for the kernel, its HMI and the command line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Override(f64);

impl Override {
    pub const MAX_PERCENT: f64 = 120.0;
    /// The range in words, for messages.
    pub const RANGE: &'static str = "above 0 and at most 120 %";

    /// From a fraction (1.0 is 100 %), as the kernel takes it.
    pub fn from_fraction(f: f64) -> Option<Override> {
        (f > 0.0 && f <= Self::MAX_PERCENT / 100.0).then_some(Override(f))
    }

    /// From a percentage, as an operator gives it.
    pub fn from_percent(p: f64) -> Option<Override> {
        (p > 0.0 && p <= Self::MAX_PERCENT).then(|| Override(p / 100.0))
    }

    pub fn fraction(self) -> f64 {
        self.0
    }
}

/// The PLC interface signals as the kernel reads them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlcInput {
    pub feed_hold: bool,
    pub read_in_disable: bool,
    pub drives_ready: bool,
    pub emergency_stop: bool,
    /// A PLC alarm standing.
    pub alarm: Option<ChannelAlarm>,
    /// The main spindle's actual speed, rev/min (signed as the setpoint).
    pub spindle_rpm: f64,
}

/// An auxiliary-function request as it goes to the PLC.
pub struct AuxOut<'a> {
    pub id: u64,
    pub cycle: u64,
    pub aux: &'a AuxFunction,
    /// The path waits for the acknowledgement.
    pub wait: bool,
}

/// The kernel's state after a cycle, for the HMI.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Status {
    pub cycle: u64,
    pub program: u32,
    pub state: Option<ChannelState>,
    pub line: u32,
    pub pos: Pos,
    /// The additional axes.
    pub add: Additional,
    pub v_path: f64,
    pub override_: f64,
    pub alarm: Option<ChannelAlarm>,
    pub aux_sent: u32,
    pub aux_acked: u32,
    pub single_block: bool,
    pub plc_alive: bool,
    /// The cycle in which the PLC's sign of life last arrived.
    pub plc_cycle: u64,
    /// Where the path is on the program.
    pub progress: Option<crate::ipo::Progress>,
    /// The spindle's speed setpoint, rev/min (signed).
    pub spindle: f64,
    /// The tool, cutting edge and work offset of the path's place.
    pub tech: crate::frontend::block::Technology,
}

/// The IPO thread's transport. Every method returns at once.
pub trait Bus {
    /// The PLC's signals if any arrived since the last call (the newest).
    fn plc(&mut self) -> Option<PlcInput>;
    /// Publishes the setpoint of the cycle.
    fn setpoint(&mut self, sp: &Setpoint);
    /// Sends an auxiliary-function request; false when it cannot be sent now.
    fn aux(&mut self, out: &AuxOut<'_>) -> bool;
    /// Calls `f(id, plc_alarm)` for each acknowledgement that arrived: done, or refused
    /// with a PLC alarm.
    fn acks(&mut self, f: &mut dyn FnMut(u64, Option<ChannelAlarm>));
    fn status(&mut self, st: &Status);
}

impl Status {
    /// Every path axis.
    pub fn axes(&self) -> AxisPos {
        AxisPos {
            geo: self.pos,
            add: self.add,
        }
    }
}

/// A program ready to run: its channel (at the program's start position) and the queue its
/// preparation thread fills.
pub struct Program {
    pub id: u32,
    pub channel: Box<Channel>,
    pub hand: Arc<Handover>,
    /// Where the program starts.
    pub start: AxisPos,
}

/// What an HMI asks.
pub enum Control {
    Start,
    Stop,
    Reset,
    SingleBlock(bool),
    Override(f64),
    Load(Box<Program>),
    /// NC start after an offset change in NC stop: the program re-prepared from the
    /// interruption point (runtime::spawn_resume) replaces the stopped one and starts with
    /// its reposition move from where the axes stand.
    Resume(Box<Program>),
    /// End the process: brakes first if the path moves.
    Shutdown,
}

/// Why a command was refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Refusal {
    /// The command needs the channel in RESET or END.
    NotInReset(ChannelState),
    /// The command needs the channel in NC stop, at rest.
    NotStopped(ChannelState),
    NoProgram,
    /// An alarm stands: reset first.
    Alarm(ChannelAlarm),
    NoPlc,
    DrivesNotReady,
    EmergencyStop,
    /// The program starts with axis `axis` (of [`crate::AXIS_NAMES`]) at `start`; it stands
    /// at `here` (the first axis that differs).
    StartsElsewhere {
        axis: usize,
        start: f64,
        here: f64,
    },
    BadOverride,
    /// The IPO thread has ended or does not answer.
    Ending,
}

/// Requests in flight to the PLC, and those waiting to be sent.
const AUX_IN_FLIGHT: usize = 32;

pub struct Cyclic {
    program: Option<Box<Program>>,
    /// The channel when no program is loaded (holds the position).
    idle: Box<Channel>,
    pending: Option<Input>,
    sp: Box<Setpoint>,
    watchdog: u64,
    plc: PlcInput,
    plc_seen: Option<u64>,
    feed_held: bool,
    /// The first alarm standing.
    alarm: Option<ChannelAlarm>,
    override_: f64,
    single_block: bool,
    aux_next: u64,
    aux_sent: u32,
    aux_acked: u32,
    /// Sent, not yet acknowledged: (id, the path waits for it).
    in_flight: heapless::Deque<(u64, bool), AUX_IN_FLIGHT>,
    /// Output at their S point, not yet sent (the PLC's queue was full).
    outbox: heapless::Deque<(u64, bool, AuxFunction), AUX_IN_FLIGHT>,
    shutdown: bool,
    reset_pending: bool,
    released: Option<Box<Program>>,
    k: u64,
    /// Records taken from preparation in the last cycle (a record of the run keeps them).
    taken: u32,
    /// A replay: each cycle takes exactly this many records, waiting for them.
    quota: Option<u32>,
}

impl Cyclic {
    /// Allocates everything the cycle uses; call before the real-time part starts.
    pub fn new(md: &MachineData, start: AxisPos) -> Self {
        Cyclic {
            program: None,
            idle: Box::new(Channel::new(md, start)),
            pending: None,
            sp: Box::new(Setpoint::new(start)),
            watchdog: u64::from(md.plc.watchdog_cycles),
            plc: PlcInput::default(),
            plc_seen: None,
            feed_held: false,
            alarm: None,
            override_: 1.0,
            single_block: false,
            aux_next: 1,
            aux_sent: 0,
            aux_acked: 0,
            in_flight: heapless::Deque::new(),
            outbox: heapless::Deque::new(),
            shutdown: false,
            reset_pending: false,
            released: None,
            k: 0,
            taken: 0,
            quota: None,
        }
    }

    fn channel(&mut self) -> &mut Channel {
        match &mut self.program {
            Some(p) => &mut p.channel,
            None => &mut self.idle,
        }
    }

    fn channel_ref(&self) -> &Channel {
        match &self.program {
            Some(p) => &p.channel,
            None => &self.idle,
        }
    }

    pub fn state(&self) -> ChannelState {
        self.program
            .as_ref()
            .map_or(self.idle.state(), |p| p.channel.state())
    }

    fn plc_alive(&self) -> bool {
        self.plc_seen
            .is_some_and(|s| self.k.saturating_sub(s) <= self.watchdog)
    }

    /// The path stands still and no program runs: the process may end.
    pub fn may_exit(&self) -> bool {
        self.shutdown && (self.state() != ChannelState::Active || self.sp.v_path == 0.0)
    }

    pub fn setpoint(&self) -> &Setpoint {
        &self.sp
    }

    /// An HMI command, between two cycles. A program replaced by `Load` or dropped by
    /// `Reset` waits in [`take_released`](Self::take_released); one refused comes back in the
    /// error.
    pub fn command(&mut self, c: Control) -> Result<(), Refusal> {
        let state = self.state();
        let at_rest = matches!(state, ChannelState::Reset | ChannelState::End);
        match c {
            Control::Start => {
                if let Some(r) = self.start_refusal() {
                    return Err(r);
                }
                if self.program.is_none() || state == ChannelState::End {
                    return Err(Refusal::NoProgram);
                }
                self.channel().start();
                Ok(())
            }
            Control::Stop => {
                // The operator's stop: releasing a feed hold may not start the path again.
                self.feed_held = false;
                self.channel().stop();
                Ok(())
            }
            Control::Reset => {
                if self.plc.emergency_stop {
                    return Err(Refusal::EmergencyStop);
                }
                // A moving path brakes first: a reset never makes a step in speed.
                self.reset_pending = true;
                if self.sp.v_path != 0.0 {
                    self.channel().stop();
                } else {
                    self.reset_now();
                }
                Ok(())
            }
            Control::SingleBlock(on) => {
                self.single_block = on;
                self.channel().set_single_block(on);
                Ok(())
            }
            Control::Override(f) => {
                let f = Override::from_fraction(f).ok_or(Refusal::BadOverride)?;
                self.override_ = f.fraction();
                self.channel().set_override(f.fraction());
                Ok(())
            }
            Control::Load(p) => {
                let refusal = if !at_rest || self.reset_pending {
                    Some(Refusal::NotInReset(state))
                } else {
                    self.starts_elsewhere(&p)
                };
                if let Some(r) = refusal {
                    self.released = Some(p);
                    return Err(r);
                }
                self.alarm = None;
                self.install(p);
                Ok(())
            }
            Control::Resume(p) => {
                let refusal = if state != ChannelState::Stopped
                    || self.sp.v_path != 0.0
                    || self.reset_pending
                {
                    Some(Refusal::NotStopped(state))
                } else {
                    self.start_refusal().or_else(|| self.starts_elsewhere(&p))
                };
                if let Some(r) = refusal {
                    self.released = Some(p);
                    return Err(r);
                }
                self.feed_held = false;
                // The re-prepared program goes on with the spindle, tool and work offset in
                // force at the interruption point: its records before it are not output again.
                let tech = self.channel_ref().technology();
                self.install(p);
                self.channel().set_technology(tech);
                self.channel().start();
                Ok(())
            }
            Control::Shutdown => {
                self.shutdown = true;
                self.channel().stop();
                Ok(())
            }
        }
    }

    /// Why NC start cannot be given now (the PLC's and the alarms' side), if it cannot.
    fn start_refusal(&self) -> Option<Refusal> {
        if self.plc.emergency_stop {
            Some(Refusal::EmergencyStop)
        } else if let Some(a) = self.alarm {
            Some(Refusal::Alarm(a))
        } else if !self.plc_alive() {
            Some(Refusal::NoPlc)
        } else if !self.plc.drives_ready {
            Some(Refusal::DrivesNotReady)
        } else {
            None
        }
    }

    /// A program whose start is not where the axes stand (within 1 µm).
    fn starts_elsewhere(&self, p: &Program) -> Option<Refusal> {
        let here = self.sp.axes();
        (0..3 + ADDITIONAL)
            .find(|&i| (p.start.axis(i) - here.axis(i)).abs() > 1e-6)
            .map(|axis| Refusal::StartsElsewhere {
                axis,
                start: p.start.axis(axis),
                here: here.axis(axis),
            })
    }

    /// `p` becomes the running program with the operator's override and single-block
    /// setting; the one it replaces is cancelled and released, and what waited for it goes.
    fn install(&mut self, mut p: Box<Program>) {
        p.channel.set_override(self.override_);
        p.channel.set_single_block(self.single_block);
        self.pending = None;
        self.in_flight.clear();
        self.outbox.clear();
        if let Some(o) = self.program.replace(p) {
            o.hand
                .cancel
                .store(true, std::sync::atomic::Ordering::Relaxed);
            self.released = Some(o);
        }
    }

    fn reset_now(&mut self) {
        self.reset_pending = false;
        self.alarm = None;
        self.feed_held = false;
        self.in_flight.clear();
        self.outbox.clear();
        self.pending = None;
        let pos = self.sp.axes();
        if let Some(p) = self.program.take() {
            // The preparation thread stops at its next record.
            p.hand
                .cancel
                .store(true, std::sync::atomic::Ordering::Relaxed);
            self.released = Some(p);
        }
        self.idle.reset();
        self.idle.set_position(pos);
        self.sp.state = ChannelState::Reset;
    }

    /// A program dropped by a reset or replaced by a load, to be freed outside the IPO
    /// thread.
    pub fn take_released(&mut self) -> Option<Box<Program>> {
        self.released.take()
    }

    /// Raises an alarm from outside the program (the first one stays shown).
    fn fault(&mut self, a: ChannelAlarm) {
        if self.alarm.is_none() {
            self.alarm = Some(a);
        }
        self.channel().fault();
    }

    /// One IPO cycle: cycle number `k`.
    pub fn cycle(&mut self, k: u64, bus: &mut impl Bus) {
        self.k = k;
        self.plc_signals(k, bus);
        self.acknowledgements(bus);
        self.take_prepared();
        let sp = &mut *self.sp;
        match &mut self.program {
            Some(p) => p.channel.cycle(k, sp),
            None => self.idle.cycle(k, sp),
        }
        if self.reset_pending && self.sp.v_path == 0.0 {
            self.reset_now();
        }
        self.events(k, bus);
        self.flush_outbox(bus);
        let st = self.status();
        bus.status(&st);
        // The setpoint last: its event wakes plc-sim, which on a shared core runs only once
        // this thread sleeps, and which then finds this cycle's aux requests already there.
        bus.setpoint(&self.sp);
    }

    /// Takes what preparation has ready, never waiting; in a replay exactly the records the
    /// recorded cycle took (waiting for them), so the lookahead is the live run's.
    fn take_prepared(&mut self) {
        self.taken = 0;
        let Some(p) = &mut self.program else {
            return;
        };
        let (hand, taken, quota) = (&p.hand, &mut self.taken, self.quota);
        p.channel.fill(&mut self.pending, || {
            let next = match quota {
                None => hand.pop(),
                Some(n) if *taken < n => loop {
                    if let Some(i) = hand.pop() {
                        break Some(i);
                    }
                    std::thread::yield_now();
                },
                Some(_) => None,
            };
            *taken += u32::from(next.is_some());
            next
        });
    }

    /// Records the last cycle took from preparation.
    pub fn taken(&self) -> u32 {
        self.taken
    }

    /// For a replay: the next cycle takes exactly `records` from preparation, waiting for
    /// them (the live cycle took what was there, never waiting).
    pub fn replay_preparation(&mut self, records: u32) {
        self.quota = Some(records);
    }

    /// Reads the PLC interface signals and reacts to them.
    fn plc_signals(&mut self, k: u64, bus: &mut impl Bus) {
        if let Some(s) = bus.plc() {
            self.plc_seen = Some(k);
            let was = self.plc;
            self.plc = s;
            let moving = self.state() == ChannelState::Active;
            self.channel().set_spindle_actual(s.spindle_rpm);
            if s.emergency_stop && !was.emergency_stop {
                self.fault(alarm::EMERGENCY_STOP);
            }
            if let Some(a) = s.alarm.filter(|_| s.alarm != was.alarm) {
                self.fault(a);
            }
            if was.drives_ready && !s.drives_ready && moving {
                self.fault(alarm::DRIVES_NOT_READY);
            }
            if s.read_in_disable != was.read_in_disable {
                self.channel().set_read_in_disable(s.read_in_disable);
            }
            if s.feed_hold && !was.feed_hold && moving {
                self.feed_held = true;
                self.channel().stop();
            }
            if !s.feed_hold && was.feed_hold && self.feed_held {
                self.feed_held = false;
                // Only the stop feed hold made is undone: not a program stop or an alarm.
                if self.alarm.is_none() && !self.channel().waits_for_start() {
                    self.channel().start();
                }
            }
        } else if let Some(seen) = self.plc_seen {
            // Sign-of-life watchdog: only while a program is loaded and not at its end, so an
            // idle kernel waiting for its PLC raises nothing.
            let running = matches!(self.state(), ChannelState::Active | ChannelState::Stopped);
            if k.saturating_sub(seen) > self.watchdog && running && self.alarm.is_none() {
                self.fault(alarm::PLC_SIGN_OF_LIFE);
            }
        }
    }

    fn acknowledgements(&mut self, bus: &mut impl Bus) {
        let mut acked: heapless::Vec<(u64, Option<ChannelAlarm>), AUX_IN_FLIGHT> =
            heapless::Vec::new();
        bus.acks(&mut |id, plc_alarm| {
            let _ = acked.push((id, plc_alarm));
        });
        for (id, plc_alarm) in acked {
            // Take the entry out, keeping the order of the others.
            let mut found = None;
            for _ in 0..self.in_flight.len() {
                let Some(e) = self.in_flight.pop_front() else {
                    break;
                };
                if found.is_none() && e.0 == id {
                    found = Some(e.1);
                } else {
                    let _ = self.in_flight.push_back(e);
                }
            }
            // None: an answer to a request from before a reset.
            let Some(wait) = found else {
                continue;
            };
            self.aux_acked += 1;
            if let Some(a) = plc_alarm {
                self.fault(a);
            } else if wait {
                self.channel().ack();
            }
        }
    }

    /// Auxiliary functions of this cycle go to the PLC; the program's alarms are shown.
    fn events(&mut self, k: u64, bus: &mut impl Bus) {
        for i in 0..self.sp.events.len() {
            match &self.sp.events[i] {
                // A change of the spindle alone (G96 without S): nothing for the PLC.
                Event::Aux { aux: a, .. } if a.words.is_empty() => {}
                Event::Aux { aux: a, wait } => {
                    let wait = *wait;
                    let id = self.aux_next;
                    self.aux_next += 1;
                    if self.outbox.is_empty()
                        && bus.aux(&AuxOut {
                            id,
                            cycle: k,
                            aux: a,
                            wait,
                        })
                    {
                        self.aux_sent += 1;
                        let _ = self.in_flight.push_back((id, wait));
                    } else if self.outbox.push_back((id, wait, a.clone())).is_err() {
                        self.fault(alarm::AUX_NOT_DELIVERED);
                    }
                }
                Event::Alarm { code, .. } if self.alarm.is_none() => {
                    self.alarm = ChannelAlarm::new(*code);
                }
                _ => {}
            }
        }
    }

    fn flush_outbox(&mut self, bus: &mut impl Bus) {
        while let Some((id, wait, a)) = self.outbox.front() {
            if self.in_flight.is_full()
                || !bus.aux(&AuxOut {
                    id: *id,
                    cycle: self.k,
                    aux: a,
                    wait: *wait,
                })
            {
                return;
            }
            let _ = self.in_flight.push_back((*id, *wait));
            self.aux_sent += 1;
            self.outbox.pop_front();
        }
    }

    pub fn status(&self) -> Status {
        Status {
            cycle: self.k,
            program: self.program.as_ref().map_or(0, |p| p.id),
            state: Some(self.sp.state),
            line: self.sp.source.map_or(0, |s| s.line),
            pos: self.sp.pos,
            add: self.sp.add,
            v_path: self.sp.v_path,
            override_: self.override_,
            alarm: self.alarm,
            aux_sent: self.aux_sent,
            aux_acked: self.aux_acked,
            single_block: self.single_block,
            plc_alive: self.plc_alive(),
            plc_cycle: self.plc_seen.unwrap_or(0),
            progress: match &self.program {
                Some(p) => p.channel.progress(),
                None => None,
            },
            spindle: self.sp.spindle,
            tech: self.channel_ref().technology(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_override_range_is_the_same_in_percent_and_as_a_fraction() {
        for p in [0.5, 1.0, 80.0, 100.0, 120.0] {
            let o = Override::from_percent(p).unwrap();
            assert_eq!(Override::from_fraction(o.fraction()), Some(o), "{p} %");
        }
        for p in [0.0, -1.0, 120.000_001, f64::NAN, f64::INFINITY] {
            assert_eq!(Override::from_percent(p), None, "{p} %");
            assert_eq!(Override::from_fraction(p / 100.0), None, "{p} %");
        }
    }

    #[test]
    fn no_alarm_is_none_on_the_wire_zero() {
        assert_eq!(ChannelAlarm::new(0), None);
        assert_eq!(ChannelAlarm::wire(None), 0);
        let a = ChannelAlarm::new(3021).unwrap();
        assert_eq!((a.number(), ChannelAlarm::wire(Some(a))), (3021, 3021));
        assert_eq!(ChannelAlarm::new(2000), Some(alarm::PLC_SIGN_OF_LIFE));
        assert_eq!(
            alarm::PLC_WATCHDOG.title(),
            ChannelAlarm::new(700_000).unwrap().title()
        );
    }
}
