//! EthernetKRL emulation: channels configured by EKI XML, client connections over real TCP,
//! RAW STREAM/BYTE records, the ALIVE and receive flags, and the EKI_* functions.
//!
//! `EKI_Send` on a RAW STREAM element sends the CHAR array up to its first NUL (or the given
//! length) plus the end string; on a RAW BYTE element it sends the given length, else the
//! element's `Size` bytes of the array, zero-padded [U].
//!
//! Assumed `Msg_No` values (the manual's numbering is not verified, see reference Part 3.3):
//! 0 OK, 2 channel not initialised, 9 connection not available (refused, lost, not open),
//! 23 initialisation already performed, 512 connection destroyed while sending.

use std::collections::{HashMap, VecDeque};
use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::time::Duration;

use crate::eki::{
    Channel as ChannelConfig, Element as RawElement, External, Framing, Kind as RawKind,
};
use crate::syntax::ast::Expr;

use super::globals::Globals;
use super::machine::{Machine, R};
use super::value::Value;

pub const MSG_NOT_INIT: i64 = 2;
pub const MSG_NO_CONNECTION: i64 = 9;
pub const MSG_ALREADY_INIT: i64 = 23;
pub const MSG_DESTROYED: i64 = 512;

#[derive(Debug)]
struct Channel {
    cfg: ChannelConfig,
    stream: Option<TcpStream>,
    rx: Vec<u8>,
    records: HashMap<String, VecDeque<Vec<u8>>>,
    counter: i64,
}

#[derive(Debug, Default)]
pub(crate) struct Eki {
    channels: HashMap<String, Channel>,
    pub(crate) stats: super::EkiStats,
    /// Flags and outputs [`Eki::pump`] changed, for the trace: `(array, 1-based index, value)`.
    pub(crate) io_changes: Vec<(&'static str, usize, bool)>,
    /// A reply in the other framing than the channel's (see [`Framing::foreign`]): the run
    /// stops with this message at once instead of waiting for a record that never completes.
    pub(crate) mismatch: Option<String>,
}

impl Eki {
    pub(crate) fn any_connected(&self) -> bool {
        self.channels.values().any(|c| c.stream.is_some())
    }

    /// Whether a connected channel sets `var[n]` (`$FLAG` or `$OUT`, 1-based; `None`: any):
    /// its alive flag or output (dropped when the peer goes away) or a receive element's.
    pub(crate) fn sets(&self, var: &str, n: Option<usize>) -> bool {
        self.channels
            .values()
            .filter(|c| c.stream.is_some())
            .flat_map(|c| {
                let flag = var == "$FLAG";
                let alive = if flag {
                    c.cfg.alive_flag
                } else {
                    c.cfg.alive_out
                };
                let elements = c
                    .cfg
                    .receive
                    .iter()
                    .map(move |e| if flag { e.set_flag } else { e.set_out });
                std::iter::once(alive).chain(elements)
            })
            .flatten()
            .any(|m| n.is_none_or(|n| n == m as usize))
    }

    pub(crate) fn close_all(&mut self) {
        for c in self.channels.values_mut() {
            c.stream = None;
        }
    }

    /// Read what has arrived (waiting up to `wait` for the first bytes), split it into records,
    /// and set the configured flags.
    pub(crate) fn pump(&mut self, globals: &mut Globals, wait: Duration) {
        let mut waited = false;
        for (name, c) in &mut self.channels {
            let Some(s) = &mut c.stream else { continue };
            let mut buf = [0u8; 8192];
            let mut closed = false;
            loop {
                let blocking = !waited && !wait.is_zero();
                let _ = if blocking {
                    s.set_nonblocking(false)
                        .and_then(|_| s.set_read_timeout(Some(wait)))
                } else {
                    s.set_nonblocking(true)
                };
                waited |= blocking;
                match s.read(&mut buf) {
                    Ok(0) => {
                        closed = true;
                        break;
                    }
                    Ok(n) => c.rx.extend_from_slice(&buf[..n]),
                    Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                        break;
                    }
                    Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                    Err(_) => {
                        closed = true;
                        break;
                    }
                }
            }
            if let Some(f) = c.foreign() {
                self.mismatch
                    .get_or_insert_with(|| mismatch(name, f, &c.rx));
                c.rx.clear();
            }
            let changes = &mut self.io_changes;
            c.split_records(globals, changes);
            if closed {
                c.stream = None;
                set_flag(globals, changes, "$FLAG", c.cfg.alive_flag, false);
                set_flag(globals, changes, "$OUT", c.cfg.alive_out, false);
            }
        }
    }
}

impl Channel {
    /// The channel's framing, when the record arriving is in the other one.
    fn foreign(&self) -> Option<Framing> {
        let el = self.cfg.receive.first()?;
        let f = match el.kind {
            RawKind::Stream { .. } => Framing::Stream,
            RawKind::Byte => Framing::Byte { size: el.size },
        };
        f.foreign(&self.rx).then_some(f)
    }

    fn split_records(
        &mut self,
        globals: &mut Globals,
        changes: &mut Vec<(&'static str, usize, bool)>,
    ) {
        let Some(el) = self.cfg.receive.first().cloned() else {
            self.rx.clear();
            return;
        };
        let size = el.size as usize;
        loop {
            let cut = match &el.kind {
                RawKind::Byte => (self.rx.len() >= size).then_some((size, size)),
                RawKind::Stream { eos } => eos
                    .0
                    .iter()
                    .filter(|e| !e.is_empty())
                    .filter_map(|e| {
                        self.rx
                            .windows(e.len())
                            .position(|w| w == e.as_slice())
                            .map(|p| (p, p + e.len()))
                    })
                    .min(),
            };
            let Some((data_end, consumed)) = cut else {
                break;
            };
            let mut record: Vec<u8> = self.rx.drain(..consumed).collect();
            record.truncate(data_end.min(size));
            self.records
                .entry(el.tag.to_ascii_uppercase())
                .or_default()
                .push_back(record);
            set_flag(globals, changes, "$FLAG", el.set_flag, true);
            set_flag(globals, changes, "$OUT", el.set_out, true);
        }
    }
}

/// What a run against a server of the other codec is told, with the first bytes it answered:
/// the spec `codec` that matches the server, or the server setting that matches the package.
fn mismatch(channel: &str, package: Framing, rx: &[u8]) -> String {
    let (server, records, spec_codec, serve_codec) = match package {
        Framing::Stream => (
            format!("HEX (binary 4-byte fields: {})", crate::eki::dump(rx, 8)),
            "RAW STREAM records ending in CR".to_owned(),
            "hex-le",
            "ascii",
        ),
        Framing::Byte { size } => {
            let text = String::from_utf8_lossy(&rx[..rx.len().min(16)]).into_owned();
            (
                format!("ASCII ({:?})", text.trim_end()),
                format!("RAW BYTE records of {size} bytes"),
                "ascii",
                "hex-le",
            )
        }
    };
    let speaks = package.codec();
    format!(
        "the vision server answers in {server}; this package speaks {speaks}: its channel `{channel}` has {records}; set `codec = \"{spec_codec}\"` in the spec and regenerate the package, or switch the server to {speaks} (Mech-Vision's Robot Communication Configuration; `krlkit sim serve --codec {serve_codec}`)"
    )
}

/// A flag or output number of the channel file as an index.
fn wide(n: Option<u32>) -> Option<usize> {
    n.map(|n| n as usize)
}

fn set_flag(
    globals: &mut Globals,
    changes: &mut Vec<(&'static str, usize, bool)>,
    var: &'static str,
    n: Option<u32>,
    v: bool,
) {
    if let Some(n) = wide(n)
        && let Some(Value::Array { items, .. }) = globals.get_mut(var)
        && let Some(slot) = n.checked_sub(1).and_then(|i| items.get_mut(i))
    {
        if *slot != Value::Bool(v) {
            changes.push((var, n, v));
        }
        *slot = Value::Bool(v);
    }
}

fn status(buff: usize, read: usize, msg: i64, connected: bool, counter: i64) -> Value {
    Value::Struc {
        ty: "EKI_STATUS".into(),
        fields: vec![
            ("Buff".into(), Value::Int(buff as i64)),
            ("Read".into(), Value::Int(read as i64)),
            ("Msg_No".into(), Value::Int(msg)),
            ("Connected".into(), Value::Bool(connected)),
            ("Counter".into(), Value::Int(counter)),
        ],
    }
}

fn load_config(m: &Machine, name: &str) -> R<ChannelConfig> {
    let key = name.to_ascii_uppercase();
    let text = match m.opts.eki_configs.get(&key) {
        Some(t) => t.clone(),
        None => {
            let found = m.opts.eki_dirs.iter().find_map(|d| {
                std::fs::read_dir(d).ok()?.flatten().find_map(|e| {
                    let p = e.path();
                    let stem = p.file_stem()?.to_str()?.to_ascii_uppercase();
                    let xml = p.extension()?.to_str()?.eq_ignore_ascii_case("xml");
                    (xml && stem == key)
                        .then(|| std::fs::read_to_string(&p).ok())
                        .flatten()
                })
            });
            found.ok_or_else(|| {
                m.err(format!(
                    "EKI_Init: no EKI configuration `{name}.xml` (looked in {})",
                    m.opts
                        .eki_dirs
                        .iter()
                        .map(|d| d.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })?
        }
    };
    let cfg = crate::eki::read(&text).map_err(|e| m.err(format!("{name}.xml: {e}")))?;
    if cfg.xml_mode {
        return Err(m.err(format!(
            "{name}.xml: XML-mode EKI channels are not supported by krlkit run (RAW only)"
        )));
    }
    Ok(cfg)
}

fn m_err_never() -> super::machine::Stop {
    super::machine::Stop::from(super::RuntimeError {
        file: String::new(),
        line: 0,
        message: "EKI channel vanished".into(),
    })
}

fn resolve(addr: &str) -> Option<SocketAddr> {
    addr.to_socket_addrs().ok()?.next()
}

/// Run `EKI_*` function `up` (upper-case name).
pub(crate) fn call(m: &mut Machine, up: &str, args: &[Option<Expr>]) -> R<Value> {
    let name = m
        .arg_value(args, 0, up)?
        .as_text()
        .ok_or_else(|| m.err(format!("{up}: the channel name must be a string")))?;
    let key = name.to_ascii_uppercase();
    let tag_arg = |m: &mut Machine| -> R<String> {
        m.arg_value(args, 1, up)?
            .as_text()
            .map(|t| t.to_ascii_uppercase())
            .ok_or_else(|| m.err(format!("{up}: the tag must be a string")))
    };
    let not_init = |m: &Machine| {
        let connected = m.eki.channels.get(&key).is_some_and(|c| c.stream.is_some());
        status(0, 0, MSG_NOT_INIT, connected, 0)
    };
    match up {
        "EKI_INIT" => {
            if m.eki.channels.contains_key(&key) {
                return Ok(status(0, 0, MSG_ALREADY_INIT, false, 0));
            }
            let cfg = load_config(m, &name)?;
            m.eki.channels.insert(
                key,
                Channel {
                    cfg,
                    stream: None,
                    rx: Vec::new(),
                    records: HashMap::new(),
                    counter: 0,
                },
            );
            Ok(status(0, 0, 0, false, 0))
        }
        "EKI_OPEN" => {
            let vision = m.opts.vision.clone();
            let Some(c) = m.eki.channels.get(&key) else {
                return Ok(not_init(m));
            };
            if c.stream.is_some() {
                return Ok(status(0, 0, 0, true, c.counter));
            }
            if c.cfg.external != External::Server {
                return Err(m.err("EKI_Open: only channels whose EXTERNAL TYPE is Server (robot = client) are supported"));
            }
            let addr_text = vision.unwrap_or_else(|| format!("{}:{}", c.cfg.ip, c.cfg.port.unwrap_or(0)));
            let timeout = Duration::from_millis(u64::from(c.cfg.connect_timeout_ms.clamp(1, 2000)));
            let stream = resolve(&addr_text).and_then(|a| TcpStream::connect_timeout(&a, timeout).ok());
            let c = m.eki.channels.get_mut(&key).ok_or_else(m_err_never)?;
            match stream {
                Some(s) => {
                    let _ = s.set_nodelay(true);
                    c.stream = Some(s);
                    let (af, ao) = (wide(c.cfg.alive_flag), wide(c.cfg.alive_out));
                    m.eki.stats.connections += 1;
                    m.set_io("$FLAG", af, true);
                    m.set_io("$OUT", ao, true);
                    Ok(status(0, 0, 0, true, 0))
                }
                None => {
                    m.eki.stats.failed_connects += 1;
                    m.eki.stats.failed_addr = Some(addr_text.clone());
                    m.message(format!("EKI: connection to {addr_text} not available (channel {name})"));
                    Ok(status(0, 0, MSG_NO_CONNECTION, false, 0))
                }
            }
        }
        "EKI_SEND" => {
            let data = m.arg_value(args, 1, up)?;
            let len = match args.get(2).and_then(|a| a.as_ref()) {
                Some(e) => Some(m.eval_int(e)?.max(0) as usize),
                None => None,
            };
            // A RAW BYTE element sends its fixed record: `Size` bytes of the array [U].
            let byte_size = m.eki.channels.get(&key).and_then(|c| {
                match c.cfg.send.first().or(c.cfg.receive.first()) {
                    Some(RawElement {
                        kind: RawKind::Byte,
                        size,
                        ..
                    }) => Some(*size as usize),
                    _ => None,
                }
            });
            let mut bytes: Vec<u8> = match (&data, len.or(byte_size)) {
                (Value::Array { items, .. }, Some(n)) => {
                    let mut b: Vec<u8> = items
                        .iter()
                        .take(n)
                        .map(|v| if let Value::Char(c) = v { *c } else { 0 })
                        .collect();
                    if len.is_none() {
                        b.resize(n, 0);
                    }
                    b
                }
                _ => data
                    .as_text()
                    .ok_or_else(|| m.err("EKI_Send: data must be a CHAR array"))?
                    .bytes()
                    .collect(),
            };
            let Some(c) = m.eki.channels.get_mut(&key) else {
                return Ok(not_init(m));
            };
            let el = c.cfg.send.first().or(c.cfg.receive.first());
            if let Some(RawElement {
                kind: RawKind::Stream { eos },
                ..
            }) = el
                && let Some(first) = eos.0.first()
            {
                bytes.extend_from_slice(first);
            }
            let counter = c.counter;
            let Some(s) = &mut c.stream else {
                return Ok(status(0, 0, MSG_NO_CONNECTION, false, counter));
            };
            let _ = s.set_nonblocking(false);
            let _ = s.set_write_timeout(Some(Duration::from_secs(2)));
            match s.write_all(&bytes) {
                Ok(()) => {
                    m.eki.stats.sends += 1;
                    Ok(status(0, 0, 0, true, counter))
                }
                Err(_) => {
                    c.stream = None;
                    let af = wide(c.cfg.alive_flag);
                    m.set_io("$FLAG", af, false);
                    Ok(status(0, 0, MSG_DESTROYED, false, counter))
                }
            }
        }
        "EKI_GETSTRING" => {
            let tag = tag_arg(m)?;
            let target = m.arg_place(args, 2, up)?;
            let mut g = std::mem::take(m.globals_mut());
            m.eki.pump(&mut g, Duration::ZERO);
            *m.globals_mut() = g;
            let Some(c) = m.eki.channels.get_mut(&key) else {
                return Ok(not_init(m));
            };
            let connected = c.stream.is_some();
            let q = c.records.entry(tag).or_default();
            match q.pop_front() {
                Some(rec) => {
                    c.counter += 1;
                    let (buff, counter) = (q.len(), c.counter);
                    let cur = m.read_value(&target)?;
                    let len = match &cur {
                        Value::Array { items, .. } => items.len(),
                        v => return Err(m.err(format!("EKI_GetString: target must be a CHAR array, found {}", v.kind_name()))),
                    };
                    m.assign(&target, Value::char_array(&rec, len))?;
                    Ok(status(buff, 1, 0, connected, counter))
                }
                None => {
                    let counter = c.counter;
                    Ok(status(0, 0, 0, connected, counter))
                }
            }
        }
        "EKI_CHECKBUFFER" => {
            let tag = tag_arg(m)?;
            let mut g = std::mem::take(m.globals_mut());
            m.eki.pump(&mut g, Duration::ZERO);
            *m.globals_mut() = g;
            let Some(c) = m.eki.channels.get(&key) else {
                return Ok(not_init(m));
            };
            let n = c.records.get(&tag).map(|q| q.len()).unwrap_or(0);
            Ok(status(n, 0, 0, c.stream.is_some(), c.counter))
        }
        "EKI_CLEARBUFFER" => {
            let tag = tag_arg(m)?;
            let Some(c) = m.eki.channels.get_mut(&key) else {
                return Ok(not_init(m));
            };
            if c.records.contains_key(&tag) {
                c.records.remove(&tag);
            } else {
                c.records.clear();
            }
            c.rx.clear();
            Ok(status(0, 0, 0, c.stream.is_some(), c.counter))
        }
        "EKI_CLOSE" | "EKI_CLEAR" => {
            let Some(c) = m.eki.channels.get_mut(&key) else {
                return Ok(not_init(m));
            };
            c.stream = None;
            let (af, ao) = (wide(c.cfg.alive_flag), wide(c.cfg.alive_out));
            if up == "EKI_CLEAR" {
                m.eki.channels.remove(&key);
            }
            m.set_io("$FLAG", af, false);
            m.set_io("$OUT", ao, false);
            Ok(status(0, 0, 0, false, 0))
        }
        "EKI_LOCK" | "EKI_UNLOCK" => {
            let Some(c) = m.eki.channels.get(&key) else {
                return Ok(not_init(m));
            };
            Ok(status(0, 0, 0, c.stream.is_some(), c.counter))
        }
        other => Err(m.err(format!(
            "{other} is not supported by krlkit run (RAW channels: EKI_Init/Open/Send/GetString/CheckBuffer/ClearBuffer/Close/Clear)"
        ))),
    }
}
