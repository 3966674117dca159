//! How the program may select its tool and base (`Caps::frames`): decided here once, so no
//! renderer refuses a frame it cannot name.

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::transpile::ir::{FrameKind, FrameRef, Why};

impl Lower<'_> {
    /// `$TOOL`/`$BASE` (`which`) set to `frame` at `span`.
    pub(super) fn held_frame(&self, which: FrameKind, frame: &FrameRef, span: Span) -> L<()> {
        let f = &self.caps.frames;
        match frame {
            FrameRef::Value(_) if !f.values => fail(
                Why::FrameValue {
                    tool: which == FrameKind::Tool,
                },
                span,
            ),
            FrameRef::Table(i) if !f.computed_numbers => match i.integer() {
                None => fail(Why::FrameNumber, i.span),
                Some(n) if n < 1 => fail(Why::FrameNegative(n), i.span),
                Some(_) => Ok(()),
            },
            _ => Ok(()),
        }
    }
}
