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

/// Following error (the linear axes' together in mm, each rotary axis's alone in degrees),
/// and the actual path's distance from the setpoint polyline in X Y Z (the setpoints lie on
/// the compensated path; between two of them the chord is within (v·T)²/8r of it), searched
/// within ±2000 rows of the actual point's row. `rotary[n]`: the trace's axis n is rotary.
pub fn summarize(trace: &Trace, rotary: &[bool]) -> Summary {
    let rows = &trace.rows;
    let rotary_at = |n: usize| rotary.get(n).copied().unwrap_or(false);
    let mut s = Summary {
        max_following_error: 0.0,
        max_deviation: 0.0,
        max_v: 0.0,
        lost: lost(rows),
        rotary: (0..trace.axes.len())
            .filter(|&n| rotary_at(n))
            .map(|n| (trace.axes[n], 0.0))
            .collect(),
    };
    for (i, r) in rows.iter().enumerate() {
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
        let (lo, hi) = (i.saturating_sub(2000), (i + 2000).min(rows.len() - 1));
        let at = |j: usize| trace.xyz(&rows[j].setpoint);
        let p = trace.xyz(&r.actual);
        // The last index pairs with itself: a point, which also covers a one-row trace.
        let best = (lo..=hi)
            .map(|j| point_segment(p, at(j), at((j + 1).min(hi))))
            .fold(f64::INFINITY, f64::min);
        s.max_deviation = s.max_deviation.max(best);
    }
    s
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
