//! The lathe samples with roughing and finishing cycles (docs/turning.md, "Sample
//! programs"): the moves the cycles expand into are drawn by `softnc path --format svg`,
//! listed by `softnc path`, checked by `softnc check` and run by `softnc run`.
//!
//! Every expectation is worked out here from the programs' words (X a radius, (Z, X) in the
//! turning plane); the pictures are read back through their own grid labels.

#[path = "support/control.rs"]
mod control;

use control::*;
use std::path::Path;
use std::process::Command;

const FANUC_SHAFT: &str = "programs/fanuc-lathe/shaft_rough_finish.nc";
const FANUC_LATHE: &str = "config/fanuc-lathe.toml";
const CYCLE95_SHAFT: &str = "programs/siemens-808d/shaft_cycle95.mpf";
const SIEMENS_LATHE: &str = "config/siemens-808d.toml";

/// Drawn positions against hand-computed ones, mm. The picture writes its pixels as f32 and
/// its grid labels to 0.01 px (about 0.001 mm at these scales); the wrong tool point (nose
/// centre instead of tip) or a pass cut to the wrong shape is off by 0.2 mm and more.
const TOL: f64 = 0.005;

/// A point in the turning plane: (Z, X), X a radius.
type Zx = (f64, f64);

fn near(a: Zx, b: Zx) -> bool {
    (a.0 - b.0).abs() < TOL && (a.1 - b.1).abs() < TOL
}

// --- The Fanuc shaft: G71 roughing, G70 finishing ---------------------------------------

/// shaft_rough_finish.nc roughs with T0201 (tool 2, offset 1: config/tools.toml's T2 D1,
/// nose R 1.2, position 3) and finishes with T0101 (T1 D1, R 0.8, position 3).
const FANUC_ROUGH_R: f64 = 1.2;
const FANUC_FINISH_R: f64 = 0.8;

/// The G71 passes: (level, end Z), each cut along Z from the start point's Z 2.
///
/// `G0 X44. Z2.` puts the start point A at (Z 2, X 22); `G71 U2. R0.5` cuts 2 deep and
/// lifts 0.5; `G71 P100 Q200 U0.4 W0.1` moves the shape by (W, U/2) = (0.1, 0.2). The shape
/// N100 … N200 has G42, so the cycle roughs the tool tip's path of the compensated shape:
/// the nose centre S at R on the right of travel, the tip P = S + (−R, −R) in (Z, X). That
/// puts P on the shape's diameters and faces themselves, with corners rounded (convex) or
/// trimmed (concave). A' is N100's X12: tip X 6, moved 6.2. So the levels are 22 − 2k
/// strictly above 6.2: 20, 18, 16, 14, 12, 10, 8. Each ends where it first meets the moved
/// tip path walking from A':
/// - 8: past the chamfer's tip line (it ends at X 8 + 0.2 + R(1/√2 − 1) = 7.85), on the
///   convex corner at (Z −2, X 8): P circles (Z −2 − R, X 8 − R) + (0.1, 0.2) = (−3.1, 7.0)
///   at radius R, so Z = −3.1 + √(R² − (8 − 7)²).
/// - 10: the face at Z −20 (the tip on it), moved −19.9; it runs up to X 11 − R + 0.2 = 10.
/// - 12: the taper to X26 Z−30 (1 up in X per 5 along −Z); its tip line passes through
///   (−20, 11) + R((1, 5)/√26 − (1, 1)) + (0.1, 0.2).
/// - 14, 16: the concave R4 fillet (G2 from Z −45 X13 to Z −49 X17: centre Z −45 X17); the
///   tip circles (−45 − R, 17 − R) + (0.1, 0.2) = (−46.1, 16) at 4 − R = 2.8, so
///   Z = −46.1 − √(2.8² − (x − 16)²).
/// - 18: the face at Z −49, moved −48.9, up to X 19 − R + 0.2 = 18.
/// - 20: the G40 ramp from the last tip (Z −70 − R, X 19) to N200's (Z −70, X 22), moved to
///   (−71.1, 19.2) … (−69.9, 22.2): Z = −71.1 + R · (20 − 19.2)/3 = −70.78.
fn fanuc_passes() -> Vec<(f64, f64)> {
    let r = FANUC_ROUGH_R;
    let s26 = 26f64.sqrt();
    let (z0, x0) = (
        -20.0 + r * (1.0 / s26 - 1.0) + 0.1,
        11.0 + r * (5.0 / s26 - 1.0) + 0.2,
    );
    let (fz, fx) = (-45.0 - r + 0.1, 17.0 - r + 0.2);
    let fillet = |x: f64| fz - ((4.0 - r).powi(2) - (x - fx).powi(2)).sqrt();
    let (cz, cx) = (-2.0 - r + 0.1, 8.0 - r + 0.2);
    vec![
        (20.0, -70.0 - r + 0.1 + r * (20.0 - 19.2) / 3.0),
        (18.0, -48.9),
        (16.0, fillet(16.0)),
        (14.0, fillet(14.0)),
        (12.0, z0 - 5.0 * (12.0 - x0)),
        (10.0, -19.9),
        (8.0, cz + (r * r - (8.0 - cx).powi(2)).sqrt()),
    ]
}

/// The last roughing cut runs along the moved tip path from A'; its diameters: Ø16 from the
/// convex corner at Z −2 (−2 − R + 0.1) to the concave one at Z −20 (−19.9), Ø26 from the
/// taper's corner (−30 − R + 0.1) to the fillet (−45 − R + 0.1), Ø38 from the face's corner
/// (−49 − R + 0.1) to the ramp (−70 − R + 0.1); each 0.2 above the diameter.
fn fanuc_rough_run() -> Vec<(Zx, Zx)> {
    let r = FANUC_ROUGH_R;
    vec![
        ((-2.0 - r + 0.1, 8.2), (-19.9, 8.2)),
        ((-30.0 - r + 0.1, 13.2), (-45.0 - r + 0.1, 13.2)),
        ((-49.0 - r + 0.1, 19.2), (-70.0 - r + 0.1, 19.2)),
    ]
}

/// G70 with T0101 under G42 (R 0.8, position 3): the tip on the diameters and faces as
/// programmed, each from where the corner before it lets go: Ø16 from Z −2 − R, the face at
/// Z −20 up to X 11 − R, Ø26 from Z −30 − R to the fillet at −45 − R, the face at Z −49 from
/// the fillet's X 17 − R to 19 − R, Ø38 from −49 − R to −70 − R.
fn fanuc_finish_lines() -> Vec<(Zx, Zx)> {
    let r = FANUC_FINISH_R;
    vec![
        ((-2.0 - r, 8.0), (-20.0, 8.0)),
        ((-20.0, 8.0), (-20.0, 11.0 - r)),
        ((-30.0 - r, 13.0), (-45.0 - r, 13.0)),
        ((-49.0, 17.0 - r), (-49.0, 19.0 - r)),
        ((-49.0 - r, 19.0), (-70.0 - r, 19.0)),
    ]
}

/// G70's fillet: the tip circle at 4 − R about (−45 − R, 17 − R), from the Ø26 to the face,
/// clockwise (G2).
fn fanuc_finish_fillet() -> (Zx, Zx, f64) {
    let r = FANUC_FINISH_R;
    ((-45.0 - r, 13.0), (-49.0, 17.0 - r), 4.0 - r)
}

// --- The 808D shaft: CYCLE95 roughing (VARI 1), CYCLE95 finishing (VARI 5) --------------

/// T1 D1 roughs (R 0.8, position 3), T2 D1 finishes (R 1.2, position 3).
const C95_ROUGH_R: f64 = 0.8;
const C95_FINISH_R: f64 = 1.2;

/// The contour CONTOUR_A … CONTOUR_E in (Z, X radius): A' (0, 7), the 45° chamfer to
/// (−3, 10), Ø20 to −18, the taper to (−28, 13), Ø26 to the RND=4 fillet (tangent at Z −36,
/// centre (−36, 17), onto the face at X 17), the face at Z −40 to the CHF=1.414 chamfer (legs
/// 1.414/√2 = 0.99985 each: from X 20 − leg to Z −40 − leg), Ø40 to −55, the face up to X 26.
fn chf_leg() -> f64 {
    1.414 / 2f64.sqrt()
}

/// `CYCLE95("CONTOUR_A:CONTOUR_E", 2, 0.1, 0.2, , 0.25, 0.15, 0.1, 1, , , 0.5)`: MID 2,
/// FALZ 0.1, FALX 0.2 (a radius), VARI 1, _VRT 0.5. The cycle roughs its own tip path (G42,
/// R 0.8, P = S + (−R, −R)) moved by (FALZ, FALX) = (+0.1, +0.2).
/// - A' tip: the chamfer's normal is (1, 1)/√2, so P = (0, 7) + R(1/√2 − 1)(1, 1), moved:
///   (0.1 + d, 7.2 + d) with d = R(1/√2 − 1).
/// - S: X the moved tip path's largest, the last face's end 26 − R + 0.2 = 25.4; Z A' + 0.5.
/// - Stock 25.4 − (7.2 + d) = 18.434 in ⌈18.434/2⌉ = 10 equal cuts of 1.8434; the first
///   nine are passes from S's Z, the tenth the run along the contour.
///
/// Returns S and the passes (level, end Z). Each ends where its level first meets the moved
/// tip path from A':
/// - on the first chamfer's tip line (X = 7.2 + d + (0.1 + d − Z)) for X below its end
///   10.2 + d;
/// - on the taper's tip line, through (−18, 10) + R((3, 10)/√109 − (1, 1)) + (0.1, 0.2),
///   0.3 up in X per 1 along −Z;
/// - on the fillet's tip circle, radius 4 − R = 3.2 about (−36 − R + 0.1, 17 − R + 0.2) =
///   (−36.7, 16.4), Z = −36.7 − √(3.2² − (x − 16.4)²), for X up to 16.4;
/// - on the face at Z −40 (tip on it) moved −39.9, up to X 20 − leg − R + 0.2;
/// - on the second chamfer's tip line, from (−40 + d + 0.1, 20 − leg + d + 0.2) 1:1 outwards;
/// - above Ø40 + R-corner (X 20.2), on the last face: Z −55 + 0.1.
fn cycle95_passes() -> (Zx, Vec<(f64, f64)>) {
    let r = C95_ROUGH_R;
    let d = r * (0.5f64.sqrt() - 1.0);
    let a = (0.1 + d, 7.2 + d);
    let s = (a.0 + 0.5, 26.0 - r + 0.2);
    let depth = (s.1 - a.1) / 10.0;
    let s109 = 109f64.sqrt();
    let taper = (
        -18.0 + r * (3.0 / s109 - 1.0) + 0.1,
        10.0 + r * (10.0 / s109 - 1.0) + 0.2,
    );
    let leg = chf_leg();
    let chamfer2 = (-40.0 + d + 0.1, 20.0 - leg + d + 0.2);
    let fillet = (-36.0 - r + 0.1, 17.0 - r + 0.2);
    // Each stretch of the moved tip path a level can meet, by its X range; the corners'
    // arcs between them hold no level of this program.
    let end = |x: f64| -> f64 {
        if x <= 10.2 + d {
            a.0 - (x - a.1)
        } else if (10.2..=taper.1 + 3.0).contains(&x) {
            taper.0 - (x - taper.1) / 0.3
        } else if (13.2..=fillet.1).contains(&x) {
            fillet.0 - ((4.0 - r).powi(2) - (x - fillet.1).powi(2)).sqrt()
        } else if (fillet.1..=20.0 - leg - r + 0.2).contains(&x) {
            -40.0 + 0.1
        } else if (chamfer2.1..=chamfer2.1 + leg).contains(&x) {
            chamfer2.0 - (x - chamfer2.1)
        } else if x >= 20.2 {
            -55.0 + 0.1
        } else {
            panic!("level X{x} lies on a corner's arc: not worked out here")
        }
    };
    let passes = (1..10)
        .map(|k| {
            let level = s.1 - k as f64 * depth;
            (level, end(level))
        })
        .collect();
    (s, passes)
}

/// The run along the moved contour (the tenth cut): Ø26 from the taper's convex corner
/// (−28 − R + 0.1) to the fillet (−36 − R + 0.1), Ø40 from the chamfer's convex corner
/// (−40 − leg − R + 0.1) to the last face (−55 + 0.1); each 0.2 above the diameter.
fn cycle95_rough_run() -> Vec<(Zx, Zx)> {
    let r = C95_ROUGH_R;
    vec![
        ((-28.0 - r + 0.1, 13.2), (-36.0 - r + 0.1, 13.2)),
        ((-40.0 - chf_leg() - r + 0.1, 20.2), (-54.9, 20.2)),
    ]
}

/// The finishing (VARI 5, T2 D1 R 1.2, the cycle's G42): the tip on the contour's diameters
/// and faces. Ø20 from the chamfer's convex corner (−3 − R) to the concave corner with the
/// taper, where the nose centre's line X 10 + R meets the taper's offset line (−18, 10) +
/// R(3, 10)/√109 + t(−10, 3): t = R(1 − 10/√109)/3, Z = −18 + 3R/√109 − 10t, less R. Ø26
/// from −28 − R to the fillet (−36 − R), the face at Z −40 from 17 − R to 20 − leg − R, Ø40
/// from −40 − leg − R to −55, the last face at Z −55 from X 20 to 26 − R.
fn cycle95_finish_lines() -> Vec<(Zx, Zx)> {
    let r = C95_FINISH_R;
    let s109 = 109f64.sqrt();
    let t = r * (1.0 - 10.0 / s109) / 3.0;
    let corner = -18.0 + 3.0 * r / s109 - 10.0 * t - r;
    let leg = chf_leg();
    vec![
        ((-3.0 - r, 10.0), (corner, 10.0)),
        ((-28.0 - r, 13.0), (-36.0 - r, 13.0)),
        ((-40.0, 17.0 - r), (-40.0, 20.0 - leg - r)),
        ((-40.0 - leg - r, 20.0), (-55.0, 20.0)),
        ((-55.0, 20.0), (-55.0, 26.0 - r)),
    ]
}

/// The finishing's fillet: the tip circle at 4 − R about (−36 − R, 17 − R), clockwise.
fn cycle95_finish_fillet() -> (Zx, Zx, f64) {
    let r = C95_FINISH_R;
    ((-36.0 - r, 13.0), (-40.0, 17.0 - r), 4.0 - r)
}

// --- Reading the picture -----------------------------------------------------------------

/// One piece of the drawn tool path, in world (Z, X).
#[derive(Debug)]
struct Piece {
    class: String,
    rapid: bool,
    from: Zx,
    to: Zx,
    /// An arc's radius (mm) and whether it turns clockwise with X up; `None` for a line.
    arc: Option<(f64, bool)>,
}

fn group<'a>(doc: &'a roxmltree::Document, id: &str) -> Option<roxmltree::Node<'a, 'a>> {
    doc.descendants().find(|n| n.attribute("id") == Some(id))
}

fn attr(n: roxmltree::Node, name: &str) -> f64 {
    n.attribute(name)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("attribute {name} on {:?}", n.tag_name()))
}

/// The linear map pixel → world along one axis, from its first and last grid label.
fn axis(labels: &[(f64, f64)]) -> impl Fn(f64) -> f64 {
    assert!(labels.len() >= 2, "at least two grid labels per axis");
    let (p0, w0) = labels[0];
    let (p1, w1) = labels[labels.len() - 1];
    let k = (w1 - w0) / (p1 - p0);
    move |p| w0 + (p - p0) * k
}

/// The SVG path data as commands with their numbers (`M x,y L x,y A rx,ry,rot,large,sweep,x,y`).
fn commands(d: &str) -> Vec<(char, Vec<f64>)> {
    let mut out: Vec<(char, String)> = Vec::new();
    for c in d.chars() {
        if c.is_ascii_alphabetic() {
            out.push((c, String::new()));
        } else if let Some((_, s)) = out.last_mut() {
            s.push(c);
        }
    }
    out.into_iter()
        .map(|(c, s)| {
            let nums = s
                .split([',', ' '])
                .filter(|t| !t.is_empty())
                .map(|t| t.parse().unwrap_or_else(|_| panic!("number {t} in {d}")))
                .collect();
            (c, nums)
        })
        .collect()
}

/// The tool path as drawn, mapped back to world coordinates through the grid's labels
/// (abscissa Z centred under its lines, ordinate X right-aligned 3.5 px below its line).
fn drawn_path(svg: &str) -> Vec<Piece> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    let grid = group(&doc, "grid").expect("grid");
    let (mut zs, mut xs) = (Vec::new(), Vec::new());
    for t in grid.children().filter(|n| n.has_tag_name("text")) {
        let Ok(value) = t.text().unwrap_or("").trim().parse::<f64>() else {
            continue;
        };
        match t.attribute("text-anchor") {
            Some("middle") => zs.push((attr(t, "x"), value)),
            Some("end") => xs.push((attr(t, "y") - 3.5, value)),
            _ => {}
        }
    }
    let (to_z, to_x) = (axis(&zs), axis(&xs));
    let at = |p: &[f64]| (to_z(p[0]), to_x(p[1]));
    // mm per px, for the arcs' radii (the same scale on both axes).
    let mm = to_z(1.0) - to_z(0.0);
    let mut pieces = Vec::new();
    for p in group(&doc, "tool-path")
        .expect("tool path")
        .children()
        .filter(|n| n.has_tag_name("path"))
    {
        let class = p.attribute("class").unwrap_or("").to_string();
        let rapid = p.attribute("stroke-dasharray").is_some();
        let mut last: Option<Zx> = None;
        for (c, n) in commands(p.attribute("d").unwrap_or("")) {
            let (to, arc) = match c {
                'M' => {
                    last = Some(at(&n));
                    continue;
                }
                'L' => (at(&n), None),
                // rx, ry, rotation, large arc, sweep, x, y. With X drawn up the screen's y
                // points down: sweep 1 is clockwise in the plane.
                'A' => (at(&n[5..7]), Some((n[0] * mm, n[4] == 1.0))),
                _ => panic!("path command {c}"),
            };
            let from = last.expect("a path starts with M");
            pieces.push(Piece {
                class: class.clone(),
                rapid,
                from,
                to,
                arc,
            });
            last = Some(to);
        }
    }
    pieces
}

/// The cuts along Z at feed that start at `z0`, as (level, end Z), deepest cut last.
fn cuts_from(pieces: &[Piece], z0: f64) -> Vec<(f64, f64)> {
    let mut cuts: Vec<(f64, f64)> = pieces
        .iter()
        .filter(|p| !p.rapid && p.arc.is_none())
        .filter(|p| (p.from.1 - p.to.1).abs() < TOL && (p.from.0 - z0).abs() < TOL)
        .map(|p| (p.from.1, p.to.0))
        .collect();
    cuts.sort_by(|a, b| b.0.total_cmp(&a.0));
    cuts
}

fn assert_cuts(what: &str, got: &[(f64, f64)], want: &[(f64, f64)]) {
    assert_eq!(
        got.len(),
        want.len(),
        "{what}: drawn {got:?}, by hand {want:?}"
    );
    for (g, w) in got.iter().zip(want) {
        assert!(near(*g, *w), "{what}: drawn {got:?}, by hand {want:?}");
    }
}

/// A line at feed from `from` to `to` of the given class is drawn.
fn assert_line(pieces: &[Piece], class: &str, (from, to): (Zx, Zx)) {
    assert!(
        pieces.iter().any(|p| !p.rapid
            && p.arc.is_none()
            && p.class == class
            && near(p.from, from)
            && near(p.to, to)),
        "no {class} line drawn from {from:?} to {to:?}"
    );
}

/// A clockwise arc at feed of the given class and radius is drawn from `from` to `to`.
fn assert_cw_arc(pieces: &[Piece], class: &str, (from, to, r): (Zx, Zx, f64)) {
    assert!(
        pieces.iter().any(|p| !p.rapid
            && p.class == class
            && near(p.from, from)
            && near(p.to, to)
            && p.arc.is_some_and(|(pr, cw)| cw && (pr - r).abs() < TOL)),
        "no clockwise {class} arc R{r} drawn from {from:?} to {to:?}"
    );
}

/// The Fanuc shaft's picture shows the seven G71 passes, G71's run along the moved shape
/// and G70's compensated finishing.
fn assert_fanuc_shaft_drawn(svg: &str) {
    let pieces = drawn_path(svg);
    assert_cuts(
        "G71 passes from Z2",
        &cuts_from(&pieces, 2.0),
        &fanuc_passes(),
    );
    for run in fanuc_rough_run() {
        assert_line(&pieces, "uncompensated", run);
    }
    for line in fanuc_finish_lines() {
        assert_line(&pieces, "contour", line);
    }
    assert_cw_arc(&pieces, "contour", fanuc_finish_fillet());
}

fn svg_of(program: &str, machine: &str) -> String {
    let out = Command::new(EXE)
        .args(["path", program, "--machine", machine, "--format", "svg"])
        .current_dir(root())
        .output()
        .expect("softnc runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8 SVG")
}

#[test]
fn the_fanuc_shaft_picture_draws_every_g71_pass_and_the_g70_finishing() {
    assert_fanuc_shaft_drawn(&svg_of(FANUC_SHAFT, FANUC_LATHE));
}

#[test]
fn the_cycle95_shaft_picture_draws_every_roughing_pass_and_the_finishing() {
    let pieces = drawn_path(&svg_of(CYCLE95_SHAFT, SIEMENS_LATHE));
    let (s, passes) = cycle95_passes();
    assert_cuts(
        "CYCLE95 passes from S's Z",
        &cuts_from(&pieces, s.0),
        &passes,
    );
    for run in cycle95_rough_run() {
        assert_line(&pieces, "uncompensated", run);
    }
    for line in cycle95_finish_lines() {
        assert_line(&pieces, "contour", line);
    }
    assert_cw_arc(&pieces, "contour", cycle95_finish_fillet());
}

// --- softnc path and softnc check on the CYCLE95 sample ----------------------------------

/// The cuts along Z at feed without compensation, in `softnc path`'s order: (level, start
/// Z, end Z) and where the rapid after the cut goes, if one follows.
type Cut = ((f64, f64, f64), Option<Zx>);

fn path_cuts(jsonl: &str) -> Vec<Cut> {
    let records: Vec<serde_json::Value> = jsonl
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect();
    let zx = |v: &serde_json::Value| (v[2].as_f64().unwrap(), v[0].as_f64().unwrap());
    let moves: Vec<&serde_json::Value> = records
        .iter()
        .filter(|r| r["type"] == "line" || r["type"] == "arc")
        .collect();
    let mut out = Vec::new();
    for (k, m) in moves.iter().enumerate() {
        let (from, to) = (zx(&m["from"]), zx(&m["to"]));
        let along_z = m["type"] == "line" && from.1 == to.1 && from.0 != to.0;
        if along_z && m["rapid"] == false && m["role"] == "uncompensated" {
            let rapid_after = moves
                .get(k + 1)
                .filter(|n| n["rapid"] == true && zx(&n["from"]) == to)
                .map(|n| zx(&n["to"]));
            out.push(((from.1, from.0, to.0), rapid_after));
        }
    }
    out
}

#[test]
fn softnc_check_passes_the_cycle95_shaft_and_softnc_path_lists_its_passes() {
    let check = Command::new(EXE)
        .args(["check", CYCLE95_SHAFT, "--machine", SIEMENS_LATHE])
        .current_dir(root())
        .output()
        .expect("softnc runs");
    let said = String::from_utf8_lossy(&check.stdout);
    assert_eq!(
        check.status.code(),
        Some(0),
        "{said}{}",
        String::from_utf8_lossy(&check.stderr)
    );
    assert!(
        said.contains(": ok: ") && said.contains(" 0 alarms"),
        "{said}"
    );

    let path = Command::new(EXE)
        .args(["path", CYCLE95_SHAFT, "--machine", SIEMENS_LATHE])
        .current_dir(root())
        .output()
        .expect("softnc runs");
    assert_eq!(path.status.code(), Some(0));
    let got = path_cuts(&String::from_utf8(path.stdout).unwrap());
    // The nine passes from S's Z, each lifted off by _VRT 0.5 at 45° (X up, Z back); then
    // the run along the moved contour cuts Ø20, Ø26 and Ø40 along Z. The finishing is
    // compensated by preparation (role contour), so nothing else is listed here.
    let (s, passes) = cycle95_passes();
    let n = passes.len();
    assert_eq!(got.len(), n + 3, "{got:?}");
    for (k, ((level, z0, z1), lift)) in got.iter().take(n).enumerate() {
        let (want_level, want_end) = passes[k];
        assert!(
            (level - want_level).abs() < 1e-9
                && (z0 - s.0).abs() < 1e-9
                && (z1 - want_end).abs() < 1e-9,
            "pass {}: X{level} Z{z0} → Z{z1}, by hand X{want_level} Z{} → Z{want_end}",
            k + 1,
            s.0
        );
        assert!(
            lift.is_some_and(|l| near(l, (want_end + 0.5, want_level + 0.5))),
            "pass {}: lift-off {lift:?}",
            k + 1
        );
    }
    for (want, ((level, z0, z1), _)) in cycle95_rough_run().iter().zip(&got[n + 1..]) {
        assert!(
            near((*z0, *level), want.0) && near((*z1, *level), want.1),
            "run along the contour: X{level} Z{z0} → Z{z1}, by hand {want:?}"
        );
    }
}

// --- softnc run ----------------------------------------------------------------------------

/// The Fanuc shaft on the control, nc-kernel and plc-sim over iceoryx2. It runs in real
/// time (`softnc run` has no time scale, and feed per revolution follows the programmed S:
/// 89 s of machine time at 100 %), so only this, the shorter of the two lathe samples, runs
/// end to end here, at the control's highest path override, 120 % (76 s): the path, its exact
/// stops at the pass ends and the picture are the same at any override.
#[test]
fn softnc_run_turns_the_fanuc_shaft_to_its_end_with_every_pass_in_the_picture() {
    let (tr, svg) = (scratch("lathe-shaft.csv"), scratch("lathe-shaft.svg"));
    let run = softnc_run(
        Path::new(FANUC_SHAFT),
        &instance("lathe-shaft"),
        &tr,
        &[
            "--machine",
            FANUC_LATHE,
            "--svg",
            svg.to_str().unwrap(),
            "--override",
            "120",
        ],
    );
    let said = run.said();
    assert!(run.success(), "{said}");
    assert!(run.stdout.contains("ran to its end"), "{said}");
    // The override acted from NC start: well under the 89 s of 100 %.
    let secs: f64 = run
        .stdout
        .split("ran to its end in ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no run time in {said}"));
    assert!((70.0..80.0).contains(&secs), "{secs} s: {said}");
    assert!(run.stdout.contains("setpoints: 0 lost"), "{said}");
    assert!(run.stdout.contains("shared memory files left: 0"), "{said}");

    // The program ends with G28 U0. W0.: at the reference point, X 60 (radius) Z 100.
    let rows = trace(&tr);
    let last = rows.last().expect("a trace");
    assert_eq!(last.state, "END");
    assert_eq!(last.sp, [60.0, 0.0, 100.0]);
    // The setpoints reach every pass's end: each pass ends in an exact stop there.
    for (level, end) in fanuc_passes() {
        assert!(
            rows.iter()
                .any(|r| (r.sp[0] - level).abs() < 1e-6 && (r.sp[2] - end).abs() < 1e-6),
            "no setpoint at the pass end X{level} Z{end}"
        );
    }

    let picture = std::fs::read_to_string(&svg).expect("the picture was written");
    assert_fanuc_shaft_drawn(&picture);
    let doc = roxmltree::Document::parse(&picture).unwrap();
    assert!(
        group(&doc, "actual-path").is_some(),
        "the axes' path is drawn"
    );
}
