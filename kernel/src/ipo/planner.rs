//! Lookahead and interpolation.
//!
//! The planner holds up to `lookahead` prepared segments. Each segment's end speed is bounded
//! by the corner to the next one ([`AxisLimits::corner`]), by both segments' speeds, and by
//! what the rest of the queue still allows: a backward pass from the last queued segment,
//! which ends at rest because nothing is known after it. So the braking distance from the
//! current speed always lies inside the queued path: when preparation falls behind, the path
//! slows down under control and waits, instead of stopping dead.
//!
//! The segment that runs gets a jerk-limited [`profile`](super::profile) from the state it is
//! entered with to its end speed, with acceleration 0 at the end. Every IPO cycle samples the
//! profile; a segment that ends inside a cycle hands over to the next at the exact time
//! (C² along the path), unless it ends at rest: then the setpoint stays exactly on its end
//! point for at least one whole cycle before the next motion starts.
//!
//! An override change or an NC stop replans the running segment from the state of the last
//! setpoint at the next cycle. Nothing here allocates.

use super::limits::{AxisLimits, SegmentLimits};
use super::path::Piece;
use super::profile::{plan, reach, Profile};
use crate::frontend::block::{Additional, AxisMove, AxisPos, Pos};
use crate::segment::{Segment, Source};

/// Longest lookahead, in segments.
pub const MAX_LOOKAHEAD: usize = 128;

/// The speed a segment may run at: programmed feed times override, within the axes' cap
/// (a feed per revolution times the spindle's actual revolutions per second `rev_s`; a
/// thread at 100 %); rapid traverse at the cap, the override acting up to 100 %; 0 for the
/// segments an NC stop holds (numbered `stop_from` and after).
fn speed(e: &Entry, stop_from: u64, ovr: f64, rev_s: f64) -> f64 {
    if e.no >= stop_from {
        return 0.0;
    }
    match e.feed {
        Some(f) if e.thread => (f * rev_s).min(e.limits.v_cap),
        Some(f) if e.per_rev => (f * rev_s * ovr).min(e.limits.v_cap),
        Some(f) => (f * ovr).min(e.limits.v_cap),
        None => e.limits.v_cap * ovr.min(1.0),
    }
}

/// A change of the spindle's actual speed smaller than this share of it leaves a feed per
/// revolution planned as it is (no replanning every cycle of a ramp's last rev/min).
const SPINDLE_REPLAN_SHARE: f64 = 0.005;

/// A segment in the lookahead queue.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    pub piece: Piece,
    pub limits: SegmentLimits,
    /// Programmed path feed in mm/s (mm/rev when `per_rev`); `None` for rapid traverse.
    pub feed: Option<f64>,
    /// Feed per spindle revolution (G95).
    pub per_rev: bool,
    /// A thread cut: per revolution at 100 %; an NC stop waits for the thread's end.
    pub thread: bool,
    /// The path stops at its end: exact stop (G09, G60), or something waits there.
    pub stop_after: bool,
    /// Numbered in the order pushed, from 0.
    pub no: u64,
    end_cap: f64,
    end_max: f64,
}

impl Entry {
    /// `Ok(None)` for a segment without length; `Err(axis)` when it moves an axis without
    /// machine data. Computed where the segment is prepared, not in the IPO thread (it
    /// evaluates the arc's trigonometry).
    pub fn new(
        seg: &Segment,
        axes: Option<&AxisMove>,
        at: &Additional,
        lim: &AxisLimits,
    ) -> Result<Option<Entry>, usize> {
        let Some(piece) = Piece::with_axes(seg, axes, at) else {
            return Ok(None);
        };
        let limits = lim.segment(&piece)?;
        Ok(Some(Entry {
            piece,
            limits,
            feed: (!seg.rapid).then_some(if seg.per_rev {
                seg.feed
            } else {
                seg.feed / 60.0
            }),
            per_rev: seg.per_rev,
            thread: seg.thread,
            stop_after: seg.exact_stop,
            no: 0,
            end_cap: 0.0,
            end_max: 0.0,
        }))
    }
}

#[derive(Clone, Copy, Debug)]
struct Run {
    prof: Profile,
    /// Time (s) the profile starts, and the end speed it was planned to.
    t0: f64,
    w: f64,
}

impl Run {
    /// A plan to rest whose phases are done at `tau`.
    fn over(&self, tau: f64) -> bool {
        self.w == 0.0 && tau >= self.prof.duration()
    }

    /// Distance, speed and acceleration at `tau`. A plan to rest that is over stays on its
    /// end point, not on the cruise after it (whose speed is 0 only up to rounding, which
    /// would creep).
    fn at(&self, tau: f64) -> (f64, f64, f64) {
        if self.over(tau) {
            (self.prof.distance(), 0.0, 0.0)
        } else {
            self.prof.at(tau)
        }
    }
}

/// One IPO cycle's output of the planner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub pos: Pos,
    /// The additional axes.
    pub add: Additional,
    /// Path speed, mm/s.
    pub v: f64,
    /// The block the setpoint belongs to (the last one after the end).
    pub source: Option<Source>,
}

pub struct Planner {
    lim: AxisLimits,
    lookahead: usize,
    queue: heapless::Deque<Entry, MAX_LOOKAHEAD>,
    pushed: u64,
    override_: f64,
    /// The spindle's actual speed, rev/s, feeds per revolution are planned with, and the
    /// last one reported.
    rev_s: f64,
    rev_seen: f64,
    stopping: bool,
    /// The first segment an NC stop holds: the running one, or after the thread being cut
    /// (Fanuc: a feed hold during threading takes effect at the thread's end); `u64::MAX`
    /// while no stop is asked for.
    stop_from: u64,
    /// Read-in disable: no segment starts, the path comes to rest at the first segment end
    /// it can still reach.
    hold: bool,
    replan: bool,
    run: Option<Run>,
    /// Distance done on the front segment before the running profile started.
    offset: f64,
    /// Distance done on the front segment at the last setpoint.
    done: f64,
    /// Path state at the last setpoint (or at a hand-over).
    v: f64,
    a: f64,
    /// When a segment handed over without stopping: the time it ended.
    t_free: f64,
    /// At rest: the first cycle a new motion may start at.
    rest_cycle: u64,
    last_t: f64,
    pos: Pos,
    add: Additional,
    source: Option<Source>,
    /// The block of the segment finished last, and how many of its segments are finished.
    finished: Option<(u32, u32)>,
    last_role: crate::segment::Role,
    /// Segments that ended at speed with nothing after them (see [`Planner::dead_stops`]).
    dead_stops: u64,
}

/// Where the path is on the program (an NC stop's interruption point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    pub source: Source,
    pub role: crate::segment::Role,
    /// The segment's place among its block's segments with length, from 0.
    pub nth: u32,
    /// How far along the segment, 0 to 1, by its parametrisation.
    pub along: f64,
}

impl Planner {
    pub fn new(lim: AxisLimits, lookahead: usize, start: AxisPos) -> Self {
        Planner {
            lim,
            lookahead: lookahead.clamp(1, MAX_LOOKAHEAD),
            queue: heapless::Deque::new(),
            pushed: 0,
            override_: 1.0,
            rev_s: 0.0,
            rev_seen: 0.0,
            stopping: false,
            stop_from: u64::MAX,
            hold: false,
            replan: false,
            run: None,
            offset: 0.0,
            done: 0.0,
            v: 0.0,
            a: 0.0,
            t_free: 0.0,
            rest_cycle: 0,
            last_t: 0.0,
            pos: start.geo,
            add: start.add,
            source: None,
            finished: None,
            last_role: crate::segment::Role::Uncompensated,
            dead_stops: 0,
        }
    }

    /// The running segment (or the next one to start, at 0), or the end of the last one
    /// when nothing is queued.
    pub fn progress(&self) -> Option<Progress> {
        let Some(f) = self.queue.front() else {
            let (seq, n) = self.finished?;
            let source = self.source?;
            return (source.seq == seq).then_some(Progress {
                source,
                role: self.last_role,
                nth: n.saturating_sub(1),
                along: 1.0,
            });
        };
        let seq = f.piece.seg.source.seq;
        Some(Progress {
            source: f.piece.seg.source,
            role: f.piece.seg.role,
            nth: self
                .finished
                .map_or(0, |(s, n)| if s == seq { n } else { 0 }),
            along: if f.piece.len > 0.0 {
                (self.done / f.piece.len).clamp(0.0, 1.0)
            } else {
                0.0
            },
        })
    }

    /// How often the path ended at speed because the last queued segment could not brake
    /// to rest on its length: a step in speed at the drives. The lookahead is built so that
    /// this never happens; tests hold it to 0.
    pub fn dead_stops(&self) -> u64 {
        self.dead_stops
    }

    /// Segments that can still be queued.
    pub fn room(&self) -> usize {
        self.lookahead.saturating_sub(self.queue.len())
    }

    /// Segments pushed so far: the number the next one gets.
    pub fn pushed(&self) -> u64 {
        self.pushed
    }

    /// Nothing queued and the path at rest.
    pub fn idle(&self) -> bool {
        self.queue.is_empty() && self.run.is_none()
    }

    /// X at the end of the running segment if it is a rapid move (constant surface speed
    /// takes its end point's speed, docs/spindle.md).
    pub fn rapid_end_x(&self) -> Option<f64> {
        self.run?;
        self.queue
            .front()
            .filter(|e| e.feed.is_none())
            .map(|e| e.piece.seg.to[0])
    }

    /// The path stands still (between segments or stopped on one).
    pub fn at_rest(&self) -> bool {
        self.v == 0.0
    }

    pub fn position(&self) -> Pos {
        self.pos
    }

    /// Every path axis at the last setpoint.
    pub fn axis_position(&self) -> AxisPos {
        AxisPos {
            geo: self.pos,
            add: self.add,
        }
    }

    /// Queues a segment (the caller keeps to [`room`](Self::room)).
    pub fn push(&mut self, mut e: Entry) {
        if self.queue.len() >= self.lookahead {
            return;
        }
        if let Some(last) = self.queue.back() {
            let c = self.end_cap(last, &e);
            if let Some(last) = self.queue.back_mut() {
                last.end_cap = c;
            }
        }
        e.no = self.pushed;
        // A thread that continues the thread an NC stop waits for is cut with it.
        if e.thread && self.stopping && e.no == self.stop_from && e.no > 0 {
            let after_thread = self.queue.back().is_some_and(|b| b.thread);
            if after_thread {
                self.stop_from += 1;
            }
        }
        e.end_cap = 0.0;
        e.end_max = 0.0;
        self.pushed += 1;
        let _ = self.queue.push_back(e);
        self.backward(false);
    }

    /// The path must come to rest at the end of the last queued segment (something waits
    /// at the next S point). With nothing queued it is at rest there already.
    pub fn stop_after_last(&mut self) {
        if let Some(last) = self.queue.back_mut() {
            last.stop_after = true;
            last.end_cap = 0.0;
            self.backward(true);
        }
    }

    /// Stops at the end of every queued segment from now on (single block); a thread goes
    /// on into the segment after it.
    pub fn stop_after_each(&mut self) {
        for e in self.queue.iter_mut().filter(|e| !e.thread) {
            e.stop_after = true;
            e.end_cap = 0.0;
        }
        self.backward(true);
    }

    /// Read-in disable on: no further segment starts, and every queued segment end becomes
    /// a place to stop, so the path rests at the first end it can still reach without
    /// leaving its limits. Off: the corners are what they were, and the path goes on.
    pub fn set_hold(&mut self, on: bool) {
        if on == self.hold {
            return;
        }
        self.hold = on;
        if on {
            for e in self.queue.iter_mut() {
                e.end_cap = 0.0;
            }
        } else {
            let mut caps: heapless::Vec<f64, MAX_LOOKAHEAD> = heapless::Vec::new();
            let mut prev: Option<&Entry> = None;
            for e in self.queue.iter() {
                if let Some(a) = prev {
                    let _ = caps.push(self.end_cap(a, e));
                }
                prev = Some(e);
            }
            for (e, c) in self.queue.iter_mut().zip(caps) {
                e.end_cap = c;
            }
        }
        self.backward(true);
        self.replan = true;
    }

    /// The speed allowed where `a` hands over to `b`: 0 where the path must rest there.
    fn end_cap(&self, a: &Entry, b: &Entry) -> f64 {
        if a.stop_after || self.hold {
            0.0
        } else {
            self.lim.corner(&a.piece, &b.piece)
        }
    }

    /// Path override, 0–1.2 (0–120 %); takes effect at the next cycle.
    pub fn set_override(&mut self, f: f64) {
        let f = if f.is_finite() {
            f.clamp(0.0, 1.2)
        } else {
            0.0
        };
        if f != self.override_ {
            self.override_ = f;
            self.backward(true);
            self.replan = true;
        }
    }

    /// The spindle's actual speed (rev/min, either sign) for feeds per revolution: taken
    /// when it differs from the one the queue was planned with by more than
    /// [`SPINDLE_REPLAN_SHARE`], reaches 0, or holds still (the end of a ramp); then the queue
    /// is replanned from the next cycle if it holds such a feed.
    pub fn set_spindle_speed(&mut self, rpm: f64) {
        let r = if rpm.is_finite() {
            rpm.abs() / 60.0
        } else {
            0.0
        };
        let steady = r == self.rev_seen;
        self.rev_seen = r;
        let big = (r - self.rev_s).abs() > SPINDLE_REPLAN_SHARE * r.max(self.rev_s);
        if r == self.rev_s || !(big || steady || r == 0.0) {
            return;
        }
        self.rev_s = r;
        if self.queue.iter().any(|e| e.per_rev) {
            self.backward(true);
            self.replan = true;
        }
    }

    /// NC stop: brake on the path, from the next cycle; during a thread cut, at the end of
    /// the thread (its last consecutive thread segment).
    pub fn stop(&mut self) {
        if !self.stopping {
            self.stopping = true;
            self.stop_from = self.thread_end();
            self.backward(true);
            self.replan = true;
        }
    }

    pub fn is_stopping(&self) -> bool {
        self.stopping
    }

    /// The number of the first segment after the thread being cut, or of the running
    /// segment when it is no thread (or nothing runs).
    fn thread_end(&self) -> u64 {
        let Some(front) = self.queue.front() else {
            return 0;
        };
        if self.run.is_none() || !front.thread {
            return front.no;
        }
        self.queue
            .iter()
            .find(|e| !e.thread)
            .map_or(self.pushed, |e| e.no)
    }

    /// After an NC stop: go on.
    pub fn resume(&mut self) {
        if self.stopping {
            self.stopping = false;
            self.stop_from = u64::MAX;
            self.backward(true);
            self.replan = true;
        }
    }

    /// Moves the idle planner to `pos` (nothing queued: the position of a fresh channel).
    pub fn set_position(&mut self, pos: AxisPos) {
        if self.idle() {
            self.pos = pos.geo;
            self.add = pos.add;
        }
    }

    /// Drops what is queued; the position stays (channel reset).
    pub fn clear(&mut self) {
        self.queue.clear();
        self.run = None;
        self.offset = 0.0;
        self.done = 0.0;
        self.v = 0.0;
        self.a = 0.0;
        self.stopping = false;
        self.stop_from = u64::MAX;
        self.replan = false;
        self.finished = None;
    }

    /// The speed the segment may run at now.
    fn vmax(&self, e: &Entry) -> f64 {
        speed(e, self.stop_from, self.override_, self.rev_s)
    }

    /// The highest speed at each segment's end from which the rest of the queue can still be
    /// done, from the back; on a push only the tail can change (`full` after an override).
    fn backward(&mut self, full: bool) {
        let (stop_from, ovr, rev_s) = (self.stop_from, self.override_, self.rev_s);
        let n = self.queue.len();
        // (start speed the next segment allows, its own cap)
        let mut next: Option<(f64, f64)> = None;
        let (a, b) = self.queue.as_mut_slices();
        for (k, e) in b.iter_mut().rev().chain(a.iter_mut().rev()).enumerate() {
            let i = n - 1 - k;
            let own = speed(e, stop_from, ovr, rev_s);
            let end = match next {
                None => 0.0,
                Some((start_next, cap_next)) => e.end_cap.min(own).min(cap_next).min(start_next),
            };
            if !full && i + 2 < n && end == e.end_max {
                break;
            }
            e.end_max = end;
            next = Some((reach(end, e.piece.len, e.limits.dynamics), own));
        }
    }

    /// The setpoint of cycle `k` (time k·T). `gate(no, at_rest)` is asked before segment
    /// `no` starts; at rest it may hold the start (false), in a running hand-over its answer
    /// is ignored (whatever waits there made the segment before stop).
    pub fn cycle(&mut self, k: u64, gate: &mut impl FnMut(u64, bool) -> bool) -> Sample {
        let t = k as f64 * self.lim.cycle();
        if std::mem::take(&mut self.replan) {
            self.replan_at(self.last_t);
        }
        loop {
            if self.run.is_none() {
                let Some(front) = self.queue.front() else {
                    break;
                };
                let at_rest = self.v == 0.0;
                let t0 = if at_rest {
                    if k < self.rest_cycle || self.hold || !gate(front.no, true) {
                        break;
                    }
                    t
                } else {
                    gate(front.no, false);
                    self.t_free
                };
                let (prof, w) = plan(
                    self.v,
                    self.a,
                    front.piece.len - self.offset,
                    self.vmax(front),
                    front.end_max,
                    front.limits.dynamics,
                );
                self.run = Some(Run { prof, t0, w });
            }
            // Borrowed, not copied: this runs every cycle.
            let (Some(run), Some(front)) = (self.run.as_ref(), self.queue.front()) else {
                break;
            };
            let rem = front.piece.len - self.offset;
            let tau = t - run.t0;
            let over = run.over(tau);
            let (s, v, a) = run.at(tau);
            // A plan that ends at rest on the end point is done when its phases are; one
            // that ends at rest before it (NC stop, override 0) stays.
            let ends_here = over && run.prof.distance() >= rem - 1e-9 * rem.max(1.0);
            if s < rem && !ends_here {
                self.done = self.offset + s;
                let p = front.piece.axes_at(self.done);
                (self.pos, self.add) = (p.geo, p.add);
                // A plan that ended at rest short of the end (NC stop): exactly at rest.
                self.v = if v > 0.0 && !over { v } else { 0.0 };
                self.a = if over { 0.0 } else { a };
                self.source = Some(front.piece.seg.source);
                break;
            }
            // The segment ends inside this cycle.
            let te = if ends_here {
                run.prof.duration()
            } else {
                run.prof.time_at(rem).unwrap_or(tau)
            };
            let (_, ve, ae) = run.prof.at(te);
            let (t0, w) = (run.t0, run.w);
            self.pos = front.piece.seg.to;
            self.add = front.piece.add_to;
            self.source = Some(front.piece.seg.source);
            let seq = front.piece.seg.source.seq;
            self.last_role = front.piece.seg.role;
            self.finished = Some(match self.finished {
                Some((s, n)) if s == seq => (s, n + 1),
                _ => (seq, 1),
            });
            self.queue.pop_front();
            self.run = None;
            self.offset = 0.0;
            self.done = 0.0;
            // Nothing follows a segment planned to hand over at speed only where the plan
            // could not brake in time: the path ends here all the same, so it is at rest
            // (a path speed is never shown without motion), counted as a dead stop.
            if w != 0.0 && self.queue.is_empty() {
                self.dead_stops += 1;
            }
            if w == 0.0 || self.queue.is_empty() {
                self.v = 0.0;
                self.a = 0.0;
                // This cycle is the first on the end point; the next motion starts with the
                // next one, whose setpoint is the same point: one whole cycle at rest.
                self.rest_cycle = k + 1;
            } else {
                self.v = ve;
                self.a = ae;
                self.t_free = t0 + te;
            }
        }
        self.last_t = t;
        Sample {
            pos: self.pos,
            add: self.add,
            v: self.v,
            source: self.source,
        }
    }

    /// A new profile for the running segment from the state of the setpoint at `t`.
    fn replan_at(&mut self, t: f64) {
        let Some(run) = self.run else {
            return;
        };
        let Some(front) = self.queue.front() else {
            return;
        };
        // As the cycle sees it: a plan to rest that is over stands on its end point.
        let (s, v, a) = run.at(t - run.t0);
        let rem = front.piece.len - self.offset;
        if s >= rem {
            return;
        }
        self.offset += s;
        let v = v.max(0.0);
        let (prof, w) = plan(
            v,
            a,
            front.piece.len - self.offset,
            self.vmax(front),
            front.end_max,
            front.limits.dynamics,
        );
        self.run = Some(Run { prof, t0: t, w });
        self.v = v;
        self.a = a;
    }
}
