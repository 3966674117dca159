//! Runtime values and types.

use std::collections::HashMap;

/// KRL's INT range (32-bit two's complement).
pub const INT_MIN: i64 = i32::MIN as i64;
pub const INT_MAX: i64 = i32::MAX as i64;

/// A KRL runtime value. Arrays are flattened row-major with 1-based KRL indices mapped to 0-based
/// offsets; CHAR arrays double as strings (NUL-terminated when shorter than the array).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Int(i64),
    Real(f64),
    Bool(bool),
    Char(u8),
    /// `#NAME`, upper-case.
    Enum(String),
    /// A string literal before it lands in a CHAR array.
    Str(String),
    Array {
        dims: Vec<usize>,
        items: Vec<Value>,
    },
    Struc {
        ty: String,
        fields: Vec<(String, Value)>,
    },
    /// An untyped aggregate (`{X 1, Y 2}`): merged into a typed value on assignment.
    Partial(Vec<(String, Value)>),
    /// A scalar of this type that was declared but never assigned: reading it is an error, as
    /// on the controller. (CHAR arrays start as empty strings instead.)
    Unset(BaseType),
}

impl Value {
    pub fn kind_name(&self) -> String {
        match self {
            Value::Int(_) => "INT".into(),
            Value::Real(_) => "REAL".into(),
            Value::Bool(_) => "BOOL".into(),
            Value::Char(_) => "CHAR".into(),
            Value::Enum(_) => "ENUM".into(),
            Value::Str(_) => "string".into(),
            Value::Array { .. } => "array".into(),
            Value::Struc { ty, .. } => ty.clone(),
            Value::Partial(_) => "aggregate".into(),
            Value::Unset(t) => format!("unassigned {}", t.name()),
        }
    }

    pub fn field(&self, name: &str) -> Option<&Value> {
        match self {
            Value::Struc { fields, .. } | Value::Partial(fields) => fields
                .iter()
                .find(|(n, _)| n.eq_ignore_ascii_case(name))
                .map(|(_, v)| v),
            _ => None,
        }
    }

    pub fn field_mut(&mut self, name: &str) -> Option<&mut Value> {
        match self {
            Value::Struc { fields, .. } | Value::Partial(fields) => fields
                .iter_mut()
                .find(|(n, _)| n.eq_ignore_ascii_case(name))
                .map(|(_, v)| v),
            _ => None,
        }
    }

    /// JSON for traces and reports: CHAR arrays as strings, STRUCs as objects.
    pub fn to_json(&self) -> serde_json::Value {
        super::machine::to_json(self)
    }

    /// The text of a CHAR array (up to the first NUL) or a string literal.
    pub fn as_text(&self) -> Option<String> {
        match self {
            Value::Str(s) => Some(s.clone()),
            Value::Char(c) => Some((*c as char).to_string()),
            Value::Array { items, .. } if items.iter().all(|v| matches!(v, Value::Char(_))) => {
                Some(
                    items
                        .iter()
                        .map_while(|v| match v {
                            Value::Char(0) => None,
                            Value::Char(c) => Some(*c as char),
                            _ => None,
                        })
                        .collect(),
                )
            }
            _ => None,
        }
    }

    /// Whether any part of the value was never assigned.
    pub fn has_unset(&self) -> bool {
        match self {
            Value::Unset(_) => true,
            Value::Array { items, .. } => items.iter().any(Value::has_unset),
            Value::Struc { fields, .. } | Value::Partial(fields) => {
                fields.iter().any(|(_, v)| v.has_unset())
            }
            _ => false,
        }
    }

    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Int(i) => Some(*i as f64),
            Value::Real(r) => Some(*r),
            _ => None,
        }
    }

    /// A CHAR array of `len` holding `text` (truncated), NUL-padded.
    pub fn char_array(text: &[u8], len: usize) -> Value {
        let mut items: Vec<Value> = text.iter().take(len).map(|b| Value::Char(*b)).collect();
        items.resize(len, Value::Char(0));
        Value::Array {
            dims: vec![len],
            items,
        }
    }
}

/// Element type of a declaration.
#[derive(Debug, Clone, PartialEq)]
pub enum BaseType {
    Int,
    Real,
    Bool,
    Char,
    Enum(String),
    Struc(String),
}

impl BaseType {
    pub fn name(&self) -> &str {
        match self {
            BaseType::Int => "INT",
            BaseType::Real => "REAL",
            BaseType::Bool => "BOOL",
            BaseType::Char => "CHAR",
            BaseType::Enum(n) | BaseType::Struc(n) => n,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct StrucDef {
    pub name: String,
    pub fields: Vec<(String, BaseType, Vec<usize>)>,
}

/// Type definitions in scope: built-in STRUCs/ENUMs plus every STRUC/ENUM of the loaded files.
#[derive(Debug, Clone, Default)]
pub struct Types {
    pub strucs: HashMap<String, StrucDef>,
    /// ENUM name → its values (upper-case).
    pub enums: HashMap<String, Vec<String>>,
}

const FRAME6: [&str; 6] = ["X", "Y", "Z", "A", "B", "C"];
const AXES: [&str; 6] = ["A1", "A2", "A3", "A4", "A5", "A6"];
const EXT: [&str; 6] = ["E1", "E2", "E3", "E4", "E5", "E6"];

impl Types {
    pub fn builtin() -> Types {
        let mut t = Types::default();
        let reals = |names: &[&str]| -> Vec<(String, BaseType, Vec<usize>)> {
            names
                .iter()
                .map(|n| (n.to_string(), BaseType::Real, vec![]))
                .collect()
        };
        let ints = |names: &[&str]| -> Vec<(String, BaseType, Vec<usize>)> {
            names
                .iter()
                .map(|n| (n.to_string(), BaseType::Int, vec![]))
                .collect()
        };
        let mut add = |name: &str, fields: Vec<(String, BaseType, Vec<usize>)>| {
            t.strucs.insert(
                name.into(),
                StrucDef {
                    name: name.into(),
                    fields,
                },
            );
        };
        add("FRAME", reals(&FRAME6));
        let mut pos = reals(&FRAME6);
        pos.extend(ints(&["S", "T"]));
        add("POS", pos.clone());
        let mut e6pos = pos;
        e6pos.extend(reals(&EXT));
        add("E6POS", e6pos);
        add("AXIS", reals(&AXES));
        let mut e6axis = reals(&AXES);
        e6axis.extend(reals(&EXT));
        add("E6AXIS", e6axis);
        let mut eki = ints(&["Buff", "Read", "Msg_No"]);
        eki.push(("Connected".into(), BaseType::Bool, vec![]));
        eki.extend(ints(&["Counter"]));
        add("EKI_STATUS", eki);
        add(
            "STATE_T",
            vec![
                ("RET1".into(), BaseType::Enum("CMD_STAT".into()), vec![]),
                ("HITS".into(), BaseType::Int, vec![]),
                ("LENGTH".into(), BaseType::Int, vec![]),
            ],
        );
        add("VEL_CP_T", reals(&["CP", "ORI1", "ORI2"]));
        add("APO_T", reals(&["CDIS", "CPTP", "CORI", "CVEL"]));
        // Motion data of the inline forms (`PDAT_ACT = PDEFAULT`, `FDAT_ACT = FHOME`, ...).
        let en = |field: &str, ty: &str| (field.to_string(), BaseType::Enum(ty.into()), vec![]);
        let mut pdat = reals(&["VEL", "ACC", "APO_DIST"]);
        pdat.push(en("APO_MODE", "APO_MODE_T"));
        pdat.extend(reals(&["GEAR_JERK"]));
        pdat.extend(ints(&["EXAX_IGN"]));
        add("PDAT", pdat);
        let mut ldat = reals(&["VEL", "ACC", "APO_DIST", "APO_FAC", "AXIS_VEL", "AXIS_ACC"]);
        ldat.push(en("ORI_TYP", "ORI_TYPE"));
        ldat.push(en("CIRC_TYP", "CIRC_TYPE"));
        ldat.extend(reals(&["JERK_FAC", "GEAR_JERK"]));
        ldat.extend(ints(&["EXAX_IGN"]));
        add("LDAT", ldat);
        let mut fdat = ints(&["TOOL_NO", "BASE_NO"]);
        fdat.push(en("IPO_FRAME", "IPO_MODE"));
        fdat.push(("POINT2".into(), BaseType::Char, vec![24]));
        fdat.push(("TQ_STATE".into(), BaseType::Bool, vec![]));
        add("FDAT", fdat);
        // The inline forms' record of the last motion's parameters (every template .dat has one).
        let text = |names: &[&str]| -> Vec<(String, BaseType, Vec<usize>)> {
            names
                .iter()
                .map(|n| (n.to_string(), BaseType::Char, vec![24]))
                .collect()
        };
        add(
            "BASIS_SUGG_T",
            text(&[
                "POINT1",
                "POINT2",
                "CP_PARAMS",
                "PTP_PARAMS",
                "CONT",
                "CP_VEL",
                "PTP_VEL",
                "SYNC_PARAMS",
                "SPL_NAME",
                "A_PARAMS",
            ]),
        );
        // User messages (KUKA's KrlMsg interface: Set_KrlMsg, Set_KrlDlg, ...).
        let chars = |name: &str, n: usize| (name.to_string(), BaseType::Char, vec![n]);
        add(
            "KRLMSG_T",
            vec![
                chars("MODUL", 24),
                ("NR".into(), BaseType::Int, vec![]),
                chars("MSG_TXT", 80),
            ],
        );
        add(
            "KRLMSGPAR_T",
            vec![
                en("PAR_TYPE", "KRLMSGPARTYPE_T"),
                chars("PAR_TXT", 26),
                ("PAR_INT".into(), BaseType::Int, vec![]),
                ("PAR_REAL".into(), BaseType::Real, vec![]),
                ("PAR_BOOL".into(), BaseType::Bool, vec![]),
            ],
        );
        add(
            "KRLMSGOPT_T",
            ["VL_STOP", "CLEAR_P_RESET", "CLEAR_P_SAW", "LOG_TO_DB"]
                .iter()
                .map(|n| (n.to_string(), BaseType::Bool, vec![]))
                .collect(),
        );
        add(
            "KRLMSGDLGSK_T",
            vec![en("SK_TYPE", "KRLMSGPARTYPE_T"), chars("SK_TXT", 10)],
        );
        add("INERTIA", reals(&["X", "Y", "Z"]));
        add("JERK_STRUC", reals(&["CP", "ORI"]));
        add(
            "LOAD",
            vec![
                ("M".into(), BaseType::Real, vec![]),
                ("CM".into(), BaseType::Struc("FRAME".into()), vec![]),
                ("J".into(), BaseType::Struc("INERTIA".into()), vec![]),
            ],
        );
        for (name, values) in [
            ("APO_MODE_T", &["CDIS", "CPTP"][..]),
            ("ORI_TYPE", &["VAR", "CONSTANT", "JOINT"][..]),
            ("CIRC_TYPE", &["BASE", "PATH"][..]),
            ("IPO_MODE", &["BASE", "TCP"][..]),
            ("MODE_OP", &["T1", "T2", "AUT", "EX", "INVALID"][..]),
            ("KRLMSGPARTYPE_T", &["VALUE", "KEY", "EMPTY"][..]),
            ("VAR_STATE", &["DECLARED", "INITIALIZED", "UNKNOWN"][..]),
            (
                "EKRLMSGTYPE",
                &["NOTIFY", "STATE", "QUIT", "WAITING", "DIALOG"][..],
            ),
        ] {
            t.enums
                .insert(name.into(), values.iter().map(|s| s.to_string()).collect());
        }
        t.enums.insert(
            "CMD_STAT".into(),
            [
                "CMD_OK",
                "CMD_TIMEOUT",
                "DATA_OK",
                "DATA_BLK",
                "DATA_END",
                "CMD_ABORT",
                "CMD_REJ",
                "CMD_SYN",
                "DATA_TYP",
                "FMT_ERR",
            ]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        );
        t
    }

    pub fn base_type(&self, name: &str) -> Option<BaseType> {
        let up = name.to_ascii_uppercase();
        Some(match up.as_str() {
            "INT" => BaseType::Int,
            "REAL" => BaseType::Real,
            "BOOL" => BaseType::Bool,
            "CHAR" => BaseType::Char,
            _ if self.strucs.contains_key(&up) => BaseType::Struc(up),
            _ if self.enums.contains_key(&up) => BaseType::Enum(up),
            _ => return None,
        })
    }

    /// The zero value of a type (for system variables and built-ins that start with a value).
    pub fn default_value(&self, ty: &BaseType, dims: &[usize]) -> Value {
        self.initial_value(ty, dims, false)
    }

    /// The value of a declaration without an initialiser: every scalar unassigned (reading it
    /// is an error until something is assigned), except that CHAR arrays start as empty
    /// strings (builtins such as SWRITE and EKI_GetString write into them).
    pub fn unset_value(&self, ty: &BaseType, dims: &[usize]) -> Value {
        self.initial_value(ty, dims, true)
    }

    fn initial_value(&self, ty: &BaseType, dims: &[usize], unset: bool) -> Value {
        if !dims.is_empty() {
            let n: usize = dims.iter().product();
            let item = self.initial_value(ty, &[], unset && *ty != BaseType::Char);
            return Value::Array {
                dims: dims.to_vec(),
                items: vec![item; n],
            };
        }
        match ty {
            BaseType::Struc(s) => match self.strucs.get(s) {
                Some(def) => Value::Struc {
                    ty: s.clone(),
                    fields: def
                        .fields
                        .iter()
                        .map(|(n, t, d)| (n.clone(), self.initial_value(t, d, unset)))
                        .collect(),
                },
                None => Value::Int(0),
            },
            t if unset => Value::Unset(t.clone()),
            BaseType::Int => Value::Int(0),
            BaseType::Real => Value::Real(0.0),
            BaseType::Bool => Value::Bool(false),
            BaseType::Char => Value::Char(0),
            BaseType::Enum(e) => Value::Enum(
                self.enums
                    .get(e)
                    .and_then(|v| v.first().cloned())
                    .unwrap_or_default(),
            ),
        }
    }

    /// The names of the six Cartesian or axis components of a motion target type.
    pub fn is_axis_type(ty: &str) -> bool {
        matches!(ty, "AXIS" | "E6AXIS")
    }
}

pub const CART_FIELDS: [&str; 6] = FRAME6;
pub const AXIS_FIELDS: [&str; 6] = AXES;
