//! Tool radius compensation (840C chapter 11; ISG, Fanuc C and 808D as their seeds say).
//!
//! The [`Compensator`] takes interpreted blocks one at a time and emits the tool-centre path
//! as [`Segment`]s. It holds one contour element back until the next one is known, because
//! the end of an equidistant depends on the corner it meets (11.4: "two blocks read in
//! advance"); blocks outside the compensation plane wait behind it (11.11).
//!
//! Nothing here knows a G code or a dialect: the dialect tables map theirs onto
//! [`TrcRules`], [`CornerPolicy`] and [`SelectionPolicy`]. Where each rule lives:
//! corners in `corner.rs`, selection in `selection.rs`, deselection in `deselection.rs`,
//! plane geometry in `geom.rs`.

pub mod corner;
pub mod cutting_edge;
pub mod deselection;
pub mod geom;
pub mod selection;
pub mod violation;

use crate::alarm::AlarmCode;
use crate::frontend::block::{
    Block, CornerPolicy, FeedAdaption, Motion, MotionKind, Plane, Pos, SelectionPolicy, TrcSide,
};
use crate::segment::{Role, Segment, Shape, Source};
use corner::{Corner, CornerError, CornerSettings, OuterCorner};
use geom::{v2, Elem, EPS, V2};
use selection::InnerCornerError;

/// What a repeated G41/G42 (same side, already active) does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RepeatRule {
    /// Ignored unless a selection method is programmed with it (840C 11.6.1).
    IgnoreWithoutApproach,
    /// The last block ends in the normal position; the compensation starts anew (808D,
    /// Fanuc "vector at right angles to the previous block").
    Restart,
}

/// How the radius of an active compensation changes (new D, or a write of the radius).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusChange {
    /// The block with the change starts with the old radius and ends with the new one;
    /// linear blocks only (840C 11.7).
    InBlockLinear,
    /// Spread over the whole block in which it is programmed, circles included (808D).
    InBlock,
    /// Spread over the next linear block in the plane (ISG, 002: "possible only together with
    /// a linear block"; TF5200's default ramp).
    NextLinear,
}

/// An armed selection (G41/G42 without a plane move) meets a circle as its first plane move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArmedArc {
    /// Selection only in G0/G1 blocks (840C 11.3, 808D, Fanuc).
    Alarm(AlarmCode),
    /// A block perpendicular to the circle's start, then the compensated circle (ISG, as
    /// TF5200 G237 does; the seed's own D-change example needs it, docs/trc.md).
    Perpendicular,
}

/// A selection block without any axis of the plane programmed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoPlaneMove {
    /// Takes effect with the next plane move (840C 11.5.2, ISG, 808D).
    Wait,
    /// Moves by the offset only, in that block (Fanuc C start-up and cancel).
    OffsetOnly,
}

/// The TRC rules of one control, in dialect-free terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrcRules {
    pub repeat: RepeatRule,
    pub side_change: SideChange,
    pub radius_change: RadiusChange,
    pub armed_arc: ArmedArc,
    pub no_plane_move: NoPlaneMove,
    /// Alarm for selecting or deselecting in a circle.
    pub not_linear: AlarmCode,
    /// 840C G451 caps its tangent extension beyond this change of direction (three blocks).
    pub intersection_cap_deg: f64,
    /// I J K in the cancel block give the direction the last corner is built against (Fanuc
    /// C, "Tool movement in offset mode cancel"); elsewhere they are refused.
    pub exit_vector: bool,
}

/// A side change (G41↔G42) while TRC is active, without a programmed method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SideChange {
    /// Deselect at the last point and reselect with this method (840C 11.6.2: G456; 808D:
    /// normal position); `None` uses the modal method (ISG).
    Reselect(Option<SelectionPolicy>),
    /// Fanuc C, "change in the offset direction in the offset mode": no deselection; the
    /// path switches sides where the old side's equidistant of the previous element meets the
    /// new side's of the next, else on the next element's normal at its start.
    Intersection,
}

/// An alarm from the compensation, before it gets the program's name.
#[derive(Clone, Debug, PartialEq)]
pub struct TrcFault {
    pub code: AlarmCode,
    pub source: Source,
    pub message: String,
}

/// Faults are boxed: the `Result`s on the per-block path stay a pointer wide.
pub type Fault = Box<TrcFault>;

#[cold]
fn fault(code: AlarmCode, source: Source, message: impl Into<String>) -> Fault {
    Box::new(TrcFault {
        code,
        source,
        message: message.into(),
    })
}

/// Where segments go, in order: the compensation appends, preparation takes them from the
/// front. A vector and a read index rather than a ring: with the front in a thread of its own
/// the compensation appends straight into the batch that crosses to the back, and the back
/// reads the segments there, one step's at a time (`limit`; prep/front.rs), with no copy in
/// between. Preparation takes every segment before it asks for the next block, so the vector
/// starts again from its beginning then and never grows past what one block (or one batch)
/// puts out.
#[derive(Debug)]
pub struct Out {
    segs: Vec<Segment>,
    next: usize,
    /// Segments from here on are not to be taken yet.
    limit: usize,
}

/// Empty, with no room yet (no allocation).
impl Default for Out {
    fn default() -> Self {
        Self::with_capacity(0)
    }
}

impl Out {
    /// Room for far more than one block puts out (held blocks + element + approach, corner
    /// and retract pieces): no allocation after the start.
    pub fn new() -> Self {
        Self::with_capacity(64)
    }

    pub fn with_capacity(n: usize) -> Self {
        Out {
            segs: Vec::with_capacity(n),
            next: 0,
            limit: usize::MAX,
        }
    }

    #[inline]
    pub fn push_back(&mut self, s: Segment) {
        self.segs.push(s);
    }

    #[inline]
    pub fn pop_front(&mut self) -> Option<Segment> {
        if self.next >= self.limit {
            return None;
        }
        let s = *self.segs.get(self.next)?;
        self.next += 1;
        self.reclaim();
        Some(s)
    }

    /// The index of the next segment, taken (it stays where it is until the next take, for
    /// a reader that looks at it in place: [`Self::at`]).
    #[inline]
    pub fn take_index(&mut self) -> Option<usize> {
        if self.next >= self.limit || self.next >= self.segs.len() {
            return None;
        }
        self.next += 1;
        Some(self.next - 1)
    }

    /// Segment `i` as put in.
    #[inline]
    pub fn at(&self, i: usize) -> &Segment {
        &self.segs[i]
    }

    /// With every segment taken (and no reader's limit on the indices): starts again at the
    /// front. [`Self::pop_front`] does so at once; a reader by [`Self::take_index`], whose
    /// segment is still lent, before the next take.
    #[inline]
    pub fn reclaim(&mut self) {
        if self.next == self.segs.len() && self.limit == usize::MAX {
            self.segs.clear();
            self.next = 0;
        }
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        self.next >= self.segs.len().min(self.limit)
    }

    /// Segments put in so far (taken ones included).
    pub fn len(&self) -> usize {
        self.segs.len()
    }

    /// Drops every segment; all may be taken again.
    pub fn clear(&mut self) {
        self.segs.clear();
        self.next = 0;
        self.limit = usize::MAX;
    }

    /// Only segments before index `limit` (of those put in) may be taken.
    pub fn limit_to(&mut self, limit: usize) {
        self.limit = limit;
    }
}

/// Feed and source of the block a segment belongs to.
#[derive(Clone, Copy, Debug)]
struct Tag {
    source: Source,
    feed: f64,
    per_rev: bool,
    thread: bool,
    rapid: bool,
    exact_stop: bool,
    /// ISG G11: the feed acts at the contour (adapted at arcs and transition blocks).
    adapt: bool,
}

/// A selection block waiting for the first contour element.
#[derive(Clone, Copy, Debug)]
struct Selection {
    tag: Tag,
    from: V2,
    q: V2,
    dir: Option<V2>,
    w0: f64,
    w1: f64,
    policy: SelectionPolicy,
}

/// A contour element whose compensated start is known and whose end waits for the next one.
#[derive(Clone, Copy, Debug)]
struct Pending {
    tag: Tag,
    prog: Elem,
    /// Compensated start.
    start: V2,
    /// Offset at the end (the start's is built into `start`).
    d1: f64,
    /// The equidistant at `d1` the end corner is built on (checked when the element came).
    carrier: Elem,
    w0: f64,
    w1: f64,
}

/// A block outside the compensation plane, executed at the end of the pending element (11.11).
#[derive(Clone, Copy, Debug)]
struct Held {
    tag: Tag,
    w0: f64,
    w1: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Off,
    /// Selected but no plane move yet (11.5.2).
    Armed,
    On,
}

/// The compensation state machine.
pub struct Compensator {
    rules: TrcRules,
    suppression: f64,
    max_outside: usize,
    mode: Mode,
    side: TrcSide,
    /// Signed offset: > 0 left of the path.
    d: f64,
    /// A radius change waiting for its block (ISG: the next linear block).
    ramp_from: Option<f64>,
    plane: Plane,
    corner: CornerPolicy,
    /// Selection method for the next selection (block-level or modal).
    method: SelectionPolicy,
    /// Deselection armed by a G40 without a plane move.
    exit_armed: Option<SelectionPolicy>,
    /// Tool position in plane coordinates, and along the normal axis.
    tool: V2,
    tool_w: f64,
    selection: Option<Selection>,
    pending: Option<Pending>,
    held: heapless::Vec<Held, 8>,
    /// Blocks outside the plane since the last plane block (moves, aux, calculations).
    outside: usize,
    /// ISG G238: the closed contour's last element, read ahead by the preparation.
    closing: Option<(Motion, Source)>,
    /// ISG G238 active: the inner corner where the contour started and will end.
    inner_exit: Option<V2>,
    /// Fanuc side change in offset mode: the next element switches sides (SideChange).
    switching: bool,
    /// Blocks seen, for `Source::seq`.
    seq: u32,
    /// ISG contour masking (G141) in the current block.
    masking: bool,
    /// Minimum contour radius for feed adaption (G11), mm.
    feed_rmin: f64,
    /// Alarm 3021 only warns (machine data `trc.violation_reaction = warn`).
    warn_violations: bool,
    /// The last contour element (programmed, in the plane) and the smaller tool radius it is
    /// cut with, for the bottleneck check.
    last_element: Option<(Elem, f64)>,
    warnings: heapless::Deque<TrcFault, 4>,
}

fn split(p: &Pos, plane: Plane) -> (V2, f64) {
    (
        v2(p[plane.abscissa as usize], p[plane.ordinate as usize]),
        p[plane.normal as usize],
    )
}

fn join(v: V2, w: f64, plane: Plane) -> Pos {
    let mut p = [0.0; 3];
    p[plane.abscissa as usize] = v.x;
    p[plane.ordinate as usize] = v.y;
    p[plane.normal as usize] = w;
    p
}

/// A coordinate for a message: up to 4 decimals, no trailing zeros.
fn num4(v: f64) -> String {
    let s = format!("{:.4}", v + 0.0);
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn side_sign(side: TrcSide) -> f64 {
    match side {
        TrcSide::Left => 1.0,
        TrcSide::Right => -1.0,
        TrcSide::Off => 0.0,
    }
}

/// The block moves in the plane or programs an axis of it, even without a path (840C 11.3,
/// 11.6.2).
fn has_plane_axis(motion: Option<&Motion>) -> bool {
    motion.is_some_and(|m| {
        m.moves_in_plane(EPS)
            || m.programmed & ((1 << m.plane.abscissa) | (1 << m.plane.ordinate)) != 0
    })
}

/// What a block's G40/G41/G42 asks of the compensation: a deselection, a selection, or both
/// (a restart: deselect at the last point, select at the programmed one).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Request {
    deselect: Option<SelectionPolicy>,
    select: Option<SelectionPolicy>,
}

impl Request {
    const NONE: Request = Request {
        deselect: None,
        select: None,
    };

    fn select(m: SelectionPolicy) -> Request {
        Request {
            deselect: None,
            select: Some(m),
        }
    }

    fn deselect(m: SelectionPolicy) -> Request {
        Request {
            deselect: Some(m),
            select: None,
        }
    }

    fn restart(m: SelectionPolicy) -> Request {
        Request {
            deselect: Some(m),
            select: Some(m),
        }
    }

    fn is_none(self) -> bool {
        self.deselect.is_none() && self.select.is_none()
    }
}

/// Alarm 3021 for an element the trimmed equidistant runs backwards on (840C 11.12).
#[cold]
fn too_large(source: Source) -> Fault {
    fault(
        AlarmCode::ContourViolation,
        source,
        "contour violation: the tool radius is too large for this element (840C 11.12)",
    )
}

/// Alarm 10762 for an inner-corner selection without a path (TF5200 "Selecting inside
/// corner of TRC"): `en` is the contour's last element, from the block at `last`.
#[cold]
fn inner_corner_fault(x: InnerCornerError, sel: &Selection, en: &Elem, last: Source) -> Fault {
    let (source, msg) = match x {
        InnerCornerError::NotClosed => (
            last,
            format!(
                "selection at an inner corner: the contour is not closed: its last block before the deselection ends at ({}, {}), not at the approach block's end point ({}, {})",
                num4(en.end().x),
                num4(en.end().y),
                num4(sel.q.x),
                num4(sel.q.y)
            ),
        ),
        InnerCornerError::FirstNotLinear => (
            sel.tag.source,
            "selection at an inner corner: the first contour block after the approach block must be a straight line".to_string(),
        ),
        InnerCornerError::NotInner => (
            sel.tag.source,
            "selection at an inner corner: the corner from the contour's last to its first block is not an inner corner on the tool side".to_string(),
        ),
        InnerCornerError::NoIntersection => (
            sel.tag.source,
            "selection at an inner corner: the tool does not fit into the inner corner at the approach block's end point".to_string(),
        ),
    };
    fault(AlarmCode::InnerCornerSelection, source, msg)
}

impl Compensator {
    /// `max_outside`: blocks allowed outside the plane between two plane blocks (11.11);
    /// `suppression`: the 11.14 distance.
    pub fn new(
        rules: TrcRules,
        max_outside: u32,
        suppression: f64,
        start: Pos,
        plane: Plane,
    ) -> Self {
        let (tool, tool_w) = split(&start, plane);
        Compensator {
            rules,
            suppression,
            max_outside: (max_outside as usize).min(8),
            mode: Mode::Off,
            side: TrcSide::Off,
            d: 0.0,
            ramp_from: None,
            plane,
            corner: CornerPolicy::TransitionCircle,
            method: SelectionPolicy::NormalPosition,
            exit_armed: None,
            tool,
            tool_w,
            selection: None,
            pending: None,
            held: heapless::Vec::new(),
            outside: 0,
            closing: None,
            inner_exit: None,
            switching: false,
            seq: 0,
            masking: false,
            feed_rmin: 0.0,
            warn_violations: false,
            last_element: None,
            warnings: heapless::Deque::new(),
        }
    }

    /// Minimum contour radius for feed adaption (ISG G11; TF5200 #TANGFEED RMIN).
    pub fn set_feed_adaption_rmin(&mut self, rmin: f64) {
        self.feed_rmin = rmin.max(0.0);
    }

    /// Alarm 3021 as a warning, the path going on (`trc.violation_reaction = warn`).
    pub fn warn_on_violation(&mut self, warn: bool) {
        self.warn_violations = warn;
    }

    /// ISG G238: the last element of the contour the coming selection starts (the last
    /// plane move before its G40), or `None` if no G40 follows.
    pub fn close_contour(&mut self, last: Option<(Motion, Source)>) {
        self.closing = last;
    }

    /// Compensation is off: selected nowhere, and no deselection waits for a plane move.
    pub fn is_off(&self) -> bool {
        self.mode == Mode::Off
    }

    /// True while blocks wait for the next element (their segments are not out yet).
    pub fn holds_back(&self) -> bool {
        self.pending.is_some() || self.selection.is_some() || !self.held.is_empty()
    }

    fn settings(&self) -> CornerSettings {
        let outer = match self.corner {
            CornerPolicy::TransitionCircle => OuterCorner::Circle,
            CornerPolicy::Intersection => OuterCorner::IntersectionBlocks {
                cap: self.rules.intersection_cap_deg.to_radians(),
            },
            CornerPolicy::IntersectionLimited { limit_deg } => OuterCorner::Intersection {
                limit: limit_deg.to_radians(),
            },
            CornerPolicy::LinearTransition => OuterCorner::LinearTransition,
            CornerPolicy::ExtendedIntersection => OuterCorner::FanucC,
        };
        CornerSettings {
            outer,
            suppression: self.suppression,
        }
    }

    /// One interpreted block; `motion` is the block's motion with the tool length applied.
    pub fn block(
        &mut self,
        b: &Block,
        motion: Option<&Motion>,
        out: &mut Out,
    ) -> Result<(), Fault> {
        let tag = self.begin(b, motion);
        let new_d = side_sign(b.modal.trc) * b.modal.radius;
        match motion {
            Some(m) if self.continues_contour(b, m, new_d) => {
                let d = self.d;
                self.element(tag, m, d, d, out)?;
            }
            _ => self.decide(b, tag, motion, new_d, out)?,
        }
        self.end_of_block(b, out)
    }

    /// Counts the block and takes its modal settings: the tag its segments carry, the corner
    /// policy and masking; with compensation off, the plane and the tool position.
    #[inline]
    fn begin(&mut self, b: &Block, motion: Option<&Motion>) -> Tag {
        self.seq = self.seq.wrapping_add(1);
        let tag = Tag {
            source: b.source(self.seq),
            feed: b.thread.unwrap_or(b.modal.feed),
            per_rev: b.modal.feed_per_rev || b.thread.is_some(),
            thread: b.thread.is_some(),
            rapid: motion.is_some_and(|m| m.kind == MotionKind::Rapid),
            exact_stop: b.exact_stop || b.modal.exact_stop,
            adapt: b.modal.feed_adaption == FeedAdaption::Contour,
        };
        if let Some(m) = motion {
            if self.mode == Mode::Off {
                self.plane = m.plane;
                let (t, w) = split(&m.start, m.plane);
                self.tool = t;
                self.tool_w = w;
            }
        }
        self.corner = b.modal.corner;
        self.masking = b.modal.masking;
        tag
    }

    /// The common block: a contour element while compensation is on and the block asks
    /// nothing of it (no G40/G41/G42, no deselection waiting for a plane move, no radius
    /// change or ramp) — where [`Self::decide`] leads, without taking its decisions one by one.
    #[inline]
    fn continues_contour(&self, b: &Block, m: &Motion, new_d: f64) -> bool {
        self.mode == Mode::On
            && b.trc.is_none()
            && self.exit_armed.is_none()
            && self.ramp_from.is_none()
            && (new_d - self.d).abs() <= EPS
            && m.moves_in_plane(EPS)
    }

    /// Any other block: what it asks of the compensation (deselection, selection, a side or
    /// radius change), then the path for the mode the compensation is in.
    fn decide(
        &mut self,
        b: &Block,
        tag: Tag,
        motion: Option<&Motion>,
        new_d: f64,
        out: &mut Out,
    ) -> Result<(), Fault> {
        let mut req = self.request(b, tag.source, new_d)?;
        if req.deselect.is_none() {
            req.deselect = self.armed_exit_due(motion);
        }
        let d1 = self.radius_change(req, tag.source, new_d)?;
        let in_plane = motion.is_some_and(|m| m.moves_in_plane(EPS));
        let has_plane = has_plane_axis(motion);
        if let Some(policy) = req.deselect {
            // 840C 11.5.2: a deselection without an axis of the plane waits for one.
            if !has_plane && self.rules.no_plane_move == NoPlaneMove::Wait && req.select.is_none() {
                return self.arm_exit(tag, motion, policy, out);
            }
            let vector = b.exit_vector.as_deref();
            self.exit(tag, motion, policy, vector, req.select.is_some(), out)?;
            if req.select.is_none() {
                self.deselected(tag, motion, has_plane, out);
                return Ok(());
            }
        }
        if let Some(policy) = req.select {
            return self.select(b, tag, motion, policy, req.deselect.is_some(), out);
        }
        match self.mode {
            Mode::Armed => self.armed(tag, motion, has_plane, out),
            Mode::Off => {
                if let Some(m) = motion {
                    self.uncompensated(tag, m, out);
                }
                Ok(())
            }
            Mode::On => self.active(b, tag, motion, in_plane, d1, out),
        }
    }

    /// What the block's G40/G41/G42 asks, given the mode the compensation is in.
    fn request(&mut self, b: &Block, source: Source, new_d: f64) -> Result<Request, Fault> {
        let Some(side) = b.trc else {
            return Ok(Request::NONE);
        };
        let method = match (side, &b.exit_vector) {
            (TrcSide::Off, Some(_)) if self.rules.exit_vector => SelectionPolicy::ExitVector,
            _ => b.approach.unwrap_or(b.modal.selection),
        };
        Ok(match self.mode {
            Mode::Off if side != TrcSide::Off && b.modal.trc != TrcSide::Off => {
                Request::select(method)
            }
            Mode::Off => Request::NONE,
            Mode::Armed if side == TrcSide::Off => {
                // Deselected before it ever took effect.
                self.mode = Mode::Off;
                Request::NONE
            }
            Mode::Armed => Request::select(method),
            Mode::On if side == TrcSide::Off => Request::deselect(method),
            Mode::On if side == self.side => self.repetition(b, method),
            Mode::On => self.side_change(b, side, source, new_d)?,
        })
    }

    /// G41/G42 repeated on the active side: ignored unless a method comes with it (840C
    /// 11.6.1), or the compensation starts anew on every repetition (808D, Fanuc).
    fn repetition(&self, b: &Block, method: SelectionPolicy) -> Request {
        match (self.rules.repeat, b.approach) {
            (RepeatRule::Restart, a) => {
                Request::restart(a.unwrap_or(SelectionPolicy::NormalPosition))
            }
            (RepeatRule::IgnoreWithoutApproach, Some(_)) => Request::restart(method),
            (RepeatRule::IgnoreWithoutApproach, None) => Request::NONE,
        }
    }

    /// G41↔G42 while active: deselect at the last point and reselect (840C 11.6.2, 808D,
    /// ISG), or Fanuc C's switch where the equidistants meet, with the next element.
    fn side_change(
        &mut self,
        b: &Block,
        side: TrcSide,
        source: Source,
        new_d: f64,
    ) -> Result<Request, Fault> {
        if self.inner_exit.is_some() {
            // TF5200 error 90127: not permitted while the contour must close in its corner.
            return Err(fault(
                AlarmCode::InnerCornerSelection,
                source,
                "selection at an inner corner: the compensation side cannot change while it is active",
            ));
        }
        let fixed = match self.rules.side_change {
            SideChange::Intersection if b.approach.is_none() => {
                // Fanuc C: no deselection; the new side takes effect with the next element.
                self.side = side;
                self.d = new_d;
                self.switching = true;
                return Ok(Request::NONE);
            }
            SideChange::Reselect(m) => m,
            SideChange::Intersection => None,
        };
        Ok(Request::restart(
            b.approach.or(fixed).unwrap_or(b.modal.selection),
        ))
    }

    /// A G40 armed without a plane move takes effect with the next plane move (840C 11.5.2).
    #[inline]
    fn armed_exit_due(&self, motion: Option<&Motion>) -> Option<SelectionPolicy> {
        self.exit_armed
            .filter(|_| motion.is_some_and(|m| m.moves_in_plane(EPS)))
    }

    /// A radius change while active (840C 11.7, 808D, ISG): the radius the next element
    /// ends with (it starts with `self.d`).
    fn radius_change(&mut self, req: Request, source: Source, new_d: f64) -> Result<f64, Fault> {
        if self.mode != Mode::On || !req.is_none() || (new_d - self.d).abs() <= EPS {
            return Ok(self.d);
        }
        if self.inner_exit.is_some() {
            // TF5200 error 90127, as for the side.
            return Err(fault(
                AlarmCode::InnerCornerSelection,
                source,
                "selection at an inner corner: the tool radius cannot change while it is active",
            ));
        }
        if self.rules.radius_change == RadiusChange::NextLinear {
            // ISG (002): the block keeps the old radius; the next linear block ramps.
            self.ramp_from.get_or_insert(self.d);
            self.d = new_d;
        }
        Ok(new_d)
    }

    /// A deselection without an axis of the plane: armed for the next plane move; a move
    /// along the tool axis waits behind the last element (840C 11.5.2, 11.11).
    fn arm_exit(
        &mut self,
        tag: Tag,
        motion: Option<&Motion>,
        policy: SelectionPolicy,
        out: &mut Out,
    ) -> Result<(), Fault> {
        self.exit_armed = Some(policy);
        match motion {
            Some(m) => self.outside(tag, m, out),
            None => Ok(()),
        }
    }

    /// The compensation is off after the deselection block; without a plane axis that block
    /// moves back by the offset (Fanuc C cancel).
    fn deselected(&mut self, tag: Tag, motion: Option<&Motion>, has_plane: bool, out: &mut Out) {
        self.side = TrcSide::Off;
        self.d = 0.0;
        self.mode = Mode::Off;
        self.exit_armed = None;
        if !has_plane {
            if let Some(m) = motion {
                self.uncompensated(tag, m, out);
            }
        }
    }

    /// G41/G42 selects with `policy`. Without an axis of the plane the selection waits for
    /// the next plane move (840C 11.5.2), unless the block reselects after a deselection
    /// (`restart`: it starts at the last point, 11.6).
    fn select(
        &mut self,
        b: &Block,
        tag: Tag,
        motion: Option<&Motion>,
        policy: SelectionPolicy,
        restart: bool,
        out: &mut Out,
    ) -> Result<(), Fault> {
        self.side = b.modal.trc;
        self.d = side_sign(b.modal.trc) * b.modal.radius;
        self.ramp_from = None;
        self.exit_armed = None;
        self.method = policy;
        if !has_plane_axis(motion) && self.rules.no_plane_move == NoPlaneMove::Wait && !restart {
            self.mode = Mode::Armed;
            if let Some(m) = motion {
                self.uncompensated(tag, m, out);
            }
            return Ok(());
        }
        self.start_selection(tag, motion, policy, out)
    }

    /// Selected, no plane move yet: the first block with an axis of the plane starts the
    /// compensation; moves before it run uncompensated (840C 11.5.2).
    fn armed(
        &mut self,
        tag: Tag,
        motion: Option<&Motion>,
        has_plane: bool,
        out: &mut Out,
    ) -> Result<(), Fault> {
        match motion {
            Some(m) if has_plane => {
                let policy = self.method;
                self.start_selection(tag, Some(m), policy, out)
            }
            Some(m) => {
                self.uncompensated(tag, m, out);
                Ok(())
            }
            None => Ok(()),
        }
    }

    /// Active: a contour element with the radii it starts and ends with, or a block outside
    /// the plane (840C 11.11).
    fn active(
        &mut self,
        b: &Block,
        tag: Tag,
        motion: Option<&Motion>,
        in_plane: bool,
        d1: f64,
        out: &mut Out,
    ) -> Result<(), Fault> {
        match motion {
            Some(m) if in_plane => {
                let (e0, e1) = self.element_radii(tag, m, d1)?;
                self.element(tag, m, e0, e1, out)?;
                self.d = e1;
            }
            Some(m) => self.outside(tag, m, out)?,
            None => {
                if !b.words.is_empty() || b.calculation || b.dwell.is_some() {
                    self.count_outside(tag)?;
                }
            }
        }
        Ok(())
    }

    /// The radii an element starts and ends with: ISG ramps a change over the next linear
    /// block (002), the 840C changes the offset number in linear blocks only (11.7).
    fn element_radii(&mut self, tag: Tag, m: &Motion, d1: f64) -> Result<(f64, f64), Fault> {
        let (mut e0, mut e1) = (self.d, d1);
        if let Some(old) = self.ramp_from {
            if m.kind.is_arc() {
                return Err(fault(
                    AlarmCode::RadiusChangeNotLinear,
                    tag.source,
                    "the tool radius can only change with a linear block; program a straight move after the change",
                ));
            }
            e0 = old;
            e1 = self.d;
            self.ramp_from = None;
        }
        if (e1 - e0).abs() > EPS
            && m.kind.is_arc()
            && self.rules.radius_change == RadiusChange::InBlockLinear
        {
            return Err(fault(
                AlarmCode::RadiusChangeNotLinear,
                tag.source,
                "the offset number can only be changed in linear blocks (840C 11.7)",
            ));
        }
        Ok((e0, e1))
    }

    /// Program end (M02/M30): TRC ends with the last element in its normal position
    /// (11.5.1, "deselection not active").
    fn end_of_block(&mut self, b: &Block, out: &mut Out) -> Result<(), Fault> {
        if b.stop.is_some_and(|s| s.ends_program()) {
            self.finish(out)?;
        }
        Ok(())
    }

    /// Flushes everything held: the pending element ends in its normal position.
    pub fn finish(&mut self, out: &mut Out) -> Result<(), Fault> {
        // A selection block with nothing after it: straight to its programmed point.
        self.flush_selection(out);
        if let Some(p) = self.pending.take() {
            let end = p.prog.normal_end(p.d1);
            self.emit_pending(&p, end, out)?;
        }
        self.flush_held(out);
        self.mode = Mode::Off;
        self.side = TrcSide::Off;
        self.d = 0.0;
        self.inner_exit = None;
        self.switching = false;
        Ok(())
    }

    /// A selection block that never met a contour element runs to its programmed point;
    /// true if there was one.
    fn flush_selection(&mut self, out: &mut Out) -> bool {
        let Some(sel) = self.selection.take() else {
            return false;
        };
        self.line(
            sel.tag,
            Role::Approach,
            sel.from,
            sel.q,
            sel.w0,
            sel.w1,
            out,
        );
        true
    }

    fn uncompensated(&mut self, tag: Tag, m: &Motion, out: &mut Out) {
        let seg = segment_of(tag, Role::Uncompensated, m);
        let (t, w) = split(&m.end, m.plane);
        self.tool = t;
        self.tool_w = w;
        out.push_back(seg);
    }

    /// Alarm 3021: an error that stops preparation before the violating block, or with
    /// `violation_reaction = warn` a warning, and the path goes on (840C 11.12: "the effect of
    /// alarm 3021 can be influenced via machine data").
    fn violation(&mut self, f: Fault) -> Result<(), Fault> {
        if self.masking {
            // ISG G141: the path goes on to the bottleneck stage, which cuts the loop out.
            return Ok(());
        }
        if !self.warn_violations {
            return Err(f);
        }
        if self.warnings.is_full() {
            self.warnings.pop_front();
        }
        let _ = self.warnings.push_back(*f);
        Ok(())
    }

    /// The contour element the last block added (programmed, in the plane) and its tool
    /// radius; `None` for blocks that were not contour elements.
    pub fn take_element(&mut self) -> Option<(Elem, f64)> {
        self.last_element.take()
    }

    /// Warnings since the last call (violations under `violation_reaction = warn`).
    pub fn take_warning(&mut self) -> Option<TrcFault> {
        self.warnings.pop_front()
    }

    fn count_outside(&mut self, tag: Tag) -> Result<(), Fault> {
        if self.pending.is_none() && self.selection.is_none() {
            return Ok(());
        }
        self.outside += 1;
        if self.outside > self.max_outside {
            let f = fault(
                AlarmCode::ContourViolation,
                tag.source,
                format!(
                    "more than {} blocks outside the compensation plane (840C 11.11)",
                    self.max_outside
                ),
            );
            // The held-block buffer has room for 8 whatever the reaction; masking cannot help.
            if self.outside > 8 || (self.masking && !self.warn_violations) {
                return Err(f);
            }
            self.violation(f)?;
        }
        Ok(())
    }

    /// A block that does not move in the plane while TRC is active: it waits behind the
    /// pending element and runs at its end point (11.11).
    fn outside(&mut self, tag: Tag, m: &Motion, out: &mut Out) -> Result<(), Fault> {
        let (_, w0) = split(&m.start, self.plane);
        let (_, w1) = split(&m.end, self.plane);
        if self.pending.is_some() || self.selection.is_some() {
            self.count_outside(tag)?;
            let _ = self.held.push(Held { tag, w0, w1 });
        } else {
            let p = self.tool;
            self.line(tag, Role::Contour, p, p, w0, w1, out);
        }
        Ok(())
    }

    fn flush_held(&mut self, out: &mut Out) {
        // Nearly always empty: taking the buffer would copy all of its capacity.
        if self.held.is_empty() {
            return;
        }
        let p = self.tool;
        for h in std::mem::take(&mut self.held) {
            self.line(h.tag, Role::Contour, p, p, h.w0, h.w1, out);
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn line(&mut self, tag: Tag, role: Role, a: V2, b: V2, w0: f64, w1: f64, out: &mut Out) {
        self.put(tag, role, Shape::Line, a, b, w0, w1, out);
    }

    #[allow(clippy::too_many_arguments)]
    fn piece(
        &mut self,
        tag: Tag,
        role: Role,
        e: &Elem,
        r0: f64,
        r1: f64,
        w0: f64,
        w1: f64,
        out: &mut Out,
    ) {
        match *e {
            Elem::Line { a, b } => self.line(tag, role, a, b, w0, w1, out),
            Elem::Arc { a, b, c, ccw } => {
                let center = join(c, w0, self.plane);
                let shape = Shape::Arc {
                    center,
                    center_end: center,
                    ccw,
                    r0,
                    r1,
                    plane: self.plane,
                };
                self.put(tag, role, shape, a, b, w0, w1, out);
            }
        }
    }

    /// Emits one segment from `a` to `b` (plane points, tool-axis values `w0`, `w1`) and moves
    /// the tool there.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn put(
        &mut self,
        tag: Tag,
        role: Role,
        shape: Shape,
        a: V2,
        b: V2,
        w0: f64,
        w1: f64,
        out: &mut Out,
    ) {
        out.push_back(Segment {
            source: tag.source,
            role,
            shape,
            from: join(a, w0, self.plane),
            to: join(b, w1, self.plane),
            feed: tag.feed,
            per_rev: tag.per_rev,
            thread: tag.thread,
            rapid: tag.rapid,
            exact_stop: tag.exact_stop,
        });
        self.tool = b;
        self.tool_w = w1;
    }

    /// Inserted corner pieces: circles are corners, lines intermediate blocks (11.1).
    fn pieces(&mut self, tag: Tag, pieces: &[Elem], w: f64, out: &mut Out) {
        let r = self.d.abs();
        // ISG G11: transition blocks go round a corner of contour radius 0; the engagement
        // point is taken to move on the minimum radius (TF5200 #TANGFEED RMIN).
        let mut tag = tag;
        if tag.adapt && self.feed_rmin > 0.0 {
            tag.feed *= (self.feed_rmin + r) / self.feed_rmin;
        }
        for e in pieces {
            let (role, r) = match e {
                Elem::Arc { .. } => (Role::Corner, r),
                Elem::Line { .. } => (Role::Intermediate, 0.0),
            };
            self.piece(tag, role, e, r, r, w, w, out);
        }
    }

    fn elem_of(&self, m: &Motion) -> Elem {
        let (a, _) = split(&m.start, self.plane);
        let (b, _) = split(&m.end, self.plane);
        if m.kind.is_arc() {
            let (c, _) = split(&m.center, self.plane);
            Elem::Arc {
                a,
                b,
                c,
                ccw: m.kind == MotionKind::ArcCcw,
            }
        } else {
            Elem::Line { a, b }
        }
    }

    fn offset(&self, tag: Tag, e: &Elem, d: f64) -> Result<Elem, Fault> {
        e.offset(d).ok_or_else(|| {
            fault(
                AlarmCode::ArcRadiusTooSmall,
                tag.source,
                format!(
                    "circle radius {:.4} is not larger than the tool radius {:.4} on the tool side",
                    e.radius(),
                    d.abs()
                ),
            )
        })
    }

    /// The equidistant an element is cut along. Under masking, an arc the tool does not fit
    /// into gets its equidistant turned inside out (`Elem::equidistant`); the bottleneck
    /// window leaves it out and joins its neighbours.
    #[inline]
    fn carrier(&self, tag: Tag, e: &Elem, d: f64) -> Result<Elem, Fault> {
        if self.masking {
            e.equidistant(d).map_or_else(|| self.offset(tag, e, d), Ok)
        } else {
            self.offset(tag, e, d)
        }
    }

    fn corner_fault(tag: Tag, e: CornerError) -> Fault {
        match e {
            CornerError::NoIntersection => fault(
                AlarmCode::ContourViolation,
                tag.source,
                "the equidistants of this corner do not meet: the tool does not fit (840C 11.12)",
            ),
        }
    }

    /// A selection: the block `motion` (may be without plane move) starts the compensation.
    /// Its path waits for the first contour element ([`Self::enter`]).
    fn start_selection(
        &mut self,
        tag: Tag,
        motion: Option<&Motion>,
        policy: SelectionPolicy,
        out: &mut Out,
    ) -> Result<(), Fault> {
        self.mode = Mode::On;
        let (q, w1, w0, dir, arc) = match motion {
            Some(m) => {
                let (q, w1) = split(&m.end, self.plane);
                let (s, w0) = split(&m.start, self.plane);
                let e = self.elem_of(m);
                let dir = (q.dist(s) > EPS || m.kind.is_arc()).then(|| e.tangent_end());
                (q, w1, w0, dir, m.kind.is_arc())
            }
            None => (self.tool, self.tool_w, self.tool_w, None, false),
        };
        if arc && policy != SelectionPolicy::Perpendicular {
            // 840C 11.3, 808D, Fanuc 026: selection in straight blocks only; ISG leads onto
            // a circle perpendicularly instead (docs/trc.md).
            if let ArmedArc::Alarm(code) = self.rules.armed_arc {
                return Err(fault(
                    code,
                    tag.source,
                    "tool radius compensation can only be selected in a straight block (rapid traverse or linear interpolation)",
                ));
            }
        }
        if policy == SelectionPolicy::Perpendicular || arc {
            return self.select_perpendicular(tag, motion, w0, w1, out);
        }
        self.selection = Some(Selection {
            tag,
            from: self.tool,
            q,
            dir,
            w0,
            w1,
            policy,
        });
        Ok(())
    }

    /// ISG perpendicular selection (TF5200 G237): the selection block itself is the first
    /// contour element, and a perpendicular block leads from the tool onto its normal
    /// position. Without a plane move it waits for one.
    fn select_perpendicular(
        &mut self,
        tag: Tag,
        motion: Option<&Motion>,
        w0: f64,
        w1: f64,
        out: &mut Out,
    ) -> Result<(), Fault> {
        let Some(m) = motion.filter(|m| m.moves_in_plane(EPS)) else {
            self.mode = Mode::Armed;
            self.method = SelectionPolicy::Perpendicular;
            return Ok(());
        };
        let e = self.elem_of(m);
        let o = self.offset(tag, &e, self.d)?;
        let from = self.tool;
        let w = self.tool_w;
        self.line(tag, Role::Approach, from, o.start(), w, w, out);
        self.pending = Some(Pending {
            tag,
            prog: e,
            start: o.start(),
            d1: self.d,
            carrier: o,
            w0,
            w1,
        });
        Ok(())
    }

    /// A new contour element: resolves the pending one (or the selection) against it.
    fn element(
        &mut self,
        tag: Tag,
        m: &Motion,
        d0: f64,
        d1: f64,
        out: &mut Out,
    ) -> Result<(), Fault> {
        self.outside = 0;
        let e = self.elem_of(m);
        self.last_element = Some((e, d0.abs().min(d1.abs())));
        let (_, w0) = split(&m.start, self.plane);
        let (_, w1) = split(&m.end, self.plane);
        // 840C 11.7: the start corner is built with the old radius, the end corner with the
        // new one; the path joins the two.
        let o_start = self.carrier(tag, &e, d0)?;
        let o_end = if d1 == d0 {
            o_start
        } else {
            self.carrier(tag, &e, d1)?
        };
        let start = if let Some(sel) = self.selection.take() {
            self.enter(tag, &sel, &e, &o_start, d0, out)?
        } else if let Some(p) = self.pending.take() {
            self.turn(tag, &p, &e, &o_start, d0, out)?
        } else {
            o_start.start()
        };
        self.pending = Some(Pending {
            tag,
            prog: e,
            start,
            d1,
            carrier: o_end,
            w0,
            w1,
        });
        Ok(())
    }

    /// The selection block meets the first contour element `e` (equidistant `o1`): its path
    /// under the selection method (840C 11.2, 11.3; ISG; Fanuc start-up), and where the
    /// element's compensated path starts.
    fn enter(
        &mut self,
        tag: Tag,
        sel: &Selection,
        e: &Elem,
        o1: &Elem,
        d: f64,
        out: &mut Out,
    ) -> Result<V2, Fault> {
        // A side change before the first element: the selection goes to the new side.
        self.switching = false;
        let settings = self.settings();
        let en = if sel.policy == SelectionPolicy::InnerCorner {
            let en = self.inner_corner_entry(sel, e, o1, d, &settings)?;
            self.inner_exit = Some(en.start);
            en
        } else {
            selection::entry(sel.from, sel.q, sel.dir, e, o1, d, sel.policy, &settings)
                .map_err(|x| Self::corner_fault(tag, x))?
        };
        // A tangential approach (ISG G05) is an arc: its radius is its own.
        let r = en.path.radius();
        self.piece(sel.tag, Role::Approach, &en.path, r, r, sel.w0, sel.w1, out);
        self.flush_held(out);
        let w = self.tool_w;
        self.pieces(tag, &en.pieces, w, out);
        Ok(en.start)
    }

    /// The pending element `p` meets the next element `e` (equidistant `o2`) at a corner
    /// (840C 11.1, 11.4): `p` goes out up to it, the held blocks and the inserted pieces
    /// after it; returns where `e`'s compensated path starts.
    #[inline]
    fn turn(
        &mut self,
        tag: Tag,
        p: &Pending,
        e: &Elem,
        o2: &Elem,
        d: f64,
        out: &mut Out,
    ) -> Result<V2, Fault> {
        // Built where it is kept (a corner with its pieces is large).
        let mut c = Corner::tangent(p.carrier.end(), o2.start());
        let found = if std::mem::take(&mut self.switching) {
            c = corner::side_change(&p.carrier, o2);
            Ok(())
        } else {
            corner::corner_into(&p.carrier, o2, e.start(), d, &self.settings(), &mut c)
        };
        match found {
            Ok(()) => {}
            // ISG masking: the tool does not reach this corner; the bottleneck window closes
            // the gap where the equidistants meet further out (or raises the alarm).
            Err(_) if self.masking => c = corner::gap(&p.carrier, o2),
            Err(x) => return Err(Self::corner_fault(tag, x)),
        }
        self.emit_pending(p, c.end1, out)?;
        self.flush_held(out);
        let w = self.tool_w;
        self.pieces(tag, &c.pieces, w, out);
        Ok(c.start2)
    }

    /// ISG G238: the entry at the closed contour's inner corner (TF5200; docs/trc.md).
    fn inner_corner_entry(
        &mut self,
        sel: &Selection,
        e1: &Elem,
        o1: &Elem,
        d: f64,
        settings: &CornerSettings,
    ) -> Result<selection::Entry, Fault> {
        let Some((m, last)) = self.closing.take() else {
            return Err(fault(
                AlarmCode::InnerCornerSelection,
                sel.tag.source,
                "selection at an inner corner: no deselection follows; the contour must be closed and ended by a deselection",
            ));
        };
        let en = self.elem_of(&m);
        selection::inner_corner(sel.from, sel.q, e1, o1, &en, d, settings)
            .map_err(|x| inner_corner_fault(x, sel, &en, last))
    }

    /// Emits the pending element from its start to `end`; a trimmed element must still run
    /// forwards (840C 11.12).
    fn emit_pending(&mut self, p: &Pending, end: V2, out: &mut Out) -> Result<(), Fault> {
        self.emit(p, end, true, out)
    }

    /// [`Self::emit_pending`]; without `past_full_turn` an arc lengthened past a full turn
    /// runs only the rest beyond it, from its start along the circle to `end`.
    fn emit(
        &mut self,
        p: &Pending,
        end: V2,
        past_full_turn: bool,
        out: &mut Out,
    ) -> Result<(), Fault> {
        match p.prog {
            Elem::Line { a, b } => self.emit_line(p, a, b, end, out),
            Elem::Arc { .. } => self.emit_arc(p, end, past_full_turn, out),
        }
    }

    /// 840C 11.12: a line (programmed from `a` to `b`) whose trimmed equidistant runs
    /// backwards is a contour violation.
    #[inline]
    fn emit_line(
        &mut self,
        p: &Pending,
        a: V2,
        b: V2,
        end: V2,
        out: &mut Out,
    ) -> Result<(), Fault> {
        if violation::line_reverses(a, b, p.start, end) {
            self.violation(too_large(p.tag.source))?;
        }
        self.line(p.tag, Role::Contour, p.start, end, p.w0, p.w1, out);
        Ok(())
    }

    /// An arc along its carrier from the pending start to `end`: checked for running
    /// backwards (840C 11.12), in two pieces past a full turn (11.14, if `past_full_turn`), a
    /// full circle closed to the bit, its feed adapted (ISG G11).
    #[inline]
    fn emit_arc(
        &mut self,
        p: &Pending,
        end: V2,
        past_full_turn: bool,
        out: &mut Out,
    ) -> Result<(), Fault> {
        // The carrier's centre and sense: the programmed ones, but for a circle turned inside
        // out under masking (`carrier`).
        let Elem::Arc { c, ccw, .. } = p.carrier else {
            return Ok(());
        };
        let (total, ccw) = self.arc_sweep(p, end, ccw)?;
        if let Some(s) = total.filter(|s| past_full_turn && *s >= std::f64::consts::TAU - 1e-9) {
            self.emit_past_full_turn(p, end, c, ccw, s, out);
            return Ok(());
        }
        // A full circle run as programmed ends where it starts, to the bit (Shape::Arc): its
        // compensated ends come from two corners and may differ in the last place, which
        // would read as an arc of no length.
        let full = matches!(p.prog, Elem::Arc { a, b, .. } if a == b);
        let end = if total.is_none() && full {
            p.start
        } else {
            end
        };
        let r0 = p.start.dist(c);
        let r1 = end.dist(c);
        let e = Elem::Arc {
            a: p.start,
            b: end,
            c,
            ccw,
        };
        let tag = self.contour_feed(p, r0, r1);
        self.piece(tag, Role::Contour, &e, r0, r1, p.w0, p.w1, out);
        Ok(())
    }

    /// How far the pending arc turns once its ends moved to `p.start` and `end`, and its
    /// sense: `None` for the programmed sweep. An arc that runs backwards is a contour
    /// violation (840C 11.12); masking leaves it out (prep/bottleneck.rs), so it goes there
    /// the short way back, not as the rest of the circle.
    #[inline]
    fn arc_sweep(&mut self, p: &Pending, end: V2, ccw: bool) -> Result<(Option<f64>, bool), Fault> {
        Ok(match violation::arc_travel(&p.carrier, p.start, end) {
            violation::ArcTravel::Programmed => (None, ccw),
            violation::ArcTravel::Changed(s) => (Some(s), ccw),
            violation::ArcTravel::Reversed => {
                self.violation(too_large(p.tag.source))?;
                (None, ccw ^ self.masking)
            }
        })
    }

    /// 840C 11.14: an arc a corner lengthened past a full turn is traversed in full (the
    /// 840C only the part above 360°), as two arcs of half the sweep `s` each: an arc from
    /// its end points alone would turn only the rest.
    fn emit_past_full_turn(
        &mut self,
        p: &Pending,
        end: V2,
        c: V2,
        ccw: bool,
        s: f64,
        out: &mut Out,
    ) {
        let r0 = p.start.dist(c);
        let r1 = end.dist(c);
        let u = p.start - c;
        let half = if ccw { s / 2.0 } else { -s / 2.0 };
        let (sn, cs) = (libm::sin(half), libm::cos(half));
        let rm = 0.5 * (r0 + r1);
        let mid = c + v2(u.x * cs - u.y * sn, u.x * sn + u.y * cs) * (rm / r0.max(EPS));
        let first = Elem::Arc {
            a: p.start,
            b: mid,
            c,
            ccw,
        };
        let second = Elem::Arc {
            a: mid,
            b: end,
            c,
            ccw,
        };
        let wm = 0.5 * (p.w0 + p.w1);
        self.piece(p.tag, Role::Contour, &first, r0, rm, p.w0, wm, out);
        self.piece(p.tag, Role::Contour, &second, rm, r1, wm, p.w1, out);
    }

    /// ISG G11 (TF5200 G10/G11): the programmed feed acts at the contour, so the centre of a
    /// tool on an arc of centre radii `r0`..`r1` moves faster outside it and slower inside;
    /// arcs below the minimum radius keep the programmed feed (#TANGFEED RMIN).
    #[inline]
    fn contour_feed(&self, p: &Pending, r0: f64, r1: f64) -> Tag {
        let mut tag = p.tag;
        if tag.adapt {
            let rp = p.prog.radius();
            if rp >= self.feed_rmin && rp > EPS {
                tag.feed *= 0.5 * (r0 + r1) / rp;
            }
        }
        tag
    }

    /// Ends the compensation at the deselection block (`m`; `None` or no plane move: by the
    /// offset only; `vector`: Fanuc's I J K). With `reselect` the block starts a new
    /// compensation instead of retracting (840C 11.6, 808D).
    fn exit(
        &mut self,
        tag: Tag,
        m: Option<&Motion>,
        policy: SelectionPolicy,
        vector: Option<&Pos>,
        reselect: bool,
        out: &mut Out,
    ) -> Result<(), Fault> {
        if m.is_some_and(|m| m.kind.is_arc()) && !reselect {
            // 840C 11.5, 808D, Fanuc 026: deselection in straight blocks only.
            return Err(fault(
                self.rules.not_linear,
                tag.source,
                "tool radius compensation can only be deselected in a straight block (rapid traverse or linear interpolation)",
            ));
        }
        self.switching = false;
        // Deselected right after selecting: the selection block goes to its point.
        if self.flush_selection(out) {
            self.flush_held(out);
        }
        let Some(p) = self.pending.take() else {
            self.flush_held(out);
            // No contour element: the deselection block runs from where the tool stands
            // (the selection block's point) to its own end.
            if let Some(m) = m.filter(|_| !reselect) {
                let (f, w1) = split(&m.end, self.plane);
                let (from, w) = (self.tool, self.tool_w);
                if f.dist(from) > EPS || (w1 - w).abs() > EPS {
                    self.line(tag, Role::Retract, from, f, w, w1, out);
                }
            }
            return Ok(());
        };
        if let (SelectionPolicy::InnerCorner, Some(x)) = (policy, self.inner_exit.take()) {
            return self.exit_at_inner_corner(tag, m, &p, x, out);
        }
        let (f, mut dir, w1) = match m {
            Some(m) => {
                let (f, w1) = split(&m.end, self.plane);
                let (s, _) = split(&m.start, self.plane);
                let dir = (f.dist(s) > EPS).then(|| (f - s).unit());
                (f, dir, w1)
            }
            None => (p.prog.end(), None, p.w1),
        };
        let vector = vector.filter(|_| policy == SelectionPolicy::ExitVector);
        if let Some(v) = vector {
            // Only the vector's part in the plane counts; none there: the normal position.
            let (v, _) = split(v, self.plane);
            dir = (v.len() > EPS).then(|| v.unit());
        }
        let x = deselection::exit(&p.prog, &p.carrier, f, dir, p.d1, policy, &self.settings())
            .map_err(|x| Self::corner_fault(tag, x))?;
        // 0i-MF: an arc the intersection lengthens past a full turn is not traced more than
        // once; it runs from its start to the intersection.
        self.emit(&p, x.end, vector.is_none(), out)?;
        self.flush_held(out);
        let w = self.tool_w;
        self.pieces(tag, &x.pieces, w, out);
        if reselect {
            // The reselecting block starts at the last point; it becomes the selection block.
            return Ok(());
        }
        self.retract(tag, m, &p, &x.path, w1, out);
        Ok(())
    }

    /// ISG G238: the contour ends where it began, in the inner corner `x`, and the
    /// deselection block leaves from there straight to its programmed point (TF5200).
    fn exit_at_inner_corner(
        &mut self,
        tag: Tag,
        m: Option<&Motion>,
        p: &Pending,
        x: V2,
        out: &mut Out,
    ) -> Result<(), Fault> {
        self.emit_pending(p, x, out)?;
        self.flush_held(out);
        let (f, w1) = match m.filter(|m| m.moves_in_plane(EPS)) {
            Some(m) => split(&m.end, self.plane),
            None => (
                p.prog.end(),
                m.map_or(p.w1, |m| split(&m.end, self.plane).1),
            ),
        };
        let (from, w) = (self.tool, self.tool_w);
        self.line(tag, Role::Retract, from, f, w, w1, out);
        Ok(())
    }

    /// The deselection block's own move (role `retract`) along `path` to its programmed
    /// point; without a plane move back to the last element's end by the offset only
    /// (840C 11.5.2, Fanuc C cancel).
    fn retract(
        &mut self,
        tag: Tag,
        m: Option<&Motion>,
        p: &Pending,
        path: &Elem,
        w1: f64,
        out: &mut Out,
    ) {
        let w = self.tool_w;
        if m.is_some_and(|m| m.moves_in_plane(EPS)) {
            let r = path.radius();
            self.piece(tag, Role::Retract, path, r, r, w, w1, out);
        } else {
            let from = self.tool;
            self.line(tag, Role::Retract, from, p.prog.end(), w, w1, out);
        }
    }
}

/// An uncompensated motion as a segment.
fn segment_of(tag: Tag, role: Role, m: &Motion) -> Segment {
    let shape = Shape::of_motion(m);
    Segment {
        source: tag.source,
        role,
        shape,
        from: m.start,
        to: m.end,
        feed: tag.feed,
        per_rev: tag.per_rev,
        thread: tag.thread,
        rapid: tag.rapid,
        exact_stop: tag.exact_stop,
    }
}

/// What the compensation's unit tests share: the east line from (0, 0) to (10, 0) with the
/// tool left of it at R 2, and corners taken as transition circles.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::corner::{CornerSettings, OuterCorner};
    use super::geom::{v2, Elem, V2};

    pub fn close(a: V2, b: V2) -> bool {
        a.dist(b) < 1e-12
    }

    pub const CIRCLE: CornerSettings = CornerSettings {
        outer: OuterCorner::Circle,
        suppression: 0.0,
    };

    /// The element east from (0, 0) to (10, 0), and its equidistant on y = 2.
    pub fn east() -> (Elem, Elem) {
        (
            Elem::Line {
                a: v2(0.0, 0.0),
                b: v2(10.0, 0.0),
            },
            Elem::Line {
                a: v2(0.0, 2.0),
                b: v2(10.0, 2.0),
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontend::Interpreter;
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    fn machine(dialect: &str) -> MachineData {
        MachineData::load(None, &[format!("dialect={dialect}")]).unwrap()
    }

    fn compensator(dialect: &str) -> Compensator {
        let rules = crate::dialect::Dialect::get(machine(dialect).dialect).trc;
        Compensator::new(rules, 3, 0.0, [0.0; 3], Plane::XY)
    }

    /// A block under the dialect's initial modal state, with the tool radius 10 on `side`,
    /// programming `trc` (G40/G41/G42) and `approach`.
    fn block(
        dialect: &str,
        side: TrcSide,
        trc: Option<TrcSide>,
        approach: Option<SelectionPolicy>,
    ) -> Block {
        let (md, tools) = (machine(dialect), ToolTable::builtin());
        let mut modal = *Interpreter::new("t", "", &md, &tools).state();
        modal.trc = side;
        modal.radius = 10.0;
        let mut b = Block::new(1, 1, None, modal);
        b.trc = trc;
        b.approach = approach;
        b
    }

    /// Compensation on, left of the contour at R 10.
    fn active_left(dialect: &str) -> Compensator {
        let mut c = compensator(dialect);
        c.mode = Mode::On;
        c.side = TrcSide::Left;
        c.d = 10.0;
        c
    }

    fn source() -> Source {
        Source {
            number: None,
            line: 1,
            col: 1,
            seq: 1,
            program: 0,
        }
    }

    fn tag(feed: f64, adapt: bool) -> Tag {
        Tag {
            source: source(),
            feed,
            per_rev: false,
            thread: false,
            rapid: false,
            exact_stop: false,
            adapt,
        }
    }

    fn segments(out: &mut Out) -> Vec<Segment> {
        std::iter::from_fn(|| out.pop_front()).collect()
    }

    fn close(a: Pos, b: Pos) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12)
    }

    /// 840C 11.6.1: G41 repeated on the active side is ignored, unless G455/G456 comes with
    /// it: then deselect and reselect with that method. 808D restarts in the normal
    /// position on every repetition.
    #[test]
    fn a_repetition_is_ignored_unless_a_method_comes_with_it_or_the_control_restarts() {
        let g41 = Some(TrcSide::Left);
        let b = block("siemens-840c", TrcSide::Left, g41, None);
        let r = active_left("siemens-840c").request(&b, source(), 10.0);
        assert_eq!(r.unwrap(), Request::NONE);
        let compensated = Some(SelectionPolicy::Compensated);
        let b = block("siemens-840c", TrcSide::Left, g41, compensated);
        let r = active_left("siemens-840c").request(&b, source(), 10.0);
        assert_eq!(r.unwrap(), Request::restart(SelectionPolicy::Compensated));
        let b = block("siemens-808d", TrcSide::Left, g41, None);
        let r = active_left("siemens-808d").request(&b, source(), 10.0);
        assert_eq!(
            r.unwrap(),
            Request::restart(SelectionPolicy::NormalPosition)
        );
    }

    /// 840C 11.6.2: G42 after G41 without a method deselects and reselects in the normal
    /// position. Fanuc C changes the side in offset mode without either: the next element
    /// switches (d = −10). Under an inner-corner selection the side may not change (TF5200).
    #[test]
    fn a_side_change_reselects_on_the_840c_and_switches_in_place_on_fanuc() {
        let g42 = Some(TrcSide::Right);
        let b = block("siemens-840c", TrcSide::Right, g42, None);
        let r = active_left("siemens-840c").request(&b, source(), -10.0);
        assert_eq!(
            r.unwrap(),
            Request::restart(SelectionPolicy::NormalPosition)
        );
        let mut c = active_left("fanuc");
        let b = block("fanuc", TrcSide::Right, g42, None);
        assert_eq!(c.request(&b, source(), -10.0).unwrap(), Request::NONE);
        assert!(c.switching && c.side == TrcSide::Right && c.d == -10.0);
        let mut c = active_left("isg");
        c.inner_exit = Some(v2(0.0, 0.0));
        let b = block("isg", TrcSide::Right, g42, None);
        let f = c.request(&b, source(), -10.0).unwrap_err();
        assert_eq!(f.code, AlarmCode::InnerCornerSelection);
    }

    /// 840C 11.5.2: G40 before the armed selection ever met a plane move deselects it;
    /// G41 with compensation off selects with the modal method.
    #[test]
    fn g40_disarms_a_waiting_selection_and_g41_selects_with_the_modal_method() {
        let mut c = compensator("siemens-840c");
        c.mode = Mode::Armed;
        let b = block("siemens-840c", TrcSide::Off, Some(TrcSide::Off), None);
        assert_eq!(c.request(&b, source(), 0.0).unwrap(), Request::NONE);
        assert_eq!(c.mode, Mode::Off);
        let b = block("siemens-840c", TrcSide::Left, Some(TrcSide::Left), None);
        let r = c.request(&b, source(), 10.0).unwrap();
        assert_eq!(r, Request::select(SelectionPolicy::Compensated));
    }

    /// 840C 11.7: a new offset in a circle is refused; in a line the element starts with the
    /// old radius and ends with the new one. ISG (002) ramps a change over the next linear
    /// block, and refuses a circle there.
    #[test]
    fn a_radius_change_goes_over_a_line_and_never_over_a_circle_where_the_control_says_so() {
        let arc = Motion {
            kind: MotionKind::ArcCcw,
            plane: Plane::XY,
            start: [10.0, 0.0, 0.0],
            end: [0.0, 10.0, 0.0],
            center: [0.0; 3],
            programmed: 3,
        };
        let line = Motion {
            kind: MotionKind::Linear,
            ..arc
        };
        let t = tag(100.0, false);
        let mut c = active_left("siemens-840c");
        let f = c.element_radii(t, &arc, 5.0).unwrap_err();
        assert_eq!(f.code, AlarmCode::RadiusChangeNotLinear);
        assert_eq!(c.element_radii(t, &line, 5.0).unwrap(), (10.0, 5.0));
        // ISG: the block with the change kept 10 and set the ramp; the next line runs 10 → 5.
        let mut c = active_left("isg");
        c.ramp_from = Some(10.0);
        c.d = 5.0;
        let f = c.element_radii(t, &arc, 5.0).unwrap_err();
        assert_eq!(f.code, AlarmCode::RadiusChangeNotLinear);
        assert_eq!(c.element_radii(t, &line, 5.0).unwrap(), (10.0, 5.0));
        assert_eq!(c.ramp_from, None);
    }

    /// 840C 11.11: up to three blocks outside the plane wait behind the pending element; the
    /// fourth is alarm 3021, or a warning under `violation_reaction = warn`.
    #[test]
    fn the_fourth_block_outside_the_plane_is_a_contour_violation() {
        for warn in [false, true] {
            let mut c = active_left("siemens-840c");
            c.warn_on_violation(warn);
            c.pending = Some(Pending {
                tag: tag(100.0, false),
                prog: Elem::Line {
                    a: v2(0.0, 0.0),
                    b: v2(10.0, 0.0),
                },
                start: v2(0.0, 10.0),
                d1: 10.0,
                carrier: Elem::Line {
                    a: v2(0.0, 10.0),
                    b: v2(10.0, 10.0),
                },
                w0: 0.0,
                w1: 0.0,
            });
            for _ in 0..3 {
                c.count_outside(tag(100.0, false)).unwrap();
            }
            let fourth = c.count_outside(tag(100.0, false));
            assert_eq!(fourth.is_err(), !warn);
            assert_eq!(c.take_warning().is_some(), warn);
        }
    }

    /// 840C 11.5.2 and 11.11, through `block`: N40 G40 has no axis of the plane and waits;
    /// N50 Z5 waits behind N30 and runs at its end; N60 deselects. N20 selects north to
    /// (0,10) with G455 and G450, N30 runs east (tool left, R 10): a right turn, so the
    /// selection block's equidistant x = −10 ends at (−10, 10) and the transition circle
    /// about (0,10) belongs to N30, to P2 = (0, 20). N60 goes on east: tangent, so N30
    /// ends in its normal position (40, 20) and N60 runs from there to (60, 10).
    #[test]
    fn a_deselection_without_a_plane_axis_waits_for_the_next_plane_move() {
        let text = "N10 G0 X0 Y0\nN20 G41 G450 D1 G1 X0 Y10 F100\nN30 X40\nN40 G40\nN50 Z5\nN60 X60\nN70 M30\n";
        let (md, tools) = (machine("siemens-840c"), ToolTable::builtin());
        let mut interp = Interpreter::new("t", text, &md, &tools);
        let mut c = compensator("siemens-840c");
        let mut out = Out::new();
        while let Some(b) = interp.next_block().unwrap() {
            c.block(b, b.motion.as_ref(), &mut out).unwrap();
        }
        let got: Vec<_> = segments(&mut out)
            .into_iter()
            .map(|s| (s.source.line, s.role, s.from, s.to))
            .collect();
        let want = [
            (1, Role::Uncompensated, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
            (2, Role::Approach, [0.0, 0.0, 0.0], [-10.0, 10.0, 0.0]),
            (3, Role::Corner, [-10.0, 10.0, 0.0], [0.0, 20.0, 0.0]),
            (3, Role::Contour, [0.0, 20.0, 0.0], [40.0, 20.0, 0.0]),
            (5, Role::Contour, [40.0, 20.0, 0.0], [40.0, 20.0, 5.0]),
            (6, Role::Retract, [40.0, 20.0, 5.0], [60.0, 10.0, 5.0]),
        ];
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!(g.0 == w.0 && g.1 == w.1, "{g:?} != {w:?}");
            assert!(close(g.2, w.2) && close(g.3, w.3), "{g:?} != {w:?}");
        }
    }

    /// 840C 11.14 (the seed's caution): a full circle r 10 about the origin, counter-
    /// clockwise from (10,0), the tool outside (R 2, right: radius 12), its end moved on by
    /// 30° to (6√3, 6) by the next corner: 390° in all, out as two arcs of 195°. The middle
    /// is (12,0) turned by 195°: (−12·cos 15°, −12·sin 15°) = (−3(√6 + √2), −3(√6 − √2)).
    #[test]
    fn an_arc_lengthened_past_a_full_turn_goes_out_in_two_halves() {
        let mut c = active_left("siemens-840c");
        let start = v2(12.0, 0.0);
        let end = v2(6.0 * 3f64.sqrt(), 6.0);
        let p = Pending {
            tag: tag(100.0, false),
            prog: Elem::Arc {
                a: v2(10.0, 0.0),
                b: v2(10.0, 0.0),
                c: v2(0.0, 0.0),
                ccw: true,
            },
            start,
            d1: -2.0,
            carrier: Elem::Arc {
                a: start,
                b: start,
                c: v2(0.0, 0.0),
                ccw: true,
            },
            w0: 0.0,
            w1: 4.0,
        };
        let mut out = Out::new();
        c.emit_pending(&p, end, &mut out).unwrap();
        let s = segments(&mut out);
        let (r6, r2) = (6f64.sqrt(), 2f64.sqrt());
        let mid = [-3.0 * (r6 + r2), -3.0 * (r6 - r2), 2.0];
        assert_eq!(s.len(), 2, "{s:?}");
        assert!(
            close(s[0].from, [12.0, 0.0, 0.0]) && close(s[0].to, mid),
            "{s:?}"
        );
        assert!(
            close(s[1].from, mid) && close(s[1].to, [end.x, end.y, 4.0]),
            "{s:?}"
        );
        for seg in &s {
            let Shape::Arc { ccw, r0, r1, .. } = seg.shape else {
                panic!("{seg:?}")
            };
            assert!(ccw && (r0 - 12.0).abs() < 1e-12 && (r1 - 12.0).abs() < 1e-12);
        }
        // The same end reached without the extra turn (moved back by 30° instead) is one
        // arc of 330°.
        let back = v2(6.0 * 3f64.sqrt(), -6.0);
        c.emit_pending(&p, back, &mut out).unwrap();
        assert_eq!(segments(&mut out).len(), 1);
    }

    /// ISG G11 (TF5200): on a programmed arc of radius 20 the centre of a tool outside it
    /// (radius 30) runs at F·30/20, inside (radius 10) at F·10/20, on a spiral at the mean
    /// of its radii; an arc below the minimum radius (25) keeps F. Transition pieces go round
    /// a corner of radius 0 taken as the minimum radius 5: F·(5 + 10)/5 with R 10.
    #[test]
    fn adapted_feed_scales_the_centre_feed_by_the_radius_ratio() {
        let mut c = active_left("isg");
        let p = Pending {
            tag: tag(1000.0, true),
            prog: Elem::Arc {
                a: v2(20.0, 0.0),
                b: v2(0.0, 20.0),
                c: v2(0.0, 0.0),
                ccw: true,
            },
            start: v2(30.0, 0.0),
            d1: -10.0,
            carrier: Elem::Arc {
                a: v2(30.0, 0.0),
                b: v2(0.0, 30.0),
                c: v2(0.0, 0.0),
                ccw: true,
            },
            w0: 0.0,
            w1: 0.0,
        };
        assert_eq!(c.contour_feed(&p, 30.0, 30.0).feed, 1500.0);
        assert_eq!(c.contour_feed(&p, 10.0, 10.0).feed, 500.0);
        // A radius changing over the block (808D): the mean of 30 and 34, F·32/20.
        assert_eq!(c.contour_feed(&p, 30.0, 34.0).feed, 1600.0);
        c.set_feed_adaption_rmin(25.0);
        assert_eq!(c.contour_feed(&p, 30.0, 30.0).feed, 1000.0);
        c.set_feed_adaption_rmin(5.0);
        let mut out = Out::new();
        let corner = Elem::Arc {
            a: v2(0.0, 10.0),
            b: v2(10.0, 0.0),
            c: v2(0.0, 0.0),
            ccw: false,
        };
        let lead = Elem::Line {
            a: v2(10.0, 0.0),
            b: v2(20.0, 0.0),
        };
        c.pieces(tag(1000.0, true), &[corner, lead], 0.0, &mut out);
        let s = segments(&mut out);
        assert_eq!((s[0].role, s[0].feed), (Role::Corner, 3000.0));
        assert_eq!((s[1].role, s[1].feed), (Role::Intermediate, 3000.0));
    }

    #[test]
    fn message_coordinates_drop_trailing_zeros() {
        assert_eq!(num4(12.345_67), "12.3457");
        assert_eq!(num4(-3.0), "-3");
        assert_eq!(num4(-0.0), "0");
        assert_eq!(num4(0.5), "0.5");
    }

    /// A Fanuc program through the interpreter and the compensator: (line, role, from, to)
    /// of every segment.
    fn fanuc_path(text: &str) -> Vec<(u32, Role, Pos, Pos)> {
        let (md, tools) = (machine("fanuc"), ToolTable::builtin());
        let mut interp = Interpreter::new("t", text, &md, &tools);
        let mut c = compensator("fanuc");
        let mut out = Out::new();
        while let Some(b) = interp.next_block().unwrap() {
            c.block(b, b.motion.as_ref(), &mut out).unwrap();
        }
        segments(&mut out)
            .into_iter()
            .map(|s| (s.source.line, s.role, s.from, s.to))
            .collect()
    }

    /// The path's last two segments: the last element's and the cancel block's.
    fn assert_exit(got: &[(u32, Role, Pos, Pos)], last: (u32, Pos), retract: (u32, Pos)) {
        let [.., a, b] = got else { panic!("{got:?}") };
        assert!(
            a.0 == last.0 && a.1 == Role::Contour && close(a.3, last.1),
            "{got:?}"
        );
        assert!(b.0 == retract.0 && b.1 == Role::Retract, "{got:?}");
        assert!(close(b.2, last.1) && close(b.3, retract.1), "{got:?}");
    }

    /// Fanuc 0i-MF, "Tool movement in offset mode cancel", G40 with I J K, in G17: N30 runs
    /// east at Y10, tool left at R 10 (D1) on y = 20. N40's I10 J10 is a virtual block
    /// north-east from (40,10) whose equidistant runs through (40 − 5√2, 10 + 5√2) along
    /// (1,1): y = 20 at x = 50 − 10√2 ≈ 35.858, where N30 ends; N40 goes from there to its
    /// programmed point (60, 0) uncompensated.
    #[test]
    fn fanuc_g40_with_i_j_ends_the_last_line_at_the_vectors_intersection() {
        let got = fanuc_path(
            "N10 G17 G0 X0. Y0.\nN20 G41 D1 G1 X0. Y10. F100.\nN30 X40.\nN40 G40 X60. Y0. I10. J10.\nN50 M30\n",
        );
        let x = [50.0 - 10.0 * std::f64::consts::SQRT_2, 20.0, 0.0];
        assert_exit(&got, (3, x), (4, [60.0, 0.0, 0.0]));
    }

    /// The same in G18 (Z abscissa, X ordinate) with I K, and a J that is not in the plane:
    /// N30 runs along +Z at X10, the tool left (+X) on X = 20; the vector (K, I) = (10, 10)
    /// gives Z = 50 − 10√2 as in G17. Positions are [X, Y, Z].
    #[test]
    fn fanuc_g40_with_i_k_in_g18_takes_the_vector_in_the_zx_plane() {
        let got = fanuc_path(
            "N10 G18 G0 X0. Z0.\nN20 G41 D1 G1 X10. Z0. F100.\nN30 Z40.\nN40 G40 X0. Z60. I10. J50. K10.\nN50 M30\n",
        );
        let x = [20.0, 0.0, 50.0 - 10.0 * std::f64::consts::SQRT_2];
        assert_exit(&got, (3, x), (4, [0.0, 0.0, 60.0]));
    }

    /// The last element an arc: N30 counter-clockwise about (0,0) from (20,0) to (0,20), the
    /// tool inside at R 5 (D2) on r = 15. N40's I0 J−10 (south): virtual equidistant x = 5,
    /// meeting r = 15 at (5, √200) = (5, 10√2), where N30 ends.
    #[test]
    fn fanuc_g40_with_i_j_after_an_arc_ends_it_on_its_equidistant() {
        let got = fanuc_path(
            "N10 G0 X30. Y-20.\nN20 G41 D2 G1 X20. Y0. F100.\nN30 G3 X0. Y20. R20.\nN40 G1 G40 X-30. Y0. I0. J-10.\nN50 M30\n",
        );
        let x = [5.0, 10.0 * std::f64::consts::SQRT_2, 0.0];
        assert_exit(&got, (3, x), (4, [-30.0, 0.0, 0.0]));
    }

    /// 0i-MF: "the tool does not trace the circle more than once". N30 is a full circle
    /// clockwise about (0,0) from (0,−20), the tool outside at R 5 on r = 25 (from (0,−25),
    /// heading −X). N40's I0 J10 (north, outer): virtual equidistant x = −5, meeting r = 25
    /// at (−5, −√600) = (−5, −10√6), just past the circle's end: N30 runs only the
    /// 11.5° (asin 0.2) from (0,−25) to there, as one arc, not 371.5° in two.
    #[test]
    fn fanuc_g40_with_i_j_after_a_full_circle_does_not_go_round_twice() {
        let got = fanuc_path(
            "N10 G0 X0. Y-40.\nN20 G41 D2 G1 X0. Y-20. F100.\nN30 G2 J20.\nN40 G1 G40 X0. Y-40. I0. J10.\nN50 M30\n",
        );
        let x = [-5.0, -10.0 * 6f64.sqrt(), 0.0];
        assert_exit(&got, (3, x), (4, [0.0, -40.0, 0.0]));
        let circle: Vec<_> = got.iter().filter(|s| s.0 == 3).collect();
        assert_eq!(circle.len(), 1, "{got:?}");
        assert!(close(circle[0].2, [0.0, -25.0, 0.0]), "{got:?}");
    }

    /// Without the dialect's rule a vector is ignored: the 840C's G40 block never carries
    /// one (the front end refuses I J K there), and the modal method decides.
    #[test]
    fn only_the_fanuc_rule_takes_an_exit_vector() {
        let mut b = block("siemens-840c", TrcSide::Off, Some(TrcSide::Off), None);
        b.exit_vector = Some(Box::new([1.0, 1.0, 0.0]));
        let mut c = active_left("siemens-840c");
        let r = c.request(&b, source(), 0.0).unwrap();
        assert_eq!(r.deselect, Some(b.modal.selection));
        let mut c = active_left("fanuc");
        let b = Block {
            modal: block("fanuc", TrcSide::Off, None, None).modal,
            ..b
        };
        let r = c.request(&b, source(), 0.0).unwrap();
        assert_eq!(r.deselect, Some(SelectionPolicy::ExitVector));
    }
}
