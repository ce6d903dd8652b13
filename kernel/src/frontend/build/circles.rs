//! SINUMERIK circles beyond centre and radius (Fundamentals, "Motion commands"): CIP, the
//! circle through an intermediate point; CT, the circle tangent to the previous path
//! element; and TURN=, the full turns a helix makes before its end point. All three are plane
//! geometry in the active plane; a helix's normal axis moves linearly over its whole sweep.
//! docs/sinumerik.md, "Circles: CIP, CT, TURN".

use super::super::block::*;
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{Val, Words};
use super::expand::{Expansion, Helix};
use super::motion::{diameter_factor, feed_programmed};
use crate::alarm::AlarmCode;
use crate::dialect::GEffect;

/// An intermediate point closer than this to the line through start and end point gives no
/// circle (mm).
const COLLINEAR: f64 = 1e-6;

use super::super::plane::{cross, dot, sub, V};

impl Interpreter<'_> {
    /// Step 8, CIP: the circle through the start, the intermediate point (I1= J1= K1=, under
    /// G90/G91 or AC()/IC() like the end point; a coordinate not written is 0, the normal
    /// axis's the start's) and the end point (Fundamentals, "Circular interpolation through
    /// intermediate point (CIP)"). The circle must lie in the active plane.
    pub(super) fn arc_through(
        &mut self,
        w: &Words,
        new: &ModalState,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        no_centre(w, "CIP")?;
        let p = new.plane;
        let (a, o, n) = (p.abscissa as usize, p.ordinate as usize, p.normal as usize);
        // Under a frame the three points are worked out in program coordinates, then mapped.
        let framed = self.coords.frame.active() && !self.machine_coordinates;
        let (start, end) = if framed {
            self.framed_points(w, new, block_col)?
        } else {
            (self.cur, self.end_point(w, new, self.cur)?)
        };
        let at = w.path.inter.iter().flatten().next().map(|v| v.pos());
        let at = at
            .or(w.path.motion.map(|m| m.1 as usize))
            .unwrap_or(block_col);
        if w.path.inter[a].is_none() && w.path.inter[o].is_none() {
            if programmed == 0 {
                return Ok(());
            }
            return Err(fault(
                AlarmCode::MissingValue,
                at,
                "CIP needs its intermediate point (I1= J1= K1=)",
            ));
        }
        let inter = self.intermediate_point(w, new, start, framed);
        if inter[n] != start[n] || end[n] != start[n] {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!(
                    "CIP: the circle must lie in the {} plane (its three points at one {})",
                    p.name(),
                    AXIS_NAMES[n]
                ),
            ));
        }
        feed_programmed(new, block_col)?;
        let plane = |q: &Pos| [q[a], q[o]];
        let (c, ccw) = through(plane(&start), plane(&inter), plane(&end)).ok_or_else(|| {
            fault(
                AlarmCode::ArcEndPoint,
                at,
                "CIP: start, intermediate and end point lie on one line",
            )
        })?;
        let mut centre = start;
        (centre[a], centre[o]) = (c[0], c[1]);
        let place = Place {
            framed,
            start,
            end,
            programmed,
            block_col,
        };
        self.place(new, place, Some(ccw), centre)
    }

    /// CIP's intermediate point: in the basic coordinate system, or in program coordinates
    /// under a frame (`framed`).
    fn intermediate_point(&self, w: &Words, new: &ModalState, start: Pos, framed: bool) -> Pos {
        let offset = if framed {
            [0.0; crate::machine_data::AXES]
        } else {
            self.work_offset(new)
        };
        let normal = new.plane.normal as usize;
        let mut q = start;
        for i in 0..3 {
            let v = w.path.inter[i];
            if v.is_none() && i == normal {
                continue;
            }
            let absolute = w.path.inter_absolute & 1 << i != 0
                || (w.path.inter_incremental & 1 << i == 0 && new.distance == Distance::Absolute);
            let distance = if absolute {
                Distance::Absolute
            } else {
                Distance::Incremental
            };
            let x = v.map_or(0.0, |v| {
                self.length(v, new.units) * diameter_factor(i, new, distance)
            });
            q[i] = if absolute {
                x + offset[i]
            } else {
                start[i] + x
            };
        }
        q
    }

    /// Step 8, CT: the circle from the position tangent to the end of the last path element
    /// (its tangent projected into the plane) to the end point; where the end point lies on
    /// the tangent, a straight line (Fundamentals, "Circular interpolation with tangential
    /// transition (CT)": the limit case). The normal axis may move: a helix.
    pub(super) fn arc_tangent(
        &mut self,
        w: &Words,
        new: &ModalState,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        no_centre(w, "CT")?;
        if programmed == 0 {
            return Ok(());
        }
        let at = w.path.motion.map_or(block_col, |m| m.1 as usize);
        let p = new.plane;
        let (a, o) = (p.abscissa as usize, p.ordinate as usize);
        let t = self.last_move.and_then(|m| end_tangent(&m, p)).ok_or_else(|| {
            fault(
                AlarmCode::MissingValue,
                at,
                format!(
                    "CT: no previous path element with a direction in the {} plane to be tangent to",
                    p.name()
                ),
            )
        })?;
        // Under a frame: the tangent and the points in program coordinates, then mapped.
        let framed = self.coords.frame.active() && !self.machine_coordinates;
        let (start, end) = if framed {
            self.framed_points(w, new, block_col)?
        } else {
            (self.cur, self.end_point(w, new, self.cur)?)
        };
        let t = if framed {
            self.program_direction(t, p, at)?
        } else {
            t
        };
        let d = [end[a] - start[a], end[o] - start[o]];
        if libm::hypot(d[0], d[1]) <= 1e-9 {
            return Err(fault(
                AlarmCode::ArcEndPoint,
                at,
                "CT: the end point lies on the start point in the plane",
            ));
        }
        feed_programmed(new, block_col)?;
        // The centre on the tangent's normal n at s, with |s| the radius: s = |d|² / (2 n·d).
        let nd = cross(t, d);
        let place = Place {
            framed,
            start,
            end,
            programmed,
            block_col,
        };
        if nd.abs() <= 1e-9 {
            return self.place(new, place, None, end);
        }
        let s = dot(d, d) / (2.0 * nd);
        let mut centre = start;
        (centre[a], centre[o]) = (start[a] - s * t[1], start[o] + s * t[0]);
        self.place(new, place, Some(s > 0.0), centre)
    }

    /// A direction `t` of `plane` in machine terms, in program coordinates under the frame
    /// (its linear part undone), of unit length.
    fn program_direction(&self, t: V, plane: Plane, at: usize) -> R<V> {
        let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
        let f = &self.coords.frame;
        let mut q = [0.0; 3];
        (q[a], q[o]) = (t[0], t[1]);
        let back = f.invert(q).zip(f.invert([0.0; 3])).ok_or_else(|| {
            fault(
                AlarmCode::Arithmetic,
                at,
                "the frame scales by 0: no way back",
            )
        })?;
        let v = [back.0[a] - back.1[a], back.0[o] - back.1[o]];
        let len = libm::hypot(v[0], v[1]);
        Ok([v[0] / len, v[1] / len])
    }

    /// The block's move: a line (`ccw` None) or a circle about `centre`, from the place's
    /// points; under a frame mapped, a mirror turning the circle's direction.
    fn place(&mut self, new: &ModalState, p: Place, ccw: Option<bool>, centre: Pos) -> R<()> {
        let kind = |ccw: Option<bool>| match ccw {
            None => MotionKind::Linear,
            Some(true) => MotionKind::ArcCcw,
            Some(false) => MotionKind::ArcCw,
        };
        if !p.framed {
            self.set_motion(new, p.start, p.end, centre, p.programmed, p.block_col)?;
        } else {
            if ccw.is_some() {
                self.frame_keeps_circles(new, p.block_col)?;
            }
            self.set_framed_motion(new, p.end, centre, p.programmed, p.block_col)?;
        }
        let flips = p.framed && self.coords.frame.flips(new.plane);
        if let Some(m) = &mut self.block.motion {
            m.kind = kind(ccw.map(|c| c != flips));
        }
        Ok(())
    }

    /// Step 8, TURN=: the block's circle becomes `n` full turns, then the programmed arc, the
    /// normal axis moving linearly over the whole sweep (Fundamentals, "Helical interpolation
    /// (G2/G3, TURN)": first the full circles, then the end point). The first turn is the
    /// block's move; the rest follow as moves of their own.
    pub(super) fn helix_turns(&mut self, turn: Val, new: &ModalState) -> R<()> {
        let (n, most) = (turn.value, self.d.helix_turns);
        if !(0.0..=most as f64).contains(&n) || n.fract() != 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                turn.at,
                format!("TURN= is a whole number from 0 to {most}, not {n}"),
            ));
        }
        let arc = self.block.motion.filter(|m| m.kind.is_arc());
        let Some(m) = arc.filter(|_| new.motion != MotionMode::ArcThrough) else {
            let circles = self.d.codes_of(&[
                GEffect::Motion(MotionMode::ArcCw),
                GEffect::Motion(MotionMode::ArcCcw),
            ]);
            return Err(fault(
                AlarmCode::Syntax,
                turn.at,
                format!("TURN= needs a circle programmed with {circles} or CT in its block"),
            ));
        };
        if n == 0.0 {
            return Ok(());
        }
        let p = m.plane;
        let (a, o, k) = (p.abscissa as usize, p.ordinate as usize, p.normal as usize);
        let sweep = sweep(&m, a, o);
        let tau = 2.0 * std::f64::consts::PI;
        let rise = (m.end[k] - m.start[k]) * tau / (n * tau + sweep);
        let mut first = m;
        first.end = m.start;
        first.end[k] = m.start[k] + rise;
        self.block.motion = Some(first);
        let helix = Helix::new(
            n as u16 - 1,
            rise,
            m.center,
            m.kind == MotionKind::ArcCcw,
            m.end,
        );
        let mut e = Expansion::helix(helix, k, first.end);
        e.set_stop(self.block.stop.take());
        self.expansion = Some(e);
        Ok(())
    }
}

/// CIP and CT take no centre and no radius.
fn no_centre(w: &Words, word: &str) -> R<()> {
    match w.radius.or(w.centre.iter().flatten().next().copied()) {
        Some(v) => Err(fault(
            AlarmCode::Syntax,
            v.at,
            format!("{word} takes no centre and no radius"),
        )),
        None => Ok(()),
    }
}

/// The centre of the circle through `s`, `i` and `e`, and whether it runs counter-clockwise
/// from `s` over `i` to `e`; `None` where `i` lies on the line through `s` and `e` (or `e`
/// on `s`).
fn through(s: V, i: V, e: V) -> Option<(V, bool)> {
    let (b, c) = (sub(i, s), sub(e, s));
    let chord = libm::hypot(c[0], c[1]);
    let k = cross(b, c);
    if chord <= 1e-9 || k.abs() / chord <= COLLINEAR {
        return None;
    }
    // Circumcentre relative to s.
    let (bb, cc) = (dot(b, b), dot(c, c));
    let d = 2.0 * k;
    let u = [(c[1] * bb - b[1] * cc) / d, (b[0] * cc - c[0] * bb) / d];
    // s, i, e in counter-clockwise order (k > 0): the circle runs counter-clockwise.
    Some(([s[0] + u[0], s[1] + u[1]], k > 0.0))
}

/// The unit tangent at the end of `m`, projected into `plane`; `None` if it has no
/// direction there.
pub(super) fn end_tangent(m: &Motion, plane: Plane) -> Option<V> {
    let mut t = [0.0; 3];
    if m.kind.is_arc() {
        let mp = m.plane;
        let (a, o) = (mp.abscissa as usize, mp.ordinate as usize);
        let r = [m.end[a] - m.center[a], m.end[o] - m.center[o]];
        let (ta, to) = if m.kind == MotionKind::ArcCcw {
            (-r[1], r[0])
        } else {
            (r[1], -r[0])
        };
        (t[a], t[o]) = (ta, to);
    } else {
        t = std::array::from_fn(|i| m.end[i] - m.start[i]);
    }
    let v = [t[plane.abscissa as usize], t[plane.ordinate as usize]];
    let len = libm::hypot(v[0], v[1]);
    (len > 1e-12).then(|| [v[0] / len, v[1] / len])
}

/// Where a circle of CIP or CT goes: its points (program coordinates under a frame) and the
/// block's programmed axes.
#[derive(Clone, Copy)]
struct Place {
    framed: bool,
    start: Pos,
    end: Pos,
    programmed: u16,
    block_col: usize,
}

/// The sweep of an arc (radians, 0 … 2π; 2π for a full circle).
fn sweep(m: &Motion, a: usize, o: usize) -> f64 {
    let tau = 2.0 * std::f64::consts::PI;
    if m.start[a] == m.end[a] && m.start[o] == m.end[o] {
        return tau;
    }
    let angle = |q: &Pos| libm::atan2(q[o] - m.center[o], q[a] - m.center[a]);
    let mut d = angle(&m.end) - angle(&m.start);
    if m.kind == MotionKind::ArcCw {
        d = -d;
    }
    d.rem_euclid(tau)
}

#[cfg(test)]
mod tests {
    use super::super::super::near;
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::frontend::MotionKind;

    fn moves(src: &str) -> Vec<(MotionKind, [f64; 3], [f64; 3])> {
        super::super::super::moves("siemens-840d", src)
    }

    fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        super::super::super::alarm_at("siemens-840d", src)
    }

    #[test]
    fn cip_and_ct_under_a_frame_are_worked_out_in_program_coordinates() {
        // (0,0) over (10,10) to (20,0): centre (10,0), clockwise; MIRROR X0 maps it to end
        // (−20, 0) about (−10, 0), counter-clockwise.
        let got = moves("MIRROR X0\nG1 F100 X0 Y0\nCIP X20 Y0 I1=10 J1=10\n");
        let (kind, end, centre) = got[1];
        assert_eq!(kind, MotionKind::ArcCcw);
        assert!(
            near(end, [-20.0, 0.0, 0.0]) && near(centre, [-10.0, 0.0, 0.0]),
            "{got:?}"
        );
        // CT under ROT RPL=90: the last move (0,0)→(10,0) in program terms; CT X20 Y10
        // from (10,0) tangent to (1,0): centre (10,10), counter-clockwise; mapped: end
        // (−10, 20), centre (−10, 10).
        let got = moves("ROT RPL=90\nG1 F100 X10\nCT X20 Y10\n");
        let (kind, end, centre) = got[1];
        assert_eq!(kind, MotionKind::ArcCcw);
        assert!(
            near(end, [-10.0, 20.0, 0.0]) && near(centre, [-10.0, 10.0, 0.0]),
            "{got:?}"
        );
    }

    #[test]
    fn cip_finds_the_circle_and_its_direction_from_three_points() {
        use MotionKind::*;
        // (0,0) over (10,10) to (20,0): centre (10,0), clockwise. Back under G91 over
        // (10,−10) to (0,0): centre (10,0), clockwise again. I1=AC(10) J1=IC(10) under G91
        // from (0,0): (10,10), to X=AC(20): the first circle once more.
        let got = moves(
            "G1 F100\nCIP X20 Y0 I1=10 J1=10\nG91 CIP X-20 Y0 I1=-10 J1=-10\nCIP X=AC(20) Y0 I1=AC(10) J1=IC(10)\n",
        );
        let want = [
            (ArcCw, [20.0, 0.0, 0.0]),
            (ArcCw, [0.0; 3]),
            (ArcCw, [20.0, 0.0, 0.0]),
        ];
        for (g, w) in got.iter().zip(want) {
            assert!(
                g.0 == w.0 && near(g.1, w.1) && near(g.2, [10.0, 0.0, 0.0]),
                "{got:?}"
            );
        }
        // Counter-clockwise: (0,0) under (10,−10) to (20,0); CIP is modal.
        let got = moves("G1 F100\nCIP X20 Y0 I1=10 J1=-10\nX0 Y0 I1=10 J1=10\n");
        assert_eq!((got[0].0, got[1].0), (ArcCcw, ArcCcw));
    }

    #[test]
    fn cip_refuses_a_line_and_a_circle_off_the_plane() {
        assert_eq!(
            alarm("G1 F100\nCIP X20 Y0 I1=5 J1=0\n"),
            (AlarmCode::ArcEndPoint, 2, 12)
        );
        assert_eq!(
            alarm("G1 F100\nCIP X20 Y0 I1=10 J1=10 K1=3\n"),
            (AlarmCode::NotSupported, 2, 12)
        );
        assert_eq!(
            alarm("G1 F100\nCIP X20 Y0\n"),
            (AlarmCode::MissingValue, 2, 1)
        );
        assert_eq!(
            alarm("G1 F100\nCIP X20 Y0 I1=10 J1=10 CR=5\n").0,
            AlarmCode::Syntax
        );
        assert_eq!(alarm("G1 CIP X1\n"), (AlarmCode::SameGroupTwice, 1, 4));
    }

    #[test]
    fn ct_continues_the_last_element_tangentially() {
        use MotionKind::*;
        // Along +X to (10,0), then CT to (20,10): the centre on the normal at (10,0),
        // s = |d|²/(2 n·d) = 200/20 = 10: (10,10), counter-clockwise. An M word between does
        // not count. The next CT leaves (20,10) heading +Y: to (20,30) lies on the tangent,
        // a straight line.
        let got = moves("G1 X10 Y0 F100\nM8\nCT X20 Y10\nCT X20 Y30\n");
        assert!(
            got[1].0 == ArcCcw && near(got[1].2, [10.0, 10.0, 0.0]),
            "{got:?}"
        );
        assert!(
            got[2].0 == Linear && near(got[2].1, [20.0, 30.0, 0.0]),
            "{got:?}"
        );
        // After a clockwise quarter from (0,10) about (0,0) to (10,0) the path heads −Y:
        // t = (0,−1), its left normal n = (1,0); to (0,−10) d = (−10,−10), n·d = −10,
        // s = 200 / −20 = −10: centre (10,0) − 10·(1,0) = (0,0), on the right: clockwise.
        let got = moves("G1 X0 Y10 F100\nG2 X10 Y0 I0 J-10\nCT X0 Y-10\n");
        assert!(got[2].0 == ArcCw && near(got[2].2, [0.0; 3]), "{got:?}");
        // A rounding between doesn't change the element CT continues: N2's +Y.
        let got = moves("G1 X10 Y0 F100 RND=2\nY10\nCT X0 Y20\n");
        let ct = got.last().unwrap();
        assert!(ct.0 == ArcCcw && near(ct.2, [0.0, 10.0, 0.0]), "{got:?}");
    }

    #[test]
    fn ct_needs_a_direction_to_continue() {
        assert_eq!(
            alarm("G1 F100\nCT X10 Y10\n"),
            (AlarmCode::MissingValue, 2, 1)
        );
        assert_eq!(
            alarm("G1 Z-5 F100\nCT X10 Y10\n"),
            (AlarmCode::MissingValue, 2, 1)
        );
        assert_eq!(
            alarm("G1 X10 F100\nCT X10 Y0 Z-1\n"),
            (AlarmCode::ArcEndPoint, 2, 1)
        );
    }

    #[test]
    fn turn_adds_full_circles_before_the_end_point() {
        use MotionKind::*;
        // (10,0,0) G3 to (−10,0,−9) about (0,0) with TURN=1: a half circle (π) after one
        // full turn (2π); Z falls 9 over 3π: −6 a turn. The full turn ends at (10,0,−6),
        // the half circle at (−10,0,−9), both about (0,0) at their start's Z.
        let b = run(
            "siemens-840d",
            "G0 X10 Y0 Z0\nG3 X-10 Y0 Z-9 I-10 J0 TURN=1 F100 M30\n",
        )
        .unwrap();
        let got: Vec<_> = b.iter().filter_map(|b| b.motion).collect();
        assert_eq!(got.len(), 3);
        assert!(got[1].kind == ArcCcw && near(got[1].end, [10.0, 0.0, -6.0]));
        assert!(near(got[1].center, [0.0; 3]));
        assert!(got[2].kind == ArcCcw && near(got[2].end, [-10.0, 0.0, -9.0]));
        assert!(near(got[2].center, [0.0, 0.0, -6.0]));
        // M30 acts after the last piece.
        assert_eq!(
            (b[1].stop, b[2].stop.map(|s| s.code())),
            (None, Some("M30"))
        );
        assert_eq!(moves("G3 X-10 Y0 I-5 TURN=0 F1\n").len(), 1);
        // CT continues the helix's last piece, also while RNDM holds blocks back: at
        // (−10,0) counter-clockwise about (0,0) it heads −Y; to (−20,−10): n = (1,0),
        // n·d = −10, s = −10: centre (−20,0), clockwise.
        for rndm in ["", "RNDM=1 "] {
            let got = moves(&format!(
                "G0 X10 Y0\n{rndm}G3 X-10 Y0 I-10 TURN=1 F100\nCT X-20 Y-10\n"
            ));
            let ct = got.last().unwrap();
            assert!(
                ct.0 == ArcCw && near(ct.2, [-20.0, 0.0, 0.0]),
                "{rndm}{got:?}"
            );
        }
        assert_eq!(
            alarm("G3 X-10 Y0 I-5 TURN=1.5 F1\n"),
            (AlarmCode::BadNumber, 1, 16)
        );
        assert_eq!(alarm("G1 X-10 Y0 TURN=1 F1\n"), (AlarmCode::Syntax, 1, 12));
    }
}
