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
//! The simulation plays operator and PLC: a program stop (M00, M01, M18) or a single-block
//! stop is followed by NC start in the next cycle, and an auxiliary function that waits for
//! an acknowledgement is acknowledged `ack_cycles` cycles after it was output.

use crate::alarm::{Alarm, AlarmCode};
use crate::handover::{with_preparation, Handover, Job, Report};
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
    let job = Job {
        name,
        source,
        md,
        tools,
        at: None,
    };
    let (result, reports) = with_preparation(job, opts.prep_delay, |start, hand| {
        ipo_loop(name, md, start, hand, opts, out, progress)
    })?;
    let mut summary = result?;
    for r in reports {
        match r {
            Report::Warning(w) => summary.warnings.push(w),
            Report::Alarm(a) => summary.alarms.push(a),
            // A simulation keeps nothing: the file of kept variables is the machine's.
            Report::KeptVariables(_) => {}
        }
    }
    Ok(summary)
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

fn ipo_loop(
    name: &str,
    md: &MachineData,
    start: crate::frontend::block::AxisPos,
    hand: &Handover,
    opts: &Options,
    out: &mut dyn Write,
    progress: &mut dyn FnMut(Progress),
) -> std::io::Result<Summary> {
    let mut ch = Box::new(Channel::new(md, start));
    ch.set_override(opts.override_);
    ch.set_single_block(opts.single_block);
    let mut sp = Setpoint::new(start);
    let mut summary = Summary::default();
    let mut pending: Option<Input> = None;
    let mut acks: std::collections::VecDeque<u64> = std::collections::VecDeque::new();
    let cycle_us = u64::from(md.ipo.cycle_us);
    let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
    // X Y Z always, then the additional axes the machine has (continuous positions: a
    // modulo axis's setpoint runs on past 360°).
    let extra: Vec<usize> = md
        .axes
        .configured()
        .map(|(i, _)| i)
        .filter(|&i| i >= 3)
        .collect();
    let names: String = extra
        .iter()
        .map(|&i| format!(",{}", crate::machine_data::AXIS_NAMES[i]))
        .collect();
    writeln!(w, "cycle,time,X,Y,Z{names},S1,v_path,block,events")?;
    let mut line = String::with_capacity(256);
    ch.start();
    let limits = Limits::new(md);
    // The simulated PLC's spindle drive.
    let mut spindle = SpindleModel::new(
        md.plc.spindle_acceleration,
        f64::from(md.ipo.cycle_us) * 1e-6,
    );
    // Cycles in a row the path stood still with nothing happening.
    let mut still: u64 = 0;
    let mut k: u64 = 0;
    loop {
        // Take what preparation has, up to the lookahead; wait for it (simulated time stands
        // still), so the result does not depend on the thread's speed.
        ch.fill(&mut pending, || loop {
            if let Some(i) = hand.pop() {
                return Some(i);
            }
            std::thread::yield_now();
        });
        // The simulated operator and PLC act between cycles.
        while acks.front().is_some_and(|&due| due <= k) {
            acks.pop_front();
            ch.ack();
        }
        let before = sp.axes();
        ch.cycle(k, &mut sp);
        ch.set_spindle_actual(spindle.follow(sp.spindle));
        still = if sp.axes() == before && sp.events.is_empty() {
            still + 1
        } else {
            0
        };
        if !ch.has_alarm() {
            if let Some(code) = limits.due(k, still) {
                // The path brakes on its contour and the channel stops with the alarm.
                ch.fault();
                let source = sp.source.unwrap_or_default();
                let _ = sp.events.push(Event::Alarm {
                    code: code.number(),
                    source,
                });
                summary.alarms.push(limit_alarm(code, sp.source, name, md));
            }
        }
        for e in &sp.events {
            if let Event::Aux { aux, .. } = e {
                summary.aux += u64::from(!aux.words.is_empty());
            }
        }
        let due = ch.acks_due() as usize;
        while acks.len() < due {
            acks.push_back(k + opts.ack_cycles.max(1));
        }
        summary.max_speed = summary.max_speed.max(sp.v_path * 60.0);
        write_row(&mut line, &sp, &extra, cycle_us);
        w.write_all(line.as_bytes())?;
        match sp.state {
            ChannelState::End => break,
            ChannelState::Stopped if !ch.has_alarm() => ch.start(),
            ChannelState::Stopped => break,
            _ => {}
        }
        k += 1;
        if k.is_multiple_of(PROGRESS_CYCLES) {
            progress(Progress {
                cycles: k,
                line: sp.source.map_or(0, |s| s.line),
            });
        }
        if k >= opts.max_cycles {
            summary.timed_out = true;
            break;
        }
    }
    w.flush()?;
    summary.cycles = k + 1;
    summary.segments = ch.planner().pushed();
    summary.dead_stops = ch.planner().dead_stops();
    summary.end_state = Some(sp.state);
    Ok(summary)
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
    line.push(',');
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
    line.push('\n');
}
