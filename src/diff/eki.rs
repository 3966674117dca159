//! The settings of an EKI channel file as `path = value` lines, read by the one EKI reader
//! ([`crate::eki::read`]), so two channel files compare setting by setting.

use crate::eki::{External, Kind};

/// `(setting, value)` pairs in file order; a file EKI would reject is one `error` setting.
pub fn settings(xml: &str) -> Vec<(String, String)> {
    let ch = match crate::eki::read(xml) {
        Ok(c) => c,
        Err(e) => return vec![("error".into(), e.to_string())],
    };
    let opt = |v: Option<u32>| v.map_or_else(|| "-".to_owned(), |v| v.to_string());
    let external = match ch.external {
        External::Server => "Server",
        External::Client => "Client",
    };
    let mut out = vec![
        ("EXTERNAL/TYPE".to_owned(), external.to_owned()),
        ("EXTERNAL/IP".to_owned(), ch.ip.clone()),
        ("EXTERNAL/PORT".to_owned(), opt(ch.port.map(u32::from))),
        (
            "INTERNAL/TIMEOUT/Connect".to_owned(),
            ch.connect_timeout_ms.to_string(),
        ),
        ("INTERNAL/ALIVE/Set_Flag".to_owned(), opt(ch.alive_flag)),
        ("INTERNAL/ALIVE/Set_Out".to_owned(), opt(ch.alive_out)),
        ("XML mode".to_owned(), ch.xml_mode.to_string()),
    ];
    for (section, elements) in [("RECEIVE", &ch.receive), ("SEND", &ch.send)] {
        for e in elements {
            let at = format!("{section}/ELEMENT[{}]", e.tag);
            let kind = match &e.kind {
                Kind::Stream { eos } => format!("STREAM, EOS {eos}"),
                Kind::Byte => "BYTE".to_owned(),
            };
            out.push((format!("{at}/Type"), kind));
            out.push((format!("{at}/Size"), e.size.to_string()));
            out.push((format!("{at}/Set_Flag"), opt(e.set_flag)));
            out.push((format!("{at}/Set_Out"), opt(e.set_out)));
        }
    }
    out
}
