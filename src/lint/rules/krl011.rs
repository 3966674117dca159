use rustc_hash::FxHashMap;

use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::text::nearest;
use crate::sema::{NameId, Resolved, RoutineId};

pub static RULE: Rule = Rule {
    code: "KRL011",
    name: "unknown-routine",
    severity: Severity::Error,
    summary: "A call reaches no routine: none of the module, no GLOBAL one, no EXT and no KSS built-in",
    doc: "## What it checks\nEvery call (a statement, a function in an expression, an interrupt's handler, a trigger's action) must reach a routine: a DEF/DEFFCT of the calling module, a GLOBAL DEF/DEFFCT or the main routine of another module of the robot, an `EXT`/`EXTFCT` declaration, or a KSS built-in (math and string functions, EthernetKRL, MsgLib, `BAS` …; see `krlkit rule KRL011` and the environment data). The help names the nearest routine.\n\nOnly reported when the whole robot is checked (a `$config.dat` among the files); calls of `MM_` names are left to MM001. Routines that KUKA's own files (system folder, technology packages, templates) call without a declaration in the workspace exist on that controller and are not reported either, and KUKA's own files are not checked. The names of an optional technology package (RSI on KR C2's `ST_` functions, FRI, ArcTech, EntertainTech: `kss.toml` `[[package]]`) are known when the config switches it on: `[lint] packages = [\"rsi_krc2\", \"fri\"]`.\n\n## Why it matters\nThe module does not link: the controller reports an unresolved subprogram when the program is selected.\n\n## Example\n```krl\nDEF cell()\n  pick_part()\nEND\nDEF pickpart()\nEND\n```\n\n## Fix\nCall the routine by its name, make it GLOBAL, or declare it with `EXT` where it is called.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    // KUKA's own files load on the controller; what they name exists there.
    if !ctx.workspace_complete() || ctx.is_vendor() {
        return;
    }
    let sema = ctx.sema;
    let mut suggestions: FxHashMap<(Option<RoutineId>, NameId), Option<&str>> =
        FxHashMap::default();
    for c in sema.calls(ctx.id) {
        if c.target != Resolved::Unresolved {
            continue;
        }
        let name = sema.name(c.name);
        if crate::catalog::has_interface_prefix(name) || ctx.in_environment(c.name) {
            continue;
        }
        let mut d = Diagnostic::error(
            RULE.code,
            c.span,
            format!(
                "`{name}` is not a routine of this module, a GLOBAL routine, an EXT declaration or a KSS built-in"
            ),
        );
        // One search per name and routine: each walks every visible name.
        let at = sema.position(ctx.id, c.span.start);
        let near = *suggestions.entry((at.routine, c.name)).or_insert_with(|| {
            let visible = sema.visible(ctx.id, c.span.start);
            let candidates = visible
                .iter()
                .filter(|(_, r)| {
                    matches!(
                        r,
                        Resolved::Routine(_) | Resolved::Ext(_) | Resolved::Builtin(_)
                    )
                })
                .map(|(n, _)| sema.name(*n));
            nearest(name, candidates)
        });
        d = match near {
            Some(n) => d.with_help(format!("did you mean `{n}`?")),
            None => d.with_help("define it, make it GLOBAL, or declare it with EXT"),
        };
        out.push(d);
    }
}

#[cfg(test)]
mod tests {
    use crate::lint::LintConfig;

    fn codes(config: &LintConfig) -> Vec<&'static str> {
        let src = "DEF cell()\n  ST_ETHERNET(1, 0, \"rsi.xml\")\n  FRIOPEN(10)\nEND\n";
        super::super::lint_robot(src, config)
            .into_iter()
            .map(|d| d.code)
            .collect()
    }

    #[test]
    fn technology_packages_are_known_when_switched_on() {
        assert_eq!(codes(&LintConfig::default()), ["KRL011", "KRL011"]);
        let on =
            crate::config::Config::parse("[lint]\npackages = [\"rsi_krc2\", \"fri\"]\n", "k.toml")
                .expect("config")
                .lint;
        assert_eq!(codes(&on), Vec::<&str>::new());
    }
}
