//! What the translation must know of a whole file before it lowers any statement, gathered in
//! one pass over the file's pieces (`syntax::parse_pieces`) without keeping the statements:
//! each routine's header and declarations, and the few facts of its body that other routines'
//! statements ask about (which names it assigns, whether it moves, which routines it calls, its
//! labels, interrupt declarations and definitions). The statements themselves are lowered later,
//! one at a time, from a second parse ([`super::Parsed::each_statement`]), so a large routine
//! is never held whole.

use std::collections::BTreeSet;

use compact_str::CompactString;
use rustc_hash::{FxHashMap, FxHashSet};

use crate::syntax::ast::{self, Definition, Lowered, Stmt, StmtKind};

/// The outline of one file.
#[derive(Debug, Default)]
pub struct Outline {
    /// In source order (the order of `ast::SourceFile::routines`).
    pub routines: Vec<RoutineOutline>,
    /// The file has statements outside any DEF (a `.sub` fragment).
    pub top_level: bool,
    /// The first data list (`DEFDAT`), its declarations and assignments apart
    /// ([`Outline::take_dat_values`]).
    pub dat: Option<ast::DatModule>,
    /// The first data list's declarations and assignments: its values, lowered once and handed
    /// over (a taught program's `.dat` holds a pose per point: its trees were most of a
    /// translation's memory while they were lowered).
    dat_values: std::sync::Mutex<DatValues>,
    /// Upper-case routine name → index of the first routine of that name (a scan per call
    /// made a file of many routines quadratic).
    by_name: FxHashMap<String, usize>,
}

/// A data list's declarations and assignments (`name[]="text"`).
#[derive(Debug, Default)]
pub struct DatValues {
    pub decls: Vec<ast::Decl>,
    pub body: Vec<Stmt>,
}

impl Outline {
    /// The data list's declarations and assignments, until they are taken.
    pub fn dat_values(&self) -> std::sync::MutexGuard<'_, DatValues> {
        self.dat_values
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Hands over the data list's declarations and assignments (empty afterwards).
    pub fn take_dat_values(&self) -> DatValues {
        std::mem::take(&mut *self.dat_values())
    }

    /// The routine called `name` (case-insensitive), the first of that name.
    pub fn routine(&self, name: &str) -> Option<&RoutineOutline> {
        let i = *self.by_name.get(&name.to_ascii_uppercase())?;
        self.routines.get(i)
    }
}

/// One routine: its head, and facts of its body.
#[derive(Debug)]
pub struct RoutineOutline {
    /// Header, the definitions before the first statement, span and `closed`; `decls` and
    /// `body` are always empty: the head's declarations come again with the statements
    /// ([`super::Statement::Head`]), so the outline does not hold every routine's.
    pub head: ast::Routine,
    /// How many statement pieces the head's declarations and definitions took (the body starts
    /// after them in a re-parse).
    pub head_pieces: usize,
    /// Where the first declaration or statement after the header starts (definitions of the
    /// head excluded): a syntax error before it is on the header.
    pub first_after_header: Option<u32>,
    pub facts: BodyFacts,
}

/// What other statements ask about a routine's body (statements after the head, nested ones
/// included, visited depth-first in source order as `syntax::ast::each_stmt` does: the handler of an `INTERRUPT DECL` and the action of a `TRIGGER` included).
/// Kept for every routine of a file, so compact: sorted name lists instead of sets, and the
/// lists most routines leave empty behind one pointer.
#[derive(Debug, Default)]
pub struct BodyFacts {
    /// Upper-case names of the routine's parameters assigned anywhere (assignment targets, FOR
    /// variables), sorted.
    pub assigned: Box<[CompactString]>,
    /// Upper-case root names of assignment targets and of call arguments, sorted.
    pub written: Box<[CompactString]>,
    /// Routines called, by statement or inside an assigned value, in the order of their first
    /// call (each once). Names are inline (`CompactString`): no allocation per name.
    pub callees: Vec<CompactString>,
    /// A motion or spline block.
    pub moves: bool,
    rare: Option<Box<Rare>>,
}

/// The facts few routines have.
#[derive(Debug, Default)]
struct Rare {
    labels: Vec<ast::Ident>,
    interrupts: Vec<Stmt>,
    global_decls: Vec<ast::Decl>,
    definitions: Vec<(Definition, bool)>,
}

impl BodyFacts {
    /// Whether the routine assigns its parameter `upper` (an upper-case name).
    pub fn assigns(&self, upper: &str) -> bool {
        self.assigned.iter().any(|n| n == upper)
    }

    /// Label names, in visiting order.
    pub fn labels(&self) -> &[ast::Ident] {
        self.rare.as_ref().map_or(&[], |r| &r.labels)
    }

    /// `INTERRUPT DECL` statements, in visiting order.
    pub fn interrupts(&self) -> &[Stmt] {
        self.rare.as_ref().map_or(&[], |r| &r.interrupts)
    }

    /// `GLOBAL` declarations of the head and among the statements, in visiting order.
    pub fn global_decls(&self) -> &[ast::Decl] {
        self.rare.as_ref().map_or(&[], |r| &r.global_decls)
    }

    /// Definitions (ENUM, SIGNAL, …) among the statements, in visiting order, and whether
    /// each is a statement of the body itself (not nested in a block).
    pub fn definitions(&self) -> &[(Definition, bool)] {
        self.rare.as_ref().map_or(&[], |r| &r.definitions)
    }

    fn rare(&mut self) -> &mut Rare {
        self.rare.get_or_insert_default()
    }
}

/// The facts of the routine being read, in the forms that grow; [`Building::finish`] makes
/// them [`BodyFacts`] when the routine ends (one of these serves every routine).
#[derive(Debug, Default)]
struct Building {
    assigned: FxHashSet<CompactString>,
    written: BTreeSet<CompactString>,
    callees: Vec<CompactString>,
    called: FxHashSet<CompactString>,
    calls: Vec<CompactString>,
}

impl Building {
    fn add(&mut self, facts: &mut BodyFacts, stmt: &Stmt) {
        ast::each_stmt(std::slice::from_ref(stmt), &mut |s| match &s.kind {
            StmtKind::Assign { target, value } => {
                if let Some(id) = target.root_name() {
                    self.assigned.insert(key(id));
                    self.written.insert(key(id));
                }
                let mut calls = std::mem::take(&mut self.calls);
                expr_calls(value, &mut calls);
                for c in calls.drain(..) {
                    self.call(c);
                }
                self.calls = calls;
            }
            StmtKind::For { var, .. } => {
                self.assigned.insert(key(var));
            }
            StmtKind::Call { name, args } => {
                self.call(name.text.clone());
                for a in args.iter().flatten() {
                    if let Some(id) = a.root_name() {
                        self.written.insert(key(id));
                    }
                }
            }
            StmtKind::Motion(_) | StmtKind::Spline { .. } => facts.moves = true,
            StmtKind::Label { name } => facts.rare().labels.push(name.clone()),
            StmtKind::InterruptDecl { .. } => facts.rare().interrupts.push(s.clone()),
            StmtKind::Decl(d) if d.global => facts.rare().global_decls.push((**d).clone()),
            StmtKind::Definition(d) => facts
                .rare()
                .definitions
                .push((d.clone(), std::ptr::eq(s, stmt))),
            _ => {}
        });
    }

    /// A call of `name`: a routine called again changes nothing another routine asks.
    fn call(&mut self, name: CompactString) {
        if !self.called.contains(&name) {
            self.called.insert(name.clone());
            self.callees.push(name);
        }
    }

    /// The routine ends: its facts in their compact forms; only the parameters' names of
    /// those assigned are kept. Leaves this empty for the next routine.
    fn finish(&mut self, facts: &mut BodyFacts, params: &[ast::ParamDecl]) {
        let mut assigned: Vec<CompactString> = self
            .assigned
            .drain()
            .filter(|n| params.iter().any(|p| p.name.is(n)))
            .collect();
        assigned.sort_unstable();
        facts.assigned = assigned.into_boxed_slice();
        facts.written = std::mem::take(&mut self.written).into_iter().collect();
        facts.callees = self.callees.drain(..).collect();
        self.called.clear();
        // Emptying a set costs its capacity: one routine calling thousands (a main routine)
        // made every routine after it pay for that (2% of a 50 MB translation).
        if self.called.capacity() > SMALL {
            self.called = FxHashSet::default();
        }
        if self.assigned.capacity() > SMALL {
            self.assigned = FxHashSet::default();
        }
        if let Some(r) = &mut facts.rare {
            r.labels.shrink_to_fit();
            r.interrupts.shrink_to_fit();
            r.global_decls.shrink_to_fit();
            r.definitions.shrink_to_fit();
        }
    }
}

/// The capacity up to which [`Building`]'s sets are kept for the next routine.
const SMALL: usize = 256;

/// A name's upper-case form, inline.
fn key(id: &ast::Ident) -> CompactString {
    let mut k = id.text.clone();
    k.make_ascii_uppercase();
    k
}

/// Names of routines called inside an expression.
pub fn expr_calls(e: &ast::Expr, out: &mut Vec<CompactString>) {
    if let ast::ExprKind::Call { name, .. } = &e.kind {
        out.push(name.text.clone());
    }
    e.for_each_operand(|o| expr_calls(o, out));
}

/// The module a piece belongs to.
enum Open {
    None,
    Routine,
    Dat(ast::DatModule),
}

/// Builds an [`Outline`] from [`Lowered`] events, in text order.
pub struct OutlineBuilder {
    outline: Outline,
    open: Open,
    /// The open routine is still in its head (declarations and definitions only so far).
    in_head: bool,
    /// The open routine's facts while they grow.
    building: Building,
    /// The last routine's facts are still in `building` (its END not read yet).
    unfinished: bool,
}

impl Default for OutlineBuilder {
    fn default() -> Self {
        OutlineBuilder {
            outline: Outline::default(),
            open: Open::None,
            in_head: false,
            building: Building::default(),
            unfinished: false,
        }
    }
}

impl OutlineBuilder {
    /// Take one event (by reference: the caller passes it on).
    pub fn add(&mut self, event: &Lowered) {
        match event {
            Lowered::Routine(r) => {
                self.end_routine();
                self.outline.routines.push(RoutineOutline {
                    head: r.clone(),
                    head_pieces: 0,
                    first_after_header: None,
                    facts: BodyFacts::default(),
                });
                self.open = Open::Routine;
                self.in_head = true;
                self.unfinished = true;
            }
            Lowered::Dat(d) => self.open = Open::Dat(d.clone()),
            Lowered::Stmt(s) => match &mut self.open {
                Open::None => self.outline.top_level = true,
                Open::Dat(d) => d.add(s.clone()),
                Open::Routine => {
                    let r = self.outline.routines.last_mut().expect("a routine is open");
                    let head_definition = matches!(s.kind, StmtKind::Definition(_));
                    if !head_definition || !self.in_head {
                        r.first_after_header.get_or_insert(s.span.start);
                    }
                    if self.in_head {
                        match &s.kind {
                            StmtKind::Decl(d) => {
                                if d.global {
                                    r.facts.rare().global_decls.push((**d).clone());
                                }
                                r.head_pieces += 1;
                                return;
                            }
                            StmtKind::Definition(d) => {
                                r.head.definitions.push(d.clone());
                                r.head_pieces += 1;
                                return;
                            }
                            _ => self.in_head = false,
                        }
                    }
                    self.building.add(&mut r.facts, s);
                }
            },
            Lowered::Header(_) => {}
            Lowered::Close { span, closed } => {
                match std::mem::replace(&mut self.open, Open::None) {
                    Open::Routine => {
                        if let Some(r) = self.outline.routines.last_mut() {
                            r.head.close(*span, *closed);
                        }
                        self.end_routine();
                    }
                    Open::Dat(mut d) => {
                        d.close(*span);
                        if self.outline.dat.is_none() {
                            self.outline.dat = Some(d);
                        }
                    }
                    Open::None => {}
                }
                self.in_head = false;
            }
        }
    }

    /// The facts read since the last routine began become its [`BodyFacts`].
    fn end_routine(&mut self) {
        if std::mem::take(&mut self.unfinished)
            && let Some(r) = self.outline.routines.last_mut()
        {
            self.building.finish(&mut r.facts, &r.head.params);
        }
    }

    pub fn finish(mut self) -> Outline {
        self.end_routine();
        let o = &mut self.outline;
        if let Some(d) = &mut o.dat {
            *o.dat_values.get_mut().unwrap_or_else(|e| e.into_inner()) = DatValues {
                decls: std::mem::take(&mut d.decls),
                body: std::mem::take(&mut d.body),
            };
        }
        o.routines.shrink_to_fit();
        for (i, r) in o.routines.iter().enumerate() {
            o.by_name.entry(r.head.name.key()).or_insert(i);
        }
        self.outline
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The outline agrees with the whole AST on everything it keeps.
    #[test]
    fn outline_matches_the_ast() {
        let text = "&ACCESS RVP\nDEF a(x:IN)\n  DECL INT x\n  ENUM m_t p, q\n  DECL GLOBAL INT g\n  x = f(2)\n  IF x > 1 THEN\n    lbl:\n    PTP HOME\n    b(y)\n  ENDIF\n  DECL GLOBAL REAL r\n  SIGNAL s $OUT[3]\nEND\nDEFFCT INT f(v:IN)\n  DECL INT v\n  RETURN v\nENDFCT\nDEFDAT big\n  DECL INT k = 3\nENDDAT\n";
        let (ast, _) = ast::lower_pieces(text);
        let mut b = OutlineBuilder::default();
        let mut lowerer = ast::PieceLowerer::new(text);
        crate::syntax::parse_pieces(text, |p| lowerer.lower(p, |e| b.add(&e)));
        let o = b.finish();
        assert_eq!(o.routines.len(), ast.routines.len());
        for (r, a) in o.routines.iter().zip(&ast.routines) {
            let mut head = a.clone();
            head.body.clear();
            head.decls.clear();
            assert_eq!(r.head, head);
        }
        assert_eq!(*o.routines[0].facts.assigned, ["X"]);
        let a = &o.routines[0];
        assert_eq!(a.head_pieces, 3);
        assert_eq!(a.facts.callees, ["f", "b"]);
        assert_eq!(*a.facts.written, ["X", "Y"]);
        assert!(a.facts.moves);
        assert_eq!(a.facts.labels().len(), 1);
        // `DECL GLOBAL INT g` of the head, `DECL GLOBAL REAL r` of the body.
        assert_eq!(a.facts.global_decls().len(), 2);
        assert_eq!(a.facts.definitions().len(), 1);
        assert!(!o.routines[1].facts.moves);
        // The data list's values are apart from its definitions.
        let mut dat = ast.dat.clone().unwrap();
        let values = o.take_dat_values();
        assert_eq!(values.decls, std::mem::take(&mut dat.decls));
        assert_eq!(values.body, std::mem::take(&mut dat.body));
        assert_eq!(o.dat, Some(dat));
        assert!(o.take_dat_values().decls.is_empty(), "handed over once");
        assert!(!o.top_level);
    }

    /// An interrupt's handler and a trigger's action are calls of the routine: hoisting a
    /// call past them (`may_write`) must know what they may write.
    #[test]
    fn calls_in_interrupt_and_trigger_bodies_are_facts() {
        let text = "DEF a(n:OUT)\n  INTERRUPT DECL 3 WHEN $IN[1] DO on_part(p)\n  TRIGGER WHEN DISTANCE=0 DELAY=0 DO n = count() PRIO=-1\n  LIN P1\nEND\n";
        let mut b = OutlineBuilder::default();
        let mut lowerer = ast::PieceLowerer::new(text);
        crate::syntax::parse_pieces(text, |p| lowerer.lower(p, |e| b.add(&e)));
        let facts = &b.finish().routines[0].facts;
        assert_eq!(facts.callees, ["on_part", "count"]);
        assert_eq!(*facts.written, ["N", "P"]);
        assert_eq!(*facts.assigned, ["N"]);
    }
}
