use super::*;

#[test]
fn default_spec_matches_the_shipped_settings() {
    let s = Spec::default();
    assert_eq!(s.channel, "XML_Kuka_MMIND");
    assert_eq!((s.alive_flag, s.receive_flag), (873, 871));
    assert_eq!(s.connect_timeout, 60);
    assert_eq!(s.server_port, 50000);
    assert_eq!(s.server_ip.to_string(), "192.168.1.121");
    assert_eq!(s.subprograms.len(), catalog().subprograms.len());
}

#[test]
fn empty_spec_equals_default_spec() {
    assert_eq!(Spec::parse("", "x").unwrap(), Spec::default());
}

#[test]
fn init_socket_is_always_emitted() {
    let s = Spec::parse("subprograms = [\"MM_Get_Status\"]", "x").unwrap();
    assert_eq!(s.subprograms, vec!["MM_Init_Socket", "MM_Get_Status"]);
}

#[test]
fn key_value_names_the_address_fields_and_the_port() {
    let s = Spec::default();
    let v: Vec<Option<f64>> = ["server_ip[1]", "server_ip[4]", "server_port"]
        .iter()
        .map(|k| s.key_value(k))
        .collect();
    assert_eq!(v, [Some(192.0), Some(121.0), Some(50000.0)]);
    for bad in [
        "server_ip[0]",
        "server_ip[5]",
        "server_ip",
        "timer",
        "server_ip[x]",
    ] {
        assert_eq!(s.key_value(bad), None, "{bad}");
    }
}

#[test]
fn interface_and_codec_keys() {
    let s = Spec::parse("interface = \"2.x\"\ncodec = \"hex-le\"", "x")
        .unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(s.interface, Interface::V2);
    assert_eq!(s.codec, Codec::HexLe);
}
