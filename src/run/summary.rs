//! `softnc run` after the control has ended: the summary from plc-sim's trace and the
//! kernel's last status, and the picture of programmed contour, compensated path and actual
//! path.

use super::RunOptions;
use nc_kernel::cycle::ChannelAlarm;
use nc_kernel::{Interpreter, Preparation, Segment};
use softnc_protocol::KernelStatus;
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
    pub files_left: usize,
    pub trace: &'a Path,
}

/// Prints the summary and writes the picture.
pub(super) fn report(o: &RunOptions<'_>, s: &Session<'_>) -> Result<(), String> {
    let rows = read_trace(s.trace)?;
    let t = summarize(&rows);
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
    println!(
        "auxiliary functions: {} output, {} acknowledged by the PLC; setpoints: {} lost",
        s.last.aux_sent, s.last.aux_acked, t.lost
    );
    let ended: Vec<String> = s
        .ended
        .iter()
        .map(|(r, st)| format!("{r} {}", st.map_or("killed".into(), |s| s.to_string())))
        .collect();
    println!(
        "processes ended: {}; shared memory files left: {}",
        ended.join(", "),
        s.files_left
    );
    picture(o, &rows)
}

/// The picture: programmed contour, compensated path and the actual path from the trace.
fn picture(o: &RunOptions<'_>, rows: &[Row]) -> Result<(), String> {
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
    let actual: Vec<[f64; 3]> = rows.iter().map(|r| r.actual).collect();
    let pic = crate::picture::Picture::new(o.name, o.source, o.md, o.tools, &segments, None)
        .with_actual(&actual);
    svg::save(&svg_path, &pic.render()).map_err(|e| format!("{}: {e}", svg_path.display()))?;
    println!("picture: {}", svg_path.display());
    Ok(())
}

/// One row of plc-sim's trace.
pub struct Row {
    pub setpoint: [f64; 3],
    pub actual: [f64; 3],
    pub following_error: [f64; 3],
    /// mm/s
    pub v_path: f64,
    pub seq: u64,
}

pub fn read_trace(path: &Path) -> Result<Vec<Row>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut rows = Vec::new();
    for (i, l) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let num = |k: usize| -> Result<f64, String> {
            f.get(k)
                .and_then(|x| x.parse::<f64>().ok())
                .ok_or_else(|| format!("{}: line {}: field {k} unreadable", path.display(), i + 1))
        };
        rows.push(Row {
            seq: num(2)? as u64,
            setpoint: [num(3)?, num(4)?, num(5)?],
            actual: [num(6)?, num(7)?, num(8)?],
            following_error: [num(9)?, num(10)?, num(11)?],
            v_path: num(12)? / 60.0,
        });
    }
    Ok(rows)
}

pub struct Summary {
    pub max_following_error: f64,
    pub max_deviation: f64,
    pub max_v: f64,
    pub lost: u64,
}

/// Following error, and the actual path's distance from the setpoint polyline (the setpoints
/// lie on the compensated path; between two of them the chord is within (v·T)²/8r of it),
/// searched within ±2000 rows of the actual point's row.
pub fn summarize(rows: &[Row]) -> Summary {
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let mut s = Summary {
        max_following_error: 0.0,
        max_deviation: 0.0,
        max_v: 0.0,
        lost: 0,
    };
    let mut last_seq = None;
    for r in rows {
        if r.seq == 0 {
            continue; // a watchdog row
        }
        if let Some(l) = last_seq {
            if r.seq > l + 1 {
                s.lost += r.seq - l - 1;
            }
        }
        last_seq = Some(r.seq);
    }
    for (i, r) in rows.iter().enumerate() {
        s.max_following_error = s.max_following_error.max(norm(r.following_error));
        s.max_v = s.max_v.max(r.v_path);
        let (lo, hi) = (i.saturating_sub(2000), (i + 2000).min(rows.len() - 1));
        // The last index pairs with itself: a point, which also covers a one-row trace.
        let best = (lo..=hi)
            .map(|j| point_segment(r.actual, rows[j].setpoint, rows[(j + 1).min(hi)].setpoint))
            .fold(f64::INFINITY, f64::min);
        s.max_deviation = s.max_deviation.max(best);
    }
    s
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Distance from `p` to the segment `a`–`b`.
pub fn point_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
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
