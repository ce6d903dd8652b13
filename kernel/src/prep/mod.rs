//! Block preparation: interpreted blocks in, the tool path out as [`Segment`]s.
//!
//! Per block: tool length compensation along the tool axis (the plane's normal), then tool
//! radius compensation ([`crate::trc`]). Streams: one block is read at a time, and the
//! compensation holds back only the element whose end depends on the next corner.

pub mod bottleneck;
pub mod front;
pub mod jsonl;
mod leads;
pub mod resume;
pub mod s_points;
mod soft_limits;
pub mod tool_tip;
mod whole;

pub use bottleneck::{Bottleneck, Gouge, Reaction, MAX_WINDOW};
pub use resume::{Interruption, Resumed};
pub use s_points::{AuxFunction, Prepared, SPoints, Stop};
pub use whole::Join;

use crate::alarm::{Alarm, AlarmCode};
use crate::frontend::Interpreter;
use crate::machine_data::{MachineData, ViolationReaction};
use crate::segment::{Segment, Source};
use crate::tools::ToolTable;
use crate::trc::Out;
use front::{Front, Step};

/// Streams the tool path of one program.
pub struct Preparation<'a> {
    name: &'a str,
    /// The subprogram files, to name the file an alarm is in.
    programs: &'a crate::ProgramLibrary,
    front: FrontEnd<'a>,
    out: Out,
    blocks: u64,
    done: bool,
    /// The end record is out (or an alarm ended the stream).
    ended: bool,
    s_points: SPoints,
    bottleneck: Bottleneck,
    /// Segments the bottleneck window let go, in order (room for all it can hold).
    released: std::collections::VecDeque<Segment>,
    /// ISG contour masking (G141) in the last block.
    masking: bool,
    /// The dialect can switch masking on.
    can_mask: bool,
    /// The compensation holds back part of the path after the last block.
    holds_back: bool,
    /// An alarm waiting until the path before it is out.
    deferred: Option<Alarm>,
    warn: bool,
    /// Records ready to hand out, in order (a segment and what waited for its start).
    ready: heapless::Deque<Prepared, 32>,
    /// Turning tools: nose centre to tool tip.
    tip: tool_tip::ToolTip,
    /// Where the program starts (the interpreter's initial position).
    start: crate::frontend::block::AxisPos,
    /// The additional axes' moves of blocks whose segment has not come out yet (block
    /// number in execution order, move), and the one of the segment that came out last.
    axis_moves: std::collections::VecDeque<(u32, crate::frontend::block::AxisMove)>,
    axes_out: Option<crate::frontend::block::AxisMove>,
    /// The axes' software limit switches, where the path is the machine's (the kernel,
    /// `softnc simulate` and `check`): a segment beyond them is an alarm.
    limits: Option<soft_limits::SoftLimits>,
    /// The whole-program check, when asked for (it allocates as the run grows).
    whole: Option<Box<whole::WholeCheck<'a>>>,
    whole_mode: WholeMode,
    /// Violations the whole-program check collected (`WholeMode::Collect`), and the run of
    /// consecutive path blocks too close to one element that is still growing.
    violations: Vec<Alarm>,
    group: Option<Group>,
    /// Preparation ended at a violation of the whole-program check.
    whole_stopped: bool,
    /// Bytes of the main program's text.
    source_len: usize,
}

/// What the whole-program check settles at `seg` (more than one only where a run ends);
/// all of them when collecting, else up to the first.
fn whole_gouges(w: &mut whole::WholeCheck, seg: &Segment, mode: WholeMode) -> Vec<Gouge> {
    let collect = mode == WholeMode::Collect;
    let mut gouges = Vec::new();
    w.segment(seg, &mut |g| {
        gouges.push(g);
        !collect
    });
    gouges
}

/// A record of [`Preparation::next_ref`]: a path segment lent, or any record moved out.
// Boxing the record would allocate once per segment where the window holds the path.
#[allow(clippy::large_enum_variant)]
#[derive(Debug)]
pub enum Lent<'p> {
    Segment(&'p Segment),
    Item(Prepared),
}

/// Consecutive path blocks too close to one element (collected as one alarm).
#[derive(Clone, Copy, Debug)]
struct Group {
    first: Gouge,
    last: Source,
    closest: f64,
}

/// What the whole-program check does at a violation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WholeMode {
    /// As the machine data's reaction says: alarm 3021 ends preparation (or, with
    /// `trc.violation_reaction = warn`, a warning). The bottleneck window stays on.
    Reaction,
    /// Every violation is collected and preparation goes on (`softnc check`); the window is
    /// left to masking, whose path it makes, since the whole check finds all it would.
    Collect,
    /// The first violation ends preparation; the window runs as without the check, so the
    /// path is the one the machine will run: a checker that runs ahead of the path (the
    /// kernel, `softnc simulate`).
    Stop,
}

/// Where the compensated blocks come from: the front in this thread, or in its own.
enum FrontEnd<'a> {
    Local(Box<Front<'a>>),
    Threaded(front::Threaded),
}

impl<'a> Preparation<'a> {
    pub fn new(name: &'a str, source: &'a str, md: &'a MachineData, tools: &'a ToolTable) -> Self {
        Self::starting_at(name, source, md, tools, None)
    }

    /// As `new`, with the axes at `at` before the first block (`None`: where the
    /// interpreter starts, the machine zero).
    pub fn starting_at(
        name: &'a str,
        source: &'a str,
        md: &'a MachineData,
        tools: &'a ToolTable,
        at: Option<crate::frontend::block::AxisPos>,
    ) -> Self {
        let mut interp = Interpreter::new(name, source, md, tools);
        if let Some(p) = at {
            interp = interp.starting_at(p);
        }
        let start = interp.axis_position();
        let front = Front::new(name, interp, md);
        Self::with_front(
            name,
            FrontEnd::Local(Box::new(front)),
            start,
            md,
            source.len(),
        )
    }

    /// The same stream, with interpretation and compensation running ahead in a thread of
    /// `scope` (the bottleneck window, S points and the tool tip stay in this one): about
    /// twice the throughput on two cores for long programs; the output is identical.
    pub fn threaded<'scope>(
        scope: &'scope std::thread::Scope<'scope, 'a>,
        name: &'a str,
        source: &'a str,
        md: &'a MachineData,
        tools: &'a ToolTable,
    ) -> Self {
        let interp = Interpreter::new(name, source, md, tools);
        let start = interp.axis_position();
        let front = Front::new(name, interp, md).threaded(scope);
        Self::with_front(name, FrontEnd::Threaded(front), start, md, source.len())
    }

    /// The kept macro variables (#500 …) as the program has left them so far (`None` with the
    /// front in a thread of its own: the runs that keep them prepare in one thread).
    pub fn kept_variables(&self) -> Option<Vec<(u32, f64)>> {
        match &self.front {
            FrontEnd::Local(f) => Some(f.kept_variables()),
            FrontEnd::Threaded(_) => None,
        }
    }

    fn with_front(
        name: &'a str,
        front: FrontEnd<'a>,
        start: crate::frontend::block::AxisPos,
        md: &'a MachineData,
        source_len: usize,
    ) -> Self {
        Preparation {
            source_len,
            name,
            programs: &md.programs,
            front,
            out: Out::new(),
            blocks: 0,
            done: false,
            ended: false,
            s_points: SPoints::new(start.geo, md.trc.aux_output, md.program.optional_stop),
            ready: heapless::Deque::new(),
            bottleneck: Bottleneck::new(md.trc.bottleneck_window as usize),
            released: std::collections::VecDeque::with_capacity(
                bottleneck::held_for((md.trc.bottleneck_window as usize).clamp(3, MAX_WINDOW)) + 8,
            ),
            masking: false,
            can_mask: crate::dialect::Dialect::get(md.dialect).masks(),
            holds_back: false,
            deferred: None,
            warn: md.trc.violation_reaction == ViolationReaction::Warn,
            tip: tool_tip::ToolTip::new(),
            start,
            axis_moves: std::collections::VecDeque::new(),
            axes_out: None,
            limits: None,
            whole: None,
            whole_mode: WholeMode::Reaction,
            violations: Vec::new(),
            group: None,
            whole_stopped: false,
        }
    }

    /// With the whole-program check: every tool-centre segment of a compensation run
    /// against every programmed element of the run (prep/whole.rs), reacting as `mode`
    /// says.
    pub fn checking_whole(mut self, mode: WholeMode) -> Self {
        let mut whole = whole::WholeCheck::new();
        // Room for about the blocks the main program's text holds (a CAM block takes two
        // dozen bytes and more): the run's records then grow in place, page by page, instead
        // of being copied at each doubling in bursts the front's thread would wait on. No
        // more than a doubling would claim.
        whole.reserve(self.source_len / 24);
        self.whole = Some(Box::new(whole));
        self.whole_mode = mode;
        self
    }

    /// The whole-program check does the check of a long run by two workers at once through
    /// `join` (without the check, nothing changes).
    pub fn with_join(mut self, join: &'a dyn Join) -> Self {
        if let Some(w) = &mut self.whole {
            w.with_join(join);
        }
        self
    }

    /// Preparation ended at a violation of the whole-program check (not another alarm).
    pub fn stopped_by_whole_check(&self) -> bool {
        self.whole_stopped
    }

    /// The violations the whole-program check collected so far (`WholeMode::Collect`), one
    /// alarm for each stretch of consecutive path blocks too close to one element; with
    /// `end`, the stretch still growing too (at the end of preparation).
    pub fn take_violations(&mut self, end: bool) -> Vec<Alarm> {
        if end {
            self.close_group();
        }
        std::mem::take(&mut self.violations)
    }

    /// A collected violation: it grows the stretch at hand (the next path block, the same
    /// element) or starts a new one.
    fn collect(&mut self, g: &Gouge) {
        if let Some(k) = &mut self.group {
            let next = g.path.seq.wrapping_sub(k.last.seq) <= 1;
            if next && g.element.seq == k.first.element.seq {
                k.last = g.path;
                k.closest = k.closest.min(g.distance);
                return;
            }
        }
        self.close_group();
        self.group = Some(Group {
            first: *g,
            last: g.path,
            closest: g.distance,
        });
    }

    fn close_group(&mut self) {
        let Some(k) = self.group.take() else {
            return;
        };
        let mut g = k.first;
        g.distance = k.closest;
        let mut alarm = self.gouge_alarm(&g);
        if k.last.seq != g.path.seq {
            let last = k
                .last
                .number
                .map_or_else(|| format!("line {}", k.last.line), |n| n.to_string());
            alarm.message =
                alarm
                    .message
                    .replacen(" comes within", &format!(" to {last} comes within"), 1);
        }
        self.violations.push(alarm);
    }

    /// The window holds the path: always but for `softnc check`'s collecting check, which
    /// finds every gouge the window would; there only where masking makes the path.
    #[inline]
    fn windowed(&self) -> bool {
        self.whole_mode != WholeMode::Collect || self.masking || !self.bottleneck.is_empty()
    }

    /// The window takes the programmed elements: wherever it may come to hold the path,
    /// which under `softnc check`'s collecting check is only where masking can begin.
    #[inline]
    fn window_meets_elements(&self) -> bool {
        let may_hold = self.whole_mode != WholeMode::Collect || self.can_mask;
        may_hold && !self.bottleneck.bypass(self.reaction())
    }

    /// With the software limit switches of `md` (alarm 10720 for a segment beyond them):
    /// the path the machine runs; without them the tool path of the program alone.
    pub fn with_soft_limits(mut self, md: &MachineData) -> Self {
        self.limits = soft_limits::SoftLimits::new(md);
        self
    }

    /// Some axis has software limits, and this preparation checks them.
    pub fn has_soft_limits(&self) -> bool {
        self.limits.is_some()
    }

    /// Where the program starts: the position before its first motion.
    pub fn start(&self) -> crate::frontend::block::AxisPos {
        self.start
    }

    /// Interpreted blocks so far.
    pub fn blocks(&self) -> u64 {
        self.blocks
    }

    /// The next segment of the tool path, skipping auxiliary functions and stops;
    /// `Ok(None)` at the end. After an alarm the stream ends.
    pub fn next_segment(&mut self) -> Result<Option<Segment>, Alarm> {
        loop {
            // Checked first: popping moves a whole (large) record even when there is none.
            if !self.ready.is_empty() {
                if let Some(Prepared::Segment(s)) = self.ready.pop_front() {
                    return Ok(Some(s));
                }
                continue;
            }
            if let Some(seg) = self.pop_path() {
                if self.s_points.idle() {
                    // Nothing waits for an S point (the common case): no queueing.
                    self.s_points.pass(&seg);
                    return Ok(Some(seg));
                }
                self.s_points.segment(seg, &mut self.ready);
                continue;
            }
            if !self.refill()? {
                return Ok(None);
            }
        }
    }

    /// The next record in execution order: segments, auxiliary functions at their S points,
    /// stops and the program end; `Ok(None)` at the end. After an alarm the stream ends.
    pub fn next_item(&mut self) -> Result<Option<Prepared>, Alarm> {
        loop {
            if let Some(x) = self.ready.pop_front() {
                return Ok(Some(x));
            }
            if let Some(seg) = self.pop_path() {
                if let Some(m) = self.axes_out.take() {
                    // Ahead of the segment and what waits for its start: the next segment's.
                    let _ = self.ready.push_back(Prepared::Axes(m, seg.source));
                }
                if self.s_points.idle() && self.ready.is_empty() {
                    self.s_points.pass(&seg);
                    return Ok(Some(Prepared::Segment(seg)));
                }
                self.s_points.segment(seg, &mut self.ready);
                continue;
            }
            if !self.refill()? {
                return Ok(None);
            }
        }
    }

    /// The next record as [`Self::next_item`] gives it, a path segment lent where it lies
    /// instead of moved out: a reader that only looks at the segments (`softnc check`) copies
    /// none of them. Segments that wait for something (the window, S points, a tool tip,
    /// additional axes) come the way `next_item` takes them.
    pub fn next_ref(&mut self) -> Result<Option<Lent<'_>>, Alarm> {
        let i = loop {
            if !self.lends() {
                return Ok(self.next_item()?.map(Lent::Item));
            }
            self.out.reclaim();
            let Some(i) = self.out.take_index() else {
                if !self.refill()? {
                    return Ok(None);
                }
                continue;
            };
            // As `pop_path` checks a segment, in place.
            if self.whole.is_some() && self.whole_segment_at(i) {
                continue;
            }
            let seg = self.out.at(i);
            if let Some(Err(o)) = self.limits.as_ref().map(|l| l.check(seg, None)) {
                let at = seg.source;
                self.overrun(&at, o);
                continue;
            }
            self.s_points.pass(self.out.at(i));
            break i;
        };
        Ok(Some(Lent::Segment(self.out.at(i))))
    }

    /// Whether the next segment, if the compensation has put one out, goes straight on: no
    /// record waits before it, the window lets it pass and nothing is added to it.
    #[inline]
    fn lends(&self) -> bool {
        self.ready.is_empty()
            && self.released.is_empty()
            && self.s_points.idle()
            && self.tip.idle()
            && self.axis_moves.is_empty()
            && self.axes_out.is_none()
            && (!self.windowed() || self.bottleneck.bypass(self.reaction()))
    }

    /// The next path segment through the bottleneck window (held back there until the
    /// window has passed it). An alarm on the way ends preparation through `deferred`; no
    /// `Result` around the segment, which the hot path would copy once more.
    #[inline]
    fn pop_path(&mut self) -> Option<Segment> {
        let mut seg = self.pop_centre_path();
        if self.whole.is_some() && seg.as_ref().is_some_and(|s| self.whole_segment(s)) {
            seg = None;
        }
        if let Some(s) = &mut seg {
            if !self.tip.idle() {
                self.tip.shift(s);
            }
            self.axes_out = None;
            if self
                .axis_moves
                .front()
                .is_some_and(|(q, _)| *q == s.source.seq)
            {
                self.axes_out = self.axis_moves.pop_front().map(|(_, m)| m);
            }
            if let Some(Err(o)) = self
                .limits
                .as_ref()
                .map(|l| l.check(s, self.axes_out.as_ref()))
            {
                self.overrun(&s.source, o);
                return None;
            }
        }
        seg
    }

    /// A segment past a software limit: preparation ends with the alarm before it.
    #[cold]
    fn overrun(&mut self, at: &Source, o: soft_limits::Overrun) {
        let name = at.program_name(self.name, self.programs);
        let alarm = Alarm::at(AlarmCode::SoftwareLimit, name, at, o.message());
        self.stop_with(alarm);
        self.released.clear();
        self.bottleneck.discard();
    }

    /// The path of the nose centre (the tool centre) through the bottleneck window.
    #[inline]
    fn pop_centre_path(&mut self) -> Option<Segment> {
        loop {
            if let Some(s) = self.released.pop_front() {
                return Some(s);
            }
            let seg = self.out.pop_front()?;
            let reaction = self.reaction();
            if self.bottleneck.bypass(reaction) || !self.windowed() {
                return Some(seg);
            }
            let found = self.bottleneck.push(seg, reaction, &mut self.released);
            self.on_gouge(found);
        }
    }

    /// A gouge the window found: a warning, or the end of preparation (true) with the path
    /// still held dropped (docs/trc.md).
    #[inline]
    fn on_gouge(&mut self, found: Result<Option<Gouge>, Gouge>) -> bool {
        // Nothing found (the common case) costs one test here.
        match found {
            Ok(None) => false,
            Ok(Some(g)) => self.gouge_found(&g, false),
            Err(g) => self.gouge_found(&g, true),
        }
    }

    /// A gouge found: a warning, or (`stop`) the end of preparation.
    #[inline(never)]
    fn gouge_found(&mut self, g: &Gouge, stop: bool) -> bool {
        let alarm = self.gouge_alarm(g);
        if stop {
            self.stop_with(alarm);
            self.bottleneck.discard();
        } else {
            let _ = self.ready.push_back(Prepared::Warning(alarm));
        }
        stop
    }

    /// A programmed element for the whole-program check (what it finds is settled at the
    /// end of the run).
    #[inline]
    fn whole_element(
        &mut self,
        source: Source,
        element: Option<(crate::trc::geom::Elem, f64)>,
        plane: crate::frontend::block::Plane,
        side: i8,
    ) {
        if let (Some(w), Some((e, r))) = (&mut self.whole, element) {
            w.set_plane(plane);
            w.element(source, e, r, side);
        }
    }

    /// A path segment for the whole-program check: true when a violation settled at it ends
    /// preparation (more than one is settled only where a run ends). Out of line: the
    /// per-segment path stays small when the check is off.
    #[inline(never)]
    fn whole_segment(&mut self, seg: &Segment) -> bool {
        let Some(w) = &mut self.whole else {
            return false;
        };
        let gouges = whole_gouges(w, seg, self.whole_mode);
        gouges.iter().any(|g| self.whole_found(g))
    }

    /// As [`Self::whole_segment`], for the segment `out` holds at `i`.
    #[inline(never)]
    fn whole_segment_at(&mut self, i: usize) -> bool {
        let Some(w) = &mut self.whole else {
            return false;
        };
        let gouges = whole_gouges(w, self.out.at(i), self.whole_mode);
        gouges.iter().any(|g| self.whole_found(g))
    }

    /// The program's end for the whole-program check: the violations that waited for the end
    /// of the last run (prep/leads.rs). True when one ends preparation.
    fn whole_finish(&mut self) -> bool {
        let Some(w) = &mut self.whole else {
            return false;
        };
        let mut gouges = Vec::new();
        w.finish(&mut |g| {
            gouges.push(g);
            false
        });
        gouges.iter().any(|g| self.whole_found(g))
    }

    /// A violation the whole-program check found; true when preparation ends with it (the
    /// segment at hand and what the window still holds do not go out).
    #[inline(never)]
    fn whole_found(&mut self, g: &Gouge) -> bool {
        match (self.whole_mode, self.reaction()) {
            (WholeMode::Collect, _) => {
                self.collect(g);
                false
            }
            (_, Reaction::Warn) => {
                let _ = self.ready.push_back(Prepared::Warning(self.gouge_alarm(g)));
                false
            }
            _ => {
                self.whole_stopped = true;
                self.stop_with(self.gouge_alarm(g));
                self.released.clear();
                self.bottleneck.discard();
                true
            }
        }
    }

    /// Preparation ends with `alarm`, once the path before it is out.
    fn stop_with(&mut self, alarm: Alarm) {
        self.done = true;
        self.ended = true;
        self.out.clear();
        self.deferred = Some(alarm);
    }

    fn reaction(&self) -> Reaction {
        if self.masking {
            Reaction::Mask
        } else if self.warn {
            Reaction::Warn
        } else {
            Reaction::Alarm
        }
    }

    fn gouge_alarm(&self, g: &Gouge) -> Alarm {
        let name = |s: &Source| {
            s.number
                .map_or_else(|| format!("line {}", s.line), |n| n.to_string())
        };
        let message = if g.unjoined {
            format!(
                    "contour violation: contour masking finds no gouge-free way past {} within the window: the tool (radius {:.4}) does not fit (840C 11.12)",
                    name(&g.path),
                    g.radius
                )
        } else {
            format!(
                    "contour violation: the tool path of {} comes within {:.4} mm of the contour of {} (tool radius {:.4}): a bottleneck narrower than the tool (840C 11.12)",
                    name(&g.path),
                    g.distance,
                    name(&g.element),
                    g.radius
                )
        };
        let name = g.path.program_name(self.name, self.programs);
        Alarm::at(AlarmCode::ContourViolation, name, &g.path, message)
    }

    /// With both queues empty: releases what waits for the current point, or reads and
    /// prepares blocks until the compensation puts something out. False at the very end.
    /// Kept out of line: the per-segment paths above stay small.
    #[inline(never)]
    fn refill(&mut self) -> Result<bool, Alarm> {
        loop {
            if !self.out.is_empty() || !self.released.is_empty() {
                return Ok(true);
            }
            if let Some(a) = self.deferred.take() {
                return Err(a);
            }
            if !self.s_points.idle() && !self.holds_back && self.bottleneck.is_empty() {
                // The path is out up to here: what waits is due at the current position.
                self.s_points.flush(&mut self.ready);
                return Ok(true);
            }
            if self.done {
                if !self.bottleneck.is_empty() {
                    let mask = self.masking;
                    if let Err(g) = self.bottleneck.flush(&mut self.released, mask) {
                        self.released.clear();
                        self.bottleneck.discard();
                        return Err(self.gouge_alarm(&g));
                    }
                    return Ok(true);
                }
                if self.whole_finish() {
                    continue;
                }
                if !self.ended {
                    self.ended = true;
                    self.s_points.finish(&mut self.ready);
                    return Ok(true);
                }
                return Ok(false);
            }
            let step = match &mut self.front {
                FrontEnd::Local(f) => f.step(&mut self.out),
                // While the front has nothing ready, the whole-program check walks the
                // run's complete part.
                FrontEnd::Threaded(t) => t.step(&mut self.out, &mut || {
                    self.whole.as_mut().is_some_and(|w| w.walk_some())
                }),
            };
            let b = match step {
                Step::Block(b) => b,
                Step::End { holds_back } => {
                    self.holds_back = holds_back;
                    self.done = true;
                    continue;
                }
                Step::EndFault(a) => {
                    self.done = true;
                    return Err(a);
                }
                Step::Decode(a) => {
                    self.done = true;
                    self.ended = true;
                    return Err(a);
                }
            };
            let info = b.info;
            let source = info.source;
            if let Some(m) = b.axes {
                self.axis_moves.push_back((source.seq, *m));
            }
            self.blocks = u64::from(source.seq);
            self.tip.block(info.tip, source.seq);
            self.s_points.set_plane(info.plane);
            let words_fit = self.s_points.block(source, b.words, info.stop, info.tech);
            let (element, fault) = (b.element, b.fault);
            self.holds_back = b.holds_back;
            // Warnings are rare: copied out only when there are any.
            let warnings = if b.warnings.is_empty() {
                Vec::new()
            } else {
                b.warnings.to_vec()
            };
            if !words_fit {
                self.done = true;
                self.ended = true;
                self.out.clear();
                return Err(Alarm::at(
                    AlarmCode::TooManyWords,
                    source.program_name(self.name, self.programs),
                    &source,
                    "too many blocks with auxiliary functions wait for their S point",
                ));
            }
            if let Some(a) = fault.map(|a| *a) {
                // The path still in the bottleneck window has not been checked against the
                // contour after it: it does not go out (docs/trc.md).
                self.stop_with(a);
                self.bottleneck.discard();
                continue;
            }
            self.masking = info.masking;
            self.bottleneck.set_plane(info.plane);
            self.whole_element(source, element, info.plane, info.side);
            // The window meets every element (masking may begin with the next block).
            if let (Some((e, r)), true) = (element, self.window_meets_elements()) {
                let found = self
                    .bottleneck
                    .element(source, e, r, info.side, self.reaction());
                if self.on_gouge(found) {
                    continue;
                }
            }
            for w in warnings {
                // Ahead of the segments of this block (`ready` is served first).
                let _ = self.ready.push_back(Prepared::Warning(w));
            }
        }
    }
}

impl Iterator for Preparation<'_> {
    type Item = Result<Segment, Alarm>;
    fn next(&mut self) -> Option<Self::Item> {
        self.next_segment().transpose()
    }
}

/// The whole tool path of a program, stopping at the first alarm (tests, small programs).
pub fn prepare(
    name: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
) -> Result<Vec<Segment>, Alarm> {
    Preparation::new(name, source, md, tools).collect()
}
