//! One line of code → CST node, via the pest grammar in `krl.pest`.
//!
//! pest pairs are mapped into our own tree here and nowhere else. Bytes that pest skips (blanks,
//! literal punctuation, keywords written inline) are re-lexed as tokens by [`gap_tokens`], which
//! is what keeps the tree lossless without spelling every comma as a grammar rule.

use std::cell::RefCell;
use std::sync::LazyLock;

use pest::Parser;
use pest::iterators::{Pair, Pairs};
use pest::pratt_parser::{Assoc, Op, PrattParser};

use super::build::Builder;
use super::cst::{Child, NodeKind, TokenKind};
use crate::diag::Span;

#[derive(pest_derive::Parser)]
#[grammar = "syntax/krl.pest"]
struct KrlGrammar;

/// A line that did not parse: where and why.
pub(crate) struct LineError {
    /// Byte offset in the file text.
    pub at: usize,
    pub len: usize,
    pub message: String,
}

/// Parse `text[start..end]` (code only: no leading/trailing blanks, no comment, no newline).
/// On success the statement's children are left pending on the builder's stack (its gaps not yet
/// filled) and its kind is returned; on failure nothing is left.
pub(crate) fn parse_code(b: &mut Builder, start: usize, end: usize) -> Result<NodeKind, LineError> {
    let text = b.text;
    // The fast path enforces the same nesting and sign-run limits itself; only a line longer
    // than MAX_OPERATORS bytes can hit the operator limit, so only such lines are pre-checked
    // first. Either way both paths accept exactly the same lines.
    let long = end - start > MAX_OPERATORS;
    if long && let Some(err) = too_deep(&text[start..end], start) {
        return Err(err);
    }
    if let Some(kind) = super::fast::parse(b, start, end) {
        return Ok(kind);
    }
    if !long && let Some(err) = too_deep(&text[start..end], start) {
        return Err(err);
    }
    parse_with_grammar(b, start, end)
}

/// The grammar alone (the fast path must agree with it wherever it answers).
/// Like [`parse_code`], children pending on success.
pub(crate) fn parse_with_grammar(
    b: &mut Builder,
    start: usize,
    end: usize,
) -> Result<NodeKind, LineError> {
    static BUDGET: std::sync::Once = std::sync::Once::new();
    BUDGET.call_once(|| pest::set_call_limit(std::num::NonZeroUsize::new(MAX_GRAMMAR_CALLS)));
    let text = b.text;
    let code = &text[start..end];
    match KrlGrammar::parse(entry_rule(code), code) {
        Ok(mut pairs) => {
            let line = pairs.next();
            let stmt = line.and_then(|l| l.into_inner().find(|p| p.as_rule() != Rule::EOI));
            match stmt.map(|p| (classify(p.as_rule()), p)) {
                Some((Class::Node(kind), p)) => {
                    let ctx = Ctx {
                        text,
                        base: start,
                        b: RefCell::new(b),
                    };
                    for inner in p.into_inner() {
                        convert(inner, &ctx);
                    }
                    Ok(kind)
                }
                _ => Err(LineError {
                    at: start,
                    len: end - start,
                    message: "expected a statement".into(),
                }),
            }
        }
        Err(e) => Err(global_decl(code, start).unwrap_or_else(|| describe(e, code, start))),
    }
}

/// `GLOBAL DECL …` is a common slip for `DECL GLOBAL …`; say so instead of pest's message.
fn global_decl(code: &str, base: usize) -> Option<LineError> {
    let mut words = code.split_whitespace();
    let first = words.next()?;
    let second = words.next()?;
    if !(first.eq_ignore_ascii_case("GLOBAL") && second.eq_ignore_ascii_case("DECL")) {
        return None;
    }
    let at = code[first.len()..].find(second)? + first.len();
    Some(LineError {
        at: base + at,
        len: second.len(),
        message: "`GLOBAL DECL` is not KRL: write `DECL GLOBAL`".into(),
    })
}

/// The cheapest grammar entry that can accept this line (always a subset of `line`).
fn entry_rule(code: &str) -> Rule {
    let bytes = code.as_bytes();
    if bytes.first() == Some(&b'$') {
        return Rule::line_ident;
    }
    if !bytes
        .first()
        .is_some_and(|b| b.is_ascii_alphabetic() || *b == b'_')
    {
        return Rule::line;
    }
    let len = bytes
        .iter()
        .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_' || **c == b'$')
        .count();
    let word = &code[..len];
    if word.eq_ignore_ascii_case("DECL") {
        Rule::line_decl
    } else if len > super::words::MAX_LEN {
        Rule::line
    } else {
        match super::words::roles(word.as_bytes()) {
            Some(r) if r & super::words::KW_LED != 0 => Rule::line_kw,
            Some(r) if r & super::words::STATEMENT != 0 => Rule::line,
            _ => Rule::line_ident,
        }
    }
}

/// Limits that keep recursion (pest, Pratt, tree walks) far from the stack's end. pest runs
/// without its own stack probe (see Cargo.toml), so this check is what makes hostile input safe.
const MAX_NESTING: usize = 64;
const MAX_PREFIX_RUN: usize = 64;
const MAX_OPERATORS: usize = 1024;
/// pest calls allowed for one line. Backtracking the grammar cannot rule out (nothing known is
/// worse than linear) stays bounded: a line that needs more is reported as too complex instead of
/// hanging. Real lines, 1,248-character aggregates included, need a small fraction of this.
const MAX_GRAMMAR_CALLS: usize = 2_000_000;

#[cfg(test)]
pub(crate) fn too_deep_for_tests(code: &str) -> bool {
    too_deep(code, 0).is_some()
}

fn too_deep(code: &str, base: usize) -> Option<LineError> {
    let bytes = code.as_bytes();
    let mut depth = 0usize;
    let mut prefix_run = 0usize;
    let mut operators = 0usize;
    let mut quote: Option<u8> = None;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if let Some(q) = quote {
            if b == q {
                quote = None;
            }
            i += 1;
            continue;
        }
        let word_len = bytes[i..]
            .iter()
            .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_' || **c == b'$')
            .count();
        let fail = |what: &str| {
            Some(LineError {
                at: base + i,
                len: 1,
                message: format!("{what}; split the expression"),
            })
        };
        match b {
            b'"' | b'\'' => quote = Some(b),
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return fail("brackets nested more than 64 deep");
                }
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        // Only words of 2..=6 ASCII letters can be operator keywords; compare without allocating.
        let mut upper = [0u8; 6];
        let word: &[u8] = if (2..=6).contains(&word_len) {
            for (u, c) in upper.iter_mut().zip(&bytes[i..i + word_len]) {
                *u = c.to_ascii_uppercase();
            }
            &upper[..word_len]
        } else {
            b""
        };
        let is_prefix = matches!(b, b'-' | b'+') || matches!(word, b"NOT" | b"B_NOT");
        let is_operator = is_prefix
            || matches!(b, b'*' | b'/' | b':' | b'<' | b'>' | b'=')
            || matches!(
                word,
                b"AND" | b"OR" | b"EXOR" | b"B_AND" | b"B_OR" | b"B_EXOR"
            );
        if is_operator {
            operators += 1;
            if operators > MAX_OPERATORS {
                return fail("more than 1024 operators on one line");
            }
        }
        if is_prefix {
            prefix_run += 1;
            if prefix_run > MAX_PREFIX_RUN {
                return fail("more than 64 signs or NOTs in a row");
            }
        } else if !matches!(b, b' ' | b'\t') {
            prefix_run = 0;
        }
        i += if word_len > 0 {
            word_len
        } else {
            code[i..].chars().next().map_or(1, char::len_utf8)
        };
    }
    None
}

/// Conversion state; the builder sits in a `RefCell` because pest's Pratt parser takes one
/// closure per operator class, all of which build.
struct Ctx<'t, 'b> {
    text: &'t str,
    base: usize,
    b: RefCell<&'b mut Builder<'t>>,
}

impl Ctx<'_, '_> {
    fn span(&self, pair: &Pair<Rule>) -> Span {
        let s = pair.as_span();
        Span::new(self.base + s.start(), self.base + s.end())
    }
}

enum Class {
    Node(NodeKind),
    Token(TokenKind),
    Expr,
}

fn classify(rule: Rule) -> Class {
    use Class::{Node as N, Token as T};
    match rule {
        Rule::expr => Class::Expr,
        Rule::def_line => N(NodeKind::DefLine),
        Rule::deffct_line => N(NodeKind::DeffctLine),
        Rule::param_list => N(NodeKind::ParamList),
        Rule::param => N(NodeKind::Param),
        Rule::end_line => N(NodeKind::EndLine),
        Rule::defdat_line => N(NodeKind::DefdatLine),
        Rule::enddat_line => N(NodeKind::EnddatLine),
        Rule::if_line => N(NodeKind::IfLine),
        Rule::else_line => N(NodeKind::ElseLine),
        Rule::endif_line => N(NodeKind::EndifLine),
        Rule::for_line => N(NodeKind::ForLine),
        Rule::endfor_line => N(NodeKind::EndforLine),
        Rule::while_line => N(NodeKind::WhileLine),
        Rule::endwhile_line => N(NodeKind::EndwhileLine),
        Rule::repeat_line => N(NodeKind::RepeatLine),
        Rule::until_line => N(NodeKind::UntilLine),
        Rule::loop_line => N(NodeKind::LoopLine),
        Rule::endloop_line => N(NodeKind::EndloopLine),
        Rule::switch_line => N(NodeKind::SwitchLine),
        Rule::case_line => N(NodeKind::CaseLine),
        Rule::default_line => N(NodeKind::DefaultLine),
        Rule::endswitch_line => N(NodeKind::EndswitchLine),
        Rule::spline_line => N(NodeKind::SplineLine),
        Rule::endspline_line => N(NodeKind::EndsplineLine),
        Rule::skip_line => N(NodeKind::SkipLine),
        Rule::endskip_line => N(NodeKind::EndskipLine),
        Rule::time_block_stmt => N(NodeKind::TimeBlockStmt),
        Rule::const_vel_stmt => N(NodeKind::ConstVelStmt),
        Rule::interrupt_decl => N(NodeKind::InterruptDecl),
        Rule::interrupt_ctl => N(NodeKind::InterruptCtl),
        Rule::trigger_stmt => N(NodeKind::TriggerStmt),
        Rule::motion_stmt => N(NodeKind::MotionStmt),
        Rule::with_clause => N(NodeKind::WithClause),
        Rule::with_item => N(NodeKind::WithItem),
        Rule::wait_for_stmt => N(NodeKind::WaitForStmt),
        Rule::wait_sec_stmt => N(NodeKind::WaitSecStmt),
        Rule::halt_stmt => N(NodeKind::HaltStmt),
        Rule::confirm_stmt => N(NodeKind::ConfirmStmt),
        Rule::brake_stmt => N(NodeKind::BrakeStmt),
        Rule::resume_stmt => N(NodeKind::ResumeStmt),
        Rule::return_stmt => N(NodeKind::ReturnStmt),
        Rule::continue_stmt => N(NodeKind::ContinueStmt),
        Rule::exit_stmt => N(NodeKind::ExitStmt),
        Rule::on_error_proceed_stmt => N(NodeKind::OnErrorProceedStmt),
        Rule::goto_stmt => N(NodeKind::GotoStmt),
        Rule::analog_stmt => N(NodeKind::AnalogStmt),
        Rule::analog_opt => N(NodeKind::AnalogOpt),
        Rule::move_emi_stmt => N(NodeKind::MoveEmiStmt),
        Rule::label_stmt => N(NodeKind::LabelStmt),
        Rule::call_stmt => N(NodeKind::CallStmt),
        Rule::assign_stmt => N(NodeKind::AssignStmt),
        Rule::decl_stmt => N(NodeKind::DeclStmt),
        Rule::type_ref => N(NodeKind::TypeRef),
        Rule::decl_var => N(NodeKind::DeclVar),
        Rule::dims => N(NodeKind::Dims),
        Rule::struc_decl => N(NodeKind::StrucDecl),
        Rule::struc_member => N(NodeKind::StrucMember),
        Rule::enum_decl => N(NodeKind::EnumDecl),
        Rule::signal_decl => N(NodeKind::SignalDecl),
        Rule::channel_decl => N(NodeKind::ChannelDecl),
        Rule::ext_decl => N(NodeKind::ExtDecl),
        Rule::ext_param => N(NodeKind::ExtParam),
        Rule::import_decl => N(NodeKind::ImportDecl),
        Rule::call => N(NodeKind::Call),
        Rule::paren => N(NodeKind::Paren),
        Rule::aggregate => N(NodeKind::Aggregate),
        Rule::agg_type => N(NodeKind::AggType),
        Rule::agg_field => N(NodeKind::AggField),
        Rule::index_suffix => N(NodeKind::Index),
        Rule::member_suffix => N(NodeKind::Member),
        Rule::ident => T(TokenKind::Ident),
        Rule::real => T(TokenKind::Real),
        Rule::int => T(TokenKind::Int),
        Rule::bits => T(TokenKind::Bits),
        Rule::hex => T(TokenKind::Hex),
        Rule::char_lit => T(TokenKind::Char),
        Rule::string => T(TokenKind::Str),
        Rule::enum_lit => T(TokenKind::EnumLit),
        Rule::bool_lit => T(TokenKind::Bool),
        Rule::import_path => T(TokenKind::ImportPath),
        Rule::op_not
        | Rule::op_bnot
        | Rule::op_neg
        | Rule::op_pos
        | Rule::op_geo
        | Rule::op_mul
        | Rule::op_div
        | Rule::op_add
        | Rule::op_sub
        | Rule::op_and
        | Rule::op_band
        | Rule::op_or
        | Rule::op_bor
        | Rule::op_exor
        | Rule::op_bexor
        | Rule::op_eq
        | Rule::op_ne
        | Rule::op_le
        | Rule::op_ge
        | Rule::op_lt
        | Rule::op_gt => T(TokenKind::Operator),
        // K_*, approx, motion_kw, param_dir
        _ => T(TokenKind::Keyword),
    }
}

/// Convert one pair and push it (one child) onto the builder's stack.
fn convert(pair: Pair<Rule>, ctx: &Ctx) {
    match classify(pair.as_rule()) {
        Class::Token(kind) => {
            let span = ctx.span(&pair);
            ctx.b
                .borrow_mut()
                .push(Child::Token(super::cst::Token { kind, span }));
        }
        Class::Node(kind) => {
            // Canonical form: nodes never end in blanks (pest's implicit whitespace before an
            // absent optional would otherwise end up inside the node); the parent re-lexes them.
            let span = tight(ctx.text, ctx.span(&pair));
            let mark = ctx.b.borrow().mark();
            for inner in pair.into_inner() {
                convert(inner, ctx);
            }
            let mut b = ctx.b.borrow_mut();
            let node = b.finish(mark, kind, span);
            b.push(node);
        }
        Class::Expr => expr(pair.into_inner(), ctx),
    }
}

/// An operator pair as a token.
fn operator(pair: &Pair<Rule>, ctx: &Ctx) -> Child {
    let kind = match classify(pair.as_rule()) {
        Class::Token(kind) => kind,
        _ => TokenKind::Operator,
    };
    Child::Token(super::cst::Token {
        kind,
        span: ctx.span(pair),
    })
}

/// KRL operator priority, highest first: `:`; NOT B_NOT (and unary signs); * /; + -;
/// AND B_AND; EXOR B_EXOR; OR B_OR; comparisons. Comparisons binding loosest follows the KSS 8
/// programming manual's priority table (unverified, marked [U] in the module docs).
static PRATT: LazyLock<PrattParser<Rule>> = LazyLock::new(|| {
    PrattParser::new()
        .op(Op::infix(Rule::op_eq, Assoc::Left)
            | Op::infix(Rule::op_ne, Assoc::Left)
            | Op::infix(Rule::op_le, Assoc::Left)
            | Op::infix(Rule::op_ge, Assoc::Left)
            | Op::infix(Rule::op_lt, Assoc::Left)
            | Op::infix(Rule::op_gt, Assoc::Left))
        .op(Op::infix(Rule::op_or, Assoc::Left) | Op::infix(Rule::op_bor, Assoc::Left))
        .op(Op::infix(Rule::op_exor, Assoc::Left) | Op::infix(Rule::op_bexor, Assoc::Left))
        .op(Op::infix(Rule::op_and, Assoc::Left) | Op::infix(Rule::op_band, Assoc::Left))
        .op(Op::infix(Rule::op_add, Assoc::Left) | Op::infix(Rule::op_sub, Assoc::Left))
        .op(Op::infix(Rule::op_mul, Assoc::Left) | Op::infix(Rule::op_div, Assoc::Left))
        .op(Op::prefix(Rule::op_not)
            | Op::prefix(Rule::op_bnot)
            | Op::prefix(Rule::op_neg)
            | Op::prefix(Rule::op_pos))
        .op(Op::infix(Rule::op_geo, Assoc::Left))
        .op(Op::postfix(Rule::index_suffix) | Op::postfix(Rule::member_suffix))
});

/// Every operand is exactly one child on top of the builder's stack when its operator is
/// applied (pest calls the primaries in text order), so combining pops the operands and pushes
/// the new node.
fn expr(pairs: Pairs<Rule>, ctx: &Ctx) {
    PRATT
        .map_primary(|p| convert(p, ctx))
        .map_prefix(|op, ()| {
            let op = operator(&op, ctx);
            let mut b = ctx.b.borrow_mut();
            let rhs = b.pop();
            let span = b.span_of(op).cover(b.span_of(rhs));
            let node = b.node(NodeKind::Unary, span, &[op, rhs]);
            b.push(node);
        })
        .map_infix(|(), op, ()| {
            let op = operator(&op, ctx);
            let mut b = ctx.b.borrow_mut();
            let rhs = b.pop();
            let lhs = b.pop();
            let span = b.span_of(lhs).cover(b.span_of(rhs));
            let node = b.node(NodeKind::Binary, span, &[lhs, op, rhs]);
            b.push(node);
        })
        .map_postfix(|(), op| {
            let kind = if op.as_rule() == Rule::member_suffix {
                NodeKind::Member
            } else {
                NodeKind::Index
            };
            let op_span = ctx.span(&op);
            let mark = {
                let b = ctx.b.borrow();
                b.mark() - 1
            };
            for p in op.into_inner() {
                convert(p, ctx);
            }
            let mut b = ctx.b.borrow_mut();
            let lhs = b.pending(mark)[0];
            let span = b.span_of(lhs).cover(op_span);
            let node = b.finish(mark, kind, span);
            b.push(node);
        })
        .parse(pairs)
}

fn tight(text: &str, span: Span) -> Span {
    let s = &text[span.range()];
    let trimmed = s.trim_end_matches([' ', '\t', '\u{0B}', '\u{0C}', '\u{A0}']);
    Span::new(span.start as usize, span.start as usize + trimmed.len())
}

fn describe(e: pest::error::Error<Rule>, code: &str, base: usize) -> LineError {
    let pos = match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    }
    .min(code.len());
    let rest = &code[pos..];
    let found_len = found_token_len(rest);
    let found = &rest[..found_len];
    let expected: Vec<&'static str> = match &e.variant {
        pest::error::ErrorVariant::ParsingError { positives, .. } => {
            let mut names: Vec<&'static str> = positives.iter().filter_map(|r| name(*r)).collect();
            names.sort_unstable();
            names.dedup();
            if names.contains(&"expression") {
                names.retain(|n| *n != "name" && *n != "operator");
            }
            names
        }
        pest::error::ErrorVariant::CustomError { message } => {
            if message.contains("limit") {
                return LineError {
                    at: base,
                    len: code.len(),
                    message: "line too complex to parse; split it".into(),
                };
            }
            Vec::new()
        }
    };
    let found_desc = if found.is_empty() {
        "end of line".to_string()
    } else {
        format!("`{found}`")
    };
    let message = if pos == 0 {
        format!("`{}` does not start a KRL statement", found)
    } else if !expected.is_empty() && expected.len() <= 4 {
        format!("expected {}, found {found_desc}", join_or(&expected))
    } else {
        format!("unexpected {found_desc}")
    };
    LineError {
        at: base + pos,
        len: found_len,
        message,
    }
}

fn found_token_len(rest: &str) -> usize {
    let ident = rest
        .bytes()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == b'_' || *c == b'$')
        .count();
    if ident > 0 {
        ident
    } else {
        rest.chars().next().map_or(0, char::len_utf8)
    }
}

fn join_or(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// Human names for the rules an error message may mention; `None` hides a rule.
fn name(rule: Rule) -> Option<&'static str> {
    Some(match rule {
        Rule::expr
        | Rule::real
        | Rule::int
        | Rule::bits
        | Rule::hex
        | Rule::char_lit
        | Rule::string
        | Rule::enum_lit
        | Rule::bool_lit
        | Rule::aggregate
        | Rule::call
        | Rule::paren
        | Rule::op_not
        | Rule::op_bnot
        | Rule::op_neg
        | Rule::op_pos => "expression",
        Rule::ident => "name",
        Rule::EOI => "end of line",
        Rule::op_geo
        | Rule::op_mul
        | Rule::op_div
        | Rule::op_add
        | Rule::op_sub
        | Rule::op_and
        | Rule::op_band
        | Rule::op_or
        | Rule::op_bor
        | Rule::op_exor
        | Rule::op_bexor
        | Rule::op_eq
        | Rule::op_ne
        | Rule::op_le
        | Rule::op_ge
        | Rule::op_lt
        | Rule::op_gt
        | Rule::index_suffix
        | Rule::member_suffix => "operator",
        Rule::K_THEN => "`THEN`",
        Rule::K_TO => "`TO`",
        Rule::K_DO => "`DO`",
        Rule::K_WHEN => "`WHEN`",
        Rule::K_DELAY => "`DELAY`",
        Rule::K_FOR => "`FOR`",
        Rule::K_SEC => "`SEC`",
        Rule::K_DECL => "`DECL`",
        Rule::param | Rule::param_list => "parameter",
        Rule::param_dir => "`IN` or `OUT`",
        Rule::type_ref => "type",
        Rule::decl_var => "variable name",
        Rule::with_clause => "`WITH`",
        Rule::approx => "approximation",
        Rule::agg_field => "aggregate field",
        _ => return None,
    })
}

#[cfg(test)]
mod entry_tests {
    use super::*;

    /// What `rule` alone makes of `code`: the tree, or only the fact that it failed.
    fn via(rule: Rule, code: &str) -> Option<crate::syntax::cst::SyntaxTree> {
        crate::syntax::build::standalone(code, |b| {
            let mut pairs = KrlGrammar::parse(rule, code).ok()?;
            let stmt = pairs
                .next()?
                .into_inner()
                .find(|p| p.as_rule() != Rule::EOI)?;
            let Class::Node(kind) = classify(stmt.as_rule()) else {
                return None;
            };
            let ctx = Ctx {
                text: code,
                base: 0,
                b: RefCell::new(b),
            };
            for inner in stmt.into_inner() {
                convert(inner, &ctx);
            }
            Some(kind)
        })
    }

    /// The narrow entry rules accept exactly what `line` accepts, with the same tree.
    #[test]
    fn entry_rules_agree_with_line() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures");
        let mut dirs = vec![std::path::PathBuf::from(root)];
        let mut lines: Vec<String> = [
            "GLOBAL DEF a(x:IN)",
            "GLOBAL DEFFCT INT f()",
            "GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )",
            "GLOBAL INT x = 1",
            "GLOBAL CONST REAL r = 1.5",
            "GLOBAL DECL INT g",
            "GLOBAL STRUC s INT a, REAL b",
            "GLOBAL ENUM e a, b",
            "GLOBAL SIGNAL s $OUT[1] TO $OUT[8]",
            "GLOBAL EXTFCT INT f(INT :IN)",
            "SIGNAL s FALSE",
            "SIGNAL = 1",
            "SIGNAL(1)",
            "TRIGGER WHEN DISTANCE=0 DELAY=10 DO $OUT[1]=TRUE PRIO=-1",
            "TRIGGER: ",
            "TRIGGER:",
            "DEF: ",
            "INTERRUPT ON 3",
            "INTERRUPT DECL 5 WHEN $IN[1] DO f()",
            "INTERRUPT x",
            "CHANNEL :SER_1 :SER_1 $PSER_1",
            "EXTP f(E6POS :OUT)",
            "STRUC",
            "DEFDAT x PUBLIC",
            "DEF f(a[,]:OUT, b[80]:IN)",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).expect("fixture dir").flatten() {
                let path = entry.path();
                if path.is_dir() {
                    dirs.push(path);
                    continue;
                }
                let text = crate::syntax::decode(&std::fs::read(&path).expect("read")).text;
                for line in text.split(['\n', '\r']) {
                    let code = line.split(';').next().unwrap_or("").trim();
                    if !code.is_empty() && !code.starts_with('&') {
                        lines.push(code.to_string());
                    }
                }
            }
        }
        for code in &lines {
            let entry = entry_rule(code);
            if entry != Rule::line {
                assert_eq!(via(entry, code), via(Rule::line, code), "{code:?}");
            }
        }
    }
}
