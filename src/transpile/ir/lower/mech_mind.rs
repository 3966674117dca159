//! Which `MM_*` calls the target translates, with which arguments given
//! (`Caps::mech_mind`): decided here once, so no renderer refuses a call of the interface.

use super::{L, Lower, fail};
use crate::catalog::{Subprogram, catalog};
use crate::diag::Span;
use crate::syntax::ast::{self, StmtKind};
use crate::transpile::ir::Why;
use crate::transpile::render::MechMind;

impl Lower<'_> {
    /// A call of `sub` with `args` (`None`: omitted), refused where the target has nothing for
    /// it or the translation reads an omitted argument.
    pub(super) fn mm_held(
        &self,
        sub: &'static Subprogram,
        args: &[Option<ast::Expr>],
        span: Span,
    ) -> L<()> {
        let robot = self.caps.robot;
        let name = || sub.name.clone();
        let reads: Vec<&str> = match self.caps.mech_mind {
            MechMind::Absent => {
                return fail(
                    Why::MmInterface {
                        name: name(),
                        robot,
                    },
                    span,
                );
            }
            MechMind::Client if sub.shape.moves() => {
                return fail(Why::MmMoves(name()), span);
            }
            MechMind::Client => match &sub.client_reads {
                Some(params) => params.iter().map(String::as_str).collect(),
                None => sub.params.iter().map(|p| p.ident()).collect(),
            },
            MechMind::Commands => match catalog().kawasaki_computed(&sub.name) {
                Some(c) => c.reads.iter().map(String::as_str).collect(),
                None => match sub.kawasaki() {
                    Some(k) => k.params.iter().filter_map(|p| p.kuka.as_deref()).collect(),
                    None => {
                        return fail(
                            Why::MmNoCommand {
                                name: name(),
                                robot,
                            },
                            span,
                        );
                    }
                },
            },
        };
        for p in reads {
            let omitted = sub
                .params
                .iter()
                .position(|q| q.ident().eq_ignore_ascii_case(p))
                .is_some_and(|i| args.get(i).is_some_and(Option::is_none));
            if omitted {
                return fail(Why::MmArgument(p.to_owned()), span);
            }
        }
        Ok(())
    }

    /// Whether statement `s`, refused, is a motion for the flow (an advance-run stop after it
    /// stays): a motion, or a call of an `MM_*` routine that moves the robot.
    pub(super) fn refused_moves(&self, s: &ast::Stmt) -> bool {
        match &s.kind {
            StmtKind::Motion(_) => true,
            StmtKind::Call { name, .. } => {
                crate::catalog::has_interface_prefix(&name.key())
                    && self.routine_named(&name.text).is_none()
                    && catalog()
                        .subprogram(&name.text)
                        .is_some_and(|sub| sub.shape.moves())
            }
            _ => false,
        }
    }
}
