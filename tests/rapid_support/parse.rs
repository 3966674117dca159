//! The syntax tree of a RAPID module and its parser. Everything outside the subset fails with
//! the file and line (ERROR handlers, late binding, `LOCAL`, `ALIAS`, …): a construct the
//! interpreter does not model is never skipped.

use super::lexer::{Tok, Token, lex};

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Storage {
    Var,
    Pers,
    Const,
}

/// A declared type: base type name (lower case) and array sizes.
#[derive(Debug, Clone)]
pub struct Decl {
    pub storage: Storage,
    pub ty: String,
    pub name: String,
    pub dims: Vec<Expr>,
    pub init: Option<Expr>,
    pub line: usize,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    In,
    InOut,
}

#[derive(Debug, Clone)]
pub struct Param {
    pub mode: Mode,
    pub ty: String,
    pub name: String,
    /// `{*}`, `{*,*}`: an array of any size with this many dimensions (0: not an array).
    pub dims: usize,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    Proc,
    Func,
    Trap,
}

#[derive(Debug, Clone)]
pub struct Routine {
    pub kind: Kind,
    pub name: String,
    pub ret: Option<String>,
    pub params: Vec<Param>,
    pub decls: Vec<Decl>,
    pub body: Vec<Stmt>,
    pub file: String,
    pub line: usize,
}

#[derive(Debug, Clone)]
pub struct Stmt {
    pub line: usize,
    pub s: S,
}

/// An argument: `value`, `\name:=value` or the switch `\name`.
#[derive(Debug, Clone)]
pub struct Arg {
    pub name: Option<String>,
    pub value: Option<Expr>,
}

#[derive(Debug, Clone)]
pub enum S {
    Assign(Expr, Expr),
    /// A procedure call or an instruction (name lower-cased).
    Call(String, Vec<Arg>),
    If(Vec<(Expr, Vec<Stmt>)>, Vec<Stmt>),
    While(Expr, Vec<Stmt>),
    For {
        var: String,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
        body: Vec<Stmt>,
    },
    Test(Expr, Vec<(Vec<Expr>, Vec<Stmt>)>, Option<Vec<Stmt>>),
    Goto(String),
    Label(String),
    Return(Option<Expr>),
    Exit,
    Connect(Expr, String),
}

#[derive(Debug, Clone)]
pub enum Expr {
    Num(f64),
    Bool(bool),
    Str(String),
    Agg(Vec<Expr>),
    /// A name, lower-cased.
    Name(String),
    Field(Box<Expr>, String),
    Index(Box<Expr>, Vec<Expr>),
    Call(String, Vec<Arg>),
    Neg(Box<Expr>),
    Not(Box<Expr>),
    Bin(&'static str, Box<Expr>, Box<Expr>),
}

/// A `RECORD`: its name and components (name, type), lower-cased.
#[derive(Debug, Clone)]
pub struct Record {
    pub name: String,
    pub fields: Vec<(String, String)>,
}

#[derive(Debug, Default)]
pub struct Module {
    pub name: String,
    pub records: Vec<Record>,
    pub data: Vec<Decl>,
    pub routines: Vec<Routine>,
}

const RESERVED: &[&str] = &[
    "alias",
    "and",
    "backward",
    "case",
    "connect",
    "const",
    "default",
    "div",
    "do",
    "else",
    "elseif",
    "endfor",
    "endfunc",
    "endif",
    "endmodule",
    "endproc",
    "endrecord",
    "endtest",
    "endtrap",
    "endwhile",
    "error",
    "exit",
    "false",
    "for",
    "from",
    "func",
    "goto",
    "if",
    "inout",
    "local",
    "mod",
    "module",
    "nostepin",
    "not",
    "noview",
    "or",
    "pers",
    "proc",
    "raise",
    "readonly",
    "record",
    "retry",
    "return",
    "step",
    "sysmodule",
    "task",
    "test",
    "then",
    "to",
    "trap",
    "true",
    "trynext",
    "undo",
    "var",
    "viewonly",
    "while",
    "with",
    "xor",
];

struct P<'a> {
    toks: &'a [Token],
    i: usize,
    file: &'a str,
}

type R<T> = Result<T, String>;

/// Parses one file (one or more modules).
pub fn parse(file: &str, text: &str) -> R<Vec<Module>> {
    let toks = lex(text).map_err(|(l, e)| format!("{file}:{l}: {e}"))?;
    let mut p = P {
        toks: &toks,
        i: 0,
        file,
    };
    let mut out = Vec::new();
    while p.i < toks.len() {
        out.push(p.module()?);
    }
    if out.is_empty() {
        return Err(format!("{file}: no MODULE"));
    }
    Ok(out)
}

impl P<'_> {
    fn line(&self) -> usize {
        self.toks
            .get(self.i)
            .or(self.toks.last())
            .map_or(1, |t| t.line)
    }
    fn fail<T>(&self, msg: impl std::fmt::Display) -> R<T> {
        Err(format!("{}:{}: {msg}", self.file, self.line()))
    }
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.i).map(|t| &t.tok)
    }
    fn peek_at(&self, k: usize) -> Option<&Tok> {
        self.toks.get(self.i + k).map(|t| &t.tok)
    }
    fn describe(&self) -> String {
        match self.peek() {
            None => "the end of the file".into(),
            Some(Tok::Id(s)) => format!("`{s}`"),
            Some(Tok::P(s)) => format!("`{s}`"),
            Some(Tok::Num(n)) => format!("the number {n}"),
            Some(Tok::Str(s)) => format!("the string {s:?}"),
        }
    }
    fn is_kw(&self, kw: &str) -> bool {
        matches!(self.peek(), Some(Tok::Id(s)) if s.eq_ignore_ascii_case(kw))
    }
    fn eat_kw(&mut self, kw: &str) -> bool {
        let yes = self.is_kw(kw);
        if yes {
            self.i += 1;
        }
        yes
    }
    fn kw(&mut self, kw: &str) -> R<()> {
        if self.eat_kw(kw) {
            Ok(())
        } else {
            self.fail(format!("`{kw}` expected, found {}", self.describe()))
        }
    }
    fn is_p(&self, p: &str) -> bool {
        matches!(self.peek(), Some(Tok::P(s)) if *s == p)
    }
    fn eat_p(&mut self, p: &str) -> bool {
        let yes = self.is_p(p);
        if yes {
            self.i += 1;
        }
        yes
    }
    fn p(&mut self, p: &str) -> R<()> {
        if self.eat_p(p) {
            Ok(())
        } else {
            self.fail(format!("`{p}` expected, found {}", self.describe()))
        }
    }
    /// A name that is not a reserved word, lower-cased.
    fn name(&mut self) -> R<String> {
        match self.peek() {
            Some(Tok::Id(s)) if !RESERVED.contains(&s.to_ascii_lowercase().as_str()) => {
                let s = s.to_ascii_lowercase();
                self.i += 1;
                Ok(s)
            }
            _ => self.fail(format!("a name expected, found {}", self.describe())),
        }
    }

    fn module(&mut self) -> R<Module> {
        self.kw("MODULE")?;
        let mut m = Module {
            name: self.name()?,
            ..Module::default()
        };
        if self.is_p("(") {
            return self.fail("module attributes are not modelled");
        }
        loop {
            let line = self.line();
            if self.eat_kw("ENDMODULE") {
                return Ok(m);
            } else if self.eat_kw("RECORD") {
                let name = self.name()?;
                let mut fields = Vec::new();
                while !self.eat_kw("ENDRECORD") {
                    let ty = self.name()?;
                    let f = self.name()?;
                    self.p(";")?;
                    fields.push((f, ty));
                }
                m.records.push(Record { name, fields });
            } else if self.is_kw("VAR") || self.is_kw("PERS") || self.is_kw("CONST") {
                m.data.push(self.decl()?);
            } else if self.is_kw("PROC") || self.is_kw("FUNC") || self.is_kw("TRAP") {
                m.routines.push(self.routine()?);
            } else if self.peek().is_none() {
                return self.fail("`ENDMODULE` missing");
            } else {
                return Err(format!(
                    "{}:{line}: {} is not a module item the test interpreter models",
                    self.file,
                    self.describe()
                ));
            }
        }
    }

    fn decl(&mut self) -> R<Decl> {
        let line = self.line();
        let storage = if self.eat_kw("VAR") {
            Storage::Var
        } else if self.eat_kw("PERS") {
            Storage::Pers
        } else {
            self.kw("CONST")?;
            Storage::Const
        };
        let ty = self.name()?;
        let name = self.name()?;
        let mut dims = Vec::new();
        if self.eat_p("{") {
            dims = self.list("}")?;
        }
        let init = if self.eat_p(":=") {
            Some(self.expr()?)
        } else {
            None
        };
        if init.is_none() && storage != Storage::Var {
            return self.fail(format!("`{name}` needs an initial value"));
        }
        if self.is_p(",") {
            return self.fail("one data object per declaration");
        }
        self.p(";")?;
        Ok(Decl {
            storage,
            ty,
            name,
            dims,
            init,
            line,
        })
    }

    fn routine(&mut self) -> R<Routine> {
        let line = self.line();
        let (kind, end) = if self.eat_kw("PROC") {
            (Kind::Proc, "ENDPROC")
        } else if self.eat_kw("FUNC") {
            (Kind::Func, "ENDFUNC")
        } else {
            self.kw("TRAP")?;
            (Kind::Trap, "ENDTRAP")
        };
        let ret = if kind == Kind::Func {
            Some(self.name()?)
        } else {
            None
        };
        let name = self.name()?;
        let mut params = Vec::new();
        if kind != Kind::Trap {
            self.p("(")?;
            while !self.eat_p(")") {
                if !params.is_empty() {
                    self.p(",")?;
                }
                if self.is_p("\\") {
                    return self.fail("optional parameters are not modelled");
                }
                let mode = if self.eat_kw("INOUT") {
                    Mode::InOut
                } else if self.is_kw("VAR") || self.is_kw("PERS") {
                    return self.fail("VAR/PERS parameters are not modelled");
                } else {
                    Mode::In
                };
                let ty = self.name()?;
                let name = self.name()?;
                let mut dims = 0;
                if self.eat_p("{") {
                    loop {
                        self.p("*")?;
                        dims += 1;
                        if !self.eat_p(",") {
                            break;
                        }
                    }
                    self.p("}")?;
                }
                params.push(Param {
                    mode,
                    ty,
                    name,
                    dims,
                });
            }
        }
        let mut decls = Vec::new();
        while self.is_kw("VAR") || self.is_kw("CONST") || self.is_kw("PERS") {
            if self.is_kw("PERS") {
                return self.fail("PERS data inside a routine");
            }
            decls.push(self.decl()?);
        }
        let body = self.block(&[end])?;
        self.kw(end)?;
        Ok(Routine {
            kind,
            name,
            ret,
            params,
            decls,
            body,
            file: self.file.to_string(),
            line,
        })
    }

    /// Statements up to (not including) one of `ends`.
    fn block(&mut self, ends: &[&str]) -> R<Vec<Stmt>> {
        let mut out = Vec::new();
        loop {
            if ends.iter().any(|e| self.is_kw(e)) {
                return Ok(out);
            }
            if self.peek().is_none() {
                return self.fail(format!("`{}` missing", ends[0]));
            }
            for kw in ["ERROR", "UNDO", "BACKWARD"] {
                if self.is_kw(kw) {
                    return self.fail(format!("{kw} handlers are not modelled"));
                }
            }
            if self.is_kw("VAR") || self.is_kw("CONST") || self.is_kw("PERS") {
                return self.fail("a declaration after the first statement");
            }
            out.push(self.stmt()?);
        }
    }

    fn stmt(&mut self) -> R<Stmt> {
        let line = self.line();
        let s = self.stmt_kind()?;
        Ok(Stmt { line, s })
    }

    fn stmt_kind(&mut self) -> R<S> {
        if self.eat_kw("IF") {
            let cond = self.expr()?;
            if !self.eat_kw("THEN") {
                // The compact IF: one simple statement.
                let then = self.stmt()?;
                return Ok(S::If(vec![(cond, vec![then])], Vec::new()));
            }
            let mut arms = vec![(cond, self.block(&["ELSEIF", "ELSE", "ENDIF"])?)];
            let mut other = Vec::new();
            loop {
                if self.eat_kw("ELSEIF") {
                    let c = self.expr()?;
                    self.kw("THEN")?;
                    arms.push((c, self.block(&["ELSEIF", "ELSE", "ENDIF"])?));
                } else if self.eat_kw("ELSE") {
                    other = self.block(&["ENDIF"])?;
                } else {
                    self.kw("ENDIF")?;
                    return Ok(S::If(arms, other));
                }
            }
        }
        if self.eat_kw("WHILE") {
            let c = self.expr()?;
            self.kw("DO")?;
            let body = self.block(&["ENDWHILE"])?;
            self.kw("ENDWHILE")?;
            return Ok(S::While(c, body));
        }
        if self.eat_kw("FOR") {
            let var = self.name()?;
            self.kw("FROM")?;
            let from = self.expr()?;
            self.kw("TO")?;
            let to = self.expr()?;
            let step = if self.eat_kw("STEP") {
                Some(self.expr()?)
            } else {
                None
            };
            self.kw("DO")?;
            let body = self.block(&["ENDFOR"])?;
            self.kw("ENDFOR")?;
            return Ok(S::For {
                var,
                from,
                to,
                step,
                body,
            });
        }
        if self.eat_kw("TEST") {
            let e = self.expr()?;
            let mut cases = Vec::new();
            let mut default = None;
            loop {
                if self.eat_kw("CASE") {
                    let mut vals = vec![self.expr()?];
                    while self.eat_p(",") {
                        vals.push(self.expr()?);
                    }
                    self.p(":")?;
                    cases.push((vals, self.block(&["CASE", "DEFAULT", "ENDTEST"])?));
                } else if self.eat_kw("DEFAULT") {
                    self.p(":")?;
                    default = Some(self.block(&["ENDTEST"])?);
                } else {
                    self.kw("ENDTEST")?;
                    return Ok(S::Test(e, cases, default));
                }
            }
        }
        let s = if self.eat_kw("GOTO") {
            S::Goto(self.name()?)
        } else if self.eat_kw("RETURN") {
            S::Return(if self.is_p(";") {
                None
            } else {
                Some(self.expr()?)
            })
        } else if self.eat_kw("EXIT") {
            S::Exit
        } else if self.eat_kw("CONNECT") {
            let ir = self.data()?;
            self.kw("WITH")?;
            S::Connect(ir, self.name()?)
        } else if matches!(self.peek(), Some(Tok::Id(_)))
            && matches!(self.peek_at(1), Some(Tok::P(":")))
        {
            let l = self.name()?;
            self.p(":")?;
            return Ok(S::Label(l));
        } else {
            // Not `postfix`: `WaitUntil (a) AND (b);` is an instruction with an argument in
            // parentheses, not a function call.
            let target = self.data()?;
            if self.eat_p(":=") {
                S::Assign(target, self.expr()?)
            } else if let Expr::Name(n) = target {
                S::Call(n, self.args(";")?)
            } else {
                return self.fail("a statement expected");
            }
        };
        self.p(";")?;
        Ok(s)
    }

    /// Arguments up to `end` (not eaten): `a, b \Opt:=c, \Switch`.
    fn args(&mut self, end: &str) -> R<Vec<Arg>> {
        let mut out = Vec::new();
        while !self.is_p(end) {
            if self.eat_p("\\") {
                let name = match self.peek() {
                    Some(Tok::Id(s)) => s.to_ascii_lowercase(),
                    _ => return self.fail("an optional argument's name expected"),
                };
                self.i += 1;
                let value = if self.eat_p(":=") {
                    Some(self.expr()?)
                } else {
                    None
                };
                out.push(Arg {
                    name: Some(name),
                    value,
                });
                self.eat_p(",");
            } else {
                out.push(Arg {
                    name: None,
                    value: Some(self.expr()?),
                });
                if !self.eat_p(",") && !self.is_p("\\") && !self.is_p(end) {
                    return self.fail(format!(
                        "`,` or `{end}` expected, found {}",
                        self.describe()
                    ));
                }
            }
        }
        Ok(out)
    }

    fn list(&mut self, end: &str) -> R<Vec<Expr>> {
        let mut out = Vec::new();
        while !self.eat_p(end) {
            if !out.is_empty() {
                self.p(",")?;
            }
            out.push(self.expr()?);
        }
        Ok(out)
    }

    fn expr(&mut self) -> R<Expr> {
        let mut l = self.and()?;
        loop {
            let op = if self.eat_kw("OR") {
                "or"
            } else if self.eat_kw("XOR") {
                "xor"
            } else {
                return Ok(l);
            };
            l = Expr::Bin(op, Box::new(l), Box::new(self.and()?));
        }
    }
    fn and(&mut self) -> R<Expr> {
        let mut l = self.not()?;
        while self.eat_kw("AND") {
            l = Expr::Bin("and", Box::new(l), Box::new(self.not()?));
        }
        Ok(l)
    }
    fn not(&mut self) -> R<Expr> {
        if self.eat_kw("NOT") {
            return Ok(Expr::Not(Box::new(self.not()?)));
        }
        self.cmp()
    }
    fn cmp(&mut self) -> R<Expr> {
        let l = self.sum()?;
        for op in ["=", "<>", "<=", ">=", "<", ">"] {
            if self.eat_p(op) {
                let op: &'static str = op;
                return Ok(Expr::Bin(op, Box::new(l), Box::new(self.sum()?)));
            }
        }
        Ok(l)
    }
    fn sum(&mut self) -> R<Expr> {
        let mut l = self.product()?;
        loop {
            let op = if self.eat_p("+") {
                "+"
            } else if self.eat_p("-") {
                "-"
            } else {
                return Ok(l);
            };
            l = Expr::Bin(op, Box::new(l), Box::new(self.product()?));
        }
    }
    fn product(&mut self) -> R<Expr> {
        let mut l = self.unary()?;
        loop {
            let op = if self.eat_p("*") {
                "*"
            } else if self.eat_p("/") {
                "/"
            } else if self.eat_kw("DIV") {
                "div"
            } else if self.eat_kw("MOD") {
                "mod"
            } else {
                return Ok(l);
            };
            l = Expr::Bin(op, Box::new(l), Box::new(self.unary()?));
        }
    }
    fn unary(&mut self) -> R<Expr> {
        if self.eat_p("-") {
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        if self.eat_p("+") {
            return self.unary();
        }
        self.postfix()
    }
    /// A data reference: a name with components and elements.
    fn data(&mut self) -> R<Expr> {
        let e = Expr::Name(self.name()?);
        self.components(e)
    }

    fn postfix(&mut self) -> R<Expr> {
        let e = self.primary()?;
        self.components(e)
    }

    fn components(&mut self, mut e: Expr) -> R<Expr> {
        loop {
            if self.eat_p(".") {
                let f = match self.peek() {
                    Some(Tok::Id(s)) => s.to_ascii_lowercase(),
                    _ => return self.fail("a component name expected"),
                };
                self.i += 1;
                e = Expr::Field(Box::new(e), f);
            } else if self.eat_p("{") {
                let idx = self.list("}")?;
                if idx.is_empty() {
                    return self.fail("an empty index `{}`");
                }
                e = Expr::Index(Box::new(e), idx);
            } else {
                return Ok(e);
            }
        }
    }
    fn primary(&mut self) -> R<Expr> {
        let tok = self.peek().cloned();
        match tok {
            Some(Tok::Num(n)) => {
                self.i += 1;
                Ok(Expr::Num(n))
            }
            Some(Tok::Str(s)) => {
                self.i += 1;
                Ok(Expr::Str(s))
            }
            Some(Tok::P("(")) => {
                self.i += 1;
                let e = self.expr()?;
                self.p(")")?;
                Ok(e)
            }
            Some(Tok::P("[")) => {
                self.i += 1;
                Ok(Expr::Agg(self.list("]")?))
            }
            Some(Tok::Id(s)) if s.eq_ignore_ascii_case("TRUE") => {
                self.i += 1;
                Ok(Expr::Bool(true))
            }
            Some(Tok::Id(s)) if s.eq_ignore_ascii_case("FALSE") => {
                self.i += 1;
                Ok(Expr::Bool(false))
            }
            Some(Tok::Id(_)) => {
                let n = self.name()?;
                if self.eat_p("(") {
                    let args = self.args(")")?;
                    self.p(")")?;
                    Ok(Expr::Call(n, args))
                } else {
                    Ok(Expr::Name(n))
                }
            }
            _ => self.fail(format!("an expression expected, found {}", self.describe())),
        }
    }
}
