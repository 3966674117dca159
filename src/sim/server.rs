//! The TCP side: one background thread that accepts one client at a time, splits its byte
//! stream into CR-terminated messages, applies injected faults and answers from [`State`].

use std::collections::{HashMap, VecDeque};
use std::fmt;
use std::io::{self, ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant, SystemTime};

use crate::catalog::catalog;

use super::clock::{Clock, SystemClock};
use super::protocol::{self, DecodeError, Request};
use super::scenario::{Fault, Scenario};
use super::state::{State, codes};

/// Requests kept in memory; older ones are dropped (the observer still saw them).
const LOG_CAPACITY: usize = 10_000;
/// How often blocked reads and the accept loop look at the stop flag.
const POLL: Duration = Duration::from_millis(20);
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);
/// Characters of a request kept in the log (the reply is bounded by the scenario).
const MAX_LOGGED_RAW: usize = 1024;

/// One request as the server saw and answered it.
#[derive(Debug, Clone, PartialEq)]
pub struct RequestLog {
    /// 1-based, in arrival order.
    pub seq: u64,
    pub time: SystemTime,
    /// Since the server started.
    pub elapsed: Duration,
    pub peer: SocketAddr,
    /// 1-based number of the TCP connection it came on (shows per-command reconnects).
    pub connection: u64,
    /// The message without its terminator (invalid UTF-8 replaced; oversized input cut).
    pub raw: String,
    /// The decoded command number, if the first field was readable.
    pub command: Option<u32>,
    /// The catalog name of the command, if known.
    pub name: Option<String>,
    /// The decoded numeric fields after the command (empty when undecodable).
    pub args: Vec<f64>,
    /// The reply line without CR; `None` when the connection was dropped without a reply.
    pub reply: Option<String>,
    /// The injected fault or input problem, in words.
    pub note: Option<String>,
}

impl fmt::Display for RequestLog {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "#{} +{:.3}s conn {} {} {:?}",
            self.seq,
            self.elapsed.as_secs_f64(),
            self.connection,
            self.peer,
            self.raw
        )?;
        if let Some(name) = &self.name {
            write!(f, " ({name})")?;
        }
        match &self.reply {
            Some(r) => write!(f, " -> {r:?}")?,
            None => write!(f, " -> no reply")?,
        }
        if let Some(n) = &self.note {
            write!(f, " [{n}]")?;
        }
        Ok(())
    }
}

/// Called on the server thread for every request, after it was answered.
pub type Observer = Box<dyn FnMut(&RequestLog) + Send>;

struct Shared {
    stop: AtomicBool,
    seq: AtomicU64,
    log: Mutex<VecDeque<RequestLog>>,
    state: Mutex<State>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic while holding the lock cannot leave the data half-written in a way that matters
    // here (log entries and state updates are single assignments), so keep serving.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A running fake vision server. Dropping it stops the server thread.
pub struct Server {
    addr: SocketAddr,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl Server {
    /// Bind `addr` (e.g. `127.0.0.1:0` for an ephemeral port) and serve `scenario`.
    pub fn start(scenario: Scenario, addr: impl ToSocketAddrs) -> io::Result<Server> {
        Server::start_with_observer(scenario, addr, Box::new(|_| {}))
    }

    /// Like [`Server::start`], and call `observer` with every request as it is answered.
    pub fn start_with_observer(
        scenario: Scenario,
        addr: impl ToSocketAddrs,
        observer: Observer,
    ) -> io::Result<Server> {
        Server::spawn(scenario, addr, observer, Arc::new(SystemClock::new()))
    }

    /// Like [`Server::start`], with Notify messages expiring on `clock` (a
    /// [`ManualClock`](super::ManualClock) in tests) instead of wall time.
    pub fn start_with_clock(
        scenario: Scenario,
        addr: impl ToSocketAddrs,
        clock: Arc<dyn Clock>,
    ) -> io::Result<Server> {
        Server::spawn(scenario, addr, Box::new(|_| {}), clock)
    }

    fn spawn(
        scenario: Scenario,
        addr: impl ToSocketAddrs,
        observer: Observer,
        clock: Arc<dyn Clock>,
    ) -> io::Result<Server> {
        // Blocking accept: a connection per command must not wait for a polling tick. `stop`
        // wakes the thread with a connection of its own.
        let listener = TcpListener::bind(addr)?;
        let addr = listener.local_addr()?;
        let shared = Arc::new(Shared {
            stop: AtomicBool::new(false),
            seq: AtomicU64::new(0),
            log: Mutex::new(VecDeque::new()),
            state: Mutex::new(State::with_clock(scenario, clock)),
        });
        let worker = Worker {
            shared: Arc::clone(&shared),
            observer,
            started: Instant::now(),
            occurrences: HashMap::new(),
            connections: 0,
        };
        let thread = thread::Builder::new()
            .name("krlkit-sim".into())
            .spawn(move || worker.run(&listener))?;
        Ok(Server {
            addr,
            shared,
            thread: Some(thread),
        })
    }

    /// The bound address (with the real port when started on port 0).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The requests so far (the most recent ones, up to a fixed capacity).
    pub fn requests(&self) -> Vec<RequestLog> {
        lock(&self.shared.log).iter().cloned().collect()
    }

    /// A copy of the protocol state (triggered projects, cursors, Viz settings, ...).
    pub fn state(&self) -> State {
        lock(&self.shared.state).clone()
    }

    /// Stop accepting, close the current client and wait for the server thread.
    pub fn shutdown(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            // The worker notices the flag within one read poll while serving a client, and on
            // its next accept otherwise: give it one to accept.
            let _ = TcpStream::connect_timeout(&wake_addr(self.addr), WRITE_TIMEOUT);
            let _ = t.join();
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop();
    }
}

struct Worker {
    shared: Arc<Shared>,
    observer: Observer,
    started: Instant,
    /// Requests per command number so far (for `occurrence` faults).
    occurrences: HashMap<u32, u32>,
    connections: u64,
}

enum Next {
    Continue,
    Close,
}

impl Worker {
    fn stopping(&self) -> bool {
        self.shared.stop.load(Ordering::SeqCst)
    }

    fn run(mut self, listener: &TcpListener) {
        while !self.stopping() {
            match listener.accept() {
                Ok(_) if self.stopping() => break,
                Ok((stream, peer)) => {
                    self.connections += 1;
                    self.serve(stream, peer);
                }
                // E.g. too many open files: back off instead of spinning.
                Err(_) => thread::sleep(POLL),
            }
        }
    }

    fn serve(&mut self, mut stream: TcpStream, peer: SocketAddr) {
        let settings = lock(&self.shared.state).scenario().server.clone();
        let configured = stream
            .set_nonblocking(false)
            .and_then(|()| stream.set_read_timeout(Some(POLL)))
            .and_then(|()| stream.set_write_timeout(Some(WRITE_TIMEOUT)))
            .and_then(|()| stream.set_nodelay(true));
        if configured.is_err() {
            return;
        }
        let idle_limit = Duration::from_millis(settings.idle_timeout_ms);
        let max = settings.max_message_bytes;
        let mut buf: Vec<u8> = Vec::new();
        let mut chunk = [0u8; 1024];
        let mut last_input = Instant::now();
        loop {
            while let Some(end) = buf.iter().position(|b| matches!(b, b'\r' | b'\n')) {
                let message: Vec<u8> = buf.drain(..=end).take(end).collect();
                let next = if message.len() > max {
                    self.oversized(&mut stream, peer, &message, max)
                } else {
                    self.message(&mut stream, peer, &message)
                };
                if matches!(next, Next::Close) {
                    return;
                }
            }
            if buf.len() > max {
                self.oversized(&mut stream, peer, &buf, max);
                return;
            }
            if self.stopping() {
                return;
            }
            match stream.read(&mut chunk) {
                Ok(0) => return,
                Ok(n) => {
                    buf.extend_from_slice(&chunk[..n]);
                    last_input = Instant::now();
                }
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                    if last_input.elapsed() >= idle_limit {
                        return;
                    }
                }
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => return,
            }
        }
    }

    fn oversized(
        &mut self,
        stream: &mut TcpStream,
        peer: SocketAddr,
        bytes: &[u8],
        max: usize,
    ) -> Next {
        let reply = format!("0,{}", codes().invalid_format);
        let shown = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]).into_owned();
        self.record(
            peer,
            format!("{shown}..."),
            None,
            Some(reply.clone()),
            Some(format!(
                "message longer than {max} bytes without a terminator; connection closed"
            )),
        );
        let _ = write_line(stream, &reply);
        Next::Close
    }

    fn message(&mut self, stream: &mut TcpStream, peer: SocketAddr, bytes: &[u8]) -> Next {
        let raw = String::from_utf8_lossy(bytes).into_owned();
        let text = raw.trim_matches([' ', '\t']);
        if text.is_empty() {
            return Next::Continue;
        }
        let bad = codes().invalid_format;
        let req = match protocol::decode(text) {
            Ok(r) => r,
            Err(e) => {
                let (cmd, echo) = match e {
                    DecodeError::NoCommand => (None, 0),
                    DecodeError::BadField(c) => (Some(c), c),
                };
                let reply = format!("{echo},{bad}");
                let decoded = cmd.map(|c| Request {
                    command: c,
                    args: Vec::new(),
                });
                self.record(
                    peer,
                    raw,
                    decoded.as_ref(),
                    Some(reply.clone()),
                    Some("not a comma-separated list of numbers".into()),
                );
                return self.send(stream, &reply);
            }
        };
        // Only catalog commands are counted (faults can only name those), so a client cycling
        // through arbitrary numbers cannot grow the map.
        let occurrence = if catalog().command(req.command).is_some() {
            let count = self.occurrences.entry(req.command).or_insert(0);
            *count = count.saturating_add(1);
            *count
        } else {
            0
        };
        let fault = lock(&self.shared.state)
            .scenario()
            .faults
            .iter()
            .find(|f| f.matches(req.command, occurrence))
            .cloned();
        let Some(fault) = fault else {
            let reply = lock(&self.shared.state).handle(&req);
            self.record(peer, raw, Some(&req), Some(reply.clone()), None);
            return self.send(stream, &reply);
        };
        if fault.delay_ms > 0 && !self.sleep(Duration::from_millis(fault.delay_ms)) {
            return Next::Close;
        }
        let (reply, note) = self.apply(&fault, &req);
        self.record(peer, raw, Some(&req), reply.clone(), Some(note));
        match reply {
            Some(r) => self.send(stream, &r),
            None => Next::Close,
        }
    }

    /// The reply (None = drop the connection) and a description of an injected fault.
    fn apply(&mut self, fault: &Fault, req: &Request) -> (Option<String>, String) {
        let delay = if fault.delay_ms > 0 {
            format!("delayed {} ms", fault.delay_ms)
        } else {
            String::new()
        };
        let join = |what: String| {
            if delay.is_empty() {
                what
            } else if what.is_empty() {
                delay.clone()
            } else {
                format!("{delay}; {what}")
            }
        };
        if fault.drop {
            return (None, join("fault: connection dropped".into()));
        }
        if let Some(status) = fault.status {
            let reply = format!("{},{status}", req.command);
            return (Some(reply), join(format!("fault: forced status {status}")));
        }
        if let Some(g) = &fault.garbage {
            return (Some(g.clone()), join("fault: garbage reply".into()));
        }
        let reply = lock(&self.shared.state).handle(req);
        if let Some(echo) = fault.wrong_echo {
            let rest = reply.find(',').map_or("", |i| &reply[i..]);
            let wrong = format!("{echo}{rest}");
            return (Some(wrong), join(format!("fault: wrong echo {echo}")));
        }
        (Some(reply), join(String::new()))
    }

    /// Sleep in small steps; false when the server is stopping.
    fn sleep(&self, total: Duration) -> bool {
        let until = Instant::now() + total;
        while Instant::now() < until {
            if self.stopping() {
                return false;
            }
            thread::sleep(POLL.min(until.saturating_duration_since(Instant::now())));
        }
        true
    }

    fn send(&self, stream: &mut TcpStream, reply: &str) -> Next {
        match write_line(stream, reply) {
            Ok(()) => Next::Continue,
            Err(_) => Next::Close,
        }
    }

    fn record(
        &mut self,
        peer: SocketAddr,
        raw: String,
        req: Option<&Request>,
        reply: Option<String>,
        note: Option<String>,
    ) {
        let raw = clip(raw, MAX_LOGGED_RAW);
        let entry = RequestLog {
            seq: self.shared.seq.fetch_add(1, Ordering::SeqCst) + 1,
            time: SystemTime::now(),
            elapsed: self.started.elapsed(),
            peer,
            connection: self.connections,
            raw,
            command: req.map(|r| r.command),
            name: req
                .and_then(|r| catalog().command(r.command))
                .map(|c| c.name.clone()),
            args: req.map(|r| r.args.clone()).unwrap_or_default(),
            reply,
            note,
        };
        {
            let mut log = lock(&self.shared.log);
            if log.len() >= LOG_CAPACITY {
                log.pop_front();
            }
            log.push_back(entry.clone());
        }
        (self.observer)(&entry);
    }
}

fn write_line(stream: &mut TcpStream, reply: &str) -> io::Result<()> {
    let mut bytes = Vec::with_capacity(reply.len() + 1);
    bytes.extend_from_slice(reply.as_bytes());
    bytes.push(b'\r');
    stream.write_all(&bytes)?;
    stream.flush()
}

/// At most `max` characters, marked with `...` when cut.
fn clip(text: String, max: usize) -> String {
    match text.char_indices().nth(max) {
        Some((i, _)) => format!("{}...", &text[..i]),
        None => text,
    }
}

/// Where to connect to reach our own listener (a wildcard bind is reached over loopback).
fn wake_addr(bound: SocketAddr) -> SocketAddr {
    let mut a = bound;
    if a.ip().is_unspecified() {
        a.set_ip(match a {
            SocketAddr::V4(_) => std::net::Ipv4Addr::LOCALHOST.into(),
            SocketAddr::V6(_) => std::net::Ipv6Addr::LOCALHOST.into(),
        });
    }
    a
}
