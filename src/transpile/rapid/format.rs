//! How RAPID spells values: numbers, strings, types, robtarget and jointtarget literals.

use crate::geom::{abc_to_matrix, matrix_to_quaternion};
use crate::transpile::ir::Ty;

pub use crate::transpile::front::literal::num;

/// What the output relies on without a primary source (`abb-rapid.md` [?] facts); listed in
/// every module's header and in README.
pub const ASSUMED: [&str; 3] = [
    "KRL FOR/REPEAT become WHILE loops; vN/zN are the predefined speeds (N mm/s) and zones (N mm)",
    "PTP speeds (% of the axes' maximum) are written as that % of vmax's TCP speed",
    "confdata [0,0,0,0] with ConfJ/ConfL \\Off: the controller picks the arm configuration",
];

/// The external axes of a target that has none.
pub const NO_EXTAX: &str = "[9E9,9E9,9E9,9E9,9E9,9E9]";

/// The RAPID type of a KRL type (`dims`: a CHAR array's length counts as one dimension).
pub fn type_name(ty: &Ty, dims: usize) -> std::borrow::Cow<'static, str> {
    let _ = dims;
    match ty {
        Ty::Int | Ty::Real | Ty::Enum(_) => "num".into(),
        Ty::Bool => "bool".into(),
        Ty::Char => "string".into(),
        Ty::Pose => "robtarget".into(),
        Ty::Joint => "jointtarget".into(),
        Ty::Struc(t) => record_name(t).into(),
        // The lowering refuses values no target holds; a signal is never declared.
        Ty::Other(_) | Ty::Signal(_) => "num".into(),
    }
}

/// A RECORD's name: the STRUC's name as a RAPID identifier (type names are no data or routine
/// names, so they do not clash with them).
pub fn record_name(krl: &str) -> String {
    crate::transpile::front::names::target_name(krl, &super::NAME_RULES).0
}

/// A RECORD component's name: the STRUC field's name as a RAPID identifier.
pub fn field_name(krl: &str) -> String {
    crate::transpile::front::names::target_name(krl, &super::NAME_RULES).0
}

/// A type's zero value, for array aggregates with elements the `.dat` does not give.
pub fn zero(ty: &Ty) -> String {
    match ty {
        Ty::Bool => "FALSE".into(),
        Ty::Char => "\"\"".into(),
        Ty::Pose => format!("[[0,0,0],[1,0,0,0],[0,0,0,0],{NO_EXTAX}]"),
        Ty::Joint => format!("[[0,0,0,0,0,0],{NO_EXTAX}]"),
        _ => "0".into(),
    }
}

/// A string literal: `"` doubled, `\` doubled.
pub fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\"\""),
            '\\' => out.push_str("\\\\"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A quaternion component: 7 decimals, trailing zeros trimmed.
pub fn quat(v: f64) -> String {
    let r = (v * 1e7).round() / 1e7;
    num(if r == 0.0 { 0.0 } else { r })
}

/// KUKA A, B, C (degrees) as RAPID's `[q1,q2,q3,q4]`.
pub fn orient(a: f64, b: f64, c: f64) -> String {
    let q = matrix_to_quaternion(&abc_to_matrix(a, b, c));
    format!(
        "[{},{},{},{}]",
        quat(q[0]),
        quat(q[1]),
        quat(q[2]),
        quat(q[3])
    )
}

/// The module's name: the file's stem as a RAPID identifier.
pub fn module_name(path: &str) -> String {
    let stem = std::path::Path::new(path)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("program");
    let (n, _) = crate::transpile::front::names::target_name(stem, &super::NAME_RULES);
    let n = &n[..n.len().min(28)];
    format!("{n}_mod")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternions_as_the_reference_computes_them() {
        assert_eq!(orient(0.0, 0.0, 0.0), "[1,0,0,0]");
        assert_eq!(orient(90.0, 0.0, 0.0), "[0.7071068,0,0,0.7071068]");
        assert_eq!(orient(0.0, 0.0, 180.0), "[0,1,0,0]");
        assert_eq!(
            orient(-90.0, 30.0, 180.0),
            "[0.1830127,-0.6830127,0.6830127,0.1830127]"
        );
        assert_eq!(
            orient(15.0, 20.0, -170.0),
            "[0.062518,-0.9746426,-0.1130491,0.1827107]"
        );
    }

    #[test]
    fn strings_escape_quotes_and_backslashes() {
        assert_eq!(string("a\"b\\c"), "\"a\"\"b\\\\c\"");
    }
}
