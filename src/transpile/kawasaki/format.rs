//! How AS spells values: numbers, sigils, pose and joint literals.

use crate::transpile::ir::Ty;

pub use crate::transpile::front::literal::num;

/// An angle computed by a conversion: rounded to 1e-6 degrees so float dust does not show.
pub fn angle(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    num(if r == 0.0 { 0.0 } else { r })
}

/// The sigil of a type in statements: `#` joints, `$` strings, none otherwise.
pub fn sigil(ty: &Ty) -> &'static str {
    match ty {
        Ty::Joint => "#",
        Ty::Char => "$",
        _ => "",
    }
}

/// `name` (possibly `.name`) with its type sigil, as statements write it: `.#j`, `$s`, `p`.
pub fn with_sigil(name: &str, ty: &Ty) -> String {
    let s = sigil(ty);
    match name.strip_prefix('.') {
        Some(bare) => format!(".{s}{bare}"),
        None => format!("{s}{name}"),
    }
}

/// `name` as a parameter in a `.PROGRAM` header or a `CALL` argument: poses get `&`.
pub fn param_sigil(name: &str, ty: &Ty) -> String {
    let s = parameter_sigil(ty);
    match name.strip_prefix('.') {
        Some(bare) => format!(".{s}{bare}"),
        None => format!("{s}{name}"),
    }
}

/// The sigil of a type as a parameter: `&` poses (passed by reference), else [`sigil`]'s.
pub fn parameter_sigil(ty: &Ty) -> &'static str {
    match ty {
        Ty::Pose => "&",
        _ => sigil(ty),
    }
}

/// `to = from` for a value of type `ty` (poses and joints need `POINT`).
pub fn copy_stmt(to: &str, from: &str, ty: &Ty) -> String {
    let (t, f) = (with_sigil(to, ty), with_sigil(from, ty));
    match ty {
        Ty::Pose | Ty::Joint => format!("POINT {t} = {f}"),
        _ => format!("{t} = {f}"),
    }
}

/// The text with every non-ASCII character replaced by `?`: the `.as` file is ASCII.
pub fn ascii(s: &str) -> std::borrow::Cow<'_, str> {
    if s.is_ascii() {
        return std::borrow::Cow::Borrowed(s);
    }
    std::borrow::Cow::Owned(
        s.chars()
            .map(|c| if c.is_ascii() { c } else { '?' })
            .collect(),
    )
}

/// `"text"` for AS (KRL strings cannot contain `"`).
pub fn string(s: &str) -> String {
    format!("\"{s}\"")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(num(3.0), "3");
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(-12.25), "-12.25");
        assert_eq!(angle(179.99999999999997), "180");
        assert_eq!(angle(-1e-12), "0");
    }

    #[test]
    fn ascii_only() {
        assert_eq!(ascii("abc"), "abc");
        assert_eq!(ascii("Stör ü"), "St?r ?");
    }

    #[test]
    fn sigils() {
        assert_eq!(with_sigil(".j", &Ty::Joint), ".#j");
        assert_eq!(with_sigil("s", &Ty::Char), "$s");
        assert_eq!(param_sigil(".p", &Ty::Pose), ".&p");
        assert_eq!(param_sigil("p", &Ty::Pose), "&p");
        assert_eq!(copy_stmt(".a", ".a_in", &Ty::Joint), "POINT .#a = .#a_in");
    }
}
