//! Bottleneck detection over a window of blocks (beyond 840C 11.12; 840D CDON, TNC M120) and
//! ISG contour masking (G141, 002).
//!
//! The local check (`trc/violation.rs`) sees three elements. A notch narrower than the tool
//! whose sides are further apart in the program, or a contour that comes back close to
//! itself, needs more: every compensated segment is held back until `window` more contour
//! blocks have come, and the definition of a gouge is checked directly — the tool circle
//! along a path segment must stay at least R from every programmed element in the window
//! (the element it belongs to included: there the distance is R exactly); a path arc whose
//! radius changes over the block is checked with the tool radius at each point (a `Spiral`).
//! A gouge is alarm 3021 before the tool gets there. With ISG contour masking on, where the
//! path crosses itself the loop is cut out instead: the earlier segment ends at the crossing,
//! the blocks in between are left out (their auxiliary functions are output there, in program
//! order, by the S-point stage) and the new segment starts at the crossing. Where the trims
//! took the crossing away — a segment that runs backwards, a circle smaller than the tool
//! (the compensator turns its equidistant inside out), a corner whose equidistants do not meet
//! (the compensator leaves a gap) — the path joins where a held segment and the new one meet,
//! either lengthened along its equidistant, at a point clear of every element. Every segment
//! is checked once more when it leaves the window; a gouge left, or a gap not closed, stays
//! an alarm (no gouge-free path inside the window).

use super::leads::{part_of, span_of};
use crate::frontend::block::{Plane, Pos};
use crate::segment::{Role, Segment, Shape};
use crate::trc::geom::{
    arcs_clear, circles_clear, clear_by_ends_of, contains, dist_elems, dist_point, eta_of,
    intersections, margin, max_abs, sweep, v2, Elem, Fence, Measured, V2,
};

/// Largest window, in blocks.
pub const MAX_WINDOW: usize = 512;

/// Segments held for a window of `depth` blocks: a block puts out at most its contour
/// segment and three inserted pieces. The queue the window releases into must take this
/// many at once (a flush).
pub fn held_for(depth: usize) -> usize {
    4 * depth + 8
}

/// A gouge found: the path segment and the block of the programmed element it comes too
/// close to.
#[derive(Clone, Copy, Debug)]
pub struct Gouge {
    pub path: crate::segment::Source,
    pub element: crate::segment::Source,
    pub distance: f64,
    pub radius: f64,
    /// Masking found no way past this block: a corner whose equidistants do not meet, or a
    /// segment that runs backwards, with no joint in the window (`distance` means nothing).
    pub unjoined: bool,
}

/// What to do with a gouge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reaction {
    Alarm,
    /// Report it, keep the path (machine data `trc.violation_reaction = warn`).
    Warn,
    /// ISG G141: cut out the loop where the path crosses itself.
    Mask,
}

#[derive(Clone, Copy, Debug)]
struct Held {
    seg: Segment,
    piece: PathPiece,
    /// A contour segment that runs against its programmed element (shorter than the trim of
    /// its corners), or one inside such a run's loop that comes too close to the contour:
    /// what masking leaves out (unless a joint or bridge takes it up).
    backwards: bool,
    /// Masking: the segment does not start where the one before it ends (a corner whose
    /// equidistants do not meet); a later join must close the gap.
    after_gap: bool,
    /// Tool radius and side the segment was made with.
    r: f64,
    side: i8,
    /// Bounding box in the plane, grown by the radius: min u, min v, max u, max v.
    bb: [f64; 4],
}

impl Held {
    /// Masking: the segment now ends at `to` (and starts at `from`), along its carrier. A
    /// backward arc turns round to its element's direction with it; a backward segment so
    /// joined runs forwards now. Measured again.
    fn rejoined(&mut self, plane: Plane, from: Option<V2>, to: V2, own: Option<&Elem>) {
        if let Some(f) = from {
            self.seg.from = at(plane, &self.seg.from, f);
        }
        self.seg.to = at(plane, &self.seg.to, to);
        // (An inserted piece keeps its direction: it never ran against an element.)
        if let (true, Shape::Arc { ccw, .. }, Some(Elem::Arc { ccw: o, .. })) = (
            self.backwards && self.seg.role == Role::Contour,
            &mut self.seg.shape,
            own,
        ) {
            *ccw = *o;
        }
        self.piece = PathPiece::plain(elem_in(&self.seg, plane));
        self.bb = self.piece.bbox(self.r);
        self.backwards = self
            .piece
            .elem()
            .is_some_and(|e| runs_backwards(self.seg.role, &e, own, self.r, self.side));
    }
}

/// Where masking joins the path: held segment `at` ends at `x` and what follows it is left
/// out. With `bridge`, held segment `bridge.0` (one that ran backwards) comes back along
/// its equidistant from `x` to `bridge.1`, and the new segment starts there; otherwise the
/// new segment starts at `x`.
#[derive(Clone, Copy, Debug)]
struct Joint {
    at: usize,
    x: V2,
    bridge: Option<(usize, V2)>,
}

/// A path segment as the window measures it.
#[derive(Clone, Copy, Debug)]
pub(super) enum PathPiece {
    /// A line or a circle.
    Plain(Measured),
    /// A path arc whose radius changes along it: checked by bisection.
    Spiral(Spiral),
    /// Nothing to measure: no move in the plane, or a radius change the window does not model.
    Off,
}

impl PathPiece {
    fn plain(e: Option<Elem>) -> PathPiece {
        e.map_or(PathPiece::Off, |e| PathPiece::Plain(Measured::new(e)))
    }

    /// Segment `s`, an arc whose radius changes about the centre of its own element `own`.
    pub(super) fn spiral(s: &Segment, plane: Plane, own: &Elem) -> PathPiece {
        Spiral::new(s, plane, own).map_or(PathPiece::Off, PathPiece::Spiral)
    }

    fn elem(&self) -> Option<Elem> {
        match *self {
            PathPiece::Plain(m) => Some(m.e),
            _ => None,
        }
    }

    /// The gouge tolerance of a plain piece ([`gouge_tol`]; a spiral has its own).
    pub(super) fn gouge_tol(&self) -> f64 {
        match self {
            PathPiece::Plain(m) => gouge_tol(&m.e),
            _ => 0.0,
        }
    }

    pub(super) fn bbox(&self, r: f64) -> [f64; 4] {
        match self {
            PathPiece::Plain(m) => bbox(&m.e, r),
            PathPiece::Spiral(sp) => sp.bbox(),
            PathPiece::Off => [0.0; 4],
        }
    }

    /// Where the tool circle (radius `r`, or a spiral's own) comes closer to `other` than
    /// its radius, beyond rounding: the distance there and the tool radius. `fence` gives the
    /// element's fence ([`Fence::new`]), asked for only where the cheap test by the element's
    /// ends is tried.
    #[inline]
    pub(super) fn too_close<'f>(
        &self,
        other: &Elem,
        fence: impl FnOnce() -> &'f Fence,
        r: f64,
    ) -> Option<(f64, f64)> {
        self.too_close_by(self.gouge_tol(), other, eta_of(other), fence, r)
    }

    /// [`Self::too_close`] with the piece's [`Self::gouge_tol`] and the element's [`eta_of`]
    /// worked out before (once for every pair a record is in).
    #[inline]
    pub(super) fn too_close_by<'f>(
        &self,
        tol: f64,
        other: &Elem,
        other_eta: f64,
        fence: impl FnOnce() -> &'f Fence,
        r: f64,
    ) -> Option<(f64, f64)> {
        match self {
            PathPiece::Plain(m) => too_close_by(m, tol, other, other_eta, fence, r).map(|d| (d, r)),
            PathPiece::Spiral(sp) => sp.too_close(other),
            PathPiece::Off => None,
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Programmed {
    source: crate::segment::Source,
    elem: Elem,
    /// What the cheap clearance test needs of the element, worked out once.
    fence: Fence,
    bb: [f64; 4],
    /// Tool radius the element is cut with.
    r: f64,
    /// Compensation side (+1 left, −1 right). Across a side change (Fanuc in offset mode)
    /// the tool crosses the contour on purpose: paths and elements of different sides are
    /// not compared.
    side: i8,
}

/// Consecutive programmed elements of the window under one box: a path piece skips the
/// chunks its box misses (most of a deep window lies far back along the path), and meets the
/// elements of the others in order.
#[derive(Clone, Copy, Debug)]
struct Chunk {
    /// Covers every element ever put in the chunk (those gone from the window too).
    bb: [f64; 4],
    /// Elements of the chunk still in the window, and all put in it.
    live: u32,
    filled: u32,
}

/// Elements a chunk takes.
const CHUNK: u32 = 8;

/// A ring's records in chunks, kept beside it: pushed and popped with it.
#[derive(Debug)]
struct Chunks(std::collections::VecDeque<Chunk>);

impl Chunks {
    fn with_capacity(records: usize) -> Self {
        Chunks(std::collections::VecDeque::with_capacity(
            records / CHUNK as usize + 2,
        ))
    }

    /// A record with box `bb` comes at the back.
    fn push(&mut self, bb: &[f64; 4]) {
        match self.0.back_mut().filter(|c| c.filled < CHUNK) {
            Some(c) => {
                c.grow(bb);
                c.live += 1;
                c.filled += 1;
            }
            None => self.0.push_back(Chunk {
                bb: *bb,
                live: 1,
                filled: 1,
            }),
        }
    }

    /// The front record goes.
    fn pop_front(&mut self) {
        if let Some(c) = self.0.front_mut() {
            c.live -= 1;
            if c.live == 0 {
                self.0.pop_front();
            }
        }
    }

    /// The back record goes.
    fn pop_back(&mut self) {
        if let Some(c) = self.0.back_mut() {
            c.live -= 1;
            if c.live == 0 {
                self.0.pop_back();
            }
        }
    }

    /// The back record's box now is `bb`.
    fn regrow_back(&mut self, bb: &[f64; 4]) {
        if let Some(c) = self.0.back_mut() {
            c.grow(bb);
        }
    }

    fn clear(&mut self) {
        self.0.clear();
    }

    /// The records the chunks hold (the ring's length).
    fn records(&self) -> usize {
        self.0.iter().map(|c| c.live as usize).sum()
    }

    /// The index ranges of the ring's records whose chunks box `bb` may overlap, in order.
    fn near<'c>(&'c self, bb: &'c [f64; 4]) -> impl Iterator<Item = std::ops::Range<usize>> + 'c {
        self.0
            .iter()
            .scan(0, |from, c| {
                let r = *from..*from + c.live as usize;
                *from = r.end;
                Some((r, c))
            })
            // A box that misses the chunk's misses each of its records'.
            .filter(|(_, c)| overlap(&c.bb, bb))
            .map(|(r, _)| r)
    }
}

impl Chunk {
    fn grow(&mut self, bb: &[f64; 4]) {
        self.bb = [
            self.bb[0].min(bb[0]),
            self.bb[1].min(bb[1]),
            self.bb[2].max(bb[2]),
            self.bb[3].max(bb[3]),
        ];
    }
}

/// Programmed elements kept for a window of `depth` blocks: a path segment meets elements up
/// to `depth` blocks before and after its own.
fn programmed_for(depth: usize) -> usize {
    2 * depth + 4
}

/// Distances below R by more than this are gouges (constructions are exact to ~1e-12 at
/// part sizes; far from the origin the rounding of the coordinates themselves counts).
fn gouge_tol(e: &Elem) -> f64 {
    1e-9_f64.max(1e-12 * max_abs(0.0, &[e.start(), e.end()]))
}

pub struct Bottleneck {
    window: usize,
    plane: Plane,
    /// Sized once for the window (masking's 3 at least): never grown on the per-block path.
    held: std::collections::VecDeque<Held>,
    programmed: std::collections::VecDeque<Programmed>,
    /// The held segments and the programmed elements in chunks (their `live` add up to them).
    held_chunks: Chunks,
    programmed_chunks: Chunks,
    /// Distinct blocks among the held segments, and the last one's number.
    blocks: usize,
    last_seq: Option<u32>,
}

impl Bottleneck {
    /// `window`: blocks a segment is checked against (0: off).
    pub fn new(window: usize) -> Self {
        Bottleneck {
            window: window.min(MAX_WINDOW),
            plane: Plane::XY,
            held: std::collections::VecDeque::with_capacity(held_for(window.clamp(3, MAX_WINDOW))),
            programmed: std::collections::VecDeque::with_capacity(programmed_for(
                window.clamp(3, MAX_WINDOW),
            )),
            held_chunks: Chunks::with_capacity(held_for(window.clamp(3, MAX_WINDOW))),
            programmed_chunks: Chunks::with_capacity(programmed_for(window.clamp(3, MAX_WINDOW))),
            blocks: 0,
            last_seq: None,
        }
    }

    /// The window in blocks for this reaction (masking checks over at least 3).
    fn depth(&self, reaction: Reaction) -> usize {
        if reaction == Reaction::Mask {
            self.window.max(3)
        } else {
            self.window
        }
    }

    /// A programmed contour element (block `source`): the held path must keep its distance.
    pub fn element(
        &mut self,
        source: crate::segment::Source,
        elem: Elem,
        r: f64,
        side: i8,
        reaction: Reaction,
    ) -> Result<Option<Gouge>, Gouge> {
        if self.depth(reaction) == 0 {
            return Ok(None);
        }
        let bb = bbox(&elem, 0.0);
        let fence = Fence::new(&elem);
        // A path segment meets elements up to `depth` blocks before and after its own.
        while self.programmed.len() >= 2 * self.depth(reaction) + 2 {
            self.pop_programmed();
        }
        self.programmed_chunks.push(&bb);
        self.programmed.push_back(Programmed {
            source,
            elem,
            fence,
            bb,
            r,
            side,
        });
        let newest = self.programmed.len() - 1;
        let mut found = None;
        // Masking checks a segment when it leaves the window: a loop cut out later may drop
        // what comes too close now.
        let checked = reaction != Reaction::Mask;
        debug_assert_eq!(self.held_chunks.records(), self.held.len());
        let near_ones = self.held_chunks.near(&bb).filter(|_| checked);
        for h in near_ones.flat_map(|r| self.held.range(r)) {
            if h.side != side || near(h.seg.source.seq, source.seq) || !overlap(&h.bb, &bb) {
                continue;
            }
            if let Some((d, radius)) = h.piece.too_close(&elem, || &fence, h.r) {
                if self.lead(newest) {
                    break;
                }
                found = Some(Gouge {
                    path: h.seg.source,
                    element: source,
                    distance: d,
                    radius,
                    unjoined: false,
                });
                break;
            }
        }
        match (found, reaction) {
            (Some(g), Reaction::Warn) => Ok(Some(g)),
            (Some(g), _) => Err(g),
            (None, _) => Ok(None),
        }
    }

    #[inline]
    pub fn set_plane(&mut self, plane: Plane) {
        self.plane = plane;
    }

    /// Off and nothing held: a segment may pass straight on.
    #[inline]
    pub fn bypass(&self, reaction: Reaction) -> bool {
        self.depth(reaction) == 0 && self.held.is_empty()
    }

    /// Takes the next segment of the path; what may go on goes to `out`. Its tool radius and
    /// side are its block's element's (a segment comes out after its element went in), else
    /// the last element's.
    pub fn push(
        &mut self,
        mut seg: Segment,
        reaction: Reaction,
        out: &mut std::collections::VecDeque<Segment>,
    ) -> Result<Option<Gouge>, Gouge> {
        let checked = matches!(seg.role, Role::Contour | Role::Corner | Role::Intermediate);
        let depth = self.depth(reaction);
        if !checked || depth == 0 {
            // Compensation starts or ends here (or nothing is checked): the window starts anew.
            self.flush(out, reaction == Reaction::Mask)?;
            if !checked {
                // Elements before this segment's block belong to an earlier compensation; the
                // first element of this one (added before its approach came out) stays.
                while self
                    .programmed
                    .front()
                    .is_some_and(|p| (p.source.seq.wrapping_sub(seg.source.seq) as i32) < 0)
                {
                    self.pop_programmed();
                }
            }
            out.push_back(seg);
            return Ok(None);
        }
        let mut warned = None;
        let own = self.own(seg.source.seq);
        let (r, side) = own
            .or(self.programmed.back())
            .map_or((0.0, 0), |p| (p.r, p.side));
        let own = own.map(|p| p.elem);
        let mask = reaction == Reaction::Mask;
        // Only masking leaves segments out (and finds gaps).
        let (mut gap, mut backwards) = (false, false);
        let mut piece = match (self.elem(&seg), own) {
            (Some(e), _) => PathPiece::Plain(Measured::new(e)),
            // Masking cuts lines and circles only (ISG has no radius change over a circle).
            (None, Some(o)) if !mask => PathPiece::spiral(&seg, self.plane, &o),
            (None, _) => PathPiece::Off,
        };
        if let (PathPiece::Plain(Measured { e, .. }), true) = (piece, mask) {
            // A gap: the compensator found no corner there (`Compensator::element`). A join
            // must start before it; one not closed when its segment leaves is an alarm.
            gap = self
                .held
                .back()
                .is_some_and(|h| uv(&h.seg.to, self.plane).dist(e.start()) > 1e-9);
            // A segment that runs backwards itself waits for the next element to join (a
            // join moves its start along its own line or circle: `backwards` holds for what
            // is pushed too).
            backwards = runs_backwards(seg.role, &e, own.as_ref(), r, side);
            let x = if backwards {
                None
            } else if gap {
                self.joined(&e, seg.source.seq, r, side, self.before_gap(), true)
            } else {
                // A crossing whose cut still comes too close to the contour gives way to a
                // joint past a backward run that does not (if there is one).
                let crossing = self.crossing_with_held(&e);
                match crossing {
                    Some(c) if self.cut_clear(c, &e, r, side) => crossing,
                    _ => self
                        .joined_past_backwards(&e, seg.source.seq, r, side, self.before_gap())
                        .or(crossing),
                }
            };
            if let Some(x) = x {
                self.cut_loop(x, &mut seg);
                piece = PathPiece::plain(self.elem(&seg));
                gap = false;
            } else if !backwards
                && !gap
                && self.held.iter().any(|h| h.backwards)
                && !self.clear(&e, r, side)
            {
                // Inside the loop of a backward run and not joined: it comes too close to
                // the contour, so it is left out with the run (a later element must join).
                backwards = true;
            }
        }
        let bb = piece.bbox(r);
        if !mask {
            if let Some(g) = self.first_gouge(seg.source, &piece, r, side, &bb, false) {
                if reaction != Reaction::Warn {
                    return Err(g);
                }
                warned = Some(g);
            }
        }
        // A new block in the window; the oldest leaves once there are more than `depth`.
        if self.last_seq != Some(seg.source.seq) {
            self.blocks += 1;
            self.last_seq = Some(seg.source.seq);
        }
        if self.held.len() >= held_for(depth) {
            self.release_block(out, mask)?;
        }
        self.hold(Held {
            seg,
            piece,
            backwards,
            after_gap: gap,
            r,
            side,
            bb,
        });
        while self.blocks > depth {
            self.release_block(out, mask)?;
        }
        Ok(warned)
    }

    /// Where a new path element crosses a held segment other than the last one (which
    /// shares its start): the held index and the point.
    fn crossing_with_held(&self, e: &Elem) -> Option<Joint> {
        let bb = bbox(e, 0.0);
        let n = self.held.len();
        for (i, h) in self.held.iter().enumerate().take(n.saturating_sub(1)) {
            if h.backwards {
                continue;
            }
            let Some(he) = h.piece.elem() else {
                continue;
            };
            if !overlap(&bbox(&he, 0.0), &bb) {
                continue;
            }
            if let Some(x) = intersections(&he, e).into_iter().find(|&x| {
                contains(&he, x)
                    && contains(e, x)
                    && x.dist(e.start()) > 1e-7
                    && x.dist(he.end()) > 1e-7
            }) {
                return Some(Joint {
                    at: i,
                    x,
                    bridge: None,
                });
            }
        }
        None
    }

    /// Whether the path cut at a crossing keeps clear of the contour: the held segment up to
    /// the point and the new element from it.
    fn cut_clear(&self, c: Joint, e: &Elem, r: f64, side: i8) -> bool {
        self.held
            .get(c.at)
            .and_then(|h| h.piece.elem())
            .is_some_and(|he| {
                self.clear(&he.with_end(c.x), r, side) && self.clear(&e.with_start(c.x), r, side)
            })
    }

    /// Masking where no held segment crosses the new element: an element shorter than the
    /// trim of its inner corner runs backwards, and its neighbours were trimmed at their
    /// intersections with it, points that are gone once it is left out. The path joins where
    /// the equidistants meet: a held segment before the backward run, lengthened past its
    /// end if need be, and the new element, lengthened back before its start if need be (002
    /// G141: "the path joins at the equidistants' intersection"), as [`Self::joined`] finds.
    fn joined_past_backwards(
        &self,
        e: &Elem,
        seq: u32,
        r: f64,
        side: i8,
        before_gap: usize,
    ) -> Option<Joint> {
        let last = self.held.iter().rposition(|h| h.backwards)?;
        // Only a run at the end of the path: after it, nothing but the new block's own
        // corner pieces (a run followed by a valid element was resolved or is no loop).
        if self
            .held
            .iter()
            .skip(last + 1)
            .any(|h| h.seg.source.seq != seq)
        {
            return None;
        }
        self.joined(e, seq, r, side, (last + 1).min(before_gap), true)
    }

    /// Where one of the first `upto` held segments, lengthened past its end if need be, and
    /// `e` (of block `seq`), lengthened back before its start if need be, meet with the tool
    /// clear of every element in the window, at the point and along both. The point must
    /// touch both blocks' elements (R from each): the masked path is the edge of what the
    /// tool may reach, never a detour through free space (two equidistants that are nearly
    /// parallel meet far from the part). The latest such segment: as little of the contour
    /// as possible is left out; of its meeting points, the one that lengthens least. With
    /// `bridge`, a backward segment that offers no such point may be bridged
    /// ([`Self::bridged`]), and so may the segment after the first unclosed gap (`upto`
    /// itself then); a joint that would leave a backward run held before its segment
    /// becomes a bridge of that segment if an earlier one joins it.
    fn joined(
        &self,
        e: &Elem,
        seq: u32,
        r: f64,
        side: i8,
        upto: usize,
        bridge: bool,
    ) -> Option<Joint> {
        // The segment after the first unclosed gap starts wrong: it may only be bridged.
        let gap = usize::from(bridge && upto == self.before_gap() && upto < self.held.len());
        for (j, h) in self.held.iter().enumerate().take(upto + gap).rev() {
            let Some(he) = self.carrier(h) else {
                continue;
            };
            if j == upto {
                if let Some(joint) = self.bridged(j, &he, e, seq, r, side) {
                    return Some(joint);
                }
                continue;
            }
            let h_seq = h.seg.source.seq;
            let mut best: Option<(f64, V2)> = None;
            for x in intersections(&he, e) {
                let (Some(u), Some(v)) = (past_end(&he, x), before_start(e, x)) else {
                    continue;
                };
                let (hx, ex) = (he.with_end(x), e.with_start(x));
                if best.is_some_and(|b| b.0 <= u + v)
                    || !self.touches(h_seq, seq, x, r)
                    || !self.touches(seq, h_seq, x, r)
                    || !self.within(h_seq, &hx)
                    || !self.within(seq, &ex)
                    || !self.clear_point(x, r, side)
                    || !self.clear(&hx, r, side)
                    || !self.clear_before(&ex, r, side, seq)
                {
                    continue;
                }
                best = Some((u + v, x));
            }
            if let Some((_, x)) = best {
                // A backward run still held before this segment: its start, where that run
                // ends, is wrong too, so it must be bridged from an earlier joint.
                if bridge && self.held.iter().take(j).any(|h| h.backwards) {
                    if let Some(first) = self.joined_back(j, &he, x, h_seq, r, side) {
                        return Some(Joint {
                            bridge: Some((j, x)),
                            ..first
                        });
                    }
                }
                return Some(Joint {
                    at: j,
                    x,
                    bridge: None,
                });
            }
            if bridge && h.backwards {
                if let Some(joint) = self.bridged(j, &he, e, seq, r, side) {
                    return Some(joint);
                }
            }
        }
        None
    }

    /// Two joints at once for held segment `j`, a backward segment whose own start is wrong
    /// too (the block before it is left out as well): `e` meets (or starts on) its carrier
    /// `he` where the tool touches both, and an earlier held segment joins the carrier before
    /// that point ([`Self::joined`], for an arc within the programmed sweep). The segment
    /// then carries the path between the two (the floor of a pocket narrower than the tool,
    /// between a wall left out and the wall `e` follows).
    fn bridged(&self, j: usize, he: &Elem, e: &Elem, seq: u32, r: f64, side: i8) -> Option<Joint> {
        let h_seq = self.held.get(j)?.seg.source.seq;
        // A tangent transition: `e` starts on the carrier, where no intersection is reliable.
        let on_carrier = match *he {
            Elem::Line { a, b } => (e.start() - a).cross(b - a).abs() <= 1e-9 * a.dist(b),
            Elem::Arc { a, c, .. } => {
                (e.start().dist(c) - a.dist(c)).abs() <= 1e-9 * (1.0 + c.len())
            }
        };
        let mut points: heapless::Vec<V2, 3> = intersections(he, e).into_iter().collect();
        if on_carrier {
            let _ = points.push(e.start());
        }
        let mut best: Option<(f64, Joint)> = None;
        for y in points {
            let Some(v) = before_start(e, y) else {
                continue;
            };
            let ey = e.with_start(y);
            if best.as_ref().is_some_and(|b| b.0 <= v)
                || !self.touches(h_seq, seq, y, r)
                || !self.touches(seq, h_seq, y, r)
                || !self.within(seq, &ey)
                || !self.clear_point(y, r, side)
                || !self.clear_before(&ey, r, side, seq)
            {
                continue;
            }
            if let Some(first) = self.joined_back(j, he, y, h_seq, r, side) {
                let joint = Joint {
                    bridge: Some((j, y)),
                    ..first
                };
                best = Some((v, joint));
            }
        }
        best.map(|(_, joint)| joint)
    }

    /// Where an earlier held segment than `j` joins `he`, the carrier of held segment `j`
    /// (block `h_seq`), lengthened back from `y`: as long as the element (a line), or over
    /// its sweep (an arc within the programmed sweep).
    fn joined_back(
        &self,
        j: usize,
        he: &Elem,
        y: V2,
        h_seq: u32,
        r: f64,
        side: i8,
    ) -> Option<Joint> {
        self.joined(&ending_at(he, y), h_seq, r, side, j, false)
    }

    /// Whether the tool at `x` touches (R from it, tool radius `r`) the element of block
    /// `seq`, or of a block left out between it and `other` that continues it on the same
    /// line or circle (together they are one element).
    fn touches(&self, seq: u32, other: u32, x: V2, r: f64) -> bool {
        let Some(own) = self.own(seq).map(|p| p.elem) else {
            return false;
        };
        let (lo, hi) = if seq.wrapping_sub(other) as i32 <= 0 {
            (seq, other)
        } else {
            (other.wrapping_add(1), seq.wrapping_add(1))
        };
        self.programmed.iter().any(|p| {
            p.source.seq.wrapping_sub(lo) < hi.wrapping_sub(lo)
                && (p.source.seq == seq || same_carrier(&p.elem, &own))
                && dist_point(&p.elem, x) <= r + 1e-6
        })
    }

    /// Whether `path` (on the equidistant of block `seq`) stays within the element's span: a
    /// circle's equidistant is the edge only over the circle's own span; lengthened further,
    /// it runs round the far side, away from the part.
    fn within(&self, seq: u32, path: &Elem) -> bool {
        match (self.own(seq).map(|p| p.elem), *path) {
            (Some(own @ Elem::Arc { c, .. }), Elem::Arc { c: pc, .. }) if c == pc => {
                path.sweep() <= own.sweep() + 1e-9
            }
            _ => true,
        }
    }

    /// Masking where the path leaves the contour (deselection, anything not checked, or the
    /// program's end with compensation on): a backward run still held has no later element
    /// to join; the last segment ends where the retract starts (or in the normal position),
    /// so the path joins into it, lengthened back before its start if need be.
    fn close_before_exit(&mut self) {
        let Some(last) = self.held.iter().rposition(|h| h.backwards) else {
            return;
        };
        let Some(h) = self.held.back().copied() else {
            return;
        };
        let Some(mut e) = h.piece.elem() else {
            return;
        };
        // The last segment itself runs backwards: what counts is its end, the retract's
        // start; the path comes to it along the equidistant in the programmed direction (an
        // arc the tool fits, over the programmed sweep, turned round).
        let own = self.own(h.seg.source.seq).map(|p| p.elem);
        let mut turn = None;
        if h.backwards {
            match (e, own) {
                (Elem::Line { b, .. }, Some(o @ Elem::Line { .. })) => e = ending_at(&o, b),
                (Elem::Arc { b, c, .. }, Some(o @ Elem::Arc { c: oc, ccw, .. }))
                    if h.seg.role == Role::Contour
                        && c == oc
                        && !(ccw == (h.side > 0) && o.radius() <= h.r + 1e-9) =>
                {
                    e = ending_at(&o, b);
                    turn = Some(ccw);
                }
                _ => {}
            }
        }
        let upto = (last + 1).min(self.held.len() - 1).min(self.before_gap());
        if let Some(joint) = self.joined(&e, h.seg.source.seq, h.r, h.side, upto, true) {
            let mut seg = h.seg;
            if let (Some(o), Shape::Arc { ccw, .. }) = (turn, &mut seg.shape) {
                *ccw = o;
            }
            self.cut_loop(joint, &mut seg);
            let piece = PathPiece::plain(self.elem(&seg));
            self.hold(Held {
                seg,
                piece,
                bb: piece.bbox(h.r),
                // Joined: it runs to where the retract starts, backwards or not.
                backwards: false,
                after_gap: false,
                ..h
            });
            self.recount();
        }
    }

    /// What a held segment offers to join along: itself; for a line that runs backwards, its
    /// equidistant from its start on in the programmed direction (the part its trim got
    /// wrong); nothing for an arc that runs backwards or a circle the tool does not fit.
    fn carrier(&self, h: &Held) -> Option<Elem> {
        let e = h.piece.elem()?;
        // An inserted piece (a transition circle or line) is left out only for coming too
        // close inside a backward run's loop: a join may still cut it short.
        if !h.backwards || h.seg.role != Role::Contour {
            return Some(e);
        }
        match (e, self.own(h.seg.source.seq)?.elem) {
            (Elem::Line { a, .. }, Elem::Line { a: pa, b: pb }) => Some(Elem::Line {
                a,
                b: a + (pb - pa),
            }),
            // An arc the tool fits: its equidistant circle from the start on, over the
            // programmed element's sweep in its direction.
            (Elem::Arc { a, c, .. }, own @ Elem::Arc { c: oc, ccw, .. })
                if c == oc && !(ccw == (h.side > 0) && own.radius() <= h.r + 1e-9) =>
            {
                Some(Elem::Arc {
                    a,
                    b: turned(a, c, if ccw { own.sweep() } else { -own.sweep() }),
                    c,
                    ccw,
                })
            }
            _ => None,
        }
    }

    /// Held segments before the first unclosed gap (all when there is none).
    fn before_gap(&self) -> usize {
        self.held
            .iter()
            .position(|h| h.after_gap)
            .unwrap_or(self.held.len())
    }

    /// The programmed element of block `seq`, if still in the window.
    fn own(&self, seq: u32) -> Option<&Programmed> {
        self.programmed.iter().rev().find(|p| p.source.seq == seq)
    }

    /// Whether the tool circle along `path` keeps clear of every programmed element of its
    /// side, its own included.
    fn clear(&self, path: &Elem, r: f64, side: i8) -> bool {
        self.clear_of(path, r, side, |_| true)
    }

    /// [`Self::clear`] against the elements before block `seq`: its own element and what
    /// comes after belong to the next joints and cuts (a corner piece of block `seq` may run
    /// on past where a later joint cuts it), and every segment is checked in full when it
    /// leaves.
    fn clear_before(&self, path: &Elem, r: f64, side: i8, seq: u32) -> bool {
        self.clear_of(path, r, side, |p| {
            (p.source.seq.wrapping_sub(seq) as i32) < 0
        })
    }

    /// Whether the tool circle along `path` keeps clear of the programmed elements of its side
    /// that `among` takes.
    fn clear_of(&self, path: &Elem, r: f64, side: i8, among: impl Fn(&Programmed) -> bool) -> bool {
        let bb = bbox(path, r);
        let path = Measured::new(*path);
        self.programmed
            .iter()
            .filter(|p| p.side == side && among(p) && overlap(&p.bb, &bb))
            .all(|p| too_close(&path, &p.elem, || &p.fence, r).is_none())
    }

    /// Whether the tool circle at `x` keeps clear of every programmed element of its side.
    fn clear_point(&self, x: V2, r: f64, side: i8) -> bool {
        self.programmed
            .iter()
            .filter(|p| p.side == side)
            .all(|p| dist_point(&p.elem, x) >= r - 1e-7)
    }

    /// Masking: the held segment `joint.at` ends at `joint.x`, the ones after it are left
    /// out (but a bridge), and `seg` starts where the joint says.
    fn cut_loop(&mut self, joint: Joint, seg: &mut Segment) {
        let Joint { at: i, x, bridge } = joint;
        let bridge = bridge.and_then(|(k, y)| Some((*self.held.get(k)?, y)));
        while self.held.len() > i + 1 {
            self.held.pop_back();
            self.held_chunks.pop_back();
        }
        let plane = self.plane;
        let own = self
            .held
            .back()
            .and_then(|h| self.own(h.seg.source.seq))
            .map(|p| p.elem);
        if let Some(h) = self.held.back_mut() {
            h.rejoined(plane, None, x, own.as_ref());
            self.held_chunks.regrow_back(&h.bb);
        }
        let mut start = x;
        if let Some((mut h, y)) = bridge {
            let own = self.own(h.seg.source.seq).map(|p| p.elem);
            h.rejoined(plane, Some(x), y, own.as_ref());
            h.after_gap = false;
            self.hold(h);
            start = y;
        }
        seg.from = at(plane, &seg.from, start);
        self.recount();
    }

    /// Preparation stops: what is held is dropped. It has not been checked against the
    /// contour that follows (which stays on the workpiece even though it is not cut), so it
    /// is not known to be clear.
    pub fn discard(&mut self) {
        self.held.clear();
        self.held_chunks.clear();
        self.programmed.clear();
        self.programmed_chunks.clear();
        self.blocks = 0;
        self.last_seq = None;
    }

    /// Everything held goes on (end of compensation or of the program); under masking a run
    /// still held joins the last segment first, and each segment is checked on its way out.
    pub fn flush(
        &mut self,
        out: &mut std::collections::VecDeque<Segment>,
        mask: bool,
    ) -> Result<(), Gouge> {
        if mask {
            self.close_before_exit();
        }
        while !self.held.is_empty() {
            self.release_block(out, mask)?;
        }
        self.blocks = 0;
        self.last_seq = None;
        Ok(())
    }

    /// The oldest block's segments go on; under masking, after the distance check.
    fn release_block(
        &mut self,
        out: &mut std::collections::VecDeque<Segment>,
        mask: bool,
    ) -> Result<(), Gouge> {
        let Some(seq) = self.held.front().map(|h| h.seg.source.seq) else {
            return Ok(());
        };
        // Read in place and copied once, into `out` (a held record is large).
        while let Some(h) = self.held.front().filter(|h| h.seg.source.seq == seq) {
            // Masking: a segment left over from what should have been left out (a gap not
            // closed, or a piece that runs backwards, away from the part) never goes out.
            if h.after_gap || h.backwards {
                return Err(Gouge {
                    path: h.seg.source,
                    element: h.seg.source,
                    distance: 0.0,
                    radius: h.r,
                    unjoined: true,
                });
            }
            if mask {
                self.check(h)?;
            }
            out.push_back(h.seg);
            self.held.pop_front();
            self.held_chunks.pop_front();
        }
        self.blocks = self.blocks.saturating_sub(1);
        Ok(())
    }

    /// A held segment against the programmed elements in the window.
    fn check(&self, h: &Held) -> Result<(), Gouge> {
        // Its own element too: a masked path may hold a piece of a block whose element the
        // tool does not fit (a corner before a circle smaller than the tool).
        match self.first_gouge(h.seg.source, &h.piece, h.r, h.side, &h.bb, true) {
            Some(g) => Err(g),
            None => Ok(()),
        }
    }

    /// The first programmed element in the window (of the same side, not the path's own
    /// block unless `own`) that the path piece of block `path` comes too close to.
    fn first_gouge(
        &self,
        path: crate::segment::Source,
        piece: &PathPiece,
        r: f64,
        side: i8,
        bb: &[f64; 4],
        own: bool,
    ) -> Option<Gouge> {
        debug_assert_eq!(self.programmed_chunks.records(), self.programmed.len());
        for range in self.programmed_chunks.near(bb) {
            let from = range.start;
            let found = self.programmed.range(range).enumerate().find_map(|(i, p)| {
                if p.side != side || (!own && near(p.source.seq, path.seq)) || !overlap(&p.bb, bb) {
                    return None;
                }
                let (distance, radius) = piece.too_close(&p.elem, || &p.fence, r)?;
                // A lead of a closed contour is no surface (its own block's piece still is).
                if p.source.seq != path.seq && self.lead(from + i) {
                    return None;
                }
                Some(Gouge {
                    path,
                    element: p.source,
                    distance,
                    radius,
                    unjoined: false,
                })
            });
            if found.is_some() {
                return found;
            }
        }
        None
    }

    /// The oldest programmed element leaves the window (and its chunk, once it has none).
    fn pop_programmed(&mut self) {
        self.programmed.pop_front();
        self.programmed_chunks.pop_front();
    }

    /// A segment comes into the window.
    fn hold(&mut self, h: Held) {
        self.held_chunks.push(&h.bb);
        self.held.push_back(h);
    }

    /// Whether programmed element `j` is a lead-in or lead-out of a contour that closes in the
    /// window (prep/leads.rs). Decided when a violation is found, with what the window holds:
    /// a loop closed later, or wider than the window, is left to the whole-program check.
    #[inline(never)]
    fn lead(&self, j: usize) -> bool {
        let span = span_of(self.programmed.iter().map(|p| &p.elem));
        !part_of(span, j as u32 + 1)
    }

    fn recount(&mut self) {
        let mut blocks = 0;
        let mut last = None;
        for h in self.held.iter() {
            if last != Some(h.seg.source.seq) {
                blocks += 1;
                last = Some(h.seg.source.seq);
            }
        }
        self.blocks = blocks;
        self.last_seq = last;
    }

    fn elem(&self, s: &Segment) -> Option<Elem> {
        elem_in(s, self.plane)
    }

    /// True when nothing is held.
    pub fn is_empty(&self) -> bool {
        self.held.is_empty()
    }
}

/// The distance from a path element to a programmed one when it is below the tool radius
/// (beyond rounding). The cheap test by the element's ends settles most pairs that share a
/// corner; the rest get the exact distance.
#[inline]
fn too_close<'f>(
    path: &Measured,
    elem: &Elem,
    fence: impl FnOnce() -> &'f Fence,
    r: f64,
) -> Option<f64> {
    too_close_by(path, gouge_tol(&path.e), elem, eta_of(elem), fence, r)
}

/// [`too_close`] with the path's [`gouge_tol`] and the element's [`eta_of`] worked out before.
#[inline]
fn too_close_by<'f>(
    path: &Measured,
    tol: f64,
    elem: &Elem,
    elem_eta: f64,
    fence: impl FnOnce() -> &'f Fence,
    r: f64,
) -> Option<f64> {
    let limit = r - tol;
    let sure = limit.max(0.0) + margin(path, elem_eta);
    if circles_clear(path, elem, sure)
        || clear_by_ends_of(path, elem, fence(), limit)
        || arcs_clear(path, elem, sure)
    {
        return None;
    }
    let d = dist_elems(&path.e, elem);
    (d < limit).then_some(d)
}

/// A path segment and its own element: R apart by construction (an equidistant). Neighbours
/// are checked: an arc that curls back over the element before it is not caught by the
/// corner construction.
fn near(a: u32, b: u32) -> bool {
    a == b
}

/// A path arc about a fixed centre whose radius changes linearly with the angle: the
/// equidistant of a programmed arc while the tool radius changes over the block (a D change
/// over an arc: 808D and Fanuc spread it over the block). The tool radius at each point is the
/// point's distance from the programmed circle. The gouge test is the definition itself,
/// f(u) = dist(P(u), E) − R(u) ≥ 0, shown by bisection: f changes by at most L·|Δu|
/// (L = |P′| + |R′| at most), so an interval whose ends are high enough is clear, and a point
/// below −tol is a gouge.
#[derive(Clone, Copy, Debug)]
pub(super) struct Spiral {
    c: V2,
    r0: f64,
    dr: f64,
    th0: f64,
    /// Signed: positive counter-clockwise.
    sweep: f64,
    /// Radius of the programmed circle.
    rho: f64,
}

impl Spiral {
    /// The spiral of a path segment whose programmed element `own` is an arc about the same
    /// centre; `None` for anything else.
    pub(super) fn new(s: &Segment, plane: Plane, own: &Elem) -> Option<Spiral> {
        let Shape::Arc {
            center,
            center_end,
            plane: p,
            ..
        } = s.shape
        else {
            return None;
        };
        let Elem::Arc { a, c: pc, .. } = *own else {
            return None;
        };
        let uv = |q: &Pos| v2(q[plane.abscissa as usize], q[plane.ordinate as usize]);
        let c = uv(&center);
        let scale = c.x.abs().max(c.y.abs()).max(1.0);
        if p != plane || center != center_end || c.dist(pc) > 1e-9 * scale {
            return None;
        }
        let Some(crate::segment::Curve::Arc {
            r0, dr, th0, sweep, ..
        }) = crate::segment::Curve::new(s)
        else {
            return None;
        };
        Some(Spiral {
            c,
            r0,
            dr,
            th0,
            sweep,
            rho: a.dist(pc),
        })
    }

    /// The point at u and the tool radius there.
    fn at(&self, u: f64) -> (V2, f64) {
        let r = self.r0 + self.dr * u;
        let th = self.th0 + self.sweep * u;
        (
            v2(self.c.x + r * libm::cos(th), self.c.y + r * libm::sin(th)),
            (r - self.rho).abs(),
        )
    }

    fn r_max(&self) -> f64 {
        self.r0.max(self.r0 + self.dr)
    }

    /// The whole circle of the largest radius, grown by the largest tool radius.
    pub(super) fn bbox(&self) -> [f64; 4] {
        let g = self.r_max()
            + (self.r0 - self.rho)
                .abs()
                .max((self.r0 + self.dr - self.rho).abs());
        [self.c.x - g, self.c.y - g, self.c.x + g, self.c.y + g]
    }

    /// Where the tool circle comes closer to `e` than its radius (beyond rounding): the
    /// distance there and the tool radius.
    fn too_close(&self, e: &Elem) -> Option<(f64, f64)> {
        let tol = gouge_tol(e).max(1e-12 * self.r_max());
        let l = self.dr.hypot(self.r_max() * self.sweep) + self.dr.abs();
        let f = |u: f64| {
            let (p, r) = self.at(u);
            let d = dist_point(e, p);
            (d - r, d, r)
        };
        let (fa, da, ra) = f(0.0);
        if fa < -tol {
            return Some((da, ra));
        }
        let (fb, db, rb) = f(1.0);
        if fb < -tol {
            return Some((db, rb));
        }
        // Depth first; an interval this short is within rounding of its ends. A stretch in
        // contact (f = 0 all along: the same circle as another element, at exactly R) is
        // never shown clear by the bound; the budget ends the search there: contact is no
        // gouge.
        let mut todo: heapless::Vec<(f64, f64, f64, f64), 64> = heapless::Vec::new();
        let _ = todo.push((0.0, fa, 1.0, fb));
        let mut budget = 4096;
        while let Some((a, fa, b, fb)) = todo.pop() {
            if (fa + fb - l * (b - a)) / 2.0 >= -tol || b - a < 1e-13 {
                continue;
            }
            budget -= 1;
            if budget == 0 {
                break;
            }
            let m = 0.5 * (a + b);
            let (fm, dm, rm) = f(m);
            if fm < -tol {
                return Some((dm, rm));
            }
            if todo.push((m, fm, b, fb)).is_err() || todo.push((a, fa, m, fm)).is_err() {
                // Deeper than any interval of width 1e-13 needs: not reached.
                continue;
            }
        }
        None
    }
}

/// A contour segment that runs against its programmed element (an element shorter than
/// the trim of its corners; under masking the compensator puts such an arc out reversed).
/// A circle the tool does not fit into (radius `r`, side +1 left) is left out whichever way
/// its path runs.
fn runs_backwards(role: Role, path: &Elem, own: Option<&Elem>, r: f64, side: i8) -> bool {
    role == Role::Contour
        && match (*path, own) {
            (Elem::Line { a, b }, Some(&Elem::Line { a: pa, b: pb })) => (b - a).dot(pb - pa) < 0.0,
            (Elem::Arc { ccw, .. }, Some(o @ &Elem::Arc { ccw: own, .. })) => {
                ccw != own || (own == (side > 0) && o.radius() <= r + 1e-9)
            }
            _ => false,
        }
}

/// `p` turned about `c` by `phi` (counter-clockwise for phi > 0).
fn turned(p: V2, c: V2, phi: f64) -> V2 {
    let (u, (sn, cs)) = (p - c, (libm::sin(phi), libm::cos(phi)));
    c + v2(u.x * cs - u.y * sn, u.x * sn + u.y * cs)
}

/// The element like `like` (a line of its direction and length, or an arc about its centre,
/// of its direction and sweep) that ends at `y`, a point of its line or circle.
fn ending_at(like: &Elem, y: V2) -> Elem {
    match *like {
        Elem::Line { a, b } => Elem::Line {
            a: y - (b - a),
            b: y,
        },
        Elem::Arc { c, ccw, .. } => Elem::Arc {
            a: turned(y, c, if ccw { -like.sweep() } else { like.sweep() }),
            b: y,
            c,
            ccw,
        },
    }
}

/// Whether two elements lie on one line, or on one circle (to rounding).
fn same_carrier(p: &Elem, q: &Elem) -> bool {
    let on = |x: V2, a: V2, b: V2| {
        let d = b - a;
        (x - a).cross(d).abs() <= 1e-9 * d.len() * (1.0 + x.len().max(a.len()))
    };
    match (*p, *q) {
        (Elem::Line { a, b }, Elem::Line { a: qa, b: qb }) => on(a, qa, qb) && on(b, qa, qb),
        (Elem::Arc { a, c, .. }, Elem::Arc { a: qa, c: qc, .. }) => {
            let tol = 1e-9 * (1.0 + c.len().max(qc.len()));
            c.dist(qc) <= tol && (a.dist(c) - qa.dist(qc)).abs() <= tol
        }
        _ => false,
    }
}

/// How far `e` must be lengthened past its end to reach `x`, a point of its line or circle
/// (0 when `x` lies on it; `None` behind its start).
fn past_end(e: &Elem, x: V2) -> Option<f64> {
    match *e {
        Elem::Line { a, b } => {
            let len = a.dist(b);
            let t = (x - a).dot(b - a) / len;
            (t >= -1e-9).then(|| (t - len).max(0.0))
        }
        Elem::Arc { b, c, ccw, .. } => Some(beyond(e, sweep(c, b, x, ccw))),
    }
}

/// How far `e` must be lengthened back before its start to reach `x` (0 when `x` lies on
/// it; `None` past its end).
fn before_start(e: &Elem, x: V2) -> Option<f64> {
    match *e {
        Elem::Line { a, b } => {
            let len = a.dist(b);
            let t = (x - a).dot(b - a) / len;
            (t <= len + 1e-9).then(|| (-t).max(0.0))
        }
        Elem::Arc { a, c, ccw, .. } => Some(beyond(e, sweep(c, x, a, ccw))),
    }
}

/// An arc lengthened by the angle `phi` (from its end onwards, or from its start back): the
/// length added, 0 where the angle lands on the arc itself.
fn beyond(e: &Elem, phi: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    if phi >= tau - 1e-12 || phi > tau - e.sweep() {
        0.0
    } else {
        phi * e.radius()
    }
}

/// `p` with its plane coordinates replaced by `x`.
fn at(plane: Plane, p: &Pos, x: V2) -> Pos {
    let mut q = *p;
    q[plane.abscissa as usize] = x.x;
    q[plane.ordinate as usize] = x.y;
    q
}

/// A segment as a plane element; `None` for what cannot cross (no move in the plane) or is
/// not a circle (an arc whose radius changes on purpose — a radius change spread over the
/// block — is a [`Spiral`]; radii equal but for rounding are one circle).
fn uv(p: &Pos, plane: Plane) -> V2 {
    v2(p[plane.abscissa as usize], p[plane.ordinate as usize])
}

// Inlined into its callers: an element returned through memory is written a coordinate at a
// time and read a point at a time, and every such read waits for the stores (docs/benchmarks.md).
#[inline(always)]
pub(super) fn elem_in(s: &Segment, plane: Plane) -> Option<Elem> {
    let (a, b) = (uv(&s.from, plane), uv(&s.to, plane));
    match s.shape {
        Shape::Line => longer_than_1e9(b - a).then_some(Elem::Line { a, b }),
        Shape::Arc {
            center,
            center_end,
            ccw,
            r0,
            r1,
            plane: p,
        } => (p == plane
            && center == center_end
            && (r0 - r1).abs() <= 1e-9 * center[0].abs().max(center[1].abs()).max(r0).max(1.0))
        .then(|| Elem::Arc {
            a,
            b,
            c: uv(&center, plane),
            ccw,
        }),
    }
}

/// Whether `d` is longer than 1e-9 mm: `d.len() > 1e-9`, with the root taken only near the
/// limit (above twice its square the length is surely longer, below half surely not).
#[inline]
fn longer_than_1e9(d: V2) -> bool {
    let l2 = d.dot(d);
    l2 > 2e-18 || (l2 > 0.5e-18 && l2.sqrt() > 1e-9)
}

/// Bounding box of an element in the plane, grown by `grow`: the whole circle for an arc
/// (cheap, and enough for a pre-filter).
pub(super) fn bbox(e: &Elem, grow: f64) -> [f64; 4] {
    let b = match *e {
        Elem::Line { a, b } => [a.x.min(b.x), a.y.min(b.y), a.x.max(b.x), a.y.max(b.y)],
        Elem::Arc { a, c, .. } => {
            let r = a.dist(c);
            [c.x - r, c.y - r, c.x + r, c.y + r]
        }
    };
    [b[0] - grow, b[1] - grow, b[2] + grow, b[3] + grow]
}

/// How far apart two boxes may lie and still meet in `overlap`.
pub(super) const OVERLAP_TOL: f64 = 1e-7;

pub(super) fn overlap(p: &[f64; 4], q: &[f64; 4]) -> bool {
    let t = OVERLAP_TOL;
    p[0] <= q[2] + t && q[0] <= p[2] + t && p[1] <= q[3] + t && q[1] <= p[3] + t
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::segment::Source;
    use proptest::prelude::*;

    proptest! {
        /// The length test takes the root only near the limit and decides as the root does,
        /// near the limit (lengths within a factor of two of it) and far from it.
        #[test]
        fn longer_than_1e9_decides_as_the_length_does(
            l in prop_oneof![0.5e-9..2e-9f64, 0.0..1e-3f64], angle in 0.0..6.3f64
        ) {
            let d = v2(l * libm::cos(angle), l * libm::sin(angle));
            prop_assert_eq!(longer_than_1e9(d), d.len() > 1e-9);
        }
    }

    /// Block `seq`, on line `seq` (the whole check's tests take it too).
    pub(in crate::prep) fn src(seq: u32) -> Source {
        Source {
            number: None,
            line: seq,
            col: 1,
            seq,
            program: 0,
        }
    }

    pub(in crate::prep) fn line(a: (f64, f64), b: (f64, f64)) -> Elem {
        Elem::Line {
            a: v2(a.0, a.1),
            b: v2(b.0, b.1),
        }
    }

    /// Block 1: the quarter circle r 50 about the origin, clockwise from (50, 0) to
    /// (0, −50), cut on its outside while the tool radius grows from 5 to 10 over it (a D
    /// change over an arc): the path is the spiral from radius 55 to 60. Block 2 leaves
    /// (0, −50) westwards. The blocks' elements with their tool radii, and block 1's path
    /// (the whole check's tests take it too).
    pub(in crate::prep) fn spiral_case() -> ([(u32, Elem, f64); 2], Segment) {
        let arc = Elem::Arc {
            a: v2(50.0, 0.0),
            b: v2(0.0, -50.0),
            c: v2(0.0, 0.0),
            ccw: false,
        };
        let spiral = Segment {
            source: src(1),
            role: Role::Contour,
            shape: Shape::Arc {
                center: [0.0; 3],
                center_end: [0.0; 3],
                ccw: false,
                r0: 55.0,
                r1: 60.0,
                plane: Plane::XY,
            },
            from: [55.0, 0.0, 0.0],
            to: [0.0, -60.0, 0.0],
            feed: 1000.0,
            per_rev: false,
            thread: false,
            rapid: false,
            exact_stop: false,
        };
        let elements = [(1, arc, 5.0), (2, line((0.0, -50.0), (-40.0, -50.0)), 10.0)];
        (elements, spiral)
    }

    /// The spiral case with block 3 `third`: the window must measure the spiral's tool
    /// circle, of the radius at each point, against it.
    fn spiral_against(third: Elem) -> Result<(), Gouge> {
        let mut b = Bottleneck::new(3);
        let mut out = std::collections::VecDeque::new();
        let (elements, spiral) = spiral_case();
        for (seq, e, r) in elements {
            b.element(src(seq), e, r, 1, Reaction::Alarm)?;
        }
        b.push(spiral, Reaction::Alarm, &mut out)?;
        b.element(src(3), third, 10.0, 1, Reaction::Alarm)
            .map(|_| ())
    }

    #[test]
    fn a_spiral_is_checked_with_the_tool_radius_at_each_point() {
        // A line 65 below the centre: at the spiral's end (0, −60) the tool (radius 10)
        // reaches 5 mm past it; with the start radius 5 it would not.
        let g = spiral_against(line((-40.0, -65.0), (40.0, -65.0))).unwrap_err();
        assert_eq!((g.path.seq, g.element.seq), (1, 3));
        assert!(
            (g.distance - 5.0).abs() < 1e-9 && (g.radius - 10.0).abs() < 1e-12,
            "{g:?}"
        );
        // 75 below: 5 mm to spare at the end, more before it.
        spiral_against(line((-40.0, -75.0), (40.0, -75.0))).unwrap();
        // Half way along (−45°) the spiral is at radius 57.5 with tool radius 7.5; a short
        // line across the radius at 63 from the centre is 5.5 from it: found by bisection.
        let (c, s) = (
            std::f64::consts::FRAC_1_SQRT_2,
            -std::f64::consts::FRAC_1_SQRT_2,
        );
        let at = |r: f64, t: f64| (r * c - t * s, r * s + t * c);
        let g = spiral_against(line(at(63.0, -3.0), at(63.0, 3.0))).unwrap_err();
        assert!(
            (g.distance - 5.5).abs() < 1e-9 && (g.radius - 7.5).abs() < 1e-12,
            "{g:?}"
        );
        // The same line at 70: 12.5 from the spiral's middle, and farther from the rest.
        spiral_against(line(at(70.0, -3.0), at(70.0, 3.0))).unwrap();
    }
}
