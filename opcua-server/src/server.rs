//! The server itself: a thread of its own with its own async runtime, the same whether it is
//! a process of its own (`softnc opcua`) or a guest in the HMI bridge's process, whose HTTP
//! side never waits on it. It reads the kernel through a bridge link it is given.

use crate::access::Access;
use crate::model;
use crate::space::{self, Identity, Space};
use hmi_bridge::link::{Link, Snapshot};
use opcua::server::node_manager::memory::{simple_node_manager_imports, SimpleNodeManager};
use opcua::server::{ServerBuilder, ServerHandle};
use std::net::{IpAddr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{RecvTimeoutError, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// How often the variables are written from the kernel's status.
const UPDATE_EVERY: Duration = Duration::from_millis(100);
/// A program file read for its block texts at most (larger ones show no text).
const MAX_PROGRAM_TEXT: u64 = 8 << 20;
/// How long the server may take to listen: with a password it makes its certificate first
/// (about 2 s in a debug build, more on a loaded machine).
const START_WAIT: Duration = Duration::from_secs(60);

/// A started server: where it listens, and its thread, which ends after `stop` is set (or
/// when the server fails; it sets `stop` then, so whoever shares the flag ends too).
pub struct Running {
    pub addr: SocketAddr,
    pub thread: JoinHandle<Result<(), String>>,
}

/// Starts the server in a thread of its own; returns once it listens (it has announced its
/// address on standard error), or why it could not.
pub fn start(
    access: Access,
    identity: Identity,
    link: Link,
    stop: Arc<AtomicBool>,
) -> Result<Running, String> {
    let (ready_tx, ready_rx) = std::sync::mpsc::sync_channel(1);
    let stop_at_end = stop.clone();
    let thread = std::thread::Builder::new()
        .name("opcua".into())
        .spawn(move || {
            let result = run(&access, &identity, link, stop_at_end.clone(), &ready_tx);
            if let Err(e) = &result {
                let _ = ready_tx.try_send(Err(e.clone()));
            }
            stop_at_end.store(true, Ordering::SeqCst);
            result
        })
        .map_err(|e| format!("cannot start the OPC UA server's thread: {e}"))?;
    match ready_rx.recv_timeout(START_WAIT) {
        Ok(Ok(addr)) => Ok(Running { addr, thread }),
        Ok(Err(e)) => {
            // Sent as the thread ends: nothing left to wait for.
            let _ = thread.join();
            Err(e)
        }
        Err(RecvTimeoutError::Timeout) => {
            // A server still starting sees the flag once it runs, and ends by itself.
            stop.store(true, Ordering::SeqCst);
            Err(format!(
                "the OPC UA server did not come up within {} s",
                START_WAIT.as_secs()
            ))
        }
        Err(RecvTimeoutError::Disconnected) => {
            let _ = thread.join();
            Err("the OPC UA server's thread ended before it listened".into())
        }
    }
}

/// The thread's work: the certificate folder, the runtime, the server until `stop`.
fn run(
    access: &Access,
    identity: &Identity,
    link: Link,
    stop: Arc<AtomicBool>,
    ready: &SyncSender<Result<SocketAddr, String>>,
) -> Result<(), String> {
    let pki = certificate_folder(&identity.serial)?;
    let result = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_name("opcua-io")
        .enable_all()
        .build()
        .map_err(|e| format!("cannot start the OPC UA runtime: {e}"))
        .and_then(|rt| rt.block_on(serve(access, identity, &pki, link, stop, ready)));
    let _ = std::fs::remove_dir_all(&pki);
    result
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

/// The host part of the endpoint URLs for `ip`: an IPv6 address in brackets (RFC 3986),
/// else `opc.tcp://::1:4840/` would read as host `:` and port `:1:4840`.
pub fn url_host(ip: IpAddr) -> String {
    match ip {
        IpAddr::V4(v4) => v4.to_string(),
        IpAddr::V6(v6) => format!("[{v6}]"),
    }
}

/// The server's configuration, listening on `bound`, before the access rules.
fn builder(identity: &Identity, pki: &Path, bound: SocketAddr) -> ServerBuilder {
    ServerBuilder::new()
        .application_name("softnc OPC UA server")
        .application_uri(format!("urn:softnc:{}", identity.serial))
        .product_uri("urn:softnc")
        .pki_dir(PathBuf::from(pki))
        .host(url_host(bound.ip()))
        .port(bound.port())
        .with_node_manager(simple_node_manager_imports(
            vec![Box::new(space::Namespaces)],
            "softnc",
        ))
}

/// Builds the server, announces its address and runs it until `stop`.
async fn serve(
    access: &Access,
    identity: &Identity,
    pki: &Path,
    link: Link,
    stop: Arc<AtomicBool>,
    ready: &SyncSender<Result<SocketAddr, String>>,
) -> Result<(), String> {
    let listener = tokio::net::TcpListener::bind(access.addr)
        .await
        .map_err(|e| format!("{}: {e}", access.addr))?;
    let bound = listener.local_addr().map_err(|e| e.to_string())?;
    let (server, handle) = access.configure(builder(identity, pki, bound)).build()?;
    let manager = handle
        .node_managers()
        .get_of_type::<SimpleNodeManager>()
        .ok_or("the server has no node manager for the machine")?;
    let space = Space::new(
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
    let _ = ready.try_send(Ok(bound));
    let updater = tokio::spawn(update(space, link, stop, handle));
    let result = server.run_with(listener).await;
    updater.abort();
    result
}

/// Writes the variables from the link's snapshot every [`UPDATE_EVERY`]; at `stop` it ends
/// the server.
async fn update(mut space: Space, link: Link, stop: Arc<AtomicBool>, server: ServerHandle) {
    let mut program = ProgramText::default();
    let mut tick = tokio::time::interval(UPDATE_EVERY);
    while !stop.load(Ordering::Relaxed) {
        tick.tick().await;
        let snap = link.snapshot();
        space.update(&program.values(&snap));
        space.update_tools(snap.tools.as_ref());
    }
    server.cancel();
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
    use super::*;
    use opcua::core::comms::url::{hostname_from_url, hostname_port_from_url};
    use opcua::server::{ServerEndpoint, ANONYMOUS_USER_TOKEN_ID};

    #[test]
    fn ipv6_hosts_in_brackets() {
        assert_eq!(url_host("10.0.0.5".parse().unwrap()), "10.0.0.5");
        assert_eq!(url_host("::1".parse().unwrap()), "[::1]");
        assert_eq!(url_host("fd00::2".parse().unwrap()), "[fd00::2]");
    }

    /// A server on an IPv6 address offers endpoints whose URL parses with that address as
    /// its host (the port is the listener's once the server runs: 0 before).
    #[test]
    fn ipv6_endpoint_urls() {
        let pki = std::env::temp_dir().join(format!("softnc-opcua-test-v6-{}", std::process::id()));
        let rt = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        let _inside = rt.enter();
        let identity = Identity {
            model: "softnc test".into(),
            serial: "mill".into(),
        };
        let bound: SocketAddr = "[fd00::2]:4841".parse().unwrap();
        let built = builder(&identity, &pki, bound)
            .discovery_urls(vec!["/".into()])
            .add_endpoint(
                "none",
                ServerEndpoint::new_none("/", &[ANONYMOUS_USER_TOKEN_ID.to_string()]),
            )
            .build();
        let _ = std::fs::remove_dir_all(&pki);
        let (_server, handle) = built.unwrap();
        let asked = "opc.tcp://[fd00::2]:4841/";
        let endpoints = handle.info().endpoints(&asked.into(), &None).unwrap();
        assert_eq!(endpoints.len(), 1);
        let url = endpoints[0].endpoint_url.as_ref();
        assert!(url.starts_with("opc.tcp://[fd00::2]:"), "{url}");
        let host = hostname_from_url(url).ok();
        assert_eq!(host.as_deref(), Some("[fd00::2]"), "{url}");
        assert_eq!(hostname_port_from_url(url, 4840).map(|(_, p)| p), Ok(0));
    }
}
