//! "Did you mean": the visible name an undeclared one reads as a typo of (KRL010, KRL019).

use rustc_hash::FxHashMap;

use crate::diag::Span;
use crate::lint::context::FileCtx;
use crate::lint::text::typo_of;
use crate::sema::{Access, FileId, NameId, Position, Resolved, RoutineId, Sema, UseKind};

/// Which visible variables may be suggested.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Candidates {
    /// Every one, the system's too.
    All,
    /// Only those declared in the files given (not the KSS environment's).
    Given,
}

/// The visible variable an undeclared name is a likely typo of ([`typo_of`] over what
/// [`Sema::visible`] lists as variables there), searched without walking every visible name
/// for each routine: a file can use undeclared names in hundreds of routines, and the
/// module's, the robot's and the system's names — thousands — are the same for all of them.
pub struct Near<'s> {
    sema: &'s Sema,
    file: FileId,
    candidates: Candidates,
    /// The variables visible outside the file's routines (built at the first search).
    outside: Option<Vec<(NameId, &'s str)>>,
    /// Per undeclared name: the names of `outside` it reads as a typo of, in name order.
    near_outside: FxHashMap<NameId, Vec<(NameId, &'s str)>>,
    /// Per routine and name: the answer.
    answers: FxHashMap<(Option<RoutineId>, NameId), Option<&'s str>>,
}

impl<'s> Near<'s> {
    pub fn new(sema: &'s Sema, file: FileId, candidates: Candidates) -> Near<'s> {
        Near {
            sema,
            file,
            candidates,
            outside: None,
            near_outside: FxHashMap::default(),
            answers: FxHashMap::default(),
        }
    }

    pub fn suggest(&mut self, routine: Option<RoutineId>, name: NameId) -> Option<&'s str> {
        if let Some(a) = self.answers.get(&(routine, name)) {
            return *a;
        }
        let (sema, id, candidates) = (self.sema, self.file, self.candidates);
        let text = sema.name(name);
        let outside = self.outside.get_or_insert_with(|| {
            let info = sema.file(id);
            let at = Position {
                robot: info.robot,
                module: info.module,
                routine: None,
            };
            sema.visible_vars_outside(id)
                .into_iter()
                .map(|n| (n, sema.name(n)))
                .filter(|&(_, s)| candidates == Candidates::All || given(sema, at, s))
                .collect()
        });
        let far = self.near_outside.entry(name).or_insert_with(|| {
            let mut v: Vec<_> = outside
                .iter()
                .filter(|&&(_, s)| typo_of(text, s))
                .map(|&(n, s)| (n, s))
                .collect();
            v.sort_unstable_by_key(|&(_, s)| s);
            v
        });
        let own = routine.map(|r| sema.routine_scope(r)).unwrap_or_default();
        let mine = own
            .iter()
            .filter(|(_, r)| matches!(r, Resolved::Symbol(_)))
            .map(|(n, _)| sema.name(*n))
            .filter(|s| typo_of(text, s))
            .min();
        // The routine's own names hide the others.
        let theirs = far
            .iter()
            .find(|(n, _)| !own.iter().any(|(o, _)| o == n))
            .map(|&(_, s)| s);
        let answer = mine.or(theirs);
        self.answers.insert((routine, name), answer);
        answer
    }
}

/// The variable `name` visible at `at` is declared in a file given (not by the KSS
/// environment).
fn given(sema: &Sema, at: Position, name: &str) -> bool {
    match sema.lookup_var(at, name) {
        Resolved::Symbol(s) => sema.symbol(s).decl.is_some(),
        _ => false,
    }
}

/// The variables a file uses that are declared nowhere visible (KRL010, KRL019): not `$`
/// names (the controller has more than krlkit lists), not names KUKA's own files use, not a
/// routine's name without parentheses (another mistake); once per name and line (`n = n + 1`
/// is one mistake). With the use's span, name and position.
pub fn undeclared_vars<'a>(
    ctx: &'a FileCtx<'a>,
) -> impl Iterator<Item = (Span, NameId, Position)> + 'a {
    let sema = ctx.sema;
    let mut seen = rustc_hash::FxHashSet::default();
    sema.uses(ctx.id)
        .iter()
        .enumerate()
        .filter(move |&(i, u)| {
            u.kind == UseKind::Var
                && u.access != Access::Mention
                && sema.resolution(ctx.id, i) == Resolved::Unresolved
        })
        .filter_map(move |(_, u)| {
            let id = sema.use_name(u);
            let name = sema.name(id);
            if name.starts_with('$') || ctx.in_environment(id) {
                return None;
            }
            let at = sema.position(ctx.id, u.span.start);
            if sema.lookup_call(at, name) != Resolved::Unresolved {
                return None;
            }
            seen.insert((ctx.lines().line_of(u.span.start as usize), id))
                .then_some((u.span, id, at))
        })
}
