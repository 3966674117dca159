use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use rustc_hash::FxHashMap;

use crate::lint::text::{distance_within, near_enough};
use crate::sema::{Access, FileId, NameId, Resolved, RoutineId, Sema, UseKind};

pub static RULE: Rule = Rule {
    code: "KRL010",
    name: "undeclared-name",
    severity: Severity::Error,
    summary: "A variable or constant is used that is declared nowhere it is visible",
    doc: "## What it checks\nEvery name a statement reads or writes must be declared where KRL looks for it, in this order: the routine (its parameters and DECLs), the module (its `.dat`), the GLOBAL declarations of the robot (PUBLIC data lists), `$config.dat` (every declaration in it, GLOBAL or not), and the system (KSS system variables and built-in data). The help names the nearest visible name.\n\nOnly reported when the whole robot is checked: with no `$config.dat` among the files, a name may be declared in a file that was not given, so the rule stays silent (`check` says so once). Names that KUKA's own files (system folder, technology packages, templates) use without a declaration in the workspace exist on that controller (an installed technology package) and are not reported either, and KUKA's own files are not checked. `$` system variables are never reported (the controller has more than krlkit lists), nor names that only appear in a line that did not parse (KRL001) or in a `VARSTATE(\"name\")` string.\n\n## Why it matters\nThe controller refuses to load the module (\"name not declared\"), often only when the program is selected on the robot.\n\n## Example\n```krl\nDEF pick()\n  DECL INT count\n  cnt = cnt + 1\nEND\n```\n\n## Fix\nDeclare the variable (in the routine, the module's `.dat`, or GLOBAL in a PUBLIC data list), or correct the name.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    // KUKA's own files load on the controller; what they name exists there.
    if !ctx.workspace_complete() || ctx.is_vendor() {
        return;
    }
    let sema = ctx.sema;
    let mut near = Near::new(sema, ctx.id);
    for (i, u) in sema.uses(ctx.id).iter().enumerate() {
        if u.kind != UseKind::Var
            || u.access == Access::Mention
            || sema.resolution(ctx.id, i) != Resolved::Unresolved
        {
            continue;
        }
        let name = sema.name(sema.use_name(u));
        if name.starts_with('$') || ctx.in_environment(sema.use_name(u)) {
            continue;
        }
        // A routine's name used without parentheses is another mistake, reported elsewhere.
        let at = sema.position(ctx.id, u.span.start);
        if sema.lookup_call(at, name) != Resolved::Unresolved {
            continue;
        }
        let d = Diagnostic::error(RULE.code, u.span, format!("`{name}` is not declared"));
        let help = match near.suggest(at.routine, sema.use_name(u)) {
            Some(n) => format!("did you mean `{n}`?"),
            None => "declare it in the routine, in the module's .dat, or GLOBAL in a PUBLIC \
                     data list"
                .to_owned(),
        };
        out.push(d.with_help(help));
    }
}

/// The nearest visible variable to an undeclared name ([`crate::lint::text::nearest`] over what
/// [`crate::sema::Sema::visible`] lists as variables there), searched without walking every
/// visible name for each routine: a file can use undeclared names in hundreds of routines, and
/// the module's, the robot's and the system's names — thousands — are the same for all of them.
struct Near<'s> {
    sema: &'s Sema,
    file: FileId,
    /// The variables visible outside the file's routines (built at the first search).
    outside: Option<Vec<(NameId, &'s str)>>,
    /// Per undeclared name: the names of `outside` near enough, nearest first.
    near_outside: FxHashMap<NameId, Vec<(usize, &'s str, NameId)>>,
    /// Per routine and name: the answer.
    answers: FxHashMap<(Option<RoutineId>, NameId), Option<&'s str>>,
}

impl<'s> Near<'s> {
    fn new(sema: &'s Sema, file: FileId) -> Near<'s> {
        Near {
            sema,
            file,
            outside: None,
            near_outside: FxHashMap::default(),
            answers: FxHashMap::default(),
        }
    }

    fn suggest(&mut self, routine: Option<RoutineId>, name: NameId) -> Option<&'s str> {
        if let Some(a) = self.answers.get(&(routine, name)) {
            return *a;
        }
        let (sema, id) = (self.sema, self.file);
        let text = sema.name(name);
        let max = near_enough(text);
        let outside = self.outside.get_or_insert_with(|| {
            sema.visible_vars_outside(id)
                .into_iter()
                .map(|n| (n, sema.name(n)))
                .collect()
        });
        let far = self.near_outside.entry(name).or_insert_with(|| {
            let mut v: Vec<_> = outside
                .iter()
                .filter_map(|&(n, s)| Some((distance_within(text, s, max)?, s, n)))
                .collect();
            v.sort_unstable();
            v
        });
        let own = routine.map(|r| sema.routine_scope(r)).unwrap_or_default();
        let mine = own
            .iter()
            .filter(|(_, r)| matches!(r, Resolved::Symbol(_)))
            .filter_map(|(n, _)| {
                let s = sema.name(*n);
                Some((distance_within(text, s, max)?, s))
            })
            .min();
        let theirs = far
            .iter()
            .find(|(_, _, n)| !own.iter().any(|(o, _)| o == n))
            .map(|&(d, s, _)| (d, s));
        let answer = mine.into_iter().chain(theirs).min().map(|(_, s)| s);
        self.answers.insert((routine, name), answer);
        answer
    }
}
