//! Auxiliary functions and program stops at S points (840C 11.10).
//!
//! An S point is the end of a segment of the tool path, inserted blocks included: where a
//! single-block stop halts and where auxiliary functions are output. They are numbered from
//! S0 at the start of each compensation (the selection block's start, as in the 11.10
//! figure) or of the program; S_k is the end of the k-th segment after it.
//!
//! Rules (11.10): a block's auxiliary functions are output at the start of its own motion,
//! after the blocks inserted in front of it ("no auxiliary functions are output in the
//! intermediate blocks"); a block outside the plane outputs them at the S point where it is
//! executed (11.11); M00, M01, M18 act at the end of their block, M02/M30 end the program.

use crate::frontend::block::{AuxWord, Plane, Pos, ProgramStop, Technology, MAX_AUX_WORDS};
use crate::machine_data::AuxOutput;
use crate::segment::{Role, Segment, Source};

/// Auxiliary functions of one block as they go to the PLC.
#[derive(Clone, Debug, PartialEq)]
pub struct AuxFunction {
    pub source: Source,
    /// M, H, S and T words in program order (the program-flow M functions are [`Stop`]s).
    pub words: heapless::Vec<AuxWord, MAX_AUX_WORDS>,
    /// The S point they are output at, and its position.
    pub at: u32,
    pub pos: Pos,
    /// Output before the motion from there starts, or with it (machine data).
    pub timing: AuxOutput,
    /// The spindle, tool and work offset from here on, when the block changed them (the
    /// channel's spindle setpoint and status follow from this S point; a record with no
    /// words goes to no PLC).
    pub tech: Option<Technology>,
}

/// M00, M01 or M18 at the end of its block, or M02/M30 at the end of the program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    pub source: Source,
    pub code: ProgramStop,
    pub at: u32,
    pub pos: Pos,
}

/// What preparation hands on, in execution order.
#[derive(Clone, Debug, PartialEq)]
pub enum Prepared {
    Segment(Segment),
    /// The additional axes move with the next segment (the block's): from, to, the block.
    Axes(crate::frontend::block::AxisMove, crate::segment::Source),
    Aux(AuxFunction),
    /// A programmed stop (M00, M01, M18) at the end of its block.
    Stop(Stop),
    /// Program end (M02, M30): the last record.
    End(Stop),
    /// An alarm that only warns (3021 with `trc.violation_reaction = warn`): the path goes on.
    Warning(crate::alarm::Alarm),
}

impl Prepared {
    /// The line of the block the record comes from.
    pub fn line(&self) -> u32 {
        match self {
            Prepared::Segment(s) => s.source.line,
            Prepared::Axes(_, s) => s.line,
            Prepared::Aux(a) => a.source.line,
            Prepared::Stop(s) | Prepared::End(s) => s.source.line,
            Prepared::Warning(w) => w.line,
        }
    }
}

/// Auxiliary words and stops waiting for their S point.
// In a fixed-capacity deque: boxing the large variant would allocate per block.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
enum Waiting {
    Aux(
        Source,
        heapless::Vec<AuxWord, MAX_AUX_WORDS>,
        Option<Technology>,
    ),
    Stop(Source, ProgramStop),
}

/// Blocks whose output can wait at once: the blocks outside the plane (≤ 8) around two plane
/// blocks, with room to spare.
const WAITING: usize = 16;

/// Puts auxiliary functions and stops between the segments at their S points.
pub struct SPoints {
    waiting: heapless::Deque<Waiting, WAITING>,
    end: Option<(Source, ProgramStop)>,
    /// Segments since S0, and the position of the last S point.
    s: u32,
    pos: Pos,
    last_role: Option<Role>,
    timing: AuxOutput,
    optional_stop: bool,
    /// S points are points of the plane: a move along the tool axis only (an infeed outside
    /// the plane, 11.11) runs at the S point it starts from.
    plane: Plane,
}

impl SPoints {
    pub fn new(start: Pos, timing: AuxOutput, optional_stop: bool) -> Self {
        SPoints {
            waiting: heapless::Deque::new(),
            end: None,
            s: 0,
            pos: start,
            last_role: None,
            timing,
            optional_stop,
            plane: Plane::XY,
        }
    }

    /// The plane of the blocks that follow.
    #[inline]
    pub fn set_plane(&mut self, plane: Plane) {
        self.plane = plane;
    }

    #[inline]
    fn count(&mut self, seg: &Segment) {
        let (a, o) = (self.plane.abscissa as usize, self.plane.ordinate as usize);
        if seg.is_arc() || seg.from[a] != seg.to[a] || seg.from[o] != seg.to[o] {
            self.s += 1;
        }
        self.last_role = Some(seg.role);
        self.pos = seg.to;
    }

    /// Nothing waits: segments pass straight through.
    #[inline]
    pub fn idle(&self) -> bool {
        self.waiting.is_empty()
    }

    /// Records what block `b` (execution number `seq`) outputs. Returns false when more
    /// blocks wait than there is room for (never with the outside-plane limit ≤ 8).
    #[inline]
    pub fn block(
        &mut self,
        source: Source,
        block_words: &[AuxWord],
        stop: Option<ProgramStop>,
        tech: Option<Technology>,
    ) -> bool {
        if block_words.is_empty() && stop.is_none() && tech.is_none() {
            return true;
        }
        let mut words = heapless::Vec::new();
        let m18_stop = stop == Some(ProgramStop::StopAtEnd);
        for w in block_words
            .iter()
            .filter(|w| is_aux(w) && !(m18_stop && w.address == b'M' && w.value == 18.0))
        {
            let _ = words.push(*w);
        }
        let mut ok = true;
        if !words.is_empty() || tech.is_some() {
            ok &= self
                .waiting
                .push_back(Waiting::Aux(source, words, tech))
                .is_ok();
        }
        match stop {
            Some(s) if s.ends_program() => self.end = Some((source, s)),
            Some(ProgramStop::OptionalStop) if !self.optional_stop => {}
            Some(s) => ok &= self.waiting.push_back(Waiting::Stop(source, s)).is_ok(),
            None => {}
        }
        ok
    }

    /// `seg` is handed out and nothing waits ([`Self::idle`]): only the count moves on.
    #[inline]
    pub fn pass(&mut self, seg: &Segment) {
        self.restart(seg);
        self.count(seg);
    }

    /// A new compensation: its selection block starts at S0 (11.10 figure).
    #[inline]
    fn restart(&mut self, seg: &Segment) {
        if seg.role == Role::Approach && self.last_role != Some(Role::Approach) {
            self.s = 0;
        }
    }

    /// `seg` is about to be handed out: what waits for a point before it goes to `out`
    /// first, then the segment.
    pub fn segment<const N: usize>(
        &mut self,
        seg: Segment,
        out: &mut heapless::Deque<Prepared, N>,
    ) {
        self.restart(&seg);
        let seq = seg.source.seq;
        // Inserted blocks belong to the next block but output none of its functions: they
        // release only what earlier blocks left.
        let own = !matches!(seg.role, Role::Intermediate | Role::Corner);
        self.release(out, |w| {
            let (src, stop) = match w {
                Waiting::Aux(s, ..) => (s, false),
                Waiting::Stop(s, _) => (s, true),
            };
            let d = seq.wrapping_sub(src.seq) as i32;
            // Stops wait for the end of their own block: a later block's segment.
            if stop {
                d > 0
            } else {
                d > 0 || (d == 0 && own)
            }
        });
        self.count(&seg);
        let _ = out.push_back(Prepared::Segment(seg));
    }

    /// Everything waiting is due now: the path holds nothing back, so the next S point is
    /// the current position.
    pub fn flush<const N: usize>(&mut self, out: &mut heapless::Deque<Prepared, N>) {
        self.release(out, |_| true);
    }

    /// The program's end: everything left, then the end record.
    pub fn finish<const N: usize>(&mut self, out: &mut heapless::Deque<Prepared, N>) {
        self.release(out, |_| true);
        if let Some((source, code)) = self.end.take() {
            let _ = out.push_back(Prepared::End(Stop {
                source,
                code,
                at: self.s,
                pos: self.pos,
            }));
        }
    }

    fn release<const N: usize>(
        &mut self,
        out: &mut heapless::Deque<Prepared, N>,
        due: impl Fn(&Waiting) -> bool,
    ) {
        while let Some(w) = self.waiting.front() {
            if !due(w) {
                break;
            }
            let item = match self.waiting.pop_front() {
                Some(Waiting::Aux(source, words, tech)) => Prepared::Aux(AuxFunction {
                    source,
                    words,
                    at: self.s,
                    pos: self.pos,
                    timing: self.timing,
                    tech,
                }),
                Some(Waiting::Stop(source, code)) => Prepared::Stop(Stop {
                    source,
                    code,
                    at: self.s,
                    pos: self.pos,
                }),
                None => break,
            };
            let _ = out.push_back(item);
        }
    }
}

/// Words that go to the PLC: M (other than the program-flow ones), H, S, T.
fn is_aux(w: &AuxWord) -> bool {
    match w.address {
        b'M' => !matches!(w.value as i64, 0 | 1 | 2 | 30) || w.value.fract() != 0.0,
        b'H' | b'S' | b'T' => true,
        _ => false,
    }
}
