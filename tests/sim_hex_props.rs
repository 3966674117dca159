//! Properties of the HEX codec: a request packed per the catalog layout (any byte order, any
//! zero padding) decodes to its fields; a frame shorter than a request is never taken; no
//! input makes the codec panic or hold more than one request of input; every reply has the
//! frame size and starts with its echo.

use krlkit::catalog::{HexKind, Interface, catalog};
use krlkit::sim::hex::{ByteOrder, HexCodec};
use krlkit::sim::protocol::{Codec, Frame, Reply};
use proptest::prelude::*;

/// Commands with a fixed request layout, and 101/201 with their pose type.
const COMMANDS: &[u32] = &[
    101, 102, 103, 105, 106, 110, 111, 201, 203, 204, 205, 206, 207, 208, 210, 501, 502, 601, 701,
    901,
];

/// A request of `code` with arbitrary values: `(fields as f64, packed little-endian words)`.
fn request(code: u32, ints: &[i32], reals: &[f32]) -> (Vec<f64>, Vec<[u8; 4]>) {
    let cmd = catalog().command_in(Interface::V1, code).unwrap();
    let (mut ni, mut nr) = (0, 0);
    let mut args = Vec::new();
    let mut words = vec![(code as i32).to_le_bytes()];
    for name in &cmd.request {
        let count = if name == "pose..." {
            if args.get(2) == Some(&1.0) || (code == 201 && args.first() == Some(&1.0)) {
                12
            } else {
                6
            }
        } else {
            1
        };
        for _ in 0..count {
            match catalog().hex.kind(name).unwrap() {
                HexKind::Int32 => {
                    // Pose types that select the 12-value payload stay 1 when drawn so.
                    let v = ints[ni % ints.len()];
                    ni += 1;
                    args.push(f64::from(v));
                    words.push(v.to_le_bytes());
                }
                HexKind::Float32 => {
                    let v = reals[nr % reals.len()];
                    nr += 1;
                    args.push(krlkit::catalog::float32_value(v));
                    words.push(v.to_le_bytes());
                }
            }
        }
    }
    (args, words)
}

fn bytes(words: &[[u8; 4]], order: ByteOrder) -> Vec<u8> {
    words
        .iter()
        .flat_map(|w| {
            let mut w = *w;
            if order == ByteOrder::Big {
                w.reverse();
            }
            w
        })
        .collect()
}

fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        (-1e6f32..1e6f32),
        Just(0.0f32),
        Just(-0.0f32),
        Just(95.7806f32),
        Just(f32::MAX)
    ]
}

proptest! {
    #[test]
    fn packed_requests_decode_to_their_fields(
        code in proptest::sample::select(COMMANDS),
        ints in proptest::collection::vec(prop_oneof![0i32..3, any::<i32>()], 1..8),
        reals in proptest::collection::vec(finite(), 1..8),
        big in any::<bool>(),
        lead in 0usize..200,
        kuka in any::<bool>(),
    ) {
        let order = if big { ByteOrder::Big } else { ByteOrder::Little };
        let (args, words) = request(code, &ints, &reals);
        prop_assume!(words.len() <= 16);
        let mut codec = HexCodec::new(order, Interface::V1, 660);
        let mut input = vec![0u8; lead * 4];
        let mut frame = bytes(&words, order);
        frame.resize(if kuka { 660 } else { 64 }, 0);
        input.extend_from_slice(&frame);
        let Some(Frame::Message(m)) = codec.next_frame(&mut input) else {
            return Err(TestCaseError::fail("a whole request is a frame"));
        };
        prop_assert!(codec.next_frame(&mut input).is_none());
        prop_assert!(input.is_empty(), "{} bytes left", input.len());
        let r = codec.decode(&m).map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        prop_assert_eq!(r.command, code);
        prop_assert_eq!(r.args, args);
    }

    #[test]
    fn truncated_requests_are_never_taken(
        code in proptest::sample::select(COMMANDS),
        cut in 4usize..64,
    ) {
        let mut codec = HexCodec::new(ByteOrder::Little, Interface::V1, 660);
        let mut frame = (code as i32).to_le_bytes().to_vec();
        frame.resize(64, 0);
        let mut input = frame[..cut].to_vec();
        prop_assert!(codec.next_frame(&mut input).is_none());
        prop_assert!(input.len() <= cut);
    }

    #[test]
    fn any_input_is_bounded_and_never_panics(
        chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..900), 1..6),
        v2 in any::<bool>(),
    ) {
        let iface = if v2 { Interface::V2 } else { Interface::V1 };
        let mut codec = HexCodec::new(ByteOrder::Little, iface, 660);
        let mut input = Vec::new();
        for c in chunks {
            input.extend_from_slice(&c);
            while let Some(f) = codec.next_frame(&mut input) {
                let Frame::Message(m) = f else {
                    return Err(TestCaseError::fail("HEX has no oversized input"));
                };
                prop_assert_eq!(m.len(), 64);
                let _ = codec.decode(&m);
                let _ = codec.show(&m);
            }
            prop_assert!(input.len() < 64, "{} bytes held", input.len());
        }
    }

    #[test]
    fn replies_have_the_frame_size_and_their_echo(
        echo in any::<i32>(),
        ints in proptest::collection::vec(any::<i64>(), 0..200),
        reals in proptest::collection::vec(any::<f64>(), 0..20),
        frame in prop_oneof![Just(0usize), Just(660), Just(980)],
    ) {
        let codec = HexCodec::new(ByteOrder::Little, Interface::V1, frame);
        let reply = Reply::new(i64::from(echo), 4).ints(&ints).reals(&reals);
        let b = codec.encode(&reply);
        let fields = 4 * (1 + ints.len() + reals.len());
        prop_assert_eq!(b.len(), fields.max(frame));
        prop_assert_eq!(&b[..4], &echo.to_le_bytes());
        prop_assert!(b[fields..].iter().all(|x| *x == 0));
    }
}
