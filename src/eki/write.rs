//! [`Channel::to_xml`]: what the file configures, in the element and attribute spelling of the
//! EKI manual. Defaults (Server, the default connect timeout) are not written, so a generated
//! file stays as Mech-Mind ships it.

use quick_xml::Writer;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};

use super::{Channel, DEFAULT_CONNECT_MS, Element, External, Kind};

impl Channel {
    /// The channel XML (LF line endings; the package writer converts them).
    pub fn to_xml(&self) -> String {
        let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
        // Writing into a Vec cannot fail; the results are ignored for that reason only.
        let _ = w.write_event(Event::Decl(BytesDecl::new("1.0", Some("utf-8"), None)));
        start(&mut w, "ETHERNETKRL");
        start(&mut w, "CONFIGURATION");
        start(&mut w, "EXTERNAL");
        if self.external == External::Client {
            text_element(&mut w, "TYPE", "Client");
        }
        text_element(&mut w, "IP", &self.ip);
        if let Some(port) = self.port {
            text_element(&mut w, "PORT", &port.to_string());
        }
        end(&mut w, "EXTERNAL");
        start(&mut w, "INTERNAL");
        let flag = self.alive_flag.map(|f| f.to_string());
        let out = self.alive_out.map(|f| f.to_string());
        if flag.is_some() || out.is_some() {
            let mut attrs = Vec::new();
            attrs.extend(flag.as_deref().map(|f| ("Set_Flag", f)));
            attrs.extend(out.as_deref().map(|o| ("Set_Out", o)));
            let _ = w.write_event(Event::Empty(
                BytesStart::new("ALIVE").with_attributes(attrs),
            ));
        }
        if self.connect_timeout_ms != DEFAULT_CONNECT_MS {
            let t = self.connect_timeout_ms.to_string();
            let _ = w.write_event(Event::Empty(
                BytesStart::new("TIMEOUT").with_attributes([("Connect", t.as_str())]),
            ));
        }
        end(&mut w, "INTERNAL");
        end(&mut w, "CONFIGURATION");
        raw_section(&mut w, "RECEIVE", &self.receive);
        raw_section(&mut w, "SEND", &self.send);
        end(&mut w, "ETHERNETKRL");
        let mut s = String::from_utf8(w.into_inner()).unwrap_or_default();
        s.push('\n');
        s
    }
}

fn start(w: &mut Writer<Vec<u8>>, name: &str) {
    let _ = w.write_event(Event::Start(BytesStart::new(name)));
}

fn end(w: &mut Writer<Vec<u8>>, name: &str) {
    let _ = w.write_event(Event::End(BytesEnd::new(name)));
}

fn text_element(w: &mut Writer<Vec<u8>>, name: &str, text: &str) {
    start(w, name);
    let _ = w.write_event(Event::Text(BytesText::new(text)));
    end(w, name);
}

fn raw_section(w: &mut Writer<Vec<u8>>, section: &str, elements: &[Element]) {
    start(w, section);
    start(w, "RAW");
    for e in elements {
        let (ty, eos) = match &e.kind {
            Kind::Stream { eos } => ("STREAM", Some(eos.to_string())),
            Kind::Byte => ("BYTE", None),
        };
        let flag = e.set_flag.map(|f| f.to_string());
        let out = e.set_out.map(|f| f.to_string());
        let size = e.size.to_string();
        let mut attrs = vec![("Tag", e.tag.as_str()), ("Type", ty)];
        attrs.extend(flag.as_deref().map(|f| ("Set_Flag", f)));
        attrs.extend(out.as_deref().map(|o| ("Set_Out", o)));
        attrs.push(("Size", size.as_str()));
        attrs.extend(eos.as_deref().map(|e| ("EOS", e)));
        let _ = w.write_event(Event::Empty(
            BytesStart::new("ELEMENT").with_attributes(attrs),
        ));
    }
    end(w, "RAW");
    end(w, section);
}
