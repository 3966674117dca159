use super::*;
use crate::transpile::ir::LoopKind;
use crate::transpile::{Target, render};

/// The loops the lowering makes of `text`'s routines, in order.
fn loop_kinds(text: &str) -> Vec<&'static str> {
    let program = front::Program::new(front::Parsed::new("t.src", text), None);
    let options = Options::default();
    let mut lower = Lower::new(&program, &options, render::backend(Target::Kawasaki).caps());
    let mut kinds = Vec::new();
    program.src.each_statement(false, |s| match s {
        front::Statement::Begin(i) => drop(lower.begin_routine(i)),
        front::Statement::Head(s) => lower.head(&s, &mut Block::new()),
        front::Statement::Stmt(s) => {
            for op in lower.stmt(&s) {
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
