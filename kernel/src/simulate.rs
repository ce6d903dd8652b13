//! `softnc simulate`: the kernel's preparation thread, queue and channel run against a
//! simulated clock (issue 5 e, f). One CSV row per IPO cycle:
//! `cycle,time,X,Y,Z,v_path,block,events`.
//!
//! Preparation runs in its own thread and hands ready [`Entry`]s (limits computed there)
//! over a bounded queue. The simulated IPO never runs ahead of it: before each cycle it takes
//! records until the lookahead is full or the program is through, waiting for them if
//! needed. So the setpoints depend on the program and the machine data only, never on how
//! fast the preparation thread happens to be: the same bits on every run.
//!
//! The simulation plays operator and PLC: a program stop (M00, M01, M18) or a single-block
//! stop is followed by NC start in the next cycle, and an auxiliary function that waits for
//! an acknowledgement is acknowledged `ack_cycles` cycles after it was output.

use crate::alarm::Alarm;
use crate::ipo::channel::Input;
use crate::ipo::{AxisLimits, Channel, ChannelState, Entry, Event, Setpoint};
use crate::prep::{Preparation, Prepared};
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
    /// Simulated time limit, cycles (a program that waits forever at override 0, say).
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
            max_cycles: 100_000_000,
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
    /// Alarms: preparation's (the channel stopped there) and warnings.
    pub alarms: Vec<Alarm>,
    pub warnings: Vec<Alarm>,
    /// The run hit `max_cycles`.
    pub timed_out: bool,
}

/// What the preparation thread sends. Not boxed: the IPO side would free the box (no
/// allocator traffic on that side).
#[allow(clippy::large_enum_variant)]
enum Fed {
    Start(crate::frontend::block::Pos),
    In(Input),
    Warning(Alarm),
    Alarm(Alarm),
}

/// Runs `source` to its end (or alarm) and writes the setpoint rows to `out`.
pub fn run(
    name: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
    opts: &Options,
    out: &mut dyn Write,
) -> std::io::Result<Summary> {
    let (tx, rx) = crossbeam::channel::bounded::<Fed>(256);
    let lim = AxisLimits::new(md);
    std::thread::scope(|scope| {
        let prep_thread = std::thread::Builder::new()
            .name("preparation".into())
            .spawn_scoped(scope, move || feed(name, source, md, tools, &lim, opts, tx))
            .map_err(std::io::Error::other)?;
        let r = ipo_loop(md, &rx, opts, out);
        drop(rx);
        let _ = prep_thread.join();
        r
    })
}

/// The preparation thread: records in program order, entries with their limits.
fn feed(
    name: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
    lim: &AxisLimits,
    opts: &Options,
    tx: crossbeam::channel::Sender<Fed>,
) {
    let mut prep = Preparation::new(name, source, md, tools);
    if tx.send(Fed::Start(prep.start())).is_err() {
        return;
    }
    let send = |f: Fed| {
        if !opts.prep_delay.is_zero() {
            std::thread::sleep(opts.prep_delay);
        }
        tx.send(f).is_ok()
    };
    loop {
        let fed = match prep.next_item() {
            Ok(None) => {
                send(Fed::In(Input::Done));
                return;
            }
            Ok(Some(Prepared::Segment(s))) => match Entry::new(&s, lim) {
                Ok(Some(e)) => Fed::In(Input::Motion(e)),
                Ok(None) => continue,
                Err(axis) => Fed::Alarm(Alarm {
                    code: crate::AlarmCode::UnknownAddress,
                    program: name.to_string(),
                    line: s.source.line,
                    col: s.source.col,
                    block: s.source.number.map(|n| n.to_string()),
                    message: format!(
                        "the path moves axis {} which has no machine data",
                        crate::frontend::block::AXIS_NAMES[axis]
                    ),
                }),
            },
            Ok(Some(Prepared::Aux(a))) => Fed::In(Input::Aux(a)),
            Ok(Some(Prepared::Stop(s))) => Fed::In(Input::Stop(s)),
            Ok(Some(Prepared::End(s))) => Fed::In(Input::End(s)),
            Ok(Some(Prepared::Warning(w))) => Fed::Warning(w),
            Err(a) => Fed::Alarm(a),
        };
        let last = matches!(fed, Fed::Alarm(_) | Fed::In(Input::End(_)));
        if !send(fed) || last {
            if last {
                send(Fed::In(Input::Done));
            }
            return;
        }
    }
}

fn ipo_loop(
    md: &MachineData,
    rx: &crossbeam::channel::Receiver<Fed>,
    opts: &Options,
    out: &mut dyn Write,
) -> std::io::Result<Summary> {
    // The machine stands where the program starts.
    let start = match rx.recv() {
        Ok(Fed::Start(p)) => p,
        _ => [0.0; 3],
    };
    let mut ch = Channel::new(md, start);
    ch.set_override(opts.override_);
    ch.set_single_block(opts.single_block);
    let mut sp = Setpoint::new(start);
    let mut summary = Summary::default();
    let mut pending: Option<Input> = None;
    let mut acks: std::collections::VecDeque<u64> = std::collections::VecDeque::new();
    let cycle_us = u64::from(md.ipo.cycle_us);
    let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
    writeln!(w, "cycle,time,X,Y,Z,v_path,block,events")?;
    let mut line = String::with_capacity(256);
    let mut started = false;
    let mut k: u64 = 0;
    loop {
        // Take what preparation has, up to the lookahead; wait for it (simulated time stands
        // still), so the result does not depend on the thread's speed.
        while !ch.input_done() {
            let input = match pending.take() {
                Some(i) => i,
                None => match rx.recv() {
                    Ok(Fed::In(i)) => i,
                    Ok(Fed::Start(_)) => continue,
                    Ok(Fed::Warning(a)) => {
                        summary.warnings.push(a);
                        continue;
                    }
                    Ok(Fed::Alarm(a)) => {
                        let source = crate::segment::Source {
                            number: None,
                            line: a.line,
                            col: a.col,
                            seq: 0,
                        };
                        let code = a.number();
                        summary.alarms.push(a);
                        Input::Alarm { code, source }
                    }
                    Err(_) => Input::Done,
                },
            };
            if matches!(input, Input::Motion(_)) {
                summary.segments += 1;
            }
            if !ch.can_take(&input) {
                pending = Some(input);
                break;
            }
            ch.take(input);
        }
        if !started {
            ch.start();
            started = true;
        }
        // The simulated operator and PLC act between cycles.
        while acks.front().is_some_and(|&due| due <= k) {
            acks.pop_front();
            ch.ack();
        }
        ch.cycle(k, &mut sp);
        for e in &sp.events {
            if let Event::Aux(_) = e {
                summary.aux += 1;
            }
        }
        let new_acks = ch.acks_due() as usize;
        while acks.len() < new_acks {
            acks.push_back(k + opts.ack_cycles.max(1));
        }
        summary.max_speed = summary.max_speed.max(sp.v_path * 60.0);
        write_row(&mut line, &sp, cycle_us);
        w.write_all(line.as_bytes())?;
        match sp.state {
            ChannelState::End => break,
            ChannelState::Stopped if summary.alarms.is_empty() => ch.start(),
            ChannelState::Stopped => break,
            _ => {}
        }
        k += 1;
        if k >= opts.max_cycles {
            summary.timed_out = true;
            break;
        }
    }
    w.flush()?;
    summary.cycles = k + 1;
    summary.end_state = Some(sp.state);
    Ok(summary)
}

/// One CSV row; numbers in the shortest form that reads back to the same bits.
fn write_row(line: &mut String, sp: &Setpoint, cycle_us: u64) {
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
    for x in sp.pos.iter().chain(std::iter::once(&(sp.v_path * 60.0))) {
        line.push(',');
        // -0.0 prints as 0: the same place.
        let x = if *x == 0.0 { 0.0 } else { *x };
        line.push_str(trim(buf.format(x)));
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
            Event::Aux(a) => {
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

/// ryu writes integers as "12.0": kept as they are (unambiguous, round-trips).
fn trim(s: &str) -> &str {
    s
}
