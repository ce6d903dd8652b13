//! SINUMERIK programs for the 808D lathe (config/siemens-808d.toml: the SINUMERIK language,
//! G18 with Z the abscissa and X the ordinate, DIAMON at switch-on, mm) in
//! tests/corpus/siemens-808d/. Every move's end point is compared with values worked out by
//! hand; each program's header comment shows the arithmetic. Positions are [X, Y, Z] with X
//! a RADIUS (the front end halves a diameter), the programmed points (no zero offset is
//! active; the nose radius compensation of d04 is checked by `softnc check`, not here).
//! Programs that run cleanly also pass `softnc check`; those that must stop name their
//! alarm's code, line and column, and the moves made before it.

#[path = "support/corpus.rs"]
mod corpus;

use corpus::*;
use nc_kernel::{AlarmCode, Block, MotionKind, Segment, ToolTable};

const CORPUS: Corpus = Corpus {
    dir: "tests/corpus/siemens-808d",
    machine: "config/siemens-808d.toml",
};

fn run(file: &str) -> (Vec<Block>, Option<nc_kernel::Alarm>) {
    CORPUS.run(file)
}

fn clean(file: &str, want: &[P]) -> Vec<Block> {
    CORPUS.clean(file, want)
}

/// The arcs' kinds and centres.
fn assert_arcs(file: &str, b: &[Block], want: &[(MotionKind, P)]) {
    let got: Vec<(MotionKind, P)> = b
        .iter()
        .filter_map(|b| b.motion)
        .filter(|m| m.kind.is_arc())
        .map(|m| (m.kind, m.center))
        .collect();
    assert_eq!(got.len(), want.len(), "{file}: arcs {got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            g.0 == w.0 && near(g.1, w.1),
            "{file}: arc {g:?}, by hand {w:?}"
        );
    }
}

#[test]
fn d01_diameter_programming() {
    clean(
        "d01_diameter_programming.mpf",
        &[
            [25.0, 0.0, 2.0],
            [20.0, 0.0, 2.0],
            [20.0, 0.0, -30.0],
            [25.0, 0.0, -35.0], // G91 X10: the diameter grows by 10
            [25.0, 0.0, -45.0],
            [30.0, 0.0, -45.0],
            [40.0, 0.0, 5.0],
        ],
    );
}

#[test]
fn d02_diamon_diamof_diam90() {
    let f = "d02_diamon_diamof_diam90.mpf";
    let b = clean(
        f,
        &[
            [20.0, 0.0, 5.0],
            [25.0, 0.0, 0.0],   // DIAMOF
            [20.0, 0.0, 0.0],   // G91 X−5, a radius
            [15.0, 0.0, 0.0],   // DIAM90, G91: a radius
            [25.0, 0.0, 0.0],   // DIAM90, G90: a diameter
            [27.0, 0.0, -10.0], // X=IC(2): a radius
            [30.0, 0.0, -10.0], // X=AC(60): a diameter
            [20.0, 0.0, -10.0], // DIAMON, G91 X−20: a diameter
            [40.0, 0.0, 5.0],
        ],
    );
    let m = |n: u32| {
        (
            block(f, &b, n).modal.diameter,
            block(f, &b, n).modal.radius_incremental,
        )
    };
    assert_eq!(
        [m(20), m(30), m(60), m(110)],
        [(true, false), (false, false), (true, true), (true, false)]
    );
}

#[test]
fn d03_g96_lims() {
    let f = "d03_g96_lims.mpf";
    let b = clean(
        f,
        &[
            [40.0, 0.0, 2.0],
            [40.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [19.0, 0.0, 2.0],
            [19.0, 0.0, -20.0],
            [25.0, 0.0, -20.0],
            [40.0, 0.0, 5.0],
        ],
    );
    let s = |n: u32| {
        let m = &block(f, &b, n).modal;
        (m.css, m.feed_per_rev, m.spindle, m.spindle_limit, m.feed)
    };
    assert_eq!(s(20), (false, false, 800.0, 0.0, 0.0));
    assert_eq!(
        s(30),
        (true, true, 180.0, 2500.0, 0.0),
        "{f}: G96 → G95, F deleted"
    );
    assert_eq!(s(40), (true, true, 180.0, 2500.0, 0.15));
    assert_eq!(
        s(70),
        (false, true, 1200.0, 2500.0, 0.15),
        "{f}: G97 keeps G95"
    );
    assert_eq!(s(90), (false, false, 1200.0, 2500.0, 200.0));
}

#[test]
fn d04_shaft_chf_rnd_g42() {
    let f = "d04_shaft_chf_rnd_g42.mpf";
    let b = clean(
        f,
        &[
            [0.0, 0.0, 5.0],
            [0.0, 0.0, 0.0],    // G42
            [8.0, 0.0, 0.0],    // the face, to the chamfer
            [10.0, 0.0, -2.0],  // CHF=2√2: legs 2
            [10.0, 0.0, -22.0], // to the rounding
            [13.0, 0.0, -25.0], // RND=3 about (13, −22)
            [17.0, 0.0, -25.0], // the shoulder, to the chamfer
            [18.0, 0.0, -26.0], // CHR=1
            [18.0, 0.0, -50.0],
            [25.0, 0.0, -50.0], // G40
            [30.0, 0.0, 5.0],
        ],
    );
    assert_arcs(f, &b, &[(MotionKind::ArcCw, [13.0, 0.0, -22.0])]);
    // The corner elements belong to their blocks and run under G42.
    let lines: Vec<(u32, bool)> = b
        .iter()
        .filter(|b| b.motion.is_some())
        .map(|b| (b.line, b.modal.trc == nc_kernel::TrcSide::Right))
        .collect();
    assert_eq!(
        lines[2..8],
        [
            (17, true),
            (17, true),
            (18, true),
            (18, true),
            (19, true),
            (19, true)
        ]
    );
}

#[test]
fn d05_polar_cr_arcs() {
    let f = "d05_polar_cr_arcs.mpf";
    let a60 = 60f64.to_radians();
    let b = clean(
        f,
        &[
            [15.0, 0.0, 2.0],
            [15.0, 0.0, 0.0],
            [25.0, 0.0, -10.0], // G3 RP=10 AP=90 about the pole (15, −10)
            [25.0, 0.0, -20.0],
            [20.0, 0.0, -25.0], // G2 CR=5
            [20.0, 0.0, -35.0],
            [25.0, 0.0, -35.0], // pole (0, −35), RP 25 at 90°
            [25.0 * a60.sin(), 0.0, -35.0 + 25.0 * a60.cos()], // G2 to 60°
            [40.0, 0.0, 5.0],
        ],
    );
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCcw, [15.0, 0.0, -10.0]),
            (MotionKind::ArcCw, [25.0, 0.0, -25.0]),
            (MotionKind::ArcCw, [0.0, 0.0, -35.0]),
        ],
    );
    for n in [40, 90] {
        assert!(
            block(f, &b, n).motion.is_none(),
            "{f}: the pole block N{n} moves nothing"
        );
    }
}

#[test]
fn d06_roughing_loop() {
    let mut want = vec![[21.0, 0.0, 2.0]];
    for r in [18.0, 16.0, 14.0, 12.0] {
        want.extend([
            [r, 0.0, 2.0],
            [r, 0.0, -30.0],
            [r + 1.0, 0.0, -30.0],
            [r + 1.0, 0.0, 2.0],
        ]);
    }
    want.push([30.0, 0.0, 10.0]);
    let f = "d06_roughing_loop.mpf";
    let b = clean(f, &want);
    let cuts = b
        .iter()
        .filter(|b| {
            b.motion
                .is_some_and(|m| m.kind == MotionKind::Linear && m.end[2] == -30.0)
        })
        .count();
    assert_eq!(cuts, 8, "{f}: four passes of two feed moves");
}

#[test]
fn d07_cip_ct_turning() {
    let f = "d07_cip_ct_turning.mpf";
    let b = clean(
        f,
        &[
            [10.0, 0.0, 2.0],
            [10.0, 0.0, 0.0],
            [20.0, 0.0, -10.0], // CIP through (r 18, Z−4)
            [20.0, 0.0, -20.0],
            [15.0, 0.0, -25.0], // CT
            [10.0, 0.0, -30.0], // CT, the other way round
            [10.0, 0.0, -40.0],
            [30.0, 0.0, 5.0],
        ],
    );
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCcw, [10.0, 0.0, -10.0]),
            (MotionKind::ArcCcw, [15.0, 0.0, -20.0]),
            (MotionKind::ArcCw, [15.0, 0.0, -30.0]),
        ],
    );
}

#[test]
fn d08_alarm_ap_without_plane_axis() {
    let f = "d08_alarm_ap_without_plane_axis.mpf";
    let (b, alarm) = run(f);
    assert_ends(f, &ends(&b), &[[20.0, 0.0, 2.0]]);
    let a = alarm.unwrap_or_else(|| panic!("{f}: no alarm"));
    assert_eq!(
        (a.code, a.line, a.col),
        (AlarmCode::UnknownAddress, 8, 8),
        "{f}: {a}"
    );
    assert_eq!(a.number(), 12050);
    assert!(a.message.contains("Y is not configured"), "{a}");
}

/// CYCLE95's roughing of d09/d10's shaft (their headers): the cycle compensates the nose
/// (R 0.8, position 3) and works on the tip path moved by FALX/FALZ; from S (21.5,
/// 0.365685) five passes at 21.5 − k·13.434315/6, each in at rapid, along Z to the moved
/// tip path, lifted off 0.5 at 45° and back to S's Z; then the moved tip path and back to S.
fn shaft_roughing() -> Vec<P> {
    let q = 0.8 / 2f64.sqrt();
    let s = [21.5, 0.0, -0.7 + q + 0.5];
    let fillet = |level: f64| -15.7 - (4.2f64 * 4.2 - (14.5 - level).powi(2)).sqrt();
    let depth = (21.5 - (7.5 + q)) / 6.0;
    let mut want = vec![s];
    for k in 1..=5 {
        let level = 21.5 - depth * k as f64;
        let z = match k {
            1 => -34.9,
            2 | 3 => -19.9,
            _ => fillet(level),
        };
        want.extend([
            [level, 0.0, s[2]],
            [level, 0.0, z],
            [level + 0.5, 0.0, z + 0.5],
            [level + 0.5, 0.0, s[2]],
        ]);
    }
    want.extend([
        [7.5 + q, 0.0, -0.7 + q],
        [9.5 + q, 0.0, -2.7 + q],
        [10.3, 0.0, -2.7], // the arc about the chamfer's edge
        [10.3, 0.0, -15.7],
        [14.5, 0.0, -19.9], // the fillet at R 4.2 about (14.5, −15.7)
        [17.5, 0.0, -19.9],
        [18.3, 0.0, -20.7], // the arc about the shoulder's edge
        [18.3, 0.0, -34.9],
        [21.5, 0.0, -34.9],
        s,
    ]);
    want
}

/// The arcs of the moved tip path (roughing: the edges' arcs turn counter-clockwise in
/// (Z, X), the fillet clockwise) and the contour's fillet (finishing).
fn shaft_arcs(finishing: bool) -> Vec<(MotionKind, P)> {
    let mut arcs = vec![
        (MotionKind::ArcCcw, [9.5, 0.0, -2.7]),
        (MotionKind::ArcCw, [14.5, 0.0, -15.7]),
        (MotionKind::ArcCcw, [17.5, 0.0, -20.7]),
    ];
    if finishing {
        arcs.push((MotionKind::ArcCw, [15.0, 0.0, -15.0]));
    }
    arcs
}

/// The finishing run along the contour from A' to B, each move's end.
const SHAFT_CONTOUR: [P; 7] = [
    [8.0, 0.0, 0.0],
    [10.0, 0.0, -2.0],
    [10.0, 0.0, -15.0],
    [15.0, 0.0, -20.0], // the fillet about (15, −15)
    [18.0, 0.0, -20.0],
    [18.0, 0.0, -35.0],
    [22.0, 0.0, -35.0],
];

#[test]
fn d09_cycle95_subprogram() {
    let f = "d09_cycle95_subprogram.mpf";
    let mut want = vec![[25.0, 0.0, 5.0]];
    want.extend(shaft_roughing());
    want.extend(SHAFT_CONTOUR);
    let s_z = -0.7 + 0.8 / 2f64.sqrt() + 0.5;
    want.extend([[21.5, 0.0, -35.0], [21.5, 0.0, s_z], [30.0, 0.0, 10.0]]);
    let b = clean(f, &want);
    assert_eq!(ends(&b).len(), want.len(), "{f}: {:?}", ends(&b));
    assert_arcs(f, &b, &shaft_arcs(true));
    // The finishing selects G42 with the move to A' and deselects it with the return.
    let sides: Vec<_> = b.iter().filter_map(|b| b.trc).collect();
    assert_eq!(
        sides,
        [nc_kernel::TrcSide::Right, nc_kernel::TrcSide::Off],
        "{f}"
    );
    // The roughing cuts at FF1 0.25, the finishing at FF3 0.1.
    let feeds: Vec<f64> = b
        .iter()
        .filter(|b| b.motion.is_some_and(|m| m.kind != MotionKind::Rapid))
        .map(|b| b.modal.feed)
        .collect();
    let (rough, finish) = feeds.split_at(5 + 8);
    assert!(rough.iter().all(|&f| f == 0.25), "{f}: {feeds:?}");
    assert!(finish.iter().all(|&f| f == 0.1), "{f}: {feeds:?}");
}

#[test]
fn d10_cycle95_label_section() {
    let f = "d10_cycle95_label_section.mpf";
    let mut want = vec![[25.0, 0.0, 5.0]];
    want.extend(shaft_roughing());
    // T2 D1 (R 1.2): S = (22 − 1.2, 1.2/√2 − 1.2 + 1).
    let s = [20.8, 0.0, 1.2 / 2f64.sqrt() - 0.2];
    want.extend([[30.0, 0.0, 10.0], [25.0, 0.0, 5.0], s]);
    want.extend(SHAFT_CONTOUR);
    want.extend([[20.8, 0.0, -35.0], s, [30.0, 0.0, 10.0]]);
    let b = clean(f, &want);
    assert_eq!(ends(&b).len(), want.len(), "{f}: {:?}", ends(&b));
    // RND=5 makes the fillet d09 programs as G2 CR=5.
    assert_arcs(f, &b, &shaft_arcs(true));
    // The contour's lines never run as blocks of the program.
    assert!(b.iter().all(|b| b.line <= 25), "{f}");
}

#[test]
fn d30_cycle95_nose_radius_fal() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let f = "d30_cycle95_nose_radius_fal.mpf";
    let taper_z = -(11.0 - 2f64.sqrt()) - 0.8; // the tip path's corner before the taper
    let h = 1.0 / 2f64.sqrt();
    let mut want = vec![[25.0, 0.0, 5.0], [19.2, 0.0, 0.2]];
    for (level, z) in [
        (17.4, -24.8),
        (15.6, taper_z - 5.4),
        (13.8, taper_z - 3.6),
        (12.0, taper_z - 1.8),
    ] {
        want.extend([
            [level, 0.0, 0.2],
            [level, 0.0, z],
            [level + 1.0, 0.0, z + 1.0],
            [level + 1.0, 0.0, 0.2],
        ]);
    }
    want.extend([
        [10.2, 0.0, -0.8],
        [10.2, 0.0, taper_z],
        [15.2 + h, 0.0, -16.8 + h],
        [16.2, 0.0, -16.8], // the arc about the edge
        [16.2, 0.0, -24.8],
        [19.2, 0.0, -24.8],
        [19.2, 0.0, 0.2],
        [30.0, 0.0, 10.0],
    ]);
    let b = clean(f, &want);
    assert_arcs(f, &b, &[(MotionKind::ArcCcw, [15.2, 0.0, -16.8])]);
}

/// The feeds of the moves that are no rapids, with their ends.
fn cut_feeds(b: &[Block]) -> Vec<(P, f64)> {
    b.iter()
        .filter_map(|b| b.motion.map(|m| (m, b.modal.feed)))
        .filter(|(m, _)| m.kind != MotionKind::Rapid)
        .map(|(m, f)| (m.end, f))
        .collect()
}

#[test]
fn d11_cycle95_face() {
    let f = "d11_cycle95_face.mpf";
    let mut want = vec![[30.0, 0.0, 5.0], [25.5, 0.0, 0.1]];
    for (z, x) in [(-1.9, 14.0), (-3.9, 16.0), (-5.9, 16.0)] {
        want.extend([
            [25.5, 0.0, z],
            [x, 0.0, z],
            [x + 0.5, 0.0, z + 0.5],
            [25.5, 0.0, z + 0.5],
        ]);
    }
    want.extend([
        [25.0, 0.0, -7.9],
        [16.0, 0.0, -7.9],
        [16.0, 0.0, -3.9],
        [12.0, 0.0, 0.1],
        [0.0, 0.0, 0.1],
        [25.5, 0.0, 0.1],
        [25.0, 0.0, -8.0],
        [16.0, 0.0, -8.0],
        [16.0, 0.0, -4.0],
        [12.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.1],
        [25.5, 0.0, 0.1],
        [30.0, 0.0, 10.0],
    ]);
    let b = clean(f, &want);
    // Three passes and the shifted contour's four moves at FF1 0.2, the finishing at FF3.
    let feeds: Vec<f64> = cut_feeds(&b).iter().map(|c| c.1).collect();
    assert_eq!(feeds, [[0.2; 7].as_slice(), &[0.08; 4]].concat(), "{f}");
}

#[test]
fn d12_cycle95_undercut() {
    let f = "d12_cycle95_undercut.mpf";
    let p = |x: f64, z: f64| [x, 0.0, z];
    let want = [
        p(25.0, 5.0),
        p(18.2, 0.5),
        // X 15.7
        p(18.2, 0.375),
        p(15.7, 0.375),
        p(15.7, -30.0),
        p(16.2, -29.5),
        // X 13.2: in front of the collar, then in the undercut
        p(16.2, 0.25),
        p(13.2, 0.25),
        p(13.2, -10.0),
        p(13.7, -9.5),
        p(16.2, -9.5),
        p(16.2, -15.0),
        p(15.7, -15.0),
        p(13.2, -15.0),
        p(13.2, -22.0),
        p(13.7, -21.5),
        // X 10.7
        p(16.2, -21.5),
        p(16.2, 0.125),
        p(10.7, 0.125),
        p(10.7, -10.0),
        p(11.2, -9.5),
        // back to S, the shifted contour, back to S
        p(18.2, -9.5),
        p(18.2, 0.5),
        p(8.2, 0.0),
        p(8.2, -10.0),
        p(14.2, -10.0),
        p(14.2, -14.0),
        p(11.2, -17.0),
        p(11.2, -22.0),
        p(14.2, -22.0),
        p(14.2, -30.0),
        p(18.2, -30.0),
        p(18.2, 0.5),
        // finishing
        p(8.0, 0.0),
        p(8.0, -10.0),
        p(14.0, -10.0),
        p(14.0, -14.0),
        p(11.0, -17.0),
        p(11.0, -22.0),
        p(14.0, -22.0),
        p(14.0, -30.0),
        p(18.0, -30.0),
        p(18.2, -30.0),
        p(18.2, 0.5),
        p(30.0, 10.0),
    ];
    let b = clean(f, &want);
    // FF2 0.1 for the in-feed into the undercut and the taper down into it while roughing;
    // FF1 0.25 for the other roughing cuts; the finishing all at FF3 0.08.
    let cuts = cut_feeds(&b);
    let (rough, finish) = cuts.split_at(5 + 8);
    let slow: Vec<P> = rough.iter().filter(|c| c.1 == 0.1).map(|c| c.0).collect();
    assert!(
        slow.len() == 2 && near(slow[0], p(13.2, -15.0)) && near(slow[1], p(11.2, -17.0)),
        "{f}: {cuts:?}"
    );
    assert!(rough.iter().all(|c| c.1 == 0.1 || c.1 == 0.25), "{f}");
    assert!(
        finish.iter().all(|c| c.1 == 0.08) && finish.len() == 8,
        "{f}"
    );
    // The contour's lines (from U_START: on line 34) never run as blocks of the program.
    assert!(b.iter().all(|b| b.line < 34), "{f}");
}

#[test]
fn d20_cycle97_m24_thread() {
    let mut want = vec![[20.0, 0.0, 20.0], [13.0, 0.0, 6.0]];
    let rough = |n: f64| 1.6 * (n / 4.0).sqrt();
    for depth in [rough(1.0), rough(2.0), rough(3.0), rough(4.0), 1.8, 1.8] {
        let r = 12.0 - depth;
        want.extend([
            [r, 0.0, 6.0],
            [r, 0.0, -43.0],
            [13.0, 0.0, -43.0],
            [13.0, 0.0, 6.0],
        ]);
    }
    want.push([30.0, 0.0, 50.0]);
    let f = "d20_cycle97_m24_thread.mpf";
    let b = clean(f, &want);
    let threads: Vec<f64> = b.iter().filter_map(|b| b.thread).collect();
    assert_eq!(threads, [3.0; 6], "{f}: six passes at the pitch of M24");
}

#[test]
fn d21_alarm_cycle97_two_starts() {
    let f = "d21_alarm_cycle97_two_starts.mpf";
    let a = CORPUS.stops(f, &[[20.0, 0.0, 20.0]], AlarmCode::NotSupported, 5, 64);
    assert_eq!(a.number(), 12580);
}

#[test]
fn d22_cycle93_groove() {
    let mut want = vec![[20.0, 0.0, 5.0]];
    for z in [-20.5, -22.5, -24.5] {
        want.extend([[16.0, 0.0, z], [11.3, 0.0, z], [16.0, 0.0, z]]);
    }
    for z in [-20.0, -25.0] {
        want.extend([
            [16.0, 0.0, z],
            [11.0, 0.0, z],
            [11.0, 0.0, -22.5],
            [16.0, 0.0, -22.5],
        ]);
    }
    want.push([30.0, 0.0, 50.0]);
    let f = "d22_cycle93_groove.mpf";
    let b = clean(f, &want);
    let dwells: Vec<f64> = b.iter().filter_map(|b| b.dwell).collect();
    assert_eq!(
        dwells, [0.5; 3],
        "{f}: a dwell at the bottom of each plunge"
    );
}

#[test]
fn d23_cycle93_trapezoid_face() {
    let mut want = vec![[30.0, 0.0, 5.0]];
    for x in [23.0, 21.0] {
        want.extend([[x, 0.0, 1.0], [x, 0.0, -2.0], [x, 0.0, 1.0]]);
    }
    want.extend([
        [25.0, 0.0, 1.0],
        [25.0, 0.0, 0.0],
        [23.0, 0.0, -2.0],
        [22.0, 0.0, -2.0],
        [22.0, 0.0, 1.0],
        [21.0, 0.0, 1.0],
        [21.0, 0.0, -2.0],
        [22.0, 0.0, -2.0],
        [22.0, 0.0, 1.0],
        [40.0, 0.0, 20.0],
    ]);
    clean("d23_cycle93_trapezoid_face.mpf", &want);
}

/// CYCLE95 on a face (VARI 10) with the nose radius of T1 D1 (R0.8, cutting edge 3), no
/// allowances: the roughing's last run along the contour is the tool tip's compensated
/// path worked out in the exchanged frame; the finishing run is compensated by preparation
/// in machine axes (the frame's side mirrored). Both must give the same tip points.
#[test]
fn cycle95_face_roughing_and_finishing_agree_on_the_compensated_tip_path() {
    let text = "N10 G18 G90 G95 T1 D1 S1000 M3\nN20 G0 X60 Z5\n\
        N30 CYCLE95(\"F_A:F_E\", 2, 0, 0, 0, 0.2, , 0.08, 10, , , 0.5)\nN40 G0 X60 Z10\n\
        N50 M30\nF_A: G1 X50 Z-8\nX32\nZ-4\nX24 Z0\nF_E: X0\n";
    let segs = nc_kernel::prepare("face", text, &CORPUS.machine(), &ToolTable::builtin())
        .unwrap_or_else(|a| panic!("{a}"));
    let cycle: Vec<_> = segs.iter().filter(|s| s.source.line == 3).collect();
    let feeds = |compensated: bool| -> Vec<[f64; 2]> {
        cycle
            .iter()
            .filter(|s| !s.rapid && (s.role != nc_kernel::Role::Uncompensated) == compensated)
            .map(|s| [s.to[0], s.to[2]])
            .collect()
    };
    let (rough, finish) = (feeds(false), feeds(true));
    // The finishing, by hand (radius, Z): the step face at Z −8 (tip on the face), the
    // diameter 16 up to the chamfer's equidistant, the corner arc, the chamfer's parallel
    // 0.8 off it, (16, −4) + 0.8·(1, 1)/√2 − (0.8, 0.8) = (15.7657, −4.2343) to
    // (11.7657, −0.2343), the arc to the front face, and the face to −0.8 (the tip beyond
    // the centre by the nose radius).
    let h = 0.8 / 2f64.sqrt() - 0.8;
    let want = [
        [16.0, -8.0],
        [16.0, -4.8],
        [16.0 + h, -4.0 + h],
        [12.0 + h, h],
        [11.2, 0.0],
        [-0.8, 0.0],
    ];
    assert_eq!(finish.len(), want.len(), "{finish:?}");
    for (f, w) in finish.iter().zip(&want) {
        assert!(
            (f[0] - w[0]).abs() < 1e-4 && (f[1] - w[1]).abs() < 1e-4,
            "finishing {f:?}, by hand {w:?}"
        );
    }
    // The roughing's last run along the contour: the same points, bit for bit close.
    let run = &rough[rough.len() - want.len()..];
    for (r, f) in run.iter().zip(&finish) {
        assert!(
            (r[0] - f[0]).abs() < 1e-9 && (r[1] - f[1]).abs() < 1e-9,
            "roughing {r:?}, finishing {f:?}"
        );
    }
}

#[test]
fn d31_cycle95_bore_diamof() {
    // (X radius, Z) as the header works them out: the roughing (VARI 3) from S (9.5, 0.7),
    // then the finishing (VARI 7) from its own S (10, 0.5).
    let f = "d31_cycle95_bore_diamof.mpf";
    let p = |x: f64, z: f64| [x, 0.0, z];
    let mut want = vec![p(5.0, 5.0), p(9.5, 0.7)];
    for (level, z) in [(12.0, -19.8), (14.5, -19.8), (17.0, -10.3)] {
        want.extend([p(level, 0.7), p(level, z), p(level - 0.5, z + 0.5)]);
        want.push(p(level - 0.5, 0.7));
    }
    want.extend([p(19.5, 0.2), p(19.5, -7.8), p(15.5, -11.8), p(15.5, -19.8)]);
    want.extend([p(9.5, -19.8), p(9.5, 0.7), p(5.0, 5.0)]);
    want.extend([p(10.0, 0.5), p(20.0, 0.0), p(20.0, -8.0), p(16.0, -12.0)]);
    want.extend([p(16.0, -20.0), p(10.0, -20.0), p(10.0, 0.5), p(5.0, 10.0)]);
    let b = clean(f, &want);
    assert_eq!(ends(&b).len(), want.len(), "{f}: {:?}", ends(&b));
    // Three passes and the moved contour's four moves at FF1 0.3, the finishing at FF3 0.1.
    let feeds: Vec<f64> = cut_feeds(&b).iter().map(|c| c.1).collect();
    assert_eq!(feeds, [[0.3; 7].as_slice(), &[0.1; 4]].concat(), "{f}");
}

#[test]
fn d32_cycle95_face_undercut_diamof() {
    let f = "d32_cycle95_face_undercut_diamof.mpf";
    let p = |x: f64, z: f64| [x, 0.0, z];
    let mut want = vec![p(30.0, 5.0), p(26.5, 0.25)];
    // Z -1.75: from the S-A'm line to the wall X 20, then the groove's stretch
    want.extend([
        p(26.0, 0.25),
        p(26.0, -1.75),
        p(20.0, -1.75),
        p(21.5, -0.25),
    ]);
    want.extend([p(21.5, 0.25), p(15.5, 0.25), p(15.5, -1.75), p(10.0, -1.75)]);
    // Z -3.75: from the line to the wall X 20
    want.extend([p(11.5, -0.25), p(11.5, 0.25), p(25.5, 0.25), p(25.5, -3.75)]);
    want.extend([p(20.0, -3.75), p(21.5, -2.25)]);
    // back to S, the moved contour, back to S
    want.extend([p(21.5, 0.25), p(26.5, 0.25), p(25.0, -5.75), p(20.0, -5.75)]);
    want.extend([
        p(20.0, -1.25),
        p(16.0, -1.25),
        p(14.0, -3.25),
        p(10.0, -3.25),
    ]);
    want.extend([p(10.0, 0.25), p(0.0, 0.25), p(26.5, 0.25)]);
    // finishing, back to S (Z first), the next block
    want.extend([p(25.0, -6.0), p(20.0, -6.0), p(20.0, -1.5), p(16.0, -1.5)]);
    want.extend([p(14.0, -3.5), p(10.0, -3.5), p(10.0, 0.0), p(0.0, 0.0)]);
    want.extend([p(0.0, 0.25), p(26.5, 0.25), p(30.0, 10.0)]);
    let b = clean(f, &want);
    assert_eq!(ends(&b).len(), want.len(), "{f}: {:?}", ends(&b));
    // FF2 0.1 for the in-feed into the groove and its flank along the moved contour; FF1
    // 0.2 for the other roughing cuts; the finishing all at FF3 0.08.
    let cuts = cut_feeds(&b);
    let (rough, finish) = cuts.split_at(4 + 7);
    let slow: Vec<P> = rough.iter().filter(|c| c.1 == 0.1).map(|c| c.0).collect();
    assert!(
        slow.len() == 2 && near(slow[0], p(15.5, -1.75)) && near(slow[1], p(14.0, -3.25)),
        "{f}: {cuts:?}"
    );
    assert!(rough.iter().all(|c| c.1 == 0.1 || c.1 == 0.2), "{f}");
    assert!(
        finish.iter().all(|c| c.1 == 0.08) && finish.len() == 7,
        "{f}"
    );
}

/// A point of the prepared path (X radius, Z) and, for an arc's end, the arc's centre.
type Tip = ([f64; 2], Option<[f64; 2]>);

/// The prepared path of the CYCLE95 block at line `line` of `text`, with `tools`: the
/// roughing (every segment before the first compensated one: uncompensated blocks the
/// cycle has compensated itself) and the finishing (the start of its first compensated
/// feed move, then every compensated feed move's end), tip points P.
fn prepared_cycle(name: &str, text: &str, line: u32, tools: &ToolTable) -> (Vec<Tip>, Vec<Tip>) {
    let segs = nc_kernel::prepare(name, text, &CORPUS.machine_for(name), tools)
        .unwrap_or_else(|a| panic!("{name}: {a}"));
    let cycle: Vec<&Segment> = segs.iter().filter(|s| s.source.line == line).collect();
    let compensated = |s: &Segment| s.role != nc_kernel::Role::Uncompensated;
    let rough = cycle
        .iter()
        .take_while(|s| !compensated(s))
        .map(|s| tip(s))
        .collect();
    let cuts: Vec<&Segment> = cycle
        .into_iter()
        .filter(|s| compensated(s) && !s.rapid)
        .collect();
    let mut finish: Vec<Tip> = cuts
        .first()
        .map(|s| ([s.from[0], s.from[2]], None))
        .into_iter()
        .collect();
    finish.extend(cuts.iter().map(|s| tip(s)));
    (rough, finish)
}

/// A segment's end and, for an arc, its centre.
fn tip(s: &Segment) -> Tip {
    let centre = match s.shape {
        nc_kernel::Shape::Arc { center, .. } => Some([center[0], center[2]]),
        nc_kernel::Shape::Line => None,
    };
    ([s.to[0], s.to[2]], centre)
}

/// `got` ends with the points and arc centres `want` (to 1e-9).
fn assert_tips(what: &str, got: &[Tip], want: &[Tip]) {
    assert!(got.len() >= want.len(), "{what}: {got:?}");
    let tail = &got[got.len() - want.len()..];
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9;
    for (g, w) in tail.iter().zip(want) {
        let centres = match (g.1, w.1) {
            (Some(a), Some(b)) => close(a, b),
            (a, b) => a.is_none() && b.is_none(),
        };
        assert!(
            close(g.0, w.0) && centres,
            "{what}: {g:?}, by hand {w:?}\n{got:?}"
        );
    }
}

/// The corpus program `file` as text, and the line of its first CYCLE95 block.
fn cycle_line(file: &str) -> (String, u32) {
    let text = std::fs::read_to_string(CORPUS.path_of(file)).expect("corpus file");
    let line = text
        .lines()
        .position(|l| l.contains(" CYCLE95("))
        .expect("a CYCLE95 block") as u32
        + 1;
    (text, line)
}

/// `centre` moved to the tip P by `v` (X, Z), arcs' centres with it.
fn to_tip(centre: &[Tip], v: [f64; 2]) -> Vec<Tip> {
    let mv = |p: [f64; 2]| [p[0] + v[0], p[1] + v[1]];
    centre.iter().map(|&(p, c)| (mv(p), c.map(mv))).collect()
}

/// d33's contour: the nose centre's path on its equidistant at `d` outside (right of
/// travel in (Z, X)), from A' to B, every element's end (X radius, Z) and the rounding's
/// centre. The concave corners (10, -10) and (18, -25) are trimmed where the parallels
/// meet; the rounding R4 about (14, -14) becomes R 4 + d about the same centre.
fn d33_centre_path(d: f64) -> Vec<Tip> {
    vec![
        ([10.0 + d, 0.0], None),
        ([10.0 + d, -10.0 + d], None),
        ([14.0, -10.0 + d], None),
        ([18.0 + d, -14.0], Some([14.0, -14.0])),
        ([18.0 + d, -25.0 + d], None),
        ([22.0, -25.0 + d], None),
    ]
}

#[test]
fn d33_cycle95_nose_fal_finishing() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let f = "d33_cycle95_nose_fal_finishing.mpf";
    let p = |x: f64, z: f64| [x, 0.0, z];
    let mut want = vec![p(25.0, 5.0), p(21.2, -0.3)];
    let arc = |level: f64| -14.8 + (25.0 - (level - 13.2f64).powi(2)).sqrt();
    for (level, z) in [
        (19.0, -24.8),
        (16.8, arc(16.8)),
        (14.6, -10.0),
        (12.4, -9.8),
    ] {
        want.extend([p(level, -0.3), p(level, z), p(level + 0.5, z + 0.5)]);
        want.push(p(level + 0.5, -0.3));
    }
    want.extend([p(10.2, -0.8), p(10.2, -9.8), p(13.2, -9.8), p(18.2, -14.8)]);
    want.extend([p(18.2, -24.8), p(21.2, -24.8), p(21.2, -0.3)]);
    want.extend([p(10.0, 0.0), p(10.0, -10.0), p(14.0, -10.0), p(18.0, -14.0)]);
    want.extend([
        p(18.0, -25.0),
        p(22.0, -25.0),
        p(21.2, -25.0),
        p(21.2, -0.3),
    ]);
    want.push(p(30.0, 10.0));
    let b = clean(f, &want);
    assert_eq!(ends(&b).len(), want.len(), "{f}: {:?}", ends(&b));
    assert_arcs(
        f,
        &b,
        &[
            (MotionKind::ArcCcw, [13.2, 0.0, -14.8]),
            (MotionKind::ArcCcw, [14.0, 0.0, -14.0]),
        ],
    );
    // Prepared: the roughing's run along the contour is the nose centre's path at FAL +
    // R = 1.0, the finishing's (compensated by preparation, G42) at R = 0.8, both moved to
    // the tip by P - S = (-0.8, -0.8) of cutting edge 3.
    let v = [-0.8, -0.8];
    let (run, contour) = (d33_centre_path(1.0), d33_centre_path(0.8));
    assert_prepared(f, &to_tip(&run, v), [21.2, -0.3], &to_tip(&contour, v));
}

/// d34's contour (d12's undercut): the nose centre's path on its equidistant at `d`
/// outside (right of travel), from A' to B. Convex edges (14, -10), (14, -14), (14, -22)
/// are rounded by arcs of d about them; the concave corners are trimmed where the
/// parallels meet: the taper X = Z + 28 moves by (+q, -q) in (X, Z), q = d/sqrt 2, to
/// X = Z + 28 + 2q, which meets X 11 + d at Z = d - 17 - 2q.
fn d34_centre_path(d: f64) -> Vec<Tip> {
    let q = d / 2f64.sqrt();
    vec![
        ([8.0 + d, 0.0], None),
        ([8.0 + d, -10.0 + d], None),
        ([14.0, -10.0 + d], None),
        ([14.0 + d, -10.0], Some([14.0, -10.0])),
        ([14.0 + d, -14.0], None),
        ([14.0 + q, -14.0 - q], Some([14.0, -14.0])),
        ([11.0 + d, d - 17.0 - 2.0 * q], None),
        ([11.0 + d, -22.0 + d], None),
        ([14.0, -22.0 + d], None),
        ([14.0 + d, -22.0], Some([14.0, -22.0])),
        ([14.0 + d, -30.0 + d], None),
        ([18.0, -30.0 + d], None),
    ]
}

/// d34's roughing levels up to the return to S (X radius, Z), as its header works them
/// out; `taper` is where the moved tip path's taper passes X 12.8.
fn d34_levels(taper: f64) -> Vec<P> {
    let p = |x: f64, z: f64| [x, 0.0, z];
    let mut want = vec![p(17.4, -0.425), p(15.1, -0.425), p(15.1, -30.0)];
    // X 15.1 lifted off; X 12.8 in front of the first collar, then in the undercut
    want.extend([
        p(15.6, -29.5),
        p(15.6, -0.55),
        p(12.8, -0.55),
        p(12.8, -10.0),
    ]);
    want.extend([p(13.3, -9.5), p(15.6, -9.5), p(15.6, taper), p(15.1, taper)]);
    want.extend([p(12.8, taper), p(12.8, -22.0), p(13.3, -21.5)]);
    // X 10.5, back to S
    want.extend([
        p(15.6, -21.5),
        p(15.6, -0.675),
        p(10.5, -0.675),
        p(10.5, -10.0),
    ]);
    want.extend([p(11.0, -9.5), p(17.4, -9.5), p(17.4, -0.3)]);
    want
}

#[test]
fn d34_cycle95_undercut_nose() {
    // The arithmetic is in the program's header; (X radius, Z) below.
    let f = "d34_cycle95_undercut_nose.mpf";
    let p = |x: f64, z: f64| [x, 0.0, z];
    // The moved tip path's taper: X = Z + 28 + 2q less the tip's (0.8, 0.8), plus FALX
    // 0.2 in X: X = Z + 28.2 + 0.8 sqrt 2; it passes X 12.8 at:
    let taper = 12.8 - (28.2 + 0.8 * 2f64.sqrt());
    let mut want = vec![p(25.0, 5.0), p(17.4, -0.3)];
    want.extend(d34_levels(taper));
    // The moved tip path from S (the nose centre's at R 0.8, moved to the tip and by
    // FALX), back to S; the finishing
    let v = [-0.8, -0.8];
    let run = to_tip(&d34_centre_path(0.8), [v[0] + 0.2, v[1]]);
    want.extend(run.iter().map(|t| p(t.0[0], t.0[1])));
    want.push(p(17.4, -0.3));
    want.extend([p(8.0, 0.0), p(8.0, -10.0), p(14.0, -10.0), p(14.0, -14.0)]);
    want.extend([
        p(11.0, -17.0),
        p(11.0, -22.0),
        p(14.0, -22.0),
        p(14.0, -30.0),
    ]);
    want.extend([p(18.0, -30.0), p(17.4, -30.0), p(17.4, -0.3), p(30.0, 10.0)]);
    let b = clean(f, &want);
    assert_eq!(ends(&b).len(), want.len(), "{f}: {:?}", ends(&b));
    // FF2 0.1 for the in-feed into the undercut, and for the edge's arc and the taper
    // down into it along the moved tip path.
    let slow: Vec<P> = cut_feeds(&b)
        .iter()
        .filter(|c| c.1 == 0.1)
        .map(|c| c.0)
        .collect();
    let at = |k: usize| p(run[k].0[0], run[k].0[1]);
    let by_hand = [p(12.8, taper), at(5), at(6)];
    assert_eq!(slow.len(), by_hand.len(), "{f}: {slow:?}");
    assert!(
        slow.iter().zip(&by_hand).all(|(s, h)| near(*s, *h)),
        "{f}: {slow:?}"
    );
    // Prepared: the finishing's tip path is the nose centre's at R 0.8 moved to the tip,
    // without FALX.
    assert_prepared(f, &run, [17.4, -0.3], &to_tip(&d34_centre_path(0.8), v));
}

/// The prepared path of `file`'s CYCLE95 (the shipped tools): the roughing ends with
/// `run` (from the G0 to its start) and the return to `s`; the finishing's compensated
/// tip path, from its start, is `contour`.
fn assert_prepared(file: &str, run: &[Tip], s: [f64; 2], contour: &[Tip]) {
    let (text, line) = cycle_line(file);
    let (rough, finish) = prepared_cycle(file, &text, line, &ToolTable::builtin());
    let mut tail = run.to_vec();
    tail.push((s, None));
    assert_tips(&format!("{file}: roughing"), &rough, &tail);
    assert_eq!(finish.len(), contour.len(), "{file}: {finish:?}");
    assert_tips(&format!("{file}: finishing"), &finish, contour);
}

/// A boring bar: nose R 0.4, cutting edge position 2 (P - S = (-R, +R) in (Z, X): the tip
/// towards the chuck and out into the bore's wall).
const BORING_BAR: &str = "[[offset]]\nt = 4\nd = 1\nradius = 0.4\nlength = 0.0\nedge = 2\n";

/// The bore of d31 (diameters here): the nose centre's path on its equidistant at `d`
/// inside (left of travel in (Z, X), towards the centre), from A' to B. The bore's wall X
/// 20 meets the taper X = Z + 28 at a corner the nose cannot reach: both parallels
/// trimmed where they meet, the taper's moved by (-h, +h) in (X, Z), h = d/sqrt 2, to X =
/// Z + 28 - 2h, which meets X 20 - d at Z = -8 - d + 2h; the taper's end (16, -12) is an
/// edge the nose goes round (an arc of d about it); the corner (16, -20) trimmed.
fn bore_centre_path(d: f64) -> Vec<Tip> {
    let h = d / 2f64.sqrt();
    vec![
        ([20.0 - d, 0.0], None),
        ([20.0 - d, -8.0 - d + 2.0 * h], None),
        ([16.0 - h, -12.0 + h], None),
        ([16.0 - d, -12.0], Some([16.0, -12.0])),
        ([16.0 - d, -20.0 + d], None),
        ([10.0, -20.0 + d], None),
    ]
}

#[test]
fn cycle95_inside_rough_and_finish_on_the_boring_bars_tip_path() {
    // VARI 11 (complete, longitudinal inside), FAL 0.1, the boring bar (R 0.4, edge 2): the
    // cycle's side G41. Roughing: the nose centre at FAL + R = 0.5 inside, the tip at
    // centre + (0.4, -0.4) in (X, Z): A'm (19.9, -0.4), the taper's parallel from Z
    // -8.5 + 0.5 sqrt 2 - 0.4 = -8.192893 (X = Z + 28.8 - 0.5 sqrt 2) to (16.046447,
    // -12.046447), the arc about (16.4, -12.4) to (15.9, -12.4), (15.9, -19.9), Bm (10.4,
    // -19.9). S = (the smallest X 10.4, -0.4 + _VRT 0.5). Stock 9.5, MID 2.5: 4 cuts of
    // 2.375, passes at 12.775 and 15.15 (the face at -19.9) and 17.525 (the taper at Z =
    // 17.525 - 28.8 + 0.5 sqrt 2), each lifted off 0.5 (X in, Z back).
    let text = "N10 G18 G90 G95 T4 D1 S1000 M3\nN20 G0 X10 Z5\n\
        N30 CYCLE95(\"B_A:B_E\", 2.5, , , 0.1, 0.3, , 0.1, 11, , , 0.5)\nN40 G0 X10 Z10\n\
        N50 M30\nB_A: G1 X40 Z0\nZ-8\nX32 Z-12\nZ-20\nB_E: X20\n";
    let tools = ToolTable::from_toml_str(BORING_BAR, "boring bar").expect("tool table");
    let (rough, finish) = prepared_cycle("bore", text, 3, &tools);
    let v = [0.4, -0.4];
    let s = [10.4, 0.1];
    let taper = 17.525 - 28.8 + 0.5 * 2f64.sqrt();
    let mut want: Vec<Tip> = vec![(s, None)];
    for (level, z) in [(12.775, -19.9), (15.15, -19.9), (17.525, taper)] {
        let up = level - 0.5;
        want.extend([[level, s[1]], [level, z], [up, z + 0.5], [up, s[1]]].map(|p| (p, None)));
    }
    want.extend(to_tip(&bore_centre_path(0.5), v));
    want.push((s, None));
    assert_eq!(rough.len(), want.len(), "{rough:?}");
    assert_tips("roughing", &rough, &want);
    // Finishing: preparation's G41 puts the nose centre at R 0.4 inside, the tip at
    // centre + (0.4, -0.4): on the wall X 16 and the face Z -20 the tip runs on the
    // contour, on the bore X 20 too.
    let contour = to_tip(&bore_centre_path(0.4), v);
    assert_eq!(finish.len(), contour.len(), "{finish:?}");
    assert_tips("finishing", &finish, &contour);
}
