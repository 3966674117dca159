//! The SRCI status word model: encoding any field values and decoding the word gives them back,
//! and decoding any word and encoding its fields gives the word back (reserved bits aside).

use proptest::prelude::*;

use krlkit::srci::{self, FIELDS, FieldKind, RESERVED_MASK};

/// A value for every field: 0/1 for flags, anything that fits for enums.
fn values() -> impl Strategy<Value = Vec<u32>> {
    FIELDS
        .iter()
        .map(|f| (0..(1u32 << f.width())).boxed())
        .collect::<Vec<_>>()
}

proptest! {
    #[test]
    fn decode_of_encode_gives_the_fields_back(values in values(), by_name in any::<bool>()) {
        let assignments: Vec<String> = FIELDS
            .iter()
            .zip(&values)
            .map(|(f, v)| match (f.kind, by_name, f.value_name(*v)) {
                (FieldKind::Enum { .. }, true, Some(name)) => format!("{}={name}", f.name),
                (FieldKind::Flag, true, _) => format!("{}={}", f.name, *v == 1),
                _ => format!("{}={v}", f.name),
            })
            .collect();
        let word = srci::encode(&assignments).unwrap();
        let d = srci::decode(word);
        prop_assert_eq!(d.reserved, 0);
        for (got, want) in d.fields.iter().zip(&values) {
            prop_assert_eq!(got.value, *want, "{}", got.field.name);
        }
    }

    #[test]
    fn encode_of_decode_gives_the_word_back(word in any::<u32>()) {
        let d = srci::decode(word);
        prop_assert_eq!(d.reserved, word & RESERVED_MASK);
        let assignments: Vec<String> = d
            .fields
            .iter()
            .map(|f| format!("{}={}", f.field.name, f.value))
            .collect();
        prop_assert_eq!(srci::encode(&assignments).unwrap(), word & !RESERVED_MASK);
    }
}
