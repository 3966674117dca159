//! Reading an EKI channel file the way the interpreter's EthernetKRL emulation uses it: the
//! external address and type, the connect timeout, the ALIVE flag/output, the RAW elements
//! (STREAM end strings, BYTE sizes), and whether RECEIVE/SEND use XML mode. Element and
//! attribute names are read case-insensitively (KUKA's examples vary, see the EKI reference
//! §3.2).

use std::collections::HashMap;

use quick_xml::Reader;
use quick_xml::events::Event as X;

#[derive(Debug, Clone, PartialEq)]
pub enum RawKind {
    Stream { eos: Vec<Vec<u8>> },
    Byte,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawElement {
    pub tag: String,
    pub kind: RawKind,
    pub size: usize,
    pub set_flag: Option<usize>,
    pub set_out: Option<usize>,
}

/// The parts of an EKI XML file the emulation uses.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChannelConfig {
    pub external_type: String,
    pub ip: String,
    pub port: u16,
    pub connect_timeout_ms: u64,
    pub alive_flag: Option<usize>,
    pub alive_out: Option<usize>,
    pub receive: Vec<RawElement>,
    pub send: Vec<RawElement>,
    /// True when RECEIVE/SEND use `<XML>` (not supported here).
    pub xml_mode: bool,
}

fn parse_eos(s: &str) -> Result<Vec<Vec<u8>>, String> {
    s.split('|')
        .map(|alt| {
            alt.split(',')
                .map(|n| {
                    n.trim()
                        .parse::<u8>()
                        .map_err(|_| format!("bad EOS value `{s}`"))
                })
                .collect()
        })
        .collect()
}

/// Read an EKI configuration (element and attribute names case-insensitive).
pub fn parse_config(xml: &str) -> Result<ChannelConfig, String> {
    let mut r = Reader::from_str(xml);
    r.config_mut().trim_text(true);
    let mut cfg = ChannelConfig {
        connect_timeout_ms: 2000,
        external_type: "Server".into(),
        ..Default::default()
    };
    let mut stack: Vec<String> = Vec::new();
    loop {
        let ev = r.read_event().map_err(|e| format!("EKI XML: {e}"))?;
        let empty = matches!(ev, X::Empty(_));
        match ev {
            X::Start(e) | X::Empty(e) => {
                let name = e.name().into_inner().to_ascii_uppercase();
                let mut attrs = HashMap::new();
                for a in e.attributes().flatten() {
                    let k = a.key.into_inner().to_ascii_uppercase();
                    #[allow(deprecated)]
                    let v = a
                        .unescape_value()
                        .map(|v| v.into_owned())
                        .unwrap_or_default();
                    attrs.insert(k, v);
                }
                let num = |k: &str| attrs.get(k).and_then(|v| v.trim().parse::<usize>().ok());
                let path = stack.join("/");
                match name.as_str() {
                    "ALIVE" => {
                        cfg.alive_flag = num("SET_FLAG");
                        cfg.alive_out = num("SET_OUT");
                    }
                    "TIMEOUT" => {
                        if let Some(t) = num("CONNECT") {
                            cfg.connect_timeout_ms = t as u64;
                        }
                    }
                    "XML" if path.contains("RECEIVE") || path.contains("SEND") => {
                        cfg.xml_mode = true
                    }
                    "ELEMENT" if path.ends_with("RAW") => {
                        let tag = attrs.get("TAG").cloned().unwrap_or_default();
                        let ty = attrs
                            .get("TYPE")
                            .map(|t| t.to_ascii_uppercase())
                            .unwrap_or_default();
                        let kind = if ty == "BYTE" {
                            RawKind::Byte
                        } else {
                            RawKind::Stream {
                                eos: match attrs.get("EOS") {
                                    Some(s) => parse_eos(s)?,
                                    None => vec![],
                                },
                            }
                        };
                        let el = RawElement {
                            tag,
                            kind,
                            size: num("SIZE").unwrap_or(3600),
                            set_flag: num("SET_FLAG"),
                            set_out: num("SET_OUT"),
                        };
                        if path.contains("RECEIVE") {
                            cfg.receive.push(el);
                        } else {
                            cfg.send.push(el);
                        }
                    }
                    _ => {}
                }
                if !empty {
                    stack.push(name);
                }
            }
            X::Text(t) => {
                let raw: &str = t.as_ref();
                let text = raw.trim().to_string();
                let path = stack.join("/");
                if path.ends_with("EXTERNAL/IP") {
                    cfg.ip = text;
                } else if path.ends_with("EXTERNAL/PORT") {
                    cfg.port = text
                        .parse()
                        .map_err(|_| format!("EKI XML: bad PORT `{text}`"))?;
                } else if path.ends_with("EXTERNAL/TYPE") {
                    cfg.external_type = text;
                }
            }
            X::End(_) => {
                stack.pop();
            }
            X::Eof => break,
            _ => {}
        }
    }
    Ok(cfg)
}
