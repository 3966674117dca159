use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "MM006",
    name: "call-before-prerequisite",
    severity: Severity::Error,
    summary: "An interface call comes before its prerequisite",
    doc: "## What it checks\nThe interface has an order (catalog `after`/`before`, from the seed and the protocol reference): `MM_Get_VisData`, `MM_Get_Dy_Data`, `MM_Get_VisPath` after `MM_Start_Vis`; `MM_Get_VizData`, `MM_Set_Branch`, `MM_Set_Index`, `MM_Get_PlanData` after `MM_Start_Viz`; `MM_Get_DoList` after `MM_Get_VizData`; `MM_Set_DoList` after `MM_Get_DoList`; `MM_Get_DyPose` after `MM_Get_Dy_Data`; `MM_Get_PlanJps`/`MM_Get_PlanPose` after `MM_Get_PlanData`; `MM_Get_Pose`/`MM_Get_Jps` after a data call; `MM_Switch_Model` and `MM_Set_BoxSize` before `MM_Start_Vis`; `MM_Set_Pos` before `MM_Start_Viz`.\n\nThe check follows the routine's control flow (IF/ELSE, SWITCH, loops, GOTO) and calls into routines of the same file:\n- a missing prerequisite is reported only when NO path reaching the call has it (\"definitely missing\"); a prerequisite later in the same loop body counts from the second iteration;\n- a `before` call (e.g. `MM_Switch_Model`) is reported when the later call (`MM_Start_Vis`) has run on every path before it and no such call can follow it (so switching the recipe between two runs is fine);\n- calls to routines of other files satisfy nothing; routines whose callers are unknown (called from another file, or from nowhere) are not checked, and the main routine of a module called from another scanned file is treated the same way.\n\n## Why it matters\nThe vision server answers out-of-order requests with an error status (or stale data), so the cycle fails at run time.\n\n## Example\n```krl\nMM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)\nMM_Set_Branch(1, 2)      ; Mech-Viz is not running yet\nMM_Start_Viz(1, start)\n```\n\n## Fix\nCall the prerequisite first (here `MM_Start_Viz`), or move the configuration call before the call it configures.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    out.extend(
        ctx.flow()
            .findings
            .iter()
            .filter(|d| d.code == RULE.code)
            .cloned(),
    );
}
