//! Smooth approach and retraction (SAR) as geometry (840D sl Fundamentals "Smooth approach
//! and retraction", FM W1 "Smooth approach and retraction"): the contour element that leads
//! tangentially onto the first contour element, or off the last one, and the heights of the
//! points P0 … P4 along the tool axis. The element is a programmed one: the compensation
//! makes its equidistant, and its size is chosen so that this equidistant is the tool-centre
//! path the manual gives. Dialect-free (the G codes are the dialect table's); the block
//! stream is build/smooth.rs.
//!
//! ```text
//!   approach, G41, G247 (quadrant), the contour along t from P4:
//!
//!        C = P4 + (d + σ·DISR)·l          l = t turned left, d = the signed offset
//!       /|
//!   A  / | r = DISR + σ·d                 programmed quarter circle A → P4 about C
//!    \/  |                                its equidistant: radius DISR about C, the tool
//!     \  |                                centre's path (Fundamentals: "DISR … radius of
//!      `-P4 ──────── t ──────►            the tool center point path")
//! ```

pub use super::super::plane::V;
use super::super::plane::{add, cross, left, len, scale, sub};

/// G147/G148, G247/G248, G347/G348: the approach or retraction contour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SarContour {
    /// A straight line along the contour's tangent.
    Line,
    /// A quarter circle.
    Quadrant,
    /// A half circle.
    Semicircle,
}

/// G140 … G143: the side the contour is approached from or left to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SarSide {
    /// G140: the compensation's side (G41 left, G42 right); without compensation as G143.
    #[default]
    Compensation,
    /// G141
    Left,
    /// G142
    Right,
    /// G143: the side of the start (approach) or end point (retraction) relative to the
    /// contour's tangent.
    Position,
}

/// G340 / G341: how the approach moves along the tool axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SarPath {
    /// G340: the approach contour descends from the safety clearance to the plane (a helix
    /// for the circles).
    #[default]
    Spatial,
    /// G341: infeed along the tool axis to the plane first, the contour in the plane.
    AxisFirst,
}

/// A height along the tool axis as DISCL= and DISRP= give it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Level {
    /// A distance from the machining plane, mm, on the side the tool comes from.
    Distance(f64),
    /// `=AC(…)`: the position on the tool axis (basic coordinates).
    At(f64),
}

/// What a SAR block asks for, lengths in mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Request {
    pub contour: SarContour,
    pub retract: bool,
    pub side: SarSide,
    pub path: SarPath,
    pub disr: Option<f64>,
    pub discl: Option<Level>,
    pub disrp: Option<Level>,
}

/// The compensation the approach ends in (or the retraction starts from).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tool {
    /// G41/G42 in force.
    pub on: bool,
    /// G41 (true) or G42.
    pub left: bool,
    /// The tool radius as the offset holds it (negative swaps the side).
    pub radius: f64,
}

impl Tool {
    /// The signed offset of the equidistant to the left of the direction of travel.
    pub fn d(&self) -> f64 {
        match (self.on, self.left) {
            (false, _) => 0.0,
            (true, true) => self.radius,
            (true, false) => -self.radius,
        }
    }
}

/// Where the approach meets the contour (or the retraction leaves it): P4, the contour's
/// tangent there (a unit vector in the direction of travel), and the point the side is taken
/// from under G143 (P0), if it is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint {
    pub p4: V,
    pub t: V,
    pub other: Option<V>,
}

/// One element in the plane, in the direction of travel: the corner geometry's.
pub(in crate::frontend) use super::super::build::Element as Piece;

/// The approach or retraction contour: the programmed element (from its far end A to P4 on
/// approach, from P4 to A on retraction) and the tool centre at A.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contour {
    pub element: Piece,
    pub far: V,
    pub tool_far: V,
}

/// Why no SAR contour exists, with the alarm the control gives.
#[derive(Clone, Debug, PartialEq)]
pub enum SarError {
    /// DISR (or DISCL, DISRP) invalid or missing (840D 10742).
    Distance(String),
    /// No side for the circle (840D 10744).
    Direction(String),
    /// The infeed would turn back along the tool axis (840D 10741).
    Reversal(String),
}

/// Lengths below this count as zero (mm).
const EPS: f64 = 1e-9;

/// The SAR contour at `j` for the compensation `tool` (NCP19 p.273, FM W1 "DISR"): a line of
/// DISR plus the tool radius (counted when the compensation is on and it is positive), or a
/// circle whose equidistant, the tool centre's path, has the radius DISR.
pub fn contour(req: &Request, tool: &Tool, j: &Joint) -> Result<Contour, SarError> {
    let d = tool.d();
    let l = left(j.t);
    // Approach: A lies behind P4 (against t); retraction: ahead of it.
    let ahead = if req.retract { 1.0 } else { -1.0 };
    if req.contour == SarContour::Line {
        return line(req, tool, j);
    }
    let rho = req
        .disr
        .ok_or_else(|| SarError::Distance("a circle needs its radius DISR=".to_string()))?;
    if rho <= EPS {
        return Err(SarError::Distance(format!(
            "DISR={rho}: the radius of the tool centre's circle must be positive"
        )));
    }
    let sigma = side(req, tool, j)?;
    // Tool on the circle's inside (σ·d > 0): the programmed circle is larger by the radius.
    let r = rho + sigma * d;
    if r <= EPS {
        return Err(SarError::Distance(format!(
            "DISR={rho} is smaller than the tool radius {:.4} on the outside of the circle: the programmed circle would have the radius {r:.4}",
            d.abs()
        )));
    }
    let centre = add(j.p4, scale(l, sigma * r));
    let (far, tool_far) = match req.contour {
        SarContour::Semicircle => (
            add(centre, scale(l, sigma * r)),
            add(centre, scale(l, sigma * rho)),
        ),
        _ => (
            add(centre, scale(j.t, ahead * r)),
            add(centre, scale(j.t, ahead * rho)),
        ),
    };
    let (from, to) = ends(req.retract, far, j.p4);
    Ok(Contour {
        element: Piece::Arc {
            from,
            to,
            centre,
            ccw: sigma > 0.0,
        },
        far,
        tool_far,
    })
}

/// G147/G148: the line along the tangent, DISR plus the tool radius long.
fn line(req: &Request, tool: &Tool, j: &Joint) -> Result<Contour, SarError> {
    let ahead = if req.retract { 1.0 } else { -1.0 };
    let disr = req.disr.unwrap_or(0.0);
    let len = disr + if tool.on { tool.radius.max(0.0) } else { 0.0 };
    if len <= EPS {
        return Err(SarError::Distance(format!(
            "the straight approach or retraction would be {len:.4} mm long (DISR={disr} plus the tool radius)"
        )));
    }
    let far = add(j.p4, scale(j.t, ahead * len));
    let (from, to) = ends(req.retract, far, j.p4);
    Ok(Contour {
        element: Piece::Line { from, to },
        far,
        tool_far: add(far, scale(left(j.t), tool.d())),
    })
}

/// The element's ends in the direction of travel.
fn ends(retract: bool, far: V, p4: V) -> (V, V) {
    if retract {
        (p4, far)
    } else {
        (far, p4)
    }
}

/// +1 for a circle on the left of the tangent, −1 on the right (G140 … G143, FM W1 "Modal G
/// code for the approach and retraction direction").
fn side(req: &Request, tool: &Tool, j: &Joint) -> Result<f64, SarError> {
    let d = tool.d();
    match req.side {
        SarSide::Left => Ok(1.0),
        SarSide::Right => Ok(-1.0),
        // A radius of 0 counts as positive.
        SarSide::Compensation if tool.on && d != 0.0 => Ok(d.signum()),
        SarSide::Compensation if tool.on => Ok(if tool.left { 1.0 } else { -1.0 }),
        // G143, and G140 without compensation.
        _ => {
            let Some(p0) = j.other else {
                return Err(SarError::Direction(
                    "the circle's side is to come from the end point (side by position, or the compensation's side without compensation), which the block does not program".to_string(),
                ));
            };
            let c = cross(j.t, sub(p0, j.p4));
            if c.abs() <= EPS * len(sub(p0, j.p4)).max(1.0) {
                return Err(SarError::Direction(
                    "the start or end point lies on the contour's tangent: it is neither left nor right of it, and the circle has no side".to_string(),
                ));
            }
            Ok(c.signum())
        }
    }
}

/// The heights of P1, P2 and P3 along the tool axis (NCP19 p.276; FM W1 "DISCL", "DISRP").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Heights {
    pub z1: f64,
    pub z2: f64,
    pub z3: f64,
}

/// Heights for P0 at `z0` and P4 at `z4`. P1 lies at DISRP, else at P0's height; P2 at DISCL.
/// G340 (`Spatial`): P3 coincides with P2, and without DISCL (or DISCL=0) with P1, so that
/// the contour descends from there. G341: P3 lies in the plane, and P2 without DISCL there
/// too. Distances count on the side of the plane P0 lies on. No move may turn back along
/// the tool axis (FM W1: "it is not permitted to change direction").
pub fn heights(req: &Request, z0: f64, z4: f64) -> Result<Heights, SarError> {
    let s = if z0 >= z4 { 1.0 } else { -1.0 };
    let level = |l: Level| match l {
        Level::Distance(v) => z4 + s * v,
        Level::At(z) => z,
    };
    let z1 = req.disrp.map_or(z0, level);
    let clearance = match req.discl {
        Some(Level::Distance(v)) if v == 0.0 && req.path == SarPath::Spatial => None,
        other => other.map(level),
    };
    let h = match req.path {
        SarPath::Spatial => {
            let z = clearance.unwrap_or(z1);
            Heights { z1, z2: z, z3: z }
        }
        SarPath::AxisFirst => Heights {
            z1,
            z2: clearance.unwrap_or(z4),
            z3: z4,
        },
    };
    let way = z4 - z0;
    let seq = [z0, h.z1, h.z2, h.z3, z4];
    for w in seq.windows(2) {
        let step = w[1] - w[0];
        if step.abs() > EPS && (way.abs() <= EPS || step.signum() != way.signum()) {
            return Err(SarError::Reversal(format!(
                "the moves along the tool axis turn back: P0 {z0:.4}, P1 {:.4}, P2 {:.4}, P3 {:.4}, P4 {z4:.4} (DISRP, DISCL)",
                h.z1, h.z2, h.z3
            )));
        }
    }
    Ok(h)
}

/// The unit tangent of a move in the plane at its start (`at_end` false) or end: a line's
/// direction, an arc's tangent there; `None` for a move that does not move in the plane.
pub fn tangent(from: V, to: V, centre: Option<(V, bool)>, at_end: bool) -> Option<V> {
    let t = match centre {
        Some((c, ccw)) => {
            let r = sub(if at_end { to } else { from }, c);
            if ccw {
                left(r)
            } else {
                scale(left(r), -1.0)
            }
        }
        None => sub(to, from),
    };
    let n = len(t);
    (n > EPS).then(|| scale(t, 1.0 / n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: V, b: V) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    fn req(contour: SarContour, retract: bool, side: SarSide, disr: f64) -> Request {
        Request {
            contour,
            retract,
            side,
            path: SarPath::Spatial,
            disr: Some(disr),
            discl: None,
            disrp: None,
        }
    }

    const G41_R5: Tool = Tool {
        on: true,
        left: true,
        radius: 5.0,
    };
    const OFF: Tool = Tool {
        on: false,
        left: true,
        radius: 5.0,
    };
    /// The contour goes up the Y axis from P4 = (0, 0); left of it is −X.
    const UP: Joint = Joint {
        p4: [0.0, 0.0],
        t: [0.0, 1.0],
        other: None,
    };

    /// G147, G41 R 5, DISR=3: the line is DISR + R = 8 long, behind P4: A = (0, −8); the
    /// tool centre there is 5 to the left: (−5, −8).
    #[test]
    fn the_line_is_disr_plus_the_tool_radius_long() {
        let c = contour(
            &req(SarContour::Line, false, SarSide::Compensation, 3.0),
            &G41_R5,
            &UP,
        )
        .unwrap();
        assert_eq!(
            c.element,
            Piece::Line {
                from: [0.0, -8.0],
                to: [0.0, 0.0]
            }
        );
        assert!(close(c.tool_far, [-5.0, -8.0]));
        // Without compensation the radius does not count: 3 long.
        let c = contour(
            &req(SarContour::Line, false, SarSide::Compensation, 3.0),
            &OFF,
            &UP,
        )
        .unwrap();
        assert!(close(c.far, [0.0, -3.0]) && close(c.tool_far, c.far));
        // DISR may be negative down to the radius: −4 leaves 1 mm, −5 nothing.
        let r = req(SarContour::Line, false, SarSide::Compensation, -4.0);
        assert!(close(contour(&r, &G41_R5, &UP).unwrap().far, [0.0, -1.0]));
        let r = req(SarContour::Line, false, SarSide::Compensation, -5.0);
        assert!(matches!(
            contour(&r, &G41_R5, &UP),
            Err(SarError::Distance(_))
        ));
    }

    /// G247, G41 R 5, DISR=10 (G140: from the left, l = (−1, 0)): the tool centre's circle
    /// has the radius 10 and ends at (−5, 0), so its centre is (−15, 0); the programmed
    /// circle about it has the radius 10 + 5 = 15 and ends at P4. A quarter before P4,
    /// against t: A = (−15, −15), the tool centre (−15, −10); counter-clockwise.
    #[test]
    fn the_quadrant_is_the_tool_centres_circle_of_radius_disr() {
        let r = req(SarContour::Quadrant, false, SarSide::Compensation, 10.0);
        let c = contour(&r, &G41_R5, &UP).unwrap();
        assert_eq!(
            c.element,
            Piece::Arc {
                from: [-15.0, -15.0],
                to: [0.0, 0.0],
                centre: [-15.0, 0.0],
                ccw: true
            }
        );
        assert!(close(c.tool_far, [-15.0, -10.0]));
        // G142 (from the right) under G41: the tool runs outside the circle, which is
        // smaller by the radius: 8 − 5 = 3 about (3, 0), from (3, −3); the tool centre from
        // (3, −8) on its radius 8. DISR=3 leaves no programmed circle.
        let r = req(SarContour::Quadrant, false, SarSide::Right, 8.0);
        let c = contour(&r, &G41_R5, &UP).unwrap();
        assert_eq!(
            c.element,
            Piece::Arc {
                from: [3.0, -3.0],
                to: [0.0, 0.0],
                centre: [3.0, 0.0],
                ccw: false
            }
        );
        assert!(close(c.tool_far, [3.0, -8.0]));
        let r = req(SarContour::Quadrant, false, SarSide::Right, 3.0);
        assert!(matches!(
            contour(&r, &G41_R5, &UP),
            Err(SarError::Distance(_))
        ));
        let r = Request {
            disr: None,
            ..req(SarContour::Quadrant, false, SarSide::Left, 1.0)
        };
        assert!(matches!(
            contour(&r, &G41_R5, &UP),
            Err(SarError::Distance(_))
        ));
    }

    /// G347 without compensation, G143, the contour along +X from (0, 0), the start at
    /// (20, −30): t × (P0 − P4) = 1·(−30) − 0·20 < 0, right of the tangent. The half circle of
    /// radius 5 lies right of the contour, centre (0, −5), from (0, −10) clockwise.
    #[test]
    fn g143_takes_the_side_of_the_start_point() {
        let j = Joint {
            p4: [0.0, 0.0],
            t: [1.0, 0.0],
            other: Some([20.0, -30.0]),
        };
        let r = req(SarContour::Semicircle, false, SarSide::Position, 5.0);
        let c = contour(&r, &OFF, &j).unwrap();
        assert_eq!(
            c.element,
            Piece::Arc {
                from: [0.0, -10.0],
                to: [0.0, 0.0],
                centre: [0.0, -5.0],
                ccw: false
            }
        );
        // G140 without compensation is G143; a start on the tangent has no side.
        let r = req(SarContour::Semicircle, false, SarSide::Compensation, 5.0);
        assert_eq!(contour(&r, &OFF, &j).unwrap(), c);
        let on_line = Joint {
            other: Some([-20.0, 0.0]),
            ..j
        };
        assert!(matches!(
            contour(&r, &OFF, &on_line),
            Err(SarError::Direction(_))
        ));
        assert!(matches!(
            contour(&r, &OFF, &UP),
            Err(SarError::Direction(_))
        ));
    }

    /// G248, G41 R 5, DISR=8, the last element going −X into P4 = (0, 0): l = (0, −1). The
    /// circle continues ahead: centre (0, −13) (8 + 5 below), radius 13, a quarter on to
    /// (−13, −13); the tool centre's circle of radius 8 from (0, −5) to (−8, −13).
    #[test]
    fn the_retraction_runs_ahead_of_p4() {
        let j = Joint {
            p4: [0.0, 0.0],
            t: [-1.0, 0.0],
            other: None,
        };
        let r = req(SarContour::Quadrant, true, SarSide::Compensation, 8.0);
        let c = contour(&r, &G41_R5, &j).unwrap();
        assert_eq!(
            c.element,
            Piece::Arc {
                from: [0.0, 0.0],
                to: [-13.0, -13.0],
                centre: [0.0, -13.0],
                ccw: true
            }
        );
        assert!(close(c.tool_far, [-8.0, -13.0]));
        // G148 DISR=3: 8 ahead, to (−8, 0), the tool centre (−8, −5).
        let r = req(SarContour::Line, true, SarSide::Compensation, 3.0);
        let c = contour(&r, &G41_R5, &j).unwrap();
        assert!(close(c.far, [-8.0, 0.0]) && close(c.tool_far, [-8.0, -5.0]));
    }

    /// Heights from P0 at 20 to P4 at −5: G340 with DISCL=2 descends along the contour from
    /// −3; G341 with DISCL=AC(3) goes down to 3, then slowly to −5; G340 without DISCL from
    /// P0's height; DISRP=10 puts P1 at 5.
    #[test]
    fn the_heights_follow_discl_and_disrp() {
        let mut r = req(SarContour::Line, false, SarSide::Compensation, 3.0);
        r.discl = Some(Level::Distance(2.0));
        let h = |r: &Request| heights(r, 20.0, -5.0).map(|h| (h.z1, h.z2, h.z3));
        assert_eq!(h(&r), Ok((20.0, -3.0, -3.0)));
        r.discl = Some(Level::Distance(0.0));
        assert_eq!(h(&r), Ok((20.0, 20.0, 20.0)));
        r.discl = None;
        assert_eq!(h(&r), Ok((20.0, 20.0, 20.0)));
        r.path = SarPath::AxisFirst;
        r.discl = Some(Level::At(3.0));
        assert_eq!(h(&r), Ok((20.0, 3.0, -5.0)));
        r.disrp = Some(Level::Distance(10.0));
        r.discl = Some(Level::Distance(2.0));
        assert_eq!(h(&r), Ok((5.0, -3.0, -5.0)));
        // From below the plane the distances count downwards: −20 → −15 (DISRP) → −7.
        assert_eq!(
            heights(&r, -20.0, -5.0).map(|h| (h.z1, h.z2, h.z3)),
            Ok((-15.0, -7.0, -5.0))
        );
        // P0 at −4, just above the plane: DISCL=2 would go up to −3 and down again.
        r.disrp = None;
        assert!(matches!(
            heights(&r, -4.0, -5.0),
            Err(SarError::Reversal(_))
        ));
    }

    /// A line's direction; an arc's tangent, counter-clockwise the radius turned left.
    #[test]
    fn tangents_at_start_and_end() {
        let arc = Some(([0.0, 0.0], true));
        assert_eq!(
            tangent([1.0, 0.0], [0.0, 1.0], arc, false),
            Some([0.0, 1.0])
        );
        assert_eq!(
            tangent([1.0, 0.0], [0.0, 1.0], arc, true),
            Some([-1.0, 0.0])
        );
        let cw = Some(([0.0, 0.0], false));
        assert_eq!(
            tangent([1.0, 0.0], [0.0, -1.0], cw, false),
            Some([0.0, -1.0])
        );
        assert_eq!(tangent([2.0, 2.0], [2.0, 2.0], None, false), None);
        assert_eq!(
            tangent([0.0, 0.0], [0.0, -4.0], None, true),
            Some([0.0, -1.0])
        );
    }
}
