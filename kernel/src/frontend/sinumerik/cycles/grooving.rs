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
//! inside; 1 … 4 starting point left, 5 … 8 right; its tens digit (chamfers or radii)
//! matters only with RCO/RCI, which are not built. Longitudinal: the groove lies along Z
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
//! where FAL1 or FAL2 is given and always for a trapezoid: down each flank and along the
//! base to the middle, first from the starting point's side [unconfirmed]. Radii and
//! chamfers (RCO1 … RCI2) and an inclined contour (STA1) are refused with alarm 12580.

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
/// RCO1, RCO2, RCI1, RCI2: not built.
const EDGES: [(usize, &str); 4] = [(7, "RCO1"), (8, "RCO2"), (9, "RCI1"), (10, "RCI2")];

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
    /// tan ANG1, tan ANG2; the width at the base, the depth, the allowances at the base and
    /// at the flanks, the tool's width.
    t1: f64,
    t2: f64,
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
        self.base + self.deep * (self.t1 + self.t2)
    }

    /// How deep roughing may cut at u: FAL2 off the flanks (along u), FAL1 off the base.
    fn floor(&self, u: f64) -> f64 {
        let mut v = self.deep - self.fal1;
        for (d, t) in [
            (u - self.fal2, self.t1),
            (self.top() - self.fal2 - u, self.t2),
        ] {
            if d < -1e-9 {
                return 0.0;
            }
            if t > 0.0 {
                v = v.min(d / t);
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

    /// Finishing cut 1 (the starting point's flank) or 2: edge D down the flank from the
    /// surface, along the base to the middle, out.
    fn finishing_cut(&self, q: &mut heapless::Deque<Step, 8>) {
        let (top, bottom, slanted) = if self.finishing == 1 {
            (0.0, self.deep * self.t1, self.t1 > 0.0)
        } else {
            let u = self.top() - self.width;
            (u, u - self.deep * self.t2, self.t2 > 0.0)
        };
        let middle = self.deep * self.t1 + (self.base - self.width) / 2.0;
        let mut push = |st| {
            let _ = q.push_back(st);
        };
        push(rapid(self.at(top, self.lift)));
        if slanted {
            push(cut(self.at(top, 0.0)));
        }
        push(cut(self.at(bottom, self.deep)));
        push(cut(self.at(middle, self.deep)));
        push(rapid(self.at(middle, self.lift)));
    }
}

/// The groove of a CYCLE93 call, its parameters checked; `width` the tool's.
pub(super) fn groove(l: &Lathe, width: f64) -> R<Groove> {
    let vari = l.whole(VARI, 1, 18, "VARI")? % 10;
    if !(1..=8).contains(&vari) {
        return Err(l.bad(VARI, "VARI: 1 … 8 or 11 … 18"));
    }
    shape_built(l)?;
    let (t1, t2) = (flank(l, ANG1)?, flank(l, ANG2)?);
    let (base, deep) = (l.len(WIDG), l.len(DIAG));
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
        t1,
        t2,
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
        // The plunges cannot cut a slanted flank: a trapezoid is always finished.
        finish: fal1 > 0.0 || fal2 > 0.0 || t1 > 0.0 || t2 > 0.0,
        k: 0,
        reached: 0.0,
        finishing: 0,
    })
}

/// Radii, chamfers and an inclined contour are not built.
fn shape_built(l: &Lathe) -> R<()> {
    if l.p.get(STA1) != 0.0 {
        return Err(l.not_built(
            STA1,
            "STA1: a groove on an inclined contour is not supported",
        ));
    }
    if let Some((k, name)) = EDGES.iter().find(|(k, _)| l.p.get(*k) != 0.0) {
        return Err(l.not_built(
            *k,
            format!("{name}: radii and chamfers at a groove's edges are not supported"),
        ));
    }
    Ok(())
}

/// The tangent of flank angle `k` (0 ≤ ANG < 89.999°, 840D sl Cycles).
fn flank(l: &Lathe, k: usize) -> R<f64> {
    let a = l.p.get(k);
    if !(0.0..89.999).contains(&a) {
        return Err(l.bad(k, format!("a flank angle {a}: 0 … 89.999 degrees")));
    }
    Ok(libm::tan(a.to_radians()))
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
    fn what_is_not_built_and_what_contradicts_is_an_alarm() {
        let at = |call: &str| alarm(&format!("{START}{call}\n"));
        // A flank angle of 90° (ANG1, column 28), a radius RCO1 (column 34), an inclined
        // contour STA1 (column 25).
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 0, 90, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::CycleParameter, 3, 28)
        );
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::NotSupported, 3, 34)
        );
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::NotSupported, 3, 25)
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
            (AlarmCode::CycleParameter, 3, 58)
        );
        // T2 has one edge: no grooving tool (at the call's name).
        let one = "N10 G18 G95 T2 D1 F0.1\nG0 X50 Z10\nCYCLE93(40, -10, 10, 5)\n";
        assert_eq!(alarm(one), (AlarmCode::CycleParameter, 3, 1));
        // No feed (at the call's name).
        let slow =
            "N10 G18 G95 T3 D1\nG0 X50 Z10\nCYCLE93(40, -10, 10, 5, , , , , , , , , , , , 1)\n";
        assert_eq!(alarm(slow), (AlarmCode::NoFeed, 3, 1));
        // As a modal call.
        let modal = "N10 G18 G95 T3 D1 F0.1\nMCALL CYCLE93(40, -10, 10, 5)\nG0 X50 Z10\n";
        assert_eq!(alarm(modal).0, AlarmCode::NotSupported);
    }
}
