//! Jerk-limited motion along the path: one dimension, the path length s.
//!
//! A [`Profile`] is a short list of phases of constant jerk from a start state (v0, a0); after
//! its last phase the velocity stays (acceleration 0). Velocity changes are the classic
//! three-phase S curve: jerk up to a peak acceleration, hold it, jerk back to 0. Sampling a
//! profile at the IPO cycle gives positions whose finite differences stay within the limits
//! the profile was built with (mean value theorem: a difference quotient of order k is the
//! k-th derivative at some point in between).
//!
//! Everything here is plain arithmetic and `sqrt` (correctly rounded): bit-identical results
//! on every x86-64 machine. No allocation.

/// Path acceleration (mm/s²) and jerk (mm/s³) limits of one segment, both > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dynamics {
    pub a: f64,
    pub j: f64,
}

/// A phase of constant jerk `j` lasting `t` seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phase {
    pub t: f64,
    pub j: f64,
}

const MAX_PHASES: usize = 7;

/// Phases of constant jerk from (s = 0, v0, a0) at time 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    n: usize,
    jerk: [f64; MAX_PHASES],
    /// State at the start of each phase, and after the last: time, s, v, a.
    t: [f64; MAX_PHASES + 1],
    s: [f64; MAX_PHASES + 1],
    v: [f64; MAX_PHASES + 1],
    a: [f64; MAX_PHASES + 1],
}

/// State after `t` seconds of jerk `j` from (s, v, a).
#[inline]
fn integrate(s: f64, v: f64, a: f64, j: f64, t: f64) -> (f64, f64, f64) {
    (
        s + t * (v + t * (a / 2.0 + t * j / 6.0)),
        v + t * (a + t * j / 2.0),
        a + t * j,
    )
}

impl Profile {
    /// Rest at (v0, a0): no phases yet.
    pub fn new(v0: f64, a0: f64) -> Self {
        let mut p = Profile {
            n: 0,
            jerk: [0.0; MAX_PHASES],
            t: [0.0; MAX_PHASES + 1],
            s: [0.0; MAX_PHASES + 1],
            v: [0.0; MAX_PHASES + 1],
            a: [0.0; MAX_PHASES + 1],
        };
        p.v[0] = v0;
        p.a[0] = a0;
        p
    }

    /// Appends phases; zero-length ones are skipped.
    pub fn push(&mut self, phases: &[Phase]) {
        for ph in phases {
            if ph.t.is_nan() || ph.t <= 0.0 || self.n == MAX_PHASES {
                continue;
            }
            let i = self.n;
            let (s, v, a) = integrate(self.s[i], self.v[i], self.a[i], ph.j, ph.t);
            self.jerk[i] = ph.j;
            self.t[i + 1] = self.t[i] + ph.t;
            self.s[i + 1] = s;
            self.v[i + 1] = v;
            self.a[i + 1] = a;
            self.n += 1;
        }
    }

    /// Time until the last phase ends.
    pub fn duration(&self) -> f64 {
        self.t[self.n]
    }

    /// Distance covered by the phases.
    pub fn distance(&self) -> f64 {
        self.s[self.n]
    }

    #[cfg(test)]
    pub fn end_velocity(&self) -> f64 {
        self.v[self.n]
    }

    /// (s, v, a) at time `tau` ≥ 0; after the phases the end velocity holds.
    pub fn at(&self, tau: f64) -> (f64, f64, f64) {
        let mut i = 0;
        while i < self.n && tau >= self.t[i + 1] {
            i += 1;
        }
        let dt = tau - self.t[i];
        if i == self.n {
            // The phases' end acceleration is 0 up to rounding: what follows is a cruise.
            return (self.s[i] + self.v[i] * dt, self.v[i], 0.0);
        }
        integrate(self.s[i], self.v[i], self.a[i], self.jerk[i], dt)
    }

    /// The first time the profile has covered `d` (≤ its distance, or reached by the cruise
    /// after it); `None` if it never does (it ends at rest before `d`).
    pub fn time_at(&self, d: f64) -> Option<f64> {
        let mut i = 0;
        while i < self.n && self.s[i + 1] < d {
            i += 1;
        }
        if i == self.n {
            if self.s[i] >= d {
                return Some(self.t[i]);
            }
            let v = self.v[i];
            return (v > 0.0).then(|| self.t[i] + (d - self.s[i]) / v);
        }
        // s is monotone within the phase (v ≥ 0): bisection to the last bit.
        let (mut lo, mut hi) = (0.0, self.t[i + 1] - self.t[i]);
        for _ in 0..64 {
            let m = 0.5 * (lo + hi);
            if m <= lo || m >= hi {
                break;
            }
            let (s, _, _) = integrate(self.s[i], self.v[i], self.a[i], self.jerk[i], m);
            if s < d {
                lo = m;
            } else {
                hi = m;
            }
        }
        Some(self.t[i] + hi)
    }
}

/// The fastest change from (v0, a0) to velocity v1 with acceleration 0 at the end: jerk
/// towards a peak acceleration, hold it, jerk back to 0 (three phases, some may be empty).
pub fn change(v0: f64, a0: f64, v1: f64, d: Dynamics) -> [Phase; 3] {
    // The velocity reached by bringing the acceleration to 0 at once.
    let vr = v0 + a0 * a0.abs() / (2.0 * d.j);
    if v1 == vr {
        return [
            Phase {
                t: a0.abs() / d.j,
                j: -a0.signum() * d.j,
            },
            Phase::default(),
            Phase::default(),
        ];
    }
    // Solved as an acceleration; a deceleration is the same with the signs turned.
    let sg = if v1 > vr { 1.0 } else { -1.0 };
    let a0s = sg * a0;
    let dv = sg * (v1 - v0);
    let free = (d.j * dv + 0.5 * a0s * a0s).max(0.0).sqrt();
    let p = free.min(d.a).max(a0s);
    let hold = if p < free {
        ((dv - (2.0 * p * p - a0s * a0s) / (2.0 * d.j)) / p).max(0.0)
    } else {
        0.0
    };
    [
        Phase {
            t: ((p - a0s) / d.j).max(0.0),
            j: sg * d.j,
        },
        Phase { t: hold, j: 0.0 },
        Phase {
            t: p / d.j,
            j: -sg * d.j,
        },
    ]
}

/// Distance covered by `phases` from (v0, a0).
pub fn distance(v0: f64, a0: f64, phases: &[Phase]) -> f64 {
    let (mut s, mut v, mut a) = (0.0, v0, a0);
    for ph in phases {
        if ph.t > 0.0 {
            (s, v, a) = integrate(s, v, a, ph.j, ph.t);
        }
    }
    s
}

/// Distance of the fastest change from (v0, a0) to v1.
pub fn change_distance(v0: f64, a0: f64, v1: f64, d: Dynamics) -> f64 {
    distance(v0, a0, &change(v0, a0, v1, d))
}

/// The highest velocity at the start of a segment of length `len` (acceleration 0 there)
/// from which the velocity can still come down to `ve` at its end: the symmetric S curve
/// from v to ve covers (v + ve)/2 · its duration. Closed form, for the lookahead's backward
/// pass.
pub fn reach(ve: f64, len: f64, d: Dynamics) -> f64 {
    if len.is_nan() || len <= 0.0 {
        return ve;
    }
    // Δ = v − ve < a²/j: no constant-acceleration phase; with x = √Δ,
    // (2·ve + x²)·x/√j = len, a cubic x³ + p·x − q = 0 with one real root.
    let x = cubic_root(2.0 * ve, len * d.j.sqrt());
    let dv = x * x;
    if dv <= d.a * d.a / d.j {
        return ve + dv;
    }
    // With a hold at full acceleration: (ve + Δ/2)(Δ/a + a/j) = len, a quadratic in Δ.
    let qa = 1.0 / (2.0 * d.a);
    let qb = d.a / (2.0 * d.j) + ve / d.a;
    let qc = ve * d.a / d.j - len;
    let disc = (qb * qb - 4.0 * qa * qc).max(0.0).sqrt();
    let dv = if qc < 0.0 {
        -2.0 * qc / (qb + disc)
    } else {
        (disc - qb) / (2.0 * qa)
    };
    ve + dv.max(0.0)
}

/// The real root of x³ + p·x − q = 0 for p, q ≥ 0 (there is one, ≥ 0): Cardano, then Newton
/// to polish the cancellation in w − p/(3w).
pub fn cubic_root(p: f64, q: f64) -> f64 {
    let w = libm::cbrt(q / 2.0 + (q * q / 4.0 + p * p * p / 27.0).sqrt());
    let mut x = if w > 0.0 { w - p / (3.0 * w) } else { 0.0 };
    for _ in 0..3 {
        let df = 3.0 * x * x + p;
        if df > 0.0 {
            x -= (x * x * x + p * x - q) / df;
        }
    }
    x.max(0.0)
}

/// Rounding allowance on a segment's length, relative (absolute in mm below 1 mm, as the
/// planner's test for a plan that ended on its segment's end): a plan that overruns the
/// length by no more than this fits (the planner ends the segment where the plan crosses
/// its length).
pub const FIT: f64 = 1e-9;

/// The plan for one segment of length `len` entered at (v0, a0): as fast as `vmax` allows,
/// ending at `ve` with acceleration 0 where the length allows it. Returns the profile and the
/// velocity it really ends at: lower than `ve` where the segment is too short to accelerate
/// to it, higher where it is too short to brake to it. In the rare case that even bringing
/// the acceleration to 0 needs more than `len`, the profile runs past `len` and the caller
/// hands over to the next segment where it crosses `len`.
pub fn plan(v0: f64, a0: f64, len: f64, vmax: f64, ve: f64, d: Dynamics) -> (Profile, f64) {
    let ve = ve.max(0.0);
    let mut prof = Profile::new(v0, a0);
    let direct = |w: f64| change_distance(v0, a0, w, d);
    let vr = v0 + a0 * a0.abs() / (2.0 * d.j);
    // The lookahead enters a segment at the speed `reach` allows to the last bit, so the
    // change to `ve` may come out longer than `len` by rounding: that still fits. (Taken as
    // too short, the end speed below would be the far root of a distance that is not
    // monotone in it: a stop from v0 needs less room than slowing to v0/3 with a = 0.)
    if direct(ve) > len + FIT * len.max(1.0) {
        if vr < 0.0 || direct(vr) >= len {
            let w = vr.max(0.0);
            prof.push(&change(v0, a0, w, d));
            return (prof, w);
        }
        // The end velocity the length allows: between ve and vr, direct(w) is monotone.
        let (mut far, mut near) = (ve, vr);
        for _ in 0..60 {
            let m = 0.5 * (far + near);
            if direct(m) > len {
                far = m;
            } else {
                near = m;
            }
        }
        prof.push(&change(v0, a0, near, d));
        if near > 0.0 {
            let rest = (len - prof.distance()).max(0.0);
            prof.push(&[Phase {
                t: rest / near,
                j: 0.0,
            }]);
        }
        return (prof, near);
    }
    // Up (or down) to vm, cruise, down to ve: the highest vm whose changes fit.
    let f = |m: f64| direct(m) + change_distance(m, 0.0, ve, d);
    let top = vmax.max(ve);
    let vm = if f(top) <= len {
        top
    } else {
        // f(ve) = direct(ve) ≤ len < f(top): bisection keeps that bracket, so it ends at a
        // vm that fits even where f is not monotone (after a replan that must brake).
        let (mut lo, mut hi) = (ve, top);
        for _ in 0..48 {
            let m = 0.5 * (lo + hi);
            if f(m) <= len {
                lo = m;
            } else {
                hi = m;
            }
        }
        lo
    };
    prof.push(&change(v0, a0, vm, d));
    let down = change(vm, 0.0, ve, d);
    let rest = len - prof.distance() - distance(vm, 0.0, &down);
    // A rest within the rounding allowance is no cruise: where the changes alone cover the
    // length, vm is ve plus rounding, and that rest at that speed would be a crawl of
    // invisible steps (a path speed without motion).
    if vm > 0.0 && rest > FIT * len.max(1.0) {
        prof.push(&[Phase {
            t: rest / vm,
            j: 0.0,
        }]);
    }
    prof.push(&down);
    (prof, ve)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const D: Dynamics = Dynamics {
        a: 1500.0,
        j: 25_000.0,
    };

    #[test]
    fn an_s_curve_from_rest_by_hand() {
        // 0 → 100 mm/s with a = 1500, j = 25000: a²/j = 90 mm/s < 100, so the curve holds
        // full acceleration: jerk 0.06 s, hold (100 − 90)/1500 s, jerk 0.06 s. Its distance
        // is the mean velocity times the duration: 50 · (0.12 + 1/150).
        let ph = change(0.0, 0.0, 100.0, D);
        assert!((ph[0].t - 0.06).abs() < 1e-15 && (ph[2].t - 0.06).abs() < 1e-15);
        assert!((ph[1].t - 10.0 / 1500.0).abs() < 1e-15);
        let d = distance(0.0, 0.0, &ph);
        assert!((d - 50.0 * (0.12 + 1.0 / 150.0)).abs() < 1e-12, "{d}");
        // Small change: no hold, peak √(j·Δv).
        let ph = change(10.0, 0.0, 14.0, D);
        assert_eq!(ph[1].t, 0.0);
        assert!((ph[0].t - (4.0f64 / 25_000.0).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn reach_inverts_the_s_curve_distance() {
        for &(ve, len) in &[
            (0.0, 0.001),
            (0.0, 5.0),
            (20.0, 0.3),
            (100.0, 40.0),
            (0.0, 500.0),
        ] {
            let v = reach(ve, len, D);
            let d = change_distance(v, 0.0, ve, D);
            assert!(
                (d - len).abs() < 1e-9 * len.max(1.0),
                "ve {ve} len {len}: v {v} d {d}"
            );
        }
    }

    #[test]
    fn a_short_segment_brakes_to_its_end_exactly() {
        // 100 mm/s into a 10 mm segment that must end at rest (braking takes 6.33 mm).
        let (p, ve) = plan(100.0, 0.0, 10.0, 100.0, 0.0, D);
        assert_eq!(ve, 0.0);
        assert!((p.distance() - 10.0).abs() < 1e-12);
        assert!(p.end_velocity().abs() < 1e-12);
        let (s, v, _) = p.at(p.duration() + 1.0);
        assert!((s - 10.0).abs() < 1e-12 && v.abs() < 1e-12);
    }

    #[test]
    fn a_segment_entered_at_its_reach_speed_ends_at_rest() {
        // The lookahead's numbers from a 0.25 mm step at F2000 (a = 2000, j = 37 500): the
        // last segment before an alarm entered 6.8e-15 above reach(0, 0.25). That is a fit,
        // not a segment too short to brake (which ended at 492 mm/min with nothing after it).
        let d = Dynamics {
            a: 2000.0,
            j: 37_500.0,
        };
        let v0 = 796.9939268869651 / 60.0;
        assert!(v0 > reach(0.0, 0.25, d));
        let (p, w) = plan(v0, -5.7e-14, 0.25, 2000.0 / 60.0, 0.0, d);
        assert_eq!(w, 0.0);
        assert!((p.distance() - 0.25).abs() < FIT);
        assert!(p.end_velocity().abs() < 1e-12);
        // A 0.8 mm Z move entered from a collinear rapid at reach(0, 0.8) (a = 1500,
        // j = 30 000): the changes alone cover the length, and what is left is rounding. A
        // cruise over that rest at the speed the bisection finds (rounding above 0) took
        // 6 ms of setpoints that did not move at 3.5e-13 mm/s.
        let d = Dynamics {
            a: 1500.0,
            j: 30_000.0,
        };
        let (len, v0) = (7.999999999999972e-1, 2.6777318003286723e1);
        let (p, w) = plan(v0, -8.640199666842818e-12, len, 100.0, 0.0, d);
        assert_eq!(w, 0.0);
        let t_stop: f64 = change(v0, 0.0, 0.0, d).iter().map(|ph| ph.t).sum();
        assert!(
            p.duration() < t_stop + 1e-6,
            "{} s, the stop {t_stop} s",
            p.duration()
        );
    }

    fn check_limits(p: &Profile, d: Dynamics) {
        let n = 400;
        for k in 0..=n {
            let t = p.duration() * k as f64 / n as f64;
            let (_, v, a) = p.at(t);
            assert!(v >= -1e-9, "v {v}");
            assert!(a.abs() <= d.a * (1.0 + 1e-9), "a {a}");
        }
        for i in 0..p.n {
            assert!(p.jerk[i].abs() <= d.j * (1.0 + 1e-12));
        }
    }

    proptest! {
        #[test]
        fn plans_cover_the_segment_and_keep_the_limits(
            v0 in 0.0..200.0f64, len in 0.001..300.0f64, vmax in 1.0..250.0f64,
            ve in 0.0..200.0f64,
        ) {
            // Entered at rest or from a feasible cruise (v0 ≤ vmax is not required: an
            // override may have dropped).
            let (p, w) = plan(v0, 0.0, len, vmax, ve.min(vmax), D);
            check_limits(&p, D);
            let end = p.distance();
            prop_assert!(end >= len - 1e-9 * len.max(1.0));
            if end <= len * (1.0 + 1e-9) + 1e-12 {
                // Fits: ends at w with a = 0.
                let (_, v, a) = p.at(p.duration());
                prop_assert!((v - w).abs() < 1e-6 * w.max(1.0), "v {} w {}", v, w);
                prop_assert!(a.abs() < 1e-9);
                // Never above the cap, unless it started above it.
                for k in 0..=200 {
                    let (_, v, _) = p.at(p.duration() * k as f64 / 200.0);
                    prop_assert!(v <= vmax.max(v0).max(w) * (1.0 + 1e-9) + 1e-9);
                }
            }
        }

        #[test]
        fn entered_at_reach_speed_a_plan_stops_on_the_length_without_crawling(
            len in 1e-4..100.0f64, ulps in -8i32..8, a0 in prop_oneof![Just(0.0), -1e-12..1e-12f64],
        ) {
            // Within rounding of the speed the backward pass allows: the plan ends at rest on
            // the segment's end (to the allowance) and takes no longer than the stop alone
            // plus one cycle: no cruise of invisible steps at a speed of rounding size.
            let v = reach(0.0, len, D);
            let v0 = v * (1.0 + f64::from(ulps) * f64::EPSILON);
            let (p, w) = plan(v0, a0, len, v0 * 2.0, 0.0, D);
            prop_assert_eq!(w, 0.0);
            prop_assert!((p.distance() - len).abs() <= len.max(1.0) * FIT, "{} of {}", p.distance(), len);
            let stop = change(v0, a0, 0.0, D);
            let t_stop: f64 = stop.iter().map(|ph| ph.t).sum();
            prop_assert!(p.duration() <= t_stop + 1e-3, "{} s, the stop takes {} s", p.duration(), t_stop);
        }

        #[test]
        fn replans_from_any_reachable_state(
            v0 in 0.0..200.0f64, a0 in -1500.0..1500.0f64, len in 0.01..300.0f64,
            vmax in 1.0..250.0f64, ve in 0.0..200.0f64,
        ) {
            // States on a plan can still stop without reversing: v ≥ a²/2j for a < 0.
            prop_assume!(a0 >= 0.0 || v0 >= a0 * a0 / (2.0 * D.j));
            let (p, _) = plan(v0, a0, len, vmax, ve.min(vmax), D);
            check_limits(&p, D);
            prop_assert!(p.time_at(len).is_some() || p.end_velocity() < 1e-9);
        }
    }
}
