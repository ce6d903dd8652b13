//! Bottleneck detection over a window of blocks (beyond 840C 11.12; 840D CDON, TNC M120) and
//! ISG contour masking (G141, 002).
//!
//! The local check (`trc/violation.rs`) sees three elements. A notch narrower than the tool
//! whose sides are further apart in the program, or a contour that comes back close to
//! itself, needs more: every compensated segment is held back until `window` more contour
//! blocks have come, and the definition of a gouge is checked directly — the tool circle
//! along a path segment must stay at least R from every programmed element in the window
//! (the element it belongs to included: there the distance is R exactly). A gouge is alarm
//! 3021 before the tool gets there. With ISG contour masking on, where the path crosses
//! itself the loop is cut out instead: the earlier segment ends at the crossing, the blocks
//! in between are left out (their auxiliary functions are output there, in program order, by
//! the S-point stage) and the new segment starts at the crossing. A gouge without such a
//! crossing (no gouge-free path inside the window) stays an alarm.

use crate::frontend::block::{Plane, Pos};
use crate::segment::{Role, Segment, Shape};
use crate::trc::geom::{clear_by_ends, contains, dist_elems, intersections, v2, Elem, V2};

/// Largest window, in blocks.
pub const MAX_WINDOW: usize = 64;
/// Segments held: a block puts out at most its contour segment and three inserted pieces.
/// The queue the window releases into must take this many at once (a flush).
pub const HELD: usize = 4 * MAX_WINDOW + 8;

/// A gouge found: the path segment and the block of the programmed element it comes too
/// close to.
#[derive(Clone, Copy, Debug)]
pub struct Gouge {
    pub path: crate::segment::Source,
    pub element: crate::segment::Source,
    pub distance: f64,
    pub radius: f64,
}

/// What to do with a gouge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reaction {
    Alarm,
    /// Report it, keep the path (machine data `trc.violation_reaction = warn`).
    Warn,
    /// ISG G141: cut out the loop where the path crosses itself.
    Mask,
}

#[derive(Clone, Copy, Debug)]
struct Held {
    seg: Segment,
    elem: Option<Elem>,
    /// Tool radius and side the segment was made with.
    r: f64,
    side: i8,
    /// Bounding box in the plane, grown by the radius: min u, min v, max u, max v.
    bb: [f64; 4],
}

#[derive(Clone, Copy, Debug)]
struct Programmed {
    source: crate::segment::Source,
    elem: Elem,
    bb: [f64; 4],
    /// Tool radius the element is cut with.
    r: f64,
    /// Compensation side (+1 left, −1 right). Across a side change (Fanuc in offset mode)
    /// the tool crosses the contour on purpose: paths and elements of different sides are
    /// not compared.
    side: i8,
}

/// Programmed elements kept: a path segment meets elements up to `window` blocks before
/// and after its own.
const PROGRAMMED: usize = 2 * MAX_WINDOW + 4;

/// Distances below R by more than this are gouges (constructions are exact to ~1e-12 at
/// part sizes; far from the origin the rounding of the coordinates themselves counts).
fn gouge_tol(e: &Elem) -> f64 {
    let m = e
        .start()
        .x
        .abs()
        .max(e.start().y.abs())
        .max(e.end().x.abs())
        .max(e.end().y.abs());
    1e-9_f64.max(1e-12 * m)
}

pub struct Bottleneck {
    window: usize,
    plane: Plane,
    held: heapless::Deque<Held, HELD>,
    programmed: heapless::Deque<Programmed, PROGRAMMED>,
    /// Distinct blocks among the held segments, and the last one's number.
    blocks: usize,
    last_seq: Option<u32>,
}

impl Bottleneck {
    /// `window`: blocks a segment is checked against (0: off).
    pub fn new(window: usize) -> Self {
        Bottleneck {
            window: window.min(MAX_WINDOW),
            plane: Plane::XY,
            held: heapless::Deque::new(),
            programmed: heapless::Deque::new(),
            blocks: 0,
            last_seq: None,
        }
    }

    /// The window in blocks for this reaction (masking checks over at least 3).
    fn depth(&self, reaction: Reaction) -> usize {
        if reaction == Reaction::Mask {
            self.window.max(3)
        } else {
            self.window
        }
    }

    /// A programmed contour element (block `source`): the held path must keep its distance.
    pub fn element(
        &mut self,
        source: crate::segment::Source,
        elem: Elem,
        r: f64,
        side: i8,
        reaction: Reaction,
    ) -> Result<Option<Gouge>, Gouge> {
        if self.depth(reaction) == 0 {
            return Ok(None);
        }
        let bb = bbox(&elem, 0.0);
        let mut found = None;
        let (x, y) = self.held.as_slices();
        // Masking checks a segment when it leaves the window: a loop cut out later may drop
        // what comes too close now.
        let checked = if reaction == Reaction::Mask {
            0
        } else {
            x.len() + y.len()
        };
        for h in x.iter().chain(y).take(checked) {
            let Some(he) = h.elem else {
                continue;
            };
            if h.side != side || near(h.seg.source.seq, source.seq) || !overlap(&h.bb, &bb) {
                continue;
            }
            if let Some(d) = too_close(&he, &elem, h.r) {
                found = Some(Gouge {
                    path: h.seg.source,
                    element: source,
                    distance: d,
                    radius: h.r,
                });
                break;
            }
        }
        // A path segment meets elements up to `depth` blocks before and after its own.
        while self.programmed.len() >= (2 * self.depth(reaction) + 2).min(PROGRAMMED) {
            self.programmed.pop_front();
        }
        let _ = self.programmed.push_back(Programmed {
            source,
            elem,
            bb,
            r,
            side,
        });
        match (found, reaction) {
            (Some(g), Reaction::Warn) => Ok(Some(g)),
            (Some(g), _) => Err(g),
            (None, _) => Ok(None),
        }
    }

    #[inline]
    pub fn set_plane(&mut self, plane: Plane) {
        self.plane = plane;
    }

    /// Off and nothing held: a segment may pass straight on.
    #[inline]
    pub fn bypass(&self, reaction: Reaction) -> bool {
        self.depth(reaction) == 0 && self.held.is_empty()
    }

    /// Takes the next segment of the path; what may go on goes to `out`. Its tool radius and
    /// side are its block's element's (a segment comes out after its element went in), else
    /// the last element's.
    pub fn push<const N: usize>(
        &mut self,
        seg: Segment,
        reaction: Reaction,
        out: &mut heapless::Deque<Segment, N>,
    ) -> Result<Option<Gouge>, Gouge> {
        let checked = matches!(seg.role, Role::Contour | Role::Corner | Role::Intermediate);
        let depth = self.depth(reaction);
        if !checked || depth == 0 {
            // Compensation starts or ends here (or nothing is checked): the window starts anew.
            self.flush(out, reaction == Reaction::Mask)?;
            if !checked {
                // Elements before this segment's block belong to an earlier compensation; the
                // first element of this one (added before its approach came out) stays.
                while self
                    .programmed
                    .front()
                    .is_some_and(|p| (p.source.seq.wrapping_sub(seg.source.seq) as i32) < 0)
                {
                    self.programmed.pop_front();
                }
            }
            let _ = out.push_back(seg);
            return Ok(None);
        }
        let mut seg = seg;
        let mut warned = None;
        let (r, side) = self
            .programmed
            .iter()
            .rev()
            .find(|p| p.source.seq == seg.source.seq)
            .or(self.programmed.back())
            .map_or((0.0, 0), |p| (p.r, p.side));
        let mut elem = self.elem(&seg);
        if let (Some(e), Reaction::Mask) = (elem, reaction) {
            if let Some(x) = self.crossing_with_held(&e) {
                self.cut_loop(x.0, x.1, &mut seg);
                elem = self.elem(&seg);
            }
        }
        let bb = elem.map_or([0.0; 4], |e| bbox(&e, r));
        if let (Some(e), false) = (elem, reaction == Reaction::Mask) {
            let (a, b) = self.programmed.as_slices();
            for p in a.iter().chain(b) {
                if p.side != side || near(p.source.seq, seg.source.seq) || !overlap(&p.bb, &bb) {
                    continue;
                }
                if let Some(d) = too_close(&e, &p.elem, r) {
                    let g = Gouge {
                        path: seg.source,
                        element: p.source,
                        distance: d,
                        radius: r,
                    };
                    if reaction != Reaction::Warn {
                        return Err(g);
                    }
                    warned = Some(g);
                    break;
                }
            }
        }
        // A new block in the window; the oldest leaves once there are more than `depth`.
        if self.last_seq != Some(seg.source.seq) {
            self.blocks += 1;
            self.last_seq = Some(seg.source.seq);
        }
        let mask = reaction == Reaction::Mask;
        if self.held.is_full() {
            self.release_block(out, mask)?;
        }
        let _ = self.held.push_back(Held {
            seg,
            elem,
            r,
            side,
            bb,
        });
        while self.blocks > depth {
            self.release_block(out, mask)?;
        }
        Ok(warned)
    }

    /// Where a new path element crosses a held segment other than the last one (which
    /// shares its start): the held index and the point.
    fn crossing_with_held(&self, e: &Elem) -> Option<(usize, V2)> {
        let bb = bbox(e, 0.0);
        let n = self.held.len();
        for (i, h) in self.held.iter().enumerate().take(n.saturating_sub(1)) {
            let Some(he) = h.elem else {
                continue;
            };
            if !overlap(&bbox(&he, 0.0), &bb) {
                continue;
            }
            if let Some(x) = intersections(&he, e).into_iter().find(|&x| {
                contains(&he, x)
                    && contains(e, x)
                    && x.dist(e.start()) > 1e-7
                    && x.dist(he.end()) > 1e-7
            }) {
                return Some((i, x));
            }
        }
        None
    }

    /// Masking: the held segment `i` ends at `x`, the ones after it are left out, and `seg`
    /// starts at `x`.
    fn cut_loop(&mut self, i: usize, x: V2, seg: &mut Segment) {
        while self.held.len() > i + 1 {
            self.held.pop_back();
        }
        let plane = self.plane;
        if let Some(h) = self.held.back_mut() {
            h.seg.to = at(plane, &h.seg.to, x);
            h.elem = elem_in(&h.seg, plane);
            h.bb = h.elem.map_or([0.0; 4], |e| bbox(&e, h.r));
        }
        seg.from = at(plane, &seg.from, x);
        self.recount();
    }

    /// Preparation stops: what is held is dropped. It has not been checked against the
    /// contour that follows (which stays on the workpiece even though it is not cut), so it
    /// is not known to be clear.
    pub fn discard(&mut self) {
        self.held.clear();
        self.programmed.clear();
        self.blocks = 0;
        self.last_seq = None;
    }

    /// Everything held goes on (end of compensation or of the program); under masking each
    /// segment is checked on its way out.
    pub fn flush<const N: usize>(
        &mut self,
        out: &mut heapless::Deque<Segment, N>,
        mask: bool,
    ) -> Result<(), Gouge> {
        while !self.held.is_empty() {
            self.release_block(out, mask)?;
        }
        self.blocks = 0;
        self.last_seq = None;
        Ok(())
    }

    /// The oldest block's segments go on; under masking, after the distance check.
    fn release_block<const N: usize>(
        &mut self,
        out: &mut heapless::Deque<Segment, N>,
        mask: bool,
    ) -> Result<(), Gouge> {
        let Some(seq) = self.held.front().map(|h| h.seg.source.seq) else {
            return Ok(());
        };
        while self.held.front().is_some_and(|h| h.seg.source.seq == seq) {
            if let Some(h) = self.held.pop_front() {
                if mask {
                    self.check(&h)?;
                }
                let _ = out.push_back(h.seg);
            }
        }
        self.blocks = self.blocks.saturating_sub(1);
        Ok(())
    }

    /// A held segment against the programmed elements in the window.
    fn check(&self, h: &Held) -> Result<(), Gouge> {
        let Some(e) = h.elem else {
            return Ok(());
        };
        let (a, b) = self.programmed.as_slices();
        for p in a.iter().chain(b) {
            if p.side != h.side || near(p.source.seq, h.seg.source.seq) || !overlap(&p.bb, &h.bb) {
                continue;
            }
            if let Some(d) = too_close(&e, &p.elem, h.r) {
                return Err(Gouge {
                    path: h.seg.source,
                    element: p.source,
                    distance: d,
                    radius: h.r,
                });
            }
        }
        Ok(())
    }

    fn recount(&mut self) {
        let mut blocks = 0;
        let mut last = None;
        for h in self.held.iter() {
            if last != Some(h.seg.source.seq) {
                blocks += 1;
                last = Some(h.seg.source.seq);
            }
        }
        self.blocks = blocks;
        self.last_seq = last;
    }

    fn elem(&self, s: &Segment) -> Option<Elem> {
        elem_in(s, self.plane)
    }

    /// True when nothing is held.
    pub fn is_empty(&self) -> bool {
        self.held.is_empty()
    }
}

/// The distance from a path element to a programmed one when it is below the tool radius
/// (beyond rounding). The cheap test by the element's ends settles most pairs that share a
/// corner; the rest get the exact distance.
fn too_close(path: &Elem, elem: &Elem, r: f64) -> Option<f64> {
    let limit = r - gouge_tol(path);
    if clear_by_ends(path, elem, limit) {
        return None;
    }
    let d = dist_elems(path, elem);
    (d < limit).then_some(d)
}

/// A path segment and its own element: R apart by construction (an equidistant). Neighbours
/// are checked: an arc that curls back over the element before it is not caught by the
/// corner construction.
fn near(a: u32, b: u32) -> bool {
    a == b
}

/// `p` with its plane coordinates replaced by `x`.
fn at(plane: Plane, p: &Pos, x: V2) -> Pos {
    let mut q = *p;
    q[plane.abscissa as usize] = x.x;
    q[plane.ordinate as usize] = x.y;
    q
}

/// A segment as a plane element; `None` for what cannot cross (no move in the plane) or is
/// not a circle (an arc whose radius changes on purpose — a radius change spread over the
/// block — is left out of the check; radii equal but for rounding are one circle).
fn elem_in(s: &Segment, plane: Plane) -> Option<Elem> {
    let uv = |p: &Pos| v2(p[plane.abscissa as usize], p[plane.ordinate as usize]);
    let (a, b) = (uv(&s.from), uv(&s.to));
    match s.shape {
        Shape::Line => (a.dist(b) > 1e-9).then_some(Elem::Line { a, b }),
        Shape::Arc {
            center,
            center_end,
            ccw,
            r0,
            r1,
            plane: p,
        } => (p == plane
            && center == center_end
            && (r0 - r1).abs() <= 1e-9 * center[0].abs().max(center[1].abs()).max(r0).max(1.0))
        .then(|| Elem::Arc {
            a,
            b,
            c: uv(&center),
            ccw,
        }),
    }
}

/// Bounding box of an element in the plane, grown by `grow`: the whole circle for an arc
/// (cheap, and enough for a pre-filter).
fn bbox(e: &Elem, grow: f64) -> [f64; 4] {
    let b = match *e {
        Elem::Line { a, b } => [a.x.min(b.x), a.y.min(b.y), a.x.max(b.x), a.y.max(b.y)],
        Elem::Arc { a, c, .. } => {
            let r = a.dist(c);
            [c.x - r, c.y - r, c.x + r, c.y + r]
        }
    };
    [b[0] - grow, b[1] - grow, b[2] + grow, b[3] + grow]
}

fn overlap(p: &[f64; 4], q: &[f64; 4]) -> bool {
    const TOL: f64 = 1e-7;
    p[0] <= q[2] + TOL && q[0] <= p[2] + TOL && p[1] <= q[3] + TOL && q[1] <= p[3] + TOL
}
