//! `MM_*` calls → methods of the script's Mech-Mind client (`mm`): IN arguments are passed,
//! OUT arguments are assigned from what the method returns, in the subprogram's order
//! (`MM_Get_VisData(1, last, n, st)` → `last, n, st = mm.get_visdata(1)`). Which methods exist
//! and what they send comes from the catalog (`client.rs`); `MM_Init_Socket` gets the vision
//! server's address from the spec or the EKI XML, as for Kawasaki.

use super::client::{method_name, supported};
use super::{R, Tx};
use crate::catalog::{Direction, Subprogram};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{Arg, ExprKind};

/// KUKA package globals and the client attributes that hold the same data.
pub(super) const GLOBALS: [(&str, &str); 4] = [
    ("MM_Last_Status", "mm.last_status"),
    ("Do_Port", "mm.do_port"),
    ("MM_UserData", "mm.user_data"),
    ("MM_Plan_Results", "mm.plan_results"),
];

impl<'a> Tx<'a> {
    pub(super) fn mm_call(&mut self, sub: &'static Subprogram, args: &[Arg], span: Span) -> R<()> {
        // The lowering refuses the rest (`Caps::mech_mind`).
        if !supported(sub) {
            return crate::transpile::render::not_lowered(
                span,
                "an MM_ routine that moves the robot",
            );
        }
        let method = format!("mm.{}", method_name(&sub.name));
        let mut ins = Vec::new();
        let mut places = Vec::new();
        if sub.name == "MM_Init_Socket" {
            // The lowering refuses the call without one (`Why::VisionServer`).
            let Some(server) = self.vision else {
                return crate::transpile::render::not_lowered(
                    span,
                    "MM_Init_Socket without a vision server",
                );
            };
            let time_out = sub
                .params
                .iter()
                .position(|p| p.ident() == "Time_Out")
                .and_then(|i| args.get(i))
                .and_then(|a| a.value.as_ref());
            let Some(time_out) = time_out else {
                return crate::transpile::render::not_lowered(span, "an omitted argument Time_Out");
            };
            ins.push(super::format::string(&server.ip.to_string()));
            ins.push(server.port.to_string());
            ins.push(self.expr(time_out)?);
            self.server_used = Some(format!("{}:{} ({})", server.ip, server.port, server.origin));
        } else {
            for (p, a) in sub.params.iter().zip(args) {
                let Some(value) = &a.value else {
                    return crate::transpile::render::not_lowered(
                        span,
                        &format!("an omitted argument {}", p.ident()),
                    );
                };
                match p.dir {
                    // `$AXIS_ACT`: None, for which the client sends the robot's current joints.
                    Direction::In if matches!(value.kind, ExprKind::Current { joints: true }) => {
                        ins.push("None".into())
                    }
                    Direction::In => ins.push(self.expr(value)?),
                    Direction::Out => {
                        // The lowering refuses it (`Why::OutArgument`).
                        let Some(place) = &a.place else {
                            return crate::transpile::render::not_lowered(
                                a.span,
                                "an OUT argument that is no variable",
                            );
                        };
                        places.push(self.target(place, a.span, true)?);
                    }
                }
            }
            self.current_pose_caveats(sub, args, span);
        }
        self.mm_used.insert(sub.name.clone());
        let call = format!("{method}({})", ins.join(", "));
        self.assign_many(&places, &call);
        Ok(())
    }

    /// Requests that carry the robot's current joints send six of a Rizon's seven; the
    /// current flange pose comes from RobotStates.
    fn current_pose_caveats(&mut self, sub: &Subprogram, args: &[Arg], span: Span) {
        // The SendPos_Type that sends the current joints, and the one that sends MM_J (the
        // catalog's meaning of SendPos_Type; `$AXIS_ACT` as MM_J also means the current joints).
        let (current, given) = match sub.name.as_str() {
            "MM_Start_Vis" => (1, 3),
            "MM_Start_Viz" => (1, 2),
            _ => return,
        };
        let Some(at) = sub.params.iter().position(|p| p.ident() == "SendPos_Type") else {
            return;
        };
        let axis_act_arg = args
            .last()
            .and_then(|a| a.value.as_ref())
            .is_some_and(|a| matches!(a.kind, ExprKind::Current { joints: true }));
        let sends_current = match args
            .get(at)
            .and_then(|a| a.value.as_ref())
            .and_then(|v| v.integer())
        {
            Some(t) => t == current || (axis_act_arg && t == given),
            None => true,
        };
        let invertible = self.fx.joint_map.as_ref().is_some_and(|m| m.invertible());
        if sends_current && !invertible {
            self.out.rep.approximate(
                FileId::Src,
                span,
                "the request carries the robot's current joints: six values, but a Rizon has seven (the client sends joints 1-6 [?])",
                "set the Mech-Vision/Mech-Viz project up for the Rizon, or give --joint-map so the joints are read back as KUKA axes",
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalog::catalog;

    #[test]
    fn package_globals_are_catalog_globals() {
        let cat = catalog();
        for (kuka, _) in GLOBALS {
            assert!(cat.global(kuka).is_some(), "KUKA global {kuka}");
        }
    }
}
