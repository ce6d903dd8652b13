//! Thread cutting in the IPO (docs/turning.md, "Threading"): a thread runs at its lead per
//! spindle revolution whatever the feed override, and an NC stop (feed hold) during a
//! thread takes effect at the thread's end — the channel driven cycle by cycle on the
//! Fanuc lathe, with the spindle model ramping to S.

use nc_kernel::ipo::{Channel, ChannelState, Setpoint, SpindleModel};
use nc_kernel::{MachineData, ToolTable};

struct Row {
    pos: [f64; 3],
    /// mm/min
    v: f64,
    line: u32,
    stopped: bool,
}

fn lathe() -> MachineData {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("config/fanuc-lathe.toml");
    MachineData::load(Some(&path), &[]).expect("machine data")
}

/// The channel's setpoints with operator actions ("stop", "start", an override in %) at
/// given cycles.
fn drive(text: &str, actions: &[(u64, &str)]) -> Vec<Row> {
    drive_single(text, actions, false)
}

/// `drive`; `single`: in single block mode, NC start given at every single-block stop.
fn drive_single(text: &str, actions: &[(u64, &str)], single: bool) -> Vec<Row> {
    let md = lathe();
    let tools = ToolTable::builtin();
    let job = nc_kernel::handover::Job {
        name: "t.nc",
        source: text,
        md: &md,
        tools: &tools,
        at: None,
    };
    let (start, inputs, reports) = nc_kernel::handover::prepare_all(job);
    assert!(reports.is_empty());
    let mut it = inputs.into_iter();
    let mut pending = None;
    let mut ch = Channel::new(&md, start);
    let mut sp = Setpoint::new(start);
    let mut spindle = SpindleModel::new(
        md.plc.spindle_acceleration,
        f64::from(md.ipo.cycle_us) * 1e-6,
    );
    ch.start();
    let mut out = Vec::new();
    for k in 0..200_000u64 {
        ch.fill(&mut pending, || it.next());
        for &(at, what) in actions {
            if at == k {
                match what {
                    "stop" => ch.stop(),
                    "start" => ch.start(),
                    o => ch.set_override(o.parse::<f64>().unwrap() / 100.0),
                }
            }
        }
        while ch.acks_due() > 0 {
            ch.ack();
        }
        if single && k == 0 {
            ch.set_single_block(true);
        }
        ch.cycle(k, &mut sp);
        ch.set_spindle_actual(spindle.follow(sp.spindle));
        let events = format!("{:?}", sp.events);
        if events.contains("SingleBlock") {
            ch.start();
        }
        out.push(Row {
            pos: sp.pos,
            v: sp.v_path * 60.0,
            line: sp.source.map_or(0, |s| s.line),
            stopped: events.contains("Stopped") || events.contains("SingleBlock"),
        });
        if sp.state == ChannelState::End {
            break;
        }
    }
    out
}

/// M3 S600, then G32 at lead 2 from Z5 to Z-40 (line 3): 2 mm × 10 rev/s = 1200 mm/min.
const PROGRAM: &str = "G0 X30. Z5.\nM3 S600\nG32 Z-40. F2.\nG0 X40.\nZ5.\nM30\n";

fn thread_rows(rows: &[Row]) -> (usize, usize) {
    let first = rows.iter().position(|r| r.line == 3).unwrap();
    let last = rows.iter().rposition(|r| r.line == 3).unwrap();
    (first, last)
}

#[test]
fn a_thread_runs_at_the_lead_per_revolution_at_100_percent_override() {
    let plain = drive(PROGRAM, &[]);
    let (first, last) = thread_rows(&plain);
    let top = plain[first..=last].iter().map(|r| r.v).fold(0.0, f64::max);
    assert!((top - 1200.0).abs() < 1e-6, "{top}");
    // Override 50 % in the middle of the thread: the thread goes on at 1200 mm/min, and
    // ends where it did without it; the rapids after it run at half speed at most.
    let mid = (first + last) / 2;
    let rows = drive(PROGRAM, &[(mid as u64, "50")]);
    let (f2, l2) = thread_rows(&rows);
    assert_eq!((f2, l2), (first, last));
    assert!(rows[mid..l2]
        .iter()
        .all(|r| (r.v - 1200.0).abs() < 1e-6 || r.pos[2] < -39.0));
    let rapid_top = |rows: &[Row]| {
        rows.iter()
            .filter(|r| r.line == 5)
            .map(|r| r.v)
            .fold(0.0, f64::max)
    };
    assert!(rapid_top(&rows) <= 0.5 * rapid_top(&plain) + 1e-6);
    assert!(rapid_top(&rows) > 0.0);
}

#[test]
fn a_feed_hold_during_the_thread_stops_at_its_end() {
    let plain = drive(PROGRAM, &[]);
    let (first, last) = thread_rows(&plain);
    let mid = (first + last) / 2;
    let rows = drive(
        PROGRAM,
        &[(mid as u64, "stop"), (last as u64 + 3000, "start")],
    );
    // The thread runs on as without the stop (the replanned profile differs by rounding
    // only) up to its braking at the end, where the path comes to rest on its end point
    // (15, -40), not on the rapid after it (without the stop the thread hands over to the
    // rapid at the corner's speed).
    let cruise = rows[mid..last]
        .iter()
        .filter(|r| (r.v - 1200.0).abs() < 1e-6)
        .count();
    for k in mid..mid + cruise {
        let d = (0..3).map(|i| (rows[k].pos[i] - plain[k].pos[i]).abs());
        assert!(d.fold(0.0, f64::max) < 1e-9, "cycle {k}");
    }
    let stopped = rows.iter().position(|r| r.stopped).unwrap();
    assert!(stopped > last && stopped < last + 3000);
    assert_eq!(rows[stopped].pos, [15.0, 0.0, -40.0]);
    assert!(rows[stopped..last + 3000]
        .iter()
        .all(|r| r.pos == [15.0, 0.0, -40.0]));
    // NC start: the program goes on to its end.
    assert_eq!(rows.last().unwrap().pos, plain.last().unwrap().pos);
    // A stop before the thread (on the rapid to it) holds before the thread starts.
    let rows = drive(PROGRAM, &[(2, "stop")]);
    assert!(rows.iter().all(|r| r.line != 3));
}

#[test]
fn single_block_does_not_stop_inside_a_thread() {
    // Two thread blocks chained without an exact stop (G64): straight to Z-20, then a
    // taper to (17, -28); then the rapids. Single block stops after the first G0, then
    // at the end of the first block after the threads that is no thread (Fanuc): G0 X40
    // at (20, -28); never between or at the end of the threads. The program's end follows.
    let text = "G64 G0 X30. Z5.\nM3 S600\nG32 Z-20. F2.\nX34. Z-28.\nG0 X40.\nZ5.\nM30\n";
    let rows = drive_single(text, &[], true);
    let stops: Vec<[f64; 3]> = rows.iter().filter(|r| r.stopped).map(|r| r.pos).collect();
    assert_eq!(stops, [[15.0, 0.0, 5.0], [20.0, 0.0, -28.0]]);
    assert_eq!(rows.last().unwrap().pos, [20.0, 0.0, 5.0]);
}

#[test]
fn a_feed_hold_in_chained_threads_waits_for_the_last_one() {
    // G32 to Z-20, then the taper to (17, -28) without an exact stop: a stop in the middle
    // of the first thread brings the path to rest at the end of the second.
    let text = "G64 G0 X30. Z5.\nM3 S600\nG32 Z-20. F2.\nX34. Z-28.\nG0 X40.\nZ5.\nM30\n";
    let plain = drive(text, &[]);
    let (first, _) = thread_rows(&plain);
    let end_first = plain.iter().position(|r| r.line == 4).unwrap();
    let mid = (first + end_first) / 2;
    let rows = drive(text, &[(mid as u64, "stop")]);
    let stopped = rows.iter().position(|r| r.stopped).unwrap();
    assert_eq!(rows[stopped].pos, [17.0, 0.0, -28.0]);
    assert!(rows[..stopped].iter().all(|r| r.line <= 4));
}
