//! The whole-program check: a violation far from the segment that gouges — beyond any
//! bottleneck window — refuses the program at load, before anything moves, naming both
//! places; `softnc check` lists it the same way; a program longer than the load-time check
//! stops before the compensation run it has not cleared; a compensation run with an alarm
//! in it does not start.

#[path = "support/control.rs"]
mod control;

use control::*;
use nc_kernel::handover::{spawn_preparation, Gated, Job};
use nc_kernel::simulate::{run, Options};
use nc_kernel::{AlarmCode, MachineData, Prepared, Role, ToolTable};

/// G41 with D1 (radius 10): line 4 runs along Y0 (the tool at Y10); then down, 200 blocks
/// to the right along Y−30 (the first and last 40 mm long, the others 4 mm), up and back
/// along Y18 (line 207, the tool at Y8): line 4's tool path comes within 8 mm of line 207's
/// element, and line 207's within 8 mm of line 4's. No window of 64 blocks sees the pair.
fn far_program() -> String {
    let mut p = vec![
        "G17 G90 G0 X-40 Y20 D1".to_string(),
        "G1 F1000".into(),
        "G41 X-20 Y0".into(),
        "G1 X100 Y0".into(),
        "G1 X100 Y-30".into(),
        "G1 X140 Y-30".into(),
    ];
    let mut x = 140;
    for _ in 0..198 {
        x += 4;
        p.push(format!("G1 X{x} Y-30"));
    }
    x += 40;
    p.push(format!("G1 X{x} Y-30"));
    p.push(format!("G1 X{x} Y18"));
    p.push("G1 X0 Y18".into());
    p.push("G40 G1 X-20 Y40".into());
    p.push("M30".into());
    p.join("\n") + "\n"
}

const FAR: u32 = 207;

fn machine(over: &[&str]) -> MachineData {
    let over: Vec<String> = over.iter().map(|s| s.to_string()).collect();
    MachineData::load(None, &over).unwrap()
}

/// The segments (line, role) the kernel's channel gets before the alarm, and the alarm.
fn up_to_the_alarm(job: Job) -> (Vec<(u32, Role)>, nc_kernel::Alarm) {
    let mut path = Gated::of_job(job);
    let mut lines = Vec::new();
    loop {
        match path.next_item() {
            Some(Ok(Prepared::Segment(s))) => lines.push((s.source.line, s.role)),
            Some(Ok(_)) => {}
            Some(Err(a)) => return (lines, a),
            None => panic!("no alarm; path {lines:?}"),
        }
    }
}

#[test]
fn the_far_program_is_what_it_claims() {
    let text = far_program();
    assert_eq!(text.lines().nth(FAR as usize - 1), Some("G1 X0 Y18"));
    // The shipped 64-block window alone lets it through: the pair is 203 blocks apart.
    let md = machine(&["trc.whole_program_check=false"]);
    let segs = nc_kernel::prepare("far", &text, &md, &ToolTable::builtin()).unwrap();
    // Line 4's tool path along Y10, line 207's along Y8 (G41 going −X: the tool below).
    let on = |line: u32| {
        segs.iter()
            .find(|s| s.source.line == line && s.role == Role::Contour)
    };
    let (a, b) = (on(4).unwrap(), on(FAR).unwrap());
    assert_eq!((a.from[1], a.to[1]), (10.0, 10.0));
    assert_eq!((b.from[1], b.to[1]), (8.0, 8.0));
}

#[test]
fn a_violation_200_blocks_on_is_refused_at_load_with_both_lines() {
    let a = refused_at_load("far.mpf", far_program());
    assert_eq!((a.code, a.line), (AlarmCode::ContourViolation, 4), "{a}");
    assert!(a.message.contains("line 207"), "{}", a.message);
    assert!(a.message.contains("8.0000 mm"), "{}", a.message);
}

/// The alarm the kernel refuses `text` with at load, on the shipped machine data (refused:
/// no hand-over exists, so nothing was queued for the IPO).
fn refused_at_load(name: &str, text: String) -> nc_kernel::Alarm {
    let refused = spawn_preparation(name.into(), text, machine(&[]), ToolTable::builtin(), None)
        .expect("thread");
    match refused {
        Err(a) => a,
        Ok(_) => panic!("the kernel took the program"),
    }
}

/// The far program with the radius changed to D2 (5 mm) one block into the run of short
/// moves: line 4's tool path (radius 10) still comes within 8 mm of line 207's element.
fn far_program_with_a_radius_change() -> String {
    let text = far_program();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[6].push_str(" D2");
    lines.join("\n") + "\n"
}

/// The kernel's check sees each segment when the 64-block window lets it go, after the
/// elements of the blocks behind it: a segment is still measured with its own block's tool
/// radius (10 here), not the one the window has reached (5: 8 mm would pass).
#[test]
fn a_segment_is_checked_with_its_own_radius_when_the_window_lets_it_go() {
    let text = far_program_with_a_radius_change();
    assert!(text.lines().nth(6).unwrap().ends_with("D2"));
    let a = refused_at_load("far-d2.mpf", text);
    assert_eq!((a.code, a.line), (AlarmCode::ContourViolation, 4), "{a}");
    assert!(
        a.message.contains("line 207") && a.message.contains("tool radius 10.0000"),
        "{}",
        a.message
    );
}

#[test]
fn softnc_check_names_both_places() {
    check_names_lines_4_and_207("whole-far.mpf", &far_program());
}

/// `softnc check` on `text` (as file `name`) fails naming the pair of lines 4 and 207 both
/// ways.
fn check_names_lines_4_and_207(name: &str, text: &str) {
    let prog = scratch(name);
    std::fs::write(&prog, text).unwrap();
    let out = std::process::Command::new(EXE)
        .arg("check")
        .arg(&prog)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!("{name}:4:1: alarm 3021"))
            && stderr.contains("of the contour of line 207"),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!("{name}:207:1: alarm 3021"))
            && stderr.contains("of the contour of line 4 "),
        "{stderr}"
    );
}

/// `softnc run`: the kernel refuses the program at load; nothing moves (no setpoint left the
/// start), and the processes end cleanly.
#[test]
fn softnc_run_refuses_the_far_program_before_any_motion() {
    let inst = instance("wholefar");
    let _scope = Scope::new(&inst);
    let prog = scratch("whole-run.mpf");
    std::fs::write(&prog, far_program()).unwrap();
    let out = std::process::Command::new(EXE)
        .arg("run")
        .arg(&prog)
        .args(["--quiet", "--instance", &inst])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(stderr.contains("nothing moved"), "{stderr}");
    assert!(
        stderr.contains("whole-run.mpf:4:1: alarm 3021") && stderr.contains("line 207"),
        "{stderr}"
    );
    assert!(!stdout.contains("IPO cycles"), "it ran: {stdout}");
}

/// Above `trc.check_at_load_blocks` the check runs ahead of the path: the moves before the
/// compensation run go out, the run itself does not, and the alarm is the check's.
#[test]
fn a_long_program_stops_before_the_run_it_has_not_cleared() {
    let md = machine(&["trc.check_at_load_blocks=2"]);
    let tools = ToolTable::builtin();
    let text = far_program();
    let job = Job {
        name: "far",
        source: &text,
        md: &md,
        tools: &tools,
        at: None,
    };
    let (lines, alarm) = up_to_the_alarm(job);
    assert_eq!(lines, [(1, Role::Uncompensated)]);
    assert_eq!((alarm.code, alarm.line), (AlarmCode::ContourViolation, 4));
    // The same through the kernel's load: not refused (beyond the load-time check), and the
    // simulated run stops at rest where the rapid move ends.
    let spawned = spawn_preparation("far".into(), text.clone(), md.clone(), tools.clone(), None)
        .expect("thread");
    assert!(spawned.is_ok(), "refused at load");
    let mut csv = Vec::new();
    let s = run("far", &text, &md, &tools, &Options::default(), &mut csv).unwrap();
    let alarms: Vec<(u32, u32)> = s.alarms.iter().map(|a| (a.number(), a.line)).collect();
    assert_eq!(alarms, [(3021, 4)]);
    // The last setpoint (cycle, time, X, Y, Z, ...): at rest where the rapid move ends.
    let csv = String::from_utf8(csv).unwrap();
    let last: Vec<&str> = csv.lines().last().unwrap().split(',').collect();
    let at: Vec<f64> = last[2..5].iter().map(|v| v.parse().unwrap()).collect();
    assert_eq!(at, [-40.0, 20.0, 0.0], "{}", csv.lines().last().unwrap());
}

/// A compensation run with an alarm in it (here a circle smaller than the tool on the tool
/// side, in its fourth block) does not start: what comes before the run goes out, then the
/// alarm, with its own number and place.
#[test]
fn a_run_with_an_alarm_in_it_does_not_start() {
    let text = "G17 G90 G0 X-30 Y0 D1\nG1 F1000\nG41 X0 Y0\nG1 X50 Y0\nG1 X50 Y20\n\
                G3 X46 Y24 I-4 J0\nG1 X0 Y24\nG40 G1 X-30 Y40\nM30\n";
    let md = machine(&[]);
    let tools = ToolTable::builtin();
    let bare = nc_kernel::prepare(
        "small-arc",
        text,
        &machine(&["trc.whole_program_check=false"]),
        &tools,
    );
    let a = bare.expect_err("the arc is smaller than the tool");
    assert_eq!(a.line, 6);
    let job = Job {
        name: "small-arc",
        source: text,
        md: &md,
        tools: &tools,
        at: None,
    };
    let (lines, alarm) = up_to_the_alarm(job);
    assert_eq!(lines, [(1, Role::Uncompensated)]);
    assert_eq!((alarm.code, alarm.line), (a.code, 6));
}

/// A CAM outside profile with arc leads (docs/trc.md "Lead-in and lead-out elements"): G41
/// in the approach line to (60, −20), a lead-in arc R20 about (40, −20) onto the bottom edge
/// at (40, 0), clockwise round the rectangle 0..100 × 0..60 back to (40, 0), a lead-out arc
/// about the same centre to (20, −20), G40. The tool (R10) runs along Y−10 under the bottom
/// edge: the last edge's path crosses the lead-in arc at X57.32 (40 + 20 cos 30°), the first
/// edge's crosses the lead-out arc at X22.68. Both arcs are air.
const LED_PROFILE: &str = "G17 G90 G0 X60 Y-40 D1\nG1 F1000\nG41 X60 Y-20\n\
    G3 X40 Y0 I-20 J0\nG1 X0 Y0\nG1 X0 Y60\nG1 X100 Y60\nG1 X100 Y0\nG1 X40 Y0\n\
    G3 X20 Y-20 I0 J-20\nG40 G1 X20 Y-40\nM30\n";

#[test]
fn cam_leads_into_a_closed_profile_are_no_surface() {
    // Without the rule both the window and the whole check see the crossings: the window
    // alone with a reach of 64 (the shipped default) finds one.
    let tools = ToolTable::builtin();
    let md = machine(&[]);
    let segs = nc_kernel::prepare("led", LED_PROFILE, &md, &tools).expect("the window");
    let last = segs.iter().rfind(|s| s.role == Role::Retract).unwrap();
    assert_eq!(last.to[..2], [20.0, -40.0]);
    // The kernel's load-time check and the window ahead of the path: no alarm to the end.
    let job = Job {
        name: "led",
        source: LED_PROFILE,
        md: &md,
        tools: &tools,
        at: None,
    };
    let mut path = Gated::of_job(job);
    while let Some(item) = path.next_item() {
        item.expect("no alarm");
    }
    let prog = scratch("led.mpf");
    std::fs::write(&prog, LED_PROFILE).unwrap();
    let out = std::process::Command::new(EXE)
        .arg("check")
        .arg(&prog)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The same profile with the lead-in arc bent back into the part (about (40, 20), ending at
/// (40, 0) going −X): it is still a lead, but its own tool path runs inside the rectangle and
/// comes too close to the left edge's element and the bottom edge — a gouge of the part the
/// check must report.
#[test]
fn a_lead_that_cuts_into_the_part_is_still_a_gouge() {
    let text = LED_PROFILE.replace(
        "G41 X60 Y-20\nG3 X40 Y0 I-20 J0",
        "G41 X20 Y20\nG2 X40 Y0 I20 J0",
    );
    let md = machine(&["trc.bottleneck_window=0"]);
    let tools = ToolTable::builtin();
    let job = Job {
        name: "led-in-part",
        source: &text,
        md: &md,
        tools: &tools,
        at: None,
    };
    let (_, alarm) = up_to_the_alarm(job);
    assert_eq!(alarm.code, AlarmCode::ContourViolation, "{alarm}");
}

/// The far program closed into a loop (back along Y18 to X−20 and down to the run's start
/// (−20, 0)) with a lead-out line after it: line 4 and line 207 are inside the loop, so the
/// violation 203 blocks apart is still reported, both ways.
#[test]
fn a_far_violation_inside_a_closed_profile_is_still_reported() {
    let text = far_program().replace(
        "G1 X0 Y18\n",
        "G1 X0 Y18\nG1 X-20 Y18\nG1 X-20 Y0\nG1 X-30 Y-10\n",
    );
    check_names_lines_4_and_207("far-closed.mpf", &text);
}

/// A hairpin under R 10: 6000 blocks of 4 mm along Y0, round below and 6000 back along Y18,
/// so every segment of either row comes closer than R to the other's elements: a run of some
/// 12 000 segments, violations all along it.
fn hairpin() -> String {
    let mut p = vec![
        "G17 G90 G0 X-40 Y20 D1".to_string(),
        "G1 F1000".into(),
        "G41 X-20 Y0".into(),
    ];
    p.extend((0..=6000).map(|i| format!("G1 X{} Y0", 4 * i)));
    p.extend(["G1 X24000 Y-30".into(), "G1 X24040 Y-30".into()]);
    p.push("G1 X24040 Y18".into());
    p.extend((0..=6000).rev().map(|i| format!("G1 X{} Y18", 4 * i)));
    p.extend(["G40 G1 X-20 Y40".into(), "M30".into()]);
    p.join("\n") + "\n"
}

/// Every violation of `text` as `softnc check` collects them, with the run checked by two
/// workers through `join` or by one.
fn collected(text: &str, join: Option<&dyn nc_kernel::Join>) -> Vec<String> {
    let md = machine(&["trc.bottleneck_window=0"]);
    let tools = ToolTable::builtin();
    let prep = nc_kernel::Preparation::new("hairpin", text, &md, &tools)
        .checking_whole(nc_kernel::WholeMode::Collect);
    let mut prep = match join {
        Some(j) => prep.with_join(j),
        None => prep,
    };
    let mut found = Vec::new();
    loop {
        let item = prep.next_item();
        let end = !matches!(item, Ok(Some(_)));
        found.extend(prep.take_violations(end).iter().map(|a| a.to_string()));
        if end {
            assert!(item.is_ok(), "{item:?}");
            return found;
        }
    }
}

/// A long run is checked by two workers taking pieces of it as they finish one: they report
/// what one worker does, every violation, in path order.
#[test]
fn two_workers_report_a_long_run_as_one_does() {
    let text = hairpin();
    let one = collected(&text, None);
    let two = collected(&text, Some(&nc_runtime::Threads));
    assert!(one.len() > 2, "{one:?}");
    assert_eq!(one, two);
    // Both rows' stretches, the first row's first.
    let line = |a: &String| {
        let rest = a.split("hairpin:").nth(1).unwrap_or_default();
        rest.split(':').next().and_then(|l| l.parse::<u32>().ok())
    };
    let lines: Vec<u32> = one.iter().filter_map(line).collect();
    assert_eq!(lines.len(), one.len(), "{one:?}");
    assert!(lines.windows(2).all(|w| w[0] < w[1]), "{lines:?}");
    assert!(
        lines[0] < 6004 && *lines.last().unwrap() > 6008,
        "{lines:?}"
    );
}

/// A compensation run still open where the program ends (no G40) is checked once at the end:
/// both of its violations are reported, once each, and asking on after the end finds nothing
/// more.
#[test]
fn a_run_open_at_the_end_is_checked_once() {
    let open = far_program().replace("G40 G1 X-20 Y40\n", "");
    assert!(!open.contains("G40"));
    let found = collected(&open, None);
    let at = |a: &String| a.split(':').nth(1).map(str::to_string);
    let lines: Vec<_> = found.iter().filter_map(at).collect();
    assert_eq!(lines, ["4", "207"], "{found:?}");
    let md = machine(&["trc.bottleneck_window=0"]);
    let tools = ToolTable::builtin();
    let mut prep = nc_kernel::Preparation::new("open", &open, &md, &tools)
        .checking_whole(nc_kernel::WholeMode::Collect);
    while let Ok(Some(_)) = prep.next_item() {}
    assert!(!prep.take_violations(true).is_empty());
    for _ in 0..3 {
        assert!(matches!(prep.next_item(), Ok(None)));
        assert!(prep.take_violations(true).is_empty());
    }
}
