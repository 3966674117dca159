//! A small interpreter for the subset of Kawasaki AS that the generated package uses, so the
//! package can run against the fake vision server in tests.
//!
//! It implements the AS facts the package header lists as assumptions ([?]) exactly as
//! assumed there (`$DECODE`, `$ENCODE(/L)`, `TCP_RECV` element size, by-reference
//! parameters, ...); a run shows the package's logic is right under those assumptions, not
//! that a controller behaves the same. It is strict where AS is: reading an undefined
//! variable, a wrong argument count or an unknown statement fails the run.
#![allow(dead_code)]

use std::collections::HashMap;
use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

#[derive(Debug, Clone, PartialEq)]
pub enum V {
    Num(f64),
    Str(String),
    Pose([f64; 6]),
    Joint([f64; 6]),
}

impl V {
    fn num(&self) -> Result<f64, String> {
        match self {
            V::Num(n) => Ok(*n),
            other => Err(format!("number expected, got {other:?}")),
        }
    }
    fn str(&self) -> Result<&str, String> {
        match self {
            V::Str(s) => Ok(s),
            other => Err(format!("string expected, got {other:?}")),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Str(String),
    Id(String),
    Fmt(String),
    P(&'static str),
}

fn lex(s: &str) -> Result<Vec<Tok>, String> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let name_char = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'.';
    while i < b.len() {
        let c = b[i];
        if c == b' ' || c == b'\t' {
            i += 1;
        } else if c == b';' {
            break;
        } else if c == b'"' {
            let end = s[i + 1..].find('"').ok_or("unterminated string")? + i + 1;
            out.push(Tok::Str(s[i + 1..end].to_string()));
            i = end + 1;
        } else if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let st = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            out.push(Tok::Num(
                s[st..i]
                    .parse()
                    .map_err(|_| format!("number {}", &s[st..i]))?,
            ));
        } else if c == b'/' && matches!(out.last(), Some(Tok::P("("))) {
            let st = i;
            while i < b.len() && b[i] != b',' {
                i += 1;
            }
            out.push(Tok::Fmt(s[st..i].trim().to_ascii_uppercase()));
        } else if c.is_ascii_alphabetic() || matches!(c, b'.' | b'$' | b'#' | b'&') {
            let st = i;
            let mut name = String::new();
            if c == b'.' {
                name.push('.');
                i += 1;
            }
            if i < b.len() && matches!(b[i], b'$' | b'#') {
                name.push(b[i] as char);
                i += 1;
            } else if i < b.len() && b[i] == b'&' {
                i += 1;
            }
            let ns = i;
            while i < b.len() && name_char(b[i]) {
                i += 1;
            }
            if ns == i {
                return Err(format!("bad name at `{}`", &s[st..]));
            }
            name.push_str(&s[ns..i].to_ascii_lowercase());
            out.push(Tok::Id(name));
        } else {
            let two = s.get(i..i + 2).unwrap_or("");
            let p: &'static str = match two {
                "==" => "==",
                "<>" => "<>",
                "<=" => "<=",
                ">=" => ">=",
                _ => match c {
                    b'(' => "(",
                    b')' => ")",
                    b'[' => "[",
                    b']' => "]",
                    b',' => ",",
                    b'+' => "+",
                    b'-' => "-",
                    b'*' => "*",
                    b'/' => "/",
                    b'<' => "<",
                    b'>' => ">",
                    b'=' => "=",
                    b':' => ":",
                    _ => return Err(format!("unexpected `{}`", c as char)),
                },
            };
            i += p.len();
            out.push(Tok::P(p));
        }
    }
    Ok(out)
}

#[derive(Debug, Clone)]
struct VarRef {
    name: String,
    idx: Vec<Expr>,
}

#[derive(Debug, Clone)]
enum Expr {
    Num(f64),
    Str(String),
    Fmt(String),
    Var(VarRef),
    Call(String, Vec<Expr>),
    Neg(Box<Expr>),
    Not(Box<Expr>),
    Bin(&'static str, Box<Expr>, Box<Expr>),
}

struct Parser {
    t: Vec<Tok>,
    i: usize,
}

impl Parser {
    fn peek(&self) -> Option<&Tok> {
        self.t.get(self.i)
    }
    fn eat(&mut self, p: &str) -> bool {
        if matches!(self.peek(), Some(Tok::P(q)) if *q == p) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn eat_kw(&mut self, kw: &str) -> bool {
        if matches!(self.peek(), Some(Tok::Id(n)) if n == kw) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn expect(&mut self, p: &str) -> Result<(), String> {
        if self.eat(p) {
            Ok(())
        } else {
            Err(format!("`{p}` expected at {:?}", self.peek()))
        }
    }
    fn expr(&mut self) -> Result<Expr, String> {
        let mut l = self.and()?;
        while self.eat_kw("or") {
            l = Expr::Bin("or", Box::new(l), Box::new(self.and()?));
        }
        Ok(l)
    }
    fn and(&mut self) -> Result<Expr, String> {
        let mut l = self.not()?;
        while self.eat_kw("and") {
            l = Expr::Bin("and", Box::new(l), Box::new(self.not()?));
        }
        Ok(l)
    }
    fn not(&mut self) -> Result<Expr, String> {
        if self.eat_kw("not") {
            return Ok(Expr::Not(Box::new(self.not()?)));
        }
        self.cmp()
    }
    fn cmp(&mut self) -> Result<Expr, String> {
        let l = self.sum()?;
        for op in ["==", "<>", "<=", ">=", "<", ">"] {
            if self.eat(op) {
                let op: &'static str = match op {
                    "==" => "==",
                    "<>" => "<>",
                    "<=" => "<=",
                    ">=" => ">=",
                    "<" => "<",
                    _ => ">",
                };
                return Ok(Expr::Bin(op, Box::new(l), Box::new(self.sum()?)));
            }
        }
        Ok(l)
    }
    fn sum(&mut self) -> Result<Expr, String> {
        let mut l = self.prod()?;
        loop {
            if self.eat("+") {
                l = Expr::Bin("+", Box::new(l), Box::new(self.prod()?));
            } else if self.eat("-") {
                l = Expr::Bin("-", Box::new(l), Box::new(self.prod()?));
            } else {
                return Ok(l);
            }
        }
    }
    fn prod(&mut self) -> Result<Expr, String> {
        let mut l = self.unary()?;
        loop {
            if self.eat("*") {
                l = Expr::Bin("*", Box::new(l), Box::new(self.unary()?));
            } else if self.eat("/") {
                l = Expr::Bin("/", Box::new(l), Box::new(self.unary()?));
            } else {
                return Ok(l);
            }
        }
    }
    fn unary(&mut self) -> Result<Expr, String> {
        if self.eat("-") {
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        self.atom()
    }
    fn atom(&mut self) -> Result<Expr, String> {
        match self.t.get(self.i).cloned() {
            Some(Tok::Num(n)) => {
                self.i += 1;
                Ok(Expr::Num(n))
            }
            Some(Tok::Str(s)) => {
                self.i += 1;
                Ok(Expr::Str(s))
            }
            Some(Tok::Fmt(f)) => {
                self.i += 1;
                Ok(Expr::Fmt(f))
            }
            Some(Tok::P("(")) => {
                self.i += 1;
                let e = self.expr()?;
                self.expect(")")?;
                Ok(e)
            }
            Some(Tok::Id(name)) => {
                self.i += 1;
                if self.eat("(") {
                    let mut args = Vec::new();
                    if !self.eat(")") {
                        loop {
                            args.push(self.expr()?);
                            if self.eat(")") {
                                break;
                            }
                            self.expect(",")?;
                        }
                    }
                    return Ok(Expr::Call(name, args));
                }
                let mut idx = Vec::new();
                if self.eat("[") {
                    loop {
                        idx.push(self.expr()?);
                        if self.eat("]") {
                            break;
                        }
                        self.expect(",")?;
                    }
                }
                Ok(Expr::Var(VarRef { name, idx }))
            }
            t => Err(format!("unexpected {t:?}")),
        }
    }
    fn var(&mut self) -> Result<VarRef, String> {
        match self.atom()? {
            Expr::Var(v) => Ok(v),
            e => Err(format!("variable expected, got {e:?}")),
        }
    }
    /// Comma-separated expressions to the end.
    fn list(&mut self) -> Result<Vec<Expr>, String> {
        let mut out = vec![self.expr()?];
        while self.eat(",") {
            out.push(self.expr()?);
        }
        self.end()?;
        Ok(out)
    }
    fn end(&self) -> Result<(), String> {
        match self.peek() {
            None => Ok(()),
            t => Err(format!("trailing {t:?}")),
        }
    }
}

fn parse_expr_text(text: &str) -> Result<Expr, String> {
    let mut p = Parser {
        t: lex(text)?,
        i: 0,
    };
    let e = p.expr()?;
    p.end()?;
    Ok(e)
}

#[derive(Debug, Clone)]
enum Stmt {
    Assign(VarRef, Expr),
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    While(Expr, Vec<Stmt>),
    For(VarRef, Expr, Expr, Vec<Stmt>),
    Case(Expr, Vec<(Vec<Expr>, Vec<Stmt>)>, Vec<Stmt>),
    Call(String, Vec<Expr>),
    Return,
    Here(VarRef),
    Decompose(VarRef, Expr),
    Jmove(Expr),
    Break,
    Twait(Expr),
    Signal(Vec<Expr>),
    Tcp(String, Vec<Expr>),
}

fn upper_words(line: &str) -> Vec<String> {
    line.split_whitespace()
        .map(str::to_ascii_uppercase)
        .collect()
}

fn code(line: &str) -> &str {
    let mut in_str = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_str = !in_str,
            ';' if !in_str => return line[..i].trim(),
            _ => {}
        }
    }
    line.trim()
}

/// Parse statements until one of `stops` (returned) or the end.
fn block(
    lines: &[(usize, String)],
    i: &mut usize,
    stops: &[&str],
) -> Result<(Vec<Stmt>, String), String> {
    let mut out = Vec::new();
    while *i < lines.len() {
        let (n, line) = &lines[*i];
        let at = |e: String| format!("line {n}: {e}: `{line}`");
        let words = upper_words(line);
        let head = words[0].clone();
        let head_kw = head.trim_end_matches(':').to_string();
        if stops.contains(&head.as_str()) || stops.contains(&head_kw.as_str()) {
            return Ok((out, head_kw));
        }
        *i += 1;
        let rest = line[words[0].len()..].trim();
        let stmt = match head.as_str() {
            "IF" => {
                let cond = rest[..rest.len() - 4].trim();
                let cond = parse_expr_text(cond).map_err(at)?;
                let (then, stop) = block(lines, i, &["ELSE", "END"])?;
                *i += 1;
                let els = if stop == "ELSE" {
                    let (e, _) = block(lines, i, &["END"])?;
                    *i += 1;
                    e
                } else {
                    Vec::new()
                };
                Stmt::If(cond, then, els)
            }
            "WHILE" => {
                let cond = parse_expr_text(rest[..rest.len() - 2].trim()).map_err(at)?;
                let (body, _) = block(lines, i, &["END"])?;
                *i += 1;
                Stmt::While(cond, body)
            }
            "FOR" => {
                let up = rest.to_ascii_uppercase();
                let to = up.find(" TO ").ok_or_else(|| at("no TO".into()))?;
                let eq = rest.find('=').ok_or_else(|| at("no =".into()))?;
                let var = Parser {
                    t: lex(&rest[..eq]).map_err(at)?,
                    i: 0,
                }
                .var()
                .map_err(at)?;
                let from = parse_expr_text(&rest[eq + 1..to]).map_err(at)?;
                let till = parse_expr_text(&rest[to + 4..]).map_err(at)?;
                let (body, _) = block(lines, i, &["END"])?;
                *i += 1;
                Stmt::For(var, from, till, body)
            }
            "CASE" => {
                let e = parse_expr_text(rest[..rest.len() - 2].trim()).map_err(at)?;
                let mut arms = Vec::new();
                let mut any = Vec::new();
                loop {
                    let (_, l) = &lines[*i];
                    let w = upper_words(l);
                    let h = w[0].trim_end_matches(':');
                    *i += 1;
                    match h {
                        "VALUE" => {
                            let list = l.trim()[5..].trim().trim_end_matches(':');
                            let vals = Parser {
                                t: lex(list).map_err(at)?,
                                i: 0,
                            }
                            .list()
                            .map_err(at)?;
                            let (b, _) = block(lines, i, &["VALUE", "ANY", "END"])?;
                            arms.push((vals, b));
                        }
                        "ANY" => {
                            let (b, _) = block(lines, i, &["END"])?;
                            any = b;
                        }
                        "END" => break,
                        other => return Err(at(format!("{other} in CASE"))),
                    }
                }
                Stmt::Case(e, arms, any)
            }
            "CALL" => {
                let (name, args) = match rest.find('(') {
                    Some(p) => {
                        let inner =
                            &rest[p + 1..rest.rfind(')').ok_or_else(|| at("no )".into()))?];
                        let args = if inner.trim().is_empty() {
                            Vec::new()
                        } else {
                            Parser {
                                t: lex(inner).map_err(at)?,
                                i: 0,
                            }
                            .list()
                            .map_err(at)?
                        };
                        (rest[..p].trim().to_ascii_lowercase(), args)
                    }
                    None => (rest.to_ascii_lowercase(), Vec::new()),
                };
                Stmt::Call(name, args)
            }
            "RETURN" => Stmt::Return,
            "BREAK" => Stmt::Break,
            "HERE" => Stmt::Here(
                Parser {
                    t: lex(rest).map_err(at)?,
                    i: 0,
                }
                .var()
                .map_err(at)?,
            ),
            "JMOVE" => Stmt::Jmove(parse_expr_text(rest).map_err(at)?),
            "TWAIT" => Stmt::Twait(parse_expr_text(rest).map_err(at)?),
            "SIGNAL" => Stmt::Signal(
                Parser {
                    t: lex(rest).map_err(at)?,
                    i: 0,
                }
                .list()
                .map_err(at)?,
            ),
            "TCP_CONNECT" | "TCP_SEND" | "TCP_RECV" | "TCP_CLOSE" => Stmt::Tcp(
                head.clone(),
                Parser {
                    t: lex(rest).map_err(at)?,
                    i: 0,
                }
                .list()
                .map_err(at)?,
            ),
            "POINT" | "DECOMPOSE" => {
                let mut p = Parser {
                    t: lex(rest).map_err(at)?,
                    i: 0,
                };
                let v = p.var().map_err(at)?;
                p.expect("=").map_err(at)?;
                let e = p.expr().map_err(at)?;
                p.end().map_err(at)?;
                if head == "POINT" {
                    Stmt::Assign(v, e)
                } else {
                    Stmt::Decompose(v, e)
                }
            }
            "ELSE" | "END" | "VALUE" | "ANY" | "ANY:" => return Err(at("misplaced".into())),
            _ => {
                let mut p = Parser {
                    t: lex(line).map_err(at)?,
                    i: 0,
                };
                let v = p.var().map_err(at)?;
                p.expect("=").map_err(at)?;
                let e = p.expr().map_err(at)?;
                p.end().map_err(at)?;
                Stmt::Assign(v, e)
            }
        };
        out.push(stmt);
    }
    if stops.is_empty() {
        Ok((out, String::new()))
    } else {
        Err(format!("{stops:?} missing"))
    }
}

struct Program {
    params: Vec<String>,
    body: Vec<Stmt>,
}

#[derive(Debug, Clone)]
enum Place {
    Global(String),
    Local(usize, String),
}

#[derive(Default)]
struct Frame {
    vars: HashMap<String, V>,
    refs: HashMap<String, Place>,
}

enum Flow {
    Next,
    Return,
}

/// What the robot looks like to HERE.
#[derive(Debug, Clone, Copy)]
pub struct Robot {
    pub joints: [f64; 6],
    pub pose: [f64; 6],
}

pub struct As {
    programs: HashMap<String, Program>,
    pub globals: HashMap<String, V>,
    frames: Vec<Frame>,
    sockets: HashMap<i64, TcpStream>,
    next_socket: i64,
    pub robot: Robot,
    /// At most this many bytes per TCP_RECV (simulates a reply arriving in pieces).
    pub recv_split: usize,
    /// AS seconds → real seconds for TCP timeouts (tests run with short ones).
    pub time_scale: f64,
    pub signals: Vec<i64>,
    pub moves: Vec<V>,
    pub waits: Vec<f64>,
    steps: u64,
}

fn key(name: &str, idx: &[f64]) -> String {
    if idx.is_empty() {
        name.to_string()
    } else {
        let i: Vec<String> = idx.iter().map(|v| format!("{}", *v as i64)).collect();
        format!("{name}[{}]", i.join(","))
    }
}

fn truth(b: bool) -> V {
    V::Num(if b { -1.0 } else { 0.0 })
}

fn six(args: &[V]) -> Result<[f64; 6], String> {
    let mut out = [0.0; 6];
    for (o, a) in out.iter_mut().zip(args) {
        *o = a.num()?;
    }
    Ok(out)
}

impl As {
    /// Load a `.as` file: its programs and its `.REALS` values.
    pub fn load(text: &str) -> Result<As, String> {
        let mut programs = HashMap::new();
        let mut globals = HashMap::new();
        let lines: Vec<&str> = text.lines().collect();
        let mut i = 0;
        while i < lines.len() {
            let l = lines[i].trim();
            if let Some(rest) = l.strip_prefix(".PROGRAM ") {
                let name = rest[..rest.find('(').unwrap()].trim().to_ascii_lowercase();
                let inner = &rest[rest.find('(').unwrap() + 1..rest.find(')').unwrap()];
                let params = inner
                    .split(',')
                    .map(|p| p.trim().replace('&', "").to_ascii_lowercase())
                    .filter(|p| !p.is_empty())
                    .collect();
                let mut body = Vec::new();
                i += 1;
                while lines[i].trim() != ".END" {
                    let c = code(lines[i]);
                    if !c.is_empty() {
                        body.push((i + 1, c.to_string()));
                    }
                    i += 1;
                }
                let mut j = 0;
                let (stmts, _) = block(&body, &mut j, &[])?;
                programs.insert(
                    name,
                    Program {
                        params,
                        body: stmts,
                    },
                );
            } else if l == ".REALS" {
                i += 1;
                while lines[i].trim() != ".END" {
                    let (n, v) = lines[i].split_once('=').unwrap();
                    globals.insert(
                        n.trim().to_ascii_lowercase(),
                        V::Num(v.trim().parse().unwrap()),
                    );
                    i += 1;
                }
            }
            i += 1;
        }
        Ok(As {
            programs,
            globals,
            frames: vec![Frame::default()],
            sockets: HashMap::new(),
            next_socket: 1,
            robot: Robot {
                joints: [0.0, -90.0, 90.0, 0.0, 90.0, 0.0],
                pose: [400.0, 0.0, 500.0, 0.0, 180.0, 0.0],
            },
            recv_split: 1 << 16,
            time_scale: 0.02,
            signals: Vec::new(),
            moves: Vec::new(),
            waits: Vec::new(),
            steps: 0,
        })
    }

    /// Run statements (e.g. `CALL mm_get_visdata(1,n,st)`) in the top-level frame, whose
    /// variables are globals.
    pub fn exec(&mut self, text: &str) -> Result<(), String> {
        let lines: Vec<(usize, String)> = text
            .lines()
            .map(code)
            .filter(|l| !l.is_empty())
            .enumerate()
            .map(|(i, l)| (i + 1, l.to_string()))
            .collect();
        let mut i = 0;
        let (stmts, _) = block(&lines, &mut i, &[])?;
        let depth = self.frames.len();
        let r = self.run(&stmts).map(|_| ());
        self.frames.truncate(depth);
        r
    }

    pub fn num(&self, name: &str) -> f64 {
        match self.globals.get(&name.to_ascii_lowercase()) {
            Some(V::Num(n)) => *n,
            other => panic!("{name}: {other:?}"),
        }
    }

    pub fn get(&self, name: &str) -> Option<&V> {
        self.globals.get(&name.to_ascii_lowercase())
    }

    fn place(&mut self, v: &VarRef) -> Result<Place, String> {
        let idx: Vec<f64> = v
            .idx
            .iter()
            .map(|e| self.eval(e).and_then(|x| x.num()))
            .collect::<Result<_, _>>()?;
        let f = self.frames.len() - 1;
        if !v.name.starts_with('.') || f == 0 {
            // The top-level frame of `exec` is the caller's program: its names are globals.
            return Ok(Place::Global(key(v.name.trim_start_matches('.'), &idx)));
        }
        if idx.is_empty()
            && let Some(p) = self.frames[f].refs.get(&v.name)
        {
            return Ok(p.clone());
        }
        Ok(Place::Local(f, key(&v.name, &idx)))
    }

    fn read(&self, p: &Place) -> Result<V, String> {
        match p {
            Place::Global(k) => self.globals.get(k).cloned(),
            Place::Local(f, k) => self.frames[*f].vars.get(k).cloned(),
        }
        .ok_or_else(|| format!("undefined variable {p:?}"))
    }

    fn write(&mut self, p: &Place, v: V) {
        match p {
            Place::Global(k) => {
                self.globals.insert(k.clone(), v);
            }
            Place::Local(f, k) => {
                self.frames[*f].vars.insert(k.clone(), v);
            }
        }
    }

    fn set(&mut self, v: &VarRef, val: V) -> Result<(), String> {
        let p = self.place(v)?;
        self.write(&p, val);
        Ok(())
    }

    fn eval(&mut self, e: &Expr) -> Result<V, String> {
        Ok(match e {
            Expr::Num(n) => V::Num(*n),
            Expr::Str(s) => V::Str(s.clone()),
            Expr::Fmt(f) => V::Str(f.clone()),
            Expr::Var(v) => {
                let p = self.place(v)?;
                self.read(&p)?
            }
            Expr::Neg(x) => V::Num(-self.eval(x)?.num()?),
            Expr::Not(x) => truth(self.eval(x)?.num()? == 0.0),
            Expr::Bin(op, a, b) => {
                let (a, b) = (self.eval(a)?, self.eval(b)?);
                match (op, &a, &b) {
                    (&"+", V::Str(x), V::Str(y)) => V::Str(format!("{x}{y}")),
                    (&"==", V::Str(x), V::Str(y)) => truth(x == y),
                    (&"<>", V::Str(x), V::Str(y)) => truth(x != y),
                    _ => {
                        let (x, y) = (a.num()?, b.num()?);
                        match *op {
                            "+" => V::Num(x + y),
                            "-" => V::Num(x - y),
                            "*" => V::Num(x * y),
                            "/" => V::Num(x / y),
                            "==" => truth(x == y),
                            "<>" => truth(x != y),
                            "<" => truth(x < y),
                            ">" => truth(x > y),
                            "<=" => truth(x <= y),
                            ">=" => truth(x >= y),
                            "and" => truth(x != 0.0 && y != 0.0),
                            "or" => truth(x != 0.0 || y != 0.0),
                            o => return Err(format!("operator {o}")),
                        }
                    }
                }
            }
            Expr::Call(f, args) if f == "$decode" => {
                let Some(Expr::Var(v)) = args.first() else {
                    return Err("$DECODE needs a variable".into());
                };
                let p = self.place(v)?;
                let s = self.read(&p)?.str()?.to_string();
                let d = self.eval(&args[1])?.str()?.to_string();
                let mode = self.eval(&args[2])?.num()?;
                if mode != 0.0 {
                    return Err("only $DECODE mode 0 is modelled".into());
                }
                let at = s.find(|c| d.contains(c)).unwrap_or(s.len());
                self.write(&p, V::Str(s[at..].to_string()));
                V::Str(s[..at].to_string())
            }
            Expr::Call(f, args) => {
                let a: Vec<V> = args
                    .iter()
                    .map(|x| self.eval(x))
                    .collect::<Result<_, _>>()?;
                let n = |i: usize| {
                    a.get(i)
                        .ok_or("missing argument".to_string())
                        .and_then(V::num)
                };
                let s = |i: usize| {
                    a.get(i)
                        .ok_or("missing argument".to_string())
                        .and_then(|v| v.str().map(str::to_string))
                };
                match f.as_str() {
                    "int" => V::Num(n(0)?.trunc()),
                    "len" => V::Num(s(0)?.len() as f64),
                    "val" => {
                        let t = s(0)?;
                        V::Num(t.trim().parse().map_err(|_| format!("VAL({t:?})"))?)
                    }
                    "asc" => {
                        V::Num(*s(0)?.as_bytes().first().ok_or("ASC of an empty string")? as f64)
                    }
                    "$chr" => V::Str(((n(0)? as u8) as char).to_string()),
                    "$left" => {
                        let t = s(0)?;
                        V::Str(t[..(n(1)?.max(0.0) as usize).min(t.len())].to_string())
                    }
                    "$right" => {
                        let t = s(0)?;
                        let k = (n(1)?.max(0.0) as usize).min(t.len());
                        V::Str(t[t.len() - k..].to_string())
                    }
                    "$mid" => {
                        let t = s(0)?;
                        let st = (n(1)? as usize).saturating_sub(1).min(t.len());
                        let k = (n(2)? as usize).min(t.len() - st);
                        V::Str(t[st..st + k].to_string())
                    }
                    "$encode" => {
                        let fmt = s(0)?;
                        let v = n(1)?;
                        V::Str(if fmt == "/L" {
                            if v.fract() == 0.0 {
                                format!("{}", v as i64)
                            } else {
                                format!("{v}")
                            }
                        } else if let Some(spec) = fmt.strip_prefix("/F") {
                            let (w, d) = spec.split_once('.').ok_or("format")?;
                            let (w, d): (usize, usize) = (w.parse().unwrap(), d.parse().unwrap());
                            format!("{v:>w$.d$}")
                        } else {
                            return Err(format!("format {fmt}"));
                        })
                    }
                    "trans" => V::Pose(six(&a)?),
                    "#ppoint" => V::Joint(six(&a)?),
                    other => return Err(format!("function {other}")),
                }
            }
        })
    }

    fn run(&mut self, stmts: &[Stmt]) -> Result<Flow, String> {
        for s in stmts {
            self.steps += 1;
            if self.steps > 50_000_000 {
                return Err("step limit (endless loop?)".into());
            }
            if let Flow::Return = self.stmt(s)? {
                return Ok(Flow::Return);
            }
        }
        Ok(Flow::Next)
    }

    fn stmt(&mut self, s: &Stmt) -> Result<Flow, String> {
        match s {
            Stmt::Assign(v, e) => {
                let val = self.eval(e)?;
                self.set(v, val)?;
            }
            Stmt::If(c, t, e) => {
                let b = self.eval(c)?.num()? != 0.0;
                return self.run(if b { t } else { e });
            }
            Stmt::While(c, body) => {
                while self.eval(c)?.num()? != 0.0 {
                    if let Flow::Return = self.run(body)? {
                        return Ok(Flow::Return);
                    }
                }
            }
            Stmt::For(v, a, b, body) => {
                let (a, b) = (self.eval(a)?.num()?, self.eval(b)?.num()?);
                let mut i = a;
                while i <= b {
                    self.set(v, V::Num(i))?;
                    if let Flow::Return = self.run(body)? {
                        return Ok(Flow::Return);
                    }
                    i += 1.0;
                }
            }
            Stmt::Case(e, arms, any) => {
                let x = self.eval(e)?.num()?;
                for (vals, body) in arms {
                    for v in vals {
                        if self.eval(v)?.num()? == x {
                            return self.run(body);
                        }
                    }
                }
                return self.run(any);
            }
            Stmt::Call(name, args) => self.call(name, args)?,
            Stmt::Return => return Ok(Flow::Return),
            Stmt::Here(v) => {
                let val = if v.name.contains('#') {
                    V::Joint(self.robot.joints)
                } else {
                    V::Pose(self.robot.pose)
                };
                self.set(v, val)?;
            }
            Stmt::Decompose(v, e) => {
                let vals = match self.eval(e)? {
                    V::Pose(p) | V::Joint(p) => p,
                    other => return Err(format!("DECOMPOSE of {other:?}")),
                };
                let start = self.eval(&v.idx[0])?.num()?;
                for (k, x) in vals.iter().enumerate() {
                    let r = VarRef {
                        name: v.name.clone(),
                        idx: vec![Expr::Num(start + k as f64)],
                    };
                    self.set(&r, V::Num(*x))?;
                }
            }
            Stmt::Jmove(e) => {
                let v = self.eval(e)?;
                self.robot.joints = match &v {
                    V::Joint(j) => *j,
                    other => return Err(format!("JMOVE to {other:?}")),
                };
                self.moves.push(v);
            }
            Stmt::Break => {}
            Stmt::Twait(e) => {
                let t = self.eval(e)?.num()?;
                self.waits.push(t);
            }
            Stmt::Signal(list) => {
                for e in list {
                    let s = self.eval(e)?.num()?;
                    self.signals.push(s as i64);
                }
            }
            Stmt::Tcp(op, args) => self.tcp(op, args)?,
        }
        Ok(Flow::Next)
    }

    fn call(&mut self, name: &str, args: &[Expr]) -> Result<(), String> {
        let params = match self.programs.get(name) {
            Some(p) => p.params.clone(),
            None => return Err(format!("CALL of unknown program {name}")),
        };
        if params.len() != args.len() {
            return Err(format!(
                "CALL {name}: {} arguments for {}",
                args.len(),
                params.len()
            ));
        }
        let mut frame = Frame::default();
        for (p, a) in params.iter().zip(args) {
            match a {
                Expr::Var(v) => {
                    let place = self.place(v)?;
                    frame.refs.insert(p.clone(), place);
                }
                e => {
                    let v = self.eval(e)?;
                    frame.vars.insert(p.clone(), v);
                }
            }
        }
        self.frames.push(frame);
        let body = self.programs[name].body.clone();
        let r = self.run(&body);
        self.frames.pop();
        r.map(|_| ()).map_err(|e| format!("{name}: {e}"))
    }

    fn arg_place(&mut self, e: &Expr) -> Result<Place, String> {
        match e {
            Expr::Var(v) => self.place(v),
            other => Err(format!("variable expected, got {other:?}")),
        }
    }

    /// The elements `base[first..]` of an array argument written `name[first]`.
    fn element(&mut self, e: &Expr, offset: usize) -> Result<VarRef, String> {
        match e {
            Expr::Var(v) => {
                let first = self.eval(&v.idx[0])?.num()?;
                Ok(VarRef {
                    name: v.name.clone(),
                    idx: vec![Expr::Num(first + offset as f64)],
                })
            }
            other => Err(format!("array element expected, got {other:?}")),
        }
    }

    fn tcp(&mut self, op: &str, a: &[Expr]) -> Result<(), String> {
        match op {
            "TCP_CONNECT" => {
                let port = self.eval(&a[1])?.num()? as u16;
                let mut ip = [0u8; 4];
                for (k, o) in ip.iter_mut().enumerate() {
                    let r = self.element(&a[2], k)?;
                    *o = self.eval(&Expr::Var(r))?.num()? as u8;
                }
                let tmo = self.eval(&a[3])?.num()? * self.time_scale;
                let addr = SocketAddr::from((ip, port));
                let sock = match TcpStream::connect_timeout(&addr, Duration::from_secs_f64(tmo)) {
                    Ok(s) => {
                        let id = self.next_socket;
                        self.next_socket += 1;
                        self.sockets.insert(id, s);
                        id as f64
                    }
                    Err(_) => -1.0,
                };
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(sock));
            }
            "TCP_SEND" => {
                let sock = self.eval(&a[1])?.num()? as i64;
                let n = self.eval(&a[3])?.num()? as usize;
                let mut bytes = String::new();
                for k in 0..n {
                    let r = self.element(&a[2], k)?;
                    bytes.push_str(self.eval(&Expr::Var(r))?.str()?);
                }
                let ok = match self.sockets.get_mut(&sock) {
                    Some(s) => s.write_all(bytes.as_bytes()).is_ok(),
                    None => false,
                };
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(if ok { 0.0 } else { -1.0 }));
            }
            "TCP_RECV" => {
                let sock = self.eval(&a[1])?.num()? as i64;
                let tmo = self.eval(&a[4])?.num()? * self.time_scale;
                let max = self.eval(&a[5])?.num()? as usize;
                let mut buf = vec![0u8; self.recv_split.max(1)];
                let got = match self.sockets.get_mut(&sock) {
                    Some(s) => {
                        s.set_read_timeout(Some(Duration::from_secs_f64(tmo)))
                            .unwrap();
                        match s.read(&mut buf) {
                            Ok(0) => None,
                            Ok(k) => Some(buf[..k].to_vec()),
                            Err(e)
                                if matches!(
                                    e.kind(),
                                    ErrorKind::WouldBlock | ErrorKind::TimedOut
                                ) =>
                            {
                                None
                            }
                            Err(_) => None,
                        }
                    }
                    None => None,
                };
                let (ret, count) = match got {
                    None => (-1.0, 0.0),
                    Some(bytes) => {
                        let chunks: Vec<&[u8]> = bytes.chunks(max.max(1)).collect();
                        for (k, c) in chunks.iter().enumerate() {
                            let r = self.element(&a[2], k)?;
                            self.set(&r, V::Str(String::from_utf8_lossy(c).into_owned()))?;
                        }
                        (0.0, chunks.len() as f64)
                    }
                };
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(ret));
                let p = self.arg_place(&a[3])?;
                self.write(&p, V::Num(count));
            }
            "TCP_CLOSE" => {
                let sock = self.eval(&a[1])?.num()? as i64;
                let found = self.sockets.remove(&sock).is_some();
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(if found { 0.0 } else { -1.0 }));
            }
            other => return Err(other.to_string()),
        }
        Ok(())
    }
}
