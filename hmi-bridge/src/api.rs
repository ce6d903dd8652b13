//! The HTTP API and the page (docs/hmi.md). Every answer is JSON (the page and the event
//! stream aside); every refusal a 4xx or 5xx with `{"error": "…"}` that says why, and a
//! refused request changes nothing.

use crate::link::{Link, Snapshot};
use crate::net::{Request, Response};
use crate::plot;
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
    /// (program path, tool table version, the plot as JSON).
    plot_cache: Mutex<Option<(String, u32, Arc<String>)>>,
}

/// A refusal: status code and message.
struct Refuse(u16, String);

fn refuse(code: u16, m: impl Into<String>) -> Refuse {
    Refuse(code, m.into())
}

type Answer = Result<(u16, Value), Refuse>;

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
            "/api/status" | "/api/tools" | "/api/programs" | "/api/program" | "/api/plot"
            | "/api/start" | "/api/stop" | "/api/reset" | "/api/single-block" | "/api/override"
            | "/api/load" | "/api/offset" => {
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
        let version = r.tools_version;
        if r.ok != 0 {
            Ok((
                200,
                json!({ "ok": true, "message": r.message(), "tools_version": version }),
            ))
        } else {
            let mut v = json!({ "error": r.message(), "tools_version": version });
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
            plot::table(table)
                .edit(t, b.d, b.wear, b.radius, limit)
                .map_err(|e| refuse(422, format!("{e}; nothing changed")))?;
        }
        self.command(Command::offset(t, b.d, b.radius, b.wear))
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
        let text =
            std::fs::read_to_string(&path).map_err(|e| refuse(404, format!("{path}: {e}")))?;
        Ok((200, json!({ "path": path, "text": text })))
    }

    fn plot(&self) -> Answer {
        let snap = self.link.snapshot();
        let (Some(path), Some(t)) = (snap.program_path, snap.tools) else {
            let empty = serde_json::to_value(plot::empty(&self.md))
                .map_err(|e| refuse(500, e.to_string()))?;
            return Ok((200, empty));
        };
        if let Ok(c) = self.plot_cache.lock() {
            if let Some((p, v, j)) = c.as_ref() {
                if *p == path && *v == t.version {
                    return Ok((200, serde_json::from_str(j).unwrap_or(Value::Null)));
                }
            }
        }
        let source =
            std::fs::read_to_string(&path).map_err(|e| refuse(404, format!("{path}: {e}")))?;
        let pl = plot::plot(&path, &source, &self.md, &plot::table(&t));
        let text = serde_json::to_string(&pl).map_err(|e| refuse(500, e.to_string()))?;
        if let Ok(mut c) = self.plot_cache.lock() {
            *c = Some((path, t.version, Arc::new(text.clone())));
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
/// not here).
fn body<T: serde::de::DeserializeOwned>(req: &Request) -> Result<T, Refuse> {
    let text = text(req)?;
    let v: Value =
        serde_json::from_str(&text).map_err(|e| refuse(400, format!("malformed JSON: {e}")))?;
    if !v.is_object() {
        return Err(refuse(400, "malformed JSON: expected an object"));
    }
    serde_json::from_value(v).map_err(|e| refuse(400, format!("malformed JSON: {e}")))
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
        "actual": s.actual.as_ref().map(|a| positions(&a.pos, n)),
        "following_error": s.actual.as_ref().map(|a| positions(&a.following_error, n)),
        "spindle_rpm": s.actual.map(|a| a.spindle_rpm),
        "tool": s.actual.map(|a| a.tool),
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
    }
}
