//! What to do instead, in AS, for each construct no target can express.

use crate::transpile::ir::Why;
use crate::transpile::ir::why::KukaOnly;

pub(super) fn help(why: &Why) -> String {
    match why {
        Why::DuplicateParameter(_) => "give each parameter its own name and translate again".into(),
        Why::SyntaxError | Why::HeaderSyntaxError => {
            "fix the syntax error (krlkit check) and translate again".into()
        }
        Why::RepeatWithoutUntil => "close the loop with UNTIL".into(),
        Why::ExitOutsideLoop => "remove it".into(),
        Why::Confirm => "remove it, or acknowledge on the teach pendant".into(),
        Why::Advance => "remove it; add BREAK where the robot must have arrived".into(),
        Why::OnErrorProceed => "check the error condition explicitly".into(),
        Why::TimeBlock => "set SPEED … S (motion time) per move instead".into(),
        Why::Skip => "port by hand".into(),
        Why::Resume => {
            "end the interrupt program with RETURN and handle the rest in the main program".into()
        }
        Why::Analog => "read or write the analog value explicitly where it is needed".into(),
        Why::Other(_) | Why::SystemVariable(_) => "port by hand".into(),
        Why::CircAngle => "compute the arc's end point and use C1MOVE/C2MOVE to it".into(),
        Why::ReadOnly(_) => "write an output or an internal signal instead".into(),
        Why::CycFlag => {
            "compute the condition where it is needed, or port it to a PC program".into()
        }
        Why::PathType => "check the orientation along the path by hand".into(),
        Why::CellFrame => "express the poses in the robot base frame".into(),
        Why::PathAcceleration => "set ACCEL/DECEL percentages by hand".into(),
        Why::KukaRoutine(_, family) => match family {
            KukaOnly::Eki => {
                "EthernetKRL channels have no AS equivalent; use TCP_CONNECT/TCP_SEND/TCP_RECV"
            }
            KukaOnly::Channel => "CWRITE/CREAD channels have no AS equivalent; use TCP_* or PRINT",
            KukaOnly::Serial => "serial channels have no AS equivalent here; port by hand",
            KukaOnly::Swrite => "format the string with $ENCODE",
            KukaOnly::Sread => "parse the string with $DECODE and VAL",
            KukaOnly::StrCopy => "assign the string ($a = $b)",
            KukaOnly::StrAdd => "concatenate with + ($a = $a + $b)",
            KukaOnly::StrClear => "assign an empty string ($a = \"\")",
            KukaOnly::KrlMsg => "KUKA system messages have no AS equivalent; use PRINT or PROMPT",
            KukaOnly::Kinematics => "kinematics functions have no AS equivalent; port by hand",
        }
        .into(),
        Why::Dialog(_) => "use PROMPT \"text\", variable and test the answer".into(),
        Why::NotAFunction(_) => "call it as a statement".into(),
        Why::Arity { .. } | Why::OmittedArgument => "pass every argument".into(),
        Why::OutArgument => "pass a variable".into(),
        Why::Bas(_) => "set SPEED/ACCURACY/TOOL/BASE explicitly".into(),
        Why::BasArguments => "port by hand".into(),
        Why::NotMm(_) => "check the name (krlkit check reports the nearest one)".into(),
        Why::MmArity { signature, .. } => format!("call it as {signature}"),
        Why::UnknownEnum(_) => {
            "replace it with its number, or declare the ENUM in the program or its .dat".into()
        }
        Why::InvalidLiteral(_) => "fix the literal in the KRL source".into(),
        Why::Structure(_) => {
            "split the structure into separate variables (reals, strings, poses)".into()
        }
        Why::Aggregate(_) => "compute the pose with TRANS() by hand, or use literal values".into(),
        Why::Component(_) => "compute the whole value (TRANS / #PPOINT) and assign it".into(),
        Why::ComputedIndex => "assign the value to a variable first".into(),
        Why::AssignTarget => "port by hand".into(),
        Why::MotionTarget(_) => "move to a pose (E6POS) or joint value (E6AXIS)".into(),
        Why::RelativeOffset | Why::RelativeCirc => {
            "compute the target (e.g. #PPOINT or SHIFT/TRANS) and move to it".into()
        }
        Why::SplOutsideSpline => "use LMOVE with ACCURACY, and check the path".into(),
        Why::PulseSignal => "pulse an output ($OUT[n]) or flag".into(),
        Why::PulseLevel => "use SIGNAL -n, TWAIT t, SIGNAL n (this waits, PULSE does not)".into(),
        Why::InterruptNumber => "use a literal number".into(),
        Why::NoInterruptDecl(_) => {
            "translate the file that declares the interrupt, or declare it here".into()
        }
        Why::NoInterrupts | Why::InterruptCondition | Why::InterruptHandler => {
            "watch the condition with a PC program, or poll it with SIG()".into()
        }
        Why::ReturnWithoutValue => "return a value".into(),
        Why::TimerFlag => "compare TIMER(n) with the limit where the flag is read".into(),
        Why::VisionServer { help, .. } => {
            help.replace(crate::transpile::ir::why::INIT_CALL, "mm_init_skt")
        }
        Why::Goto => "restructure the jump".into(),
        Why::WaitCall => "assign the function's value to a variable and wait on that".into(),
        Why::Load => "set the payload with WEIGHT mass, cx, cy, cz".into(),
        Why::MessageText => "pass the text".into(),
        Why::BitwiseNot => {
            "use BXOR with a mask of the bits you need (e.g. x BXOR ^HFF for 8 bits)".into()
        }
    }
}
