//! Grooving (808D Turning "Groove cycle - CYCLE93"; 840D sl Cycles "Groove - CYCLE93"):
//!
//! ```text
//! CYCLE93(SPD, SPL, WIDG, DIAG, STA1, ANG1, ANG2, RCO1, RCO2, RCI1, RCI2, FAL1, FAL2,
//!         IDEP, DTB, VARI, _VRT, _DN)
//! ```
//!
//! A groove DIAG deep and WIDG wide at its base [unconfirmed: the base, not the surface],
//! its flanks leaning out by ANG1 (on the starting point's side) and ANG2, its corner on the
//! starting point's side at (SPD, SPL) on the surface. VARI's units digit says where (840D
//! sl Cycles, CYCLE93 "VARI"): 1 3 5 7 longitudinal, 2 4 6 8 face; 1 2 5 6 outside, 3 4 7 8
//! inside; 1 … 4 starting point left, 5 … 8 right; its tens digit says how a chamfer is
//! given: 0 by its length, 1 by its leg. RCO1/RCO2 round (> 0) or chamfer (< 0) the corners
//! at the surface, RCI1/RCI2 those at the base (1: the starting point's side). Longitudinal: the groove lies along Z
//! from SPL to the right (left start) or the left (right start), its depth into X. Face:
//! along X from SPD towards the centre (outside) or away from it (inside), its depth into
//! Z, towards +Z for a left, −Z for a right start [unconfirmed].
//!
//! The tool is a grooving tool of two edges: D, which the tool's position names, and D+1
//! (or _DN), lying the tool's width further along the groove; the width is the difference
//! of the two edges' lengths [unconfirmed]. Roughing: plunges spread evenly over the
//! groove's width at the surface less FAL2 at each flank, each as deep as both edges stay
//! FAL2 off the flanks and FAL1 off the base, in infeeds of IDEP (all at once where IDEP is
//! 0) with a 1 mm retraction between them to break the chip, a dwell of DTB at the bottom,
//! out at rapid to the start level, _VRT (1 mm where empty) off the surface. Finishing,
//! where FAL1 or FAL2 is given and always for a trapezoid or chamfers: down each flank
//! (over its chamfers and radii) and along the base to the middle, first from the starting
//! point's side [unconfirmed]. An inclined contour (STA1) is refused with alarm 12580.

use super::super::super::block::Pos;
use super::super::super::build::Step;
use super::super::super::fault::{fault, R};
use super::lathe::{cut, rapid, Lathe};
use crate::alarm::AlarmCode;

const SPD: usize = 0;
const SPL: usize = 1;
const WIDG: usize = 2;
const DIAG: usize = 3;
const STA1: usize = 4;
const ANG1: usize = 5;
const ANG2: usize = 6;
const FAL1: usize = 11;
const FAL2: usize = 12;
const IDEP: usize = 13;
const DTB: usize = 14;
const VARI: usize = 15;
const VRT: usize = 16;
const RCO1: usize = 7;
const RCO2: usize = 8;
const RCI1: usize = 9;
const RCI2: usize = 10;

/// The retraction between two infeeds to break the chip (840D sl Cycles, CYCLE93).
const CHIP_BREAK: f64 = 1.0;
/// The start level off the surface where _VRT is empty [unconfirmed].
const LIFT_OFF: f64 = 1.0;

/// A CYCLE93 groove in its own coordinates — u along it from the starting point's edge at
/// the surface, v its depth below the surface — and where its machining stands.
#[derive(Clone, Debug)]
pub struct Groove {
    /// The axis along the groove and the axis of its depth.
    along: usize,
    across: usize,
    /// u = 0, v = 0 in machine coordinates, and the ways u and v go there.
    corner: (f64, f64),
    way: f64,
    into: f64,
    y: f64,
    /// The flank on the starting point's side and the other; the width at the base, the
    /// depth, the allowances at the base and at the flanks, the tool's width.
    flanks: [Flank; 2],
    base: f64,
    deep: f64,
    fal1: f64,
    fal2: f64,
    width: f64,
    /// The start level (v, above the surface).
    lift: f64,
    /// Edge D's u at the first plunge, the step between plunges, their number.
    from: f64,
    step: f64,
    plunges: u32,
    infeed: f64,
    dwell: Option<f64>,
    finish: bool,
    /// The plunge coming next, the depth its last infeed reached (0 before the first), and
    /// the finishing cut (0, 1, 2) coming next.
    k: u32,
    reached: f64,
    finishing: u8,
}

impl Groove {
    /// Infeeds and finishing cuts, for the loop budget.
    pub(super) fn passes(&self) -> u32 {
        let per = if self.infeed > 0.0 {
            libm::ceil(((self.deep - self.fal1) / self.infeed).min(1e9) - 1e-9) as u32
        } else {
            1
        };
        self.plunges
            .saturating_mul(per.max(1))
            .saturating_add(2 * u32::from(self.finish))
    }

    fn at(&self, u: f64, v: f64) -> Pos {
        let mut p = [0.0, self.y, 0.0];
        p[self.along] = self.corner.0 + self.way * u;
        p[self.across] = self.corner.1 + self.into * v;
        p
    }

    /// The width at the surface.
    fn top(&self) -> f64 {
        self.base + self.deep * (self.flanks[0].tan + self.flanks[1].tan)
    }

    /// How deep roughing may cut at u: FAL2 off the flanks and the chamfers at the base
    /// (along u), FAL1 off the base. The shape is convex: each edge's half-plane holds it.
    fn floor(&self, u: f64) -> f64 {
        let mut v = self.deep - self.fal1;
        for (f, w) in self.flanks.iter().zip([u, self.top() - u]) {
            let w = w - self.fal2;
            if w < -1e-9 {
                return 0.0;
            }
            if f.tan > 0.0 {
                v = v.min(w / f.tan);
            }
            if f.inner > 0.0 {
                let (q, b) = (f.inner_from(self.deep), f.inner_to(self.deep));
                v = v.min(q.1 + (w - q.0) * (b.1 - q.1) / (b.0 - q.0));
            }
        }
        v
    }

    pub(super) fn refill(&mut self, q: &mut heapless::Deque<Step, 8>) {
        while self.k < self.plunges {
            let s = self.from + self.step * f64::from(self.k);
            // Both edges stay off the flanks (the shape is convex: its ends bound it).
            let depth = self.floor(s).min(self.floor(s + self.width));
            if depth <= 1e-9 {
                self.k += 1;
                continue;
            }
            self.infeed_steps(q, s, depth);
            return;
        }
        if self.finish && self.finishing < 2 {
            self.finishing += 1;
            self.finishing_cut(q);
        }
    }

    /// The next infeed of the plunge with edge D at u = `s`, `depth` deep.
    fn infeed_steps(&mut self, q: &mut heapless::Deque<Step, 8>, s: f64, depth: f64) {
        let mut push = |st| {
            let _ = q.push_back(st);
        };
        if self.reached == 0.0 {
            push(rapid(self.at(s, self.lift)));
        }
        let deeper = self.reached + self.infeed;
        let last = self.infeed <= 0.0 || deeper >= depth - 1e-9;
        let to = if last { depth } else { deeper };
        push(cut(self.at(s, to)));
        if last {
            if let Some(t) = self.dwell {
                push(Step::Dwell(t));
            }
            push(rapid(self.at(s, self.lift)));
            (self.reached, self.k) = (0.0, self.k + 1);
        } else {
            push(rapid(self.at(s, to - CHIP_BREAK)));
            self.reached = to;
        }
    }

    /// Whether the arc from `a` about `c` to `b` ((u, v)) turns counter-clockwise in the
    /// plane (Z the abscissa, X the ordinate) — the way it turns the shorter way round.
    fn ccw(&self, a: (f64, f64), c: (f64, f64), b: (f64, f64)) -> bool {
        let (s, e) = ((a.0 - c.0, a.1 - c.1), (b.0 - c.0, b.1 - c.1));
        // In (u, v); u runs along `way`, v along `into`; (Z, X) or (X, Z).
        let turn = (s.0 * e.1 - s.1 * e.0) * self.way * self.into;
        let swapped = self.along == 0;
        (turn > 0.0) != swapped
    }

    /// Finishing cut 1 (the starting point's flank) or 2: edge D down the flank from the
    /// surface (over the chamfers), along the base to the middle, out.
    fn finishing_cut(&self, q: &mut heapless::Deque<Step, 8>) {
        let side = usize::from(self.finishing == 2);
        let f = &self.flanks[side];
        // A point (w from the flank's top corner into the groove, v) as edge D's u.
        let u = |w: f64| {
            if side == 0 {
                w
            } else {
                self.top() - w - self.width
            }
        };
        let mut path: heapless::Vec<Cut, 6> = heapless::Vec::new();
        let mut add = |p: (f64, f64), c: Option<(f64, f64)>| {
            let _ = path.push((p, c));
        };
        if f.outer > 0.0 {
            add((-f.outer, 0.0), None);
            let centre = (f.outer_radius > 0.0).then_some((-f.outer, f.outer_radius));
            add(f.outer_to(), centre);
        } else if f.tan > 0.0 {
            add((0.0, 0.0), None);
        }
        if f.inner > 0.0 {
            let to = f.inner_to(self.deep);
            add(f.inner_from(self.deep), None);
            let centre = (f.inner_radius > 0.0).then_some((to.0, to.1 - f.inner_radius));
            add(to, centre);
        } else {
            add((self.deep * f.tan, self.deep), None);
        }
        let middle = self.deep * self.flanks[0].tan + (self.base - self.width) / 2.0;
        let mut push = |st| {
            let _ = q.push_back(st);
        };
        let first = path.first().map_or(0.0, |p| u(p.0 .0));
        push(rapid(self.at(first, self.lift)));
        let mut from = (first, self.lift);
        for &((w, v), centre) in &path {
            let to = self.at(u(w), v);
            push(match centre {
                Some(c) => Step::Arc {
                    to,
                    centre: self.at(u(c.0), c.1),
                    ccw: self.ccw(from, (u(c.0), c.1), (u(w), v)),
                    feed: None,
                },
                None => cut(to),
            });
            from = (u(w), v);
        }
        push(cut(self.at(middle, self.deep)));
        push(rapid(self.at(middle, self.lift)));
    }
}

/// A finishing cut's end (w, v), and the centre of a rounded corner's arc ending there.
type Cut = ((f64, f64), Option<(f64, f64)>);

/// A flank: the tangent of its angle and the legs of the chamfers at its outer (surface)
/// and inner (base) corner (0: none).
#[derive(Clone, Copy, Debug)]
struct Flank {
    tan: f64,
    outer: f64,
    inner: f64,
    /// The radii of the rounded corners (0: a chamfer or a sharp corner).
    outer_radius: f64,
    inner_radius: f64,
}

impl Flank {
    /// The unit vector down the flank, (w, v).
    fn down(&self) -> (f64, f64) {
        let n = libm::sqrt(1.0 + self.tan * self.tan);
        (self.tan / n, 1.0 / n)
    }

    /// The outer chamfer's end on the flank.
    fn outer_to(&self) -> (f64, f64) {
        let d = self.down();
        (self.outer * d.0, self.outer * d.1)
    }

    /// The inner chamfer's start on the flank and its end on the base.
    fn inner_from(&self, deep: f64) -> (f64, f64) {
        let d = self.down();
        (deep * self.tan - self.inner * d.0, deep - self.inner * d.1)
    }

    fn inner_to(&self, deep: f64) -> (f64, f64) {
        (deep * self.tan + self.inner, deep)
    }

    /// Along the flank, without its chamfers.
    fn length(&self, deep: f64) -> f64 {
        deep * libm::sqrt(1.0 + self.tan * self.tan)
    }
}

/// The groove of a CYCLE93 call, its parameters checked; `width` the tool's.
pub(super) fn groove(l: &Lathe, width: f64) -> R<Groove> {
    let vari = l.machining_type(VARI, 1, 18)? % 10;
    if !(1..=8).contains(&vari) {
        return Err(fault(
            AlarmCode::CycleMachiningType,
            l.p.at(VARI),
            "VARI: 1 … 8 or 11 … 18",
        ));
    }
    let (base, deep) = (l.len(WIDG), l.len(DIAG));
    let flanks = flanks(l, base, deep)?;
    let (fal1, fal2) = (l.len(FAL1), l.len(FAL2));
    if deep <= fal1 {
        return Err(l.bad(DIAG, "the groove depth DIAG must be greater than FAL1"));
    }
    if width <= 0.0 || width > base - 2.0 * fal2 + 1e-9 {
        return Err(l.bad(
            WIDG,
            format!("the tool ({width} wide) does not fit the groove WIDG less 2·FAL2"),
        ));
    }
    if l.feed <= 0.0 {
        return Err(fault(AlarmCode::NoFeed, l.p.call, "CYCLE93 needs a feed F"));
    }
    let dwell = dwell(l)?;
    let (along, across, way, into) = placement(vari);
    let corner = l.point(SPL, SPD);
    let lift_by = if l.p.given(VRT) { l.len(VRT) } else { LIFT_OFF };
    let (t1, t2) = (flanks[0].tan, flanks[1].tan);
    let span = base + deep * (t1 + t2) - 2.0 * fal2 - width;
    let plunges = libm::ceil((span / width).min(1e9) - 1e-9).max(0.0) as u32 + 1;
    let step = if plunges > 1 {
        span / f64::from(plunges - 1)
    } else {
        0.0
    };
    Ok(Groove {
        along,
        across,
        corner: (corner[along], corner[across]),
        way,
        into,
        y: l.at[1],
        flanks,
        base,
        deep,
        fal1,
        fal2,
        width,
        lift: -lift_by,
        from: fal2,
        step,
        plunges,
        infeed: l.len(IDEP),
        dwell,
        // The plunges cut neither a slanted flank nor a chamfer: those are always finished.
        finish: fal1 > 0.0
            || fal2 > 0.0
            || flanks
                .iter()
                .any(|f| f.tan > 0.0 || f.outer > 0.0 || f.inner > 0.0),
        k: 0,
        reached: 0.0,
        finishing: 0,
    })
}

/// The groove's flanks, checked: on a straight contour, the base chamfers within the base.
fn flanks(l: &Lathe, base: f64, deep: f64) -> R<[Flank; 2]> {
    if l.p.get(STA1) != 0.0 {
        return Err(l.not_built(
            STA1,
            "STA1: a groove on an inclined contour is not supported",
        ));
    }
    let chr = l.p.get(VARI) >= 10.0;
    let flanks = [
        flank(l, ANG1, RCO1, RCI1, chr, deep)?,
        flank(l, ANG2, RCO2, RCI2, chr, deep)?,
    ];
    if flanks[0].inner + flanks[1].inner > base + 1e-9 {
        return Err(l.bad(
            RCI2,
            "the corners RCI1 and RCI2 are wider than the groove's base",
        ));
    }
    Ok(flanks)
}

/// Flank `ang` (0 ≤ ANG < 89.999°, 840D sl Cycles) with the corners `outer` and `inner`
/// name: < 0 a chamfer, its leg (`chr`, VARI 11 … 18) or its length (VARI 1 … 8); > 0 a
/// radius.
fn flank(l: &Lathe, ang: usize, outer: usize, inner: usize, chr: bool, deep: f64) -> R<Flank> {
    let a = l.p.get(ang);
    if !(0.0..89.999).contains(&a) {
        return Err(l.bad(ang, format!("a flank angle {a}: 0 … 89.999 degrees")));
    }
    // Both corners of a flank open by 90° + ANG: a chamfer of length c has legs
    // c / (2·sin((90° + ANG)/2)).
    let legs = c_legs(chr, a);
    // A radius r touches both lines r / tan((90° + ANG)/2) from the corner.
    let touch = 1.0 / libm::tan((90.0 + a).to_radians() / 2.0);
    let mut f = Flank {
        tan: libm::tan(a.to_radians()),
        outer: 0.0,
        inner: 0.0,
        outer_radius: 0.0,
        inner_radius: 0.0,
    };
    for (k, leg, radius) in [
        (outer, &mut f.outer, &mut f.outer_radius),
        (inner, &mut f.inner, &mut f.inner_radius),
    ] {
        let v = l.p.get(k) * l.unit();
        if v > 0.0 {
            (*leg, *radius) = (v * touch, v);
        } else {
            *leg = -v * legs;
        }
    }
    if f.outer + f.inner > f.length(deep) + 1e-9 {
        return Err(l.bad(inner, "the chamfers or radii are longer than their flank"));
    }
    Ok(f)
}

/// The leg of a chamfer per unit of the programmed value.
fn c_legs(chr: bool, ang: f64) -> f64 {
    if chr {
        1.0
    } else {
        1.0 / (2.0 * libm::sin((90.0 + ang).to_radians() / 2.0))
    }
}

/// VARI's units digit: (axis along the groove, axis of its depth, the way along, the way in).
fn placement(vari: u32) -> (usize, usize, f64, f64) {
    let outside = matches!(vari, 1 | 2 | 5 | 6);
    let left = vari <= 4;
    let sign = |b: bool| if b { 1.0 } else { -1.0 };
    if vari.is_multiple_of(2) {
        // Face: along X from SPD (towards the centre outside), the depth along Z.
        (0, 2, sign(!outside), sign(left))
    } else {
        // Longitudinal: along Z from SPL (to the right for a left start), the depth in X.
        (2, 0, sign(left), sign(!outside))
    }
}

/// DTB in seconds (negative: spindle revolutions, as in the drilling cycles).
fn dwell(l: &Lathe) -> R<Option<f64>> {
    let v = l.p.get(DTB);
    if v > 0.0 {
        return Ok(Some(v));
    }
    if v == 0.0 {
        return Ok(None);
    }
    if l.speed <= 0.0 {
        return Err(l.bad(DTB, "a dwell in revolutions needs the spindle speed S"));
    }
    Ok(Some(-v * 60.0 / l.speed))
}

#[cfg(test)]
mod tests {
    use super::super::lathe::tests::{alarm, lathe, moves, r6, How, How::*};
    use crate::alarm::AlarmCode;
    use crate::frontend::MotionKind;

    /// T3 is the 3 mm grooving tool of config/tools.toml (D1 length 0, D2 length 3).
    const START: &str = "N10 G18 G90 G95 T3 D1 S500 M3 F0.1\nN20 G0 X50 Z10\n";

    fn cycle(call: &str) -> Vec<(How, f64, f64)> {
        let m = moves(&format!("{START}{call}\nG0 X60\n"));
        m[1..m.len() - 1].to_vec()
    }

    #[test]
    fn an_outside_longitudinal_groove_in_infeeds_with_allowances() {
        // D40 (radius 20) at Z-10, 10 wide, 5 deep, VARI 1 (longitudinal, outside, start
        // left: the groove runs Z-10 … Z0, its depth down X). FAL1 0.2, FAL2 0.5, IDEP 2,
        // DTB 1 s. Start level radius 21. Roughing to 20 − (5 − 0.2) = 15.2 over Z-9.5 …
        // Z-0.5 less the 3 mm tool: span 10 − 1 − 3 = 6, plunges ⌈6/3⌉ + 1 = 3, step 3:
        // edge D at Z-9.5, -6.5, -3.5. Infeeds 18, 16, 15.2, 1 mm back after each but the
        // last. Finishing: down each flank to the bottom radius 15 and along it to the
        // middle (-10 + -3)/2 = -6.5 (edge D at Z-10, then at Z0 − 3 = -3).
        let m = cycle("CYCLE93(40, -10, 10, 5, 0, 0, 0, 0, 0, 0, 0, 0.2, 0.5, 2, 1, 1)");
        let mut want = vec![];
        for z in [-9.5, -6.5, -3.5] {
            let f = F(0.1);
            want.extend([
                (R, 21.0, z),
                (f, 18.0, z),
                (R, 19.0, z),
                (f, 16.0, z),
                (R, 17.0, z),
                (f, 15.2, z),
                (R, 21.0, z),
            ]);
        }
        for z in [-10.0, -3.0] {
            want.extend([
                (R, 21.0, z),
                (F(0.1), 15.0, z),
                (F(0.1), 15.0, -6.5),
                (R, 21.0, -6.5),
            ]);
        }
        assert_eq!(m, want);
        let b = lathe(&format!(
            "{START}CYCLE93(40, -10, 10, 5, 0, 0, 0, 0, 0, 0, 0, 0.2, 0.5, 2, 1, 1)\n"
        ))
        .unwrap();
        let dwells: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
        assert_eq!(dwells, [1.0, 1.0, 1.0]);
    }

    #[test]
    fn a_face_groove_in_radius_programming_plunges_at_once() {
        // DIAMOF: SPD 20 is a radius. VARI 6: face, outside (from X20 towards the centre),
        // start right (the depth towards -Z). 7 wide, 3 deep, no allowances, IDEP 0: span
        // 7 − 3 = 4, plunges ⌈4/3⌉ + 1 = 3, step 2: edge D at X20, 18, 16, each from Z1 to
        // Z-3 and back; no finishing.
        let m = cycle("DIAMOF\nCYCLE93(20, 0, 7, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 6)");
        let mut want = vec![];
        for x in [20.0, 18.0, 16.0] {
            want.extend([(R, x, 1.0), (F(0.1), x, -3.0), (R, x, 1.0)]);
        }
        assert_eq!(m, want);
    }

    #[test]
    fn an_inside_groove_starting_right_grows_to_the_left_and_out() {
        // VARI 7: longitudinal, inside, start right. D30 (radius 15) at Z-5, 3 wide (one
        // plunge: the tool's width), 2 deep, _VRT 0.5: from radius 14.5 at Z-5 to 17 and
        // back.
        let m = cycle("CYCLE93(30, -5, 3, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0.5)");
        assert_eq!(m, [(R, 14.5, -5.0), (F(0.1), 17.0, -5.0), (R, 14.5, -5.0)]);
    }

    #[test]
    fn a_trapezoid_groove_plunges_between_its_flanks_and_finishes_along_them() {
        // VARI 1 at D40 (radius 20), Z-10; base 4 wide, 3 deep, ANG1 = ANG2 = 45° (tan 1):
        // 4 + 3 + 3 = 10 wide at the surface (Z-10 … Z0). No allowances, IDEP 0. Edge D's
        // u (from Z-10) spread over 0 … 10 − 3: ⌈7/3⌉ + 1 = 4 plunges, 7/3 apart: u 0,
        // 2.333333, 4.666667, 7. A plunge goes as deep as both edges stay off the flanks:
        // u 0 and 7: 0 (left out); u 2.333333: min(2.333333, 3) = 2.333333 (radius
        // 17.666667); u 4.666667: min(3, 10 − 7.666667) = 2.333333. Finishing (a trapezoid
        // always): edge D from the top corner Z-10 (radius 20) down the flank to (17, Z-7),
        // along the base to the middle u = 3 + (4 − 3)/2 = 3.5 (Z-6.5); then from Z-3 (the
        // other edge at the top corner Z0) to (17, Z-6), to the middle.
        let m = cycle("CYCLE93(40, -10, 4, 3, 0, 45, 45, 0, 0, 0, 0, 0, 0, 0, 0, 1)");
        let f = F(0.1);
        let mut want = vec![];
        for z in [-10.0 + 7.0 / 3.0, -10.0 + 14.0 / 3.0] {
            let (z, x) = (r6(z), r6(20.0 - 7.0 / 3.0));
            want.extend([(R, 21.0, z), (f, x, z), (R, 21.0, z)]);
        }
        want.extend([
            (R, 21.0, -10.0),
            (f, 20.0, -10.0),
            (f, 17.0, -7.0),
            (f, 17.0, -6.5),
            (R, 21.0, -6.5),
            (R, 21.0, -3.0),
            (f, 20.0, -3.0),
            (f, 17.0, -6.0),
            (f, 17.0, -6.5),
            (R, 21.0, -6.5),
        ]);
        assert_eq!(m, want);
    }

    #[test]
    fn chamfers_at_the_edges_are_finished_and_kept_out_of_the_plunges() {
        // VARI 11 (chamfers by their legs): D40 at Z-10, 6 wide, 3 deep; RCO1 -1 (the surface
        // corner on the starting side), RCI2 -0.5 (the base corner on the far side). The
        // 3 mm tool: plunges at u 0 and 3 (span 3: 2 plunges). The far base chamfer runs from
        // (w 0, v 2.5) to (w 0.5, v 3) on the far flank (w = 6 − u): v ≤ 2.5 + w. Plunge u 0:
        // both edges 3 deep (radius 17); u 3: its far edge at w 0 goes 2.5 deep (radius 17.5).
        // Finishing 1: from the surface 1 before the corner (Z-11) down the chamfer to the
        // flank 1 below the surface (radius 19, Z-10), down to the base (17), to the middle
        // u 1.5 (Z-8.5). Finishing 2: edge D at u 6 − 3 = 3 (Z-7) down to the chamfer's start
        // (radius 17.5), along it to u 2.5 (Z-7.5) on the base, to the middle.
        let m = cycle("CYCLE93(40, -10, 6, 3, 0, 0, 0, -1, 0, 0, -0.5, 0, 0, 0, 0, 11)");
        let f = F(0.1);
        assert_eq!(
            m,
            [
                (R, 21.0, -10.0),
                (f, 17.0, -10.0),
                (R, 21.0, -10.0),
                (R, 21.0, -7.0),
                (f, 17.5, -7.0),
                (R, 21.0, -7.0),
                (R, 21.0, -11.0),
                (f, 20.0, -11.0),
                (f, 19.0, -10.0),
                (f, 17.0, -10.0),
                (f, 17.0, -8.5),
                (R, 21.0, -8.5),
                (R, 21.0, -7.0),
                (f, 17.5, -7.0),
                (f, 17.0, -7.5),
                (f, 17.0, -8.5),
                (R, 21.0, -8.5)
            ]
        );
        // VARI 1: the same -1 is the chamfer's length: legs 1/(2·sin 45°) = 0.707107.
        let m = cycle("CYCLE93(40, -10, 6, 3, 0, 0, 0, -1, 0, 0, 0, 0, 0, 0, 0, 1)");
        assert_eq!(
            m[6..9],
            [
                (R, 21.0, -10.707107),
                (f, 20.0, -10.707107),
                (f, 19.292893, -10.0)
            ]
        );
    }

    #[test]
    fn radii_at_the_edges_are_arcs_of_the_finishing_cut() {
        // As the chamfer test, with RCO1 1 and RCI2 0.5 radii (> 0): on a square corner a
        // radius touches both lines r from the corner, so the plunges and the points are
        // those of the chamfers, the chamfers now arcs. The outer arc from (20, Z-11) about
        // (19, Z-11) to (19, Z-10): in (Z, X) from (0, 1) to (1, 0) about the centre, a
        // clockwise turn; the inner from (17.5, Z-7) about (17.5, Z-7.5) to (17, Z-7.5):
        // from (0.5, 0) to (0, -0.5), clockwise too.
        let call = "CYCLE93(40, -10, 6, 3, 0, 0, 0, 1, 0, 0, 0.5, 0, 0, 0, 0, 1)";
        let m = cycle(call);
        let f = F(0.1);
        assert_eq!(
            m[6..],
            [
                (R, 21.0, -11.0),
                (f, 20.0, -11.0),
                (f, 19.0, -10.0),
                (f, 17.0, -10.0),
                (f, 17.0, -8.5),
                (R, 21.0, -8.5),
                (R, 21.0, -7.0),
                (f, 17.5, -7.0),
                (f, 17.0, -7.5),
                (f, 17.0, -8.5),
                (R, 21.0, -8.5)
            ]
        );
        let b = lathe(&format!("{START}{call}\n")).unwrap();
        let arcs: Vec<(MotionKind, [f64; 3])> = b
            .iter()
            .filter_map(|b| b.motion)
            .filter(|m| m.kind.is_arc())
            .map(|m| (m.kind, m.center))
            .collect();
        assert_eq!(
            arcs,
            [
                (MotionKind::ArcCw, [19.0, 0.0, -11.0]),
                (MotionKind::ArcCw, [17.5, 0.0, -7.5])
            ]
        );
        // On the face (VARI 6, radius programming: X20 at Z0, the groove towards the centre
        // and -Z), RCO1 0.5: from (20.5, Z0) about (20.5, Z-0.5) to (20, Z-0.5): in (Z, X)
        // from (0.5, 0) to (0, -0.5), clockwise.
        let face = "DIAMOF\nCYCLE93(20, 0, 4, 2, 0, 0, 0, 0.5, 0, 0, 0, 0, 0, 0, 0, 6)\n";
        let b = lathe(&format!("{START}{face}")).unwrap();
        let arc = b.iter().filter_map(|b| b.motion).find(|m| m.kind.is_arc());
        let r = |p: [f64; 3]| p.map(r6);
        let arc = arc.map(|m| (m.kind, r(m.start), r(m.end), r(m.center)));
        assert_eq!(
            arc,
            Some((
                MotionKind::ArcCw,
                [20.5, 0.0, 0.0],
                [20.0, 0.0, -0.5],
                [20.5, 0.0, -0.5]
            ))
        );
    }

    #[test]
    fn what_is_not_built_and_what_contradicts_is_an_alarm() {
        let at = |call: &str| alarm(&format!("{START}{call}\n"));
        // A flank angle of 90° (ANG1, column 28), an inclined contour STA1 (column 25),
        // chamfers longer than the flank (at RCI1, column 41).
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 0, 90, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 28)
        );
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::NotSupported, 3, 25)
        );
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 0, 0, 0, -3, 0, -3, 0, 0, 0, 0, 0, 11)"),
            (AlarmCode::CycleParameter, 3, 41)
        );
        // The groove narrower than the tool; DIAG not more than FAL1; VARI 9.
        assert_eq!(
            at("CYCLE93(40, -10, 2, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 18)
        );
        assert_eq!(
            at("CYCLE93(40, -10, 10, 0.5, 0, 0, 0, 0, 0, 0, 0, 0.5, 0, 0, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 22)
        );
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 9)"),
            (AlarmCode::CycleMachiningType, 3, 58)
        );
        // T2's second edge, _DN 99, is in no table: no grooving tool (at the call's name).
        let one = "N10 G18 G95 T2 D1 F0.1\nG0 X50 Z10\n\
            CYCLE93(40, -10, 10, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, , 99)\n";
        assert_eq!(alarm(one), (AlarmCode::CycleParameter, 3, 1));
        // Base corners wider than the base (at RCI2); a dwell in revolutions without S.
        assert_eq!(
            at("CYCLE93(40, -10, 4, 5, 0, 0, 0, 0, 0, -3, -3, 0, 0, 0, 0, 11)"),
            (AlarmCode::CycleParameter, 3, 43)
        );
        let no_s = "N10 G18 G95 T3 D1 F0.1\nG0 X50 Z10\n\
            CYCLE93(40, -10, 10, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -2, 1)\n";
        assert_eq!(alarm(no_s), (AlarmCode::CycleParameter, 3, 55));
        // No feed (at the call's name).
        let slow =
            "N10 G18 G95 T3 D1\nG0 X50 Z10\nCYCLE93(40, -10, 10, 5, , , , , , , , , , , , 1)\n";
        assert_eq!(alarm(slow), (AlarmCode::NoFeed, 3, 1));
        // As a modal call.
        let modal = "N10 G18 G95 T3 D1 F0.1\nMCALL CYCLE93(40, -10, 10, 5)\nG0 X50 Z10\n";
        assert_eq!(alarm(modal).0, AlarmCode::NotSupported);
    }
}
