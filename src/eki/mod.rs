//! The EthernetKRL channel file (`<channel>.xml`), written with quick-xml per the EKI 2.2
//! schema: EXTERNAL IP/PORT, INTERNAL ALIVE flag, RAW receive/send elements: STREAM ending in
//! CR for the ASCII codec, fixed-size BYTE records for HEX (as Mech-Mind's shipped XML).

use quick_xml::Writer;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};

use crate::generate::view::{RX_TAG, TX_TAG};
use crate::spec::{Codec, Spec};

/// End-of-stream byte of Mech-Mind's ASCII framing (CR).
pub const EOS: &str = "13";

/// Sizes of the RAW records for a spec: `(receive, send)` in bytes.
pub fn record_sizes(spec: &Spec) -> (u32, u32) {
    let p = crate::generate::view::Package::new(spec);
    (p.rx_size, p.tx_size)
}

/// The channel XML for `spec` (LF line endings; the package writer converts them).
pub fn channel_xml(spec: &Spec) -> String {
    let (rx_size, tx_size) = record_sizes(spec);
    let (kind, eos) = match spec.codec {
        Codec::Ascii => ("STREAM", Some(EOS)),
        Codec::HexLe | Codec::HexBe => ("BYTE", None),
    };
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    // Writing into a Vec cannot fail; the results are ignored for that reason only.
    let _ = w.write_event(Event::Decl(BytesDecl::new("1.0", Some("utf-8"), None)));
    let _ = w.write_event(Event::Start(BytesStart::new("ETHERNETKRL")));
    let _ = w.write_event(Event::Start(BytesStart::new("CONFIGURATION")));
    let _ = w.write_event(Event::Start(BytesStart::new("EXTERNAL")));
    text_element(&mut w, "IP", &spec.server_ip.to_string());
    text_element(&mut w, "PORT", &spec.server_port.to_string());
    let _ = w.write_event(Event::End(BytesEnd::new("EXTERNAL")));
    let _ = w.write_event(Event::Start(BytesStart::new("INTERNAL")));
    let alive = spec.alive_flag.to_string();
    let _ = w.write_event(Event::Empty(
        BytesStart::new("ALIVE").with_attributes([("Set_Flag", alive.as_str())]),
    ));
    let _ = w.write_event(Event::End(BytesEnd::new("INTERNAL")));
    let _ = w.write_event(Event::End(BytesEnd::new("CONFIGURATION")));

    let recv_flag = spec.receive_flag.to_string();
    let rx = rx_size.to_string();
    let mut rx_attrs = vec![
        ("Tag", RX_TAG),
        ("Type", kind),
        ("Set_Flag", recv_flag.as_str()),
        ("Size", rx.as_str()),
    ];
    rx_attrs.extend(eos.map(|e| ("EOS", e)));
    raw_section(&mut w, "RECEIVE", &rx_attrs);
    let tx = tx_size.to_string();
    let mut tx_attrs = vec![("Tag", TX_TAG), ("Type", kind), ("Size", tx.as_str())];
    tx_attrs.extend(eos.map(|e| ("EOS", e)));
    raw_section(&mut w, "SEND", &tx_attrs);
    let _ = w.write_event(Event::End(BytesEnd::new("ETHERNETKRL")));
    let mut s = String::from_utf8(w.into_inner()).unwrap_or_default();
    s.push('\n');
    s
}

fn text_element(w: &mut Writer<Vec<u8>>, name: &str, text: &str) {
    let _ = w.write_event(Event::Start(BytesStart::new(name)));
    let _ = w.write_event(Event::Text(BytesText::new(text)));
    let _ = w.write_event(Event::End(BytesEnd::new(name)));
}

fn raw_section(w: &mut Writer<Vec<u8>>, section: &str, attrs: &[(&str, &str)]) {
    let _ = w.write_event(Event::Start(BytesStart::new(section)));
    let _ = w.write_event(Event::Start(BytesStart::new("RAW")));
    let _ = w.write_event(Event::Empty(
        BytesStart::new("ELEMENT").with_attributes(attrs.iter().copied()),
    ));
    let _ = w.write_event(Event::End(BytesEnd::new("RAW")));
    let _ = w.write_event(Event::End(BytesEnd::new(section)));
}
