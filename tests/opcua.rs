//! The OPC UA server (docs/opcua.md): a Python asyncua client browses Machines/<machine>
//! during `softnc run --opcua` and reads ChannelState, FeedOverride, the active program and
//! block and the spindle, and is refused a write; the server inside the HMI bridge's
//! process reads the channel through the bridge's link; on an address other than loopback
//! (0.0.0.0, and this machine's own) only the user with the password gets in, and neither
//! the server nor a run starts there without one.
//!
//! Without a Python that has asyncua a client test says so and passes, unless
//! SOFTNC_REQUIRE_CLIENTS is set (.ci/run installs asyncua into the clients' venv and points
//! SOFTNC_CLIENTS_PYTHON at it): then it fails, as does the own-address test on a machine
//! with no address besides loopback.

#[path = "support/control.rs"]
mod control;

use control::*;
use serde_json::{json, Value};
use std::net::{IpAddr, Ipv4Addr, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::Command as Proc;
use std::time::{Duration, Instant};

const CLIENT: &str = "clients/python/opcua_browse.py";
const PASSWORD: &str = "correct horse battery";

fn required() -> bool {
    std::env::var_os("SOFTNC_REQUIRE_CLIENTS").is_some()
}

/// The clients' Python if it has asyncua; without, the test says so and passes unless
/// SOFTNC_REQUIRE_CLIENTS is set.
fn python_with_asyncua() -> Option<String> {
    let py = std::env::var("SOFTNC_CLIENTS_PYTHON").unwrap_or_else(|_| "python3".into());
    let ok = Proc::new(&py)
        .args(["-c", "import asyncua"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        return Some(py);
    }
    if required() {
        panic!("{py} has no asyncua, and SOFTNC_REQUIRE_CLIENTS is set (.ci/run installs it)");
    }
    eprintln!("{py} has no asyncua: test skipped (.ci/run installs it)");
    None
}

/// The `host:port` the server announced in `log` on the line with `prefix`, once it has
/// (the child still running).
fn announced(kid: &mut Kid, log: &Path, prefix: &str) -> String {
    let t = Instant::now();
    loop {
        let text = std::fs::read_to_string(log).unwrap_or_default();
        if let Some(line) = text.lines().find(|l| l.contains(prefix)) {
            if let Some(a) = softnc_opcua::address_in(line) {
                return a.to_string();
            }
        }
        if let Ok(Some(s)) = kid.0.try_wait() {
            panic!("ended ({s}) before it announced its address:\n{text}");
        }
        // With a password the server makes its certificate first (an RSA key: seconds in a
        // debug build on a busy machine).
        assert!(t.elapsed() < Duration::from_secs(60), "no address:\n{text}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The port of an announced `host:port`.
fn port_of(addr: &str) -> &str {
    addr.rsplit_once(':').map_or(addr, |(_, p)| p)
}

/// The client's standard output; it must exit 0.
fn client(py: &str, args: &[&str]) -> String {
    let out = Proc::new(py)
        .current_dir(root())
        .arg(CLIENT)
        .args(args)
        .output()
        .expect("python runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// Waits for the child's end, at most `limit`.
fn ended(kid: &mut Kid, limit: Duration) -> std::process::ExitStatus {
    let t = Instant::now();
    loop {
        if let Ok(Some(s)) = kid.0.try_wait() {
            return s;
        }
        assert!(t.elapsed() < limit, "did not end within {limit:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// SIGTERM to the child: it ends with exit status 0 within 10 s.
fn ends_cleanly(kid: &mut Kid, log: &Path) {
    // SAFETY: a plain signal to our own child.
    unsafe { libc::kill(kid.0.id() as i32, libc::SIGTERM) };
    let status = ended(kid, Duration::from_secs(10));
    let text = std::fs::read_to_string(log).unwrap_or_default();
    assert!(status.success(), "{text}");
}

/// About `seconds` of motion at F3000 after the spindle is at 1200 rev/min (M3 waits for
/// it): the spindle starts in line 2, the motion from line 4 on.
fn spindle_program(seconds: f64) -> PathBuf {
    let mut text = String::from("N1 G0 X0 Y0 Z0\nN2 S1200 M3\nN3 G1 F3000\n");
    let legs = (seconds * 50.0 / 100.0).ceil() as usize + 1;
    for i in 0..legs {
        let x = if i % 2 == 0 { 100 } else { 0 };
        text.push_str(&format!("N{} X{x} Y{}\n", 10 + i, i % 7));
    }
    text.push_str("M5\nM30\n");
    let p = scratch(&format!("opcua-spindle-{seconds}.mpf"));
    std::fs::write(&p, text).unwrap();
    p
}

/// A program of about 10 s under `softnc run --opcua 0`: once it moves (line 4 on) the
/// client finds the machine by browsing, the channel Active (OPC 40501-1 ChannelState 0) in
/// Automatic (ChannelMode 0) at 100 % FeedOverride, the program by its file name in the
/// channel and as Production's active program, Running; the running line and its text
/// (read in one request); the spindle at its 1200 rev/min setpoint and turning;
/// Identification names softnc and the instance; the tool list has the built-in table's D1
/// (radius 10, length 100, config/tools.toml). A write to FeedOverride is refused and
/// changes nothing. The run then ends normally, the server with it.
#[test]
fn a_client_reads_the_channel_during_a_run() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    let inst = instance("opcua-run");
    let scope = Scope::new(&inst);
    let prog = spindle_program(10.0);
    let log = scratch("opcua-run.log");
    let trace = scratch("opcua-run.csv");
    let mut run = spawn(
        "run",
        &[
            prog.to_str().unwrap(),
            "--quiet",
            "--instance",
            scope.0.name(),
            "--trace",
            trace.to_str().unwrap(),
            "--opcua",
            "0",
        ],
        &log,
    );
    let addr = announced(&mut run, &log, "OPC UA:");
    let url = format!("opc.tcp://{addr}/");
    let args = [
        &url,
        "--wait-running",
        "30",
        "--min-line",
        "4",
        "--try-write",
    ];
    let v: Value = serde_json::from_str(client(&py, &args).trim()).expect("one JSON object");
    let name = prog.file_name().unwrap().to_str().unwrap();
    assert_eq!(v["machine"], scope.0.name(), "{v}");
    assert_eq!(v["identification"]["Manufacturer"], "softnc", "{v}");
    assert_eq!(v["identification"]["SerialNumber"], scope.0.name(), "{v}");
    assert_eq!(v["channel_state"], "Active", "{v}");
    assert_eq!(v["channel_mode"], 0, "{v}");
    assert_eq!(v["feed_override"], 100.0, "{v}");
    assert_eq!(v["kernel_connected"], true, "{v}");
    assert_eq!(v["program"], name, "{v}");
    assert_eq!(v["active_program"], name, "{v}");
    assert_eq!(v["production_state"], "Running", "{v}");
    the_block_is_the_running_line(&v, &prog);
    the_spindle_turns_at(&v, 1200.0);
    // Read-only: refused for want of write access, the value unchanged.
    let write = &v["feed_override_write"];
    assert!(
        ["refused: BadNotWritable", "refused: BadUserAccessDenied"]
            .contains(&write["answer"].as_str().unwrap_or("")),
        "{v}"
    );
    assert_eq!(write["read_back"], 100.0, "{v}");
    let d1 = v["tools"]
        .as_array()
        .and_then(|t| t.iter().find(|t| t["name"] == "D1"))
        .unwrap_or_else(|| panic!("no D1: {v}"));
    assert_eq!(
        (&d1["radius"], &d1["length"]),
        (&10.0.into(), &100.0.into())
    );
    let status = ended(&mut run, Duration::from_secs(120));
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(status.success(), "{text}");
}

/// Line and Block name the same line of the program: a motion block, line 4 on.
fn the_block_is_the_running_line(v: &Value, prog: &Path) {
    let line = v["line"].as_u64().unwrap_or(0) as usize;
    assert!(line >= 4, "{v}");
    let text = std::fs::read_to_string(prog).unwrap();
    let expected = text.lines().nth(line - 1).map(str::trim);
    assert_eq!(v["block"].as_str(), expected, "{v}");
    assert!(
        expected.is_some_and(|b| b.starts_with('N') && b.contains('X')),
        "{v}"
    );
}

/// The spindle past its M3 (which waits until it is at speed): setpoint `rpm`, the actual
/// speed within plc-sim's at-speed window (0.5 %), rotating.
fn the_spindle_turns_at(v: &Value, rpm: f64) {
    assert_eq!(v["spindle_setpoint"], rpm, "{v}");
    let actual = v["spindle_actual"].as_f64().unwrap_or(f64::NAN);
    assert!((actual - rpm).abs() <= 0.006 * rpm, "{v}");
    assert_eq!(v["spindle_rotating"], true, "{v}");
}

/// `softnc hmi-bridge --opcua 0`: the bridge's process serves OPC UA on the bridge's own
/// link to the kernel (no second reader joins the instance), here on 0.0.0.0 with a
/// password. The client logs in and sees the channel Active with the program; an anonymous
/// client is refused. The HTTP side answers meanwhile; SIGTERM ends both with exit
/// status 0.
#[test]
fn the_bridge_hosts_the_server_on_its_link() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    let inst = instance("opcua-bridge");
    let scope = Scope::new(&inst);
    let name = scope.0.name();
    // Long enough to be running still when the client has logged in; the test ends it.
    let prog = long_program(30.0);
    let mut kids = vec![spawn(
        "plc-sim",
        &["--instance", name],
        &scratch("opcua-bridge-plc.log"),
    )];
    let kernel = ["--instance", name, prog.to_str().unwrap(), "--start"];
    kids.push(spawn(
        "nc-kernel",
        &kernel,
        &scratch("opcua-bridge-nck.log"),
    ));
    let log = scratch("opcua-bridge-hmi.log");
    let mut bridge = vec!["--instance", name, "--port", "0", "--opcua", "0"];
    bridge.extend(["--opcua-listen", "0.0.0.0", "--opcua-password", PASSWORD]);
    kids.push(spawn("hmi-bridge", &bridge, &log));
    let addr = announced(&mut kids[2], &log, "opc.tcp://");
    assert!(addr.starts_with("0.0.0.0:"), "{addr}");
    let url = format!("opc.tcp://127.0.0.1:{}/", port_of(&addr));
    let login = [&url, "--user", "operator", "--password", PASSWORD];
    let mut args = login.to_vec();
    args.extend(["--wait-running", "30"]);
    let v: Value = serde_json::from_str(client(&py, &args).trim()).expect("one JSON object");
    assert_eq!(v["channel_state"], "Active", "{v}");
    assert_eq!(v["feed_override"], 100.0, "{v}");
    let program = prog.file_name().unwrap().to_str().unwrap();
    assert_eq!(v["active_program"], program, "{v}");
    let anonymous = client(&py, &[&url, "--try-login"]);
    assert!(
        anonymous.starts_with("refused: BadIdentityTokenInvalid"),
        "{anonymous}"
    );
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    let http = hmi_bridge::address_in(&text).unwrap_or_else(|| panic!("no HTTP: {text}"));
    let status = hmi_bridge::client::Bridge::new(http.to_string(), None)
        .get("/api/status")
        .map(|a| a.json())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(status["connected"], json!(true), "{status}");
    // One reader of the kernel: the bridge's node, no `opcua` node of a second link.
    let users = scope.0.users();
    let nodes: Vec<&str> = users.iter().map(|u| u.name.as_str()).collect();
    assert!(nodes.contains(&"hmi-bridge"), "{nodes:?}");
    assert!(!nodes.contains(&"opcua"), "{nodes:?}");
    ends_cleanly(&mut kids[2], &log);
}

/// The bridge does not start when its OPC UA server may not: on 0.0.0.0 without a
/// password, or with a short one (exit status 2, before it serves HTTP).
#[test]
fn the_bridge_refuses_an_open_server_without_a_password() {
    let inst = instance("opcua-bridge-nopass");
    let scope = Scope::light(&inst);
    for (extra, says) in [
        (&[][..], "--opcua-password"),
        (&["--opcua-password", "short"][..], "at least 12"),
    ] {
        let log = scratch("opcua-bridge-nopass.log");
        let mut args = vec!["--instance", scope.0.name(), "--port", "0", "--opcua", "0"];
        args.extend(["--opcua-listen", "0.0.0.0"]);
        args.extend(extra);
        let mut kid = spawn("hmi-bridge", &args, &log);
        let status = ended(&mut kid, Duration::from_secs(10));
        let text = std::fs::read_to_string(&log).unwrap();
        assert_eq!(status.code(), Some(2), "{text}");
        assert!(text.contains(says) && !text.contains("http://"), "{text}");
    }
}

/// This machine's address on its default route (no packet is sent: a UDP socket's connect
/// only picks the source address), else the first IPv4 address of an interface that is not
/// loopback; `None` without one.
fn own_address() -> Option<IpAddr> {
    route_source().or_else(interface_address)
}

fn route_source() -> Option<IpAddr> {
    let s = UdpSocket::bind("0.0.0.0:0").ok()?;
    s.connect("192.0.2.1:9").ok()?;
    let ip = s.local_addr().ok()?.ip();
    (!ip.is_loopback() && !ip.is_unspecified()).then_some(ip)
}

fn interface_address() -> Option<IpAddr> {
    let mut list: *mut libc::ifaddrs = std::ptr::null_mut();
    // SAFETY: getifaddrs fills `list` (freed below); each entry's address is read as the
    // sockaddr_in its family says it is.
    unsafe {
        if libc::getifaddrs(&mut list) != 0 {
            return None;
        }
        let mut found = None;
        let mut p = list;
        while !p.is_null() && found.is_none() {
            let a = (*p).ifa_addr;
            if !a.is_null() && i32::from((*a).sa_family) == libc::AF_INET {
                let sin = &*(a as *const libc::sockaddr_in);
                let ip = Ipv4Addr::from(u32::from_be(sin.sin_addr.s_addr));
                if !ip.is_loopback() && !ip.is_unspecified() {
                    found = Some(IpAddr::V4(ip));
                }
            }
            p = (*p).ifa_next;
        }
        libc::freeifaddrs(list);
        found
    }
}

/// `softnc opcua --listen LISTEN --password …`, reached at `host` (the announced port):
/// the server offers only a user name and password, the password to be encrypted with
/// Basic256Sha256, and takes only `operator` with the password: an anonymous client, a
/// wrong password and another user are refused at session activation, each for its reason
/// (not a timeout or a lost line); the right login reads the machine's serial number (its
/// instance). SIGTERM ends it with exit status 0.
fn only_the_user_with_the_password(py: &str, tag: &str, listen: &str, host: &str) {
    let inst = instance(tag);
    let scope = Scope::light(&inst);
    let log = scratch(&format!("{tag}.log"));
    let mut server = spawn(
        "opcua",
        &[
            "--instance",
            scope.0.name(),
            "--listen",
            listen,
            "--port",
            "0",
            "--password",
            PASSWORD,
        ],
        &log,
    );
    let addr = announced(&mut server, &log, "opc.tcp://");
    let url = format!("opc.tcp://{host}:{}/", port_of(&addr));
    let offered: Value = serde_json::from_str(client(py, &[&url, "--policies"]).trim()).unwrap();
    let user = json!({
        "type": "UserName",
        "security_policy": "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256",
    });
    assert_eq!(offered, json!([user]));
    let anonymous = client(py, &[&url, "--try-login"]);
    assert!(
        anonymous.starts_with("refused: BadIdentityTokenInvalid"),
        "{anonymous}"
    );
    for (user, pass) in [("operator", "wrong password!"), ("someone", PASSWORD)] {
        let args = [&url, "--try-login", "--user", user, "--password", pass];
        let wrong = client(py, &args);
        assert!(wrong.starts_with("refused: BadUserAccessDenied"), "{wrong}");
    }
    let args = [
        &url,
        "--try-login",
        "--user",
        "operator",
        "--password",
        PASSWORD,
    ];
    let right = client(py, &args);
    assert_eq!(right.trim(), format!("accepted: {}", scope.0.name()));
    ends_cleanly(&mut server, &log);
}

/// The unspecified address is not loopback: bound to 0.0.0.0 the server takes only the user
/// with the password, also from a client that comes over 127.0.0.1. Needs no network, so
/// the rule is checked on every machine.
#[test]
fn the_unspecified_address_takes_only_the_user_with_the_password() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    only_the_user_with_the_password(&py, "opcua-any", "0.0.0.0", "127.0.0.1");
}

/// The same on this machine's own address, reached there.
#[test]
fn the_own_address_takes_only_the_user_with_the_password() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    let Some(ip) = own_address() else {
        assert!(
            !required(),
            "this machine has no address besides loopback, and SOFTNC_REQUIRE_CLIENTS is set"
        );
        eprintln!("this machine has no address besides loopback: test skipped");
        return;
    };
    let ip = ip.to_string();
    only_the_user_with_the_password(&py, "opcua-own", &ip, &ip);
}

/// On IPv6 loopback the server takes anonymous clients, and its endpoint URLs carry the
/// address in brackets, which asyncua connects to. Skipped where IPv6 is off.
#[test]
fn ipv6_loopback_serves_anonymous_clients() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    if std::net::TcpListener::bind("[::1]:0").is_err() {
        eprintln!("this machine has no IPv6 loopback: test skipped");
        return;
    }
    let inst = instance("opcua-v6");
    let scope = Scope::light(&inst);
    let log = scratch("opcua-v6.log");
    let args = [
        "--instance",
        scope.0.name(),
        "--listen",
        "::1",
        "--port",
        "0",
    ];
    let mut server = spawn("opcua", &args, &log);
    let addr = announced(&mut server, &log, "opc.tcp://");
    assert!(addr.starts_with("[::1]:"), "{addr}");
    let url = format!("opc.tcp://{addr}/");
    let offered: Value = serde_json::from_str(client(&py, &[&url, "--policies"]).trim()).unwrap();
    let types: Vec<&Value> = offered
        .as_array()
        .unwrap()
        .iter()
        .map(|p| &p["type"])
        .collect();
    assert_eq!(types, [&json!("Anonymous")], "{offered}");
    let right = client(&py, &[&url, "--try-login"]);
    assert_eq!(right.trim(), format!("accepted: {}", scope.0.name()));
    ends_cleanly(&mut server, &log);
}

/// Without a password, or with a short one, the server does not start on another address;
/// nor does a run with such a server (before it starts any process).
#[test]
fn another_address_without_a_password_is_refused() {
    let inst = instance("opcua-nopass");
    let scope = Scope::light(&inst);
    for (extra, says) in [
        (&[][..], "--password"),
        (&["--password", "short"][..], "at least 12"),
    ] {
        let log = scratch("opcua-nopass.log");
        let mut args = vec!["--instance", scope.0.name(), "--listen", "0.0.0.0"];
        args.extend(["--port", "0"]);
        args.extend(extra);
        let mut kid = spawn("opcua", &args, &log);
        let status = ended(&mut kid, Duration::from_secs(10));
        let text = std::fs::read_to_string(&log).unwrap();
        assert_eq!(status.code(), Some(2), "{text}");
        assert!(text.contains(says), "{text}");
    }
    let prog = long_program(1.0);
    let trace = scratch("opcua-nopass.csv");
    let args = ["--opcua", "0", "--opcua-listen", "0.0.0.0"];
    let out = softnc_run(&prog, scope.0.name(), &trace, &args);
    assert_eq!(out.code, Some(2), "{}", out.said());
    assert!(out.stderr.contains("--opcua-password"), "{}", out.said());
}

/// `softnc run --opcua-listen 0.0.0.0` with the password from SOFTNC_OPCUA_PASSWORD: the
/// server beside the run takes the user with it (the run hands the password on in the
/// server's environment, not its arguments) and refuses anonymous clients.
#[test]
fn a_run_serves_another_address_with_the_password() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    let inst = instance("opcua-run-listen");
    let scope = Scope::new(&inst);
    let prog = long_program(10.0);
    let log = scratch("opcua-run-listen.log");
    let trace = scratch("opcua-run-listen.csv");
    let file = std::fs::File::create(&log).unwrap();
    let args = ["--opcua", "0", "--opcua-listen", "0.0.0.0"];
    let mut run = Kid(Proc::new(EXE)
        .current_dir(root())
        .arg("run")
        .arg(&prog)
        .args(["--quiet", "--instance", scope.0.name(), "--trace"])
        .arg(&trace)
        .args(args)
        .env(softnc_opcua::PASSWORD_VARIABLE, PASSWORD)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(file)
        .spawn()
        .unwrap());
    let addr = announced(&mut run, &log, "OPC UA:");
    assert!(addr.starts_with("0.0.0.0:"), "{addr}");
    let url = format!("opc.tcp://127.0.0.1:{}/", port_of(&addr));
    let anonymous = client(&py, &[&url, "--try-login"]);
    assert!(
        anonymous.starts_with("refused: BadIdentityTokenInvalid"),
        "{anonymous}"
    );
    let args = [
        &url,
        "--try-login",
        "--user",
        "operator",
        "--password",
        PASSWORD,
    ];
    let right = client(&py, &args);
    assert_eq!(right.trim(), format!("accepted: {}", scope.0.name()));
    let status = ended(&mut run, Duration::from_secs(120));
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(status.success(), "{text}");
}
