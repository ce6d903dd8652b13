//! `softnc run`: the control as three processes on this machine. Starts nc-kernel and
//! plc-sim (this executable in their roles, each in its own process group), loads and starts
//! the program over the command service, shows progress from the kernel's status
//! (watch.rs), and at the end prints a summary from plc-sim's trace and draws programmed
//! contour, compensated path and actual path (summary.rs). Ctrl-C: NC stop, the axes brake,
//! the children end, the instance's shared memory is removed.

mod summary;
mod watch;

use nc_kernel::{MachineData, ToolTable};
use nc_runtime::Failure;
use softnc_protocol::iceoryx2::prelude::ipc;
use softnc_protocol::{command, newest, Command, Instance, KernelStatus, Reply};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, ExitStatus, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use watch::Watch;

pub struct RunOptions<'a> {
    pub name: &'a str,
    pub source: &'a str,
    pub program: &'a Path,
    pub md: &'a MachineData,
    pub tools: &'a ToolTable,
    pub tools_file: Option<&'a Path>,
    /// The work-offset file nc-kernel reads and saves edits to.
    pub offsets_file: Option<&'a Path>,
    /// Kept macro variables: read and saved by the kernel.
    pub macro_variables_file: Option<&'a Path>,
    pub set: &'a [String],
    pub instance: Option<String>,
    pub trace: Option<PathBuf>,
    pub svg: Option<PathBuf>,
    pub plc_args: &'a [String],
    pub quiet: bool,
    /// Path override from NC start on, a fraction (1: 100 %).
    pub override_: f64,
    /// Also start hmi-bridge (`Some(port)`; `None` in the port: machine data `hmi.port`),
    /// and keep the control up after the program's end until Ctrl-C.
    pub hmi: Option<Option<u16>>,
    /// Also start the OPC UA server (`--opcua`, on 127.0.0.1 or `--opcua-listen` with a
    /// password); it ends with the run.
    pub opcua: softnc_opcua::ServerOptions,
    /// nc-kernel records its inputs to this file (and its setpoints to `setpoints`).
    pub record: Option<&'a Path>,
    pub setpoints: Option<&'a Path>,
}

/// The files of a run: the machine data the children read, plc-sim's trace and each
/// process's log. Those it made itself are removed when the run ends.
struct Files {
    machine: PathBuf,
    trace: PathBuf,
    /// nc-kernel's, plc-sim's, hmi-bridge's and the OPC UA server's.
    logs: [PathBuf; 4],
    temp: Vec<PathBuf>,
}

impl Files {
    fn new(o: &RunOptions<'_>, instance: &str) -> Result<Files, String> {
        let tmp = std::env::temp_dir();
        let at = |what: &str| tmp.join(format!("softnc-{instance}-{what}"));
        let machine = at("machine.toml");
        let text = toml::to_string(o.md).map_err(|e| format!("machine data: {e}"))?;
        std::fs::write(&machine, text).map_err(|e| format!("{}: {e}", machine.display()))?;
        let mut temp = vec![machine.clone()];
        let trace = o.trace.clone().unwrap_or_else(|| {
            temp.push(at("trace.csv"));
            at("trace.csv")
        });
        let logs = ["nc-kernel", "plc-sim", "hmi-bridge", "opcua"].map(|r| at(&format!("{r}.log")));
        temp.extend(logs.iter().cloned());
        Ok(Files {
            machine,
            trace,
            logs,
            temp,
        })
    }

    fn log(&self, role: &str) -> &Path {
        match role {
            "nc-kernel" => &self.logs[0],
            "plc-sim" => &self.logs[1],
            "hmi-bridge" => &self.logs[2],
            _ => &self.logs[3],
        }
    }

    /// What the kernel and plc-sim said about alarms and errors.
    fn echo_alarms(&self) {
        for f in &self.logs[..2] {
            let text = std::fs::read_to_string(f).unwrap_or_default();
            for l in text.lines() {
                if l.contains("alarm") || l.contains("error") {
                    eprintln!("{l}");
                }
            }
        }
    }
}

impl Drop for Files {
    fn drop(&mut self) {
        for p in &self.temp {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// The run's processes, by role.
struct Children(Vec<(&'static str, Child)>);

impl Children {
    /// Ends every one still running at once: SIGTERM (a process that ends by it leaves
    /// nothing in shared memory, one killed while it opens its services may), and SIGKILL
    /// for what has not ended after `grace`.
    fn stop_all(&mut self, grace: Duration) {
        for (_, c) in &mut self.0 {
            if let Ok(None) = c.try_wait() {
                terminate(c);
            }
        }
        let t = Instant::now();
        for (_, c) in &mut self.0 {
            while let Ok(None) = c.try_wait() {
                if t.elapsed() > grace {
                    let _ = c.kill();
                    let _ = c.wait();
                    break;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
        }
    }

    /// Ends `role` with SIGTERM, killing it after 10 s; how it ended (`None`: no status).
    fn end(&mut self, role: &'static str) -> Option<(&'static str, Option<ExitStatus>)> {
        let (_, c) = self.0.iter_mut().find(|(r, _)| *r == role)?;
        terminate(c);
        let t = Instant::now();
        let status = loop {
            if let Ok(Some(s)) = c.try_wait() {
                break Some(s);
            }
            if t.elapsed() > Duration::from_secs(10) {
                let _ = c.kill();
                break c.wait().ok();
            }
            std::thread::sleep(Duration::from_millis(10));
        };
        Some((role, status))
    }
}

fn terminate(c: &Child) {
    nc_runtime::os::terminate(c.id());
}

/// The run's side of the kernel, as an HMI's: commands and status.
struct Hmi {
    client: softnc_protocol::iceoryx2::port::client::Client<ipc::Service, Command, (), Reply, ()>,
    status: softnc_protocol::Sub<KernelStatus>,
    _node: softnc_protocol::iceoryx2::node::Node<ipc::Service>,
}

impl Hmi {
    fn connect(instance: &Instance) -> Result<Hmi, String> {
        let node = instance.node("softnc-run").map_err(|e| e.to_string())?;
        let client = instance.commands(&node).map_err(|e| e.to_string())?;
        let status = instance.status(&node).map_err(|e| e.to_string())?;
        Ok(Hmi {
            client: client
                .client_builder()
                .create()
                .map_err(|e| format!("command client: {e:?}"))?,
            status: status
                .subscriber_builder()
                .create()
                .map_err(|e| format!("status subscriber: {e:?}"))?,
            _node: node,
        })
    }

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
    let name = o
        .instance
        .clone()
        .unwrap_or_else(|| format!("run-{}", std::process::id()));
    // The server's address and password are checked before anything starts.
    o.opcua.access()?;
    let instance = claim(&name)?;
    let files = Files::new(&o, &name)?;
    let mut run = Supervisor {
        o: &o,
        instance,
        children: Children(Vec::new()),
        files,
        interrupts: Arc::new(AtomicU32::new(0)),
    };
    let hmi_url = run.spawn()?;
    run.on_interrupt();
    let hmi = Hmi::connect(&run.instance)?;
    let mut last = run.load_and_start(&hmi)?;
    let mut watch = Watch::new(o.source, o.quiet);
    let mut outcome = watch.run(&hmi, &mut run, &mut last);
    if !o.quiet {
        eprintln!();
    }
    let end_cycle = last.cycle;
    if let (Some(url), Ok(_)) = (&hmi_url, &outcome) {
        if run.interrupts() == 0 {
            outcome = run.stay_for_hmi(&hmi, url, &mut last).and(outcome);
        }
    }
    let ended = run.shut_down(&hmi);
    drop(hmi);
    let released = run.instance.release();
    let finished = outcome?;
    if hmi_url.is_some() {
        println!("with the HMI: the summary and the picture cover the whole session");
    }
    run.files.echo_alarms();
    let session = summary::Session {
        finished,
        first_cycle: watch.first_cycle,
        end_cycle,
        alarm: watch.alarm,
        last,
        ended: &ended,
        released: &released,
        instance: &name,
        trace: &run.files.trace,
    };
    summary::report(&o, &session)?;
    if finished {
        Ok(())
    } else {
        Err(Failure::Reported)
    }
}

/// The instance for the run, which no other control may be using: what crashed processes of
/// it left is removed first. Clients of other parties may be attached already (a subscriber
/// waiting for the setpoints): they use the instance, they do not run it.
fn claim(name: &str) -> Result<Instance, String> {
    let instance = Instance::new(name).map_err(|e| e.to_string())?;
    let (cleaned, _) = instance.cleanup_dead_nodes();
    if cleaned > 0 {
        eprintln!("removed what {cleaned} crashed process(es) of instance '{name}' left behind");
    }
    let control: Vec<_> = instance
        .users()
        .into_iter()
        .filter(|u| u.is_softnc())
        .collect();
    if !control.is_empty() {
        return Err(format!(
            "instance '{name}' is in use by running processes ({}): choose another --instance",
            softnc_protocol::User::list(&control)
        ));
    }
    Ok(instance)
}

/// A run of the control: its instance, files and processes, and the operator's Ctrl-C.
struct Supervisor<'a> {
    o: &'a RunOptions<'a>,
    instance: Instance,
    // Before the files: the logs are removed after the children have ended.
    children: Children,
    files: Files,
    interrupts: Arc<AtomicU32>,
}

impl Drop for Supervisor<'_> {
    fn drop(&mut self) {
        // A run that gives up on the control (an error, a panic) ends its processes here,
        // and takes what they left in shared memory with them (after an orderly end there is
        // nothing left).
        self.children.stop_all(Duration::from_secs(2));
        let _ = self.instance.release();
    }
}

impl Supervisor<'_> {
    /// Starts plc-sim and nc-kernel, and hmi-bridge if asked for: the page's address then.
    fn spawn(&mut self) -> Result<Option<String>, String> {
        let o = self.o;
        let mut common = vec![
            "--instance".to_string(),
            self.instance.name().to_string(),
            "--machine".into(),
            self.files.machine.display().to_string(),
        ];
        let mut plc = common.clone();
        plc.extend(["--trace".into(), self.files.trace.display().to_string()]);
        plc.extend(o.plc_args.iter().cloned());
        self.start("plc-sim", &plc)?;
        let mut kernel = common.clone();
        if let Some(t) = o.tools_file {
            kernel.extend(["--tools".into(), t.display().to_string()]);
        }
        for s in o.set {
            kernel.extend(["--set".into(), s.clone()]);
        }
        if let Some(f) = o.offsets_file {
            kernel.extend(["--offsets".into(), f.display().to_string()]);
        }
        if let Some(f) = o.macro_variables_file {
            kernel.extend(["--macro-variables".into(), f.display().to_string()]);
        }
        if let Some(f) = o.record {
            kernel.extend(["--record".into(), f.display().to_string()]);
        }
        if let Some(f) = o.setpoints {
            kernel.extend(["--setpoints".into(), f.display().to_string()]);
        }
        self.start("nc-kernel", &kernel)?;
        if let Some(port) = o.opcua.opcua {
            self.start_opcua(&common, port)?;
        }
        let Some(port) = o.hmi else {
            return Ok(None);
        };
        if let Some(p) = port {
            common.extend(["--port".into(), p.to_string()]);
        }
        // The page offers the programs beside this one.
        if let Some(dir) = std::fs::canonicalize(o.program)
            .ok()
            .and_then(|p| p.parent().map(Path::to_path_buf))
        {
            common.extend(["--programs".into(), dir.display().to_string()]);
        }
        self.start("hmi-bridge", &common)?;
        let url = format!(
            "http://{}/",
            self.announced("hmi-bridge", hmi_bridge::address_in)?
        );
        eprintln!("HMI: {url}");
        Ok(Some(url))
    }

    /// `softnc opcua` with the run's OPC UA options; the password goes in its environment,
    /// not in its arguments, which every user of the machine can list.
    fn start_opcua(&mut self, common: &[String], port: u16) -> Result<(), String> {
        let options = &self.o.opcua;
        let mut args = common.to_vec();
        args.extend(["--port".into(), port.to_string()]);
        args.extend(["--user".into(), options.user().to_string()]);
        if let Some(listen) = &options.opcua_listen {
            args.extend(["--listen".into(), listen.clone()]);
        }
        let password = options.password().unwrap_or_default();
        let env = [(softnc_opcua::PASSWORD_VARIABLE, password.as_str())];
        self.start_with("opcua", &args, &env)?;
        let addr = self.announced("opcua", softnc_opcua::address_in)?;
        eprintln!("OPC UA: opc.tcp://{addr}/");
        Ok(())
    }

    /// This executable in `role`, its stderr to the role's log.
    fn start(&mut self, role: &'static str, args: &[String]) -> Result<(), String> {
        self.start_with(role, args, &[])
    }

    /// `start`, with these variables in the child's environment.
    fn start_with(
        &mut self,
        role: &'static str,
        args: &[String],
        env: &[(&str, &str)],
    ) -> Result<(), String> {
        let exe =
            std::env::current_exe().map_err(|e| format!("cannot find this executable: {e}"))?;
        let path = self.files.log(role);
        let log = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let child = std::process::Command::new(exe)
            .arg(role)
            .args(args)
            .envs(env.iter().copied())
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(log)
            // Its own process group: Ctrl-C reaches only this process, which stops the
            // children in order.
            .process_group(0)
            .spawn()
            .map_err(|e| format!("cannot start {role}: {e}"))?;
        self.children.0.push((role, child));
        Ok(())
    }

    /// The `host:port` a server of the run announces on its first line (it may have taken
    /// any free port): the bridge's page, the OPC UA server's endpoint.
    fn announced(
        &mut self,
        role: &'static str,
        address_in: fn(&str) -> Option<&str>,
    ) -> Result<String, String> {
        let t = Instant::now();
        let log = self.files.log(role).to_path_buf();
        loop {
            let text = std::fs::read_to_string(&log).unwrap_or_default();
            if let Some(a) = address_in(&text) {
                return Ok(a.to_string());
            }
            if let Some((_, c)) = self.children.0.iter_mut().find(|(r, _)| *r == role) {
                if let Ok(Some(s)) = c.try_wait() {
                    return Err(format!("{role} ended ({s}):\n{}", text.trim_end()));
                }
            }
            // The OPC UA server with a password makes its certificate first: an RSA key,
            // seconds in a debug build on a busy machine.
            let limit = Duration::from_secs(if role == "opcua" { 60 } else { 20 });
            if t.elapsed() > limit {
                return Err(format!("{role} did not come up:\n{}", text.trim_end()));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Ctrl-C: NC stop; a second one ends the processes without waiting for the kernel.
    fn on_interrupt(&self) {
        let i = self.interrupts.clone();
        let _ = ctrlc::set_handler(move || {
            i.fetch_add(1, Ordering::SeqCst);
        });
    }

    fn interrupts(&self) -> u32 {
        self.interrupts.load(Ordering::SeqCst)
    }

    /// An error naming the first child that has ended, with its log.
    fn check_children(&mut self) -> Result<(), String> {
        for (role, c) in self.children.0.iter_mut() {
            if let Ok(Some(s)) = c.try_wait() {
                let log = std::fs::read_to_string(self.files.log(role)).unwrap_or_default();
                return Err(format!("{role} ended ({s}):\n{}", log.trim_end()));
            }
        }
        Ok(())
    }

    /// Loads the program (once the kernel answers), then gives NC start once plc-sim has
    /// been seen: the kernel's last status.
    fn load_and_start(&mut self, hmi: &Hmi) -> Result<KernelStatus, Failure> {
        let program = self.o.program;
        let path =
            std::fs::canonicalize(program).map_err(|e| format!("{}: {e}", program.display()))?;
        let load = Command::new(command::LOAD).with_text(&path.display().to_string());
        let t = Instant::now();
        let r = loop {
            self.check_children()?;
            match hmi.ask(load, Duration::from_millis(600)) {
                Ok(r) => break r,
                Err(_) if t.elapsed() < Duration::from_secs(20) => continue,
                Err(e) => return Err(e.into()),
            }
        };
        if r.ok == 0 {
            let why = format!("the kernel refused the program: {}", r.message());
            // Refused with an alarm (the whole-program check): the program's fault.
            return Err(if r.alarm != 0 {
                Failure::Failed(why)
            } else {
                Failure::Error(why)
            });
        }
        let mut last = KernelStatus::default();
        let t = Instant::now();
        loop {
            self.check_children()?;
            last = newest(&hmi.status).unwrap_or(last);
            if last.plc_alive != 0 {
                break;
            }
            if self.interrupts() > 0 {
                return Err("interrupted before NC start".into());
            }
            if t.elapsed() > Duration::from_secs(20) {
                return Err("plc-sim did not come up".into());
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        if self.o.override_ != 1.0 {
            let mut c = Command::new(command::OVERRIDE);
            c.value = self.o.override_;
            let r = hmi.ask(c, Duration::from_secs(5))?;
            if r.ok == 0 {
                return Err(format!("override refused: {}", r.message()).into());
            }
        }
        let r = hmi.ask(Command::new(command::START), Duration::from_secs(5))?;
        if r.ok == 0 {
            return Err(format!("NC start refused: {}", r.message()).into());
        }
        Ok(last)
    }

    /// After the program's end the operator carries on at the page (load, start, offsets)
    /// until Ctrl-C.
    fn stay_for_hmi(
        &mut self,
        hmi: &Hmi,
        url: &str,
        last: &mut KernelStatus,
    ) -> Result<(), String> {
        eprintln!("the program ended; the control stays up for the HMI at {url}: Ctrl-C ends it");
        while self.interrupts() == 0 {
            self.check_children()?;
            *last = newest(&hmi.status).unwrap_or(*last);
            std::thread::sleep(Duration::from_millis(20));
        }
        Ok(())
    }

    /// The orderly end: the HMI and the OPC UA server first (no command arrives meanwhile),
    /// the kernel (it brakes if the path moves and stops its setpoints), then plc-sim. How
    /// each ended.
    fn shut_down(&mut self, hmi: &Hmi) -> Vec<(&'static str, Option<ExitStatus>)> {
        let mut ended: Vec<_> = self.children.end("hmi-bridge").into_iter().collect();
        ended.extend(self.children.end("opcua"));
        let _ = hmi.ask(Command::new(command::SHUTDOWN), Duration::from_secs(2));
        ended.extend(self.children.end("nc-kernel"));
        ended.extend(self.children.end("plc-sim"));
        ended
    }
}
