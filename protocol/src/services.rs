//! The iceoryx2 services of one softnc instance, opened the same way by every process.
//!
//! ```text
//!  nc-kernel ──setpoints (pub-sub, every cycle) + setpoints.event──► plc-sim
//!  nc-kernel ──aux (request-response: AuxRequest → AuxAck)─────────► plc-sim
//!  nc-kernel ◄─plc.signals (pub-sub: feed hold, read-in disable, drives ready, E-stop)── plc-sim
//!  anyone    ◄─plc.actuals (pub-sub)── plc-sim        anyone ◄─status (pub-sub)── nc-kernel
//!  HMI, softnc ──commands (request-response: Command → Reply)──► nc-kernel
//! ```
//!
//! Service names live under the instance name (`<instance>/setpoints`), and every file
//! iceoryx2 makes carries the prefix `softnc_<instance>_`: two instances, or a test and a
//! running machine, never see each other. Every service carries the attribute `softnc.abi`:
//! a peer built from a different protocol is refused by name when it opens a service.
//! Publishers never block: a slow subscriber loses its oldest samples (hence the sequence
//! numbers in the payloads).

use crate::payload::*;
use iceoryx2::config::Config;
use iceoryx2::node::{Node, NodeBuilder, NodeView};
use iceoryx2::prelude::*;
use iceoryx2::service::attribute::{AttributeKey, AttributeValue};
use iceoryx2::service::port_factory::{event, publish_subscribe, request_response};
use std::fmt;
use std::path::PathBuf;

/// Version of the protocol; with the payloads' layouts it makes the ABI string.
/// 2: `Command::t` (offsets of T/D tables); 5: `ToolEntry::cutting_edge`.
pub const PROTOCOL_VERSION: u32 = 5;
pub const ABI_KEY: &str = "softnc.abi";

/// The default instance; tests and side-by-side machines take their own.
pub const DEFAULT_INSTANCE: &str = "softnc";

pub type PubSub<T> = publish_subscribe::PortFactory<ipc::Service, T, ()>;
pub type ReqRes<Q, A> = request_response::PortFactory<ipc::Service, Q, (), A, ()>;
pub type Events = event::PortFactory<ipc::Service>;
/// A subscriber to one of an instance's publish-subscribe services.
pub type Sub<T> = iceoryx2::port::subscriber::Subscriber<ipc::Service, T, ()>;

/// Hands every sample that arrived since the last call to `f`, oldest first. A receive
/// error ends the round like an empty queue: the next call tries again.
pub fn receive_each<T: ZeroCopySend + fmt::Debug + Copy>(sub: &Sub<T>, mut f: impl FnMut(T)) {
    while let Ok(Some(s)) = sub.receive() {
        f(*s.payload());
    }
}

/// The newest sample that arrived since the last call, if any (the older ones are passed
/// over).
pub fn newest<T: ZeroCopySend + fmt::Debug + Copy>(sub: &Sub<T>) -> Option<T> {
    let mut last = None;
    receive_each(sub, |s| last = Some(s));
    last
}

/// This build's ABI: the protocol version and a hash over every payload's name, size and
/// alignment.
pub fn abi() -> String {
    // FNV-1a: stable across builds and platforms, unlike std's hasher.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for (name, size, align) in layouts() {
        for b in format!("{name}:{size}:{align};").bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("softnc-ipc/{PROTOCOL_VERSION}/{h:016x}")
}

/// Node names of softnc's own processes. A client of another party names its node anything
/// else: it is a user of the instance, not a part of the control.
pub const ROLES: [&str; 5] = [
    "nc-kernel",
    "nc-kernel-hmi",
    "plc-sim",
    "hmi-bridge",
    "softnc-run",
];

/// A process alive on an instance, as iceoryx2 lists its node.
#[derive(Clone, Debug, PartialEq)]
pub struct User {
    /// The node's name: the role for softnc's processes ([`ROLES`]).
    pub name: String,
    pub pid: i32,
}

impl User {
    /// One of softnc's own processes (else a client of another party).
    pub fn is_softnc(&self) -> bool {
        ROLES.contains(&self.name.as_str())
    }

    /// `name (pid N), …` for messages.
    pub fn list(users: &[User]) -> String {
        let each: Vec<String> = users
            .iter()
            .map(|u| format!("{} (pid {})", u.name, u.pid))
            .collect();
        each.join(", ")
    }
}

/// What [`Instance::release`] left.
#[derive(Debug)]
pub struct Released {
    /// The instance's files still there: none unless `users` is not empty.
    pub files: Vec<PathBuf>,
    /// Processes still attached (clients of other parties, once softnc's have ended).
    pub users: Vec<User>,
}

/// Why a service could not be opened, for the user.
#[derive(Debug)]
pub struct IpcError(pub String);

impl fmt::Display for IpcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for IpcError {}

/// One softnc instance: its name, its iceoryx2 configuration and the ABI it speaks.
#[derive(Clone)]
pub struct Instance {
    name: String,
    config: Config,
    abi: String,
}

impl fmt::Debug for Instance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Instance({})", self.name)
    }
}

impl Instance {
    pub fn new(name: &str) -> Result<Self, IpcError> {
        Self::with_abi(name, &abi())
    }

    /// An instance that speaks another ABI: what a peer built from another protocol looks
    /// like (tests).
    pub fn with_abi(name: &str, abi: &str) -> Result<Self, IpcError> {
        let valid = !name.is_empty()
            && name.len() <= 48
            && name
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
        if !valid {
            return Err(IpcError(format!(
                "instance name '{name}': use 1 to 48 letters, digits, '-' or '_'"
            )));
        }
        // Built here rather than read from a file: iceoryx2 would otherwise look for
        // ./config/iceoryx2.toml, which in this repository is the machine data folder.
        let mut config = Config::default();
        config.global.prefix = FileName::new(Self::prefix_of(name).as_bytes())
            .map_err(|e| IpcError(format!("instance name '{name}': {e:?}")))?;
        Ok(Instance {
            name: name.to_string(),
            config,
            abi: abi.to_string(),
        })
    }

    fn prefix_of(name: &str) -> String {
        format!("softnc_{name}_")
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn abi(&self) -> &str {
        &self.abi
    }

    /// The instance's iceoryx2 configuration (the default with the instance's prefix): what a
    /// client of another party opens the services with.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// A node for one process (`role`: "nc-kernel", "plc-sim", …). Signals are left to the
    /// process. Nodes of processes that died are cleaned up first, so a crashed run leaves
    /// nothing behind for the next start.
    pub fn node(&self, role: &str) -> Result<Node<ipc::Service>, IpcError> {
        let name = NodeName::new(role).map_err(|e| IpcError(format!("node name {role}: {e:?}")))?;
        let node = NodeBuilder::new()
            .name(&name)
            .config(&self.config)
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .map_err(|e| {
                IpcError(format!(
                    "{}: cannot create the {role} node: {e:?}",
                    self.name
                ))
            })?;
        node.try_cleanup_dead_nodes();
        Ok(node)
    }

    /// Removes what dead processes of this instance left: (cleaned, failed).
    pub fn cleanup_dead_nodes(&self) -> (u64, u64) {
        let mut cleaned = 0;
        let mut failed = 0;
        let _ = Node::<ipc::Service>::list(&self.config, |state| {
            if let NodeState::Dead(view) = state {
                match view.try_remove_stale_resources() {
                    Ok(_) => cleaned += 1,
                    Err(_) => failed += 1,
                }
            }
            CallbackProgression::Continue
        });
        (cleaned, failed)
    }

    /// Processes of this instance that are alive.
    pub fn alive_nodes(&self) -> usize {
        self.users().len()
    }

    /// The processes alive on this instance: each node's name and process id.
    pub fn users(&self) -> Vec<User> {
        let mut out = Vec::new();
        let _ = Node::<ipc::Service>::list(&self.config, |state| {
            if let NodeState::Alive(view) = state {
                out.push(match view.details() {
                    Some(d) => User {
                        name: d.name().to_string(),
                        pid: d.process_id().value(),
                    },
                    None => User {
                        name: String::new(),
                        pid: 0,
                    },
                });
            }
            CallbackProgression::Continue
        });
        out
    }

    /// For the owner of a private instance, after its processes have ended: removes what
    /// dead ones left and iceoryx2's per-instance node counter (a 16-byte segment iceoryx2
    /// keeps on purpose). Returns the files still there (none, normally). Does nothing while
    /// a process of the instance is alive.
    pub fn remove_when_unused(&self) -> Result<Vec<PathBuf>, IpcError> {
        let released = self.release();
        if !released.users.is_empty() {
            return Err(IpcError(format!(
                "{}: {} process(es) still use the instance: {}",
                self.name,
                released.users.len(),
                User::list(&released.users)
            )));
        }
        Ok(released.files)
    }

    /// For the owner of a private instance, after its own processes have ended: removes what
    /// dead processes left, and the node counter once no process uses the instance. A client
    /// of another party (a subscriber in Python, a HIL rig) may still be attached: what it
    /// holds is its own — iceoryx2 removes each service when the last process using it lets
    /// go — and the counter is left to it (`softnc clean` removes it once the client has
    /// ended).
    pub fn release(&self) -> Released {
        self.cleanup_dead_nodes();
        let users = self.users();
        if users.is_empty() {
            // SAFETY: no process of this instance is alive (checked just above), and the
            // instance belongs to the caller, so none of softnc's can start meanwhile.
            let _ = unsafe {
                iceoryx2::testing::remove_global_mgmt_segment::<ipc::Service>(&self.config)
            };
        }
        Released {
            files: self.files(),
            users,
        }
    }

    /// The files of this instance in shared memory and in iceoryx2's folder: none once every
    /// process of it has ended and dead ones are cleaned up.
    pub fn files(&self) -> Vec<PathBuf> {
        let prefix = Self::prefix_of(&self.name);
        let mut out = Vec::new();
        let root = PathBuf::from(self.config.global.root_path().to_string());
        let mut dirs = vec![PathBuf::from("/dev/shm"), root];
        while let Some(dir) = dirs.pop() {
            let Ok(entries) = std::fs::read_dir(&dir) else {
                continue;
            };
            for e in entries.flatten() {
                let path = e.path();
                let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
                let ours = e.file_name().to_string_lossy().starts_with(&prefix);
                if is_dir && dir != std::path::Path::new("/dev/shm") {
                    dirs.push(path.clone());
                }
                if ours {
                    out.push(path);
                }
            }
        }
        out.sort();
        out
    }

    /// The full name of one of the instance's services (`<instance>/setpoints`).
    pub fn service_name(&self, service: &str) -> Result<ServiceName, IpcError> {
        let full = format!("{}/{service}", self.name);
        ServiceName::new(&full).map_err(|e| IpcError(format!("service name {full}: {e:?}")))
    }

    fn verifier(&self) -> AttributeVerifier {
        let key = AttributeKey::new(ABI_KEY.as_bytes()).expect("a valid attribute key");
        let value = AttributeValue::new(self.abi.as_bytes()).expect("ABI strings are short");
        AttributeVerifier::new()
            .require(&key, &value)
            .expect("one attribute fits")
    }

    /// The message for a service that exists with another ABI, naming the peer's (read
    /// from the service's static configuration, whatever its payload types).
    fn abi_mismatch(&self, service: &str, pattern: MessagingPattern, detail: &str) -> IpcError {
        let key = AttributeKey::new(ABI_KEY.as_bytes()).expect("a valid attribute key");
        let peer = self.service_name(service).ok().and_then(|n| {
            let details = ipc::Service::details(&n, &self.config, pattern).ok()??;
            let abi = details.static_details.attributes().key_value(&key, 0)?;
            Some(abi.to_string())
        });
        IpcError(format!(
            "{}/{service}: refused, the peer speaks another protocol ({detail}): it has {}, this \
             build has {}. Build nc-kernel, plc-sim and softnc from the same source.",
            self.name,
            peer.map_or("an ABI of another layout".to_string(), |p| format!(
                "ABI {p}"
            )),
            self.abi
        ))
    }

    /// Opens or creates a service with `attempt`, retrying while another process cleans up
    /// or creates the same service; `attempt` gives `Err(Ok(e))` for a final refusal and
    /// `Err(Err(why))` for one worth retrying.
    fn retry<T>(
        &self,
        service: &str,
        mut attempt: impl FnMut() -> Result<T, Result<IpcError, String>>,
    ) -> Result<T, IpcError> {
        let mut last = String::new();
        for _ in 0..50 {
            match attempt() {
                Ok(t) => return Ok(t),
                Err(Ok(e)) => return Err(e),
                Err(Err(e)) => last = e,
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        Err(IpcError(format!(
            "{}/{service}: cannot open or create the service: {last}",
            self.name
        )))
    }

    fn pubsub<T: std::fmt::Debug + ZeroCopySend + Copy>(
        &self,
        node: &Node<ipc::Service>,
        service: &str,
        buffer: usize,
        history: usize,
    ) -> Result<PubSub<T>, IpcError> {
        use iceoryx2::service::builder::publish_subscribe::{
            PublishSubscribeOpenError as O, PublishSubscribeOpenOrCreateError as E,
        };
        let name = self.service_name(service)?;
        self.retry(service, || {
            node.service_builder(&name)
                .publish_subscribe::<T>()
                .enable_safe_overflow(true)
                .history_size(history)
                .subscriber_max_buffer_size(buffer)
                .subscriber_max_borrowed_samples(2)
                .max_publishers(2)
                .max_subscribers(8)
                .max_nodes(12)
                .open_or_create_with_attributes(&self.verifier())
                .map_err(|e| match e {
                    E::PublishSubscribeOpenError(O::IncompatibleAttributes) => Ok(self
                        .abi_mismatch(
                            service,
                            MessagingPattern::PublishSubscribe,
                            "attributes differ",
                        )),
                    E::PublishSubscribeOpenError(O::IncompatibleTypes) => Ok(self.abi_mismatch(
                        service,
                        MessagingPattern::PublishSubscribe,
                        "payload type differs",
                    )),
                    e => Err(format!("{e:?}")),
                })
        })
    }

    fn reqres<Q, A>(
        &self,
        node: &Node<ipc::Service>,
        service: &str,
        active: usize,
    ) -> Result<ReqRes<Q, A>, IpcError>
    where
        Q: std::fmt::Debug + ZeroCopySend + Copy,
        A: std::fmt::Debug + ZeroCopySend + Copy,
    {
        use iceoryx2::service::builder::request_response::{
            RequestResponseOpenError as O, RequestResponseOpenOrCreateError as E,
        };
        let name = self.service_name(service)?;
        self.retry(service, || {
            node.service_builder(&name)
                .request_response::<Q, A>()
                .enable_safe_overflow_for_requests(true)
                .enable_safe_overflow_for_responses(true)
                .max_active_requests_per_client(active)
                .max_response_buffer_size(2)
                .max_servers(2)
                .max_clients(8)
                .max_nodes(12)
                .open_or_create_with_attributes(&self.verifier())
                .map_err(|e| match e {
                    E::RequestResponseOpenError(O::IncompatibleAttributes) => Ok(self
                        .abi_mismatch(
                            service,
                            MessagingPattern::RequestResponse,
                            "attributes differ",
                        )),
                    E::RequestResponseOpenError(O::IncompatibleRequestOrResponseType) => Ok(self
                        .abi_mismatch(
                            service,
                            MessagingPattern::RequestResponse,
                            "payload type differs",
                        )),
                    e => Err(format!("{e:?}")),
                })
        })
    }

    /// Setpoints, kernel → PLC, every IPO cycle.
    pub fn setpoints(&self, node: &Node<ipc::Service>) -> Result<PubSub<SetpointMsg>, IpcError> {
        self.pubsub(node, "setpoints", 64, 0)
    }

    /// Wakes the PLC when a setpoint is out.
    pub fn setpoint_event(&self, node: &Node<ipc::Service>) -> Result<Events, IpcError> {
        use iceoryx2::service::builder::event::{EventOpenError as O, EventOpenOrCreateError as E};
        let service = "setpoints.event";
        let name = self.service_name(service)?;
        self.retry(service, || {
            node.service_builder(&name)
                .event()
                .max_notifiers(2)
                .max_listeners(4)
                .max_nodes(12)
                .open_or_create_with_attributes(&self.verifier())
                .map_err(|e| match e {
                    E::EventOpenError(O::IncompatibleAttributes) => Ok(self.abi_mismatch(
                        service,
                        MessagingPattern::Event,
                        "attributes differ",
                    )),
                    e => Err(format!("{e:?}")),
                })
        })
    }

    /// Auxiliary functions, kernel → PLC, acknowledged.
    pub fn aux(&self, node: &Node<ipc::Service>) -> Result<ReqRes<AuxRequest, AuxAck>, IpcError> {
        self.reqres(node, "aux", 16)
    }

    pub fn plc_signals(&self, node: &Node<ipc::Service>) -> Result<PubSub<PlcSignals>, IpcError> {
        self.pubsub(node, "plc.signals", 16, 0)
    }

    pub fn actual_values(
        &self,
        node: &Node<ipc::Service>,
    ) -> Result<PubSub<ActualValues>, IpcError> {
        self.pubsub(node, "plc.actuals", 64, 0)
    }

    pub fn status(&self, node: &Node<ipc::Service>) -> Result<PubSub<KernelStatus>, IpcError> {
        self.pubsub(node, "status", 16, 0)
    }

    /// The kernel's tool table, published when it changes; a new subscriber gets the
    /// newest at once.
    pub fn tools(&self, node: &Node<ipc::Service>) -> Result<PubSub<ToolTableMsg>, IpcError> {
        self.pubsub(node, "tools", 2, 1)
    }

    /// The kernel's work-offset table, published when it changes; a new subscriber gets
    /// the newest at once.
    pub fn work_offsets(
        &self,
        node: &Node<ipc::Service>,
    ) -> Result<PubSub<WorkOffsetsMsg>, IpcError> {
        self.pubsub(node, "work-offsets", 2, 1)
    }

    /// HMI commands to the kernel.
    pub fn commands(&self, node: &Node<ipc::Service>) -> Result<ReqRes<Command, Reply>, IpcError> {
        self.reqres(node, "commands", 4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn abi_names_version_and_layout() {
        let a = abi();
        assert!(a.starts_with("softnc-ipc/5/"), "{a}");
        assert_eq!(a, abi());
        assert!(a.len() < 64);
    }

    #[test]
    fn instance_names_are_checked() {
        assert!(Instance::new("bad/name").is_err());
        assert!(Instance::new("").is_err());
        assert!(Instance::new("cell-1_a").is_ok());
    }
}
