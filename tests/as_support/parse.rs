//! AS expressions and statements. A program's statements are compiled to a flat list of
//! operations with resolved jump targets, so `GOTO` may leave any block (the translator turns
//! KRL `EXIT` into a `GOTO` to a label after the loop) and blocks cost no recursion.

use std::collections::HashMap;

use super::lexer::{Tok, lex};

#[derive(Debug, Clone)]
pub struct VarRef {
    /// Lower case, with scope dot and `#`/`$` sigil; without `&`.
    pub name: String,
    /// Written with `&` (a transformation passed by reference).
    pub amp: bool,
    pub idx: Vec<Expr>,
    /// Written `name[]` / `name[,]`: the whole array (a CALL argument).
    pub whole: bool,
}

#[derive(Debug, Clone)]
pub enum Expr {
    Num(f64),
    Str(String),
    Fmt(String),
    /// The null transformation.
    Null,
    Var(VarRef),
    Call(String, Vec<Expr>),
    /// `SHIFT(p BY dx, dy, dz)`
    Shift(Box<Expr>, Vec<Expr>),
    Neg(Box<Expr>),
    Not(Box<Expr>),
    Bin(&'static str, Box<Expr>, Box<Expr>),
    /// A parenthesised expression (kept to tell `(a AND b) OR c` from `a AND b OR c`).
    Group(Box<Expr>),
}

/// The logical operator at the top of `e`, unless parenthesised.
fn logic_op(e: &Expr) -> Option<&'static str> {
    match e {
        Expr::Bin(op, ..) if LEVELS[0].contains(op) || LEVELS[1].contains(op) => Some(op),
        _ => None,
    }
}

pub struct Parser {
    t: Vec<Tok>,
    i: usize,
}

/// Binary operators by level, loosest first; names are keywords.
const LEVELS: [&[&str]; 5] = [
    &["or", "xor", "bor", "bxor"],
    &["and", "band"],
    &["==", "<>", "<=", ">=", "<", ">"],
    &["+", "-"],
    &["*", "/", "mod"],
];

impl Parser {
    pub fn new(text: &str) -> Result<Parser, String> {
        Ok(Parser {
            t: lex(text)?,
            i: 0,
        })
    }
    pub fn peek(&self) -> Option<&Tok> {
        self.t.get(self.i)
    }
    pub fn at_end(&self) -> bool {
        self.i >= self.t.len()
    }
    pub fn eat(&mut self, p: &str) -> bool {
        if matches!(self.peek(), Some(Tok::P(q)) if *q == p) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    pub fn eat_kw(&mut self, kw: &str) -> bool {
        if matches!(self.peek(), Some(Tok::Id(n)) if n == kw) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    pub fn expect(&mut self, p: &str) -> Result<(), String> {
        if self.eat(p) {
            Ok(())
        } else {
            Err(format!("`{p}` expected, found {}", self.found()))
        }
    }
    pub fn expect_kw(&mut self, kw: &str) -> Result<(), String> {
        if self.eat_kw(kw) {
            Ok(())
        } else {
            Err(format!(
                "`{}` expected, found {}",
                kw.to_ascii_uppercase(),
                self.found()
            ))
        }
    }
    fn found(&self) -> String {
        match self.peek() {
            None => "the end of the line".into(),
            Some(Tok::Num(n)) => format!("`{n}`"),
            Some(Tok::Str(s)) => format!("\"{s}\""),
            Some(Tok::Id(s) | Tok::Fmt(s)) => format!("`{s}`"),
            Some(Tok::P(p)) => format!("`{p}`"),
        }
    }
    pub fn name(&mut self) -> Result<String, String> {
        match self.peek().cloned() {
            Some(Tok::Id(n)) => {
                self.i += 1;
                Ok(n)
            }
            _ => Err(format!("a name expected, found {}", self.found())),
        }
    }
    pub fn end(&self) -> Result<(), String> {
        if self.at_end() {
            Ok(())
        } else {
            Err(format!("unexpected {} after the statement", self.found()))
        }
    }

    pub fn expr(&mut self) -> Result<Expr, String> {
        self.level(0)
    }

    fn op_at(&self, level: usize) -> Option<&'static str> {
        let ops = LEVELS[level];
        match self.peek()? {
            Tok::P(p) => ops.iter().find(|o| *o == p).copied(),
            Tok::Id(n) => ops.iter().find(|o| *o == n).copied(),
            _ => None,
        }
    }

    fn level(&mut self, level: usize) -> Result<Expr, String> {
        if level == LEVELS.len() {
            return self.unary();
        }
        // NOT binds tighter than AND/OR and looser than comparisons.
        let operand = |p: &mut Parser| {
            if level == 1 {
                p.not()
            } else {
                p.level(level + 1)
            }
        };
        let mut l = operand(self)?;
        while let Some(op) = self.op_at(level) {
            self.i += 1;
            let r = operand(self)?;
            if level < 2 {
                // AS documents no precedence among its logical operators.
                for side in [&l, &r] {
                    if let Some(inner) = logic_op(side).filter(|o| *o != op) {
                        return Err(format!(
                            "`{}` inside `{}` without parentheses (AS precedence unverified)",
                            inner.to_ascii_uppercase(),
                            op.to_ascii_uppercase()
                        ));
                    }
                }
            }
            l = Expr::Bin(op, Box::new(l), Box::new(r));
            if level == 2 {
                // Comparisons do not chain.
                break;
            }
        }
        Ok(l)
    }

    fn not(&mut self) -> Result<Expr, String> {
        if self.eat_kw("not") {
            let operand = self.not_operand()?;
            if self.op_at(2).is_some() {
                return Err(
                    "`NOT a` followed by a comparison without parentheses (AS precedence unverified)"
                        .into(),
                );
            }
            return Ok(Expr::Not(Box::new(operand)));
        }
        self.level(2)
    }

    fn not_operand(&mut self) -> Result<Expr, String> {
        if self.eat_kw("not") {
            return Ok(Expr::Not(Box::new(self.not_operand()?)));
        }
        self.level(3)
    }

    fn unary(&mut self) -> Result<Expr, String> {
        if self.eat("-") {
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        if self.eat("+") {
            return self.unary();
        }
        self.atom()
    }

    fn atom(&mut self) -> Result<Expr, String> {
        let Some(t) = self.peek().cloned() else {
            return Err("an expression expected, found the end of the line".into());
        };
        self.i += 1;
        match t {
            Tok::Num(n) => Ok(Expr::Num(n)),
            Tok::Str(s) => Ok(Expr::Str(s)),
            Tok::Fmt(f) => Ok(Expr::Fmt(f)),
            Tok::P("(") => {
                let e = self.expr()?;
                self.expect(")")?;
                Ok(Expr::Group(Box::new(e)))
            }
            Tok::Id(name) => {
                match name.as_str() {
                    "true" | "on" => return Ok(Expr::Num(-1.0)),
                    "false" | "off" => return Ok(Expr::Num(0.0)),
                    "null" => return Ok(Expr::Null),
                    _ => {}
                }
                if LEVELS.iter().any(|l| l.contains(&name.as_str())) || name == "not" {
                    return Err(format!("an operand expected, found `{name}`"));
                }
                if self.eat("(") {
                    if name == "shift" {
                        let p = self.expr()?;
                        self.expect_kw("by")?;
                        let d = self.list_until(")")?;
                        return Ok(Expr::Shift(Box::new(p), d));
                    }
                    let args = if self.eat(")") {
                        Vec::new()
                    } else {
                        self.list_until(")")?
                    };
                    return Ok(Expr::Call(name, args));
                }
                self.i -= 1;
                Ok(Expr::Var(self.var()?))
            }
            Tok::P(p) => Err(format!("an expression expected, found `{p}`")),
        }
    }

    /// Comma-separated expressions up to and including `close`.
    fn list_until(&mut self, close: &str) -> Result<Vec<Expr>, String> {
        let mut v = vec![self.expr()?];
        while !self.eat(close) {
            self.expect(",")?;
            v.push(self.expr()?);
        }
        Ok(v)
    }

    pub fn var(&mut self) -> Result<VarRef, String> {
        let raw = self.name()?;
        let amp = raw.contains('&');
        let name = raw.replace('&', "");
        let mut idx = Vec::new();
        let mut whole = false;
        if self.eat("[") {
            if matches!(self.peek(), Some(Tok::P("]" | ","))) {
                while self.eat(",") {}
                self.expect("]")?;
                whole = true;
            } else {
                idx = self.list_until("]")?;
            }
        }
        Ok(VarRef {
            name,
            amp,
            idx,
            whole,
        })
    }

    /// Comma-separated expressions to the end of the line.
    pub fn list(&mut self) -> Result<Vec<Expr>, String> {
        let mut out = vec![self.expr()?];
        while self.eat(",") {
            out.push(self.expr()?);
        }
        self.end()?;
        Ok(out)
    }

    /// Comma-separated expressions to the end, any of them empty (`TDRAW ,,10`).
    fn sparse_list(&mut self) -> Result<Vec<Option<Expr>>, String> {
        let mut out = Vec::new();
        loop {
            if self.at_end() || matches!(self.peek(), Some(Tok::P(","))) {
                out.push(None);
            } else {
                out.push(Some(self.expr()?));
            }
            if self.at_end() {
                return Ok(out);
            }
            self.expect(",")?;
        }
    }
}

/// Kinds of values a program parameter holds, from its sigil.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    Real,
    Pose,
    Joint,
    Str,
}

#[derive(Debug, Clone)]
pub struct Param {
    /// Storage name (`.x`, `.#j`, `.$s`, `.p` for `.&p`).
    pub name: String,
    pub kind: Kind,
    /// Written `.a[]` (`.a[,]` …): receives a whole array.
    pub array: bool,
}

impl Param {
    pub fn parse(text: &str) -> Result<Param, String> {
        let t = text.trim().to_ascii_lowercase();
        let (t, array) = match t.find('[') {
            Some(i) if t.ends_with(']') && t[i + 1..t.len() - 1].chars().all(|c| c == ',') => {
                (t[..i].to_string(), true)
            }
            Some(_) => return Err(format!("bad parameter `{}`", text.trim())),
            None => (t, false),
        };
        let kind = if t.contains('&') {
            Kind::Pose
        } else if t.contains('#') {
            Kind::Joint
        } else if t.contains('$') {
            Kind::Str
        } else {
            Kind::Real
        };
        let name = t.replace('&', "");
        let ok = name.strip_prefix('.').unwrap_or(&name);
        let ok = ok.trim_start_matches(['#', '$']);
        if !ok.starts_with(|c: char| c.is_ascii_alphabetic())
            || !ok
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
        {
            return Err(format!("bad parameter `{}`", text.trim()));
        }
        Ok(Param { name, kind, array })
    }
}

#[derive(Debug, Clone)]
pub enum Move {
    /// JMOVE, LMOVE, C1MOVE, C2MOVE to a target.
    To(&'static str, Expr),
    /// JAPPRO/LAPPRO target, distance.
    Appro(&'static str, Expr, Expr),
    /// JDEPART/LDEPART distance.
    Depart(&'static str, Expr),
    /// DRAW/TDRAW dx, dy, dz [, rx, ry, rz [, speed]].
    Draw(&'static str, Vec<Option<Expr>>),
    Home(Option<Expr>),
    /// DRIVE joint, degrees [, speed %].
    Drive(Vec<Expr>),
}

#[derive(Debug, Clone)]
pub enum Setting {
    /// value, unit ("%", "MM/S", "MM/MIN", "S"), ALWAYS
    Speed(Expr, &'static str, bool),
    /// value, "ALWAYS" | "FINE" | ""
    Accuracy(Expr, &'static str),
    Accel(Expr, bool),
    Decel(Expr, bool),
    Tool(Expr),
    Base(Expr),
    Weight(Vec<Expr>),
    Cp(bool),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StopKind {
    Pause,
    Halt,
    Stop,
}

#[derive(Debug, Clone)]
pub enum Op {
    Assign(VarRef, Expr),
    Point(VarRef, Expr),
    Here(VarRef),
    Decompose(VarRef, Expr),
    Jump(usize),
    JumpUnless(Expr, usize),
    JumpIf(Expr, usize),
    ForInit {
        var: VarRef,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
    },
    /// Leaves the loop (to `exit`) when the variable is past the end; the loop's end value and
    /// step live in the frame under the index of the ForInit (`init`).
    ForTest {
        var: VarRef,
        init: usize,
        exit: usize,
    },
    ForNext {
        var: VarRef,
        init: usize,
        test: usize,
    },
    Case {
        sel: Expr,
        string: bool,
        arms: Vec<(Vec<Expr>, usize)>,
        any: Option<usize>,
        end: usize,
    },
    Call(String, Vec<Expr>),
    Return,
    Move(Move),
    Setting(Setting),
    Signal(Vec<Expr>),
    Swait(Vec<Expr>),
    Pulse(Expr, Option<Expr>),
    Bits(Expr, Expr, Expr),
    Twait(Expr),
    Wait(Expr),
    Timer(Expr, Expr),
    Stop(StopKind),
    Print(Vec<Expr>),
    On(Expr, String),
    Ignore(Expr),
    /// BREAK / BRAKE: motions are instantaneous here.
    Nothing,
    Tcp(&'static str, Vec<Expr>),
}

/// One operation and the source line it came from.
#[derive(Debug, Clone)]
pub struct Step {
    pub op: Op,
    pub line: usize,
    pub text: String,
}

#[derive(Debug)]
pub struct Program {
    pub name: String,
    pub file: String,
    pub params: Vec<Param>,
    pub steps: Vec<Step>,
}

/// An open block while compiling.
enum Open {
    If {
        line: usize,
        test: usize,
        skip_else: Option<usize>,
    },
    While {
        line: usize,
        start: usize,
        test: usize,
    },
    Do {
        line: usize,
        start: usize,
    },
    For {
        line: usize,
        init: usize,
    },
    Case {
        line: usize,
        op: usize,
        string: bool,
        in_arm: bool,
        arm_ends: Vec<usize>,
    },
}

impl Open {
    fn line(&self) -> usize {
        match self {
            Open::If { line, .. }
            | Open::While { line, .. }
            | Open::Do { line, .. }
            | Open::For { line, .. }
            | Open::Case { line, .. } => *line,
        }
    }
}

const PLACEHOLDER: usize = usize::MAX;

struct Compiler {
    steps: Vec<Step>,
    open: Vec<Open>,
    labels: HashMap<String, usize>,
    gotos: Vec<(usize, String)>,
}

fn set_target(op: &mut Op, to: usize) {
    match op {
        Op::Jump(t) | Op::JumpUnless(_, t) | Op::JumpIf(_, t) => *t = to,
        Op::ForTest { exit, .. } => *exit = to,
        Op::Case { end, .. } => *end = to,
        _ => unreachable!("not a jump"),
    }
}

/// Compile the body of a program: `lines` are (line number, code without comment).
pub fn compile(
    name: &str,
    file: &str,
    params: Vec<Param>,
    lines: &[(usize, String)],
) -> Result<Program, String> {
    let mut c = Compiler {
        steps: Vec::new(),
        open: Vec::new(),
        labels: HashMap::new(),
        gotos: Vec::new(),
    };
    for (n, text) in lines {
        c.line(*n, text)
            .map_err(|e| format!("{file}:{n}: {e}: `{text}` (in {name})"))?;
    }
    if let Some(o) = c.open.last() {
        let n = o.line();
        let text = &lines.iter().find(|(k, _)| *k == n).expect("open line").1;
        return Err(format!(
            "{file}:{n}: this block has no end before .END: `{text}` (in {name})"
        ));
    }
    for (at, label) in std::mem::take(&mut c.gotos) {
        let Some(to) = c.labels.get(&label).copied() else {
            let s = &c.steps[at];
            return Err(format!(
                "{file}:{}: GOTO to the undefined label `{label}`: `{}` (in {name})",
                s.line, s.text
            ));
        };
        set_target(&mut c.steps[at].op, to);
    }
    Ok(Program {
        name: name.to_string(),
        file: file.to_string(),
        params,
        steps: c.steps,
    })
}

fn is_label(text: &str) -> Option<String> {
    let l = text.strip_suffix(':')?.trim_end();
    let ok = l.starts_with(|c: char| c.is_ascii_alphabetic())
        && l.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.');
    (ok && !l.eq_ignore_ascii_case("any")).then(|| l.to_ascii_lowercase())
}

impl Compiler {
    fn push(&mut self, op: Op, line: usize, text: &str) -> usize {
        self.steps.push(Step {
            op,
            line,
            text: text.to_string(),
        });
        self.steps.len() - 1
    }

    fn here(&self) -> usize {
        self.steps.len()
    }

    fn patch(&mut self, at: usize, to: usize) {
        set_target(&mut self.steps[at].op, to);
    }

    fn line(&mut self, n: usize, text: &str) -> Result<(), String> {
        if let Some(label) = is_label(text) {
            if self.labels.insert(label.clone(), self.here()).is_some() {
                return Err(format!("label `{label}` defined twice"));
            }
            return Ok(());
        }
        let head = text
            .split(|c: char| c.is_whitespace() || c == '(')
            .next()
            .unwrap_or("")
            .to_ascii_uppercase();
        let head = head.trim_end_matches(':').to_string();
        let rest = text[text.len().min(head.len())..].trim();
        let mut p = Parser::new(rest)?;
        let op = match head.as_str() {
            "IF" => {
                let cond = p.expr()?;
                if p.eat_kw("goto") {
                    let label = p.name()?;
                    p.end()?;
                    let at = self.push(Op::JumpIf(cond, PLACEHOLDER), n, text);
                    self.gotos.push((at, label));
                    return Ok(());
                }
                p.expect_kw("then")?;
                p.end()?;
                let test = self.push(Op::JumpUnless(cond, PLACEHOLDER), n, text);
                self.open.push(Open::If {
                    line: n,
                    test,
                    skip_else: None,
                });
                return Ok(());
            }
            "ELSE" => {
                p.end()?;
                match self.open.last_mut() {
                    Some(Open::If {
                        test,
                        skip_else: skip @ None,
                        ..
                    }) => {
                        let test = *test;
                        let at = self.steps.len();
                        *skip = Some(at);
                        self.push(Op::Jump(PLACEHOLDER), n, text);
                        let here = self.here();
                        self.patch(test, here);
                        return Ok(());
                    }
                    _ => return Err("ELSE without IF".into()),
                }
            }
            "WHILE" => {
                let cond = p.expr()?;
                p.expect_kw("do")?;
                p.end()?;
                let start = self.here();
                let test = self.push(Op::JumpUnless(cond, PLACEHOLDER), n, text);
                self.open.push(Open::While {
                    line: n,
                    start,
                    test,
                });
                return Ok(());
            }
            "DO" => {
                p.end()?;
                let start = self.here();
                self.open.push(Open::Do { line: n, start });
                return Ok(());
            }
            "UNTIL" => {
                let cond = p.expr()?;
                p.end()?;
                match self.open.pop() {
                    Some(Open::Do { start, .. }) => {
                        self.push(Op::JumpUnless(cond, start), n, text);
                        return Ok(());
                    }
                    _ => return Err("UNTIL without DO".into()),
                }
            }
            "FOR" => {
                let var = p.var()?;
                p.expect("=")?;
                let from = p.expr()?;
                p.expect_kw("to")?;
                let to = p.expr()?;
                let step = if p.eat_kw("step") {
                    Some(p.expr()?)
                } else {
                    None
                };
                p.end()?;
                let init = self.push(
                    Op::ForInit {
                        var: var.clone(),
                        from,
                        to,
                        step,
                    },
                    n,
                    text,
                );
                self.push(
                    Op::ForTest {
                        var,
                        init,
                        exit: PLACEHOLDER,
                    },
                    n,
                    text,
                );
                self.open.push(Open::For { line: n, init });
                return Ok(());
            }
            "CASE" | "SCASE" => {
                let sel = p.expr()?;
                p.expect_kw("of")?;
                p.end()?;
                let string = head == "SCASE";
                let op = self.push(
                    Op::Case {
                        sel,
                        string,
                        arms: Vec::new(),
                        any: None,
                        end: PLACEHOLDER,
                    },
                    n,
                    text,
                );
                self.open.push(Open::Case {
                    line: n,
                    op,
                    string,
                    in_arm: false,
                    arm_ends: Vec::new(),
                });
                return Ok(());
            }
            "VALUE" | "SVALUE" | "ANY" => {
                let here = self.here();
                let Some(Open::Case {
                    op,
                    string,
                    in_arm,
                    arm_ends,
                    ..
                }) = self.open.last_mut()
                else {
                    return Err(format!("{head} outside CASE"));
                };
                if (head == "SVALUE") != *string && head != "ANY" {
                    return Err(format!(
                        "{head} in a {}",
                        if *string { "SCASE" } else { "CASE" }
                    ));
                }
                let (op, was_in_arm) = (*op, *in_arm);
                *in_arm = true;
                if was_in_arm {
                    arm_ends.push(here);
                }
                let values = if head == "ANY" {
                    if rest != ":" && !text.trim_end().ends_with(':') {
                        return Err("`ANY:` expected".into());
                    }
                    None
                } else {
                    let list = rest
                        .strip_suffix(':')
                        .ok_or("`:` expected after the values")?;
                    Some(Parser::new(list)?.list()?)
                };
                if was_in_arm {
                    self.push(Op::Jump(PLACEHOLDER), n, text);
                }
                let start = self.here();
                let Op::Case { arms, any, .. } = &mut self.steps[op].op else {
                    unreachable!("case op");
                };
                match values {
                    Some(v) => arms.push((v, start)),
                    None if any.is_some() => return Err("a second ANY".into()),
                    None => *any = Some(start),
                }
                return Ok(());
            }
            "END" => {
                p.end()?;
                let Some(open) = self.open.pop() else {
                    return Err("END without an open block".into());
                };
                match open {
                    Open::If {
                        test, skip_else, ..
                    } => {
                        let here = self.here();
                        match skip_else {
                            Some(j) => self.patch(j, here),
                            None => self.patch(test, here),
                        }
                    }
                    Open::While { start, test, .. } => {
                        self.push(Op::Jump(start), n, text);
                        let here = self.here();
                        self.patch(test, here);
                    }
                    Open::For { init, .. } => {
                        let Op::ForInit { var, .. } = &self.steps[init].op else {
                            unreachable!("for op");
                        };
                        let var = var.clone();
                        self.push(
                            Op::ForNext {
                                var,
                                init,
                                test: init + 1,
                            },
                            n,
                            text,
                        );
                        let here = self.here();
                        self.patch(init + 1, here);
                    }
                    Open::Case { op, arm_ends, .. } => {
                        // The arm-end jumps were pushed as placeholders right where recorded.
                        let here = self.here();
                        for j in arm_ends {
                            self.patch(j, here);
                        }
                        self.patch(op, here);
                    }
                    Open::Do { .. } => return Err("END closes a DO (use UNTIL)".into()),
                }
                return Ok(());
            }
            "GOTO" => {
                let label = p.name()?;
                p.end()?;
                let at = self.push(Op::Jump(PLACEHOLDER), n, text);
                self.gotos.push((at, label));
                return Ok(());
            }
            "CALL" => {
                let name = p.name()?;
                let args = if p.eat("(") {
                    if p.eat(")") {
                        Vec::new()
                    } else {
                        p.list_until(")")?
                    }
                } else {
                    Vec::new()
                };
                p.end()?;
                Op::Call(name, args)
            }
            "RETURN" => {
                p.end()?;
                Op::Return
            }
            "POINT" | "DECOMPOSE" => {
                let v = p.var()?;
                p.expect("=")?;
                let e = p.expr()?;
                p.end()?;
                if head == "POINT" {
                    Op::Point(v, e)
                } else {
                    Op::Decompose(v, e)
                }
            }
            "HERE" => {
                let v = p.var()?;
                p.end()?;
                Op::Here(v)
            }
            "JMOVE" | "LMOVE" | "C1MOVE" | "C2MOVE" => {
                let e = p.expr()?;
                p.end()?;
                Op::Move(Move::To(kw(&head), e))
            }
            "JAPPRO" | "LAPPRO" => {
                let e = p.expr()?;
                p.expect(",")?;
                let d = p.expr()?;
                p.end()?;
                Op::Move(Move::Appro(kw(&head), e, d))
            }
            "JDEPART" | "LDEPART" => {
                let d = p.expr()?;
                p.end()?;
                Op::Move(Move::Depart(kw(&head), d))
            }
            "DRAW" | "TDRAW" => Op::Move(Move::Draw(kw(&head), p.sparse_list()?)),
            "DRIVE" => Op::Move(Move::Drive(p.list()?)),
            "HOME" => {
                let n = if p.at_end() { None } else { Some(p.expr()?) };
                p.end()?;
                Op::Move(Move::Home(n))
            }
            "SPEED" => {
                let v = p.expr()?;
                let unit = if p.eat_kw("mm") {
                    p.expect("/")?;
                    if p.eat_kw("s") {
                        "MM/S"
                    } else if p.eat_kw("min") {
                        "MM/MIN"
                    } else {
                        return Err("MM/S or MM/MIN expected".into());
                    }
                } else if p.eat_kw("s") {
                    "S"
                } else {
                    "%"
                };
                let always = p.eat_kw("always");
                p.end()?;
                Op::Setting(Setting::Speed(v, unit, always))
            }
            "ACCURACY" => {
                let v = p.expr()?;
                let mode = if p.eat_kw("always") {
                    "ALWAYS"
                } else if p.eat_kw("fine") {
                    "FINE"
                } else {
                    ""
                };
                p.end()?;
                Op::Setting(Setting::Accuracy(v, mode))
            }
            "ACCEL" | "DECEL" => {
                let v = p.expr()?;
                let always = p.eat_kw("always");
                p.end()?;
                Op::Setting(if head == "ACCEL" {
                    Setting::Accel(v, always)
                } else {
                    Setting::Decel(v, always)
                })
            }
            "TOOL" | "BASE" => {
                let v = p.expr()?;
                p.end()?;
                Op::Setting(if head == "TOOL" {
                    Setting::Tool(v)
                } else {
                    Setting::Base(v)
                })
            }
            "WEIGHT" => Op::Setting(Setting::Weight(p.list()?)),
            "CP" => {
                let on = if p.eat_kw("on") {
                    true
                } else if p.eat_kw("off") {
                    false
                } else {
                    return Err("CP ON or CP OFF expected".into());
                };
                p.end()?;
                Op::Setting(Setting::Cp(on))
            }
            "SIGNAL" => Op::Signal(p.list()?),
            "SWAIT" => Op::Swait(p.list()?),
            "PULSE" => {
                let mut l = p.list()?;
                if l.len() > 2 {
                    return Err("PULSE takes a signal and a time".into());
                }
                let t = if l.len() == 2 { l.pop() } else { None };
                Op::Pulse(l.remove(0), t)
            }
            "BITS" => {
                let start = p.expr()?;
                p.expect(",")?;
                let count = p.expr()?;
                p.expect("=")?;
                let v = p.expr()?;
                p.end()?;
                Op::Bits(start, count, v)
            }
            "TWAIT" => {
                let t = p.expr()?;
                p.end()?;
                Op::Twait(t)
            }
            "WAIT" => {
                let c = p.expr()?;
                p.end()?;
                Op::Wait(c)
            }
            "TIMER" => {
                let i = p.expr()?;
                p.expect("=")?;
                let v = p.expr()?;
                p.end()?;
                Op::Timer(i, v)
            }
            "PAUSE" | "HALT" | "STOP" => {
                p.end()?;
                Op::Stop(match head.as_str() {
                    "PAUSE" => StopKind::Pause,
                    "HALT" => StopKind::Halt,
                    _ => StopKind::Stop,
                })
            }
            "PRINT" | "TYPE" => {
                if p.at_end() {
                    Op::Print(Vec::new())
                } else {
                    Op::Print(p.list()?)
                }
            }
            "ON" => {
                let sig = p.expr()?;
                p.expect_kw("call")?;
                let prog = p.name()?;
                p.end()?;
                Op::On(sig, prog)
            }
            "IGNORE" => {
                let sig = p.expr()?;
                p.end()?;
                Op::Ignore(sig)
            }
            "BREAK" | "BRAKE" => {
                p.end()?;
                Op::Nothing
            }
            "TCP_CONNECT" | "TCP_SEND" | "TCP_RECV" | "TCP_CLOSE" => Op::Tcp(kw(&head), p.list()?),
            _ => {
                // `var = expr`, or a statement this interpreter does not know.
                let mut p = Parser::new(text)?;
                let assign = p.var().ok().filter(|_| p.eat("="));
                match assign {
                    Some(v) => {
                        let e = p.expr()?;
                        p.end()?;
                        Op::Assign(v, e)
                    }
                    None => {
                        return Err(format!(
                            "`{head}` is not an AS statement this test interpreter supports"
                        ));
                    }
                }
            }
        };
        self.push(op, n, text);
        Ok(())
    }
}

/// The statement keyword as a static string.
fn kw(head: &str) -> &'static str {
    const ALL: [&str; 16] = [
        "JMOVE",
        "LMOVE",
        "C1MOVE",
        "C2MOVE",
        "JAPPRO",
        "LAPPRO",
        "JDEPART",
        "LDEPART",
        "DRAW",
        "TDRAW",
        "HOME",
        "TCP_CONNECT",
        "TCP_SEND",
        "TCP_RECV",
        "TCP_CLOSE",
        "",
    ];
    ALL.iter().find(|k| **k == head).copied().unwrap_or("")
}
