//! The machine's spindle drives (docs/spindle.md): each configured spindle follows the
//! kernel's newest speed setpoint at `plc.spindle_acceleration`, and says what an auxiliary
//! function waits for of it: at speed (a drive's n_act = n_set signal), at rest, oriented.
//!
//! The ramp is the kernel's `SpindleModel`, so plc-sim's actual speed and the model
//! `softnc simulate` runs without a PLC agree.
//! Everything is a fixed array of `MAX_SPINDLES`: a drive cycle allocates nothing.

use nc_kernel::ipo::SpindleModel;
use softnc_protocol::{spindle_mode, SetpointMsg, MAX_SPINDLES};
use std::ops::BitOrAssign;

/// A speed per spindle, rev/min, signed as the setpoint (positive clockwise, M3).
pub type Spindles = [f64; MAX_SPINDLES];

/// Spindles the machine data configures: the main spindle (`[spindle]`, one today). The
/// trace's columns are made from it at the start, before a setpoint says how many the
/// kernel drives.
pub const CONFIGURED: usize = 1;

/// rev/min: a spindle at most this fast stands; and one within this of its setpoint, or
/// within [`AT_SPEED_SHARE`] of it if that is more, is at speed. Exact equality would never
/// come from a real drive's speed measurement, and a window of a share keeps high speeds
/// from waiting on the last fraction of a ramp.
const STANDSTILL_RPM: f64 = 1.0;
const AT_SPEED_SHARE: f64 = 0.005;

/// Conditions on the main spindle a request waits for, each dropped once it has held.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Waits(u8);

impl Waits {
    pub const NONE: Waits = Waits(0);
    /// At speed: the actual speed within the window of the setpoint (M3, M4, S).
    pub const AT_SPEED: Waits = Waits(1);
    /// At rest (M5).
    pub const STOPPED: Waits = Waits(2);
    /// At rest, told to orient (M19).
    pub const ORIENTED: Waits = Waits(4);

    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    fn without(self, w: Waits, holds: bool) -> Waits {
        if holds {
            Waits(self.0 & !w.0)
        } else {
            self
        }
    }
}

impl BitOrAssign for Waits {
    fn bitor_assign(&mut self, w: Waits) {
        self.0 |= w.0;
    }
}

/// The spindle drives: what each was last told and how fast it turns.
#[derive(Clone, Copy, Debug)]
pub struct SpindleDrives {
    /// `spindle_mode::*` of the newest setpoint.
    mode: [u8; MAX_SPINDLES],
    /// The speed each drive follows: the kernel's while it is told to turn, else 0.
    setpoint: Spindles,
    drive: [SpindleModel; MAX_SPINDLES],
}

impl SpindleDrives {
    /// Drives standing, accelerating at `acceleration` rev/min per s in cycles of `cycle_s`.
    pub fn new(acceleration: f64, cycle_s: f64) -> Self {
        SpindleDrives {
            mode: [spindle_mode::STOP; MAX_SPINDLES],
            setpoint: [0.0; MAX_SPINDLES],
            drive: [SpindleModel::new(acceleration, cycle_s); MAX_SPINDLES],
        }
    }

    /// One drive cycle with the setpoint `sp`: each spindle it configures (`spindles`) ramps
    /// towards its speed when told to turn, to rest when told to stop or orient; one past
    /// its count is no longer driven and comes to rest. While `brake` (the watchdog), every
    /// spindle comes to rest whatever the setpoint says, as the axes do.
    pub fn follow(&mut self, sp: &SetpointMsg, brake: bool) {
        let count = usize::from(sp.spindles).min(MAX_SPINDLES);
        for i in 0..MAX_SPINDLES {
            let mode = if i < count {
                sp.spindle_mode[i]
            } else {
                spindle_mode::STOP
            };
            // A speed that is no number (a peer's fault) stops the spindle rather than
            // turning it at an unknown speed.
            let turn = mode == spindle_mode::TURN && sp.spindle[i].is_finite();
            self.mode[i] = mode;
            self.setpoint[i] = if turn { sp.spindle[i] } else { 0.0 };
            self.drive[i].follow(if brake { 0.0 } else { self.setpoint[i] });
        }
    }

    /// One drive cycle bringing every spindle to rest (the watchdog, no setpoint).
    pub fn brake(&mut self) {
        for d in &mut self.drive {
            d.follow(0.0);
        }
    }

    /// The speed each drive follows, rev/min.
    pub fn setpoint(&self) -> Spindles {
        self.setpoint
    }

    /// The actual speeds, rev/min.
    pub fn actual(&self) -> Spindles {
        self.drive.map(|d| d.rpm())
    }

    /// The main spindle is told to turn (an S word then waits for the new speed).
    pub fn turning(&self) -> bool {
        self.mode[0] == spindle_mode::TURN
    }

    /// Which of `waits` still do not hold. They are the main spindle's: an auxiliary
    /// function on the wire names no spindle. `idle`: the kernel runs no program (RESET,
    /// END), so nothing is to be oriented any more and an M19 is done once the spindle
    /// stands; otherwise it would wait for ever and hold the kernel's request port.
    pub fn open(&self, waits: Waits, idle: bool) -> Waits {
        let (set, act) = (self.setpoint[0], self.drive[0].rpm());
        let stopped = act.abs() <= STANDSTILL_RPM;
        let window = STANDSTILL_RPM.max(AT_SPEED_SHARE * set.abs());
        let oriented = stopped && (self.mode[0] == spindle_mode::ORIENT || idle);
        waits
            .without(Waits::AT_SPEED, (act - set).abs() <= window)
            .without(Waits::STOPPED, stopped)
            .without(Waits::ORIENTED, oriented)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setpoint(mode: u8, speed: f64) -> SetpointMsg {
        SetpointMsg {
            spindles: 1,
            spindle_mode: [mode, spindle_mode::STOP],
            spindle: [speed, 0.0],
            ..Default::default()
        }
    }

    /// 6000 rev/min per s in 1 ms cycles: 6 rev/min a cycle; 1000 is within its window
    /// (5 rev/min, 0.5 %) at 996, after 166 cycles, and reached after 167.
    #[test]
    fn a_drive_ramps_by_its_step_and_is_at_speed_within_the_window() {
        let mut d = SpindleDrives::new(6000.0, 0.001);
        let sp = setpoint(spindle_mode::TURN, 1000.0);
        for k in 1..=165 {
            d.follow(&sp, false);
            assert_eq!(d.actual()[0], 6.0 * k as f64);
            assert_eq!(d.open(Waits::AT_SPEED, false), Waits::AT_SPEED, "cycle {k}");
        }
        d.follow(&sp, false);
        assert_eq!(d.actual()[0], 996.0);
        assert!(d.open(Waits::AT_SPEED, false).is_empty());
        d.follow(&sp, false);
        assert_eq!(d.actual(), [1000.0, 0.0]);
        assert!(d.turning());
    }

    /// Told to orient, the drive comes to rest and is then oriented; told to stop, it is
    /// oriented only when the kernel runs no program.
    #[test]
    fn orientation_holds_at_rest_when_told_or_when_the_kernel_is_idle() {
        let mut d = SpindleDrives::new(6000.0, 0.001);
        for _ in 0..2 {
            d.follow(&setpoint(spindle_mode::TURN, 12.0), false);
        }
        d.follow(&setpoint(spindle_mode::ORIENT, 500.0), false);
        assert_eq!((d.setpoint()[0], d.actual()[0]), (0.0, 6.0));
        let all = {
            let mut w = Waits::STOPPED;
            w |= Waits::ORIENTED;
            w
        };
        assert_eq!(d.open(all, false), all);
        d.follow(&setpoint(spindle_mode::ORIENT, 0.0), false);
        assert!(d.open(all, false).is_empty());
        d.follow(&setpoint(spindle_mode::STOP, 0.0), false);
        assert_eq!(d.open(Waits::ORIENTED, false), Waits::ORIENTED);
        assert!(d.open(Waits::ORIENTED, true).is_empty());
    }

    /// A speed that is no number stops the spindle; braking ignores the setpoint; a spindle
    /// past the setpoint's count comes to rest.
    #[test]
    fn bad_speeds_braking_and_unconfigured_spindles_come_to_rest() {
        let mut d = SpindleDrives::new(6000.0, 0.001);
        let mut two = setpoint(spindle_mode::TURN, 600.0);
        two.spindles = 2;
        two.spindle_mode[1] = spindle_mode::TURN;
        two.spindle[1] = -600.0;
        for _ in 0..100 {
            d.follow(&two, false);
        }
        assert_eq!(d.actual(), [600.0, -600.0]);
        d.follow(&setpoint(spindle_mode::TURN, f64::NAN), false);
        assert_eq!(d.setpoint(), [0.0, 0.0]);
        assert_eq!(d.actual(), [594.0, -594.0]);
        d.follow(&two, true);
        assert_eq!(d.actual(), [588.0, -588.0]);
        d.brake();
        assert_eq!(d.actual(), [582.0, -582.0]);
    }
}
