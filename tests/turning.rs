//! Turning (issue 8): tool nose radius compensation with cutting edge positions, hand-computed.
//!
//! Lathe plane G18: Z abscissa, X ordinate; the tests program X as a radius (DIAMOF) unless
//! they say otherwise. A turning tool is measured at its theoretical tip P; the setpoints
//! address P. With TRC the nose centre S runs on the equidistant and P = S + v, where v for
//! cutting edge position k (840C, behind the centre of rotation, in (Z, X)) is
//! 1 (+R,+R) 2 (−R,+R) 3 (−R,−R) 4 (+R,−R) 5 (+R,0) 6 (0,+R) 7 (−R,0) 8 (0,−R) 9 (0,0).

use nc_kernel::{prepare, MachineData, ToolTable};
use nc_kernel::{Role, Segment, Shape};

const R: f64 = 0.8;

/// (Z, X) of a position.
fn zx(p: [f64; 3]) -> [f64; 2] {
    [p[2], p[0]]
}

fn v(edge: u8) -> [f64; 2] {
    match edge {
        1 => [R, R],
        2 => [-R, R],
        3 => [-R, -R],
        4 => [R, -R],
        5 => [R, 0.0],
        6 => [0.0, R],
        7 => [-R, 0.0],
        8 => [0.0, -R],
        _ => [0.0, 0.0],
    }
}

/// The shipped lathe machine data (config/siemens-808d.toml).
fn lathe() -> MachineData {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/config/siemens-808d.toml");
    MachineData::load(Some(std::path::Path::new(path)), &[]).unwrap()
}

fn run(program: &str, edge: u8) -> Vec<Segment> {
    let tools = ToolTable::from_toml_str(
        &format!("[[offset]]\nt = 1\nd = 1\nradius = {R}\nedge = {edge}\n"),
        "test",
    )
    .unwrap();
    prepare("turn", program, &lathe(), &tools).unwrap_or_else(|a| panic!("{a}"))
}

fn close(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
    (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
}

/// Outside diameter along −Z at X20 (radius), then a face up at Z−20 to X40, G42: the nose
/// centre runs at X 20.8 and Z −19.2, the inner corner at (−19.2, 20.8).
const OD_AND_FACE: &str = "N10 G18 G90 DIAMOF T1 D1 G0 X30 Z10\nN20 G42 G1 X20 Z5 F100\nN30 Z-20\nN40 X40\nN50 G40 G0 X50 Z10\nN60 M30\n";

#[test]
fn the_tip_is_the_nose_centre_plus_the_position_vector() {
    for edge in 1..=9u8 {
        let segs = run(OD_AND_FACE, edge);
        let contour: Vec<&Segment> = segs.iter().filter(|s| s.role == Role::Contour).collect();
        let w = v(edge);
        let corner = [-19.2 + w[0], 20.8 + w[1]];
        let (od, face) = (contour[0], contour[1]);
        assert!(close(zx(od.to), corner, 1e-12), "edge {edge}: {:?}", od.to);
        assert!(close(zx(face.from), corner, 1e-12), "edge {edge}");
        assert!(close(zx(face.to), [-19.2 + w[0], 40.0 + w[1]], 1e-12));
        // The OD runs at X = 20.8 + vx: on the contour (X 20) exactly when the tip is the
        // lowest point of the nose (positions 3, 4, 8); the face at Z = −19.2 + vz: on the
        // contour (Z −20) for the leftmost (2, 3, 7).
        let on_od = (zx(od.from)[1] - 20.0).abs() < 1e-12 && (zx(od.to)[1] - 20.0).abs() < 1e-12;
        assert_eq!(on_od, matches!(edge, 3 | 4 | 8), "edge {edge}");
        let on_face = (zx(face.from)[0] + 20.0).abs() < 1e-12;
        assert_eq!(on_face, matches!(edge, 2 | 3 | 7), "edge {edge}");
        // With TRC off (before the approach, after the retract) P is the programmed point.
        let first = segs.first().unwrap();
        assert!(close(zx(first.to), [10.0, 30.0], 0.0));
        let retract = segs.iter().find(|s| s.role == Role::Retract).unwrap();
        assert!(close(zx(retract.from), [-19.2 + w[0], 40.0 + w[1]], 1e-12));
        assert!(close(zx(retract.to), [10.0, 50.0], 0.0));
    }
}

/// A finishing profile with a taper, a convex and a concave radius (G42, position 3):
/// P − v = S keeps exactly R from every programmed element (the nose circle touches it).
#[test]
fn the_nose_circle_touches_tapers_and_radii() {
    // Radius programming. Contour (Z, X): (2,10) → (−10,10), taper to (−20,15), G3 R5 to
    // (−25,20) about (−25,15), line to (−30,20), G2 R5 to (−35,25) about (−30,25), face to
    // X30. Every element is checked on its own (the corners are whatever they are).
    let prog = "N10 G18 G90 DIAMOF T1 D1 G0 X12 Z5\nN20 G42 G1 X10 Z2 F100\nN30 Z-10\nN40 X15 Z-20\nN50 G3 X20 Z-25 CR=5\nN60 G1 Z-30\nN70 G2 X25 Z-35 CR=5\nN80 G1 X30\nN90 G40 G0 X40 Z5\nN100 M30\n";
    let segs = run(prog, 3);
    let w = v(3);
    let s = |p: [f64; 3]| [zx(p)[0] - w[0], zx(p)[1] - w[1]];
    // The programmed elements, by block line.
    let line_dist = |a: [f64; 2], b: [f64; 2], p: [f64; 2]| {
        let d = [b[0] - a[0], b[1] - a[1]];
        ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]).abs() / d[0].hypot(d[1])
    };
    let mut checked = 0;
    for seg in segs.iter().filter(|x| x.role == Role::Contour) {
        let (p0, p1) = (s(seg.from), s(seg.to));
        let d = |p: [f64; 2]| -> f64 {
            match seg.source.line {
                3 => line_dist([2.0, 10.0], [-10.0, 10.0], p),
                4 => line_dist([-10.0, 10.0], [-20.0, 15.0], p),
                // N50 G3 from (−20,15) to (−25,20), R5: centre (−25,15) (ccw in Z/X).
                5 => ((p[0] + 25.0).hypot(p[1] - 15.0) - 5.0).abs(),
                6 => line_dist([-25.0, 20.0], [-30.0, 20.0], p),
                // N70 G2 from (−30,20) to (−35,25), R5: centre (−30,25).
                7 => ((p[0] + 30.0).hypot(p[1] - 25.0) - 5.0).abs(),
                8 => line_dist([-35.0, 25.0], [-35.0, 30.0], p),
                l => panic!("contour segment of line {l}"),
            }
        };
        for p in [p0, p1] {
            assert!(
                (d(p) - R).abs() < 1e-9,
                "line {}: {p:?} at {}",
                seg.source.line,
                d(p)
            );
        }
        if let Shape::Arc { center, .. } = seg.shape {
            let c = s(center);
            let want = if seg.source.line == 5 {
                [-25.0, 15.0]
            } else {
                [-30.0, 25.0]
            };
            assert!(close(c, want, 1e-12), "arc centre {c:?}");
        }
        checked += 1;
    }
    assert!(checked >= 6);
}

/// 840C 11.13: without TRC, P runs on the programmed taper and the nose leaves material:
/// normal to a taper at angle α to the Z axis the error is R(sin α + cos α − 1) for a tool in
/// position 3 cutting its outside.
#[test]
fn without_compensation_a_taper_is_off_by_the_closed_form() {
    // Taper (Z, X): (0, 10) → (−20, 20), tan α = 10/20.
    let prog = "N10 G18 G90 DIAMOF T1 D1 G0 X10 Z2\nN20 G1 Z0 F100\nN30 X20 Z-20\nN40 M30\n";
    let segs = run(prog, 3);
    let taper = segs.iter().find(|s| s.source.line == 3).unwrap();
    assert!(close(zx(taper.from), [0.0, 10.0], 0.0) && close(zx(taper.to), [-20.0, 20.0], 0.0));
    let alpha = (10.0f64 / 20.0).atan();
    let expected = R * (alpha.sin() + alpha.cos() - 1.0);
    // The nose centre S = P − v and its distance from the taper line, minus R.
    let w = v(3);
    for p in [taper.from, taper.to] {
        let s = [zx(p)[0] - w[0], zx(p)[1] - w[1]];
        let d = ((s[0] - 0.0) * 10.0 - (s[1] - 10.0) * -20.0).abs() / 500f64.sqrt();
        assert!(
            (d - R - expected).abs() < 1e-12,
            "error {} vs {expected}",
            d - R
        );
    }
    // 0.8 mm nose, 26.57°: 0.2733 mm normal to the taper.
    assert!((expected - 0.273_312_629).abs() < 1e-9);
}

/// 808D (seed 004, programs/siemens-808d/d_change.mpf): D1 (R 0.8, position 3) → D2
/// (R 0.4, position 4) over the taper N50, and back over the arc N70: the radius and the tip
/// vector both change along the block, so the centre of N70 moves from S's centre + v(D2) to
/// + v(D1).
#[test]
fn an_offset_change_over_an_arc_moves_its_centre_with_the_tip() {
    let segs = shipped("d_change.mpf");
    // N40: D16 (radius 8) with D1: S at X 8.8, P = S + (−0.8, −0.8) at X 8.
    let n40 = segs.iter().find(|s| s.source.line == 15).unwrap();
    assert!((n40.from[0] - 8.0).abs() < 1e-12 && (n40.to[0] - 8.0).abs() < 1e-12);
    // N70: the concave fillet R5 from D24 to D34 (radius 12 → 17) at Z −30 → −35, G2:
    // centre (Z −30, X 17), on the tool's side, so the nose centre runs at 5 − R. The nose
    // radius goes 0.4 → 0.8 and the tip vector from
    // (+0.4, −0.4) (position 4) to (−0.8, −0.8) (position 3): the centre moves with it.
    let n70 = segs
        .iter()
        .find(|s| s.source.line == 18 && s.role == Role::Contour)
        .unwrap();
    let Shape::Arc {
        center,
        center_end,
        r0,
        r1,
        ..
    } = n70.shape
    else {
        panic!("N70 is an arc")
    };
    assert!(
        close(zx(center), [-30.0 + 0.4, 17.0 - 0.4], 1e-12),
        "{center:?}"
    );
    assert!(
        close(zx(center_end), [-30.0 - 0.8, 17.0 - 0.8], 1e-12),
        "{center_end:?}"
    );
    assert!(
        (r0 - 4.6).abs() < 1e-12 && (r1 - 4.2).abs() < 1e-12,
        "{r0} {r1}"
    );
}

/// A shipped 808D program through preparation with the shipped tools (T1 D1: R 0.8 in
/// position 3, v = (−0.8, −0.8); T1 D2: R 0.4 in position 4, v = (+0.4, −0.4)).
fn shipped(file: &str) -> Vec<Segment> {
    let path = format!(
        "{}/programs/siemens-808d/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    let src = std::fs::read_to_string(&path).unwrap();
    prepare(file, &src, &lathe(), &ToolTable::builtin()).unwrap_or_else(|a| panic!("{a}"))
}

/// The segment of block `n` in `role` (the first, or the only one).
fn seg<'a>(segs: &'a [Segment], n: &str, role: Role) -> &'a Segment {
    segs.iter()
        .find(|s| s.role == role && s.source.number.is_some_and(|b| b.to_string() == n))
        .unwrap_or_else(|| panic!("no {role:?} segment in {n}"))
}

fn assert_line(s: &Segment, from: [f64; 2], to: [f64; 2]) {
    let n = s.source.number.map(|b| b.to_string()).unwrap_or_default();
    assert!(
        close(zx(s.from), from, 1e-6),
        "{n} from {:?}, want {from:?}",
        zx(s.from)
    );
    assert!(
        close(zx(s.to), to, 1e-6),
        "{n} to {:?}, want {to:?}",
        zx(s.to)
    );
}

/// 808D "G40": the last contour block ends in the normal end position, the deselection block
/// then goes to the programmed point. N90 G2 CR=5 from (Z−35, r15) to (Z−40, r20) about
/// (Z−35, r20); G42 puts the nose on the centre's side: radius 5 − 0.8 = 4.2, normal end
/// S = (−35 − 4.2, 20) = (−39.2, 20), P = S + v = (−40, 19.2). N100 G40 X50 Z−40: P to
/// (Z−40, r25), the programmed point.
#[test]
fn s808d_g40_normal_end_position_then_the_programmed_point() {
    let segs = shipped("g40_deselection.mpf");
    let n90 = seg(&segs, "N90", Role::Contour);
    assert!(close(zx(n90.to), [-40.0, 19.2], 1e-9), "{:?}", zx(n90.to));
    let Shape::Arc { center, r1, .. } = n90.shape else {
        panic!("N90 is an arc")
    };
    assert!(close(zx(center), [-35.8, 19.2], 1e-9) && (r1 - 4.2).abs() < 1e-9);
    assert_line(
        seg(&segs, "N100", Role::Retract),
        [-40.0, 19.2],
        [-40.0, 25.0],
    );
}

/// 808D G41 → G42: the last block on the old side ends in its normal end position, the G42
/// block goes to the normal start position of the block after it.
/// N40 faces down Z0 from r24 to r0 with G41 (nose at Z +0.8): ends at S (0.8, 0), P (0, −0.8).
/// N60's chamfer (Z1, r8) → (Z−1, r10), heading (−1, 1)/√2, right normal (1, 1)/√2: normal
/// start S = (1 + 0.4√2, 8 + 0.4√2), P = S + (−0.8, −0.8).
/// N60 → N70 turns left with the tool right: convex, G450 arc about (Z−1, r10).
/// N70 → N80 turns right: concave, the intersection S (−24.2, 10.8), P (−25, 10).
/// N90 ends normal (G40 follows): S (−40, 15.8), P (−40.8, 15); N100 to (Z−40, r18).
#[test]
fn s808d_direction_change_g41_to_g42() {
    let segs = shipped("direction_change.mpf");
    let h = 0.4 * 2f64.sqrt();
    assert_line(seg(&segs, "N40", Role::Contour), [0.0, 23.2], [0.0, -0.8]);
    assert_line(
        seg(&segs, "N50", Role::Approach),
        [0.0, -0.8],
        [1.0 + h - 0.8, 8.0 + h - 0.8],
    );
    assert_line(
        seg(&segs, "N60", Role::Contour),
        [1.0 + h - 0.8, 8.0 + h - 0.8],
        [-1.0 + h - 0.8, 10.0 + h - 0.8],
    );
    let corner = seg(&segs, "N70", Role::Corner);
    let Shape::Arc { center, .. } = corner.shape else {
        panic!("G450 arc")
    };
    assert!(close(zx(center), [-1.8, 9.2], 1e-9));
    assert_line(
        seg(&segs, "N70", Role::Contour),
        [-1.8, 10.0],
        [-25.0, 10.0],
    );
    assert_line(
        seg(&segs, "N90", Role::Contour),
        [-25.8, 15.0],
        [-40.8, 15.0],
    );
    assert_line(
        seg(&segs, "N100", Role::Retract),
        [-40.8, 15.0],
        [-40.0, 18.0],
    );
}

/// 808D: G41 programmed again while active is a new selection. N50 (G0 back to Z2, r12, still
/// compensated) meets N40 at a concave corner: the intersection of Z = 0.8 with N50's
/// equidistant; N50 itself ends in its normal end position before the new start, and N60
/// approaches N70's normal start (nose below r24: S (−18, 23.2), P (−18.8, 22.4)).
#[test]
fn s808d_repeated_g41_is_a_new_selection() {
    let segs = shipped("repeat_g41.mpf");
    // N50 heading (2, 12)/√148, left normal (−12, 2)/√148 · 0.8.
    let l = 148f64.sqrt();
    let n = [-12.0 / l * 0.8, 2.0 / l * 0.8];
    // On N50's equidistant where Z = 0.8: t along (2, 12)/l from (0,0) + n.
    let t = (0.8 - n[0]) / (2.0 / l);
    let x_int = n[1] + t * 12.0 / l;
    assert_line(
        seg(&segs, "N40", Role::Contour),
        [0.0, 11.2],
        [0.0, x_int - 0.8],
    );
    let n50 = seg(&segs, "N50", Role::Contour);
    assert_line(
        n50,
        [0.0, x_int - 0.8],
        [2.0 + n[0] - 0.8, 12.0 + n[1] - 0.8],
    );
    assert_line(
        seg(&segs, "N60", Role::Approach),
        [2.0 + n[0] - 0.8, 12.0 + n[1] - 0.8],
        [-18.8, 22.4],
    );
    // N70 → N80 concave: S (−19.2, 23.2), P (−20, 22.4); N80 ends normal at S (−19.2, 10).
    assert_line(
        seg(&segs, "N70", Role::Contour),
        [-18.8, 22.4],
        [-20.0, 22.4],
    );
    assert_line(
        seg(&segs, "N80", Role::Contour),
        [-20.0, 22.4],
        [-20.0, 9.2],
    );
    assert_line(
        seg(&segs, "N90", Role::Retract),
        [-20.0, 9.2],
        [-18.0, 12.0],
    );
}

/// 808D D change over a line (N50, D1 → D2 on the taper (Z−10, r8) → (Z−20, r12)): the block
/// start intersection with the old radius, the end with the new (840C 11.7), and the tip
/// vector going from position 3's to position 4's along the line.
#[test]
fn s808d_offset_change_over_a_line() {
    let segs = shipped("d_change.mpf");
    let l = 116f64.sqrt();
    // Right normal of the taper's heading (−10, 4)/l: (4, 10)/l.
    let nr = [4.0 / l, 10.0 / l];
    // Start: N40's equidistant r 8.8 meets the taper's at R 0.8.
    let o = [-10.0 + 0.8 * nr[0], 8.0 + 0.8 * nr[1]];
    let t = (8.8 - o[1]) / (4.0 / l);
    let start_s = [o[0] - 10.0 / l * t, 8.8];
    // End: convex corner to N60 (G450): normal end with R 0.4.
    let end_s = [-20.0 + 0.4 * nr[0], 12.0 + 0.4 * nr[1]];
    assert_line(
        seg(&segs, "N50", Role::Contour),
        [start_s[0] - 0.8, start_s[1] - 0.8],
        [end_s[0] + 0.4, end_s[1] - 0.4],
    );
}

/// 808D diameter programming: X words are diameters, the centre offset I stays a radius, and
/// every output gives X as a radius. G2 from (Z0, D20) to (Z−5, D30) with I5 K0: centre
/// (Z0, r15), radius 5 (I5 read as a diameter would put it at r12.5, off both end points).
#[test]
fn diameter_programming_reads_i_as_a_radius() {
    let prog = "N10 G18 G90 DIAMON T1 D1 G0 X20 Z0\nN20 G2 X30 Z-5 I5 K0 F100\nN30 M30\n";
    let segs = run(prog, 3);
    let arc = segs.iter().find(|s| s.source.line == 2).unwrap();
    let Shape::Arc {
        center, r0, ccw, ..
    } = arc.shape
    else {
        panic!("N20 is an arc")
    };
    assert!(close(zx(arc.from), [0.0, 10.0], 0.0) && close(zx(arc.to), [-5.0, 15.0], 0.0));
    assert!(close(zx(center), [0.0, 15.0], 1e-12) && (r0 - 5.0).abs() < 1e-12 && !ccw);
}
