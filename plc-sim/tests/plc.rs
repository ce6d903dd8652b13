//! The simulated PLC's reactions on a mock transport and a mock clock, without iceoryx2:
//! each one checked against numbers worked out by hand from the built-in machine data
//! (IPO cycle 1 ms, plc.watchdog_cycles 50, kv 16.667/s, dead time 1 cycle, 2000 mm/s² per
//! axis, tool change 800 ms, spindle 6000 rpm/s, software limit X ±1000).

use nc_kernel::cycle::{alarm, PlcInput};
use nc_kernel::MachineData;
use plc_sim::args::Window;
use plc_sim::plc::{Actual, Plc, Row, Script, Transport};
use softnc_protocol::{state, AuxRequest, AuxWordMsg, SetpointMsg, MAX_AXES};
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
    signals: Vec<(u64, PlcInput)>,
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
    fn signals(&mut self, echo_cycle: u64, s: &PlcInput) {
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
            events: r.events.to_string(),
        });
    }
    fn log(&mut self, line: &str) {
        self.logs.push(line.to_string());
    }
}

/// A PLC with its kernel: `seq` and `cycle` count the setpoints sent.
struct Rig {
    plc: Plc,
    io: Mock,
    seq: u64,
    cycle: u64,
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
        }
    }

    /// One PLC cycle with a setpoint at X Y Z `pos` from a kernel in `st`.
    fn send(&mut self, pos: [f64; 3], st: u8) -> PlcInput {
        let mut wire = [0.0; MAX_AXES];
        wire[..3].copy_from_slice(&pos);
        self.send_wire(wire, st)
    }

    /// One PLC cycle with a setpoint at `pos`, every configured axis in wire order.
    fn send_wire(&mut self, pos: [f64; MAX_AXES], st: u8) -> PlcInput {
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
            ..Default::default()
        });
        self.step()
    }

    /// One PLC cycle: its signals.
    fn step(&mut self) -> PlcInput {
        self.plc.cycle(&mut self.io);
        self.io.signals.last().unwrap().1
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
    let mut r = AuxRequest {
        id,
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

/// S1000 M3 from standstill: 1000/6000 s = 166.67 ms of ramp, 6 rpm per drive cycle, so
/// the acknowledgement comes with the 167th setpoint after the request, at 1000 rpm.
#[test]
fn m3_is_acknowledged_when_the_spindle_is_at_speed() {
    let mut rig = Rig::new(Script::default());
    rig.send([0.0; 3], state::ACTIVE);
    rig.io
        .requests
        .push_back((1, request(4, &[(b'S', 1000.0), (b'M', 3.0)])));
    rig.send([0.0; 3], state::ACTIVE);
    for _ in 0..166 {
        rig.send([0.0; 3], state::ACTIVE);
    }
    assert!(rig.io.acks.is_empty());
    assert!((rig.io.actuals.last().unwrap().spindle_rpm - 996.0).abs() < 1e-9);
    rig.send([0.0; 3], state::ACTIVE);
    assert_eq!(rig.io.acks.len(), 1);
    assert!((rig.io.actuals.last().unwrap().spindle_rpm - 1000.0).abs() < 1e-9);
    // M5 stops it (acknowledged at once); an S alone while it stands changes nothing.
    rig.io.requests.push_back((2, request(5, &[(b'M', 5.0)])));
    rig.send([0.0; 3], state::ACTIVE);
    assert_eq!(rig.io.acks.len(), 2);
    for _ in 0..200 {
        rig.send([0.0; 3], state::ACTIVE);
    }
    assert_eq!(rig.io.actuals.last().unwrap().spindle_rpm, 0.0);
    rig.io.requests.push_back((3, request(6, &[(b'S', 500.0)])));
    for _ in 0..10 {
        rig.send([0.0; 3], state::ACTIVE);
    }
    assert_eq!(rig.io.actuals.last().unwrap().spindle_rpm, 0.0);
    assert_eq!(rig.io.acks.len(), 3);
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
