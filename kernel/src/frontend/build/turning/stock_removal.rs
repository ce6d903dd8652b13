//! Stock removal in turning, type I (Fanuc 0i-TF, "Stock removal in turning (G71)"), and
//! the finishing cycle's run along the shape (G70). In (X radius, Z):
//!
//! ```text
//!   A (start) ──────────────── the passes begin at A's Z, Δd apart in X:
//!   │  ← feed along Z to the shape (offset by Δu/2, Δw), retract e at 45°,
//!   │    rapid back to A's Z, in by Δd for the next pass
//!   A' (first point of the shape) … B (last point, block Q)
//! ```
//!
//! After the last pass the tool runs along the offset shape from A' to B at the roughing
//! feed and returns to A at rapid (X first, then Z). Type I needs a shape monotonic in X
//! and in Z (pockets are type II).
//!
//! Stock removal in facing (G72) is the same cycle with X and Z exchanged: the caller
//! hands the start and the shape over [`exchange`]d and asks [`TurningRun::exchanged`];
//! the run exchanges every move back. Pattern repeating (G73) runs the whole shape again
//! and again, shifted towards it ([`Repeat`], [`TurningRun::repeating`]).

use super::super::super::block::*;
use super::super::expand::Step;
use super::contour::Element;

mod pockets;
pub use pockets::{deepest, z_turns};

/// Distances below this are equal (mm): the passes' levels, the monotony check.
pub const EPS: f64 = 1e-9;

/// The roughing passes of G71: depth of cut, retract, the directions (G72: of the frame
/// with X and Z exchanged, so "X" below is Z there).
#[derive(Clone, Copy, Debug)]
pub struct Passes {
    pub depth: f64,
    pub retract: f64,
    /// +1 when the passes go towards smaller X (outer turning), -1 inner.
    pub sx: f64,
    /// +1 when the cut goes towards larger Z, -1 towards the chuck.
    pub sz: f64,
    /// The in-feed at rapid (the shape's first block is G00) or at the feed (G01).
    pub rapid_in: bool,
    pub count: u32,
}

impl Passes {
    /// How many levels lie strictly between A and A' (the offset shape's first point): the
    /// pass on A' itself is the run along the shape.
    pub fn count(total: f64, depth: f64) -> f64 {
        libm::ceil((total - EPS) / depth) - 1.0
    }
}

/// G73's passes: the whole shape `count` times, the first shifted by `first`, the last by
/// `last` (the allowances), the ones between evenly in between; (X radius, Z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Repeat {
    pub first: [f64; 2],
    pub last: [f64; 2],
    pub count: u32,
}

impl Repeat {
    /// The shift of pass `j` (1 … count).
    pub fn shift(&self, j: u32) -> [f64; 2] {
        if self.count <= 1 {
            return self.last;
        }
        let t = (j - 1) as f64 / (self.count - 1) as f64;
        [0, 1].map(|i| self.first[i] + (self.last[i] - self.first[i]) * t)
    }
}

/// X and Z exchanged, so that G72's facing runs as G71's turning (an arc's sense turns
/// with it: see [`Element::exchanged`]).
pub fn exchange(mut p: Pos) -> Pos {
    p.swap(0, 2);
    p
}

impl Element {
    /// The element mirrored about the line X = Z: its points exchanged, an arc's sense
    /// reversed.
    pub fn exchanged(&self) -> Element {
        let mode = match self.mode {
            MotionMode::ArcCw => MotionMode::ArcCcw,
            MotionMode::ArcCcw => MotionMode::ArcCw,
            m => m,
        };
        Element {
            to: exchange(self.to),
            centre: exchange(self.centre),
            mode,
            ..*self
        }
    }

    /// The element moved by `d` (X radius, Z), its centre with it.
    pub fn shifted(&self, d: [f64; 2]) -> Element {
        let mv = |mut p: Pos| {
            p[0] += d[0];
            p[2] += d[1];
            p
        };
        Element {
            to: mv(self.to),
            centre: mv(self.centre),
            ..*self
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    Pass(u32),
    Shape(usize),
    Home,
    /// G73 (pass, element): that element of that pass; past the last element, the return
    /// to the start.
    Repeat(u32, usize),
    /// Type II (level, stretch): that stretch of stock at that level.
    Pocket(u32, u32),
    Done,
}

/// A turning cycle's moves still to come, streamed a few at a time.
#[derive(Clone, Debug)]
pub struct TurningRun {
    start: Pos,
    /// The shape (G71: offset by the allowances), its first element the move to A'.
    shape: Vec<Element>,
    passes: Option<Passes>,
    /// G70: the shape's F and S act.
    own_feeds: bool,
    /// G72: every point is handed over with X and Z exchanged, and goes out exchanged back.
    exchanged: bool,
    repeat: Option<Repeat>,
    /// G70: G40/G41/G42 of the shape, before the element of the index.
    compensation: Vec<(usize, TrcSide)>,
    phase: Phase,
    at: Pos,
    queue: heapless::Deque<Step, 8>,
}

impl TurningRun {
    pub fn new(start: Pos, shape: Vec<Element>, passes: Option<Passes>) -> Self {
        TurningRun {
            start,
            shape,
            own_feeds: passes.is_none(),
            phase: match passes {
                Some(p) if p.count > 0 => Phase::Pass(1),
                _ => Phase::Shape(0),
            },
            passes,
            exchanged: false,
            repeat: None,
            compensation: Vec::new(),
            at: start,
            queue: heapless::Deque::new(),
        }
    }

    /// G70: the shape's G40/G41/G42, each acting from the element of its index on (an index
    /// past the last element: from the return to the start point on).
    pub fn compensated(mut self, sides: Vec<(usize, TrcSide)>) -> Self {
        self.compensation = sides;
        self
    }

    /// G72: `start`, the shape and the passes were given with X and Z exchanged
    /// ([`exchange`], [`Element::exchanged`]); the moves come out in machine axes.
    pub fn exchanged(mut self) -> Self {
        self.exchanged = true;
        self
    }

    /// Type II (pockets): the passes cut every stretch of stock at each level, and the
    /// moved shape is run from the start point A. `passes.count` levels: see [`deepest`].
    pub fn pockets(mut self) -> Self {
        if self.passes.is_some_and(|p| p.count > 0) {
            self.phase = Phase::Pocket(1, 0);
        }
        self
    }

    /// G73: the shape (as programmed, from `start`) run `r.count` times, each pass shifted
    /// by [`Repeat::shift`] and followed by the return to the start at rapid; the cycle's
    /// F and S act, not the shape's.
    pub fn repeating(start: Pos, shape: Vec<Element>, r: Repeat) -> Self {
        let mut run = TurningRun::new(start, shape, None);
        run.own_feeds = false;
        run.repeat = Some(r);
        run.phase = Phase::Repeat(1, 0);
        run
    }

    pub fn next(&mut self) -> Option<Step> {
        if self.done() {
            None
        } else {
            self.queue.pop_front()
        }
    }

    /// No step is left (works out the next ones if it must).
    pub fn done(&mut self) -> bool {
        loop {
            if !self.queue.is_empty() {
                return false;
            }
            if self.phase == Phase::Done {
                return true;
            }
            self.refill();
        }
    }

    fn refill(&mut self) {
        match self.phase {
            Phase::Pass(k) => {
                let Some(p) = self.passes else {
                    self.phase = Phase::Shape(0);
                    return;
                };
                self.pass(&p, k);
                self.phase = if k < p.count {
                    Phase::Pass(k + 1)
                } else {
                    Phase::Shape(0)
                };
            }
            Phase::Shape(i) => {
                match self.shape.get(i).copied() {
                    Some(e) => self.element(e, i),
                    None => self.phase = Phase::Home,
                }
                if let Phase::Shape(i) = self.phase {
                    self.phase = Phase::Shape(i + 1);
                }
            }
            Phase::Home => {
                self.compensate(self.shape.len());
                self.home();
                self.phase = Phase::Done;
            }
            Phase::Repeat(j, i) => self.repeat_step(j, i),
            Phase::Pocket(k, i) => match self.passes {
                Some(p) => self.pocket_step(&p, k, i),
                None => self.phase = Phase::Shape(0),
            },
            Phase::Done => {}
        }
    }

    /// Back to the start at rapid: X (the depth axis) first, then Z.
    fn home(&mut self) {
        let mut over = self.at;
        over[0] = self.start[0];
        self.go(over, true, None);
        self.go(self.start, true, None);
    }

    /// G73: element `i` of pass `j`, or past the last element the return to the start.
    fn repeat_step(&mut self, j: u32, i: usize) {
        let Some(r) = self.repeat else {
            self.phase = Phase::Done;
            return;
        };
        match self.shape.get(i).copied() {
            Some(e) => {
                self.element(e.shifted(r.shift(j)), i);
                self.phase = Phase::Repeat(j, i + 1);
            }
            None => {
                self.home();
                self.phase = if j < r.count {
                    Phase::Repeat(j + 1, 0)
                } else {
                    Phase::Done
                };
            }
        }
    }

    /// Roughing pass `k`: in to its level, along Z to the shape, out at 45°, back to A's Z.
    fn pass(&mut self, p: &Passes, k: u32) {
        let level = self.start[0] - p.sx * k as f64 * p.depth;
        let z = crossing(&self.shape, level, p.sx);
        let mut to = self.start;
        to[0] = level;
        self.go(to, p.rapid_in, None);
        to[2] = z;
        self.go(to, false, None);
        to[0] += p.sx * p.retract;
        to[2] -= p.sz * p.retract;
        self.go(to, true, None);
        to[2] = self.start[2];
        self.go(to, true, None);
    }

    /// Element `i` of the shape; G70 sets its S and F, and its compensation.
    fn element(&mut self, e: Element, i: usize) {
        let first = i == 0;
        let feed = if self.own_feeds { e.feed } else { None };
        if let (true, Some(s)) = (self.own_feeds, e.speed) {
            self.push(Step::Speed(s));
        }
        self.compensate(i);
        match e.mode {
            MotionMode::ArcCw | MotionMode::ArcCcw => {
                self.push(Step::Arc {
                    to: e.to,
                    centre: e.centre,
                    ccw: e.mode == MotionMode::ArcCcw,
                    feed,
                });
                self.at = e.to;
            }
            m => {
                let rapid = m == MotionMode::Rapid || (first && self.rapid_in());
                if e.to != self.at {
                    self.push(Step::Path {
                        to: e.to,
                        rapid,
                        feed,
                    });
                    self.at = e.to;
                }
            }
        }
    }

    /// The compensation programmed before element `i` (G70; of several, the last): it goes
    /// with the next move.
    fn compensate(&mut self, i: usize) {
        let side = self.compensation.iter().rev().find(|c| c.0 == i);
        if let Some(&(_, side)) = side {
            self.push(Step::Compensation(side));
        }
    }

    fn rapid_in(&self) -> bool {
        self.passes.is_some_and(|p| p.rapid_in)
    }

    /// A move to `to`, left out if the tool is there.
    fn go(&mut self, to: Pos, rapid: bool, feed: Option<f64>) {
        if to != self.at {
            self.push(Step::Move {
                to,
                rapid,
                axes: None,
                feed,
            });
            self.at = to;
        }
    }

    fn push(&mut self, s: Step) {
        let s = if self.exchanged { exchanged(s) } else { s };
        // A refill pushes at most four steps into the empty queue of eight.
        let _ = self.queue.push_back(s);
    }
}

/// A step of the exchanged frame in machine axes.
fn exchanged(s: Step) -> Step {
    match s {
        Step::Move {
            to,
            rapid,
            axes,
            feed,
        } => Step::Move {
            to: exchange(to),
            rapid,
            axes,
            feed,
        },
        Step::Path { to, rapid, feed } => Step::Path {
            to: exchange(to),
            rapid,
            feed,
        },
        Step::Arc {
            to,
            centre,
            ccw,
            feed,
        } => Step::Arc {
            to: exchange(to),
            centre: exchange(centre),
            ccw: !ccw,
            feed,
        },
        other => other,
    }
}

/// Where the level X = `level` meets the shape first, walking from A' (the end of its first
/// element); past its end, the end's Z.
pub fn crossing(shape: &[Element], level: f64, sx: f64) -> f64 {
    let Some(first) = shape.first() else {
        return 0.0;
    };
    let mut p = first.to;
    for e in &shape[1..] {
        if sx * (e.to[0] - level) >= -EPS {
            return z_at(p, e, level);
        }
        p = e.to;
    }
    p[2]
}

/// Z of the element from `p` to `e.to` at X = `level` (the element spans the level).
fn z_at(p: Pos, e: &Element, level: f64) -> f64 {
    let q = e.to;
    match e.mode {
        MotionMode::ArcCw | MotionMode::ArcCcw => {
            let c = e.centre;
            let r2 = (p[0] - c[0]).powi(2) + (p[2] - c[2]).powi(2);
            let dz = libm::sqrt((r2 - (level - c[0]).powi(2)).max(0.0));
            let (lo, hi) = (p[2].min(q[2]), p[2].max(q[2]));
            let off = |z: f64| (lo - z).max(z - hi).max(0.0);
            let (a, b) = (c[2] + dz, c[2] - dz);
            if off(a) <= off(b) {
                a
            } else {
                b
            }
        }
        _ if (q[0] - p[0]).abs() < EPS => p[2],
        _ => p[2] + (level - p[0]) * (q[2] - p[2]) / (q[0] - p[0]),
    }
}

/// The first element that breaks type I's rule, with what it breaks: X must move back
/// towards the start (`sx`) and Z on in the cut's direction (`sz`), arcs included.
pub fn non_monotonic(shape: &[Element], sx: f64, sz: f64) -> Option<(usize, &'static str)> {
    let mut p = shape.first()?.to;
    for (i, e) in shape.iter().enumerate().skip(1) {
        let q = e.to;
        if sx * (q[0] - p[0]) < -EPS {
            return Some((i, "X turns back"));
        }
        if sz * (q[2] - p[2]) < -EPS {
            return Some((i, "Z turns back"));
        }
        if e.mode.is_arc() && arc_turns(p, e) {
            return Some((i, "the arc passes a turning point in X or Z"));
        }
        p = q;
    }
    None
}

/// The arc from `p` contains, strictly inside, a point where X or Z turns.
fn arc_turns(p: Pos, e: &Element) -> bool {
    use std::f64::consts::{FRAC_PI_2, TAU};
    let c = e.centre;
    // Angles in the Z-X plane (Z the abscissa): G03 counts them up.
    let angle = |q: Pos| libm::atan2(q[0] - c[0], q[2] - c[2]);
    let (a0, a1) = (angle(p), angle(e.to));
    let ccw = e.mode == MotionMode::ArcCcw;
    let from_start = |t: f64| {
        if ccw {
            (t - a0).rem_euclid(TAU)
        } else {
            (a0 - t).rem_euclid(TAU)
        }
    };
    let span = from_start(a1);
    (0..4).any(|k| {
        let d = from_start(k as f64 * FRAC_PI_2 - std::f64::consts::PI);
        d > 1e-9 && d < span - 1e-9
    })
}
