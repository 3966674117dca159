use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "MM007",
    name: "plan-jps-pos-mismatch",
    severity: Severity::Error,
    summary: "`MM_Get_PlanJps`/`MM_Get_PlanPose` with a Jps_Pos of the wrong kind or different from `MM_Get_PlanData`",
    doc: "## What it checks\n`MM_Get_PlanJps` reads joint waypoints (Jps_Pos 1 or 3), `MM_Get_PlanPose` reads TCP waypoints (Jps_Pos 2 or 4). When the Jps_Pos argument's value is known (literal, constant, or a variable assigned earlier in the routine), it must be of the right kind, and it must equal the Jps_Pos of the `MM_Get_PlanData` call that fetched the waypoints on every path where that value is known. If any path reaches the call with an unknown Jps_Pos, only the kind is checked.\n\n## Why it matters\nThe waypoints are stored in the format `MM_Get_PlanData` asked for; reading them in another format gives joint values as a pose (or the other way round) and moves the robot somewhere unexpected.\n\n## Example\n```krl\nMM_Get_PlanData(1, num, vis_pos, status)\nMM_Get_PlanPose(1, 2, pose, move_type, tool, speed)   ; fetched as joints (1)\n```\n\n## Fix\nUse the same Jps_Pos in both calls and the matching routine: PlanJps for 1/3, PlanPose for 2/4.",
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
