//! The finished shape of a multiple repetitive turning cycle: the blocks from sequence
//! number P to Q of the running program (Fanuc 0i-TF, "Stock removal in turning (G71)":
//! the shape is programmed once, between ns and nf). They are read here as geometry: G00
//! G01 G02 G03 with X Z (a diameter and Z), U W (incremental), R or I K, the F and S that
//! the finishing cycle G70 uses, and G40/G41/G42 (the nose radius compensation: G70 carries
//! it, G71–G73 rough the compensated shape). Anything else in them is refused with an alarm
//! at its word, so that no block of the shape is silently left out.

use super::super::super::block::*;
use super::super::super::block_text::{self, BlockEnd};
use super::super::super::calls::Mark;
use super::super::super::fault::{fault, R};
use super::super::super::interpreter::Interpreter;
use super::super::super::lexer::Cursor;
use super::super::super::number;
use super::super::super::words::Val;
use super::super::motion::diameter_factor;
use crate::alarm::AlarmCode;
use crate::dialect::GEffect;
use crate::frontend::arc::{self, CentreSpec};

/// One element of the shape, machine coordinates (X a radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Element {
    pub to: Pos,
    pub mode: MotionMode,
    /// The arc's centre (G02/G03).
    pub centre: Pos,
    /// F and S written in the element's block (the finishing cycle's).
    pub feed: Option<f64>,
    pub speed: Option<f64>,
}

/// The shape between P and Q and where the program goes on after block Q.
#[derive(Clone, Debug)]
pub struct Contour {
    pub elements: Vec<Element>,
    /// The first block wrote X (or U), Z (or W): with both, a type II shape.
    pub first_has: [bool; 2],
    /// G40/G41/G42 written in the shape: the side from the element of that index on (an
    /// index past the last element: from the return to the start point on).
    pub compensation: Vec<(usize, TrcSide)>,
    /// Where each element's block starts (position, line, line start): alarms about an
    /// element name its block.
    pub blocks: Vec<Mark>,
    pub after: Mark,
}

/// The words of one block of the shape.
#[derive(Default)]
struct ShapeWords {
    g: Option<(MotionMode, usize)>,
    /// G40/G41/G42 and where it was written.
    trc: Option<(TrcSide, usize)>,
    x: Option<(Val, bool)>,
    z: Option<(Val, bool)>,
    r: Option<Val>,
    i: Option<Val>,
    k: Option<Val>,
    f: Option<Val>,
    s: Option<Val>,
    number: Option<u32>,
}

impl Interpreter<'_> {
    /// The shape from block `p` to block `q`, starting at the tool position `from`. A fault
    /// in a block of the shape names that block's line.
    pub(super) fn read_contour(
        &mut self,
        (p, p_at): (u32, usize),
        (q, q_at): (u32, usize),
        from: Pos,
        new: &ModalState,
    ) -> R<Contour> {
        let (mut pos, mut line, mut line_start) = self.find_label(p, p_at)?;
        let (mut at, mut mode) = (from, None);
        let mut elements = Vec::new();
        let mut first_has = [false; 2];
        let mut sides = Vec::new();
        let mut blocks = Vec::new();
        // Bounded by the text: every round reads one block further.
        loop {
            if pos >= self.src.len() {
                return Err(fault(
                    AlarmCode::JumpTarget,
                    q_at,
                    format!("the shape's last block N{q} does not follow block N{p}"),
                ));
            }
            let (end, next) = self.block_after(pos, line, line_start);
            let sw = self
                .shape_words(pos, end)
                .and_then(|sw| {
                    if elements.is_empty() && mode.is_none() {
                        self.first_block(&sw, p, pos)?;
                        first_has = [sw.x.is_some(), sw.z.is_some()];
                    }
                    if let Some(side) = self.shape_side(&sw, mode)? {
                        sides.push((elements.len(), side));
                    }
                    Ok(sw)
                })
                .map_err(|f| self.fault_at_line(f, line, line_start))?;
            if let Some(e) = self
                .shape_element(&sw, &mut mode, at, new)
                .map_err(|f| self.fault_at_line(f, line, line_start))?
            {
                at = e.to;
                elements.push(e);
                blocks.push((pos, line, line_start));
            }
            if sw.number == Some(q) {
                return Ok(Contour {
                    elements,
                    first_has,
                    compensation: sides,
                    blocks,
                    after: next,
                });
            }
            (pos, line, line_start) = next;
        }
    }

    /// The end of the block starting at `pos` (a `;` or the line's end) and where the next
    /// one starts.
    fn block_after(&self, pos: usize, line: u32, line_start: usize) -> (usize, Mark) {
        let line_end = super::super::super::lexer::find_byte(self.src, pos, [b'\n']);
        match block_text::fanuc_block_end(&self.src[..line_end], pos) {
            BlockEnd::Semicolon(i) if i < line_end => (i, (i + 1, line, line_start)),
            _ => (line_end, (line_end + 1, line + 1, line_end + 1)),
        }
    }

    /// The shape's first block states its motion, G00 or G01.
    fn first_block(&self, sw: &ShapeWords, p: u32, pos: usize) -> R<()> {
        if sw
            .g
            .is_some_and(|g| matches!(g.0, MotionMode::Rapid | MotionMode::Linear))
        {
            return Ok(());
        }
        let codes = self.d.codes_of(&[
            GEffect::Motion(MotionMode::Rapid),
            GEffect::Motion(MotionMode::Linear),
        ]);
        Err(fault(
            AlarmCode::MissingValue,
            pos,
            format!("the shape's first block N{p} needs {codes}"),
        ))
    }

    /// A fault in another block than the one being built: the alarm names its line.
    pub(super) fn fault_at_line(
        &mut self,
        f: Box<super::super::super::fault::Fault>,
        line: u32,
        line_start: usize,
    ) -> Box<super::super::super::fault::Fault> {
        (self.blk_line, self.blk_line_start, self.blk_number) = (line, line_start, None);
        f
    }

    /// The words of the block `src[start..end]`.
    fn shape_words(&self, start: usize, end: usize) -> R<ShapeWords> {
        let mut c = Cursor::new(self.src, start, end);
        let mut sw = ShapeWords {
            number: block_text::block_number(self.src, start, end).map(|n| n.value),
            ..Default::default()
        };
        block_text::skip_prefix(&mut c);
        loop {
            c.skip_blanks();
            let Some(ch) = c.peek() else { return Ok(sw) };
            let at = c.i;
            if ch == b'(' {
                c.skip_comment();
                continue;
            }
            let Some(letter) = c.letter() else {
                return Err(not_in_shape(at, &(ch as char).to_string()));
            };
            let Some((n, e)) = number::parse(self.src, at + 1).filter(|&(_, e)| e <= end) else {
                return Err(not_in_shape(at + 1, "a value other than a number"));
            };
            c.i = e;
            self.shape_word(&mut sw, letter, Val::new(n, at), at)?;
        }
    }

    fn shape_word(&self, sw: &mut ShapeWords, letter: u8, v: Val, at: usize) -> R<()> {
        let slot = match letter {
            b'G' => return self.shape_code(sw, v, at),
            b'X' | b'U' => {
                sw.x = Some((v, letter == b'U'));
                return Ok(());
            }
            b'Z' | b'W' => {
                sw.z = Some((v, letter == b'W'));
                return Ok(());
            }
            b'R' => &mut sw.r,
            b'I' => &mut sw.i,
            b'K' => &mut sw.k,
            b'F' => &mut sw.f,
            b'S' => &mut sw.s,
            _ => return Err(not_in_shape(at, &format!("{}", letter as char))),
        };
        *slot = Some(v);
        Ok(())
    }

    /// The compensation a block of the shape programs: G41/G42 in a block that moves at
    /// G00/G01 (the start-up), G40 anywhere (with the next move).
    fn shape_side(&self, sw: &ShapeWords, mode: Option<MotionMode>) -> R<Option<TrcSide>> {
        let Some((side, at)) = sw.trc else {
            return Ok(None);
        };
        if side == TrcSide::Off {
            return Ok(Some(side));
        }
        let m = sw.g.map(|g| g.0).or(mode);
        let linear = matches!(m, Some(MotionMode::Rapid | MotionMode::Linear));
        if !linear || (sw.x.is_none() && sw.z.is_none()) {
            let codes = self.d.codes_of(&[
                GEffect::Motion(MotionMode::Rapid),
                GEffect::Motion(MotionMode::Linear),
            ]);
            return Err(fault(
                self.d.trc_not_linear,
                at,
                format!("the shape's compensation starts in a block that moves at {codes}"),
            ));
        }
        Ok(Some(side))
    }

    /// A G code of the shape: a motion, or the nose radius compensation (G40/G41/G42).
    fn shape_code(&self, sw: &mut ShapeWords, v: Val, at: usize) -> R<()> {
        let code = v.value;
        let def = (code.fract() == 0.0 && (0.0..1000.0).contains(&code))
            .then(|| self.d.gcode(code as u16))
            .flatten();
        match def.map(|d| d.effect) {
            Some(GEffect::Motion(m)) => sw.g = Some((m, at)),
            Some(GEffect::Trc(side)) => sw.trc = Some((side, at)),
            _ => {
                return Err(not_in_shape(
                    at,
                    &crate::dialect::GName(code as u16).to_string(),
                ))
            }
        }
        Ok(())
    }

    /// The element the block's words make, from `at` (none for a block without X or Z).
    fn shape_element(
        &self,
        sw: &ShapeWords,
        mode: &mut Option<MotionMode>,
        at: Pos,
        new: &ModalState,
    ) -> R<Option<Element>> {
        if let Some((m, _)) = sw.g {
            *mode = Some(m);
        }
        let zero = self.zero(new.work_offset);
        let mut to = at;
        for (i, word) in [(0, sw.x), (2, sw.z)] {
            if let Some((v, inc)) = word {
                let d = if inc {
                    Distance::Incremental
                } else {
                    Distance::Absolute
                };
                let len = self.length(v, new.units) * diameter_factor(i, new, d);
                to[i] = if inc { at[i] + len } else { len + zero[i] };
            }
        }
        if sw.x.is_none() && sw.z.is_none() {
            return Ok(None);
        }
        let m = mode.unwrap_or(MotionMode::Linear);
        let centre = match m {
            MotionMode::Rapid | MotionMode::Linear => to,
            MotionMode::ArcCw | MotionMode::ArcCcw => self.shape_centre(sw, m, at, to, new)?,
            _ => return Err(not_in_shape(sw.g.map_or(0, |g| g.1), "this motion")),
        };
        Ok(Some(Element {
            to,
            mode: m,
            centre,
            feed: sw.f.map(|v| v.value),
            speed: sw.s.map(|v| v.value),
        }))
    }

    /// An arc's centre from R or I K (I a radius, not a diameter).
    fn shape_centre(
        &self,
        sw: &ShapeWords,
        m: MotionMode,
        from: Pos,
        to: Pos,
        new: &ModalState,
    ) -> R<Pos> {
        let spec = match (sw.r, sw.i.or(sw.k)) {
            (Some(r), _) => CentreSpec::Radius(self.length(r, new.units)),
            (None, Some(_)) => {
                let off = |v: Option<Val>| v.map_or(0.0, |v| self.length(v, new.units));
                CentreSpec::Offsets([off(sw.i), 0.0, off(sw.k)])
            }
            (None, None) => {
                return Err(fault(
                    AlarmCode::MissingValue,
                    sw.g.map_or(0, |g| g.1),
                    "an arc of the shape needs R or I K",
                ))
            }
        };
        let tol = self.md.program.arc_endpoint_tolerance;
        arc::centre(from, to, Plane::ZX, m == MotionMode::ArcCcw, spec, tol).map_err(|e| {
            fault(
                AlarmCode::ArcEndPoint,
                sw.r.or(sw.i).or(sw.k).map_or(0, |v| v.pos()),
                format!("no arc of the shape fits: {e:?}"),
            )
        })
    }
}

#[cold]
fn not_in_shape(at: usize, what: &str) -> Box<super::super::super::fault::Fault> {
    fault(
        AlarmCode::NotSupported,
        at,
        format!("{what} in a turning cycle's shape is not supported by softnc (only moves with X Z U W R I K F S)"),
    )
}
