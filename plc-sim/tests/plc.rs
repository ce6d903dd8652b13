//! The simulated PLC's reactions on a mock transport and a mock clock, without iceoryx2:
//! each one checked against numbers worked out by hand from the built-in machine data
//! (IPO cycle 1 ms, plc.watchdog_cycles 50, kv 16.667/s, dead time 1 cycle, 2000 mm/s² per
//! axis, tool change 800 ms, spindle 6000 rev/min per s, so 6 rev/min per drive cycle,
//! software limit X ±1000).

use nc_kernel::cycle::alarm;
use nc_kernel::MachineData;
use plc_sim::args::Window;
use plc_sim::plc::{Actual, Plc, Row, Script, Signals, Transport};
use softnc_protocol::{
    spindle_mode, state, AuxRequest, AuxWordMsg, SetpointMsg, MAX_AXES, MAX_SPINDLES,
};
use std::collections::VecDeque;
use std::time::Duration;

const MS: u64 = 1_000_000;

/// A trace row as the mock keeps it.
#[derive(Clone, Debug)]
struct Kept {
    cycle: u64,
    seq: u64,
    axes: usize,
    /// The first three wire axes (X Y Z of the built-in mill).
    actual: [f64; 3],
    following_error: [f64; MAX_AXES],
    spindles: usize,
    /// The first spindle's setpoint and actual speed (S1, AS1).
    spindle: [f64; 2],
    events: String,
}

/// The kernel's side and the clock: setpoints and requests queued by the test, one PLC
/// cycle of 1 ms per wait; everything the PLC sends is recorded with the time it was sent.
#[derive(Default)]
struct Mock {
    now: u64,
    setpoints: VecDeque<SetpointMsg>,
    requests: VecDeque<(u64, AuxRequest)>,
    acks: Vec<(u64, u64, u64)>,
    signals: Vec<(u64, Signals)>,
    actuals: Vec<Actual>,
    rows: Vec<Kept>,
    logs: Vec<String>,
}

impl Transport for Mock {
    fn now_ns(&mut self) -> u64 {
        self.now
    }
    fn wait(&mut self, timeout: Duration) -> bool {
        self.now += timeout.as_nanos() as u64;
        !self.setpoints.is_empty()
    }
    fn setpoint(&mut self) -> Option<SetpointMsg> {
        self.setpoints.pop_front()
    }
    fn request(&mut self) -> Option<(u64, AuxRequest)> {
        self.requests.pop_front()
    }
    fn ack(&mut self, ticket: u64, id: u64) {
        self.acks.push((ticket, id, self.now));
    }
    fn signals(&mut self, echo_cycle: u64, s: &Signals) {
        self.signals.push((echo_cycle, *s));
    }
    fn actuals(&mut self, a: &Actual) {
        self.actuals.push(*a);
    }
    fn row(&mut self, r: &Row<'_>) {
        self.rows.push(Kept {
            cycle: r.cycle,
            seq: r.seq,
            axes: r.axes,
            actual: [r.actual[0], r.actual[1], r.actual[2]],
            following_error: r.following_error,
            spindles: r.spindles,
            spindle: [r.spindle_setpoint[0], r.spindle_actual[0]],
            events: r.events.to_string(),
        });
    }
    fn log(&mut self, line: &str) {
        self.logs.push(line.to_string());
    }
}

/// A PLC with its kernel: `seq` and `cycle` count the setpoints sent, `spindle` is what
/// they tell the main spindle (`spindle_mode::*`, rev/min).
struct Rig {
    plc: Plc,
    io: Mock,
    seq: u64,
    cycle: u64,
    spindle: (u8, f64),
}

impl Rig {
    /// The events of the last trace row.
    fn last_events(&self) -> &str {
        self.io.rows.last().map_or("", |r| r.events.as_str())
    }

    fn new(script: Script) -> Rig {
        Rig::of(&MachineData::load(None, &[]).unwrap(), script)
    }

    fn of(md: &MachineData, script: Script) -> Rig {
        Rig {
            plc: Plc::new(md, script, 0),
            io: Mock::default(),
            seq: 0,
            cycle: 0,
            spindle: (spindle_mode::STOP, 0.0),
        }
    }

    /// One PLC cycle with a setpoint at X Y Z `pos` from a kernel in `st`.
    fn send(&mut self, pos: [f64; 3], st: u8) -> Signals {
        let mut wire = [0.0; MAX_AXES];
        wire[..3].copy_from_slice(&pos);
        self.send_wire(wire, st)
    }

    /// One PLC cycle with a setpoint at `pos`, every configured axis in wire order.
    fn send_wire(&mut self, pos: [f64; MAX_AXES], st: u8) -> Signals {
        self.seq += 1;
        self.cycle += 1;
        self.io.setpoints.push_back(SetpointMsg {
            seq: self.seq,
            cycle: self.cycle,
            // Sent as the PLC's wait begins; due by the end of the next cycle.
            sent_ns: self.io.now,
            deadline_ns: self.io.now + 2 * MS,
            pos,
            state: st,
            axes: self.plc.axes().count,
            spindles: 1,
            spindle_mode: [self.spindle.0, spindle_mode::STOP],
            spindle: [self.spindle.1, 0.0],
            ..Default::default()
        });
        self.step()
    }

    /// One PLC cycle: its signals.
    fn step(&mut self) -> Signals {
        self.plc.cycle(&mut self.io);
        self.io.signals.last().unwrap().1
    }

    /// The setpoints tell the main spindle `mode` at `rpm` from the next one on.
    fn spindle(&mut self, mode: u8, rpm: f64) {
        self.spindle = (mode, rpm);
    }

    /// `n` PLC cycles with a setpoint at the origin from a running kernel.
    fn hold(&mut self, n: u32) {
        for _ in 0..n {
            self.send([0.0; 3], state::ACTIVE);
        }
    }

    /// The main spindle's actual speed after the last setpoint.
    fn rpm(&self) -> f64 {
        self.io.actuals.last().map_or(0.0, |a| a.spindle_rpm[0])
    }

    /// A request (ticket `id`) output in the cycle of the next setpoint, as the kernel does
    /// at an S point: the requests of a cycle go out before its setpoint.
    fn ask(&mut self, id: u64, words: &[(u8, f64)]) {
        let r = request_at(id, self.cycle + 1, words);
        self.io.requests.push_back((id, r));
    }

    /// The tickets acknowledged so far.
    fn acked(&self) -> Vec<u64> {
        self.io.acks.iter().map(|a| a.0).collect()
    }

    /// Drives X along at 50 mm/s for 2 s: the axis is at speed.
    fn at_speed(&mut self) -> f64 {
        for k in 0..2000 {
            self.send([0.05 * k as f64, 0.0, 0.0], state::ACTIVE);
        }
        let rows = &self.io.rows;
        let n = rows.len();
        (rows[n - 1].actual[0] - rows[n - 2].actual[0]) / 0.001
    }
}

fn request(id: u64, words: &[(u8, f64)]) -> AuxRequest {
    request_at(id, 0, words)
}

/// A request output in kernel cycle `cycle`.
fn request_at(id: u64, cycle: u64, words: &[(u8, f64)]) -> AuxRequest {
    let mut r = AuxRequest {
        id,
        cycle,
        count: words.len() as u32,
        ..Default::default()
    };
    for (slot, (a, v)) in r.words.iter_mut().zip(words) {
        *slot = AuxWordMsg {
            address: *a,
            value: *v,
            ..Default::default()
        };
    }
    r
}

/// 49 silent cycles pass; the 50th raises 700000, drops "drives ready" and brakes from
/// 50 mm/s at 2 mm/s per cycle: 48, 46, … 2, 0 mm/s, 0.6 mm in all, then the axis stands.
#[test]
fn the_watchdog_brakes_after_n_silent_cycles_with_alarm_700000() {
    let mut rig = Rig::new(Script::default());
    let v = rig.at_speed();
    assert!((v - 50.0).abs() < 1e-6, "{v} mm/s");
    let rows_before = rig.io.rows.len();
    for _ in 0..49 {
        let s = rig.step();
        assert_eq!((s.alarm, s.drives_ready), (None, true));
    }
    assert_eq!(rig.io.rows.len(), rows_before, "no row while the axes wait");
    let s = rig.step();
    assert_eq!(
        (s.alarm, s.drives_ready),
        (Some(alarm::PLC_WATCHDOG), false)
    );
    assert_eq!(rig.io.logs.len(), 1);
    assert!(rig.io.logs[0].contains("alarm 700000: no setpoint for 50 cycles after cycle 2000"));
    for _ in 0..30 {
        rig.step();
    }
    let braking = &rig.io.rows[rows_before..];
    assert_eq!(braking.len(), 31);
    assert_eq!((braking[0].cycle, braking[0].seq), (2050, 0));
    assert!(braking[0]
        .events
        .contains("watchdog: no setpoint for 50 cycles"));
    let x: Vec<f64> = braking.iter().map(|r| r.actual[0]).collect();
    for (i, w) in x.windows(2).enumerate() {
        let want = if i < 24 {
            0.048 - 0.002 * i as f64
        } else {
            0.0
        };
        assert!(
            (w[1] - w[0] - want).abs() < 1e-9,
            "cycle {i}: {}",
            w[1] - w[0]
        );
    }
    // The acknowledgement: setpoints from a kernel that is ACTIVE leave the alarm, one in
    // RESET takes it away and the drives follow again from the setpoint.
    let rest = [x[30], 0.0, 0.0];
    assert_eq!(
        rig.send(rest, state::ACTIVE).alarm,
        Some(alarm::PLC_WATCHDOG)
    );
    let at = [x[30] + 0.0001, 0.0, 0.0];
    let s = rig.send(at, state::RESET);
    assert_eq!((s.alarm, s.drives_ready), (None, true));
    let last = rig.io.rows.last().unwrap();
    assert!(last.events.contains("watchdog acknowledged"));
    assert_eq!(
        last.actual, at,
        "the drives start again where the setpoint is"
    );
}

#[test]
fn a_setpoint_beyond_the_software_limit_raises_700001_and_stops_at_the_limit() {
    let mut rig = Rig::new(Script::default());
    rig.send([999.0, 0.0, 0.0], state::ACTIVE);
    assert_eq!(rig.step().alarm, None);
    let s = rig.send([1200.0, 0.0, 0.0], state::ACTIVE);
    assert_eq!(s.alarm, Some(alarm::PLC_SOFTWARE_LIMIT));
    assert!(rig.last_events().contains("software limit"));
    for _ in 0..3000 {
        rig.send([1200.0, 0.0, 0.0], state::ACTIVE);
    }
    let a = rig.io.actuals.last().unwrap();
    assert!((a.pos[0] - 1000.0).abs() < 1e-9, "{:?}", a.pos);
    assert_eq!(a.alarm, Some(alarm::PLC_SOFTWARE_LIMIT));
}

/// M6 T3 arrives in the PLC cycle that ends at 5 ms: the tool is 3 at once, the
/// acknowledgement comes 800 ms later to the cycle, none before.
#[test]
fn m6_is_acknowledged_after_the_tool_change_time() {
    let mut rig = Rig::new(Script::default());
    for _ in 0..4 {
        rig.send([0.0; 3], state::ACTIVE);
    }
    rig.io
        .requests
        .push_back((7, request(1, &[(b'M', 6.0), (b'T', 3.0)])));
    rig.send([0.0; 3], state::ACTIVE);
    assert_eq!(rig.io.now, 5 * MS);
    for _ in 0..799 {
        rig.send([0.0; 3], state::ACTIVE);
        assert!(rig.io.acks.is_empty(), "at {} ns", rig.io.now);
    }
    assert_eq!(rig.io.actuals.last().unwrap().tool, 3);
    rig.send([0.0; 3], state::ACTIVE);
    assert_eq!(rig.io.acks, [(7, 1, 805 * MS)]);
    rig.send([0.0; 3], state::ACTIVE);
    assert!(rig.last_events().contains("ack M6 T3"));
    assert_eq!(rig.plc.stats().aux_acked, 1);
}

/// The control panel's script: feed hold for kernel cycles 50–59, read-in disable 60–64,
/// emergency stop from 100 on and the drives off from 120 on, each as the signals echo the
/// cycle.
#[test]
fn scripted_inputs_act_in_their_cycle_windows() {
    let mut rig = Rig::new(Script {
        estop_at: Some(100),
        feed_hold: Some(Window {
            from: 50,
            cycles: 10,
        }),
        read_in_disable: Some(Window {
            from: 60,
            cycles: 5,
        }),
        drives_off_at: Some(120),
    });
    for c in 1..=150u64 {
        let s = rig.send([0.0; 3], state::ACTIVE);
        assert_eq!(rig.io.signals.last().unwrap().0, c);
        assert_eq!(s.feed_hold, (50..60).contains(&c), "cycle {c}");
        assert_eq!(s.read_in_disable, (60..65).contains(&c), "cycle {c}");
        assert_eq!(s.emergency_stop, c >= 100, "cycle {c}");
        assert_eq!(s.drives_ready, c < 120, "cycle {c}");
    }
    let events = |c: u64| {
        rig.io
            .rows
            .iter()
            .find(|r| r.cycle == c)
            .unwrap()
            .events
            .clone()
    };
    assert_eq!(events(100), "emergency stop;");
    assert_eq!(events(120), "drives off;");
}

/// Setpoints 1, 2, 3, 7, 8: three lost, said in the row of 7; a restarted kernel counting
/// from 1 again loses nothing.
#[test]
fn gaps_in_the_sequence_count_as_lost() {
    let mut rig = Rig::new(Script::default());
    for _ in 0..3 {
        rig.send([0.0; 3], state::ACTIVE);
    }
    rig.seq += 3;
    rig.send([0.0; 3], state::ACTIVE);
    rig.send([0.0; 3], state::ACTIVE);
    assert_eq!(rig.plc.stats().lost, 3);
    let rows = &rig.io.rows;
    assert_eq!(
        (
            rows[3].seq,
            rows[3].events.as_str(),
            rows[4].events.as_str()
        ),
        (7, "lost 3;", "")
    );
    rig.seq = 0;
    rig.send([0.0; 3], state::RESET);
    assert_eq!(rig.plc.stats().lost, 3);
    assert_eq!(rig.plc.stats().samples, 6);
    // Each setpoint was taken 1 ms after it was sent, within its deadline.
    let h = &rig.plc.stats().latency;
    assert_eq!((rig.plc.stats().late, h.len()), (0, 6));
    assert!(h.equivalent(h.min(), MS) && h.equivalent(h.max(), MS));
}

/// A five-axis machine (X Y Z, A tilting between its end stops, C a modulo rotary table),
/// each axis with machine data of its own.
const FIVE_AXES: &str = "dialect = \"fanuc\"\n\
    [axes.X]\nmax_velocity = 15000.0\nmax_acceleration = 3000.0\nmax_jerk = 6e4\n\
    software_limits = [-500.0, 500.0]\n\
    [axes.Y]\nmax_velocity = 15000.0\nmax_acceleration = 3000.0\nmax_jerk = 6e4\n\
    software_limits = [-400.0, 400.0]\n\
    [axes.Z]\nmax_velocity = 10000.0\nmax_acceleration = 2000.0\nmax_jerk = 5e4\n\
    software_limits = [-450.0, 50.0]\n\
    [axes.A]\nkind = \"rotary\"\nmax_velocity = 5400.0\nmax_acceleration = 600.0\n\
    max_jerk = 12000.0\nsoftware_limits = [-120.0, 30.0]\n\
    [axes.C]\nkind = \"rotary\"\nmodulo = true\nmax_velocity = 36000.0\n\
    max_acceleration = 900.0\nmax_jerk = 15000.0\n";

/// plc.kv of the built-in machine data, 1/s.
const KV: f64 = 16.667;

/// Every axis on a ramp of its own (mm/s, °/s in wire order X Y Z A C) for 2 s: each one's
/// following error settles at its own v/kv, the actual position trails the setpoint by it
/// (and by the one cycle of dead time), C counts on past 360° uncut; the trace row carries
/// all five. Then A runs on towards +120°: PLC alarm 700001 as its setpoint passes its end
/// stop at +30°, A comes to rest there, the other axes follow on.
#[test]
fn five_axes_follow_with_their_own_errors_and_a_stops_at_its_limit() {
    let md = MachineData::from_toml_str(FIVE_AXES, "5ax.toml").unwrap();
    let mut rig = Rig::of(&md, Script::default());
    assert_eq!(rig.plc.axes().names().collect::<String>(), "XYZAC");
    let mut v = [50.0, -20.0, 5.0, -30.0, 270.0];
    let t = 0.001;
    let mut sp = [0.0; MAX_AXES];
    for k in 1..=2000 {
        for n in 0..5 {
            sp[n] = v[n] * t * k as f64;
        }
        assert_eq!(rig.send_wire(sp, state::ACTIVE).alarm, None, "cycle {k}");
    }
    let a = *rig.io.actuals.last().unwrap();
    for n in 0..5 {
        let fe = a.following_error[n];
        assert!((fe - v[n] / KV).abs() < 1e-6, "axis {n}: {fe}");
        let trails = sp[n] - v[n] * t - fe;
        assert!((a.pos[n] - trails).abs() < 1e-9, "axis {n}: {:?}", a.pos);
    }
    assert!(a.pos[4] > 500.0, "C counts on: {}", a.pos[4]);
    assert!(a.pos[5..].iter().all(|&p| p == 0.0), "{:?}", a.pos);
    let row = rig.io.rows.last().unwrap();
    assert_eq!(row.axes, 5);
    assert_eq!(row.following_error, a.following_error);

    // A from −60° up at 60°/s: its setpoint passes +30° 1.5 s on.
    v[3] = 60.0;
    let from = sp;
    let mut alarm_at = None;
    for k in 1..=3000 {
        for n in 0..5 {
            sp[n] = from[n] + v[n] * t * k as f64;
        }
        let s = rig.send_wire(sp, state::ACTIVE);
        if s.alarm.is_some() && alarm_at.is_none() {
            alarm_at = Some(k);
            assert_eq!(s.alarm, Some(alarm::PLC_SOFTWARE_LIMIT));
            assert!(rig.last_events().contains("software limit"));
            assert!(
                sp[3] > 30.0 && sp[3] - v[3] * t <= 30.0 + 1e-9,
                "at A {}",
                sp[3]
            );
        }
    }
    assert!(alarm_at.is_some(), "no alarm 700001");
    let a = *rig.io.actuals.last().unwrap();
    assert_eq!(a.alarm, Some(alarm::PLC_SOFTWARE_LIMIT));
    assert!((a.pos[3] - 30.0).abs() < 1e-6, "A at {}", a.pos[3]);
    assert!(a.following_error[3].abs() < 1e-6);
    for n in [0, 1, 2, 4] {
        assert!((a.following_error[n] - v[n] / KV).abs() < 1e-6, "axis {n}");
    }
}

/// From rest to 1200 rev/min at 6 rev/min per drive cycle: 6·k after the k-th setpoint,
/// 1200 after the 200th and there it stays. The signals (every PLC cycle), the actual values
/// and the trace (S1, AS1) carry it.
#[test]
fn the_spindle_ramps_to_its_setpoint_at_the_acceleration() {
    let mut rig = Rig::new(Script::default());
    rig.spindle(spindle_mode::TURN, 1200.0);
    for k in 1..=210u32 {
        let s = rig.send([0.0; 3], state::ACTIVE);
        let want = (6.0 * f64::from(k)).min(1200.0);
        assert_eq!(s.spindle_rpm, [want, 0.0], "cycle {k}");
        assert_eq!(rig.rpm(), want, "cycle {k}");
        let row = rig.io.rows.last().unwrap();
        assert_eq!(
            (row.spindles, row.spindle),
            (1, [1200.0, want]),
            "cycle {k}"
        );
    }
    assert_eq!(
        rig.io.actuals.last().unwrap().spindle_rpm.len(),
        MAX_SPINDLES
    );
}

/// S250 M3 from standstill with the setpoint 1000 (the S word is not read: under G96 it
/// would be m/min; the speed comes with the setpoints). At 6 rev/min per cycle the spindle
/// is within the at-speed window of 1000 (max(1, 0.5 %) = 5 rev/min) at 996, after the
/// 166th setpoint: the acknowledgement comes in that PLC cycle, not one before.
#[test]
fn m3_is_acknowledged_only_at_speed() {
    let mut rig = Rig::new(Script::default());
    rig.hold(1);
    rig.ask(1, &[(b'S', 250.0), (b'M', 3.0)]);
    rig.spindle(spindle_mode::TURN, 1000.0);
    rig.hold(165);
    assert!(rig.io.acks.is_empty());
    assert_eq!(rig.rpm(), 990.0);
    rig.hold(1);
    assert_eq!(rig.io.acks, [(1, 1, 167 * MS)]);
    assert_eq!(rig.rpm(), 996.0);
    rig.hold(1);
    assert_eq!(rig.rpm(), 1000.0);
    assert!(rig.last_events().contains("ack S250 M3"));
    assert_eq!(rig.plc.stats().aux_acked, 1);
}

/// A request counts from the setpoint of its own cycle: with the spindle at 1000 and still
/// told 1000, an M3 output in a cycle whose setpoint has not come waits for it; one that
/// arrives before any setpoint waits for the first.
#[test]
fn a_request_waits_for_the_setpoint_of_its_cycle() {
    let mut rig = Rig::new(Script::default());
    rig.io.requests.push_back((1, request(1, &[(b'M', 5.0)])));
    for _ in 0..5 {
        rig.step();
    }
    assert!(rig.io.acks.is_empty(), "no setpoint yet");
    rig.hold(1);
    assert_eq!(rig.acked(), [1]);
    rig.spindle(spindle_mode::TURN, 1000.0);
    rig.hold(200);
    let cycle = rig.cycle + 3;
    rig.io
        .requests
        .push_back((2, request_at(2, cycle, &[(b'M', 3.0)])));
    rig.hold(2);
    assert_eq!(rig.acked(), [1]);
    rig.hold(1);
    assert_eq!((rig.acked(), rig.cycle), (vec![1, 2], cycle));
}

/// M4 at 1000 clockwise: the setpoint −1000 takes the spindle down through 0 without a
/// step, 1000 − 6k after the k-th setpoint (4 after the 166th, −2 after the 167th), and it
/// is at speed (within 5 of −1000) at −998, after the 333rd: acknowledged then.
#[test]
fn m4_reverses_through_zero_and_is_acknowledged_at_speed() {
    let mut rig = Rig::new(Script::default());
    rig.spindle(spindle_mode::TURN, 1000.0);
    rig.hold(200);
    rig.ask(1, &[(b'M', 4.0)]);
    rig.spindle(spindle_mode::TURN, -1000.0);
    for k in 1..=332u32 {
        rig.hold(1);
        assert_eq!(rig.rpm(), 1000.0 - 6.0 * f64::from(k), "cycle {k}");
    }
    assert!(rig.io.acks.is_empty());
    let rows = rig.io.rows.len();
    assert_eq!(rig.io.rows[rows - 333 + 166].spindle, [-1000.0, 4.0]);
    assert_eq!(rig.io.rows[rows - 333 + 167].spindle, [-1000.0, -2.0]);
    rig.hold(1);
    assert_eq!((rig.acked(), rig.rpm()), (vec![1], -998.0));
    rig.hold(1);
    assert_eq!(rig.rpm(), -1000.0);
}

/// M5 at 1000: the spindle comes to rest at 6 rev/min per cycle, 4 after the 166th
/// setpoint, 0 after the 167th (a last step of 4), and M5 is acknowledged at rest (at most
/// 1 rev/min), with the 167th. M19 from 600: oriented at rest after the 100th. An M5 to a
/// spindle at rest whose setpoint has come is acknowledged at once, without a new setpoint.
#[test]
fn m5_stops_the_spindle_and_is_acknowledged_at_rest() {
    let mut rig = Rig::new(Script::default());
    rig.spindle(spindle_mode::TURN, 1000.0);
    rig.hold(200);
    rig.ask(1, &[(b'M', 5.0)]);
    rig.spindle(spindle_mode::STOP, 0.0);
    rig.hold(166);
    assert_eq!((rig.io.acks.len(), rig.rpm()), (0, 4.0));
    rig.hold(1);
    assert_eq!((rig.acked(), rig.rpm()), (vec![1], 0.0));

    rig.spindle(spindle_mode::TURN, 600.0);
    rig.hold(100);
    rig.ask(2, &[(b'M', 19.0)]);
    rig.spindle(spindle_mode::ORIENT, 0.0);
    rig.hold(99);
    assert_eq!((rig.acked(), rig.rpm()), (vec![1], 6.0));
    rig.hold(1);
    assert_eq!((rig.acked(), rig.rpm()), (vec![1, 2], 0.0));

    let now = rig.cycle;
    rig.io
        .requests
        .push_back((3, request_at(3, now, &[(b'M', 5.0)])));
    rig.step();
    assert_eq!(rig.acked(), [1, 2, 3]);
}

/// An S word while the spindle turns waits for the new speed: 1000 → 1500 is within 7.5
/// rev/min at 1498, after the 83rd setpoint. While it stands, S is acknowledged at once and
/// turns nothing.
#[test]
fn an_s_word_waits_for_the_new_speed_only_while_the_spindle_turns() {
    let mut rig = Rig::new(Script::default());
    rig.hold(1);
    rig.ask(1, &[(b'S', 500.0)]);
    rig.hold(1);
    assert_eq!((rig.acked(), rig.rpm()), (vec![1], 0.0));
    rig.spindle(spindle_mode::TURN, 1000.0);
    rig.hold(200);
    rig.ask(2, &[(b'S', 1500.0)]);
    rig.spindle(spindle_mode::TURN, 1500.0);
    rig.hold(82);
    assert_eq!((rig.acked(), rig.rpm()), (vec![1], 1492.0));
    rig.hold(1);
    assert_eq!((rig.acked(), rig.rpm()), (vec![1, 2], 1498.0));
}

/// Constant surface speed on a facing cut: 200 m/min with the tool moving from r = 50 mm
/// to r = 10 mm at 0.04 mm per cycle, n = 200000 / (2π r) every cycle. The setpoint rises
/// by 8000 / (2π r²) ≈ 1273 / r² rev/min per cycle: below 6 down to r = 15, where the drive
/// follows it cycle by cycle; above 6 from r = 14 on, where it rises by exactly 6 per cycle
/// behind it. At the centre the setpoint stands (3183.1) and the drive catches up.
#[test]
fn the_spindle_follows_a_setpoint_that_changes_every_cycle() {
    let n = |r: f64| 200_000.0 / (2.0 * std::f64::consts::PI * r);
    let mut rig = Rig::new(Script::default());
    rig.spindle(spindle_mode::TURN, n(50.0));
    rig.hold(200);
    assert!((rig.rpm() - n(50.0)).abs() < 1e-9);
    let mut last = rig.rpm();
    for k in 1..=1000u32 {
        let r = 50.0 - 0.04 * f64::from(k);
        rig.spindle(spindle_mode::TURN, n(r));
        rig.hold(1);
        let a = rig.rpm();
        if r >= 15.0 {
            assert!((a - n(r)).abs() < 1e-9, "r {r}: {a} for {}", n(r));
        }
        if r <= 14.0 {
            assert!(a < n(r) - 1.0, "r {r}: {a} for {}", n(r));
            assert!((a - last - 6.0).abs() < 1e-9, "r {r}: {}", a - last);
        }
        last = a;
    }
    let behind = n(10.0) - rig.rpm();
    assert!(behind > 6.0, "{behind}");
    rig.hold((behind / 6.0).ceil() as u32);
    assert!((rig.rpm() - n(10.0)).abs() < 1e-9);
}

/// T2 M6 M3, taken in the PLC cycle that ends at 2 ms, waits for both: with 1000 rev/min
/// the spindle is at speed after 166 setpoints, the tool change takes 800 ms: acknowledged
/// at 802 ms, with the 801st setpoint after the request's. With 6000 rev/min the spindle is
/// within 30 rev/min at 5970, after the 995th: acknowledged then, at 996 ms.
#[test]
fn a_request_with_several_conditions_waits_for_all() {
    for (rpm, ack_after) in [(1000.0, 801u32), (6000.0, 995)] {
        let mut rig = Rig::new(Script::default());
        rig.hold(1);
        rig.ask(1, &[(b'T', 2.0), (b'M', 6.0), (b'M', 3.0)]);
        rig.spindle(spindle_mode::TURN, rpm);
        rig.hold(ack_after - 1);
        assert!(rig.io.acks.is_empty(), "{rpm}");
        rig.hold(1);
        assert_eq!(
            rig.io.acks,
            [(1, 1, (1 + u64::from(ack_after)) * MS)],
            "{rpm}"
        );
        assert_eq!(rig.io.actuals.last().unwrap().tool, 2);
    }
}

/// A spindle wait when the kernel is gone: the spindle told 3000 is at 600 after 100
/// setpoints when they stop. The watchdog brakes the spindle with the axes, 6 rev/min per
/// silent cycle from the 50th on, to rest after the 149th; the M3 is not acknowledged (its
/// speed was never reached). A new kernel in RESET (cycles from 1, spindle stopped) takes
/// the alarm away, and its setpoint of the request's cycle (2) ends the wait: the spindle
/// is at its setpoint, 0.
#[test]
fn a_spindle_wait_ends_with_the_watchdog_and_a_new_kernel() {
    let mut rig = Rig::new(Script::default());
    rig.hold(1);
    rig.ask(1, &[(b'M', 3.0)]);
    rig.spindle(spindle_mode::TURN, 3000.0);
    rig.hold(100);
    assert_eq!(rig.rpm(), 600.0);
    let rows = rig.io.rows.len();
    for _ in 0..160 {
        rig.step();
    }
    let braking = &rig.io.rows[rows..];
    assert_eq!(braking.len(), 111);
    for (j, r) in braking.iter().enumerate() {
        let want = (600.0 - 6.0 * (j + 1) as f64).max(0.0);
        assert_eq!((r.seq, r.spindle), (0, [3000.0, want]), "row {j}");
    }
    assert_eq!(rig.io.signals.last().unwrap().1.spindle_rpm, [0.0; 2]);
    assert!(rig.io.acks.is_empty());

    rig.seq = 0;
    rig.cycle = 0;
    rig.spindle(spindle_mode::STOP, 0.0);
    let s = rig.send([0.0; 3], state::RESET);
    assert_eq!((s.alarm, rig.io.acks.len()), (None, 0));
    rig.send([0.0; 3], state::RESET);
    assert_eq!(rig.acked(), [1]);
}
