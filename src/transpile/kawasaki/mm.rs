//! `MM_*` calls → the Kawasaki `mm_*` programs, driven by the catalog: every `[[kawasaki]]`
//! entry names the KUKA subprogram it corresponds to and, per parameter, the KUKA parameter
//! it takes its value from (`kuka`), the spec key that supplies it (`spec`) or the value to
//! pass (`default`). KUKA routines without a Kawasaki program either read the `vis_*` globals
//! (`MM_Get_PlanJps`/`MM_Get_PlanPose`, with the Vision Move index shift from the catalog) or
//! are untranslatable.

use crate::transpile::render::Emit;
use std::net::Ipv4Addr;

use super::format::{self, num};
use super::{R, Tx};
use crate::catalog::{AsKind, Direction, KawasakiCommand, Subprogram, catalog};
use crate::diag::Span;
use crate::transpile::front::names::package_name;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{Arg, ExprKind, Place, Ty};

/// KUKA package globals and the Kawasaki globals that hold the same data. `MM_UserData` and
/// `MM_Plan_Results` hold the data of one selected point on KUKA; Kawasaki keeps them per
/// point (`vis_custom_data[i,j]`, `vis_plan_result[i,j]`), so the translation fills AS copies
/// with these names where KUKA selects the point.
pub(super) const GLOBALS: [(&str, &str); 4] = [
    ("MM_Last_Status", "mm_status"),
    ("Do_Port", "mm_do_list"),
    ("MM_UserData", "mm_userdata"),
    ("MM_Plan_Results", "mm_plan_results"),
];

impl<'a> Tx<'a> {
    pub(super) fn mm_call(&mut self, sub: &'static Subprogram, args: &[Arg], span: Span) -> R<()> {
        let cat = catalog();
        match sub.name.as_str() {
            "MM_Get_PlanJps" | "MM_Get_PlanPose" => return self.plan_point(sub, args, span),
            // KUKA splits "get the custom data" and "select one point"; Kawasaki's
            // mm_get_dydata stores every point and mm_get_pose selects one.
            "MM_Get_DyPose" => {
                if let Some(k) = cat.kawasaki_computing(&sub.name) {
                    self.mm_command(sub, k, args, span)?;
                    let serial = self.kuka_arg(sub, args, "Serial", span)?;
                    return self.copy_point_data(&serial, false, span);
                }
            }
            _ => {}
        }
        match sub.kawasaki() {
            Some(k) => self.mm_command(sub, k, args, span),
            // The lowering refuses it (`Caps::mech_mind`).
            None => crate::transpile::render::not_lowered(
                span,
                "an MM_ routine without a Kawasaki command",
            ),
        }
    }

    /// `CALL mm_x(…)` with the arguments mapped parameter by parameter.
    fn mm_command(
        &mut self,
        sub: &'static Subprogram,
        k: &'static KawasakiCommand,
        args: &[Arg],
        span: Span,
    ) -> R<()> {
        let mut rendered = Vec::new();
        let mut used = vec![false; sub.params.len()];
        let mut prelude: Vec<String> = Vec::new();
        let mut server: Option<&crate::transpile::VisionServer> = None;
        for p in &k.params {
            // The KUKA parameter this one takes its value from, if the called routine has it
            // (MM_Get_DyPose borrows mm_get_pose, whose .speed it lacks).
            let kuka_index = p.kuka.as_ref().and_then(|kp| {
                sub.params
                    .iter()
                    .position(|q| q.ident().eq_ignore_ascii_case(kp))
            });
            if let Some(i) = kuka_index {
                let kp = sub.params[i].ident();
                used[i] = true;
                // The lowering refuses an omitted one (`Caps::mech_mind`).
                let Some(arg) = args.get(i).filter(|a| a.value.is_some()) else {
                    return crate::transpile::render::not_lowered(
                        span,
                        &format!("an omitted argument {kp}"),
                    );
                };
                rendered.push(self.mm_arg(p.kind, p.dir, arg, &mut prelude)?);
                if p.dir == Direction::In
                    && p.has_range()
                    && let Some(v) = arg.value.as_ref().and_then(|v| v.number())
                    && !p.in_range(v)
                {
                    self.out.rep.approximate(
                        FileId::Src,
                        arg.span,
                        format!(
                            "{} = {} is outside the range Kawasaki's {} documents for {} ({})",
                            kp,
                            num(v),
                            k.name,
                            p.name,
                            p.range_text().unwrap_or_default()
                        ),
                        "check the value against the Kawasaki interface",
                    );
                }
            } else if let Some(key) = &p.spec {
                if server.is_none() {
                    server = self.vision;
                }
                let s = server.as_ref().map(|s| (s.ip, s.port));
                let v = s.and_then(|(ip, port)| spec_value(key, ip, port));
                let Some(v) = v else {
                    return crate::transpile::render::catalog_defect(
                        span,
                        &format!("spec key `{key}` for {} is unknown", p.name),
                    );
                };
                rendered.push(num(v));
            } else if let Some(d) = p.default {
                rendered.push(num(d));
            } else if p.dir == Direction::Out {
                // An output KUKA does not have: a scratch local receives it.
                let tmp = self.scratch(&format!("mm_{}", p.ident()));
                let ty = as_ty(p.kind);
                rendered.push(format::param_sigil(&tmp, &ty));
            } else {
                return crate::transpile::render::catalog_defect(
                    span,
                    &format!("{} of {} has no value", p.name, k.name),
                );
            }
        }
        // KUKA arguments Kawasaki does not take.
        let mut after = Vec::new();
        let mut dropped_inputs = Vec::new();
        for (i, q) in sub.params.iter().enumerate() {
            if used[i] {
                continue;
            }
            if sub.name == "MM_Init_Socket" && i < 3 {
                // XML name and EKI flags: they selected the channel whose address is used.
                continue;
            }
            match q.dir {
                Direction::In => dropped_inputs.push(q.ident().to_owned()),
                Direction::Out => {
                    let Some(arg) = args.get(i) else {
                        continue;
                    };
                    let Some(place) = &arg.place else {
                        continue;
                    };
                    match k
                        .sets
                        .iter()
                        .find(|s| s.kuka.eq_ignore_ascii_case(q.ident()))
                    {
                        Some(set) => {
                            let (n, v) = (&set.kuka, set.value);
                            let ty = self.place_ty(place);
                            let t = self.place_text(place, &ty, arg.span)?;
                            after.push(format!("{t} = {}", num(v)));
                            self.out.rep.approximate(
                                FileId::Src,
                                arg.span,
                                format!("{} has no {n}; {} is set to {} after the call (all data arrive in one call)", k.name, self.src.src.slice(arg.span), num(v)),
                                "a loop that fetches further batches runs once; check that one call returns all points you need",
                            );
                        }
                        // A catalog test keeps every such output in the command's `sets`.
                        None => {
                            return crate::transpile::render::catalog_defect(
                                arg.span,
                                &format!("{} has no output {}", k.name, q.ident()),
                            );
                        }
                    }
                }
            }
        }
        if !dropped_inputs.is_empty() {
            let (noun, verb) = if dropped_inputs.len() == 1 {
                ("argument", "is")
            } else {
                ("arguments", "are")
            };
            self.out.rep.approximate(
                FileId::Src,
                span,
                format!(
                    "{} takes no {}; the {noun} {verb} dropped",
                    k.name,
                    dropped_inputs.join(", ")
                ),
                match k.assumption.as_deref() {
                    Some(a) => {
                        format!("check the behaviour on the Kawasaki side ({}: {a})", k.name)
                    }
                    None => format!("check the behaviour of {} on the Kawasaki side", k.name),
                },
            );
        }
        if let Some(s) = &server {
            self.server_used = Some(format!("{}:{} ({})", s.ip, s.port, s.origin));
        }
        for l in prelude {
            self.line(l);
        }
        if rendered.is_empty() {
            self.line_fmt(format_args!("CALL {}", k.name));
        } else {
            self.line_fmt(format_args!("CALL {}({})", k.name, rendered.join(",")));
        }
        for l in after {
            self.line(l);
        }
        Ok(())
    }

    /// One argument for a Kawasaki parameter of `kind`.
    fn mm_arg(
        &mut self,
        kind: AsKind,
        dir: Direction,
        arg: &Arg,
        prelude: &mut Vec<String>,
    ) -> R<String> {
        let Some(value) = &arg.value else {
            return crate::transpile::render::not_lowered(arg.span, "an omitted argument");
        };
        match (kind, dir) {
            (AsKind::Joint, Direction::In) => {
                if let ExprKind::Current { .. } = &value.kind {
                    let tmp = self.scratch("mm_here");
                    prelude.push(format!("HERE {}", format::with_sigil(&tmp, &Ty::Joint)));
                    return Ok(format::with_sigil(&tmp, &Ty::Joint));
                }
                if let ExprKind::Aggregate(a) = &value.kind {
                    let v = self.literal(a, value.span, FileId::Src)?;
                    let tmp = self.scratch("mm_joints");
                    let t = format::with_sigil(&tmp, &Ty::Joint);
                    prelude.push(format!("POINT {t} = {v}"));
                    return Ok(t);
                }
                if let ExprKind::Place(p) = &value.kind {
                    return self.place_text(p, &Ty::Joint, arg.span);
                }
                // A call's value is hoisted into a temporary: axis values reach here as a
                // place, a literal or `$AXIS_ACT` only.
                crate::transpile::render::not_lowered(arg.span, "a joint argument that is no value")
            }
            (_, Direction::Out) => {
                // The lowering refuses it (`Why::OutArgument`).
                let Some(place) = &arg.place else {
                    return crate::transpile::render::not_lowered(
                        arg.span,
                        "an OUT argument that is no variable",
                    );
                };
                let ty = as_ty(kind);
                let t = self.place_text(place, &ty, arg.span)?;
                Ok(if kind == AsKind::Pose {
                    format::param_sigil(&t, &ty)
                } else {
                    t
                })
            }
            (AsKind::Pose, Direction::In) => {
                if let ExprKind::Current { .. } = &value.kind {
                    let tmp = self.scratch("mm_here_p");
                    prelude.push(format!("HERE {tmp}"));
                    return Ok(format::param_sigil(&tmp, &Ty::Pose));
                }
                if let Some(p) = &arg.place {
                    let t = self.place_text(p, &Ty::Pose, arg.span)?;
                    return Ok(format::param_sigil(&t, &Ty::Pose));
                }
                self.expr(value)
            }
            _ => self.expr(value),
        }
    }

    /// The KUKA argument named `param`, rendered as a value.
    fn kuka_arg(&mut self, sub: &Subprogram, args: &[Arg], param: &str, span: Span) -> R<String> {
        let i = sub
            .params
            .iter()
            .position(|p| p.ident().eq_ignore_ascii_case(param));
        match i.and_then(|i| args.get(i)).and_then(|a| a.value.as_ref()) {
            Some(a) => self.expr(a),
            None => {
                crate::transpile::render::not_lowered(span, &format!("an omitted argument {param}"))
            }
        }
    }

    /// `MM_Get_PlanJps` / `MM_Get_PlanPose`: Kawasaki has no command; the waypoint is read
    /// from the `vis_*` globals mm_get_plandata filled.
    fn plan_point(&mut self, sub: &'static Subprogram, args: &[Arg], span: Span) -> R<()> {
        let joints = sub.name == "MM_Get_PlanJps";
        let serial = self.kuka_arg(sub, args, "Serial", span)?;
        let arg = |name: &str| -> Option<(Place, Span)> {
            sub.params
                .iter()
                .position(|p| p.ident().eq_ignore_ascii_case(name))
                .and_then(|i| args.get(i))
                .and_then(|a| a.place.clone().map(|p| (p, a.span)))
        };
        let (target_param, ty, parts) = if joints {
            (
                "MM_J",
                Ty::Joint,
                [
                    "vis_pos_j1",
                    "vis_pos_j2",
                    "vis_pos_j3",
                    "vis_pos_j4",
                    "vis_pos_j5",
                    "vis_pos_j6",
                ],
            )
        } else {
            (
                "MM_P",
                Ty::Pose,
                [
                    "vis_pos_x",
                    "vis_pos_y",
                    "vis_pos_z",
                    "vis_pos_o",
                    "vis_pos_a",
                    "vis_pos_t",
                ],
            )
        };
        for g in parts
            .iter()
            .chain(&["vis_pos_type", "vis_pos_tool", "vis_pos_spd"])
        {
            global(g, span)?;
        }
        let Some((target, at)) = arg(target_param) else {
            return crate::transpile::render::not_lowered(
                span,
                &format!("an omitted argument {target_param}"),
            );
        };
        let t = self.place_text(&target, &ty, at)?;
        let values: Vec<String> = parts.iter().map(|g| format!("{g}[{serial}]")).collect();
        let value = if joints {
            format!("#PPOINT({})", values.join(","))
        } else {
            format!("TRANS({})", values.join(","))
        };
        self.line_fmt(format_args!("POINT {t} = {value}"));
        for (kuka, global_name) in [
            ("MM_MoveType", "vis_pos_type"),
            ("MM_ToolNum", "vis_pos_tool"),
            ("MM_Speed", "vis_pos_spd"),
        ] {
            if let Some((a, at)) = arg(kuka) {
                let ty = self.place_ty(&a);
                let t = self.place_text(&a, &ty, at)?;
                self.line_fmt(format_args!("{t} = {global_name}[{serial}]"));
            }
        }
        self.copy_point_data(&serial, true, span)
    }

    /// KUKA fills `MM_UserData` (and, for plan points, `MM_Plan_Results`) with the data of the
    /// selected point, zeros where the point has none; the translation fills AS copies the
    /// same way, from the per-point Kawasaki globals, when the program reads them.
    /// `vision_move`: the data exist only for Vision Move waypoints (plan data).
    fn copy_point_data(&mut self, serial: &str, vision_move: bool, span: Span) -> R<()> {
        let user = self.src.uses_name("MM_UserData");
        let plan = vision_move && self.src.uses_name("MM_Plan_Results");
        if !user && !plan {
            return Ok(());
        }
        let cat = catalog();
        for g in [
            "vis_custom_data",
            "num_customdata",
            "vis_plan_result",
            "vis_pos_vismove",
        ] {
            global(g, span)?;
        }
        let k = self.scratch("mm_k");
        let user_to = package_name(&super::NAME_RULES, "MM_UserData").unwrap_or("mm_userdata");
        let plan_to =
            package_name(&super::NAME_RULES, "MM_Plan_Results").unwrap_or("mm_plan_results");
        if user {
            self.zero_loop(&k, user_to, cat.limits.user_data_len);
        }
        if plan {
            self.zero_loop(&k, plan_to, cat.kuka_plan_len());
        }
        if vision_move {
            self.line_fmt(format_args!("IF vis_pos_vismove[{serial}] == 1 THEN"));
            self.out.depth += 1;
        }
        if user {
            self.line_fmt(format_args!("FOR {k} = 1 TO num_customdata[{serial}]"));
            self.line_fmt(format_args!(
                "  {user_to}[{k}] = vis_custom_data[{serial},{k}]"
            ));
            self.line("END");
        }
        if plan {
            let mut runs: Vec<(u32, u32, i64)> = Vec::new();
            for kk in 1..=cat.kuka_plan_len() {
                let Some(w) = cat.kawasaki_plan_index(kk) else {
                    continue;
                };
                let shift = i64::from(w) - i64::from(kk);
                match runs.last_mut() {
                    Some(r) if r.2 == shift && r.1 + 1 == kk => r.1 = kk,
                    _ => runs.push((kk, kk, shift)),
                }
            }
            for (a, b, shift) in runs {
                let j = match shift {
                    0 => k.clone(),
                    s => format!("{k}+{s}"),
                };
                self.line_fmt(format_args!("FOR {k} = {a} TO {b}"));
                self.line_fmt(format_args!(
                    "  {plan_to}[{k}] = vis_plan_result[{serial},{j}]"
                ));
                self.line("END");
            }
            self.note(format!(
                "MM_Plan_Results[k] -> {plan_to}[k], copied from vis_plan_result[i,j] (Kawasaki inserts element 17, so KUKA 17..{} are Kawasaki 18..{})",
                cat.kuka_plan_len(),
                cat.kawasaki_plan_len()
            ));
        }
        if vision_move {
            self.out.depth -= 1;
            self.line("END");
        }
        if user {
            self.note(format!(
                "MM_UserData[k] -> {user_to}[k], copied from vis_custom_data[i,j] where KUKA selects point i"
            ));
        }
        Ok(())
    }

    fn zero_loop(&mut self, k: &str, array: &str, n: u32) {
        self.line_fmt(format_args!("FOR {k} = 1 TO {n}"));
        self.line_fmt(format_args!("  {array}[{k}] = 0"));
        self.line("END");
    }
}

/// A catalog Kawasaki global that must exist.
fn global(name: &str, span: Span) -> R<()> {
    match catalog().kawasaki_global(name) {
        Some(_) => Ok(()),
        None => crate::transpile::render::catalog_defect(
            span,
            &format!("Kawasaki global {name} is missing"),
        ),
    }
}

fn as_ty(kind: AsKind) -> Ty {
    match kind {
        AsKind::Real => Ty::Real,
        AsKind::Joint => Ty::Joint,
        AsKind::Pose => Ty::Pose,
        AsKind::String => Ty::Char,
    }
}

/// The value of a catalog `spec = "…"` key: `server_ip[1]`…`server_ip[4]`, `server_port`.
fn spec_value(key: &str, ip: Ipv4Addr, port: u16) -> Option<f64> {
    if key == "server_port" {
        return Some(f64::from(port));
    }
    let i: usize = key
        .strip_prefix("server_ip[")?
        .strip_suffix(']')?
        .parse()
        .ok()?;
    ip.octets().get(i.checked_sub(1)?).map(|o| f64::from(*o))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn package_globals_exist_on_both_sides() {
        let cat = catalog();
        for (kuka, kaw) in GLOBALS {
            assert!(cat.global(kuka).is_some(), "KUKA global {kuka}");
            if !matches!(kuka, "MM_UserData" | "MM_Plan_Results") {
                assert!(cat.kawasaki_global(kaw).is_some(), "Kawasaki global {kaw}");
            }
            assert!(kaw.len() <= super::super::NAME_RULES.max_len);
        }
    }

    /// Every parameter of every Kawasaki command a KUKA routine translates to gets a value:
    /// from a KUKA parameter, a known spec key, a default, or (an output) a scratch variable.
    #[test]
    fn every_kawasaki_parameter_has_a_source() {
        let ip = Ipv4Addr::new(192, 168, 1, 121);
        for k in catalog().kawasaki.iter().filter(|k| k.kuka.is_some()) {
            for p in &k.params {
                let ok = match (&p.kuka, &p.spec) {
                    (_, Some(key)) => spec_value(key, ip, 50000).is_some(),
                    (Some(_), None) => true,
                    (None, None) => p.default.is_some() || p.dir == Direction::Out,
                };
                assert!(ok, "{} of {}", p.name, k.name);
            }
        }
        for g in [
            "vis_pos_j1",
            "vis_pos_x",
            "vis_pos_t",
            "vis_pos_type",
            "vis_pos_tool",
            "vis_pos_spd",
        ] {
            assert!(global(g, Span::new(0, 0)).is_ok(), "{g}");
        }
    }

    #[test]
    fn spec_keys() {
        let ip = Ipv4Addr::new(192, 168, 1, 121);
        assert_eq!(spec_value("server_ip[4]", ip, 50000), Some(121.0));
        assert_eq!(spec_value("server_port", ip, 50000), Some(50000.0));
        assert_eq!(spec_value("server_ip[5]", ip, 1), None);
        assert_eq!(spec_value("server_ip[0]", ip, 1), None);
    }
}
