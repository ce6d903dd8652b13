//! Where preparation gets its blocks: the interpreter in the same thread, or the interpreter
//! running ahead in a thread of its own (a decoding task before the preparation task, as
//! controls split it) — the same blocks in the same order either way.
//!
//! The thread hands blocks over in batches: a fixed set of batch buffers circulates between
//! the two threads over two bounded channels (full ones to preparation, empty ones back), so
//! nothing is allocated per block and the threads meet once per batch, not once per block.

use crate::alarm::Alarm;
use crate::frontend::block::{Block, Motion, SelectionPolicy, TrcSide};
use crate::frontend::Interpreter;
use crate::segment::Source;
use crossbeam::channel::{bounded, Receiver, Sender};

/// Blocks per batch and batches in flight: enough to ride out a scheduling hiccup of the
/// other thread (~512 blocks), small enough to stay in the caches.
const BATCH: usize = 128;
const BATCHES: usize = 4;

/// The last block moving in the plane before the next G40, for ISG's inner-corner selection.
pub type Closing = Option<(Motion, Source)>;

/// Blocks decoded in a row; an alarm or the program's end closes the stream.
#[derive(Default)]
struct Batch {
    blocks: Vec<(Block, Closing)>,
    alarm: Option<Box<Alarm>>,
}

/// The interpreter's output as preparation reads it.
pub enum Decoder<'a> {
    Direct(Interpreter<'a>),
    Threaded(Threaded),
}

/// The preparation side of a decoding thread.
pub struct Threaded {
    full: Receiver<Batch>,
    empty: Sender<Batch>,
    batch: Batch,
    next: usize,
    /// The block handed out last (an index into `batch`).
    current: usize,
    ended: bool,
    /// What `current` shows before the first block.
    blank: Block,
}

impl<'a> Decoder<'a> {
    /// The interpreter in a thread of `scope`. The thread ends when the program does, or when
    /// the decoder is dropped.
    pub fn threaded<'scope>(
        scope: &'scope std::thread::Scope<'scope, 'a>,
        mut interp: Interpreter<'a>,
    ) -> Decoder<'a> {
        let (full_tx, full_rx) = bounded::<Batch>(BATCHES);
        let (empty_tx, empty_rx) = bounded::<Batch>(BATCHES);
        for _ in 0..BATCHES {
            let _ = empty_tx.send(Batch {
                blocks: Vec::with_capacity(BATCH),
                alarm: None,
            });
        }
        let blank = interp.current().clone();
        scope.spawn(move || {
            // Batches are refilled in place: after the first round nothing is allocated.
            while let Ok(mut batch) = empty_rx.recv() {
                batch.blocks.clear();
                let mut end = false;
                while batch.blocks.len() < BATCH {
                    match interp.next_block() {
                        Ok(Some(b)) => {
                            let closing = if selects_at_inner_corner(b) {
                                closing_element(&interp)
                            } else {
                                None
                            };
                            batch.blocks.push((interp.current().clone(), closing));
                        }
                        Ok(None) => {
                            end = true;
                            break;
                        }
                        Err(a) => {
                            batch.alarm = Some(Box::new(a));
                            end = true;
                            break;
                        }
                    }
                }
                if full_tx.send(batch).is_err() || end {
                    return;
                }
            }
        });
        Decoder::Threaded(Threaded {
            full: full_rx,
            empty: empty_tx,
            batch: Batch::default(),
            next: 0,
            current: 0,
            ended: false,
            blank,
        })
    }

    /// The next block, `Ok(None)` at the end; the block stays readable through [`current`].
    #[inline]
    pub fn next_block(&mut self) -> Result<Option<&Block>, Alarm> {
        match self {
            Decoder::Direct(i) => i.next_block(),
            Decoder::Threaded(t) => t.next_block(),
        }
    }

    /// The block `next_block` returned last.
    #[inline]
    pub fn current(&self) -> &Block {
        match self {
            Decoder::Direct(i) => i.current(),
            Decoder::Threaded(t) => t.batch.blocks.get(t.current).map_or(&t.blank, |b| &b.0),
        }
    }

    /// For a block selecting compensation at an inner corner: the contour's closing element.
    pub fn closing(&self) -> Closing {
        match self {
            Decoder::Direct(i) => closing_element(i),
            Decoder::Threaded(t) => t.batch.blocks.get(t.current).and_then(|b| b.1),
        }
    }
}

impl Threaded {
    fn next_block(&mut self) -> Result<Option<&Block>, Alarm> {
        loop {
            if self.next < self.batch.blocks.len() {
                self.current = self.next;
                self.next += 1;
                return Ok(Some(&self.batch.blocks[self.current].0));
            }
            if let Some(a) = self.batch.alarm.take() {
                self.ended = true;
                return Err(*a);
            }
            if self.ended {
                return Ok(None);
            }
            // This batch is done: back to the decoder, and the next one. A closed channel
            // is the end of the program (the decoder sent its last batch and stopped).
            let done = std::mem::take(&mut self.batch);
            if done.blocks.capacity() > 0 {
                let _ = self.empty.send(done);
            }
            self.next = 0;
            self.current = 0;
            match self.full.recv() {
                Ok(b) => self.batch = b,
                Err(_) => self.ended = true,
            }
        }
    }
}

/// A G41/G42 block under ISG's inner-corner selection (G238).
pub fn selects_at_inner_corner(b: &Block) -> bool {
    b.trc.is_some_and(|s| s != TrcSide::Off)
        && b.approach.is_none()
        && b.modal.selection == SelectionPolicy::InnerCorner
}

/// G238 needs the contour's last element before it starts: the last block moving in the plane
/// before the next G40, read ahead by a copy of the interpreter (once per selection; `None`
/// when the program ends or stops with an alarm first, which the main stream then reports).
pub fn closing_element(interp: &Interpreter) -> Closing {
    let mut ahead = interp.clone();
    let mut last = None;
    while let Ok(Some(b)) = ahead.next_block() {
        if b.trc == Some(TrcSide::Off) {
            return last;
        }
        if let Some(m) = b.motion.filter(|m| m.moves_in_plane(1e-9)) {
            last = Some((
                m,
                Source {
                    number: b.number,
                    line: b.line,
                    col: b.col,
                    seq: 0,
                },
            ));
        }
    }
    None
}
