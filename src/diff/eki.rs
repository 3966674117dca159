//! The settings of an EKI channel file as `path = value` lines, read by the one EKI reader
//! ([`crate::eki::read`]), so two channel files compare setting by setting.

/// `(setting, value)` pairs in file order; an unreadable file is one `error` setting.
pub fn settings(xml: &str) -> Vec<(String, String)> {
    let cfg = match crate::eki::read::parse_config(xml) {
        Ok(c) => c,
        Err(e) => return vec![("error".into(), e)],
    };
    let opt = |v: Option<usize>| v.map_or_else(|| "-".to_owned(), |v| v.to_string());
    let mut out = vec![
        ("EXTERNAL/TYPE".to_owned(), cfg.external_type.clone()),
        ("EXTERNAL/IP".to_owned(), cfg.ip.clone()),
        ("EXTERNAL/PORT".to_owned(), cfg.port.to_string()),
        (
            "EXTERNAL/TIMEOUT".to_owned(),
            cfg.connect_timeout_ms.to_string(),
        ),
        ("INTERNAL/ALIVE/Set_Flag".to_owned(), opt(cfg.alive_flag)),
        ("INTERNAL/ALIVE/Set_Out".to_owned(), opt(cfg.alive_out)),
        ("XML mode".to_owned(), cfg.xml_mode.to_string()),
    ];
    for (section, elements) in [("RECEIVE", &cfg.receive), ("SEND", &cfg.send)] {
        for e in elements {
            let at = format!("{section}/ELEMENT[{}]", e.tag);
            let kind = match &e.kind {
                crate::eki::read::RawKind::Stream { eos } => format!("STREAM EOS {eos:?}"),
                crate::eki::read::RawKind::Byte => "BYTE".to_owned(),
            };
            out.push((format!("{at}/Type"), kind));
            out.push((format!("{at}/Size"), e.size.to_string()));
            out.push((format!("{at}/Set_Flag"), opt(e.set_flag)));
            out.push((format!("{at}/Set_Out"), opt(e.set_out)));
        }
    }
    out
}
