//! The equidistant of a turning contour: the curve at a constant distance d beside it, on
//! one side of the direction of travel. Every line moves along its normal, every arc keeps
//! its centre and changes its radius by d; where two elements meet at a corner that opens
//! on that side (a convex corner) an arc of radius d about the corner joins them, where it
//! closes (a concave corner) both are trimmed to where their parallels meet.
//!
//! Two users, one construction: SINUMERIK CYCLE95's finishing allowance FAL (Cycles,
//! "CYCLE95": "FAL finishing allowance according to the contour"), and the nose centre's
//! path in the roughing cycles under nose radius compensation ([`tip_path`]: the
//! equidistant at the nose radius, shifted to the tool tip; docs/turning.md).
//!
//! Plane vectors are (Z, X): the turning plane's abscissa and ordinate, X a radius.

use super::super::super::block::*;
use super::super::{intersections, Curve};
use super::contour::Element;
use super::stock_removal::EPS;
use crate::frontend::plane::{add, cross, dist, dot, left, scale, sub, unit, V};
use crate::trc::cutting_edge::tip_vector;

fn zx(p: Pos) -> V {
    [p[2], p[0]]
}

/// `like` with its Z and X from `v`.
fn pos(v: V, like: Pos) -> Pos {
    let mut p = like;
    p[2] = v[0];
    p[0] = v[1];
    p
}

/// One element of the contour in the plane: its start and end, and its circle's centre
/// and direction (arcs).
#[derive(Clone, Copy, Debug)]
struct Piece {
    from: V,
    to: V,
    arc: Option<(V, bool)>,
}

impl Piece {
    fn of(from: Pos, e: &Element) -> Piece {
        let arc = e
            .mode
            .is_arc()
            .then(|| (zx(e.centre), e.mode == MotionMode::ArcCcw));
        Piece {
            from: zx(from),
            to: zx(e.to),
            arc,
        }
    }

    /// The unit tangent in the direction of travel at `q`, a point of the piece.
    fn tangent(&self, q: V) -> V {
        match self.arc {
            Some((c, ccw)) => {
                let r = unit(sub(q, c));
                if ccw {
                    left(r)
                } else {
                    [r[1], -r[0]]
                }
            }
            None => unit(sub(self.to, self.from)),
        }
    }

    /// Its parallel at `d` on the left (`side` +1) or the right (−1), the same length
    /// or sweep; `None` where an arc's parallel shrinks to nothing.
    fn parallel(&self, d: f64, side: f64) -> Option<Piece> {
        let shift = |q: V| add(q, scale(left(self.tangent(q)), side * d));
        let p = Piece {
            from: shift(self.from),
            to: shift(self.to),
            ..*self
        };
        match self.arc {
            // The shifted start must stay on the centre's side it was on: a distance
            // larger than an arc's radius on its inside turns the parallel inside out.
            Some((c, _)) => {
                (dist(p.from, c) > EPS && dot(sub(p.from, c), sub(self.from, c)) > 0.0).then_some(p)
            }
            None => Some(p),
        }
    }

    fn curve(&self) -> Curve {
        match self.arc {
            Some((c, _)) => Curve::Circle {
                c,
                r: dist(self.from, c),
            },
            None => Curve::Line {
                p: self.from,
                d: unit(sub(self.to, self.from)),
            },
        }
    }

    /// Runs the same way as `orig` (a trim that turns a piece round makes it vanish).
    fn keeps_direction(&self, orig: &Piece) -> bool {
        match self.arc {
            Some((c, _)) => {
                let turn = |p: &Piece| cross(sub(p.from, c), sub(p.to, c));
                turn(self) * turn(orig) >= 0.0
            }
            None => dot(sub(self.to, self.from), sub(orig.to, orig.from)) > EPS,
        }
    }

    fn element(&self, like: &Element) -> Element {
        let (mode, centre) = match self.arc {
            Some((c, ccw)) => (
                if ccw {
                    MotionMode::ArcCcw
                } else {
                    MotionMode::ArcCw
                },
                pos(c, like.to),
            ),
            None => (MotionMode::Linear, pos(self.to, like.to)),
        };
        Element {
            to: pos(self.to, like.to),
            mode,
            centre,
            ..*like
        }
    }
}

/// The equidistant of `contour` (its first element the move to its start) at `d` on the
/// left of the direction of travel (`side` +1, in (Z, X)) or the right (−1). `Err(k)`: the
/// distance makes element k vanish (an arc smaller than d on its inside, an element
/// shorter than the corner's trim).
pub fn equidistant(contour: &[Element], d: f64, side: f64) -> Result<Vec<Element>, usize> {
    let orig: Vec<Piece> = contour
        .windows(2)
        .map(|w| Piece::of(w[0].to, &w[1]))
        .collect();
    let mut par = Vec::with_capacity(orig.len());
    for (k, p) in orig.iter().enumerate() {
        par.push(p.parallel(d, side).ok_or(k + 1)?);
    }
    let mut out = vec![Element {
        to: pos(
            par.first().map_or(zx(contour[0].to), |p| p.from),
            contour[0].to,
        ),
        ..contour[0]
    }];
    for k in 0..par.len() {
        let mut joint = None;
        if let Some(next) = par.get(k + 1).copied() {
            let corner = orig[k].to;
            let turn = cross(orig[k].tangent(corner), orig[k + 1].tangent(corner));
            if dist(par[k].to, next.from) <= EPS {
            } else if turn * side < 0.0 {
                // Convex on the allowance's side: round about the corner.
                joint = Some(Piece {
                    from: par[k].to,
                    to: next.from,
                    arc: Some((corner, turn > 0.0)),
                });
            } else {
                let meet = intersections(par[k].curve(), next.curve())
                    .into_iter()
                    .min_by(|a, b| dist(*a, corner).total_cmp(&dist(*b, corner)))
                    .ok_or(k + 1)?;
                par[k].to = meet;
                par[k + 1].from = meet;
            }
        }
        if !par[k].keeps_direction(&orig[k]) {
            return Err(k + 1);
        }
        out.push(par[k].element(&contour[k + 1]));
        if let Some(j) = joint {
            out.push(j.element(&contour[k + 1]));
        }
    }
    Ok(out)
}

/// The tool nose under compensation: the side (G41 left of travel, G42 right), the nose
/// radius R and the cutting edge position (1 … 9, 0 none) of the active offset.
/// `exchanged`: the shape is given with X and Z exchanged (facing, G72 or a transverse
/// cycle), `side` as seen in that frame (the mirror of the machine's side).
#[derive(Clone, Copy, Debug)]
pub struct Nose {
    pub side: TrcSide,
    pub radius: f64,
    pub edge: u8,
    pub exchanged: bool,
}

/// The path of the tool tip P when the nose centre S runs on the equidistant at R of the
/// elements `on + 1 .. off` of `shape`: element `on` (the selection, G41/G42's block) goes
/// to the first S + v, element `off` (the deselection, G40's; `shape.len()`: none) from
/// the last S + v to its programmed end, the others are as programmed. v = P − S of the
/// cutting edge position (`trc::cutting_edge`), so these points are what preparation
/// addresses for an uncompensated block. `Err(k)`: element k's equidistant vanishes or
/// turns inside out (an arc not larger than R on the nose's side, an element shorter than
/// its corners' trim).
pub fn tip_path(
    shape: &[Element],
    nose: Nose,
    on: usize,
    off: usize,
) -> Result<Vec<Element>, usize> {
    let side = match nose.side {
        TrcSide::Left => 1.0,
        TrcSide::Right => -1.0,
        TrcSide::Off => return Ok(shape.to_vec()),
    };
    let off = off.min(shape.len());
    if nose.radius <= 0.0 || on >= off {
        return Ok(shape.to_vec());
    }
    let eq = equidistant(&shape[on..off], nose.radius, side).map_err(|k| on + k)?;
    // v is (Z, X); `shifted` takes the frame's (first, third) coordinates.
    let v = tip_vector(nose.edge, nose.radius, Plane::ZX);
    let shift = if nose.exchanged {
        [v.x, v.y]
    } else {
        [v.y, v.x]
    };
    let mut out = shape[..on].to_vec();
    out.extend(eq.iter().map(|e| e.shifted(shift)));
    out.extend_from_slice(&shape[off..]);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn el(x: f64, z: f64, mode: MotionMode, centre: (f64, f64)) -> Element {
        Element {
            to: [x, 0.0, z],
            mode,
            centre: [centre.0, 0.0, centre.1],
            feed: None,
            speed: None,
        }
    }

    fn line(x: f64, z: f64) -> Element {
        el(x, z, MotionMode::Linear, (x, z))
    }

    fn near(a: Pos, b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-9 && (a[2] - b[1]).abs() < 1e-9
    }

    #[test]
    fn a_shoulder_gets_its_allowance_normal_to_every_element() {
        // (X radius, Z): A' (10, 0), along −Z to (10, −20) (a concave corner: the face
        // closes on the outside), up to (20, −20) (convex: the edge opens), on to
        // (20, −40). FAL 0.5 on the outside, the right of travel in (Z, X): A' (10.5, 0),
        // the line at X 10.5 to the face's parallel at Z −19.5, the face at Z −19.5 up to
        // X 20, an arc of 0.5 about the edge (20, −20) to (20.5, −20), then X 20.5.
        let contour = [
            line(10.0, 0.0),
            line(10.0, -20.0),
            line(20.0, -20.0),
            line(20.0, -40.0),
        ];
        let e = equidistant(&contour, 0.5, -1.0).unwrap();
        let want = [
            [10.5, 0.0],
            [10.5, -19.5],
            [20.0, -19.5],
            [20.5, -20.0],
            [20.5, -40.0],
        ];
        assert_eq!(e.len(), want.len(), "{e:?}");
        for (g, w) in e.iter().zip(&want) {
            assert!(near(g.to, *w), "{e:?}");
        }
        // The edge's arc turns as the contour does there: from +X to −Z is a left turn in
        // (Z, X), counter-clockwise.
        assert_eq!(e[3].mode, MotionMode::ArcCcw);
        assert!(near(e[3].centre, [20.0, -20.0]));
    }

    #[test]
    fn an_arc_keeps_its_centre_and_a_too_large_allowance_is_refused() {
        // A concave fillet of radius 5 about (15, −15) from (10, −15) to (15, −20): its
        // parallel outside has radius 4.5; the line before it (X 10 → 10.5) meets it at
        // (10.5, −15), the face after it (Z −20 → −19.5) at (15, −19.5).
        let contour = [
            line(10.0, 5.0),
            line(10.0, 0.0),
            line(10.0, -15.0),
            el(15.0, -20.0, MotionMode::ArcCw, (15.0, -15.0)),
            line(20.0, -20.0),
        ];
        let e = equidistant(&contour, 0.5, -1.0).unwrap();
        assert!(near(e[2].to, [10.5, -15.0]), "{e:?}");
        assert!(near(e[3].to, [15.0, -19.5]) && near(e[3].centre, [15.0, -15.0]));
        assert!(near(e[4].to, [20.0, -19.5]));
        // FAL 5 or more swallows the fillet (element 3): at 6 the shifted points would lie
        // 1 beyond the centre, the parallel inside out.
        assert_eq!(equidistant(&contour, 5.0, -1.0).unwrap_err(), 3);
        assert_eq!(equidistant(&contour, 6.0, -1.0).unwrap_err(), 3);
    }

    #[test]
    fn the_tip_path_in_the_exchanged_frame_is_the_machine_one_exchanged() {
        // A face (X down), a taper and a rounding (G2 R5), G41, R 0.8, position 3:
        // computed in machine axes, or with X and Z exchanged and the side mirrored, the
        // tip path is the same point for point (the exchange is a mirror: it swaps left and
        // right and the tip vector's components).
        let shape = [
            line(42.0, -6.0),
            line(30.0, -6.0),
            line(20.0, -2.0),
            el(15.0, 3.0, MotionMode::ArcCw, (15.0, -2.0)),
            line(0.0, 3.0),
        ];
        let nose = Nose {
            side: TrcSide::Left,
            radius: 0.8,
            edge: 3,
            exchanged: false,
        };
        let machine = tip_path(&shape, nose, 0, shape.len()).unwrap();
        let frame: Vec<Element> = shape.iter().map(Element::exchanged).collect();
        let mirrored = Nose {
            side: TrcSide::Right, // mirroring X and Z swaps left and right
            exchanged: true,
            ..nose
        };
        let swapped = tip_path(&frame, mirrored, 0, frame.len()).unwrap();
        assert_eq!(machine.len(), swapped.len());
        for (m, f) in machine.iter().zip(&swapped) {
            let back = f.exchanged();
            assert!(
                near(back.to, [m.to[0], m.to[2]]),
                "{machine:?}\n{swapped:?}"
            );
            assert!(near(back.centre, [m.centre[0], m.centre[2]]));
            assert_eq!(back.mode, m.mode);
        }
        // And the face's first point by hand: the nose centre 0.8 on the +Z side of the
        // face at Z −6 (left of travel along −X), the tip 0.8 lower and towards −Z.
        assert!(near(machine[0].to, [41.2, -6.0]));
    }
}
