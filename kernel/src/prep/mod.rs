//! Block preparation: interpreted blocks in, the tool path out as [`Segment`]s.
//!
//! Per block: tool length compensation along the tool axis (the plane's normal), then tool
//! radius compensation ([`crate::trc`]). Streams: one block is read at a time, and the
//! compensation holds back only the element whose end depends on the next corner.

pub mod bottleneck;
pub mod decoder;
pub mod jsonl;
pub mod resume;
pub mod s_points;
pub mod tool_tip;

pub use bottleneck::{Bottleneck, Gouge, Reaction};
pub use decoder::Decoder;
pub use resume::{Interruption, Resumed};
pub use s_points::{AuxFunction, Prepared, SPoints, Stop};

use crate::alarm::{Alarm, AlarmCode};
use crate::dialect::Dialect;
use crate::frontend::block::{Block, Motion, TrcSide};
use crate::frontend::Interpreter;
use crate::machine_data::{MachineData, ViolationReaction};
use crate::segment::{Segment, Source};
use crate::tools::ToolTable;
use crate::trc::{Compensator, Out, TrcFault};

/// Streams the tool path of one program.
pub struct Preparation<'a> {
    name: &'a str,
    decoder: Decoder<'a>,
    trc: Compensator,
    out: Out,
    /// Tool length in effect on the tool axis, and the one the active offset asks for: a new
    /// length is traversed with the next move of the tool axis (002, 840C 11.5.2 "N15 Z..").
    length: f64,
    blocks: u64,
    done: bool,
    /// The end record is out (or an alarm ended the stream).
    ended: bool,
    s_points: SPoints,
    bottleneck: Bottleneck,
    /// Segments the bottleneck window let go, in order (room for all it can hold).
    released: heapless::Deque<Segment, { bottleneck::HELD + 8 }>,
    /// ISG contour masking (G141) in the last block.
    masking: bool,
    /// An alarm waiting until the path before it is out.
    deferred: Option<Alarm>,
    warn: bool,
    /// Records ready to hand out, in order (a segment and what waited for its start).
    ready: heapless::Deque<Prepared, 32>,
    /// Turning tools: nose centre to tool tip.
    tip: tool_tip::ToolTip,
}

impl<'a> Preparation<'a> {
    pub fn new(name: &'a str, source: &'a str, md: &'a MachineData, tools: &'a ToolTable) -> Self {
        let interp = Interpreter::new(name, source, md, tools);
        let (plane, start) = (interp.state().plane, interp.position());
        Self::with_decoder(name, Decoder::Direct(interp), plane, start, md)
    }

    /// The same stream, with the interpreter running ahead in a thread of `scope` (about
    /// twice the throughput on two cores for long programs; the output is identical).
    pub fn threaded<'scope>(
        scope: &'scope std::thread::Scope<'scope, 'a>,
        name: &'a str,
        source: &'a str,
        md: &'a MachineData,
        tools: &'a ToolTable,
    ) -> Self {
        let interp = Interpreter::new(name, source, md, tools);
        let (plane, start) = (interp.state().plane, interp.position());
        Self::with_decoder(name, Decoder::threaded(scope, interp), plane, start, md)
    }

    fn with_decoder(
        name: &'a str,
        decoder: Decoder<'a>,
        plane: crate::frontend::block::Plane,
        start: crate::frontend::block::Pos,
        md: &'a MachineData,
    ) -> Self {
        let rules = Dialect::get(md.dialect).trc;
        let mut trc = Compensator::new(
            rules,
            md.trc.max_blocks_outside_plane,
            md.trc.suppression_distance,
            start,
            plane,
        );
        trc.warn_on_violation(md.trc.violation_reaction == ViolationReaction::Warn);
        trc.set_feed_adaption_rmin(md.trc.feed_adaption_rmin);
        Preparation {
            name,
            decoder,
            trc,
            out: Out::new(),
            length: 0.0,
            blocks: 0,
            done: false,
            ended: false,
            s_points: SPoints::new(start, md.trc.aux_output, md.program.optional_stop),
            ready: heapless::Deque::new(),
            bottleneck: Bottleneck::new(md.trc.bottleneck_window as usize),
            released: heapless::Deque::new(),
            masking: false,
            deferred: None,
            warn: md.trc.violation_reaction == ViolationReaction::Warn,
            tip: tool_tip::ToolTip::new(),
        }
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
            if let Some(seg) = self.pop_path()? {
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
            if let Some(seg) = self.pop_path()? {
                if self.s_points.idle() {
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

    /// The next path segment through the bottleneck window (held back there until the
    /// window has passed it).
    #[inline]
    fn pop_path(&mut self) -> Result<Option<Segment>, Alarm> {
        let seg = self.pop_centre_path()?;
        match seg {
            Some(mut s) if !self.tip.idle() => {
                self.tip.shift(&mut s);
                Ok(Some(s))
            }
            s => Ok(s),
        }
    }

    /// The path of the nose centre (the tool centre) through the bottleneck window.
    #[inline]
    fn pop_centre_path(&mut self) -> Result<Option<Segment>, Alarm> {
        loop {
            if let Some(s) = self.released.pop_front() {
                return Ok(Some(s));
            }
            let Some(seg) = self.out.pop_front() else {
                return Ok(None);
            };
            let reaction = self.reaction();
            if self.bottleneck.bypass(reaction) {
                return Ok(Some(seg));
            }
            let found = self.bottleneck.push(seg, reaction, &mut self.released);
            self.on_gouge(found);
        }
    }

    /// A gouge the window found: a warning, or the end of preparation (true) with the path
    /// still held dropped (docs/trc.md).
    fn on_gouge(&mut self, found: Result<Option<Gouge>, Gouge>) -> bool {
        match found {
            Ok(None) => false,
            Ok(Some(g)) => {
                let w = self.gouge_alarm(&g);
                let _ = self.ready.push_back(Prepared::Warning(w));
                false
            }
            Err(g) => {
                self.stop_with(self.gouge_alarm(&g));
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
        Alarm {
            code: AlarmCode::ContourViolation,
            program: self.name.to_string(),
            line: g.path.line,
            col: g.path.col,
            block: g.path.number.map(|n| n.to_string()),
            message: format!(
                "contour violation: the tool path of {} comes within {:.4} mm of the contour of {} (tool radius {:.4}): a bottleneck narrower than the tool (840C 11.12)",
                name(&g.path),
                g.distance,
                name(&g.element),
                g.radius
            ),
        }
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
            if !self.s_points.idle() && !self.trc.holds_back() && self.bottleneck.is_empty() {
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
                if !self.ended {
                    self.ended = true;
                    self.s_points.finish(&mut self.ready);
                    return Ok(true);
                }
                return Ok(false);
            }
            let inner_corner = match self.decoder.next_block() {
                Ok(Some(b)) => decoder::selects_at_inner_corner(b),
                Ok(None) => {
                    self.done = true;
                    let r = self.trc.finish(&mut self.out);
                    if let Err(f) = r {
                        return Err(self.alarm(*f));
                    }
                    continue;
                }
                Err(a) => {
                    self.done = true;
                    self.ended = true;
                    return Err(a);
                }
            };
            self.blocks += 1;
            if inner_corner {
                let closing = self.decoder.closing();
                self.trc.close_contour(closing);
            }
            let block = self.decoder.current();
            self.tip.block(block, self.blocks as u32);
            self.s_points.set_plane(block.modal.plane);
            if !self.s_points.block(block, self.blocks as u32) {
                self.done = true;
                self.ended = true;
                return Err(Alarm {
                    code: AlarmCode::TooManyWords,
                    program: self.name.to_string(),
                    line: block.line,
                    col: block.col,
                    block: block.number.map(|n| n.to_string()),
                    message: "too many blocks with auxiliary functions wait for their S point"
                        .into(),
                });
            }
            let motion = block
                .motion
                .map(|m| with_length(&m, &mut self.length, block));
            if let Err(f) = self.trc.block(block, motion.as_ref(), &mut self.out) {
                // The path still in the bottleneck window has not been checked against the
                // contour after it: it does not go out (docs/trc.md).
                let a = self.alarm(*f);
                self.stop_with(a);
                self.bottleneck.discard();
                continue;
            }
            self.masking = block.modal.masking;
            self.bottleneck.set_plane(block.modal.plane);
            let element = self.trc.take_element();
            if let (Some((e, r)), false) = (element, self.bottleneck.bypass(self.reaction())) {
                let source = Source {
                    number: block.number,
                    line: block.line,
                    col: block.col,
                    seq: self.blocks as u32,
                };
                let side = match block.modal.trc {
                    TrcSide::Left => 1,
                    TrcSide::Right => -1,
                    TrcSide::Off => 0,
                };
                let found = self.bottleneck.element(source, e, r, side, self.reaction());
                if self.on_gouge(found) {
                    continue;
                }
            }
            while let Some(w) = self.trc.take_warning() {
                // Ahead of the segments of this block (`ready` is served first).
                let w = self.alarm(w);
                let _ = self.ready.push_back(Prepared::Warning(w));
            }
        }
    }

    fn alarm(&self, f: TrcFault) -> Alarm {
        Alarm {
            code: f.code,
            program: self.name.to_string(),
            line: f.source.line,
            col: f.source.col,
            block: f.source.number.map(|n| n.to_string()),
            message: f.message,
        }
    }
}

/// The motion with the tool length on the tool axis: the old length up to a block that
/// programs the tool axis, the new one from its end on.
fn with_length(m: &Motion, length: &mut f64, b: &Block) -> Motion {
    let n = m.plane.normal as usize;
    let mut m = *m;
    m.start[n] += *length;
    m.center[n] += *length;
    if m.programmed & (1 << n) != 0 {
        *length = b.modal.length;
    }
    m.end[n] += *length;
    m
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
