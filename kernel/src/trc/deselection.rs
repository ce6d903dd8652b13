//! Deselecting TRC: how the tool leaves the last equidistant for the programmed end point
//! of the deselection block (840C 11.5, 11.5.1; 808D G40; Fanuc C cancel, with I J K too; ISG
//! G138/G139/G05/G239).

use super::corner::{classify, corner, crossing, CornerError, CornerKind, CornerSettings};
use super::geom::{Elem, V2};
use super::selection::tangent_arc;
use crate::frontend::block::SelectionPolicy;

#[derive(Clone, Debug, PartialEq)]
pub struct Exit {
    /// Where the last element's compensated path ends.
    pub end: V2,
    /// Blocks inserted between it and the retraction; they belong to the deselection block.
    pub pieces: heapless::Vec<Elem, 3>,
    /// The deselection block's path, ending at its programmed point `f`.
    pub path: Elem,
}

/// The exit from the last element `en` (equidistant `on`, offset `d`) through a deselection
/// block ending at `f`; `dir` is that block's direction of travel at its start, or under
/// [`SelectionPolicy::ExitVector`] the direction of the vector I J K.
pub fn exit(
    en: &Elem,
    on: &Elem,
    f: V2,
    dir: Option<V2>,
    d: f64,
    policy: SelectionPolicy,
    s: &CornerSettings,
) -> Result<Exit, CornerError> {
    let p1 = on.end();
    let normal = straight_from(p1, f);
    let Some(dir) = dir else {
        return Ok(normal);
    };
    let q = en.end();
    let n = dir.left() * d;
    let ol = Elem::Line {
        a: q + n,
        b: q + dir + n,
    };
    let compensated = || -> Result<Exit, CornerError> {
        let c = corner(on, &ol, q, d, s)?;
        Ok(Exit {
            end: c.end1,
            pieces: c.pieces,
            path: Elem::Line { a: c.start2, b: f },
        })
    };
    match policy {
        // 840C G455 mirrors the selection: α < 180° takes the corner mode (11.5).
        SelectionPolicy::Compensated => {
            let kind = classify(en.tangent_end(), dir, d);
            if kind == CornerKind::Outer {
                compensated()
            } else {
                Ok(normal)
            }
        }
        SelectionPolicy::Indirect => compensated(),
        // Fanuc 0i-MF, "Tool movement in offset mode cancel", G40 with I J K: a virtual block
        // from the last element's end along the vector, on the same side; the intersection
        // whether the corner is inner or outer, the normal position where there is none.
        SelectionPolicy::ExitVector => {
            Ok(crossing(on, &ol).map_or(normal, |x| straight_from(x, f)))
        }
        SelectionPolicy::Tangential => Ok(Exit {
            end: p1,
            pieces: heapless::Vec::new(),
            path: tangent_arc(p1, f, on.tangent_end(), false),
        }),
        // 840C G456, 808D ("the normal end position ... independently of the start angle"),
        // Fanuc cancel, ISG G138/G239.
        _ => Ok(normal),
    }
}

/// The last element ends at `x`, and the deselection block runs straight from there to `f`.
fn straight_from(x: V2, f: V2) -> Exit {
    Exit {
        end: x,
        pieces: heapless::Vec::new(),
        path: Elem::Line { a: x, b: f },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trc::fixtures::{close, east, CIRCLE};
    use crate::trc::geom::v2;
    use std::f64::consts::{FRAC_1_SQRT_2, SQRT_2};

    fn leave(f: V2, dir: Option<V2>, policy: SelectionPolicy) -> Exit {
        let (en, on) = east();
        exit(&en, &on, f, dir, 2.0, policy, &CIRCLE).unwrap()
    }

    /// 840C G456, 808D G40 ("the normal end position ... independently of the start
    /// angle"), Fanuc cancel, ISG G138: the last element ends at P1 = (10, 2) and the
    /// deselection block runs from there to its programmed point. So does every method
    /// for a deselection without a plane move (no direction).
    #[test]
    fn the_normal_position_method_ends_at_p1() {
        let f = v2(20.0, -10.0);
        let down = Some(v2(FRAC_1_SQRT_2, -FRAC_1_SQRT_2));
        for (dir, p) in [
            (down, SelectionPolicy::NormalPosition),
            (down, SelectionPolicy::Direct),
            (None, SelectionPolicy::Compensated),
            (None, SelectionPolicy::Indirect),
        ] {
            let x = leave(f, dir, p);
            assert!(close(x.end, v2(10.0, 2.0)) && x.pieces.is_empty(), "{p:?}");
            assert_eq!(x.path, Elem::Line { a: x.end, b: f });
        }
    }

    /// 840C G455 (11.5) at α < 180°: the deselection block runs south-east from (10,0) to
    /// (20,−10), a right turn away from the tool: outer. Its equidistant starts at
    /// q + R·left(dir) = (10,0) + 2·(1,1)/√2 = (10 + √2, √2); the transition circle about
    /// (10,0) runs clockwise from P1 = (10,2) to there, and the block from there to (20,−10).
    #[test]
    fn the_compensated_method_takes_the_corner_mode_at_an_outer_angle() {
        let f = v2(20.0, -10.0);
        let x = leave(
            f,
            Some(v2(FRAC_1_SQRT_2, -FRAC_1_SQRT_2)),
            SelectionPolicy::Compensated,
        );
        let b = v2(10.0 + SQRT_2, SQRT_2);
        assert!(close(x.end, v2(10.0, 2.0)), "{x:?}");
        let Elem::Arc { a, b: e, c, ccw } = x.pieces[0] else {
            panic!("{x:?}")
        };
        assert!(close(a, v2(10.0, 2.0)) && close(e, b) && close(c, v2(10.0, 0.0)) && !ccw);
        assert!(close(x.path.start(), b) && x.path.end() == f);
    }

    /// Leaving north-east for (20,10) turns left, towards the tool (inner): G455 ends at P1
    /// (11.5, α ≥ 180°). ISG G139 ends where y = 2 meets the deselection block's equidistant
    /// through (10,0) + 2·(−1,1)/√2 = (10 − √2, √2) along (1,1): √2 + s = 2, s = 2 − √2,
    /// x = 12 − 2√2.
    #[test]
    fn at_an_inner_angle_compensated_ends_at_p1_and_indirect_at_the_intersection() {
        let f = v2(20.0, 10.0);
        let ne = Some(v2(FRAC_1_SQRT_2, FRAC_1_SQRT_2));
        let x = leave(f, ne, SelectionPolicy::Compensated);
        assert!(close(x.end, v2(10.0, 2.0)) && x.pieces.is_empty(), "{x:?}");
        let x = leave(f, ne, SelectionPolicy::Indirect);
        let i = v2(12.0 - 2.0 * SQRT_2, 2.0);
        assert!(
            close(x.end, i) && close(x.path.start(), i) && x.pieces.is_empty(),
            "{x:?}"
        );
    }

    /// Fanuc G40 with I J K: the last element east from (0,0) to (10,0), tool left at R 2
    /// (equidistant y = 2, P1 = (10,2)); the G40 block ends at f = (20,−10) whatever the
    /// vector. The virtual block starts at (10,0) along the vector v, its equidistant on the
    /// same side runs through (10,0) + 2·left(v/|v|).
    fn vector(v: V2) -> Exit {
        leave(v2(20.0, -10.0), Some(v.unit()), SelectionPolicy::ExitVector)
    }

    fn ends_at(x: &Exit, p: V2) {
        assert!(close(x.end, p) && x.pieces.is_empty(), "{x:?}");
        assert_eq!(
            x.path,
            Elem::Line {
                a: x.end,
                b: v2(20.0, -10.0)
            }
        );
    }

    /// Inner corner, I1 J1 (north-east, a left turn towards the tool): through
    /// (10 − √2, √2) along (1,1), y = 2 at s = 2 − √2, x = 12 − 2√2 ≈ 9.172: the element ends
    /// short of P1.
    #[test]
    fn an_exit_vector_at_an_inner_corner_ends_at_the_intersection() {
        ends_at(&vector(v2(1.0, 1.0)), v2(12.0 - 2.0 * SQRT_2, 2.0));
    }

    /// Outer corners take the intersection too ("irrespective of whether inner or outer"),
    /// never the corner policy. I1 J−1 (south-east, 45° to the right): through (10 + √2, √2)
    /// along (1,−1), y = 2 at s = √2 − 2, x = 8 + 2√2 ≈ 10.828. I−1 J−1 (south-west, an acute
    /// 135° turn): through (10 + √2, −√2) along (−1,−1), y = 2 at s = −2 − √2,
    /// x = 12 + 2√2 ≈ 14.828: the element runs on past P1 to there.
    #[test]
    fn an_exit_vector_at_an_outer_corner_ends_at_the_intersection_too() {
        ends_at(&vector(v2(1.0, -1.0)), v2(8.0 + 2.0 * SQRT_2, 2.0));
        ends_at(&vector(v2(-1.0, -1.0)), v2(12.0 + 2.0 * SQRT_2, 2.0));
    }

    /// No intersection: the normal position P1 = (10,2). I−1 J0 reverses the element (its
    /// virtual equidistant is y = −2, parallel); I1 J0 goes on along it (y = 2 itself: no
    /// single point).
    #[test]
    fn an_exit_vector_without_an_intersection_ends_in_the_normal_position() {
        ends_at(&vector(v2(-1.0, 0.0)), v2(10.0, 2.0));
        ends_at(&vector(v2(1.0, 0.0)), v2(10.0, 2.0));
    }

    /// The last element an arc: counter-clockwise about (0,0) from (20,0) to (0,20), tool left
    /// (inside) at R 5: equidistant r = 15 from (15,0) to P1 = (0,15). I0 J−1 (south, a left
    /// turn at the arc's end, where it runs west): virtual equidistant x = 0 + 5 = 5, which
    /// meets r = 15 at (5, ±√200); nearest P1 and (5,20): (5, 10√2), short of P1. I0 J1
    /// (north, outer): x = −5, at (−5, 10√2), beyond P1.
    #[test]
    fn an_exit_vector_after_an_arc_meets_the_arcs_equidistant() {
        let en = Elem::Arc {
            a: v2(20.0, 0.0),
            b: v2(0.0, 20.0),
            c: v2(0.0, 0.0),
            ccw: true,
        };
        let on = Elem::Arc {
            a: v2(15.0, 0.0),
            b: v2(0.0, 15.0),
            c: v2(0.0, 0.0),
            ccw: true,
        };
        let f = v2(-30.0, 0.0);
        for (v, want) in [
            (v2(0.0, -1.0), v2(5.0, 10.0 * SQRT_2)),
            (v2(0.0, 1.0), v2(-5.0, 10.0 * SQRT_2)),
        ] {
            let x = exit(
                &en,
                &on,
                f,
                Some(v),
                5.0,
                SelectionPolicy::ExitVector,
                &CIRCLE,
            )
            .unwrap();
            assert!(x.end.dist(want) < 1e-12 && x.pieces.is_empty(), "{x:?}");
            assert_eq!(x.path, Elem::Line { a: x.end, b: f });
        }
    }

    /// ISG G05: from P1 = (10,2) an arc tangent to the last direction (1,0) there, to
    /// (12,4). Its centre lies on the normal x = 10 at (10, 2 + ρ) with
    /// ρ² = 2² + (2 + ρ − 4)², ρ = 2: about (10,4), counter-clockwise.
    #[test]
    fn the_tangential_method_leaves_on_an_arc() {
        let x = leave(
            v2(12.0, 4.0),
            Some(v2(1.0, 0.0)),
            SelectionPolicy::Tangential,
        );
        let Elem::Arc { a, b, c, ccw } = x.path else {
            panic!("{x:?}")
        };
        assert!(close(a, v2(10.0, 2.0)) && close(b, v2(12.0, 4.0)));
        assert!(close(c, v2(10.0, 4.0)) && ccw, "{x:?}");
    }
}
