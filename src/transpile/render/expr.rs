//! Expressions with explicit parentheses, as AS and RAPID write them: every rendered operand
//! knows how tightly it binds, and an infix operator puts parentheses exactly where its
//! operands need them.

/// Binding strengths, loosest last.
pub const ATOM: u8 = 10;
pub const UNARY: u8 = 8;
pub const MUL: u8 = 7;
pub const ADD: u8 = 6;
pub const CMP: u8 = 4;
pub const LOGIC: u8 = 2;
/// A unary result that is parenthesised as any operand (RAPID's `NOT`, and a sign after an
/// operator).
pub const LOOSE_UNARY: u8 = 1;

/// A rendered expression and how tightly it binds.
pub struct Rendered {
    pub text: String,
    pub prec: u8,
    /// The operator, for chains of the same operator that need no parentheses.
    pub op: Option<&'static str>,
}

impl Rendered {
    pub fn atom(text: String) -> Rendered {
        Rendered {
            text,
            prec: ATOM,
            op: None,
        }
    }

    /// A result of `prec` without an operator to chain.
    pub fn of(text: String, prec: u8) -> Rendered {
        Rendered {
            text,
            prec,
            op: None,
        }
    }

    /// `NOT x`, `-x` binding as `prec` (`UNARY`, or `LOOSE_UNARY` where the target
    /// parenthesises it as an operand): the operand in parentheses unless it binds tighter.
    pub fn prefix(sym: &str, inner: Rendered, prec: u8) -> Rendered {
        let text = if inner.prec < UNARY {
            format!("{sym}({})", inner.text)
        } else {
            format!("{sym}{}", inner.text)
        };
        Rendered::of(text, prec)
    }

    /// `l sym r` binding as `prec`: arithmetic is left-associative (`a - b + c` needs no
    /// parentheses, `a - (b + c)` does), a comparison's operands are arithmetic, and a logic
    /// operator chains only with itself.
    pub fn infix(sym: &'static str, prec: u8, l: Rendered, r: Rendered) -> Rendered {
        let side = |c: Rendered, right: bool| -> String {
            let paren = if prec >= ADD {
                c.prec < prec || (c.prec == prec && right)
            } else if prec == CMP {
                c.prec < ADD
            } else {
                c.prec < UNARY && (right || c.op != Some(sym))
            };
            if paren {
                format!("({})", c.text)
            } else {
                c.text
            }
        };
        let text = format!("{} {sym} {}", side(l, false), side(r, true));
        Rendered {
            text,
            prec,
            op: Some(sym),
        }
    }
}
