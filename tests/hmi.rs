//! The HMI bridge (issue 7): offsets changed at the machine through the HTTP API, end to end
//! with kernel and plc-sim, checked from plc-sim's trace; bad requests of every kind refused
//! with a 4xx and a message, changing nothing; the `softnc` commands that go through the
//! bridge. The browser test is tests/browser.rs.

#[path = "support/control.rs"]
mod control;
#[path = "support/station.rs"]
mod station;

use control::*;
use hmi_bridge::client::Bridge;
use serde_json::{json, Value};
use station::*;
use std::io::{Read, Write};
use std::time::{Duration, Instant};

/// Distance from `p` (outside it) to the square [0, 100]².
fn off_square(p: [f64; 3]) -> f64 {
    let dx = (0.0 - p[0]).max(p[0] - 100.0).max(0.0);
    let dy = (0.0 - p[1]).max(p[1] - 100.0).max(0.0);
    (dx * dx + dy * dy).sqrt()
}

const SQUARE: &str = "N10 G0 X-30 Y-30 Z0\nN20 G1 G41 D1 X0 Y0 F3000\nN30 Y100\nN40 X100\nN50 Y0\nN60 X0\nN70 G40 X-30 Y-30\nM30\n";

/// 840C 11.8 through the HMI: D1 changed from 10 to 12 in NC stop halfway along the top
/// edge of a square (G41, outside, G450 corners). NC start repositions onto the new
/// equidistant, and from there every setpoint of the contour lies 12 mm from the square;
/// before the stop every one lay 10 mm from it. The same edit while the program runs is
/// refused and changes nothing.
#[test]
fn offset_changed_in_nc_stop_resumes_on_the_new_equidistant() {
    let prog = write("square.mpf", SQUARE);
    let mut st = station("offset", Some(&prog), &["--set", "D1=10"], &[]);
    // On N40 (line 4), at speed.
    st.watch(Duration::from_secs(30), |s| {
        s["line"] == json!(4) && f(&s["feed_mm_min"]) > 2400.0
    });
    let (code, r) = st.post("/api/offset", json!({ "d": 1, "radius": 12.0 }));
    assert_eq!(code, 409, "{r}");
    assert!(r["error"].as_str().unwrap().contains("running"), "{r}");
    let stopped = st.nc_stop();
    assert_eq!(
        stopped["tools_version"],
        json!(1),
        "the refused edit changed nothing"
    );
    assert_eq!(stopped["line"], json!(4));
    // The status shows the offset number in force (no T on the 840C).
    assert_eq!(
        (&stopped["edge"], &stopped["tool"]),
        (&json!(1), &Value::Null)
    );
    assert!((off_square(pos(&stopped)) - 10.0).abs() < 1e-6);
    let (code, r) = st.post("/api/offset", json!({ "d": 1, "radius": 12.0 }));
    assert_eq!(code, 200, "{r}");
    assert_eq!(r["tools_version"], json!(2), "{r}");
    let tools = st.bridge.get("/api/tools").unwrap().json();
    assert_eq!(
        (
            tools["version"].clone(),
            tools["offsets"][0]["radius"].clone()
        ),
        (json!(2), json!(12.0))
    );
    let (code, r) = st.post("/api/start", json!({}));
    assert_eq!(code, 200, "{r}");
    st.until_end(Duration::from_secs(30));

    let rows = st.trace();
    let contour = |r: &TraceRow| (3..=6).contains(&r.line);
    let stop = rows
        .iter()
        .position(|r| r.state == "STOPPED")
        .expect("NC stop in the trace");
    let mut checked = [0usize; 2];
    for (i, r) in rows[..stop].iter().enumerate().filter(|(_, r)| contour(r)) {
        let d = off_square(r.sp);
        assert!((d - 10.0).abs() < 1e-6, "row {i} before the stop: {d} mm");
        checked[0] += 1;
    }
    // After NC start: the reposition move (moving out from 10 to 12 mm), then the contour
    // at 12 mm up to the retract.
    let on_new = stop
        + rows[stop..]
            .iter()
            .position(|r| (off_square(r.sp) - 12.0).abs() < 1e-6)
            .expect("the path reaches the new equidistant");
    for (i, r) in rows.iter().enumerate().take(on_new).skip(stop) {
        let d = off_square(r.sp);
        assert!(
            (10.0 - 1e-6..=12.0 + 1e-6).contains(&d),
            "reposition row {i}: {d}"
        );
    }
    for (i, r) in rows
        .iter()
        .enumerate()
        .skip(on_new)
        .filter(|(_, r)| contour(r))
    {
        let d = off_square(r.sp);
        assert!((d - 12.0).abs() < 1e-6, "row {i} after resuming: {d} mm");
        checked[1] += 1;
    }
    assert!(checked[0] > 2000 && checked[1] > 4000, "{checked:?}");
}

/// An offset that would violate the contour (a slot 22 mm wide: R 12 does not fit, 840C
/// 11.12): NC start is refused with the alarm and nothing moves; the offset set back, NC
/// start goes on.
#[test]
fn an_offset_that_violates_the_contour_is_refused_before_any_motion() {
    let prog = write(
        "slot.mpf",
        "N10 G0 X-30 Y-30 Z0\nN20 G1 G41 D1 X0 Y0 F3000\nN30 Y100\nN40 X40\nN50 Y60\nN60 X62\nN70 Y100\nN80 X100\nN90 Y0\nN100 X0\nN110 G40 X-30 Y-30\nM30\n",
    );
    let st = station("violate", Some(&prog), &["--set", "D1=10"], &[]);
    st.watch(Duration::from_secs(30), |s| {
        s["line"] == json!(3) && f(&s["feed_mm_min"]) > 2400.0
    });
    let stopped = st.nc_stop();
    assert_eq!(
        st.post("/api/offset", json!({ "d": 1, "radius": 12.0 })).0,
        200
    );
    let (code, r) = st.post("/api/start", json!({}));
    assert_eq!(code, 409, "{r}");
    assert_eq!(r["alarm"], json!(3021), "{r}");
    assert!(
        r["error"].as_str().unwrap().contains("nothing moved"),
        "{r}"
    );
    let c0 = stopped["cycle"].as_u64().unwrap();
    for s in st.watch(Duration::from_secs(5), |s| {
        s["cycle"].as_u64().unwrap() > c0 + 300
    }) {
        assert_eq!(s["state"], json!("STOPPED"));
        assert_eq!(pos(&s), pos(&stopped));
    }
    // Set back to 10: NC start resumes and the program runs to its end.
    assert_eq!(
        st.post("/api/offset", json!({ "d": 1, "radius": 10.0 })).0,
        200
    );
    let (code, r) = st.post("/api/start", json!({}));
    assert_eq!(code, 200, "{r}");
    st.until_end(Duration::from_secs(30));
}

/// With machine data `hmi.edit_while_active`, an edit while the program runs is stored and
/// acts when the program next programs that D (840C 11.8): the contour running at the edit
/// keeps R 10, the one selected with D1 after it runs on R 12.
#[test]
fn an_edit_while_active_acts_at_the_next_d_when_machine_data_allows_it() {
    let mut text = String::from("N10 G0 X-30 Y-30 Z0\nN20 G1 G41 D1 X0 Y0 F3000\n");
    for k in 1..=600 {
        text.push_str(&format!("Y{k}\n"));
    }
    // Lines 603–607.
    text.push_str("G40 X-30 Y650\nG41 D1 X0 Y700\nY800\nG40 X-30 Y850\nM30\n");
    let prog = write("live.mpf", &text);
    let md = write("live.toml", "[hmi]\nedit_while_active = true\n");
    let md = md.to_str().unwrap();
    let mut st = station("live", Some(&prog), &["--machine", md], &["--machine", md]);
    st.watch(Duration::from_secs(30), |s| {
        f(&s["pos"][1]) > 20.0 && f(&s["feed_mm_min"]) > 2400.0
    });
    let (code, r) = st.post("/api/offset", json!({ "d": 1, "radius": 12.0 }));
    assert_eq!(code, 200, "{r}");
    assert!(
        r["message"]
            .as_str()
            .unwrap()
            .contains("next programs this D"),
        "{r}"
    );
    let y_edit = f(&st.status()["pos"][1]);
    st.until_end(Duration::from_secs(60));
    let rows = st.trace();
    let first: Vec<_> = rows
        .iter()
        .filter(|r| (3..=602).contains(&r.line))
        .collect();
    assert!(first.iter().any(|r| r.sp[1] > y_edit + 100.0));
    for r in &first {
        assert!(
            (r.sp[0] + 10.0).abs() < 1e-9,
            "first contour at x = {}",
            r.sp[0]
        );
    }
    let second: Vec<_> = rows.iter().filter(|r| r.line == 605).collect();
    assert!(second.len() > 1000, "{}", second.len());
    for r in &second {
        assert!(
            (r.sp[0] + 12.0).abs() < 1e-9,
            "second contour at x = {}",
            r.sp[0]
        );
    }
}

/// A raw POST to /api/offset with the token and `fields` (each ending in CRLF), then
/// `body`.
fn offset_post(fields: &str, body: &str) -> Vec<u8> {
    format!("POST /api/offset HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer {TOKEN}\r\n{fields}\r\n{body}")
        .into_bytes()
}

/// One raw request; the status code of the answer (or 0 if the connection closed without
/// one) and its text.
fn raw(addr: &str, bytes: &[u8]) -> (u16, String) {
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    let _ = s.write_all(bytes);
    let mut out = Vec::new();
    let _ = s.read_to_end(&mut out);
    let text = String::from_utf8_lossy(&out).to_string();
    let code = text
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    (code, text)
}

const TOKEN: &str = "s3cret-token-for-tests";

/// An hmi-bridge alone (no kernel: every request below is refused before one is asked),
/// with a token.
struct Lone {
    bridge: Bridge,
    _kid: Kid,
    _scope: Scope,
}

fn lone(tag: &str) -> Lone {
    let name = instance(tag);
    let scope = Scope::light(&name);
    let log = scratch(&format!("{tag}-hmi.log"));
    let kid = spawn(
        "hmi-bridge",
        &["--instance", &name, "--port", "0", "--token", TOKEN],
        &log,
    );
    let addr = bridge_address(&log);
    Lone {
        bridge: Bridge::new(addr, Some(TOKEN.into())),
        _kid: kid,
        _scope: scope,
    }
}

/// The answer has status `want` and a message that says something.
/// A program with a byte that is not UTF-8 in a comment (an old editor's Latin-1 `Ø`): the
/// control loads, runs and shows it as `softnc check` reads it, the byte as U+FFFD (in a word
/// the byte is an alarm at its line and column, as any character the language does not know).
#[test]
fn a_latin1_byte_in_a_comment_runs_and_shows_as_softnc_check_reads_it() {
    let prog = scratch("latin1.mpf");
    std::fs::write(
        &prog,
        b"N10 G0 X0 Y0 Z0 (\xD8 10 mm)\nN20 G1 X10 F3000\nM30\n",
    )
    .unwrap();
    let check = std::process::Command::new(env!("CARGO_BIN_EXE_softnc"))
        .arg("check")
        .arg(&prog)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&check.stderr);
    assert!(check.status.success(), "{said}");
    let st = station("latin1", Some(&prog), &[], &[]);
    let end = st.until_end(Duration::from_secs(30));
    assert!((pos(&end)[0] - 10.0).abs() < 1e-6, "{end}");
    let shown = st.bridge.get("/api/program").unwrap();
    assert_eq!(shown.status, 200, "{}", shown.body);
    let text = "N10 G0 X0 Y0 Z0 (\u{FFFD} 10 mm)\nN20 G1 X10 F3000\nM30\n";
    assert_eq!(shown.json()["text"], json!(text));
    let plot = st.bridge.get("/api/plot").unwrap();
    assert_eq!(plot.status, 200, "{}", plot.body);
}

fn refused(a: hmi_bridge::client::Answer, want: u16, what: &str) -> String {
    assert_eq!(a.status, want, "{what}: {}", a.body);
    let msg = a.json()["error"].as_str().unwrap_or("").to_string();
    assert!(msg.len() > 5, "{what}: no message in {}", a.body);
    msg
}

fn offset_raw(b: &Bridge, body: &str) -> hmi_bridge::client::Answer {
    b.request("POST", "/api/offset", Some(body)).unwrap()
}

#[test]
fn a_missing_token_is_refused() {
    let l = lone("notoken");
    let none = Bridge::new(l.bridge.addr.clone(), None);
    let m = refused(none.get("/api/status").unwrap(), 401, "status");
    assert!(m.contains("token"), "{m}");
    refused(offset_raw(&none, r#"{"d":1,"radius":12}"#), 401, "offset");
    refused(none.get("/").unwrap(), 401, "the page");
}

#[test]
fn a_wrong_token_is_refused() {
    let l = lone("wrongtoken");
    let wrong = Bridge::new(l.bridge.addr.clone(), Some("not-the-token-at-all".into()));
    let m = refused(offset_raw(&wrong, r#"{"d":1,"radius":12}"#), 401, "offset");
    assert!(m.contains("wrong token"), "{m}");
    // The token in the address (event streams and the page) is checked alike.
    let (code, _) = raw(
        &l.bridge.addr,
        b"GET /api/events?token=nope HTTP/1.1\r\nHost: x\r\n\r\n",
    );
    assert_eq!(code, 401);
}

#[test]
fn malformed_json_is_refused() {
    let l = lone("malformed");
    for body in [
        r#"{"d":1,"radius":"#,
        "radius=12",
        "",
        "[1,2]",
        r#"{"d":1,"radius":1e999}"#,
    ] {
        let m = refused(offset_raw(&l.bridge, body), 400, body);
        assert!(m.contains("malformed JSON"), "{body}: {m}");
    }
    refused(
        l.bridge
            .request("POST", "/api/start", Some("[1,2]"))
            .unwrap(),
        400,
        "start",
    );
}

#[test]
fn nan_is_refused() {
    let l = lone("nan");
    refused(offset_raw(&l.bridge, r#"{"d":1,"radius":NaN}"#), 400, "NaN");
    refused(
        offset_raw(&l.bridge, r#"{"d":1,"radius":"NaN"}"#),
        400,
        "NaN as text",
    );
}

#[test]
fn unknown_and_missing_fields_are_refused() {
    let l = lone("fields");
    let m = refused(
        offset_raw(&l.bridge, r#"{"d":1,"radius":12,"force":true}"#),
        400,
        "unknown",
    );
    assert!(m.contains("force"), "{m}");
    let m = refused(offset_raw(&l.bridge, r#"{"d":1}"#), 400, "missing");
    assert!(m.contains("radius"), "{m}");
    refused(
        offset_raw(&l.bridge, r#"{"d":-1,"radius":12}"#),
        400,
        "negative D",
    );
}

#[test]
fn huge_values_are_refused() {
    let l = lone("huge");
    let m = refused(
        offset_raw(&l.bridge, r#"{"d":1,"radius":1e300}"#),
        422,
        "1e300",
    );
    assert!(m.contains("hmi.max_radius"), "{m}");
    refused(
        offset_raw(&l.bridge, r#"{"d":1,"radius":-500.5}"#),
        422,
        "beyond the limit",
    );
    let m = refused(
        offset_raw(&l.bridge, r#"{"d":1,"radius":1.5,"wear":true}"#),
        422,
        "wear",
    );
    assert!(m.contains("hmi.max_wear"), "{m}");
    refused(
        l.bridge
            .post("/api/override", &json!({ "percent": 500 }))
            .unwrap(),
        422,
        "override",
    );
}

#[test]
fn oversized_bodies_are_refused() {
    let l = lone("oversized");
    let big = format!(r#"{{"d":1,"radius":12,"x":"{}"}}"#, "a".repeat(20_000));
    refused(offset_raw(&l.bridge, &big), 413, "20 kB");
    // Announced far larger than allowed: refused before it is read.
    let (code, text) = raw(
        &l.bridge.addr,
        &offset_post("Content-Length: 1000000000\r\n", "{"),
    );
    assert_eq!(code, 413, "{text}");
    // A body without a length.
    let (code, text) = raw(
        &l.bridge.addr,
        &offset_post("Transfer-Encoding: chunked\r\n", ""),
    );
    assert_eq!(code, 411, "{text}");
    // A head with too many fields.
    let mut head = String::from("GET /api/status HTTP/1.1\r\n");
    for i in 0..100 {
        head.push_str(&format!("X-Field-{i}: {i}\r\n"));
    }
    head.push_str("\r\n");
    assert_eq!(raw(&l.bridge.addr, head.as_bytes()).0, 431);
}

#[test]
fn slow_clients_are_refused_and_others_served_meanwhile() {
    let l = lone("slow");
    let addr = l.bridge.addr.clone();
    let t = Instant::now();
    std::thread::scope(|s| {
        let body = s.spawn(|| raw(&addr, &offset_post("Content-Length: 40\r\n", "{\"d\":1,")));
        let head = s.spawn(|| raw(&addr, b"GET /api/status HTTP/1.1\r\nHost: x\r\n"));
        // Meanwhile others are served at once.
        std::thread::sleep(Duration::from_millis(300));
        let t1 = Instant::now();
        assert_eq!(l.bridge.get("/api/programs").unwrap().status, 200);
        assert!(t1.elapsed() < Duration::from_secs(1));
        let (code, text) = body.join().unwrap();
        assert_eq!(code, 408, "{text}");
        assert!(text.contains("too slowly"), "{text}");
        let (code, text) = head.join().unwrap();
        assert_eq!(code, 408, "{text}");
    });
    assert!(t.elapsed() < Duration::from_secs(15));
}

#[test]
fn unknown_resources_wrong_methods_and_foreign_programs_are_refused() {
    let l = lone("routes");
    refused(l.bridge.get("/api/nothing").unwrap(), 404, "unknown");
    refused(l.bridge.get("/api/offset").unwrap(), 405, "GET offset");
    refused(
        l.bridge.request("DELETE", "/api/status", None).unwrap(),
        405,
        "DELETE",
    );
    for p in [
        "../Cargo.toml",
        "/etc/passwd",
        "",
        "siemens-840c/nothing.mpf",
    ] {
        refused(
            l.bridge
                .post("/api/load", &json!({ "program": p }))
                .unwrap(),
            422,
            p,
        );
    }
}

/// Random requests (bytes, and requests built from the bridge's own routes with random
/// methods, header fields, lengths and JSON bodies), each on its own connection whose sending
/// side is closed after it: every one gets an answer, 200 or a refusal with a 4xx (503 for a
/// command: no kernel here), never a 5xx of the bridge's own, and the bridge serves on.
#[test]
fn random_requests_are_answered_and_the_bridge_stays_up() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config, TestRunner};
    let l = lone("fuzz");
    let json_value = prop_oneof![
        Just("null".to_string()),
        Just("true".to_string()),
        any::<i64>().prop_map(|n| n.to_string()),
        any::<f64>().prop_map(|x| format!("{x:?}")),
        Just("1e999".to_string()),
        "\\PC{0,12}".prop_map(|t| serde_json::to_string(&t).unwrap()),
        Just("[1,2]".to_string()),
        Just("{}".to_string()),
    ];
    let key = prop_oneof![
        Just("d"),
        Just("t"),
        Just("radius"),
        Just("wear"),
        Just("program"),
        Just("percent"),
        Just("on"),
        Just("set"),
        Just("values"),
        Just("x"),
    ];
    // Values of the right kind for the key, or anything.
    let typed = (key, json_value).prop_flat_map(|(k, any_value)| {
        let right: BoxedStrategy<String> = match k {
            "d" | "t" => (0u32..4).prop_map(|n| n.to_string()).boxed(),
            "radius" | "percent" => (-20.0f64..150.0).prop_map(|x| format!("{x}")).boxed(),
            "wear" | "on" => any::<bool>().prop_map(|b| b.to_string()).boxed(),
            "set" => prop_oneof![
                Just("\"G54\"".to_string()),
                Just("\"g54.1 p3\"".to_string())
            ]
            .boxed(),
            "values" => (
                prop_oneof![Just("X"), Just("z"), Just("Q")],
                -20.0f64..150.0,
            )
                .prop_map(|(a, v)| format!("{{\"{a}\":{v}}}"))
                .boxed(),
            "program" => prop_oneof![
                Just("\"square.mpf\"".to_string()),
                Just("\"../etc/passwd\"".to_string()),
                Just("\"/tmp\"".to_string()),
            ]
            .boxed(),
            _ => Just("1".to_string()).boxed(),
        };
        prop_oneof![3 => right, 1 => Just(any_value)].prop_map(move |v| (k, v))
    });
    let body = prop_oneof![
        4 => proptest::collection::vec(typed, 0..4).prop_map(|kv| {
            let fields: Vec<String> = kv.iter().map(|(k, v)| format!("\"{k}\":{v}")).collect();
            format!("{{{}}}", fields.join(",")).into_bytes()
        }),
        1 => proptest::collection::vec(any::<u8>(), 0..64),
    ];
    let method = prop_oneof![
        2 => Just("GET".to_string()),
        6 => Just("POST".to_string()),
        1 => Just("PUT".to_string()),
        1 => Just("HEAD".to_string()),
        1 => "[A-Z]{1,8}",
        1 => "[ -~]{0,6}",
    ];
    // Not /api/events: a stream that runs until the client goes away.
    let path = prop_oneof![
        Just("/".to_string()),
        Just("/api/status".to_string()),
        Just("/api/tools".to_string()),
        Just("/api/programs".to_string()),
        Just("/api/program".to_string()),
        Just("/api/plot".to_string()),
        Just("/api/offset".to_string()),
        Just("/api/work-offsets".to_string()),
        Just("/api/work-offset".to_string()),
        Just("/api/load".to_string()),
        Just("/api/override".to_string()),
        Just("/api/single-block".to_string()),
        Just("/api/start".to_string()),
        Just("/api/stop".to_string()),
        Just("/api/reset".to_string()),
        "/[!-~]{0,30}",
    ];
    let length = prop_oneof![
        1 => Just(None),
        6 => Just(Some("exact".to_string())),
        1 => "[0-9]{1,25}".prop_map(Some),
        1 => "[ -~]{0,8}".prop_map(Some),
    ];
    // Mostly well-formed field names (a malformed one only ever gets the 400).
    let fields = proptest::collection::vec(
        (
            prop_oneof![4 => "[A-Za-z][A-Za-z0-9-]{0,11}", 1 => "[!-9;-~]{1,12}"],
            "[ -~]{0,20}",
        ),
        0..4,
    );
    let built = (method, path, any::<u8>(), length, fields, body).prop_map(
        |(m, p, token, length, fields, body)| {
            let mut head = format!("{m} {p} HTTP/1.1\r\nHost: x\r\n");
            if token < 220 {
                head += &format!("Authorization: Bearer {TOKEN}\r\n");
            }
            match length.as_deref() {
                Some("exact") => head += &format!("Content-Length: {}\r\n", body.len()),
                Some(v) => head += &format!("Content-Length: {v}\r\n"),
                None => {}
            }
            for (k, v) in fields {
                head += &format!("{k}: {v}\r\n");
            }
            let mut bytes = format!("{head}\r\n").into_bytes();
            bytes.extend(body);
            bytes
        },
    );
    let request = prop_oneof![
        1 => proptest::collection::vec(any::<u8>(), 0..400),
        4 => built,
    ];
    let allowed = [200, 400, 401, 404, 405, 409, 411, 413, 422, 431, 503];
    let mut runner = TestRunner::new(Config {
        cases: 300,
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&request, |bytes| {
            let mut s = std::net::TcpStream::connect(&l.bridge.addr).unwrap();
            s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
            let _ = s.write_all(&bytes);
            let _ = s.shutdown(std::net::Shutdown::Write);
            let mut out = Vec::new();
            let _ = s.read_to_end(&mut out);
            let text = String::from_utf8_lossy(&out);
            let code: u16 = text
                .split_whitespace()
                .nth(1)
                .and_then(|c| c.parse().ok())
                .unwrap_or(0);
            prop_assert!(
                allowed.contains(&code),
                "{code} for {:?}: {text}",
                String::from_utf8_lossy(&bytes)
            );
            Ok(())
        })
        .unwrap();
    assert_eq!(l.bridge.get("/api/status").unwrap().status, 200);
}

/// Through a whole control: an unknown D is refused, and after every kind of bad request
/// nothing has changed: the tool table at version 1 with D1 = 10, the channel in RESET.
#[test]
fn bad_requests_change_nothing() {
    let st = station("bad", None, &["--set", "D1=10"], &["--token", TOKEN]);
    let m = refused(
        offset_raw(&st.bridge, r#"{"d":99,"radius":12}"#),
        422,
        "unknown D",
    );
    assert!(m.contains("D99"), "{m}");
    let none = Bridge::new(st.bridge.addr.clone(), None);
    // A good edit without the token, then bad ones with it.
    let bodies = [
        r#"{"d":1,"radius":12}"#,
        r#"{"d":1,"radius":"#,
        r#"{"d":1,"radius":NaN}"#,
        r#"{"d":1,"radius":12,"force":true}"#,
        r#"{"d":1,"radius":1e300}"#,
        r#"{"d":1,"radius":2,"wear":true}"#,
    ];
    for body in bodies {
        let a = offset_raw(&none, body);
        assert_eq!(a.status, 401);
    }
    for body in &bodies[1..] {
        let a = offset_raw(&st.bridge, body);
        assert!((400..500).contains(&a.status), "{body}: {}", a.body);
    }
    let (code, _) = raw(
        &st.bridge.addr,
        &offset_post("Content-Length: 40\r\n", "{\"d\":1,\"radius\":12"),
    );
    assert_eq!(code, 408);
    let tools = st.bridge.get("/api/tools").unwrap().json();
    assert_eq!(tools["version"], json!(1));
    assert_eq!(tools["offsets"][0]["radius"], json!(10.0));
    assert_eq!(st.status()["state"], json!("RESET"));
}

/// A bridge on another address than loopback insists on a token.
#[test]
fn another_address_needs_a_token() {
    let log = scratch("listen.log");
    let mut kid = spawn(
        "hmi-bridge",
        &[
            "--instance",
            &instance("listen"),
            "--listen",
            "0.0.0.0",
            "--port",
            "0",
        ],
        &log,
    );
    let status = kid.0.wait().unwrap();
    let text = std::fs::read_to_string(&log).unwrap();
    assert_eq!(status.code(), Some(2), "{text}");
    assert!(text.contains("--token"), "{text}");
}

/// `softnc status`, `start`, `stop`, `reset` and `offset set` through the bridge.
#[test]
fn the_softnc_commands_go_through_the_bridge() {
    let prog = write("cli.mpf", SQUARE);
    let folder = prog.parent().unwrap().to_str().unwrap().to_string();
    let st = station("cli", None, &["--set", "D1=10"], &["--programs", &folder]);
    let run = |args: &[&str]| {
        let out = std::process::Command::new(EXE)
            .args(args)
            .args(["--bridge", &st.bridge.addr])
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).to_string(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (code, out, _) = run(&["status"]);
    assert_eq!(code, Some(0));
    assert!(out.starts_with("RESET"), "{out}");
    let (code, out, _) = run(&["offset", "set", "D1", "--radius", "10.02"]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("version 2"), "{out}");
    let (code, out, _) = run(&["offset", "set", "D1", "--radius", "-0.01", "--wear"]);
    assert_eq!(code, Some(0), "{out}");
    let tools = st.bridge.get("/api/tools").unwrap().json();
    assert_eq!(tools["offsets"][0]["radius"], json!(10.02));
    assert_eq!(tools["offsets"][0]["radius_wear"], json!(-0.01));
    let (code, _, err) = run(&["offset", "set", "D99", "--radius", "1"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("D99"), "{err}");
    let (code, _, err) = run(&["start"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("no program"), "{err}");
    let (code, r) = st.post("/api/load", json!({ "program": "cli.mpf" }));
    assert_eq!(code, 200, "{r}");
    let (code, out, _) = run(&["start"]);
    assert_eq!(code, Some(0), "{out}");
    st.watch(Duration::from_secs(30), |s| s["state"] == json!("ACTIVE"));
    let (code, out, _) = run(&["stop"]);
    assert_eq!(code, Some(0), "{out}");
    st.watch(Duration::from_secs(10), |s| s["state"] == json!("STOPPED"));
    let (code, out, _) = run(&["status"]);
    assert_eq!(code, Some(0));
    assert!(
        out.starts_with("STOPPED") && out.contains("cli.mpf"),
        "{out}"
    );
    let (code, out, _) = run(&["reset"]);
    assert_eq!(code, Some(0), "{out}");
    st.watch(Duration::from_secs(10), |s| s["state"] == json!("RESET"));
    let (code, out, _) = run(&["status", "--json"]);
    assert_eq!(code, Some(0));
    assert_eq!(
        serde_json::from_str::<Value>(&out).unwrap()["tools_version"],
        json!(3)
    );
}

/// A table numbered per tool (the lathe tools of config/tools.toml: T1 D1, T1 D2, T2 D1,
/// beside the global D1 and D2): an edit names the tool and changes that entry only, through
/// the API and through `softnc offset set T2D1`; a D the tool does not have is refused.
#[test]
fn offsets_numbered_per_tool_are_edited_by_tool_and_d() {
    let st = station("tdtable", None, &[], &[]);
    let entry = |t: Option<u64>, d: u64| {
        let tools = st.bridge.get("/api/tools").unwrap().json();
        tools["offsets"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["t"].as_u64() == t && o["d"].as_u64() == Some(d))
            .unwrap_or_else(|| panic!("T{t:?} D{d} in {tools}"))
            .clone()
    };
    assert_eq!(entry(Some(1), 2)["radius"], json!(0.4));
    let (code, r) = st.post("/api/offset", json!({ "t": 1, "d": 2, "radius": 0.5 }));
    assert_eq!(code, 200, "{r}");
    assert!(
        r["message"]
            .as_str()
            .unwrap()
            .contains("T1 D2 radius = 0.5 mm"),
        "{r}"
    );
    assert_eq!(entry(Some(1), 2)["radius"], json!(0.5));
    assert_eq!(entry(None, 2)["radius"], json!(5.0));
    assert_eq!(entry(Some(1), 1)["radius"], json!(0.8));
    let (code, r) = st.post("/api/offset", json!({ "t": 2, "d": 2, "radius": 1.0 }));
    assert_eq!(code, 422, "{r}");
    assert!(
        r["error"]
            .as_str()
            .unwrap()
            .contains("T2 D2 is not in the tool table"),
        "{r}"
    );
    let out = std::process::Command::new(EXE)
        .args(["offset", "set", "T2D1", "--radius", "-0.05", "--wear"])
        .args(["--bridge", &st.bridge.addr])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(entry(Some(2), 1)["radius_wear"], json!(-0.05));
    assert_eq!(entry(None, 1)["radius_wear"], json!(0.0));
    assert_eq!(st.status()["tools_version"], json!(3));
}

/// A lathe's plot on the live page: the kernel publishes each offset's cutting edge
/// position with its tool table, so the bridge draws the tool tip P the axes run, not the
/// nose centre. The Fanuc shaft's Ø40 roughing pass (T2 D1: nose R 1.2, position 3) ends at
/// the tip's Z −71.1 + R·0.8/3 = −70.78 (worked out in tests/lathe_samples.rs); the nose
/// centre's would end at Z −48.0.
#[test]
fn a_lathes_plot_draws_the_tool_tip_from_the_kernels_table() {
    let md = root().join("config/fanuc-lathe.toml");
    let md = ["--machine", md.to_str().unwrap()];
    let prog = root().join("programs/fanuc-lathe/shaft_rough_finish.nc");
    let st = station_with("lathe-plot", &md, Some(&prog), &md, &md);
    let tools = st.bridge.get("/api/tools").unwrap().json();
    let entry = |t: Value, d: u64| {
        tools["offsets"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["t"] == t && o["d"] == json!(d))
            .unwrap_or_else(|| panic!("T{t} D{d} in {tools}"))
            .clone()
    };
    let t2d1 = entry(json!(2), 1);
    assert_eq!(
        (&t2d1["radius"], &t2d1["cutting_edge"]),
        (&json!(1.2), &json!(3))
    );
    assert_eq!(entry(Value::Null, 1)["cutting_edge"], Value::Null);

    let t = Instant::now();
    let plot = loop {
        let p = st.bridge.get("/api/plot").unwrap().json();
        if p["path"].as_array().is_some_and(|l| !l.is_empty()) {
            break p;
        }
        assert!(t.elapsed() < Duration::from_secs(30), "no plot: {p}");
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(plot["alarm"], Value::Null, "{plot}");
    let cut = plot["path"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l[0] == json!([2.0, 20.0]))
        .unwrap_or_else(|| panic!("no pass at X20 from Z2 in {plot}"));
    let end = cut[1][0].as_f64().unwrap();
    assert!((end - (-71.1 + 1.2 * 0.8 / 3.0)).abs() < 1e-9, "{cut}");
}

/// `softnc run --hmi`: the bridge comes up with the run, the page's API answers while the
/// program runs and after its end, the control stays up until Ctrl-C, and then all three
/// processes end cleanly and nothing is left in shared memory.
#[test]
fn softnc_run_with_the_hmi_stays_up_until_ctrl_c() {
    let inst = instance("runhmi");
    let _scope = Scope::new(&inst);
    let prog = write("runhmi.mpf", SQUARE);
    let (err, svg) = (scratch("runhmi.err"), scratch("runhmi.svg"));
    let mut run = std::process::Command::new(EXE)
        .arg("run")
        .arg(&prog)
        .args(["--quiet", "--hmi", "--hmi-port", "0", "--instance", &inst])
        .arg("--svg")
        .arg(&svg)
        .stdout(std::process::Stdio::piped())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .unwrap();
    let t = Instant::now();
    let text = loop {
        let text = std::fs::read_to_string(&err).unwrap();
        if text.contains("stays up") {
            break text;
        }
        assert!(run.try_wait().unwrap().is_none(), "run ended: {text}");
        assert!(t.elapsed() < Duration::from_secs(120), "{text}");
        std::thread::sleep(Duration::from_millis(50));
    };
    let addr = hmi_bridge::address_in(&text).unwrap_or_else(|| panic!("{text}"));
    let bridge = Bridge::new(addr, None);
    let status = bridge.get("/api/status").unwrap().json();
    assert_eq!(
        (&status["connected"], &status["state"]),
        (&json!(true), &json!("END")),
        "{status}"
    );
    // The page offers the programs beside the one that ran.
    let programs = bridge.get("/api/programs").unwrap().json();
    assert!(
        programs["programs"]
            .as_array()
            .unwrap()
            .contains(&json!("runhmi.mpf")),
        "{programs}"
    );
    // Still up a while later; then Ctrl-C.
    std::thread::sleep(Duration::from_millis(500));
    assert!(run.try_wait().unwrap().is_none());
    unsafe {
        libc::kill(run.id() as i32, libc::SIGINT);
    }
    let out = run.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("ran to its end"), "{stdout}");
    assert!(
        stdout.contains(
            "processes ended: hmi-bridge exit status: 0, nc-kernel exit status: 0, plc-sim exit status: 0; shared memory files left: 0"
        ),
        "{stdout}"
    );
    assert!(softnc_protocol::Instance::new(&inst)
        .unwrap()
        .files()
        .is_empty());
    assert!(bridge.get("/api/status").is_err(), "the bridge has ended");
}

/// Edits from two clients at once are taken one after the other: every one is answered with
/// its own table version, the versions run 2, 3, … without a gap or a repeat, and the table
/// ends with the value of the edit that got the last version. The tool file, written
/// atomically, holds that table.
#[test]
fn concurrent_edits_are_serialised_and_named_by_version() {
    let tools = scratch("concurrent-tools.toml");
    std::fs::copy(root().join("config/tools.toml"), &tools).unwrap();
    let st = station(
        "concurrent",
        None,
        &["--tools", tools.to_str().unwrap()],
        &[],
    );
    let results: Vec<(u64, f64)> = std::thread::scope(|s| {
        let clients: Vec<_> = (0..2)
            .map(|c| {
                let bridge = st.bridge.clone();
                s.spawn(move || {
                    (0..10)
                        .map(|i| {
                            let r = 10.0 + c as f64 + i as f64 / 100.0;
                            let a = bridge
                                .post("/api/offset", &json!({ "d": 1, "radius": r }))
                                .unwrap();
                            assert_eq!(a.status, 200, "{}", a.body);
                            (a.json()["tools_version"].as_u64().unwrap(), r)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        clients
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    let mut versions: Vec<u64> = results.iter().map(|(v, _)| *v).collect();
    versions.sort();
    assert_eq!(versions, (2..=21).collect::<Vec<u64>>());
    let last = results.iter().max_by_key(|(v, _)| *v).unwrap().1;
    let table = st.bridge.get("/api/tools").unwrap().json();
    assert_eq!(table["version"], json!(21));
    assert_eq!(table["offsets"][0]["radius"], json!(last));
    let saved = nc_kernel::ToolTable::load(&tools).unwrap();
    assert_eq!(saved.find(None, 1).unwrap().radius, last);
}

/// kill -9 of the kernel while it saves edit after edit: the tool file is whole afterwards,
/// holding the table of one of the edits (or the one before them), never a torn one.
#[test]
fn a_crash_while_saving_leaves_a_whole_tool_file() {
    let tools = scratch("crash-tools.toml");
    std::fs::copy(root().join("config/tools.toml"), &tools).unwrap();
    let mut st = station("crash", None, &["--tools", tools.to_str().unwrap()], &[]);
    let stop = std::sync::atomic::AtomicBool::new(false);
    let written: Vec<f64> = std::thread::scope(|s| {
        let writer = s.spawn(|| {
            let mut sent = vec![10.0];
            let mut i = 0;
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                i += 1;
                let r = 10.0 + i as f64 / 1000.0;
                sent.push(r);
                if st
                    .bridge
                    .post("/api/offset", &json!({ "d": 1, "radius": r }))
                    .map_or(true, |a| a.status != 200)
                {
                    break;
                }
            }
            sent
        });
        std::thread::sleep(Duration::from_millis(400));
        st.kids[1].0.kill().unwrap();
        st.kids[1].0.wait().unwrap();
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        writer.join().unwrap()
    });
    assert!(
        written.len() > 5,
        "edits were being saved: {}",
        written.len()
    );
    let saved = nc_kernel::ToolTable::load(&tools).expect("a whole tool file");
    let r = saved.find(None, 1).unwrap().radius;
    assert!(written.contains(&r), "{r} is none of the values written");
    assert_eq!(
        saved.offset.len(),
        nc_kernel::ToolTable::builtin().offset.len()
    );
}

/// A raw POST to /api/work-offset.
fn work_offset_raw(b: &Bridge, body: &str) -> hmi_bridge::client::Answer {
    b.request("POST", "/api/work-offset", Some(body)).unwrap()
}

/// Without a kernel: a malformed edit is refused as such; a well-formed one and the table
/// wait for the kernel's table (503); the wrong methods are 405.
#[test]
fn work_offset_requests_without_a_kernel() {
    let l = lone("wolone");
    let m = refused(
        work_offset_raw(&l.bridge, r#"{"set":"G54","values":{"X":"#),
        400,
        "malformed",
    );
    assert!(m.contains("malformed JSON"), "{m}");
    let m = refused(
        work_offset_raw(&l.bridge, r#"{"set":"G54","values":{"X":1}}"#),
        503,
        "no table",
    );
    assert!(m.contains("work-offset table"), "{m}");
    refused(l.bridge.get("/api/work-offsets").unwrap(), 503, "table");
    refused(l.bridge.get("/api/work-offset").unwrap(), 405, "GET edit");
    refused(
        l.bridge.post("/api/work-offsets", &json!({})).unwrap(),
        405,
        "POST table",
    );
}

/// Work offsets through a whole control (840C: G54 … G57 on X, Y, Z), the table saved to a
/// file: every kind of bad edit is answered 4xx with its reason and changes nothing (the
/// version, the values and the file stay); a good edit in RESET is taken, named by the new
/// version and saved.
#[test]
fn work_offset_edits_are_checked_taken_and_saved() {
    let offsets = write("wo-api.toml", "[G54]\nX = 10.0\n");
    let st = station(
        "woapi",
        None,
        &["--offsets", offsets.to_str().unwrap()],
        &[],
    );
    let table = st.work_offsets();
    let names: Vec<&str> = table["sets"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|s| s["name"].as_str())
        .collect();
    assert_eq!(names, ["G54", "G55", "G56", "G57"], "{table}");
    assert_eq!(table["axes"], json!(["X", "Y", "Z"]));
    assert_eq!(
        (&table["version"], &table["saved"]),
        (&json!(1), &json!(true))
    );
    assert_eq!(
        table["sets"][0]["values"],
        json!({ "X": 10.0, "Y": 0.0, "Z": 0.0 })
    );
    assert_eq!(table["max_work_offset"], json!(10000.0));
    let file = std::fs::read_to_string(&offsets).unwrap();
    let bad = [
        (r#"{"set":"G60","values":{"X":1}}"#, 422, "G54 … G57"),
        (
            r#"{"set":"G54.1 P3","values":{"X":1}}"#,
            422,
            "not a work offset",
        ),
        (
            r#"{"set":"G54","values":{"C":1}}"#,
            422,
            "its axes are X, Y, Z",
        ),
        (r#"{"set":"G54","values":{"Q":1}}"#, 422, "not an axis"),
        (
            r#"{"set":"G54","values":{"X":10000.5}}"#,
            422,
            "hmi.max_work_offset",
        ),
        (
            r#"{"set":"G54","values":{"Y":-1e300}}"#,
            422,
            "hmi.max_work_offset",
        ),
        (r#"{"set":"G54","values":{}}"#, 422, "no axis value"),
        (r#"{"set":"G54","values":{"x":1,"X":2}}"#, 422, "twice"),
        (r#"{"set":"G54","values":{"X":"#, 400, "malformed JSON"),
        (r#"{"set":"G54","values":{"X":NaN}}"#, 400, "malformed JSON"),
        (r#"{"set":"G54","values":{"X":"5"}}"#, 400, "malformed JSON"),
        (r#"{"set":"G54","values":[5]}"#, 400, "malformed JSON"),
        (
            r#"{"set":"G54","values":{"X":1},"force":true}"#,
            400,
            "force",
        ),
        (r#"{"values":{"X":1}}"#, 400, "set"),
    ];
    for (body, code, says) in bad {
        let m = refused(work_offset_raw(&st.bridge, body), code, body);
        assert!(m.contains(says), "{body}: {m}");
        let now = st.work_offsets();
        assert_eq!(now["version"], json!(1), "{body}: {now}");
        assert_eq!(now["sets"], table["sets"], "{body}");
        assert_eq!(st.status()["work_offsets_version"], json!(1), "{body}");
    }
    assert_eq!(std::fs::read_to_string(&offsets).unwrap(), file);

    let (code, r) = st.post(
        "/api/work-offset",
        json!({ "set": "g 55", "values": { "x": 12.5, "Z": -3 } }),
    );
    assert_eq!(code, 200, "{r}");
    assert_eq!(r["work_offsets_version"], json!(2), "{r}");
    assert!(r["message"].as_str().unwrap().contains("G55"), "{r}");
    let now = st.work_offsets();
    assert_eq!(now["version"], json!(2));
    assert_eq!(
        now["sets"][1]["values"],
        json!({ "X": 12.5, "Y": 0.0, "Z": -3.0 })
    );
    assert_eq!(now["sets"][0], table["sets"][0], "G54 untouched");
    assert_eq!(st.status()["work_offsets_version"], json!(2));
    let md = nc_kernel::MachineData::load(None, &[]).unwrap();
    let saved = nc_kernel::WorkOffsets::load(&offsets, &md).expect("a whole work-offset file");
    assert_eq!(saved.get(2)[..3], [12.5, 0.0, -3.0]);
    assert_eq!(saved.get(1)[..3], [10.0, 0.0, 0.0]);
}

/// A Fanuc control's 54 sets (G54 … G59, G54.1 P1 … P48): a numbered set is named as the
/// operator writes it, case and spaces aside, and the kernel takes it under its own name.
#[test]
fn numbered_work_offsets_are_found_by_name() {
    let md = root().join("config/fanuc.toml");
    let md = ["--machine", md.to_str().unwrap()];
    let st = station_with("wofanuc", &md, None, &md, &md);
    let table = st.work_offsets();
    let sets = table["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 54, "{table}");
    assert_eq!(
        (&sets[6]["name"], &sets[53]["name"]),
        (&json!("G54.1 P1"), &json!("G54.1 P48"))
    );
    let (code, r) = st.post(
        "/api/work-offset",
        json!({ "set": "g54.1p3", "values": { "Y": -40.25 } }),
    );
    assert_eq!(code, 200, "{r}");
    let now = st.work_offsets();
    assert_eq!(now["sets"][8]["name"], json!("G54.1 P3"));
    assert_eq!(now["sets"][8]["values"]["Y"], json!(-40.25));
    assert_eq!(now["version"], json!(2));
    let m = refused(
        work_offset_raw(&st.bridge, r#"{"set":"G54.1 P49","values":{"Y":1}}"#),
        422,
        "P49",
    );
    assert!(m.contains("G54 … G54.1 P48"), "{m}");
    assert_eq!(st.work_offsets()["version"], json!(2));
}
