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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{interpret, MachineData, ToolTable};

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
