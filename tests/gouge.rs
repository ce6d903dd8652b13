//! Gouge test, independent of the production geometry (issue 4): random contours of lines and
//! arcs, both sides, random tool radii, notches narrower than the tool and tiny segments.
//!
//! (A) Whatever softnc puts out — up to an alarm, or all of it — every tool-centre segment
//!     other than approach and retract keeps the tool circle outside the programmed contour:
//!     its exact distance to every contour element is at least R − 1e-9 mm.
//! (B) No false alarms: the test builds the full offset itself — for polylines (equidistants
//!     trimmed at inner corners, transition circles at outer ones) and for contours with arcs
//!     whose corners are all outer or tangent — and measures it; when it clears the contour
//!     by 1e-6 mm, softnc must prepare the program without an alarm (here some 4 500 such
//!     arc contours and 14 800 polylines).
//!
//! The bottleneck window is 64 blocks, longer than any contour here, so softnc sees all of
//! it. The distance functions below are this file's own.

use nc_kernel::{MachineData, ToolTable};
use nc_kernel::{Role, Shape};

type P = [f64; 2];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1]]
}
fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1]]
}
fn mul(a: P, k: f64) -> P {
    [a[0] * k, a[1] * k]
}
fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: P, b: P) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn norm(a: P) -> f64 {
    dot(a, a).sqrt()
}

/// A piece of the plane: a segment, or an arc given by centre, radius, start angle and
/// signed sweep (ccw > 0).
#[derive(Clone, Copy, Debug)]
enum Piece {
    Seg(P, P),
    Arc { c: P, r: f64, a0: f64, sw: f64 },
}

impl Piece {
    /// Unit direction of travel at the start or the end.
    fn tangent(&self, at_end: bool) -> P {
        match *self {
            Piece::Seg(a, b) => mul(sub(b, a), 1.0 / norm(sub(b, a))),
            Piece::Arc { a0, sw, .. } => {
                let a = if at_end { a0 + sw } else { a0 };
                let s = sw.signum();
                [-a.sin() * s, a.cos() * s]
            }
        }
    }

    fn at(&self, t: f64) -> P {
        match *self {
            Piece::Seg(a, b) => add(a, mul(sub(b, a), t)),
            Piece::Arc { c, r, a0, sw } => {
                let a = a0 + sw * t;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            }
        }
    }
}

/// Exact distance from a point to a piece.
fn point_dist(p: P, q: &Piece) -> f64 {
    nearest(p, q).0
}

/// Exact distance from a point to a piece, and where along the piece (0 to 1) the nearest
/// point lies.
fn nearest(p: P, q: &Piece) -> (f64, f64) {
    match *q {
        Piece::Seg(a, b) => {
            let d = sub(b, a);
            let l = dot(d, d);
            let t = if l == 0.0 {
                0.0
            } else {
                (dot(sub(p, a), d) / l).clamp(0.0, 1.0)
            };
            (norm(sub(p, add(a, mul(d, t)))), t)
        }
        Piece::Arc { c, r, a0, sw } => {
            // Angle of p seen from the centre, relative to the start, in the sweep's sense.
            let v = sub(p, c);
            let (d0, d1) = (norm(sub(p, q.at(0.0))), norm(sub(p, q.at(1.0))));
            let ends = if d0 <= d1 { (d0, 0.0) } else { (d1, 1.0) };
            if norm(v) == 0.0 {
                return (r, 0.0);
            }
            let mut rel = (v[1].atan2(v[0]) - a0) * sw.signum();
            rel = rel.rem_euclid(std::f64::consts::TAU);
            if rel <= sw.abs() && (norm(v) - r).abs() <= ends.0 {
                ((norm(v) - r).abs(), rel / sw.abs())
            } else {
                ends
            }
        }
    }
}

/// Exact distance between two pieces: 0 if they cross, else the smallest of the candidates
/// where a closest pair can be (end points, and for arcs the points on the line through the
/// centre perpendicular to the other piece or towards the other centre).
fn piece_dist(x: &Piece, y: &Piece) -> f64 {
    if crosses(x, y) {
        return 0.0;
    }
    let mut d = f64::INFINITY;
    for (p, q) in [(x, y), (y, x)] {
        for t in [0.0, 1.0] {
            d = d.min(point_dist(p.at(t), q));
        }
        if let Piece::Arc { c, r, .. } = *p {
            let dirs: Vec<P> = match *q {
                Piece::Seg(a, b) => {
                    let n = [-(b[1] - a[1]), b[0] - a[0]];
                    vec![n, mul(n, -1.0)]
                }
                Piece::Arc { c: c2, .. } => {
                    let u = sub(c2, c);
                    vec![u, mul(u, -1.0)]
                }
            };
            for u in dirs {
                let l = norm(u);
                if l == 0.0 {
                    continue;
                }
                let pt = add(c, mul(u, r / l));
                if point_dist(pt, p) < 1e-12 {
                    d = d.min(point_dist(pt, q));
                }
            }
        }
    }
    d
}

/// Whether two pieces cross or touch (by sampling the sign of the distance to the other's
/// line/circle between their intersections would be overkill: solve directly).
fn crosses(x: &Piece, y: &Piece) -> bool {
    let on = |p: P, q: &Piece| point_dist(p, q) < 1e-12;
    let pts: Vec<P> = match (*x, *y) {
        (Piece::Seg(a, b), Piece::Seg(c, d)) => {
            let den = cross(sub(b, a), sub(d, c));
            if den == 0.0 {
                return false;
            }
            let t = cross(sub(c, a), sub(d, c)) / den;
            vec![add(a, mul(sub(b, a), t))]
        }
        (Piece::Seg(a, b), Piece::Arc { c, r, .. })
        | (Piece::Arc { c, r, .. }, Piece::Seg(a, b)) => {
            let d = sub(b, a);
            let f = sub(a, c);
            let (qa, qb, qc) = (dot(d, d), 2.0 * dot(f, d), dot(f, f) - r * r);
            let disc = qb * qb - 4.0 * qa * qc;
            if disc < 0.0 || qa == 0.0 {
                return false;
            }
            let s = disc.sqrt();
            vec![
                add(a, mul(d, (-qb - s) / (2.0 * qa))),
                add(a, mul(d, (-qb + s) / (2.0 * qa))),
            ]
        }
        (Piece::Arc { c: c1, r: r1, .. }, Piece::Arc { c: c2, r: r2, .. }) => {
            let v = sub(c2, c1);
            let l = norm(v);
            if l == 0.0 || l > r1 + r2 || l < (r1 - r2).abs() {
                return false;
            }
            let a = (r1 * r1 - r2 * r2 + l * l) / (2.0 * l);
            let h = (r1 * r1 - a * a).max(0.0).sqrt();
            let m = add(c1, mul(v, a / l));
            let n = [-v[1] / l, v[0] / l];
            vec![add(m, mul(n, h)), add(m, mul(n, -h))]
        }
    };
    pts.into_iter().any(|p| on(p, x) && on(p, y))
}

/// Deterministic random numbers (64-bit LCG).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// A random open contour: its pieces, the program text and the tool radius.
struct Case {
    pieces: Vec<Piece>,
    program: String,
    r: f64,
    left: bool,
}

/// 15 decimals: the program text reads back as exactly the same doubles, so an arc's end
/// point is on its circle to ~1e-14 mm and the 1e-9 tolerance means something.
fn fmt(v: f64) -> String {
    format!("{:.15}", v + 0.0)
}

/// Coordinates are rounded to 15 decimals as the program writes them (a no-op for doubles of
/// this size, kept so that both sides provably see the same contour).
fn make_case(rng: &mut Rng, lines_only: bool) -> Case {
    let r = if rng.next() < 0.5 {
        rng.range(0.5, 3.0)
    } else {
        rng.range(3.0, 12.0)
    };
    let left = rng.next() < 0.5;
    let n = 2 + (rng.next() * 8.0) as usize;
    let round = |v: f64| fmt(v).parse::<f64>().unwrap();
    let mut p: P = [0.0, 0.0];
    let mut heading: f64 = rng.range(0.0, std::f64::consts::TAU);
    let mut pieces = Vec::new();
    let mut body = String::new();
    for _ in 0..n {
        // Sharp and gentle turns, notches (turn back), tiny and long elements.
        let turn = match rng.next() {
            x if x < 0.15 => rng.range(-3.0, 3.0),
            x if x < 0.3 => 0.0,
            _ => rng.range(-1.6, 1.6),
        };
        heading += turn;
        let len = if rng.next() < 0.15 {
            rng.range(0.01, 1.0)
        } else {
            rng.range(2.0, 40.0)
        };
        if lines_only || rng.next() < 0.6 {
            let q = [
                round(p[0] + len * heading.cos()),
                round(p[1] + len * heading.sin()),
            ];
            if norm(sub(q, p)) < 1e-3 {
                continue;
            }
            body.push_str(&format!("G1 X{} Y{}\n", fmt(q[0]), fmt(q[1])));
            pieces.push(Piece::Seg(p, q));
            heading = (q[1] - p[1]).atan2(q[0] - p[0]);
            p = q;
        } else {
            // A tangent arc: centre on the normal, radius random (some below R).
            let ccw = rng.next() < 0.5;
            let rad = if rng.next() < 0.2 {
                rng.range(0.2, 2.0)
            } else {
                rng.range(2.0, 30.0)
            };
            let sweep = rng.range(0.2, 3.0);
            let nrm = if ccw {
                [-heading.sin(), heading.cos()]
            } else {
                [heading.sin(), -heading.cos()]
            };
            let c = [round(p[0] + rad * nrm[0]), round(p[1] + rad * nrm[1])];
            let rr = norm(sub(p, c));
            let a0 = (p[1] - c[1]).atan2(p[0] - c[0]);
            let sw = if ccw { sweep } else { -sweep };
            let end = [
                round(c[0] + rr * (a0 + sw).cos()),
                round(c[1] + rr * (a0 + sw).sin()),
            ];
            // The end as written: project it back onto the circle for the test's piece.
            let ea = (end[1] - c[1]).atan2(end[0] - c[0]);
            let mut swr = ea - a0;
            if ccw {
                swr = swr.rem_euclid(std::f64::consts::TAU);
            } else {
                swr = -(-swr).rem_euclid(std::f64::consts::TAU);
            }
            if swr.abs() < 1e-3 {
                continue;
            }
            body.push_str(&format!(
                "G{} X{} Y{} I{} J{}\n",
                if ccw { 3 } else { 2 },
                fmt(end[0]),
                fmt(end[1]),
                fmt(c[0] - p[0]),
                fmt(c[1] - p[1])
            ));
            pieces.push(Piece::Arc {
                c,
                r: rr,
                a0,
                sw: swr,
            });
            heading = ea
                + if ccw {
                    std::f64::consts::FRAC_PI_2
                } else {
                    -std::f64::consts::FRAC_PI_2
                };
            p = end;
        }
    }
    // Approach and departure along the first and last directions (tangent: α = 180°, so
    // the contour starts and ends in the normal positions whatever the selection rule).
    let first_dir = match pieces.first() {
        Some(Piece::Seg(a, b)) => mul(sub(*b, *a), 1.0 / norm(sub(*b, *a))),
        Some(Piece::Arc { a0, sw, .. }) => {
            let t = a0 + sw.signum() * std::f64::consts::FRAC_PI_2;
            [t.cos(), t.sin()]
        }
        None => [1.0, 0.0],
    };
    let s = [round(-30.0 * first_dir[0]), round(-30.0 * first_dir[1])];
    let e = [
        round(p[0] + 30.0 * heading.cos()),
        round(p[1] + 30.0 * heading.sin()),
    ];
    let program = format!(
        "G0 G17 G90 D1 X{} Y{} Z0\nG1 F100 G450\nG{} X0 Y0\n{body}G1 G40 X{} Y{}\nM30\n",
        fmt(s[0]),
        fmt(s[1]),
        if left { 41 } else { 42 },
        fmt(e[0]),
        fmt(e[1])
    );
    Case {
        pieces,
        program,
        r,
        left,
    }
}

/// The shipped 840C machine data as it is: the 64-block window and the whole-program check.
fn machine() -> MachineData {
    MachineData::load(None, &[]).unwrap()
}

/// The shipped ISG machine data as it is (contour masking, G141, over the 64-block window,
/// the whole-program check on the masked path).
fn isg_masking() -> MachineData {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("config/isg.toml");
    MachineData::load(Some(&path), &[]).unwrap()
}

/// The same contour as an ISG program with G141: transition circles (G26) for the 840C's
/// G450, masking on.
fn with_masking(case: &Case) -> Case {
    Case {
        pieces: case.pieces.clone(),
        program: case.program.replace("G1 F100 G450", "G1 F100 G26 G141"),
        r: case.r,
        left: case.left,
    }
}

/// softnc's path as pieces, approach and retract left out: what the kernel's channel takes
/// (with the whole-program check ahead of it when the machine data asks for it).
fn softnc_pieces(case: &Case, md: &MachineData) -> (Vec<Piece>, bool) {
    let mut tools = ToolTable::builtin();
    tools.set_radius(1, case.r).unwrap();
    let mut out = Vec::new();
    let mut path = nc_kernel::handover::Gated::of_job(nc_kernel::handover::Job {
        name: "gouge",
        source: &case.program,
        md,
        tools: &tools,
        at: None,
    });
    let mut alarm = false;
    loop {
        let next = match path.next_item() {
            Some(Ok(nc_kernel::Prepared::Segment(s))) => Ok(Some(s)),
            Some(Ok(_)) => continue,
            Some(Err(a)) => Err(a),
            None => Ok(None),
        };
        match next {
            Ok(Some(s)) => {
                if !matches!(s.role, Role::Contour | Role::Corner | Role::Intermediate) {
                    continue;
                }
                let (a, b) = ([s.from[0], s.from[1]], [s.to[0], s.to[1]]);
                match s.shape {
                    Shape::Line => {
                        if norm(sub(b, a)) > 0.0 {
                            out.push(Piece::Seg(a, b));
                        }
                    }
                    Shape::Arc {
                        center,
                        ccw,
                        r0,
                        r1,
                        ..
                    } => {
                        let c = [center[0], center[1]];
                        if (r0 - r1).abs() > 1e-9 {
                            // Radius changes over the arc: not made by these programs.
                            panic!("unexpected spiral in {}", case.program);
                        }
                        let a0 = (a[1] - c[1]).atan2(a[0] - c[0]);
                        let a1 = (b[1] - c[1]).atan2(b[0] - c[0]);
                        let mut sw = if ccw {
                            (a1 - a0).rem_euclid(std::f64::consts::TAU)
                        } else {
                            -(a0 - a1).rem_euclid(std::f64::consts::TAU)
                        };
                        if sw == 0.0 {
                            sw = if ccw {
                                std::f64::consts::TAU
                            } else {
                                -std::f64::consts::TAU
                            };
                        }
                        out.push(Piece::Arc { c, r: r0, a0, sw });
                    }
                }
            }
            Ok(None) => break,
            Err(_) => {
                alarm = true;
                break;
            }
        }
    }
    (out, alarm)
}

/// Distance from a point to the nearest of `set`.
fn dist_to(p: P, set: &[Piece]) -> f64 {
    set.iter()
        .map(|q| point_dist(p, q))
        .fold(f64::INFINITY, f64::min)
}

fn min_dist(path: &[Piece], contour: &[Piece]) -> f64 {
    let mut d = f64::INFINITY;
    for p in path {
        for q in contour {
            d = d.min(piece_dist(p, q));
        }
    }
    d
}

/// The test's own full offset of a polyline: equidistants trimmed at inner corners, circles
/// about the vertex at outer ones, each with the elements it is built on (its own and its
/// neighbours: at exactly R from them by construction). `None` if an element's equidistant
/// runs backwards.
fn offset_polyline(case: &Case) -> Option<Vec<(Piece, usize, usize)>> {
    let side = if case.left { 1.0 } else { -1.0 };
    let segs: Vec<(P, P)> = case
        .pieces
        .iter()
        .map(|p| match *p {
            Piece::Seg(a, b) => (a, b),
            Piece::Arc { .. } => unreachable!("polylines only"),
        })
        .collect();
    let normal = |a: P, b: P| {
        let d = sub(b, a);
        let l = norm(d);
        mul([-d[1] / l, d[0] / l], side * case.r)
    };
    let mut starts: Vec<P> = segs.iter().map(|&(a, b)| add(a, normal(a, b))).collect();
    let mut ends: Vec<P> = segs.iter().map(|&(a, b)| add(b, normal(a, b))).collect();
    let mut corners = Vec::new();
    for i in 0..segs.len().saturating_sub(1) {
        let (a1, b1) = segs[i];
        let (a2, b2) = segs[i + 1];
        let (d1, d2) = (sub(b1, a1), sub(b2, a2));
        let turn = cross(d1, d2) / (norm(d1) * norm(d2));
        let along = dot(d1, d2);
        if turn.abs() < 1e-12 && along > 0.0 {
            continue;
        }
        if turn * side > 0.0 && along > -norm(d1) * norm(d2) * (1.0 - 1e-12) {
            // Inner: both equidistants end at their intersection.
            let (p, u) = (starts[i], d1);
            let (q, w) = (starts[i + 1], d2);
            let t = cross(sub(q, p), w) / cross(u, w);
            let x = add(p, mul(u, t));
            ends[i] = x;
            starts[i + 1] = x;
        } else {
            // Outer (or a reversal): the circle about the vertex.
            let circle = corner_circle(b1, ends[i], starts[i + 1], side, case.r);
            corners.push((circle, i, i + 1));
        }
    }
    let mut out = corners;
    for i in 0..segs.len() {
        let d = sub(segs[i].1, segs[i].0);
        if dot(sub(ends[i], starts[i]), d) < -1e-9 * norm(d) {
            return None;
        }
        if norm(sub(ends[i], starts[i])) > 0.0 {
            out.push((Piece::Seg(starts[i], ends[i]), i.saturating_sub(1), i + 1));
        }
    }
    Some(out)
}

/// The test's own full offset of a contour with lines and arcs whose corners are all outer
/// or tangent (no trimming needed): equidistants, and circles about the vertex at outer
/// corners. `None` for contours with an inner corner or an arc the tool does not fit.
fn offset_outer(case: &Case) -> Option<Vec<(Piece, usize, usize)>> {
    let side = if case.left { 1.0 } else { -1.0 };
    let mut out = Vec::new();
    for (i, p) in case.pieces.iter().enumerate() {
        let piece = match *p {
            Piece::Seg(a, b) => {
                let t = p.tangent(false);
                let n = mul([-t[1], t[0]], side * case.r);
                Piece::Seg(add(a, n), add(b, n))
            }
            Piece::Arc { c, r, a0, sw } => {
                // Left of a counter-clockwise arc is towards the centre.
                let ro = r - side * sw.signum() * case.r;
                if ro <= 1e-9 {
                    return None;
                }
                Piece::Arc { c, r: ro, a0, sw }
            }
        };
        out.push((piece, i.saturating_sub(1), i + 1));
        if i + 1 < case.pieces.len() {
            let (t1, t2) = (p.tangent(true), case.pieces[i + 1].tangent(false));
            let turn = cross(t1, t2);
            if turn.abs() < 1e-9 && dot(t1, t2) > 0.0 {
                continue;
            }
            if turn * side > 0.0 {
                return None;
            }
            let v = p.at(1.0);
            let e = add(v, mul([-t1[1], t1[0]], side * case.r));
            let s2 = add(v, mul([-t2[1], t2[0]], side * case.r));
            out.push((corner_circle(v, e, s2, side, case.r), i, i + 1));
        }
    }
    Some(out)
}

/// Where two equidistants' carriers meet: a line (point, unit direction) or a circle.
#[derive(Clone, Copy, Debug)]
enum Carrier {
    Line(P, P),
    Circle(P, f64),
}

/// The carriers' intersection nearest `near` (the corner's normal points), if they meet.
fn meet(x: Carrier, y: Carrier, near: P) -> Option<P> {
    let line_circle = |p: P, u: P, c: P, r: f64| -> Vec<P> {
        let f = sub(p, c);
        let b = dot(f, u);
        let disc = b * b - (dot(f, f) - r * r);
        if disc < -1e-12 * r * r {
            return vec![];
        }
        let h = disc.max(0.0).sqrt();
        vec![add(p, mul(u, -b - h)), add(p, mul(u, -b + h))]
    };
    let found: Vec<P> = match (x, y) {
        (Carrier::Line(p, u), Carrier::Line(q, w)) => {
            let k = cross(u, w);
            if k.abs() < 1e-12 {
                vec![]
            } else {
                vec![add(p, mul(u, cross(sub(q, p), w) / k))]
            }
        }
        (Carrier::Line(p, u), Carrier::Circle(c, r))
        | (Carrier::Circle(c, r), Carrier::Line(p, u)) => line_circle(p, u, c, r),
        (Carrier::Circle(c1, r1), Carrier::Circle(c2, r2)) => {
            let d = norm(sub(c2, c1));
            if d < 1e-12 || d > r1 + r2 + 1e-9 || d < (r1 - r2).abs() - 1e-9 {
                vec![]
            } else {
                let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
                let h = (r1 * r1 - a * a).max(0.0).sqrt();
                let e = mul(sub(c2, c1), 1.0 / d);
                let m = add(c1, mul(e, a));
                vec![add(m, mul([-e[1], e[0]], h)), add(m, mul([e[1], -e[0]], h))]
            }
        }
    };
    found
        .into_iter()
        .min_by(|a, b| norm(sub(*a, near)).total_cmp(&norm(sub(*b, near))))
}

/// The test's own full offset of any contour of lines and arcs: equidistants trimmed at
/// their intersection at inner corners (line/line, line/circle, circle/circle: the one
/// nearest the corner), circles about the vertex at outer ones, each with the elements it is
/// built on. `None` where an equidistant runs backwards, an arc's shrinks to nothing or two
/// do not meet.
fn offset_general(case: &Case) -> Option<Vec<(Piece, usize, usize)>> {
    let side = if case.left { 1.0 } else { -1.0 };
    let n = case.pieces.len();
    let mut carriers = Vec::with_capacity(n);
    let mut starts = Vec::with_capacity(n);
    let mut ends = Vec::with_capacity(n);
    for p in &case.pieces {
        match *p {
            Piece::Seg(a, b) => {
                let t = p.tangent(false);
                let nrm = mul([-t[1], t[0]], side * case.r);
                carriers.push(Carrier::Line(add(a, nrm), t));
                starts.push(add(a, nrm));
                ends.push(add(b, nrm));
            }
            Piece::Arc { c, r, a0, sw } => {
                let ro = r - side * sw.signum() * case.r;
                if ro <= 1e-9 {
                    return None;
                }
                carriers.push(Carrier::Circle(c, ro));
                starts.push(add(c, [ro * a0.cos(), ro * a0.sin()]));
                ends.push(add(c, [ro * (a0 + sw).cos(), ro * (a0 + sw).sin()]));
            }
        }
    }
    let mut out = Vec::new();
    for i in 0..n.saturating_sub(1) {
        let (t1, t2) = (
            case.pieces[i].tangent(true),
            case.pieces[i + 1].tangent(false),
        );
        let turn = cross(t1, t2);
        if turn.abs() < 1e-9 && dot(t1, t2) > 0.0 {
            continue;
        }
        if turn * side > 0.0 && dot(t1, t2) > -(1.0 - 1e-12) {
            let near = mul(add(ends[i], starts[i + 1]), 0.5);
            let x = meet(carriers[i], carriers[i + 1], near)?;
            ends[i] = x;
            starts[i + 1] = x;
        } else {
            let v = case.pieces[i].at(1.0);
            let circle = corner_circle(v, ends[i], starts[i + 1], side, case.r);
            out.push((circle, i, i + 1));
        }
    }
    let pi = std::f64::consts::PI;
    for (i, p) in case.pieces.iter().enumerate() {
        let (s, e) = (starts[i], ends[i]);
        let piece = match (*p, carriers[i]) {
            (Piece::Seg(a, b), _) => {
                let d = sub(b, a);
                if dot(sub(e, s), d) < -1e-9 * norm(d) {
                    return None;
                }
                if norm(sub(e, s)) == 0.0 {
                    continue;
                }
                Piece::Seg(s, e)
            }
            (Piece::Arc { c, a0, sw, .. }, Carrier::Circle(_, ro)) => {
                // Positions along the arc's direction, the start near 0 and the end near |sw|.
                let k = sw.signum();
                let along = |q: P, around: f64| {
                    let a = ((q[1] - c[1]).atan2(q[0] - c[0]) - a0) * k;
                    around + (a - around + pi).rem_euclid(std::f64::consts::TAU) - pi
                };
                let (ts, te) = (along(s, 0.0), along(e, sw.abs()));
                if te < ts - 1e-9 {
                    return None;
                }
                Piece::Arc {
                    c,
                    r: ro,
                    a0: a0 + k * ts,
                    sw: k * (te - ts),
                }
            }
            (Piece::Arc { .. }, Carrier::Line(..)) => unreachable!("an arc's carrier is a circle"),
        };
        out.push((piece, i.saturating_sub(1), i + 1));
    }
    Some(out)
}

/// The transition circle about the vertex `v` of an outer corner, radius `r`, from `from` to
/// `to` (the equidistants' ends there), turning away from the tool side (`side` +1 left).
fn corner_circle(v: P, from: P, to: P, side: f64, r: f64) -> Piece {
    let a0 = (from[1] - v[1]).atan2(from[0] - v[0]);
    let a1 = (to[1] - v[1]).atan2(to[0] - v[0]);
    let sw = if side < 0.0 {
        (a1 - a0).rem_euclid(std::f64::consts::TAU)
    } else {
        -(a0 - a1).rem_euclid(std::f64::consts::TAU)
    };
    Piece::Arc { c: v, r, a0, sw }
}

/// Smallest distance from the offset pieces to the contour elements they are built on
/// (`built_on`), or to all the others.
fn clearance(offset: &[(Piece, usize, usize)], contour: &[Piece], built_on: bool) -> f64 {
    let mut d = f64::INFINITY;
    for (p, lo, hi) in offset {
        for (j, q) in contour.iter().enumerate() {
            if (*lo..=*hi).contains(&j) == built_on {
                d = d.min(piece_dist(p, q));
            }
        }
    }
    d
}

const CASES: usize = 100_000;

/// No piece of `path` comes closer than R − 1e-9 mm to the contour of `case` (`what` names
/// the case in the message).
fn assert_clear(path: &[Piece], case: &Case, what: &str) {
    let d = min_dist(path, &case.pieces);
    assert!(
        d >= case.r - 1e-9,
        "{what}: tool path within {d} of the contour, R = {}\n{}",
        case.r,
        case.program
    );
}

#[test]
fn softnc_never_puts_out_a_gouge() {
    let md = machine();
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let mut alarms = 0;
    for k in 0..CASES {
        let case = make_case(&mut rng, k % 2 == 0);
        if case.pieces.is_empty() {
            continue;
        }
        let (path, alarm) = softnc_pieces(&case, &md);
        alarms += usize::from(alarm);
        assert_clear(&path, &case, &format!("case {k}"));
    }
    // The generator makes plenty of both kinds.
    assert!(
        alarms > CASES / 20 && alarms < CASES - CASES / 20,
        "{alarms} alarms"
    );
}

/// The whole-program check is the first line of defence: with the controls' own shallow
/// windows (the 840C's 3 blocks; ISG's masking over 3), which let gouging segments out on
/// contours whose bottleneck lies further away, nothing that gouges goes out.
#[test]
fn the_whole_check_keeps_gouges_in_with_the_controls_own_windows() {
    let own = |config: Option<&str>, window: &str| {
        let path = config.map(|c| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(c));
        MachineData::load(
            path.as_deref(),
            &[format!("trc.bottleneck_window={window}")],
        )
        .unwrap()
    };
    let unchecked = |md: &MachineData| {
        let mut md = md.clone();
        md.trc.whole_program_check = false;
        md
    };
    for (config, window, masking) in [(None, "3", false), (Some("config/isg.toml"), "0", true)] {
        let md = own(config, window);
        let bare = unchecked(&md);
        let mut rng = Rng(0x243f6a8885a308d3);
        let (mut caught, mut n) = (0, 0);
        for k in 0..CASES / 10 {
            let case = make_case(&mut rng, k % 2 == 0);
            if case.pieces.is_empty() {
                continue;
            }
            let case = if masking { with_masking(&case) } else { case };
            n += 1;
            let (path, _) = softnc_pieces(&case, &md);
            assert_clear(
                &path,
                &case,
                &format!("{config:?} window {window}, case {k}"),
            );
            // Without the check the shallow window lets some of them out.
            let (bare_path, _) = softnc_pieces(&case, &bare);
            caught += usize::from(min_dist(&bare_path, &case.pieces) < case.r - 1e-9);
        }
        assert!(caught > 0, "{config:?}: no gouge to catch in {n} cases");
        eprintln!("{config:?} window {window}: {caught} of {n} contours gouge without the check");
    }
}

/// (A) with ISG contour masking: loops are cut out instead of stopping, and what is put out
/// still never gouges, nor strays from the contour (a joint of two nearly parallel
/// equidistants far from the part, or a segment that runs backwards, once did).
#[test]
fn masking_never_puts_out_a_gouge() {
    let md = isg_masking();
    let mut rng = Rng(0x13198a2e03707344);
    let (mut alarms, mut n) = (0, 0);
    for k in 0..CASES / 4 {
        let case = make_case(&mut rng, k % 2 == 0);
        if case.pieces.is_empty() {
            continue;
        }
        let case = with_masking(&case);
        let (path, alarm) = softnc_pieces(&case, &md);
        n += 1;
        alarms += usize::from(alarm);
        assert_clear(&path, &case, &format!("case {k}"));
        // No detour: every end and midpoint of the path touches the contour (the edge of
        // what the tool may reach is R from the nearest element), within 1 µm: the
        // intersection of two nearly collinear equidistants is found to some 10 nm.
        for q in &path {
            for t in [0.0, 0.5, 1.0] {
                let far = dist_to(q.at(t), &case.pieces);
                assert!(
                    far <= case.r + 1e-3,
                    "case {k}: the path at {:?} is {far} from the contour, R = {}\n{}",
                    q.at(t),
                    case.r,
                    case.program
                );
            }
        }
    }
    assert!(alarms < n, "{alarms} alarms in {n} cases");
}

/// Whether the test's own offset clears the contour: by R with a margin from the elements it
/// does not belong to, and by R less rounding from its neighbours too (an arc can curl back
/// over the element before it).
fn clears(offset: &[(Piece, usize, usize)], case: &Case) -> bool {
    clearance(offset, &case.pieces, false) >= case.r + 1e-6
        && clearance(offset, &case.pieces, true) >= case.r - 1e-7
}

/// (B) with arcs: contours whose corners are all outer or tangent, offset by the test.
#[test]
fn gouge_free_outer_contours_with_arcs_pass_without_an_alarm() {
    let md = machine();
    let mut rng = Rng(0xa4093822299f31d0);
    let (mut clear, mut checked) = (0, 0);
    for k in 0..CASES / 2 {
        let case = make_case(&mut rng, false);
        if case.pieces.is_empty() || case.pieces.iter().all(|p| matches!(p, Piece::Seg(..))) {
            continue;
        }
        let Some(offset) = offset_outer(&case) else {
            continue;
        };
        checked += 1;
        if !clears(&offset, &case) {
            continue;
        }
        clear += 1;
        let (_, alarm) = softnc_pieces(&case, &md);
        assert!(
            !alarm,
            "case {k}: the full offset clears the contour, softnc raised an alarm (R = {})\n{}",
            case.r, case.program
        );
    }
    assert!(clear > 100, "{clear} of {checked} gouge-free");
}

/// (C) with arcs and inner corners: the test trims the equidistants itself (line/circle and
/// circle/circle intersections), and a contour whose full offset clears it passes.
#[test]
fn gouge_free_contours_with_arcs_and_inner_corners_pass_without_an_alarm() {
    let md = machine();
    let mut rng = Rng(0x082efa98ec4e6c89);
    let (mut clear, mut checked, mut inner_arcs) = (0, 0, 0);
    for k in 0..CASES / 2 {
        let case = make_case(&mut rng, false);
        if case.pieces.iter().all(|p| matches!(p, Piece::Seg(..))) {
            continue;
        }
        let Some(offset) = offset_general(&case) else {
            continue;
        };
        checked += 1;
        if !clears(&offset, &case) {
            continue;
        }
        clear += 1;
        // An inner corner next to an arc: what (B) and the polylines leave out.
        let side = if case.left { 1.0 } else { -1.0 };
        inner_arcs += usize::from(case.pieces.windows(2).any(|w| {
            let arc = matches!(w[0], Piece::Arc { .. }) || matches!(w[1], Piece::Arc { .. });
            let (a, b, c) = (w[0].at(1.0 - 1e-6), w[0].at(1.0), w[1].at(1e-6));
            arc && cross(sub(b, a), sub(c, b)) * side > 1e-15
        }));
        let (_, alarm) = softnc_pieces(&case, &md);
        assert!(
            !alarm,
            "case {k}: the full offset clears the contour, softnc raised an alarm (R = {})\n{}",
            case.r, case.program
        );
    }
    assert!(
        clear > 100 && inner_arcs > 100,
        "{clear} of {checked} gouge-free, {inner_arcs} with an inner corner at an arc"
    );
}

/// The contour as a cavalier_contours polyline (arcs as bulges: every generated arc is under
/// a half turn).
fn cavalier_polyline(case: &Case) -> cavalier_contours::polyline::Polyline<f64> {
    use cavalier_contours::polyline::{PlineSourceMut, Polyline};
    let mut pl = Polyline::new();
    for p in &case.pieces {
        match *p {
            Piece::Seg(a, _) => pl.add(a[0], a[1], 0.0),
            Piece::Arc { sw, .. } => {
                let a = p.at(0.0);
                pl.add(a[0], a[1], (sw / 4.0).tan());
            }
        }
    }
    if let Some(last) = case.pieces.last() {
        let e = last.at(1.0);
        pl.add(e[0], e[1], 0.0);
    }
    pl
}

/// cavalier's offset of the case's contour on the tool side, as pieces, where it is one
/// polyline (`None` for an empty contour or an offset in several pieces).
fn cavalier_offset(case: &Case) -> Option<Vec<Piece>> {
    use cavalier_contours::polyline::PlineSource;
    if case.pieces.is_empty() {
        return None;
    }
    let cav = cavalier_polyline(case).parallel_offset(if case.left { case.r } else { -case.r });
    match cav.as_slice() {
        [one] => Some(cavalier_pieces(one)),
        _ => None,
    }
}

/// cavalier's offset as pieces.
fn cavalier_pieces(pl: &cavalier_contours::polyline::Polyline<f64>) -> Vec<Piece> {
    use cavalier_contours::polyline::PlineSource;
    let mut out = Vec::new();
    for i in 0..pl.vertex_count().saturating_sub(1) {
        let (v, w) = (pl.at(i), pl.at(i + 1));
        let (a, b) = ([v.x, v.y], [w.x, w.y]);
        if v.bulge == 0.0 {
            out.push(Piece::Seg(a, b));
        } else {
            // Bulge b = tan(sweep/4): the centre from the chord.
            let sw = 4.0 * v.bulge.atan();
            let chord = norm(sub(b, a));
            let r = chord / (2.0 * (sw / 2.0).sin().abs());
            let m = mul(add(a, b), 0.5);
            let d = mul(sub(b, a), 1.0 / chord);
            // Centre left of the chord for a ccw arc under a half turn.
            let h = (r * r - chord * chord / 4.0).max(0.0).sqrt() * sw.signum();
            let c = add(m, mul([-d[1], d[0]], h));
            let a0 = (a[1] - c[1]).atan2(a[0] - c[0]);
            out.push(Piece::Arc { c, r, a0, sw });
        }
    }
    out
}

/// Whether an offset path visits the contour in program order, as masking can: it leaves
/// blocks out and joins later ones, never goes back to an earlier block. Each piece touches
/// the contour (is R from it, at its midpoint, within cavalier's 1e-5 mm) at a place along
/// it: element k at its nearest point t (0 to 1) is k + t, so a vertex is one place, the end
/// of one element and the start of the next. Some choice of these places must never
/// decrease. cavalier offsets the contour as a whole: where the contour crosses itself its
/// path may go round a later part first, and round a tiny element it may turn about the
/// element's end before its start, which no control that runs the blocks in order can do.
fn in_program_order(path: &[Piece], contour: &[Piece], r: f64) -> bool {
    let mut at = 0.0;
    for p in path {
        let m = p.at(0.5);
        let place = (0..contour.len())
            .filter_map(|k| {
                let (d, t) = nearest(m, &contour[k]);
                ((d - r).abs() <= 1e-5).then_some(k as f64 + t)
            })
            .filter(|&x| x >= at - 1e-9)
            .min_by(f64::total_cmp);
        let Some(x) = place else {
            return false;
        };
        at = x;
    }
    true
}

/// (D) Masking against an independent oracle: where cavalier_contours' offset (which trims
/// what comes closer than R, globally) is one piece from the first normal position to the
/// last, clears the contour and visits its blocks in program order, a gouge-free masked path
/// exists, and softnc with ISG masking (G141, G26 transition circles, a 64-block window) must
/// prepare the contour without an alarm and without a gouge.
///
/// Both are checked in full on all 10^5 contours (docs/trc.md, "Masking: how the path joins,
/// and known gaps"): none of the 70 513 with a masked path ends in an alarm; 12 more contours
/// have an oracle path out of program order, and each of them crosses itself (asserted).
/// History of the alarms on the first 10 000 contours (7 108, then 7 107 with a path): 1 344
/// at first; 974 after joins past backward runs of lines and arcs, circles smaller than the
/// tool and corners whose equidistants do not meet; 37 after a line was lengthened past a
/// step shorter than its trim; 17 after segments inside a backward run's loop were left out
/// with it, backward arcs joined along their circles and blocks on one line counted as one
/// element; 6 after a backward segment could be bridged between two joints; 5 after a
/// crossing whose cut comes too close gave way to a clear joint; 4 after a left-out
/// transition circle could be cut short by a joint; 1 after a joint's new segment had to
/// clear only the elements before its own block; 0 once the oracle's paths that go round a
/// later part of a self-crossing contour first were no longer counted (one contour there).
/// On all 10^5 (70 514 with a path): 13, then 11 (the rule before last); 6 after a joint into
/// a segment that follows a backward run became a bridge; 2 after a backward arc at the end
/// joined the retract along its circle; 1 after the segment after a gap could be bridged; 0
/// once a path that turns about a tiny element's end before its start (on a contour that
/// crosses itself there) counted as out of program order.
#[test]
fn masking_cuts_without_an_alarm_where_a_gouge_free_path_exists() {
    let md = isg_masking();
    let mut rng = Rng(0x452821e638d01377);
    let (mut exists, mut masked) = (0, 0);
    let (mut alarms, mut gouges, mut out_of_order) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..CASES {
        let case = make_case(&mut rng, k % 2 == 0);
        let Some(pieces) = cavalier_offset(&case) else {
            continue;
        };
        // Both ends kept: the path runs from the first normal position to the last.
        let side = if case.left { 1.0 } else { -1.0 };
        let normal_at = |p: &Piece, at_end: bool| {
            let (q, t) = (p.at(if at_end { 1.0 } else { 0.0 }), p.tangent(at_end));
            add(q, mul([-t[1], t[0]], side * case.r))
        };
        let (first, last) = (&case.pieces[0], &case.pieces[case.pieces.len() - 1]);
        let (Some(s), Some(e)) = (pieces.first(), pieces.last()) else {
            continue;
        };
        if norm(sub(s.at(0.0), normal_at(first, false))) > 1e-6
            || norm(sub(e.at(1.0), normal_at(last, true))) > 1e-6
        {
            continue;
        }
        // Clear at this test's precision, with a margin for cavalier's own 1e-5 fuzz.
        if min_dist(&pieces, &case.pieces) < case.r - 1e-7 {
            continue;
        }
        if !in_program_order(&pieces, &case.pieces, case.r) {
            // Only a contour that crosses itself can make cavalier go round a later part
            // first (or round a vertex early).
            let n = case.pieces.len();
            assert!(
                (0..n).any(|i| (i + 2..n).any(|j| crosses(&case.pieces[i], &case.pieces[j]))),
                "case {k}: the oracle's path is out of program order on a contour that does \
                 not cross itself\n{}",
                case.program
            );
            out_of_order.push(k);
            continue;
        }
        exists += 1;
        let full = offset_general(&case)
            .is_some_and(|o| clearance(&o, &case.pieces, false) >= case.r + 1e-6);
        masked += usize::from(!full);
        let case = with_masking(&case);
        let (path, alarm) = softnc_pieces(&case, &md);
        let d = min_dist(&path, &case.pieces);
        if d < case.r - 1e-9 {
            gouges.push(format!(
                "case {k}: distance {d}, R = {}\n{}",
                case.r, case.program
            ));
        }
        if alarm {
            alarms.push(format!("case {k}: R = {}\n{}", case.r, case.program));
        }
    }
    assert!(
        gouges.is_empty(),
        "{} of {exists} gouge; the first:\n{}",
        gouges.len(),
        gouges[0]
    );
    // Contour 3496 crosses itself (a later line runs across line 4): cavalier's path goes
    // round the later blocks 8 and 9 before block 5, and no path in program order exists
    // (docs/trc.md). 71243 has a spike of two lines and an arc of radius 0.38 whose lines
    // cross: cavalier's path turns about the arc's end before its start.
    assert_eq!(out_of_order.len(), 12, "{out_of_order:?}");
    assert!(out_of_order.contains(&3496) && out_of_order.contains(&71243));
    assert_eq!(exists, 70_513);
    assert!(
        alarms.is_empty(),
        "{} of {exists} raise an alarm; the first:\n{}",
        alarms.len(),
        alarms[0]
    );
    assert!(
        exists > 1000 && masked > 50,
        "{exists} with a path, {masked} of them masked"
    );
}

/// (D′) Where softnc's masking does get through, its path is the oracle's: every end and
/// midpoint of a softnc piece lies on cavalier's offset and every vertex and segment midpoint
/// of cavalier's lies on softnc's path, within cavalier's own 1e-5 mm, on all 10^5 contours.
/// Known exceptions (docs/trc.md): 41 of the 70 581 compared paths, 10 to 23 nm apart (on
/// the first 10 000 contours 3 of 7 114; 20 of 6 140, up to 10.5 mm apart, before the
/// window's joints had to touch the contour). The count is pinned, and none may be more than
/// 30 nm apart: more is a regression, fewer an improvement to write down here.
#[test]
fn masked_paths_follow_the_oracle() {
    let md = isg_masking();
    let mut rng = Rng(0x452821e638d01377);
    let (mut compared, mut differ) = (0, Vec::new());
    for k in 0..CASES {
        let case = make_case(&mut rng, k % 2 == 0);
        let Some(oracle) = cavalier_offset(&case) else {
            continue;
        };
        if min_dist(&oracle, &case.pieces) < case.r - 1e-7 {
            continue;
        }
        let masked = with_masking(&case);
        let (path, alarm) = softnc_pieces(&masked, &md);
        if alarm || path.is_empty() {
            continue;
        }
        let mut worst: (f64, P) = (0.0, [0.0; 2]);
        for (from, to) in [(&path, &oracle), (&oracle, &path)] {
            for q in from {
                for t in [0.0, 0.5, 1.0] {
                    let (p, d) = (q.at(t), dist_to(q.at(t), to));
                    if d > worst.0 {
                        worst = (d, p);
                    }
                }
            }
        }
        // The oracle's ends are the first and last normal positions; softnc's path between
        // the selection and deselection starts and ends there too.
        if worst.0 > 1e-5 {
            differ.push((
                worst.0,
                format!("case {k}: {:.6} mm apart at {:?}", worst.0, worst.1),
            ));
        }
        compared += 1;
    }
    let list = differ
        .iter()
        .map(|d| d.1.as_str())
        .collect::<Vec<_>>()
        .join("\n");
    assert_eq!(compared, 70_581);
    assert!(
        differ.len() <= 41 && differ.iter().all(|d| d.0 <= 3e-5),
        "{} of {compared} differ:\n{list}",
        differ.len(),
    );
}

#[test]
fn gouge_free_polylines_pass_without_an_alarm() {
    let md = machine();
    let mut rng = Rng(0x243f6a8885a308d3);
    let (mut clear, mut checked) = (0, 0);
    for k in 0..CASES / 4 {
        let case = make_case(&mut rng, true);
        if case.pieces.is_empty() {
            continue;
        }
        let Some(offset) = offset_polyline(&case) else {
            continue;
        };
        checked += 1;
        // Clear of every element it is not built on, with a margin either way.
        let far = clearance(&offset, &case.pieces, false);
        if far < case.r + 1e-6 {
            continue;
        }
        clear += 1;
        let (_, alarm) = softnc_pieces(&case, &md);
        assert!(
            !alarm,
            "case {k}: the full offset clears the contour, softnc raised an alarm (R = {})\n{}",
            case.r, case.program
        );
    }
    assert!(clear > checked / 10, "{clear} of {checked} gouge-free");
}
