//! `softnc run` while the program runs: the progress line, the first alarm, Ctrl-C, and the
//! bounds on every wait.

use super::{Hmi, Supervisor};
use nc_kernel::cycle::ChannelAlarm;
use softnc_protocol::{command, receive_each, state, AxisList, Command, KernelStatus, MAX_AXES};
use std::io::Write;
use std::time::{Duration, Instant};

/// How long the path may take to come to rest after NC stop before the run stops waiting
/// for the kernel (braking from top speed takes well under a second on every shipped
/// machine); plc-sim's watchdog brakes the axes of a kernel that is ended then.
const REST_AFTER_STOP: Duration = Duration::from_secs(10);
/// The kernel publishes its status every IPO cycle: silence this long means it hangs.
const STATUS_SILENCE: Duration = Duration::from_secs(3);

/// The program running: the progress line, the first alarm, Ctrl-C.
pub(super) struct Watch {
    quiet: bool,
    total_lines: u32,
    /// The first cycle seen ACTIVE, and the first alarm.
    pub first_cycle: Option<u64>,
    pub alarm: Option<ChannelAlarm>,
    /// When NC stop was sent for Ctrl-C.
    stop_sent: Option<Instant>,
    shown: Instant,
    heard: Instant,
}

impl Watch {
    pub fn new(source: &str, quiet: bool) -> Self {
        Watch {
            quiet,
            total_lines: source.lines().count().max(1) as u32,
            first_cycle: None,
            alarm: None,
            stop_sent: None,
            shown: Instant::now() - Duration::from_secs(1),
            heard: Instant::now(),
        }
    }

    /// Follows the status until the program ends (`Ok(true)`), stops with an alarm or for
    /// Ctrl-C (`Ok(false)`), or the control fails: a child ends, the kernel falls silent,
    /// the path does not come to rest after NC stop, or a second Ctrl-C. Every way ends.
    pub fn run(
        &mut self,
        hmi: &Hmi,
        run: &mut Supervisor<'_>,
        last: &mut KernelStatus,
    ) -> Result<bool, String> {
        loop {
            run.check_children()?;
            receive_each(&hmi.status, |s| {
                *last = s;
                self.heard = Instant::now();
                if s.state == state::ACTIVE && self.first_cycle.is_none() {
                    self.first_cycle = Some(s.cycle);
                }
            });
            if self.heard.elapsed() > STATUS_SILENCE {
                return Err(format!(
                    "nc-kernel published no status for {} s: it hangs; ending the processes",
                    STATUS_SILENCE.as_secs()
                ));
            }
            let alarm = ChannelAlarm::new(last.alarm);
            if let Some(a) = alarm.filter(|_| self.alarm.is_none()) {
                self.alarm = Some(a);
                if !self.quiet {
                    eprintln!("\ralarm {a} at line {}              ", last.line);
                }
            }
            self.interrupt(hmi, run.interrupts())?;
            self.progress(last);
            match last.state {
                state::END => return Ok(true),
                state::STOPPED if alarm.is_some() || self.stop_sent.is_some() => return Ok(false),
                _ => {}
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Ctrl-C: NC stop once; an error when the path does not come to rest in time or a
    /// second Ctrl-C comes.
    fn interrupt(&mut self, hmi: &Hmi, interrupts: u32) -> Result<(), String> {
        match self.stop_sent {
            None if interrupts > 0 => {
                self.stop_sent = Some(Instant::now());
                eprintln!("\rinterrupted: NC stop, the axes brake … (Ctrl-C again ends at once)");
                let _ = hmi.ask(Command::new(command::STOP), Duration::from_secs(2));
                Ok(())
            }
            Some(_) if interrupts > 1 => Err("interrupted twice: ending the processes without waiting for the path to rest (plc-sim brakes the axes)".into()),
            Some(t) if t.elapsed() > REST_AFTER_STOP => Err(format!(
                "the path did not come to rest within {} s of NC stop: ending the processes (plc-sim brakes the axes)",
                REST_AFTER_STOP.as_secs()
            )),
            _ => Ok(()),
        }
    }

    fn progress(&mut self, last: &KernelStatus) {
        if self.quiet || self.shown.elapsed() <= Duration::from_millis(100) {
            return;
        }
        self.shown = Instant::now();
        let total = self.total_lines;
        let frac = (f64::from(last.line) / f64::from(total)).min(1.0);
        let n = (frac * 30.0) as usize;
        eprint!(
            "\r[{}{}] line {:>5}/{total}  {:<7}  {} {:>7.0} mm/min",
            "#".repeat(n),
            " ".repeat(30 - n),
            last.line,
            state::name(last.state),
            positions(&last.axes, &last.pos),
            last.v_path * 60.0
        );
        let _ = std::io::stderr().flush();
    }
}

/// Every configured axis with its position, as the operator reads it: a modulo axis within
/// 0…360°.
pub(super) fn positions(axes: &AxisList, pos: &[f64; MAX_AXES]) -> String {
    let mut out = String::new();
    for (n, (name, p)) in axes.names().zip(pos).enumerate() {
        let shown = if axes.modulo(n) {
            p.rem_euclid(360.0)
        } else {
            *p
        };
        out.push_str(&format!("{name}{shown:>9.3} "));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_axis_is_shown_by_name_a_modulo_one_within_a_turn() {
        let mut axes = AxisList::default();
        axes.names[..3].copy_from_slice(b"XZC");
        axes.count = 3;
        axes.kinds = 1 << 2 | 1 << (8 + 2);
        let mut pos = [0.0; MAX_AXES];
        pos[..3].copy_from_slice(&[12.5, -3.0, 370.0]);
        assert_eq!(positions(&axes, &pos), "X   12.500 Z   -3.000 C   10.000 ");
    }
}
