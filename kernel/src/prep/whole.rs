//! The whole-program check: every tool-centre segment of a compensation run against every
//! programmed element of the same run, wherever in the program it lies (840C 11.12 checks
//! three blocks, the bottleneck window a few dozen; softnc prepares a program far faster
//! than the machine runs it, so it can know the whole run before the first cut).
//!
//! The definition is the window's (prep/bottleneck.rs): the tool circle along a segment
//! must stay at least R from every programmed element of its side, its own block's element
//! aside (an equidistant is R from it by construction); a radius change over an arc is
//! checked with the radius at each point. What differs is the reach: elements and segments
//! go into a uniform grid over the plane, so each new one meets only those near it, and
//! every pair is looked at once, when the later of the two comes — a cost close to linear
//! in the length of the program. Under ISG masking the segments checked are the masked path
//! (the window's output).

use super::bottleneck::{bbox, elem_in, overlap, Gouge, PathPiece};
use super::leads::{part_of, Closure};
use crate::frontend::block::Plane;
use crate::segment::{Role, Segment, Source};
use crate::trc::geom::{Elem, Fence, Measured};
use std::collections::HashMap;

/// An element or a segment whose box covers more grid cells than this is kept in a list of
/// its own and met by everything (a large arc's box is its whole circle).
const MAX_CELLS: i64 = 64;

#[derive(Clone, Copy, Debug)]
struct Element {
    source: Source,
    elem: Elem,
    /// Tool radius the element is cut with.
    r: f64,
    fence: Fence,
    bb: [f64; 4],
    side: i8,
}

#[derive(Clone, Copy, Debug)]
struct PathSegment {
    source: Source,
    /// A violation of it is on record: it is not reported again.
    reported: bool,
    /// Violations of it waiting for the end of the run (at most `MAX_WAITING`).
    waiting: u8,
    piece: PathPiece,
    r: f64,
    side: i8,
    /// Box in the plane grown by the tool radius.
    bb: [f64; 4],
}

/// Where the members of one kind lie: grid cells, and the large ones apart. A cell holds the
/// head of a list threaded through `entries` (member, next entry): no allocation per cell.
#[derive(Default)]
struct Grid {
    cells: HashMap<(i64, i64), u32, Cells>,
    entries: Vec<(u32, u32)>,
    large: Vec<u32>,
}

/// Violations of one segment that wait for the end of its run, at most (a lead is one to
/// three elements at each end of a run: the first few suffice).
const MAX_WAITING: u8 = 8;

/// The end of a cell's list.
const NONE: u32 = u32::MAX;

impl Grid {
    fn clear(&mut self) {
        self.cells.clear();
        self.entries.clear();
        self.large.clear();
    }

    fn insert(&mut self, cells: Option<[i64; 4]>, i: u32) {
        match cells {
            Some([x0, y0, x1, y1]) => {
                for x in x0..=x1 {
                    for y in y0..=y1 {
                        let at = self.entries.len() as u32;
                        let head = self.cells.entry((x, y)).or_insert(NONE);
                        self.entries.push((i, *head));
                        *head = at;
                    }
                }
            }
            None => self.large.push(i),
        }
    }

    /// Every member in the cells of `cells` (a large box: every member), each once: `seen`
    /// holds the query's stamp for those already met.
    fn each(
        &self,
        cells: Option<[i64; 4]>,
        all: usize,
        seen: &mut [u32],
        stamp: u32,
        mut f: impl FnMut(u32) -> bool,
    ) -> bool {
        let mut visit = |i: u32| {
            let s = &mut seen[i as usize];
            if *s == stamp {
                return false;
            }
            *s = stamp;
            f(i)
        };
        let Some([x0, y0, x1, y1]) = cells else {
            return (0..all as u32).any(&mut visit);
        };
        for x in x0..=x1 {
            for y in y0..=y1 {
                let mut at = self.cells.get(&(x, y)).copied().unwrap_or(NONE);
                while let Some(&(i, next)) = self.entries.get(at as usize) {
                    if visit(i) {
                        return true;
                    }
                    at = next;
                }
            }
        }
        self.large.iter().any(|&i| visit(i))
    }
}

/// The whole-program check of one preparation.
pub struct WholeCheck {
    plane: Plane,
    /// Grid cell edge, mm: set by the first element of a run from its tool radius.
    cell: f64,
    elements: Vec<Element>,
    segments: Vec<PathSegment>,
    element_grid: Grid,
    segment_grid: Grid,
    element_seen: Vec<u32>,
    segment_seen: Vec<u32>,
    stamp: u32,
    /// The last element's tool radius and side: what a segment of a block without an
    /// element takes (as in the window).
    last: Option<(f64, i8)>,
    /// Violations found in the run: the segment, the violation and the element's index;
    /// settled at the end of the run, when its closed loops are known (prep/leads.rs).
    pending: Vec<(u32, Gouge, u32)>,
}

impl Default for WholeCheck {
    fn default() -> Self {
        Self::new()
    }
}

impl WholeCheck {
    pub fn new() -> Self {
        WholeCheck {
            plane: Plane::XY,
            cell: 0.0,
            elements: Vec::new(),
            segments: Vec::new(),
            element_grid: Grid::default(),
            segment_grid: Grid::default(),
            element_seen: Vec::new(),
            segment_seen: Vec::new(),
            stamp: 0,
            last: None,
            pending: Vec::new(),
        }
    }

    pub fn set_plane(&mut self, plane: Plane) {
        self.plane = plane;
    }

    /// A programmed contour element of block `source`, cut with radius `r` on `side`: each
    /// segment of the run already out that comes too close to it is on record for the end
    /// of the run.
    pub fn element(&mut self, source: Source, elem: Elem, r: f64, side: i8) {
        if self.cell == 0.0 {
            self.cell = (8.0 * r.abs()).max(1.0);
        }
        self.last = Some((r, side));
        let e = Element {
            source,
            elem,
            r,
            fence: Fence::new(&elem),
            bb: bbox(&elem, 0.0),
            side,
        };
        let (cells, i) = self.add_element(e);
        let stamp = self.next_stamp();
        let (segments, elements, pending) = (&mut self.segments, &self.elements, &mut self.pending);
        let all = segments.len();
        self.segment_grid
            .each(cells, all, &mut self.segment_seen, stamp, |k| {
                report(
                    &mut segments[k as usize],
                    k,
                    &elements[i as usize],
                    i,
                    pending,
                );
                false
            });
    }

    /// A segment of the tool-centre path as it goes out: each element of its run it comes
    /// too close to is on record. A segment that is no contour, corner or intermediate
    /// block (an approach, a retract, a move without compensation) ends the run: `found`
    /// gets its violations (until it says to stop), and what comes after is met afresh.
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
        let s = PathSegment {
            source: seg.source,
            reported: false,
            waiting: 0,
            piece,
            r,
            side,
            bb: piece.bbox(r),
        };
        let cells = self.cells(&s.bb);
        let i = self.segments.len() as u32;
        self.segments.push(s);
        self.segment_seen.push(0);
        self.segment_grid.insert(cells, i);
        let stamp = self.next_stamp();
        let (segments, elements, pending) = (&mut self.segments, &self.elements, &mut self.pending);
        let s = &mut segments[i as usize];
        self.element_grid
            .each(cells, elements.len(), &mut self.element_seen, stamp, |k| {
                report(s, i, &elements[k as usize], k, pending);
                false
            });
    }

    /// The program ends: violations still waiting for the run's end are settled.
    pub fn finish(&mut self, found: &mut impl FnMut(Gouge) -> bool) {
        self.settle(None, found);
    }

    /// The run's contour is complete (it ends before the block of `end`; the elements of
    /// later blocks belong to the next): a violation of an element that is part of it goes
    /// to `found` (in path order, one a segment), one of a lead is dropped.
    fn settle(&mut self, end: Option<u32>, found: &mut impl FnMut(Gouge) -> bool) {
        if self.pending.is_empty() {
            return;
        }
        let mut closure = Closure::default();
        let before = |e: &&Element| end.is_none_or(|q| (e.source.seq.wrapping_sub(q) as i32) < 0);
        for e in self.elements.iter().take_while(before) {
            closure.element(&e.elem);
        }
        let span = closure.span();
        let mut pending = std::mem::take(&mut self.pending);
        pending.sort_by_key(|p| p.0);
        for (i, g, ordinal) in pending.drain(..) {
            let Some(s) = self.segments.get_mut(i as usize) else {
                continue;
            };
            // One violation a segment: its first in the part.
            if s.reported || !part_of(span, ordinal + 1) {
                continue;
            }
            s.reported = true;
            if found(g) {
                break;
            }
        }
        // Drained: empty, its capacity kept for the next run.
        self.pending = pending;
    }

    /// The element of block `seq`, if the run has one (elements come in block order).
    fn own(&self, seq: u32) -> Option<&Element> {
        self.elements
            .iter()
            .rev()
            .take(8)
            .find(|e| e.source.seq == seq)
    }

    /// The run ends before the block of `seq`: everything before it goes; an element of a
    /// later block (the next run's first, read before its approach came out) stays.
    fn end_run(&mut self, seq: u32) {
        if self.segments.is_empty() && self.elements.is_empty() {
            return;
        }
        let keep: Vec<Element> = self
            .elements
            .iter()
            .filter(|e| (e.source.seq.wrapping_sub(seq) as i32) >= 0)
            .copied()
            .collect();
        self.segments.clear();
        self.segment_seen.clear();
        self.elements.clear();
        self.element_seen.clear();
        self.element_grid.clear();
        self.segment_grid.clear();
        self.pending.clear();
        self.cell = 0.0;
        for e in keep {
            if self.cell == 0.0 {
                self.cell = (8.0 * self.last.map_or(1.0, |l| l.0.abs())).max(1.0);
            }
            self.add_element(e);
        }
    }

    /// An element on record and in the grid: its cells and its index.
    fn add_element(&mut self, e: Element) -> (Option<[i64; 4]>, u32) {
        let cells = self.cells(&e.bb);
        let i = self.elements.len() as u32;
        self.elements.push(e);
        self.element_seen.push(0);
        self.element_grid.insert(cells, i);
        (cells, i)
    }

    /// The grid cells a box covers; `None` for a box too large to list (or not finite).
    fn cells(&self, bb: &[f64; 4]) -> Option<[i64; 4]> {
        let c = |v: f64| (v / self.cell).floor();
        let (x0, y0, x1, y1) = (c(bb[0]), c(bb[1]), c(bb[2]), c(bb[3]));
        let n = (x1 - x0 + 1.0) * (y1 - y0 + 1.0);
        (n.is_finite() && n <= MAX_CELLS as f64)
            .then_some([x0 as i64, y0 as i64, x1 as i64, y1 as i64])
    }

    fn next_stamp(&mut self) -> u32 {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            // Wrapped: no stale stamp may equal a new one.
            self.element_seen.fill(0);
            self.segment_seen.fill(0);
            self.stamp = 1;
        }
        self.stamp
    }
}

/// Segment `s` (index `i`) at element `e` (index `k`): a violation waits in `pending` for
/// the end of the run, where it is reported if `e` is part of the contour and not a lead
/// (prep/leads.rs). A segment keeps its first few.
fn report(s: &mut PathSegment, i: u32, e: &Element, k: u32, pending: &mut Vec<(u32, Gouge, u32)>) {
    if s.reported || s.waiting >= MAX_WAITING {
        return;
    }
    if let Some(g) = gouge(s, e) {
        s.waiting += 1;
        pending.push((i, g, k));
    }
}

/// The gouge of segment `s` at element `e`, if it comes too close (its own block's element,
/// the other side's and far ones are not compared).
fn gouge(s: &PathSegment, e: &Element) -> Option<Gouge> {
    if s.side != e.side || s.source.seq == e.source.seq || !overlap(&s.bb, &e.bb) {
        return None;
    }
    let (distance, radius) = s.piece.too_close(&e.elem, &e.fence, s.r)?;
    Some(Gouge {
        path: s.source,
        element: e.source,
        distance,
        radius,
        unjoined: false,
    })
}

/// A fast hash for grid cells (the standard SipHash guards against inputs chosen to collide,
/// which two integer coordinates of a part program are not).
#[derive(Default, Clone, Copy)]
pub(super) struct Cells;

impl std::hash::BuildHasher for Cells {
    type Hasher = CellHasher;
    fn build_hasher(&self) -> CellHasher {
        CellHasher(0)
    }
}

pub(super) struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 =
                (self.0.rotate_left(5) ^ u64::from(*b)).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
        }
    }
    fn write_i64(&mut self, v: i64) {
        self.0 = (self.0.rotate_left(5) ^ v as u64).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}
