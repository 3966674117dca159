//! Types: the primitive types, STRUCs and ENUMs (built-in or declared), arrays of them, and what
//! may be assigned to what.

use super::ids::{Loc, NameId, TypeId};
use super::scope::Scope;

/// The type of a value, a declaration or an expression. Arrays keep their element type and the
/// number of dimensions (the sizes live on the declaration).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Ty {
    pub kind: TyKind,
    /// Array dimensions; 0 for a scalar.
    pub dims: u8,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TyKind {
    Int,
    Real,
    Bool,
    Char,
    /// A string literal of this many bytes (assignable to CHAR arrays).
    Str(u32),
    Struc(TypeId),
    Enum(TypeId),
    /// `#VALUE` whose ENUM is not known from the context.
    EnumLit(NameId),
    /// `{X 1, Y 2}` without a type name: fits any STRUC.
    Aggregate,
    /// Not known (an unresolved name, an expression the model does not type): never judged.
    Unknown,
}

impl Ty {
    pub const UNKNOWN: Ty = Ty::scalar(TyKind::Unknown);
    pub const INT: Ty = Ty::scalar(TyKind::Int);
    pub const REAL: Ty = Ty::scalar(TyKind::Real);
    pub const BOOL: Ty = Ty::scalar(TyKind::Bool);
    pub const CHAR: Ty = Ty::scalar(TyKind::Char);

    pub const fn scalar(kind: TyKind) -> Ty {
        Ty { kind, dims: 0 }
    }

    pub fn array(kind: TyKind, dims: u8) -> Ty {
        Ty { kind, dims }
    }

    pub fn is_unknown(self) -> bool {
        self.kind == TyKind::Unknown
    }

    pub fn is_array(self) -> bool {
        self.dims > 0
    }

    /// The element type of one index step (`a[i]` of `a[,]` is still an array of one dimension).
    pub fn index(self, n: usize) -> Ty {
        if self.dims == 0 {
            // Indexing a CHAR scalar or a STRUC: not something the model types.
            return Ty::UNKNOWN;
        }
        Ty {
            kind: self.kind,
            dims: self.dims.saturating_sub(n.min(255) as u8),
        }
    }

    fn numeric(self) -> bool {
        self.dims == 0 && matches!(self.kind, TyKind::Int | TyKind::Real | TyKind::Char)
    }
}

/// One STRUC field.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    pub name: NameId,
    pub ty: Ty,
    /// Array sizes (0 where not a constant).
    pub sizes: Sizes,
    pub decl: Option<Loc>,
}

/// Array sizes of a declaration, up to three dimensions (0: not a literal).
pub type Sizes = [u32; 3];

#[derive(Debug, Clone, PartialEq)]
pub enum TypeDefKind {
    /// INT, REAL, BOOL or CHAR.
    Primitive,
    Struc(Vec<Field>),
    Enum(Vec<NameId>),
}

/// A type of the type table.
#[derive(Debug, Clone, PartialEq)]
pub struct TypeDef {
    pub name: NameId,
    pub kind: TypeDefKind,
    pub scope: Scope,
    pub decl: Option<Loc>,
    pub doc: Option<&'static str>,
    /// Taken from an entry of the KSS data marked unverified: rules do not judge it.
    pub unverified: bool,
}

/// Families of STRUCs that KRL converts into each other on assignment (missing fields stay):
/// 1 for the poses and frames, 2 for the axis types, 0 for the others.
pub fn family(upper_name: &str) -> u8 {
    match upper_name {
        "POS" | "E6POS" | "FRAME" | "E3POS" => 1,
        "AXIS" | "E6AXIS" | "E3AXIS" => 2,
        _ => 0,
    }
}

/// What [`assignable`] needs to know about declared types.
pub trait TypeFacts {
    /// [`family`] of the type's name.
    fn family(&self, id: TypeId) -> u8;
    /// Taken from an unverified entry of the KSS data: never judged.
    fn unverified(&self, id: TypeId) -> bool;
    /// Whether the ENUM has the value.
    fn enum_has(&self, id: TypeId, value: NameId) -> bool;
}

/// Whether a value of type `value` may be assigned to a place of type `target`, as far as the
/// model can tell: `Some(false)` only for a clear mismatch (a string to REAL, a pose to INT, an
/// ENUM value its type does not have), `None` when it cannot judge (unknown types, arrays).
pub fn assignable(target: Ty, value: Ty, facts: &impl TypeFacts) -> Option<bool> {
    use TyKind as K;
    if target.is_unknown() || value.is_unknown() {
        return None;
    }
    if target.dims > 0 {
        // A string literal fills a CHAR array; a single value never fills an array of numbers.
        return match value.kind {
            K::Str(_) if value.dims == 0 => Some(target.kind == K::Char && target.dims == 1),
            K::Int | K::Real | K::Bool | K::Aggregate | K::EnumLit(_)
                if value.dims == 0 && target.kind != K::Char =>
            {
                Some(false)
            }
            _ => None,
        };
    }
    if value.dims > 0 {
        return match target.kind {
            K::Int | K::Real | K::Bool | K::Struc(_) | K::Enum(_) if value.kind != K::Char => {
                Some(false)
            }
            _ => None,
        };
    }
    let unverified = |k: K| match k {
        K::Struc(id) | K::Enum(id) => facts.unverified(id),
        _ => false,
    };
    if unverified(target.kind) || unverified(value.kind) {
        return None;
    }
    Some(match (target.kind, value.kind) {
        (K::Int | K::Real | K::Char, _) if value.numeric() => true,
        (K::Char, K::Str(n)) => n <= 1,
        (K::Bool, K::Bool) => true,
        (K::Struc(a), K::Struc(b)) => {
            a == b || (facts.family(a) != 0 && facts.family(a) == facts.family(b))
        }
        (K::Struc(_), K::Aggregate) => true,
        (K::Enum(a), K::Enum(b)) => a == b,
        (K::Enum(e), K::EnumLit(v)) => facts.enum_has(e, v),
        _ => false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Facts;

    impl TypeFacts for Facts {
        fn family(&self, id: TypeId) -> u8 {
            family(["E6POS", "FRAME", "E6AXIS", "MYSTRUC", "MYENUM"][id.index()])
        }
        fn unverified(&self, _: TypeId) -> bool {
            false
        }
        fn enum_has(&self, _: TypeId, v: NameId) -> bool {
            v.0 == 1
        }
    }

    fn check(t: Ty, v: Ty) -> Option<bool> {
        assignable(t, v, &Facts)
    }

    #[test]
    fn numbers_convert_structs_do_not() {
        let e6pos = Ty::scalar(TyKind::Struc(TypeId(0)));
        let frame = Ty::scalar(TyKind::Struc(TypeId(1)));
        let e6axis = Ty::scalar(TyKind::Struc(TypeId(2)));
        let my = Ty::scalar(TyKind::Struc(TypeId(3)));
        let en = Ty::scalar(TyKind::Enum(TypeId(4)));
        assert_eq!(check(Ty::INT, Ty::REAL), Some(true));
        assert_eq!(check(Ty::REAL, Ty::CHAR), Some(true));
        assert_eq!(check(Ty::INT, e6pos), Some(false));
        assert_eq!(check(Ty::REAL, Ty::scalar(TyKind::Str(3))), Some(false));
        assert_eq!(check(Ty::BOOL, Ty::INT), Some(false));
        assert_eq!(check(e6pos, frame), Some(true));
        assert_eq!(check(e6pos, e6axis), Some(false));
        assert_eq!(check(my, Ty::scalar(TyKind::Aggregate)), Some(true));
        assert_eq!(check(my, e6pos), Some(false));
        assert_eq!(
            check(en, Ty::scalar(TyKind::EnumLit(NameId(1)))),
            Some(true)
        );
        assert_eq!(
            check(en, Ty::scalar(TyKind::EnumLit(NameId(2)))),
            Some(false)
        );
        assert_eq!(
            check(Ty::INT, Ty::scalar(TyKind::EnumLit(NameId(1)))),
            Some(false)
        );
        assert_eq!(
            check(Ty::array(TyKind::Char, 1), Ty::scalar(TyKind::Str(5))),
            Some(true)
        );
        assert_eq!(check(Ty::INT, Ty::UNKNOWN), None);
        assert_eq!(check(Ty::array(TyKind::Int, 1), Ty::INT), Some(false));
        assert_eq!(
            check(Ty::array(TyKind::Int, 1), Ty::array(TyKind::Int, 1)),
            None
        );
    }
}
