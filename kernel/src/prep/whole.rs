//! The whole-program check: every tool-centre segment of a compensation run against every
//! programmed element of the same run, wherever in the program it lies (840C 11.12 checks
//! three blocks, the bottleneck window a few dozen; softnc prepares a program far faster
//! than the machine runs it, so it can know the whole run before the first cut).
//!
//! The definition is the window's (prep/bottleneck.rs): the tool circle along a segment
//! must stay at least R from every programmed element of its side, its own block's element
//! aside (an equidistant is R from it by construction); a radius change over an arc is
//! checked with the radius at each point. What differs is the reach: when a run is complete
//! its elements go into a uniform grid over their extent and each segment meets only those
//! in the cells its box covers — a cost close to linear in the length of the program. Under
//! ISG masking the segments checked are the masked path (the window's output).

use super::bottleneck::{bbox, elem_in, overlap, Gouge, PathPiece};
use super::leads::{part_of, Closure, Span};
use crate::frontend::block::Plane;
use crate::segment::{Role, Segment, Source};
use crate::trc::geom::{Elem, Fence, Measured};
use core::sync::atomic::{AtomicUsize, Ordering};

/// An element whose box covers more grid cells than this is kept in a list of its own and
/// met by every segment (a large arc's box is its whole circle).
const MAX_CELLS: usize = 64;

/// Grid cell edge in tool radii: a segment's box (grown by R) meets a few cells, and a cell
/// holds the few elements near it.
const CELL_RADII: f64 = 4.0;

/// A programmed element as the run keeps it. Its box lies apart (`WholeCheck::boxes`: the
/// grid's build reads only the boxes, densely), and its [`Fence`] is worked out when the run
/// is checked, beside the grid's build, not while the path streams.
#[derive(Clone, Copy, Debug)]
struct Element {
    source: Source,
    elem: Elem,
    /// Tool radius the element is cut with.
    r: f64,
    side: i8,
}

/// A tool-centre segment as the run keeps it (its box is worked out when it is checked).
#[derive(Clone, Copy, Debug)]
struct PathSegment {
    source: Source,
    piece: PathPiece,
    r: f64,
    side: i8,
}

/// What the check reads of the run's elements.
#[derive(Clone, Copy)]
struct Run<'r> {
    elements: &'r [Element],
    boxes: &'r [[f64; 4]],
    fences: &'r [Fence],
}

/// The elements of one run in a uniform grid over their extent, built when the run is
/// complete: each cell's members lie together in `members` (a counting sort), so a query is
/// index arithmetic and a scan, no hashing and no allocation per cell.
#[derive(Default)]
struct Grid {
    /// Lower corner of the extent, the inverse cell edge, the cells along x and y.
    x0: f64,
    y0: f64,
    inv: f64,
    nx: usize,
    ny: usize,
    /// Cell k's members are `members[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    members: Vec<u32>,
    /// Elements whose box covers more than `MAX_CELLS` cells (or is not finite).
    large: Vec<u32>,
    /// Each element's cells (x0, y0, x1, y1), between the counting and the filling pass.
    spans: Vec<[u32; 4]>,
}

/// Each cell of span `s` in a grid `nx` cells wide, by its index.
#[inline]
fn each_cell(nx: usize, s: [u32; 4], mut f: impl FnMut(usize)) {
    for y in s[1]..=s[3] {
        let row = y as usize * nx;
        for x in s[0]..=s[2] {
            f(row + x as usize);
        }
    }
}

/// The cell index of `v` on an axis of `n` cells, clamped to the grid: a truncation with a
/// correction for negative values (the core's floor is a library call).
#[inline]
fn cell_of(v: f64, n: usize) -> usize {
    if v >= 0.0 {
        // `as` saturates: a huge value lands in the last cell.
        (v as usize).min(n - 1)
    } else {
        0
    }
}

impl Grid {
    /// The grid of the elements with `boxes`, cells about `edge` mm, never many more cells
    /// than elements.
    fn build(&mut self, boxes: &[[f64; 4]], edge: f64) {
        self.start.clear();
        self.members.clear();
        self.large.clear();
        self.spans.clear();
        let mut ext = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for bb in boxes.iter().filter(|bb| bb.iter().all(|v| v.is_finite())) {
            ext = [
                ext[0].min(bb[0]),
                ext[1].min(bb[1]),
                ext[2].max(bb[2]),
                ext[3].max(bb[3]),
            ];
        }
        let (w, h) = ((ext[2] - ext[0]).max(0.0), (ext[3] - ext[1]).max(0.0));
        // Cells enough for the elements: the edge grows where the extent is large for them.
        let room = 4.0 * boxes.len() as f64 + 64.0;
        let edge = edge
            .max(((w * h) / room).sqrt())
            .max(w / room)
            .max(h / room);
        if !(edge.is_finite() && edge > 0.0) {
            self.nx = 0;
            self.large.extend(0..boxes.len() as u32);
            return;
        }
        (self.x0, self.y0, self.inv) = (ext[0], ext[1], 1.0 / edge);
        self.nx = (w * self.inv) as usize + 1;
        self.ny = (h * self.inv) as usize + 1;
        self.start.resize(self.nx * self.ny + 1, 0);
        for (i, bb) in boxes.iter().enumerate() {
            let s = self.span(bb);
            let n = s.map_or(usize::MAX, |s| {
                (s[2] - s[0] + 1) as usize * (s[3] - s[1] + 1) as usize
            });
            match s {
                Some(s) if n <= MAX_CELLS => {
                    each_cell(self.nx, s, |k| self.start[k + 1] += 1);
                    self.spans.push(s);
                }
                _ => {
                    self.large.push(i as u32);
                    self.spans.push([1, 1, 0, 0]);
                }
            }
        }
        for k in 1..self.start.len() {
            self.start[k] += self.start[k - 1];
        }
        self.members
            .resize(self.start[self.nx * self.ny] as usize, 0);
        // Filled from each cell's end backwards: `start` ends as the cells' beginnings.
        let mut fill = std::mem::take(&mut self.start);
        fill.rotate_left(1);
        for (i, s) in self.spans.iter().enumerate() {
            each_cell(self.nx, *s, |k| {
                fill[k] -= 1;
                self.members[fill[k] as usize] = i as u32;
            });
        }
        // Each cell's fill has come down to its beginning; the last entry closes the last cell.
        if let Some(last) = fill.last_mut() {
            *last = self.members.len() as u32;
        }
        self.start = fill;
    }

    /// The cells a box covers, clamped to the grid; `None` for a box not finite or off it.
    #[inline]
    fn span(&self, bb: &[f64; 4]) -> Option<[u32; 4]> {
        if self.nx == 0 || !bb.iter().all(|v| v.is_finite()) {
            return None;
        }
        let (x0, y0) = ((bb[0] - self.x0) * self.inv, (bb[1] - self.y0) * self.inv);
        let (x1, y1) = ((bb[2] - self.x0) * self.inv, (bb[3] - self.y0) * self.inv);
        if x1 < 0.0 || y1 < 0.0 || x0 >= self.nx as f64 || y0 >= self.ny as f64 {
            return None;
        }
        Some([
            cell_of(x0, self.nx) as u32,
            cell_of(y0, self.ny) as u32,
            cell_of(x1, self.nx) as u32,
            cell_of(y1, self.ny) as u32,
        ])
    }

    /// Every element near box `bb`, each once (`seen` holds the query's stamp for those
    /// already met), the large ones last.
    #[inline]
    fn each(&self, bb: &[f64; 4], seen: &mut [u32], stamp: u32, mut f: impl FnMut(u32)) {
        if let Some(s) = self.span(bb) {
            each_cell(self.nx, s, |k| {
                let (a, b) = (self.start[k] as usize, self.start[k + 1] as usize);
                for &i in &self.members[a..b] {
                    let m = &mut seen[i as usize];
                    if *m != stamp {
                        *m = stamp;
                        f(i);
                    }
                }
            });
        }
        for &i in &self.large {
            f(i);
        }
    }
}

/// Runs two pieces of work, at once where the runtime can: the core starts no thread of its
/// own (the command line gives one that does, the kernel none).
pub trait Join: Sync {
    fn join(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send));
}

/// A run with fewer segments than this is checked in one piece (a thread costs more than
/// its half).
const PARALLEL_SEGMENTS: usize = 8192;

/// Segments a worker takes at a time from a long run: the two take the next piece as they
/// finish one, so neither waits on a half that turned out longer (cache misses and exact
/// distances are not spread evenly over a program).
const PIECE: usize = 2048;

/// One worker's check of a run: its own stamps, and the violations it found.
#[derive(Default)]
struct Share {
    /// The query's stamp of each element already met by it.
    seen: Vec<u32>,
    stamp: u32,
    /// Each segment's first violation of the part, in path order, with the segment's index.
    hits: Vec<(u32, Gouge)>,
    /// The run's closed loops, worked out at the worker's first violation (prep/leads.rs).
    span: Option<Span>,
}

impl Share {
    /// Starts a check of `run`.
    fn reset(&mut self, run: Run<'_>) {
        self.hits.clear();
        self.seen.clear();
        self.seen.resize(run.elements.len(), 0);
        self.stamp = 0;
        self.span = None;
    }

    /// Takes pieces of `segments` (by `next`, shared with the other worker) until none is
    /// left, and checks each against the elements of `run` (in `grid`).
    fn take(&mut self, segments: &[PathSegment], next: &AtomicUsize, run: Run<'_>, grid: &Grid) {
        loop {
            let from = next.fetch_add(PIECE, Ordering::Relaxed);
            if from >= segments.len() {
                return;
            }
            let to = (from + PIECE).min(segments.len());
            self.check(&segments[from..to], from, run, grid);
        }
    }

    /// Checks `segments` (the first is the run's segment `first`) against the elements of
    /// `run` (in `grid`).
    fn check(&mut self, segments: &[PathSegment], first: usize, run: Run<'_>, grid: &Grid) {
        let span = &mut self.span;
        for (i, s) in segments.iter().enumerate() {
            self.stamp = self.stamp.wrapping_add(1);
            if self.stamp == 0 {
                // Wrapped: no stale stamp may equal a new one.
                self.seen.fill(0);
                self.stamp = 1;
            }
            let mut found: Option<(u32, Gouge)> = None;
            let bb = s.piece.bbox(s.r);
            grid.each(&bb, &mut self.seen, self.stamp, |k| {
                if found.is_some_and(|(f, _)| f < k) {
                    return;
                }
                let Some(g) = gouge(s, &bb, run, k as usize) else {
                    return;
                };
                let span = *span.get_or_insert_with(|| loops(run.elements));
                if part_of(span, k + 1) {
                    found = Some((k, g));
                }
            });
            self.hits
                .extend(found.map(|(_, g)| ((first + i) as u32, g)));
        }
    }
}

/// The whole-program check of one preparation: the run's elements and segments are kept as
/// they come, and checked against each other when the run is complete (the kernel lets no
/// segment of a run go before the whole run is met, and a violation of a lead is known only
/// then: prep/leads.rs).
pub struct WholeCheck<'a> {
    plane: Plane,
    elements: Vec<Element>,
    /// Each element's box, beside it.
    boxes: Vec<[f64; 4]>,
    /// Each element's fence, worked out when the run is checked.
    fences: Vec<Fence>,
    segments: Vec<PathSegment>,
    grid: Grid,
    /// The two workers of a long run (one does all of a short one).
    shares: [Share; 2],
    join: Option<&'a dyn Join>,
    /// The last element's tool radius and side: what a segment of a block without an
    /// element takes (as in the window).
    last: Option<(f64, i8)>,
}

impl Default for WholeCheck<'_> {
    fn default() -> Self {
        Self::new()
    }
}

impl<'a> WholeCheck<'a> {
    pub fn new() -> Self {
        WholeCheck {
            plane: Plane::XY,
            elements: Vec::new(),
            boxes: Vec::new(),
            fences: Vec::new(),
            segments: Vec::new(),
            grid: Grid::default(),
            shares: Default::default(),
            join: None,
            last: None,
        }
    }

    /// Long runs are checked by two workers at once through `join`.
    pub fn with_join(&mut self, join: &'a dyn Join) {
        self.join = Some(join);
    }

    pub fn set_plane(&mut self, plane: Plane) {
        self.plane = plane;
    }

    /// A programmed contour element of block `source`, cut with radius `r` on `side`.
    pub fn element(&mut self, source: Source, elem: Elem, r: f64, side: i8) {
        self.last = Some((r, side));
        self.elements.push(Element {
            source,
            elem,
            r,
            side,
        });
        self.boxes.push(bbox(&elem, 0.0));
    }

    /// A segment of the tool-centre path as it goes out. A segment that is no contour,
    /// corner or intermediate block (an approach, a retract, a move without compensation)
    /// ends the run: the run is checked and `found` gets its violations in path order (until
    /// it says to stop); what comes after is met afresh.
    pub fn segment(&mut self, seg: &Segment, found: &mut impl FnMut(Gouge) -> bool) {
        if !matches!(seg.role, Role::Contour | Role::Corner | Role::Intermediate) {
            self.settle(Some(seg.source.seq), found);
            self.end_run(seg.source.seq);
            return;
        }
        let own = self.own(seg.source.seq).copied();
        let (r, side) = own.map(|e| (e.r, e.side)).or(self.last).unwrap_or((0.0, 0));
        let piece = match (elem_in(seg, self.plane), own) {
            (Some(e), _) => PathPiece::Plain(Measured::new(e)),
            (None, Some(o)) => PathPiece::spiral(seg, self.plane, &o.elem),
            (None, None) => PathPiece::Off,
        };
        if matches!(piece, PathPiece::Off) {
            return;
        }
        self.segments.push(PathSegment {
            source: seg.source,
            piece,
            r,
            side,
        });
    }

    /// The program ends: the last run is checked.
    pub fn finish(&mut self, found: &mut impl FnMut(Gouge) -> bool) {
        self.settle(None, found);
    }

    /// The run's contour is complete (it ends before the block of `end`; the elements of
    /// later blocks belong to the next): each segment too close to an element that is part
    /// of it goes to `found` (in path order, one violation a segment: the earliest element
    /// it reaches); one of a lead is dropped. A long run is checked by two workers at
    /// once, piece by piece, where the runtime gave a [`Join`].
    fn settle(&mut self, end: Option<u32>, found: &mut impl FnMut(Gouge) -> bool) {
        if self.segments.is_empty() {
            return;
        }
        let before = |e: &Element| end.is_none_or(|q| (e.source.seq.wrapping_sub(q) as i32) < 0);
        let n = self.elements.iter().take_while(|e| before(e)).count();
        let (elements, boxes) = (&self.elements[..n], &self.boxes[..n]);
        let segments = &self.segments[..];
        let edge = CELL_RADII * elements.first().map_or(1.0, |e| e.r.abs()).max(0.25);
        let (grid, fences) = (&mut self.grid, &mut self.fences);
        let mut fence = || {
            fences.clear();
            fences.extend(elements.iter().map(|e| Fence::new(&e.elem)));
        };
        let long = self.join.filter(|_| segments.len() >= PARALLEL_SEGMENTS);
        match long {
            Some(join) => join.join(&mut || grid.build(boxes, edge), &mut fence),
            None => {
                grid.build(boxes, edge);
                fence();
            }
        }
        let (grid, fences) = (&self.grid, &self.fences[..]);
        let run = Run {
            elements,
            boxes,
            fences,
        };
        let [first, second] = &mut self.shares;
        first.reset(run);
        second.reset(run);
        let next = AtomicUsize::new(0);
        match long {
            Some(join) => join.join(&mut || first.take(segments, &next, run, grid), &mut || {
                second.take(segments, &next, run, grid)
            }),
            None => first.take(segments, &next, run, grid),
        }
        // Each worker's hits come in path order: merged, all of them do.
        let (mut a, mut b) = (first.hits.iter().peekable(), second.hits.iter().peekable());
        while let Some(&(_, g)) = match (a.peek(), b.peek()) {
            (Some(x), Some(y)) if y.0 < x.0 => b.next(),
            (Some(_), _) => a.next(),
            (None, _) => b.next(),
        } {
            if found(g) {
                return;
            }
        }
    }

    /// The element of block `seq`, if the run has one. Elements come in block order, and
    /// ahead of their segments by as many blocks as the bottleneck window holds back: the
    /// search goes back over those, no further.
    fn own(&self, seq: u32) -> Option<&Element> {
        self.elements
            .iter()
            .rev()
            .take(super::bottleneck::MAX_WINDOW + 8)
            .find(|e| (e.source.seq.wrapping_sub(seq) as i32) <= 0)
            .filter(|e| e.source.seq == seq)
    }

    /// The run ends before the block of `seq`: everything before it goes; an element of a
    /// later block (the next run's first, read before its approach came out) stays.
    fn end_run(&mut self, seq: u32) {
        self.segments.clear();
        // Elements come in block order: those that stay are the last few.
        let gone = self
            .elements
            .iter()
            .take_while(|e| (e.source.seq.wrapping_sub(seq) as i32) < 0)
            .count();
        self.elements.drain(..gone);
        self.boxes.drain(..gone);
    }
}

/// The closed loops of a run's elements (prep/leads.rs).
#[cold]
fn loops(elements: &[Element]) -> Span {
    let mut closure = Closure::default();
    for e in elements {
        closure.element(&e.elem);
    }
    closure.span()
}

/// The gouge of segment `s` (box `bb`) at element `k` of `run`, if it comes too close (its
/// own block's element, the other side's and far ones are not compared).
#[inline]
fn gouge(s: &PathSegment, bb: &[f64; 4], run: Run<'_>, k: usize) -> Option<Gouge> {
    // The box first: the boxes lie densely, and it settles most pairs.
    if !overlap(bb, &run.boxes[k]) {
        return None;
    }
    let e = &run.elements[k];
    if s.side != e.side || s.source.seq == e.source.seq {
        return None;
    }
    let (distance, radius) = s.piece.too_close(&e.elem, &run.fences[k], s.r)?;
    Some(Gouge {
        path: s.source,
        element: e.source,
        distance,
        radius,
        unjoined: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trc::geom::v2;
    use proptest::prelude::*;

    fn elem() -> impl Strategy<Value = Elem> {
        let p = || (-200.0..200.0f64, -50.0..50.0f64).prop_map(|(x, y)| v2(x, y));
        prop_oneof![
            4 => (p(), (-8.0..8.0f64, -8.0..8.0f64)).prop_map(|(a, (dx, dy))| Elem::Line { a, b: v2(a.x + dx, a.y + dy) }),
            1 => (p(), 0.5..60.0f64, any::<bool>()).prop_map(|(c, r, ccw)| Elem::Arc {
                a: v2(c.x + r, c.y),
                b: v2(c.x, c.y + r),
                c,
                ccw,
            }),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// A query meets every element whose box overlaps its own, each once, whatever the
        /// cell edge (small edges grow where the extent is large for the elements).
        #[test]
        fn the_grid_meets_every_element_near_a_box(
            elems in proptest::collection::vec(elem(), 1..120),
            edge in 0.05..40.0f64,
            queries in proptest::collection::vec(((-250.0..250.0f64, -80.0..80.0f64), (0.0..30.0f64, 0.0..30.0f64)), 1..20),
        ) {
            let boxes: Vec<[f64; 4]> = elems.iter().map(|e| bbox(e, 0.0)).collect();
            let mut grid = Grid::default();
            grid.build(&boxes, edge);
            let mut seen = vec![0u32; boxes.len()];
            for (stamp, ((x, y), (w, h))) in queries.into_iter().enumerate() {
                let bb = [x, y, x + w, y + h];
                let mut met = vec![0u32; boxes.len()];
                grid.each(&bb, &mut seen, stamp as u32 + 1, |k| met[k as usize] += 1);
                for (k, ebb) in boxes.iter().enumerate() {
                    prop_assert!(met[k] <= 1, "element {k} met {} times", met[k]);
                    if overlap(&bb, ebb) {
                        prop_assert_eq!(met[k], 1, "element {} not met by {:?}", k, bb);
                    }
                }
            }
        }
    }
}
