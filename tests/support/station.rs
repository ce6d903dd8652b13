//! A whole control for a test: plc-sim, nc-kernel and hmi-bridge of one instance, and the
//! bridge's API as the test reads it.
#![allow(dead_code)] // each test file uses a different part

use crate::control::*;
use hmi_bridge::client::Bridge;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The `host:port` a starting hmi-bridge printed to its log.
pub fn bridge_address(log: &Path) -> String {
    let t = Instant::now();
    loop {
        let text = std::fs::read_to_string(log).unwrap_or_default();
        if let Some(a) = hmi_bridge::address_in(&text) {
            return a.to_string();
        }
        assert!(t.elapsed() < Duration::from_secs(30), "no bridge: {text}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// plc-sim, nc-kernel and hmi-bridge of one instance.
pub struct Station {
    pub bridge: Bridge,
    pub trace: PathBuf,
    // Children before the scope: they are killed before the instance is cleaned.
    pub kids: Vec<Kid>,
    _scope: Scope,
}

pub fn station(tag: &str, program: Option<&Path>, kernel: &[&str], bridge: &[&str]) -> Station {
    station_with(tag, &[], program, kernel, bridge)
}

/// A station whose plc-sim takes `plc` too (its machine data for one).
pub fn station_with(
    tag: &str,
    plc: &[&str],
    program: Option<&Path>,
    kernel: &[&str],
    bridge: &[&str],
) -> Station {
    let name = instance(tag);
    let scope = Scope::new(&name);
    let trace = scratch(&format!("{tag}.csv"));
    let mut plc_args = vec![
        "--instance",
        name.as_str(),
        "--trace",
        trace.to_str().unwrap(),
    ];
    plc_args.extend(plc);
    let mut kids = vec![spawn(
        "plc-sim",
        &plc_args,
        &scratch(&format!("{tag}-plc.log")),
    )];
    let mut args = vec!["--instance", name.as_str()];
    if let Some(p) = program {
        args.extend([p.to_str().unwrap(), "--start"]);
    }
    args.extend(kernel);
    kids.push(spawn(
        "nc-kernel",
        &args,
        &scratch(&format!("{tag}-nck.log")),
    ));
    let log = scratch(&format!("{tag}-hmi.log"));
    let mut args = vec!["--instance", name.as_str(), "--port", "0"];
    args.extend(bridge);
    kids.push(spawn("hmi-bridge", &args, &log));
    let addr = bridge_address(&log);
    let token = bridge
        .windows(2)
        .find(|w| w[0] == "--token")
        .map(|w| w[1].to_string());
    let s = Station {
        bridge: Bridge::new(addr, token),
        trace,
        kids,
        _scope: scope,
    };
    s.watch(Duration::from_secs(30), |v| v["connected"] == json!(true));
    // Ready when the kernel's tool table has arrived too.
    let t = Instant::now();
    while s.bridge.get("/api/tools").unwrap().status != 200 {
        assert!(t.elapsed() < Duration::from_secs(10), "no tool table");
        std::thread::sleep(Duration::from_millis(10));
    }
    s
}

impl Station {
    pub fn status(&self) -> Value {
        let a = self.bridge.get("/api/status").unwrap();
        assert_eq!(a.status, 200, "{}", a.body);
        a.json()
    }

    /// Statuses until `until` holds for one (all of them returned), within `limit`.
    pub fn watch(&self, limit: Duration, until: impl Fn(&Value) -> bool) -> Vec<Value> {
        let t = Instant::now();
        let mut seen = Vec::new();
        while t.elapsed() < limit {
            let s = self.status();
            let done = until(&s);
            seen.push(s);
            if done {
                return seen;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        panic!("not reached in {limit:?}; last {:?}", seen.last());
    }

    /// The kernel's work-offset table through the bridge, once it has arrived (it is
    /// published just after the tool table).
    pub fn work_offsets(&self) -> Value {
        let t = Instant::now();
        loop {
            let a = self.bridge.get("/api/work-offsets").unwrap();
            if a.status == 200 {
                return a.json();
            }
            assert!(
                t.elapsed() < Duration::from_secs(10),
                "no work-offset table: {}",
                a.body
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// NC stop through the API; the status once the channel is in NC stop, at rest.
    pub fn nc_stop(&self) -> Value {
        assert_eq!(self.post("/api/stop", json!({})).0, 200);
        self.watch(Duration::from_secs(10), |s| s["state"] == json!("STOPPED"))
            .pop()
            .unwrap()
    }

    /// Waits (within `limit`) for the program's end or an alarm, and asserts it ended
    /// without one; the last status.
    pub fn until_end(&self, limit: Duration) -> Value {
        let end = self
            .watch(limit, |s| {
                s["state"] == json!("END") || !s["alarm"].is_null()
            })
            .pop()
            .unwrap();
        assert_eq!(
            (end["state"].clone(), end["alarm"].clone()),
            (json!("END"), Value::Null),
            "the program ends without an alarm"
        );
        end
    }

    pub fn post(&self, path: &str, body: Value) -> (u16, Value) {
        let a = self.bridge.post(path, &body).unwrap();
        (a.status, a.json())
    }

    /// plc-sim ends (flushing its trace); its rows.
    pub fn trace(&mut self) -> Vec<TraceRow> {
        terminate(&mut self.kids[0]);
        trace(&self.trace)
    }
}

pub fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

pub fn pos(s: &Value) -> [f64; 3] {
    [f(&s["pos"][0]), f(&s["pos"][1]), f(&s["pos"][2])]
}

pub fn write(name: &str, text: &str) -> PathBuf {
    let p = scratch(name);
    std::fs::write(&p, text).unwrap();
    p
}
