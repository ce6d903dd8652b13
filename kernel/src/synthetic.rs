//! Synthetic part programs for benchmarks and soak tests: a serpentine of `G1 X… Y…` lines
//! and `G2 X… Y… I… J…` half circles with 4-decimal coordinates, valid in every dialect
//! and in LinuxCNC's rs274 (so both can be timed on the same text).

use std::fmt::Write;

/// Deterministic pseudo-random numbers (64-bit LCG); no dependency, same sequence everywhere.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    /// A value in [lo, lo + span) with 4 decimals, as ten-thousandths.
    fn tenth_mm(&mut self, lo: i64, span: i64) -> i64 {
        lo * 10_000 + (self.next() % (span as u64 * 10_000)) as i64
    }
}

fn fmt4(out: &mut String, v: i64) {
    let sign = if v < 0 { "-" } else { "" };
    let a = v.unsigned_abs();
    let _ = write!(out, "{sign}{}.{:04}", a / 10_000, a % 10_000);
}

/// A program of `blocks` motion blocks (half lines, half arcs) after a one-line header
/// `G17 G90 G1 F1000`, ending with `M30`.
pub fn line_arc_program(blocks: usize) -> String {
    let mut out = String::with_capacity(blocks * 30 + 64);
    out.push_str("G17 G90 G1 F1000\n");
    let mut rng = Lcg(0x5eed);
    // Coordinates in ten-thousandths of a mm, so every value is exact with 4 decimals.
    let mut y: i64 = 0;
    let mut right = true;
    let mut last_x: i64 = 0;
    for k in 0..blocks {
        if k % 2 == 0 {
            let x = if right {
                rng.tenth_mm(80, 40)
            } else {
                rng.tenth_mm(-20, 40)
            };
            out.push_str("G1 X");
            fmt4(&mut out, x);
            out.push_str(" Y");
            fmt4(&mut out, y);
            out.push('\n');
            last_x = x;
        } else {
            // Half circle clockwise: at the right end downwards, at the left end upwards.
            let r = rng.tenth_mm(2, 6);
            let x = last_x;
            let (dy, j) = if right { (-2 * r, -r) } else { (2 * r, r) };
            y += dy;
            out.push_str("G2 X");
            fmt4(&mut out, x);
            out.push_str(" Y");
            fmt4(&mut out, y);
            out.push_str(" I0.0000 J");
            fmt4(&mut out, j);
            out.push('\n');
            right = !right;
        }
    }
    out.push_str("M30\n");
    out
}

/// Which control the compensated program's header is written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Header {
    /// `G41` with offset D1 from the tool table (radius 10 in config/tools.toml): every softnc
    /// dialect.
    Softnc,
    /// LinuxCNC's `G41.1 D20` (D is the diameter there): the same contour for `rs274`.
    Rs274,
}

/// Tool radius the compensated program is made for (D1 in the shipped tool table).
pub const COMPENSATED_RADIUS: f64 = 10.0;

/// A gouge-free G41 serpentine of `blocks` contour blocks (half lines, half arcs): rows going
/// alternately right and left, 2r apart, joined by half circles of radius r in [12, 16) mm,
/// clockwise at the right end (tool outside, r + 10) and counter-clockwise at the left end
/// (tool inside, r − 10). Selection in a line to the first row, deselection in a line away
/// from the last; 4-decimal coordinates, as in [`line_arc_program`].
pub fn compensated_program(blocks: usize, header: Header) -> String {
    let mut out = String::with_capacity(blocks * 36 + 128);
    match header {
        Header::Softnc => out.push_str("G17 G90 G0 X-40 Y20 D1\nG1 F1000\nG41 X-20 Y0\n"),
        Header::Rs274 => {
            out.push_str("G21 G17 G90 G64\nG0 X-40 Y20\nG41.1 D20\nG1 X-20 Y0 F1000\n")
        }
    }
    let mut rng = Lcg(0xc0ffee);
    let mut y: i64 = 0;
    let mut right = true;
    let mut x: i64 = -20 * 10_000;
    for k in 0..blocks {
        if k % 2 == 0 {
            x = if right {
                rng.tenth_mm(80, 40)
            } else {
                rng.tenth_mm(-20, 40)
            };
            out.push_str("G1 X");
            fmt4(&mut out, x);
            out.push_str(" Y");
            fmt4(&mut out, y);
        } else {
            let r = rng.tenth_mm(12, 4);
            y -= 2 * r;
            out.push_str(if right { "G2 X" } else { "G3 X" });
            fmt4(&mut out, x);
            out.push_str(" Y");
            fmt4(&mut out, y);
            out.push_str(" I0.0000 J");
            fmt4(&mut out, -r);
            right = !right;
        }
        out.push('\n');
    }
    // Deselection: a line away from the last element, on the far side of the tool.
    out.push_str("G40 G1 X");
    fmt4(&mut out, x + if right { -40 } else { 40 } * 10_000);
    out.push_str(" Y");
    fmt4(&mut out, y - 30 * 10_000);
    out.push_str(match header {
        Header::Softnc => "\nM30\n",
        Header::Rs274 => "\nM2\n",
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{interpret, MachineData, ToolTable};

    #[test]
    fn compensated_program_prepares_in_every_dialect() {
        let text = compensated_program(1000, Header::Softnc);
        for dialect in ["siemens-840c", "isg", "fanuc"] {
            let md = MachineData::load(None, &[format!("dialect={dialect}")]).unwrap();
            let segs = crate::prepare("bench", &text, &md, &ToolTable::builtin())
                .unwrap_or_else(|a| panic!("{dialect}: {a:?}"));
            let contour = segs
                .iter()
                .filter(|s| s.role == crate::segment::Role::Contour)
                .count();
            // The first row is the selection target, so every contour block is compensated.
            assert_eq!(contour, 1000, "{dialect}");
        }
    }

    #[test]
    fn synthetic_program_interprets_in_every_dialect() {
        let text = line_arc_program(1000);
        assert_eq!(text.lines().count(), 1002);
        for dialect in ["siemens-840c", "isg", "fanuc"] {
            let md = MachineData::load(None, &[format!("dialect={dialect}")]).unwrap();
            let blocks = interpret("bench", &text, &md, &ToolTable::default()).unwrap();
            let motions = blocks.iter().filter(|b| b.motion.is_some()).count();
            assert_eq!(motions, 1000, "{dialect}");
        }
    }
}
