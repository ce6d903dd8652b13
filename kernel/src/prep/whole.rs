//! The whole-program check: every tool-centre segment of a compensation run against every
//! programmed element of the same run, wherever in the program it lies (840C 11.12 checks
//! three blocks, the bottleneck window a few dozen; softnc prepares a program far faster
//! than the machine runs it, so it can know the whole run before the first cut).
//!
//! The definition is the window's (prep/bottleneck.rs): the tool circle along a segment
//! must stay at least R from every programmed element of its side, its own block's element
//! aside (an equidistant is R from it by construction); a radius change over an arc is
//! checked with the radius at each point. What differs is the reach: when a run is complete
//! its elements, in their order along the contour, go into a tree of boxes (a leaf holds a
//! few consecutive elements and the segments of their blocks), and the tree is walked against
//! itself: a pair of subtrees whose boxes are apart is left, so neighbours along the contour
//! meet in a leaf or one level up, and a part of the contour that comes back near another
//! meets it where their boxes overlap — a cost close to linear in the length of the program.
//! Where preparation runs in two threads, the thread that takes the path walks the complete
//! part of a run while it waits for the front ([`WholeCheck::walk_some`]), so that the end of
//! the run finds less left to walk.
//! Under ISG masking the segments checked are the masked path (the window's output).

use super::bottleneck::{elem_in, Gouge, PathPiece, Spiral};
use super::leads::{part_of, Closure, Span};
use crate::frontend::block::{BlockNo, Plane};
use crate::segment::{Role, Segment, Source};
use crate::trc::geom::{bounds, eta_of, Elem, Fence, Measured, V2};
use core::sync::atomic::{AtomicUsize, Ordering};

/// The most blocks [`WholeCheck::reserve`] makes room for (about 300 MB of address space).
const RESERVE_BLOCKS: usize = 1 << 20;

/// Consecutive elements a leaf of the tree holds (and the segments of their blocks): few, so
/// a leaf meets its neighbour in a few box tests, and not fewer, which makes more nodes to
/// build, visit and keep (8 against 4: 4 % less CPU for the check, docs/benchmarks.md).
const LEAF: usize = 8;

/// A programmed element as the run keeps it, in 32 bytes: its block's place in execution
/// order and line (the rest of the block's [`Source`] in `Tables::blocks` where it is not as
/// the blocks before lead to expect), its end (it starts where the one before it ends, or —
/// the top bit of `tool` — at its entry in `Tables::element_starts`), what it is, its tool
/// radius and side by an index (they change seldom). Its box is worked out again where the
/// walk meets its leaf ([`BoxCache`]), and its [`Fence`] only for a pair that needs it.
/// Small, because a long run keeps every one, and memory first written costs 0.5–0.7 ms a
/// megabyte on the benchmark machine (docs/benchmarks.md).
#[derive(Clone, Copy, Debug)]
struct Element {
    seq: u32,
    line: u32,
    b: V2,
    kind: Kind,
    /// Its tool radius and side: an entry of `Tables::tools` (and `APART`).
    tool: u32,
}

/// An element that does not start where the one before it ends.
const APART: u32 = 1 << 31;

/// A tool-centre segment as the run keeps it, in 24 bytes: its end (it starts where the one
/// before it ends, or — `Block::APART` — at its entry in `Tables::segment_starts`), what it is
/// and its block (its box is worked out again where the walk meets its leaf: [`BoxCache`]).
#[derive(Clone, Copy, Debug)]
struct PathSegment {
    b: V2,
    kind: Kind,
    block: Block,
}

/// What a record's piece is, in four bytes beside its ends: a line, an arc (its centre an
/// entry of `Tables::centres` — or, for a path arc, a point of its block's element: a
/// corner's arc turns about the corner, an arc's equidistant about the arc's centre — and
/// its direction), or — rare: a radius change over an arc — a spiral (an entry of
/// `Tables::spirals`, which holds all of it). The kind in the top two bits, the index below
/// them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Kind(u32);

impl Kind {
    const LINE: Kind = Kind(3 << 30);
    const INDEX: u32 = (1 << 30) - 1;

    /// A path arc's centre: its element's start, end or centre (indices no table reaches).
    const ABOUT_START: u32 = Self::INDEX;
    const ABOUT_END: u32 = Self::INDEX - 1;
    const ABOUT_CENTRE: u32 = Self::INDEX - 2;

    fn arc(centre: usize, ccw: bool) -> Kind {
        Kind(centre as u32 & Self::INDEX | u32::from(ccw) << 30)
    }

    fn arc_about(point: u32, ccw: bool) -> Kind {
        Kind(point | u32::from(ccw) << 30)
    }

    fn spiral(i: usize) -> Kind {
        Kind(i as u32 & Self::INDEX | 2 << 30)
    }

    fn index(self) -> usize {
        (self.0 & Self::INDEX) as usize
    }

    fn spiral_index(self) -> Option<usize> {
        (self.0 >> 30 == 2).then(|| self.index())
    }
}

/// A path segment's block, and so its tool radius and side: almost always the block of an
/// element of the run (its index), otherwise (the top bit) an entry of `Tables::orphans`; the
/// next bit tells a segment that does not start where the one before it ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Block(u32);

impl Block {
    const ORPHAN: u32 = 1 << 31;
    const APART: u32 = 1 << 30;
    const INDEX: u32 = Self::APART - 1;

    fn own(k: usize) -> Block {
        Block(k as u32 & Self::INDEX)
    }

    fn orphan(i: usize) -> Block {
        Block(i as u32 & Self::INDEX | Self::ORPHAN)
    }

    fn index(self) -> usize {
        (self.0 & Self::INDEX) as usize
    }

    /// The element's index, for a block that has one.
    fn own_index(self) -> Option<usize> {
        (self.0 & Self::ORPHAN == 0).then_some(self.index())
    }
}

/// Bit for bit the same point (a record that starts there needs no start of its own).
fn same(p: V2, q: V2) -> bool {
    p.x.to_bits() == q.x.to_bits() && p.y.to_bits() == q.y.to_bits()
}

/// Whether record `i`, starting at `a` after a record that ends at `prev`, needs a start of
/// its own; if so, it goes into `starts` (record, start; in order).
fn starts_apart(prev: Option<V2>, a: V2, i: usize, starts: &mut Vec<(u32, V2)>) -> bool {
    let apart = prev.is_none_or(|p| !same(p, a));
    if apart {
        starts.push((i as u32, a));
    }
    apart
}

/// Where record `i` starts: where the one before it ends (`prev`), or, `apart`, at its entry
/// in `starts`.
#[inline]
fn start_of(apart: bool, prev: impl FnOnce() -> V2, starts: &[(u32, V2)], i: usize) -> V2 {
    if !apart {
        return prev();
    }
    let k = starts.partition_point(|&(j, _)| (j as usize) < i);
    starts[k].1
}

/// The part of an element's [`Source`] that the element does not keep: where it is not as
/// the entry before predicts (the same column and file, the block number counted on by
/// `step` for each block in execution order), it has an entry of its own in `Tables::blocks`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BlockTail {
    col: u32,
    number: Option<BlockNo>,
    program: u16,
    /// What the block number grows by from one block to the next (learnt from the second
    /// element of the entry).
    step: u32,
}

impl BlockTail {
    fn of(s: &Source) -> BlockTail {
        BlockTail {
            col: s.col,
            number: s.number,
            program: s.program,
            step: 0,
        }
    }

    /// The source of block `seq` on `line`, `seq - seq0` blocks after this entry's element.
    fn source(&self, seq0: u32, seq: u32, line: u32) -> Source {
        let ahead = seq.wrapping_sub(seq0);
        Source {
            number: self.number.map(|n| BlockNo {
                value: n.value.wrapping_add(self.step.wrapping_mul(ahead)),
                digits: n.digits,
            }),
            line,
            col: self.col,
            seq,
            program: self.program,
        }
    }

    /// The step that leads from this entry (block `seq0`) to `s`, if a whole one does.
    fn step_to(&self, seq0: u32, s: &Source) -> Option<u32> {
        let (Some(n0), Some(n)) = (self.number, s.number) else {
            return None;
        };
        let ahead = s.seq.wrapping_sub(seq0);
        let grown = n.value.wrapping_sub(n0.value);
        (ahead > 0 && grown % ahead == 0).then(|| grown / ahead)
    }
}

/// A path segment whose block has no element of the run: what the element would tell.
#[derive(Clone, Copy, Debug)]
struct Orphan {
    source: Source,
    r: f64,
    side: i8,
}

/// What the records of a run point to: arcs' centres, the tool radii and sides of its
/// elements, the segments of blocks without an element, the spirals.
#[derive(Default)]
struct Tables {
    centres: Vec<V2>,
    tools: Vec<(f64, i8)>,
    orphans: Vec<Orphan>,
    spirals: Vec<Spiral>,
    element_starts: Vec<(u32, V2)>,
    segment_starts: Vec<(u32, V2)>,
    /// The rest of the elements' sources: an entry (element, tail) where the prediction from
    /// the one before fails (for a program of plain lines, one for the run).
    blocks: Vec<(u32, BlockTail)>,
}

impl Tables {
    fn clear(&mut self) {
        self.centres.clear();
        self.tools.clear();
        self.orphans.clear();
        self.spirals.clear();
        self.element_starts.clear();
        self.segment_starts.clear();
        self.blocks.clear();
    }

    /// Keeps what element `elements.len()` (to come) does not of its block's `source`.
    fn keep_block(&mut self, elements: &[Element], source: &Source) {
        if let Some((j, tail)) = self.blocks.last_mut() {
            let seq0 = elements[*j as usize].seq;
            if tail.source(seq0, source.seq, source.line) == *source {
                return;
            }
            // The entry's second element teaches it its block number step.
            let second = *j as usize + 1 == elements.len() && tail.step == 0;
            if let Some(step) = tail.step_to(seq0, source).filter(|_| second) {
                let learnt = BlockTail { step, ..*tail };
                if learnt.source(seq0, source.seq, source.line) == *source {
                    *tail = learnt;
                    return;
                }
            }
        }
        let k = elements.len() as u32;
        self.blocks.push((k, BlockTail::of(source)));
    }

    /// The source of element `k`'s block.
    fn source(&self, elements: &[Element], k: usize) -> Source {
        let i = self.blocks.partition_point(|&(j, _)| j as usize <= k);
        let e = &elements[k];
        match i.checked_sub(1).map(|i| self.blocks[i]) {
            Some((j, tail)) => tail.source(elements[j as usize].seq, e.seq, e.line),
            None => Source {
                seq: e.seq,
                line: e.line,
                ..Source::default()
            },
        }
    }

    /// `e` as a record keeps it: its ends and kind (an arc's centre goes into the table).
    fn pack(&mut self, e: &Elem) -> (V2, V2, Kind) {
        match *e {
            Elem::Line { a, b } => (a, b, Kind::LINE),
            Elem::Arc { a, b, c, ccw } => {
                // Indices wrap at 2^30 like the blocks' (a run of a billion arcs is some 16 GB
                // of centres); the last three name an element's points.
                debug_assert!(self.centres.len() < Kind::ABOUT_CENTRE as usize);
                self.centres.push(c);
                (a, b, Kind::arc(self.centres.len() - 1, ccw))
            }
        }
    }

    /// A path segment `e` of the block of element `own`, as its record keeps it: an arc's
    /// centre goes into the table only where it is no point of that element.
    fn pack_segment(
        &mut self,
        e: &Elem,
        elements: &[Element],
        own: Option<usize>,
    ) -> (V2, V2, Kind) {
        let (Elem::Arc { a, b, c, ccw }, Some(k)) = (*e, own) else {
            return self.pack(e);
        };
        let arc = elements[k].kind != Kind::LINE;
        let about = [Kind::ABOUT_START, Kind::ABOUT_END, Kind::ABOUT_CENTRE]
            .into_iter()
            .filter(|&p| p != Kind::ABOUT_CENTRE || arc)
            .find(|&p| same(c, self.element_point(elements, k, p)));
        match about {
            Some(p) => (a, b, Kind::arc_about(p, ccw)),
            None => self.pack(e),
        }
    }

    /// Point `about` (`Kind::ABOUT_*`) of element `k`: its start, its end, or its centre (an
    /// arc's: a path arc is packed about it only then).
    #[inline(always)]
    fn element_point(&self, elements: &[Element], k: usize, about: u32) -> V2 {
        match about {
            Kind::ABOUT_START => self.element_start(elements, k),
            Kind::ABOUT_END => elements[k].b,
            _ => self.centres[elements[k].kind.index()],
        }
    }

    /// Segment `seg`'s line or arc (not a spiral), starting at `a`.
    #[inline(always)]
    fn segment_elem(&self, elements: &[Element], seg: &PathSegment, a: V2) -> Elem {
        let i = seg.kind.index() as u32;
        if seg.kind == Kind::LINE || i < Kind::ABOUT_CENTRE {
            return self.elem(a, seg.b, seg.kind);
        }
        // Only a segment of a block with an element is packed about it.
        Elem::Arc {
            a,
            b: seg.b,
            c: self.element_point(elements, seg.block.index(), i),
            ccw: seg.kind.0 >> 30 == 1,
        }
    }

    /// The line or arc a record keeps (not a spiral).
    #[inline]
    fn elem(&self, a: V2, b: V2, kind: Kind) -> Elem {
        match kind.0 >> 30 {
            3 => Elem::Line { a, b },
            ccw => Elem::Arc {
                a,
                b,
                c: self.centres[kind.index()],
                ccw: ccw == 1,
            },
        }
    }

    /// The index of tool radius `r` and `side`: the last entry, or a new one.
    fn tool(&mut self, r: f64, side: i8) -> u32 {
        if self.tools.last() != Some(&(r, side)) {
            self.tools.push((r, side));
        }
        self.tools.len() as u32 - 1
    }

    /// Element `k` of `elements`.
    #[inline]
    fn element(&self, elements: &[Element], k: usize) -> Elem {
        let e = &elements[k];
        self.elem(self.element_start(elements, k), e.b, e.kind)
    }

    /// Where element `k` of `elements` starts.
    #[inline]
    fn element_start(&self, elements: &[Element], k: usize) -> V2 {
        let apart = elements[k].tool & APART != 0;
        start_of(apart, || elements[k - 1].b, &self.element_starts, k)
    }

    fn element_tool(&self, e: &Element) -> (f64, i8) {
        self.tools[(e.tool & !APART) as usize]
    }

    /// Segment `s` of `segments` (of the run of `elements`) as the window measures it.
    #[inline]
    fn piece(&self, elements: &[Element], segments: &[PathSegment], s: usize) -> PathPiece {
        match segments[s].kind.spiral_index() {
            Some(i) => PathPiece::Spiral(self.spirals[i]),
            None => PathPiece::Plain(Measured::new(self.segment(elements, segments, s))),
        }
    }

    /// Segment `s` of `segments`, a line or an arc.
    #[inline(always)]
    fn segment(&self, elements: &[Element], segments: &[PathSegment], s: usize) -> Elem {
        let seg = &segments[s];
        let apart = seg.block.0 & Block::APART != 0;
        let a = start_of(apart, || segments[s - 1].b, &self.segment_starts, s);
        self.segment_elem(elements, seg, a)
    }
}

/// The boxes under a node of the tree: of the path segments (each grown by its tool radius)
/// and of the programmed elements.
#[derive(Clone, Copy, Debug)]
struct Node {
    path: Bx,
    elements: Bx,
}

/// A box of the walk: single precision, grown by the window's overlap tolerance, so that it
/// meets every box the window's test (`bottleneck::overlap`) would and the walk reads half
/// the memory. Which pairs it lets through decides only how many go on to the
/// exact test, never a result.
type Bx = [f32; 4];

/// The empty box: every union leaves it, no overlap meets it.
const NOTHING: Bx = [
    f32::INFINITY,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
];

/// `b` as the walk keeps it: grown by the window's tolerance on every side, then rounded to
/// single precision. Rounding to nearest keeps the order of any two numbers (and a coordinate
/// beyond single precision's range becomes infinite), so two kept boxes meet wherever the
/// window's test lets their f64 boxes meet.
fn kept_box(b: &[f64; 4]) -> Bx {
    const TOL: f64 = super::bottleneck::OVERLAP_TOL;
    let (lo, hi) = (|x: f64| (x - TOL) as f32, |x: f64| (x + TOL) as f32);
    [lo(b[0]), lo(b[1]), hi(b[2]), hi(b[3])]
}

/// Whether two boxes of the walk meet.
#[inline]
fn meets(p: &Bx, q: &Bx) -> bool {
    p[0] <= q[2] && q[0] <= p[2] && p[1] <= q[3] && q[1] <= p[3]
}

fn grow(bb: &mut Bx, by: &Bx) {
    *bb = [
        bb[0].min(by[0]),
        bb[1].min(by[1]),
        bb[2].max(by[2]),
        bb[3].max(by[3]),
    ];
}

/// Part of the walk, done by one worker at a time: a subtree against itself, or two subtrees
/// of one level against each other (by level and index).
#[derive(Clone, Copy, Debug)]
enum Task {
    Within(usize, usize),
    Across(usize, usize, usize),
}

/// An element's box as the walk keeps it.
#[inline]
fn element_box(e: &Elem) -> Bx {
    kept_box(&bounds(e))
}

/// A segment's box grown by its tool radius `r`, as the walk keeps it.
#[inline]
fn reach_box(e: &Elem, r: f64) -> Bx {
    let (bb, r) = (bounds(e), r.abs());
    kept_box(&[bb[0] - r, bb[1] - r, bb[2] + r, bb[3] + r])
}

/// A leaf's segments: a range of the run's in path order, or listed (some came out of order).
#[derive(Clone, Copy)]
enum LeafSegments<'t> {
    /// From the first, how many.
    Run(usize, usize),
    Listed(&'t [u32]),
}

impl LeafSegments<'_> {
    fn len(&self) -> usize {
        match self {
            LeafSegments::Run(_, n) => *n,
            LeafSegments::Listed(l) => l.len(),
        }
    }

    #[inline]
    fn get(&self, i: usize) -> usize {
        match self {
            LeafSegments::Run(first, _) => first + i,
            LeafSegments::Listed(l) => l[i] as usize,
        }
    }
}

/// Where the walk takes its boxes: those of the elements `ks` of one leaf, and those of the
/// segments `ss` of a leaf (each grown by its tool radius), in the order given.
trait LeafBoxes {
    fn boxes(
        &mut self,
        a: usize,
        ss: LeafSegments<'_>,
        b: usize,
        ks: core::ops::Range<usize>,
    ) -> (&[Bx], &[Bx]);
}

/// Leaves whose boxes a [`BoxCache`] keeps: the walk takes a leaf against itself and then
/// against its neighbours, and in a subtree of this many leaves the halves' leaves at the
/// seam are still kept when the halves meet (so nearly every box is worked out once a walk).
const SLOTS: usize = 64;

/// The boxes of the leaves a walk met lately, worked out from the records (the records keep
/// none: 16 bytes a record would be a third of a run's memory, and memory first written costs
/// more here than working the boxes out again, docs/benchmarks.md). A slot a leaf modulo
/// [`SLOTS`], for its elements and for its segments apart: a pair of leaves never contends.
#[derive(Default)]
struct BoxCache {
    /// The run it was filled for ([`Tree::generation`]).
    generation: u64,
    /// Per slot: the leaf + 1 (0: none) and how many of its elements, their boxes.
    elements: Vec<(usize, usize, [Bx; LEAF])>,
    /// Per slot: the leaf + 1 (0: none), its segments' boxes.
    segments: Vec<(usize, Vec<Bx>)>,
}

impl BoxCache {
    /// Ready for the run of `generation`: emptied where it was filled for another.
    fn keep_for(&mut self, generation: u64) {
        if self.generation != generation || self.elements.is_empty() {
            self.clear(generation);
        }
    }

    /// Empty, for the run of `generation`.
    fn clear(&mut self, generation: u64) {
        self.generation = generation;
        self.elements.clear();
        self.elements.resize(SLOTS, (0, 0, [NOTHING; LEAF]));
        self.segments.resize_with(SLOTS, Default::default);
        for slot in &mut self.segments {
            slot.0 = 0;
        }
    }
}

/// The boxes of a run's records, worked out through a [`BoxCache`].
struct RecordBoxes<'c, 'r> {
    c: Checked<'r>,
    cache: &'c mut BoxCache,
}

impl LeafBoxes for RecordBoxes<'_, '_> {
    #[inline]
    fn boxes(
        &mut self,
        a: usize,
        ss: LeafSegments<'_>,
        b: usize,
        ks: core::ops::Range<usize>,
    ) -> (&[Bx], &[Bx]) {
        let c = &self.c;
        let (sa, sb) = (a % SLOTS, b % SLOTS);
        let slot = &mut self.cache.segments[sa];
        if slot.0 != a + 1 || slot.1.len() != ss.len() {
            slot.0 = a + 1;
            slot.1.clear();
            slot.1
                .extend((0..ss.len()).map(|i| c.segment_box(ss.get(i))));
        }
        let slot = &mut self.cache.elements[sb];
        if slot.0 != b + 1 || slot.1 != ks.len() {
            (slot.0, slot.1) = (b + 1, ks.len());
            for (bb, k) in slot.2.iter_mut().zip(ks.clone()) {
                *bb = element_box(&c.tables.element(c.elements, k));
            }
        }
        let n = self.cache.elements[sb].1;
        (&self.cache.segments[sa].1, &self.cache.elements[sb].2[..n])
    }
}

/// A run's elements in their order along the contour, in a tree of boxes: leaf l holds
/// elements `LEAF·l ..` and the segments anchored at them, node i of a level the nodes 2i and
/// 2i + 1 of the level below. The leaves grow as the elements and segments come (the thread
/// that takes the path has time to spare while the front works); the levels above are built
/// when the run is complete, from the order alone, in linear time: no sorting by place.
#[derive(Default)]
struct Tree {
    /// `levels[0]` are the leaves, the last level the root.
    levels: Vec<Vec<Node>>,
    /// Segments anchored at each leaf, then (at the run's end) where each leaf's begin:
    /// leaf l's are `first[l]..first[l + 1]` in path order, or the indices in `order` there
    /// where a segment came anchored before one of an earlier leaf (a counting sort).
    first: Vec<u32>,
    order: Vec<u32>,
    /// Each segment's leaf, once one has come out of leaf order (`order` is built from it);
    /// while they come in order, the counts in `first` tell it. The last segment's leaf.
    leaf: Vec<u32>,
    last_leaf: Option<u32>,
    in_order: bool,
    /// Elements under the leaves.
    elements: usize,
    /// The levels are built ([`Tree::build`]): the run is complete.
    built: bool,
    /// The walk of the run's complete part while the run grows ([`WholeCheck::walk_some`]).
    early: EarlyWalk,
    /// Counts the runs and the early walks started afresh: boxes kept for one
    /// ([`BoxCache`]) are not read for another.
    generation: u64,
}

/// The walk done while a run grows, in the time the thread that takes the path would wait
/// for the front: a leaf is complete when all its elements are in and a segment of a later
/// leaf has come (segments come in leaf order), and a subtree when its last leaf is; each
/// complete subtree is walked against itself as soon as it is, so that the run's end finds
/// little left but the subtrees its last leaves are in. A segment out of leaf order, or a
/// run that turns out to end before a walked leaf, has the run walked whole at its end.
#[derive(Default)]
struct EarlyWalk {
    /// Leaves whose subtrees are walked; the leaf after them, while its work is on `stack`.
    walked: usize,
    at: Option<usize>,
    stack: Vec<Task>,
    /// Where the segments of each leaf begin up to the one at hand (and the next's), while
    /// `first` counts.
    begin: Vec<u32>,
    /// Each violation found so far, by segment and element (before the run's closed loops are
    /// known: prep/leads.rs); the first `kept` are of walked leaves, the rest of the one at
    /// hand.
    hits: Vec<(u32, u32, Gouge)>,
    kept: usize,
}

/// Pieces of the early walk done between two looks at the front's channel: some tens of
/// microseconds, about what a batch takes the front.
const EARLY_STEPS: usize = 32;

impl Tree {
    fn new() -> Self {
        let mut t = Tree::default();
        t.clear();
        t
    }

    /// Room for `elements` elements and twice as many segments.
    fn reserve(&mut self, elements: usize) {
        let leaves = elements / LEAF + 1;
        if let Some(l) = self.levels.first_mut() {
            l.reserve(leaves);
        }
        self.first.reserve(leaves + 1);
    }

    /// A new run: no leaves.
    fn clear(&mut self) {
        self.levels.resize_with(1, Vec::new);
        self.levels[0].clear();
        self.first.clear();
        self.order.clear();
        self.leaf.clear();
        self.last_leaf = None;
        self.in_order = true;
        self.elements = 0;
        self.built = false;
        self.forget_early();
    }

    /// The walk of the run starts afresh at its end.
    fn forget_early(&mut self) {
        self.generation += 1;
        let e = &mut self.early;
        (e.walked, e.at, e.kept) = (0, None, 0);
        e.stack.clear();
        e.begin.clear();
        e.begin.push(0);
        e.hits.clear();
    }

    /// Whether node `i` of `level` was walked against itself while the run grew.
    #[inline]
    fn walked(&self, level: usize, i: usize) -> bool {
        (i + 1) << level <= self.early.walked
    }

    /// The work leaf `walked` completes, on the stack, if it is complete with `elements`
    /// elements in: the leaf against itself, and each subtree it completes, its halves
    /// against each other (the node is built here). False when it is not.
    fn take_leaf(&mut self, elements: usize) -> bool {
        let l = self.early.walked;
        let segments_past = self.last_leaf.is_some_and(|last| last as usize > l);
        if !self.in_order || !segments_past || elements < (l + 1) * LEAF {
            return false;
        }
        let next = self.early.begin[l] + self.first[l];
        self.early.begin.push(next);
        self.early.stack.push(Task::Within(0, l));
        let mut level = 1;
        while (l + 1).is_multiple_of(1 << level) {
            let i = ((l + 1) >> level) - 1;
            if self.levels.len() <= level {
                self.levels.push(Vec::new());
            }
            let below = &self.levels[level - 1];
            let mut n = below[2 * i];
            grow(&mut n.path, &below[2 * i + 1].path);
            grow(&mut n.elements, &below[2 * i + 1].elements);
            self.levels[level].truncate(i);
            self.levels[level].push(n);
            self.early
                .stack
                .push(Task::Across(level - 1, 2 * i, 2 * i + 1));
            level += 1;
        }
        self.early.at = Some(l);
        true
    }

    /// Up to `steps` pieces of the walk of complete leaves, in leaf order, each pair of a
    /// segment and an element whose boxes overlap to `f`; it stops where a leaf's work is
    /// done, so that the caller knows which of what `f` got belongs to walked leaves. False
    /// when there was none to do.
    fn work(
        &mut self,
        elements: usize,
        steps: usize,
        boxes: &mut impl LeafBoxes,
        f: &mut impl FnMut(u32, u32),
    ) -> bool {
        // A segment out of leaf order ends the early walk, wherever a leaf's work stands
        // (the work on the stack reads the leaves' segments by their counts): the run is
        // walked whole at its end (`early_stands`).
        if !self.in_order {
            return false;
        }
        for step in 0..steps {
            let Some(task) = self.early.stack.pop() else {
                if let Some(l) = self.early.at.take() {
                    self.early.walked = l + 1;
                    return true;
                }
                if !self.take_leaf(elements) {
                    return step > 0;
                }
                continue;
            };
            match task {
                Task::Within(_, l) => self.leaves(l, l, boxes, f),
                Task::Across(0, a, b) => self.across(0, a, b, boxes, f),
                Task::Across(level, a, b) => {
                    if self.meet(level, a, b) {
                        let n = self.levels[level - 1].len();
                        let pairs =
                            child_pairs(n, a, b).map(|(x, y)| Task::Across(level - 1, x, y));
                        self.early.stack.extend(pairs);
                    }
                }
            }
        }
        true
    }

    /// Whether the walk done while the run grew stands for the run complete with its first
    /// `elements` elements: it met none of the next run's, and no segment goes into a walked
    /// leaf at the end (`fold_beyond`).
    fn early_stands(&self, elements: usize) -> bool {
        let leaves = elements.div_ceil(LEAF).max(1);
        let folded = self.last_leaf.is_some_and(|l| l as usize >= leaves);
        self.in_order
            && self.early.walked * LEAF <= elements
            && !(folded && leaves - 1 < self.early.walked)
    }

    /// The leaf of element `k`, there from now on.
    fn leaf_of(&mut self, k: usize) -> usize {
        let l = k / LEAF;
        if self.levels.is_empty() {
            self.levels.push(Vec::new());
        }
        let leaves = &mut self.levels[0];
        if leaves.len() <= l {
            let empty = Node {
                path: NOTHING,
                elements: NOTHING,
            };
            leaves.resize(l + 1, empty);
            self.first.resize(l + 1, 0);
        }
        l
    }

    /// Element `k` (they come in order) with box `bb`.
    fn element(&mut self, k: usize, bb: &Bx) {
        let l = self.leaf_of(k);
        grow(&mut self.levels[0][l].elements, bb);
    }

    /// The next segment, anchored at element `k` (any element is right; one near it keeps
    /// the walk short), with box `bb` (grown by its tool radius).
    fn segment(&mut self, k: usize, bb: &Bx) {
        let l = self.leaf_of(k);
        grow(&mut self.levels[0][l].path, bb);
        if self.in_order && self.last_leaf.is_some_and(|last| last as usize > l) {
            // The first out of order: the leaves of those before it, from their counts.
            self.in_order = false;
            self.leaf.clear();
            for (leaf, &n) in self.first.iter().enumerate() {
                self.leaf
                    .extend(std::iter::repeat_n(leaf as u32, n as usize));
            }
        }
        self.first[l] += 1;
        if !self.in_order {
            self.leaf.push(l as u32);
        }
        self.last_leaf = Some(l as u32);
    }

    /// The run is complete with its first `elements` elements (those after them belong to
    /// the next run; no segment of this run is anchored there).
    fn build(&mut self, elements: usize) {
        self.elements = elements;
        let leaves = elements.div_ceil(LEAF).max(1);
        self.leaf_of((leaves - 1) * LEAF);
        self.fold_beyond(leaves);
        // Counts to beginnings.
        self.first.push(0);
        let mut at = 0;
        for f in &mut self.first {
            (*f, at) = (at, at + *f);
        }
        if !self.in_order {
            self.order.clear();
            self.order.resize(self.leaf.len(), 0);
            let mut next = self.first.clone();
            for (i, &l) in self.leaf.iter().enumerate() {
                self.order[next[l as usize] as usize] = i as u32;
                next[l as usize] += 1;
            }
        }
        self.build_levels();
        self.built = true;
    }

    /// Leaves past the run's `leaves` hold the next run's first elements and no segment; one
    /// anchored there all the same goes to the run's last leaf, so that none is left out (in
    /// leaf order those are the last segments: the order holds).
    fn fold_beyond(&mut self, leaves: usize) {
        let extra: u32 = self.first[leaves..].iter().sum();
        if extra > 0 {
            let path = self.levels[0][leaves..].iter().fold(NOTHING, |mut bb, n| {
                grow(&mut bb, &n.path);
                bb
            });
            grow(&mut self.levels[0][leaves - 1].path, &path);
            self.first[leaves - 1] += extra;
            for l in self.leaf.iter_mut().filter(|l| **l as usize >= leaves) {
                *l = (leaves - 1) as u32;
            }
        }
        self.levels[0].truncate(leaves);
        self.first.truncate(leaves);
    }

    fn build_levels(&mut self) {
        self.levels.truncate(1);
        while let Some(below) = self.levels.last().filter(|l| l.len() > 1) {
            let up: Vec<Node> = below
                .chunks(2)
                .map(|pair| {
                    let mut n = pair[0];
                    if let Some(b) = pair.get(1) {
                        grow(&mut n.path, &b.path);
                        grow(&mut n.elements, &b.elements);
                    }
                    n
                })
                .collect();
            self.levels.push(up);
        }
    }

    /// The walk in tasks: subtrees of the first level with at most `nodes` nodes, and the
    /// pairs of them whose boxes overlap (all of it in one task when the tree is that small).
    fn tasks(&self, nodes: usize, out: &mut Vec<Task>) {
        out.clear();
        let at = self.levels.iter().position(|l| l.len() <= nodes);
        let top = self.levels.len() - 1;
        self.split_within(top, 0, at.unwrap_or(top), out);
    }

    fn split_within(&self, level: usize, i: usize, at: usize, out: &mut Vec<Task>) {
        if self.walked(level, i) {
            return;
        }
        if level <= at {
            out.push(Task::Within(level, i));
            return;
        }
        let (a, b) = (2 * i, 2 * i + 1);
        self.split_within(level - 1, a, at, out);
        if b < self.levels[level - 1].len() {
            self.split_within(level - 1, b, at, out);
            self.split_across(level - 1, a, b, at, out);
        }
    }

    fn split_across(&self, level: usize, a: usize, b: usize, at: usize, out: &mut Vec<Task>) {
        if !self.meet(level, a, b) {
            return;
        }
        if level <= at {
            out.push(Task::Across(level, a, b));
            return;
        }
        for (x, y) in self.children(level, a, b) {
            self.split_across(level - 1, x, y, at, out);
        }
    }

    /// Whether some segment under node `a` may reach an element under `b`, or back.
    #[inline]
    fn meet(&self, level: usize, a: usize, b: usize) -> bool {
        let (na, nb) = (&self.levels[level][a], &self.levels[level][b]);
        meets(&na.path, &nb.elements) || meets(&nb.path, &na.elements)
    }

    /// The pairs of children of nodes `a` and `b` of `level`.
    fn children(&self, level: usize, a: usize, b: usize) -> impl Iterator<Item = (usize, usize)> {
        child_pairs(self.levels[level - 1].len(), a, b)
    }

    /// Each pair of a segment and an element of `task` whose boxes overlap, to `f`.
    fn run(&self, task: Task, boxes: &mut impl LeafBoxes, f: &mut impl FnMut(u32, u32)) {
        match task {
            Task::Within(level, i) => self.within(level, i, boxes, f),
            Task::Across(level, a, b) => self.across(level, a, b, boxes, f),
        }
    }

    fn within(
        &self,
        level: usize,
        i: usize,
        boxes: &mut impl LeafBoxes,
        f: &mut impl FnMut(u32, u32),
    ) {
        if self.walked(level, i) {
            return;
        }
        if level == 0 {
            return self.leaves(i, i, boxes, f);
        }
        let (a, b) = (2 * i, 2 * i + 1);
        self.within(level - 1, a, boxes, f);
        if b < self.levels[level - 1].len() {
            self.within(level - 1, b, boxes, f);
            self.across(level - 1, a, b, boxes, f);
        }
    }

    fn across(
        &self,
        level: usize,
        a: usize,
        b: usize,
        boxes: &mut impl LeafBoxes,
        f: &mut impl FnMut(u32, u32),
    ) {
        if level > 0 {
            if self.meet(level, a, b) {
                for (x, y) in self.children(level, a, b) {
                    self.across(level - 1, x, y, boxes, f);
                }
            }
            return;
        }
        let (na, nb) = (&self.levels[0][a], &self.levels[0][b]);
        if meets(&na.path, &nb.elements) {
            self.leaves(a, b, boxes, f);
        }
        if meets(&nb.path, &na.elements) {
            self.leaves(b, a, boxes, f);
        }
    }

    /// The segments of leaf `a` against the elements of leaf `b`, box by box.
    #[inline]
    fn leaves(&self, a: usize, b: usize, boxes: &mut impl LeafBoxes, f: &mut impl FnMut(u32, u32)) {
        let end = if self.built {
            self.elements
        } else {
            usize::MAX
        };
        let starts = if self.built {
            &self.first
        } else {
            &self.early.begin
        };
        let range = starts[a] as usize..starts[a + 1] as usize;
        let ss = if self.in_order {
            LeafSegments::Run(range.start, range.len())
        } else {
            LeafSegments::Listed(&self.order[range])
        };
        let (segments, elements) = boxes.boxes(a, ss, b, b * LEAF..((b + 1) * LEAF).min(end));
        let near = &self.levels[0][b].elements;
        for (i, bb) in segments.iter().enumerate() {
            if meets(bb, near) {
                for (j, e) in elements.iter().enumerate() {
                    if meets(bb, e) {
                        f(ss.get(i) as u32, (b * LEAF + j) as u32);
                    }
                }
            }
        }
    }
}

/// The pairs of children of nodes `a` and `b` of a level whose level below has `n` nodes.
fn child_pairs(n: usize, a: usize, b: usize) -> impl Iterator<Item = (usize, usize)> {
    [(0, 0), (0, 1), (1, 0), (1, 1)]
        .into_iter()
        .map(move |(i, j)| (2 * a + i, 2 * b + j))
        .filter(move |&(x, y)| x < n && y < n)
}

/// Runs two pieces of work, at once where the runtime can: the core starts no thread of its
/// own (the command line gives one that does, the kernel none).
pub trait Join: Sync {
    fn join(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send));
}

/// A run with fewer segments than this is checked in one piece (a thread costs more than
/// its half).
const PARALLEL_SEGMENTS: usize = 8192;

/// The walk of a long run is cut into tasks at the first level of the tree with at most this
/// many nodes: the two workers take the next task as they finish one, so neither waits on a
/// half that turned out longer (a contour that comes back on itself, exact distances, are not
/// spread evenly over a program).
const TASK_NODES: usize = 256;

/// One worker's check of a run: the violations it found.
#[derive(Default)]
struct Share {
    /// Each violation of a segment, by the segment's and the element's index.
    hits: Vec<(u32, u32, Gouge)>,
    /// The run's closed loops, worked out at the worker's first violation (prep/leads.rs).
    span: Option<Span>,
    boxes: BoxCache,
}

impl Share {
    /// Takes tasks (by `next`, shared with the other worker) until none is left, and checks
    /// the pairs of segments and elements each meets.
    fn take(&mut self, tasks: &[Task], next: &AtomicUsize, tree: &Tree, c: Checked<'_>) {
        self.hits.clear();
        self.span = None;
        self.boxes.clear(tree.generation);
        let mut boxes = RecordBoxes {
            c,
            cache: &mut self.boxes,
        };
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(&task) = tasks.get(i) else {
                return;
            };
            let mut pairs = Pairs::new(&c);
            tree.run(task, &mut boxes, &mut |s, k| {
                let Some(g) = pairs.gouge(s as usize, k as usize) else {
                    return;
                };
                let span = *self.span.get_or_insert_with(|| loops(c.elements, c.tables));
                if part_of(span, k + 1) {
                    self.hits.push((s, k, g));
                }
            });
        }
    }
}

/// What the workers read: the run's elements and segments.
#[derive(Clone, Copy)]
struct Checked<'r> {
    elements: &'r [Element],
    segments: &'r [PathSegment],
    tables: &'r Tables,
}

/// The whole-program check of one preparation: the run's elements and segments are kept as
/// they come, and checked against each other when the run is complete (the kernel lets no
/// segment of a run go before the whole run is met, and a violation of a lead is known only
/// then: prep/leads.rs).
pub struct WholeCheck<'a> {
    plane: Plane,
    elements: Vec<Element>,
    segments: Vec<PathSegment>,
    tables: Tables,
    /// The elements that stay when a run ends (their blocks' run goes on), while it ends.
    staying: Vec<(Source, Elem, f64, i8)>,
    tree: Tree,
    /// The boxes the walk done while the run grows met lately.
    early_boxes: BoxCache,
    tasks: Vec<Task>,
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
            segments: Vec::new(),
            tables: Tables::default(),
            staying: Vec::new(),
            tree: Tree::new(),
            early_boxes: BoxCache::default(),
            tasks: Vec::new(),
            shares: Default::default(),
            join: None,
            last: None,
        }
    }

    /// Room for a run of about `blocks` blocks (at most `RESERVE_BLOCKS`; a longer run grows
    /// its records as they come). Only the pages written are ever taken from the system.
    pub fn reserve(&mut self, blocks: usize) {
        let n = blocks.min(RESERVE_BLOCKS);
        self.elements.reserve(n);
        // A contour block and its corner.
        self.segments.reserve(2 * n);
        // The arcs programmed (a path arc about a point of its element takes no entry).
        self.tables.centres.reserve(n);
        self.tree.reserve(n);
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
        let (a, b, kind) = self.tables.pack(&elem);
        let mut tool = self.tables.tool(r, side);
        let prev = self.elements.last().map(|p| p.b);
        let k = self.elements.len();
        if starts_apart(prev, a, k, &mut self.tables.element_starts) {
            tool |= APART;
        }
        self.tables.keep_block(&self.elements, &source);
        self.elements.push(Element {
            seq: source.seq,
            line: source.line,
            b,
            kind,
            tool,
        });
        self.tree.element(k, &element_box(&elem));
    }

    /// A segment of the tool-centre path as it goes out. A segment that is no contour,
    /// corner or intermediate block (an approach, a retract, a move without compensation)
    /// ends the run: the run is checked and `found` gets its violations in path order (until
    /// it says to stop); what comes after is met afresh.
    pub fn segment(&mut self, seg: &Segment, found: &mut impl FnMut(Gouge) -> bool) {
        if !matches!(seg.role, Role::Contour | Role::Corner | Role::Intermediate) {
            self.settle(Some(seg.source.seq), found);
            self.end_run(Some(seg.source.seq));
            return;
        }
        let (own, anchor) = self.own(seg.source.seq);
        let shape = match (elem_in(seg, self.plane), own) {
            (Some(e), _) => Ok(e),
            (None, Some(k)) => {
                let own = self.tables.element(&self.elements, k);
                let Some(sp) = Spiral::new(seg, self.plane, &own) else {
                    return;
                };
                Err(sp)
            }
            (None, None) => return,
        };
        let (mut block, r) = match own {
            Some(k) => (Block::own(k), self.tables.element_tool(&self.elements[k]).0),
            None => {
                let (r, side) = self.last.unwrap_or((0.0, 0));
                let source = seg.source;
                self.tables.orphans.push(Orphan { source, r, side });
                (Block::orphan(self.tables.orphans.len() - 1), r)
            }
        };
        let (a, b, kind, reach) = match shape {
            Ok(e) => {
                let (a, b, kind) = self.tables.pack_segment(&e, &self.elements, own);
                (a, b, kind, reach_box(&e, r))
            }
            Err(sp) => {
                self.tables.spirals.push(sp);
                let kind = Kind::spiral(self.tables.spirals.len() - 1);
                (V2::default(), V2::default(), kind, kept_box(&sp.bbox()))
            }
        };
        // A spiral keeps its start in its own entry.
        let prev = self.segments.last().map(|p| p.b);
        let starts = &mut self.tables.segment_starts;
        if kind.spiral_index().is_none() && starts_apart(prev, a, self.segments.len(), starts) {
            block.0 |= Block::APART;
        }
        self.tree.segment(anchor, &reach);
        self.segments.push(PathSegment { b, kind, block });
    }

    /// Some of the run's walk, on its complete part (the front is ahead: this thread would
    /// wait for it). False when there is nothing to walk yet.
    pub fn walk_some(&mut self) -> bool {
        let c = Checked {
            elements: &self.elements,
            segments: &self.segments,
            tables: &self.tables,
        };
        self.early_boxes.keep_for(self.tree.generation);
        let mut boxes = RecordBoxes {
            c,
            cache: &mut self.early_boxes,
        };
        let mut hits = std::mem::take(&mut self.tree.early.hits);
        let elements = self.elements.len();
        let mut pairs = Pairs::new(&c);
        let did = self
            .tree
            .work(elements, EARLY_STEPS, &mut boxes, &mut |s, k| {
                if let Some(g) = pairs.gouge(s as usize, k as usize) {
                    hits.push((s, k, g));
                }
            });
        if self.tree.early.at.is_none() {
            // No leaf at hand: all found so far is of walked leaves.
            self.tree.early.kept = hits.len();
        }
        self.tree.early.hits = hits;
        did
    }

    /// The program ends: the last run is checked, once (nothing of it stays to be checked
    /// again).
    pub fn finish(&mut self, found: &mut impl FnMut(Gouge) -> bool) {
        self.settle(None, found);
        self.end_run(None);
    }

    /// The run's contour is complete (it ends before the block of `end`; the elements of
    /// later blocks belong to the next): each segment too close to an element that is part
    /// of it goes to `found` (in path order, one violation a segment: the earliest element
    /// it reaches); one of a lead is dropped. A long run is checked by two workers at
    /// once, task by task, where the runtime gave a [`Join`].
    fn settle(&mut self, end: Option<u32>, found: &mut impl FnMut(Gouge) -> bool) {
        let n = self.before(end);
        if self.segments.is_empty() || n == 0 {
            return;
        }
        self.finish_early(n);
        let elements = &self.elements[..n];
        let (segments, tables) = (&self.segments[..], &self.tables);
        let long = self.join.filter(|_| segments.len() >= PARALLEL_SEGMENTS);
        self.tree.build(n);
        let nodes = if long.is_some() { TASK_NODES } else { 1 };
        self.tree.tasks(nodes, &mut self.tasks);
        let (tree, tasks) = (&self.tree, &self.tasks[..]);
        let c = Checked {
            elements,
            segments,
            tables,
        };
        let [first, second] = &mut self.shares;
        let next = AtomicUsize::new(0);
        match long {
            Some(join) => join.join(&mut || first.take(tasks, &next, tree, c), &mut || {
                second.take(tasks, &next, tree, c)
            }),
            None => {
                second.hits.clear();
                first.take(tasks, &next, tree, c);
            }
        }
        // One violation a segment, in path order: the earliest element it reaches.
        let mut hits = std::mem::take(&mut first.hits);
        hits.append(&mut second.hits);
        let early = &mut self.tree.early.hits;
        if !early.is_empty() {
            let span = loops(elements, &self.tables);
            hits.extend(early.drain(..).filter(|&(_, k, _)| part_of(span, k + 1)));
        }
        hits.sort_unstable_by_key(|&(s, k, _)| (s, k));
        let mut last = None;
        for &(s, _, g) in &hits {
            if last.replace(s) != Some(s) && found(g) {
                break;
            }
        }
        hits.clear();
        first.hits = hits;
    }

    /// The walk done while the run grew, kept for the leaves it finished where it stands for
    /// the run complete with its first `n` elements, or forgotten.
    fn finish_early(&mut self, n: usize) {
        let e = &mut self.tree.early;
        if e.at.take().is_some() {
            e.stack.clear();
            e.hits.truncate(e.kept);
        }
        if !self.tree.early_stands(n) {
            self.tree.forget_early();
        }
    }

    /// The element of block `seq`, if the run has one, and the element a segment of the block
    /// is anchored at in the tree: the last of its block or before. Elements come in block
    /// order, and ahead of their segments by as many blocks as the bottleneck window holds
    /// back: the search goes back over those, no further (past them any anchor is right).
    fn own(&self, seq: u32) -> (Option<usize>, usize) {
        let n = self.elements.len();
        let back = self
            .elements
            .iter()
            .rev()
            .take(super::bottleneck::MAX_WINDOW + 8)
            .position(|e| (e.seq.wrapping_sub(seq) as i32) <= 0);
        match back {
            Some(i) => {
                let k = n - 1 - i;
                (Some(k).filter(|&k| self.elements[k].seq == seq), k)
            }
            None => (None, n.saturating_sub(1)),
        }
    }

    /// How many elements belong to blocks before the block of `seq` (all of them for
    /// `None`). Elements come in block order: found by bisection, not a walk over a long run.
    fn before(&self, seq: Option<u32>) -> usize {
        self.elements
            .partition_point(|e| seq.is_none_or(|q| (e.seq.wrapping_sub(q) as i32) < 0))
    }

    /// The run ends before the block of `seq` (or with the program): everything before it
    /// goes; an element of a later block (the next run's first, read before its approach
    /// came out) stays.
    fn end_run(&mut self, seq: Option<u32>) {
        self.segments.clear();
        // Those that stay are the last few: kept again, in fresh tables.
        let gone = self.before(seq);
        let mut stay = std::mem::take(&mut self.staying);
        stay.clear();
        stay.extend((gone..self.elements.len()).map(|k| {
            let e = &self.elements[k];
            let (r, side) = self.tables.element_tool(e);
            let source = self.tables.source(&self.elements, k);
            (source, self.tables.element(&self.elements, k), r, side)
        }));
        self.elements.clear();
        self.tables.clear();
        self.tree.clear();
        // They were the last elements in: `last` stays what it was.
        for &(source, e, r, side) in &stay {
            self.element(source, e, r, side);
        }
        self.staying = stay;
    }
}

/// The closed loops of a run's elements (prep/leads.rs).
#[cold]
fn loops(elements: &[Element], tables: &Tables) -> Span {
    let mut closure = Closure::default();
    for k in 0..elements.len() {
        closure.element(&tables.element(elements, k));
    }
    closure.span()
}

impl Checked<'_> {
    /// Segment `s`'s block (its place in execution order), tool radius and side.
    #[inline]
    fn block(&self, s: &PathSegment) -> (u32, f64, i8) {
        match s.block.own_index() {
            Some(k) => {
                let e = &self.elements[k];
                let (r, side) = self.tables.element_tool(e);
                (e.seq, r, side)
            }
            None => {
                let o = &self.tables.orphans[s.block.index()];
                (o.source.seq, o.r, o.side)
            }
        }
    }

    /// Segment `s`'s block.
    #[cold]
    fn block_source(&self, s: &PathSegment) -> Source {
        match s.block.own_index() {
            Some(k) => self.tables.source(self.elements, k),
            None => self.tables.orphans[s.block.index()].source,
        }
    }

    /// Segment `s`'s box grown by its tool radius, as it was when it came.
    fn segment_box(&self, s: usize) -> Bx {
        let seg = &self.segments[s];
        if let Some(i) = seg.kind.spiral_index() {
            return kept_box(&self.tables.spirals[i].bbox());
        }
        let e = self.tables.segment(self.elements, self.segments, s);
        reach_box(&e, self.block(seg).1)
    }

    /// What a pair's test first asks of segment `s`: its block, tool radius and side.
    #[inline]
    fn segment_view(&self, s: usize) -> SegmentView {
        let (seq, r, side) = self.block(&self.segments[s]);
        SegmentView {
            s,
            seq,
            r,
            side,
            piece: None,
        }
    }

    /// What a pair's test asks of element `k`.
    #[inline]
    fn element_view(&self, k: usize) -> ElementView {
        let elem = self.tables.element(self.elements, k);
        ElementView {
            k,
            elem,
            eta: eta_of(&elem),
            fence: None,
        }
    }
}

/// What a pair's test needs of a segment, worked out once for all the elements it meets: its
/// block, and (for a pair that gets past the blocks' test) its piece and gouge tolerance.
struct SegmentView {
    s: usize,
    seq: u32,
    r: f64,
    side: i8,
    piece: Option<(PathPiece, f64)>,
}

/// What a pair's test needs of an element, worked out once for all the segments that meet
/// it: the element, its rounding margin, and its fence once one pair has asked for it.
struct ElementView {
    k: usize,
    elem: Elem,
    eta: f64,
    fence: Option<Fence>,
}

/// The pairs one worker tests, with the records at hand decoded once: the walk meets a
/// segment's pairs one after another, and a leaf's elements (`LEAF` consecutive ones, a slot
/// each) with every segment near them.
struct Pairs<'c, 'r> {
    c: &'c Checked<'r>,
    segment: Option<SegmentView>,
    elements: [Option<ElementView>; LEAF],
}

impl<'c, 'r> Pairs<'c, 'r> {
    fn new(c: &'c Checked<'r>) -> Self {
        Pairs {
            c,
            segment: None,
            elements: Default::default(),
        }
    }

    /// The gouge of segment `s` at element `k` (their boxes meet), if it comes too close
    /// (its own block's element and the other side's are not compared).
    #[inline]
    fn gouge(&mut self, s: usize, k: usize) -> Option<Gouge> {
        let c = self.c;
        if c.segments[s].block.own_index() == Some(k) {
            // Its own block's element: settled before either record is read further.
            return None;
        }
        let sv = match &mut self.segment {
            Some(v) if v.s == s => v,
            slot => slot.insert(c.segment_view(s)),
        };
        let e = &c.elements[k];
        if sv.side != c.tables.element_tool(e).1 || sv.seq == e.seq {
            return None;
        }
        let ev = match &mut self.elements[k % LEAF] {
            Some(v) if v.k == k => v,
            slot => slot.insert(c.element_view(k)),
        };
        let (piece, tol) = sv.piece.get_or_insert_with(|| {
            let piece = c.tables.piece(c.elements, c.segments, s);
            let tol = piece.gouge_tol();
            (piece, tol)
        });
        // The element is read where it is kept, not copied. The fence is worked out for the
        // few pairs that get that far (a line beside a line never needs it), once an element.
        let ElementView {
            elem, eta, fence, ..
        } = ev;
        let (elem, eta) = (&*elem, *eta);
        let fence = move || {
            let slot = fence;
            &*slot.get_or_insert_with(|| Fence::with_eta(elem, eta))
        };
        let (distance, radius) = piece.too_close_by(*tol, elem, eta, fence, sv.r)?;
        Some(Gouge {
            path: c.block_source(&c.segments[s]),
            element: c.tables.source(c.elements, k),
            distance,
            radius,
            unjoined: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prep::bottleneck::tests::{line, spiral_case, src};
    use crate::prep::bottleneck::{overlap, OVERLAP_TOL};
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

    /// A contour segment of block `seq` in XY.
    fn segment(
        seq: u32,
        shape: crate::segment::Shape,
        from: (f64, f64),
        to: (f64, f64),
    ) -> Segment {
        Segment {
            source: src(seq),
            role: Role::Contour,
            shape,
            from: [from.0, from.1, 0.0],
            to: [to.0, to.1, 0.0],
            feed: 1000.0,
            per_rev: false,
            thread: false,
            rapid: false,
            exact_stop: false,
        }
    }

    /// A segment's shape in XY starting at `a`: a line, or an arc about `centre`.
    fn shape_xy(a: V2, centre: Option<V2>, ccw: bool) -> crate::segment::Shape {
        match centre {
            None => crate::segment::Shape::Line,
            Some(c) => crate::segment::Shape::Arc {
                center: [c.x, c.y, 0.0],
                center_end: [c.x, c.y, 0.0],
                ccw,
                r0: a.dist(c),
                r1: a.dist(c),
                plane: Plane::XY,
            },
        }
    }

    /// The violations of one run: `elements` (block, element, tool radius), then `segments`.
    fn gouges(elements: &[(u32, Elem, f64)], segments: &[Segment]) -> Vec<Gouge> {
        let mut w = WholeCheck::new();
        for &(seq, e, r) in elements {
            w.element(src(seq), e, r, 1);
        }
        let mut found = Vec::new();
        for s in segments {
            w.segment(s, &mut |g| {
                found.push(g);
                false
            });
        }
        w.finish(&mut |g| {
            found.push(g);
            false
        });
        found
    }

    /// The walk's boxes from slices of them, for the tree alone.
    struct SliceBoxes<'a> {
        elements: &'a [Bx],
        segments: &'a [Bx],
        listed: Vec<Bx>,
    }

    impl LeafBoxes for SliceBoxes<'_> {
        fn boxes(
            &mut self,
            _: usize,
            ss: LeafSegments<'_>,
            _: usize,
            ks: core::ops::Range<usize>,
        ) -> (&[Bx], &[Bx]) {
            self.listed.clear();
            self.listed
                .extend((0..ss.len()).map(|i| self.segments[ss.get(i)]));
            (&self.listed, &self.elements[ks])
        }
    }

    /// A run keeps every element and segment: their records must not grow unnoticed
    /// (docs/benchmarks.md measures what a megabyte of them costs).
    #[test]
    fn the_records_stay_small() {
        assert!(std::mem::size_of::<Element>() <= 32);
        assert!(std::mem::size_of::<PathSegment>() <= 24);
    }

    /// A block's source in steps: 1–3 blocks on in execution order and 0–4 lines on (loops
    /// and calls go back), the column, number and file as they come.
    fn sources() -> impl Strategy<Value = Vec<Source>> {
        let step = (1u32..4, 0u32..5, 0u8..8, 0u32..40, 1u8..4, any::<bool>());
        proptest::collection::vec(step, 1..60).prop_map(|steps| {
            let mut at = Source {
                number: None,
                line: 1,
                col: 1,
                seq: 1,
                program: 0,
            };
            let mut out = Vec::new();
            for (ahead, lines, what, n, digits, in_file) in steps {
                at.seq = at.seq.wrapping_add(ahead);
                at.line += lines;
                let digits = std::num::NonZeroU8::new(digits).unwrap_or(std::num::NonZeroU8::MIN);
                match what {
                    // Numbered on by a step of 10 a block, or by some other.
                    0..=2 => {
                        let value = at.number.map_or(10, |b| b.value + 10 * ahead);
                        at.number = Some(BlockNo { value, digits });
                    }
                    3 => at.number = Some(BlockNo { value: n, digits }),
                    4 => at.number = None,
                    5 => at.col = n + 1,
                    6 => at.program = u16::from(in_file),
                    _ => {}
                }
                out.push(at);
            }
            out
        })
    }

    proptest! {
        /// Every element's block reads back as it came, however its numbers, columns and
        /// files run (most of them from the entry before it).
        #[test]
        fn an_elements_block_reads_back_as_it_came(blocks in sources()) {
            let mut w = WholeCheck::new();
            for (i, s) in blocks.iter().enumerate() {
                let x = i as f64;
                w.element(*s, Elem::Line { a: v2(x, 0.0), b: v2(x + 1.0, 0.0) }, 1.0, 1);
            }
            for (k, s) in blocks.iter().enumerate() {
                prop_assert_eq!(w.tables.source(&w.elements, k), *s, "element {}", k);
            }
        }
    }

    /// A run of blocks with an element each (lines and arcs, some starting apart) and a path
    /// of segments: the equidistant-like piece of the block and, now and then, an arc about the
    /// element's end, start or centre (a corner's, an arc's offset) or about some other point.
    fn run_of_blocks() -> impl Strategy<Value = (Vec<Elem>, Vec<Segment>)> {
        let block = (elem(), any::<bool>(), 0..5u8, any::<bool>(), -3.0..3.0f64);
        proptest::collection::vec(block, 1..40).prop_map(|blocks| {
            let (mut elements, mut segments) = (Vec::new(), Vec::new());
            let mut end: Option<V2> = None;
            for (i, (e, chained, about, ccw, d)) in blocks.into_iter().enumerate() {
                let seq = i as u32 + 1;
                // Most elements start where the one before ends.
                let e = match (end, chained) {
                    (Some(p), true) => match e {
                        Elem::Line { b, .. } => Elem::Line { a: p, b },
                        Elem::Arc { c, ccw, .. } => {
                            let r = p.dist(c);
                            Elem::Arc {
                                a: p,
                                b: v2(c.x, c.y + r),
                                c,
                                ccw,
                            }
                        }
                    },
                    _ => e,
                };
                end = Some(e.end());
                elements.push(e);
                let centre = match (about, e) {
                    (0, _) => None,
                    (1, _) => Some(e.end()),
                    (2, _) => Some(e.start()),
                    (3, Elem::Arc { c, .. }) => Some(c),
                    _ => Some(v2(e.end().x + d, e.end().y - d)),
                };
                let (a, b) = (
                    v2(e.start().x + d, e.start().y),
                    v2(e.end().x, e.end().y + d),
                );
                let shape = shape_xy(a, centre, ccw);
                // An arc's end on its circle, as the compensation puts it.
                let b = match centre {
                    Some(c) => {
                        let r = a.dist(c);
                        v2(c.x - r, c.y)
                    }
                    None => b,
                };
                segments.push(segment(seq, shape, (a.x, a.y), (b.x, b.y)));
            }
            (elements, segments)
        })
    }

    proptest! {
        /// The records give back every element and path segment bit for bit: chained starts,
        /// arc centres in their table.
        #[test]
        fn the_records_read_back_as_they_came((elements, segments) in run_of_blocks()) {
            let mut w = WholeCheck::new();
            for (i, e) in elements.iter().enumerate() {
                w.element(src(i as u32 + 1), *e, 2.0, 1);
            }
            for s in &segments {
                w.segment(s, &mut |_| false);
            }
            for (k, e) in elements.iter().enumerate() {
                prop_assert_eq!(w.tables.element(&w.elements, k), *e, "element {}", k);
            }
            let mut i = 0;
            for s in &segments {
                let Some(want) = elem_in(s, Plane::XY) else { continue };
                let got = match w.tables.piece(&w.elements, &w.segments, i) {
                    PathPiece::Plain(m) => Some(m.e),
                    _ => None,
                };
                prop_assert_eq!(got, Some(want), "segment {}", i);
                i += 1;
            }
            prop_assert_eq!(i, w.segments.len());
        }
    }

    proptest! {
        /// The boxes the walk works out from the records are those of the elements and of the
        /// segments (grown by their blocks' tool radii) as they came, bit for bit.
        #[test]
        fn the_walks_boxes_are_those_of_the_records_as_they_came(
            (elements, segments) in run_of_blocks()
        ) {
            let radius = |k: usize| 0.5 + (k % 3) as f64;
            let mut w = WholeCheck::new();
            for (k, e) in elements.iter().enumerate() {
                w.element(src(k as u32 + 1), *e, radius(k), 1);
            }
            for s in &segments {
                w.segment(s, &mut |_| false);
            }
            prop_assert_eq!(w.segments.len(), segments.len());
            let c = Checked { elements: &w.elements, segments: &w.segments, tables: &w.tables };
            let mut cache = BoxCache::default();
            cache.clear(w.tree.generation);
            let mut boxes = RecordBoxes { c, cache: &mut cache };
            let n = elements.len();
            for leaf in 0..n.div_ceil(LEAF) {
                let ks = leaf * LEAF..((leaf + 1) * LEAF).min(n);
                let ss = LeafSegments::Run(0, segments.len());
                let (sb, eb) = boxes.boxes(leaf, ss, leaf, ks.clone());
                for (bb, k) in eb.iter().zip(ks) {
                    prop_assert_eq!(*bb, element_box(&elements[k]), "element {}", k);
                }
                for (bb, seg) in sb.iter().zip(&segments) {
                    let e = elem_in(seg, Plane::XY).expect("a line or an arc in XY");
                    let k = seg.source.seq as usize - 1;
                    prop_assert_eq!(*bb, reach_box(&e, radius(k)), "segment of block {}", k + 1);
                }
            }
        }
    }

    proptest! {
        /// A pair's answer does not depend on what the worker decoded before it: every pair
        /// of a run, taken in the walk's order, the other way round and in a scrambled one by
        /// one worker, gives what a fresh worker gives for it alone (tool radii and sides
        /// vary, so that pairs fail the blocks' test, pass it and gouge).
        #[test]
        fn a_pairs_answer_does_not_depend_on_what_was_decoded_before(
            (elements, segments) in run_of_blocks(), seed in any::<u64>()
        ) {
            let mut w = WholeCheck::new();
            for (i, e) in elements.iter().enumerate() {
                let (r, side) = (1.0 + (i % 3) as f64, if i % 4 == 3 { -1 } else { 1 });
                w.element(src(i as u32 + 1), *e, r, side);
            }
            for s in &segments {
                w.segment(s, &mut |_| false);
            }
            let c = Checked {
                elements: &w.elements,
                segments: &w.segments,
                tables: &w.tables,
            };
            let answer = |g: Option<Gouge>| g.map(|g| (g.path.seq, g.element.seq, g.distance.to_bits()));
            let (ns, nk) = (w.segments.len(), w.elements.len());
            let mut pairs: Vec<(usize, usize)> =
                (0..ns).flat_map(|s| (0..nk).map(move |k| (s, k))).collect();
            let alone: Vec<_> = pairs.iter().map(|&(s, k)| answer(Pairs::new(&c).gouge(s, k))).collect();
            let mut orders = vec![pairs.clone()];
            pairs.sort_by_key(|&(s, k)| (k, s));
            orders.push(pairs.clone());
            let mut x = seed | 1;
            pairs.sort_by_cached_key(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                x
            });
            orders.push(pairs);
            for order in orders {
                let mut worker = Pairs::new(&c);
                for (s, k) in order {
                    let want = alone[s * nk + k];
                    prop_assert_eq!(answer(worker.gouge(s, k)), want, "segment {} element {}", s, k);
                }
            }
        }
    }

    /// Blocks numbered N10, N20 … on consecutive lines take one entry for the whole run.
    #[test]
    fn numbered_blocks_on_consecutive_lines_take_one_entry() {
        let mut w = WholeCheck::new();
        for i in 0..100u32 {
            let mut s = src(i + 1);
            s.number = Some(BlockNo {
                value: 10 * (i + 1),
                digits: std::num::NonZeroU8::new(4).unwrap(),
            });
            let x = f64::from(i);
            w.element(
                s,
                Elem::Line {
                    a: v2(x, 0.0),
                    b: v2(x + 1.0, 0.0),
                },
                1.0,
                1,
            );
        }
        assert_eq!(w.tables.blocks.len(), 1);
        assert_eq!(
            w.tables.source(&w.elements, 57).number.map(|n| n.value),
            Some(580)
        );
    }

    /// The window's spiral case (`bottleneck::tests::spiral_case`) with block 3 `third`.
    fn spiral_against(third: Elem) -> Vec<Gouge> {
        let ([first, second], spiral) = spiral_case();
        gouges(&[first, second, (3, third, 10.0)], &[spiral])
    }

    #[test]
    fn a_spiral_is_checked_with_the_tool_radius_at_each_point() {
        // 65 below the centre: at the spiral's end the tool (radius 10) reaches 5 mm past it.
        let g = spiral_against(line((-40.0, -65.0), (40.0, -65.0)));
        assert_eq!(g.len(), 1, "{g:?}");
        assert_eq!((g[0].path.seq, g[0].element.seq), (1, 3));
        assert!((g[0].distance - 5.0).abs() < 1e-9 && (g[0].radius - 10.0).abs() < 1e-12);
        // 75 below: 5 mm to spare.
        assert!(spiral_against(line((-40.0, -75.0), (40.0, -75.0))).is_empty());
    }

    /// A segment of a block without an element of its own is measured with the last
    /// element's tool radius and side, and named by its own block.
    #[test]
    fn a_segment_without_an_element_keeps_its_block() {
        let elements = [
            (1, line((0.0, 0.0), (100.0, 0.0)), 10.0),
            (2, line((100.0, 0.0), (100.0, 50.0)), 10.0),
        ];
        // Block 3 has no element; its segment runs 4 mm left of block 2's element.
        let near = segment(3, crate::segment::Shape::Line, (96.0, 10.0), (96.0, 40.0));
        let g = gouges(&elements, &[near]);
        assert_eq!(g.len(), 1, "{g:?}");
        assert_eq!((g[0].path, g[0].element.seq), (src(3), 2));
        assert!((g[0].distance - 4.0).abs() < 1e-9 && (g[0].radius - 10.0).abs() < 1e-12);
        // 12 mm away: clear.
        let far = segment(3, crate::segment::Shape::Line, (88.0, 12.0), (88.0, 40.0));
        assert!(gouges(&elements, &[far]).is_empty());
    }

    /// What a program feeds the check, in order: the element of a block, a path segment, or
    /// a look at the walk while the front is busy (`walk_some`).
    #[derive(Clone, Debug)]
    enum Feed {
        Element(u32, Elem),
        Segment(Segment),
        Walk(usize),
    }

    /// A random program's feed: elements ahead of their blocks' segments by a few blocks, some
    /// blocks with no element or several segments, a block's segments now and then ahead of
    /// the block's before it (out of leaf order), a run ended by a move without compensation
    /// now and then, and looks at the walk anywhere.
    fn feed() -> impl Strategy<Value = Vec<Feed>> {
        let block = (
            prop::option::weighted(0.9, elem()),
            proptest::collection::vec((elem(), any::<bool>()), 0..3),
            0..4usize,
            prop::bool::weighted(0.03),
            0..6usize,
            prop::bool::weighted(0.04),
        );
        proptest::collection::vec(block, 1..160).prop_map(|blocks| {
            let mut out = Vec::new();
            let mut waiting: std::collections::VecDeque<Vec<Feed>> = Default::default();
            for (seq, (element, segs, lag, ends, walks, swap)) in blocks.into_iter().enumerate() {
                let seq = seq as u32 + 1;
                if let Some(e) = element {
                    out.push(Feed::Element(seq, e));
                }
                let mut mine: Vec<Feed> = segs
                    .into_iter()
                    .map(|(e, ccw)| {
                        let (a, b) = (e.start(), e.end());
                        let centre = match e {
                            Elem::Line { .. } => None,
                            Elem::Arc { c, .. } => Some(c),
                        };
                        let shape = shape_xy(a, centre, ccw);
                        let mut s = segment(seq, shape, (a.x, a.y), (b.x, b.y));
                        if ends {
                            s.role = Role::Approach;
                        }
                        Feed::Segment(s)
                    })
                    .collect();
                mine.extend((0..walks).map(Feed::Walk));
                waiting.push_back(mine);
                // Now and then a block's segments ahead of the block's before it (within a
                // run: a segment that ends one comes after all of the run's).
                let n = waiting.len();
                let ends_run = |g: &Vec<Feed>| {
                    g.iter()
                        .any(|f| matches!(f, Feed::Segment(s) if s.role != Role::Contour))
                };
                if swap && n >= 2 && !ends_run(&waiting[n - 1]) && !ends_run(&waiting[n - 2]) {
                    waiting.swap(n - 1, n - 2);
                }
                while waiting.len() > lag {
                    out.extend(waiting.pop_front().into_iter().flatten());
                }
            }
            out.extend(waiting.into_iter().flatten());
            out
        })
    }

    /// Every violation `feed` gives, with or without its looks at the walk.
    fn fed(feed: &[Feed], walks: bool) -> Vec<(u32, u32, u64)> {
        let mut w = WholeCheck::new();
        let mut found = Vec::new();
        let mut take = |g: Gouge| {
            found.push((g.path.seq, g.element.seq, g.distance.to_bits()));
            false
        };
        for f in feed {
            match f {
                Feed::Element(seq, e) => w.element(src(*seq), *e, 6.0, 1),
                Feed::Segment(s) => w.segment(s, &mut take),
                Feed::Walk(n) if walks => {
                    for _ in 0..=*n {
                        w.walk_some();
                    }
                }
                Feed::Walk(_) => {}
            }
        }
        w.finish(&mut take);
        found
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// The walk done while a run grows, wherever it stops, and the walk at the run's end
        /// find together what the walk at the end finds alone, in the same order.
        #[test]
        fn walking_early_finds_what_the_end_finds(feed in feed()) {
            prop_assert_eq!(fed(&feed, true), fed(&feed, false));
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// The walk meets every pair of a segment and an element whose boxes meet, each once,
        /// wherever the segments are anchored, whether in one task or cut into many; and
        /// among them every pair the window's test lets overlap.
        #[test]
        fn the_tree_meets_every_pair_whose_boxes_overlap(
            elems in proptest::collection::vec(elem(), 1..120),
            paths in proptest::collection::vec((elem(), 0.0..12.0f64, 0..200usize), 0..150),
            nodes in prop_oneof![Just(1usize), Just(2), Just(5), Just(256)],
            in_order in any::<bool>(),
        ) {
            let boxes: Vec<[f64; 4]> = elems.iter().map(bounds).collect();
            let reach: Vec<([f64; 4], usize)> = paths
                .iter()
                .map(|(e, r, k)| {
                    let b = bounds(e);
                    ([b[0] - r, b[1] - r, b[2] + r, b[3] + r], *k)
                })
                .collect();
            let mut reach = reach;
            if in_order {
                reach.sort_by_key(|r| r.1);
            }
            let kept: Vec<Bx> = boxes.iter().map(kept_box).collect();
            let seg_boxes: Vec<Bx> = reach.iter().map(|r| kept_box(&r.0)).collect();
            // The segments anchored anywhere, beyond the run's elements too.
            let mut tree = Tree::new();
            for (k, bb) in kept.iter().enumerate() {
                tree.element(k, bb);
            }
            for (bb, (_, k)) in seg_boxes.iter().zip(&reach) {
                tree.segment(*k, bb);
            }
            tree.build(boxes.len());
            let mut all = SliceBoxes { elements: &kept, segments: &seg_boxes, listed: Vec::new() };
            let mut tasks = Vec::new();
            tree.tasks(nodes, &mut tasks);
            let mut met = vec![0u32; reach.len() * boxes.len()];
            for &t in &tasks {
                tree.run(t, &mut all, &mut |s, k| met[s as usize * boxes.len() + k as usize] += 1);
            }
            for (s, (bb, _)) in reach.iter().enumerate() {
                for (k, ebb) in boxes.iter().enumerate() {
                    let m = met[s * boxes.len() + k];
                    let meet = meets(&seg_boxes[s], &kept[k]);
                    prop_assert_eq!(m, u32::from(meet), "segment {} element {}", s, k);
                    prop_assert!(meet || !overlap(bb, ebb), "segment {} element {}", s, k);
                }
            }
        }

        /// Boxes the window's test lets overlap meet as the walk keeps them, at every scale.
        #[test]
        fn kept_boxes_meet_where_the_windows_overlap(
            x in prop_oneof![-2.0..2.0f64, -1e12..1e12f64],
            scale in prop_oneof![Just(1e-9), Just(1e-3), Just(1.0), Just(1e4), Just(1e9), Just(1e40)],
            w in 0.0..2.0f64,
            gap in -1.0..1.0f64,
        ) {
            // q lies right of p by `gap` times the tolerance (touching or just apart).
            let p = [x, x, x + w * scale, x + w * scale];
            let q0 = p[2] + gap * OVERLAP_TOL;
            let q = [q0, x, q0 + scale, x + scale];
            if overlap(&p, &q) {
                prop_assert!(meets(&kept_box(&p), &kept_box(&q)), "{:?} {:?}", p, q);
            }
        }

        /// An element's box holds every point of it.
        #[test]
        fn an_elements_box_holds_it(e in elem(), t in 0.0..1.0f64) {
            let bb = bounds(&e);
            let p = match e {
                Elem::Line { a, b } => a + (b - a) * t,
                Elem::Arc { a, b, c, ccw } => {
                    let (u, w) = (a - c, b - c);
                    let mut sweep = w.y.atan2(w.x) - u.y.atan2(u.x);
                    if ccw && sweep <= 0.0 { sweep += std::f64::consts::TAU; }
                    if !ccw && sweep >= 0.0 { sweep -= std::f64::consts::TAU; }
                    let th = u.y.atan2(u.x) + sweep * t;
                    c + v2(th.cos(), th.sin()) * a.dist(c)
                }
            };
            prop_assert!(overlap(&bb, &[p.x, p.y, p.x, p.y]), "{:?} {:?} {:?}", e, bb, p);
        }
    }
}
