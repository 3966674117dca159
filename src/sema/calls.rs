//! What a routine does to the rest of the program, from the model's resolved uses: the
//! routines it calls, the variables it (or anything it calls) may write, and the Mech-Mind
//! interface subprogram a statement calls. Consumers (the transpiler's call graph and hoisting,
//! the MM rules) ask these instead of matching names as text.

use crate::catalog::{Interface, Subprogram};
use crate::diag::Span;

use super::scope::Scope;
use super::{Access, FileId, Resolved, RoutineId, Sema, SymbolId, UseKind};

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
}
