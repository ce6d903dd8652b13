//! Synthetic part programs for benchmarks and soak tests, with 4-decimal coordinates, valid
//! in every dialect and in LinuxCNC's rs274 (so both can be timed on the same text): a
//! serpentine of `G1` lines and `G2` half circles, and three gouge-free G41 contours — the
//! tangent serpentine of a finishing pass, the zig-zag rows of a roughing pass and the
//! castellated contour of a row of bars, both with a non-tangent corner at every block.

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

/// Machine data overrides that give X, Y and Z the travel of these programs: a long one runs
/// kilometres beyond any machine's software limits (`--md` form).
pub fn unlimited_travel() -> Vec<String> {
    ["X", "Y", "Z"]
        .iter()
        .map(|a| format!("axes.{a}.software_limits=[-1e9, 1e9]"))
        .collect()
}

/// The selection: a line to (-20, 0), from where the first contour block goes in +X.
fn header(out: &mut String, header: Header) {
    match header {
        Header::Softnc => out.push_str("G17 G90 G0 X-40 Y20 D1\nG1 F1000\nG41 X-20 Y0\n"),
        Header::Rs274 => {
            out.push_str("G21 G17 G90 G64\nG0 X-40 Y20\nG41.1 D20\nG1 X-20 Y0 F1000\n")
        }
    }
}

/// The deselection: `G40` in a line to `to`, and the program end.
fn footer(out: &mut String, header: Header, to: [i64; 2]) {
    line(out, "G40 G1", to);
    out.push_str(match header {
        Header::Softnc => "M30\n",
        Header::Rs274 => "M2\n",
    });
}

/// `word X… Y…` and a new line.
fn line(out: &mut String, word: &str, to: [i64; 2]) {
    out.push_str(word);
    out.push_str(" X");
    fmt4(out, to[0]);
    out.push_str(" Y");
    fmt4(out, to[1]);
    out.push('\n');
}

/// An arc to `to` about the start plus `ij`, clockwise or not.
fn arc(out: &mut String, cw: bool, to: [i64; 2], ij: [i64; 2]) {
    out.push_str(if cw { "G2 X" } else { "G3 X" });
    fmt4(out, to[0]);
    out.push_str(" Y");
    fmt4(out, to[1]);
    out.push_str(" I");
    fmt4(out, ij[0]);
    out.push_str(" J");
    fmt4(out, ij[1]);
    out.push('\n');
}

/// A gouge-free G41 serpentine of `blocks` contour blocks (half lines, half arcs): rows going
/// alternately right and left, 2r apart, joined by half circles of radius r in [12, 16) mm,
/// clockwise at the right end (tool outside, r + 10) and counter-clockwise at the left end
/// (tool inside, r − 10). Selection in a line to the first row, deselection in a line away
/// from the last; 4-decimal coordinates, as in [`line_arc_program`]. Every transition is
/// tangent: the finishing pass.
pub fn compensated_program(blocks: usize, header_for: Header) -> String {
    let mut out = String::with_capacity(blocks * 36 + 128);
    header(&mut out, header_for);
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
            line(&mut out, "G1", [x, y]);
        } else {
            let r = rng.tenth_mm(12, 4);
            y -= 2 * r;
            arc(&mut out, right, [x, y], [0, -r]);
            right = !right;
        }
    }
    // Deselection: a line away from the last element, on the far side of the tool.
    let away = if right { -40 } else { 40 } * 10_000;
    footer(&mut out, header_for, [x + away, y - 30 * 10_000]);
    out
}

/// Blocks of a roughing row: a 30 mm line in, the zig-zag, a 30 mm line out, the step down.
const ROW: usize = 40;
/// Distance of the rows' base lines: the tool corridor between two rows is at least 30 mm
/// (each row keeps within 15 mm of its base line), a tool of 20 mm and 10 mm to spare.
const ROW_PITCH: i64 = 60 * 10_000;

/// Arcs of the roughing rows whose end points and centre are exact with 4 decimals: start and
/// end lie on the 3-4-5 lattice about the centre, in units of 3, 4 or 5 mm (radius 15–25 mm,
/// above the tool's 10 even with the tool inside). Start and end relative to the centre, for
/// a row going right with the arc bulging up.
const ARCS: [([i64; 2], [i64; 2]); 3] = [([-3, 4], [3, 4]), ([-3, 4], [4, 3]), ([-4, 3], [3, 4])];

/// A gouge-free G41 contour of `blocks` blocks with a non-tangent corner at every block: the
/// rows of a roughing pass. Rows go alternately right and left, 60 mm apart; each starts and
/// ends with a 30 mm line on its base line and zig-zags between: lines 20–35 mm along the row
/// to 1–8 mm either side of the base line, every fourth block an arc of radius 15–25 mm
/// bulging to either side (some with the tool inside). A 60 mm line steps down to the next
/// row: outer corners at the right end, inner ones at the left. Every corner turns by more
/// than 0.1 rad (rs274 takes turns below 0.05 rad as tangent).
pub fn roughing_program(blocks: usize, header_for: Header) -> String {
    let mut out = String::with_capacity(blocks * 36 + 128);
    header(&mut out, header_for);
    let mut rng = Lcg(0xface);
    let (mut p, mut base, mut dir, mut zig) = ([-20 * 10_000, 0], 0i64, 1i64, 1i64);
    let mut heading = [1, 0];
    for k in 0..blocks {
        let at = k % ROW;
        if at == ROW - 1 {
            base -= ROW_PITCH;
            dir = -dir;
            (p, heading) = ([p[0], base], [0, -1]);
            line(&mut out, "G1", p);
        } else if at == 0 || at == ROW - 2 {
            let q = [p[0] + dir * 30 * 10_000, base];
            (p, heading) = (q, [q[0] - p[0], q[1] - p[1]]);
            line(&mut out, "G1", p);
        } else if at.is_multiple_of(4) {
            // Drawn again while the corner would be near tangent (a few draws at most).
            let arc_block = std::iter::repeat_with(|| roughing_arc(&mut rng, p, dir))
                .take(16)
                .find(|a| corner(heading, a.start));
            let a = arc_block.unwrap_or_else(|| roughing_arc(&mut rng, p, dir));
            (p, heading) = (a.to, a.end);
            arc(&mut out, a.cw, a.to, a.ij);
        } else {
            zig = -zig;
            let q = std::iter::repeat_with(|| {
                [
                    p[0] + dir * rng.tenth_mm(20, 15),
                    base + zig * rng.tenth_mm(1, 7),
                ]
            })
            .take(16)
            .find(|q| {
                let d = [q[0] - p[0], q[1] - p[1]];
                // The last zig turns into the line out of the row as well.
                let out = [dir * 30 * 10_000, base - q[1]];
                corner(heading, d) && (at != ROW - 3 || corner(d, out))
            })
            .unwrap_or([p[0] + dir * 20 * 10_000, base + zig * 8 * 10_000]);
            (p, heading) = (q, [q[0] - p[0], q[1] - p[1]]);
            line(&mut out, "G1", p);
        }
    }
    footer(
        &mut out,
        header_for,
        [p[0] + dir * 40 * 10_000, p[1] + dir * 30 * 10_000],
    );
    out
}

/// An arc of a roughing row from `p`: end, centre offset, direction, and its tangents at the
/// start and the end (unnormalised).
struct RowArc {
    to: [i64; 2],
    ij: [i64; 2],
    cw: bool,
    start: [i64; 2],
    end: [i64; 2],
}

fn roughing_arc(rng: &mut Lcg, p: [i64; 2], dir: i64) -> RowArc {
    let (v0, v1) = ARCS[(rng.next() % 3) as usize];
    let m = rng.tenth_mm(3, 3) / 10_000 * 10_000;
    let sy = if rng.next().is_multiple_of(2) { 1 } else { -1 };
    let (r0, r1) = (
        [dir * v0[0] * m, sy * v0[1] * m],
        [dir * v1[0] * m, sy * v1[1] * m],
    );
    let c = [p[0] - r0[0], p[1] - r0[1]];
    let cw = (dir > 0) == (sy > 0);
    // The tangent of a clockwise arc is the radius turned by −90°, of a counter-clockwise +90°.
    let tangent = |r: [i64; 2]| if cw { [r[1], -r[0]] } else { [-r[1], r[0]] };
    RowArc {
        to: [c[0] + r1[0], c[1] + r1[1]],
        ij: [-r0[0], -r0[1]],
        cw,
        start: tangent(r0),
        end: tangent(r1),
    }
}

/// Whether going on in direction `b` after direction `a` turns by more than 0.1 rad:
/// sin² of the turn above sin²(0.1) = 0.00997, or a turn over 90° (no libm: the same on
/// every machine).
fn corner(a: [i64; 2], b: [i64; 2]) -> bool {
    let (a, b) = ([a[0] as f64, a[1] as f64], [b[0] as f64, b[1] as f64]);
    let cross = a[0] * b[1] - a[1] * b[0];
    let dot = a[0] * b[0] + a[1] * b[1];
    let norms = (a[0] * a[0] + a[1] * a[1]) * (b[0] * b[0] + b[1] * b[1]);
    dot < 0.0 || cross * cross > 0.00997 * norms
}

/// A gouge-free G41 contour of `blocks` blocks round a row of bars standing in +Y, every
/// corner 90° (the tool's side alternating outer and inner): up a bar's side 15–40 mm, over
/// its top 5–20 mm, down, and along the slot's floor 22–35 mm (the 20 mm tool fits with at
/// least 1 mm either side).
pub fn bars_program(blocks: usize, header_for: Header) -> String {
    let mut out = String::with_capacity(blocks * 32 + 128);
    header(&mut out, header_for);
    let mut rng = Lcg(0xba25);
    let mut p = [-20 * 10_000, 0];
    let mut height = 0;
    for k in 0..blocks {
        p = match k % 4 {
            0 => [p[0] + rng.tenth_mm(22, 13), 0],
            1 => {
                height = rng.tenth_mm(15, 25);
                [p[0], height]
            }
            2 => [p[0] + rng.tenth_mm(5, 15), height],
            _ => [p[0], 0],
        };
        line(&mut out, "G1", p);
    }
    footer(
        &mut out,
        header_for,
        [p[0] + 40 * 10_000, p[1] + 30 * 10_000],
    );
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
