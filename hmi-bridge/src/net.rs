//! The HTTP/1.1 transport: one request per connection (`Connection: close`), the head parsed
//! by `httparse`, with the limits an HMI on a shop-floor network needs, which tiny_http
//! could not give (it reads without time limits, and a time limit on its listener ends its
//! accept loop):
//!
//! - a client has `CLIENT_TIME` for its whole request, head and body; slower → 408;
//! - the head at most `MAX_HEAD` bytes (431), the body at most `MAX_BODY` (413), announced
//!   by Content-Length (411 without one; chunked request bodies are not taken);
//! - at most `MAX_CONNECTIONS` at once (503 beyond), each in a thread of its own, so a slow
//!   client never holds up another.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub const MAX_HEAD: usize = 16 * 1024;
pub const MAX_BODY: usize = 16 * 1024;
const MAX_HEADERS: usize = 64;
pub const CLIENT_TIME: Duration = Duration::from_secs(5);
const MAX_CONNECTIONS: usize = 64;

/// A request as the API sees it.
#[derive(Debug)]
pub struct Request {
    pub method: String,
    pub path: String,
    pub query: String,
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Request {
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }
}

/// An answer: a whole body, or an event stream the handler writes itself.
pub enum Response {
    Full {
        status: u16,
        content_type: &'static str,
        body: Vec<u8>,
    },
    /// `text/event-stream`: `write` gets the connection after the head and keeps it.
    Stream(Box<dyn FnOnce(&mut TcpStream) + Send>),
}

impl Response {
    pub fn json(status: u16, v: &serde_json::Value) -> Self {
        Response::Full {
            status,
            content_type: "application/json",
            body: v.to_string().into_bytes(),
        }
    }

    pub fn error(status: u16, message: &str) -> Self {
        Self::json(status, &serde_json::json!({ "error": message }))
    }
}

fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        400 => "Bad Request",
        401 => "Unauthorized",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        411 => "Length Required",
        413 => "Content Too Large",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        503 => "Service Unavailable",
        _ => "Status",
    }
}

/// Binds `addr`; `serve` then answers on it until `stop` is set.
pub fn listen(addr: SocketAddr) -> std::io::Result<TcpListener> {
    let l = TcpListener::bind(addr)?;
    // Non-blocking accept, so the loop sees `stop`.
    l.set_nonblocking(true)?;
    Ok(l)
}

pub fn serve(
    listener: TcpListener,
    handler: Arc<dyn Fn(Request) -> Response + Send + Sync>,
    stop: Arc<AtomicBool>,
) {
    let open = Arc::new(AtomicUsize::new(0));
    while !stop.load(Ordering::Relaxed) {
        let (sock, _) = match listener.accept() {
            Ok(s) => s,
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(10));
                continue;
            }
            Err(_) => {
                std::thread::sleep(Duration::from_millis(10));
                continue;
            }
        };
        let _ = sock.set_nonblocking(false);
        if open.fetch_add(1, Ordering::AcqRel) >= MAX_CONNECTIONS {
            open.fetch_sub(1, Ordering::AcqRel);
            let mut sock = sock;
            let _ = sock.set_write_timeout(Some(Duration::from_secs(1)));
            write_full(&mut sock, &Response::error(503, "too many connections"));
            continue;
        }
        let (handler, open2) = (handler.clone(), open.clone());
        let spawned = std::thread::Builder::new()
            .name("http".into())
            .spawn(move || {
                connection(sock, &*handler);
                open2.fetch_sub(1, Ordering::AcqRel);
            });
        if spawned.is_err() {
            open.fetch_sub(1, Ordering::AcqRel);
        }
    }
}

fn connection(mut sock: TcpStream, handler: &(dyn Fn(Request) -> Response + Send + Sync)) {
    let _ = sock.set_write_timeout(Some(CLIENT_TIME));
    let response = match read_request(&mut sock) {
        Ok(req) => handler(req),
        Err(r) => r,
    };
    match response {
        Response::Stream(write) => {
            let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n";
            if sock.write_all(head.as_bytes()).is_ok() {
                write(&mut sock);
            }
        }
        full => write_full(&mut sock, &full),
    }
    let _ = sock.shutdown(std::net::Shutdown::Both);
}

fn write_full(sock: &mut TcpStream, r: &Response) {
    let Response::Full {
        status,
        content_type,
        body,
    } = r
    else {
        return;
    };
    let head = format!(
        "HTTP/1.1 {status} {}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
        reason(*status),
        body.len()
    );
    let _ = sock
        .write_all(head.as_bytes())
        .and_then(|_| sock.write_all(body));
    let _ = sock.flush();
}

/// Reads from `sock` into `buf` until `done(buf)` or the deadline; the refusal on a
/// timeout or a closed connection.
fn read_until(
    sock: &mut TcpStream,
    buf: &mut Vec<u8>,
    deadline: Instant,
    limit: usize,
    done: impl Fn(&[u8]) -> bool,
    what: &str,
) -> Result<(), Response> {
    let mut chunk = [0u8; 4096];
    while !done(buf) {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(Response::error(408, &format!("the {what} came too slowly")));
        }
        let _ = sock.set_read_timeout(Some(left));
        match sock.read(&mut chunk) {
            Ok(0) => {
                return Err(Response::error(
                    400,
                    &format!("the connection closed inside the {what}"),
                ))
            }
            Ok(n) => buf.extend_from_slice(&chunk[..n]),
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                return Err(Response::error(408, &format!("the {what} came too slowly")));
            }
            Err(e) => {
                return Err(Response::error(
                    400,
                    &format!("cannot read the {what}: {e}"),
                ))
            }
        }
        if buf.len() > limit && !done(buf) {
            return Err(if what == "request head" {
                Response::error(
                    431,
                    &format!("the request head is larger than {MAX_HEAD} bytes"),
                )
            } else {
                Response::error(413, &format!("the body is larger than {MAX_BODY} bytes"))
            });
        }
    }
    Ok(())
}

fn head_end(b: &[u8]) -> Option<usize> {
    b.windows(4).position(|w| w == b"\r\n\r\n").map(|i| i + 4)
}

fn read_request(sock: &mut TcpStream) -> Result<Request, Response> {
    let deadline = Instant::now() + CLIENT_TIME;
    let mut buf = Vec::with_capacity(1024);
    read_until(
        sock,
        &mut buf,
        deadline,
        MAX_HEAD,
        |b| head_end(b).is_some(),
        "request head",
    )?;
    let end = head_end(&buf).unwrap_or(buf.len());
    if end > MAX_HEAD {
        return Err(Response::error(
            431,
            &format!("the request head is larger than {MAX_HEAD} bytes"),
        ));
    }
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut parsed = httparse::Request::new(&mut headers);
    match parsed.parse(&buf[..end]) {
        Ok(httparse::Status::Complete(_)) => {}
        Ok(httparse::Status::Partial) => {
            return Err(Response::error(400, "an incomplete request head"))
        }
        Err(httparse::Error::TooManyHeaders) => {
            return Err(Response::error(
                431,
                &format!("more than {MAX_HEADERS} header fields"),
            ))
        }
        Err(e) => return Err(Response::error(400, &format!("a malformed request: {e}"))),
    }
    let method = parsed.method.unwrap_or("").to_string();
    let target = parsed.path.unwrap_or("/");
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let mut hs = Vec::new();
    for h in parsed.headers.iter() {
        hs.push((
            h.name.to_string(),
            String::from_utf8_lossy(h.value).trim().to_string(),
        ));
    }
    let mut req = Request {
        method,
        path: path.to_string(),
        query: query.to_string(),
        headers: hs,
        body: Vec::new(),
    };
    if req
        .header("Transfer-Encoding")
        .is_some_and(|t| !t.eq_ignore_ascii_case("identity"))
    {
        return Err(Response::error(411, "send the body with a Content-Length"));
    }
    let length = match req.header("Content-Length") {
        None => 0,
        Some(v) => v
            .parse::<u64>()
            .map_err(|_| Response::error(400, &format!("Content-Length {v:?} is not a number")))?,
    };
    if length > MAX_BODY as u64 {
        return Err(Response::error(
            413,
            &format!("the body is larger than {MAX_BODY} bytes"),
        ));
    }
    let length = length as usize;
    let mut body = buf[end..].to_vec();
    read_until(
        sock,
        &mut body,
        deadline,
        MAX_BODY,
        |b| b.len() >= length,
        "body",
    )?;
    body.truncate(length);
    req.body = body;
    Ok(req)
}
