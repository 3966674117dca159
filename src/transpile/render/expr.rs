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
        let paren = inner.prec < UNARY;
        let mut text = String::with_capacity(sym.len() + inner.text.len() + 2);
        text.push_str(sym);
        push_operand(&mut text, &inner.text, paren);
        Rendered::of(text, prec)
    }

    /// `l sym r` binding as `prec`: arithmetic is left-associative (`a - b + c` needs no
    /// parentheses, `a - (b + c)` does), a comparison's operands are arithmetic, and a logic
    /// operator chains only with itself.
    pub fn infix(sym: &'static str, prec: u8, l: Rendered, r: Rendered) -> Rendered {
        let paren = |c: &Rendered, right: bool| -> bool {
            if prec >= ADD {
                c.prec < prec || (c.prec == prec && right)
            } else if prec == CMP {
                c.prec < ADD
            } else {
                c.prec < UNARY && (right || c.op != Some(sym))
            }
        };
        let (pl, pr) = (paren(&l, false), paren(&r, true));
        // Written in place into the left operand's text when it needs no parentheses.
        let mut text = if pl {
            let mut t = String::with_capacity(l.text.len() + sym.len() + r.text.len() + 6);
            push_operand(&mut t, &l.text, true);
            t
        } else {
            let mut t = l.text;
            t.reserve(sym.len() + r.text.len() + 4);
            t
        };
        text.push(' ');
        text.push_str(sym);
        text.push(' ');
        push_operand(&mut text, &r.text, pr);
        Rendered {
            text,
            prec,
            op: Some(sym),
        }
    }
}

/// `operand`, in parentheses when `paren`, at the end of `text`.
fn push_operand(text: &mut String, operand: &str, paren: bool) {
    if paren {
        text.push('(');
        text.push_str(operand);
        text.push(')');
    } else {
        text.push_str(operand);
    }
}
