//! Segments: what block preparation hands to interpolation. One segment is one straight or
//! circular piece of the tool path, tagged with the block it belongs to and why it exists.

use crate::frontend::block::{BlockNo, Motion, MotionKind, Plane, Pos};

/// Where a segment comes from in the program.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Source {
    pub number: Option<BlockNo>,
    /// 1-based line and column of the block's first character.
    pub line: u32,
    pub col: u32,
    /// The block's place in execution order (1, 2, …; a loop's blocks get a new one on every
    /// pass; wraps after 2³² blocks, so compare with `wrapping_sub`).
    pub seq: u32,
    /// The file the block is in: 0 the main program's, k a subprogram file of the machine
    /// data's program library (`ProgramLibrary::name`).
    pub program: u16,
}

impl Source {
    /// The name of the file this position is in: `main`, or a subprogram file's.
    pub fn program_name<'n>(&self, main: &'n str, library: &'n crate::ProgramLibrary) -> &'n str {
        library.name(self.program).unwrap_or(main)
    }
}

/// Why a segment is in the path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// The selection block's move onto the contour.
    Approach,
    /// A programmed element (compensated when TRC is active).
    Contour,
    /// A transition circle at an outer corner (840C 11.1 G450, ISG G26).
    Corner,
    /// A linear block inserted at an outer corner (840C G451, ISG G25, Fanuc C).
    Intermediate,
    /// The deselection block's move off the contour.
    Retract,
    /// A move with TRC off.
    Uncompensated,
}

impl Role {
    const ALL: [Role; 6] = [
        Role::Approach,
        Role::Contour,
        Role::Corner,
        Role::Intermediate,
        Role::Retract,
        Role::Uncompensated,
    ];

    /// A number for the wire (1…6; 0 stands for none).
    pub fn code(self) -> u8 {
        Self::ALL
            .iter()
            .position(|r| *r == self)
            .map_or(0, |i| i as u8 + 1)
    }

    pub fn from_code(c: u8) -> Option<Role> {
        Self::ALL.get(usize::from(c).checked_sub(1)?).copied()
    }

    pub fn name(self) -> &'static str {
        match self {
            Role::Approach => "approach",
            Role::Contour => "contour",
            Role::Corner => "corner",
            Role::Intermediate => "intermediate",
            Role::Retract => "retract",
            Role::Uncompensated => "uncompensated",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Line,
    /// An arc about `center` in `plane`; the radius goes linearly from `r0` at the start to
    /// `r1` at the end over the sweep (they differ only while a radius change is spread over
    /// the block). `from == to` in the plane with `r0 == r1` is a full circle. The centre
    /// moves linearly with the sweep from `center` to `center_end` where a turning tool's
    /// cutting edge changes over the block (prep/tool_tip.rs); otherwise they are equal.
    Arc {
        center: Pos,
        center_end: Pos,
        ccw: bool,
        r0: f64,
        r1: f64,
        plane: Plane,
    },
}

/// One piece of the tool-centre path, in mm, [X, Y, Z] workpiece coordinates with the tool
/// length along the tool axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub source: Source,
    pub role: Role,
    pub shape: Shape,
    pub from: Pos,
    pub to: Pos,
    /// Path feed, mm/min (over every moving axis, docs/ipo.md); mm per spindle revolution
    /// when `per_rev`.
    pub feed: f64,
    /// Feed per revolution (G95): the path speed follows the spindle's actual speed.
    pub per_rev: bool,
    /// A thread cut (Fanuc G32 and the threading cycles): per revolution, at 100 % feed
    /// override, and a feed hold waits for its end (docs/turning.md, "Threading").
    pub thread: bool,
    pub rapid: bool,
    /// Exact stop at the end (G09 of the block, or the modal G60/G61; inserted blocks take
    /// the next block's, 840C 11.10).
    pub exact_stop: bool,
}

impl Shape {
    /// A programmed motion's shape: a line, or an arc about its centre whose radius is the
    /// start point's distance from it.
    pub fn of_motion(m: &Motion) -> Shape {
        if !m.kind.is_arc() {
            return Shape::Line;
        }
        let (a, o) = (m.plane.abscissa as usize, m.plane.ordinate as usize);
        let (da, d_o) = (m.start[a] - m.center[a], m.start[o] - m.center[o]);
        let r = (da * da + d_o * d_o).sqrt();
        Shape::Arc {
            center: m.center,
            center_end: m.center,
            ccw: m.kind == MotionKind::ArcCcw,
            r0: r,
            r1: r,
            plane: m.plane,
        }
    }
}

impl Segment {
    pub fn is_arc(&self) -> bool {
        matches!(self.shape, Shape::Arc { .. })
    }
}

/// A segment as a curve of one parameter u from 0 (its start) to 1 (its end): a line, or
/// angle θ0 + u·sweep, radius r0 + u·(r1 − r0), centre c0 + u·(c1 − c0) and coordinate along
/// the plane's normal h0 + u·(h1 − h0) — arcs, helices, the TRC core's radius changes and a
/// turning tool's moving centre alike. The radii are the end points' own distances from
/// their centres, so the curve runs exactly from `from` to `to`. The interpolator samples it
/// (ipo/path.rs); a resumed block starts on it (prep/resume.rs).
#[derive(Clone, Copy, Debug)]
pub enum Curve {
    Line {
        from: Pos,
        d: Pos,
    },
    Arc {
        plane: Plane,
        c0: [f64; 2],
        dc: [f64; 2],
        r0: f64,
        dr: f64,
        th0: f64,
        /// Signed: positive counter-clockwise.
        sweep: f64,
        h0: f64,
        dh: f64,
    },
}

impl Curve {
    /// `None` for an arc with an end on its centre.
    pub fn new(seg: &Segment) -> Option<Curve> {
        let Shape::Arc {
            center,
            center_end,
            ccw,
            plane,
            ..
        } = seg.shape
        else {
            let d = [
                seg.to[0] - seg.from[0],
                seg.to[1] - seg.from[1],
                seg.to[2] - seg.from[2],
            ];
            return Some(Curve::Line { from: seg.from, d });
        };
        let (ia, io, ino) = (
            plane.abscissa as usize,
            plane.ordinate as usize,
            plane.normal as usize,
        );
        let c0 = [center[ia], center[io]];
        let c1 = [center_end[ia], center_end[io]];
        let (fa, fo) = (seg.from[ia] - c0[0], seg.from[io] - c0[1]);
        let (ta, to) = (seg.to[ia] - c1[0], seg.to[io] - c1[1]);
        let r0 = (fa * fa + fo * fo).sqrt();
        let r1 = (ta * ta + to * to).sqrt();
        if r0.is_nan() || r1.is_nan() || r0 <= 0.0 || r1 <= 0.0 {
            return None;
        }
        let th0 = libm::atan2(fo, fa);
        let th1 = libm::atan2(to, ta);
        let full = seg.from[ia] == seg.to[ia] && seg.from[io] == seg.to[io];
        let tau = std::f64::consts::TAU;
        let mut sweep = if ccw { th1 - th0 } else { th0 - th1 };
        if full {
            sweep = tau;
        } else if sweep < 0.0 {
            sweep += tau;
            // An arc whose ends differ only by rounding is not a full circle.
            if sweep >= tau {
                sweep = 0.0;
            }
        }
        Some(Curve::Arc {
            plane,
            c0,
            dc: [c1[0] - c0[0], c1[1] - c0[1]],
            r0,
            dr: r1 - r0,
            th0,
            sweep: if ccw { sweep } else { -sweep },
            h0: seg.from[ino],
            dh: seg.to[ino] - seg.from[ino],
        })
    }

    /// The point at parameter u.
    pub fn point(&self, u: f64) -> Pos {
        match *self {
            Curve::Line { from, d } => [from[0] + d[0] * u, from[1] + d[1] * u, from[2] + d[2] * u],
            Curve::Arc {
                plane,
                c0,
                dc,
                r0,
                dr,
                th0,
                sweep,
                h0,
                dh,
            } => {
                let th = th0 + sweep * u;
                let r = r0 + dr * u;
                let mut p = [0.0; 3];
                p[plane.abscissa as usize] = c0[0] + dc[0] * u + r * libm::cos(th);
                p[plane.ordinate as usize] = c0[1] + dc[1] * u + r * libm::sin(th);
                p[plane.normal as usize] = h0 + dh * u;
                p
            }
        }
    }

    /// dP/du and d²P/du² at u.
    pub fn derivatives(&self, u: f64) -> (Pos, Pos) {
        let (plane, dc, r0, dr, th0, sweep, dh) = match *self {
            Curve::Line { d, .. } => return (d, [0.0; 3]),
            Curve::Arc {
                plane,
                dc,
                r0,
                dr,
                th0,
                sweep,
                dh,
                ..
            } => (plane, dc, r0, dr, th0, sweep, dh),
        };
        let th = th0 + sweep * u;
        let (sn, cs) = (libm::sin(th), libm::cos(th));
        let r = r0 + dr * u;
        let mut d1 = [0.0; 3];
        let mut d2 = [0.0; 3];
        let (ia, io, ino) = (
            plane.abscissa as usize,
            plane.ordinate as usize,
            plane.normal as usize,
        );
        // P = c + r·e(θ); e' = sweep·e⊥, e⊥' = −sweep·e.
        d1[ia] = dc[0] + dr * cs - r * sweep * sn;
        d1[io] = dc[1] + dr * sn + r * sweep * cs;
        d1[ino] = dh;
        d2[ia] = -2.0 * dr * sweep * sn - r * sweep * sweep * cs;
        d2[io] = 2.0 * dr * sweep * cs - r * sweep * sweep * sn;
        (d1, d2)
    }
}
/// A segment is copied from the compensation to the path and kept by the whole-program
/// check's runs: it must not grow unnoticed (docs/benchmarks.md measures the copies).
#[cfg(test)]
#[test]
fn a_segment_stays_small() {
    assert!(std::mem::size_of::<Source>() <= 24);
    assert!(std::mem::size_of::<Segment>() <= 160);
}
