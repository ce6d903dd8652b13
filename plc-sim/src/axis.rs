//! A feed axis as the PLC's drives see it: a dead time, then a proportional position loop
//! (gain kv) whose velocity command is limited in speed and acceleration.
//!
//! Each cycle the drive measures its position, compares it with the setpoint that left the
//! dead time, and moves with the resulting velocity for one cycle:
//!
//! ```text
//!   e_n = s_{n−d} − x_n          (following error, the control deviation)
//!   v_n = clamp(kv·e_n)          (|v| ≤ v_max, |v_n − v_{n−1}| ≤ a_max·T)
//!   x_{n+1} = x_n + T·v_n
//! ```
//!
//! On a ramp s = v·t the error settles at e = v/kv exactly (e_{n+1} = (1 − kv·T)·e_n + v·T),
//! and x is an average of past setpoints, so it never leaves the path by more than e.

/// Longest dead time, cycles.
pub const MAX_DEAD_TIME: usize = 100;

#[derive(Clone, Debug)]
pub struct Axis {
    kv: f64,
    t: f64,
    v_max: f64,
    a_max: f64,
    delay: std::collections::VecDeque<f64>,
    dead: usize,
    pub pos: f64,
    pub vel: f64,
    /// Setpoint at the loop's input (after the dead time) minus the measured position.
    pub following_error: f64,
}

impl Axis {
    /// `v_max` mm/s, `a_max` mm/s², cycle `t` s, standing at `pos`.
    pub fn new(kv: f64, t: f64, v_max: f64, a_max: f64, dead: usize, pos: f64) -> Self {
        let dead = dead.min(MAX_DEAD_TIME);
        let mut delay = std::collections::VecDeque::with_capacity(dead + 1);
        delay.extend(std::iter::repeat_n(pos, dead));
        Axis {
            kv,
            t,
            v_max,
            a_max,
            delay,
            dead,
            pos,
            vel: 0.0,
            following_error: 0.0,
        }
    }

    /// One cycle with setpoint `s`; returns the position measured at its start.
    pub fn step(&mut self, s: f64) -> f64 {
        self.delay.push_back(s);
        let target = if self.delay.len() > self.dead {
            self.delay.pop_front().unwrap_or(s)
        } else {
            s
        };
        let measured = self.pos;
        self.following_error = target - measured;
        let wanted = (self.kv * self.following_error).clamp(-self.v_max, self.v_max);
        let dv = self.a_max * self.t;
        self.vel = wanted.clamp(self.vel - dv, self.vel + dv);
        self.pos += self.vel * self.t;
        measured
    }

    /// One cycle braking at the acceleration limit, setpoints ignored (watchdog).
    pub fn brake(&mut self) -> f64 {
        let measured = self.pos;
        let dv = self.a_max * self.t;
        self.vel = if self.vel.abs() <= dv {
            0.0
        } else {
            self.vel - dv * self.vel.signum()
        };
        self.pos += self.vel * self.t;
        self.following_error = 0.0;
        // Whatever is in the dead time is stale now.
        let p = self.pos;
        for x in self.delay.iter_mut() {
            *x = p;
        }
        measured
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn following_error_settles_at_v_over_kv() {
        // kv 16.667/s, 1 ms, 100 mm/s ramp: e = 6.0 mm exactly in the limit.
        let (kv, t, v) = (16.667, 0.001, 100.0);
        let mut a = Axis::new(kv, t, 1000.0, 1e9, 1, 0.0);
        for n in 0..20_000 {
            a.step(v * t * n as f64);
        }
        assert!(
            (a.following_error - v / kv).abs() < 1e-9,
            "{}",
            a.following_error
        );
        assert!((a.vel - v).abs() < 1e-9);
    }

    #[test]
    fn dead_time_delays_the_setpoint() {
        let mut a = Axis::new(10.0, 0.001, 1000.0, 1e9, 3, 0.0);
        for _ in 0..3 {
            a.step(1.0);
            assert_eq!(a.vel, 0.0);
        }
        a.step(1.0);
        assert!((a.vel - 10.0).abs() < 1e-12);
    }

    #[test]
    fn limits_hold_and_braking_stops() {
        let mut a = Axis::new(100.0, 0.001, 50.0, 1000.0, 0, 0.0);
        let mut last = 0.0;
        for _ in 0..1000 {
            a.step(100.0);
            assert!(a.vel <= 50.0 + 1e-12);
            assert!(a.vel - last <= 1.0 + 1e-12);
            last = a.vel;
        }
        let mut n = 0;
        while a.vel != 0.0 {
            a.brake();
            n += 1;
        }
        assert_eq!(n, 50); // 50 mm/s at 1000 mm/s²: 50 ms
    }
}
