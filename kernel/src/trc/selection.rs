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
            let (kind, _) = classify(dir, e1.tangent_start(), d);
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
    let (kind, _) = classify(en.tangent_end(), e1.tangent_start(), d);
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
