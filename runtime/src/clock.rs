//! The IPO cycle's clock: cycle starts at absolute times t0 + n·T on the monotonic clock.
//!
//! A cycle that starts a full period or more late (the thread, or the whole VM, was held up)
//! does not make up the periods it missed in a burst of cycles: they are skipped and
//! counted. A burst would put many setpoints into one instant — the axes would jump, the
//! PLC's queue would overflow — and it would count the PLC's silence during the hold-up,
//! when the PLC could not run either, as missed signs of life: a false watchdog alarm.
//! Skipped, the path pauses for the hold-up and every consumer still gets one setpoint per
//! period.

use crate::os;

/// When one cycle started.
#[derive(Clone, Copy, Debug)]
pub struct Tick {
    /// The planned start of the cycle, ns.
    pub start: u64,
    /// When the thread woke for it, ns.
    pub woke: u64,
    /// The end of the cycle: its setpoint is due at the PLC by then.
    pub deadline: u64,
}

pub struct CycleClock {
    t0: u64,
    period: u64,
    slot: u64,
    skipped: u64,
}

impl CycleClock {
    /// The first cycle starts one period from now.
    pub fn new(period_ns: u64) -> Self {
        Self::starting_at(os::now_ns() + period_ns, period_ns)
    }

    pub fn starting_at(t0: u64, period_ns: u64) -> Self {
        CycleClock {
            t0,
            period: period_ns.max(1),
            slot: 0,
            skipped: 0,
        }
    }

    /// Sleeps until the next cycle starts.
    pub fn wait(&mut self) -> Tick {
        let start = self.t0 + self.slot * self.period;
        os::sleep_until(start);
        let woke = os::now_ns();
        self.advance(start, woke)
    }

    /// The cycle planned for `start` began at `woke`: the next one is the first period
    /// start after `woke`.
    fn advance(&mut self, start: u64, woke: u64) -> Tick {
        let behind = woke.saturating_sub(start) / self.period;
        self.skipped += behind;
        self.slot += behind + 1;
        Tick {
            start,
            woke,
            deadline: start + self.period,
        }
    }

    /// Periods skipped so far.
    pub fn skipped(&self) -> u64 {
        self.skipped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn on_time_cycles_follow_each_other_and_a_hold_up_skips_what_it_missed() {
        let mut c = CycleClock::starting_at(1_000, 100);
        let t = c.advance(1_000, 1_030);
        assert_eq!((t.start, t.deadline, c.skipped()), (1_000, 1_100, 0));
        // 99 ns late is still this cycle, no skip.
        let t = c.advance(1_100, 1_199);
        assert_eq!((t.start, c.skipped(), c.slot), (1_100, 0, 2));
        // Woken 3.5 periods late: three periods skipped, the next cycle at the next start.
        let t = c.advance(1_200, 1_550);
        assert_eq!((t.deadline, c.skipped(), c.slot), (1_300, 3, 6));
        assert_eq!(c.t0 + c.slot * c.period, 1_600);
    }
}
