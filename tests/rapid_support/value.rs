//! RAPID values and types: `num`, `bool`, `string`, records (the predefined ones the subset
//! uses and `RECORD`s of the program) and arrays. An aggregate `[…]` has no type until it is
//! stored: [`Types::coerce`] checks it against the declared type, component by component.

use std::collections::HashMap;

#[derive(Debug, Clone, PartialEq)]
pub enum V {
    Num(f64),
    Bool(bool),
    Str(String),
    /// A record of the named type, its components in declaration order.
    Rec(String, Vec<V>),
    Arr(Vec<V>),
    /// An aggregate not yet given a type.
    Agg(Vec<V>),
    /// A `triggdata` filled by `TriggIO`: output number, value, at the start (else the end).
    Trigg(Option<(i64, bool, bool)>),
}

impl V {
    pub fn num(&self) -> Result<f64, String> {
        match self {
            V::Num(n) => Ok(*n),
            other => Err(format!("a num expected, got {}", other.describe())),
        }
    }
    pub fn bool(&self) -> Result<bool, String> {
        match self {
            V::Bool(b) => Ok(*b),
            other => Err(format!("a bool expected, got {}", other.describe())),
        }
    }
    pub fn str(&self) -> Result<&str, String> {
        match self {
            V::Str(s) => Ok(s),
            other => Err(format!("a string expected, got {}", other.describe())),
        }
    }
    /// The components of a record of type `ty`.
    pub fn rec(&self, ty: &str) -> Result<&[V], String> {
        match self {
            V::Rec(t, f) if t == ty => Ok(f),
            other => Err(format!("a {ty} expected, got {}", other.describe())),
        }
    }
    /// The numbers of a record whose components are all num (pos, orient, speeddata, …).
    pub fn nums<const N: usize>(&self, ty: &str) -> Result<[f64; N], String> {
        let f = self.rec(ty)?;
        let v: Vec<f64> = f.iter().map(V::num).collect::<Result<_, _>>()?;
        v.try_into()
            .map_err(|_| format!("a {ty} with {N} components expected"))
    }
    pub fn describe(&self) -> String {
        match self {
            V::Num(n) => format!("the num {n}"),
            V::Bool(b) => format!("the bool {b}"),
            V::Str(s) => format!("the string {s:?}"),
            V::Rec(t, _) => format!("a {t}"),
            V::Arr(a) => format!("an array of {}", a.len()),
            V::Agg(a) => format!("an aggregate of {}", a.len()),
            V::Trigg(_) => "a triggdata".into(),
        }
    }
}

/// A type: base name (lower case) and array sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct Ty {
    pub base: String,
    pub dims: Vec<usize>,
}

impl Ty {
    pub fn scalar(base: &str) -> Ty {
        Ty {
            base: base.to_string(),
            dims: Vec::new(),
        }
    }
}

const BUILTIN: &[(&str, &[(&str, &str)])] = &[
    ("pos", &[("x", "num"), ("y", "num"), ("z", "num")]),
    (
        "orient",
        &[("q1", "num"), ("q2", "num"), ("q3", "num"), ("q4", "num")],
    ),
    ("pose", &[("trans", "pos"), ("rot", "orient")]),
    (
        "confdata",
        &[
            ("cf1", "num"),
            ("cf4", "num"),
            ("cf6", "num"),
            ("cfx", "num"),
        ],
    ),
    (
        "extjoint",
        &[
            ("eax_a", "num"),
            ("eax_b", "num"),
            ("eax_c", "num"),
            ("eax_d", "num"),
            ("eax_e", "num"),
            ("eax_f", "num"),
        ],
    ),
    (
        "robtarget",
        &[
            ("trans", "pos"),
            ("rot", "orient"),
            ("robconf", "confdata"),
            ("extax", "extjoint"),
        ],
    ),
    (
        "robjoint",
        &[
            ("rax_1", "num"),
            ("rax_2", "num"),
            ("rax_3", "num"),
            ("rax_4", "num"),
            ("rax_5", "num"),
            ("rax_6", "num"),
        ],
    ),
    (
        "jointtarget",
        &[("robax", "robjoint"), ("extax", "extjoint")],
    ),
    (
        "speeddata",
        &[
            ("v_tcp", "num"),
            ("v_ori", "num"),
            ("v_leax", "num"),
            ("v_reax", "num"),
        ],
    ),
    (
        "zonedata",
        &[
            ("finep", "bool"),
            ("pzone_tcp", "num"),
            ("pzone_ori", "num"),
            ("pzone_eax", "num"),
            ("zone_ori", "num"),
            ("zone_leax", "num"),
            ("zone_reax", "num"),
        ],
    ),
    (
        "loaddata",
        &[
            ("mass", "num"),
            ("cog", "pos"),
            ("aom", "orient"),
            ("ix", "num"),
            ("iy", "num"),
            ("iz", "num"),
        ],
    ),
    (
        "tooldata",
        &[
            ("robhold", "bool"),
            ("tframe", "pose"),
            ("tload", "loaddata"),
        ],
    ),
    (
        "wobjdata",
        &[
            ("robhold", "bool"),
            ("ufprog", "bool"),
            ("ufmec", "string"),
            ("uframe", "pose"),
            ("oframe", "pose"),
        ],
    ),
];

/// The record types known to a program: the predefined ones and its `RECORD`s.
pub struct Types {
    records: HashMap<String, Vec<(String, String)>>,
}

impl Types {
    pub fn new() -> Types {
        let records = BUILTIN
            .iter()
            .map(|(n, f)| {
                let f = f
                    .iter()
                    .map(|(a, b)| (a.to_string(), b.to_string()))
                    .collect();
                (n.to_string(), f)
            })
            .collect();
        Types { records }
    }

    pub fn add(&mut self, name: &str, fields: Vec<(String, String)>) -> Result<(), String> {
        if self.is_type(name) {
            return Err(format!("the type `{name}` is defined twice"));
        }
        self.records.insert(name.to_string(), fields);
        Ok(())
    }

    pub fn is_type(&self, name: &str) -> bool {
        matches!(
            name,
            "num" | "dnum" | "bool" | "string" | "intnum" | "triggdata"
        ) || self.records.contains_key(name)
    }

    pub fn fields(&self, ty: &str) -> Option<&[(String, String)]> {
        self.records.get(ty).map(Vec::as_slice)
    }

    /// Component `field` of record type `ty`: its position and type.
    pub fn field(&self, ty: &str, field: &str) -> Result<(usize, Ty), String> {
        let fields = self
            .fields(ty)
            .ok_or_else(|| format!("a {ty} has no components"))?;
        fields
            .iter()
            .position(|(n, _)| n == field)
            .map(|i| (i, Ty::scalar(&fields[i].1)))
            .ok_or_else(|| format!("a {ty} has no component `{field}`"))
    }

    /// The value an uninitialised `VAR` holds.
    pub fn default(&self, ty: &Ty) -> Result<V, String> {
        if let Some((n, rest)) = ty.dims.split_first() {
            let inner = Ty {
                base: ty.base.clone(),
                dims: rest.to_vec(),
            };
            return Ok(V::Arr(vec![self.default(&inner)?; *n]));
        }
        Ok(match ty.base.as_str() {
            "num" | "dnum" | "intnum" => V::Num(0.0),
            "bool" => V::Bool(false),
            "string" => V::Str(String::new()),
            "triggdata" => V::Trigg(None),
            t => {
                let fields = self
                    .fields(t)
                    .ok_or_else(|| format!("unknown type `{t}`"))?;
                let v = fields
                    .iter()
                    .map(|(_, f)| self.default(&Ty::scalar(f)))
                    .collect::<Result<_, _>>()?;
                V::Rec(t.to_string(), v)
            }
        })
    }

    /// `v` as a value of type `ty`: aggregates become records or arrays; anything else must
    /// already be of that type.
    pub fn coerce(&self, v: V, ty: &Ty) -> Result<V, String> {
        let bad = |v: &V| Err(format!("{} where a {} is expected", v.describe(), show(ty)));
        if let Some((n, rest)) = ty.dims.split_first() {
            let inner = Ty {
                base: ty.base.clone(),
                dims: rest.to_vec(),
            };
            return match v {
                V::Agg(items) | V::Arr(items) if items.len() == *n => Ok(V::Arr(
                    items
                        .into_iter()
                        .map(|x| self.coerce(x, &inner))
                        .collect::<Result<_, _>>()?,
                )),
                other => bad(&other),
            };
        }
        match (ty.base.as_str(), v) {
            ("num" | "dnum" | "intnum", V::Num(n)) => Ok(V::Num(n)),
            ("bool", V::Bool(b)) => Ok(V::Bool(b)),
            ("string", V::Str(s)) => Ok(V::Str(s)),
            ("triggdata", V::Trigg(t)) => Ok(V::Trigg(t)),
            (t, V::Rec(u, f)) if t == u => Ok(V::Rec(u, f)),
            (t, V::Agg(items)) if self.records.contains_key(t) => {
                let fields = &self.records[t];
                if items.len() != fields.len() {
                    return Err(format!(
                        "an aggregate of {} where a {t} ({} components) is expected",
                        items.len(),
                        fields.len()
                    ));
                }
                let v = items
                    .into_iter()
                    .zip(fields)
                    .map(|(x, (_, f))| self.coerce(x, &Ty::scalar(f)))
                    .collect::<Result<_, _>>()?;
                Ok(V::Rec(t.to_string(), v))
            }
            (_, other) => bad(&other),
        }
    }
}

pub fn show(ty: &Ty) -> String {
    if ty.dims.is_empty() {
        ty.base.clone()
    } else {
        let d: Vec<String> = ty.dims.iter().map(ToString::to_string).collect();
        format!("{}{{{}}}", ty.base, d.join(","))
    }
}

/// The speeddata sizes RAPID predefines (`vN`: v_tcp N mm/s).
pub const SPEEDS: [u32; 25] = [
    5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000, 1500, 2000, 2500,
    3000, 4000, 5000, 6000, 7000,
];
/// The zonedata sizes RAPID predefines (`zN`: pzone_tcp N mm).
pub const ZONES: [u32; 14] = [0, 1, 5, 10, 15, 20, 30, 40, 50, 60, 80, 100, 150, 200];

/// The predefined data (name, type, value) with `vmax.v_tcp` = `vmax` mm/s. Orientation,
/// external-axis speeds and zone sizes other than pzone_tcp follow the reference's [?] values:
/// no comparison reads them.
pub fn predefined(vmax: f64) -> Vec<(String, &'static str, V)> {
    let n = V::Num;
    let pose0 = || {
        V::Agg(vec![
            V::Agg(vec![n(0.0), n(0.0), n(0.0)]),
            V::Agg(vec![n(1.0), n(0.0), n(0.0), n(0.0)]),
        ])
    };
    let load = |m: f64| {
        V::Agg(vec![
            n(m),
            V::Agg(vec![n(0.0), n(0.0), n(0.001)]),
            V::Agg(vec![n(1.0), n(0.0), n(0.0), n(0.0)]),
            n(0.0),
            n(0.0),
            n(0.0),
        ])
    };
    let mut out = vec![
        (
            "tool0".to_string(),
            "tooldata",
            V::Agg(vec![V::Bool(true), pose0(), load(0.001)]),
        ),
        (
            "wobj0".to_string(),
            "wobjdata",
            V::Agg(vec![
                V::Bool(false),
                V::Bool(true),
                V::Str(String::new()),
                pose0(),
                pose0(),
            ]),
        ),
        ("load0".to_string(), "loaddata", load(0.001)),
        (
            "fine".to_string(),
            "zonedata",
            V::Agg(vec![
                V::Bool(true),
                n(0.0),
                n(0.0),
                n(0.0),
                n(0.0),
                n(0.0),
                n(0.0),
            ]),
        ),
        ("high".to_string(), "num", n(1.0)),
        ("low".to_string(), "num", n(0.0)),
        ("edge".to_string(), "num", n(2.0)),
        ("pi".to_string(), "num", n(std::f64::consts::PI)),
    ];
    let speed = |v: f64| V::Agg(vec![n(v), n(500.0), n(5000.0), n(1000.0)]);
    for s in SPEEDS {
        out.push((format!("v{s}"), "speeddata", speed(f64::from(s))));
    }
    out.push(("vmax".to_string(), "speeddata", speed(vmax)));
    for z in ZONES {
        let d = if z == 0 { 0.3 } else { f64::from(z) };
        out.push((
            format!("z{z}"),
            "zonedata",
            V::Agg(vec![
                V::Bool(false),
                n(d),
                n(1.5 * d),
                n(1.5 * d),
                n(0.15 * d),
                n(1.5 * d),
                n(0.15 * d),
            ]),
        ));
    }
    out
}
