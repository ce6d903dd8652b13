//! Interpolation checked from the setpoint stream alone (issue 5): `softnc simulate`'s rows
//! against the prepared path and the machine data, with geometry and finite differences
//! written here.
//!
//! - every setpoint lies on its block's compensated path (1e-9 mm);
//! - no axis exceeds its velocity, acceleration or jerk limit (finite differences of the
//!   setpoints over the IPO cycle; tolerance 1e-6 relative plus rounding);
//! - at every G9 block end the setpoint is exactly the end point for two cycles (path speed 0
//!   for one whole cycle);
//! - corner speeds do not exceed the planner's corner limit;
//! - NC stop, override and single block;
//! - the same program and machine data give the same bits (sha256 pinned per sample program,
//!   and with the preparation thread slowed down).

use nc_kernel::ipo::{AxisLimits, Piece};
use nc_kernel::simulate::{run, Options, Summary};
use nc_kernel::{MachineData, Segment, Shape, ToolTable};
use sha2::{Digest, Sha256};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[derive(Debug, Clone)]
struct Row {
    cycle: u64,
    pos: [f64; 3],
    /// mm/min
    v: f64,
    block: String,
    events: String,
}

fn machine(file: Option<&str>, over: &[&str]) -> MachineData {
    let over: Vec<String> = over.iter().map(|s| s.to_string()).collect();
    let path = file.map(|f| root().join("config").join(f));
    MachineData::load(path.as_deref(), &over).expect("machine data")
}

fn simulate_bytes(md: &MachineData, text: &str, opts: &Options) -> (Vec<u8>, Summary) {
    let tools = ToolTable::builtin();
    let mut out = Vec::new();
    let s = run("test.mpf", text, md, &tools, opts, &mut out).expect("simulate");
    (out, s)
}

fn rows(csv: &[u8]) -> Vec<Row> {
    let text = std::str::from_utf8(csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("cycle,time,X,Y,Z,S1,v_path,block,events")
    );
    lines
        .map(|l| {
            let f: Vec<&str> = l.splitn(9, ',').collect();
            Row {
                cycle: f[0].parse().unwrap(),
                pos: [
                    f[2].parse().unwrap(),
                    f[3].parse().unwrap(),
                    f[4].parse().unwrap(),
                ],
                // f[5]: the spindle (tests/spindle.rs)
                v: f[6].parse().unwrap(),
                block: f[7].to_string(),
                events: f[8].to_string(),
            }
        })
        .collect()
}

fn simulate(md: &MachineData, text: &str) -> (Vec<Row>, Summary) {
    let (b, s) = simulate_bytes(md, text, &Options::default());
    (rows(&b), s)
}

fn block_name(s: &Segment) -> String {
    match s.source.number {
        Some(n) => n.to_string(),
        None => format!("L{}", s.source.line),
    }
}

/// Distance from `p` to a prepared segment, written independently of the kernel: a line, or
/// an arc about a fixed centre whose radius and normal coordinate change linearly with the
/// angle from `from` to `to`.
fn dist_to(seg: &Segment, p: [f64; 3]) -> f64 {
    match seg.shape {
        Shape::Line => {
            let d = [
                seg.to[0] - seg.from[0],
                seg.to[1] - seg.from[1],
                seg.to[2] - seg.from[2],
            ];
            let w = [p[0] - seg.from[0], p[1] - seg.from[1], p[2] - seg.from[2]];
            let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let t = ((w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / dd).clamp(0.0, 1.0);
            let q = [w[0] - t * d[0], w[1] - t * d[1], w[2] - t * d[2]];
            (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt()
        }
        Shape::Arc {
            center,
            center_end,
            ccw,
            plane,
            ..
        } => {
            assert_eq!(center, center_end, "moving centres are not checked here");
            let (a, o, n) = (
                plane.abscissa as usize,
                plane.ordinate as usize,
                plane.normal as usize,
            );
            let ang = |q: [f64; 3]| (q[o] - center[o]).atan2(q[a] - center[a]);
            let rad = |q: [f64; 3]| (q[a] - center[a]).hypot(q[o] - center[o]);
            let tau = std::f64::consts::TAU;
            let dir = |x: f64| {
                let x = if ccw { x } else { -x };
                x.rem_euclid(tau)
            };
            let full = seg.from[a] == seg.to[a] && seg.from[o] == seg.to[o];
            let sweep = if full {
                tau
            } else {
                dir(ang(seg.to) - ang(seg.from))
            };
            let mut phi = dir(ang(p) - ang(seg.from));
            if phi > sweep && phi > (sweep + tau) / 2.0 {
                phi -= tau; // just before the start
            }
            let (r0, r1) = (rad(seg.from), rad(seg.to));
            let u = phi / sweep;
            if !(-1e-9..=1.0 + 1e-9).contains(&u) {
                return f64::INFINITY;
            }
            let r = r0 + (r1 - r0) * u;
            let h = seg.from[n] + (seg.to[n] - seg.from[n]) * u;
            (rad(p) - r).hypot(p[n] - h)
        }
    }
}

/// Every setpoint lies on a segment of its block (1e-9 mm); returns the rows checked.
fn assert_on_path(md: &MachineData, text: &str, rows: &[Row]) -> usize {
    let segs = nc_kernel::prepare("test.mpf", text, md, &ToolTable::builtin()).expect("path");
    let mut checked = 0;
    for r in rows {
        let own: Vec<&Segment> = segs.iter().filter(|s| block_name(s) == r.block).collect();
        if own.is_empty() {
            continue;
        }
        let d = own
            .iter()
            .map(|s| dist_to(s, r.pos))
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= 1e-9,
            "cycle {} ({}) at {:?}: {d:e} mm off the path",
            r.cycle,
            r.block,
            r.pos
        );
        checked += 1;
    }
    checked
}

/// Largest |finite difference| of order 1, 2, 3 per axis over the cycle, relative to the
/// axis's limit; panics on any above 1 + 1e-6.
fn assert_within_limits(md: &MachineData, rows: &[Row]) -> [[f64; 3]; 3] {
    let t = f64::from(md.ipo.cycle_us) * 1e-6;
    let mut worst = [[0.0; 3]; 3];
    for ax in 0..3 {
        let Some(lim) = md.axes.get(ax) else {
            continue;
        };
        let x: Vec<f64> = rows.iter().map(|r| r.pos[ax]).collect();
        let v: Vec<f64> = x.windows(2).map(|w| (w[1] - w[0]) / t).collect();
        let a: Vec<f64> = v.windows(2).map(|w| (w[1] - w[0]) / t).collect();
        let j: Vec<f64> = a.windows(2).map(|w| (w[1] - w[0]) / t).collect();
        // Rounding of positions ~1e2 mm: ~1e-14 mm per setpoint, /T³ for the jerk.
        let noise = 1e-13 / (t * t * t);
        for (k, (series, limit)) in [
            (&v, lim.max_velocity / 60.0),
            (&a, lim.max_acceleration),
            (&j, lim.max_jerk),
        ]
        .into_iter()
        .enumerate()
        {
            for (i, d) in series.iter().enumerate() {
                let r = (d.abs() - noise.min(limit * 1e-6)) / limit;
                assert!(
                    r <= 1.0 + 1e-6,
                    "axis {} order {} at cycle {}: {} above the limit {}",
                    ["X", "Y", "Z"][ax],
                    k + 1,
                    rows[i + k + 1].cycle,
                    d,
                    limit
                );
                worst[ax][k] = f64::max(worst[ax][k], r);
            }
        }
    }
    worst
}

fn workpiece() -> String {
    std::fs::read_to_string(root().join("programs/siemens-840c/11_15_workpiece.mpf")).unwrap()
}

#[test]
fn the_840c_workpiece_runs_on_its_path_within_the_axis_limits() {
    let md = machine(None, &[]);
    let text = workpiece();
    let (rows, s) = simulate(&md, &text);
    assert_eq!(s.end_state.map(|s| s.name()), Some("END"));
    assert!(s.alarms.is_empty());
    let checked = assert_on_path(&md, &text, &rows);
    assert!(checked > 40_000, "{checked}");
    let worst = assert_within_limits(&md, &rows);
    // The axes are used: acceleration and velocity reach their limits somewhere.
    assert!(worst[1][0] > 0.99 && worst[1][1] > 0.99, "{worst:?}");
    // It ends exactly at N130's end point (Z50 plus D1's tool length 100) with M30 and END.
    let last = rows.last().unwrap();
    assert_eq!(last.pos, [15.0, 60.0, 150.0]);
    assert_eq!(last.events, "M30;END");
    // M3 waits for its acknowledgement: the path stands at S0 for it.
    let m3 = rows
        .iter()
        .position(|r| r.events.contains("aux S80 M3"))
        .unwrap();
    assert_eq!(rows[m3].v, 0.0);
    assert_eq!(rows[m3].pos, rows[m3 + 1].pos);
}

#[test]
fn helices_and_full_circles_lie_on_their_curves() {
    let md = machine(None, &[]);
    let text = "N10 G17 G90 G0 X10 Y0 Z0\n\
                N20 G3 X10 Y0 Z-6 I-10 J0 F2000 ; a full helix turn\n\
                N30 G2 X-10 Y0 I-10 J0 ; half circle\n\
                N40 G1 X-10 Y20 Z0\n\
                N50 G3 X-30 Y20 I-10 J0 Z-3 ; half helix\n\
                N60 M30\n";
    let (rows, s) = simulate(&md, text);
    assert_eq!(s.end_state.map(|s| s.name()), Some("END"));
    assert!(assert_on_path(&md, text, &rows) > 1000);
    assert_within_limits(&md, &rows);
}

#[test]
fn every_g9_block_ends_exactly_at_rest_for_a_cycle() {
    let md = machine(None, &[]);
    let text = "N10 G90 G1 X20 Y0 F3000\n\
                N20 G9 X40 Y5\n\
                N30 X60 Y0\n\
                N40 G9 G2 X80 Y0 I10 J0\n\
                N50 G1 X100 Y0\n\
                N60 G9 X100.001 Y0 ; a tiny block\n\
                N70 X120 Y10\n\
                N80 M30\n";
    let (rows, _) = simulate(&md, text);
    for (block, end) in [
        ("N20", [40.0, 5.0, 0.0]),
        ("N40", [80.0, 0.0, 0.0]),
        ("N60", [100.001, 0.0, 0.0]),
    ] {
        let k = rows
            .iter()
            .position(|r| r.pos == end)
            .unwrap_or_else(|| panic!("{block}'s end point is never a setpoint"));
        assert_eq!(rows[k + 1].pos, end, "{block}: one cycle at rest");
        assert_eq!(rows[k + 1].v, 0.0, "{block}");
        assert_eq!(rows[k].block, block);
    }
    assert_within_limits(&md, &rows);
    assert_on_path(&md, text, &rows);
}

#[test]
fn corners_are_not_passed_faster_than_the_planner_allows() {
    // A polygon with corners of 5°, 30°, 90°, 150° and a tangent line-to-arc transition.
    let md = machine(None, &[]);
    let text = "N10 G90 G1 X50 Y0 F6000\n\
                N20 X100 Y4.374\n\
                N30 X140 Y27.468\n\
                N40 X117 Y67.3\n\
                N50 X20 Y40\n\
                N60 X0 Y40\n\
                N70 G2 X-20 Y20 I0 J-20\n\
                N80 G1 X-20 Y0\n\
                N90 M30\n";
    let segs = nc_kernel::prepare("test.mpf", text, &md, &ToolTable::builtin()).unwrap();
    let lim = AxisLimits::new(&md);
    let (rows, _) = simulate(&md, text);
    let t = f64::from(md.ipo.cycle_us) * 1e-6;
    let mut seen = 0;
    for w in segs.windows(2) {
        let (a, b) = (Piece::new(&w[0]).unwrap(), Piece::new(&w[1]).unwrap());
        let limit = lim.corner(&a, &b) * 60.0; // mm/min
        let (na, nb) = (block_name(&w[0]), block_name(&w[1]));
        // The rows on either side of the corner: the path's acceleration is 0 there and the
        // jerk at most the axes', so within a cycle the speed moves by < j·T²/2.
        let slack = 50_000.0 * t * t * 60.0;
        let Some(k) = rows
            .windows(2)
            .position(|p| p[0].block == na && p[1].block == nb)
        else {
            panic!("no transition {na} → {nb}");
        };
        for r in &rows[k..k + 2] {
            assert!(
                r.v <= limit + slack,
                "{na} → {nb}: {} mm/min above the corner limit {limit}",
                r.v
            );
        }
        seen += 1;
    }
    assert_eq!(seen, 7);
    assert_within_limits(&md, &rows);
}

#[test]
fn override_scales_the_feed_and_keeps_the_limits() {
    let md = machine(None, &[]);
    let text = "N10 G90 G1 X200 F3000\nN20 M30\n";
    let top = |ovr: f64| {
        let opts = Options {
            override_: ovr,
            ..Default::default()
        };
        let (b, _) = simulate_bytes(&md, text, &opts);
        let rows = rows(&b);
        assert_within_limits(&md, &rows);
        (rows.iter().map(|r| r.v).fold(0.0, f64::max), rows.len())
    };
    let (v100, n100) = top(1.0);
    let (v50, n50) = top(0.5);
    let (v120, _) = top(1.2);
    assert!((v100 - 3000.0).abs() < 1e-6, "{v100}");
    assert!((v50 - 1500.0).abs() < 1e-6, "{v50}");
    assert!((v120 - 3600.0).abs() < 1e-6, "{v120}");
    assert!(n50 > n100);
}

#[test]
fn m00_and_single_block_stop_at_block_end() {
    let md = machine(None, &[]);
    let text = "N10 G90 G1 X20 F3000\nN20 X40 M0\nN30 X60\nN40 M30\n";
    let (stopped, _) = simulate(&md, text);
    let k = stopped
        .iter()
        .position(|r| r.events.contains("M0"))
        .unwrap();
    assert_eq!(stopped[k].pos, [40.0, 0.0, 0.0]);
    assert_eq!(stopped[k].v, 0.0);
    assert!(stopped[k].events.contains("STOPPED"));
    // Single block: a stop at every S point before the next motion (N10's and N20's
    // ends), each exactly on it; N30's end is the program end.
    let text = "N10 G90 G1 X20 F3000\nN20 X40\nN30 X60\nN40 M30\n";
    let opts = Options {
        single_block: true,
        ..Default::default()
    };
    let (b, s) = simulate_bytes(&md, text, &opts);
    assert_eq!(s.end_state.map(|s| s.name()), Some("END"));
    let stops: Vec<([f64; 3], f64)> = rows(&b)
        .iter()
        .filter(|r| r.events.contains("single-block"))
        .map(|r| (r.pos, r.v))
        .collect();
    assert_eq!(
        stops,
        vec![([20.0, 0.0, 0.0], 0.0), ([40.0, 0.0, 0.0], 0.0)]
    );
}

/// The machine data file for a sample program's directory.
fn md_for(dir: &str) -> Option<&'static str> {
    match dir {
        "isg" => Some("isg.toml"),
        "fanuc" => Some("fanuc.toml"),
        "siemens-808d" => Some("siemens-808d.toml"),
        "siemens-808d-c" => Some("siemens-808d-c.toml"),
        "fanuc-5axis" => Some("fanuc-5axis.toml"),
        "fanuc-lathe" => Some("fanuc-lathe.toml"),
        "siemens-840d" => Some("siemens-840d.toml"),
        _ => None,
    }
}

/// Machine data a sample runs with beyond its directory's file. Two ISG feature examples draw
/// contours that touch themselves (the tool path of N50 of the feed example ends on N90's
/// line; the two circles of the D change example overlap at one depth): the shipped deep
/// check rightly refuses them, so they run with the ISG control's own checking.
fn own_checking(rel: &str) -> &'static [&'static str] {
    match rel {
        "programs/isg/d_change.nc" | "programs/isg/g11_feed_adaption.nc" => {
            &["trc.bottleneck_window=0", "trc.whole_program_check=false"]
        }
        _ => &[],
    }
}

fn sample_programs() -> Vec<(String, PathBuf, Option<&'static str>)> {
    let mut out = Vec::new();
    let mut dirs: Vec<_> = std::fs::read_dir(root().join("programs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dirs.sort();
    for d in dirs {
        let dname = d.file_name().unwrap().to_string_lossy().to_string();
        let mut files: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        files.sort();
        for f in files {
            let rel = format!(
                "programs/{}/{}",
                dname,
                f.file_name().unwrap().to_string_lossy()
            );
            out.push((rel, f, md_for(&dname)));
        }
    }
    out
}

fn sha256_hex(b: &[u8]) -> String {
    Sha256::digest(b)
        .iter()
        .map(|x| format!("{x:02x}"))
        .collect()
}

const HASHES: &str = "tests/data/simulate.sha256";

#[test]
fn sample_programs_give_their_pinned_setpoint_hashes() {
    // The first 150 000 cycles (2.5 min of machine time): all but the ISG grinding cycle,
    // which grinds at F5 for a day, run to their end.
    let opts = Options {
        max_cycles: 150_000,
        ..Default::default()
    };
    let mut lines = Vec::new();
    for (rel, path, md_file) in sample_programs() {
        let md = machine(md_file, own_checking(&rel));
        let text = std::fs::read_to_string(&path).unwrap();
        let (b, s) = simulate_bytes(&md, &text, &opts);
        assert!(
            !s.timed_out || rel.ends_with("grinding_cycle.nc"),
            "{rel} did not end"
        );
        lines.push(format!("{}  {}", sha256_hex(&b), rel));
    }
    let now = lines.join("\n") + "\n";
    let file = root().join(HASHES);
    if std::env::var_os("SOFTNC_BLESS").is_some() {
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(&file, &now).unwrap();
        return;
    }
    let pinned = std::fs::read_to_string(&file)
        .expect("tests/data/simulate.sha256 (SOFTNC_BLESS=1 writes it)");
    for (p, n) in pinned.lines().zip(now.lines()) {
        assert_eq!(p, n, "setpoints changed (if on purpose: SOFTNC_BLESS=1 cargo test --test ipo, and say why in the commit)");
    }
    assert_eq!(
        pinned.lines().count(),
        now.lines().count(),
        "sample programs added or removed: rebless"
    );
}

#[test]
fn a_slow_preparation_thread_changes_no_bit() {
    let mut md = machine(None, &[]);
    // The synthetic program wanders beyond the built-in machine's travel; this test is about
    // the hand-over, not the software limits.
    for a in [&mut md.axes.x, &mut md.axes.y, &mut md.axes.z]
        .into_iter()
        .flatten()
    {
        a.software_limits = None;
    }
    let text = workpiece();
    let (fast, _) = simulate_bytes(&md, &text, &Options::default());
    let slow_opts = Options {
        prep_delay: std::time::Duration::from_millis(2),
        ..Default::default()
    };
    let (slow, _) = simulate_bytes(&md, &text, &slow_opts);
    assert_eq!(sha256_hex(&fast), sha256_hex(&slow));
    // A longer program whose lookahead is refilled all the time.
    let long = nc_kernel::synthetic::compensated_program(400, nc_kernel::synthetic::Header::Softnc);
    let (fast, _) = simulate_bytes(&md, &long, &Options::default());
    let slow_opts = Options {
        prep_delay: std::time::Duration::from_micros(100),
        ..Default::default()
    };
    let (slow, s) = simulate_bytes(&md, &long, &slow_opts);
    assert!(s.segments > 400);
    assert_eq!(sha256_hex(&fast), sha256_hex(&slow));
}

/// Runs the channel directly with operator actions at given cycles; rows as `simulate`
/// writes them.
fn drive(md: &MachineData, text: &str, actions: &[(u64, &str)]) -> Vec<Row> {
    drive_fed(md, text, actions, None)
}

/// `drive`, with the records offered one every `every` cycles when given (a preparation that
/// falls behind).
fn drive_fed(
    md: &MachineData,
    text: &str,
    actions: &[(u64, &str)],
    every: Option<u64>,
) -> Vec<Row> {
    use nc_kernel::ipo::{Channel, ChannelState, Setpoint};
    let tools = ToolTable::builtin();
    let job = nc_kernel::handover::Job {
        name: "test.mpf",
        source: text,
        md,
        tools: &tools,
        at: None,
    };
    let (start, inputs, reports) = nc_kernel::handover::prepare_all(job);
    assert!(reports.is_empty());
    let mut it = inputs.into_iter();
    let mut pending = None;
    let mut ch = Channel::new(md, start);
    let mut sp = Setpoint::new(start);
    ch.start();
    let mut out = Vec::new();
    for k in 0..2_000_000u64 {
        let mut budget = every.map_or(usize::MAX, |n| usize::from(k % n == 0));
        ch.fill(&mut pending, || {
            budget = budget.checked_sub(1)?;
            it.next()
        });
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
        ch.cycle(k, &mut sp);
        out.push(Row {
            cycle: k,
            pos: sp.pos,
            v: sp.v_path * 60.0,
            block: sp.source.map_or(String::new(), |s| {
                s.number.map_or(format!("L{}", s.line), |n| n.to_string())
            }),
            events: format!("{:?}", sp.events),
        });
        if sp.state == ChannelState::End {
            break;
        }
    }
    out
}

#[test]
fn nc_stop_and_override_replan_within_one_cycle_and_keep_to_the_path() {
    let md = machine(None, &[]);
    let text = workpiece();
    let plain = drive(&md, &text, &[]);
    // NC stop at cycle 3000 (on N20 at F400), NC start at 5000; override 30 % at 9000,
    // 120 % at 15000.
    let acts = [
        (3000, "stop"),
        (5000, "start"),
        (9000, "30"),
        (15000, "120"),
    ];
    let rows = drive(&md, &text, &acts);
    assert_eq!(rows.last().unwrap().pos, plain.last().unwrap().pos);
    assert_on_path(&md, &text, &rows);
    assert_within_limits(&md, &rows);
    // Identical up to the stop; the setpoint of the next cycle already brakes.
    assert_eq!(
        rows[..=2999].iter().map(|r| r.pos).collect::<Vec<_>>(),
        plain[..=2999].iter().map(|r| r.pos).collect::<Vec<_>>()
    );
    assert!(
        rows[3000].v < plain[3000].v,
        "{} {}",
        rows[3000].v,
        plain[3000].v
    );
    // At rest, then STOPPED, holding the position until NC start.
    let stopped = rows
        .iter()
        .position(|r| r.events.contains("Stopped"))
        .unwrap();
    assert!(stopped < 5000 && rows[stopped].v == 0.0);
    assert!(rows[stopped..5000]
        .iter()
        .all(|r| r.pos == rows[stopped].pos));
    // The braking from F400 (6.7 mm/s) takes well under a second.
    assert!(stopped - 3000 < 500, "{}", stopped - 3000);
    // Override: 30 % of F400 is 120 mm/min, reached and held on N40's long line.
    assert!(rows[9000..15000]
        .iter()
        .all(|r| r.v <= 400.0 * 0.3 + 1e-6 || r.cycle < 9300));
    // 120 %: F400 runs at 480 mm/min on the long lines.
    let top = rows[15000..]
        .iter()
        .filter(|r| r.block == "N100")
        .map(|r| r.v)
        .fold(0.0, f64::max);
    assert!((top - 480.0).abs() < 1e-6, "{top}");
}

#[test]
fn the_simulate_command_writes_the_same_rows_and_says_how_it_ended() {
    let dir = std::env::temp_dir().join(format!("softnc-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("w.csv");
    let program = root().join("programs/siemens-840c/11_15_workpiece.mpf");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_softnc"))
        .arg("simulate")
        .arg(&program)
        .arg("-o")
        .arg(&csv)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains(": END: 50817 cycles (50.817 s machine time)"),
        "{said}"
    );
    let (lib, _) = simulate_bytes(&machine(None, &[]), &workpiece(), &Options::default());
    assert!(
        std::fs::read(&csv).unwrap() == lib,
        "the command and the library differ"
    );
    // An override of 0 would hold the path forever: refused.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_softnc"))
        .args(["simulate", "--override", "0"])
        .arg(&program)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("--override 0: expected a percentage above 0"));
    // A program with a preparation alarm within the load-time check: refused as the kernel
    // refuses its load (the compensation run with the alarm in it may not start, and the
    // check sees it before NC start), exit status 1, the alarm printed like a diagnostic.
    let alarm = root().join("programs/siemens-840c/11_11_four_blocks_outside_plane_alarm.mpf");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_softnc"))
        .arg("simulate")
        .arg(&alarm)
        .arg("-o")
        .arg(&csv)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("alarm 3021") && said.contains(": STOPPED: "),
        "{said}"
    );
    let rows = rows(&std::fs::read(&csv).unwrap());
    let last = rows.last().unwrap();
    assert!(
        last.events.contains("alarm 3021") && last.v == 0.0,
        "{last:?}"
    );
    // Nothing moved: every row where the program starts.
    assert!(rows.iter().all(|r| r.pos == [0.0; 3]), "something moved");
    // The kernel refuses the load with the same alarm.
    let text = std::fs::read_to_string(&alarm).unwrap();
    let refused = nc_kernel::handover::spawn_preparation(
        "a".into(),
        text,
        machine(None, &[]),
        ToolTable::builtin(),
        None,
    )
    .unwrap()
    .err()
    .expect("refused at load");
    assert_eq!(refused.number(), 3021);
    let _ = std::fs::remove_dir_all(&dir);
}

mod random_contours {
    use super::*;
    use proptest::prelude::*;

    /// A block of a random contour: a line, or an arc given by its centre offset and the
    /// angle it turns, with a random feed, exact stop and Z.
    #[derive(Debug, Clone)]
    enum Step {
        Line(f64, f64, f64),
        Arc {
            r: f64,
            turn: f64,
            ccw: bool,
            dz: f64,
        },
    }

    fn step() -> impl Strategy<Value = (Step, f64, bool)> {
        let s = prop_oneof![
            (
                -40.0..40.0f64,
                -40.0..40.0f64,
                prop_oneof![Just(0.0), -3.0..3.0f64]
            )
                .prop_map(|(x, y, z)| Step::Line(x, y, z)),
            (
                0.5..30.0f64,
                0.1..6.2f64,
                any::<bool>(),
                prop_oneof![Just(0.0), -2.0..2.0f64]
            )
                .prop_map(|(r, turn, ccw, dz)| Step::Arc { r, turn, ccw, dz }),
        ];
        (s, 50.0..9000.0f64, prop::bool::weighted(0.2))
    }

    /// The program text (4 decimals, so the arcs' ends lie on their circles to 1e-4 and the
    /// front end puts the centre where both radii agree).
    fn program(steps: &[(Step, f64, bool)]) -> String {
        let (mut x, mut y, mut z) = (0.0f64, 0.0f64, 0.0f64);
        let mut t = String::from("N1 G17 G90 G1 X0 Y0 Z0 F1000\n");
        let mut heading: f64 = 0.0;
        for (i, (s, f, g9)) in steps.iter().enumerate() {
            let n = 10 * (i + 1);
            let g9 = if *g9 { " G9" } else { "" };
            match *s {
                Step::Line(dx, dy, dz) => {
                    if dx.hypot(dy) < 0.01 && dz == 0.0 {
                        continue;
                    }
                    x += dx;
                    y += dy;
                    z += dz;
                    heading = dy.atan2(dx);
                    t += &format!("N{n}{g9} G1 X{x:.4} Y{y:.4} Z{z:.4} F{f:.1}\n");
                }
                Step::Arc { r, turn, ccw, dz } => {
                    // Centre to the left (ccw) or right of the current heading.
                    let side = if ccw { 1.0 } else { -1.0 };
                    let (cx, cy) = (x - side * r * heading.sin(), y + side * r * heading.cos());
                    let a0 = (y - cy).atan2(x - cx);
                    let a1 = a0 + side * turn;
                    let (ex, ey) = (cx + r * a1.cos(), cy + r * a1.sin());
                    let (ex, ey) = ((ex * 1e4).round() / 1e4, (ey * 1e4).round() / 1e4);
                    let (i_, j_) = (cx - x, cy - y);
                    let g = if ccw { "G3" } else { "G2" };
                    z += dz;
                    t += &format!(
                        "N{n}{g9} {g} X{ex:.4} Y{ey:.4} Z{z:.4} I{i_:.4} J{j_:.4} F{f:.1}\n"
                    );
                    x = ex;
                    y = ey;
                    heading = a1 + side * std::f64::consts::FRAC_PI_2;
                }
            }
        }
        t + "N999 M30\n"
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

        #[test]
        fn random_contours_stay_on_the_path_within_the_limits(
            steps in prop::collection::vec(step(), 1..7)
        ) {
            let md = machine(None, &[]);
            let text = program(&steps);
            let opts = Options { max_cycles: 3_000_000, ..Default::default() };
            let (b, s) = simulate_bytes(&md, &text, &opts);
            // Arcs the front end rejects (the rounded end off the circle) end in an alarm:
            // then the run stops there; the rest still holds.
            prop_assert!(!s.timed_out, "{}", text);
            let rows = rows(&b);
            if s.alarms.is_empty() {
                prop_assert_eq!(s.end_state.map(|s| s.name()), Some("END"));
                let segs = nc_kernel::prepare("t", &text, &md, &ToolTable::builtin()).unwrap();
                prop_assert_eq!(rows.last().unwrap().pos, segs.last().unwrap().to);
            }
            assert_on_path(&md, &text, &rows);
            assert_within_limits(&md, &rows);
        }
    }
}

#[test]
fn a_preparation_that_falls_behind_slows_the_path_under_control() {
    // The serpentine at F1000 (a segment takes at most ~7 000 cycles) with one record offered
    // every 20 000 cycles: the lookahead runs dry before every segment, so the path brakes to
    // rest at the end of what it has and waits — within the axis limits, on the path, with
    // no jump.
    let md = machine(None, &[]);
    let text = nc_kernel::synthetic::compensated_program(12, nc_kernel::synthetic::Header::Softnc);
    let full = drive(&md, &text, &[]);
    let starved = drive_fed(&md, &text, &[], Some(20_000));
    assert_on_path(&md, &text, &starved);
    assert_within_limits(&md, &starved);
    assert_eq!(starved.last().unwrap().pos, full.last().unwrap().pos);
    assert!(starved.len() > full.len());
    // It came to rest between segments and went on: rows at speed 0 in the middle.
    let rests = starved
        .windows(2)
        .filter(|w| w[0].v > 0.0 && w[1].v == 0.0)
        .count();
    assert!(rests >= 10, "{rests}");
}

#[test]
fn more_aux_functions_at_one_s_point_than_fit_in_a_cycle_all_go_out_in_order() {
    // Eight blocks of auxiliary functions between two lines (machine data allows eight
    // blocks outside the plane): all come out at N10's end, in program order, in two
    // consecutive cycles (six fit in one setpoint; the path runs on through, none of them
    // waits for an acknowledgement).
    let md = machine(None, &["trc.max_blocks_outside_plane=8"]);
    let text = "N10 G90 G1 X10 F1000\nN11 H1\nN12 H2\nN13 H3\nN14 H4\nN15 H5\nN16 H6\nN17 H7\nN18 H8\nN20 X20\nN30 M30\n";
    let (rows, s) = simulate(&md, text);
    assert_eq!(s.end_state.map(|s| s.name()), Some("END"));
    let with: Vec<&Row> = rows.iter().filter(|r| r.events.contains("aux")).collect();
    let words: Vec<String> = with
        .iter()
        .flat_map(|r| r.events.split(';'))
        .filter_map(|e| {
            e.strip_prefix("aux ")
                .map(|w| w.split(" @").next().unwrap().to_string())
        })
        .collect();
    assert_eq!(words, ["H1", "H2", "H3", "H4", "H5", "H6", "H7", "H8"]);
    assert_eq!(with.len(), 2);
    assert_eq!(with[1].cycle, with[0].cycle + 1);
}

/// A long simulation says where it is every 65 536 cycles: the cycle counts in order, the
/// line of the block running then, and the same setpoints as without the reports.
#[test]
fn a_long_simulation_reports_its_progress() {
    let md = machine(None, &[]);
    // 400 mm at F100: 240 s of machine time.
    let text = "N10 G0 X0 Y0 Z0\nN20 G1 X400 F100\nN30 M30\n";
    let tools = ToolTable::builtin();
    let mut seen = Vec::new();
    let mut out = Vec::new();
    let s = nc_kernel::simulate::run_with_progress(
        "test.mpf",
        text,
        &md,
        &tools,
        &Options::default(),
        &mut out,
        &mut |p| seen.push((p.cycles, p.line)),
    )
    .unwrap();
    let every = nc_kernel::simulate::PROGRESS_CYCLES;
    assert!(s.cycles > 240_000, "{}", s.cycles);
    assert_eq!(seen.len() as u64, (s.cycles - 1) / every);
    for (i, (cycles, line)) in seen.iter().enumerate() {
        assert_eq!((*cycles, *line), ((i as u64 + 1) * every, 2));
    }
    assert_eq!(out, simulate_bytes(&md, text, &Options::default()).0);
}
