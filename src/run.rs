//! `softnc run`: the control as three processes on this machine. Starts nc-kernel and
//! plc-sim (this executable in their roles, each in its own process group), loads and starts
//! the program over the command service, shows progress from the kernel's status, and at the
//! end prints a summary from plc-sim's trace and draws programmed contour, compensated path
//! and actual path. Ctrl-C: NC stop, the axes brake, the children end, the instance's shared
//! memory is removed.

use nc_kernel::Segment;
use nc_kernel::{MachineData, Preparation, ToolTable};
use nc_runtime::Failure;
use softnc_protocol::iceoryx2::prelude::ipc;
use softnc_protocol::{
    command, newest, receive_each, state, Command, Instance, KernelStatus, Reply,
};
use std::io::Write;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub struct RunOptions<'a> {
    pub name: &'a str,
    pub source: &'a str,
    pub program: &'a Path,
    pub md: &'a MachineData,
    pub tools: &'a ToolTable,
    pub tools_file: Option<&'a Path>,
    pub set: &'a [String],
    pub instance: Option<String>,
    pub trace: Option<PathBuf>,
    pub svg: Option<PathBuf>,
    pub plc_args: &'a [String],
    pub quiet: bool,
    /// Also start hmi-bridge (`Some(port)`; `None` in the port: machine data `hmi.port`),
    /// and keep the control up after the program's end until Ctrl-C.
    pub hmi: Option<Option<u16>>,
}

/// Temporary files of a run, removed when it ends.
struct Temp(Vec<PathBuf>);

impl Drop for Temp {
    fn drop(&mut self) {
        for p in &self.0 {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// Children that are killed if the run ends early (an error, a panic).
struct Children(Vec<(&'static str, Child)>);

impl Drop for Children {
    fn drop(&mut self) {
        for (_, c) in &mut self.0 {
            if let Ok(None) = c.try_wait() {
                let _ = c.kill();
                let _ = c.wait();
            }
        }
    }
}

fn signal(c: &Child, sig: i32) {
    // SAFETY: kill(2) on our own child's pid.
    unsafe {
        libc::kill(c.id() as i32, sig);
    }
}

fn wait_for(c: &mut Child, limit: Duration) -> Option<std::process::ExitStatus> {
    let t = Instant::now();
    loop {
        if let Ok(Some(s)) = c.try_wait() {
            return Some(s);
        }
        if t.elapsed() > limit {
            return None;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

struct Hmi {
    client: softnc_protocol::iceoryx2::port::client::Client<ipc::Service, Command, (), Reply, ()>,
    status: softnc_protocol::Sub<KernelStatus>,
    _node: softnc_protocol::iceoryx2::node::Node<ipc::Service>,
}

impl Hmi {
    /// Sends a command and waits for the kernel's reply (retrying while no kernel serves the
    /// commands yet), up to `limit`.
    fn ask(&self, c: Command, limit: Duration) -> Result<Reply, String> {
        let t = Instant::now();
        loop {
            if let Ok(pending) = self.client.send_copy(c) {
                let t1 = Instant::now();
                while t1.elapsed() < Duration::from_millis(500) {
                    if let Ok(Some(r)) = pending.receive() {
                        return Ok(*r.payload());
                    }
                    std::thread::sleep(Duration::from_millis(1));
                }
            }
            if t.elapsed() > limit {
                return Err("the kernel does not answer".into());
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

/// Runs the program on the control: `Ok` when it ran to its end; an alarm or Ctrl-C stop it
/// (the summary says so); a control that fails is an error.
pub fn run(o: RunOptions<'_>) -> Result<(), Failure> {
    match run_inner(o)? {
        true => Ok(()),
        false => Err(Failure::Reported),
    }
}

fn run_inner(o: RunOptions<'_>) -> Result<bool, String> {
    let instance_name = o
        .instance
        .clone()
        .unwrap_or_else(|| format!("run-{}", std::process::id()));
    let instance = Instance::new(&instance_name).map_err(|e| e.to_string())?;
    let (cleaned, _) = instance.cleanup_dead_nodes();
    if cleaned > 0 {
        eprintln!(
            "removed what {cleaned} crashed process(es) of instance '{instance_name}' left behind"
        );
    }
    if instance.alive_nodes() > 0 {
        return Err(format!(
            "instance '{instance_name}' is in use by running processes: choose another --instance"
        ));
    }
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this executable: {e}"))?;
    let tmp = std::env::temp_dir();
    let md_file = tmp.join(format!("softnc-{instance_name}-machine.toml"));
    let md_text = toml::to_string(o.md).map_err(|e| format!("machine data: {e}"))?;
    std::fs::write(&md_file, md_text).map_err(|e| format!("{}: {e}", md_file.display()))?;
    let mut temp = Temp(vec![md_file.clone()]);
    let trace = match &o.trace {
        Some(p) => p.clone(),
        None => {
            let p = tmp.join(format!("softnc-{instance_name}-trace.csv"));
            temp.0.push(p.clone());
            p
        }
    };
    let logs = [
        tmp.join(format!("softnc-{instance_name}-nc-kernel.log")),
        tmp.join(format!("softnc-{instance_name}-plc-sim.log")),
        tmp.join(format!("softnc-{instance_name}-hmi-bridge.log")),
    ];
    temp.0.extend(logs.iter().cloned());
    let log_of = |role: &str| match role {
        "nc-kernel" => &logs[0],
        "plc-sim" => &logs[1],
        _ => &logs[2],
    };

    let spawn = |role: &str, args: &[String], log: &Path| -> Result<Child, String> {
        let log = std::fs::File::create(log).map_err(|e| format!("{}: {e}", log.display()))?;
        std::process::Command::new(&exe)
            .arg(role)
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(log)
            // Its own process group: Ctrl-C reaches only this process, which stops the
            // children in order.
            .process_group(0)
            .spawn()
            .map_err(|e| format!("cannot start {role}: {e}"))
    };
    let mut kargs = vec![
        "--instance".to_string(),
        instance_name.clone(),
        "--machine".into(),
        md_file.display().to_string(),
    ];
    if let Some(t) = o.tools_file {
        kargs.extend(["--tools".into(), t.display().to_string()]);
    }
    for s in o.set {
        kargs.extend(["--set".into(), s.clone()]);
    }
    let mut pargs = vec![
        "--instance".to_string(),
        instance_name.clone(),
        "--machine".into(),
        md_file.display().to_string(),
        "--trace".into(),
        trace.display().to_string(),
    ];
    pargs.extend(o.plc_args.iter().cloned());
    let mut children = Children(Vec::new());
    children
        .0
        .push(("plc-sim", spawn("plc-sim", &pargs, &logs[1])?));
    children
        .0
        .push(("nc-kernel", spawn("nc-kernel", &kargs, &logs[0])?));
    let hmi_url = match o.hmi {
        None => None,
        Some(port) => {
            let mut bargs = vec![
                "--instance".to_string(),
                instance_name.clone(),
                "--machine".into(),
                md_file.display().to_string(),
            ];
            if let Some(p) = port {
                bargs.extend(["--port".into(), p.to_string()]);
            }
            // The page offers the programs beside this one.
            if let Some(dir) = std::fs::canonicalize(o.program)
                .ok()
                .and_then(|p| p.parent().map(Path::to_path_buf))
            {
                bargs.extend(["--programs".into(), dir.display().to_string()]);
            }
            let mut c = spawn("hmi-bridge", &bargs, &logs[2])?;
            let url = bridge_url(&mut c, &logs[2]);
            children.0.push(("hmi-bridge", c));
            let url = url?;
            eprintln!("HMI: {url}");
            Some(url)
        }
    };

    // Ctrl-C: NC stop; a second one ends the processes without waiting for the kernel.
    let interrupts = Arc::new(AtomicU32::new(0));
    {
        let i = interrupts.clone();
        let _ = ctrlc::set_handler(move || {
            i.fetch_add(1, Ordering::SeqCst);
        });
    }
    let interrupted = || interrupts.load(Ordering::SeqCst) > 0;

    let node = instance.node("softnc-run").map_err(|e| e.to_string())?;
    let hmi = Hmi {
        client: instance
            .commands(&node)
            .map_err(|e| e.to_string())?
            .client_builder()
            .create()
            .map_err(|e| format!("command client: {e:?}"))?,
        status: instance
            .status(&node)
            .map_err(|e| e.to_string())?
            .subscriber_builder()
            .create()
            .map_err(|e| format!("status subscriber: {e:?}"))?,
        _node: node,
    };
    let check_children = |children: &mut Children| -> Result<(), String> {
        for (role, c) in children.0.iter_mut() {
            if let Ok(Some(s)) = c.try_wait() {
                let log = std::fs::read_to_string(log_of(role)).unwrap_or_default();
                return Err(format!("{role} ended ({s}):\n{}", log.trim_end()));
            }
        }
        Ok(())
    };
    let path =
        std::fs::canonicalize(o.program).map_err(|e| format!("{}: {e}", o.program.display()))?;
    let t_start = Instant::now();
    let r = loop {
        check_children(&mut children)?;
        match hmi.ask(
            Command::new(command::LOAD).with_text(&path.display().to_string()),
            Duration::from_millis(600),
        ) {
            Ok(r) => break r,
            Err(_) if t_start.elapsed() < Duration::from_secs(20) => continue,
            Err(e) => return Err(e),
        }
    };
    if r.ok == 0 {
        return Err(format!("the kernel refused the program: {}", r.message()));
    }
    // NC start once plc-sim has been seen.
    let mut last = KernelStatus::default();
    let t0 = Instant::now();
    loop {
        check_children(&mut children)?;
        last = newest(&hmi.status).unwrap_or(last);
        if last.plc_alive != 0 {
            break;
        }
        if interrupted() {
            return Err("interrupted before NC start".into());
        }
        if t0.elapsed() > Duration::from_secs(20) {
            return Err("plc-sim did not come up".into());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let r = hmi.ask(Command::new(command::START), Duration::from_secs(5))?;
    if r.ok == 0 {
        return Err(format!("NC start refused: {}", r.message()));
    }

    let cycle_s = f64::from(o.md.ipo.cycle_us) * 1e-6;
    let mut watch = Watch::new(&o);
    let outcome = watch.run(&hmi, &mut children, &check_children, &interrupts, &mut last);
    let (first_cycle, alarm) = (watch.first_cycle, watch.alarm);
    if !o.quiet {
        eprintln!();
    }
    let end_cycle = last.cycle;
    let mut outcome = outcome;
    if let (Some(url), Ok(_), false) = (&hmi_url, &outcome, interrupted()) {
        // The operator carries on at the page (load, start, offsets) until Ctrl-C.
        eprintln!("the program ended; the control stays up for the HMI at {url}: Ctrl-C ends it");
        while !interrupted() {
            if let Err(e) = check_children(&mut children) {
                outcome = Err(e);
                break;
            }
            last = newest(&hmi.status).unwrap_or(last);
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    // Orderly end: the HMI first (no command arrives meanwhile), the kernel (it brakes if
    // the path moves and stops its setpoints), then plc-sim.
    let mut statuses = Vec::new();
    if let Some((_, c)) = children.0.iter_mut().find(|(r, _)| *r == "hmi-bridge") {
        signal(c, libc::SIGTERM);
        let s = wait_for(c, Duration::from_secs(10)).or_else(|| {
            let _ = c.kill();
            c.wait().ok()
        });
        statuses.push(("hmi-bridge", s));
    }
    let _ = hmi.ask(Command::new(command::SHUTDOWN), Duration::from_secs(2));
    for role in ["nc-kernel", "plc-sim"] {
        if let Some((_, c)) = children.0.iter_mut().find(|(r, _)| *r == role) {
            signal(c, libc::SIGTERM);
            let s = wait_for(c, Duration::from_secs(10)).or_else(|| {
                let _ = c.kill();
                c.wait().ok()
            });
            statuses.push((role, s));
        }
    }
    drop(hmi);
    let leftover = instance.remove_when_unused().map_err(|e| e.to_string())?;
    let kernel_log = std::fs::read_to_string(&logs[0]).unwrap_or_default();
    let plc_log = std::fs::read_to_string(&logs[1]).unwrap_or_default();
    let finished = outcome?;
    if hmi_url.is_some() {
        println!("with the HMI: the summary and the picture cover the whole session");
    }
    for l in kernel_log.lines().chain(plc_log.lines()) {
        if l.contains("alarm") || l.contains("error") {
            eprintln!("{l}");
        }
    }

    // The summary, from the trace.
    let rows = read_trace(&trace)?;
    let segments: Vec<Segment> = Preparation::new(o.name, o.source, o.md, o.tools)
        .map_while(Result::ok)
        .collect();
    let s = summarize(&rows);
    let blocks = nc_kernel::Interpreter::new(o.name, o.source, o.md, o.tools)
        .map_while(Result::ok)
        .count();
    let secs = first_cycle.map_or(0.0, |f| (end_cycle.saturating_sub(f)) as f64 * cycle_s);
    println!(
        "{}: {} in {secs:.2} s ({blocks} blocks, {} IPO cycles of {} µs)",
        o.name,
        if finished {
            "ran to its end".to_string()
        } else if alarm != 0 {
            format!("stopped with alarm {alarm}")
        } else {
            "stopped by the operator".to_string()
        },
        end_cycle.saturating_sub(first_cycle.unwrap_or(end_cycle)),
        o.md.ipo.cycle_us
    );
    println!(
        "max following error {:.4} mm (v/kv at {:.0} mm/min: {:.4} mm); actual path within {:.4} mm of the compensated path",
        s.max_following_error,
        s.max_v * 60.0,
        s.max_v / o.md.plc.kv,
        s.max_deviation
    );
    println!(
        "auxiliary functions: {} output, {} acknowledged by the PLC; setpoints: {} lost",
        last.aux_sent, last.aux_acked, s.lost
    );
    println!(
        "processes ended: {}; shared memory files left: {}",
        statuses
            .iter()
            .map(|(r, st)| format!("{r} {}", st.map_or("killed".into(), |s| s.to_string())))
            .collect::<Vec<_>>()
            .join(", "),
        leftover.len()
    );
    let svg_path = o.svg.clone().unwrap_or_else(|| {
        let stem = o
            .program
            .file_stem()
            .map_or("program".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.run.svg"))
    });
    let actual: Vec<[f64; 3]> = rows.iter().map(|r| r.actual).collect();
    let pic = crate::picture::Picture::new(o.name, o.source, o.md, o.tools, &segments, None)
        .with_actual(&actual);
    svg::save(&svg_path, &pic.render()).map_err(|e| format!("{}: {e}", svg_path.display()))?;
    println!("picture: {}", svg_path.display());
    drop(temp);
    Ok(finished)
}

/// How long the path may take to come to rest after NC stop before the run stops waiting
/// for the kernel (braking from top speed takes well under a second on every shipped
/// machine); plc-sim's watchdog brakes the axes of a kernel that is ended then.
const REST_AFTER_STOP: Duration = Duration::from_secs(10);
/// The kernel publishes its status every IPO cycle: silence this long means it hangs.
const STATUS_SILENCE: Duration = Duration::from_secs(3);

/// The program running: the progress line, the first alarm, Ctrl-C.
struct Watch {
    quiet: bool,
    total_lines: u32,
    /// The first cycle seen ACTIVE, and the first alarm.
    first_cycle: Option<u64>,
    alarm: u32,
    /// When NC stop was sent for Ctrl-C.
    stop_sent: Option<Instant>,
    shown: Instant,
    heard: Instant,
}

impl Watch {
    fn new(o: &RunOptions<'_>) -> Self {
        Watch {
            quiet: o.quiet,
            total_lines: o.source.lines().count().max(1) as u32,
            first_cycle: None,
            alarm: 0,
            stop_sent: None,
            shown: Instant::now() - Duration::from_secs(1),
            heard: Instant::now(),
        }
    }

    /// Follows the status until the program ends (`Ok(true)`), stops with an alarm or for
    /// Ctrl-C (`Ok(false)`), or the control fails: a child ends, the kernel falls silent,
    /// the path does not come to rest after NC stop, or a second Ctrl-C. Every way ends.
    fn run(
        &mut self,
        hmi: &Hmi,
        children: &mut Children,
        check_children: &dyn Fn(&mut Children) -> Result<(), String>,
        interrupts: &AtomicU32,
        last: &mut KernelStatus,
    ) -> Result<bool, String> {
        loop {
            check_children(children)?;
            receive_each(&hmi.status, |s| {
                *last = s;
                self.heard = Instant::now();
                if s.state == state::ACTIVE && self.first_cycle.is_none() {
                    self.first_cycle = Some(s.cycle);
                }
            });
            if self.heard.elapsed() > STATUS_SILENCE {
                return Err(format!(
                    "nc-kernel published no status for {} s: it hangs; ending the processes",
                    STATUS_SILENCE.as_secs()
                ));
            }
            if last.alarm != 0 && self.alarm == 0 {
                self.alarm = last.alarm;
                if !self.quiet {
                    eprintln!("\ralarm {} at line {}              ", last.alarm, last.line);
                }
            }
            self.interrupt(hmi, interrupts)?;
            self.progress(last);
            match last.state {
                state::END => return Ok(true),
                state::STOPPED if last.alarm != 0 || self.stop_sent.is_some() => return Ok(false),
                _ => {}
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Ctrl-C: NC stop once; an error when the path does not come to rest in time or a
    /// second Ctrl-C comes.
    fn interrupt(&mut self, hmi: &Hmi, interrupts: &AtomicU32) -> Result<(), String> {
        let n = interrupts.load(Ordering::SeqCst);
        match self.stop_sent {
            None if n > 0 => {
                self.stop_sent = Some(Instant::now());
                eprintln!("\rinterrupted: NC stop, the axes brake … (Ctrl-C again ends at once)");
                let _ = hmi.ask(Command::new(command::STOP), Duration::from_secs(2));
                Ok(())
            }
            Some(_) if n > 1 => Err("interrupted twice: ending the processes without waiting for the path to rest (plc-sim brakes the axes)".into()),
            Some(t) if t.elapsed() > REST_AFTER_STOP => Err(format!(
                "the path did not come to rest within {} s of NC stop: ending the processes (plc-sim brakes the axes)",
                REST_AFTER_STOP.as_secs()
            )),
            _ => Ok(()),
        }
    }

    fn progress(&mut self, last: &KernelStatus) {
        if self.quiet || self.shown.elapsed() <= Duration::from_millis(100) {
            return;
        }
        self.shown = Instant::now();
        let total = self.total_lines;
        let frac = (f64::from(last.line) / f64::from(total)).min(1.0);
        let n = (frac * 30.0) as usize;
        eprint!(
            "\r[{}{}] line {:>5}/{total}  {:<7}  X{:>9.3} Y{:>9.3} Z{:>9.3}  {:>7.0} mm/min",
            "#".repeat(n),
            " ".repeat(30 - n),
            last.line,
            state::name(last.state),
            last.pos[0],
            last.pos[1],
            last.pos[2],
            last.v_path * 60.0
        );
        let _ = std::io::stderr().flush();
    }
}

/// The page's address, from the bridge's first line (it may have taken any free port).
fn bridge_url(c: &mut Child, log: &Path) -> Result<String, String> {
    let t = Instant::now();
    loop {
        let text = std::fs::read_to_string(log).unwrap_or_default();
        if let Some(a) = hmi_bridge::address_in(&text) {
            return Ok(format!("http://{a}/"));
        }
        if let Ok(Some(s)) = c.try_wait() {
            return Err(format!("hmi-bridge ended ({s}):\n{}", text.trim_end()));
        }
        if t.elapsed() > Duration::from_secs(20) {
            return Err(format!("hmi-bridge did not come up:\n{}", text.trim_end()));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
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
