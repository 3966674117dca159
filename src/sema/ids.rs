//! Ids: everything in the model is addressed by a small integer, never by a string.

use crate::diag::Span;

macro_rules! id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub u32);

        impl $name {
            /// The position in the model's table of these.
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    };
}

id!(
    /// A file of the workspace (its position in the input order).
    FileId
);
id!(
    /// A module: the `.src`/`.sub` and `.dat` of one name in one folder.
    ModuleId
);
id!(
    /// A DEF or DEFFCT of the workspace.
    RoutineId
);
id!(
    /// A declared name: variable, constant, parameter, SIGNAL, IMPORT, CHANNEL or system variable.
    SymbolId
);
id!(
    /// A type: INT, REAL, BOOL, CHAR, or a STRUC/ENUM (built-in or declared).
    TypeId
);
id!(
    /// An interned, case-insensitive name (see [`super::Names`]).
    NameId
);
id!(
    /// An EXT/EXTFCT declaration.
    ExtId
);
id!(
    /// A built-in function or subprogram of the KSS environment.
    BuiltinId
);
id!(
    /// One robot of the workspace: the files that share one `$config.dat` and one global scope.
    RobotId
);

/// A place in a file: what "go to definition" jumps to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Loc {
    pub file: FileId,
    pub span: Span,
}
