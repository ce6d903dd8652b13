//! Stock removal type II (Fanuc 0i-TF, "Stock removal in turning (G71)", type II: X and Z in
//! the shape's first block): the shape may go down and up in X (pockets), Z only one way.
//! The stock is what lies between the start's X and the boundary A → A' → … → B (the first
//! block's move included). Its rules where the manual is silent are softnc's
//! (docs/turning.md, "Type II"):
//!
//! - the levels go down one after the other, each cutting its stretches of stock in the
//!   cut's order (a stretch: where the boundary lies deeper than the level);
//! - the tool gets to a stretch above the stock already cut: up to the deepest level cut
//!   over the whole way there, less the retract e, along Z, then down to the level above
//!   the stretch at rapid and in by Δd at the feed;
//! - each stretch ends with G71's retract, e at 45° (kept inside the stretch);
//! - after the last level the tool goes back to A the same way and runs the moved shape
//!   from A.

use super::*;

/// Where an element of the boundary meets a level: the point and whether the boundary goes
/// into the stock there (deeper than the level) or out.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    at: Pos,
    down: bool,
}

/// An arc of the boundary as angles about its centre in the Z-X plane (Z the abscissa,
/// G03 counting up, as `arc_turns`).
struct Sweep {
    c: Pos,
    r: f64,
    a0: f64,
    span: f64,
    ccw: bool,
}

impl Sweep {
    fn of(from: Pos, e: &Element) -> Sweep {
        let c = e.centre;
        let angle = |q: Pos| libm::atan2(q[0] - c[0], q[2] - c[2]);
        let (a0, a1) = (angle(from), angle(e.to));
        let ccw = e.mode == MotionMode::ArcCcw;
        let mut s = Sweep {
            c,
            r: libm::hypot(from[0] - c[0], from[2] - c[2]),
            a0,
            span: 0.0,
            ccw,
        };
        s.span = s.swept_to(a1);
        if s.span < 1e-12 {
            s.span = std::f64::consts::TAU;
        }
        s
    }

    /// How far the angle `t` lies from the start along the arc.
    fn swept_to(&self, t: f64) -> f64 {
        let d = if self.ccw { t - self.a0 } else { self.a0 - t };
        d.rem_euclid(std::f64::consts::TAU)
    }

    fn point(&self, s: f64) -> Pos {
        let t = if self.ccw { self.a0 + s } else { self.a0 - s };
        let mut p = self.c;
        p[0] += self.r * libm::sin(t);
        p[2] += self.r * libm::cos(t);
        p
    }

    /// The arc's points strictly inside it at X = `x`, in the arc's order.
    fn at_x(&self, x: f64) -> heapless::Vec<f64, 2> {
        let mut out = heapless::Vec::new();
        let s = (x - self.c[0]) / self.r;
        if !(-1.0..=1.0).contains(&s) {
            return out;
        }
        let t = libm::asin(s);
        let mut ds = [self.swept_to(t), self.swept_to(std::f64::consts::PI - t)];
        ds.sort_by(|a, b| a.total_cmp(b));
        for d in ds {
            let fresh = out.last().is_none_or(|&l: &f64| d - l > 1e-12);
            if d > 1e-12 && d < self.span - 1e-12 && fresh {
                let _ = out.push(d);
            }
        }
        out
    }

    /// The arc passes the angle `t` strictly inside.
    fn passes(&self, t: f64) -> bool {
        let d = self.swept_to(t);
        d > 1e-12 && d < self.span - 1e-12
    }
}

impl TurningRun {
    /// The boundary's elements with their start points: the first from A.
    fn boundary(&self) -> impl Iterator<Item = (Pos, &Element)> {
        let starts = std::iter::once(self.start).chain(self.shape.iter().map(|e| e.to));
        starts.zip(self.shape.iter())
    }

    /// Depth below the start's X, into the stock.
    fn depth(&self, p: &Passes, x: f64) -> f64 {
        p.sx * (self.start[0] - x)
    }

    /// Distance along the cut from the start's Z.
    fn along(&self, p: &Passes, z: f64) -> f64 {
        p.sz * (z - self.start[2])
    }

    /// The crossings of the element from `from` with the level at depth `level`, in order.
    fn crossings(
        &self,
        p: &Passes,
        from: Pos,
        e: &Element,
        level: f64,
    ) -> heapless::Vec<Crossing, 4> {
        let x = self.start[0] - p.sx * level;
        let deep = |q: Pos| self.depth(p, q[0]) > level + EPS;
        // The points where the element is at the level, with the state of the piece after it.
        let mut cuts: heapless::Vec<(Pos, bool), 4> = heapless::Vec::new();
        let mut state = deep(from);
        let mut mark = |at: Pos, now: bool, state: &mut bool| {
            if now != *state {
                let _ = cuts.push((at, now));
                *state = now;
            }
        };
        if e.mode.is_arc() {
            let s = Sweep::of(from, e);
            let ds = s.at_x(x);
            let mut prev = 0.0;
            for &d in ds.iter().chain(std::iter::once(&s.span)) {
                let mid = deep(s.point((prev + d) / 2.0));
                let mut at = from;
                if prev > 0.0 {
                    at = s.point(prev);
                    at[0] = x;
                }
                mark(at, mid, &mut state);
                prev = d;
            }
        } else {
            let q = e.to;
            let (dp, dq) = (x - from[0], x - q[0]);
            let lerp = |t: f64| {
                let mut a = from;
                a[0] += t * (q[0] - from[0]);
                a[2] += t * (q[2] - from[2]);
                a
            };
            if dp * dq < 0.0 {
                let t = dp / (dp - dq);
                mark(from, deep(lerp(t / 2.0)), &mut state);
                let mut at = lerp(t);
                at[0] = x;
                mark(at, deep(lerp((1.0 + t) / 2.0)), &mut state);
            } else {
                mark(from, deep(lerp(0.5)), &mut state);
            }
        }
        mark(e.to, deep(e.to), &mut state);
        cuts.iter()
            .map(|&(at, down)| Crossing { at, down })
            .collect()
    }

    /// The `i`-th stretch of stock at depth `level` (0: the first along the cut): where the
    /// boundary goes in and where it comes out (past its end: B's Z). Where the boundary
    /// only touches the level from below (out and in again at one point) the stretch goes
    /// on: the tool passes the point on the shape.
    fn stretch(&self, p: &Passes, level: f64, i: u32) -> Option<(Pos, Pos)> {
        let (mut entry, mut exit): (Option<Pos>, Option<Pos>) = (None, None);
        let mut found = 0;
        let mut last = self.start;
        for (from, e) in self.boundary() {
            for c in self.crossings(p, from, e, level) {
                if let (Some(a), Some(b)) = (entry, exit) {
                    let touch = (c.at[0] - b[0]).abs() <= EPS && (c.at[2] - b[2]).abs() <= EPS;
                    if c.down && touch {
                        exit = None;
                        continue;
                    }
                    if found == i {
                        return Some((a, b));
                    }
                    (found, entry, exit) = (found + 1, None, None);
                }
                match (c.down, entry) {
                    (true, None) => entry = Some(c.at),
                    (false, Some(_)) => exit = Some(c.at),
                    _ => {}
                }
            }
            last = e.to;
        }
        let mut end = last;
        end[0] = self.start[0] - p.sx * level;
        let a = entry.filter(|_| found == i)?;
        Some((a, exit.unwrap_or(end)))
    }

    /// The shallowest depth of the boundary over the Z between `z0` and `z1`; an element
    /// that only touches the ends (a wall along X there) does not count.
    fn shallowest(&self, p: &Passes, z0: f64, z1: f64) -> f64 {
        let (lo, hi) = (
            self.along(p, z0).min(self.along(p, z1)),
            self.along(p, z0).max(self.along(p, z1)),
        );
        let mut min = f64::INFINITY;
        for (from, e) in self.boundary() {
            let (va, vb) = (self.along(p, from[2]), self.along(p, e.to[2]));
            if vb.min(va) >= hi - EPS || vb.max(va) <= lo + EPS {
                continue;
            }
            let (v0, v1) = (lo.max(va.min(vb)), hi.min(va.max(vb)));
            let u = if e.mode.is_arc() {
                self.arc_shallowest(p, from, e, v0, v1)
            } else {
                // The line clipped to the way.
                let at = |v: f64| {
                    let t = ((v - va) / (vb - va)).clamp(0.0, 1.0);
                    self.depth(p, from[0] + t * (e.to[0] - from[0]))
                };
                at(v0).min(at(v1))
            };
            min = min.min(u);
        }
        min
    }

    /// The shallowest depth of the arc from `from` over the Z between `v0` and `v1` (along
    /// the cut, within the arc's): the arc turns nowhere in Z, so that piece is one sub-arc,
    /// shallowest at an end or at the arc's top.
    fn arc_shallowest(&self, p: &Passes, from: Pos, e: &Element, v0: f64, v1: f64) -> f64 {
        let s = Sweep::of(from, e);
        // Where along the sweep the arc is at the Z `v` along the cut (of the two angles
        // with that Z, the one on the arc).
        let param = |v: f64| {
            let z = self.start[2] + p.sz * v;
            let t = libm::acos(((z - s.c[2]) / s.r).clamp(-1.0, 1.0));
            // How far off the arc a sweep is (past its end, or just before its start after
            // a turn), and the nearest point of the arc to it.
            let fit = |d: f64| {
                let back = std::f64::consts::TAU - d;
                if d <= s.span {
                    (0.0, d)
                } else if back < d - s.span {
                    (back, 0.0)
                } else {
                    (d - s.span, s.span)
                }
            };
            let (a, b) = (fit(s.swept_to(t)), fit(s.swept_to(-t)));
            if a.0 <= b.0 {
                a.1
            } else {
                b.1
            }
        };
        let (s0, s1) = (param(v0).min(param(v1)), param(v0).max(param(v1)));
        let top = s.swept_to(p.sx * std::f64::consts::FRAC_PI_2);
        let mut u = self
            .depth(p, s.point(s0)[0])
            .min(self.depth(p, s.point(s1)[0]));
        if top > s0 && top < s1 {
            u = u.min(self.depth(p, s.c[0] + p.sx * s.r));
        }
        u
    }

    /// The way over the stock to the Z of `to` from where the tool is, `levels` levels cut:
    /// up to the deepest cut level over the whole way less e (A's X at the most), along Z.
    fn over_to(&mut self, p: &Passes, to: Pos, levels: u32) {
        let above = levels as f64 * p.depth;
        let top = self.shallowest(p, self.at[2], to[2]);
        let cut = (libm::floor((top - EPS) / p.depth) * p.depth).clamp(0.0, above);
        let safe = (cut - p.retract).max(0.0);
        if self.depth(p, self.at[0]) > safe + EPS {
            let mut up = self.at;
            up[0] = self.start[0] - p.sx * safe;
            self.go(up, true, None);
        }
        let mut over = self.at;
        over[2] = to[2];
        self.go(over, true, None);
    }

    /// Type II: stretch `i` of level `k`, or on to the next level, or back to A.
    pub(super) fn pocket_step(&mut self, p: &Passes, k: u32, i: u32) {
        let level = k as f64 * p.depth;
        let Some((a, b)) = self.stretch(p, level, i) else {
            if k < p.count {
                self.phase = Phase::Pocket(k + 1, 0);
                return;
            }
            let start = self.start;
            self.over_to(p, start, p.count);
            self.go(start, true, None);
            self.phase = Phase::Shape(0);
            return;
        };
        // In at rapid only on the first block's G00 move (in the air before the stock).
        let rapid_in = p.rapid_in
            && self
                .shape
                .first()
                .is_some_and(|e| self.along(p, a[2]) <= self.along(p, e.to[2]) + EPS);
        self.over_to(p, a, k - 1);
        let above = (k - 1) as f64 * p.depth;
        if !rapid_in && self.depth(p, self.at[0]) < above - EPS {
            let mut down = self.at;
            down[0] = self.start[0] - p.sx * above;
            self.go(down, true, None);
        }
        self.go(a, rapid_in, None);
        self.go(b, false, None);
        let back = self.along(p, b[2]) - self.along(p, a[2]);
        let mut out = b;
        out[0] += p.sx * p.retract;
        out[2] -= p.sz * p.retract.min(back.max(0.0));
        self.go(out, true, None);
        self.phase = Phase::Pocket(k, i + 1);
    }
}

/// The first element (the first block's move from A included) whose Z turns back against
/// the cut (`sz`), or an arc passing a point where Z turns: type II allows X to go both
/// ways, Z one way only.
pub fn z_turns(start: Pos, shape: &[Element], sz: f64) -> Option<usize> {
    let mut p = start;
    for (i, e) in shape.iter().enumerate() {
        if sz * (e.to[2] - p[2]) < -EPS {
            return Some(i);
        }
        if e.mode.is_arc() {
            let s = Sweep::of(p, e);
            if s.passes(0.0) || s.passes(std::f64::consts::PI) {
                return Some(i);
            }
        }
        p = e.to;
    }
    None
}

/// The deepest point below the start's X (`sx` as in [`Passes`]) of the boundary from
/// `start` along `shape`: where the levels of type II end.
pub fn deepest(start: Pos, shape: &[Element], sx: f64) -> f64 {
    let depth = |x: f64| sx * (start[0] - x);
    let mut max: f64 = 0.0;
    let mut from = start;
    for e in shape {
        max = max.max(depth(e.to[0]));
        if e.mode.is_arc() {
            let s = Sweep::of(from, e);
            if s.passes(-sx * std::f64::consts::FRAC_PI_2) {
                max = max.max(depth(s.c[0] - sx * s.r));
            }
        }
        from = e.to;
    }
    max
}
