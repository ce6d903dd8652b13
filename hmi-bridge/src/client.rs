//! A small HTTP/1.1 client for the bridge's API on this machine (the `softnc status`, `start`,
//! `stop`, `reset` and `offset` commands, and the tests): one request per connection, JSON
//! in and out.

use std::io::{Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

/// Where the bridge is and how to be let in.
#[derive(Clone, Debug)]
pub struct Bridge {
    /// `host:port`.
    pub addr: String,
    pub token: Option<String>,
}

/// A response: status code and body.
#[derive(Debug)]
pub struct Answer {
    pub status: u16,
    pub body: String,
}

impl Answer {
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_str(&self.body).unwrap_or(serde_json::Value::Null)
    }
}

impl Bridge {
    pub fn new(addr: impl Into<String>, token: Option<String>) -> Self {
        let addr = addr.into();
        let addr = addr
            .strip_prefix("http://")
            .unwrap_or(&addr)
            .trim_end_matches('/')
            .to_string();
        Bridge { addr, token }
    }

    pub fn get(&self, path: &str) -> Result<Answer, String> {
        self.request("GET", path, None)
    }

    pub fn post(&self, path: &str, body: &serde_json::Value) -> Result<Answer, String> {
        self.request("POST", path, Some(&body.to_string()))
    }

    pub fn request(&self, method: &str, path: &str, body: Option<&str>) -> Result<Answer, String> {
        let unreachable = |e: std::io::Error| {
            format!(
                "cannot reach hmi-bridge at {}: {e} (is it running? `softnc hmi-bridge --instance NAME`)",
                self.addr
            )
        };
        let sock = self
            .addr
            .to_socket_addrs()
            .map_err(unreachable)?
            .next()
            .ok_or_else(|| format!("{}: no address", self.addr))?;
        let mut s =
            TcpStream::connect_timeout(&sock, Duration::from_secs(3)).map_err(unreachable)?;
        s.set_read_timeout(Some(Duration::from_secs(15)))
            .map_err(|e| e.to_string())?;
        let body = body.unwrap_or("");
        let mut head = format!(
            "{method} {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n",
            self.addr,
            body.len()
        );
        if let Some(t) = &self.token {
            head.push_str(&format!("Authorization: Bearer {t}\r\n"));
        }
        head.push_str("\r\n");
        s.write_all(head.as_bytes())
            .and_then(|_| s.write_all(body.as_bytes()))
            .map_err(|e| format!("cannot send to hmi-bridge: {e}"))?;
        let raw =
            read_response(&mut s).map_err(|e| format!("no answer from {}: {e}", self.addr))?;
        parse(&raw)
    }
}

/// One response: up to the end of its body by Content-Length, the last chunk, or the end
/// of the connection (a server may keep it open despite `Connection: close`).
fn read_response(s: &mut TcpStream) -> std::io::Result<Vec<u8>> {
    let mut raw = Vec::new();
    let mut chunk = [0u8; 8192];
    loop {
        if let Some(end) = raw.windows(4).position(|w| w == b"\r\n\r\n").map(|i| i + 4) {
            let head = String::from_utf8_lossy(&raw[..end]).to_ascii_lowercase();
            let length = head
                .lines()
                .find_map(|l| l.strip_prefix("content-length:"))
                .and_then(|v| v.trim().parse::<usize>().ok());
            if let Some(n) = length {
                if raw.len() >= end + n {
                    raw.truncate(end + n);
                    return Ok(raw);
                }
            } else if head.contains("transfer-encoding: chunked") && raw.ends_with(b"0\r\n\r\n") {
                return Ok(raw);
            }
        }
        let n = s.read(&mut chunk)?;
        if n == 0 {
            return Ok(raw);
        }
        raw.extend_from_slice(&chunk[..n]);
    }
}

/// Status code and body of a raw HTTP/1.1 response (Content-Length or chunked).
pub fn parse(raw: &[u8]) -> Result<Answer, String> {
    let text = String::from_utf8_lossy(raw);
    let (head, rest) = text
        .split_once("\r\n\r\n")
        .ok_or("a response without a header end")?;
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .ok_or("a response without a status code")?;
    let chunked = head.lines().any(|l| {
        let l = l.to_ascii_lowercase();
        l.starts_with("transfer-encoding:") && l.contains("chunked")
    });
    let body = if chunked {
        let mut out = String::new();
        let mut r = rest;
        while let Some((size, tail)) = r.split_once("\r\n") {
            let n = usize::from_str_radix(size.trim(), 16).unwrap_or(0);
            if n == 0 || tail.len() < n {
                break;
            }
            out.push_str(&tail[..n]);
            r = tail[n..].trim_start_matches("\r\n");
        }
        out
    } else {
        rest.to_string()
    };
    Ok(Answer { status, body })
}
