//! Runtime values and types.

use rustc_hash::FxHashMap;

use crate::sema::env::EnvTypeDecl;
use crate::syntax::ast::{EnumDecl, ExprKind, StrucDecl};

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
        use serde_json::json;
        match self {
            Value::Unset(_) => serde_json::Value::Null,
            Value::Int(i) => json!(i),
            Value::Real(r) => json!(r),
            Value::Bool(b) => json!(b),
            Value::Char(c) => json!((*c as char).to_string()),
            Value::Enum(e) => json!(format!("#{e}")),
            Value::Str(s) => json!(s),
            Value::Array { items, .. } => {
                if let Some(t) = self.as_text()
                    && matches!(items.first(), Some(Value::Char(_)))
                {
                    return json!(t);
                }
                serde_json::Value::Array(items.iter().map(Value::to_json).collect())
            }
            Value::Struc { fields, .. } | Value::Partial(fields) => {
                let mut m = serde_json::Map::new();
                for (k, x) in fields {
                    m.insert(k.clone(), x.to_json());
                }
                serde_json::Value::Object(m)
            }
        }
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
    pub strucs: FxHashMap<String, StrucDef>,
    /// ENUM name → its values (upper-case).
    pub enums: FxHashMap<String, Vec<String>>,
}

const FRAME6: [&str; 6] = ["X", "Y", "Z", "A", "B", "C"];
const AXES: [&str; 6] = ["A1", "A2", "A3", "A4", "A5", "A6"];

impl Types {
    /// The KSS environment's STRUC and ENUM types, as `kss.toml` (`sema::env`) writes them.
    pub fn builtin() -> Types {
        let mut t = Types::default();
        let env = crate::sema::env();
        let mut enums = Vec::new();
        let mut strucs = Vec::new();
        for ty in &env.types {
            match &ty.decl {
                EnvTypeDecl::Enum(e) => enums.push(e),
                EnvTypeDecl::Struc(s) => strucs.push(s),
            }
        }
        let defined = t.define(&enums, &strucs);
        debug_assert!(defined.is_ok(), "kss.toml types: {defined:?}");
        t
    }

    /// Add ENUM and STRUC definitions (replacing built-ins of the same name). On a field whose
    /// type is unknown or whose dimension is not a positive literal: the index of its STRUC in
    /// `strucs` and the message.
    pub fn define(
        &mut self,
        enums: &[&EnumDecl],
        strucs: &[&StrucDecl],
    ) -> Result<(), (usize, String)> {
        // ENUMs first so STRUC fields can name them.
        for e in enums {
            self.enums
                .insert(e.name.key(), e.values.iter().map(|v| v.key()).collect());
        }
        // Register names before fields so STRUCs may nest in any order.
        for s in strucs {
            self.strucs.entry(s.name.key()).or_insert(StrucDef {
                name: s.name.key(),
                fields: vec![],
            });
        }
        for (i, s) in strucs.iter().enumerate() {
            let mut fields = Vec::new();
            for f in &s.fields {
                let ty = self.base_type(&f.ty.text).ok_or_else(|| {
                    (
                        i,
                        format!("unknown type `{}` in STRUC {}", f.ty.text, s.name.text),
                    )
                })?;
                let mut dims = Vec::new();
                for d in &f.dims {
                    match d.as_ref().map(|e| &e.kind) {
                        Some(ExprKind::Int(n)) if *n > 0 => dims.push(*n as usize),
                        _ => {
                            return Err((
                                i,
                                format!(
                                    "STRUC {}: field {} needs a constant dimension",
                                    s.name.text, f.name.text
                                ),
                            ));
                        }
                    }
                }
                fields.push((f.name.text.to_string(), ty, dims));
            }
            self.strucs.insert(
                s.name.key(),
                StrucDef {
                    name: s.name.key(),
                    fields,
                },
            );
        }
        Ok(())
    }

    pub fn base_type(&self, name: &str) -> Option<BaseType> {
        for (n, t) in [
            ("INT", BaseType::Int),
            ("REAL", BaseType::Real),
            ("BOOL", BaseType::Bool),
            ("CHAR", BaseType::Char),
        ] {
            if name.eq_ignore_ascii_case(n) {
                return Some(t);
            }
        }
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
