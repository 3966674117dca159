use super::*;

fn full() -> Channel {
    Channel {
        external: External::Client,
        ip: "10.1.2.3".into(),
        port: Some(54600),
        alive_flag: Some(12),
        alive_out: Some(40),
        connect_timeout_ms: 500,
        receive: vec![Element {
            tag: "In".into(),
            kind: Kind::Stream {
                eos: Eos(vec![vec![13, 10], vec![59]]),
            },
            size: 2700,
            set_flag: Some(11),
            set_out: Some(41),
        }],
        send: vec![Element {
            tag: "Out".into(),
            kind: Kind::Stream { eos: Eos::cr() },
            size: 64,
            set_flag: None,
            set_out: None,
        }],
        xml_mode: false,
    }
}

#[test]
fn the_reader_reads_what_the_writer_writes() {
    let c = full();
    assert_eq!(read(&c.to_xml()), Ok(c));
    let defaults = Channel {
        ip: "127.0.0.1".into(),
        receive: vec![Element {
            tag: "Rx".into(),
            kind: Kind::Byte,
            size: 660,
            set_flag: Some(871),
            set_out: None,
        }],
        ..Channel::default()
    };
    let xml = defaults.to_xml();
    assert!(!xml.contains("TYPE") && !xml.contains("TIMEOUT") && !xml.contains("ALIVE"));
    assert_eq!(read(&xml), Ok(defaults));
}

#[test]
fn eos_is_written_as_read() {
    assert_eq!(Eos(vec![vec![13, 10], vec![59]]).to_string(), "13,10|59");
    assert_eq!(Eos::cr().to_string(), "13");
}
