//! The EthernetKRL channel file (`<channel>.xml`) as a typed value, written with quick-xml per
//! the EKI 2.2 schema: EXTERNAL IP/PORT, INTERNAL ALIVE flag, RAW receive/send elements (STREAM
//! ending in CR for the ASCII codec, fixed-size BYTE records for HEX, as Mech-Mind's shipped
//! XML). A leaf: it imports no krlkit module; `generate` builds a [`Channel`] from the spec.

pub mod read;

use quick_xml::Writer;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};
use serde::Serialize;

/// End-of-stream byte of Mech-Mind's ASCII framing (CR).
pub const EOS: &str = "13";

/// One EKI channel: what the file configures.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Channel {
    /// `CONFIGURATION/EXTERNAL/IP`.
    pub ip: String,
    /// `CONFIGURATION/EXTERNAL/PORT`.
    pub port: u16,
    /// `CONFIGURATION/INTERNAL/ALIVE@Set_Flag`.
    pub alive_flag: Option<u32>,
    /// `RECEIVE/RAW/ELEMENT`s.
    pub receive: Vec<Element>,
    /// `SEND/RAW/ELEMENT`s.
    pub send: Vec<Element>,
}

/// One RAW element.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Element {
    pub tag: String,
    pub kind: Kind,
    /// `Size` in bytes.
    pub size: u32,
    /// `Set_Flag` (receive elements).
    pub set_flag: Option<u32>,
}

/// How a RAW element frames its bytes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub enum Kind {
    /// `Type="STREAM"`, ending in the `EOS` bytes (as written: `"13"`, `"13,10"`).
    Stream { eos: String },
    /// `Type="BYTE"`: fixed-size records.
    Byte,
}

impl Channel {
    /// The channel XML (LF line endings; the package writer converts them).
    pub fn to_xml(&self) -> String {
        let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
        // Writing into a Vec cannot fail; the results are ignored for that reason only.
        let _ = w.write_event(Event::Decl(BytesDecl::new("1.0", Some("utf-8"), None)));
        let _ = w.write_event(Event::Start(BytesStart::new("ETHERNETKRL")));
        let _ = w.write_event(Event::Start(BytesStart::new("CONFIGURATION")));
        let _ = w.write_event(Event::Start(BytesStart::new("EXTERNAL")));
        text_element(&mut w, "IP", &self.ip);
        text_element(&mut w, "PORT", &self.port.to_string());
        let _ = w.write_event(Event::End(BytesEnd::new("EXTERNAL")));
        let _ = w.write_event(Event::Start(BytesStart::new("INTERNAL")));
        if let Some(alive) = self.alive_flag {
            let alive = alive.to_string();
            let _ = w.write_event(Event::Empty(
                BytesStart::new("ALIVE").with_attributes([("Set_Flag", alive.as_str())]),
            ));
        }
        let _ = w.write_event(Event::End(BytesEnd::new("INTERNAL")));
        let _ = w.write_event(Event::End(BytesEnd::new("CONFIGURATION")));
        raw_section(&mut w, "RECEIVE", &self.receive);
        raw_section(&mut w, "SEND", &self.send);
        let _ = w.write_event(Event::End(BytesEnd::new("ETHERNETKRL")));
        let mut s = String::from_utf8(w.into_inner()).unwrap_or_default();
        s.push('\n');
        s
    }
}

fn text_element(w: &mut Writer<Vec<u8>>, name: &str, text: &str) {
    let _ = w.write_event(Event::Start(BytesStart::new(name)));
    let _ = w.write_event(Event::Text(BytesText::new(text)));
    let _ = w.write_event(Event::End(BytesEnd::new(name)));
}

fn raw_section(w: &mut Writer<Vec<u8>>, section: &str, elements: &[Element]) {
    let _ = w.write_event(Event::Start(BytesStart::new(section)));
    let _ = w.write_event(Event::Start(BytesStart::new("RAW")));
    for e in elements {
        let (ty, eos) = match &e.kind {
            Kind::Stream { eos } => ("STREAM", Some(eos.as_str())),
            Kind::Byte => ("BYTE", None),
        };
        let flag = e.set_flag.map(|f| f.to_string());
        let size = e.size.to_string();
        let mut attrs = vec![("Tag", e.tag.as_str()), ("Type", ty)];
        attrs.extend(flag.as_deref().map(|f| ("Set_Flag", f)));
        attrs.push(("Size", size.as_str()));
        attrs.extend(eos.map(|e| ("EOS", e)));
        let _ = w.write_event(Event::Empty(
            BytesStart::new("ELEMENT").with_attributes(attrs),
        ));
    }
    let _ = w.write_event(Event::End(BytesEnd::new("RAW")));
    let _ = w.write_event(Event::End(BytesEnd::new(section)));
}
