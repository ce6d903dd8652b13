//! The preparation thread and its hand-over to the IPO side.
//!
//! ```text
//!  preparation thread                         IPO thread (cyclic, SCHED_FIFO)
//!  Preparation::next_item ─► Entry::new ─► [ ArrayQueue<Input> ] ─► Channel::cycle ─► Setpoint
//!        │ (may allocate)          bounded, lock-free        (no allocation, no lock, never
//!        └─► reports (alarms, warnings, for the user)          blocks: takes what is there)
//! ```
//!
//! The queue is a fixed-capacity lock-free array queue: pushing and popping are a few atomic
//! operations, neither side ever waits for a lock held by the other. The preparation thread
//! waits (sleeping briefly) while the queue is full; the IPO thread only takes what is there
//! and, when preparation falls behind, the lookahead's braking (planner.rs) slows the path.
//! Alarms and warnings carry text, so they go to the reporting side on their own channel:
//! the IPO thread gets only their number and block, and never frees memory.

use crate::alarm::Alarm;
pub use crate::checker::Gated;
use crate::ipo::Input;
use crate::ipo::{AxisLimits, Entry};
use crate::prep::{Preparation, Prepared, WholeMode};
use crate::{MachineData, ToolTable};
use crossbeam::channel::Sender;
use crossbeam::queue::ArrayQueue;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::time::Duration;

/// Records the queue holds between the threads.
pub const QUEUE: usize = 256;

/// What preparation tells the user.
#[derive(Clone, Debug)]
pub enum Report {
    Warning(Alarm),
    Alarm(Alarm),
    /// The kept macro variables (#500 …) at the end of the program's preparation, to save
    /// (docs/fanuc.md).
    KeptVariables(Vec<(u32, f64)>),
}

/// The two threads' shared state.
pub struct Handover {
    pub queue: ArrayQueue<Input>,
    /// Set by the preparation thread when it has pushed its last record (or gave up).
    pub finished: AtomicBool,
    /// Set (before `finished`) when the preparation thread failed instead of finishing the
    /// program: what it pushed is followed by alarm 1011, not by the program's end.
    pub failed: AtomicBool,
    /// Set by the consumer to make the preparation thread stop early.
    pub cancel: AtomicBool,
    /// Line of the last record prepared: where a failed preparation stopped.
    line: AtomicU32,
}

impl Default for Handover {
    fn default() -> Self {
        Handover {
            queue: ArrayQueue::new(QUEUE),
            finished: AtomicBool::new(false),
            failed: AtomicBool::new(false),
            cancel: AtomicBool::new(false),
            line: AtomicU32::new(0),
        }
    }
}

impl Handover {
    /// The next record; once the preparation thread has ended and everything it pushed is
    /// taken, `Input::Done` (or alarm 1011 if it failed); `None` while it is still at work.
    pub fn pop(&self) -> Option<Input> {
        self.queue.pop().or_else(|| {
            if !(self.finished.load(Ordering::Acquire) && self.queue.is_empty()) {
                return None;
            }
            if !self.failed.load(Ordering::Acquire) {
                return Some(Input::Done);
            }
            Some(Input::Alarm {
                code: crate::AlarmCode::PreparationFailed.number(),
                source: crate::segment::Source {
                    number: None,
                    line: self.line().max(1),
                    col: 1,
                    seq: 0,
                    program: 0,
                },
            })
        })
    }

    /// Line of the last record prepared (0: none yet).
    pub fn line(&self) -> u32 {
        self.line.load(Ordering::Relaxed)
    }
}

/// Runs the preparation thread's `work`. However it ends, the hand-over is marked finished,
/// so a waiting consumer never waits for ever; a panic (an internal error) is reported as
/// alarm 1011 and marks it failed, so the channel stops with the alarm instead of taking the
/// prepared part for the whole program.
fn guarded(hand: &Handover, name: &str, reports: &Sender<Report>, work: impl FnOnce()) {
    if let Err(panic) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        let _ = reports.send(Report::Alarm(Alarm {
            code: crate::AlarmCode::PreparationFailed,
            program: name.to_string(),
            line: hand.line().max(1),
            col: 1,
            block: None,
            message: format!(
                "block preparation failed after this line (internal error: {what}); the path stops where the prepared part ends"
            ),
        }));
        hand.failed.store(true, Ordering::Release);
    }
    hand.finished.store(true, Ordering::Release);
}

/// What the preparation thread prepares.
#[derive(Clone, Copy)]
pub struct Job<'a> {
    pub name: &'a str,
    pub source: &'a str,
    pub md: &'a MachineData,
    pub tools: &'a ToolTable,
    /// Where the axes stand before the first block (`None`: the machine zero).
    pub at: Option<crate::frontend::block::AxisPos>,
}

/// Stack for the preparation thread: `Preparation` keeps its queues in place (no heap), and
/// unoptimised builds copy it around.
const PREP_STACK: usize = 32 << 20;

/// Records from preparation as the channel takes them: each segment with the additional
/// axes' move that came before it, or with them standing where the last move left them.
struct ToInput<'l> {
    lim: &'l AxisLimits,
    axes: Option<crate::frontend::block::AxisMove>,
    here: crate::frontend::block::Additional,
}

impl<'l> ToInput<'l> {
    fn new(lim: &'l AxisLimits, start: &crate::frontend::block::AxisPos) -> Self {
        ToInput {
            lim,
            axes: None,
            here: start.add,
        }
    }

    /// One record; `None` for what the channel does not see (a segment without length, a
    /// warning, the axes' move it takes with the next segment). Alarms and warnings go to
    /// `report` with their text; the channel gets the alarm's number and place.
    fn take(
        &mut self,
        item: Result<Prepared, Alarm>,
        name: &str,
        report: &mut dyn FnMut(Report),
    ) -> Option<Input> {
        match item {
            Ok(Prepared::Segment(s)) => {
                let axes = self.axes.take();
                let e = Entry::new(&s, axes.as_ref(), &self.here, self.lim);
                if let Some(m) = axes {
                    self.here = m.to;
                }
                match e {
                    Ok(e) => e.map(Input::Motion),
                    Err(axis) => path_alarm(unknown_axis(name, &s.source, axis), report),
                }
            }
            Ok(Prepared::Axes(m, _)) => {
                self.axes = Some(m);
                None
            }
            Ok(Prepared::Aux(a)) => Some(Input::Aux(a)),
            Ok(Prepared::Stop(s)) => Some(Input::Stop(s)),
            Ok(Prepared::End(s)) => Some(Input::End(s)),
            Ok(Prepared::Warning(w)) => {
                report(Report::Warning(w));
                None
            }
            Err(a) => path_alarm(a, report),
        }
    }
}

fn unknown_axis(name: &str, at: &crate::segment::Source, axis: usize) -> Alarm {
    Alarm::at(
        crate::AlarmCode::UnknownAddress,
        name,
        at,
        format!(
            "the path moves axis {} which has no machine data",
            crate::frontend::block::AXIS_NAMES[axis]
        ),
    )
}

/// An alarm to the user with its text, and to the channel as its number and place.
fn path_alarm(a: Alarm, report: &mut dyn FnMut(Report)) -> Option<Input> {
    let i = Input::Alarm {
        code: a.number(),
        source: crate::segment::Source {
            number: None,
            line: a.line,
            col: a.col,
            seq: 0,
            program: 0,
        },
    };
    report(Report::Alarm(a));
    Some(i)
}

/// The preparation thread's work: the start position to `start` first, then every record,
/// ready for the channel, into the queue in program order; `Input::Done` last (the caller's
/// [`guarded`] marks the hand-over finished). `delay` slows it down (a test hook).
fn prepare_into(
    job: Job<'_>,
    start: &crossbeam::channel::Sender<crate::frontend::block::AxisPos>,
    lim: &AxisLimits,
    hand: &Handover,
    reports: &crossbeam::channel::Sender<Report>,
    delay: Duration,
) {
    let path = Gated::of_job_checked(job);
    let _ = start.send(path.start());
    feed(path, job.name, lim, hand, reports, delay);
}

/// Pushes every record of `path`, ready for the channel, into the queue in program order;
/// `Input::Done` last.
fn feed(
    mut path: Gated<'_>,
    name: &str,
    lim: &AxisLimits,
    hand: &Handover,
    reports: &crossbeam::channel::Sender<Report>,
    delay: Duration,
) {
    let push = |mut x: Input| -> bool {
        if !delay.is_zero() {
            std::thread::sleep(delay);
        }
        loop {
            match hand.queue.push(x) {
                Ok(()) => return true,
                Err(back) => {
                    if hand.cancel.load(Ordering::Relaxed) {
                        return false;
                    }
                    x = back;
                    // Full: 256 records are at least 256 cycles of path. Napping 2 ms instead
                    // cost the IPO thread's wake-up p99 20–80 µs on a 2-core VM (measured).
                    std::thread::sleep(Duration::from_millis(20));
                }
            }
        }
    };
    let mut report = |r: Report| {
        let _ = reports.send(r);
    };
    let mut to_input = ToInput::new(lim, &path.start());
    while let Some(item) = path.next_item() {
        if let Ok(p) = &item {
            hand.line.store(p.line(), Ordering::Relaxed);
        }
        let Some(input) = to_input.take(item, name, &mut report) else {
            continue;
        };
        let last = matches!(input, Input::Alarm { .. } | Input::End(_));
        if !push(input) || last {
            break;
        }
    }
    // What the program wrote is kept, up to an alarm too (as the control keeps it).
    if let Some(k) = path.kept_variables() {
        report(Report::KeptVariables(k));
    }
    push(Input::Done);
}

/// Runs `consumer` beside a preparation thread working on `job`. The consumer gets the
/// program's start position and the hand-over; when it returns, the preparation thread is
/// told to stop and joined. Returns the consumer's result and preparation's reports.
pub fn with_preparation<R>(
    job: Job<'_>,
    delay: Duration,
    consumer: impl FnOnce(crate::frontend::block::AxisPos, &Handover) -> R,
) -> std::io::Result<(R, Vec<Report>)> {
    let lim = AxisLimits::new(job.md);
    let hand = Handover::default();
    let (report_tx, report_rx) = crossbeam::channel::unbounded();
    let (start_tx, start_rx) = crossbeam::channel::bounded(1);
    let r = std::thread::scope(|scope| {
        let (hand, lim) = (&hand, &lim);
        let prep = std::thread::Builder::new()
            .name("preparation".into())
            .stack_size(PREP_STACK)
            .spawn_scoped(scope, move || {
                guarded(hand, job.name, &report_tx, || {
                    prepare_into(job, &start_tx, lim, hand, &report_tx, delay)
                });
            })?;
        // The machine stands where the program starts.
        let start = start_rx.recv().unwrap_or_default();
        let r = consumer(start, hand);
        hand.cancel.store(true, Ordering::Relaxed);
        let _ = prep.join();
        Ok::<R, std::io::Error>(r)
    })?;
    Ok((r, report_rx.try_iter().collect()))
}

/// A preparation thread that owns its program and prepares it as [`with_preparation`] does
/// (no refusal at load: an alarm stops the channel where the path gets to it): for a
/// simulation stepped from outside, cycle by cycle.
pub fn spawn_simulation(
    name: String,
    source: String,
    md: MachineData,
    tools: ToolTable,
    delay: Duration,
) -> std::io::Result<Spawned> {
    let (start_tx, start_rx) = crossbeam::channel::bounded(1);
    let (hand, reports, thread) = spawn_owned(name.clone(), move |hand, reports| {
        let lim = AxisLimits::new(&md);
        let job = Job {
            name: &name,
            source: &source,
            md: &md,
            tools: &tools,
            at: None,
        };
        prepare_into(job, &start_tx, &lim, hand, reports, delay);
    })?;
    // The machine stands where the program starts.
    let start = start_rx.recv().unwrap_or_default();
    Ok(Spawned {
        hand,
        start,
        reports,
        thread,
    })
}

/// A preparation thread that owns its program: for a kernel process that loads programs
/// while it runs.
pub struct Spawned {
    pub hand: std::sync::Arc<Handover>,
    /// Where the program starts.
    pub start: crate::frontend::block::AxisPos,
    /// Alarms and warnings with their text, as preparation finds them.
    pub reports: crossbeam::channel::Receiver<Report>,
    pub thread: std::thread::JoinHandle<()>,
}

/// A preparation thread of its own for program `name`, with its hand-over and report
/// channel; `work` fills them (see [`guarded`] for how the thread may end).
fn spawn_owned(
    name: String,
    work: impl FnOnce(&Handover, &crossbeam::channel::Sender<Report>) + Send + 'static,
) -> std::io::Result<(
    std::sync::Arc<Handover>,
    crossbeam::channel::Receiver<Report>,
    std::thread::JoinHandle<()>,
)> {
    let hand = std::sync::Arc::new(Handover::default());
    let (report_tx, reports) = crossbeam::channel::unbounded();
    let h = hand.clone();
    let thread = std::thread::Builder::new()
        .name("preparation".into())
        .stack_size(PREP_STACK)
        .spawn(move || guarded(&h, &name, &report_tx, || work(&h, &report_tx)))?;
    Ok((hand, reports, thread))
}

/// Starts preparing `source` in a thread of its own; it ends at the program's end or when
/// the hand-over is cancelled. With the whole-program check on, the program is checked up to
/// `trc.check_at_load_blocks` blocks first: `Ok(Err(alarm))` for a violation there (the
/// load is refused, nothing was queued); further on the check runs ahead of the path.
pub fn spawn_preparation(
    name: String,
    source: String,
    md: MachineData,
    tools: ToolTable,
    at: Option<crate::frontend::block::AxisPos>,
) -> std::io::Result<Result<Spawned, Alarm>> {
    let (ready_tx, ready_rx) = crossbeam::channel::bounded(1);
    let (hand, reports, thread) = spawn_owned(name.clone(), move |hand, reports| {
        let lim = AxisLimits::new(&md);
        let job = Job {
            name: &name,
            source: &source,
            md: &md,
            tools: &tools,
            at,
        };
        let path = Gated::of_job_checked(job);
        if let Some(a) = path.refusal() {
            let _ = ready_tx.send(Err(a.clone()));
            return;
        }
        let _ = ready_tx.send(Ok(path.start()));
        feed(path, &name, &lim, hand, reports, Duration::ZERO);
    })?;
    Ok(answer(ready_rx.recv(), hand, reports, thread))
}

/// What a spawned preparation thread answered: its program ready at a start position, or
/// the alarm that refused it (the thread joined then).
fn answer(
    ready: Result<Result<crate::frontend::block::AxisPos, Alarm>, crossbeam::channel::RecvError>,
    hand: std::sync::Arc<Handover>,
    reports: crossbeam::channel::Receiver<Report>,
    thread: std::thread::JoinHandle<()>,
) -> Result<Spawned, Alarm> {
    match ready {
        Ok(Ok(start)) => Ok(Spawned {
            hand,
            start,
            reports,
            thread,
        }),
        Ok(Err(a)) => {
            let _ = thread.join();
            Err(a)
        }
        // The thread ended without an answer (an internal error): its report says why.
        Err(_) => {
            let _ = thread.join();
            let why = reports.try_iter().find_map(|r| match r {
                Report::Alarm(a) => Some(a),
                Report::Warning(_) | Report::KeptVariables(_) => None,
            });
            Err(why.unwrap_or_else(|| Alarm {
                code: crate::AlarmCode::PreparationFailed,
                program: String::new(),
                line: 1,
                col: 1,
                block: None,
                message: "block preparation ended without an answer".into(),
            }))
        }
    }
}

/// The rest of a program after an offset change in NC stop (prep/resume.rs), prepared in a
/// thread of its own: the reposition move from `axes` first. The rest is prepared to its
/// end once before (the program's alarms checked with the new offsets): `Ok(Err(alarm))`
/// when it cannot go on with them (a contour violation, say), and nothing was queued.
#[allow(clippy::too_many_arguments)]
pub fn spawn_resume(
    name: String,
    source: String,
    md: MachineData,
    tools: ToolTable,
    start: Option<crate::frontend::block::AxisPos>,
    at: crate::prep::Interruption,
    axes: crate::frontend::block::AxisPos,
) -> std::io::Result<Result<Spawned, Alarm>> {
    let (ready_tx, ready_rx) = crossbeam::channel::bounded(1);
    let (hand, reports, thread) = spawn_owned(name.clone(), move |hand, reports| {
        let lim = AxisLimits::new(&md);
        let resume = || Preparation::resume(&name, &source, &md, &tools, start, at, axes);
        // The whole rest is checked first: a violation anywhere after the interruption
        // refuses the start before anything moves, not when the path gets there.
        let check = || -> Result<(), Alarm> {
            let r = resume()?;
            let mut rest = if md.trc.whole_program_check {
                r.rest.checking_whole(WholeMode::Stop)
            } else {
                r.rest
            };
            while rest.next_item()?.is_some() {}
            Ok(())
        };
        match check().and_then(|()| resume()) {
            Ok(r) => {
                let _ = ready_tx.send(Ok(axes));
                // The whole rest was checked above, with the whole-program check.
                let path = Gated::new(r.rest, r.first, None);
                feed(path, &name, &lim, hand, reports, Duration::ZERO);
            }
            Err(a) => {
                let _ = ready_tx.send(Err(a));
            }
        }
    })?;
    Ok(answer(ready_rx.recv(), hand, reports, thread))
}

/// The whole program as the channel takes it, prepared in this thread (tests, benchmarks):
/// the start position and the records, `Input::Done` last; alarms and warnings are dropped
/// into the reports.
pub fn prepare_all(job: Job<'_>) -> (crate::frontend::block::AxisPos, Vec<Input>, Vec<Report>) {
    let lim = AxisLimits::new(job.md);
    let mut path = Gated::of_job_checked(job);
    let start = path.start();
    let (mut inputs, mut reports) = (Vec::new(), Vec::new());
    let mut to_input = ToInput::new(&lim, &start);
    while let Some(item) = path.next_item() {
        let failed = item.is_err();
        if let Some(i) = to_input.take(item, job.name, &mut |r| reports.push(r)) {
            inputs.push(i);
        }
        if failed {
            break;
        }
    }
    inputs.push(Input::Done);
    (start, inputs, reports)
}
