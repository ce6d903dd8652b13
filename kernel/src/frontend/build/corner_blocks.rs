//! Chamfer and corner words in the block stream (Fanuc 0i-MF/0i-TF "Optional angle
//! chamfering and corner rounding": `,C` and `,R` at the end of a G01/G02/G03 block). The
//! block build checks the word ([`Interpreter::corner_request`]); the interpreter then holds
//! the block back until the next block is built, which must be a move in the same plane; the
//! two moves are trimmed ([`super::corners`]) and handed out with the inserted element
//! between them, one per `next_block`. The element belongs to the block that carries the word
//! (its line, its feed and modal state) and takes over its program stop, so that a stop
//! still acts where the programmed block ends. Blocks are held in program coordinates after
//! the frame and before tool radius compensation, so compensation sees the chamfer or the
//! rounding as an ordinary contour element.

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::column;
use super::super::words::{CornerWord, Words};
use super::corners::{self, CornerError, CornerKind, Cornered, Element, V};
use crate::alarm::{Alarm, AlarmCode};
use crate::dialect::GEffect;
use crate::segment::Source;

/// What a block's corner word asks for, and where it stands (for the alarms that the next
/// block may raise).
#[derive(Clone, Debug)]
pub struct Request<'a> {
    kind: CornerKind,
    /// The chamfer's distance or the rounding's radius, mm.
    size: f64,
    /// The word as the dialect writes it (`,C`).
    word: &'static str,
    source: Source,
    /// The file the block is in.
    name: &'a str,
    /// The element's own feed (SINUMERIK FRC=/FRCM=, mm/min or mm/rev), else its block's.
    feed: Option<f64>,
    /// Modal rounding (SINUMERIK RNDM=): where no fitting move follows, nothing is inserted
    /// and no alarm raised.
    soft: bool,
}

/// The corner words' state while a chain of cornered blocks is in the stream.
#[derive(Clone, Debug, Default)]
pub struct Corners<'a> {
    /// The corner word of the block just built.
    request: Option<Request<'a>>,
    /// The block that waits for the next move, with its request.
    held: Option<(Block, Request<'a>)>,
    /// Blocks to hand out before the next one is read: the inserted element, the next move.
    out: heapless::Deque<Block, 2>,
    /// The interpreter's modal state (that of the last block built) while earlier blocks
    /// are handed out.
    modal: Option<ModalState>,
    /// SINUMERIK RNDM=: the radius every corner gets (0: off), mm.
    round: f64,
    /// SINUMERIK FRCM=: the feed of every corner element (0: its block's F).
    feed: f64,
}

impl<'a> Interpreter<'a> {
    /// Block build step 10: the block's corner word. It needs a G01, G02 or G03 move in the
    /// plane (no rapid, no cycle or reference point return, no machine coordinates, no
    /// additional axes); a size of 0 asks for nothing. Out of line: the block build of a
    /// block without the word only tests for it.
    #[cold]
    #[inline(never)]
    pub(super) fn corner_request(
        &mut self,
        word: CornerWord,
        new: &ModalState,
        feed: Option<f64>,
    ) -> R<()> {
        let at = word.value.at;
        if !self.corner_fits() {
            let moves = self.d.codes_of(&[
                GEffect::Motion(MotionMode::Linear),
                GEffect::Motion(MotionMode::ArcCw),
                GEffect::Motion(MotionMode::ArcCcw),
            ]);
            return Err(fault(
                AlarmCode::CornerWithoutMove,
                at,
                format!(
                    "{} needs a {moves} move in the {} plane in its block",
                    word.text,
                    new.plane.name()
                ),
            ));
        }
        let size = self.length(word.value, new.units) * self.corner_scale(new.plane, at)?;
        if size < 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                at,
                format!("{} must not be negative", word.text),
            ));
        }
        if size == 0.0 {
            return Ok(());
        }
        let col = column(self.src, self.blk_line_start, at as usize);
        self.request(word.kind, size, word.text, col, feed, false);
        Ok(())
    }

    /// The block's move may get a corner element after it: a G01, G02 or G03 move in the
    /// plane, not part of an expansion, not in machine coordinates, no additional axes.
    fn corner_fits(&self) -> bool {
        let fits = self.block.motion.filter(|m| {
            m.kind != MotionKind::Rapid
                && m.moves_in_plane(1e-9)
                && m.end[m.plane.normal as usize] == m.start[m.plane.normal as usize]
        });
        fits.is_some()
            && self.expansion.is_none()
            && !self.machine_coordinates
            && self.block.axes.is_none()
    }

    /// The request of the block just built.
    fn request(
        &mut self,
        kind: CornerKind,
        size: f64,
        word: &'static str,
        col: u32,
        feed: Option<f64>,
        soft: bool,
    ) {
        let request = Request {
            kind,
            size,
            word,
            source: Source {
                number: self.blk_number,
                line: self.blk_line,
                col,
                seq: 0,
                program: self.calls.running.program,
            },
            name: self.name,
            feed,
            soft,
        };
        self.corners.get_or_insert_with(Default::default).request = Some(request);
    }

    /// Block build step 10 on SINUMERIK: RNDM= and FRCM= set the modal rounding and corner
    /// feed; the block's CHF=/CHR=/RND=, or else the modal rounding, asks for its element,
    /// with FRC= (this block) or FRCM= as its feed (Fundamentals, "Chamfer, rounding (CHF,
    /// CHR, RND, RNDM, FRC, FRCM)"). FRC= alone, without an element, does nothing.
    #[cold]
    #[inline(never)]
    pub(super) fn sinumerik_corners(&mut self, w: &Words, new: &ModalState) -> R<()> {
        let (round, modal_feed) = self.modal_corner_words(w, new)?;
        let feed = match w.path.frc {
            Some(f) if f.value <= 0.0 => {
                return Err(fault(
                    AlarmCode::BadNumber,
                    f.at,
                    "FRC= must be greater than 0",
                ))
            }
            Some(f) => Some(self.feed_value(f.value, new)),
            None => (modal_feed > 0.0).then_some(modal_feed),
        };
        if let Some(word) = w.corner {
            return self.corner_request(word, new, feed);
        }
        if round > 0.0 && self.corner_fits() {
            self.request(
                CornerKind::Round,
                round,
                "RNDM=",
                self.block.col,
                feed,
                true,
            );
        }
        Ok(())
    }

    /// RNDM= and FRCM= of the block: the modal rounding radius (mm) and corner feed after it.
    fn modal_corner_words(&mut self, w: &Words, new: &ModalState) -> R<(f64, f64)> {
        let c = self.corners.as_deref();
        let (mut round, mut feed) = c.map_or((0.0, 0.0), |c| (c.round, c.feed));
        if let Some(v) = w.path.rndm {
            round = self.length(v, new.units) * self.corner_scale(new.plane, v.at)?;
            if round < 0.0 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    v.at,
                    "RNDM= must not be negative",
                ));
            }
        }
        if let Some(v) = w.path.frcm {
            if v.value < 0.0 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    v.at,
                    "FRCM= must not be negative (0: the block's F)",
                ));
            }
            feed = self.feed_value(v.value, new);
        }
        if round > 0.0 || feed > 0.0 || self.corners.is_some() {
            let c = self.corners.get_or_insert_with(Default::default);
            (c.round, c.feed) = (round, feed);
        }
        Ok((round, feed))
    }

    /// Under a scaling frame the corner scales with the contour; a plane scaled unevenly (or
    /// tilted by the frame) has no corner.
    fn corner_scale(&self, plane: Plane, at: u32) -> R<f64> {
        let frame = &self.coords.frame;
        if !frame.active() {
            return Ok(1.0);
        }
        frame.plane_scale(plane).ok_or_else(|| {
            fault(
                AlarmCode::NotSupported,
                at,
                "a chamfer or corner needs the same scale on both axes of the plane",
            )
        })
    }

    /// Before the next block is read while corner words are in play: a block waiting to be
    /// handed out goes out now (`Some(true)`); else the interpreter's modal state comes back
    /// and reading goes on (`None`). Out of line: `next_block` of a program without corner
    /// words only tests for them.
    #[cold]
    #[inline(never)]
    pub(in crate::frontend) fn corner_waiting(&mut self) -> Option<bool> {
        let c = self.corners.as_deref_mut()?;
        if let Some(b) = c.out.pop_front() {
            self.block = b;
            return Some(true);
        }
        if let Some(m) = c.modal.take() {
            self.block.modal = m;
        }
        if c.held.is_none() && c.request.is_none() && c.round == 0.0 && c.feed == 0.0 {
            self.corners = None;
        }
        None
    }

    /// The block just built (or the program's end, `produced` false) meets the corner
    /// state: a block with a corner word is held; the held block's successor is joined to
    /// it. `Some`: what `next_block` says now; `None`: read on.
    #[cold]
    #[inline(never)]
    pub(in crate::frontend) fn take_block(
        &mut self,
        produced: bool,
    ) -> Result<Option<bool>, Alarm> {
        let Some(c) = self.corners.as_deref_mut() else {
            return Ok(Some(produced));
        };
        let request = c.request.take();
        match (c.held.take(), produced) {
            (None, true) => match request {
                Some(r) => {
                    c.held = Some((self.block.clone(), r));
                    Ok(None)
                }
                None => Ok(Some(true)),
            },
            (None, false) => Ok(Some(false)),
            (Some((b1, r)), false) if r.soft => {
                self.block = b1;
                Ok(Some(true))
            }
            (Some((_, r)), false) => Err(self.corner_alarm(
                AlarmCode::CornerNextBlock,
                &r,
                "the program ends before the move it needs".to_string(),
            )),
            (Some((b1, r)), true) => {
                self.join(b1, r, request)?;
                Ok(Some(true))
            }
        }
    }

    /// The held block `b1` with its request `r` and the block just built: both trimmed and
    /// put in order, `b1` into the block handed out now, the inserted element and the next
    /// move after it (or the next move held in turn when it has a corner word `next`).
    fn join(
        &mut self,
        mut b1: Block,
        r: Request<'a>,
        next: Option<Request<'a>>,
    ) -> Result<(), Alarm> {
        let (m1, mut m2) = match self.next_move(&b1) {
            Ok(m) => m,
            Err(_) if r.soft => {
                self.no_corner(b1, next);
                return Ok(());
            }
            Err(why) => return Err(self.corner_alarm(AlarmCode::CornerNextBlock, &r, why)),
        };
        let plane = m1.plane;
        let cut = corners::corner(element(&m1), element(&m2), r.kind, r.size);
        let cut = match cut {
            Ok(cut) => cut,
            Err(e) => {
                return Err(self.corner_alarm(AlarmCode::CornerTooLarge, &r, too_large(e, &r)))
            }
        };
        let mut insert = None;
        if let Some(cut) = cut {
            let mut m1 = m1;
            set(&mut m1.end, plane, cut.first_end);
            set(&mut m2.start, plane, cut.second_start);
            b1.motion = Some(m1);
            self.block.motion = Some(m2);
            insert = Some(inserted(&mut b1, &m1, &cut, r.feed));
        }
        let b2 = std::mem::replace(&mut self.block, b1);
        let Some(c) = self.corners.as_deref_mut() else {
            return Ok(());
        };
        c.modal = Some(b2.modal);
        if let Some(i) = insert {
            let _ = c.out.push_back(i);
        }
        match next {
            Some(n) => c.held = Some((b2, n)),
            None => {
                let _ = c.out.push_back(b2);
            }
        }
        Ok(())
    }

    /// A modal rounding whose next block is no fitting move: `b1` goes out as it is, the
    /// block just built after it (or held in turn with its own request `next`).
    fn no_corner(&mut self, b1: Block, next: Option<Request<'a>>) {
        let b2 = std::mem::replace(&mut self.block, b1);
        let Some(c) = self.corners.as_deref_mut() else {
            return;
        };
        c.modal = Some(b2.modal);
        match next {
            Some(n) => c.held = Some((b2, n)),
            None => {
                let _ = c.out.push_back(b2);
            }
        }
    }

    /// The held block's move and the one just built, if that one may follow it: a G01,
    /// G02 or G03 move in the same plane, nothing but the plane's axes moving, under the
    /// same zero, no cycle or reference point return.
    fn next_move(&self, b1: &Block) -> Result<(Motion, Motion), String> {
        let m1 = b1.motion.ok_or_else(String::new)?;
        let b2 = &self.block;
        let Some(m2) = b2.motion.filter(|m| m.kind != MotionKind::Rapid) else {
            return Err("the next block is not a cutting move".to_string());
        };
        if m2.plane != m1.plane {
            return Err(format!(
                "the next move is in the {} plane, not the {} plane",
                m2.plane.name(),
                m1.plane.name()
            ));
        }
        let normal = m1.plane.normal as usize;
        if m2.end[normal] != m2.start[normal] || b2.axes.is_some() || !m2.moves_in_plane(1e-9) {
            return Err(format!(
                "the next move does not stay in the {} plane",
                m1.plane.name()
            ));
        }
        if self.expansion.is_some()
            || self.machine_coordinates
            || b2.modal.work_offset != b1.modal.work_offset
        {
            return Err("the next move changes the coordinate system".to_string());
        }
        Ok((m1, m2))
    }

    /// An alarm at the corner word of a held block; the interpreter stops.
    #[cold]
    fn corner_alarm(&mut self, code: AlarmCode, r: &Request, why: String) -> Alarm {
        self.finished = true;
        self.corners = None;
        let what = match r.kind {
            CornerKind::Chamfer | CornerKind::ChamferLength => "chamfer",
            CornerKind::Round => "corner rounding",
        };
        let message = format!("{what} {}{}: {why}", r.word, r.size);
        Alarm::at(code, r.name, &r.source, message)
    }
}

#[cold]
fn too_large(e: CornerError, r: &Request) -> String {
    match e {
        CornerError::TooLarge => format!("{} is too large for the two moves", r.size),
        CornerError::NoRound => "no arc of this radius touches both moves".to_string(),
    }
}

/// A move in its plane's coordinates.
fn element(m: &Motion) -> Element {
    let p = m.plane;
    let at = |q: &Pos| [q[p.abscissa as usize], q[p.ordinate as usize]];
    let (from, to) = (at(&m.start), at(&m.end));
    match m.kind {
        MotionKind::ArcCw | MotionKind::ArcCcw => Element::Arc {
            from,
            to,
            centre: at(&m.center),
            ccw: m.kind == MotionKind::ArcCcw,
        },
        _ => Element::Line { from, to },
    }
}

/// `q`'s plane coordinates set to `v`.
fn set(q: &mut Pos, p: Plane, v: V) {
    q[p.abscissa as usize] = v[0];
    q[p.ordinate as usize] = v[1];
}

/// The block of the inserted element: `b1`'s place, feed and modal state, no words; `b1`'s
/// program stop, exact stop and message move to it (they act at the programmed block's end).
fn inserted(b1: &mut Block, m1: &Motion, cut: &Cornered, feed: Option<f64>) -> Block {
    let mut b = Block::new(b1.line, b1.col, b1.number, b1.modal);
    if let Some(f) = feed {
        b.modal.feed = f;
    }
    b.program = b1.program;
    b.stop = b1.stop.take();
    b.message = b1.message.take();
    b.exact_stop = std::mem::take(&mut b1.exact_stop);
    let (from, to) = (m1.end, {
        let mut q = m1.end;
        set(&mut q, m1.plane, cut.insert.end());
        q
    });
    let (kind, centre) = match cut.insert {
        Element::Arc { centre, ccw, .. } => {
            let mut c = from;
            set(&mut c, m1.plane, centre);
            (
                if ccw {
                    MotionKind::ArcCcw
                } else {
                    MotionKind::ArcCw
                },
                c,
            )
        }
        Element::Line { .. } => (MotionKind::Linear, to),
    };
    b.motion = Some(Motion {
        kind,
        plane: m1.plane,
        start: from,
        end: to,
        center: centre,
        programmed: 1 << m1.plane.abscissa | 1 << m1.plane.ordinate,
    });
    b
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::frontend::{Block, MotionKind};

    /// (kind, start X Y, end X Y) of every move.
    fn moves(src: &str) -> Vec<(MotionKind, [f64; 2], [f64; 2])> {
        run("fanuc", src)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion)
            .map(|m| (m.kind, [m.start[0], m.start[1]], [m.end[0], m.end[1]]))
            .collect()
    }

    fn near(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9
    }

    #[test]
    fn the_corner_comes_between_the_two_moves_as_a_block_of_the_first() {
        use MotionKind::*;
        // 50 along X, 5 chamfered off the corner (50,0); then up to Y30, R8 rounded off the
        // corner (50,30) towards X0: centre (42, 22), counter-clockwise.
        let src = "G0 X0 Y0\nG1 X50. F100. ,C5.\nY30. ,R8. F200.\nX0 M30\n";
        let want = [
            (Rapid, [0.0, 0.0], [0.0, 0.0]),
            (Linear, [0.0, 0.0], [45.0, 0.0]),
            (Linear, [45.0, 0.0], [50.0, 5.0]),
            (Linear, [50.0, 5.0], [50.0, 22.0]),
            (ArcCcw, [50.0, 22.0], [42.0, 30.0]),
            (Linear, [42.0, 30.0], [0.0, 30.0]),
        ];
        let got = moves(src);
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!(g.0 == w.0 && near(g.1, w.1) && near(g.2, w.2), "{got:?}");
        }
        let b = run("fanuc", src).unwrap();
        // The chamfer is line 2's block with its feed; the rounding line 3's with F200.
        let at = |k: usize| (b[k].line, b[k].modal.feed);
        assert_eq!(
            [at(1), at(2), at(3), at(4), at(5)],
            [(2, 100.0), (2, 100.0), (3, 200.0), (3, 200.0), (4, 200.0)]
        );
        assert!(b[2].words.is_empty() && b[4].motion.unwrap().center[..2] == [42.0, 22.0]);
        assert_eq!(b.last().and_then(|b| b.stop).map(|s| s.code()), Some("M30"));
    }

    /// (kind, end X Y, feed) of every move of a SINUMERIK program.
    fn sinumerik_moves(src: &str) -> Vec<(MotionKind, [f64; 2], f64)> {
        run("siemens-840d", src)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| {
                b.motion
                    .map(|m| (m.kind, [m.end[0], m.end[1]], b.modal.feed))
            })
            .collect()
    }

    #[test]
    fn rndm_rounds_every_corner_until_rndm_0_with_the_frcm_feed() {
        use MotionKind::*;
        // RNDM=2 FRCM=50 from N1 on: R2 at (10,0) (centre (8,2)) and at (10,10) (centre
        // (8,8)), both at F50; N3 has a G0 after it: no rounding, no alarm.
        let want = [
            (Linear, [8.0, 0.0], 100.0),
            (ArcCcw, [10.0, 2.0], 50.0),
            (Linear, [10.0, 8.0], 100.0),
            (ArcCcw, [8.0, 10.0], 50.0),
            (Linear, [0.0, 10.0], 100.0),
            (Rapid, [0.0, 10.0], 100.0),
        ];
        let got = sinumerik_moves(
            "G1 X10 Y0 F100 RNDM=2 FRCM=50
Y10
X0
G0 Z5
",
        );
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(g.0 == w.0 && near(g.1, w.1) && g.2 == w.2, "{got:?}");
        }
        // RNDM=0 in N2: only N1's corner; the program may end after a rounded block.
        let got = sinumerik_moves(
            "G1 X10 F100 RNDM=2
Y10 RNDM=0
X0
",
        );
        assert_eq!(got.iter().filter(|m| m.0 == ArcCcw).count(), 1, "{got:?}");
        let got = sinumerik_moves(
            "G1 X10 F100 RNDM=2
Y10
",
        );
        assert!(got.len() == 3 && near(got[2].1, [10.0, 10.0]), "{got:?}");
    }

    #[test]
    fn frc_is_the_feed_of_its_blocks_element_only() {
        use MotionKind::*;
        let got = sinumerik_moves(
            "G1 X10 Y0 F100 RND=2 FRC=50
Y10 CHR=1
X0
",
        );
        let feeds: Vec<(MotionKind, f64)> = got.iter().map(|m| (m.0, m.2)).collect();
        assert_eq!(
            feeds,
            [
                (Linear, 100.0),
                (ArcCcw, 50.0),
                (Linear, 100.0),
                (Linear, 100.0),
                (Linear, 100.0)
            ]
        );
        // FRC without an element does nothing; FRC=0 and FRCM=-1 are refused.
        assert_eq!(
            sinumerik_moves(
                "G1 X10 F100 FRC=5
"
            )
            .len(),
            1
        );
        let a = run(
            "siemens-840d",
            "G1 X10 F100 RND=1 FRC=0
Y5
",
        )
        .unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::BadNumber, 19));
        let a = run(
            "siemens-840d",
            "FRCM=-1
",
        )
        .unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::BadNumber, 1));
    }

    #[test]
    fn a_program_stop_acts_after_the_corner() {
        let b = run("fanuc", "G1 X10. F100. ,C1. M0\nY10.\n").unwrap();
        let stops: Vec<bool> = b.iter().map(|b: &Block| b.stop.is_some()).collect();
        assert_eq!(stops, [false, true, false]);
    }

    #[test]
    fn macro_statements_between_are_no_blocks() {
        let got = moves("G1 X10. F100. ,R2.\n#1=5.\nY#1\n");
        assert!(
            near(got[0].2, [8.0, 0.0]) && near(got[2].1, [10.0, 2.0]),
            "{got:?}"
        );
    }

    #[test]
    fn what_is_refused_and_where() {
        let alarm = |src: &str| {
            let a = run("fanuc", src).unwrap_err();
            (a.code, a.line, a.col)
        };
        // The next block must be a cutting move: not an M function alone, not G0.
        let next = AlarmCode::CornerNextBlock;
        assert_eq!(alarm("G1 X50. F100. ,C5.\nM3\nY5.\n"), (next, 1, 15));
        assert_eq!(alarm("G1 X50. F100. ,C5.\nG0 Y5.\n"), (next, 1, 15));
        assert_eq!(alarm("G1 X50. F100. ,C5.\n"), (next, 1, 15));
        // ... in the same plane, under the same zero.
        assert_eq!(alarm("G1 X50. F100. ,R2.\nG18 X40. Z-5.\n"), (next, 1, 15));
        assert_eq!(alarm("G1 X50. F100. ,R2.\nG55 Y5.\n"), (next, 1, 15));
        assert_eq!(alarm("G1 X50. F100. ,R2.\nY5. Z1.\n"), (next, 1, 15));
        // Larger than an element.
        let large = AlarmCode::CornerTooLarge;
        assert_eq!(
            alarm("N5 G1 X10. F100.\nN6 Y10. ,C11.\nN7 X20.\n"),
            (large, 2, 9)
        );
        assert_eq!(alarm("G1 X10. F100. ,R6.\nY5.\n"), (large, 1, 15));
        // Only in a G01, G02 or G03 block that moves in the plane.
        let without = AlarmCode::CornerWithoutMove;
        assert_eq!(alarm("G0 X10. ,C1.\nG1 Y5. F100.\n"), (without, 1, 9));
        assert_eq!(alarm("G1 F100. ,C1.\n"), (without, 1, 10));
        assert_eq!(alarm("G1 Z-5. F100. ,C1.\n"), (without, 1, 15));
        assert_eq!(alarm("G1 X5. F100. ,C1. ,R1.\n").0, AlarmCode::AddressTwice);
        assert_eq!(alarm("G1 X5. F100. ,C-1.\nY5.\n").0, AlarmCode::BadNumber);
        let a = run("fanuc", "G1 X10. F100. ,C11.\nY10.\n").unwrap_err();
        assert_eq!(a.message, "chamfer ,C11: 11 is too large for the two moves");
    }

    #[test]
    fn the_lathe_reads_x_as_a_diameter_and_the_corner_as_a_length() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../config/fanuc-lathe.toml");
        let md =
            crate::machine_data::MachineData::load(Some(std::path::Path::new(path)), &[]).unwrap();
        // Face up to Ø30 at Z0 with a 1 mm chamfer, turn to Z-20, R2 into the shoulder Ø40.
        // As (X radius, Z): (15, 0) is the corner, (14, 0) and (15, −1) the chamfer's ends;
        // the rounding touches (15, −18) and (17, −20) about (17, −18).
        let src = "G0 X20. Z0\nG1 X30. F0.1 ,C1.\nZ-20. ,R2.\nX40.\n";
        let b = crate::frontend::interpret("l.nc", src, &md, &crate::tools::ToolTable::builtin())
            .unwrap();
        let ends: Vec<[f64; 2]> = b
            .iter()
            .filter_map(|b| b.motion)
            .map(|m| [m.end[0], m.end[2]])
            .collect();
        let want = [
            [10.0, 0.0],
            [14.0, 0.0],
            [15.0, -1.0],
            [15.0, -18.0],
            [17.0, -20.0],
            [20.0, -20.0],
        ];
        assert!(
            ends.iter().zip(&want).all(|(g, w)| near(*g, *w)) && ends.len() == 6,
            "{ends:?}"
        );
        let round = b[4].motion.unwrap();
        assert_eq!([round.center[0], round.center[2]], [17.0, -18.0]);
    }
}
