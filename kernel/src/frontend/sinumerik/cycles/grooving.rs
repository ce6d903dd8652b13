//! Grooving (808D Turning "Groove cycle - CYCLE93"; 840D sl Cycles "Groove - CYCLE93"):
//!
//! ```text
//! CYCLE93(SPD, SPL, WIDG, DIAG, STA1, ANG1, ANG2, RCO1, RCO2, RCI1, RCI2, FAL1, FAL2,
//!         IDEP, DTB, VARI, _VRT, _DN)
//! ```
//!
//! A rectangular groove WIDG wide and DIAG deep, one edge at (SPD, SPL). VARI's units digit
//! says where (840D sl Cycles, CYCLE93 "VARI"): 1 3 5 7 longitudinal, 2 4 6 8 face;
//! 1 2 5 6 outside, 3 4 7 8 inside; 1 … 4 starting point left, 5 … 8 right; its tens digit
//! (chamfers or radii) matters only with RCO/RCI, which are not built. Longitudinal: the
//! groove lies along Z from SPL to the right (left start) or the left (right start), its
//! depth into X. Face: along X from SPD towards the centre (outside) or away from it
//! (inside), its depth into Z, towards +Z for a left, −Z for a right start [unconfirmed].
//!
//! The tool is a grooving tool of two edges: D, which the tool's position names, and D+1
//! (or _DN), lying the tool's width further along the groove; the width is the difference
//! of the two edges' lengths [unconfirmed]. Roughing: plunges spread evenly over the groove
//! less FAL2 at each flank, each to DIAG − FAL1 in infeeds of IDEP (all at once where IDEP
//! is 0) with a 1 mm retraction between them to break the chip, a dwell of DTB at the
//! bottom, out at rapid to the start level, _VRT (1 mm where empty) off the surface.
//! Finishing, where FAL1 or FAL2 is given: down each flank and along the base to the
//! middle, first from the starting point's side. Flank angles, radii and chamfers and an
//! inclined contour (ANG1, ANG2, RCO1 … RCI2, STA1) are refused with alarm 12580.

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
const FAL1: usize = 11;
const FAL2: usize = 12;
const IDEP: usize = 13;
const DTB: usize = 14;
const VARI: usize = 15;
const VRT: usize = 16;
/// ANG1, ANG2, RCO1, RCO2, RCI1, RCI2: not built.
const SHAPE: [(usize, &str); 6] = [
    (5, "ANG1"),
    (6, "ANG2"),
    (7, "RCO1"),
    (8, "RCO2"),
    (9, "RCI1"),
    (10, "RCI2"),
];

/// The retraction between two infeeds to break the chip (840D sl Cycles, CYCLE93).
const CHIP_BREAK: f64 = 1.0;
/// The start level off the surface where _VRT is empty [unconfirmed].
const LIFT_OFF: f64 = 1.0;

/// A CYCLE93 groove and where its machining stands.
#[derive(Clone, Debug)]
pub struct Groove {
    /// The axis along the groove's width and the axis of its depth; the way into the part.
    along: usize,
    across: usize,
    into: f64,
    /// The start level (off the surface), the roughing depth and the bottom, on `across`.
    lift: f64,
    rough: f64,
    bottom: f64,
    /// Edge D's position at each flank: on the starting point's side and the other.
    first: f64,
    last: f64,
    /// Edge D's position at the first plunge, the step between plunges, their number.
    from: f64,
    step: f64,
    plunges: u32,
    infeed: f64,
    dwell: Option<f64>,
    finish: bool,
    y: f64,
    /// The surface on `across`.
    surface: f64,
    /// The plunge coming next, the depth its last infeed reached (the surface before the
    /// first), and the finishing cut (0, 1, 2) coming next.
    k: u32,
    reached: f64,
    finishing: u8,
}

impl Groove {
    /// Infeeds and finishing cuts, for the loop budget.
    pub(super) fn passes(&self) -> u32 {
        let per = if self.infeed > 0.0 {
            libm::ceil(((self.rough - self.surface).abs() / self.infeed).min(1e9) - 1e-9) as u32
        } else {
            1
        };
        self.plunges
            .saturating_mul(per.max(1))
            .saturating_add(2 * u32::from(self.finish))
    }

    fn at(&self, along: f64, across: f64) -> Pos {
        let mut p = [0.0, self.y, 0.0];
        p[self.along] = along;
        p[self.across] = across;
        p
    }

    pub(super) fn refill(&mut self, q: &mut heapless::Deque<Step, 8>) {
        let mut push = |s| {
            let _ = q.push_back(s);
        };
        if self.k < self.plunges {
            let s = self.from + self.step * f64::from(self.k);
            if self.reached == self.surface {
                push(rapid(self.at(s, self.lift)));
            }
            let deeper = self.reached + self.into * self.infeed;
            let reached = self.infeed <= 0.0 || (self.rough - deeper) * self.into <= 1e-9;
            let to = if reached { self.rough } else { deeper };
            push(cut(self.at(s, to), None));
            if reached {
                if let Some(t) = self.dwell {
                    push(Step::Dwell(t));
                }
                push(rapid(self.at(s, self.lift)));
                (self.reached, self.k) = (self.surface, self.k + 1);
            } else {
                push(rapid(self.at(s, to - self.into * CHIP_BREAK)));
                self.reached = to;
            }
            return;
        }
        if !self.finish || self.finishing >= 2 {
            return;
        }
        let middle = (self.first + self.last) / 2.0;
        let edge = if self.finishing == 0 {
            self.first
        } else {
            self.last
        };
        self.finishing += 1;
        push(rapid(self.at(edge, self.lift)));
        push(cut(self.at(edge, self.bottom), None));
        push(cut(self.at(middle, self.bottom), None));
        push(rapid(self.at(middle, self.lift)));
    }
}

/// The groove of a CYCLE93 call, its parameters checked; `width` the tool's.
pub(super) fn groove(l: &Lathe, width: f64) -> R<Groove> {
    let vari = l.whole(VARI, 1, 18, "VARI")? % 10;
    if !(1..=8).contains(&vari) {
        return Err(l.bad(VARI, "VARI: 1 … 8 or 11 … 18"));
    }
    if l.p.get(STA1) != 0.0 {
        return Err(l.not_built(
            STA1,
            "STA1: a groove on an inclined contour is not supported",
        ));
    }
    if let Some((k, name)) = SHAPE.iter().find(|(k, _)| l.p.get(*k) != 0.0) {
        return Err(l.not_built(
            *k,
            format!("{name}: flank angles, radii and chamfers of a groove are not supported"),
        ));
    }
    let (wide, deep) = (l.len(WIDG), l.len(DIAG));
    let (fal1, fal2) = (l.len(FAL1), l.len(FAL2));
    if deep <= fal1 {
        return Err(l.bad(DIAG, "the groove depth DIAG must be greater than FAL1"));
    }
    if width <= 0.0 || width > wide - 2.0 * fal2 + 1e-9 {
        return Err(l.bad(
            WIDG,
            format!("the tool ({width} wide) does not fit the groove WIDG less 2·FAL2"),
        ));
    }
    if l.feed <= 0.0 {
        return Err(fault(AlarmCode::NoFeed, l.p.call, "CYCLE93 needs a feed F"));
    }
    let dwell = dwell(l)?;
    let face = vari % 2 == 0;
    let outside = matches!(vari, 1 | 2 | 5 | 6);
    let left = vari <= 4;
    let corner = l.point(SPL, SPD);
    let (along, across) = if face { (0, 2) } else { (2, 0) };
    let (way, into) = match (face, outside, left) {
        (false, o, lft) => (if lft { 1.0 } else { -1.0 }, if o { -1.0 } else { 1.0 }),
        (true, o, lft) => (if o { -1.0 } else { 1.0 }, if lft { 1.0 } else { -1.0 }),
    };
    let surface = corner[across];
    let lift_by = if l.p.given(VRT) { l.len(VRT) } else { LIFT_OFF };
    let first = corner[along];
    let last = first + way * (wide - width);
    let span = wide - 2.0 * fal2 - width;
    let plunges = libm::ceil((span / width).min(1e9) - 1e-9).max(0.0) as u32 + 1;
    let step = if plunges > 1 {
        way * span / f64::from(plunges - 1)
    } else {
        0.0
    };
    let lift = surface - into * lift_by;
    Ok(Groove {
        along,
        across,
        into,
        lift,
        rough: surface + into * (deep - fal1),
        bottom: surface + into * deep,
        first,
        last,
        from: first + way * fal2,
        step,
        plunges,
        infeed: l.len(IDEP),
        dwell,
        finish: fal1 > 0.0 || fal2 > 0.0,
        y: l.at[1],
        surface,
        k: 0,
        reached: surface,
        finishing: 0,
    })
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
    use super::super::lathe::tests::{alarm, lathe, moves, How, How::*};
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
    fn what_is_not_built_and_what_contradicts_is_an_alarm() {
        let at = |call: &str| alarm(&format!("{START}{call}\n"));
        // A flank angle ANG1 (column 28) and an inclined contour STA1 (column 25).
        assert_eq!(
            at("CYCLE93(40, -10, 10, 5, 0, 15, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1)"),
            (AlarmCode::NotSupported, 3, 28)
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
