//! Behaviour at corners (840C 11.1, 11.4, 11.14; 808D G450/G451; ISG G25/G26; Fanuc C).
//!
//! Every construction starts from the same points (docs/trc.md has the picture):
//! `C` the programmed corner, `P1` the normal position at the end of the first element,
//! `P2` the normal position at the start of the second, `t1`/`t2` the directions of travel
//! there, and `T` the intersection of the tangents through P1 along t1 and through P2 along t2.
//! Inner corners always get the intersection of the equidistants (11.1); outer corners get
//! what the active [`OuterCorner`] construction says.

use super::geom::{self, turn, Elem, ANGLE_EPS, EPS, V2};
use std::f64::consts::{FRAC_PI_2, PI};

/// How an outer corner is closed. The compensation core knows these, not G codes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OuterCorner {
    /// An arc of radius |R| about the corner from P1 to P2 (840C/808D G450, ISG G26).
    Circle,
    /// 840C G451: line/line corners up to a 90° change of direction meet at the
    /// intersection; other corners get the two blocks P1→T→P2, and beyond `cap` (change of
    /// direction, rad) the tangents are cut off at the extension they have at `cap`, giving
    /// the three blocks P1→A→B→P2.
    IntersectionBlocks { cap: f64 },
    /// 808D/840D G451: the intersection of the equidistants themselves (line or circle), no
    /// blocks; a transition circle above `limit` (change of direction, rad) or where the
    /// equidistants do not meet.
    Intersection { limit: f64 },
    /// Fanuc cutter compensation C: obtuse outer corners meet at the intersection of the
    /// equidistants (line or circle; the tangents where circles do not meet); acute ones
    /// (more than 90° change of direction) get the extension by |R| of [`Self::LinearTransition`].
    FanucC,
    /// ISG G25: the tangent construction with linear transition blocks; a piece
    /// that runs along a straight element is added to that element instead of becoming a
    /// block. Obtuse: P1→T→P2; acute (more than 90°): P1→A→B→P2 with A, B at |R| along
    /// the tangents (TF5200 "linear transition", Fanuc C "outer corner, acute").
    LinearTransition,
}

/// A resolved corner.
#[derive(Clone, Debug, PartialEq)]
pub struct Corner {
    /// Where the first element's compensated path now ends.
    pub end1: V2,
    /// Where the second element's compensated path now starts.
    pub start2: V2,
    /// Inserted elements from `end1` to `start2`; they belong to the second block (11.1).
    pub pieces: heapless::Vec<Elem, 3>,
    pub kind: CornerKind,
}

impl Corner {
    /// No change of direction: the first element ends at `end1`, the second starts at
    /// `start2`, nothing between them.
    pub fn tangent(end1: V2, start2: V2) -> Self {
        Corner {
            end1,
            start2,
            pieces: heapless::Vec::new(),
            kind: CornerKind::Tangent,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerKind {
    /// No change of direction.
    Tangent,
    /// Tool on the inside of the turn (material angle ≥ 180°).
    Inner,
    /// Tool on the outside (material angle < 180°).
    Outer,
}

/// Why a corner has no path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerError {
    /// The equidistants of an inner corner do not meet: the tool does not fit (11.12).
    NoIntersection,
}

/// A turn whose sine (of unit directions) exceeds this is far from both `ANGLE_EPS` limits
/// (|a| ≥ |sin a| and π − |a| ≥ |sin a|): its kind needs no angle.
const CLEAR_TURN: f64 = 1e-6;

/// Classifies the corner between an element ending in direction `t1` and one starting in
/// direction `t2`, the tool at offset `d` (> 0 left).
pub fn classify(t1: V2, t2: V2, d: f64) -> CornerKind {
    // Most contour transitions are tangent: no atan2 for them (atan z ≤ z for z ≥ 0).
    let (y, x) = (t1.cross(t2), t1.dot(t2));
    if x > 0.0 && y.abs() <= ANGLE_EPS * x {
        return CornerKind::Tangent;
    }
    // |sin a| well above the tolerance: neither tangent nor a reversal, and the side of the
    // turn is the sign of the cross product (no atan2 for the common sharp corner).
    if y.abs() > CLEAR_TURN {
        return if y * d < 0.0 {
            CornerKind::Outer
        } else {
            CornerKind::Inner
        };
    }
    let a = turn(t1, t2);
    if a.abs() <= ANGLE_EPS {
        CornerKind::Tangent
    } else if PI - a.abs() <= ANGLE_EPS || a * d < 0.0 {
        // A reversal is always outer: the tool has to go round the end.
        CornerKind::Outer
    } else {
        CornerKind::Inner
    }
}

/// Parameters that do not depend on the corner.
#[derive(Clone, Copy, Debug)]
pub struct CornerSettings {
    pub outer: OuterCorner,
    /// 840C 11.14: normal positions closer than this meet at their intersection with no
    /// intermediate block; closer than twice this, arc/arc G451 corners take the circle.
    pub suppression: f64,
}

/// The corner between the equidistants `o1` (ending at P1) and `o2` (starting at P2) of two
/// programmed elements meeting at `c`, tool offset `d`.
pub fn corner(
    o1: &Elem,
    o2: &Elem,
    c: V2,
    d: f64,
    s: &CornerSettings,
) -> Result<Corner, CornerError> {
    let mut out = Corner::tangent(o1.end(), o2.start());
    corner_into(o1, o2, c, d, s, &mut out).map(|()| out)
}

/// [`corner`] built in `out` (a corner with its pieces is some 200 bytes: built where the
/// caller keeps it, not moved there).
pub fn corner_into(
    o1: &Elem,
    o2: &Elem,
    c: V2,
    d: f64,
    s: &CornerSettings,
    out: &mut Corner,
) -> Result<(), CornerError> {
    let (p1, p2) = (o1.end(), o2.start());
    out.end1 = p1;
    out.start2 = p2;
    out.pieces.clear();
    out.kind = CornerKind::Tangent;
    // Most transitions are tangent: tell them before normalising anything.
    let (h1, h2) = (o1.heading_at(p1), o2.heading_at(p2));
    if h1.dot(h2) > 0.0 && h1.cross(h2).abs() <= ANGLE_EPS * h1.dot(h2) {
        return Ok(());
    }
    let (t1, t2) = (h1.unit(), h2.unit());
    out.kind = classify(t1, t2, d);
    if d.abs() <= EPS || out.kind == CornerKind::Tangent {
        return Ok(());
    }
    if out.kind == CornerKind::Inner {
        // 840C 11.1: inner corners always get the intersection of the equidistants.
        let x = nearest_intersection(o1, o2, p1, p2).ok_or(CornerError::NoIntersection)?;
        meet(out, x);
        return Ok(());
    }
    let g = Outer {
        o1,
        o2,
        c,
        d,
        t1,
        t2,
    };
    if p1.dist(p2) < s.suppression {
        g.suppressed(out);
        return Ok(());
    }
    match s.outer {
        OuterCorner::Circle => g.circle(out),
        OuterCorner::IntersectionBlocks { cap } => g.intersection_blocks(out, cap, s),
        OuterCorner::Intersection { limit } => g.intersection_limited(out, limit),
        OuterCorner::FanucC => g.fanuc_c(out),
        OuterCorner::LinearTransition => linear_transition(out, o1, o2, g.a(), d),
    }
    Ok(())
}

/// Both elements end at `x`, with no block between them.
fn meet(out: &mut Corner, x: V2) {
    out.end1 = x;
    out.start2 = x;
}

/// An outer corner: the equidistants `o1` (ending at P1 in direction `t1`) and `o2`
/// (starting at P2 in direction `t2`) about the programmed corner `c`, tool offset `d`,
/// change of direction `a`.
struct Outer<'a> {
    o1: &'a Elem,
    o2: &'a Elem,
    c: V2,
    d: f64,
    t1: V2,
    t2: V2,
}

impl Outer<'_> {
    /// The turn's angle: only the corner types that tell corners by it take the atan2.
    fn a(&self) -> f64 {
        turn(self.t1, self.t2)
    }

    fn p1(&self) -> V2 {
        self.o1.end()
    }

    fn p2(&self) -> V2 {
        self.o2.start()
    }

    /// 840C 11.14: normal positions too close for intermediate blocks approach the
    /// intersection; a line between them where there is none.
    fn suppressed(&self, out: &mut Corner) {
        let (p1, p2) = (self.p1(), self.p2());
        if let Some(x) = nearest_intersection(self.o1, self.o2, p1, p2) {
            meet(out, x);
        } else {
            push(out, Elem::Line { a: p1, b: p2 });
        }
    }

    /// 840C/808D G450, ISG G26 (840C 11.1): an arc of radius |R| about the corner from P1
    /// to P2.
    fn circle(&self, out: &mut Corner) {
        push(
            out,
            Elem::Arc {
                a: self.p1(),
                b: self.p2(),
                c: self.c,
                ccw: self.d < 0.0,
            },
        )
    }

    /// 840C G451 (11.1, 11.4, 11.14; docs/trc.md): line/line up to 90° meets at T; other
    /// corners get P1→T→P2, and beyond `cap` the tangents are cut off at the extension they
    /// have at `cap` (P1→A→B→P2). Arc/arc closer than twice the 11.14 distance takes the
    /// circle.
    fn intersection_blocks(&self, out: &mut Corner, cap: f64, s: &CornerSettings) {
        let (p1, p2, t1, t2) = (self.p1(), self.p2(), self.t1, self.t2);
        let arcs = self.o1.is_arc() || self.o2.is_arc();
        if arcs && self.o1.is_arc() && self.o2.is_arc() && p1.dist(p2) < 2.0 * s.suppression {
            // 11.14: switch from intersection to transition circle at arc/arc.
            return self.circle(out);
        }
        let a = self.a().abs();
        if !arcs && a <= FRAC_PI_2 + ANGLE_EPS {
            meet(out, tangent_point(p1, t1, p2, t2));
        } else if a <= cap {
            let x = tangent_point(p1, t1, p2, t2);
            push(out, Elem::Line { a: p1, b: x });
            push(out, Elem::Line { a: x, b: p2 });
        } else {
            let e = self.d.abs() * libm::tan(cap / 2.0);
            let (pa, pb) = (p1 + t1 * e, p2 - t2 * e);
            push(out, Elem::Line { a: p1, b: pa });
            push(out, Elem::Line { a: pa, b: pb });
            push(out, Elem::Line { a: pb, b: p2 });
        }
    }

    /// 808D/840D G451: the intersection of the equidistants themselves up to `limit`;
    /// above it, or where they do not meet, the transition circle.
    fn intersection_limited(&self, out: &mut Corner, limit: f64) {
        let x = if self.a().abs() > limit {
            None
        } else {
            outer_intersection(self.o1, self.o2, self.p1(), self.p2())
        };
        match x {
            Some(x) => meet(out, x),
            None => self.circle(out),
        }
    }

    /// Fanuc C, offset mode: obtuse outer corners meet at the intersection of the
    /// equidistants (the tangent construction where circles do not meet), acute ones get
    /// the linear transition with the extension |R|.
    fn fanuc_c(&self, out: &mut Corner) {
        let (o1, o2) = (self.o1, self.o2);
        if self.a().abs() <= FRAC_PI_2 + ANGLE_EPS {
            if let Some(x) = outer_intersection(o1, o2, self.p1(), self.p2()) {
                meet(out, x);
                return;
            }
        }
        linear_transition(out, o1, o2, self.a(), self.d);
    }
}

/// Fanuc C, "change in the offset direction in the offset mode" (003; Fanuc operator's
/// manuals): `o1` is the previous element's equidistant on the old side, `o2` the next one's
/// on the new side. Neither inner nor outer: the path switches at their intersection nearest
/// the corner; where they do not meet, the previous element runs to the normal position at
/// the next one's start (a line becomes slanted, an arc changes its radius over its sweep).
pub fn side_change(o1: &Elem, o2: &Elem) -> Corner {
    let (p1, p2) = (o1.end(), o2.start());
    let x = nearest_intersection(o1, o2, p1, p2).unwrap_or(p2);
    Corner::tangent(x, x)
}

/// Fanuc C, G40 with I J K: where the equidistant `o1` (ending at P1) meets `o2` (starting
/// at P2), inner corner or outer, the intersection nearest both as at an inner corner.
pub fn crossing(o1: &Elem, o2: &Elem) -> Option<V2> {
    nearest_intersection(o1, o2, o1.end(), o2.start())
}

/// ISG contour masking where the equidistants `o1` and `o2` do not meet: the path leaves a
/// gap from one normal position to the other, which the bottleneck window closes where the
/// equidistants meet further out (prep/bottleneck.rs).
pub fn gap(o1: &Elem, o2: &Elem) -> Corner {
    Corner {
        end1: o1.end(),
        start2: o2.start(),
        pieces: heapless::Vec::new(),
        kind: CornerKind::Inner,
    }
}

/// The tangent construction of [`OuterCorner::LinearTransition`].
fn linear_transition(out: &mut Corner, o1: &Elem, o2: &Elem, a: f64, d: f64) {
    let (p1, p2) = (o1.end(), o2.start());
    let (t1, t2) = (o1.tangent_end(), o2.tangent_start());
    let (pa, pb) = if a.abs() <= FRAC_PI_2 + ANGLE_EPS {
        let x = tangent_point(p1, t1, p2, t2);
        (x, x)
    } else {
        (p1 + t1 * d.abs(), p2 - t2 * d.abs())
    };
    if o1.is_arc() {
        push(out, Elem::Line { a: p1, b: pa });
    } else {
        out.end1 = pa;
    }
    if pa.dist(pb) > EPS {
        push(out, Elem::Line { a: pa, b: pb });
    }
    if o2.is_arc() {
        push(out, Elem::Line { a: pb, b: p2 });
    } else {
        out.start2 = pb;
    }
}

fn push(out: &mut Corner, e: Elem) {
    // At most three pieces by construction.
    let _ = out.pieces.push(e);
}

/// T: where the tangent through P1 along t1 meets the one through P2 along t2 (they are
/// parallel only at a reversal, which the callers send to the capped construction).
fn tangent_point(p1: V2, t1: V2, p2: V2, t2: V2) -> V2 {
    geom::line_line(p1, t1, p2, t2).unwrap_or_else(|| (p1 + p2) * 0.5)
}

/// The intersection of the carriers nearest to both P1 and P2 (inner corners, 11.14).
fn nearest_intersection(o1: &Elem, o2: &Elem, p1: V2, p2: V2) -> Option<V2> {
    geom::intersections(o1, o2).into_iter().min_by(|x, y| {
        let fx = x.dist(p1) + x.dist(p2);
        let fy = y.dist(p1) + y.dist(p2);
        fx.total_cmp(&fy)
    })
}

/// At an outer corner the intersection must lie ahead of P1 on the first equidistant and
/// behind P2 on the second (both are extended); otherwise there is none.
fn outer_intersection(o1: &Elem, o2: &Elem, p1: V2, p2: V2) -> Option<V2> {
    let (t1, t2) = (o1.tangent_end(), o2.tangent_start());
    geom::intersections(o1, o2)
        .into_iter()
        .filter(|&x| (x - p1).dot(t1) >= -EPS && (p2 - x).dot(t2) >= -EPS)
        .min_by(|x, y| {
            let fx = x.dist(p1) + x.dist(p2);
            let fy = y.dist(p1) + y.dist(p2);
            fx.total_cmp(&fy)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trc::geom::v2;
    use std::f64::consts::SQRT_2;

    fn close(a: V2, b: V2) -> bool {
        a.dist(b) < 1e-12
    }

    fn line(a: V2, b: V2) -> Elem {
        Elem::Line { a, b }
    }

    fn settings(outer: OuterCorner) -> CornerSettings {
        CornerSettings {
            outer,
            suppression: 0.0,
        }
    }

    const CAP_150: f64 = 150.0 * PI / 180.0;

    /// The tool left (d = +2) of a line east from (0,0) to (10,0): its equidistant y = 2.
    fn east() -> Elem {
        line(v2(0.0, 2.0), v2(10.0, 2.0))
    }

    /// Then south from (10,0) to (10,−10): left of south is east, x = 12 (P2 = (12,0)).
    fn south() -> Elem {
        line(v2(12.0, 0.0), v2(12.0, -10.0))
    }

    fn assert_pieces(c: &Corner, want: &[Elem]) {
        assert_eq!(c.pieces.len(), want.len(), "{c:?}");
        for (p, w) in c.pieces.iter().zip(want) {
            assert!(
                close(p.start(), w.start()) && close(p.end(), w.end()) && p.is_arc() == w.is_arc(),
                "{p:?} != {w:?}"
            );
        }
    }

    #[test]
    fn a_turn_towards_the_tool_is_inner_away_from_it_or_back_outer() {
        let (e, n, w) = (v2(1.0, 0.0), v2(0.0, 1.0), v2(-1.0, 0.0));
        // East → north turns left by 90°: the tool on the left is inside the turn.
        assert_eq!(classify(e, n, 2.0), CornerKind::Inner);
        assert!((turn(e, n) - FRAC_PI_2).abs() < 1e-15);
        // The tool on the right (d < 0) is outside it.
        assert_eq!(classify(e, n, -2.0), CornerKind::Outer);
        // Straight on: tangent; back the way it came: outer on either side.
        assert_eq!(classify(e, e, 2.0), CornerKind::Tangent);
        assert_eq!(classify(e, w, 2.0), CornerKind::Outer);
        assert_eq!(classify(e, w, -2.0), CornerKind::Outer);
    }

    /// 840C 11.1, G450: the outer corner east → south with the tool left at R 2. P1 = (10,2),
    /// P2 = (12,0); the transition circle runs clockwise (a right turn) about the programmed
    /// corner C = (10,0), radius |P1 − C| = |P2 − C| = 2.
    #[test]
    fn an_outer_corner_gets_a_transition_circle_about_the_programmed_corner() {
        let c = corner(
            &east(),
            &south(),
            v2(10.0, 0.0),
            2.0,
            &settings(OuterCorner::Circle),
        );
        let c = c.unwrap();
        assert_eq!(c.kind, CornerKind::Outer);
        assert!(close(c.end1, v2(10.0, 2.0)) && close(c.start2, v2(12.0, 0.0)));
        assert_eq!(
            c.pieces.as_slice(),
            &[Elem::Arc {
                a: v2(10.0, 2.0),
                b: v2(12.0, 0.0),
                c: v2(10.0, 0.0),
                ccw: false,
            }]
        );
        assert_eq!(c.pieces[0].radius(), 2.0);
    }

    /// 840C 11.1: east → north turns left, towards the tool (R 2, left): the equidistants
    /// y = 2 and x = 8 (left of north is west) meet at (8, 2), whatever the outer policy.
    #[test]
    fn an_inner_corner_meets_at_the_intersection_of_the_equidistants() {
        let north = line(v2(8.0, 0.0), v2(8.0, 10.0));
        for outer in [
            OuterCorner::Circle,
            OuterCorner::IntersectionBlocks { cap: CAP_150 },
            OuterCorner::Intersection { limit: FRAC_PI_2 },
            OuterCorner::FanucC,
            OuterCorner::LinearTransition,
        ] {
            let c = corner(&east(), &north, v2(10.0, 0.0), 2.0, &settings(outer)).unwrap();
            assert_eq!(c.kind, CornerKind::Inner);
            assert!(c.pieces.is_empty());
            assert!(
                close(c.end1, v2(8.0, 2.0)) && close(c.start2, v2(8.0, 2.0)),
                "{c:?}"
            );
        }
    }

    /// 840C 11.12: after y = 2 the equidistant turns left (inner) onto a circle of radius 1
    /// about (7,0), starting at (8,0) heading north; it never reaches above y = 1, so the
    /// equidistants do not meet: the tool does not fit.
    #[test]
    fn an_inner_corner_whose_equidistants_miss_each_other_has_no_path() {
        let arc = Elem::Arc {
            a: v2(8.0, 0.0),
            b: v2(6.0, 0.0),
            c: v2(7.0, 0.0),
            ccw: true,
        };
        let c = corner(
            &east(),
            &arc,
            v2(10.0, 0.0),
            2.0,
            &settings(OuterCorner::Circle),
        );
        assert_eq!(c, Err(CornerError::NoIntersection));
    }

    /// 840C G451 (docs/trc.md): a line/line corner of 90° meets where the equidistants
    /// y = 2 and x = 12 cross, (12, 2), with no block.
    #[test]
    fn intersection_840c_meets_at_t_up_to_ninety_degrees() {
        let s = settings(OuterCorner::IntersectionBlocks { cap: CAP_150 });
        let c = corner(&east(), &south(), v2(10.0, 0.0), 2.0, &s).unwrap();
        assert!(c.pieces.is_empty());
        assert!(
            close(c.end1, v2(12.0, 2.0)) && close(c.start2, v2(12.0, 2.0)),
            "{c:?}"
        );
    }

    /// 840C G451, 135° (the 11.10 corner): east, then south-west from (10,0) to (0,−10).
    /// Left of (−1,−1)/√2 is (1,−1)/√2, so P2 = (10 + √2, −√2). The tangent through P2
    /// along (−1,−1) meets y = 2 where −√2 − s = 2, s = −(2 + √2): T = (12 + 2√2, 2).
    /// Two intermediate blocks P1 → T → P2.
    #[test]
    fn intersection_840c_inserts_two_blocks_through_t_beyond_ninety_degrees() {
        let p2 = v2(10.0 + SQRT_2, -SQRT_2);
        let sw = line(p2, v2(SQRT_2, -10.0 - SQRT_2));
        let s = settings(OuterCorner::IntersectionBlocks { cap: CAP_150 });
        let c = corner(&east(), &sw, v2(10.0, 0.0), 2.0, &s).unwrap();
        let t = v2(12.0 + 2.0 * SQRT_2, 2.0);
        assert_pieces(&c, &[line(v2(10.0, 2.0), t), line(t, p2)]);
        assert!(close(c.end1, v2(10.0, 2.0)) && close(c.start2, p2));
    }

    /// 840C G451 beyond the 150° cap: a reversal east → west. P1 = (10,2); left of west is
    /// south, P2 = (10,−2). The tangents are cut at e = R·tan 75° = 2(2 + √3):
    /// A = P1 + e·(1,0) = (14 + 2√3, 2), B = P2 − e·(−1,0) = (14 + 2√3, −2).
    #[test]
    fn intersection_840c_cuts_the_tangents_off_beyond_its_cap() {
        let west = line(v2(10.0, -2.0), v2(0.0, -2.0));
        let s = settings(OuterCorner::IntersectionBlocks { cap: CAP_150 });
        let c = corner(&east(), &west, v2(10.0, 0.0), 2.0, &s).unwrap();
        let x = 14.0 + 2.0 * 3f64.sqrt();
        let (a, b) = (v2(x, 2.0), v2(x, -2.0));
        assert_pieces(
            &c,
            &[line(v2(10.0, 2.0), a), line(a, b), line(b, v2(10.0, -2.0))],
        );
    }

    /// 808D G451: the 90° corner meets at (12, 2) under a 100° limit, and takes the
    /// transition circle under an 80° one.
    #[test]
    fn intersection_808d_takes_the_circle_above_its_limit() {
        let lim = |deg: f64| {
            settings(OuterCorner::Intersection {
                limit: deg * PI / 180.0,
            })
        };
        let c = corner(&east(), &south(), v2(10.0, 0.0), 2.0, &lim(100.0)).unwrap();
        assert!(c.pieces.is_empty() && close(c.end1, v2(12.0, 2.0)));
        let c = corner(&east(), &south(), v2(10.0, 0.0), 2.0, &lim(80.0)).unwrap();
        assert!(c.pieces.len() == 1 && c.pieces[0].is_arc() && close(c.end1, v2(10.0, 2.0)));
    }

    /// ISG G25 (TF5200 table, LIN-LIN): obtuse, the lines meet at T = (12, 2) with no block;
    /// acute (the reversal), A = P1 + R·t1 = (12, 2) and B = P2 − R·t2 = (12, −2): the
    /// extensions join the lines, and one block A → B is inserted. Fanuc C does the same at
    /// the acute corner and meets at the intersection at the obtuse one.
    #[test]
    fn linear_transition_extends_lines_by_the_radius_at_acute_corners() {
        let west = line(v2(10.0, -2.0), v2(0.0, -2.0));
        for outer in [OuterCorner::LinearTransition, OuterCorner::FanucC] {
            let s = settings(outer);
            let c = corner(&east(), &south(), v2(10.0, 0.0), 2.0, &s).unwrap();
            assert!(c.pieces.is_empty() && close(c.end1, v2(12.0, 2.0)), "{c:?}");
            assert!(close(c.start2, v2(12.0, 2.0)));
            let c = corner(&east(), &west, v2(10.0, 0.0), 2.0, &s).unwrap();
            assert_pieces(&c, &[line(v2(12.0, 2.0), v2(12.0, -2.0))]);
            assert!(close(c.end1, v2(12.0, 2.0)) && close(c.start2, v2(12.0, -2.0)));
        }
    }

    /// 840C 11.14: east, then to (20,−1), a right turn by a = atan(1/10). P1P2 = 2R·sin(a/2)
    /// ≈ 0.2 < 0.5: the elements meet at the intersection R·tan(a/2) beyond P1, where
    /// tan(a/2) = sin a / (1 + cos a) = 1 / (√101 + 10). Without suppression, the circle.
    #[test]
    fn normal_positions_closer_than_the_suppression_distance_meet_at_the_intersection() {
        let r = 101f64.sqrt();
        // Left of (10,−1)/√101 is (1,10)/√101: P2 = (10,0) + 2·(1,10)/√101.
        let p2 = v2(10.0 + 2.0 / r, 20.0 / r);
        let next = line(p2, p2 + v2(10.0, -1.0));
        let s = CornerSettings {
            outer: OuterCorner::Circle,
            suppression: 0.5,
        };
        let c = corner(&east(), &next, v2(10.0, 0.0), 2.0, &s).unwrap();
        let x = v2(10.0 + 2.0 / (r + 10.0), 2.0);
        assert!(c.pieces.is_empty(), "{c:?}");
        assert!(close(c.end1, x) && close(c.start2, x), "{c:?}");
        let c = corner(
            &east(),
            &next,
            v2(10.0, 0.0),
            2.0,
            &settings(OuterCorner::Circle),
        );
        assert!(c.unwrap().pieces[0].is_arc());
    }

    /// Fanuc C side change: the old side's equidistant of east (left, y = 2) and the new
    /// side's of north from (10,0) (right, x = 12) cross at (12, 2). Where they are parallel
    /// (east again, right side: y = −2), the path goes to the normal position (10, −2).
    #[test]
    fn a_side_change_switches_where_the_old_and_new_equidistants_meet() {
        let north_right = line(v2(12.0, 0.0), v2(12.0, 10.0));
        let c = side_change(&east(), &north_right);
        assert!(
            close(c.end1, v2(12.0, 2.0)) && close(c.start2, v2(12.0, 2.0)),
            "{c:?}"
        );
        let east_right = line(v2(10.0, -2.0), v2(20.0, -2.0));
        let c = side_change(&east(), &east_right);
        assert!(
            close(c.end1, v2(10.0, -2.0)) && c.pieces.is_empty(),
            "{c:?}"
        );
    }
}
