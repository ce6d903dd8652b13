//! Blocks that the control executes as several moves: a reference point return (G28: to the
//! intermediate point, then to the reference point) and the canned cycles (positioning, R
//! point, hole bottom, retraction). The block build computes the first [`Step`] into the
//! programmed block itself (with its words and modal changes); the rest come out of the
//! [`Expansion`] one block per `next_block`, before the next block's text is read, so that
//! even a peck cycle of many pecks streams.

use super::super::block::*;
use super::super::fault::R;
use super::super::interpreter::Interpreter;
use super::super::sinumerik::cycles::{CycleRun, StockRemovalRun};
use super::cycles::Drilling;
use super::lathe::LatheRun;
use super::turning::TurningRun;

/// One move or action of an expanded block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step {
    /// A move in machine coordinates: at rapid, or at the modal feed; the additional axes
    /// (U V W A B C) to `axes` with it, where given.
    Move {
        to: Pos,
        rapid: bool,
        axes: Option<Additional>,
        /// The feed of this move alone (a SINUMERIK cycle's own feeds); `None`: the modal
        /// feed.
        feed: Option<f64>,
    },
    /// A move along a contour (a turning cycle's shape): like `Move`, but the modal exact
    /// stop (G61/G64) decides whether the tool stops at its end, as in a programmed block.
    Path {
        to: Pos,
        rapid: bool,
        feed: Option<f64>,
    },
    /// An arc about `centre` (its plane coordinates) in the modal plane, without a stop at
    /// its end (a piece of a helix, an arc of a turning cycle's shape); `feed` as for a move.
    Arc {
        to: Pos,
        centre: Pos,
        ccw: bool,
        feed: Option<f64>,
    },
    /// A thread cut (a lathe cycle's): a straight move to `to` at the lead per spindle
    /// revolution along the longer axis; `stop`: an exact stop at its end (none where a
    /// chamfer goes on cutting the thread).
    Thread { to: Pos, lead: f64, stop: bool },
    /// A dwell, seconds.
    Dwell(f64),
    /// The spindle turns, stops or orients; its M function goes to the PLC.
    Spindle(SpindleDir),
    /// The spindle's speed (rev/min); its S word goes to the PLC.
    Speed(f64),
    /// A program stop inside the expansion (SINUMERIK CYCLE87: M0 for the operator).
    Stop(ProgramStop),
    /// G40/G41/G42 written in a turning cycle's shape (G70): the side from the next step
    /// on, which goes into the same block (the compensation starts or ends with a move).
    Compensation(TrcSide),
}

/// The steps still to come of the block being expanded, and the program stop of its block
/// (M00 … M30 act when the whole block is done: with its last step).
#[derive(Clone, Debug)]
pub struct Expansion {
    steps: Steps,
    stop: Option<ProgramStop>,
}

#[derive(Clone, Debug)]
enum Steps {
    /// A short fixed list, handed out from the front.
    Fixed(heapless::Deque<Step, 8>),
    /// A drilling cycle's remaining holes and pecks.
    Drilling(Drilling),
    /// A SINUMERIK drilling cycle's remaining moves.
    Cycle(Box<CycleRun>),
    /// A helix's remaining turns and its last arc.
    Helix(Helix),
    /// A turning cycle's passes and its run along the shape (Fanuc lathe G70, G71).
    Turning(Box<TurningRun>),
    /// A lathe cycle's remaining passes (Fanuc lathe G74, G75, G76).
    Lathe(Box<LatheRun>),
    /// A SINUMERIK stock removal cycle's approach, passes and finishing (CYCLE95).
    StockRemoval(Box<StockRemovalRun>),
    /// Blocks made ready elsewhere (a SINUMERIK smooth approach or retraction,
    /// build/smooth.rs), handed out as they are; then the modal state comes back.
    Blocks(Box<Queued>),
}

/// Ready blocks and the interpreter's modal state after them.
#[derive(Clone, Debug)]
pub struct Queued {
    blocks: std::collections::VecDeque<Block>,
    modal: ModalState,
}

/// The turns of a helix after its first (SINUMERIK TURN=): `left` full circles, each
/// rising by `rise` along the normal axis `normal`, then the arc to `end`.
#[derive(Clone, Debug)]
pub struct Helix {
    left: u16,
    rise: f64,
    centre: Pos,
    ccw: bool,
    end: Pos,
    /// Where the next turn starts; `None` once the last arc is out.
    at: Option<Pos>,
    normal: usize,
}

impl Helix {
    /// `at` is set by [`Expansion::helix`] from the first turn's end.
    pub fn new(left: u16, rise: f64, centre: Pos, ccw: bool, end: Pos) -> Self {
        Helix {
            left,
            rise,
            centre,
            ccw,
            end,
            at: None,
            normal: 2,
        }
    }

    fn next(&mut self) -> Option<Step> {
        let from = self.at?;
        let to = if self.left > 0 {
            self.left -= 1;
            let mut to = from;
            to[self.normal] += self.rise;
            self.at = Some(to);
            to
        } else {
            self.at = None;
            self.end
        };
        Some(Step::Arc {
            to,
            centre: self.centre,
            ccw: self.ccw,
            feed: None,
        })
    }
}

impl Expansion {
    pub fn of(steps: &[Step]) -> Self {
        let mut q = heapless::Deque::new();
        for &s in steps {
            // At most eight steps are built into a fixed list (G28: two).
            let _ = q.push_back(s);
        }
        Expansion {
            steps: Steps::Fixed(q),
            stop: None,
        }
    }

    pub fn drilling(d: Drilling) -> Self {
        Expansion {
            steps: Steps::Drilling(d),
            stop: None,
        }
    }

    pub fn cycle(c: CycleRun) -> Self {
        Expansion {
            steps: Steps::Cycle(Box::new(c)),
            stop: None,
        }
    }

    pub fn lathe(l: LatheRun) -> Self {
        Expansion {
            steps: Steps::Lathe(Box::new(l)),
            stop: None,
        }
    }

    pub fn turning(t: TurningRun) -> Self {
        Expansion {
            steps: Steps::Turning(Box::new(t)),
            stop: None,
        }
    }

    pub fn stock_removal(r: StockRemovalRun) -> Self {
        Expansion {
            steps: Steps::StockRemoval(Box::new(r)),
            stop: None,
        }
    }

    /// The helix `h` after its first turn, which ended at `at`; `normal` is the axis it
    /// rises along.
    pub fn helix(mut h: Helix, normal: usize, at: Pos) -> Self {
        h.normal = normal;
        h.at = Some(at);
        Expansion {
            steps: Steps::Helix(h),
            stop: None,
        }
    }

    /// `blocks` to hand out one per `next_block`, then the modal state `modal` (the last
    /// block built's) is the interpreter's again.
    pub fn blocks(blocks: Vec<Block>, modal: ModalState) -> Self {
        Expansion {
            steps: Steps::Blocks(Box::new(Queued {
                blocks: blocks.into(),
                modal,
            })),
            stop: None,
        }
    }

    /// The programmed block's stop, which acts with the last step.
    pub fn set_stop(&mut self, stop: Option<ProgramStop>) {
        self.stop = stop;
    }

    fn next(&mut self) -> Option<Step> {
        match &mut self.steps {
            Steps::Fixed(q) => q.pop_front(),
            Steps::Drilling(d) => d.next(),
            Steps::Cycle(c) => c.next(),
            Steps::Helix(h) => h.next(),
            Steps::Turning(t) => t.next(),
            Steps::Lathe(l) => l.next(),
            Steps::StockRemoval(r) => r.next(),
            Steps::Blocks(_) => None,
        }
    }

    /// No step is left.
    fn done(&mut self) -> bool {
        match &mut self.steps {
            Steps::Fixed(q) => q.is_empty(),
            Steps::Drilling(d) => d.done(),
            Steps::Cycle(c) => c.done(),
            Steps::Helix(h) => h.at.is_none(),
            Steps::Turning(t) => t.done(),
            Steps::Lathe(l) => l.done(),
            Steps::StockRemoval(r) => r.done(),
            Steps::Blocks(q) => q.blocks.is_empty(),
        }
    }
}

impl Interpreter<'_> {
    /// The first step of the expansion just set, into the programmed block; the block's
    /// program stop waits for the last step.
    pub(in crate::frontend) fn expand_first(&mut self, new: &mut ModalState) {
        if let Some(step) = self.expansion.as_mut().and_then(Expansion::next) {
            self.apply_with_next(step, new);
        }
        if let Some(e) = self.expansion.as_mut() {
            if !e.done() {
                e.stop = self.block.stop.take();
            }
        }
    }

    /// The next expanded block, if an expansion is running; when it ends, what the
    /// programmed block asked for after it (a call) runs. False: read on in the text.
    pub(in crate::frontend) fn next_expanded(&mut self) -> R<bool> {
        if let Some(ready) = self.queued() {
            if !ready {
                self.expansion = None;
                self.after_block()?;
            }
            return Ok(ready);
        }
        let Some(step) = self.expansion.as_mut().and_then(Expansion::next) else {
            self.expansion = None;
            self.after_block()?;
            return Ok(false);
        };
        let b = &mut self.block;
        let (line, col, number) = (b.line, b.col, b.number);
        super::reset(b, line, col, number);
        b.words.clear();
        let mut modal = b.modal;
        self.apply_with_next(step, &mut modal);
        if let (true, Some(m)) = (self.d.sinumerik, self.block.motion) {
            // The element a SINUMERIK CT continues (a helix's last turn).
            self.last_move = Some(m);
        }
        self.block.modal = modal;
        if let Some(e) = self.expansion.as_mut() {
            if e.done() {
                self.block.stop = e.stop.take();
                self.finished |= self.block.stop.is_some_and(|s| s.ends_program());
            }
        }
        Ok(true)
    }

    /// The next ready block, if the expansion is a queue of them; `Some(false)` when it is
    /// done (the modal state is back). A program end acts with the block that carries it.
    fn queued(&mut self) -> Option<bool> {
        let Steps::Blocks(q) = &mut self.expansion.as_mut()?.steps else {
            return None;
        };
        let Some(b) = q.blocks.pop_front() else {
            self.block.modal = q.modal;
            return Some(false);
        };
        if let (true, Some(m)) = (self.d.sinumerik, b.motion) {
            self.last_move = Some(m);
        }
        self.finished |= b.stop.is_some_and(|s| s.ends_program());
        self.block = b;
        Some(true)
    }

    /// A step into the block being built; a compensation step takes the step after it along.
    fn apply_with_next(&mut self, step: Step, modal: &mut ModalState) {
        self.apply_step(step, modal);
        if let Step::Compensation(_) = step {
            if let Some(next) = self.expansion.as_mut().and_then(Expansion::next) {
                self.apply_step(next, modal);
            }
        }
    }

    /// Puts a step into the block being built: its motion from the position now (exact
    /// stop at its end), its dwell, or its spindle function.
    fn apply_step(&mut self, step: Step, modal: &mut ModalState) {
        let blk = &mut self.block;
        match step {
            Step::Move {
                to,
                rapid,
                axes,
                feed,
            } => {
                if let Some(f) = feed {
                    modal.feed = f;
                }
                if let Some(a) = axes.filter(|a| *a != self.cur_add) {
                    blk.axes = Some(AxisMove {
                        from: self.cur_add,
                        to: a,
                    });
                    self.cur_add = a;
                }
                let moved = (0..3).fold(
                    0u16,
                    |m, i| {
                        if to[i] != self.cur[i] {
                            m | 1 << i
                        } else {
                            m
                        }
                    },
                );
                blk.motion = Some(Motion {
                    kind: if rapid {
                        MotionKind::Rapid
                    } else {
                        MotionKind::Linear
                    },
                    plane: modal.plane,
                    start: self.cur,
                    end: to,
                    center: to,
                    programmed: moved,
                });
                blk.exact_stop = true;
                self.cur = to;
            }
            Step::Path { to, rapid, feed } => {
                self.apply_step(
                    Step::Move {
                        to,
                        rapid,
                        axes: None,
                        feed,
                    },
                    modal,
                );
                self.block.exact_stop = false;
            }
            Step::Arc {
                to,
                centre,
                ccw,
                feed,
            } => {
                if let Some(f) = feed {
                    modal.feed = f;
                }
                let plane = modal.plane;
                let mut c = self.cur;
                c[plane.abscissa as usize] = centre[plane.abscissa as usize];
                c[plane.ordinate as usize] = centre[plane.ordinate as usize];
                blk.motion = Some(Motion {
                    kind: if ccw {
                        MotionKind::ArcCcw
                    } else {
                        MotionKind::ArcCw
                    },
                    plane,
                    start: self.cur,
                    end: to,
                    center: c,
                    programmed: 1 << plane.abscissa | 1 << plane.ordinate | 1 << plane.normal,
                });
                self.cur = to;
            }
            Step::Thread { to, lead, stop } => self.thread_step(to, lead, stop, modal),
            Step::Dwell(s) => blk.dwell = Some(s),
            Step::Speed(s) => {
                modal.spindle = s;
                let _ = blk.words.push(AuxWord {
                    address: b'S',
                    value: s,
                });
            }
            Step::Stop(stop) => blk.stop = Some(stop),
            Step::Compensation(side) => {
                blk.trc = Some(side);
                modal.trc = side;
            }
            Step::Spindle(dir) => {
                modal.spindle_dir = dir;
                let code = self
                    .d
                    .mcodes
                    .iter()
                    .find(|def| def.effect == crate::dialect::MEffect::Spindle(dir));
                if let Some(def) = code {
                    let _ = blk.words.push(AuxWord {
                        address: b'M',
                        value: def.code as f64,
                    });
                }
            }
        }
    }
}

impl Interpreter<'_> {
    /// A thread step: a move at the feed, tagged as a thread at its lead.
    fn thread_step(&mut self, to: Pos, lead: f64, stop: bool, modal: &mut ModalState) {
        let step = Step::Move {
            to,
            rapid: false,
            axes: None,
            feed: None,
        };
        self.apply_step(step, modal);
        if let Some(m) = self.block.motion {
            self.block.thread = Some(super::lathe::thread_feed(&m, lead));
        }
        self.block.exact_stop = stop;
    }
}
