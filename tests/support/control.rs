//! The control's processes in tests: each test takes an instance of its own, starts
//! `softnc` in the roles it needs as children (killed when the test ends in any way),
//! reads plc-sim's trace, and leaves no shared memory behind.
#![allow(dead_code)] // each test file uses a different part

use softnc_protocol::Instance;
use std::path::{Path, PathBuf};
use std::process::{Child, Command as Proc, Stdio};

pub const EXE: &str = env!("CARGO_BIN_EXE_softnc");

/// What a `softnc run` printed, and how it ended.
pub struct RunOutput {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl RunOutput {
    pub fn success(&self) -> bool {
        self.code == Some(0)
    }

    /// Both streams, for assertion messages.
    pub fn said(&self) -> String {
        format!("{}\n{}", self.stdout, self.stderr)
    }
}

/// `softnc run PROGRAM --quiet --instance INST --trace TRACE ARGS…` from the repository
/// root.
pub fn softnc_run(program: &Path, inst: &str, trace: &Path, args: &[&str]) -> RunOutput {
    let out = Proc::new(EXE)
        .current_dir(root())
        .arg("run")
        .arg(program)
        .args(["--quiet", "--instance", inst, "--trace"])
        .arg(trace)
        .args(args)
        .output()
        .expect("softnc runs");
    RunOutput {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn instance(tag: &str) -> String {
    format!("t-{tag}-{}", std::process::id())
}

pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softnc-ipc-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// The test's instance, cleaned when the test ends in any way (declared before the
/// children, so it is dropped after they are killed): no run leaves shared memory behind.
///
/// A scope also takes one of `STATIONS` places: a kernel's IPO thread and plc-sim run
/// SCHED_FIFO, and more than two unoptimised controls at once on a 2-core machine leave the
/// kernels' control threads (normal priority) too little time to answer commands.
pub struct Scope(pub Instance, Option<Place>);

const STATIONS: usize = 2;

static PLACES: (std::sync::Mutex<usize>, std::sync::Condvar) =
    (std::sync::Mutex::new(0), std::sync::Condvar::new());

pub struct Place;

impl Place {
    fn take() -> Place {
        let mut n = PLACES.0.lock().unwrap_or_else(|e| e.into_inner());
        while *n >= STATIONS {
            n = PLACES.1.wait(n).unwrap_or_else(|e| e.into_inner());
        }
        *n += 1;
        Place
    }
}

impl Drop for Place {
    fn drop(&mut self) {
        let mut n = PLACES.0.lock().unwrap_or_else(|e| e.into_inner());
        *n -= 1;
        PLACES.1.notify_one();
    }
}

impl Scope {
    pub fn new(name: &str) -> Scope {
        Scope(Instance::new(name).unwrap(), Some(Place::take()))
    }

    /// For an instance without kernel and plc-sim (nothing real-time): no place taken.
    pub fn light(name: &str) -> Scope {
        Scope(Instance::new(name).unwrap(), None)
    }
}

impl Drop for Scope {
    fn drop(&mut self) {
        // A child killed a moment ago may still be seen half-gone by iceoryx2 (its dead
        // node's resources not yet removable): try again for a while before giving up.
        for _ in 0..50 {
            if self
                .0
                .remove_when_unused()
                .is_ok_and(|left| left.is_empty())
            {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
        eprintln!("{:?} left in shared memory", self.0.files());
    }
}

/// A child that is killed when the test ends in any way.
pub struct Kid(pub Child);

impl Drop for Kid {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

pub fn spawn(role: &str, args: &[&str], log: &Path) -> Kid {
    let log = std::fs::File::create(log).unwrap();
    Kid(Proc::new(EXE)
        .arg(role)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .unwrap())
}

/// A program that keeps the axes moving for about `seconds` at F3000 (50 mm/s).
pub fn long_program(seconds: f64) -> PathBuf {
    let mut text = String::from("N1 G0 X0 Y0 Z0\nN2 G1 F3000\n");
    let legs = (seconds * 50.0 / 100.0).ceil() as usize + 1;
    for i in 0..legs {
        let x = if i % 2 == 0 { 100 } else { 0 };
        text.push_str(&format!("N{} X{x} Y{}\n", 10 + i, i % 7));
    }
    text.push_str("M30\n");
    let p = scratch(&format!("long-{seconds}.mpf"));
    std::fs::write(&p, text).unwrap();
    p
}

/// A row of plc-sim's trace. `sp`, `act` and `fe` are X, Y and Z (0 for an axis the
/// machine does not have); `axes` has every configured axis.
pub struct TraceRow {
    /// plc-sim's clock when it drove the row's cycle, s.
    pub time: f64,
    pub cycle: u64,
    pub seq: u64,
    pub sp: [f64; 3],
    pub act: [f64; 3],
    pub fe: [f64; 3],
    /// Each configured axis in the machine's order: its name, then setpoint, actual
    /// position and following error.
    pub axes: Vec<(char, [f64; 3])>,
    /// Each spindle of the trace (S1, AS1, …): speed setpoint and actual speed, rev/min,
    /// signed (positive clockwise); empty for a trace from before the spindle columns.
    pub spindle: Vec<[f64; 2]>,
    /// Path speed, mm/s.
    pub v: f64,
    pub line: u32,
    pub state: String,
    pub events: String,
}

impl TraceRow {
    /// Setpoint, actual position and following error of axis `name`.
    pub fn axis(&self, name: char) -> Option<[f64; 3]> {
        self.axes.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }
}

/// The axes and the number of spindles of a trace header: `time,cycle,seq`, the setpoint
/// columns named after the axes, the same with `A` (actual) and `F` (following error) before
/// the name, per spindle i (from 1) `Si` (speed setpoint) and `ASi` (actual speed), then
/// `v_path,line,state,events`. A header from before the spindle columns has none.
fn trace_axes(header: &str) -> (Vec<char>, usize) {
    let cols: Vec<&str> = header.split(',').collect();
    let s = cols.iter().filter(|c| c.starts_with('S')).count();
    let n = cols.len().saturating_sub(7 + 2 * s) / 3;
    assert_eq!(cols.len(), 7 + 3 * n + 2 * s, "{header}");
    assert_eq!(&cols[..3], ["time", "cycle", "seq"], "{header}");
    assert_eq!(
        &cols[3 + 3 * n + 2 * s..],
        ["v_path", "line", "state", "events"],
        "{header}"
    );
    let names: Vec<char> = cols[3..3 + n]
        .iter()
        .map(|c| c.chars().next().unwrap())
        .collect();
    for (i, c) in names.iter().enumerate() {
        assert_eq!(cols[3 + n + i], format!("A{c}"), "{header}");
        assert_eq!(cols[3 + 2 * n + i], format!("F{c}"), "{header}");
    }
    for i in 0..s {
        assert_eq!(cols[3 + 3 * n + 2 * i], format!("S{}", i + 1), "{header}");
        assert_eq!(cols[4 + 3 * n + 2 * i], format!("AS{}", i + 1), "{header}");
    }
    (names, s)
}

pub fn trace(path: &Path) -> Vec<TraceRow> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let (names, s) = trace_axes(lines.next().unwrap_or(""));
    let n = names.len();
    lines
        .map(|l| {
            let f: Vec<&str> = l.splitn(3 * n + 2 * s + 7, ',').collect();
            let num = |k: usize| f[k].parse::<f64>().unwrap();
            let axes: Vec<(char, [f64; 3])> = names
                .iter()
                .enumerate()
                .map(|(i, &c)| (c, [num(3 + i), num(3 + n + i), num(3 + 2 * n + i)]))
                .collect();
            let xyz = |k: usize| {
                ['X', 'Y', 'Z'].map(|c| {
                    axes.iter()
                        .find(|(a, _)| *a == c)
                        .map_or(0.0, |(_, v)| v[k])
                })
            };
            let spindle = (0..s)
                .map(|i| [num(3 + 3 * n + 2 * i), num(4 + 3 * n + 2 * i)])
                .collect();
            let rest = 3 + 3 * n + 2 * s;
            TraceRow {
                time: num(0),
                cycle: f[1].parse().unwrap(),
                seq: f[2].parse().unwrap(),
                sp: xyz(0),
                act: xyz(1),
                fe: xyz(2),
                v: num(rest) / 60.0,
                line: f[rest + 1].parse().unwrap(),
                state: f[rest + 2].to_string(),
                events: f.get(rest + 3).unwrap_or(&"").to_string(),
                axes,
                spindle,
            }
        })
        .collect()
}

pub fn dist_to_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let l2 = ab.iter().map(|x| x * x).sum::<f64>();
    let t = if l2 > 0.0 {
        (ap.iter().zip(ab.iter()).map(|(x, y)| x * y).sum::<f64>() / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3)
        .map(|i| (p[i] - a[i] - t * ab[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

pub fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// SIGTERM: the process ends cleanly (plc-sim flushes its trace); waits for it.
pub fn terminate(kid: &mut Kid) {
    unsafe {
        libc::kill(kid.0.id() as i32, libc::SIGTERM);
    }
    kid.0.wait().unwrap();
}

/// A straight line from the origin along `axis` at F3000.
pub fn line_program(name: &str, axis: char, length: f64) -> PathBuf {
    let p = scratch(name);
    std::fs::write(
        &p,
        format!("N1 G0 X0 Y0 Z0\nN2 G1 F3000 {axis}{length}\nM30\n"),
    )
    .unwrap();
    p
}
