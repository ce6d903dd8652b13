//! `softnc simulate`: the kernel's preparation thread, queue and channel run against a
//! simulated clock. One CSV row per IPO cycle:
//! `cycle,time,X,Y,Z,S1,v_path,block,events` (the configured additional axes after Z, the
//! spindle's speed setpoint in rev/min under S1).
//!
//! Preparation runs in its own thread and hands ready [`Entry`](crate::ipo::Entry)s (limits computed there)
//! over a bounded queue. The simulated IPO never runs ahead of it: before each cycle it takes
//! records until the lookahead is full or the program is through, waiting for them if
//! needed. So the setpoints depend on the program and the machine data only, never on how
//! fast the preparation thread happens to be: the same bits on every run.
//!
//! One run is a [`Simulation`], stepped one cycle per call: [`run`] steps it to the end and
//! writes the rows, the co-simulation library (crate softnc-cosim) steps it from C.
//!
//! The simulation plays operator and PLC: a program stop (M00, M01, M18) or a single-block
//! stop is followed by NC start in the next cycle, and an auxiliary function that waits for
//! an acknowledgement is acknowledged `ack_cycles` cycles after it was output.

use crate::alarm::{Alarm, AlarmCode};
use crate::handover::Report;
use crate::ipo::Input;
use crate::ipo::{Channel, ChannelState, Event, Setpoint, SpindleModel};
use crate::segment::Source;
use crate::{MachineData, ToolTable};
use std::io::Write;
use std::time::Duration;

#[derive(Clone, Debug)]
pub struct Options {
    /// Cycles from an aux output to its acknowledgement.
    pub ack_cycles: u64,
    /// Path override, 0–1.2.
    pub override_: f64,
    pub single_block: bool,
    /// The caller's budget, cycles: the rows stop after this many, wherever the path is
    /// (`timed_out`). Machine data `simulate.*` ends a run with an alarm instead.
    pub max_cycles: u64,
    /// Test hook: preparation sleeps this long per record.
    pub prep_delay: Duration,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            ack_cycles: 1,
            override_: 1.0,
            single_block: false,
            max_cycles: u64::MAX,
            prep_delay: Duration::ZERO,
        }
    }
}

/// What came of a run.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    pub cycles: u64,
    pub segments: u64,
    pub aux: u64,
    /// Highest path speed, mm/min.
    pub max_speed: f64,
    pub end_state: Option<ChannelState>,
    /// Preparation's alarms (the channel stopped there) and warnings.
    pub alarms: Vec<Alarm>,
    pub warnings: Vec<Alarm>,
    /// The run hit `max_cycles`.
    pub timed_out: bool,
    /// Segments that ended at speed with nothing after them (the planner's dead stops).
    pub dead_stops: u64,
}

/// Where a long simulation is: told every [`PROGRESS_CYCLES`] cycles.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    pub cycles: u64,
    /// Line of the block the setpoint belongs to (0: none yet).
    pub line: u32,
}

/// Cycles between two progress reports (65 s of machine time at 1 ms).
pub const PROGRESS_CYCLES: u64 = 1 << 16;

/// Runs `source` to its end (or alarm) and writes the setpoint rows to `out`.
pub fn run(
    name: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
    opts: &Options,
    out: &mut dyn Write,
) -> std::io::Result<Summary> {
    run_with_progress(name, source, md, tools, opts, out, &mut |_| {})
}

/// As [`run`], telling `progress` where it is every [`PROGRESS_CYCLES`] cycles.
pub fn run_with_progress(
    name: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
    opts: &Options,
    out: &mut dyn Write,
    progress: &mut dyn FnMut(Progress),
) -> std::io::Result<Summary> {
    let mut sim = Simulation::new(name, source, md, tools, opts)?;
    let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
    writeln!(w, "{}", sim.header())?;
    let mut line = String::with_capacity(256);
    loop {
        let step = sim.step();
        sim.row(&mut line);
        w.write_all(line.as_bytes())?;
        if step != Step::Running {
            break;
        }
        let k = sim.next_cycle();
        if k.is_multiple_of(PROGRESS_CYCLES) {
            progress(Progress {
                cycles: k,
                line: sim.setpoint().source.map_or(0, |s| s.line),
            });
        }
        if k >= opts.max_cycles {
            sim.summary.timed_out = true;
            break;
        }
    }
    w.flush()?;
    Ok(sim.finish())
}

/// What a cycle of a [`Simulation`] left the channel doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// The next cycle goes on (moving, waiting, or restarted after a stop).
    Running,
    /// The program ended (M02, M30, the end of the text).
    Ended,
    /// The channel stopped with an alarm (reset to go on); also every cycle a stepped
    /// simulation is asked for after it stopped or ended.
    Stopped,
}

/// One simulated run, cycle by cycle: its preparation thread, the channel, and the simulated
/// operator and PLC around it. [`run`] steps it to the end; a co-simulation (crate
/// softnc-cosim) steps it one cycle per call and may play operator and PLC itself.
pub struct Simulation {
    name: String,
    md: MachineData,
    prep: Option<crate::handover::Spawned>,
    ch: Box<Channel>,
    sp: Setpoint,
    pending: Option<Input>,
    /// Cycles at which the simulated PLC acknowledges the aux functions waiting.
    acks: std::collections::VecDeque<u64>,
    ack_cycles: u64,
    /// The simulated PLC's spindle drive.
    spindle: SpindleModel,
    limits: Limits,
    /// Cycles in a row the path stood still with nothing happening.
    still: u64,
    /// The next cycle's number.
    k: u64,
    /// The additional axes the machine has, in CSV order.
    extra: Vec<usize>,
    /// The last step ended or stopped the run: further steps do nothing.
    over: bool,
    /// The simulated operator gives NC start after a stop without alarm (on for [`run`]).
    pub operator: bool,
    /// The simulated PLC acknowledges aux functions `ack_cycles` after their output and
    /// reports the spindle's actual speed (on for [`run`]).
    pub plc: bool,
    pub summary: Summary,
}

/// Where a run that would not end is ended (machine data `simulate`), in cycles.
struct Limits {
    cycles: u64,
    rest: u64,
}

impl Limits {
    fn new(md: &MachineData) -> Self {
        let cycle_s = f64::from(md.ipo.cycle_us) * 1e-6;
        let cycles = |s: f64| ((s / cycle_s).ceil() as u64).max(1);
        Limits {
            cycles: cycles(md.simulate.max_machine_time),
            rest: cycles(md.simulate.max_rest_time),
        }
    }

    /// The alarm due after `k + 1` cycles of which the last `still` stood still.
    fn due(&self, k: u64, still: u64) -> Option<AlarmCode> {
        if k + 1 >= self.cycles {
            Some(AlarmCode::SimulationTimeLimit)
        } else if still >= self.rest {
            Some(AlarmCode::NoProgress)
        } else {
            None
        }
    }
}

/// The alarm a simulation limit raised at the block of `at`.
fn limit_alarm(code: AlarmCode, at: Option<Source>, name: &str, md: &MachineData) -> Alarm {
    let message = match code {
        AlarmCode::SimulationTimeLimit => format!(
            "simulation ended at the machine-time limit of {} s (machine data simulate.max_machine_time): the path braked and stopped here",
            md.simulate.max_machine_time
        ),
        _ => format!(
            "simulation ended: the path stood still with nothing happening for {} s (machine data simulate.max_rest_time); the program waits here for something that does not come",
            md.simulate.max_rest_time
        ),
    };
    let at = at.unwrap_or(Source {
        line: 1,
        col: 1,
        ..Source::default()
    });
    Alarm::at(code, name, &at, message)
}

impl Simulation {
    /// Starts preparing `source` in a thread of its own, the channel in NC start at the
    /// program's start position.
    pub fn new(
        name: &str,
        source: &str,
        md: &MachineData,
        tools: &ToolTable,
        opts: &Options,
    ) -> std::io::Result<Simulation> {
        let prep = crate::handover::spawn_simulation(
            name.to_string(),
            source.to_string(),
            md.clone(),
            tools.clone(),
            opts.prep_delay,
        )?;
        let start = prep.start;
        let mut ch = Box::new(Channel::new(md, start));
        ch.set_override(opts.override_);
        ch.set_single_block(opts.single_block);
        ch.start();
        let extra = extra_axes(md);
        Ok(Simulation {
            name: name.to_string(),
            md: md.clone(),
            prep: Some(prep),
            ch,
            sp: Setpoint::new(start),
            pending: None,
            acks: std::collections::VecDeque::new(),
            ack_cycles: opts.ack_cycles.max(1),
            spindle: SpindleModel::new(
                md.plc.spindle_acceleration,
                f64::from(md.ipo.cycle_us) * 1e-6,
            ),
            limits: Limits::new(md),
            still: 0,
            k: 0,
            extra,
            over: false,
            operator: true,
            plc: true,
            summary: Summary::default(),
        })
    }

    /// One IPO cycle: takes what preparation has, lets the simulated PLC act, computes the
    /// setpoint ([`Self::setpoint`]).
    pub fn step(&mut self) -> Step {
        if self.over {
            return Step::Stopped;
        }
        self.take_prepared();
        // The simulated operator and PLC act between cycles.
        while self.acks.front().is_some_and(|&due| due <= self.k) {
            self.acks.pop_front();
            self.ch.ack();
        }
        let before = self.sp.axes();
        self.ch.cycle(self.k, &mut self.sp);
        if self.plc {
            self.ch
                .set_spindle_actual(self.spindle.follow(self.sp.spindle));
        }
        self.still = if self.sp.axes() == before && self.sp.events.is_empty() {
            self.still + 1
        } else {
            0
        };
        self.check_limits();
        self.count();
        let step = match self.sp.state {
            ChannelState::End => Step::Ended,
            ChannelState::Stopped if !self.ch.has_alarm() => {
                if self.operator {
                    self.ch.start();
                }
                Step::Running
            }
            ChannelState::Stopped => Step::Stopped,
            _ => Step::Running,
        };
        if step == Step::Running {
            self.k += 1;
        } else {
            self.over = true;
        }
        step
    }

    /// Takes what preparation has, up to the lookahead; waits for it (simulated time stands
    /// still), so the result does not depend on the thread's speed.
    fn take_prepared(&mut self) {
        let Some(prep) = &self.prep else {
            return;
        };
        let hand = &prep.hand;
        self.ch.fill(&mut self.pending, || loop {
            if let Some(i) = hand.pop() {
                return Some(i);
            }
            std::thread::yield_now();
        });
    }

    /// Machine data `simulate.*`: a run that would not end brakes on its contour and stops
    /// with an alarm.
    fn check_limits(&mut self) {
        if self.ch.has_alarm() {
            return;
        }
        if let Some(code) = self.limits.due(self.k, self.still) {
            self.ch.fault();
            let source = self.sp.source.unwrap_or_default();
            let _ = self.sp.events.push(Event::Alarm {
                code: code.number(),
                source,
            });
            let a = limit_alarm(code, self.sp.source, &self.name, &self.md);
            self.summary.alarms.push(a);
        }
    }

    /// The cycle's aux functions into the summary and, for the simulated PLC, the
    /// acknowledgements due.
    fn count(&mut self) {
        for e in &self.sp.events {
            if let Event::Aux { aux, .. } = e {
                self.summary.aux += u64::from(!aux.words.is_empty());
            }
        }
        let due = self.ch.acks_due() as usize;
        if self.plc {
            while self.acks.len() < due {
                self.acks.push_back(self.k + self.ack_cycles);
            }
        }
        self.summary.max_speed = self.summary.max_speed.max(self.sp.v_path * 60.0);
    }

    /// The setpoint of the last cycle stepped.
    pub fn setpoint(&self) -> &Setpoint {
        &self.sp
    }

    /// The number the next cycle gets (the cycles stepped while running).
    pub fn next_cycle(&self) -> u64 {
        self.k
    }

    /// The channel, to feed it what a PLC or an operator would (override, NC start and
    /// stop, read-in disable, aux acknowledgements, the spindle's actual speed).
    pub fn channel(&mut self) -> &mut Channel {
        &mut self.ch
    }

    /// The channel, to read.
    pub fn channel_ref(&self) -> &Channel {
        &self.ch
    }

    /// The IPO cycle, µs.
    pub fn cycle_us(&self) -> u32 {
        self.md.ipo.cycle_us
    }

    /// The CSV header: `cycle,time,X,Y,Z{additional axes},S1,v_path,block,events`.
    pub fn header(&self) -> String {
        csv_header(&self.extra)
    }

    /// The last setpoint as `softnc simulate` writes it, with its newline.
    pub fn row(&self, line: &mut String) {
        write_row(line, &self.sp, &self.extra, u64::from(self.md.ipo.cycle_us));
    }

    /// The last setpoint's block column as `softnc simulate` writes it (appended).
    pub fn block(&self, line: &mut String) {
        write_block(line, &self.sp);
    }

    /// The last setpoint's events column as `softnc simulate` writes it (appended).
    pub fn events(&self, line: &mut String) {
        write_events(line, &self.sp);
    }

    /// The additional axes the CSV rows carry after Z (indices into U V W A B C + 3).
    pub fn extra_axes(&self) -> &[usize] {
        &self.extra
    }

    /// Stops the preparation thread and hands over what came of the run: preparation's
    /// alarms and warnings after the simulation's own.
    pub fn finish(mut self) -> Summary {
        let mut summary = std::mem::take(&mut self.summary);
        summary.cycles = self.k + 1;
        summary.segments = self.ch.planner().pushed();
        summary.dead_stops = self.ch.planner().dead_stops();
        summary.end_state = Some(self.sp.state);
        for r in self.stop_preparation() {
            match r {
                Report::Warning(w) => summary.warnings.push(w),
                Report::Alarm(a) => summary.alarms.push(a),
                // A simulation keeps nothing: the file of kept variables is the machine's.
                Report::KeptVariables(_) => {}
            }
        }
        summary
    }

    /// Tells the preparation thread to stop, joins it and returns its reports.
    fn stop_preparation(&mut self) -> Vec<Report> {
        let Some(prep) = self.prep.take() else {
            return Vec::new();
        };
        prep.hand
            .cancel
            .store(true, std::sync::atomic::Ordering::Relaxed);
        let _ = prep.thread.join();
        prep.reports.try_iter().collect()
    }
}

impl Drop for Simulation {
    fn drop(&mut self) {
        self.stop_preparation();
    }
}

/// The additional axes the CSV rows carry after Z: X Y Z always, then the additional axes
/// the machine has (continuous positions: a modulo axis's setpoint runs on past 360°).
pub fn extra_axes(md: &MachineData) -> Vec<usize> {
    md.axes
        .configured()
        .map(|(i, _)| i)
        .filter(|&i| i >= 3)
        .collect()
}

/// The CSV header for the additional axes `extra` ([`extra_axes`]).
pub fn csv_header(extra: &[usize]) -> String {
    let names: String = extra
        .iter()
        .map(|&i| format!(",{}", crate::machine_data::AXIS_NAMES[i]))
        .collect();
    format!("cycle,time,X,Y,Z{names},S1,v_path,block,events")
}

/// One CSV row as `softnc simulate` writes it, with its newline (a live run's setpoints
/// written by a record of it, a replay's).
pub fn setpoint_row(line: &mut String, sp: &Setpoint, extra: &[usize], cycle_us: u64) {
    write_row(line, sp, extra, cycle_us);
}

/// One CSV row; numbers in the shortest form that reads back to the same bits.
fn write_row(line: &mut String, sp: &Setpoint, extra: &[usize], cycle_us: u64) {
    use std::fmt::Write as _;
    line.clear();
    let us = sp.cycle * cycle_us;
    let _ = write!(
        line,
        "{},{}.{:06}",
        sp.cycle,
        us / 1_000_000,
        us % 1_000_000
    );
    let mut buf = ryu::Buffer::new();
    let add = extra.iter().map(|&i| &sp.add[i - 3]);
    for x in sp
        .pos
        .iter()
        .chain(add)
        .chain(std::iter::once(&sp.spindle))
        .chain(std::iter::once(&(sp.v_path * 60.0)))
    {
        line.push(',');
        // -0.0 prints as 0: the same place.
        let x = if *x == 0.0 { 0.0 } else { *x };
        line.push_str(buf.format(x));
    }
    line.push(',');
    write_block(line, sp);
    line.push(',');
    write_events(line, sp);
    line.push('\n');
}

/// The block column: the block number (`N10`) or, without one, the line (`L3`); empty
/// before the first block.
fn write_block(line: &mut String, sp: &Setpoint) {
    use std::fmt::Write as _;
    if let Some(s) = sp.source {
        match s.number {
            Some(n) => {
                let _ = write!(line, "{n}");
            }
            None => {
                let _ = write!(line, "L{}", s.line);
            }
        }
    }
}

/// The events column: the cycle's events, `;` between them.
fn write_events(line: &mut String, sp: &Setpoint) {
    use std::fmt::Write as _;
    for (i, e) in sp.events.iter().enumerate() {
        if i > 0 {
            line.push(';');
        }
        match e {
            Event::Aux { aux: a, .. } if a.words.is_empty() => {
                let _ = write!(line, "tech @S{}", a.at);
            }
            Event::Aux { aux: a, .. } => {
                line.push_str("aux");
                for w in &a.words {
                    let _ = write!(line, " {w}");
                }
                let _ = write!(line, " @S{}", a.at);
            }
            Event::Stop(s) => line.push_str(s.code.code()),
            Event::End(s) => line.push_str(s.code.code()),
            Event::SingleBlock => line.push_str("single-block"),
            Event::Alarm { code, .. } => {
                let _ = write!(line, "alarm {code}");
            }
            Event::State(st) => {
                let _ = write!(line, "{}", st.name());
            }
        }
    }
}
