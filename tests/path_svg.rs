//! `softnc path --format svg`: the picture is well-formed SVG, and what it draws is where the
//! geometry says. The world→pixel map is recovered from the picture's own grid labels, so the
//! test checks the drawn positions against coordinates worked out here by hand.

use std::process::Command;

struct Run {
    code: i32,
    svg: String,
}

fn run(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_softnc"))
        .arg("path")
        .args(args)
        .args(["--format", "svg"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("softnc runs");
    Run {
        code: out.status.code().unwrap_or(-1),
        svg: String::from_utf8(out.stdout).expect("utf-8 svg"),
    }
}

fn group<'a>(doc: &'a roxmltree::Document, id: &str) -> Option<roxmltree::Node<'a, 'a>> {
    doc.descendants().find(|n| n.attribute("id") == Some(id))
}

/// An element's text; the SVG writer puts it on its own line.
fn text<'a>(n: roxmltree::Node<'a, '_>) -> &'a str {
    n.text().unwrap_or("").trim()
}

fn attr(n: roxmltree::Node, name: &str) -> f64 {
    n.attribute(name)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("attribute {name} on {:?}", n.tag_name()))
}

/// The linear map pixel → world along one axis, from two grid labels.
fn axis(labels: &[(f64, f64)]) -> impl Fn(f64) -> f64 {
    assert!(labels.len() >= 2, "grid has at least two labels per axis");
    let (p0, w0) = labels[0];
    let (p1, w1) = labels[labels.len() - 1];
    let k = (w1 - w0) / (p1 - p0);
    move |p| w0 + (p - p0) * k
}

/// Pixel → world maps (abscissa, ordinate) from the grid labels: abscissa values centred
/// under vertical lines, ordinate values right-aligned (baseline 3.5 px below the line).
fn maps(doc: &roxmltree::Document) -> (impl Fn(f64) -> f64, impl Fn(f64) -> f64) {
    let grid = group(doc, "grid").expect("grid");
    let mut us = Vec::new();
    let mut vs = Vec::new();
    for t in grid.children().filter(|n| n.has_tag_name("text")) {
        let Ok(value) = text(t).parse::<f64>() else {
            continue;
        };
        match t.attribute("text-anchor") {
            Some("middle") => us.push((attr(t, "x"), value)),
            Some("end") => vs.push((attr(t, "y") - 3.5, value)),
            _ => {}
        }
    }
    (axis(&us), axis(&vs))
}

#[test]
fn workpiece_picture_shows_the_tool_at_each_block_end() {
    let r = run(&["programs/siemens-840c/11_15_workpiece.mpf"]);
    assert_eq!(r.code, 0);
    let doc = roxmltree::Document::parse(&r.svg).expect("well-formed SVG");
    assert_eq!(doc.root_element().tag_name().name(), "svg");

    let (to_u, to_v) = maps(&doc);

    // One tool circle per compensated block: N10 (selection) … N110, and N120 (deselection).
    let circles: Vec<_> = group(&doc, "tool-circles")
        .expect("tool circles")
        .children()
        .filter(|n| n.has_tag_name("circle"))
        .collect();
    assert_eq!(circles.len(), 12);

    // Tool centres at block ends, by hand (R = 10, G41, 840C 11.15):
    // N20 (30,60)→(40,80): left normal (-2,1)/√5 → (40,80) + 10·(-2,1)/√5.
    // N30 G2 about (40,55), r 25, tool outside (r 35); the N40 equidistant is y = 65 (inner
    //   corner): x = 40 + √(35² − 10²).
    // N110 (40,40)→(30,60): left normal (-2,-1)/√5.  N120 G40 ends at P0 (15,60).
    let s5 = 5f64.sqrt();
    let expected = [
        ("N20", 40.0 - 20.0 / s5, 80.0 + 10.0 / s5),
        ("N30", 40.0 + (35f64 * 35.0 - 100.0).sqrt(), 65.0),
        ("N110", 30.0 - 20.0 / s5, 60.0 - 10.0 / s5),
        ("N120", 15.0, 60.0),
    ];
    for (block, u, v) in expected {
        let c = circles
            .iter()
            .find(|c| {
                c.children()
                    .find(|n| n.has_tag_name("title"))
                    .is_some_and(|t| text(t).starts_with(&format!("{block}:")))
            })
            .unwrap_or_else(|| panic!("a tool circle for {block}"));
        let (cu, cv) = (to_u(attr(*c, "cx")), to_v(attr(*c, "cy")));
        // Pixel coordinates are written to 0.01 px; at this scale (~7 px/mm) that is < 0.01 mm.
        assert!(
            (cu - u).abs() < 0.01 && (cv - v).abs() < 0.01,
            "{block}: drawn at ({cu}, {cv}), expected ({u}, {v})"
        );
        let r_px = attr(*c, "r");
        let r_mm = to_u(attr(*c, "cx") + r_px) - cu;
        assert!(
            (r_mm - 10.0).abs() < 0.01,
            "{block}: tool circle radius {r_mm} mm"
        );
        let tip = c.children().find(|n| n.has_tag_name("title")).unwrap();
        assert_eq!(
            text(tip),
            format!("{block}: tool centre X{} Y{}, R10", fmt3(u), fmt3(v))
        );
    }

    // Every numbered block is labelled; the start point carries all four blocks that end there.
    let labels: Vec<&str> = group(&doc, "labels")
        .expect("labels")
        .children()
        .filter(|n| n.has_tag_name("text"))
        .map(text)
        .collect();
    assert!(labels.contains(&"N1, N5, N120, N130"), "{labels:?}");
    assert!(labels.contains(&"N10, N110"), "{labels:?}");
    for n in [
        "N20", "N30", "N40", "N50", "N60", "N70", "N80", "N90", "N100",
    ] {
        assert!(labels.contains(&n), "label {n} in {labels:?}");
    }

    // The tool path: every non-rapid segment that moves in the plane is drawn, by role.
    let path = group(&doc, "tool-path").expect("tool path");
    let count = |class: &str| {
        path.children()
            .filter(|n| n.attribute("class") == Some(class))
            .count()
    };
    // N20…N110: ten contour elements; N10 approach, N120 retract.
    assert_eq!(count("contour"), 10);
    assert_eq!(count("approach"), 1);
    assert_eq!(count("retract"), 1);
    // G450 transition circles at the five right turns (outer corners under G41): at (40,80),
    // (110,70), (110,35), (65,15) and (40,40); the other four corners are inner.
    assert_eq!(count("corner"), 5);
    assert!(group(&doc, "alarm").is_none());
}

fn fmt3(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[test]
fn alarm_is_marked_and_exit_code_says_so() {
    let r = run(&["programs/siemens-840c/11_11_four_blocks_outside_plane_alarm.mpf"]);
    assert_eq!(r.code, 1, "an alarm that stops preparation exits non-zero");
    let doc = roxmltree::Document::parse(&r.svg).expect("well-formed SVG even after an alarm");
    let marker = group(&doc, "alarm").expect("alarm marker");
    assert!(marker.descendants().any(|n| text(n) == "alarm 3021"));
    let legend = group(&doc, "legend").expect("legend");
    assert!(legend
        .descendants()
        .any(|n| text(n).starts_with("alarm 3021 at line 18:1 N45:")));
}

#[test]
fn long_programs_leave_out_labels_and_tool_circles() {
    let dir = std::env::temp_dir().join(format!("softnc-svg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("zigzag.mpf");
    let mut prog = String::from("N1 G0 G17 G90 D1 X0 Y0\nN2 G41 G1 X10 Y0 F1000\n");
    for i in 0..600 {
        prog.push_str(&format!(
            "X{} Y{}\n",
            20 + 10 * i,
            if i % 2 == 0 { 30 } else { 0 }
        ));
    }
    prog.push_str("G40 X6030 Y-20\nM30\n");
    std::fs::write(&file, prog).unwrap();
    // 6 m of zig-zag: beyond the default machine's software limit of X.
    let r = run(&[
        file.to_str().unwrap(),
        "--md",
        "axes.X.software_limits=[-1e4,1e4]",
    ]);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(r.code, 0);
    let doc = roxmltree::Document::parse(&r.svg).unwrap();
    assert!(group(&doc, "labels").is_none());
    assert!(group(&doc, "tool-circles").is_none());
    let path = group(&doc, "tool-path").unwrap();
    assert_eq!(
        path.children()
            .filter(|n| n.attribute("class") == Some("contour"))
            .count(),
        600
    );
}

/// A lathe (808D, d_change.mpf: T1 D1 R0.8 in position 3): the path drawn is the tool tip, the
/// circle at a block end is the nose, centred on S = P − v. In front of the centre of rotation
/// (`tool_post = "in-front"`) X is drawn downwards and nothing else changes: the same path
/// output byte for byte, the nose circle at the same world position.
#[test]
fn lathe_nose_circles_and_the_view_from_in_front() {
    let prog = "programs/siemens-808d/d_change.mpf";
    let path_out = |post: &str| {
        Command::new(env!("CARGO_BIN_EXE_softnc"))
            .args([
                "path",
                prog,
                "--machine",
                "config/siemens-808d.toml",
                "--md",
            ])
            .arg(format!("tool_post={post}"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("softnc runs")
            .stdout
    };
    assert_eq!(path_out("behind"), path_out("in-front"));
    let mut slopes = Vec::new();
    for post in ["behind", "in-front"] {
        let md = format!("tool_post={post}");
        let r = run(&[prog, "--machine", "config/siemens-808d.toml", "--md", &md]);
        assert_eq!(r.code, 0);
        let doc = roxmltree::Document::parse(&r.svg).expect("well-formed SVG");
        let frame = group(&doc, "grid")
            .and_then(|g| g.children().find(|n| n.has_tag_name("rect")))
            .expect("plot frame");
        assert!(attr(frame, "height") > 0.0, "{post}: frame height");
        let (to_u, to_v) = maps(&doc);
        // World X (ordinate) per pixel downwards: negative when X is drawn up.
        slopes.push(to_v(100.0) - to_v(0.0));
        // N40 ends at the concave corner with N50: nose centre at r 8.8 on the taper's
        // equidistant (docs/turning.md; tests/turning.rs works it out): Z −9.8459.
        let circle = group(&doc, "tool-circles")
            .expect("tool circles")
            .children()
            .filter(|n| n.has_tag_name("circle"))
            .find(|c| {
                c.children()
                    .find(|n| n.has_tag_name("title"))
                    .is_some_and(|t| text(t).starts_with("N40:"))
            })
            .expect("a nose circle for N40");
        let (z, x) = (to_u(attr(circle, "cx")), to_v(attr(circle, "cy")));
        assert!(
            (z + 9.8459).abs() < 0.01 && (x - 8.8).abs() < 0.01,
            "{post}: N40 nose drawn at Z{z} X{x}"
        );
        let title = circle.children().find(|n| n.has_tag_name("title")).unwrap();
        assert!(text(title).contains("nose centre"), "{}", text(title));
    }
    assert!(slopes[0] < 0.0 && slopes[1] > 0.0, "{slopes:?}");
}

/// A lathe program that goes to its reference point (X60 Z100) between the cuts at Z 0 … −70:
/// the picture frames the cutting moves, and the rapids to the reference point are cut off at
/// the frame's edge, so the shaft fills the picture.
#[test]
fn travel_to_a_far_reference_point_does_not_shrink_the_work() {
    let prog = "programs/fanuc-lathe/shaft_rough_finish.nc";
    let r = run(&[prog, "--machine", "config/fanuc-lathe.toml"]);
    assert_eq!(r.code, 0);
    let doc = roxmltree::Document::parse(&r.svg).expect("well-formed SVG");
    let title = group(&doc, "title").expect("title");
    assert!(
        title
            .descendants()
            .any(|n| text(n).contains("framed on the cutting moves")),
        "the subtitle says the picture is framed"
    );
    let (to_u, to_v) = maps(&doc);
    let frame = group(&doc, "grid")
        .and_then(|g| g.children().find(|n| n.has_tag_name("rect")))
        .expect("plot frame");
    let (x0, w) = (attr(frame, "x"), attr(frame, "width"));
    let (y0, h) = (attr(frame, "y"), attr(frame, "height"));
    // Z across the frame: the shaft's −70 … 0 plus the start at Z2, not the reference
    // point's Z100; X (radius) from the bore's 6 to the bar's 22, not the reference's 30.
    let (z_lo, z_hi) = (to_u(x0), to_u(x0 + w));
    assert!(z_lo < -70.0 && z_lo > -80.0, "left edge Z{z_lo}");
    assert!(z_hi > 2.0 && z_hi < 12.0, "right edge Z{z_hi}");
    let (xa, xb) = (to_v(y0), to_v(y0 + h));
    let (x_lo, x_hi) = (xa.min(xb), xa.max(xb));
    assert!(
        x_lo < 6.0 && x_hi > 22.0 && x_hi < 28.0,
        "X {x_lo} … {x_hi}"
    );
    // Everything drawn along the path is clipped to the frame.
    for id in ["programmed", "tool-path"] {
        let g = group(&doc, id).unwrap_or_else(|| panic!("group {id}"));
        assert_eq!(g.attribute("clip-path"), Some("url(#plot)"), "{id}");
    }
}
