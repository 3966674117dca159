//! What a routine does to the rest of the program, from the model's resolved uses: the
//! routines it calls, the variables it (or anything it calls) may write, the Mech-Mind
//! interface subprogram a statement calls, what a call of a name reaches and whether such a
//! call moves the robot. Consumers (the transpiler's call graph and hoisting, the MM rules)
//! ask these instead of matching names as text.

use crate::catalog::{Interface, Subprogram};
use crate::diag::Span;

use super::scope::Scope;
use super::{Access, FileId, Position, Resolved, RoutineId, Sema, SymbolId, UseKind, env};

impl Sema {
    /// The routines of the workspace `routine` calls, each once, in the order of their first
    /// call (including calls in its INTERRUPT declarations and TRIGGER actions).
    pub fn callees(&self, routine: RoutineId) -> Vec<RoutineId> {
        let mut out = Vec::new();
        for c in self.calls(self.routine(routine).file) {
            if c.caller == Some(routine)
                && let Resolved::Routine(t) = c.target
                && !out.contains(&t)
            {
                out.push(t);
            }
        }
        out
    }

    /// The variables outside any routine's frame (module data, GLOBAL and system variables)
    /// that `routine` or a routine it calls, transitively, may write: assigned, or passed as a
    /// variable to a routine (which writes it when the parameter is OUT). Sorted, each once.
    pub fn writes(&self, routine: RoutineId) -> Vec<SymbolId> {
        let mut seen = vec![routine];
        let mut todo = vec![routine];
        let mut out = Vec::new();
        while let Some(r) = todo.pop() {
            let info = self.routine(r);
            for (k, u) in self.uses(info.file).iter().enumerate() {
                if u.owner != info.index
                    || u.kind != UseKind::Var
                    || !matches!(u.access, Access::Write | Access::Arg)
                {
                    continue;
                }
                if let Resolved::Symbol(s) = self.resolution(info.file, k)
                    && !matches!(self.symbol(s).scope, Scope::Routine(_))
                {
                    out.push(s);
                }
            }
            for c in self.callees(r) {
                if !seen.contains(&c) {
                    seen.push(c);
                    todo.push(c);
                }
            }
        }
        out.sort_unstable_by_key(|s| s.index());
        out.dedup();
        out
    }

    /// What a call of `name` reaches when made inside `caller` (`None`: outside any routine)
    /// of `file`: the lookup the model makes for a call written there.
    pub fn call_target(&self, file: FileId, caller: Option<RoutineId>, name: &str) -> Resolved {
        let info = self.file(file);
        let at = Position {
            robot: info.robot,
            module: info.module,
            routine: caller,
        };
        self.lookup_call(at, name)
    }

    /// The Mech-Mind subprogram a call that reaches `target` calls (the catalog's, or an EXT
    /// of one), in either interface generation (1.x first).
    pub fn mm_target(&self, target: Resolved) -> Option<&'static Subprogram> {
        self.mm_subprogram(target, Interface::V1)
            .or_else(|| self.mm_subprogram(target, Interface::V2))
    }

    /// Whether a call that reaches `target` moves the robot, as far as the model knows without
    /// reading a body: a Mech-Mind subprogram (or an EXT of one) when its catalog shape moves;
    /// a KSS built-in, or an EXT declaring one, unless `kss.toml` marks it `still`; a routine
    /// of another module (an EXT, or a name the model cannot see) may. `None` for a routine
    /// of the workspace: its body decides.
    pub fn call_moves(&self, target: Resolved) -> Option<bool> {
        if let Resolved::Routine(_) = target {
            return None;
        }
        if let Some(s) = self.mm_target(target) {
            return Some(s.shape.moves());
        }
        let still = |name: &str| {
            env()
                .routines
                .iter()
                .any(|r| r.still && r.decl.name.is(name))
        };
        Some(match target {
            Resolved::Builtin(b) => !env().routines[self.builtin(b).env_index].still,
            Resolved::Ext(x) => !still(self.name(self.ext(x).name)),
            _ => true,
        })
    }

    /// The Mech-Mind interface subprogram (catalog, 1.x) that the statement at `span` of
    /// `file` calls: a call the model resolved to the catalog, or to the package's routine (or
    /// an EXT of it) of that name ([`Sema::mm_subprogram`]).
    pub fn mm_call(&self, file: FileId, span: Span) -> Option<&'static Subprogram> {
        self.calls(file)
            .filter(|c| span.start <= c.span.start && c.span.end <= span.end)
            .find_map(|c| self.mm_subprogram(c.target, Interface::V1))
    }
}

#[cfg(test)]
mod tests {
    use super::super::Analysis;
    use super::super::tests::analysis;
    use super::*;

    fn routine(a: &Analysis, name: &str) -> RoutineId {
        a.sema
            .routines()
            .find(|(_, r)| a.sema.name(r.name).eq_ignore_ascii_case(name))
            .map(|(id, _)| id)
            .expect("routine")
    }

    fn names(a: &Analysis, ids: Vec<RoutineId>) -> Vec<String> {
        ids.into_iter()
            .map(|r| a.sema.name(a.sema.routine(r).name).to_string())
            .collect()
    }

    const CELL: &str = "DEF cell()\nDECL INT n\nINTERRUPT DECL 3 WHEN $IN[1] DO on_stop()\n\
        LIN {X 1} \nTRIGGER WHEN DISTANCE=0 DELAY=0 DO mark()\nbump(n)\nbump(n)\nn = 2\nEND\n\
        DEF bump(k:OUT)\nDECL INT k\nk = 1\ncount = count + 1\nEND\n\
        DEF on_stop()\nstopped = TRUE\nEND\n\
        DEF mark()\nEND\n";
    const CELL_DAT: &str =
        "DEFDAT cell\nDECL INT count = 0\nDECL BOOL stopped = FALSE\nDECL INT unused = 0\nENDDAT\n";

    #[test]
    fn callees_include_interrupt_and_trigger_calls_once_each() {
        let a = analysis(&[("cell.src", CELL), ("cell.dat", CELL_DAT)]);
        let got = names(&a, a.sema.callees(routine(&a, "cell")));
        assert_eq!(got, ["on_stop", "mark", "bump"]);
        assert!(a.sema.callees(routine(&a, "mark")).is_empty());
    }

    #[test]
    fn writes_are_transitive_and_leave_out_locals() {
        let a = analysis(&[("cell.src", CELL), ("cell.dat", CELL_DAT)]);
        let mut got: Vec<String> = a
            .sema
            .writes(routine(&a, "cell"))
            .into_iter()
            .map(|s| a.sema.name(a.sema.symbol(s).name).to_string())
            .collect();
        got.sort();
        assert_eq!(got, ["count", "stopped"]);
        let bump: Vec<_> = a.sema.writes(routine(&a, "bump"));
        assert_eq!(bump.len(), 1, "bump writes count, not its parameter");
    }

    #[test]
    fn mm_call_is_the_catalog_subprogram_the_statement_calls() {
        let src = "DEF cell()\nMM_Start_Vis(1, 0, 1, 0)\nn = 1\nEND\n";
        let a = analysis(&[("cell.src", src)]);
        let f = a.sema.file_id("cell.src").expect("file");
        let line = |i: usize| {
            let start: usize = src.split_inclusive('\n').take(i).map(str::len).sum();
            let len = src.split_inclusive('\n').nth(i).expect("line").len();
            Span::new(start, start + len)
        };
        let got = a.sema.mm_call(f, line(1)).map(|s| s.name.as_str());
        assert_eq!(
            got.map(str::to_ascii_uppercase).as_deref(),
            Some("MM_START_VIS")
        );
        assert!(a.sema.mm_call(f, line(2)).is_none());
    }

    /// A call reaches what the model declares where it is written; whether it moves comes
    /// from the catalog's shape, `kss.toml`'s `still` (also through an EXT declaring the
    /// built-in) or, for a routine of the workspace, from its body (`None`).
    #[test]
    fn call_targets_and_whether_they_move() {
        let src = "DEF cell()\nEXT BAS(BAS_COMMAND :IN, REAL :IN)\nEXT elsewhere()\n\
            EXT MM_Get_Status(INT :OUT)\nEXT MM_Calib(INT :IN)\nEND\n\
            DEF helper()\nEND\n";
        let a = analysis(&[("cell.src", src)]);
        let f = a.sema.file_id("cell.src").expect("file");
        let cell = routine(&a, "cell");
        let moves = |caller, name| a.sema.call_moves(a.sema.call_target(f, caller, name));
        assert_eq!(
            a.sema.call_target(f, Some(cell), "HELPER"),
            Resolved::Routine(routine(&a, "helper"))
        );
        assert_eq!(moves(Some(cell), "helper"), None);
        assert_eq!(moves(Some(cell), "MsgNotify"), Some(false));
        assert_eq!(moves(None, "StrLen"), Some(false));
        assert_eq!(
            moves(Some(cell), "BAS"),
            Some(false),
            "an EXT of a still built-in"
        );
        assert!(matches!(
            a.sema.call_target(f, Some(cell), "BAS"),
            Resolved::Ext(_)
        ));
        assert_eq!(moves(Some(cell), "elsewhere"), Some(true));
        assert_eq!(
            moves(None, "elsewhere"),
            Some(true),
            "declared nowhere outside cell"
        );
        assert_eq!(moves(None, "MM_Get_Status"), Some(false));
        assert_eq!(moves(None, "MM_Calib"), Some(true));
        assert_eq!(moves(None, "MM_Get_Property"), Some(false), "2.x only");
        assert_eq!(
            moves(Some(cell), "MM_Get_Status"),
            Some(false),
            "an EXT of it"
        );
        assert_eq!(moves(Some(cell), "MM_Calib"), Some(true), "an EXT of it");
    }
}
