//! The spec's EKI channel: the server address, the flags, and one RAW element each way whose
//! size is the package's record size.

use super::view::{Package, RX_TAG, TX_TAG};
use crate::eki::{Channel, Element, Eos, Kind};
use crate::spec::{Codec, Spec};

pub fn channel(spec: &Spec, pkg: &Package) -> Channel {
    let kind = match spec.codec {
        Codec::Ascii => Kind::Stream { eos: Eos::cr() },
        Codec::HexLe | Codec::HexBe => Kind::Byte,
    };
    Channel {
        ip: spec.server_ip.to_string(),
        port: Some(spec.server_port),
        alive_flag: Some(spec.alive_flag),
        receive: vec![Element {
            tag: RX_TAG.into(),
            kind: kind.clone(),
            size: pkg.rx_size,
            set_flag: Some(spec.receive_flag),
            set_out: None,
        }],
        send: vec![Element {
            tag: TX_TAG.into(),
            kind,
            size: pkg.tx_size,
            set_flag: None,
            set_out: None,
        }],
        ..Channel::default()
    }
}
