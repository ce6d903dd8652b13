//! Robustness of block preparation: no panic on any program the front end accepts.
//!
//! "TRC soup": random sequences of selections and deselections (G41/G42/G40, each dialect's
//! selection methods and corner modes), offsets (D0, D1, D2, negative and huge radii), lines,
//! arcs (including full circles and tiny ones), tool-axis moves, auxiliary functions, program
//! stops and masking, in all four dialects, with the bottleneck window off, 3 and 64 and both
//! violation reactions. Every run must end with records or an alarm, and an alarm must point
//! into the program. Deterministic (a fixed LCG), bounded: 4 × 6 × 400 programs.

use nc_kernel::prep::Prepared;
use nc_kernel::segment::Role;
use nc_kernel::{MachineData, Preparation, ToolTable};
use std::path::Path;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[(self.next() % xs.len() as u64) as usize]
    }
    fn coord(&mut self) -> String {
        match self.next() % 10 {
            0 => "0".into(),
            1 => format!("{}.{:03}", self.next() % 3, self.next() % 1000),
            _ => format!(
                "{}{}.{}",
                if self.next().is_multiple_of(2) {
                    "-"
                } else {
                    ""
                },
                self.next() % 120,
                self.next() % 10
            ),
        }
    }
}

fn program(rng: &mut Rng, dialect: &str) -> String {
    let (corner, select, mask): (&[&str], &[&str], &[&str]) = match dialect {
        "isg" => (
            &["G25", "G26"],
            &["G138", "G139", "G237", "G239", "G05", ""],
            &["G140", "G141"],
        ),
        "siemens-840c" => (&["G450", "G451"], &["G455", "G456", ""], &[""]),
        "siemens-808d" => (&["G450", "G451"], &[""], &[""]),
        _ => (&[""], &[""], &[""]),
    };
    let lathe = dialect == "siemens-808d";
    let (a, b, i, j) = if lathe {
        ("Z", "X", "K", "I")
    } else {
        ("X", "Y", "I", "J")
    };
    let mut s = if lathe {
        String::from("N1 G18 G90 G0 X20 Z10 T1 D1\nN2 G1 F100\n")
    } else {
        String::from("N1 G17 G90 G0 X0 Y0 Z0 D1\nN2 G1 F100\n")
    };
    let n = 4 + rng.next() % 20;
    let mut cur: (f64, f64) = if lathe { (10.0, 20.0) } else { (0.0, 0.0) };
    for k in 0..n {
        let mut line = format!("N{} ", 10 + 10 * k);
        match rng.next() % 14 {
            0 => line.push_str(rng.pick(&["G41 ", "G42 ", "G40 "])),
            1 => {
                line.push_str(rng.pick(corner));
                line.push(' ');
                line.push_str(rng.pick(select));
                line.push(' ');
                line.push_str(rng.pick(mask));
            }
            2 => line.push_str(rng.pick(&["D1 ", "D2 ", "D0 ", "D6 "])),
            3 => line.push_str(rng.pick(&["M3 S1000", "M8", "H2", "M0", "M1"])),
            4 if !lathe => line.push_str(&format!("Z{}", rng.coord())),
            _ => {}
        }
        if !rng.next().is_multiple_of(4) {
            let g = rng.pick(&["G1", "G1", "G1", "G2", "G3", "G0"]);
            if g == "G2" || g == "G3" {
                // A circle through the current point: centre offset, end at a random angle
                // (sometimes the start again: a full circle).
                let (ci, cj) = (
                    (rng.next() % 4000) as f64 / 100.0 - 20.0,
                    (rng.next() % 4000) as f64 / 100.0 - 20.0,
                );
                let (cx, cy) = (cur.0 + ci, cur.1 + cj);
                let r = (ci * ci + cj * cj).sqrt();
                let ang = if rng.next().is_multiple_of(8) {
                    (-cj).atan2(-ci)
                } else {
                    (rng.next() % 6283) as f64 / 1000.0
                };
                let end = (cx + r * ang.cos(), cy + r * ang.sin());
                line.push_str(&format!(
                    " {g} {a}{:.6} {b}{:.6} {i}{ci:.6} {j}{cj:.6}",
                    end.0, end.1
                ));
                cur = end;
            } else {
                let (x, y) = (rng.coord(), rng.coord());
                line.push_str(&format!(" {g} {a}{x} {b}{y}"));
                cur = (x.parse().unwrap_or(0.0), y.parse().unwrap_or(0.0));
            }
        }
        s.push_str(line.trim_end());
        s.push('\n');
    }
    s.push_str(rng.pick(&["N999 M30\n", "N999 G40 X0 Y0\nN1000 M30\n", ""]));
    s
}

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
