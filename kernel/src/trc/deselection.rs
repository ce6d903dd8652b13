//! Deselecting TRC: how the tool leaves the last equidistant for the programmed end point
//! of the deselection block (840C 11.5, 11.5.1; 808D G40; Fanuc C cancel; ISG G138/G139/G05/G239).

use super::corner::{classify, corner, CornerError, CornerKind, CornerSettings};
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
/// block ending at `f`; `dir` is that block's direction of travel at its start.
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
    let normal = Exit {
        end: p1,
        pieces: heapless::Vec::new(),
        path: Elem::Line { a: p1, b: f },
    };
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
            let (kind, _) = classify(en.tangent_end(), dir, d);
            if kind == CornerKind::Outer {
                compensated()
            } else {
                Ok(normal)
            }
        }
        SelectionPolicy::Indirect => compensated(),
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
