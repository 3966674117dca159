//! Just enough of an EthernetKRL XML config for the cross-check and the transpiler: the channel
//! name (file stem), the alive flag (`CONFIGURATION/INTERNAL/ALIVE@Set_Flag`), the receive flag
//! (`RECEIVE/RAW/ELEMENT@Set_Flag`) and the server address (`CONFIGURATION/EXTERNAL/IP`, `PORT`).

use quick_xml::events::Event;

/// One EKI channel as the lint needs it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EkiChannel {
    /// File stem, case preserved (EKI channel names are case-sensitive).
    pub name: String,
    pub path: String,
    pub alive_flag: Option<i64>,
    pub receive_flag: Option<i64>,
    /// `CONFIGURATION/EXTERNAL/IP`, trimmed.
    pub ip: Option<String>,
    /// `CONFIGURATION/EXTERNAL/PORT`, when it is a number.
    pub port: Option<u16>,
}

/// EKI configs among `paths` (XML files named or found by walking, see
/// [`crate::files::walk_xml`]); files that cannot be read or are not EKI XML are skipped.
pub fn scan(paths: &[std::path::PathBuf]) -> Vec<EkiChannel> {
    use rayon::prelude::*;
    crate::files::walk_xml(paths)
        .par_iter()
        .filter_map(|p| {
            let bytes = std::fs::read(p).ok()?;
            let text = crate::syntax::decode(&bytes).text;
            read(&channel_name(p), &p.display().to_string(), &text)
        })
        .collect()
}

/// The channel a config file defines: its file stem, case preserved.
pub fn channel_name(path: &std::path::Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Read a channel from XML text. `None` if the root element is not `ETHERNETKRL`.
pub fn read(name: &str, path: &str, xml: &str) -> Option<EkiChannel> {
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut stack: Vec<String> = Vec::new();
    let mut ch = EkiChannel {
        name: name.to_owned(),
        path: path.to_owned(),
        alive_flag: None,
        receive_flag: None,
        ip: None,
        port: None,
    };
    loop {
        let (e, empty) = match reader.read_event() {
            Ok(Event::Start(e)) => (e, false),
            Ok(Event::Empty(e)) => (e, true),
            Ok(Event::End(_)) => {
                stack.pop();
                continue;
            }
            Ok(Event::Eof) => break,
            Ok(Event::Text(t)) => {
                let path: Vec<&str> = stack.iter().map(String::as_str).collect();
                let raw: &str = t.as_ref();
                let text = raw.trim().to_owned();
                match path.as_slice() {
                    [.., "CONFIGURATION", "EXTERNAL", "IP"] if !text.is_empty() => {
                        ch.ip = Some(text)
                    }
                    [.., "CONFIGURATION", "EXTERNAL", "PORT"] => ch.port = text.parse().ok(),
                    _ => {}
                }
                continue;
            }
            Ok(_) => continue,
            Err(_) => return None,
        };
        let tag = e.name().as_ref().to_ascii_uppercase();
        if stack.is_empty() && tag != "ETHERNETKRL" {
            return None;
        }
        let flag = || {
            e.attributes().flatten().find_map(|a| {
                a.key
                    .as_ref()
                    .eq_ignore_ascii_case("Set_Flag")
                    .then(|| a.value.trim().parse::<i64>().ok())
                    .flatten()
            })
        };
        let path: Vec<&str> = stack.iter().map(String::as_str).collect();
        match (tag.as_str(), path.as_slice()) {
            ("ALIVE", [.., "CONFIGURATION", "INTERNAL"]) => {
                ch.alive_flag = flag().or(ch.alive_flag)
            }
            ("ELEMENT", [.., "RECEIVE", "RAW"]) => ch.receive_flag = flag().or(ch.receive_flag),
            _ => {}
        }
        if !empty {
            stack.push(tag);
        }
    }
    (!stack.is_empty()
        || ch.alive_flag.is_some()
        || ch.receive_flag.is_some()
        || xml.contains("ETHERNETKRL"))
    .then_some(ch)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_flags() {
        let xml = r#"<ETHERNETKRL><CONFIGURATION><EXTERNAL><IP>1.2.3.4</IP></EXTERNAL><INTERNAL><ALIVE Set_Flag="873"/></INTERNAL></CONFIGURATION><RECEIVE><RAW><ELEMENT Tag="Buffer" Type="BYTE" Set_Flag="871" Size="1408"/></RAW></RECEIVE><SEND/></ETHERNETKRL>"#;
        let c = read("XML_Kuka_MMIND", "x.xml", xml).expect("channel");
        assert_eq!(c.alive_flag, Some(873));
        assert_eq!(c.receive_flag, Some(871));
        assert_eq!(c.ip.as_deref(), Some("1.2.3.4"));
        assert_eq!(c.port, None);
        let with_port = xml.replace("</IP>", "</IP><PORT> 50001 </PORT>");
        assert_eq!(
            read("a", "a.xml", &with_port).expect("channel").port,
            Some(50001)
        );
        assert!(read("a", "a.xml", "<other/>").is_none());
    }
}
