//! The HMI page in a real browser (issue 7): headless Chromium driven over WebDriver
//! (chromedriver) loads the page of a running control, stops the program, edits D1, resumes,
//! and sees the state and the plot follow. It keeps a screenshot in
//! target/hmi-screenshot.png (docs/img/hmi.png is one of these).
//!
//! Needs Debian's `chromium` and `chromium-driver`; without them the test says so and
//! passes, unless SOFTNC_REQUIRE_BROWSER is set (CI sets it, after installing them).

#[path = "support/control.rs"]
mod control;
#[path = "support/station.rs"]
mod station;

use control::*;
use hmi_bridge::client::Bridge;
use serde_json::{json, Value};
use station::*;
use std::process::{Command as Proc, Stdio};
use std::time::{Duration, Instant};

const ELEMENT: &str = "element-6066-11e4-a52e-4f735466cecf";

fn which(name: &str) -> Option<String> {
    let out = Proc::new("sh")
        .args(["-c", &format!("command -v {name}")])
        .output()
        .ok()?;
    let p = String::from_utf8_lossy(&out.stdout).trim().to_string();
    (!p.is_empty()).then_some(p)
}

/// A WebDriver session.
struct Browser {
    driver: Bridge,
    session: String,
    _kid: Kid,
}

impl Browser {
    /// The HMI page of the bridge at `addr`.
    fn open(&self, addr: &impl std::fmt::Display) {
        self.call("POST", "/url", json!({ "url": format!("http://{addr}/") }));
    }

    fn start(chromium: &str, chromedriver: &str) -> Browser {
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let kid = Kid(Proc::new(chromedriver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap());
        let driver = Bridge::new(format!("127.0.0.1:{port}"), None);
        let t = Instant::now();
        while driver.get("/status").is_err() {
            assert!(
                t.elapsed() < Duration::from_secs(20),
                "chromedriver did not start"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        let caps = json!({ "capabilities": { "alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {
                "binary": chromium,
                "args": ["--headless=new", "--no-sandbox", "--disable-gpu",
                         "--disable-dev-shm-usage", "--window-size=1440,980",
                         "--force-device-scale-factor=1"]
            }
        }}});
        let a = driver.post("/session", &caps).unwrap();
        assert_eq!(a.status, 200, "{}", a.body);
        let session = a.json()["value"]["sessionId"].as_str().unwrap().to_string();
        Browser {
            driver,
            session,
            _kid: kid,
        }
    }

    fn call(&self, method: &str, path: &str, body: Value) -> Value {
        let p = format!("/session/{}{path}", self.session);
        let a = self
            .driver
            .request(method, &p, Some(&body.to_string()))
            .unwrap();
        assert_eq!(a.status, 200, "{method} {path}: {}", a.body);
        a.json()["value"].clone()
    }

    fn script(&self, js: &str) -> Value {
        self.call("POST", "/execute/sync", json!({ "script": js, "args": [] }))
    }

    fn find(&self, css: &str) -> String {
        let v = self.call(
            "POST",
            "/element",
            json!({ "using": "css selector", "value": css }),
        );
        v[ELEMENT].as_str().unwrap().to_string()
    }

    fn click(&self, css: &str) {
        let e = self.find(css);
        self.call("POST", &format!("/element/{e}/click"), json!({}));
    }

    fn type_into(&self, css: &str, text: &str) {
        let e = self.find(css);
        self.call("POST", &format!("/element/{e}/clear"), json!({}));
        self.call(
            "POST",
            &format!("/element/{e}/value"),
            json!({ "text": text }),
        );
    }

    /// Waits until the script gives `want`.
    fn wait(&self, js: &str, want: &Value, limit: Duration) {
        let t = Instant::now();
        loop {
            let v = self.script(js);
            if &v == want {
                return;
            }
            assert!(t.elapsed() < limit, "{js} stayed {v}, wanted {want}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn screenshot(&self, to: &std::path::Path) {
        let v = self.call("GET", "/screenshot", json!({}));
        let png = decode_base64(v.as_str().unwrap());
        assert_eq!(&png[1..4], b"PNG");
        std::fs::write(to, png).unwrap();
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self
            .driver
            .request("DELETE", &format!("/session/{}", self.session), None);
    }
}

fn decode_base64(s: &str) -> Vec<u8> {
    let val = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in s.bytes().filter_map(val) {
        acc = (acc << 6) | c;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    out
}

/// Chromium and its driver; `None` (the test skipped) where they are not installed, unless
/// SOFTNC_REQUIRE_BROWSER asks for them.
fn browser() -> Option<(String, String)> {
    match (which("chromium"), which("chromedriver")) {
        (Some(c), Some(d)) => Some((c, d)),
        _ if std::env::var_os("SOFTNC_REQUIRE_BROWSER").is_some() => {
            panic!("chromium and chromedriver are required (SOFTNC_REQUIRE_BROWSER is set)")
        }
        _ => {
            eprintln!(
                "skipped: chromium or chromedriver not installed (Debian: chromium chromium-driver)"
            );
            None
        }
    }
}

const SQUARE: &str = "; softnc HMI demo: a square with G41, D1\nN10 G0 X-30 Y-30 Z0 M3 S800\nN20 G1 G41 D1 X0 Y0 F1500\nN30 Y100\nN40 X100\nN50 Y0\nN60 X0\nN70 G40 X-30 Y-30\nM30\n";

#[test]
fn the_page_stops_edits_an_offset_and_resumes() {
    let Some((chromium, chromedriver)) = browser() else {
        return;
    };
    let prog = scratch("square-hmi.mpf");
    std::fs::write(&prog, SQUARE).unwrap();
    let st = station("browser", Some(&prog), &["--set", "D1=10"], &[]);
    let b = Browser::start(&chromium, &chromedriver);
    b.open(&st.bridge.addr);
    b.wait(
        "return document.body.dataset.state",
        &json!("ACTIVE"),
        Duration::from_secs(30),
    );
    // The program text is shown and the plot drawn.
    b.wait(
        "return document.querySelectorAll('#program div').length",
        &json!(SQUARE.lines().count()),
        Duration::from_secs(10),
    );
    b.wait(
        "return document.querySelectorAll('#g-path polyline').length > 0",
        &json!(true),
        Duration::from_secs(10),
    );
    b.wait(
        "return [...document.querySelectorAll('span[data-axis]:not([id])')].map(e => e.textContent).join()",
        &json!("X,Y,Z"),
        Duration::from_secs(5),
    );
    // On the top edge (N40): the offset number and the spindle in force are shown; NC stop.
    st.watch(Duration::from_secs(60), |s| s["line"] == json!(5));
    b.wait(
        "return document.querySelector('#tool-now').textContent",
        &json!("D1"),
        Duration::from_secs(5),
    );
    b.wait(
        "return document.querySelector('#spindle-now').textContent",
        &json!("800 rev/min (actual 800)"),
        Duration::from_secs(5),
    );
    b.click("#btn-stop");
    b.wait(
        "return document.body.dataset.state",
        &json!("STOPPED"),
        Duration::from_secs(10),
    );
    let path_before = b.script("return document.querySelector('#g-path').innerHTML");
    // D1 from 10 to 12 (the global D1, not the lathe tools' T1 D1 and T2 D1).
    b.type_into("input[data-d='1']:not([data-t])[data-wear='0']", "12");
    b.click("button[data-set='1']:not([data-t])");
    b.wait(
        "return document.body.dataset.toolsVersion",
        &json!("2"),
        Duration::from_secs(10),
    );
    b.wait(
        "return document.querySelector('#msg').className",
        &json!("good"),
        Duration::from_secs(5),
    );
    // The plot follows the new radius.
    let t = Instant::now();
    while b.script("return document.querySelector('#g-path').innerHTML") == path_before {
        assert!(
            t.elapsed() < Duration::from_secs(10),
            "the plot did not change"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let tools = st.bridge.get("/api/tools").unwrap().json();
    assert_eq!(tools["offsets"][0]["radius"], json!(12.0));
    // NC start: repositioning, then on.
    b.click("#btn-start");
    b.wait(
        "return document.body.dataset.state",
        &json!("ACTIVE"),
        Duration::from_secs(10),
    );
    st.watch(Duration::from_secs(60), |s| s["line"] == json!(6));
    std::thread::sleep(Duration::from_millis(1500));
    let shot = root().join("target").join("hmi-screenshot.png");
    b.screenshot(&shot);
    b.wait(
        "return document.body.dataset.state",
        &json!("END"),
        Duration::from_secs(60),
    );
    assert!(std::fs::metadata(&shot).unwrap().len() > 10_000);
}

/// A lathe with a C axis (config/siemens-808d-c.toml): the page lists X, Z and C by name, C
/// in degrees within one turn while the setpoint counts on past 360°, the plot in the Z/X
/// plane, the tool table with each offset's cutting edge position; plc-sim's trace has X, Z
/// and C columns and no Y.
#[test]
fn the_page_shows_a_lathes_axes_by_name() {
    let Some((chromium, chromedriver)) = browser() else {
        return;
    };
    let prog = scratch("lathe-c-hmi.mpf");
    std::fs::write(
        &prog,
        "N10 G18 G90 G0 X62 Z2 C0\nN20 G91 C400\nN30 G90 G1 Z-20 F300\nM30\n",
    )
    .unwrap();
    let md = root().join("config/siemens-808d-c.toml");
    let md = ["--machine", md.to_str().unwrap()];
    let mut st = station_with("browser-lathe", &md, Some(&prog), &md, &md);
    let b = Browser::start(&chromium, &chromedriver);
    b.open(&st.bridge.addr);
    b.wait(
        "return document.body.dataset.state",
        &json!("END"),
        Duration::from_secs(60),
    );
    b.wait(
        "return [...document.querySelectorAll('span[data-axis]:not([id])')].map(e => e.textContent).join()",
        &json!("X,Z,C"),
        Duration::from_secs(5),
    );
    b.wait(
        "return document.querySelector('#pos-C').textContent",
        &json!("40.000°"),
        Duration::from_secs(5),
    );
    b.wait(
        "return document.querySelector('#plane').textContent",
        &json!("Z → X ↑"),
        Duration::from_secs(5),
    );
    // The tool table names each turning tool's cutting edge position (config/tools.toml:
    // T1 D1 in position 3, T1 D2 in 4), a milling cutter's none.
    b.wait(
        "return [...document.querySelectorAll('#tools tr')].map(r => r.cells[0].textContent + ':' + r.cells[1].textContent).filter(s => /^(D1|T1 D1|T1 D2):/.test(s)).join()",
        &json!("D1:–,T1 D1:3,T1 D2:4"),
        Duration::from_secs(5),
    );
    let end = st.status();
    assert_eq!(end["pos"][2], json!(400.0), "{end}");
    let rows = st.trace();
    let last = rows.last().unwrap();
    assert_eq!(last.axes.iter().map(|(c, _)| *c).collect::<String>(), "XZC");
    assert_eq!(last.axis('C').map(|c| c[0]), Some(400.0));
    assert_eq!(last.sp[1], 0.0, "a lathe has no Y");
}

/// The work-offset panel: the kernel's sets (G54 … G57 on the 840C) with a value per axis;
/// values typed into G54's row and set: the page follows the new table version and shows
/// the kernel's message, the values are in the API's table and in the saved file. A value
/// beyond `hmi.max_work_offset` is refused on the page with its reason, nothing changed.
#[test]
fn the_page_edits_a_work_offset() {
    let Some((chromium, chromedriver)) = browser() else {
        return;
    };
    let offsets = write("browser-wo.toml", "[G55]\nY = -7.5\n");
    let st = station(
        "browser-wo",
        None,
        &["--offsets", offsets.to_str().unwrap()],
        &[],
    );
    st.work_offsets();
    let b = Browser::start(&chromium, &chromedriver);
    b.open(&st.bridge.addr);
    b.wait(
        "return [...document.querySelectorAll('#work tr')].map(r => r.dataset.set).join()",
        &json!("G54,G55,G56,G57"),
        Duration::from_secs(10),
    );
    b.wait(
        "return [...document.querySelectorAll('#wo-head th')].map(e => e.textContent).join()",
        &json!("Set,X,Y,Z,"),
        Duration::from_secs(5),
    );
    let input = |set: &str, axis: &str| format!("tr[data-set='{set}'] input[data-axis='{axis}']");
    let value = |css: &str| format!("return document.querySelector(\"{css}\").value");
    b.wait(
        &value(&input("G55", "Y")),
        &json!("-7.5"),
        Duration::from_secs(5),
    );
    b.type_into(&input("G54", "X"), "12.5");
    b.type_into(&input("G54", "Z"), "-3");
    b.click("button[data-work='G54']");
    b.wait(
        "return document.body.dataset.workOffsetsVersion",
        &json!("2"),
        Duration::from_secs(10),
    );
    b.wait(
        "return document.querySelector('#wo-msg').className",
        &json!("good"),
        Duration::from_secs(5),
    );
    let msg = b.script("return document.querySelector('#wo-msg').textContent");
    assert!(msg.as_str().unwrap_or("").contains("G54"), "{msg}");
    // The table shown again, from the kernel's new version.
    b.wait(
        &value(&input("G54", "Z")),
        &json!("-3"),
        Duration::from_secs(5),
    );
    let table = st.work_offsets();
    assert_eq!(table["version"], json!(2));
    assert_eq!(
        table["sets"][0]["values"],
        json!({ "X": 12.5, "Y": 0.0, "Z": -3.0 })
    );
    let md = nc_kernel::MachineData::load(None, &[]).unwrap();
    let saved = nc_kernel::WorkOffsets::load(&offsets, &md).expect("a whole work-offset file");
    assert_eq!(saved.get(1)[..3], [12.5, 0.0, -3.0]);
    assert_eq!(saved.get(2)[..3], [0.0, -7.5, 0.0]);

    // Beyond the limit: refused with its reason, the version stays.
    b.type_into(&input("G56", "X"), "20000");
    b.click("button[data-work='G56']");
    b.wait(
        "return document.querySelector('#wo-msg').className",
        &json!("bad"),
        Duration::from_secs(5),
    );
    let msg = b.script("return document.querySelector('#wo-msg').textContent");
    assert!(
        msg.as_str().unwrap_or("").contains("hmi.max_work_offset"),
        "{msg}"
    );
    assert_eq!(st.work_offsets()["version"], json!(2));
    assert_eq!(
        b.script("return document.body.dataset.workOffsetsVersion"),
        json!("2")
    );
}
