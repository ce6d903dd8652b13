//! softnc's OPC UA server (docs/opcua.md): the OPC 40501-1 machine-tool model subset —
//! Identification, Monitoring (channel, spindle), Production (active program), Notification
//! (alarms), Equipment (tools) — over what the kernel publishes, read through the HMI
//! bridge's link (one thread owns the iceoryx2 ports; the kernel is never waited for). It
//! listens on 127.0.0.1 and takes anonymous clients there; another address needs a user
//! and password, and then only those are taken. It runs as a process of its own (`softnc
//! opcua`, which `softnc run --opcua` starts) or inside the HMI bridge's process (`softnc
//! hmi-bridge --opcua`, hosted.rs), on the bridge's link.

mod access;
mod hosted;
mod model;
mod server;
mod space;

pub use access::{Access, DEFAULT_PORT, DEFAULT_USER, PASSWORD_VARIABLE};
pub use hosted::bridge_main;
pub use server::{start, url_host, Running};
pub use space::{Identity, MACHINE_TOOL_NS, SOFTNC_NS};

use nc_runtime::process::args::{machine, ControlArgs};
use nc_runtime::Failure;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

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

/// The OPC UA server beside another command (`softnc run`) or inside it (`softnc
/// hmi-bridge`): the arguments of `softnc opcua`, prefixed.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct ServerOptions {
    /// Also serve OPC UA (docs/opcua.md) on port PORT (default 4840; 0: any free one) of
    /// 127.0.0.1, or of --opcua-listen.
    #[arg(long, value_name = "PORT", num_args = 0..=1, default_missing_value = "4840")]
    pub opcua: Option<u16>,
    /// The OPC UA server listens on another address than 127.0.0.1; needs --opcua-password.
    #[arg(long, value_name = "ADDRESS[:PORT]", requires = "opcua")]
    pub opcua_listen: Option<String>,
    /// The user name OPC UA clients log in with [default: operator].
    #[arg(long, value_name = "NAME", requires = "opcua")]
    pub opcua_user: Option<String>,
    /// The OPC UA password, at least 12 characters (or the environment variable
    /// SOFTNC_OPCUA_PASSWORD).
    #[arg(long, value_name = "PASSWORD", requires = "opcua")]
    pub opcua_password: Option<String>,
}

impl ServerOptions {
    /// The user name clients log in with.
    pub fn user(&self) -> &str {
        self.opcua_user.as_deref().unwrap_or(DEFAULT_USER)
    }

    /// The password given, by argument or by [`PASSWORD_VARIABLE`].
    pub fn password(&self) -> Option<String> {
        self.opcua_password
            .clone()
            .or_else(|| std::env::var(PASSWORD_VARIABLE).ok())
    }

    /// Where the server is to listen and whom it takes (by `softnc opcua`'s rules);
    /// `None` without --opcua.
    pub fn access(&self) -> Result<Option<Access>, String> {
        let Some(port) = self.opcua else {
            return Ok(None);
        };
        let listen = self.opcua_listen.as_deref();
        Access::new(
            listen,
            port,
            self.user(),
            self.password(),
            "--opcua-password",
        )
        .map(Some)
    }
}

/// The `host:port` in a log the server wrote: it announces `opc.tcp://HOST:PORT/` on its
/// first line; `None` until the address is written in full (up to its `/`).
pub fn address_in(log: &str) -> Option<&str> {
    let (addr, _) = log.split("opc.tcp://").nth(1)?.split_once('/')?;
    Some(addr)
}

/// What Identification says of the control: its machine data's kind, its instance.
pub fn identity(control: &ControlArgs) -> Result<Identity, String> {
    let md = machine(control.machine.as_deref())?;
    let kind = match md.machine {
        nc_kernel::MachineKind::Milling => "milling machine",
        nc_kernel::MachineKind::Turning => "lathe",
    };
    Ok(Identity {
        model: format!("softnc {} {kind}", md.dialect.as_str()),
        serial: control.instance.name().to_string(),
    })
}

/// The OPC UA server process: until SIGINT or SIGTERM. It reads the kernel through a link
/// of its own, under the node name `opcua`.
pub fn main(args: OpcuaArgs) -> Result<(), Failure> {
    let password = args
        .password
        .or_else(|| std::env::var(PASSWORD_VARIABLE).ok());
    let access = Access::new(
        args.listen.as_deref(),
        args.port,
        &args.user,
        password,
        "--password",
    )?;
    let identity = identity(&args.control)?;
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst))
            .map_err(|e| format!("cannot install the signal handler: {e}"))?;
    }
    let instance = args.control.instance;
    let (link, link_thread) =
        hmi_bridge::link::start(instance, "opcua", |_| String::new(), stop.clone())?;
    let result = start(access, identity, link, stop.clone()).and_then(|running| {
        running
            .thread
            .join()
            .unwrap_or_else(|_| Err("the OPC UA server's thread panicked".into()))
    });
    stop.store(true, Ordering::SeqCst);
    let _ = link_thread.join();
    result.map_err(Failure::Error)
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
