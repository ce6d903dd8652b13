//! The channel: its states around the planner, and the auxiliary functions,
//! program stops and the program end output at their S points.
//!
//! RESET → ACTIVE (NC start) → STOPPED (NC stop: braking on the path, then holding;
//! resumable) → ACTIVE → END (M02/M30) → RESET. M00, M01 (with the optional-stop switch)
//! and M18 stop at the end of their block and wait for NC start; single-block mode does the
//! same at every S point, inserted blocks included. An auxiliary function listed in
//! `ipo.wait_for_ack` makes the path stop where it is output and wait for the PLC's
//! acknowledgement. A preparation alarm stops the channel where the prepared path ends, with
//! the position kept.
//!
//! What arrives from preparation is tagged with the number of the segment it comes before;
//! it is output when that segment starts (or, after the last one, when the path is done).

use super::planner::{Entry, Planner, Sample};
use super::spindle::spindle_setpoint;
use crate::frontend::block::{Additional, AxisPos, Pos, SpindleDir, SpindleProgram, Technology};
use crate::machine_data::MachineData;
use crate::prep::{AuxFunction, Stop};
use crate::segment::Source;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChannelState {
    Reset,
    Active,
    Stopped,
    End,
}

impl ChannelState {
    pub fn name(self) -> &'static str {
        match self {
            ChannelState::Reset => "RESET",
            ChannelState::Active => "ACTIVE",
            ChannelState::Stopped => "STOPPED",
            ChannelState::End => "END",
        }
    }
}

/// Something that happened in a cycle.
#[derive(Clone, Debug, PartialEq)]
// Events live in a fixed-size vector in the setpoint: boxing the large one would allocate on
// the IPO path.
#[allow(clippy::large_enum_variant)]
pub enum Event {
    /// Auxiliary functions output to the PLC at their S point; `wait`: the path waits for
    /// the acknowledgement (`ipo.wait_for_ack`).
    Aux { aux: AuxFunction, wait: bool },
    /// M00, M01 or M18 reached: the channel stops.
    Stop(Stop),
    /// M02 or M30 reached.
    End(Stop),
    /// Single-block mode stopped at an S point.
    SingleBlock,
    /// A preparation alarm reached: the channel stops with its position kept.
    Alarm { code: u32, source: Source },
    /// The channel changed state.
    State(ChannelState),
}

/// What preparation feeds the channel, in program order.
// Nearly every input is a motion: boxing it would allocate, and the IPO thread frees nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum Input {
    Motion(Entry),
    Aux(AuxFunction),
    Stop(Stop),
    End(Stop),
    Alarm {
        code: u32,
        source: Source,
    },
    /// The program is through (after its last record).
    Done,
}

/// Events in one setpoint. What waits at an S point beyond that goes out in the next
/// cycles, before the path moves on; two places stay free for a single-block stop and a
/// state change.
pub const MAX_EVENTS: usize = 8;
const RECORDS_PER_CYCLE: usize = MAX_EVENTS - 2;

/// One IPO cycle's output.
#[derive(Clone, Debug, PartialEq)]
pub struct Setpoint {
    pub cycle: u64,
    pub pos: Pos,
    /// The additional axes (U V W A B C; 0 where not configured).
    pub add: Additional,
    /// Path speed, mm/s.
    pub v_path: f64,
    pub source: Option<Source>,
    pub state: ChannelState,
    /// The spindle's speed setpoint, rev/min: positive clockwise, negative
    /// counter-clockwise (docs/spindle.md).
    pub spindle: f64,
    /// What the spindle is told to do (an oriented stop has speed 0 too).
    pub spindle_dir: SpindleDir,
    pub events: heapless::Vec<Event, MAX_EVENTS>,
}

/// Records waiting for their S point.
const WAITING: usize = 64;

/// A record waiting for the start of segment `tag` (after the last one: the end).
struct Waiting {
    tag: u64,
    event: Event,
    /// An auxiliary function the PLC must acknowledge before the path goes on.
    acked: bool,
}

/// The channel's state apart from the planner (a separate borrow in the cycle).
struct Gate {
    waiting: heapless::Deque<Waiting, WAITING>,
    acks_due: u32,
    /// Waits for NC start (program stop, single block, alarm).
    halted: bool,
    alarm: bool,
    single_block: bool,
    /// The segment NC start released last (single block), and the last one started.
    released: Option<u64>,
    started: Option<u64>,
    wait_for_ack: heapless::Vec<(u8, f64), 16>,
    /// The spindle, tool and work offset as of the last record output.
    tech: Technology,
}

impl Gate {
    /// Outputs what waits for the start of segment `no` (all of it for `None`: the end), as
    /// much as fits in this cycle; true when all of it is out. Nothing goes out while the
    /// channel waits for NC start: what follows a program stop (M00 before M30 at the same
    /// S point, say) belongs to blocks after it.
    fn drain(&mut self, no: Option<u64>, out: &mut heapless::Vec<Event, MAX_EVENTS>) -> bool {
        while let Some(w) = self.waiting.front() {
            if self.halted {
                return false;
            }
            if no.is_some_and(|n| w.tag > n) {
                return true;
            }
            if out.len() >= RECORDS_PER_CYCLE {
                return false;
            }
            let Some(Waiting {
                event: e, acked, ..
            }) = self.waiting.pop_front()
            else {
                break;
            };
            if acked {
                self.acks_due += 1;
            }
            match &e {
                Event::Aux { aux, .. } => {
                    if let Some(t) = aux.tech {
                        self.tech = t;
                    }
                }
                Event::Stop(_) => self.halted = true,
                Event::Alarm { .. } => {
                    self.halted = true;
                    self.alarm = true;
                }
                _ => {}
            }
            let _ = out.push(e);
        }
        !self.halted
    }

    /// At the start of segment `no`: what waits for it goes out; true when the segment may
    /// start.
    fn pass(&mut self, no: u64, at_rest: bool, out: &mut heapless::Vec<Event, MAX_EVENTS>) -> bool {
        let all_out = self.drain(Some(no), out);
        if at_rest
            && self.single_block
            && self.started.is_some()
            && self.released != Some(no)
            && !self.halted
        {
            self.halted = true;
            // The S point is where the segment before ended; its block is the one shown.
            let _ = out.push(Event::SingleBlock);
        }
        let go = all_out && !(self.halted || self.acks_due > 0);
        if go || !at_rest {
            self.started = Some(no);
        }
        go
    }
}

pub struct Channel {
    planner: Planner,
    gate: Gate,
    /// Machine data `spindle.max_speed`, rev/min.
    spindle_max: f64,
    state: ChannelState,
    input_done: bool,
    ended: bool,
}

impl Channel {
    pub fn new(md: &MachineData, start: AxisPos) -> Self {
        let lim = super::AxisLimits::new(md);
        let mut wait = heapless::Vec::new();
        for w in md.ipo.ack_words() {
            let _ = wait.push(w);
        }
        Channel {
            planner: Planner::new(lim, md.ipo.lookahead as usize, start),
            gate: Gate {
                waiting: heapless::Deque::new(),
                acks_due: 0,
                halted: false,
                alarm: false,
                single_block: false,
                released: None,
                started: None,
                wait_for_ack: wait,
                tech: Technology::default(),
            },
            spindle_max: md.spindle.max_speed,
            state: ChannelState::Reset,
            input_done: false,
            ended: false,
        }
    }

    pub fn state(&self) -> ChannelState {
        self.state
    }

    pub fn planner(&self) -> &Planner {
        &self.planner
    }

    /// Whether `input` can be taken now (room in the lookahead, or for what waits).
    fn can_take(&self, input: &Input) -> bool {
        match input {
            Input::Motion(_) => self.planner.room() > 0,
            Input::Done => true,
            _ => !self.gate.waiting.is_full(),
        }
    }

    /// Takes the next record from preparation; gives it back when there is no room (offer it
    /// again after a cycle). After the end of the input, whatever comes is dropped. The record
    /// comes back by value: boxing it would allocate on the IPO path.
    #[allow(clippy::result_large_err)]
    pub fn take(&mut self, input: Input) -> Result<(), Input> {
        if self.input_done {
            return Ok(());
        }
        if !self.can_take(&input) {
            return Err(input);
        }
        let tag = self.planner.pushed();
        let (event, acked) = match input {
            Input::Motion(mut e) => {
                // A thread is not interrupted: single block stops at the end of the
                // first segment after it that is no thread (Fanuc), or where it stops anyway.
                if self.gate.single_block && !e.thread {
                    e.stop_after = true;
                }
                self.planner.push(e);
                return Ok(());
            }
            Input::Done => {
                self.input_done = true;
                return Ok(());
            }
            Input::Aux(a) => {
                let wait = a.words.iter().any(|w| {
                    let word = (w.address.to_ascii_uppercase(), w.value);
                    self.gate.wait_for_ack.contains(&word)
                });
                (Event::Aux { aux: a, wait }, wait)
            }
            Input::Stop(s) => (Event::Stop(s), false),
            Input::End(s) => {
                self.input_done = true;
                (Event::End(s), false)
            }
            Input::Alarm { code, source } => {
                self.input_done = true;
                (Event::Alarm { code, source }, false)
            }
        };
        // Whatever waits here (an acknowledgement, a stop, the end, an alarm) needs the path
        // at rest: the segment before ends with an exact stop.
        if acked || !matches!(event, Event::Aux { .. }) {
            self.planner.stop_after_last();
        }
        let _ = self.gate.waiting.push_back(Waiting { tag, event, acked });
        Ok(())
    }

    /// Takes records from `next` until the lookahead is full or the input is done; one that
    /// does not fit waits in `pending` for the next call.
    pub fn fill(&mut self, pending: &mut Option<Input>, mut next: impl FnMut() -> Option<Input>) {
        while !self.input_done {
            let Some(input) = pending.take().or_else(&mut next) else {
                return;
            };
            if let Err(back) = self.take(input) {
                *pending = Some(back);
                return;
            }
        }
    }

    /// An alarm from outside the program (PLC, drives, emergency stop): the path brakes on
    /// its contour and the channel stops with the alarm; NC start is refused until reset.
    pub fn fault(&mut self) {
        self.gate.alarm = true;
        if self.state == ChannelState::Active {
            self.gate.halted = true;
            self.planner.stop();
        }
    }

    /// Where the path is on the program (see [`Planner::progress`]).
    pub fn progress(&self) -> Option<super::planner::Progress> {
        self.planner.progress()
    }

    /// Waiting for NC start after a program stop, a single-block stop or an alarm.
    pub fn waits_for_start(&self) -> bool {
        self.gate.halted
    }

    /// Read-in disable (PLC): no further block starts; the path comes to rest at the first
    /// block end it can still reach, and goes on when the signal drops.
    pub fn set_read_in_disable(&mut self, on: bool) {
        self.planner.set_hold(on);
    }

    /// All input taken (the end of the program is known).
    pub fn input_done(&self) -> bool {
        self.input_done
    }

    /// NC start: RESET → ACTIVE, or STOPPED → ACTIVE (after an NC stop, a program stop or
    /// a single-block stop). Not after an alarm or at the end: reset first.
    pub fn start(&mut self) {
        match self.state {
            ChannelState::Reset => self.state = ChannelState::Active,
            // NC start while still braking from an NC stop: go on from where it is.
            ChannelState::Active => self.planner.resume(),
            ChannelState::Stopped if !self.gate.alarm => {
                self.state = ChannelState::Active;
                self.planner.resume();
                if self.gate.halted {
                    self.gate.halted = false;
                    self.gate.released = Some(self.planner.pushed().min(self.next_segment()));
                }
            }
            _ => {}
        }
    }

    /// The number of the next segment to start.
    fn next_segment(&self) -> u64 {
        self.gate.started.map_or(0, |s| s + 1)
    }

    /// NC stop: the path brakes and holds; STOPPED once at rest.
    pub fn stop(&mut self) {
        if self.state == ChannelState::Active {
            self.planner.stop();
        }
    }

    /// Reset: the program is dropped, the position stays.
    pub fn reset(&mut self) {
        self.planner.clear();
        self.planner.set_hold(false);
        self.gate.waiting.clear();
        self.gate.acks_due = 0;
        self.gate.halted = false;
        self.gate.alarm = false;
        self.gate.released = None;
        self.gate.started = None;
        self.input_done = false;
        self.ended = false;
        self.state = ChannelState::Reset;
    }

    /// Where the channel stands, for a channel with nothing queued (after a reset).
    pub fn set_position(&mut self, pos: AxisPos) {
        self.planner.set_position(pos);
    }

    /// The PLC acknowledged an auxiliary function.
    pub fn ack(&mut self) {
        self.gate.acks_due = self.gate.acks_due.saturating_sub(1);
    }

    /// A preparation alarm stopped the channel (reset to go on).
    pub fn has_alarm(&self) -> bool {
        self.gate.alarm
    }

    pub fn acks_due(&self) -> u32 {
        self.gate.acks_due
    }

    pub fn set_override(&mut self, f: f64) {
        self.planner.set_override(f);
    }

    /// Single-block mode: stop at every S point.
    pub fn set_single_block(&mut self, on: bool) {
        self.gate.single_block = on;
        if on {
            self.planner.stop_after_each();
        }
    }

    /// The setpoint of cycle `k`.
    pub fn cycle(&mut self, k: u64, out: &mut Setpoint) {
        out.events.clear();
        let before = self.state;
        let sample = match self.state {
            ChannelState::Active | ChannelState::Stopped => {
                let gate = &mut self.gate;
                let events = &mut out.events;
                self.planner
                    .cycle(k, &mut |no, rest| gate.pass(no, rest, events))
            }
            ChannelState::Reset | ChannelState::End => Sample {
                pos: self.planner.position(),
                add: self.planner.axis_position().add,
                v: 0.0,
                source: out.source,
            },
        };
        if let Some(started) = self.gate.started {
            // What a running hand-over left for lack of room in its cycle.
            self.gate.drain(Some(started), &mut out.events);
        }
        if self.state == ChannelState::Active {
            // The path is done: what waits after the last segment is due now.
            if self.planner.idle()
                && self.input_done
                && !self.ended
                && self.gate.drain(None, &mut out.events)
            {
                self.ended = true;
                if !self.gate.alarm {
                    self.state = ChannelState::End;
                }
            }
            if self.planner.at_rest() && (self.gate.halted || self.planner.is_stopping()) {
                self.state = ChannelState::Stopped;
            }
        }
        if self.state != before {
            let _ = out.events.push(Event::State(self.state));
        }
        out.cycle = k;
        out.pos = sample.pos;
        out.add = sample.add;
        out.v_path = sample.v;
        out.source = sample.source;
        out.state = self.state;
        // Reset, the program's end and an alarm stop the spindle (docs/spindle.md).
        let p = match self.state {
            _ if self.gate.alarm => SpindleProgram::default(),
            ChannelState::Active | ChannelState::Stopped => self.gate.tech.spindle,
            ChannelState::Reset | ChannelState::End => SpindleProgram::default(),
        };
        // Constant surface speed during a rapid move: the speed of its end point (Fanuc,
        // 840D: the speed does not follow a rapid traverse).
        let x = self.planner.rapid_end_x().unwrap_or(sample.pos[0]);
        out.spindle = spindle_setpoint(&p, x, self.spindle_max);
        out.spindle_dir = p.dir;
    }

    /// The spindle, tool, cutting edge and work offset of the path's place (for the HMI).
    pub fn technology(&self) -> Technology {
        self.gate.tech
    }

    /// A program resumed in NC stop starts with what was in force where it stopped.
    pub fn set_technology(&mut self, t: Technology) {
        self.gate.tech = t;
    }

    /// The spindle's actual speed, rev/min (the PLC's, or a model's): a feed per revolution
    /// follows it.
    pub fn set_spindle_actual(&mut self, rpm: f64) {
        self.planner.set_spindle_speed(rpm);
    }
}

impl Setpoint {
    /// Every path axis.
    pub fn axes(&self) -> AxisPos {
        AxisPos {
            geo: self.pos,
            add: self.add,
        }
    }

    pub fn new(start: AxisPos) -> Self {
        Setpoint {
            cycle: 0,
            pos: start.geo,
            add: start.add,
            v_path: 0.0,
            source: None,
            state: ChannelState::Reset,
            spindle: 0.0,
            spindle_dir: SpindleDir::Stop,
            events: heapless::Vec::new(),
        }
    }
}
