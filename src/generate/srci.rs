//! The SRCI status packer (`spec.srci_status`): a routine for the KUKA submit interpreter that
//! computes the RaStatusWord from system variables and writes it to a 32-bit output group.
//! Everything comes from `srci::FIELDS` (bit, width, value names, KUKA source): this file
//! restates no bit.

use crate::spec::Spec;
use crate::srci::{FIELDS, FieldKind, Kuka, Otherwise, RESERVED_MASK};

/// Name of the packer's module (`.src` + `.dat`) and routine.
pub const SRCI_MODULE: &str = "SRCI_Status";
/// The output group signal, declared in the packer's `.dat`.
pub const SRCI_SIGNAL: &str = "SRCI_Word";
/// Last operation mode seen (kept while `$MODE_OP` is between modes).
const LAST_PREFIX: &str = "SRCI_Last_";

/// One `CASE` of a mapped enum.
pub struct Case {
    pub krl: String,
    pub value: u32,
    pub name: String,
}

/// How one field is computed, in KRL terms.
pub enum Step {
    /// `IF cond THEN Word = Word + add ENDIF`.
    Flag { cond: String, add: u32 },
    /// `SWITCH var` over `cases`, adding `value << bit`.
    Map {
        var: String,
        cases: Vec<(Case, u32)>,
    },
    /// `SWITCH var` storing into the `.dat` variable `last` (kept otherwise), then adding it.
    MapKeep {
        var: String,
        last: String,
        cases: Vec<Case>,
        multiplier: u32,
    },
    /// A constant that is not zero.
    Add { add: u32 },
}

/// One documented field (the header comment) and how it is computed.
pub struct PackField {
    pub bits: String,
    pub name: &'static str,
    pub source: String,
    pub step: Option<Step>,
}

pub struct Packer {
    pub module: &'static str,
    pub signal: &'static str,
    pub first: u32,
    pub last: u32,
    pub fields: Vec<PackField>,
    /// `.dat` variables that keep a last value, with their initial value.
    pub keeps: Vec<String>,
    pub reserved: String,
}

fn bits(bit: u32, width: u32) -> String {
    if width == 1 {
        bit.to_string()
    } else {
        format!("{}-{}", bit, bit + width - 1)
    }
}

fn case(field: &crate::srci::Field, krl: &str, value: u32) -> Case {
    Case {
        krl: krl.to_string(),
        value,
        name: field.value_name(value).unwrap_or("undefined").to_string(),
    }
}

impl Packer {
    pub fn new(spec: &Spec) -> Packer {
        let mut keeps = Vec::new();
        let fields = FIELDS
            .iter()
            .map(|f| {
                let (source, step) = match f.kuka {
                    Kuka::When(cond) => (
                        cond.to_string(),
                        Some(Step::Flag {
                            cond: cond.to_string(),
                            add: 1 << f.bit,
                        }),
                    ),
                    Kuka::Map {
                        var,
                        values,
                        otherwise,
                    } => {
                        let list = values
                            .iter()
                            .map(|(k, v)| format!("#{k} {v}"))
                            .collect::<Vec<_>>()
                            .join(", ");
                        match otherwise {
                            Otherwise::Value(v) => (
                                format!("{var}: {list}, otherwise {v}"),
                                Some(Step::Map {
                                    var: var.to_string(),
                                    cases: values
                                        .iter()
                                        .filter(|(_, v2)| *v2 != v)
                                        .map(|(k, v2)| (case(f, k, *v2), (*v2 - v) << f.bit))
                                        .collect(),
                                }),
                            ),
                            Otherwise::KeepLast => {
                                let last = format!("{LAST_PREFIX}{}", f.name);
                                keeps.push(last.clone());
                                (
                                    format!("{var}: {list}, otherwise the last value (0 at first)"),
                                    Some(Step::MapKeep {
                                        var: var.to_string(),
                                        last,
                                        cases: values.iter().map(|(k, v)| case(f, k, *v)).collect(),
                                        multiplier: 1 << f.bit,
                                    }),
                                )
                            }
                        }
                    }
                    Kuka::Constant { value, why } => (
                        format!(
                            "constant {}: {why}",
                            match f.kind {
                                FieldKind::Flag =>
                                    if value == 1 {
                                        "TRUE".to_string()
                                    } else {
                                        "FALSE".to_string()
                                    },
                                FieldKind::Enum { .. } => value.to_string(),
                            }
                        ),
                        (value != 0).then_some(Step::Add {
                            add: value << f.bit,
                        }),
                    ),
                };
                PackField {
                    bits: bits(f.bit, f.width()),
                    name: f.name,
                    source,
                    step,
                }
            })
            .collect();
        let reserved_from = RESERVED_MASK.trailing_zeros();
        Packer {
            module: SRCI_MODULE,
            signal: SRCI_SIGNAL,
            first: spec.srci_output,
            last: spec.srci_output + 31,
            fields,
            keeps,
            reserved: format!("{reserved_from}-31"),
        }
    }
}
