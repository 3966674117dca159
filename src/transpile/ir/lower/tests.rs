use super::*;
use crate::transpile::ir::{LoopKind, Place};
use crate::transpile::{Target, render};

/// The loops the lowering makes of `text`'s routines, in order.
fn loop_kinds(text: &str) -> Vec<&'static str> {
    let program = front::Program::new(front::Parsed::new("t.src", text), None);
    let options = Options::default();
    let mut lower = Lower::new(&program, &options, render::backend(Target::Kawasaki).caps());
    let mut kinds = Vec::new();
    program.src.each_statement(false, |s| match s {
        front::Statement::Begin(i) => drop(lower.begin_routine(*i)),
        front::Statement::Head(s) => lower.head(s, &mut Block::new()),
        front::Statement::Stmt(s) => {
            for op in lower.stmt(s) {
                if let Op::Loop { kind, .. } = &op.op {
                    kinds.push(match kind {
                        LoopKind::While(_) => "while",
                        LoopKind::Forever => "forever",
                        _ => "other",
                    });
                }
            }
        }
        front::Statement::End(_) => drop(lower.end_routine()),
    });
    kinds
}

/// A WHILE whose test stops the advance run stays a WHILE when its body cannot move the
/// robot, and becomes an endless loop testing at its top when it may: whether a call moves
/// is the model's answer (a `still` KSS routine, called directly or through a routine of the
/// file, does not; a routine of the file that moves does), the same for a direct call as for
/// one nested in a callee.
#[test]
fn whether_a_call_moves_comes_from_the_model() {
    let text = "DEF main()\n  WHILE $IN[1]\n    MsgNotify(\"a\", \"b\", 1)\n  ENDWHILE\n  \
        WHILE $IN[2]\n    note()\n  ENDWHILE\n  WHILE $IN[3]\n    go()\n  ENDWHILE\nEND\n\
        DEF note()\n  MsgQuit(\"a\", \"b\", 2)\nEND\nDEF go()\n  PTP HOME\nEND\n";
    assert_eq!(loop_kinds(text), ["while", "while", "forever"]);
}

/// Per op of interest (`kept`, or refused): `None` where it was kept, the reason where the
/// lowering refused its statement.
fn refusals(ops: Vec<Op>, kept: fn(&Op) -> bool) -> Vec<Option<Why>> {
    ops.into_iter()
        .filter_map(|op| match op {
            Op::Unsupported { why, .. } => Some(Some(why)),
            op if kept(&op) => Some(None),
            _ => None,
        })
        .collect()
}

/// The top-level ops the lowering makes of `text` for `target`, and the program it recorded
/// (with joint maps for every target).
fn lowered(text: &str, target: Target) -> (Program, Vec<Op>) {
    let mut options = Options {
        joint_map: Some(crate::transpile::kawasaki::joint_map("A1,A2,A3,A4,A5,A6").unwrap()),
        ..Options::default()
    };
    options.flexiv.joint_map =
        Some(crate::transpile::flexiv::options::joint_map("A1,A2,0,A3,A4,A5,A6").unwrap());
    lowered_with(text, target, &options)
}

fn lowered_with(text: &str, target: Target, options: &Options) -> (Program, Vec<Op>) {
    let program = front::Program::new(front::Parsed::new("t.src", text), None);
    let mut lower = Lower::new(&program, options, render::backend(target).caps());
    let mut ops = Vec::new();
    program.src.each_statement(false, |s| match s {
        front::Statement::Begin(i) => ops.extend(lower.begin_routine(*i).into_iter().map(|s| s.op)),
        front::Statement::Head(s) => lower.head(s, &mut Block::new()),
        front::Statement::Stmt(s) => ops.extend(lower.stmt(s).into_iter().map(|s| s.op)),
        front::Statement::End(_) => ops.extend(lower.end_routine().into_iter().map(|s| s.op)),
    });
    (lower.finish().program, ops)
}

/// A target without functions (`Caps::functions`) gets a DEFFCT as a routine with an OUT
/// parameter in the model: its RETURN assigns it, its calls pass the receiving place last.
#[test]
fn a_function_without_functions_is_an_out_parameter() {
    let text = "DEF main()\nDECL REAL x\nx = f(2.0) + 1\nx = f(3.0)\nEND\n\
        DEFFCT REAL f(a:IN)\nDECL REAL a\nRETURN a * 2\nENDFCT\n";
    for target in [Target::Kawasaki, Target::Rapid] {
        let functions = render::backend(target).caps().functions;
        let (program, ops) = lowered(text, target);
        let f = program.routine(RoutineId(1));
        assert_eq!(f.result.is_some(), !functions, "{target:?}");
        assert_eq!(f.params.len(), 1 + usize::from(!functions), "{target:?}");
        assert_eq!(f.krl_params().len(), 1);
        let calls: Vec<(usize, bool)> = ops
            .iter()
            .filter_map(|op| match op {
                Op::Call { args, ret, .. } => Some((args.len(), ret.is_some())),
                _ => None,
            })
            .collect();
        let want = if functions { (1, true) } else { (2, false) };
        assert_eq!(calls, [want, want], "{target:?}");
        let returns: Vec<bool> = ops
            .iter()
            .filter_map(|op| match op {
                Op::Return(v) => Some(v.is_some()),
                _ => None,
            })
            .collect();
        assert_eq!(returns, [functions], "{target:?}");
        if let Some(r) = f.result {
            assert!(
                ops.iter()
                    .any(|op| matches!(op, Op::Assign { place: Place::Var(v), .. } if *v == r))
            );
        }
    }
}

/// The lowering maps KRL's blending kinds onto what the target holds (`Caps::blending`):
/// C_PTP becomes a distance with a TR002 where the target blends by distance only, and a
/// blended motion to axis values stops where the target cannot blend it.
#[test]
fn blending_kinds_follow_the_targets_caps() {
    use crate::transpile::ir::Blend;
    let text = "DEF main()\nPTP {X 1, Y 2, Z 3, A 0, B 0, C 0} C_PTP\n\
        PTP {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0} C_DIS\nEND\n";
    for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
        let caps = render::backend(target).caps().blending;
        let (program, ops) = lowered(text, target);
        let blends: Vec<&Blend> = ops
            .iter()
            .filter_map(|op| match op {
                Op::Move(m) => Some(&m.blend),
                _ => None,
            })
            .collect();
        assert_eq!(blends.len(), 2);
        assert_eq!(
            matches!(blends[0], Blend::Percent { .. }),
            caps.krl_kinds,
            "{target:?}"
        );
        assert_eq!(*blends[1] == Blend::Exact, !caps.to_axes, "{target:?}");
        let findings = program.findings.len();
        let want = usize::from(!caps.krl_kinds) + usize::from(!caps.to_axes);
        assert_eq!(findings, want, "{target:?}: {:?}", program.findings);
    }
}

/// The lowering decides a Cartesian relative move from `Caps::relative_motions`: a turn in a
/// frame beyond what the target holds is TR001, a PTP_REL without a joint path a TR002.
#[test]
fn relative_moves_follow_the_targets_caps() {
    let text = "DEF main()\nLIN_REL {X 5, A 30} #TOOL\nLIN_REL {Z 5, C 15}\nPTP_REL {Z 30}\nEND\n";
    for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
        let caps = render::backend(target).caps().relative_motions;
        let (program, ops) = lowered(text, target);
        let refused: Vec<bool> = ops
            .iter()
            .filter_map(|op| match op {
                Op::Move(_) => Some(false),
                Op::Unsupported { .. } => Some(true),
                _ => None,
            })
            .collect();
        assert_eq!(
            refused,
            [caps.tool_turns < 1, caps.base_turns < 1, false],
            "{target:?}"
        );
        assert_eq!(
            program.findings.len(),
            usize::from(!caps.joint_path),
            "{target:?}"
        );
    }
}

/// Without a joint map the lowering refuses KUKA axis values where the target needs the map
/// (`Caps::axis_values`), and a LIN to axis values where the target's linear motions need a
/// pose; no renderer meets them.
#[test]
fn axis_values_follow_the_targets_caps() {
    use crate::transpile::ir::why::AxisUse;
    let text = "DEF main()\nDECL E6AXIS j\nj = {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0}\n\
        PTP j\nLIN j\nPTP_REL {A6 90}\nj = $AXIS_ACT\nEND\n";
    for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
        let a = render::backend(target).caps().axis_values;
        let (_, ops) = lowered_with(text, target, &Options::default());
        let refused = refusals(ops, |op| {
            matches!(op, Op::Move(_) | Op::Assign { .. } | Op::ReadPos { .. })
        });
        let robot = render::backend(target).caps().robot;
        let no_map = |at| Some(Why::NoJointMap { at, axes: a, robot });
        let want = [
            a.written.then(|| no_map(AxisUse::Values)).flatten(),
            a.every.then(|| no_map(AxisUse::Values)).flatten(),
            if a.linear {
                a.every.then(|| no_map(AxisUse::Values)).flatten()
            } else {
                Some(Why::LinearToAxes("LIN"))
            },
            no_map(AxisUse::Relative),
            (a.every || !a.written)
                .then(|| no_map(AxisUse::Read))
                .flatten(),
        ];
        assert_eq!(refused, want, "{target:?}");
    }
}

/// An omitted argument of a routine, and an OUT argument that is no variable, are refused by
/// the lowering for every target (none passes "no value" or assigns a value back to it).
#[test]
fn call_arguments_every_target_refuses() {
    let text = "DEF main()\nDECL INT n\ngo(1, )\nget(n + 1)\nget(n)\nEND\n\
        DEF go(a:IN, b:IN)\nINT a, b\nEND\nDEF get(x:OUT)\nINT x\nx = 1\nEND\n";
    for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
        let (_, ops) = lowered(text, target);
        let refused = refusals(ops, |op| matches!(op, Op::Call { .. }));
        assert_eq!(
            refused,
            [Some(Why::OmittedArgument), Some(Why::OutArgument), None],
            "{target:?}"
        );
    }
}

/// Which `MM_*` calls a target translates, and which omitted arguments it refuses, is decided
/// by the lowering from `Caps::mech_mind` and the catalog.
#[test]
fn mech_mind_calls_follow_the_targets_caps() {
    use crate::transpile::render::MechMind;
    let text =
        "DEF main()\nDECL E6AXIS j\nMM_Start_Vis(2, 0, 1, j)\nMM_Start_Vis(2, , 1, j)\nEND\n";
    for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
        let caps = render::backend(target).caps();
        let (_, ops) = lowered(text, target);
        let refused = refusals(ops, |op| matches!(op, Op::Call { .. }));
        let want = match caps.mech_mind {
            MechMind::Absent => {
                let refused = Some(Why::MmInterface {
                    name: "MM_Start_Vis".into(),
                    robot: caps.robot,
                });
                [refused.clone(), refused]
            }
            // The second parameter is one the translation reads.
            _ => [None, Some(Why::MmArgument("Pos_Num_Need".into()))],
        };
        assert_eq!(refused, want, "{target:?}");
    }
}

/// External axes in a literal: the lowering refuses those beyond `Caps::external_axes`.
#[test]
fn external_axes_follow_the_targets_caps() {
    let text = "DEF main()\nDECL E6POS p\nDECL REAL e\n\
        p = {X 1, Y 2, Z 3, A 0, B 0, C 0, E1 5}\np = {X 1, Y 2, Z 3, A 0, B 0, C 0, E2 5}\n\
        p = {X 1, Y 2, Z 3, A 0, B 0, C 0, E1 e}\nEND\n";
    for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
        let held = render::backend(target).caps().external_axes;
        let (_, ops) = lowered(text, target);
        let refused = refusals(ops, |op| matches!(op, Op::Assign { .. }));
        let beyond = |n: u8| (held < n).then_some(Why::ExternalAxes { held });
        let computed = if held == 0 {
            Why::ExternalAxes { held }
        } else {
            Why::ExternalAxisValue
        };
        assert_eq!(
            refused,
            [beyond(1), beyond(2), Some(computed)],
            "{target:?}"
        );
    }
}

/// Signal groups, output groups read back and computed signal numbers: the lowering refuses
/// what `Caps::signals` excludes.
#[test]
fn signals_follow_the_targets_caps() {
    let text = "DEF main()\nSIGNAL grp $IN[1] TO $IN[4]\nSIGNAL ogrp $OUT[1] TO $OUT[4]\n\
        DECL INT n, i\nn = grp\nn = ogrp\n$OUT[i] = TRUE\nEND\n";
    for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
        let s = render::backend(target).caps().signals;
        let (_, ops) = lowered(text, target);
        let refused = refusals(ops, |op| matches!(op, Op::Assign { .. } | Op::SetIo { .. }));
        let group = (!s.groups).then_some(Why::SignalGroup);
        let out_group = group
            .clone()
            .or((!s.output_groups_read).then_some(Why::OutputGroupRead));
        let computed = (!s.computed_numbers).then_some(Why::ComputedSignal);
        assert_eq!(refused, [group, out_group, computed], "{target:?}");
    }
}
