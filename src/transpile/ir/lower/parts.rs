//! Which parts of a value the target reads or assigns alone (`Caps::components`): pose and
//! axis components, one character of a string, rows of a CHAR array. Decided here once, so no
//! renderer refuses a place it cannot write.

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::transpile::ir::why::{Part, Reach};
use crate::transpile::ir::{Place, Ty, Why};

impl Lower<'_> {
    /// `p` used so at `at`.
    pub(super) fn reachable(&self, p: &Place, reach: Reach, at: Span) -> L<()> {
        let parts = &self.caps.components;
        match p {
            Place::Var(_) | Place::Temp(_) => Ok(()),
            Place::Component(base, c) => {
                if !parts.of(*c).allows(reach) {
                    return fail(
                        Why::Part {
                            part: Part::Component(*c),
                            reach,
                        },
                        at,
                    );
                }
                self.reachable(base, reach, at)
            }
            Place::Index(base, idx) => {
                let string = matches!(&**base, Place::Var(v) if self.var_decl(*v).ty == Ty::Char);
                if string {
                    match idx.as_slice() {
                        [None] | [] => {}
                        [Some(_)] if !parts.characters.allows(reach) => {
                            return fail(
                                Why::Part {
                                    part: Part::Character,
                                    reach,
                                },
                                at,
                            );
                        }
                        [Some(_)] => {}
                        _ if !parts.char_rows => return fail(Why::CharRows, at),
                        _ => {}
                    }
                }
                self.reachable(base, reach, at)
            }
            Place::Member(base, _) => self.reachable(base, reach, at),
        }
    }
}
