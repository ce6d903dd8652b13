//! SINUMERIK compensation words in the block build (840D sl Fundamentals "Tool radius
//! compensation"; docs/sinumerik.md "Compensation words"):
//!
//! - NORM and KONT choose the compensation's approach and retraction (the dialect table maps
//!   them onto selection policies); DISC= with G450 chooses between the transition circle
//!   (0) and the intersection (100).
//! - The smooth approach (G147 G247 G347) is held in the block build until the contour
//!   element it leads onto is built: its contour depends on that element's direction. The
//!   blocks built meanwhile are held too (they take the full way: the plain path is off).
//!   Then all go out as an expansion (build/expand.rs), programmed blocks before
//!   compensation: the infeed P0 → P1 → P2 → P3 and the approach contour P3 → P4, tangent
//!   to the element ([`crate::frontend::sinumerik::approach`] has the geometry), the held
//!   blocks and the element. The first of them selects the compensation, straight to its
//!   normal position, so that the equidistant of the approach contour is the tool centre's
//!   path.
//! - The smooth retraction (G148 G248 G348) knows all it needs when its block is built (the
//!   last contour element is the interpreter's last move): its blocks go out in its place.
//!
//! Nothing here is on the way of a block while no compensation word is in play: the
//! interpreter's stream is untouched, and the block build asks one `Option` at its end.

use super::super::block::*;
use super::super::fault::{fault, Fault, R};
use super::super::interpreter::Interpreter;
use super::super::sinumerik::approach::{
    self, Contour, Heights, Joint, Level, Piece, Request, SarContour, SarError, SarPath, SarSide,
    Tool, V,
};
use super::super::sinumerik::compensation::{CompensationWords, LevelWord};
use super::super::words::Words;
use super::gcodes::{BlockCodes, Codes};
use super::Expansion;
use crate::alarm::AlarmCode;
use crate::dialect::{Dialect, GEffect};

/// At most this many blocks without a traversing motion may stand between a smooth approach
/// and the contour element it leads onto (808D Programming and Operating Manual, milling,
/// "Smooth approach and retraction": 5).
const BLOCKS_BETWEEN: usize = 5;

/// Lengths below this count as zero (mm).
const EPS: f64 = 1e-9;

/// The compensation words' state: the modal settings, an approach waiting for its contour
/// element, and the blocks to hand out. `None` in the interpreter until a program uses one
/// of the words, so that a program without them pays nothing.
#[derive(Clone, Debug)]
pub struct Smooth<'a> {
    /// G140 … G143 in force.
    pub side: SarSide,
    /// G340 / G341 in force.
    pub path: SarPath,
    /// DISC in force: 0 (transition circle) or 100 (intersection).
    disc: u8,
    /// G450 is the corner code in force (DISC acts only under it).
    g450: bool,
    hold: Option<Box<Hold<'a>>>,
    /// A retraction's blocks, to go out in place of its block.
    out: Vec<Block>,
}

/// A smooth approach waiting for the contour element.
#[derive(Clone, Debug)]
struct Hold<'a> {
    req: Request,
    fad: Option<Pace>,
    /// The approach block as built; `None` until it is complete.
    sar: Option<Block>,
    /// Where the tool stands before it (P0), and the modal state in force there.
    p0: Pos,
    old: ModalState,
    /// P4: the approach block's end if it programs an axis of the plane, else the end of the
    /// next block that moves (NCP19 p.278), which is then held too.
    p4: Option<Pos>,
    p4_block: Option<Block>,
    /// Blocks without a traversing motion before P4 is known, and after.
    before: Vec<Block>,
    after: Vec<Block>,
    /// The approach block's line, line start and number, and its code's byte offset: the
    /// alarms the later blocks raise point there.
    place: (u32, usize, Option<BlockNo>),
    at: u32,
    /// The plain-block fast path as it was (held blocks take the full one).
    plain_path: bool,
    /// Ties the hold to the program text's lifetime, as the interpreter.
    text: std::marker::PhantomData<&'a str>,
}

/// How a generated block moves: at rapid, or at a feed (mm/min, or mm/rev).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pace {
    rapid: bool,
    feed: f64,
    per_rev: bool,
}

impl Pace {
    fn feed(feed: f64, per_rev: bool) -> Pace {
        Pace {
            rapid: false,
            feed,
            per_rev,
        }
    }
}

impl<'a> Interpreter<'a> {
    /// The compensation words' state, created at the first use.
    pub(super) fn smooth_state(&mut self) -> &mut Smooth<'a> {
        let g450 = self.block.modal.corner == CornerPolicy::TransitionCircle;
        self.smooth.get_or_insert_with(|| {
            Box::new(Smooth {
                side: SarSide::default(),
                path: SarPath::default(),
                disc: 0,
                g450,
                hold: None,
                out: Vec::new(),
            })
        })
    }

    /// Block build step 4, the named G functions (NORM, KONT, …), DISC and the corner it
    /// sets; SAR parameters belong to a SAR block. Out of line: only blocks with these words,
    /// or programs that use them, come here.
    #[cold]
    #[inline(never)]
    pub(super) fn compensation_words(
        &mut self,
        w: &Words,
        codes: &Codes,
        g: &BlockCodes,
        new: &mut ModalState,
    ) -> R<()> {
        if let Some(cw) = w.compensation.as_deref() {
            self.named_codes(cw, codes, new)?;
            if let Some(v) = cw.disc {
                let disc = disc_value(v.value, v.at)?;
                self.smooth_state().disc = disc;
            }
            if let (None, Some((at, name))) = (g.sar, cw.sar_parameter()) {
                let sar = self.d.codes_of(&[
                    GEffect::SmoothApproach(SarContour::Line),
                    GEffect::SmoothRetraction(SarContour::Line),
                ]);
                return Err(fault(
                    AlarmCode::Syntax,
                    at,
                    format!("{name} belongs to a smooth approach or retraction block ({sar} …)"),
                ));
            }
        }
        let corner_code = codes.iter().find_map(|(def, _)| match def.effect {
            GEffect::Corner(c) => Some(c),
            _ => None,
        });
        let intersection = self.d.initial_corner_intersection;
        // NORM and KONT alone leave the state alone (and later blocks their fast way).
        let Some(s) = self.smooth.as_deref_mut() else {
            return Ok(());
        };
        if let Some(c) = corner_code {
            s.g450 = c == CornerPolicy::TransitionCircle;
        }
        // Fundamentals "G450 DISC": 0 the transition circle, 100 the intersection of the
        // equidistants, which is the dialect's intersection policy (the 808D/840D G451's).
        if s.g450 {
            new.corner = if s.disc == 100 {
                intersection
            } else {
                CornerPolicy::TransitionCircle
            };
        }
        Ok(())
    }

    /// NORM, KONT, KONTC, KONTT: one of a group a block, not with a G code of the group;
    /// what softnc does not build is alarm 12580.
    fn named_codes(&self, cw: &CompensationWords, codes: &Codes, new: &mut ModalState) -> R<()> {
        for (k, &(def, at)) in cw.codes.iter().enumerate() {
            let numbered = codes.iter().map(|(d, _)| (d.effect, ""));
            let named = cw.codes[..k].iter().map(|(d, _)| (d.effect, d.text));
            if let Some((_, other)) = numbered
                .chain(named)
                .find(|(e, _)| Dialect::same_group(*e, def.effect))
            {
                return Err(fault(
                    AlarmCode::SameGroupTwice,
                    at,
                    format!("{} and {other} belong to the same group", def.text),
                ));
            }
            match def.effect {
                GEffect::Selection(sp) => new.selection = sp,
                GEffect::Unsupported(what) => {
                    return Err(fault(
                        AlarmCode::NotSupported,
                        at,
                        format!("{what} is not supported by softnc"),
                    ))
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// DISC=: 0 … 100 (Fundamentals "G450 DISC": type INT). softnc builds the two ends; the
/// conic in between is alarm 12580.
fn disc_value(v: f64, at: u32) -> R<u8> {
    if !(0.0..=100.0).contains(&v) || v.fract() != 0.0 {
        return Err(fault(
            AlarmCode::BadNumber,
            at,
            format!("DISC={v}: the overshoot is a whole number from 0 to 100"),
        ));
    }
    if v != 0.0 && v != 100.0 {
        return Err(fault(
            AlarmCode::NotSupported,
            at,
            format!("DISC={v}: softnc builds the transition circle (DISC=0) and the intersection (DISC=100), not the curve between them"),
        ));
    }
    Ok(v as u8)
}

/// `p`'s coordinates in `plane`: the point in the plane, and the height on the normal axis.
fn split(p: &Pos, plane: Plane) -> (V, f64) {
    (
        [p[plane.abscissa as usize], p[plane.ordinate as usize]],
        p[plane.normal as usize],
    )
}

/// The position at `v` in `plane` and height `z`.
fn join(v: V, z: f64, plane: Plane) -> Pos {
    let mut p = [0.0; 3];
    p[plane.abscissa as usize] = v[0];
    p[plane.ordinate as usize] = v[1];
    p[plane.normal as usize] = z;
    p
}

/// The axes of `plane` as [`Motion::programmed`] bits.
fn plane_bits(plane: Plane) -> u16 {
    1 << plane.abscissa | 1 << plane.ordinate
}

/// The unit tangent of `m` in its plane at its start or end (`None`: it does not move in the
/// plane).
fn tangent_of(m: &Motion, at_end: bool) -> Option<V> {
    let (a, _) = split(&m.start, m.plane);
    let (b, _) = split(&m.end, m.plane);
    let centre = m
        .kind
        .is_arc()
        .then(|| (split(&m.center, m.plane).0, m.kind == MotionKind::ArcCcw));
    approach::tangent(a, b, centre, at_end)
}

/// The blocks a SAR plan becomes: each starts where the last ended, with the SAR block's
/// place and its modal state, changed by what the move needs.
struct Gen {
    plane: Plane,
    template: Block,
    at: Pos,
    blocks: Vec<Block>,
}

impl Gen {
    fn new(template: &Block, at: Pos) -> Gen {
        let mut t = Block::new(template.line, template.col, template.number, template.modal);
        t.program = template.program;
        Gen {
            plane: template.modal.plane,
            template: t,
            at,
            blocks: Vec::new(),
        }
    }

    /// A straight move to `to`; `always`: also when it moves nothing (a selection or
    /// deselection block, which must program the plane's axes).
    fn line(&mut self, to: Pos, pace: Pace, always: bool) -> Option<&mut Block> {
        let moved = (0..3).any(|i| (to[i] - self.at[i]).abs() > EPS);
        if !moved && !always {
            return None;
        }
        let bits = (0..3).fold(plane_bits(self.plane), |b, i| {
            b | u16::from((to[i] - self.at[i]).abs() > EPS) << i
        });
        let kind = if pace.rapid {
            MotionKind::Rapid
        } else {
            MotionKind::Linear
        };
        let m = Motion {
            kind,
            plane: self.plane,
            start: self.at,
            end: to,
            center: to,
            programmed: bits,
        };
        Some(self.push(m, pace))
    }

    /// The approach or retraction contour, ending at height `z_end`.
    fn element(&mut self, e: &Piece, z_end: f64, pace: Pace) -> &mut Block {
        let plane = self.plane;
        let (_, z0) = split(&self.at, plane);
        let bits = plane_bits(plane) | u16::from((z_end - z0).abs() > EPS) << plane.normal;
        let m = match *e {
            Piece::Line { to, .. } => Motion {
                kind: MotionKind::Linear,
                plane,
                start: self.at,
                end: join(to, z_end, plane),
                center: join(to, z_end, plane),
                programmed: bits,
            },
            Piece::Arc {
                to, centre, ccw, ..
            } => Motion {
                kind: if ccw {
                    MotionKind::ArcCcw
                } else {
                    MotionKind::ArcCw
                },
                plane,
                start: self.at,
                end: join(to, z_end, plane),
                center: join(centre, z0, plane),
                programmed: bits,
            },
        };
        self.push(m, pace)
    }

    fn push(&mut self, m: Motion, pace: Pace) -> &mut Block {
        let mut b = self.template.clone();
        b.modal.motion = match m.kind {
            MotionKind::Rapid => MotionMode::Rapid,
            MotionKind::Linear => MotionMode::Linear,
            MotionKind::ArcCw => MotionMode::ArcCw,
            MotionKind::ArcCcw => MotionMode::ArcCcw,
        };
        b.modal.feed = pace.feed;
        b.modal.feed_per_rev = pace.per_rev;
        b.motion = Some(m);
        self.at = m.end;
        self.blocks.push(b);
        let last = self.blocks.len() - 1;
        &mut self.blocks[last]
    }

    /// The SAR block's words go with the first block, its stop, message and exact stop with
    /// the last (they act where the programmed block ends).
    fn finish(mut self, sar: &Block) -> Vec<Block> {
        if let Some(first) = self.blocks.first_mut() {
            first.words = sar.words.clone();
            first.offset_changed = sar.offset_changed;
            first.calculation = sar.calculation;
        }
        if let Some(last) = self.blocks.last_mut() {
            last.stop = sar.stop;
            last.message = sar.message.clone();
            last.exact_stop = sar.exact_stop;
        }
        self.blocks
    }
}

/// The SAR error as a fault at the SAR code.
fn sar_fault(e: SarError, at: u32) -> Box<super::super::fault::Fault> {
    let (code, why) = sar_alarm(e);
    fault(code, at, why)
}

fn sar_alarm(e: SarError) -> (AlarmCode, String) {
    match e {
        SarError::Distance(m) => (AlarmCode::SarDistance, m),
        SarError::Direction(m) => (AlarmCode::SarDirection, m),
        SarError::Reversal(m) => (AlarmCode::SarReversal, m),
    }
}

/// What the block's words ask of the SAR: DISR, DISCL, DISRP in mm (inch converted), DISCL
/// and DISRP as distances (not negative) or positions on the tool axis, FAD as a pace.
struct SarWords {
    disr: Option<f64>,
    discl: Option<Level>,
    disrp: Option<Level>,
    fad: Option<Pace>,
}

impl Interpreter<'_> {
    /// DISR DISCL DISRP FAD of the block, checked.
    fn sar_words(&self, w: &Words, new: &ModalState) -> R<SarWords> {
        let cw = w.compensation.as_deref();
        let units = new.units;
        let disr = cw.and_then(|c| c.disr).map(|v| self.length(v, units));
        let discl = cw
            .and_then(|c| c.discl)
            .map(|l| self.level(l, new, "DISCL"))
            .transpose()?;
        let disrp = cw
            .and_then(|c| c.disrp)
            .map(|l| self.level(l, new, "DISRP"))
            .transpose()?;
        let fad = match cw.and_then(|c| c.fad) {
            None => None,
            Some(f) => {
                if f.value.value <= 0.0 {
                    return Err(fault(
                        AlarmCode::BadNumber,
                        f.value.at,
                        "the feed FAD must be positive",
                    ));
                }
                let per_rev = f.per_rev.unwrap_or(new.feed_per_rev);
                // Inch per minute or per revolution, converted as F is.
                let scale = if units == crate::machine_data::Units::Inch {
                    25.4
                } else {
                    1.0
                };
                Some(Pace::feed(f.value.value * scale, per_rev))
            }
        };
        Ok(SarWords {
            disr,
            discl,
            disrp,
            fad,
        })
    }

    /// A frame acts on the block's coordinates.
    fn framed(&self) -> bool {
        self.coords.frame.active() && !self.machine_coordinates
    }

    /// The frame moves the plane rigidly (translations, rotations in it, nothing mirrored or
    /// scaled) and the tool axis along itself: lengths, sides and the tool axis stay, so the
    /// SAR is built where the frame puts the contour.
    fn frame_rigid(&self, plane: Plane) -> bool {
        let f = &self.coords.frame;
        let n = plane.normal as usize;
        let mut axis = [0.0; 3];
        axis[n] = 1.0;
        f.plane_scale(plane)
            .is_some_and(|s| (s - 1.0).abs() < 1e-12)
            && !f.flips(plane)
            && (f.turn(axis)[n] - 1.0).abs() < 1e-12
    }

    /// DISCL= or DISRP=: a distance (not negative) or with AC() a position on the tool axis.
    fn level(&self, l: LevelWord, new: &ModalState, name: &str) -> R<Level> {
        let normal = new.plane.normal as usize;
        if l.absolute {
            let abs = ModalState {
                distance: Distance::Absolute,
                ..*new
            };
            let zero = self.zero(new.work_offset);
            let mut z = self.axis_target(l.value, normal, &abs, 0.0, zero[normal]);
            if self.framed() {
                // A rigid frame moves the tool axis only along itself.
                let mut p = [0.0; 3];
                p[normal] = z - zero[normal];
                z = self.coords.frame.apply(p)[normal] + zero[normal];
            }
            return Ok(Level::At(z));
        }
        let v = self.length(l.value, new.units);
        if v < 0.0 {
            return Err(fault(
                AlarmCode::SarDistance,
                l.value.at,
                format!(
                    "{name}={}: a distance from the machining plane is not negative",
                    l.value.value
                ),
            ));
        }
        Ok(Level::Distance(v))
    }
}

/// What may not stand in a SAR block (alarm 12580 at the SAR code): a block that is not a
/// plain move.
fn sar_block_alone(w: &Words, g: &BlockCodes) -> Option<&'static str> {
    if g.dwell.is_some() {
        Some("a dwell")
    } else if g.working_area.is_some() || g.setting.is_some() || g.frame.is_some() {
        Some("a setting")
    } else if g.reference.is_some() || g.cycle.is_some() {
        Some("a cycle or a reference point return")
    } else if w.corner.is_some() || !w.path.is_empty() || g.pole.is_some() {
        Some("a chamfer, a rounding, a pole or a path word (CIP, CT, AP=, RP=, TURN=, RNDM=)")
    } else if w.additional.iter().any(Option::is_some) {
        Some("an additional axis")
    } else if w.centre.iter().any(Option::is_some) || w.radius.is_some() {
        Some("circle parameters")
    } else {
        None
    }
}

impl<'a> Interpreter<'a> {
    /// Block build step 8 for a SAR block: its axis words are P4 (approach) or P0
    /// (retraction). The approach waits for its contour element; the retraction's blocks are
    /// ready now.
    #[cold]
    #[inline(never)]
    pub(super) fn smooth_block(
        &mut self,
        w: &Words,
        g: &BlockCodes,
        new: &mut ModalState,
        (effect, at): (GEffect, u32),
    ) -> R<()> {
        if let Some(what) = self.sar_refused(w, g, new) {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("a smooth approach or retraction with {what} is not supported by softnc"),
            ));
        }
        let (contour, retract) = match effect {
            GEffect::SmoothRetraction(c) => (c, true),
            GEffect::SmoothApproach(c) => (c, false),
            _ => return Ok(()),
        };
        let words = self.sar_words(w, new)?;
        let normal = new.plane.normal as usize;
        if !self.md.has_axis(normal) && (words.discl.is_some() || words.disrp.is_some()) {
            return Err(fault(
                AlarmCode::UnknownAddress,
                at,
                format!(
                    "DISCL= and DISRP= move along {}, which this machine does not have",
                    AXIS_NAMES[normal]
                ),
            ));
        }
        let s = self.smooth_state();
        let req = Request {
            contour,
            retract,
            side: s.side,
            path: s.path,
            disr: words.disr,
            discl: words.discl,
            disrp: words.disrp,
        };
        let end = self.sar_end(w, new, at)?;
        let programmed = (0..3).fold(0u16, |b, i| b | u16::from(w.axis[i].is_some()) << i);
        // The G40/G41/G42 of the block go with the blocks it becomes.
        self.block.trc = None;
        if retract {
            let last = self.last_move;
            return self.retraction(req, words.fad, new, end, programmed, last, at);
        }
        self.approach(req, words.fad, new, end, programmed, at)
    }

    /// What a SAR block cannot go with (alarm 12580): see [`sar_block_alone`]; a frame that
    /// is not rigid, machine coordinates, a pending chamfer or rounding, an approach that
    /// still waits.
    fn sar_refused(&self, w: &Words, g: &BlockCodes, new: &ModalState) -> Option<String> {
        if let Some(what) = sar_block_alone(w, g) {
            return Some(what.to_string());
        }
        if self.calls.modal.is_some() {
            return Some("a modal call (MCALL)".to_string());
        }
        let framed = self.framed() && !self.frame_rigid(new.plane);
        if framed || self.machine_coordinates || self.corners.is_some() {
            return Some("a frame that scales, mirrors or tilts, machine coordinates, or a pending chamfer or rounding".to_string());
        }
        let waiting = self.smooth.as_ref().is_some_and(|s| s.hold.is_some());
        waiting.then(|| "an approach still waiting for its contour".to_string())
    }

    /// The SAR block's end point; under a frame worked out in program coordinates, then
    /// through the frame and the zero (frames.rs).
    fn sar_end(&self, w: &Words, new: &ModalState, at: u32) -> R<Pos> {
        if !self.framed() {
            return self.end_point(w, new, self.cur);
        }
        let (_, p) = self.framed_points(w, new, at as usize)?;
        let zero = self.zero(new.work_offset);
        let q = self.coords.frame.apply(p);
        Ok(std::array::from_fn(|i| q[i] + zero[i]))
    }

    /// A smooth approach: held until its contour element is built ([`Self::smooth_built`]).
    fn approach(
        &mut self,
        req: Request,
        fad: Option<Pace>,
        new: &ModalState,
        end: Pos,
        programmed: u16,
        at: u32,
    ) -> R<()> {
        if new.trc == TrcSide::Off && self.block.modal.trc != TrcSide::Off {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "a smooth approach cannot deselect the compensation",
            ));
        }
        let start = self.cur;
        self.block.motion = Some(Motion {
            kind: MotionKind::Linear,
            plane: new.plane,
            start,
            end,
            center: end,
            programmed,
        });
        let p4 = (programmed & plane_bits(new.plane) != 0).then_some(end);
        let hold = Hold {
            req,
            fad,
            sar: None,
            p0: start,
            old: self.block.modal,
            p4,
            p4_block: None,
            before: Vec::new(),
            after: Vec::new(),
            place: (self.blk_line, self.blk_line_start, self.blk_number),
            at,
            plain_path: self.plain_path,
            text: std::marker::PhantomData,
        };
        // Until the contour element: every block the full way, which holds it.
        self.plain_path = false;
        self.smooth_state().hold = Some(Box::new(hold));
        Ok(())
    }
}

/// The retraction's point P0 as the block programs it (NCP19 p.279; PG04 8-50): a plane
/// axis programmed (the other is modal) → the full way to P0; only the tool axis → the way
/// ends at P1 (and on to P0, the plane's position unchanged, when the block also deselects);
/// nothing → it ends at P2.
#[derive(Clone, Copy, Debug, PartialEq)]
enum RetractEnd {
    Full,
    AxisOnly,
    None,
}

/// What a retraction is built from.
struct Retraction {
    req: Request,
    fad: Option<Pace>,
    /// P4 (where the tool stands) and P0 (the programmed end).
    p4: Pos,
    p0: Pos,
    end: RetractEnd,
    /// The compensation before the block, and whether the block deselects it.
    tool: Tool,
    deselect: bool,
    old: ModalState,
}

impl Interpreter<'_> {
    /// A smooth retraction: its blocks go out in place of its block ([`Self::smooth_built`]).
    #[allow(clippy::too_many_arguments)]
    fn retraction(
        &mut self,
        req: Request,
        fad: Option<Pace>,
        new: &ModalState,
        p0: Pos,
        programmed: u16,
        last: Option<Motion>,
        at: u32,
    ) -> R<()> {
        let old = self.block.modal;
        if new.trc != TrcSide::Off && new.trc != old.trc {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                "a smooth retraction cannot select the compensation",
            ));
        }
        let t = last.and_then(|m| tangent_of(&m, true)).ok_or_else(|| {
            fault(
                AlarmCode::SarDirection,
                at,
                "a smooth retraction leaves the contour element in the block before it, which must move in the plane",
            )
        })?;
        let plane = new.plane;
        let end = if programmed & plane_bits(plane) != 0 {
            RetractEnd::Full
        } else if programmed & 1 << plane.normal != 0 {
            RetractEnd::AxisOnly
        } else {
            RetractEnd::None
        };
        let r = Retraction {
            req,
            fad,
            p4: self.cur,
            p0,
            end,
            tool: Tool {
                on: old.trc != TrcSide::Off,
                left: old.trc == TrcSide::Left,
                radius: old.radius,
            },
            deselect: old.trc != TrcSide::Off && new.trc == TrcSide::Off,
            old,
        };
        let blocks = self.retraction_blocks(&r, t, new).map_err(|e| match e {
            Fail::Sar(e) => sar_fault(e, at),
            Fail::Feed => no_feed(at),
        })?;
        self.block.motion = blocks.last().and_then(|b| b.motion);
        self.smooth_state().out.extend(blocks);
        Ok(())
    }
}

/// The block deselects the compensation straight from the last element's normal position,
/// if a deselection is `pending`.
fn deselection(b: &mut Block, pending: &mut bool) {
    if std::mem::take(pending) {
        b.trc = Some(TrcSide::Off);
        b.approach = Some(SelectionPolicy::NormalPosition);
    }
}

/// Why a SAR plan fails: its geometry, or a move without a feed.
enum Fail {
    Sar(SarError),
    Feed,
}

impl From<SarError> for Fail {
    fn from(e: SarError) -> Fail {
        Fail::Sar(e)
    }
}

#[cold]
fn no_feed(at: u32) -> Box<super::super::fault::Fault> {
    fault(
        AlarmCode::NoFeed,
        at,
        "no feed programmed (F) for the smooth approach or retraction",
    )
}

/// A feed pace, if there is a feed.
fn feed_pace(m: &ModalState) -> Result<Pace, Fail> {
    if m.feed > 0.0 {
        Ok(Pace::feed(m.feed, m.feed_per_rev))
    } else {
        Err(Fail::Feed)
    }
}

impl Interpreter<'_> {
    /// The retraction's blocks (NCP19 p.276, p.280): the contour from P4 (at the old feed, or
    /// FAD under G340), under G341 the slow lift to P2 (FAD), then P1 and P0 at the block's
    /// own motion. A deselection goes with the first block after the contour, in tool-centre
    /// coordinates, straight from the contour's normal position.
    fn retraction_blocks(
        &self,
        r: &Retraction,
        t: V,
        new: &ModalState,
    ) -> Result<Vec<Block>, Fail> {
        let plane = new.plane;
        let (p4, z4) = split(&r.p4, plane);
        let (p0, z_prog) = split(&r.p0, plane);
        let given = (r.end == RetractEnd::Full).then_some(p0);
        let joint = Joint {
            p4,
            t,
            other: given,
        };
        let contour = approach::contour(&r.req, &r.tool, &joint)?;
        let h = retraction_heights(r, z4, z_prog)?;
        let old_feed = feed_pace(&r.old)?;
        let slow = r.fad.unwrap_or(old_feed);
        let own = own_pace(new)?;
        let mut template = self.block.clone();
        template.modal = ModalState {
            trc: r.old.trc,
            ..*new
        };
        let mut gen = Gen::new(&template, r.p4);
        let first = if r.req.path == SarPath::Spatial {
            slow
        } else {
            old_feed
        };
        gen.element(&contour.element, h.z3, first);
        let far = if r.deselect {
            contour.tool_far
        } else {
            contour.far
        };
        let mut steps = vec![
            (join(far, h.z2, plane), slow),
            (join(far, h.z1, plane), own),
        ];
        if r.end == RetractEnd::Full || (r.end == RetractEnd::AxisOnly && r.deselect) {
            steps.push((r.p0, own));
        }
        let here = join(far, h.z3, plane);
        after_contour(&mut gen, here, &steps, r.deselect, own, new.trc);
        Ok(gen.finish(&self.block))
    }
}

/// The heights of a retraction: P0's is the programmed one, or where it ends at P2 (no axis
/// programmed) DISCL above the plane (DISCL=0 or none: in the plane), without a P1.
fn retraction_heights(r: &Retraction, z4: f64, z_prog: f64) -> Result<Heights, Fail> {
    let mut req = r.req;
    let z0 = if r.end == RetractEnd::None {
        req.disrp = None;
        match req.discl {
            Some(Level::Distance(v)) => z4 + v,
            Some(Level::At(z)) => z,
            None => z4,
        }
    } else {
        z_prog
    };
    Ok(approach::heights(&req, z0, z4)?)
}

/// The block's own motion: rapid under G0, else its feed.
fn own_pace(new: &ModalState) -> Result<Pace, Fail> {
    if new.motion.kind() == MotionKind::Rapid {
        Ok(Pace {
            rapid: true,
            ..Pace::feed(new.feed, new.feed_per_rev)
        })
    } else {
        feed_pace(new)
    }
}

/// The retraction's moves after its contour, from `here` (in the coordinates after the
/// contour: the tool centre's when the block deselects, for the deselection itself moves
/// nothing). The deselection goes with the first of them; a block of its own, moving
/// nothing, where none moves.
fn after_contour(
    gen: &mut Gen,
    here: Pos,
    steps: &[(Pos, Pace)],
    deselect: bool,
    own: Pace,
    trc: TrcSide,
) {
    let mut pending = deselect;
    let mut here = here;
    for &(to, pace) in steps {
        if (0..3).all(|i| (to[i] - here[i]).abs() <= EPS) {
            continue;
        }
        here = to;
        if let Some(b) = gen.line(to, pace, true) {
            b.modal.trc = trc;
            deselection(b, &mut pending);
        }
    }
    if pending {
        if let Some(b) = gen.line(here, own, true) {
            b.modal.trc = trc;
            deselection(b, &mut pending);
        }
    }
}

impl<'a> Interpreter<'a> {
    /// Block build step 11 while compensation words are in play (build/mod.rs): a SAR block
    /// is not handed out — a retraction's blocks go out in its place, an approach waits for
    /// its contour element — and while an approach waits, the blocks built wait with it.
    /// False: nothing to hand out now. Out of line: a program without the words never
    /// comes here.
    #[cold]
    #[inline(never)]
    pub(super) fn smooth_built(&mut self) -> R<bool> {
        let Some(s) = self.smooth.as_deref_mut() else {
            return Ok(true);
        };
        if !s.out.is_empty() {
            let blocks = std::mem::take(&mut s.out);
            self.queue(blocks);
            return Ok(false);
        }
        let Some(h) = s.hold.as_deref_mut() else {
            return Ok(true);
        };
        if h.sar.is_none() {
            h.sar = Some(self.block.clone());
            if self.finished {
                let why = "the program ends in the smooth approach's block";
                return Err(self.hold_fault(AlarmCode::SarBlocks, why.into()));
            }
            return Ok(false);
        }
        self.hold_next()
    }

    /// The blocks go out one per `next_block` (an expansion, build/expand.rs), then the
    /// modal state of the block just built is the interpreter's again; a program end acts
    /// with the block that carries it.
    fn queue(&mut self, blocks: Vec<Block>) {
        self.finished = false;
        self.expansion = Some(Expansion::blocks(blocks, self.block.modal));
    }

    /// The held approach meets the block just built: one without a traversing motion
    /// (held), the one that gives P4 (held), or the contour element.
    fn hold_next(&mut self) -> R<bool> {
        if let Some(what) = self.not_while_held() {
            let why = format!(
                "{what} between a smooth approach and its contour element is not supported"
            );
            return Err(self.hold_fault(AlarmCode::NotSupported, why));
        }
        let b = &self.block;
        let traversing = b.motion.is_some_and(|m| {
            m.kind.is_arc() || (0..3).any(|i| (m.end[i] - m.start[i]).abs() > EPS)
        });
        let ends = b.stop.is_some_and(|s| s.ends_program());
        let Some(h) = self
            .smooth
            .as_deref_mut()
            .and_then(|s| s.hold.as_deref_mut())
        else {
            return Ok(true);
        };
        if !traversing {
            if ends || h.before.len() + h.after.len() >= BLOCKS_BETWEEN {
                let why = format!("more than {BLOCKS_BETWEEN} blocks without a traversing motion, or the program's end, before the contour element the smooth approach leads onto");
                return Err(self.hold_fault(AlarmCode::SarBlocks, why));
            }
            let list = if h.p4.is_none() {
                &mut h.before
            } else {
                &mut h.after
            };
            list.push(self.block.clone());
            return Ok(false);
        }
        if h.p4.is_none() {
            h.p4 = self.block.motion.map(|m| m.end);
            h.p4_block = Some(self.block.clone());
            return Ok(false);
        }
        self.release()?;
        Ok(false)
    }

    /// What may not stand among the blocks an approach holds: a block that expands (a
    /// cycle, a helix's turns), a chamfer or rounding, G40/G41/G42.
    fn not_while_held(&self) -> Option<String> {
        if self.expansion.is_some() {
            Some("a cycle or a helix with turns".to_string())
        } else if self.corners.is_some() {
            Some("a chamfer or rounding".to_string())
        } else if self.block.trc.is_some() {
            Some(self.d.codes_of(&[
                GEffect::Trc(TrcSide::Off),
                GEffect::Trc(TrcSide::Left),
                GEffect::Trc(TrcSide::Right),
            ]))
        } else {
            None
        }
    }

    /// The contour element is the block just built: the approach's blocks, the held ones and
    /// the element go out in order.
    fn release(&mut self) -> R<()> {
        let Some(h) = self.smooth.as_deref_mut().and_then(|s| s.hold.take()) else {
            return Ok(());
        };
        self.plain_path = h.plain_path;
        let blocks = match self.approach_blocks(&h) {
            Ok(b) => b,
            Err(e) => {
                let (code, why) = match e {
                    Fail::Sar(e) => sar_alarm(e),
                    Fail::Feed => (
                        AlarmCode::NoFeed,
                        "no feed programmed (F) for the smooth approach".to_string(),
                    ),
                };
                return Err(self.fault_at(&h, code, why));
            }
        };
        let mut queue = h.before;
        queue.extend(blocks);
        if let Some(b) = h
            .p4_block
            .filter(|b| !b.words.is_empty() || b.stop.is_some())
        {
            // The block that gave P4 moves with the approach; its words act at P4.
            queue.push(Block { motion: None, ..b });
        }
        queue.extend(h.after);
        queue.push(self.block.clone());
        self.queue(queue);
        Ok(())
    }

    /// The approach's blocks for the contour element just built (NCP19 p.276, p.280): P0 →
    /// P1 selects the compensation, P1 → P2 (→ P3 under G341) at the speed before the block,
    /// G341's slow infeed P2 → P3 at FAD, the contour P3 → P4 at FAD (G340) or F.
    fn approach_blocks(&self, h: &Hold) -> Result<Vec<Block>, Fail> {
        let (Some(sar), Some(p4)) = (&h.sar, h.p4) else {
            return Ok(Vec::new());
        };
        let new = sar.modal;
        let plane = new.plane;
        let t = self
            .block
            .motion
            .filter(|m| m.plane == plane)
            .and_then(|m| tangent_of(&m, false))
            .ok_or_else(|| {
                SarError::Direction(format!(
                    "the block after the smooth approach must be a line or a circle in the {} plane",
                    plane.name()
                ))
            })?;
        let tool = Tool {
            on: new.trc != TrcSide::Off,
            left: new.trc == TrcSide::Left,
            radius: new.radius,
        };
        let (p4v, z4) = split(&p4, plane);
        let (p0v, z0) = split(&h.p0, plane);
        let joint = Joint {
            p4: p4v,
            t,
            other: Some(p0v),
        };
        let contour = approach::contour(&h.req, &tool, &joint)?;
        let heights = approach::heights(&h.req, z0, z4)?;
        let programmed = feed_pace(&new)?;
        let before = if h.old.motion.kind() == MotionKind::Rapid {
            Pace {
                rapid: true,
                ..Pace::feed(h.old.feed, h.old.feed_per_rev)
            }
        } else {
            feed_pace(&h.old)?
        };
        let slow = h.fad.unwrap_or(programmed);
        let paces = [before, slow, programmed];
        Ok(approach_moves(
            sar, h, &contour, heights, z4, paces, tool.on,
        ))
    }

    /// At the program's end: an approach still waiting is alarm 10740 at its code.
    pub(in crate::frontend) fn smooth_unfinished(&mut self) -> Option<Box<Fault>> {
        self.smooth.as_ref()?.hold.as_ref()?;
        let why = "the program ends before the contour element the smooth approach leads onto";
        Some(self.hold_fault(AlarmCode::SarBlocks, why.into()))
    }

    /// A fault at the held approach's code (the approach is dropped).
    #[cold]
    fn hold_fault(&mut self, code: AlarmCode, why: String) -> Box<Fault> {
        match self.smooth.as_deref_mut().and_then(|s| s.hold.take()) {
            Some(h) => self.fault_at(&h, code, why),
            None => fault(code, self.blk_line_start, why),
        }
    }

    /// A fault at `h`'s code: the block the alarm names becomes the approach block.
    #[cold]
    fn fault_at(&mut self, h: &Hold, code: AlarmCode, why: String) -> Box<Fault> {
        self.plain_path = h.plain_path;
        (self.blk_line, self.blk_line_start, self.blk_number) = h.place;
        fault(code, h.at, why)
    }
}

/// The approach's moves from P0: `paces` are the speed before the block, the slow infeed's
/// and the programmed feed. With compensation the first move is the selection block, to the
/// normal position of the approach contour's start, even where it moves nothing.
fn approach_moves(
    sar: &Block,
    h: &Hold,
    contour: &Contour,
    z: Heights,
    z4: f64,
    [before, slow, programmed]: [Pace; 3],
    trc: bool,
) -> Vec<Block> {
    let plane = sar.modal.plane;
    let far = |z| join(contour.far, z, plane);
    let mut gen = Gen::new(sar, h.p0);
    if let Some(b) = gen.line(far(z.z1), before, trc) {
        if trc {
            b.trc = Some(sar.modal.trc);
            b.approach = Some(SelectionPolicy::NormalPosition);
        }
    }
    gen.line(far(z.z2), before, false);
    gen.line(far(z.z3), slow, false);
    let pace = if h.req.path == SarPath::Spatial {
        slow
    } else {
        programmed
    };
    gen.element(&contour.element, z4, pace);
    gen.finish(sar)
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::frontend::{Block, CornerPolicy, MotionKind, SelectionPolicy, TrcSide};

    const D840: &str = "siemens-840d";

    fn blocks(src: &str) -> Vec<Block> {
        run(D840, src).unwrap_or_else(|a| panic!("{a}"))
    }

    /// (line, kind, end) of every move.
    fn moves(src: &str) -> Vec<(u32, MotionKind, [f64; 3])> {
        blocks(src)
            .iter()
            .filter_map(|b| b.motion.map(|m| (b.line, m.kind, m.end)))
            .collect()
    }

    fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        let a = run(D840, src).expect_err("an alarm");
        (a.code, a.line, a.col)
    }

    /// NORM and KONT are modal (group 17): the selection policy of the blocks after them.
    #[test]
    fn norm_and_kont_choose_the_selection_policy() {
        let b = blocks("G1 F100 X1\nKONT X2\nX3\nNORM X4\n");
        let sel: Vec<SelectionPolicy> = b.iter().map(|b| b.modal.selection).collect();
        use SelectionPolicy::*;
        assert_eq!(
            sel,
            [NormalPosition, Compensated, Compensated, NormalPosition]
        );
        assert_eq!(
            alarm("G1 F100 NORM KONT X1\n"),
            (AlarmCode::SameGroupTwice, 1, 14)
        );
        assert_eq!(
            alarm("N5 KONTC G41 D2 X1\n"),
            (AlarmCode::NotSupported, 1, 4)
        );
        assert_eq!(alarm("KONTT\n").0, AlarmCode::NotSupported);
    }

    /// DISC= under G450: 0 the transition circle, 100 the intersection (the 840D's G451
    /// policy); it waits under G451 and comes back with G450. Between: 12580.
    #[test]
    fn disc_chooses_between_circle_and_intersection() {
        let b = blocks("G450 DISC=100\nDISC=0\nG451\nDISC=100 X1\nG450\n");
        let corners: Vec<CornerPolicy> = b.iter().map(|b| b.modal.corner).collect();
        let inter = CornerPolicy::IntersectionLimited { limit_deg: 100.0 };
        assert_eq!(
            corners,
            [inter, CornerPolicy::TransitionCircle, inter, inter, inter]
        );
        assert_eq!(alarm("G450 DISC=50\n"), (AlarmCode::NotSupported, 1, 6));
        assert_eq!(alarm("DISC=101\n").0, AlarmCode::BadNumber);
        assert_eq!(alarm("DISC=2.5\n").0, AlarmCode::BadNumber);
        // The SAR distances belong to a SAR block.
        assert_eq!(alarm("G1 F100 X1 DISR=5\n"), (AlarmCode::Syntax, 1, 12));
        assert_eq!(alarm("DISR 5\n"), (AlarmCode::Syntax, 1, 1));
    }

    /// NCP19 p.278: the approach block without an axis of the plane takes P4 from the next
    /// block that moves; blocks without motion between stay in order before (or after) the
    /// approach. G147 without compensation: the line is DISR = 4 long, against the direction
    /// of the contour (+X): from (16, 0) to P4 (20, 0). G340 without DISCL: P1 = P3 = (16,
    /// 0, 10) at P0's height, the line descends to −2.
    #[test]
    fn the_approach_waits_for_p4_and_its_contour() {
        let src = "G0 X0 Y0 Z10\nG147 DISR=4 F200\nM8\nG1 X20 Y0 Z-2\nM9\nX30\nM30\n";
        let b = blocks(src);
        let lines: Vec<u32> = b.iter().map(|b| b.line).collect();
        assert_eq!(
            lines,
            [1, 3, 2, 2, 5, 6, 7],
            "M8 first, the approach, M9, the contour"
        );
        let got = moves(src);
        use MotionKind::*;
        assert_eq!(
            got,
            [
                (1, Rapid, [0.0, 0.0, 10.0]),
                (2, Rapid, [16.0, 0.0, 10.0]),
                (2, Linear, [20.0, 0.0, -2.0]),
                (6, Linear, [30.0, 0.0, -2.0]),
            ]
        );
        assert_eq!(b[3].modal.feed, 200.0);
    }

    /// The approach with compensation: the first block selects it straight to the normal
    /// position (G41 and NORM-like whatever KONT says), the infeed follows.
    #[test]
    fn the_first_approach_block_selects_the_compensation() {
        let src = "G0 X-30 Y-30 Z20 T5 D2 KONT\nG41 G147 DISR=3 DISCL=2 X0 Y0 Z-5 F400\nG1 Y40\n";
        let b = blocks(src);
        let m: Vec<&Block> = b.iter().filter(|b| b.line == 2).collect();
        assert_eq!(m.len(), 3);
        assert_eq!(
            (m[0].trc, m[0].approach),
            (Some(TrcSide::Left), Some(SelectionPolicy::NormalPosition))
        );
        assert!(m[1..]
            .iter()
            .all(|b| b.trc.is_none() && b.modal.trc == TrcSide::Left));
        // DISR + R = 8 behind (0, 0) against +Y: (0, −8); DISCL=2 above Z−5: −3.
        let ends: Vec<[f64; 3]> = m.iter().map(|b| b.motion.unwrap().end).collect();
        assert_eq!(
            ends,
            [[0.0, -8.0, 20.0], [0.0, -8.0, -3.0], [0.0, 0.0, -5.0]]
        );
    }

    /// Under a frame that moves the plane rigidly (TRANS, ROT in it) the SAR is built where
    /// the frame puts the contour: TRANS X100 Y50 with AROT RPL=90 takes every end point p to
    /// (100 − p.y, 50 + p.x). A frame that mirrors is refused.
    #[test]
    fn the_approach_follows_a_rigid_frame() {
        let sar = "G0 X-30 Y-30 Z20 T5 D2\nG41 G247 DISR=4 DISCL=2 X0 Y0 Z-5 F400\nG1 Y40\nX40\nG40 G248 DISR=4 X60 Y60 Z20\n";
        let plain: Vec<[f64; 3]> = moves(sar).iter().map(|m| m.2).collect();
        let framed: Vec<[f64; 3]> = moves(&format!("TRANS X100 Y50\nAROT RPL=90\n{sar}"))
            .iter()
            .map(|m| m.2)
            .collect();
        assert_eq!(plain.len(), framed.len());
        for (p, q) in plain.iter().zip(&framed) {
            let want = [100.0 - p[1], 50.0 + p[0], p[2]];
            assert!(
                (0..3).all(|i| (q[i] - want[i]).abs() < 1e-9),
                "{q:?} {want:?}"
            );
        }
        let a = alarm(&format!("MIRROR X0\n{sar}"));
        assert_eq!((a.0, a.1), (AlarmCode::NotSupported, 3));
    }

    /// Alarms at the SAR code: no contour element (program end, more than 5 empty blocks),
    /// a contour element out of the plane, a circle without DISR, a reversal along Z, a
    /// retraction without a contour element before it.
    #[test]
    fn what_the_approach_refuses_and_where() {
        let pre = "G0 X0 Y0 Z10 T5 D2\n";
        let a = |s: &str| alarm(&format!("{pre}{s}"));
        assert_eq!(
            a("G41 G147 DISR=2 X5 Y0 F100\n"),
            (AlarmCode::SarBlocks, 2, 5)
        );
        let empty = "M8\nM9\nM8\nM9\nM8\nM9\n";
        assert_eq!(
            a(&format!("G147 DISR=2 X5 F100\n{empty}G1 X9\n")).0,
            AlarmCode::SarBlocks
        );
        assert_eq!(a("G147 DISR=2 X5 F100\nM30\n").0, AlarmCode::SarBlocks);
        assert_eq!(
            a("G147 DISR=2 X5 F100\nG1 Z-5\n"),
            (AlarmCode::SarDirection, 2, 1)
        );
        assert_eq!(
            a("G41 G247 X5 F100\nG1 Y5\n"),
            (AlarmCode::SarDistance, 2, 5)
        );
        assert_eq!(
            a("G0 Z-4\nG147 DISR=2 DISCL=2 X5 Z-5 F100\nG1 Y9\n"),
            (AlarmCode::SarReversal, 3, 1)
        );
        assert_eq!(
            a("G1 F100 Z0\nG248 DISR=2 X5\n"),
            (AlarmCode::SarDirection, 3, 1)
        );
        assert_eq!(a("G147 DISR=2 X5\nG1 Y9\n").0, AlarmCode::NoFeed);
        assert_eq!(a("G147 G4 F1\n"), (AlarmCode::NotSupported, 2, 1));
        assert_eq!(a("G147 DISCL=-1 X5 F100\n"), (AlarmCode::SarDistance, 2, 6));
    }
}
