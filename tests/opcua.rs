//! The OPC UA server (docs/opcua.md): a Python asyncua client browses Machines/<machine>
//! during `softnc run --opcua` and reads ChannelState, FeedOverride and the active program;
//! on another address than loopback only the user with the password gets in, and the server
//! refuses to start there without one.
//!
//! Without a Python that has asyncua a client test says so and passes, unless
//! SOFTNC_REQUIRE_CLIENTS is set (.ci/run installs asyncua into the clients' venv and points
//! SOFTNC_CLIENTS_PYTHON at it): then it fails.

#[path = "support/control.rs"]
mod control;

use control::*;
use serde_json::Value;
use std::net::{IpAddr, UdpSocket};
use std::process::Command as Proc;
use std::time::{Duration, Instant};

const CLIENT: &str = "clients/python/opcua_browse.py";

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
    if std::env::var_os("SOFTNC_REQUIRE_CLIENTS").is_some() {
        panic!("{py} has no asyncua, and SOFTNC_REQUIRE_CLIENTS is set (.ci/run installs it)");
    }
    eprintln!("{py} has no asyncua: test skipped (.ci/run installs it)");
    None
}

/// The `host:port` the server announced in `log`, once it has (the child still running).
fn announced(kid: &mut Kid, log: &std::path::Path, prefix: &str) -> String {
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
        assert!(t.elapsed() < Duration::from_secs(30), "no address:\n{text}");
        std::thread::sleep(Duration::from_millis(20));
    }
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

/// A program of about 10 s at F3000 under `softnc run --opcua 0`: while it runs the client
/// finds the machine by browsing, the channel Active (OPC 40501-1 ChannelState 0) in
/// Automatic (ChannelMode 0) at 100 % FeedOverride, the program by its file name in the
/// channel and as Production's active program, Running; Identification names softnc and
/// the instance; the tool list has the built-in table's D1 (radius 10, length 100,
/// config/tools.toml). The run then ends normally, the server with it.
#[test]
fn a_client_reads_the_channel_during_a_run() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    let inst = instance("opcua-run");
    let scope = Scope::new(&inst);
    let prog = long_program(10.0);
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
    let out = client(&py, &[&url, "--wait-running", "30"]);
    let v: Value = serde_json::from_str(out.trim()).expect("one JSON object");
    let name = prog.file_name().unwrap().to_str().unwrap();
    assert_eq!(v["machine"], scope.0.name(), "{v}");
    assert_eq!(v["identification"]["Manufacturer"], "softnc", "{v}");
    assert_eq!(v["identification"]["SerialNumber"], scope.0.name(), "{v}");
    assert_eq!(v["channel_state"], "Active", "{v}");
    assert_eq!(v["channel_mode"], 0, "{v}");
    assert_eq!(v["feed_override"], 100.0, "{v}");
    assert_eq!(v["program"], name, "{v}");
    assert_eq!(v["active_program"], name, "{v}");
    assert_eq!(v["production_state"], "Running", "{v}");
    assert!(v["line"].as_u64().is_some_and(|l| l >= 1), "{v}");
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

/// This machine's address on its default route (no packet is sent: a UDP socket's connect
/// only picks the source address); `None` without one.
fn own_address() -> Option<IpAddr> {
    let s = UdpSocket::bind("0.0.0.0:0").ok()?;
    s.connect("192.0.2.1:9").ok()?;
    let ip = s.local_addr().ok()?.ip();
    (!ip.is_loopback() && !ip.is_unspecified()).then_some(ip)
}

/// On another address the server offers only a user name and password, the password to be
/// encrypted with Basic256Sha256, and takes only `operator` with the password: an
/// anonymous client, a wrong password and another user are refused, the right login reads
/// the machine's serial number (its instance). SIGTERM
/// ends it with exit status 0.
#[test]
fn another_address_takes_only_the_user_with_the_password() {
    let Some(py) = python_with_asyncua() else {
        return;
    };
    let Some(ip) = own_address() else {
        eprintln!("this machine has no address besides loopback: test skipped");
        return;
    };
    let inst = instance("opcua-listen");
    let scope = Scope::light(&inst);
    let log = scratch("opcua-listen.log");
    let password = "correct horse battery";
    let mut server = spawn(
        "opcua",
        &[
            "--instance",
            scope.0.name(),
            "--listen",
            &ip.to_string(),
            "--port",
            "0",
            "--password",
            password,
        ],
        &log,
    );
    let addr = announced(&mut server, &log, "opc.tcp://");
    let url = format!("opc.tcp://{addr}/");
    // Only a user and password is offered, the password to be encrypted.
    let offered: Value = serde_json::from_str(client(&py, &[&url, "--policies"]).trim()).unwrap();
    let user = serde_json::json!({
        "type": "UserName",
        "security_policy": "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256",
    });
    assert_eq!(offered, serde_json::json!([user]));
    // Refused at session activation, each for its reason (not a timeout or a lost line).
    let anonymous = client(&py, &[&url, "--try-login"]);
    assert!(
        anonymous.starts_with("refused: BadIdentityTokenInvalid"),
        "{anonymous}"
    );
    for (user, pass) in [("operator", "wrong password!"), ("someone", password)] {
        let wrong = client(
            &py,
            &[&url, "--try-login", "--user", user, "--password", pass],
        );
        assert!(wrong.starts_with("refused: BadUserAccessDenied"), "{wrong}");
    }
    let right = client(
        &py,
        &[
            &url,
            "--try-login",
            "--user",
            "operator",
            "--password",
            password,
        ],
    );
    assert_eq!(right.trim(), format!("accepted: {}", scope.0.name()));
    // SAFETY: a plain signal to our own child.
    unsafe { libc::kill(server.0.id() as i32, libc::SIGTERM) };
    let status = ended(&mut server, Duration::from_secs(10));
    assert!(
        status.success(),
        "{}",
        std::fs::read_to_string(&log).unwrap()
    );
}

/// Without a password, or with a short one, the server does not start on another address.
#[test]
fn another_address_without_a_password_is_refused() {
    let inst = instance("opcua-nopass");
    let scope = Scope::light(&inst);
    for (extra, says) in [
        (&[][..], "--password"),
        (&["--password", "short"][..], "at least 12"),
    ] {
        let log = scratch("opcua-nopass.log");
        let mut args = vec![
            "--instance",
            scope.0.name(),
            "--listen",
            "0.0.0.0",
            "--port",
            "0",
        ];
        args.extend(extra);
        let mut kid = spawn("opcua", &args, &log);
        let status = ended(&mut kid, Duration::from_secs(10));
        let text = std::fs::read_to_string(&log).unwrap();
        assert_eq!(status.code(), Some(2), "{text}");
        assert!(text.contains(says), "{text}");
    }
}
