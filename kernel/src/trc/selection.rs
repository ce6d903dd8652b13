//! Selecting TRC: how the tool gets from its position onto the first equidistant
//! (840C 11.2, 11.3; Fanuc C start-up; 808D; ISG G138/G139/G05, TF5200).

use super::corner::{classify, corner, CornerError, CornerKind, CornerSettings};
use super::geom::{Elem, EPS, V2};
use crate::frontend::block::SelectionPolicy;

/// The selection block's path and what follows it.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// The selection block's own path, from the tool position (a line, or an arc for G05).
    pub path: Elem,
    /// Blocks inserted after it; they belong to the first contour block (11.1).
    pub pieces: heapless::Vec<Elem, 3>,
    /// Where the first contour element's compensated path starts.
    pub start: V2,
}

/// The entry from `from` (the tool, uncompensated) through the selection block ending at
/// `q` onto the first element `e1` (equidistant `o1`, offset `d`). `dir` is the selection
/// block's direction of travel at `q`, `None` when it does not move in the plane.
#[allow(clippy::too_many_arguments)]
pub fn entry(
    from: V2,
    q: V2,
    dir: Option<V2>,
    e1: &Elem,
    o1: &Elem,
    d: f64,
    policy: SelectionPolicy,
    s: &CornerSettings,
) -> Result<Entry, CornerError> {
    let p2 = o1.start();
    let normal = Entry {
        path: Elem::Line { a: from, b: p2 },
        pieces: heapless::Vec::new(),
        start: p2,
    };
    let Some(dir) = dir else {
        return Ok(normal);
    };
    // The selection block as if it were compensated (its end at distance |R|).
    let n = dir.left() * d;
    let ol = Elem::Line {
        a: q - dir + n,
        b: q + n,
    };
    let compensated = |ol: &Elem| -> Result<Entry, CornerError> {
        let c = corner(ol, o1, q, d, s)?;
        Ok(Entry {
            path: Elem::Line { a: from, b: c.end1 },
            pieces: c.pieces,
            start: c.start2,
        })
    };
    match policy {
        // 840C G455: α < 180° takes the corner mode, α ≥ 180° the normal position (11.2, 11.3).
        SelectionPolicy::Compensated => {
            let kind = classify(dir, e1.tangent_start(), d);
            if kind == CornerKind::Outer {
                compensated(&ol)
            } else {
                Ok(normal)
            }
        }
        // ISG G139: the selection block is compensated at its end for every angle.
        SelectionPolicy::Indirect => compensated(&ol),
        // ISG G05: an arc from the start, tangent to the equidistant at the normal position.
        SelectionPolicy::Tangential => Ok(Entry {
            path: tangent_arc(from, p2, e1.tangent_start(), true),
            pieces: heapless::Vec::new(),
            start: p2,
        }),
        // 840C G456, 808D, Fanuc C start-up, ISG G138/G239 (and the rest, handled by the
        // compensator before it gets here): straight to the normal position.
        _ => Ok(normal),
    }
}

/// Why an inner-corner selection (ISG G238) has no path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InnerCornerError {
    /// The contour's last element does not end where the approach block ends.
    NotClosed,
    /// The first contour element is not a straight line.
    FirstNotLinear,
    /// The corner from the last to the first element is not an inner corner on the tool side.
    NotInner,
    /// The equidistants do not meet there: the tool does not fit into the corner.
    NoIntersection,
}

/// ISG G238 (TF5200 "Selecting inside corner of TRC"): on a closed contour the approach block
/// runs straight from the tool (`from`) to the intersection of the equidistants of the
/// contour's last element `en` and its first `e1` (equidistant `o1`), the inner corner at
/// the approach block's end `q`. The contour later ends at the same point (see
/// [`super::Compensator`]'s deselection), so the tool enters and leaves the contour where no
/// mark is left: in the inner corner.
pub fn inner_corner(
    from: V2,
    q: V2,
    e1: &Elem,
    o1: &Elem,
    en: &Elem,
    d: f64,
    s: &CornerSettings,
) -> Result<Entry, InnerCornerError> {
    if e1.is_arc() {
        return Err(InnerCornerError::FirstNotLinear);
    }
    // Programs give their points to 3–4 decimals: a closed contour closes exactly.
    if en.end().dist(q) > 1e-6 {
        return Err(InnerCornerError::NotClosed);
    }
    let kind = classify(en.tangent_end(), e1.tangent_start(), d);
    if kind != CornerKind::Inner {
        return Err(InnerCornerError::NotInner);
    }
    let on = en.offset(d).ok_or(InnerCornerError::NoIntersection)?;
    let c = corner(&on, o1, q, d, s).map_err(|_| InnerCornerError::NoIntersection)?;
    Ok(Entry {
        path: Elem::Line {
            a: from,
            b: c.start2,
        },
        pieces: heapless::Vec::new(),
        start: c.start2,
    })
}

/// An arc between `a` and `b` that is tangent to direction `t` at `b` (entry, `at_end`) or
/// at `a` (exit). A straight line where no such arc exists (the points on the normal).
pub fn tangent_arc(a: V2, b: V2, t: V2, at_end: bool) -> Elem {
    let (p, other) = if at_end { (b, a) } else { (a, b) };
    let n = t.left();
    let w = p - other;
    let den = 2.0 * n.dot(w);
    if den.abs() <= EPS * w.len().max(1.0) || w.len() <= EPS {
        return Elem::Line { a, b };
    }
    let c = p + n * (-w.dot(w) / den);
    let ccw = (p - c).left().dot(t) > 0.0;
    Elem::Arc { a, b, c, ccw }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trc::fixtures::{close, east, CIRCLE};
    use crate::trc::geom::v2;
    use std::f64::consts::{FRAC_1_SQRT_2, SQRT_2};

    /// 840C G456, 808D, Fanuc start-up, ISG G138/G239: straight from the tool to P2,
    /// whatever the angle.
    #[test]
    fn the_normal_position_method_runs_straight_to_p2() {
        let (e1, o1) = east();
        let ne = Some(v2(FRAC_1_SQRT_2, FRAC_1_SQRT_2));
        for p in [
            SelectionPolicy::NormalPosition,
            SelectionPolicy::OffsetVector,
            SelectionPolicy::Direct,
            SelectionPolicy::WithoutBlock,
        ] {
            let en = entry(
                v2(-20.0, -10.0),
                v2(0.0, 0.0),
                ne,
                &e1,
                &o1,
                2.0,
                p,
                &CIRCLE,
            )
            .unwrap();
            assert!(
                close(en.start, v2(0.0, 2.0)) && en.pieces.is_empty(),
                "{p:?}"
            );
            assert_eq!(en.path.end(), en.start);
            assert_eq!(en.path.start(), v2(-20.0, -10.0));
        }
    }

    /// 840C G455 (11.2, 11.3) at α < 180°: the selection block runs north-east from
    /// (−10,−10) to (0,0), then east, a right turn away from the tool (left): outer. Its
    /// equidistant ends at q + R·left(dir) = (−√2, √2), and the transition circle about
    /// (0,0) runs clockwise from there to P2 = (0, 2).
    #[test]
    fn the_compensated_method_takes_the_corner_mode_at_an_outer_angle() {
        let (e1, o1) = east();
        let ne = Some(v2(FRAC_1_SQRT_2, FRAC_1_SQRT_2));
        let en = entry(
            v2(-10.0, -10.0),
            v2(0.0, 0.0),
            ne,
            &e1,
            &o1,
            2.0,
            SelectionPolicy::Compensated,
            &CIRCLE,
        )
        .unwrap();
        let a = v2(-SQRT_2, SQRT_2);
        assert!(close(en.path.end(), a), "{en:?}");
        assert_eq!(en.pieces.len(), 1);
        let Elem::Arc { a: s, b, c, ccw } = en.pieces[0] else {
            panic!("{en:?}")
        };
        assert!(close(s, a) && close(b, v2(0.0, 2.0)) && close(c, v2(0.0, 0.0)) && !ccw);
        assert!(close(en.start, v2(0.0, 2.0)));
    }

    /// 840C 11.3 at α ≥ 180°: coming south-east from (−10,10), the turn onto east is towards
    /// the tool (inner): G455 goes to the normal position P2 = (0, 2). ISG G139 instead ends
    /// where the selection block's equidistant, through q + R·left(dir) = (√2, √2) along
    /// (1,−1), meets y = 2: √2 − s = 2, s = √2 − 2, x = 2√2 − 2.
    #[test]
    fn at_an_inner_angle_compensated_goes_to_p2_and_indirect_to_the_intersection() {
        let (e1, o1) = east();
        let se = Some(v2(FRAC_1_SQRT_2, -FRAC_1_SQRT_2));
        let from = v2(-10.0, 10.0);
        let q = v2(0.0, 0.0);
        let en = entry(
            from,
            q,
            se,
            &e1,
            &o1,
            2.0,
            SelectionPolicy::Compensated,
            &CIRCLE,
        );
        let en = en.unwrap();
        assert!(
            close(en.start, v2(0.0, 2.0)) && en.pieces.is_empty(),
            "{en:?}"
        );
        let en = entry(
            from,
            q,
            se,
            &e1,
            &o1,
            2.0,
            SelectionPolicy::Indirect,
            &CIRCLE,
        )
        .unwrap();
        let x = v2(2.0 * SQRT_2 - 2.0, 2.0);
        assert!(close(en.start, x) && close(en.path.end(), x) && en.pieces.is_empty());
    }

    /// ISG G05: from (−2,0) an arc tangent to the first element's direction (1,0) at
    /// P2 = (0,2). Its centre lies on the normal x = 0 at (0, 2 − ρ) with ρ² = 4 + (2 − ρ)²,
    /// ρ = 2: about (0,0), clockwise (at the top of the circle it runs east).
    #[test]
    fn the_tangential_method_arcs_onto_p2() {
        let (e1, o1) = east();
        let dir = Some(v2(1.0, 0.0));
        let from = v2(-2.0, 0.0);
        let en = entry(
            from,
            v2(0.0, 0.0),
            dir,
            &e1,
            &o1,
            2.0,
            SelectionPolicy::Tangential,
            &CIRCLE,
        );
        let en = en.unwrap();
        let Elem::Arc { a, b, c, ccw } = en.path else {
            panic!("{en:?}")
        };
        assert!(close(a, from) && close(b, v2(0.0, 2.0)) && close(c, v2(0.0, 0.0)) && !ccw);
    }

    /// ISG G238 (TF5200): the contour closes at q = (0,0), its last block coming south from
    /// (0,10), its first going east. South → east turns left, towards the tool (left, R 2):
    /// inner. The equidistants x = 2 (left of south is east) and y = 2 cross at (2, 2),
    /// where the approach block goes straight.
    #[test]
    fn the_inner_corner_method_enters_where_the_last_and_first_equidistants_cross() {
        let (e1, o1) = east();
        let last = Elem::Line {
            a: v2(0.0, 10.0),
            b: v2(0.0, 0.0),
        };
        let from = v2(-5.0, -5.0);
        let q = v2(0.0, 0.0);
        let en = inner_corner(from, q, &e1, &o1, &last, 2.0, &CIRCLE).unwrap();
        assert!(
            close(en.start, v2(2.0, 2.0)) && en.pieces.is_empty(),
            "{en:?}"
        );
        assert_eq!(en.path.start(), from);
        // Not closed: the last block ends 1 mm off q.
        let open = Elem::Line {
            a: v2(0.0, 10.0),
            b: v2(0.0, 1.0),
        };
        let e = inner_corner(from, q, &e1, &o1, &open, 2.0, &CIRCLE);
        assert_eq!(e, Err(InnerCornerError::NotClosed));
        // The tool on the right (d = −2): the same turn is an outer corner.
        let o1r = Elem::Line {
            a: v2(0.0, -2.0),
            b: v2(10.0, -2.0),
        };
        let e = inner_corner(from, q, &e1, &o1r, &last, -2.0, &CIRCLE);
        assert_eq!(e, Err(InnerCornerError::NotInner));
        // A circle as the first element.
        let arc = Elem::Arc {
            a: q,
            b: v2(10.0, 0.0),
            c: v2(5.0, 0.0),
            ccw: true,
        };
        let e = inner_corner(from, q, &arc, &o1, &last, 2.0, &CIRCLE);
        assert_eq!(e, Err(InnerCornerError::FirstNotLinear));
    }
}
