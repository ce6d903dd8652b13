//! hmi-bridge: the operator's side of a softnc control (docs/hmi.md). It talks to
//! the kernel over iceoryx2 (link.rs) and serves an HTTP JSON API, a Server-Sent-Events
//! status stream and one web page (api.rs, page.html) on 127.0.0.1. Another address needs
//! `--listen` and a token that every request then carries.

mod api;
pub mod client;
pub mod link;
mod net;
mod plot;
mod work;

use nc_runtime::process::args::{machine, ControlArgs};
use nc_runtime::Failure;
use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The operator's side of a softnc control: an HTTP JSON API, a live status stream and a
/// web page (docs/hmi.md). It listens on 127.0.0.1; another address needs a token, which
/// every request then carries.
#[derive(clap::Parser, Debug)]
#[command(name = "hmi-bridge")]
pub struct BridgeArgs {
    #[command(flatten)]
    pub control: ControlArgs,
    /// The TCP port (0: any free one, printed) [default: machine data hmi.port].
    #[arg(long, value_name = "PORT")]
    pub port: Option<u16>,
    /// Listen on another address than 127.0.0.1; needs --token.
    #[arg(long, value_name = "ADDRESS[:PORT]")]
    pub listen: Option<String>,
    /// The token every request must carry, at least 12 characters (or the environment
    /// variable SOFTNC_HMI_TOKEN).
    #[arg(long, value_name = "TOKEN")]
    pub token: Option<String>,
    /// The folder the page offers programs from.
    #[arg(long, value_name = "DIR", default_value = "programs")]
    pub programs: PathBuf,
}

/// The `host:port` in a log the bridge wrote: it announces `http://HOST:PORT/` on its
/// first line (with `--port 0`, whatever port it got). For those who start it and read its
/// log: `softnc run --hmi`, the tests. `None` until the address is written in full (up to
/// its `/`): a reader may catch the line half written.
pub fn address_in(log: &str) -> Option<&str> {
    let (addr, _) = log.split("http://").nth(1)?.split_once('/')?;
    Some(addr)
}

/// The address `--listen` names, `ADDRESS` (on `port`) or `ADDRESS:PORT`; 127.0.0.1 on
/// `port` without one. The bridge's rule, and the OPC UA server's.
pub fn listen_address(listen: Option<&str>, port: u16) -> Result<SocketAddr, String> {
    match listen {
        None => Ok(SocketAddr::from(([127, 0, 0, 1], port))),
        Some(a) => a
            .parse::<SocketAddr>()
            .or_else(|_| a.parse::<IpAddr>().map(|ip| SocketAddr::new(ip, port)))
            .map_err(|_| {
                format!("--listen {a}: expected an address like 0.0.0.0 or 10.0.0.5:{port}")
            }),
    }
}

/// A server that shares the bridge's link to the kernel instead of opening a link of its
/// own (the OPC UA server, `softnc hmi-bridge --opcua`, docs/opcua.md). Called once the link
/// is up, with the link and the bridge's stop flag, it starts in threads of its own and
/// returns when it serves (or why it cannot: the bridge then does not start); it runs until
/// the flag is set, and sets it itself if it fails, so that the bridge ends with it. The
/// bridge waits for its thread at the end.
pub type Guest = Box<dyn FnOnce(link::Link, Arc<AtomicBool>) -> Result<GuestThread, String> + Send>;

/// A guest's thread: how the guest ended.
pub type GuestThread = std::thread::JoinHandle<Result<(), String>>;

/// The hmi-bridge process.
pub fn main(args: BridgeArgs) -> Result<(), Failure> {
    main_with(args, None)
}

/// The hmi-bridge process with a guest server on its link.
pub fn main_with(args: BridgeArgs, guest: Option<Guest>) -> Result<(), Failure> {
    let instance = args.control.instance;
    let md = machine(args.control.machine.as_deref())?;
    // 0: any free port (tests); the address taken is printed.
    let port = args.port.unwrap_or(md.hmi.port);
    let addr = listen_address(args.listen.as_deref(), port)?;
    let token = token(args.token, addr)?;
    let programs = args.programs;

    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst))
            .map_err(|e| format!("cannot install the signal handler: {e}"))?;
    }
    let (link, link_thread) = link::start(
        instance.clone(),
        "hmi-bridge",
        api::status_text,
        stop.clone(),
    )?;
    let (listener, guest) = match open(addr, guest, &link, &stop) {
        Ok(o) => o,
        Err(e) => {
            stop.store(true, Ordering::SeqCst);
            let _ = link_thread.join();
            return Err(Failure::Error(e));
        }
    };
    let bound = listener.local_addr().map_err(|e| e.to_string())?;
    let api = Arc::new(api::Api::new(link, token.clone(), md, programs));
    eprintln!(
        "hmi-bridge: instance '{}': http://{bound}/{}",
        instance.name(),
        if token.is_some() {
            " (token required)"
        } else {
            ""
        }
    );
    let handler: Arc<dyn Fn(net::Request) -> net::Response + Send + Sync> =
        Arc::new(move |req| api.handle(req));
    net::serve(listener, handler, stop.clone());
    stop.store(true, Ordering::SeqCst);
    let guest = guest.map(|g| {
        g.join()
            .unwrap_or_else(|_| Err("the guest server's thread panicked".into()))
    });
    let _ = link_thread.join();
    guest.transpose().map(|_| ()).map_err(Failure::Error)
}

/// The HTTP listener, then the guest on the link: the bridge announces its address only
/// when both serve.
fn open(
    addr: SocketAddr,
    guest: Option<Guest>,
    link: &link::Link,
    stop: &Arc<AtomicBool>,
) -> Result<(std::net::TcpListener, Option<GuestThread>), String> {
    let listener = net::listen(addr).map_err(|e| format!("{addr}: {e}"))?;
    let guest = guest.map(|g| g(link.clone(), stop.clone())).transpose()?;
    Ok((listener, guest))
}

/// The token requests must carry: `given`, or the environment's; required on an address
/// other than loopback, and at least 12 characters.
fn token(given: Option<String>, addr: SocketAddr) -> Result<Option<String>, Failure> {
    let token = given
        .or_else(|| std::env::var("SOFTNC_HMI_TOKEN").ok())
        .filter(|t| !t.is_empty());
    if !addr.ip().is_loopback() && token.is_none() {
        return Err(Failure::Error(format!(
            "listening on {addr} lets other machines command the control: give --token (or SOFTNC_HMI_TOKEN)"
        )));
    }
    if token.as_ref().is_some_and(|t| t.len() < 12) {
        return Err("the token is too short: use at least 12 characters".into());
    }
    Ok(token)
}

#[cfg(test)]
mod tests {
    #[test]
    fn address_only_when_written_in_full() {
        let line = "hmi-bridge: instance 'a': http://127.0.0.1:8123/ (token)\n";
        assert_eq!(super::address_in(line), Some("127.0.0.1:8123"));
        for cut in 0..line.find(":8123/").unwrap() + 6 {
            assert_eq!(super::address_in(&line[..cut]), None, "{}", &line[..cut]);
        }
    }
}
