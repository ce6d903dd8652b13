//! The spindle (docs/spindle.md): S and the spindle M functions of every dialect, constant
//! surface speed from the transverse axis with its limit, and the feed per revolution that
//! follows the spindle's actual speed — through `softnc simulate`'s setpoint stream, with
//! speeds and path speeds worked out by hand.

#[path = "support/sim.rs"]
mod sim;

use nc_kernel::simulate::{run, Options};
use nc_kernel::{interpret, AlarmCode, MachineData, SpindleDir, ToolTable};

struct Row {
    x: f64,
    z: f64,
    spindle: f64,
    /// mm/min
    v: f64,
    line: u32,
}

fn machine(over: &[&str]) -> MachineData {
    let over: Vec<String> = over.iter().map(|s| s.to_string()).collect();
    MachineData::load(None, &over).expect("machine data")
}

fn lathe(over: &[&str]) -> MachineData {
    let over: Vec<String> = over.iter().map(|s| s.to_string()).collect();
    MachineData::load(
        Some(std::path::Path::new("config/siemens-808d.toml")),
        &over,
    )
    .expect("lathe machine data")
}

fn simulate(md: &MachineData, text: &str) -> Vec<Row> {
    let (text, s) = sim::csv(md, text);
    assert!(s.alarms.is_empty(), "{:?}", s.alarms);
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let col = |name: &str| sim::column(header, name);
    let (x, z, s1, v, b) = (col("X"), col("Z"), col("S1"), col("v_path"), col("block"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Row {
                x: f[x].parse().unwrap(),
                z: f[z].parse().unwrap(),
                spindle: f[s1].parse().unwrap(),
                v: f[v].parse().unwrap(),
                line: f[b].trim_start_matches('L').parse().unwrap_or(0),
            }
        })
        .collect()
}

#[test]
fn the_spindle_m_functions_of_each_dialect_set_its_direction() {
    for (dialect, text) in [
        ("siemens-840c", "M3 S1000\nM4\nM5\nM19\n"),
        ("fanuc", "M3 S1000 ;\nM4 ;\nM5 ;\nM19 ;\n"),
        ("isg", "M3 S1000\nM4\nM5\nM19\n"),
    ] {
        let md = machine(&[&format!("dialect=\"{dialect}\"")]);
        let b = interpret("s.nc", text, &md, &ToolTable::builtin()).unwrap();
        let dirs: Vec<SpindleDir> = b.iter().map(|b| b.modal.spindle_dir).collect();
        assert_eq!(
            dirs,
            [
                SpindleDir::Clockwise,
                SpindleDir::CounterClockwise,
                SpindleDir::Stop,
                SpindleDir::Orient
            ],
            "{dialect}"
        );
        assert_eq!(b[1].modal.spindle, 1000.0, "S stays");
        // The M words still go to the PLC.
        assert!(b[1]
            .words
            .iter()
            .any(|w| w.address == b'M' && w.value == 4.0));
    }
    let md = machine(&[]);
    let a = interpret("s.nc", "M3 M4 S100\n", &md, &ToolTable::builtin()).unwrap_err();
    assert_eq!((a.code, a.col), (AlarmCode::SameGroupTwice, 4), "{a}");
}

#[test]
fn the_speed_setpoint_follows_s_and_the_direction_at_the_s_points() {
    // 840C: M3 S1200 before line 2's motion, M4 S800 before line 3's; M5 before line 4's.
    // (No block numbers: simulate's block column names the line.)
    let md = machine(&[]);
    let rows = simulate(
        &md,
        "G0 X0 Y0 Z0\nM3 S1200 G1 X10 F1000\nM4 S800 X20\nM5 X30\nM30\n",
    );
    // While a block's motion runs its spindle is set; line 2's M4 waits for its
    // acknowledgement (machine data ipo.wait_for_ack), so it goes out with the path at rest
    // at line 2's end; line 4's M5 does not wait: it goes out as line 4's motion starts.
    let moving = |line: u32| rows.iter().filter(move |r| r.line == line && r.v > 0.0);
    assert!(moving(2).count() > 500 && moving(2).all(|r| r.spindle == 1200.0));
    assert!(moving(3).count() > 500 && moving(3).all(|r| r.spindle == -800.0));
    let m5 = rows.iter().position(|r| r.line == 4).unwrap();
    assert!(rows[m5 + 1..].iter().all(|r| r.spindle == 0.0));
    assert!(rows[..m5]
        .iter()
        .filter(|r| r.line == 3)
        .all(|r| r.spindle == -800.0));
    // Over machine data's maximum: the maximum.
    let md = machine(&["spindle.max_speed=1000"]);
    let rows = simulate(&md, "M3 S1200 G1 X10 F1000\nM30\n");
    assert!(rows
        .iter()
        .filter(|r| r.line == 1 && r.v > 0.0)
        .all(|r| r.spindle == 1000.0));
}

#[test]
fn constant_surface_speed_follows_the_diameter_with_the_lims_limit() {
    // 808D lathe, X in diameter: a facing cut from X80 (r 40) to X0 at 180 m/min,
    // LIMS=3000. n = 180000 / (2π·r): 716.197 rev/min at r 40; the limit 3000 below
    // r = 180000 / (2π·3000) = 9.5493 mm.
    let md = lathe(&[]);
    let rows = simulate(
        &md,
        "G0 X80 Z0\nG96 S180 LIMS=3000 M3\nG1 X0 F300\nG97 S500\nG0 Z5\nM30\n",
    );
    let facing: Vec<&Row> = rows.iter().filter(|r| r.line == 3).collect();
    assert!(facing.len() > 100);
    for r in &facing {
        let radius = r.x.abs();
        let want = if 2.0 * std::f64::consts::PI * radius * 3000.0 <= 180_000.0 {
            3000.0
        } else {
            180_000.0 / (2.0 * std::f64::consts::PI * radius)
        };
        assert!(
            (r.spindle - want).abs() < 1e-9,
            "r {radius}: {} vs {want}",
            r.spindle
        );
    }
    assert!((facing[0].spindle - 716.197_243_913_529_3).abs() < 0.5);
    assert_eq!(facing.last().unwrap().spindle, 3000.0);
    // G97 S500 (line 4, no motion) goes out as line 5's infeed outside the plane starts
    // (840C 11.11): from there 500 rev/min, whatever X; at the program's end the spindle
    // stops.
    let retract: Vec<&Row> = rows.iter().filter(|r| r.line == 5).collect();
    assert!(retract.len() > 100);
    assert!(retract[1..retract.len() - 1]
        .iter()
        .all(|r| r.spindle == 500.0));
    assert_eq!(rows.last().unwrap().spindle, 0.0, "stopped at the end");
    assert!(rows.iter().all(|r| r.z <= 5.0));
}

#[test]
fn feed_per_revolution_follows_the_spindle_as_it_comes_up_to_speed() {
    // 840C: M3 S1000 then G95 F0.3: 0.3 mm/rev × 1000 rev/min = 300 mm/min once the
    // spindle is at speed. The simulated drive ramps at plc.spindle_acceleration (6000
    // rev/min per s: 1000 rev/min after 1/6 s); M3 waits for its acknowledgement (at once in
    // simulate), so the path starts while the spindle comes up and its speed follows.
    let md = machine(&[]);
    let rows = simulate(&md, "G0 X0 Y0 Z0\nM3 S1000\nG95 G1 X50 F0.3\nM30\n");
    let cut: Vec<&Row> = rows.iter().filter(|r| r.line == 3).collect();
    let top = cut.iter().map(|r| r.v).fold(0.0, f64::max);
    assert!(
        (top - 300.0).abs() < 1e-6,
        "cruise at 0.3 × 1000 = 300 mm/min: {top}"
    );
    assert!(cut.iter().all(|r| r.v <= 300.0 + 1e-6));
    // While the spindle comes up the path never runs faster than F × its actual speed:
    // the model's 6 rev/min per cycle from the cycle M3 went out.
    let m3 = rows.iter().position(|r| r.spindle == 1000.0).unwrap();
    for (k, r) in rows.iter().enumerate().skip(m3) {
        let n_actual = (6.0 * (k - m3 + 1) as f64).min(1000.0);
        assert!(
            r.v <= 0.3 * n_actual + 1e-6,
            "cycle {k}: {} > 0.3 × {n_actual}",
            r.v
        );
    }
    // At 50 mm in 300 mm/min the cut takes 10 s (plus ramps); at 1000 mm/min (F as per
    // minute) it would take 3 s.
    assert!(cut.len() > 10_000, "{}", cut.len());
    assert_eq!(cut.last().unwrap().x, 50.0);
}

#[test]
fn feed_per_revolution_waits_while_the_spindle_stands() {
    // G95 with the spindle stopped: the path does not move (Fanuc, Siemens: no feed without
    // revolutions); simulate's rest limit ends the run with alarm 90002 instead of a hang.
    let md = machine(&["simulate.max_rest_time=2"]);
    let mut out = Vec::new();
    let s = run(
        "s.nc",
        "N10 G0 X0 Y0 Z0\nN20 G95 G1 X50 F0.3\nN30 M30\n",
        &md,
        &ToolTable::builtin(),
        &Options::default(),
        &mut out,
    )
    .unwrap();
    let codes: Vec<u32> = s.alarms.iter().map(|a| a.number()).collect();
    assert_eq!(codes, [90002], "{:?}", s.alarms);
}

#[test]
fn g97_without_s_keeps_the_speed_constant_surface_speed_had_there() {
    // 808D: G96 S150 at X62 (r 31): 150000 / (2π·31) = 770.1046 rev/min; G97 alone there
    // keeps that speed (840D, TF5200: the last speed remains), wherever X goes after.
    let md = lathe(&[]);
    let rows = simulate(
        &md,
        "G0 X62 Z2\nG96 S150 M3\nG1 Z-5 F200\nG97\nG1 X40 Z-10\nM30\n",
    );
    let n = 150_000.0 / (2.0 * std::f64::consts::PI * 31.0);
    let after: Vec<&Row> = rows.iter().filter(|r| r.line == 5 && r.v > 0.0).collect();
    assert!(after.len() > 100);
    assert!(
        after.iter().all(|r| (r.spindle - n).abs() < 1e-9),
        "{}",
        after[0].spindle
    );
}

#[test]
fn a_change_of_the_feeds_unit_deletes_f() {
    // 840D feeds: "the programmed F value is deleted when switching G93/G94/G95": a move
    // after G95 without a new F is alarm 10860 at its block, not 200 mm/rev.
    let md = machine(&[]);
    let a = interpret(
        "s.nc",
        "S1000 M3\nG1 X10 F200\nG95 X300\n",
        &md,
        &ToolTable::builtin(),
    )
    .unwrap_err();
    assert_eq!((a.number(), a.line), (10860, 3), "{a}");
    assert!(interpret(
        "s.nc",
        "S1000 M3\nG1 X10 F200\nG95 X20 F0.1\nG94 X30 F300\n",
        &md,
        &ToolTable::builtin()
    )
    .is_ok());
}

#[test]
fn constant_surface_speed_takes_a_rapid_moves_end_point() {
    // G0 X30 from X80 under G96 S180 (Fanuc, 840D: the speed does not follow a rapid
    // traverse): the whole move at the speed of r = 15, 180000 / (2π·15) = 1909.86.
    let md = lathe(&[]);
    let rows = simulate(&md, "G0 X80 Z2\nG96 S180 M3\nG0 X30\nG1 Z-5 F100\nM30\n");
    let n = 180_000.0 / (2.0 * std::f64::consts::PI * 15.0);
    let rapid: Vec<&Row> = rows.iter().filter(|r| r.line == 3 && r.v > 0.0).collect();
    assert!(rapid.len() > 10);
    assert!(
        rapid.iter().all(|r| (r.spindle - n).abs() < 1e-9),
        "{}",
        rapid[0].spindle
    );
}

#[test]
fn an_alarm_stops_the_spindle() {
    // simulate's machine-time limit (alarm 90001) in the middle of a cut: the path brakes
    // and the spindle's setpoint is 0 from the alarm on.
    let md = machine(&["simulate.max_machine_time=2"]);
    let mut out = Vec::new();
    let s = run(
        "s.nc",
        "S1000 M3\nG1 X500 F1000\nM30\n",
        &md,
        &ToolTable::builtin(),
        &Options::default(),
        &mut out,
    )
    .unwrap();
    assert_eq!(s.alarms.first().map(|a| a.number()), Some(90001));
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    let s1 = sim::column(lines.next().unwrap(), "S1");
    let speeds: Vec<f64> = lines
        .map(|l| l.split(',').nth(s1).unwrap().parse().unwrap())
        .collect();
    assert!(speeds.contains(&1000.0));
    assert_eq!(*speeds.last().unwrap(), 0.0);
}
