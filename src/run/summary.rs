//! `softnc run` after the control has ended: the summary from plc-sim's trace and the
//! kernel's last status, and the picture of programmed contour, compensated path and actual
//! path.

use super::RunOptions;
use nc_kernel::cycle::ChannelAlarm;
use nc_kernel::{AxisKind, Interpreter, MachineData, Pos, Preparation, Segment};
use softnc_protocol::{KernelStatus, Released, User, MAX_AXES, MAX_SPINDLES};
use std::path::{Path, PathBuf};
use std::process::ExitStatus;

/// What the run saw of the control.
pub(super) struct Session<'a> {
    /// The program ran to its end (else an alarm or the operator stopped it).
    pub finished: bool,
    /// The first cycle seen ACTIVE and the cycle when the program stopped or ended.
    pub first_cycle: Option<u64>,
    pub end_cycle: u64,
    pub alarm: Option<ChannelAlarm>,
    /// The kernel's last status (after an HMI session, at its end).
    pub last: KernelStatus,
    /// How each process ended (`None`: killed).
    pub ended: &'a [(&'static str, Option<ExitStatus>)],
    /// What the run left of its instance: nothing, or what clients still attached hold.
    pub released: &'a Released,
    pub instance: &'a str,
    pub trace: &'a Path,
}

/// Prints the summary and writes the picture.
pub(super) fn report(o: &RunOptions<'_>, s: &Session<'_>) -> Result<(), String> {
    let trace = read_trace(s.trace)?;
    let rotary: Vec<bool> = trace.axes.iter().map(|&c| is_rotary(o.md, c)).collect();
    let t = summarize(&trace, &rotary);
    let blocks = Interpreter::new(o.name, o.source, o.md, o.tools)
        .map_while(Result::ok)
        .count();
    let cycle_s = f64::from(o.md.ipo.cycle_us) * 1e-6;
    let cycles = s
        .end_cycle
        .saturating_sub(s.first_cycle.unwrap_or(s.end_cycle));
    let secs = s.first_cycle.map_or(0.0, |_| cycles as f64 * cycle_s);
    let how = match (s.finished, s.alarm) {
        (true, _) => "ran to its end".to_string(),
        (false, Some(a)) => format!("stopped with alarm {a}"),
        (false, None) => "stopped by the operator".to_string(),
    };
    println!(
        "{}: {how} in {secs:.2} s ({blocks} blocks, {cycles} IPO cycles of {} µs)",
        o.name, o.md.ipo.cycle_us
    );
    println!(
        "max following error {:.4} mm (v/kv at {:.0} mm/min: {:.4} mm); actual path within {:.4} mm of the compensated path",
        t.max_following_error,
        t.max_v * 60.0,
        t.max_v / o.md.plc.kv,
        t.max_deviation
    );
    if !t.rotary.is_empty() {
        let each: Vec<String> = t
            .rotary
            .iter()
            .map(|(c, e)| format!("{c} {e:.4}°"))
            .collect();
        println!("rotary axes: max following error {}", each.join(", "));
    }
    println!(
        "auxiliary functions: {} output, {} acknowledged by the PLC; setpoints: {} lost",
        s.last.aux_sent, s.last.aux_acked, t.lost
    );
    let ended: Vec<String> = s
        .ended
        .iter()
        .map(|(r, st)| format!("{r} {}", st.map_or("killed".into(), |s| s.to_string())))
        .collect();
    let whose = if s.released.users.is_empty() {
        ""
    } else {
        " (in use by the clients below)"
    };
    println!(
        "processes ended: {}; shared memory files left: {}{whose}",
        ended.join(", "),
        s.released.files.len()
    );
    if !s.released.users.is_empty() {
        // Not an error: a client of the instance holds its own part until it lets go.
        println!(
            "still attached to the instance, not started by this run: {}; what they hold is theirs \
             (`softnc clean --instance {}` once they have ended removes the rest)",
            User::list(&s.released.users),
            s.instance
        );
    }
    picture(o, &trace)
}

/// Whether the machine's axis `name` is a rotary axis (degrees).
fn is_rotary(md: &MachineData, name: char) -> bool {
    u8::try_from(name)
        .ok()
        .and_then(|l| md.axes.of_letter(l))
        .and_then(|i| md.axes.get(i))
        .is_some_and(|a| a.kind == AxisKind::Rotary)
}

/// The picture: programmed contour, compensated path and the actual path from the trace.
fn picture(o: &RunOptions<'_>, trace: &Trace) -> Result<(), String> {
    let svg_path = o.svg.clone().unwrap_or_else(|| {
        let stem = o
            .program
            .file_stem()
            .map_or("program".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.run.svg"))
    });
    let segments: Vec<Segment> = Preparation::new(o.name, o.source, o.md, o.tools)
        .map_while(Result::ok)
        .collect();
    let actual: Vec<Pos> = trace.rows.iter().map(|r| trace.xyz(&r.actual)).collect();
    let pic = crate::picture::Picture::new(o.name, o.source, o.md, o.tools, &segments, None)
        .with_actual(&actual);
    svg::save(&svg_path, &pic.render()).map_err(|e| format!("{}: {e}", svg_path.display()))?;
    println!("picture: {}", svg_path.display());
    Ok(())
}

/// Positions of every axis of a trace, in its order.
pub type Axes = [f64; MAX_AXES];

/// One row of plc-sim's trace.
pub struct Row {
    pub setpoint: Axes,
    pub actual: Axes,
    pub following_error: Axes,
    /// mm/s
    pub v_path: f64,
    pub seq: u64,
}

/// plc-sim's trace: its axes (in the order of every row's positions) and its rows.
pub struct Trace {
    pub axes: Vec<char>,
    /// Where X, Y and Z are among the axes.
    geo: [Option<usize>; 3],
    pub rows: Vec<Row>,
}

impl Trace {
    /// X, Y and Z of `p` (0 for one the machine does not have, as the kernel keeps it).
    pub fn xyz(&self, p: &Axes) -> Pos {
        self.geo.map(|g| g.map_or(0.0, |n| p[n]))
    }
}

/// What a trace header names: the axes, in the order of every row's positions, and the
/// number of spindles.
#[derive(Debug, PartialEq)]
struct Header {
    axes: Vec<char>,
    spindles: usize,
}

/// The columns of a trace header: `time,cycle,seq`, the setpoints under the axes' letters,
/// the actual positions under `A` and the letter, the following errors under `F` and the
/// letter, per spindle i (from 1) its speed setpoint `Si` and actual speed `ASi`, then
/// `v_path,line,state,events`. Traces from before the spindle columns have none.
fn header_axes(header: &str) -> Option<Header> {
    let cols: Vec<&str> = header.split(',').collect();
    let fixed = cols.len() >= 7
        && cols[..3] == ["time", "cycle", "seq"]
        && cols[cols.len() - 4..] == ["v_path", "line", "state", "events"];
    if !fixed {
        return None;
    }
    let middle = &cols[3..cols.len() - 4];
    let spindles = middle.iter().filter(|c| c.starts_with('S')).count();
    let (axis_cols, spindle_cols) = middle.split_at(middle.len().checked_sub(2 * spindles)?);
    let named_spindles = (0..spindles).all(|i| {
        spindle_cols[2 * i] == format!("S{}", i + 1)
            && spindle_cols[2 * i + 1] == format!("AS{}", i + 1)
    });
    if !named_spindles || spindles > MAX_SPINDLES {
        return None;
    }
    let axes = axis_names(axis_cols)?;
    Some(Header { axes, spindles })
}

/// The axes of the axis columns: setpoints, actual positions (`A`), following errors (`F`).
fn axis_names(cols: &[&str]) -> Option<Vec<char>> {
    let n = cols.len() / 3;
    if cols.len() != 3 * n || n > MAX_AXES {
        return None;
    }
    let mut names = Vec::with_capacity(n);
    for i in 0..n {
        let mut c = cols[i].chars();
        let (Some(name), None) = (c.next(), c.next()) else {
            return None;
        };
        let named = |k: usize, prefix: char| {
            let mut c = cols[k].chars();
            c.next() == Some(prefix) && c.next() == Some(name) && c.next().is_none()
        };
        if !named(n + i, 'A') || !named(2 * n + i, 'F') {
            return None;
        }
        names.push(name);
    }
    Some(names)
}

pub fn read_trace(path: &Path) -> Result<Trace, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("");
    let Header { axes, spindles } = header_axes(header)
        .ok_or_else(|| format!("{}: not plc-sim's trace header: {header}", path.display()))?;
    let n = axes.len();
    // The path speed follows the axes' and the spindles' columns.
    let v_path = 3 + 3 * n + 2 * spindles;
    let geo = ['X', 'Y', 'Z'].map(|c| axes.iter().position(|&a| a == c));
    let mut rows = Vec::new();
    for (i, l) in lines.enumerate() {
        let f: Vec<&str> = l.splitn(v_path + 4, ',').collect();
        let num = |k: usize| -> Result<f64, String> {
            f.get(k)
                .and_then(|x| x.parse::<f64>().ok())
                .ok_or_else(|| format!("{}: line {}: field {k} unreadable", path.display(), i + 2))
        };
        let axes_from = |first: usize| -> Result<Axes, String> {
            let mut a = [0.0; MAX_AXES];
            for (k, x) in a.iter_mut().enumerate().take(n) {
                *x = num(first + k)?;
            }
            Ok(a)
        };
        rows.push(Row {
            seq: num(2)? as u64,
            setpoint: axes_from(3)?,
            actual: axes_from(3 + n)?,
            following_error: axes_from(3 + 2 * n)?,
            v_path: num(v_path)? / 60.0,
        });
    }
    Ok(Trace { axes, geo, rows })
}

pub struct Summary {
    /// Of the linear axes together, mm.
    pub max_following_error: f64,
    pub max_deviation: f64,
    pub max_v: f64,
    pub lost: u64,
    /// Each rotary axis's largest following error, degrees.
    pub rotary: Vec<(char, f64)>,
}

/// Rows either side of an actual point's row whose setpoints it is measured against: the
/// actual position lags its setpoint by the following error, well within this, and a wider
/// window would also find the passes that come back over the same place.
const WINDOW: usize = 2000;

/// Following error (the linear axes' together in mm, each rotary axis's alone in degrees),
/// and the actual path's distance from the setpoint polyline in X Y Z (the setpoints lie on
/// the compensated path; between two of them the chord is within (v·T)²/8r of it), searched
/// within ±[`WINDOW`] rows of the actual point's row. `rotary[n]`: the trace's axis n is rotary.
pub fn summarize(trace: &Trace, rotary: &[bool]) -> Summary {
    let rows = &trace.rows;
    let rotary_at = |n: usize| rotary.get(n).copied().unwrap_or(false);
    let mut s = Summary {
        max_following_error: 0.0,
        max_deviation: max_deviation(trace, WINDOW),
        max_v: 0.0,
        lost: lost(rows),
        rotary: (0..trace.axes.len())
            .filter(|&n| rotary_at(n))
            .map(|n| (trace.axes[n], 0.0))
            .collect(),
    };
    for r in rows {
        let mut linear = 0.0;
        let mut turning = s.rotary.iter_mut();
        for (n, e) in r.following_error.iter().enumerate().take(trace.axes.len()) {
            if !rotary_at(n) {
                linear += e * e;
            } else if let Some((_, max)) = turning.next() {
                *max = max.max(e.abs());
            }
        }
        s.max_following_error = s.max_following_error.max(linear.sqrt());
        s.max_v = s.max_v.max(r.v_path);
    }
    s
}

/// The largest distance of an actual point from the setpoint pieces within ±`window` rows
/// of its own row (the window's last setpoint counts as a point of its own, which also
/// covers a one-row trace).
fn max_deviation(trace: &Trace, window: usize) -> f64 {
    let rows = &trace.rows;
    let pieces = Pieces::new(rows.iter().map(|r| trace.xyz(&r.setpoint)).collect());
    let mut max = 0.0_f64;
    for (i, r) in rows.iter().enumerate() {
        let (lo, hi) = (i.saturating_sub(window), (i + window).min(rows.len() - 1));
        max = max.max(pieces.nearest(trace.xyz(&r.actual), lo, hi));
    }
    max
}

/// A box, as its lowest and highest corner.
type Bounds = [Pos; 2];

/// Nothing inside: its distance from any point is infinite.
const EMPTY: Bounds = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];

/// Rounding slack when a box is ruled out: it is passed over only when it lies farther
/// than the nearest piece found by more than this, so no piece that [`point_segment`]
/// measures nearer is missed and the answer is the plain search's to the bit.
const SLACK: f64 = 1e-9;

/// The setpoint polyline's pieces (piece j from point j to point j + 1) under a binary tree
/// of bounding boxes: the nearest piece of a window of rows is found by opening only the
/// boxes near the actual point instead of measuring every piece of the window.
struct Pieces {
    points: Vec<Pos>,
    /// Node 1 is the root, node k's children are 2k and 2k + 1; leaf `leaves + j` bounds
    /// piece j (empty past the last piece).
    boxes: Vec<Bounds>,
    leaves: usize,
}

impl Pieces {
    fn new(points: Vec<Pos>) -> Pieces {
        let n = points.len().saturating_sub(1);
        let leaves = n.next_power_of_two();
        let mut boxes = vec![EMPTY; 2 * leaves];
        for (j, w) in points.windows(2).enumerate() {
            boxes[leaves + j] = union(&[w[0], w[0]], &[w[1], w[1]]);
        }
        for k in (1..leaves).rev() {
            boxes[k] = union(&boxes[2 * k], &boxes[2 * k + 1]);
        }
        Pieces {
            points,
            boxes,
            leaves,
        }
    }

    /// The distance from `p` to the nearest piece j with `lo <= j < hi` and to point `hi`:
    /// the minimum [`point_segment`] gives over them.
    fn nearest(&self, p: Pos, lo: usize, hi: usize) -> f64 {
        let end = self.points[hi];
        let mut best = f64::INFINITY.min(point_segment(p, end, end));
        if lo < hi {
            self.descend(1, (0, self.leaves), p, (lo, hi), &mut best);
        }
        best
    }

    /// Searches node `k` (pieces `span.0 .. span.1`) for pieces of `window` nearer than
    /// `best`, nearer child first.
    fn descend(
        &self,
        k: usize,
        span: (usize, usize),
        p: Pos,
        window: (usize, usize),
        best: &mut f64,
    ) {
        if span.1 <= window.0 || span.0 >= window.1 || !self.may_hold(k, p, *best) {
            return;
        }
        if k >= self.leaves {
            let j = span.0;
            *best = best.min(point_segment(p, self.points[j], self.points[j + 1]));
            return;
        }
        let mid = (span.0 + span.1) / 2;
        let (near, far) = ((2 * k, (span.0, mid)), (2 * k + 1, (mid, span.1)));
        let (near, far) =
            if box_distance2(&self.boxes[far.0], p) < box_distance2(&self.boxes[near.0], p) {
                (far, near)
            } else {
                (near, far)
            };
        self.descend(near.0, near.1, p, window, best);
        self.descend(far.0, far.1, p, window, best);
    }

    /// Whether node `k`'s box may hold a piece nearer to `p` than `best`.
    fn may_hold(&self, k: usize, p: Pos, best: f64) -> bool {
        let bound = best + SLACK;
        box_distance2(&self.boxes[k], p) <= bound * bound
    }
}

fn union(a: &Bounds, b: &Bounds) -> Bounds {
    let mut u = *a;
    for n in 0..3 {
        u[0][n] = u[0][n].min(b[0][n]);
        u[1][n] = u[1][n].max(b[1][n]);
    }
    u
}

/// The squared distance from `p` to box `b` (0 inside it; `max` passes over a NaN
/// coordinate, so a box is never ruled out by one).
fn box_distance2(b: &Bounds, p: Pos) -> f64 {
    (0..3)
        .map(|n| {
            let d = (b[0][n] - p[n]).max(p[n] - b[1][n]).max(0.0);
            d * d
        })
        .sum()
}

/// Setpoints missing from the sequence (watchdog rows, seq 0, aside).
fn lost(rows: &[Row]) -> u64 {
    let mut lost = 0;
    let mut last_seq = None;
    for r in rows.iter().filter(|r| r.seq != 0) {
        if let Some(l) = last_seq.filter(|&l| r.seq > l + 1) {
            lost += r.seq - l - 1;
        }
        last_seq = Some(r.seq);
    }
    lost
}

fn sub(a: Pos, b: Pos) -> Pos {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: Pos, b: Pos) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Distance from `p` to the segment `a`–`b`.
pub fn point_segment(p: Pos, a: Pos, b: Pos) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    let t = if l2 > 0.0 {
        (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
    dot(sub(p, q), sub(p, q)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> PathBuf {
        let p = std::env::temp_dir().join(format!("softnc-summary-{}-{name}", std::process::id()));
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn a_lathe_trace_with_c_is_read_by_axis_name() {
        let p = write(
            "lathe.csv",
            "time,cycle,seq,X,Z,C,AX,AZ,AC,FX,FZ,FC,v_path,line,state,events
             0.001000,1,1,10,-5,370,9.7,-4.6,369,0.3,0.4,1,600,3,ACTIVE,
             0.002000,2,3,10,-5,371,10,-5,370.5,0,0,0.5,0,4,END,ack M5
",
        );
        let t = read_trace(&p).unwrap();
        let _ = std::fs::remove_file(&p);
        assert_eq!(t.axes, ['X', 'Z', 'C']);
        assert_eq!(t.xyz(&t.rows[0].setpoint), [10.0, 0.0, -5.0]);
        assert_eq!(t.xyz(&t.rows[1].actual), [10.0, 0.0, -5.0]);
        assert_eq!(t.rows[0].following_error[2], 1.0);
        assert_eq!(t.rows[0].v_path, 10.0);
        let s = summarize(&t, &[false, false, true]);
        assert!((s.max_following_error - 0.5).abs() < 1e-12);
        assert_eq!(s.rotary, [('C', 1.0)]);
        assert_eq!(s.lost, 1);
        assert!((s.max_deviation - 0.5).abs() < 1e-12, "{}", s.max_deviation);
    }

    /// A trace in the turning plane (X, Z) from setpoints and actual positions.
    fn lathe_trace(points: &[([f64; 2], [f64; 2])]) -> Trace {
        let axes = |p: [f64; 2]| {
            let mut a = [0.0; MAX_AXES];
            a[..2].copy_from_slice(&p);
            a
        };
        let rows = points
            .iter()
            .enumerate()
            .map(|(i, &(sp, act))| Row {
                setpoint: axes(sp),
                actual: axes(act),
                following_error: axes([sp[0] - act[0], sp[1] - act[1]]),
                v_path: 0.0,
                seq: i as u64 + 1,
            })
            .collect();
        Trace {
            axes: vec!['X', 'Z'],
            geo: [Some(0), None, Some(1)],
            rows,
        }
    }

    /// The search as it was first written: every piece of the window measured.
    fn every_piece_of_the_window(trace: &Trace, window: usize) -> f64 {
        let rows = &trace.rows;
        let mut max = 0.0_f64;
        for (i, r) in rows.iter().enumerate() {
            let (lo, hi) = (i.saturating_sub(window), (i + window).min(rows.len() - 1));
            let at = |j: usize| trace.xyz(&rows[j].setpoint);
            let p = trace.xyz(&r.actual);
            let best = (lo..=hi)
                .map(|j| point_segment(p, at(j), at((j + 1).min(hi))))
                .fold(f64::INFINITY, f64::min);
            max = max.max(best);
        }
        max
    }

    /// Two roughing passes 0.25 mm apart in X, the second more than a window's rows after
    /// the first: the first pass digs 0.3 mm below its setpoint once, and that is measured
    /// against its own pass, not against the second pass 0.05 mm away. The same answer as
    /// every piece of the window gives.
    #[test]
    fn the_deviation_is_measured_within_the_window_of_rows() {
        const ROWS: usize = 50;
        let mut points = Vec::new();
        let pass = |points: &mut Vec<_>, x: f64, dig: Option<usize>| {
            for k in 0..200 {
                let z = -0.3 * k as f64;
                let act = if dig == Some(k) { x - 0.3 } else { x };
                points.push(([x, z], [act, z + 0.01]));
            }
        };
        pass(&mut points, 20.0, Some(20));
        for k in 0..30 {
            let z = -60.0 + 2.0 * k as f64;
            points.push(([20.5, z], [20.5, z - 0.05]));
        }
        pass(&mut points, 19.75, None);
        let trace = lathe_trace(&points);
        let dev = max_deviation(&trace, ROWS);
        assert_eq!(dev, every_piece_of_the_window(&trace, ROWS));
        assert!((dev - 0.3).abs() < 1e-9, "{dev}");
        // Over the whole trace the dig would be 0.05 from the second pass.
        let at = |j: usize| trace.xyz(&trace.rows[j].setpoint);
        let dig = trace.xyz(&trace.rows[20].actual);
        let nearest = (0..trace.rows.len() - 1)
            .map(|j| point_segment(dig, at(j), at(j + 1)))
            .fold(f64::INFINITY, f64::min);
        assert!((nearest - 0.05).abs() < 1e-9, "{nearest}");
    }

    /// A path that winds back over itself many times, with rests (repeated setpoints) and
    /// an actual path wandering about it: the tree's answer is bit for bit the one of
    /// measuring every piece of the window, for the trace and for single rows.
    #[test]
    fn the_tree_finds_what_every_piece_of_the_window_finds() {
        let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let points: Vec<([f64; 2], [f64; 2])> = (0..3000)
            .map(|i| {
                let t = (i / 3) as f64 * 0.02; // every setpoint three times: rests
                let sp = [20.0 + 5.0 * (t * 0.7).sin(), 30.0 * (t * 0.31).cos()];
                (sp, [sp[0] + next(), sp[1] + next()])
            })
            .collect();
        let trace = lathe_trace(&points);
        for window in [40, 700] {
            assert_eq!(
                max_deviation(&trace, window),
                every_piece_of_the_window(&trace, window),
                "window {window}"
            );
        }
        let at = |j: usize| trace.xyz(&trace.rows[j].setpoint);
        let pieces = Pieces::new((0..trace.rows.len()).map(at).collect());
        let last = trace.rows.len() - 1;
        for i in (0..trace.rows.len()).step_by(7) {
            let p = trace.xyz(&trace.rows[i].actual);
            // Windows cut at the trace's ends, and a single point.
            for (lo, hi) in [(i.saturating_sub(WINDOW), (i + WINDOW).min(last)), (i, i)] {
                let every = (lo..=hi)
                    .map(|j| point_segment(p, at(j), at((j + 1).min(hi))))
                    .fold(f64::INFINITY, f64::min);
                assert_eq!(
                    pieces.nearest(p, lo, hi),
                    every,
                    "row {i}, rows {lo}..={hi}"
                );
            }
        }
    }

    #[test]
    fn a_header_that_is_not_plc_sims_is_refused() {
        for bad in [
            "time,cycle,seq,X,Y,AX,AY,FX,FZ,v_path,line,state,events",
            "time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,v_path,line,state",
            "",
            // Spindle columns out of their place, order or numbering, or too many.
            "time,cycle,seq,X,S1,AS1,AX,FX,v_path,line,state,events",
            "time,cycle,seq,X,AX,FX,AS1,S1,v_path,line,state,events",
            "time,cycle,seq,X,AX,FX,S2,AS2,v_path,line,state,events",
            "time,cycle,seq,X,AX,FX,S1,AS1,v_path,line,state,events,S2,AS2",
            "time,cycle,seq,X,AX,FX,S1,AS1,S2,AS2,S3,AS3,v_path,line,state,events",
        ] {
            assert_eq!(header_axes(bad), None, "{bad}");
        }
        assert_eq!(
            header_axes("time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,v_path,line,state,events")
                .map(|h| h.axes),
            Some(vec!['X', 'Y', 'Z'])
        );
    }

    #[test]
    fn spindle_columns_are_read_past_and_old_traces_have_none() {
        let h = |s| header_axes(s).map(|h| (h.axes, h.spindles));
        assert_eq!(
            h("time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,v_path,line,state,events"),
            Some((vec!['X', 'Y', 'Z'], 0))
        );
        assert_eq!(
            h("time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,S1,AS1,v_path,line,state,events"),
            Some((vec!['X', 'Y', 'Z'], 1))
        );
        assert_eq!(
            h("time,cycle,seq,X,Z,C,AX,AZ,AC,FX,FZ,FC,S1,AS1,S2,AS2,v_path,line,state,events"),
            Some((vec!['X', 'Z', 'C'], 2))
        );
        let p = write(
            "spindle.csv",
            "time,cycle,seq,X,Y,Z,AX,AY,AZ,FX,FY,FZ,S1,AS1,v_path,line,state,events
             0.001000,1,1,1,2,3,0.5,1.5,2.5,0.5,0.5,0.5,-1200,-996,600,3,ACTIVE,
             0.002000,2,2,1,2,3,1,2,3,0,0,0,-1200,-1002,0,4,ACTIVE,ack M4
",
        );
        let t = read_trace(&p).unwrap();
        let _ = std::fs::remove_file(&p);
        assert_eq!(t.axes, ['X', 'Y', 'Z']);
        assert_eq!(t.rows[0].following_error[..3], [0.5, 0.5, 0.5]);
        assert_eq!((t.rows[0].v_path, t.rows[1].v_path), (10.0, 0.0));
        assert_eq!(t.xyz(&t.rows[1].actual), [1.0, 2.0, 3.0]);
    }
}
