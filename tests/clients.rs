//! Clients in other languages (docs/interfaces.md): the C header compiled and the Python
//! classes asked for their layout, both against the Rust payloads; a client of another party
//! attached across the end of `softnc run`; the Python subscriber on a whole run.
//!
//! Without a C compiler, or a Python with the iceoryx2 package of the crate's version, a
//! test says so and passes, unless SOFTNC_REQUIRE_CLIENTS is set (.ci/run makes a venv and
//! points SOFTNC_CLIENTS_PYTHON at it): then it fails.

#[path = "support/control.rs"]
mod control;

use control::*;
use softnc_protocol::iceoryx2::node::{Node, NodeBuilder};
use softnc_protocol::iceoryx2::port::subscriber::Subscriber;
use softnc_protocol::iceoryx2::prelude::*;
use softnc_protocol::iceoryx2::service::attribute::{AttributeKey, AttributeValue};
use softnc_protocol::iceoryx2::service::port_factory::publish_subscribe::PortFactory;
use softnc_protocol::iceoryx2::service::port_factory::PortFactory as _;
use softnc_protocol::layout::payloads;
use softnc_protocol::{abi, services::ABI_KEY, state, Instance, SetpointMsg};
use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command as Proc, Stdio};
use std::time::{Duration, Instant};

/// Whether a client language's tool is here; without it the test says so and passes, unless
/// SOFTNC_REQUIRE_CLIENTS is set.
fn available(what: &str, ok: bool) -> bool {
    if !ok {
        if std::env::var_os("SOFTNC_REQUIRE_CLIENTS").is_some() {
            panic!("{what} not found, and SOFTNC_REQUIRE_CLIENTS is set (.ci/run installs it)");
        }
        eprintln!("{what} not found: test skipped (.ci/run installs it)");
    }
    ok
}

/// The Python of the clients' tests: .ci/run's venv, or python3.
fn python() -> String {
    std::env::var("SOFTNC_CLIENTS_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// Runs `program args`, its stdout if it exits 0.
fn stdout_of(program: &str, args: &[&str]) -> Option<String> {
    let out = Proc::new(program)
        .args(args)
        .current_dir(root())
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The iceoryx2 version Cargo.toml pins (`iceoryx2 = "=0.10.0"`).
fn iceoryx2_version() -> String {
    let toml = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let line = toml
        .lines()
        .find(|l| l.starts_with("iceoryx2 = \"="))
        .expect("Cargo.toml pins iceoryx2");
    line.trim_start_matches("iceoryx2 = \"=")
        .trim_end_matches('"')
        .to_string()
}

/// Every payload's size and alignment, and every field's offset and size, one per line, as
/// the Rust types have them: what the C and Python probes below must print.
fn rust_layout() -> String {
    let mut s = String::new();
    for p in payloads() {
        writeln!(s, "{} {} {}", p.rust, p.size, p.align).unwrap();
        for f in &p.fields {
            writeln!(s, "{}.{} {} {}", p.rust, f.name, f.offset, f.size).unwrap();
        }
    }
    s
}

/// A C program printing the same lines from the header, by sizeof, _Alignof and offsetof.
fn c_probe() -> String {
    let mut c =
        String::from("#include <stddef.h>\n#include <stdio.h>\n#include \"softnc_ipc.h\"\n");
    c.push_str("int main(void) {\n");
    for p in payloads() {
        let t = format!("struct softnc_{}", p.rust);
        writeln!(
            c,
            "    printf(\"{} %zu %zu\\n\", sizeof({t}), _Alignof({t}));",
            p.rust
        )
        .unwrap();
        for f in &p.fields {
            writeln!(
                c,
                "    printf(\"{}.{} %zu %zu\\n\", offsetof({t}, {}), sizeof((({t} *)0)->{}));",
                p.rust, f.name, f.name, f.name
            )
            .unwrap();
        }
    }
    c.push_str("    return 0;\n}\n");
    c
}

#[test]
fn the_c_header_has_the_rust_layout() {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    if !available("a C compiler", stdout_of(&cc, &["--version"]).is_some()) {
        return;
    }
    let (src, exe) = (scratch("layout_probe.c"), scratch("layout_probe"));
    std::fs::write(&src, c_probe()).unwrap();
    let built = Proc::new(&cc)
        .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic", "-I"])
        .arg(root().join("clients/c"))
        .arg(&src)
        .arg("-o")
        .arg(&exe)
        .output()
        .unwrap();
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let printed = stdout_of(exe.to_str().unwrap(), &[]).expect("the probe runs");
    assert_eq!(printed, rust_layout());
}

/// Prints what `rust_layout` does from the ctypes classes, then each one's type name.
const PY_PROBE: &str = r#"
import ctypes, sys
sys.path.insert(0, "clients/python")
import softnc_ipc as s
for c in s.PAYLOADS:
    print(c.__name__, ctypes.sizeof(c), ctypes.alignment(c))
    for name, _ in c._fields_:
        f = getattr(c, name)
        print(f"{c.__name__}.{name} {f.offset} {f.size}")
for c in s.PAYLOADS:
    print(c.type_name())
print(s.ABI)
"#;

#[test]
fn the_python_classes_have_the_rust_layout() {
    let py = python();
    if !available("python3", stdout_of(&py, &["--version"]).is_some()) {
        return;
    }
    let printed = stdout_of(&py, &["-c", PY_PROBE]).expect("the probe runs");
    let mut expected = rust_layout();
    for p in payloads() {
        writeln!(expected, "{}", p.type_name).unwrap();
    }
    writeln!(expected, "{}", abi()).unwrap();
    assert_eq!(printed, expected);
}

/// A client of another party in Rust: a node of its own (not one of softnc's roles) with a
/// subscriber to the setpoints, opened, never created, and only with this build's ABI.
struct Monitor {
    subscriber: Subscriber<ipc::Service, SetpointMsg, ()>,
    service: PortFactory<ipc::Service, SetpointMsg, ()>,
    _node: Node<ipc::Service>,
}

/// What a client saw of the setpoints.
#[derive(Debug, Default)]
struct Seen {
    count: u64,
    gaps: u64,
    first: Option<SetpointMsg>,
    last: Option<SetpointMsg>,
}

impl Monitor {
    /// Attaches to `inst` (`node_created` is called once its node exists) and opens the
    /// setpoints as soon as softnc has created them.
    fn attach(inst: &Instance, node_created: impl FnOnce()) -> Monitor {
        let node = NodeBuilder::new()
            .name(&NodeName::new("hil-monitor").unwrap())
            .config(inst.config())
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .unwrap();
        node_created();
        let name = inst.service_name("setpoints").unwrap();
        let key = AttributeKey::new(ABI_KEY.as_bytes()).unwrap();
        let abi = AttributeValue::new(abi().as_bytes()).unwrap();
        let verifier = AttributeVerifier::new().require(&key, &abi).unwrap();
        let t = Instant::now();
        let service = loop {
            match node
                .service_builder(&name)
                .publish_subscribe::<SetpointMsg>()
                .open_with_attributes(&verifier)
            {
                Ok(s) => break s,
                Err(e) if t.elapsed() > Duration::from_secs(60) => panic!("{e:?}"),
                Err(_) => std::thread::sleep(Duration::from_millis(10)),
            }
        };
        let subscriber = service.subscriber_builder().create().unwrap();
        Monitor {
            subscriber,
            service,
            _node: node,
        }
    }

    /// Every setpoint until the kernel has gone (its publisher with it).
    fn follow(&self, limit: Duration) -> Seen {
        let mut seen = Seen::default();
        let t = Instant::now();
        loop {
            let mut got = false;
            while let Ok(Some(s)) = self.subscriber.receive() {
                let msg = *s.payload();
                if seen.last.is_some_and(|l| msg.seq != l.seq + 1) {
                    seen.gaps += 1;
                }
                seen.first.get_or_insert(msg);
                seen.last = Some(msg);
                seen.count += 1;
                got = true;
            }
            let gone = self.service.dynamic_config().number_of_publishers() == 0;
            if (seen.count > 0 && gone && !got) || t.elapsed() > limit {
                return seen;
            }
            std::thread::sleep(Duration::from_micros(500));
        }
    }
}

/// A HIL monitor attached from before the run until after its end: it sees every setpoint,
/// `softnc run` ends with exit 0 and names it, and what the monitor held goes with it.
#[test]
fn a_client_attached_past_the_end_of_a_run_is_normal() {
    let inst = instance("client");
    let scope = Scope::new(&inst);
    let (prog, tr) = (line_program("client.mpf", 'X', 50.0), scratch("client.csv"));
    let (seen, run) = Monitor::across_a_run(&scope.0, &prog, &tr);
    assert!(run.success(), "{}", run.said());
    assert!(run.stdout.contains("ran to its end"), "{}", run.stdout);
    assert!(
        run.stdout
            .contains("still attached to the instance, not started by this run: hil-monitor"),
        "{}",
        run.stdout
    );
    // N1 G0 X0 Y0 Z0, N2 G1 F3000 X50, M30: it ends at X50 Y0 Z0.
    let (first, last) = (seen.first.unwrap(), seen.last.unwrap());
    assert_eq!(seen.gaps, 0, "{seen:?}");
    assert_eq!(seen.count, last.seq - first.seq + 1);
    assert_eq!(first.state, state::RESET, "attached before NC start");
    assert_eq!(
        (last.state, &last.pos[..3]),
        (state::END, &[50.0, 0.0, 0.0][..])
    );
    // Its services went with it; softnc clean's part is the node counter.
    assert_eq!(
        scope.0.remove_when_unused().unwrap(),
        Vec::<std::path::PathBuf>::new()
    );
}

impl Monitor {
    /// Attaches to `instance` in a thread of its own while `softnc run` starts on it, follows
    /// the setpoints until the kernel has gone, and stays attached until the run has ended.
    fn across_a_run(instance: &Instance, prog: &Path, tr: &Path) -> (Seen, RunOutput) {
        let client_side = instance.clone();
        let (created, node_up) = std::sync::mpsc::channel();
        let (ended, run_over) = std::sync::mpsc::channel::<()>();
        let client = std::thread::spawn(move || {
            let monitor = Monitor::attach(&client_side, move || {
                let _ = created.send(());
            });
            let seen = monitor.follow(Duration::from_secs(120));
            let _ = run_over.recv_timeout(Duration::from_secs(300));
            seen
        });
        // The node first: a run accepts an instance a client is already on.
        node_up.recv_timeout(Duration::from_secs(30)).unwrap();
        let run = softnc_run(prog, instance.name(), tr, &[]);
        let _ = ended.send(());
        (client.join().unwrap(), run)
    }
}

/// A Python with the iceoryx2 package of the crate's version, if there is one.
fn python_with_iceoryx2() -> Option<String> {
    let py = python();
    let want = iceoryx2_version();
    let probe = "import importlib.metadata as m, iceoryx2; print(m.version('iceoryx2'))";
    let found = stdout_of(&py, &["-c", probe]).map(|s| s.trim().to_string());
    let what = format!("{py} with the iceoryx2 package {want} (found {found:?})");
    available(&what, found.as_deref() == Some(want.as_str())).then_some(py)
}

/// The Done-when of the clients' part: the Python subscriber (clients/python) on a whole
/// `softnc run` of the ISG star (programs/isg/g238_star.nc, config/isg.toml). It attaches
/// before the run, sees every setpoint with no gap, and the last one is the program's end
/// point: N400 G00 X0 Y0 after G40 (N390) takes the tool centre back to X0 Y0, and Z stays
/// 0 from N2 (D1's length acts from the next block that programs Z; none does). The run
/// exits 0 with the subscriber still attached.
#[test]
fn a_python_subscriber_sees_every_setpoint_of_a_run() {
    let Some(py) = python_with_iceoryx2() else {
        return;
    };
    let inst = instance("python");
    let scope = Scope::new(&inst);
    let tr = scratch("python.csv");
    let script = root().join("clients/python/softnc_subscribe.py");
    let mut sub = Kid(Proc::new(&py)
        .arg(&script)
        .args([
            "--instance",
            &inst,
            "--json",
            "--hold",
            "5",
            "--wait",
            "120",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap());
    let t = Instant::now();
    while !scope
        .0
        .users()
        .iter()
        .any(|u| u.name == "python-subscriber")
    {
        assert!(
            t.elapsed() < Duration::from_secs(60),
            "the subscriber did not start"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let run = softnc_run(
        Path::new("programs/isg/g238_star.nc"),
        &inst,
        &tr,
        &["--machine", "config/isg.toml"],
    );
    assert!(run.success(), "{}", run.said());
    assert!(
        run.stdout
            .contains("still attached to the instance, not started by this run: python-subscriber"),
        "{}",
        run.stdout
    );
    let out = wait_for(&mut sub, Duration::from_secs(60));
    let s: serde_json::Value = serde_json::from_str(out.trim()).expect(&out);
    assert_eq!(s["gaps"], 0, "{s}");
    assert_eq!(s["lost"], 0, "{s}");
    assert_eq!(s["restarts"], 0, "{s}");
    assert_eq!(s["first_state"], "RESET", "attached before NC start: {s}");
    let (first, last) = (
        s["first_seq"].as_u64().unwrap(),
        s["last_seq"].as_u64().unwrap(),
    );
    assert_eq!(s["setpoints"].as_u64(), Some(last - first + 1), "{s}");
    assert_eq!(
        (&s["state"], &s["alarm"], &s["axes"]),
        (&"END".into(), &0.into(), &"XYZ".into())
    );
    assert_eq!(s["pos"], serde_json::json!([0.0, 0.0, 0.0]), "{s}");
    // plc-sim drove the axes to the same point.
    assert_eq!(trace(&tr).last().unwrap().sp, [0.0, 0.0, 0.0]);
    assert_eq!(
        scope.0.remove_when_unused().unwrap(),
        Vec::<std::path::PathBuf>::new()
    );
}

/// The child's stdout once it has exited 0 within `limit`.
fn wait_for(kid: &mut Kid, limit: Duration) -> String {
    let t = Instant::now();
    let status = loop {
        if let Some(s) = kid.0.try_wait().unwrap() {
            break s;
        }
        assert!(t.elapsed() < limit, "the subscriber did not end");
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut out = String::new();
    let mut err = String::new();
    use std::io::Read;
    kid.0
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    kid.0
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(status.success(), "{status}: {out}\n{err}");
    out
}
