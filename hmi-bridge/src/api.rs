//! The HTTP API and the page (docs/hmi.md). Every answer is JSON (the page and the event
//! stream aside); every refusal a 4xx or 5xx with `{"error": "…"}` that says why, and a
//! refused request changes nothing.

use crate::link::{Link, Snapshot};
use crate::net::{Request, Response};
use crate::plot;
use crate::work::{self, WorkOffsetEdit};
use nc_kernel::cycle::{ChannelAlarm, Override};
use nc_kernel::MachineData;
use serde::Deserialize;
use serde_json::{json, Value};
use softnc_protocol::{command, state, AxisList, Command, MAX_AXES};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Event-stream clients served at once.
const MAX_STREAMS: usize = 16;

const PAGE: &str = include_str!("page.html");

pub struct Api {
    pub link: Link,
    pub token: Option<String>,
    pub md: MachineData,
    pub programs: PathBuf,
    streams: Arc<AtomicUsize>,
    plot_cache: Mutex<Option<PlotCache>>,
}

/// The last plot as JSON and what it was drawn from: a program and the versions of the
/// tool table and the work offsets.
struct PlotCache {
    from: (String, u32, u32),
    json: Arc<String>,
}

/// A refusal: status code and message.
struct Refuse(u16, String);

fn refuse(code: u16, m: impl Into<String>) -> Refuse {
    Refuse(code, m.into())
}

type Answer = Result<(u16, Value), Refuse>;

/// The program's text as the kernel reads it (`nc_runtime::read_program`: a byte that is not
/// UTF-8 shows as U+FFFD, where the kernel reports it if it is not in a comment).
fn read_program(path: &str) -> Result<String, Refuse> {
    nc_runtime::read_program(std::path::Path::new(path))
        .map_err(|e| refuse(404, format!("{path}: {e}")))
}

impl Api {
    pub fn new(link: Link, token: Option<String>, md: MachineData, programs: PathBuf) -> Self {
        Api {
            link,
            token,
            md,
            programs,
            streams: Arc::new(AtomicUsize::new(0)),
            plot_cache: Mutex::new(None),
        }
    }

    /// Answers one request (an event stream keeps its connection's thread).
    pub fn handle(self: &Arc<Self>, req: Request) -> Response {
        if let Err(Refuse(code, m)) = self.authorised(&req) {
            return Response::error(code, &m);
        }
        match (req.method.as_str(), req.path.as_str()) {
            ("GET", "/") | ("GET", "/index.html") => Response::Full {
                status: 200,
                content_type: "text/html; charset=utf-8",
                body: PAGE.as_bytes().to_vec(),
            },
            ("GET", "/api/events") => self.events(),
            _ => match self.route(&req) {
                Ok((code, v)) => Response::json(code, &v),
                Err(Refuse(code, m)) => Response::error(code, &m),
            },
        }
    }

    fn authorised(&self, req: &Request) -> Result<(), Refuse> {
        let Some(token) = &self.token else {
            return Ok(());
        };
        let given = req
            .header("Authorization")
            .and_then(|v| v.strip_prefix("Bearer "))
            .map(str::to_string)
            .or_else(|| {
                req.query
                    .split('&')
                    .find_map(|kv| kv.strip_prefix("token="))
                    .map(str::to_string)
            });
        match given {
            None => Err(refuse(
                401,
                "a token is required: send \"Authorization: Bearer <token>\"",
            )),
            Some(g) if constant_time_eq(g.as_bytes(), token.as_bytes()) => Ok(()),
            Some(_) => Err(refuse(401, "wrong token")),
        }
    }

    fn route(&self, req: &Request) -> Answer {
        let (method, path) = (req.method.as_str(), req.path.as_str());
        let post = method == "POST";
        if !post && method != "GET" {
            return Err(refuse(
                405,
                format!("{method} is not taken here: GET or POST"),
            ));
        }
        match path {
            "/api/status" if !post => Ok((200, status_json(&self.link.snapshot()))),
            "/api/tools" if !post => self.tools(),
            "/api/programs" if !post => self.program_list(),
            "/api/program" if !post => self.program_text(),
            "/api/plot" if !post => self.plot(),
            "/api/start" if post => self.simple(req, Command::new(command::START)),
            "/api/stop" if post => self.simple(req, Command::new(command::STOP)),
            "/api/reset" if post => self.simple(req, Command::new(command::RESET)),
            "/api/single-block" if post => {
                let b: SingleBlock = body(req)?;
                let mut c = Command::new(command::SINGLE_BLOCK);
                c.value = if b.on { 1.0 } else { 0.0 };
                self.command(c)
            }
            "/api/override" if post => {
                let b: OverrideBody = body(req)?;
                let o = Override::from_percent(b.percent).ok_or_else(|| {
                    refuse(
                        422,
                        format!("override {} %: expected {}", b.percent, Override::RANGE),
                    )
                })?;
                let mut c = Command::new(command::OVERRIDE);
                c.value = o.fraction();
                self.command(c)
            }
            "/api/load" if post => {
                let b: Load = body(req)?;
                let p = self.program_path(&b.program)?;
                let text = p.to_string_lossy().to_string();
                if text.len() > softnc_protocol::TEXT {
                    return Err(refuse(422, "the program's path is too long"));
                }
                self.command(Command::new(command::LOAD).with_text(&text))
            }
            "/api/offset" if post => {
                let b: Offset = body(req)?;
                self.offset(b)
            }
            "/api/work-offsets" if !post => self.work_offsets(),
            "/api/work-offset" if post => {
                let b: WorkOffsetEdit = body(req)?;
                self.work_offset(&b)
            }
            "/api/status" | "/api/tools" | "/api/programs" | "/api/program" | "/api/plot"
            | "/api/start" | "/api/stop" | "/api/reset" | "/api/single-block" | "/api/override"
            | "/api/load" | "/api/offset" | "/api/work-offsets" | "/api/work-offset" => {
                Err(refuse(405, format!("{path} does not take {method}")))
            }
            _ => Err(refuse(404, format!("no such resource: {path}"))),
        }
    }

    /// A command without parameters: its body must be empty or `{}`.
    fn simple(&self, req: &Request, c: Command) -> Answer {
        let text = text(req)?;
        if !text.trim().is_empty() {
            match serde_json::from_str::<Value>(&text) {
                Ok(Value::Object(m)) if m.is_empty() => {}
                Ok(_) => {
                    return Err(refuse(
                        400,
                        "this command takes no parameters: send {} or nothing",
                    ))
                }
                Err(e) => return Err(refuse(400, format!("malformed JSON: {e}"))),
            }
        }
        self.command(c)
    }

    fn command(&self, c: Command) -> Answer {
        let r = self.link.ask(c).map_err(|e| refuse(503, e))?;
        let (tools, work) = (r.tools_version, r.work_offsets_version);
        if r.ok != 0 {
            Ok((
                200,
                json!({
                    "ok": true,
                    "message": r.message(),
                    "tools_version": tools,
                    "work_offsets_version": work,
                }),
            ))
        } else {
            let mut v = json!({
                "error": r.message(),
                "tools_version": tools,
                "work_offsets_version": work,
            });
            if let Some(a) = ChannelAlarm::new(r.alarm) {
                v["alarm"] = json!(a.number());
            }
            // The kernel refused: the request is fine, the control's state is not.
            Ok((409, v))
        }
    }

    fn offset(&self, b: Offset) -> Answer {
        // The kernel checks again; here the answer can say the request is wrong (422): the
        // same edit on a copy of the kernel's last table (unless the message was cut short).
        let limit = self.md.hmi.offset_limit(b.wear);
        let t = b.t.filter(|&t| t != 0);
        nc_kernel::check_edit(b.wear, b.radius, limit)
            .map_err(|e| refuse(422, format!("{e}; nothing changed")))?;
        let snap = self.link.snapshot();
        if let Some(table) = snap.tools.as_ref().filter(|m| m.truncated == 0) {
            nc_runtime::tool_table(table)
                .edit(t, b.d, b.wear, b.radius, limit)
                .map_err(|e| refuse(422, format!("{e}; nothing changed")))?;
        }
        self.command(Command::offset(t, b.d, b.radius, b.wear))
    }

    /// A work-offset edit: checked here against the kernel's last table (422 says what is
    /// wrong), then the kernel's answer (it checks again and knows the channel's state).
    fn work_offset(&self, b: &WorkOffsetEdit) -> Answer {
        let snap = self.link.snapshot();
        let Some(table) = snap.work_offsets else {
            return Err(refuse(503, "no work-offset table from the kernel yet"));
        };
        let (name, values) = work::check(&table, self.md.hmi.max_work_offset, b)
            .map_err(|e| refuse(422, format!("{e}; nothing changed")))?;
        self.command(Command::work_offset(&name, &values))
    }

    fn work_offsets(&self) -> Answer {
        let snap = self.link.snapshot();
        let Some(t) = snap.work_offsets else {
            return Err(refuse(503, "no work-offset table from the kernel yet"));
        };
        let mut v = work::table_json(&t, snap.status.map_or(0, |s| s.work_offset));
        v["max_work_offset"] = json!(self.md.hmi.max_work_offset);
        v["edit_while_active"] = json!(self.md.hmi.edit_while_active);
        Ok((200, v))
    }

    fn tools(&self) -> Answer {
        let snap = self.link.snapshot();
        let Some(t) = snap.tools else {
            return Err(refuse(503, "no tool table from the kernel yet"));
        };
        let offsets: Vec<Value> = t
            .entries()
            .iter()
            .map(|e| {
                json!({
                    "t": (e.t != 0).then_some(e.t),
                    "d": e.d,
                    "radius": e.radius,
                    "radius_wear": e.radius_wear,
                    "length": e.length,
                    "length_wear": e.length_wear,
                    "cutting_edge": (e.cutting_edge != 0).then_some(e.cutting_edge),
                })
            })
            .collect();
        Ok((
            200,
            json!({
                "version": t.version,
                "saved": t.saved != 0,
                "truncated": t.truncated != 0,
                "offsets": offsets,
                "max_radius": self.md.hmi.max_radius,
                "max_wear": self.md.hmi.max_wear,
                "edit_while_active": self.md.hmi.edit_while_active,
            }),
        ))
    }

    fn program_list(&self) -> Answer {
        let mut names = Vec::new();
        let mut dirs = vec![self.programs.clone()];
        while let Some(d) = dirs.pop() {
            let Ok(entries) = std::fs::read_dir(&d) else {
                continue;
            };
            for e in entries.flatten() {
                let p = e.path();
                if p.is_dir() {
                    dirs.push(p);
                } else if let Ok(rel) = p.strip_prefix(&self.programs) {
                    names.push(rel.to_string_lossy().to_string());
                }
            }
        }
        names.sort();
        Ok((
            200,
            json!({ "dir": self.programs.display().to_string(), "programs": names }),
        ))
    }

    /// A program of the programs folder, by its path there; nothing outside it.
    fn program_path(&self, rel: &str) -> Result<PathBuf, Refuse> {
        let bad = || {
            refuse(
                422,
                format!("{rel:?} is not a program in {}", self.programs.display()),
            )
        };
        if rel.is_empty()
            || Path::new(rel).is_absolute()
            || rel.split(['/', '\\']).any(|c| c == "..")
        {
            return Err(bad());
        }
        let root = self.programs.canonicalize().map_err(|_| bad())?;
        let p = root.join(rel).canonicalize().map_err(|_| bad())?;
        if !p.starts_with(&root) || !p.is_file() {
            return Err(bad());
        }
        Ok(p)
    }

    fn program_text(&self) -> Answer {
        let snap = self.link.snapshot();
        let Some(path) = snap.program_path else {
            return Ok((200, json!({ "path": null, "text": null })));
        };
        let text = read_program(&path)?;
        Ok((200, json!({ "path": path, "text": text })))
    }

    /// The plot with the kernel's tool table and work offsets (a program in G54 is drawn
    /// where the axes go, beside their actual position); cached per program and versions.
    fn plot(&self) -> Answer {
        let snap = self.link.snapshot();
        let (Some(path), Some(t)) = (snap.program_path, snap.tools) else {
            let empty = serde_json::to_value(plot::empty(&self.md))
                .map_err(|e| refuse(500, e.to_string()))?;
            return Ok((200, empty));
        };
        let from = (
            path.clone(),
            t.version,
            snap.work_offsets.as_ref().map_or(0, |w| w.version),
        );
        if let Ok(c) = self.plot_cache.lock() {
            if let Some(c) = c.as_ref().filter(|c| c.from == from) {
                return Ok((200, serde_json::from_str(&c.json).unwrap_or(Value::Null)));
            }
        }
        let source = read_program(&path)?;
        let mut md = self.md.clone();
        if let Some(w) = &snap.work_offsets {
            md.work_offsets = plot::work_offsets(w, &self.md);
        }
        // The subprogram files it calls, as the kernel reads them (none if unreadable: the
        // plot then ends where the kernel's alarm says).
        let library = nc_runtime::program_library(Path::new(&path), &md.program.search_path);
        md.programs = Arc::new(library.unwrap_or_default());
        let pl = plot::plot(&path, &source, &md, &nc_runtime::tool_table(&t));
        let text = serde_json::to_string(&pl).map_err(|e| refuse(500, e.to_string()))?;
        if let Ok(mut c) = self.plot_cache.lock() {
            *c = Some(PlotCache {
                from,
                json: Arc::new(text.clone()),
            });
        }
        Ok((200, serde_json::from_str(&text).unwrap_or(Value::Null)))
    }

    /// Server-Sent Events: the status every 100 ms, in the connection's thread until the
    /// client goes away.
    fn events(self: &Arc<Self>) -> Response {
        if self.streams.fetch_add(1, Ordering::AcqRel) >= MAX_STREAMS {
            self.streams.fetch_sub(1, Ordering::AcqRel);
            return Response::error(503, "too many event streams open");
        }
        let rx = self.link.subscribe();
        let streams = self.streams.clone();
        Response::Stream(Box::new(move |w| {
            let mut ok = true;
            while ok {
                let msg = match rx.recv_timeout(std::time::Duration::from_secs(10)) {
                    Ok(text) => format!("data: {text}\n\n"),
                    // A comment keeps proxies and the browser from closing it.
                    Err(crossbeam::channel::RecvTimeoutError::Timeout) => ": idle\n\n".into(),
                    Err(_) => break,
                };
                ok = w.write_all(msg.as_bytes()).and_then(|_| w.flush()).is_ok();
            }
            streams.fetch_sub(1, Ordering::AcqRel);
        }))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SingleBlock {
    on: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OverrideBody {
    percent: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Load {
    program: String,
}

/// `{"d": 1, "radius": 10.02}`; `"wear": true` sets the radius wear instead; `"t": 1`
/// names the tool on a T/D table (808D).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Offset {
    #[serde(default)]
    t: Option<u32>,
    d: u32,
    radius: f64,
    #[serde(default)]
    wear: bool,
}

fn text(req: &Request) -> Result<String, Refuse> {
    String::from_utf8(req.body.clone()).map_err(|_| refuse(400, "the body is not UTF-8"))
}

/// The body as a JSON object of type `T` (serde would also take an array in field order:
/// not here), each field once.
fn body<T: serde::de::DeserializeOwned>(req: &Request) -> Result<T, Refuse> {
    let text = text(req)?;
    let v: Value =
        serde_json::from_str(&text).map_err(|e| refuse(400, format!("malformed JSON: {e}")))?;
    if !v.is_object() {
        return Err(refuse(400, "malformed JSON: expected an object"));
    }
    // From the text, not from `v`: a `Value` keeps one of two equal keys silently, the
    // text makes `{"d": 1, "d": 2}` a duplicate field.
    serde_json::from_str(&text).map_err(|e| refuse(400, format!("malformed JSON: {e}")))
}

fn constant_time_eq(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// The machine's axes as the status lists them: name, rotary (degrees), modulo (shown
/// within 0…360°), in the order of `pos`, `actual` and `following_error`.
fn axes_json(list: &AxisList) -> Value {
    list.names()
        .enumerate()
        .map(|(n, c)| {
            json!({
                "name": c.to_string(),
                "rotary": list.rotary(n),
                "modulo": list.modulo(n),
            })
        })
        .collect()
}

/// The first `count` positions of a wire array: one per configured axis.
fn positions(p: &[f64; MAX_AXES], count: usize) -> &[f64] {
    &p[..count.min(MAX_AXES)]
}

/// The status as the API and the event stream give it. Positions are arrays with one
/// entry per configured axis, in the order `axes` names them (X Y Z on a mill).
pub fn status_json(s: &Snapshot) -> Value {
    let Some(st) = s.status else {
        return json!({ "connected": false });
    };
    let alarm =
        ChannelAlarm::new(st.alarm).map(|a| json!({ "number": a.number(), "text": a.title() }));
    let n = usize::from(st.axes.count);
    json!({
        "connected": s.connected(),
        "state": state::name(st.state),
        "cycle": st.cycle,
        "program": st.program,
        "program_path": s.program_path,
        "line": st.line,
        "axes": axes_json(&st.axes),
        "pos": positions(&st.pos, n),
        "feed_mm_min": st.v_path * 60.0,
        "override_percent": st.override_ * 100.0,
        "alarm": alarm,
        "single_block": st.single_block != 0,
        "plc_alive": st.plc_alive != 0,
        "aux_sent": st.aux_sent,
        "aux_acked": st.aux_acked,
        "tools_version": st.tools_version,
        "work_offsets_version": st.work_offsets_version,
        "work_offset": work::active_name(s.work_offsets.as_ref(), st.work_offset),
        "tool": (st.tool != 0).then_some(st.tool),
        "edge": (st.edge != 0).then_some(st.edge),
        "actual": s.actual.as_ref().map(|a| positions(&a.pos, n)),
        "following_error": s.actual.as_ref().map(|a| positions(&a.following_error, n)),
        "spindle_rpm": s.actual.map(|a| a.spindle_rpm[0]),
        "spindle_setpoint": st.spindle[0],
        // The tool in the spindle as the PLC reports it (T output as an aux function).
        "plc_tool": s.actual.map(|a| a.tool),
        "plc_alarm": s.actual.and_then(|a| ChannelAlarm::new(a.plc_alarm)).map(ChannelAlarm::number),
    })
}

pub fn status_text(s: &Snapshot) -> String {
    status_json(s).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use softnc_protocol::{ActualValues, KernelStatus};

    /// A lathe with a C axis: three positions each, named by `axes`; C is rotary and modulo
    /// (the page shows it within 0…360°), its position counted on past a turn.
    #[test]
    fn positions_come_with_their_axes_names() {
        let mut st = KernelStatus::default();
        st.axes.names[..3].copy_from_slice(b"XZC");
        st.axes.count = 3;
        st.axes.kinds = 1 << 2 | 1 << (8 + 2);
        st.pos[..3].copy_from_slice(&[10.0, -5.0, 370.0]);
        let mut a = ActualValues::default();
        a.pos[..3].copy_from_slice(&[9.5, -4.5, 369.0]);
        a.following_error[..3].copy_from_slice(&[0.5, -0.5, 1.0]);
        let snap = Snapshot {
            status: Some(st),
            status_age: Some(std::time::Duration::ZERO),
            actual: Some(a),
            ..Default::default()
        };
        let j = status_json(&snap);
        assert_eq!(
            j["axes"],
            json!([
                { "name": "X", "rotary": false, "modulo": false },
                { "name": "Z", "rotary": false, "modulo": false },
                { "name": "C", "rotary": true, "modulo": true },
            ])
        );
        assert_eq!(j["pos"], json!([10.0, -5.0, 370.0]));
        assert_eq!(j["actual"], json!([9.5, -4.5, 369.0]));
        assert_eq!(j["following_error"], json!([0.5, -0.5, 1.0]));
        // No tool, edge or work offset active: null, not 0.
        assert_eq!(
            (&j["tool"], &j["edge"], &j["work_offset"]),
            (&Value::Null, &Value::Null, &Value::Null)
        );
    }

    /// An 840C mill's table (G54 … G57 on X, Y, Z), G55 active, T3 D2 in the channel.
    fn snapshot_with_work_offsets() -> Snapshot {
        let mut w = softnc_protocol::WorkOffsetsMsg {
            version: 4,
            count: 4,
            ..Default::default()
        };
        w.axes.names[..3].copy_from_slice(b"XYZ");
        w.axes.count = 3;
        for (i, e) in w.entries.iter_mut().take(4).enumerate() {
            *e = softnc_protocol::WorkOffsetEntry::new(&format!("G5{}", 4 + i), [0.0; MAX_AXES]);
        }
        w.entries[1].values[0] = -120.5;
        let mut st = KernelStatus {
            work_offsets_version: 4,
            work_offset: 2,
            tool: 3,
            edge: 2,
            ..Default::default()
        };
        st.axes = w.axes;
        Snapshot {
            status: Some(st),
            status_age: Some(std::time::Duration::ZERO),
            work_offsets: Some(w),
            ..Default::default()
        }
    }

    fn api(snap: Snapshot) -> (Arc<Api>, crossbeam::channel::Receiver<crate::link::Job>) {
        let (link, jobs) = crate::link::fake(snap);
        let md = MachineData::load(None, &[]).expect("the built-in machine data");
        (
            Arc::new(Api::new(link, None, md, PathBuf::from("programs"))),
            jobs,
        )
    }

    fn request(api: &Arc<Api>, method: &str, path: &str, body: &str) -> (u16, Value) {
        let req = Request {
            method: method.into(),
            path: path.into(),
            query: String::new(),
            headers: Vec::new(),
            body: body.as_bytes().to_vec(),
        };
        match api.handle(req) {
            crate::net::Response::Full { status, body, .. } => {
                (status, serde_json::from_slice(&body).unwrap_or(Value::Null))
            }
            crate::net::Response::Stream(_) => panic!("{path}: a stream"),
        }
    }

    #[test]
    fn status_names_the_work_offset_tool_and_edge() {
        let j = status_json(&snapshot_with_work_offsets());
        assert_eq!(j["work_offset"], json!("G55"));
        assert_eq!(j["work_offsets_version"], json!(4));
        assert_eq!((&j["tool"], &j["edge"]), (&json!(3), &json!(2)));
    }

    #[test]
    fn the_work_offset_table_as_json() {
        let (api, _) = api(snapshot_with_work_offsets());
        let (code, j) = request(&api, "GET", "/api/work-offsets", "");
        assert_eq!(code, 200, "{j}");
        assert_eq!(j["active"], json!("G55"));
        assert_eq!(j["sets"][1]["values"]["X"], json!(-120.5));
        assert_eq!(j["max_work_offset"], json!(10000.0));
        assert_eq!(j["edit_while_active"], json!(false));
        let (empty, _) = self::api(Snapshot::default());
        assert_eq!(request(&empty, "GET", "/api/work-offsets", "").0, 503);
        assert_eq!(request(&api, "POST", "/api/work-offsets", "{}").0, 405);
        assert_eq!(request(&api, "GET", "/api/work-offset", "").0, 405);
    }

    /// Every malformed or wrong edit is answered 400 or 422 with a reason, and no command
    /// reaches the kernel.
    #[test]
    fn wrong_work_offset_edits_are_refused_before_the_kernel() {
        let (api, jobs) = api(snapshot_with_work_offsets());
        let cases = [
            (400, r#"{"set":"G54","values":{"X":"#, "malformed JSON"),
            (400, r#"[1,2]"#, "expected an object"),
            (400, r#"{"set":"G54"}"#, "values"),
            (400, r#"{"set":"G54","values":{"X":1},"force":1}"#, "force"),
            (400, r#"{"set":"G54","values":{"X":NaN}}"#, "malformed JSON"),
            (
                400,
                r#"{"set":"G54","values":{"X":1e999}}"#,
                "malformed JSON",
            ),
            (
                400,
                r#"{"set":"G54","set":"G55","values":{"X":1}}"#,
                "duplicate",
            ),
            (422, r#"{"set":"G59","values":{"X":1}}"#, "G54 … G57"),
            (
                422,
                r#"{"set":"G54","values":{"C":1}}"#,
                "its axes are X, Y, Z",
            ),
            (422, r#"{"set":"G54","values":{}}"#, "no axis value"),
            (
                422,
                r#"{"set":"G54","values":{"X":10000.5}}"#,
                "hmi.max_work_offset",
            ),
            (422, r#"{"set":"G54","values":{"x":1,"X":1}}"#, "twice"),
        ];
        for (want, body, says) in cases {
            let (code, j) = request(&api, "POST", "/api/work-offset", body);
            let e = j["error"].as_str().unwrap_or_default();
            assert_eq!(code, want, "{body}: {j}");
            assert!(e.contains(says), "{body}: {e}");
        }
        assert!(jobs.try_recv().is_err(), "a command was sent");
    }

    /// A good edit goes to the kernel by the set's own name, its axes by slot; the answer
    /// carries the kernel's message and both table versions.
    #[test]
    fn a_work_offset_edit_goes_to_the_kernel() {
        let (api, jobs) = api(snapshot_with_work_offsets());
        let kernel = std::thread::spawn(move || {
            let job = jobs.recv().expect("a command");
            let c = job.command;
            let mut r = softnc_protocol::Reply::new(true, 0, "G56 taken");
            (r.tools_version, r.work_offsets_version) = (1, 5);
            let _ = job.answer.send(Ok(r));
            (
                c.kind,
                c.text().to_string(),
                c.axis_values().collect::<Vec<_>>(),
            )
        });
        let body = r#"{"set":"g 56","values":{"z":-3,"X":10.5}}"#;
        let (code, j) = request(&api, "POST", "/api/work-offset", body);
        assert_eq!(code, 200, "{j}");
        assert_eq!(
            j,
            json!({ "ok": true, "message": "G56 taken", "tools_version": 1, "work_offsets_version": 5 })
        );
        let (kind, name, values) = kernel.join().expect("the fake kernel");
        assert_eq!(kind, command::SET_WORK_OFFSET);
        assert_eq!(name, "G56");
        assert_eq!(values, [(0, 10.5), (2, -3.0)]);
    }
}
