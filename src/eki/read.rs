//! The one EKI channel-file reader: `check` (lint's channels), `transpile` (the vision server's
//! address) and `run` (the EthernetKRL emulation) all read a file through [`read`], so a file
//! one of them rejects, all reject, with the same message.
//!
//! What EthernetKRL accepts (EKI reference Part 3.2; ranges from the catalog's `[limits]`):
//! - the root element is `ETHERNETKRL`; otherwise the file is not an EKI config ([`ReadError::NotEki`]);
//! - element and attribute names are read case-insensitively (KUKA's own examples vary);
//! - `CONFIGURATION/EXTERNAL/TYPE` is Server or Client (default Server), `IP` is text, `PORT` a
//!   number 1 … 65534; `CONFIGURATION/INTERNAL/ALIVE` carries `Set_Flag`/`Set_Out`,
//!   `CONFIGURATION/INTERNAL/TIMEOUT@Connect` is 0 … 65534 ms; elements of those names anywhere
//!   else mean nothing to EKI and are ignored;
//! - `RECEIVE/RAW/ELEMENT` and `SEND/RAW/ELEMENT` need a `Tag` and a `Type` of BYTE or STREAM,
//!   `Size` 1 … 3600 (3600 when absent [U]), a STREAM an `EOS` of one or two `|`-joined end
//!   strings of 1 to 32 comma-separated byte values; BYTE and STREAM are not mixed on one
//!   channel; `RECEIVE/XML` or `SEND/XML` sets [`Channel::xml_mode`];
//! - flags are `$FLAG` numbers, outputs `$OUT` numbers, in the catalog's ranges;
//! - a malformed document, an element left open, or a number that is not one is an error, never
//!   ignored.

use std::fmt;

use quick_xml::Reader;
use quick_xml::events::{BytesStart, Event};

use super::{Channel, Element, Eos, External, Kind};
use crate::catalog::catalog;

/// Why a file is not a channel EKI would load.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReadError {
    /// No `<ETHERNETKRL>` root element: some other XML file (or not XML at all).
    NotEki,
    /// An EthernetKRL config EKI would reject.
    Invalid(String),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::NotEki => {
                f.write_str("not an EthernetKRL config (no <ETHERNETKRL> root element)")
            }
            ReadError::Invalid(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for ReadError {}

fn invalid(message: impl Into<String>) -> ReadError {
    ReadError::Invalid(message.into())
}

/// Read an EKI channel file.
pub fn read(xml: &str) -> Result<Channel, ReadError> {
    let mut r = Reader::from_str(xml);
    r.config_mut().trim_text(true);
    let mut ch = Channel::default();
    let mut stack: Vec<String> = Vec::new();
    let mut rooted = false;
    loop {
        let ev = match r.read_event() {
            Ok(ev) => ev,
            Err(_) if !rooted => return Err(ReadError::NotEki),
            Err(e) => return Err(invalid(format!("malformed XML: {e}"))),
        };
        match ev {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let name = e.name().into_inner().to_ascii_uppercase();
                if stack.is_empty() {
                    if rooted {
                        return Err(invalid(format!("a second root element <{name}>")));
                    }
                    if name != "ETHERNETKRL" {
                        return Err(ReadError::NotEki);
                    }
                    rooted = true;
                }
                let path: Vec<&str> = stack.iter().map(String::as_str).collect();
                element(&mut ch, &name, &path, &Attrs::of(e)?)?;
                if matches!(ev, Event::Start(_)) {
                    stack.push(name);
                }
            }
            Event::Text(t) => {
                let raw: &str = t.as_ref();
                text(&mut ch, &stack, raw.trim())?;
            }
            Event::End(_) => {
                stack.pop();
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if !rooted {
        return Err(ReadError::NotEki);
    }
    if let Some(open) = stack.last() {
        return Err(invalid(format!("malformed XML: <{open}> is not closed")));
    }
    let mut kinds = ch.receive.iter().chain(&ch.send).map(|e| &e.kind);
    if let Some(first) = kinds.next()
        && kinds.any(|k| std::mem::discriminant(k) != std::mem::discriminant(first))
    {
        return Err(invalid(
            "RAW elements mix Type BYTE and STREAM (EKI takes one binary kind per channel)",
        ));
    }
    Ok(ch)
}

fn element(ch: &mut Channel, name: &str, path: &[&str], a: &Attrs) -> Result<(), ReadError> {
    let lim = &catalog().limits;
    let flag = |key: &str, what: &str| {
        let (lo, hi) = (lim.flag_min.max(0) as u32, lim.flag_max.max(0) as u32);
        a.number(key, what, lo, hi)
    };
    let out = |key: &str, what: &str| a.number(key, what, 1, lim.out_max);
    match (name, path) {
        ("ALIVE", ["ETHERNETKRL", "CONFIGURATION", "INTERNAL"]) => {
            ch.alive_flag = flag("SET_FLAG", "ALIVE Set_Flag")?;
            ch.alive_out = out("SET_OUT", "ALIVE Set_Out")?;
        }
        ("TIMEOUT", ["ETHERNETKRL", "CONFIGURATION", "INTERNAL"]) => {
            let max = lim.eki_connect_ms_max;
            if let Some(t) = a.number("CONNECT", "TIMEOUT Connect", 0, max)? {
                ch.connect_timeout_ms = t;
            }
        }
        ("XML", ["ETHERNETKRL", "RECEIVE" | "SEND"]) => ch.xml_mode = true,
        ("ELEMENT", ["ETHERNETKRL", section @ ("RECEIVE" | "SEND"), "RAW"]) => {
            let tag = a.get("TAG").unwrap_or_default().to_owned();
            if tag.is_empty() {
                return Err(invalid(format!("a {section} RAW element without Tag")));
            }
            let what = |attr: &str| format!("RAW element `{tag}` {attr}");
            let kind = match a.get("TYPE").map(str::to_ascii_uppercase).as_deref() {
                Some("BYTE") => Kind::Byte,
                Some("STREAM") => match a.get("EOS") {
                    Some(eos) => Kind::Stream {
                        eos: parse_eos(eos).ok_or_else(|| {
                            invalid(format!(
                                "{} `{eos}` is not one or two `|`-joined lists of 1 to 32 \
                                 comma-separated byte values",
                                what("EOS")
                            ))
                        })?,
                    },
                    None => {
                        return Err(invalid(format!(
                            "{} STREAM needs an EOS (its end string)",
                            what("Type")
                        )));
                    }
                },
                Some(other) => {
                    return Err(invalid(format!(
                        "{} `{other}` is neither BYTE nor STREAM",
                        what("Type")
                    )));
                }
                None => {
                    return Err(invalid(format!(
                        "RAW element `{tag}` has no Type (BYTE or STREAM)"
                    )));
                }
            };
            let max = lim.eki_raw_size_max;
            let el = Element {
                size: a.number("SIZE", &what("Size"), 1, max)?.unwrap_or(max),
                set_flag: flag("SET_FLAG", &what("Set_Flag"))?,
                set_out: out("SET_OUT", &what("Set_Out"))?,
                tag,
                kind,
            };
            if *section == "RECEIVE" {
                ch.receive.push(el);
            } else {
                ch.send.push(el);
            }
        }
        _ => {}
    }
    Ok(())
}

fn text(ch: &mut Channel, stack: &[String], text: &str) -> Result<(), ReadError> {
    let path: Vec<&str> = stack.iter().map(String::as_str).collect();
    let ["ETHERNETKRL", "CONFIGURATION", "EXTERNAL", field] = path.as_slice() else {
        return Ok(());
    };
    match *field {
        "IP" => ch.ip = text.to_owned(),
        "PORT" => {
            let max = catalog().limits.eki_port_max;
            ch.port = Some(
                text.parse::<u16>()
                    .ok()
                    .filter(|p| (1..=max).contains(&u32::from(*p)))
                    .ok_or_else(|| {
                        invalid(format!("EXTERNAL PORT `{text}` is not a number 1 … {max}"))
                    })?,
            );
        }
        "TYPE" => {
            ch.external = if text.eq_ignore_ascii_case("Server") {
                External::Server
            } else if text.eq_ignore_ascii_case("Client") {
                External::Client
            } else {
                return Err(invalid(format!(
                    "EXTERNAL TYPE `{text}` is neither Server nor Client"
                )));
            }
        }
        _ => {}
    }
    Ok(())
}

fn parse_eos(s: &str) -> Option<Eos> {
    let alts: Option<Vec<Vec<u8>>> = s
        .split('|')
        .map(|alt| {
            let bytes: Option<Vec<u8>> = alt.split(',').map(|n| n.trim().parse().ok()).collect();
            bytes.filter(|b| (1..=32).contains(&b.len()))
        })
        .collect();
    alts.filter(|a| a.len() <= 2).map(Eos)
}

/// An element's attributes, names upper-cased.
struct Attrs(Vec<(String, String)>);

impl Attrs {
    fn of(e: &BytesStart) -> Result<Attrs, ReadError> {
        let mut out = Vec::new();
        for a in e.attributes() {
            let a = a.map_err(|e| invalid(format!("malformed XML: {e}")))?;
            let key = a.key.into_inner().to_ascii_uppercase();
            #[allow(deprecated)]
            let value = a
                .unescape_value()
                .map(|v| v.into_owned())
                .unwrap_or_default();
            out.push((key, value));
        }
        Ok(Attrs(out))
    }

    fn get(&self, key: &str) -> Option<&str> {
        self.0
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// `key` as a number in `lo ..= hi`; `None` when absent, an error when it is not one.
    fn number(&self, key: &str, what: &str, lo: u32, hi: u32) -> Result<Option<u32>, ReadError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (lo..=hi).contains(n))
            .map(Some)
            .ok_or_else(|| invalid(format!("{what} `{v}` is not a number {lo} … {hi}")))
    }
}
