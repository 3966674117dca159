//! The TCP side: an accept thread and one session thread per connected client (at most
//! `max_clients`), each cutting its byte stream into messages with a [`Codec`], applying
//! injected faults and answering from the shared [`State`].
//!
//! Sessions share the protocol state (the one Mech-Vision/Mech-Viz project a real server runs:
//! a 101 on one connection is fetched by a 102 on the next, as the KUKA package connects per
//! command), the fault occurrence counters and the request log; each has its own input buffer
//! and idle timer. The idle timer restarts on complete messages only, so a client that sends a
//! byte now and then cannot keep its session (and, at the cap, another client) waiting.

use std::collections::{HashMap, VecDeque};
use std::fmt;
use std::io::{self, ErrorKind, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant, SystemTime};

use crate::catalog::{Codec as Wire, Interface, catalog};

use super::clock::{Clock, SystemClock};
use super::hex::{ByteOrder, HexCodec};
use super::protocol::{AsciiCodec, Codec, DecodeError, Frame, Reply, Request};
use super::scenario::{Fault, Scenario, ServerSettings};
use super::state::{State, codes};

/// Requests kept in memory; older ones are dropped (the observer still saw them).
const LOG_CAPACITY: usize = 10_000;
/// Longest a blocked read waits before the session looks at the stop flag and its idle timer
/// again (a stop also shuts the socket down, which ends the read at once).
const MAX_READ_WAIT: Duration = Duration::from_millis(250);
/// How often a fault's delay looks at the stop flag.
const POLL: Duration = Duration::from_millis(20);
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);
/// Characters of a request kept in the log (the reply is bounded by the scenario).
const MAX_LOGGED_RAW: usize = 1024;
/// Bytes of a message in the other framing shown in the log (a HEX frame is 660 bytes).
const FOREIGN_SHOWN: usize = 16;
/// After a message in the other framing without a line end, input is dropped until the client
/// was quiet this long: the rest of that frame is no new message, and gets no second reply.
const FOREIGN_QUIET: Duration = Duration::from_millis(100);
/// Stack of a session thread: sessions only parse short messages and format replies.
const SESSION_STACK: usize = 256 * 1024;

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

/// Called for every request, after it was answered (from the session's thread; calls are
/// serialised and come in `seq` order).
pub type Observer = Box<dyn FnMut(&RequestLog) + Send>;

/// Open sessions: a handle on each socket (to end it at a stop) and every session thread.
#[derive(Default)]
struct Sessions {
    open: HashMap<u64, TcpStream>,
    threads: Vec<JoinHandle<()>>,
}

struct Shared {
    stop: AtomicBool,
    started: Instant,
    settings: ServerSettings,
    interface: Interface,
    /// TCP connections accepted so far (refused ones included).
    connections: AtomicU64,
    log: Mutex<Log>,
    observer: Mutex<Observer>,
    state: Mutex<State>,
    /// Requests per catalog command so far (for `occurrence` faults), over all sessions.
    occurrences: Mutex<HashMap<u32, u32>>,
    sessions: Mutex<Sessions>,
}

#[derive(Default)]
struct Log {
    seq: u64,
    entries: VecDeque<RequestLog>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic while holding the lock cannot leave the data half-written in a way that matters
    // here (log entries and state updates are single assignments), so keep serving.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Shared {
    fn stopping(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }

    fn record(&self, peer: SocketAddr, connection: u64, entry: Entry) {
        let Entry {
            raw,
            request,
            reply,
            note,
        } = entry;
        let mut log = lock(&self.log);
        log.seq += 1;
        let record = RequestLog {
            seq: log.seq,
            time: SystemTime::now(),
            elapsed: self.started.elapsed(),
            peer,
            connection,
            raw: clip(raw, MAX_LOGGED_RAW),
            command: request.as_ref().map(|r| r.command),
            name: request
                .as_ref()
                .and_then(|r| catalog().command_in(self.interface, r.command))
                .map(|c| c.name.clone()),
            args: request.map(|r| r.args).unwrap_or_default(),
            reply,
            note,
        };
        if log.entries.len() >= LOG_CAPACITY {
            log.entries.pop_front();
        }
        log.entries.push_back(record.clone());
        // Still under the log lock, so observers see records in `seq` order.
        (lock(&self.observer))(&record);
    }
}

/// What a log entry says, before the server numbers and stamps it.
struct Entry {
    raw: String,
    request: Option<Request>,
    reply: Option<String>,
    note: Option<String>,
}

/// A running fake vision server. Dropping it stops every thread of it promptly.
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
            started: Instant::now(),
            settings: scenario.server.clone(),
            interface: scenario.interface,
            connections: AtomicU64::new(0),
            log: Mutex::new(Log::default()),
            observer: Mutex::new(observer),
            state: Mutex::new(State::with_clock(scenario, clock)),
            occurrences: Mutex::new(HashMap::new()),
            sessions: Mutex::new(Sessions::default()),
        });
        let accepting = Arc::clone(&shared);
        let thread = thread::Builder::new()
            .name("krlkit-sim".into())
            .spawn(move || accept_loop(&accepting, &listener))?;
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
        lock(&self.shared.log).entries.iter().cloned().collect()
    }

    /// A copy of the protocol state (triggered projects, cursors, Viz settings, ...).
    pub fn state(&self) -> State {
        lock(&self.shared.state).clone()
    }

    /// Sessions open right now.
    pub fn open_sessions(&self) -> usize {
        lock(&self.shared.sessions).open.len()
    }

    /// Stop accepting, close every client and wait for all server threads.
    pub fn shutdown(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        let Some(accept) = self.thread.take() else {
            return;
        };
        // The accept thread registers sessions under this lock and checks the flag there, so
        // no session opens after this pass; shutting the sockets down ends blocked reads.
        for s in lock(&self.shared.sessions).open.values() {
            let _ = s.shutdown(Shutdown::Both);
        }
        let _ = TcpStream::connect_timeout(&wake_addr(self.addr), WRITE_TIMEOUT);
        let _ = accept.join();
        let threads = std::mem::take(&mut lock(&self.shared.sessions).threads);
        for t in threads {
            let _ = t.join();
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop();
    }
}

fn accept_loop(shared: &Arc<Shared>, listener: &TcpListener) {
    while !shared.stopping() {
        match listener.accept() {
            Ok(_) if shared.stopping() => break,
            Ok((stream, peer)) => admit(shared, stream, peer),
            // E.g. too many open files: back off instead of spinning.
            Err(_) => thread::sleep(POLL),
        }
    }
}

/// Start a session for a new connection, or refuse it when `max_clients` are open.
fn admit(shared: &Arc<Shared>, stream: TcpStream, peer: SocketAddr) {
    let connection = shared.connections.fetch_add(1, Ordering::SeqCst) + 1;
    let max = shared.settings.max_clients;
    let mut sessions = lock(&shared.sessions);
    if shared.stopping() {
        return;
    }
    sessions.threads.retain(|t| !t.is_finished());
    if sessions.open.len() >= max {
        drop(sessions);
        refuse(
            shared,
            &stream,
            peer,
            connection,
            format!("connection refused: {max} clients are connected (max_clients)"),
        );
        return;
    }
    let Ok(handle) = stream.try_clone() else {
        drop(sessions);
        let why = "connection refused: cannot use the socket".to_string();
        refuse(shared, &stream, peer, connection, why);
        return;
    };
    let worker = Arc::clone(shared);
    let spawned = thread::Builder::new()
        .name(format!("krlkit-sim-{connection}"))
        .stack_size(SESSION_STACK)
        .spawn(move || {
            Session::new(&worker, stream, peer, connection).run();
            lock(&worker.sessions).open.remove(&connection);
        });
    match spawned {
        Ok(t) => {
            sessions.open.insert(connection, handle);
            sessions.threads.push(t);
        }
        Err(e) => {
            drop(sessions);
            let why = format!("connection refused: no session thread ({e})");
            refuse(shared, &handle, peer, connection, why);
        }
    }
}

/// Close a connection that gets no session, and say why in the request log.
fn refuse(shared: &Shared, stream: &TcpStream, peer: SocketAddr, connection: u64, why: String) {
    // Logged before the close, so whoever sees the close finds the entry.
    shared.record(
        peer,
        connection,
        Entry {
            raw: String::new(),
            request: None,
            reply: None,
            note: Some(why),
        },
    );
    let _ = stream.shutdown(Shutdown::Both);
}

enum Next {
    Continue,
    Close,
}

/// One client's connection: its input buffer, codec and idle timer.
struct Session<'s> {
    shared: &'s Shared,
    stream: TcpStream,
    peer: SocketAddr,
    connection: u64,
    codec: Box<dyn Codec>,
    /// The server's framing, to recognise a client that uses the other one.
    framing: crate::eki::Framing,
}

impl<'s> Session<'s> {
    fn new(shared: &'s Shared, stream: TcpStream, peer: SocketAddr, connection: u64) -> Self {
        let settings = &shared.settings;
        let hex = |order| -> Box<dyn Codec> {
            Box::new(HexCodec::new(
                order,
                shared.interface,
                settings.hex_reply_bytes(),
            ))
        };
        let codec: Box<dyn Codec> = match settings.codec {
            Wire::Ascii => Box::new(
                AsciiCodec::new(settings.max_message_bytes)
                    .with_unterminated(Duration::from_millis(settings.ascii_unterminated_ms)),
            ),
            Wire::HexLe => hex(ByteOrder::Little),
            Wire::HexBe => hex(ByteOrder::Big),
        };
        let framing = match settings.codec {
            Wire::Ascii => crate::eki::Framing::Stream,
            Wire::HexLe | Wire::HexBe => crate::eki::Framing::Byte {
                size: u32::try_from(settings.hex_reply_bytes()).unwrap_or(u32::MAX),
            },
        };
        Session {
            codec,
            framing,
            shared,
            stream,
            peer,
            connection,
        }
    }

    fn run(mut self) {
        let configured = self
            .stream
            .set_nonblocking(false)
            .and_then(|()| self.stream.set_write_timeout(Some(WRITE_TIMEOUT)))
            .and_then(|()| self.stream.set_nodelay(true));
        if configured.is_err() {
            return;
        }
        let idle_limit = Duration::from_millis(self.shared.settings.idle_timeout_ms);
        let mut input: Vec<u8> = Vec::new();
        let mut chunk = [0u8; 1024];
        // Restarted by complete messages only: bytes that never make one do not keep a
        // session open.
        let mut last_message = Instant::now();
        let mut last_input = Instant::now();
        let mut discarding = false;
        loop {
            loop {
                if !discarding && self.framing.foreign(&input) {
                    // The foreign message ends at a line end if it has one; else the rest of
                    // it is still arriving and is dropped until the client is quiet.
                    let end = input.iter().position(|b| b"\r\n".contains(b));
                    let bytes: Vec<u8> = match end {
                        Some(e) => input.drain(..=e).collect(),
                        None => std::mem::take(&mut input),
                    };
                    if matches!(self.foreign(&bytes), Next::Close) {
                        return;
                    }
                    discarding = end.is_none();
                    continue;
                }
                if discarding {
                    input.clear();
                    break;
                }
                let frame = match self.codec.next_frame(&mut input) {
                    Some(f) => f,
                    // Input the codec takes without a terminator once it stayed quiet.
                    None => match self.codec.pending_wait(&input) {
                        Some(quiet) if last_input.elapsed() >= quiet => {
                            match self.codec.flush(&mut input) {
                                Some(f) => f,
                                None => break,
                            }
                        }
                        _ => break,
                    },
                };
                let next = match frame {
                    Frame::Message(m) => self.message(&m),
                    Frame::Oversized(bytes) => self.oversized(&bytes),
                };
                if matches!(next, Next::Close) {
                    return;
                }
                last_message = Instant::now();
            }
            if self.shared.stopping() {
                return;
            }
            let idle_left = idle_limit.saturating_sub(last_message.elapsed());
            if idle_left.is_zero() {
                return;
            }
            let quiet_left = self.codec.pending_wait(&input).map(|q| {
                q.saturating_sub(last_input.elapsed())
                    .max(Duration::from_millis(1))
            });
            let wait = idle_left
                .min(MAX_READ_WAIT)
                .min(quiet_left.unwrap_or(MAX_READ_WAIT))
                .min(if discarding {
                    FOREIGN_QUIET
                } else {
                    MAX_READ_WAIT
                });
            if self.stream.set_read_timeout(Some(wait)).is_err() {
                return;
            }
            match self.stream.read(&mut chunk) {
                Ok(0) => return,
                Ok(n) => {
                    input.extend_from_slice(&chunk[..n]);
                    last_input = Instant::now();
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted
                    ) =>
                {
                    discarding &= last_input.elapsed() < FOREIGN_QUIET;
                }
                Err(_) => return,
            }
        }
    }

    /// A message in the other framing (a HEX client of an ASCII server, or the reverse): said
    /// in the log at once, with a short hex dump, and answered with the invalid-format reply in
    /// the server's own framing, which the client's EthernetKRL recognises as foreign in turn.
    fn foreign(&mut self, bytes: &[u8]) -> Next {
        let server = self.framing.codec();
        let (client, fix) = match self.framing {
            crate::eki::Framing::Stream => ("HEX (binary 4-byte fields)", "hex-le"),
            crate::eki::Framing::Byte { .. } => ("ASCII (text)", "ascii"),
        };
        let shown = match self.framing {
            crate::eki::Framing::Stream => crate::eki::dump(bytes, FOREIGN_SHOWN),
            crate::eki::Framing::Byte { .. } => {
                clip(String::from_utf8_lossy(bytes).into_owned(), FOREIGN_SHOWN)
            }
        };
        let reply = Reply::new(0, 0).int(i64::from(codes().invalid_format));
        self.record(Entry {
            raw: shown,
            request: None,
            reply: Some(reply.text()),
            note: Some(format!(
                "the client speaks {client}; this server speaks {server}: serve it with `--codec {fix}` (or `[server] codec`), or give the package the server's codec in its spec"
            )),
        });
        self.send(&reply)
    }

    fn record(&self, entry: Entry) {
        self.shared.record(self.peer, self.connection, entry);
    }

    fn oversized(&mut self, bytes: &[u8]) -> Next {
        let max = self.shared.settings.max_message_bytes;
        let reply = Reply::new(0, 0).int(i64::from(codes().invalid_format));
        let shown = self.codec.show(&bytes[..bytes.len().min(64)]);
        self.record(Entry {
            raw: format!("{shown}..."),
            request: None,
            reply: Some(reply.text()),
            note: Some(format!(
                "message longer than {max} bytes without a terminator; connection closed"
            )),
        });
        let _ = self.send(&reply);
        Next::Close
    }

    fn message(&mut self, bytes: &[u8]) -> Next {
        let raw = self.codec.show(bytes);
        let req = match self.codec.decode(bytes) {
            Ok(r) => r,
            Err(e) => {
                let (cmd, echo) = match e {
                    DecodeError::NoCommand => (None, 0),
                    DecodeError::BadField(c) => (Some(c), c),
                };
                let reply = Reply::new(i64::from(echo), 0).int(i64::from(codes().invalid_format));
                self.record(Entry {
                    raw,
                    request: cmd.map(|c| Request {
                        command: c,
                        args: Vec::new(),
                    }),
                    reply: Some(reply.text()),
                    note: Some(match self.shared.settings.codec {
                        Wire::Ascii => "not a comma-separated list of numbers".into(),
                        _ => "not a request of 4-byte fields (command, then int32/float32)".into(),
                    }),
                });
                return self.send(&reply);
            }
        };
        let fault = self.fault_for(&req);
        let Some(fault) = fault else {
            let reply = lock(&self.shared.state).handle(&req);
            self.record(Entry {
                raw,
                request: Some(req),
                reply: Some(reply.text()),
                note: None,
            });
            return self.send(&reply);
        };
        if fault.delay_ms > 0 && !self.sleep(Duration::from_millis(fault.delay_ms)) {
            return Next::Close;
        }
        let (reply, note) = self.apply(&fault, &req);
        self.record(Entry {
            raw,
            request: Some(req),
            reply: reply.as_ref().map(Reply::text),
            note: Some(note),
        });
        match reply {
            Some(r) => self.send(&r),
            None => Next::Close,
        }
    }

    /// The fault this request triggers, counting it among its command's occurrences.
    fn fault_for(&self, req: &Request) -> Option<Fault> {
        // Only catalog commands are counted (faults can only name those), so a client cycling
        // through arbitrary numbers cannot grow the map.
        let occurrence = if catalog()
            .command_in(self.shared.interface, req.command)
            .is_some()
        {
            let mut occurrences = lock(&self.shared.occurrences);
            let count = occurrences.entry(req.command).or_insert(0);
            *count = count.saturating_add(1);
            *count
        } else {
            0
        };
        lock(&self.shared.state)
            .scenario()
            .faults
            .iter()
            .find(|f| f.matches(req.command, occurrence))
            .cloned()
    }

    /// The reply (None = drop the connection) and a description of an injected fault.
    fn apply(&self, fault: &Fault, req: &Request) -> (Option<Reply>, String) {
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
        let echo = i64::from(req.command);
        if let Some(status) = fault.status {
            let reply = Reply::new(echo, 0).int(i64::from(status));
            return (Some(reply), join(format!("fault: forced status {status}")));
        }
        if let Some(g) = &fault.garbage {
            let reply = Reply::garbage(echo, g);
            return (Some(reply), join("fault: garbage reply".into()));
        }
        let reply = lock(&self.shared.state).handle(req);
        if let Some(wrong) = fault.wrong_echo {
            let reply = reply.with_echo(wrong);
            return (Some(reply), join(format!("fault: wrong echo {wrong}")));
        }
        (Some(reply), join(String::new()))
    }

    /// Sleep in small steps; false when the server is stopping.
    fn sleep(&self, total: Duration) -> bool {
        let until = Instant::now() + total;
        while Instant::now() < until {
            if self.shared.stopping() {
                return false;
            }
            thread::sleep(POLL.min(until.saturating_duration_since(Instant::now())));
        }
        true
    }

    fn send(&mut self, reply: &Reply) -> Next {
        let bytes = self.codec.encode(reply);
        match self
            .stream
            .write_all(&bytes)
            .and_then(|()| self.stream.flush())
        {
            Ok(()) => Next::Continue,
            Err(_) => Next::Close,
        }
    }
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
