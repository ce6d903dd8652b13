//! The front half of block preparation: the interpreter's blocks through tool length and tool
//! radius compensation, one [`Step`] per block. The back half ([`super::Preparation`]: the
//! bottleneck window, S points, the tool tip) takes the steps in the same thread, or — with
//! [`Front::threaded`] — from a thread of their own, as controls split block decoding and
//! preparation into tasks. The steps, and so the output, are the same bit for bit.
//!
//! The thread hands steps over in batches: a fixed set of batch buffers circulates between
//! the two threads over two bounded channels (full ones to the back, empty ones back), so
//! nothing is allocated per block and the threads meet once per batch, not once per block.
//! The compensation appends its segments straight into the batch, and the back reads them
//! there: it swaps the batch's [`Out`] in as its own, one step's segments visible at a time.

use crate::alarm::Alarm;
use crate::frontend::block::{
    AuxWord, AxisMove, Block, Motion, Plane, ProgramStop, SelectionPolicy, Technology, TrcSide,
};
use crate::frontend::Interpreter;
use crate::machine_data::{MachineData, ViolationReaction};
use crate::segment::Source;
use crate::trc::cutting_edge::tip_vector;
use crate::trc::geom::{v2, Elem, V2};
use crate::trc::{Compensator, Out, TrcFault};
use crossbeam::channel::{bounded, Receiver, RecvError, Sender, TryRecvError};

/// What one block gave. Its segments went into the `out` the step was asked with.
pub enum Step<'b> {
    Block(BlockStep<'b>),
    /// The interpreter stopped with an alarm.
    Decode(Alarm),
    /// The program's end: the compensation's last segments are in `out`.
    End {
        holds_back: bool,
    },
    /// The compensation could not end (its alarm).
    EndFault(Alarm),
}

/// What the back needs of a block (a few dozen bytes: it crosses threads).
#[derive(Clone, Copy, Debug)]
pub struct BlockInfo {
    /// The block, with its number in execution order.
    pub source: Source,
    pub plane: Plane,
    /// ISG contour masking (G141).
    pub masking: bool,
    /// Compensation side: +1 left, −1 right, 0 off.
    pub side: i8,
    /// Nose centre → tool tip of the active cutting edge (zero for a milling tool).
    pub tip: V2,
    pub stop: Option<ProgramStop>,
    /// The spindle, tool and work offset from this block on, when the block changed them.
    pub tech: Option<Technology>,
}

pub struct BlockStep<'b> {
    pub info: BlockInfo,
    /// The block's auxiliary and technology words.
    pub words: &'b [AuxWord],
    /// The programmed contour element and the radius it is cut with.
    pub element: Option<(Elem, f64)>,
    /// The compensation still holds back part of the path (S points wait for it).
    pub holds_back: bool,
    /// A compensation alarm in this block: its segments are not valid. (Boxed: the step is
    /// moved per block, the alarm almost never there.)
    pub fault: Option<Box<Alarm>>,
    /// Violations the machine data lets pass.
    pub warnings: &'b [Alarm],
    /// The additional axes' move beside the block's segment (boxed as `fault`: rare).
    pub axes: Option<Box<AxisMove>>,
}

/// Interpretation, tool length, tool radius compensation.
pub struct Front<'a> {
    name: &'a str,
    /// The subprogram files, to name the file an alarm is in.
    programs: &'a crate::ProgramLibrary,
    interp: Interpreter<'a>,
    trc: Compensator,
    /// Tool length in effect on the tool axis, and the one the active offset asks for: a new
    /// length is traversed with the next move of the tool axis (002, 840C 11.5.2 "N15 Z..").
    length: f64,
    /// The spindle, tool and work offset as the blocks so far programmed them.
    tech: Technology,
    blocks: u32,
    warnings: Vec<Alarm>,
}

impl<'a> Front<'a> {
    /// The interpreter's kept macro variables (#500 …).
    pub fn kept_variables(&self) -> Vec<(u32, f64)> {
        self.interp.kept_variables()
    }

    pub fn new(name: &'a str, interp: Interpreter<'a>, md: &'a MachineData) -> Self {
        let rules = crate::dialect::Dialect::get(md.dialect).trc;
        let mut trc = Compensator::new(
            rules,
            md.trc.max_blocks_outside_plane,
            md.trc.suppression_distance,
            interp.position(),
            interp.state().plane,
        );
        trc.warn_on_violation(md.trc.violation_reaction == ViolationReaction::Warn);
        trc.set_feed_adaption_rmin(md.trc.feed_adaption_rmin);
        Front {
            name,
            programs: &md.programs,
            interp,
            trc,
            length: 0.0,
            tech: Technology::default(),
            blocks: 0,
            warnings: Vec::new(),
        }
    }

    /// The next block through the compensation; its segments go to `out`.
    pub fn step(&mut self, out: &mut Out) -> Step<'_> {
        let inner_corner = match self.interp.next_block() {
            Ok(Some(b)) => selects_at_inner_corner(b),
            Ok(None) => {
                return match self.trc.finish(out) {
                    Ok(()) => Step::End {
                        holds_back: self.trc.holds_back(),
                    },
                    Err(f) => Step::EndFault(alarm(self.name, self.programs, *f)),
                }
            }
            Err(a) => return Step::Decode(a),
        };
        self.blocks = self.blocks.wrapping_add(1);
        if inner_corner {
            self.trc.close_contour(closing_element(&self.interp));
        }
        let block = self.interp.current();
        let lengthened;
        let motion = match &block.motion {
            Some(m) if needs_length(m, self.length, block.modal.length) => {
                lengthened = with_length(m, &mut self.length, block.modal.length);
                Some(&lengthened)
            }
            m => m.as_ref(),
        };
        let fault = if block.axes.is_some() && !self.trc.is_off() {
            // A deselection still waits for its plane move (840C G40 alone): the
            // compensation's pieces could not carry a rotary move (docs/axes.md).
            Some(Box::new(additional_under_trc(
                self.name,
                self.programs,
                block,
            )))
        } else {
            self.trc
                .block(block, motion, out)
                .err()
                .map(|f| Box::new(alarm(self.name, self.programs, *f)))
        };
        self.warnings.clear();
        while let Some(w) = self.trc.take_warning() {
            self.warnings.push(alarm(self.name, self.programs, w));
        }
        if let Some(m) = &block.message {
            self.warnings
                .push(message(self.name, self.programs, block, m));
        }
        let info = BlockInfo {
            source: block.source(self.blocks),
            plane: block.modal.plane,
            masking: block.modal.masking,
            side: match block.modal.trc {
                TrcSide::Left => 1,
                TrcSide::Right => -1,
                TrcSide::Off => 0,
            },
            tip: if block.modal.edge == 0 {
                v2(0.0, 0.0)
            } else {
                tip_vector(block.modal.edge, block.modal.radius, block.modal.plane)
            },
            stop: block.stop,
            tech: changed(&mut self.tech, block.modal.technology()),
        };
        Step::Block(BlockStep {
            info,
            words: &block.words,
            element: self.trc.take_element(),
            holds_back: self.trc.holds_back(),
            fault,
            warnings: &self.warnings,
            axes: block.axes.map(Box::new),
        })
    }

    /// This front in a thread of `scope`, running ahead of the back. The thread ends when the
    /// program does, or when the returned handle is dropped.
    pub fn threaded<'scope>(self, scope: &'scope std::thread::Scope<'scope, 'a>) -> Threaded {
        let (full_tx, full_rx) = bounded::<Batch>(BATCHES);
        let (empty_tx, empty_rx) = bounded::<Batch>(BATCHES);
        for _ in 0..BATCHES {
            let _ = empty_tx.send(Batch {
                steps: Vec::with_capacity(BATCH),
                segments: Out::with_capacity(4 * BATCH),
                words: Vec::new(),
                rare: Vec::new(),
                alarms: Vec::new(),
            });
        }
        let mut front = self;
        scope.spawn(move || {
            // Batches are refilled in place: after the first round nothing is allocated.
            while let Ok(mut batch) = recv_soon(&empty_rx) {
                batch.clear();
                let mut end = false;
                while batch.steps.len() < BATCH && !end {
                    // The compensation appends the step's segments to the batch's.
                    let first = batch.segments.len() as u32;
                    let step = front.step(&mut batch.segments);
                    let segments = (first, batch.segments.len() as u32);
                    let w0 = batch.words.len() as u32;
                    let owned = match step {
                        Step::Block(b) => {
                            batch.words.extend_from_slice(b.words);
                            let rare = batch.rare(b.fault, b.axes, b.warnings);
                            Owned::Block {
                                info: b.info,
                                words: (w0, batch.words.len() as u32),
                                element: b.element,
                                holds_back: b.holds_back,
                                rare,
                                segments,
                            }
                        }
                        Step::Decode(a) => {
                            end = true;
                            Owned::Decode(batch.alarm(a))
                        }
                        Step::End { holds_back } => {
                            end = true;
                            Owned::End {
                                holds_back,
                                segments,
                            }
                        }
                        Step::EndFault(a) => {
                            end = true;
                            Owned::EndFault(batch.alarm(a))
                        }
                    };
                    batch.steps.push(owned);
                }
                if full_tx.send(batch).is_err() || end {
                    return;
                }
            }
        });
        Threaded {
            full: full_rx,
            empty: empty_tx,
            batch: Batch::default(),
            next: 0,
            ended: false,
        }
    }
}

/// Steps per batch and batches in flight. The front may run some 4000 blocks ahead: the
/// back's bursts (fresh pages of the whole-program check's records, a window that meets a
/// crowded stretch) do not stop it, and a batch comes back for refilling long after the back
/// read it, when its lines have left the back's cache, so the front does not wait for them
/// to be handed over. Four batches in flight leave the threaded front up to a third slower
/// (docs/benchmarks.md); a batch is some 100 kB.
const BATCH: usize = 128;
const BATCHES: usize = 32;

/// A step as it crosses threads: what a few blocks have besides (an alarm, warnings, an
/// additional axes' move) lies in the batch's `rare`, so that a step has nothing to drop and
/// refilling a batch does not read its old steps again (lines the back had last).
// Nearly every step is a block: boxing it would allocate once per block.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy)]
enum Owned {
    Block {
        info: BlockInfo,
        /// The block's words: a range of the batch's.
        words: (u32, u32),
        element: Option<(Elem, f64)>,
        holds_back: bool,
        /// Its entry in the batch's `rare` (`PLAIN`: none).
        rare: u32,
        /// The step's segments: a range of the batch's.
        segments: (u32, u32),
    },
    /// The alarm: an entry of the batch's `alarms`.
    Decode(u32),
    End {
        holds_back: bool,
        segments: (u32, u32),
    },
    EndFault(u32),
}

/// A block step with no entry in `rare`.
const PLAIN: u32 = u32::MAX;

/// What few blocks have besides their step.
struct Rare {
    fault: Option<Box<Alarm>>,
    axes: Option<Box<AxisMove>>,
    warnings: Vec<Alarm>,
}

#[derive(Default)]
struct Batch {
    steps: Vec<Owned>,
    segments: Out,
    words: Vec<AuxWord>,
    rare: Vec<Rare>,
    alarms: Vec<Alarm>,
}

impl Batch {
    fn clear(&mut self) {
        self.steps.clear();
        self.segments.clear();
        self.words.clear();
        self.rare.clear();
        self.alarms.clear();
    }

    /// The entry in `rare` of a block with these, if it has any.
    fn rare(
        &mut self,
        fault: Option<Box<Alarm>>,
        axes: Option<Box<AxisMove>>,
        warnings: &[Alarm],
    ) -> u32 {
        if fault.is_none() && axes.is_none() && warnings.is_empty() {
            return PLAIN;
        }
        let warnings = warnings.to_vec();
        self.rare.push(Rare {
            fault,
            axes,
            warnings,
        });
        self.rare.len() as u32 - 1
    }

    fn alarm(&mut self, a: Alarm) -> u32 {
        self.alarms.push(a);
        self.alarms.len() as u32 - 1
    }
}

/// The back's side of a front thread.
pub struct Threaded {
    full: Receiver<Batch>,
    empty: Sender<Batch>,
    batch: Batch,
    next: usize,
    ended: bool,
}

impl Threaded {
    /// The next step; its segments go to `out`, which must be empty: it is the batch's own
    /// segments (swapped in with the batch), shown one step's at a time. While the front has
    /// no batch ready, `idle` does some other work of this thread (false: none left).
    pub fn step(&mut self, out: &mut Out, idle: &mut impl FnMut() -> bool) -> Step<'_> {
        loop {
            if self.next < self.batch.steps.len() {
                let i = self.next;
                self.next += 1;
                let b = &mut self.batch;
                let mut take = |(_, last): (u32, u32)| out.limit_to(last as usize);
                return match &b.steps[i] {
                    Owned::Block {
                        info,
                        words: w,
                        element,
                        holds_back,
                        rare,
                        segments,
                    } => {
                        take(*segments);
                        let (fault, axes, warnings) = match b.rare.get_mut(*rare as usize) {
                            Some(r) => (r.fault.take(), r.axes.take(), &r.warnings[..]),
                            None => (None, None, &[][..]),
                        };
                        Step::Block(BlockStep {
                            info: *info,
                            words: &b.words[w.0 as usize..w.1 as usize],
                            element: *element,
                            holds_back: *holds_back,
                            fault,
                            warnings,
                            axes,
                        })
                    }
                    Owned::Decode(a) => {
                        self.ended = true;
                        Step::Decode(b.alarms[*a as usize].clone())
                    }
                    Owned::End {
                        holds_back,
                        segments,
                    } => {
                        self.ended = true;
                        take(*segments);
                        Step::End {
                            holds_back: *holds_back,
                        }
                    }
                    Owned::EndFault(a) => {
                        self.ended = true;
                        Step::EndFault(b.alarms[*a as usize].clone())
                    }
                };
            }
            if self.ended {
                // Asked again after the end: the end again, with nothing more.
                return Step::End { holds_back: false };
            }
            // This batch is done: back to the front, and the next one. A closed channel
            // means the front stopped without an end step (it cannot; treated as the end).
            let done = std::mem::take(&mut self.batch);
            if done.steps.capacity() > 0 {
                let _ = self.empty.send(done);
            }
            self.next = 0;
            let next = loop {
                match self.full.try_recv() {
                    Ok(b) => break Ok(b),
                    Err(TryRecvError::Empty) if idle() => {}
                    Err(TryRecvError::Empty) => break recv_soon(&self.full),
                    Err(TryRecvError::Disconnected) => break Err(RecvError),
                }
            };
            match next {
                Ok(mut b) => {
                    // `out` is drained: it goes back with this batch, and the new batch's
                    // segments are read where the front put them.
                    std::mem::swap(out, &mut b.segments);
                    out.limit_to(0);
                    self.batch = b;
                }
                Err(_) => self.ended = true,
            }
        }
    }
}

/// Receives, spinning a little before the thread sleeps: a batch is a few tens of
/// microseconds of work, about what waking a sleeping thread costs on a VM (docs/benchmarks.md),
/// so sleeping at every hand-over would halve the throughput.
fn recv_soon<T>(rx: &Receiver<T>) -> Result<T, RecvError> {
    for _ in 0..SPIN {
        match rx.try_recv() {
            Ok(x) => return Ok(x),
            Err(TryRecvError::Disconnected) => return Err(RecvError),
            Err(TryRecvError::Empty) => std::hint::spin_loop(),
        }
    }
    rx.recv()
}

/// Spins before sleeping: ~50 µs here.
const SPIN: u32 = 20_000;

/// Alarm 10754 for a block that moves additional axes while compensation is still active.
#[cold]
fn additional_under_trc(main: &str, programs: &crate::ProgramLibrary, b: &Block) -> Alarm {
    let source = b.source(0);
    Alarm::at(
        crate::alarm::AlarmCode::ForbiddenWithTrc,
        source.program_name(main, programs),
        &source,
        "an additional axis cannot move before the deselection has reached the plane".to_string(),
    )
}

/// The program's message for the operator (`#3006`), as a warning at its block.
#[cold]
fn message(main: &str, programs: &crate::ProgramLibrary, b: &Block, text: &str) -> Alarm {
    let source = b.source(0);
    let name = source.program_name(main, programs);
    Alarm::at(crate::AlarmCode::ProgramMessage, name, &source, text)
}

fn alarm(main: &str, programs: &crate::ProgramLibrary, f: TrcFault) -> Alarm {
    let name = f.source.program_name(main, programs);
    Alarm::at(f.code, name, &f.source, f.message)
}

/// A G41/G42 block under ISG's inner-corner selection (G238).
fn selects_at_inner_corner(b: &Block) -> bool {
    b.trc.is_some_and(|s| s != TrcSide::Off)
        && b.approach.is_none()
        && b.modal.selection == SelectionPolicy::InnerCorner
}

/// G238 needs the contour's last element before it starts: the last block moving in the plane
/// before the next G40, read ahead by a copy of the interpreter (once per selection; `None`
/// when the program ends or stops with an alarm first, which the main stream then reports).
fn closing_element(interp: &Interpreter) -> Option<(Motion, Source)> {
    let mut ahead = interp.clone();
    let mut last = None;
    while let Ok(Some(b)) = ahead.next_block() {
        if b.trc == Some(TrcSide::Off) {
            return last;
        }
        if let Some(m) = b.motion.filter(|m| m.moves_in_plane(1e-9)) {
            last = Some((m, b.source(0)));
        }
    }
    None
}

/// `now` if it differs from `last` (which becomes it).
#[inline]
fn changed(last: &mut Technology, now: Technology) -> Option<Technology> {
    (*last != now).then(|| {
        *last = now;
        now
    })
}

/// Whether [`with_length`] changes the motion or the length, bit for bit: its additions
/// made and compared (adding a length of +0 turns a coordinate of −0 into +0; a length of −0
/// changes nothing), without the copy of the motion.
#[inline]
fn needs_length(m: &Motion, length: f64, block_length: f64) -> bool {
    let n = m.plane.normal as usize;
    let new = if m.programmed & (1 << n) != 0 {
        block_length
    } else {
        length
    };
    let moves = |v: f64, by: f64| (v + by).to_bits() != v.to_bits();
    new.to_bits() != length.to_bits()
        || moves(m.start[n], length)
        || moves(m.center[n], length)
        || moves(m.end[n], new)
}

/// The motion with the tool length on the tool axis: the old length up to a block that
/// programs the tool axis, the new one from its end on.
fn with_length(m: &Motion, length: &mut f64, block_length: f64) -> Motion {
    let n = m.plane.normal as usize;
    let mut m = *m;
    m.start[n] += *length;
    m.center[n] += *length;
    if m.programmed & (1 << n) != 0 {
        *length = block_length;
    }
    m.end[n] += *length;
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontend::block::{MotionKind, Pos};
    use proptest::prelude::*;

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![Just(0.0), Just(-0.0), -50.0..50.0f64]
    }

    fn motion() -> impl Strategy<Value = Motion> {
        let pos = || [coordinate(), coordinate(), coordinate()];
        (pos(), pos(), pos(), 0..8u16, 0..3usize).prop_map(|(start, end, center, programmed, p)| {
            Motion {
                kind: MotionKind::Linear,
                plane: [Plane::XY, Plane::ZX, Plane::YZ][p],
                start,
                end,
                center,
                programmed,
            }
        })
    }

    proptest! {
        /// A motion lent as it is (`needs_length` false) is what `with_length` would have
        /// made of it, bit for bit, and the length stays.
        #[test]
        fn a_motion_lent_as_it_is_is_the_lengthened_one(
            m in motion(),
            length in prop_oneof![Just(0.0), Just(-0.0), -5.0..5.0f64],
            block_length in prop_oneof![Just(0.0), Just(-0.0), -5.0..5.0f64],
        ) {
            let mut after = length;
            let lengthened = with_length(&m, &mut after, block_length);
            if !needs_length(&m, length, block_length) {
                let bits = |p: &Pos| p.map(f64::to_bits);
                prop_assert_eq!(bits(&lengthened.start), bits(&m.start));
                prop_assert_eq!(bits(&lengthened.end), bits(&m.end));
                prop_assert_eq!(bits(&lengthened.center), bits(&m.center));
                prop_assert_eq!(after.to_bits(), length.to_bits());
            }
        }
    }
}
