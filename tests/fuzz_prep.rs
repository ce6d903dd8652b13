//! Robustness of block preparation: no panic on any program the front end accepts.
//!
//! "TRC soup": random sequences of selections and deselections (G41/G42/G40, each dialect's
//! selection methods and corner modes), offsets (D0, D1, D2, negative and huge radii), lines,
//! arcs (including full circles and tiny ones), tool-axis moves, auxiliary functions, program
//! stops and masking, in all four dialects, with the bottleneck window off, 3 and 64 and both
//! violation reactions. Every run must end with records or an alarm, and an alarm must point
//! into the program. Deterministic (a fixed LCG), bounded: 4 × 6 × 400 programs.

#[path = "support/soup.rs"]
mod soup;

use nc_kernel::Prepared;
use nc_kernel::Role;
use nc_kernel::{Lent, MachineData, Preparation, ToolTable, WholeMode};
use soup::{program, Rng};
use std::path::Path;

#[test]
fn preparation_never_panics() {
    let mut rng = Rng(0x5151_2026);
    let (mut runs, mut compensated, mut alarmed) = (0usize, 0usize, 0usize);
    for dialect in ["siemens-840c", "isg", "fanuc", "siemens-808d"] {
        let config = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("config")
            .join(format!("{dialect}.toml"));
        for md_over in [
            ["trc.bottleneck_window=0", "trc.violation_reaction=stop"],
            ["trc.bottleneck_window=3", "trc.violation_reaction=stop"],
            ["trc.bottleneck_window=64", "trc.violation_reaction=stop"],
            ["trc.bottleneck_window=0", "trc.violation_reaction=warn"],
            ["trc.bottleneck_window=3", "trc.violation_reaction=warn"],
            ["trc.bottleneck_window=64", "trc.violation_reaction=warn"],
        ] {
            let over: Vec<String> = md_over
                .iter()
                .map(|s| s.to_string())
                .chain(["program.decimal_input=calculator".to_string()])
                .filter(|s| dialect == "fanuc" || !s.starts_with("program.decimal"))
                .collect();
            let md = MachineData::load(Some(&config), &over).unwrap();
            for _ in 0..400 {
                let src = program(&mut rng, dialect);
                let mut tools = ToolTable::builtin();
                let r = match rng.next() % 6 {
                    0 => -3.0,
                    1 => 0.5,
                    2 => 60.0,
                    _ => 5.0,
                };
                tools.set_radius(1, r).unwrap();
                let run = std::panic::catch_unwind(|| {
                    let mut p = Preparation::new("fuzz", &src, &md, &tools);
                    let (mut n, mut contour, mut alarm) = (0usize, false, false);
                    loop {
                        match p.next_item() {
                            Ok(Some(Prepared::Warning(a))) => check_alarm(&a, &src),
                            Ok(Some(Prepared::Segment(s))) => {
                                n += 1;
                                contour |= s.role == Role::Contour;
                            }
                            Ok(Some(_)) => n += 1,
                            Ok(None) => break,
                            Err(a) => {
                                check_alarm(&a, &src);
                                alarm = true;
                                break;
                            }
                        }
                        assert!(n < 100_000, "runaway output");
                    }
                    (contour, alarm)
                });
                match run {
                    Ok((c, a)) => {
                        runs += 1;
                        compensated += usize::from(c);
                        alarmed += usize::from(a);
                    }
                    Err(_) => panic!("{dialect} {md_over:?} R {r}: preparation panicked on\n{src}"),
                }
            }
        }
    }
    // The soup reaches the compensation often, and is not all alarms.
    assert!(
        compensated * 10 > runs,
        "{compensated} of {runs} runs compensated"
    );
    assert!(alarmed < runs, "{alarmed} of {runs} runs ended in an alarm");
    eprintln!("{runs} runs: {compensated} compensated, {alarmed} alarms");
}

fn check_alarm(a: &nc_kernel::Alarm, src: &str) {
    let lines = src.lines().count() as u32;
    assert!(
        a.line >= 1 && a.line <= lines.max(1) && a.col >= 1 && !a.message.is_empty(),
        "alarm outside the program: {a:?}\n{src}"
    );
}

/// Everything preparation puts out, as text (records and the final alarm).
fn records(mut next: impl FnMut() -> Result<Option<Prepared>, nc_kernel::Alarm>) -> Vec<String> {
    let mut out = Vec::new();
    loop {
        match next() {
            Ok(Some(x)) => out.push(format!("{x:?}")),
            Ok(None) => return out,
            Err(a) => {
                out.push(format!("alarm {a:?}"));
                return out;
            }
        }
    }
}

/// The interpreter in its own thread (`Preparation::threaded`) gives the same records, bit
/// for bit, as in preparation's thread: on the soup, on a program long enough for many
/// batches, and on one whose alarm comes after several batches.
#[test]
fn threaded_decoding_gives_the_same_records() {
    let mut rng = Rng(0x7e5d_2026);
    let mut programs: Vec<(String, String)> = Vec::new();
    for dialect in ["siemens-840c", "isg", "fanuc", "siemens-808d"] {
        for _ in 0..150 {
            programs.push((dialect.to_string(), program(&mut rng, dialect)));
        }
    }
    let long =
        nc_kernel::synthetic::compensated_program(3000, nc_kernel::synthetic::Header::Softnc);
    programs.push(("siemens-840c".into(), long.clone()));
    programs.push(("siemens-840c".into(), long.replace("G40", "X1 Y1 Q=)\nG40")));
    programs.push((
        "isg".into(),
        include_str!("../programs/isg/g238_star.nc").into(),
    ));
    let tools = ToolTable::builtin();
    let mut compared = 0;
    for (dialect, src) in &programs {
        let config = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("config")
            .join(format!("{dialect}.toml"));
        let md = MachineData::load(Some(&config), &["trc.bottleneck_window=3".into()]).unwrap();
        let direct = {
            let mut p = Preparation::new("t", src, &md, &tools);
            records(|| p.next_item())
        };
        let threaded = std::thread::scope(|s| {
            let mut p = Preparation::threaded(s, "t", src, &md, &tools);
            records(|| p.next_item())
        });
        assert_eq!(direct, threaded, "{dialect}:\n{src}");
        compared += direct.len();
        if src.contains("Q=)") {
            // The alarm comes after more than 20 batches of blocks.
            let last = direct.last().map_or("", |r| r.as_str());
            assert!(
                direct.len() > 2900 && last.starts_with("alarm"),
                "{} {last}",
                direct.len()
            );
        }
    }
    assert!(compared > 8000, "{compared} records compared");
}

/// `next_ref` lends the path's segments where they lie and gives every other record as
/// `next_item` does: the same records in the same order, the same violations collected at
/// the same points and the same final alarm, on the soup with the checks `softnc check` runs
/// (software limits tight enough to be reached, the whole-program check collecting or
/// stopping) and in both threadings.
#[test]
fn lent_records_are_the_records() {
    let mut rng = Rng(0x1e47_2026);
    let tools = ToolTable::builtin();
    let long =
        nc_kernel::synthetic::compensated_program(3000, nc_kernel::synthetic::Header::Softnc);
    let (mut compared, mut lent) = (0usize, 0usize);
    for dialect in ["siemens-840c", "isg", "fanuc", "siemens-808d"] {
        let config = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("config")
            .join(format!("{dialect}.toml"));
        for (limits, mode) in [
            ("[-1e9,1e9]", WholeMode::Collect),
            ("[-30,30]", WholeMode::Collect),
            ("[-30,30]", WholeMode::Stop),
            ("[-1e9,1e9]", WholeMode::Reaction),
        ] {
            let axes: &[&str] = if dialect == "siemens-808d" {
                &["X", "Z"]
            } else {
                &["X", "Y", "Z"]
            };
            let over: Vec<String> = axes
                .iter()
                .map(|a| format!("axes.{a}.software_limits={limits}"))
                .collect();
            let md = MachineData::load(Some(&config), &over).unwrap();
            let mut programs: Vec<String> = (0..150).map(|_| program(&mut rng, dialect)).collect();
            if dialect == "siemens-840c" {
                programs.push(long.clone());
            }
            for src in &programs {
                let run = |threaded: bool, lend: bool| {
                    let go = |p: Preparation| {
                        let mut p = p.with_soft_limits(&md).checking_whole(mode);
                        let mut lent = 0;
                        let got = records_with_violations(|| {
                            let item = if lend {
                                p.next_ref().map(|x| {
                                    x.map(|x| match x {
                                        Lent::Segment(s) => {
                                            lent += 1;
                                            Prepared::Segment(*s)
                                        }
                                        Lent::Item(i) => i,
                                    })
                                })
                            } else {
                                p.next_item()
                            };
                            let end = !matches!(item, Ok(Some(_)));
                            (item, p.take_violations(end))
                        });
                        (got, lent)
                    };
                    if threaded {
                        std::thread::scope(|s| go(Preparation::threaded(s, "t", src, &md, &tools)))
                    } else {
                        go(Preparation::new("t", src, &md, &tools))
                    }
                };
                let (items, _) = run(false, false);
                for threaded in [false, true] {
                    let (got, n) = run(threaded, true);
                    assert_eq!(
                        items, got,
                        "{dialect} {limits} {mode:?} threaded {threaded}:\n{src}"
                    );
                    lent += n;
                }
                compared += items.len();
            }
        }
    }
    // Most segments of the collecting runs are lent, not moved.
    assert!(
        compared > 20_000 && lent > compared / 4,
        "{compared} records, {lent} lent"
    );
}

/// As `records`, with the violations collected so far after each record.
fn records_with_violations(
    mut next: impl FnMut() -> (
        Result<Option<Prepared>, nc_kernel::Alarm>,
        Vec<nc_kernel::Alarm>,
    ),
) -> Vec<String> {
    let mut out = Vec::new();
    loop {
        let (item, violations) = next();
        out.extend(violations.iter().map(|v| format!("violation {v:?}")));
        match item {
            Ok(Some(x)) => out.push(format!("{x:?}")),
            Ok(None) => return out,
            Err(a) => {
                out.push(format!("alarm {a:?}"));
                return out;
            }
        }
    }
}
