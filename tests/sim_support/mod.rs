//! A plain std TCP client for the fake vision server, with short bounded timeouts.
#![allow(dead_code)]

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::time::Duration;

use krlkit::sim::{Scenario, Server};

pub const TIMEOUT: Duration = Duration::from_secs(3);

pub fn fixture(name: &str) -> Scenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/scenarios")
        .join(name);
    let text = std::fs::read_to_string(&path).expect("fixture readable");
    Scenario::from_toml_str(&text, name).unwrap_or_else(|e| panic!("{e}"))
}

pub fn scenario(text: &str) -> Scenario {
    Scenario::from_toml_str(text, "inline.toml").unwrap_or_else(|e| panic!("{e}"))
}

pub fn start(s: Scenario) -> Server {
    Server::start(s, "127.0.0.1:0").expect("server starts on an ephemeral port")
}

pub struct Client {
    stream: TcpStream,
    buf: Vec<u8>,
}

/// What a read ended with.
#[derive(Debug, PartialEq, Eq)]
pub enum Read1 {
    Line(String),
    Closed,
    TimedOut,
}

impl Client {
    pub fn connect(addr: SocketAddr) -> Client {
        let stream = TcpStream::connect_timeout(&addr, TIMEOUT).expect("connect");
        stream.set_read_timeout(Some(TIMEOUT)).expect("timeout");
        stream.set_write_timeout(Some(TIMEOUT)).expect("timeout");
        Client {
            stream,
            buf: Vec::new(),
        }
    }

    /// A second handle on the socket (to write from another thread).
    pub fn try_clone_stream(&self) -> TcpStream {
        self.stream.try_clone().expect("clone")
    }

    pub fn set_read_timeout(&self, t: Duration) {
        self.stream.set_read_timeout(Some(t)).expect("timeout");
    }

    pub fn send_raw(&mut self, bytes: &[u8]) {
        self.stream.write_all(bytes).expect("write");
    }

    /// The next CR-terminated reply (without the CR).
    pub fn read(&mut self) -> Read1 {
        loop {
            if let Some(i) = self.buf.iter().position(|b| *b == b'\r') {
                let line: Vec<u8> = self.buf.drain(..=i).take(i).collect();
                return Read1::Line(String::from_utf8(line).expect("ASCII reply"));
            }
            let mut chunk = [0u8; 4096];
            match self.stream.read(&mut chunk) {
                Ok(0) => return Read1::Closed,
                Ok(n) => self.buf.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                    return Read1::TimedOut;
                }
                Err(_) => return Read1::Closed,
            }
        }
    }

    pub fn recv(&mut self) -> String {
        match self.read() {
            Read1::Line(l) => l,
            other => panic!("expected a reply, got {other:?}"),
        }
    }

    /// Send one message (CR appended) and read its reply.
    pub fn ask(&mut self, msg: &str) -> String {
        self.send_raw(format!("{msg}\r").as_bytes());
        self.recv()
    }
}

/// One command on its own connection, as the generated KRL package does it.
pub fn ask_once(addr: SocketAddr, msg: &str) -> String {
    Client::connect(addr).ask(msg)
}

/// The reply's fields.
pub fn fields(reply: &str) -> Vec<&str> {
    reply.split(',').collect()
}
