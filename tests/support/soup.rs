//! The "TRC soup": random programs of selections and deselections (G41/G42/G40, each
//! dialect's selection methods and corner modes), offsets, lines, arcs (full circles and tiny
//! ones among them), tool-axis moves, auxiliary functions, program stops and masking, in all
//! four dialects. Deterministic: a fixed LCG. Used by tests/fuzz_prep.rs (preparation never
//! panics) and tests/alarm_stops.rs (every run through the kernel ends).
#![allow(dead_code)] // each test file uses a different part

pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    pub fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[(self.next() % xs.len() as u64) as usize]
    }
    pub fn coord(&mut self) -> String {
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

/// A random program for `dialect` (its machine data file's name).
pub fn program(rng: &mut Rng, dialect: &str) -> String {
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
