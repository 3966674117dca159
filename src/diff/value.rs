//! Data values as `diff` compares them: KRL aggregates read into fields, numbers compared as
//! numbers (`1.0` = `1.00000`), and the delta of a moved position, frame or axis value in the
//! robot's units. Orientation maths is [`crate::geom`]'s (one gimbal convention).

use serde::Serialize;

/// `{[TYPE:] NAME value, …}` → `(NAME upper case, value text)`; `None` if not an aggregate.
pub fn fields(value: &str) -> Option<Vec<(String, String)>> {
    let inner = value.trim().strip_prefix('{')?.strip_suffix('}')?;
    let inner = match inner.split_once(':') {
        Some((ty, rest)) if !ty.contains(['{', ',', '"']) => rest,
        _ => inner,
    };
    let mut out = Vec::new();
    for item in top_level(inner) {
        let item = item.trim();
        if item.is_empty() {
            continue;
        }
        let end = item
            .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '$'))
            .unwrap_or(item.len());
        out.push((
            item[..end].to_ascii_uppercase(),
            item[end..].trim().to_owned(),
        ));
    }
    Some(out)
}

/// Split at commas outside braces and strings.
fn top_level(s: &str) -> Vec<&str> {
    let (mut depth, mut in_str, mut start) = (0i32, false, 0);
    let mut out = Vec::new();
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_str = !in_str,
            '{' if !in_str => depth += 1,
            '}' if !in_str => depth -= 1,
            ',' if !in_str && depth == 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

fn number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok()
}

/// Whether two scalar or aggregate values are the same value (numbers as numbers, names and
/// keywords case-insensitive, nested aggregates field by field, field order free).
pub fn same(a: &str, b: &str) -> bool {
    if let (Some(x), Some(y)) = (number(a), number(b)) {
        return x == y;
    }
    match (fields(a), fields(b)) {
        (Some(fa), Some(fb)) => {
            fa.len() == fb.len()
                && fa.iter().all(|(k, v)| {
                    fb.iter()
                        .find(|(k2, _)| k2 == k)
                        .is_some_and(|(_, w)| same(v, w))
                })
        }
        _ => super::krl::normalize(a) == super::krl::normalize(b),
    }
}

/// How a data value moved.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Delta {
    Cartesian(CartesianDelta),
    Axes(AxesDelta),
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CartesianDelta {
    pub dx: f64,
    pub dy: f64,
    pub dz: f64,
    pub distance_mm: f64,
    pub da: f64,
    pub db: f64,
    pub dc: f64,
    pub angle_deg: f64,
    /// `[old, new]` when the status changed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub s: Option<[String; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t: Option<[String; 2]>,
    /// External axes that moved, `de1` … (mm or deg, as the axis).
    #[serde(flatten)]
    pub external: std::collections::BTreeMap<String, f64>,
}

/// Joint deltas: `da1` … `da6`, `de1` … (deg, or mm for linear axes).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxesDelta {
    #[serde(flatten)]
    pub axes: std::collections::BTreeMap<String, f64>,
}

impl Delta {
    /// The size a list is sorted by: distance, else the largest angle.
    pub fn magnitude(&self) -> f64 {
        match self {
            Delta::Cartesian(c) => c.distance_mm.max(c.angle_deg),
            Delta::Axes(a) => a.axes.values().fold(0.0, |m, v| m.max(v.abs())),
        }
    }

    /// Whether the move is within `(mm, deg)` and nothing else (status, turn) changed.
    pub fn within(&self, mm: f64, deg: f64) -> bool {
        match self {
            Delta::Cartesian(c) => {
                c.s.is_none()
                    && c.t.is_none()
                    && c.distance_mm <= mm
                    && c.angle_deg <= deg
                    && c.external.values().all(|v| v.abs() <= mm.max(deg))
            }
            Delta::Axes(a) => a.axes.iter().all(|(k, v)| {
                let tol = if k.starts_with("de") {
                    mm.max(deg)
                } else {
                    deg
                };
                v.abs() <= tol
            }),
        }
    }
}

/// Rounded to 1e-6 (far below what a controller stores), so output carries no float noise.
fn r6(x: f64) -> f64 {
    let r = (x * 1e6).round() / 1e6;
    if r == 0.0 { 0.0 } else { r }
}

fn get(f: &[(String, String)], k: &str) -> Option<f64> {
    f.iter().find(|(n, _)| n == k).and_then(|(_, v)| number(v))
}

fn text(f: &[(String, String)], k: &str) -> Option<String> {
    f.iter()
        .find(|(n, _)| n == k)
        .map(|(_, v)| v.trim().to_owned())
}

const CARTESIAN: [&str; 3] = ["E6POS", "POS", "FRAME"];
const AXES: [&str; 2] = ["E6AXIS", "AXIS"];

/// The delta between two values of type `ty` (upper case; empty = infer from the fields), or
/// `None` for values that are not positions, frames, axes or loads.
pub fn delta(ty: &str, old: &str, new: &str) -> Option<Delta> {
    let (fo, fn_) = (fields(old)?, fields(new)?);
    let has = |k: &str| fo.iter().chain(&fn_).any(|(n, _)| n == k);
    if ty == "LOAD" || (ty.is_empty() && has("CM") && has("M")) {
        // A load moves by its centre of mass (the mass shows in old → new).
        let (co, cn) = (text(&fo, "CM")?, text(&fn_, "CM")?);
        return delta("FRAME", &co, &cn).filter(|d| d.magnitude() > 0.0);
    }
    let cartesian = CARTESIAN.contains(&ty) || (ty.is_empty() && has("X") && has("A"));
    let axes = AXES.contains(&ty) || (ty.is_empty() && has("A1"));
    if cartesian {
        let v = |f: &[(String, String)], k: &str| get(f, k).unwrap_or(0.0);
        let d = |k: &str| v(&fn_, k) - v(&fo, k);
        let (dx, dy, dz) = (d("X"), d("Y"), d("Z"));
        let angle = orientation_angle(
            [v(&fo, "A"), v(&fo, "B"), v(&fo, "C")],
            [v(&fn_, "A"), v(&fn_, "B"), v(&fn_, "C")],
        );
        let status = |k| {
            let (a, b) = (text(&fo, k), text(&fn_, k));
            (a.as_deref().map(number) != b.as_deref().map(number))
                .then(|| [a.unwrap_or_default(), b.unwrap_or_default()])
        };
        let external = (1..=6)
            .map(|i| format!("E{i}"))
            .filter(|k| d(k.as_str()) != 0.0)
            .map(|k| (format!("d{}", k.to_ascii_lowercase()), r6(d(&k))))
            .collect();
        return Some(Delta::Cartesian(CartesianDelta {
            dx: r6(dx),
            dy: r6(dy),
            dz: r6(dz),
            distance_mm: r6((dx * dx + dy * dy + dz * dz).sqrt()),
            da: r6(crate::geom::norm(d("A"))),
            db: r6(crate::geom::norm(d("B"))),
            dc: r6(crate::geom::norm(d("C"))),
            angle_deg: r6(angle),
            s: status("S"),
            t: status("T"),
            external,
        }));
    }
    if axes {
        let names = (1..=6)
            .map(|i| format!("A{i}"))
            .chain((1..=6).map(|i| format!("E{i}")));
        let axes = names
            .filter(|k| has(k))
            .map(|k| {
                let d = get(&fn_, &k).unwrap_or(0.0) - get(&fo, &k).unwrap_or(0.0);
                (format!("d{}", k.to_ascii_lowercase()), r6(d))
            })
            .collect();
        return Some(Delta::Axes(AxesDelta { axes }));
    }
    None
}

/// `X, Y, Z, A, B, C` of a position or frame value (missing fields 0); `None` if it has no X.
pub fn xyzabc(value: &str) -> Option<[f64; 6]> {
    let f = fields(value)?;
    get(&f, "X")?;
    Some(["X", "Y", "Z", "A", "B", "C"].map(|k| get(&f, k).unwrap_or(0.0)))
}

/// The angle between two KUKA A, B, C orientations (degrees, from rotation matrices: wraps
/// and the gimbal case give the true angle). The one call into the orientation maths.
pub fn orientation_angle(old: [f64; 3], new: [f64; 3]) -> f64 {
    let a = crate::geom::abc_to_matrix(old[0], old[1], old[2]);
    let b = crate::geom::abc_to_matrix(new[0], new[1], new[2]);
    crate::geom::rotation_angle(&a, &b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_fields_with_type_prefix_and_nesting() {
        let f = fields("{LOAD: M 5,CM {X 1,Y 0,Z 2,A 0,B 0,C 0},J {X 0,Y 0,Z 0}}").expect("agg");
        assert_eq!(f[0], ("M".into(), "5".into()));
        assert_eq!(f[1].0, "CM");
        assert!(fields("5").is_none());
    }

    #[test]
    fn numbers_compare_as_numbers() {
        assert!(same("{X 1.0,Y 2}", "{x 1.000, y 2.0}"));
        assert!(!same("{X 1.0,Y 2}", "{X 1.5,Y 2}"));
        assert!(same("#ON", "#on"));
    }

    #[test]
    fn a_wrapped_angle_is_no_rotation() {
        let Some(Delta::Cartesian(d)) = delta(
            "E6POS",
            "{X 0,Y 0,Z 0,A 179,B 0,C 0,S 2,T 3}",
            "{X 3,Y 4,Z 0,A -179,B 0,C 0,S 2,T 10}",
        ) else {
            panic!("cartesian delta")
        };
        assert_eq!(d.distance_mm, 5.0);
        assert_eq!(d.da, 2.0);
        assert!((d.angle_deg - 2.0).abs() < 1e-6);
        assert_eq!(d.t, Some(["3".into(), "10".into()]));
    }

    #[test]
    fn joint_deltas_per_axis() {
        let Some(Delta::Axes(d)) = delta("", "{A1 0,A2 -90,E1 0}", "{A1 10,A2 -90,E1 5}") else {
            panic!("axes delta")
        };
        assert_eq!(d.axes["da1"], 10.0);
        assert_eq!(d.axes["de1"], 5.0);
        assert!(!Delta::Axes(d).within(1.0, 1.0));
    }
}
