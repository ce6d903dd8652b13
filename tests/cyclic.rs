//! The kernel's cycle with its PLC and HMI (runtime/cyclic.rs, issue 6), on a mock clock and
//! a mock PLC in this thread: each reaction to a PLC signal is checked cycle by cycle, with
//! the cycle numbers worked out from the machine data (built-in: IPO cycle 1 ms,
//! plc.watchdog_cycles 50, 2000 mm/s² per axis). The processes around it are tested in
//! tests/ipc.rs; here nothing depends on the machine's timing.

#[path = "support/counting.rs"]
mod counting;
#[path = "support/plc_mock.rs"]
mod plc_mock;

use nc_kernel::cycle::{alarm, ChannelAlarm, Control, Refusal, Status};
use nc_kernel::handover::Handover;
use nc_kernel::ipo::ChannelState;
use nc_kernel::ipo::Input;
use nc_kernel::MachineData;
use plc_mock::{state, Rig};
use std::sync::Arc;

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

const WATCHDOG: u64 = 50;
/// F3000: 50 mm/s.
const V: f64 = 50.0;

fn md() -> MachineData {
    MachineData::load(None, &[]).unwrap()
}

/// The path's speed never rises from `from` on, and it ends at rest.
fn brakes(rows: &[Status]) {
    for w in rows.windows(2) {
        assert!(
            w[1].v_path <= w[0].v_path + 1e-9,
            "speed rises at cycle {}: {} after {}",
            w[1].cycle,
            w[1].v_path,
            w[0].v_path
        );
    }
    assert_eq!(rows.last().unwrap().v_path, 0.0);
}

/// On the X axis line through the origin: braking stays on the contour.
fn on_x_axis(rows: &[Status]) {
    for s in rows {
        assert_eq!((s.pos[1], s.pos[2]), (0.0, 0.0), "cycle {}", s.cycle);
    }
}

fn at_speed(rig: &mut Rig) -> u64 {
    rig.run_until(5_000, |s| (s.v_path - V).abs() < 1e-9);
    rig.k
}

#[test]
fn plc_silence_raises_2000_one_cycle_after_the_watchdog_time_and_the_path_brakes() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, "N1 G1 X500 F3000\nM30\n");
    let c = at_speed(&mut rig);
    // The PLC's last sign of life arrives in cycle c - 1.
    rig.plc.alive = false;
    let a = rig.run_until(1_000, |s| s.alarm.is_some());
    assert_eq!(a.alarm, Some(alarm::PLC_SIGN_OF_LIFE));
    assert_eq!(a.cycle, (c - 1) + WATCHDOG + 1);
    assert_eq!(a.plc_cycle, c - 1);
    assert!(!a.plc_alive);
    // The alarm's own setpoint is the first slower one.
    let before = rig.since(a.cycle - 1)[0].v_path;
    assert!((before - V).abs() < 1e-9 && a.v_path < before - 1e-6);
    rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
    let rows = rig.since(a.cycle);
    brakes(rows);
    on_x_axis(rows);
    // Braking from 50 mm/s with at most 2000 mm/s² and 50000 mm/s³: no shorter than the
    // jerk-limited S curve, v·sqrt(v/j) = 1.58 mm; the planner's stop profile (a lower path
    // jerk) takes 1.78 mm; anything beyond twice the minimum would be a late reaction.
    let travel = rows.last().unwrap().pos[0] - rows[0].pos[0];
    let least = V * (V / 50_000.0f64).sqrt();
    assert!(
        travel >= least - 1e-9 && travel <= 2.0 * least,
        "braking travel {travel} mm"
    );
    assert_eq!(
        rig.ask(Control::Start),
        Err(Refusal::Alarm(alarm::PLC_SIGN_OF_LIFE))
    );
    // The PLC back: reset takes the alarm away.
    rig.plc.alive = true;
    rig.step();
    assert_eq!(rig.ask(Control::Reset), Ok(()));
    let s = rig.step();
    assert_eq!((state(&s), s.alarm), (ChannelState::Reset, None));
}

#[test]
fn an_idle_kernel_without_plc_raises_nothing() {
    let md = md();
    let mut rig = Rig::new(&md, 1_000);
    rig.step();
    rig.plc.alive = false;
    for _ in 0..500 {
        let s = rig.step();
        assert_eq!(s.alarm, None);
    }
    assert!(!rig.cyclic.status().plc_alive);
    rig.ask(Control::Load(plc_mock::program(
        &md,
        1,
        "G1 X1 F100\nM30\n",
        None,
    )))
    .unwrap();
    assert_eq!(rig.ask(Control::Start), Err(Refusal::NoPlc));
}

#[test]
fn feed_hold_brakes_to_rest_and_its_release_resumes_the_program() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, "N1 G1 X200 F3000\nM30\n");
    let c = at_speed(&mut rig);
    rig.plc.signals.feed_hold = true;
    let s = rig.step();
    assert!(
        s.v_path < V,
        "braking starts in the cycle the signal arrives"
    );
    rig.run_until(1_000, |s| s.v_path == 0.0);
    let stopped = rig.run_until(10, |s| state(s) == ChannelState::Stopped);
    for _ in 0..300 {
        let s = rig.step();
        assert_eq!((s.pos, s.v_path), (stopped.pos, 0.0), "it stays at rest");
    }
    brakes(rig.since(c));
    rig.plc.signals.feed_hold = false;
    let r = rig.k;
    let s = rig.step();
    assert_eq!(state(&s), ChannelState::Active);
    let end = rig.run_until(10_000, |s| state(s) == ChannelState::End);
    assert_eq!(end.alarm, None);
    assert_eq!(end.pos, [200.0, 0.0, 0.0]);
    on_x_axis(rig.since(c));
    assert!(rig.since(r + 1)[0].v_path > 0.0);
}

#[test]
fn feed_hold_release_does_not_restart_an_operator_stop() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, "N1 G1 X200 F3000\nM30\n");
    at_speed(&mut rig);
    rig.plc.signals.feed_hold = true;
    rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
    // NC stop by the operator while feed hold stands: releasing feed hold may not start.
    rig.ask(Control::Stop).unwrap();
    rig.step();
    rig.plc.signals.feed_hold = false;
    for _ in 0..200 {
        let s = rig.step();
        assert_eq!((state(&s), s.v_path), (ChannelState::Stopped, 0.0));
    }
    rig.ask(Control::Start).unwrap();
    let end = rig.run_until(10_000, |s| state(s) == ChannelState::End);
    assert_eq!(end.pos, [200.0, 0.0, 0.0]);
}

/// Three blocks on one line: without read-in disable the path passes X10 at speed; with it,
/// the path rests exactly at the end of N1, the first block end it can still stop at.
#[test]
fn read_in_disable_rests_at_the_first_reachable_block_end() {
    let md = md();
    let prog = "N1 G1 X10 F3000\nN2 X20\nN3 X30\nM30\n";
    let mut free = Rig::new(&md, 100_000);
    free.load_and_start(&md, 1, prog);
    free.run_until(10_000, |s| state(s) == ChannelState::End);
    let passing = free
        .plc
        .status
        .iter()
        .filter(|s| (s.pos[0] - 10.0).abs() < 1.0)
        .map(|s| s.v_path)
        .fold(f64::INFINITY, f64::min);
    assert!(
        passing > 0.9 * V,
        "without the signal X10 is passed at {passing} mm/s"
    );

    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, prog);
    // 20 cycles after the start: about 0.1 mm travelled, X10 easily reachable.
    rig.run_until(100, |s| s.cycle >= 20);
    rig.plc.signals.read_in_disable = true;
    let rest = rig.run_until(1_000, |s| s.v_path == 0.0);
    assert_eq!(rest.pos, [10.0, 0.0, 0.0]);
    for _ in 0..500 {
        let s = rig.step();
        assert_eq!((s.pos, s.v_path), (rest.pos, 0.0));
        assert_eq!(s.alarm, None);
    }
    rig.plc.signals.read_in_disable = false;
    let end = rig.run_until(10_000, |s| state(s) == ChannelState::End);
    assert_eq!(end.pos, [30.0, 0.0, 0.0]);
    assert_eq!(end.alarm, None);
}

#[test]
fn drives_lost_while_moving_raise_21612_and_the_path_brakes() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, "N1 G1 X500 F3000\nM30\n");
    let c = at_speed(&mut rig);
    rig.plc.signals.drives_ready = false;
    let a = rig.step();
    assert_eq!((a.cycle, a.alarm), (c, Some(alarm::DRIVES_NOT_READY)));
    assert!(a.v_path < V);
    rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
    brakes(rig.since(c));
    on_x_axis(rig.since(c));
    rig.plc.signals.drives_ready = true;
    rig.step();
    assert_eq!(
        rig.ask(Control::Start),
        Err(Refusal::Alarm(alarm::DRIVES_NOT_READY))
    );
    rig.ask(Control::Reset).unwrap();
    assert_eq!(rig.step().alarm, None);
}

#[test]
fn emergency_stop_raises_3000_brakes_and_blocks_start_and_reset_while_pressed() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, "N1 G1 X500 F3000\nM30\n");
    let c = at_speed(&mut rig);
    rig.plc.signals.emergency_stop = true;
    let a = rig.step();
    assert_eq!((a.cycle, a.alarm), (c, Some(alarm::EMERGENCY_STOP)));
    rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
    brakes(rig.since(c));
    on_x_axis(rig.since(c));
    assert_eq!(rig.ask(Control::Start), Err(Refusal::EmergencyStop));
    assert_eq!(rig.ask(Control::Reset), Err(Refusal::EmergencyStop));
    rig.plc.signals.emergency_stop = false;
    rig.step();
    assert_eq!(rig.ask(Control::Reset), Ok(()));
    let s = rig.step();
    assert_eq!((state(&s), s.alarm), (ChannelState::Reset, None));
}

/// M6 waits for its acknowledgement (ipo.wait_for_ack); M8 does not.
#[test]
fn the_path_waits_at_m6_until_the_plc_acknowledges_and_passes_m8() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.plc.ack_after = Some(400);
    rig.load_and_start(
        &md,
        1,
        "N1 G1 X10 F3000\nN2 M6 T2\nN3 X20\nN4 M8\nN5 X30\nM30\n",
    );
    let end = rig.run_until(20_000, |s| state(s) == ChannelState::End);
    assert_eq!(end.pos, [30.0, 0.0, 0.0]);
    // The program ends without waiting for M8's acknowledgement; it arrives later.
    let acked = rig.run_until(1_000, |s| s.aux_acked == 2);
    assert_eq!((acked.aux_sent, state(&acked)), (2, ChannelState::End));
    let req = rig.plc.requests.clone();
    assert_eq!(req.len(), 2, "{req:?}");
    assert_eq!((req[0].word, req[0].wait), ((b'M', 6.0), true));
    assert_eq!((req[1].word, req[1].wait), ((b'M', 8.0), false));
    // Sent when the path stood at X10; no motion until the acknowledgement (delivered in
    // the cycle after `ack_after` cycles).
    let sent = rig.since(req[0].cycle)[0];
    assert_eq!((sent.pos, sent.v_path), ([10.0, 0.0, 0.0], 0.0));
    for s in rig.since(req[0].cycle).iter().take(401) {
        assert_eq!(
            (s.pos, s.v_path),
            ([10.0, 0.0, 0.0], 0.0),
            "cycle {}",
            s.cycle
        );
    }
    assert!(rig.since(req[0].cycle + 402)[0].v_path > 0.0);
    // M8 goes out at X20 without stopping the path.
    let m8 = rig.since(req[1].cycle)[0];
    assert!((m8.pos[0] - 20.0).abs() < V * 1e-3 + 1e-9, "{m8:?}");
    assert!(m8.v_path > 0.0);
}

/// A PLC whose request queue is full: the requests wait in the kernel's outbox and go out
/// in program order once it takes them again; the path waits for the one it must.
#[test]
fn requests_the_plc_cannot_take_go_out_later_in_order() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.plc.full = true;
    rig.load_and_start(
        &md,
        1,
        "N1 G1 X10 F3000\nN2 M8\nN3 X20\nN4 M6 T3\nN5 X30\nM30\n",
    );
    rig.run_until(10_000, |s| {
        s.aux_sent == 0 && s.pos[0] >= 20.0 && s.v_path == 0.0
    });
    // M8 could not be sent, and M6 holds the path at X20.
    assert!(rig.plc.requests.is_empty());
    for _ in 0..100 {
        assert_eq!(rig.step().pos, [20.0, 0.0, 0.0]);
    }
    rig.plc.full = false;
    let end = rig.run_until(20_000, |s| state(s) == ChannelState::End);
    let words: Vec<_> = rig.plc.requests.iter().map(|r| r.word).collect();
    assert_eq!(words, [(b'M', 8.0), (b'M', 6.0)]);
    assert_eq!(end.pos, [30.0, 0.0, 0.0]);
    assert_eq!((end.aux_sent, end.aux_acked, end.alarm), (2, 2, None));
}

#[test]
fn reset_while_moving_brakes_first_then_resets_where_the_path_stopped() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, "N1 G1 X500 F3000\nM30\n");
    let c = at_speed(&mut rig);
    rig.ask(Control::Reset).unwrap();
    let r = rig.run_until(1_000, |s| state(s) == ChannelState::Reset);
    brakes(rig.since(c));
    on_x_axis(rig.since(c));
    assert!(r.pos[0] > 0.0 && r.pos[0] < 500.0);
    let rest = r.pos;
    // Released for the control thread to free.
    assert_eq!(rig.cyclic.take_released().map(|p| p.id), Some(1));
    // A program that starts elsewhere is refused; loaded where the axes stand, it runs.
    let elsewhere = plc_mock::program(&md, 2, "G1 X1 F100\nM30\n", None);
    assert!(matches!(
        rig.ask(Control::Load(elsewhere)),
        Err(Refusal::StartsElsewhere { .. })
    ));
    rig.load_and_start(&md, 3, "N1 G1 X0 F3000\nM30\n");
    assert_eq!(rig.cyclic.status().program, 3);
    let end = rig.run_until(20_000, |s| state(s) == ChannelState::End);
    assert_eq!(end.pos, [0.0, 0.0, 0.0]);
    assert!(rest[0] > 0.0);
}

#[test]
fn load_is_refused_while_the_program_runs() {
    let md = md();
    let mut rig = Rig::new(&md, 100_000);
    rig.load_and_start(&md, 1, "N1 G1 X500 F3000\nM30\n");
    at_speed(&mut rig);
    let other = plc_mock::program(&md, 2, "G1 X1 F100\nM30\n", None);
    assert!(matches!(
        rig.ask(Control::Load(other)),
        Err(Refusal::NotInReset(ChannelState::Active))
    ));
    // The refused program comes back to be freed outside the cycle.
    assert_eq!(rig.cyclic.take_released().map(|p| p.id), Some(2));
    assert_eq!(rig.step().program, 1);
}

/// The whole cycle, bus included, never touches the allocator: a program with waiting and
/// non-waiting aux functions, feed hold, read-in disable, an override change, NC stop and
/// start, the PLC silent long enough for alarm 2000, a reset and a second program.
#[test]
fn the_cycle_does_not_touch_the_allocator() {
    counting::self_test();
    let md = md();
    let mut rig = Rig::new(&md, 200_000);
    rig.plc.ack_after = Some(200);
    let prog = "N1 G1 X10 F3000\nN2 M6 T2\nN3 X20\nN4 M8\nN5 X60\nN6 X100\nM30\n";
    let first = plc_mock::program(&md, 1, prog, None);
    for _ in 0..3 {
        rig.step();
    }
    let (released, events) = counting::counted(|| {
        rig.ask(Control::Load(first)).unwrap();
        rig.ask(Control::Start).unwrap();
        rig.run_until(10_000, |s| s.pos[0] > 25.0);
        rig.ask(Control::Override(0.5)).unwrap();
        rig.plc.signals.feed_hold = true;
        rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
        rig.plc.signals.feed_hold = false;
        rig.run_until(1_000, |s| state(s) == ChannelState::Active);
        rig.plc.signals.read_in_disable = true;
        rig.run_until(10_000, |s| s.v_path == 0.0);
        rig.plc.signals.read_in_disable = false;
        rig.run_until(1_000, |s| s.v_path > 0.0);
        rig.ask(Control::Stop).unwrap();
        rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
        rig.ask(Control::Start).unwrap();
        rig.run_until(1_000, |s| s.v_path > 0.0);
        rig.plc.alive = false;
        rig.run_until(1_000, |s| s.alarm == Some(alarm::PLC_SIGN_OF_LIFE));
        rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
        rig.plc.alive = true;
        rig.step();
        rig.ask(Control::Reset).unwrap();
        rig.step();
        rig.cyclic.take_released()
    });
    assert_eq!(events, 0, "allocator calls in the cycle");
    assert_eq!(released.map(|p| p.id), Some(1));
    assert!(rig.plc.status.len() > 1_000);
    assert_eq!(rig.plc.requests.len(), 2);
}

/// At rest after NC stop the setpoint stays the same, bit for bit, however long it waits.
#[test]
fn the_setpoint_at_rest_after_nc_stop_does_not_move() {
    let md = md();
    for prog in [
        "N1 G1 X500 F3000\nM30\n",
        "N10 G0 X-30 Y-30 Z0\nN20 G1 G41 D1 X0 Y0 F3000\nN30 Y100\nN40 X40\nM30\n",
    ] {
        let mut rig = Rig::new(&md, 100_000);
        rig.load_and_start(&md, 1, prog);
        // At speed on the first line, or on N30 of the second program.
        rig.run_until(5_000, |s| {
            (s.v_path - V).abs() < 1e-9 && (s.line == 1 || s.pos[1] > 1.0)
        });
        rig.ask(Control::Stop).unwrap();
        let stopped = rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
        for _ in 0..1_000 {
            let s = rig.step();
            assert_eq!((s.pos, s.v_path), (stopped.pos, 0.0), "{prog}");
        }
        // An override turned in NC stop plans the rest again from where the path stands:
        // still not a bit of motion.
        for ovr in [0.3, 1.2, 0.05, 1.0] {
            rig.ask(Control::Override(ovr)).unwrap();
            for _ in 0..200 {
                let s = rig.step();
                assert_eq!((s.pos, s.v_path), (stopped.pos, 0.0), "{prog} at {ovr}");
            }
        }
    }
}

/// N10's motion handed over, then nothing: the path waits at rest, ACTIVE, at X10.
fn waiting_for_preparation(
    md: &MachineData,
    rig: &mut Rig,
    text: &str,
) -> (Arc<Handover>, Vec<Input>) {
    for _ in 0..3 {
        rig.step();
    }
    let (p, mut inputs, _) = plc_mock::fed(md, 1, text, Some(rig.cyclic.setpoint().axes()));
    let hand = p.hand.clone();
    rig.ask(Control::Load(p)).unwrap();
    rig.ask(Control::Start).unwrap();
    let Input::Motion(_) = inputs[0] else {
        panic!("{:?}", inputs[0])
    };
    let _ = hand.queue.push(inputs.remove(0));
    let rest = rig.run_until(5_000, |s| s.pos[0] == 10.0);
    assert_eq!((state(&rest), rest.v_path), (ChannelState::Active, 0.0));
    // Waiting is no alarm: preparation may be slow.
    for _ in 0..500 {
        let s = rig.step();
        assert_eq!(
            (state(&s), s.v_path, s.alarm),
            (ChannelState::Active, 0.0, None)
        );
    }
    (hand, inputs)
}

/// An alarm from preparation that comes while the path waits for it (the lookahead ran
/// dry) stops the channel at once, at rest where the prepared path ends.
#[test]
fn a_preparation_alarm_while_the_path_waits_stops_the_channel_with_it() {
    let md = md();
    let mut rig = Rig::new(&md, 20_000);
    let text = "N10 G1 X10 F3000\nN20 X20 Q5\nM30\n";
    let (h, inputs) = waiting_for_preparation(&md, &mut rig, text);
    let Input::Alarm { code, .. } = inputs[0] else {
        panic!("{:?}", inputs[0])
    };
    assert_eq!(code, 12050);
    let _ = h.queue.push(inputs[0].clone());
    let s = rig.run_until(3, |s| state(s) == ChannelState::Stopped);
    assert_eq!(
        (s.alarm.map(ChannelAlarm::number), s.pos, s.v_path),
        (Some(12050), [10.0, 0.0, 0.0], 0.0)
    );
    assert_eq!(
        rig.ask(Control::Start),
        Err(Refusal::Alarm(ChannelAlarm::new(12050).unwrap()))
    );
    assert_eq!(rig.ask(Control::Reset), Ok(()));
    assert_eq!(state(&rig.step()), ChannelState::Reset);
}

/// NC stop while the path waits for preparation: STOPPED at once; NC start goes on when the
/// rest arrives.
#[test]
fn nc_stop_while_the_path_waits_for_preparation_stops_it() {
    let md = md();
    let mut rig = Rig::new(&md, 20_000);
    let (h, inputs) = waiting_for_preparation(&md, &mut rig, "N10 G1 X10 F3000\nN20 X20\nM30\n");
    assert_eq!(rig.ask(Control::Stop), Ok(()));
    let s = rig.run_until(2, |s| state(s) == ChannelState::Stopped);
    assert_eq!((s.alarm, s.pos, s.v_path), (None, [10.0, 0.0, 0.0], 0.0));
    for i in inputs {
        let _ = h.queue.push(i);
    }
    assert_eq!(rig.ask(Control::Start), Ok(()));
    let end = rig.run_until(5_000, |s| state(s) == ChannelState::End);
    assert_eq!(end.pos, [20.0, 0.0, 0.0]);
}

/// A preparation thread that fails (panics) while the path waits: the channel stops with
/// alarm 1011 at the end of what was prepared, not with the program's end.
#[test]
fn a_failed_preparation_thread_stops_the_channel_with_1011() {
    let md = md();
    let mut rig = Rig::new(&md, 20_000);
    let (h, _) = waiting_for_preparation(&md, &mut rig, "N10 G1 X10 F3000\nN20 X20\nM30\n");
    h.failed.store(true, std::sync::atomic::Ordering::Release);
    h.finished.store(true, std::sync::atomic::Ordering::Release);
    let s = rig.run_until(3, |s| state(s) == ChannelState::Stopped);
    assert_eq!(
        (s.alarm.map(ChannelAlarm::number), s.pos, s.v_path),
        (Some(1011), [10.0, 0.0, 0.0], 0.0)
    );
}

/// The PLC falls silent while the path waits for its acknowledgement of M6: alarm 2000 one
/// cycle after the watchdog time, and the channel stops (it was at rest already).
#[test]
fn plc_silence_while_the_path_waits_for_an_acknowledgement_stops_the_channel() {
    let md = md();
    let mut rig = Rig::new(&md, 20_000);
    rig.plc.ack_after = None;
    rig.load_and_start(&md, 1, "N1 G1 X10 F3000\nN2 M6 T2\nN3 X20\nM30\n");
    rig.run_until(5_000, |s| s.aux_sent == 1);
    for _ in 0..200 {
        let s = rig.step();
        assert_eq!(
            (state(&s), s.pos, s.v_path),
            (ChannelState::Active, [10.0, 0.0, 0.0], 0.0)
        );
    }
    let c = rig.k;
    rig.plc.alive = false;
    let s = rig.run_until(1_000, |s| state(s) == ChannelState::Stopped);
    assert_eq!(
        (s.alarm, s.pos),
        (Some(alarm::PLC_SIGN_OF_LIFE), [10.0, 0.0, 0.0])
    );
    assert!(s.cycle <= c + WATCHDOG + 2, "{} after {c}", s.cycle);
    // NC stop and reset still act.
    assert_eq!(rig.ask(Control::Stop), Ok(()));
    assert_eq!(rig.ask(Control::Reset), Ok(()));
    assert_eq!(state(&rig.step()), ChannelState::Reset);
}

/// Ten 5 mm moves along X at F3000 (50 mm/s; braking from it takes 0.625 mm at 2000 mm/s²),
/// handed over by a slow preparation: one record every 40 cycles.
fn late_records(md: &MachineData, replay: Option<&[u32]>) -> (Vec<Status>, Vec<u32>) {
    let mut text = String::from("N1 G1 F3000 X5\n");
    for i in 2..=10 {
        text.push_str(&format!("N{i} X{}\n", 5 * i));
    }
    text.push_str("M30\n");
    let mut rig = Rig::new(md, 20_000);
    for _ in 0..3 {
        rig.step();
    }
    let (p, inputs, _) = plc_mock::fed(md, 1, &text, Some(rig.cyclic.setpoint().axes()));
    let hand = p.hand.clone();
    let mut inputs = inputs.into_iter();
    if replay.is_some() {
        // The replay's preparation is done before the first cycle.
        for i in inputs.by_ref() {
            let _ = hand.queue.push(i);
        }
        hand.finished
            .store(true, std::sync::atomic::Ordering::Release);
    }
    rig.ask(Control::Load(p)).unwrap();
    rig.ask(Control::Start).unwrap();
    let mut taken = Vec::new();
    while state(rig.plc.status.last().unwrap()) != ChannelState::End {
        assert!(rig.k < 10_000, "no end");
        match replay {
            Some(t) => rig
                .cyclic
                .replay_preparation(t.get(taken.len()).copied().unwrap_or(u32::MAX)),
            None if rig.k.is_multiple_of(40) => match inputs.next() {
                Some(i) => {
                    let _ = hand.queue.push(i);
                }
                None => hand
                    .finished
                    .store(true, std::sync::atomic::Ordering::Release),
            },
            None => {}
        }
        rig.step();
        taken.push(rig.cyclic.taken());
    }
    (rig.since(3).to_vec(), taken)
}

/// A replay takes into its lookahead exactly the records the live cycle took, whenever its
/// own preparation has them: the path that braked for records still missing live brakes
/// the same in the replay, bit for bit (docs/interfaces.md, "Record and replay").
#[test]
fn a_replay_takes_the_records_the_live_cycle_took_and_moves_the_same() {
    let md = md();
    let (live, taken) = late_records(&md, None);
    let (replayed, _) = late_records(&md, Some(&taken));
    let bits = |s: &Status| (s.cycle, s.pos.map(f64::to_bits), s.v_path.to_bits());
    assert_eq!(live.len(), replayed.len());
    for (a, b) in live.iter().zip(&replayed) {
        assert_eq!(bits(a), bits(b), "cycle {}", a.cycle);
    }
    // The live path stood waiting for records (5 mm at 50 mm/s is 100 cycles, a record
    // came every 40: it braked at each known end): a replay with the whole program in its
    // lookahead would have moved otherwise.
    assert!(live
        .iter()
        .skip(50)
        .any(|s| s.v_path < 20.0 && state(s) == ChannelState::Active));
    assert!(live.len() > 400, "{} cycles", live.len());
    let (whole, _) = late_records(&md, Some(&vec![u32::MAX; taken.len()]));
    let moves = |r: &[Status]| r.iter().map(bits).collect::<Vec<_>>();
    assert_ne!(
        moves(&whole),
        moves(&live),
        "the lookahead made no difference"
    );
}
