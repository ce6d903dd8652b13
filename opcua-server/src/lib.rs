//! softnc's OPC UA server (docs/opcua.md): the OPC 40501-1 machine-tool model subset —
//! Identification, Monitoring (channel, spindle), Production (active program), Notification
//! (alarms), Equipment (tools) — over what the kernel publishes, read through the HMI
//! bridge's link (one thread owns the iceoryx2 ports; the kernel is never waited for). It
//! listens on 127.0.0.1 and takes anonymous clients there; another address needs a user
//! and password, and then only those are taken.

mod access;
mod model;
mod space;

pub use access::{Access, DEFAULT_PORT, DEFAULT_USER};
pub use space::{MACHINE_TOOL_NS, SOFTNC_NS};

use hmi_bridge::link::{Link, Snapshot};
use nc_runtime::process::args::{machine, ControlArgs};
use nc_runtime::Failure;
use opcua::server::node_manager::memory::{simple_node_manager_imports, SimpleNodeManager};
use opcua::server::ServerBuilder;
use space::{Identity, Space};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// How often the variables are written from the kernel's status.
const UPDATE_EVERY: Duration = Duration::from_millis(100);
/// A program file read for its block texts at most (larger ones show no text).
const MAX_PROGRAM_TEXT: u64 = 8 << 20;

/// softnc's OPC UA server: the OPC 40501-1 machine-tool model subset, read-only
/// (docs/opcua.md). It listens on 127.0.0.1 and takes anonymous clients; another address
/// needs --password, and then only the user with it is taken.
#[derive(clap::Parser, Debug)]
#[command(name = "opcua")]
pub struct OpcuaArgs {
    #[command(flatten)]
    pub control: ControlArgs,
    /// The TCP port (0: any free one, printed).
    #[arg(long, value_name = "PORT", default_value_t = DEFAULT_PORT)]
    pub port: u16,
    /// Listen on another address than 127.0.0.1; needs --password.
    #[arg(long, value_name = "ADDRESS[:PORT]")]
    pub listen: Option<String>,
    /// The user name clients log in with on another address.
    #[arg(long, value_name = "NAME", default_value = DEFAULT_USER)]
    pub user: String,
    /// The password, at least 12 characters (or the environment variable
    /// SOFTNC_OPCUA_PASSWORD).
    #[arg(long, value_name = "PASSWORD")]
    pub password: Option<String>,
}

/// The `host:port` in a log the server wrote: it announces `opc.tcp://HOST:PORT/` on its
/// first line; `None` until the address is written in full (up to its `/`).
pub fn address_in(log: &str) -> Option<&str> {
    let (addr, _) = log.split("opc.tcp://").nth(1)?.split_once('/')?;
    Some(addr)
}

/// The OPC UA server process: until SIGINT or SIGTERM.
pub fn main(args: OpcuaArgs) -> Result<(), Failure> {
    let password = args
        .password
        .or_else(|| std::env::var("SOFTNC_OPCUA_PASSWORD").ok());
    let access = Access::new(args.listen.as_deref(), args.port, &args.user, password)?;
    let instance = args.control.instance;
    let md = machine(args.control.machine.as_deref())?;
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst))
            .map_err(|e| format!("cannot install the signal handler: {e}"))?;
    }
    let pki = certificate_folder(instance.name())?;
    let identity = Identity {
        model: format!("softnc {} {}", md.dialect.as_str(), machine_kind(&md)),
        serial: instance.name().to_string(),
    };
    let (link, link_thread) =
        match hmi_bridge::link::start(instance.clone(), "opcua", |_| String::new(), stop.clone()) {
            Ok(l) => l,
            Err(e) => {
                let _ = std::fs::remove_dir_all(&pki);
                return Err(Failure::Error(e));
            }
        };
    let result = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| format!("cannot start the runtime: {e}"))
        .and_then(|rt| rt.block_on(serve(&access, &identity, &pki, link, stop.clone())));
    stop.store(true, Ordering::SeqCst);
    let _ = link_thread.join();
    let _ = std::fs::remove_dir_all(&pki);
    result.map_err(Failure::Error)
}

/// The server's certificate store: a folder of its own per process, only the user's
/// (the key to the password's encryption is made in it at start), removed at the end.
fn certificate_folder(instance: &str) -> Result<PathBuf, String> {
    use std::os::unix::fs::DirBuilderExt;
    let pki = std::env::temp_dir().join(format!(
        "softnc-opcua-{instance}-{}-pki",
        std::process::id()
    ));
    // A folder of that name left by a crashed server of an earlier process is not trusted.
    let _ = std::fs::remove_dir_all(&pki);
    std::fs::DirBuilder::new()
        .mode(0o700)
        .create(&pki)
        .map_err(|e| format!("{}: {e}", pki.display()))?;
    Ok(pki)
}

fn machine_kind(md: &nc_kernel::MachineData) -> &'static str {
    match md.machine {
        nc_kernel::MachineKind::Milling => "milling machine",
        nc_kernel::MachineKind::Turning => "lathe",
    }
}

/// Builds the server, announces its address and runs it until `stop`.
async fn serve(
    access: &Access,
    identity: &Identity,
    pki: &std::path::Path,
    link: Link,
    stop: Arc<AtomicBool>,
) -> Result<(), String> {
    let listener = tokio::net::TcpListener::bind(access.addr)
        .await
        .map_err(|e| format!("{}: {e}", access.addr))?;
    let bound = listener.local_addr().map_err(|e| e.to_string())?;
    let builder = ServerBuilder::new()
        .application_name("softnc OPC UA server")
        .application_uri(format!("urn:softnc:{}", identity.serial))
        .product_uri("urn:softnc")
        .pki_dir(PathBuf::from(pki))
        .host(bound.ip().to_string())
        .port(bound.port())
        .with_node_manager(simple_node_manager_imports(
            vec![Box::new(space::Namespaces)],
            "softnc",
        ));
    let (server, handle) = access.configure(builder).build()?;
    let manager = handle
        .node_managers()
        .get_of_type::<SimpleNodeManager>()
        .ok_or("the server has no node manager for the machine")?;
    let mut space = Space::new(
        manager,
        handle.subscriptions().clone(),
        &identity.serial,
        identity,
    )?;
    eprintln!(
        "opcua: instance '{}': opc.tcp://{bound}/ {}",
        identity.serial,
        access.describe()
    );
    let cancel = handle.clone();
    let updater = tokio::spawn(async move {
        let mut program = ProgramText::default();
        let mut tick = tokio::time::interval(UPDATE_EVERY);
        while !stop.load(Ordering::Relaxed) {
            tick.tick().await;
            let snap = link.snapshot();
            space.update(&program.values(&snap));
            space.update_tools(snap.tools.as_ref());
        }
        cancel.cancel();
    });
    let result = server.run_with(listener).await;
    updater.abort();
    result
}

/// The loaded program's text, read once per program for the running line's text, and
/// whether it has been seen running.
#[derive(Default)]
struct ProgramText {
    program: u32,
    path: Option<String>,
    text: String,
    started: bool,
}

impl ProgramText {
    fn values(&mut self, snap: &Snapshot) -> model::Values {
        let st = snap.status.unwrap_or_default();
        if st.program != self.program || snap.program_path != self.path {
            self.program = st.program;
            self.path = snap.program_path.clone();
            self.text = self.path.as_deref().map(read_program).unwrap_or_default();
            self.started = false;
        }
        self.started |= st.state == softnc_protocol::state::ACTIVE;
        let block = model::line_text(&self.text, st.line);
        model::Values::new(snap, block, self.started)
    }
}

/// A program's text; empty when it cannot be read or is too large to show.
fn read_program(path: &str) -> String {
    match std::fs::metadata(path) {
        Ok(m) if m.len() <= MAX_PROGRAM_TEXT => std::fs::read(path)
            .map(|b| String::from_utf8_lossy(&b).into_owned())
            .unwrap_or_default(),
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn address_only_when_written_in_full() {
        let line = "opcua: instance 'a': opc.tcp://127.0.0.1:4841/ (anonymous)\n";
        assert_eq!(super::address_in(line), Some("127.0.0.1:4841"));
        for cut in 0..line.find(":4841/").unwrap() + 6 {
            assert_eq!(super::address_in(&line[..cut]), None, "{}", &line[..cut]);
        }
    }
}
