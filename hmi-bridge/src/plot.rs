//! What the page plots: the programmed contour (from the interpreter) and the compensated
//! path (from preparation, with the kernel's current tool table: the tool centre, and on a
//! lathe the tool tip P of the offset's cutting edge position), as polylines in the
//! program's plane, arcs sampled finely enough to look round.

use nc_kernel::geometry::{Curve, Fineness};
use nc_kernel::Prepared;
use nc_kernel::{Interpreter, MachineData, Preparation, ToolTable, WorkOffsets};
use nc_kernel::{MotionKind, Plane, Pos};
use nc_runtime::WireAxes;
use softnc_protocol::WorkOffsetsMsg;

/// Points kept at most per picture: longer programs are thinned.
const MAX_POINTS: usize = 100_000;

#[derive(Debug, Default, serde::Serialize)]
pub struct Plot {
    /// Abscissa and ordinate of the plane: "X", "Y" (G17), "Z", "X" (G18), "Y", "Z" (G19).
    pub axes: [&'static str; 2],
    /// The same as indices into the status's position arrays (the machine's configured
    /// axes in its order: X 0, Z 1 on a lathe); `None` for an axis the machine does not
    /// have. The page draws the actual position with them.
    pub index: [Option<usize>; 2],
    pub programmed: Vec<Vec<[f64; 2]>>,
    pub path: Vec<Vec<[f64; 2]>>,
    /// Preparation's first alarm, rendered (the path ends there).
    pub alarm: Option<String>,
}

/// The kernel's work offsets as the preparation reads them. Axes are matched by letter;
/// a set or axis this machine data does not know (the bridge started with another
/// `--machine` than the kernel) is left at zero.
pub fn work_offsets(m: &WorkOffsetsMsg, md: &MachineData) -> WorkOffsets {
    let mut table = WorkOffsets::default();
    for e in m.entries() {
        let values: Vec<(usize, f64)> = m
            .axes
            .names()
            .zip(e.values)
            .filter(|(_, v)| *v != 0.0)
            .filter_map(|(c, v)| {
                let axis = nc_kernel::AXIS_NAMES.iter().position(|&n| n == c)?;
                md.has_axis(axis).then_some((axis, v))
            })
            .collect();
        if !values.is_empty() {
            let _ = table.edit(md, e.name(), &values, nc_kernel::MAX_WORK_OFFSET);
        }
    }
    table
}

/// Names of the geometry axes by index.
const AXES: [&str; 3] = ["X", "Y", "Z"];

/// Where geometry axis `i` (X 0, Y 1, Z 2) is in the status's position arrays.
fn wire_index(md: &MachineData, i: usize) -> Option<usize> {
    let name = AXES.get(i)?.chars().next()?;
    WireAxes::new(md).list.index(name)
}

/// The plot of no program: nothing drawn, in the plane the machine starts in.
pub fn empty(md: &MachineData) -> Plot {
    let plane = contour_plane("", "", md, &ToolTable::default());
    framed(md, plane)
}

fn framed(md: &MachineData, plane: Plane) -> Plot {
    let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
    Plot {
        axes: [AXES[a], AXES[o]],
        index: [wire_index(md, a), wire_index(md, o)],
        ..Default::default()
    }
}

/// Arcs as chords of at most 2° and at most 1 mm: round on any screen.
const FINE: Fineness = Fineness {
    max_angle: std::f64::consts::PI / 90.0,
    max_length: 1.0,
};

/// The picture is drawn in the plane of the program's first feed move (where the contour
/// is: a turned part in G18 is a Z/X picture); moves in other planes are drawn projected
/// onto it.
pub fn plot(name: &str, source: &str, md: &MachineData, tools: &ToolTable) -> Plot {
    let plane = contour_plane(name, source, md, tools);
    let (a, o) = (plane.abscissa as usize, plane.ordinate as usize);
    let mut out = framed(md, plane);
    let mut interp = Interpreter::new(name, source, md, tools);
    let mut line: Vec<[f64; 2]> = Vec::new();
    // Up to the first alarm: preparation below reports it.
    while let Ok(Some(b)) = interp.next_block() {
        let Some(m) = &b.motion else { continue };
        if m.kind == MotionKind::Rapid {
            flush(&mut out.programmed, &mut line);
            continue;
        }
        let curve = Curve::of_motion(m);
        piece(
            &mut out.programmed,
            &mut line,
            (a, o),
            curve,
            m.start,
            m.end,
        );
    }
    flush(&mut out.programmed, &mut line);

    let mut prep = Preparation::new(name, source, md, tools);
    loop {
        let seg = match prep.next_item() {
            Ok(Some(Prepared::Segment(s))) => s,
            Ok(Some(_)) => continue,
            Ok(None) => break,
            Err(e) => {
                out.alarm = Some(e.render(source));
                break;
            }
        };
        if seg.rapid {
            flush(&mut out.path, &mut line);
            continue;
        }
        let Some(c) = Curve::new(&seg) else { continue };
        piece(&mut out.path, &mut line, (a, o), Some(c), seg.from, seg.to);
    }
    flush(&mut out.path, &mut line);
    thin(&mut out.programmed);
    thin(&mut out.path);
    out
}

/// The plane of the first move at feed, else the one the program starts in.
fn contour_plane(name: &str, source: &str, md: &MachineData, tools: &ToolTable) -> Plane {
    let mut interp = Interpreter::new(name, source, md, tools);
    let start = interp.state().plane;
    while let Ok(Some(b)) = interp.next_block() {
        if b.motion
            .as_ref()
            .is_some_and(|m| m.kind != MotionKind::Rapid)
        {
            return b.modal.plane;
        }
    }
    start
}

/// Adds one piece from `from` to `to` (along `curve`, sampled) to the polyline in `line`,
/// which is flushed to `to` first when the piece does not start where it ends.
fn piece(
    to: &mut Vec<Vec<[f64; 2]>>,
    line: &mut Vec<[f64; 2]>,
    (a, o): (usize, usize),
    curve: Option<Curve>,
    from: Pos,
    end: Pos,
) {
    let p0 = [from[a], from[o]];
    if line.last() != Some(&p0) {
        flush(to, line);
        line.push(p0);
    }
    for p in curve.into_iter().flat_map(|c| c.interior(FINE)) {
        line.push([p[a], p[o]]);
    }
    line.push([end[a], end[o]]);
}

fn flush(to: &mut Vec<Vec<[f64; 2]>>, line: &mut Vec<[f64; 2]>) {
    if line.len() >= 2 {
        to.push(std::mem::take(line));
    }
    line.clear();
}

/// Keeps every k-th point (and each line's ends) when there are too many.
fn thin(lines: &mut [Vec<[f64; 2]>]) {
    let total: usize = lines.iter().map(Vec::len).sum();
    if total <= MAX_POINTS {
        return;
    }
    let k = total.div_ceil(MAX_POINTS);
    for l in lines.iter_mut() {
        let last = l.len() - 1;
        let kept: Vec<[f64; 2]> = l
            .iter()
            .enumerate()
            .filter(|(i, _)| i % k == 0 || *i == last)
            .map(|(_, p)| *p)
            .collect();
        *l = kept;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turned_part_is_drawn_in_its_zx_plane() {
        // G18: Z is the abscissa, X the ordinate (840C machine data: X as a radius value).
        // D1 has radius 10 in the built-in table; G42 on the outside of the part while
        // turning towards the chuck puts the tool centre 10 mm above the contour in X.
        let text = "N10 G18 G90 G0 X50 Z10 D1\nN20 G1 G42 X20 Z0 F100\nN30 Z-10\nN40 X30 Z-20\nN50 G40 G0 X50 Z10\nM30\n";
        let md = MachineData::load(None, &[]).unwrap();
        let p = plot("t.mpf", text, &md, &ToolTable::builtin());
        assert_eq!((p.axes, p.index), (["Z", "X"], [Some(2), Some(0)]));
        assert!(p.alarm.is_none(), "{:?}", p.alarm);
        assert_eq!(
            p.programmed,
            vec![vec![
                [10.0, 50.0],
                [0.0, 20.0],
                [-10.0, 20.0],
                [-20.0, 30.0]
            ]]
        );
        // Selection straight to N30's normal position (0, 30); N30's equidistant at X 30 up
        // to the inner corner with N40 (135°): Z −10 + 10·tan 22.5°; N40's end point moved
        // 10 mm along its right-hand normal (1, 1)/√2. The G0 deselection is not drawn.
        let h = 10.0 / 2f64.sqrt();
        let want = [
            [10.0, 50.0],
            [0.0, 30.0],
            [-10.0 + 10.0 * (std::f64::consts::PI / 8.0).tan(), 30.0],
            [-20.0 + h, 30.0 + h],
        ];
        assert_eq!(p.path.len(), 1);
        assert_eq!(p.path[0].len(), want.len());
        for (got, want) in p.path[0].iter().zip(want) {
            assert!((got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9);
        }
    }

    /// A program in G55 is drawn where the kernel's G55 puts it: its values per axis by
    /// letter from the kernel's table (here listed X Y Z), G54 untouched.
    #[test]
    fn the_kernels_work_offsets_move_the_picture() {
        let md = MachineData::load(None, &[]).unwrap();
        let mut m = WorkOffsetsMsg {
            count: 2,
            ..Default::default()
        };
        m.axes.names[..3].copy_from_slice(b"XYZ");
        m.axes.count = 3;
        let mut g55 = [0.0; softnc_protocol::MAX_AXES];
        g55[..3].copy_from_slice(&[100.0, -20.0, 5.0]);
        m.entries[0] = softnc_protocol::WorkOffsetEntry::new("G54", Default::default());
        m.entries[1] = softnc_protocol::WorkOffsetEntry::new("G55", g55);
        let mut shifted = md.clone();
        shifted.work_offsets = work_offsets(&m, &md);
        assert_eq!(shifted.work_offsets.get(2)[..3], [100.0, -20.0, 5.0]);
        assert!(shifted.work_offsets.get(1).iter().all(|v| *v == 0.0));
        let text = "N10 G55 G0 X0 Y0\nN20 G1 X10 F100\nM30\n";
        let p = plot("t.mpf", text, &shifted, &ToolTable::builtin());
        assert_eq!(p.programmed, vec![vec![[100.0, -20.0], [110.0, -20.0]]]);
    }

    /// A lathe (X and Z): Z is the second entry of its positions, and it has no Y.
    #[test]
    fn a_lathe_plots_z_and_x_at_their_wire_places() {
        let md = MachineData::from_toml_str(
            "dialect = \"siemens-808d\"\nmachine = \"turning\"\n[program]\ninitial_plane = \"zx\"\n\
             [axes.X]\nmax_velocity = 6000\nmax_acceleration = 1500\nmax_jerk = 3e4\n\
             [axes.Z]\nmax_velocity = 6000\nmax_acceleration = 1500\nmax_jerk = 3e4\n",
            "lathe.toml",
        )
        .unwrap();
        let p = empty(&md);
        assert_eq!((p.axes, p.index), (["Z", "X"], [Some(1), Some(0)]));
        assert_eq!(wire_index(&md, 1), None);
    }

    /// A lathe's roughing cycle as the kernel's preparation streams it, with the tool table
    /// as the kernel publishes it and the bridge reads it: the plot has every G71 pass of
    /// the Fanuc shaft sample as a cut of its own (rapids in between), ending where the
    /// tool tip does, and G70's finishing on the part's diameters.
    #[test]
    fn a_lathe_roughing_cycle_plots_every_pass_and_the_finishing() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let md = MachineData::load(Some(&root.join("config/fanuc-lathe.toml")), &[]).unwrap();
        let file = root.join("programs/fanuc-lathe/shaft_rough_finish.nc");
        let source = std::fs::read_to_string(file).unwrap();
        // The kernel's own table (config/tools.toml) through the wire: T0201 is T2 D1, nose
        // R 1.2, and T0101 T1 D1, R 0.8, both in cutting edge position 3 (tip P = nose
        // centre + (−R, −R)). Without the position the plot is the nose centre's: the Ø40
        // pass then ends at Z −48.0, the finishing R off the part.
        let wire = nc_runtime::tool_table_msg(&ToolTable::builtin(), 1, false);
        let tools = nc_runtime::tool_table(&wire);
        let p = plot("shaft_rough_finish.nc", &source, &md, &tools);
        assert_eq!(p.axes, ["Z", "X"]);
        assert!(p.alarm.is_none(), "{:?}", p.alarm);

        // G71 U2. from A (Z 2, X 22), shape moved by (W, U/2) = (0.1, 0.2), A' tip at X 6.2:
        // levels 20, 18 … 8. Each ends on the moved tip path of the G42 shape (worked out in
        // tests/lathe_samples.rs): 20 on the G40 ramp (−71.1, 19.2) … (−69.9, 22.2); 18 and 16
        // at the face Z −49 + 0.1 (16 where the fillet's tip circle, radius 4 − R about
        // (−46.1, 16), meets it); 14 on that circle; 12 on the taper's tip line; 10 on the
        // face at Z −20 + 0.1; 8 on the convex corner's circle, radius R about (−3.1, 7).
        let r: f64 = 1.2;
        let s26 = 26f64.sqrt();
        let (tz, tx) = (
            -20.0 + r * (1.0 / s26 - 1.0) + 0.1,
            11.0 + r * (5.0 / s26 - 1.0) + 0.2,
        );
        let want = [
            (20.0, -71.1 + r * 0.8 / 3.0),
            (18.0, -48.9),
            (16.0, -46.1 - (4.0 - r)),
            (14.0, -46.1 - ((4.0 - r).powi(2) - 4.0).sqrt()),
            (12.0, tz - 5.0 * (12.0 - tx)),
            (10.0, -19.9),
            (8.0, -3.1 + (r * r - 1.0).sqrt()),
        ];
        let cuts: Vec<&Vec<[f64; 2]>> = p
            .path
            .iter()
            .filter(|l| l.len() == 2 && l[0][0] == 2.0 && l[0][1] == l[1][1])
            .collect();
        assert_eq!(cuts.len(), want.len(), "{cuts:?}");
        for (c, (level, end)) in cuts.iter().zip(want) {
            assert!(
                (c[0][1] - level).abs() < 1e-9 && (c[1][0] - end).abs() < 1e-9,
                "cut {c:?}, by hand X{level} to Z{end}"
            );
        }

        // G70 (R 0.8 under G42): from its rapid approach to the tip's first point (Z 2 − R,
        // X 6) along the shape to the G40 ramp's end (Z −70, X 22), with the tip on the
        // diameters: Ø16 down to the face at Z −20, Ø26 to the fillet at −45 − R, Ø38 to
        // −70 − R.
        let finishing = p
            .path
            .iter()
            .find(|l| l[0] == [2.0 - 0.8, 6.0])
            .expect("G70's finishing");
        assert_eq!(finishing.last(), Some(&[-70.0, 22.0]));
        for corner in [[-20.0, 8.0], [-45.8, 13.0], [-70.8, 19.0]] {
            assert!(
                finishing
                    .iter()
                    .any(|q| (q[0] - corner[0]).abs() < 1e-9 && (q[1] - corner[1]).abs() < 1e-9),
                "the finishing passes {corner:?}"
            );
        }
    }
}
