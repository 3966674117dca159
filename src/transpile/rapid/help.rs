//! What to do instead, in RAPID, for each construct no target can express.

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
        Why::Advance => "remove it; add WaitTime \\InPos, 0; where the robot must have arrived".into(),
        Why::OnErrorProceed => "check the error condition explicitly".into(),
        Why::TimeBlock => "give the motion time with \\T per move instead".into(),
        Why::Skip => "port by hand".into(),
        Why::Resume => {
            "end the TRAP and handle the rest in the main routine (StorePath/ClearPath and an error handler)".into()
        }
        Why::Analog => "read or write the analog value explicitly where it is needed".into(),
        Why::Other(_) | Why::SystemVariable(_) => "port by hand".into(),
        Why::CircAngle => "compute the arc's end point and use MoveC to it".into(),
        Why::ReadOnly(_) => "write an output or a variable instead".into(),
        Why::CycFlag => {
            "compute the condition where it is needed, or port it to a PC program".into()
        }
        Why::PathType => "check the orientation along the path by hand".into(),
        Why::CellFrame => "express the poses in the robot base frame".into(),
        Why::PathAcceleration => "set AccSet percentages by hand".into(),
        Why::KukaRoutine(_, family) => match family {
            KukaOnly::Eki => {
                "EthernetKRL channels have no RAPID equivalent; use SocketCreate/SocketConnect/SocketSend/SocketReceive"
            }
            KukaOnly::Channel => "CWRITE/CREAD channels have no RAPID equivalent; use Socket* or TPWrite",
            KukaOnly::Serial => "serial channels: use Open/Write/ReadStr on the serial device by hand",
            KukaOnly::Swrite => "build the string with NumToStr and +",
            KukaOnly::Sread => "parse the string with StrPart and StrToVal",
            KukaOnly::StrCopy => "assign the string (a := b;)",
            KukaOnly::StrAdd => "concatenate with + (a := a + b;)",
            KukaOnly::StrClear => "assign an empty string (a := \"\";)",
            KukaOnly::KrlMsg => "KUKA system messages have no RAPID equivalent; use TPWrite, ErrWrite or UIMsgBox",
            KukaOnly::Kinematics => "use CalcJointT / CalcRobT",
        }
        .into(),
        Why::Dialog(_) => "use UIMsgBox or TPReadFK and test the answer".into(),
        Why::NotAFunction(_) => "call it as a statement".into(),
        Why::Arity { .. } | Why::OmittedArgument => "pass every argument".into(),
        Why::OutArgument => "pass a variable".into(),
        Why::Bas(_) => "give speed, zone, tool and work object in the motions".into(),
        Why::BasArguments => "port by hand".into(),
        Why::NotMm(_) => "check the name (krlkit check reports the nearest one)".into(),
        Why::MmArity { signature, .. } => format!("call it as {signature}"),
        Why::UnknownEnum(_) => {
            "replace it with its number, or declare the ENUM in the program or its .dat".into()
        }
        Why::InvalidLiteral(_) => "fix the literal in the KRL source".into(),
        Why::Structure(_) => {
            "declare a RECORD and port by hand".into()
        }
        Why::Aggregate(_) => "compute the robtarget with Offs/RelTool by hand, or use literal values".into(),
        Why::Component(_) => "compute the whole value and assign it".into(),
        Why::ComputedIndex => "assign the value to a variable first".into(),
        Why::AssignTarget => "port by hand".into(),
        Why::MotionTarget(_) => "move to a robtarget or a jointtarget".into(),
        Why::RelativeOffset | Why::RelativeCirc => {
            "compute the target with Offs/RelTool and move to it".into()
        }
        Why::SplOutsideSpline => "use MoveL with a zone, and check the path".into(),
        Why::PulseSignal => "pulse an output ($OUT[n])".into(),
        Why::PulseLevel => "use SetDO sig, 0; WaitTime t; SetDO sig, 1; (this waits, PULSE does not)".into(),
        Why::InterruptNumber => "use a literal number".into(),
        Why::NoInterruptDecl(_) => {
            "translate the file that declares the interrupt, or declare it here".into()
        }
        Why::NoInterrupts | Why::InterruptCondition | Why::InterruptHandler => {
            "watch the condition with ISignalDI on one input, or poll it with WaitUntil".into()
        }
        Why::ReturnWithoutValue => "return a value".into(),
        Why::TimerFlag => "compare ClkRead(clock) with the limit where the flag is read".into(),
        Why::VisionServer { help, .. } => {
            help.replace(crate::transpile::ir::why::INIT_CALL, "the Mech-Mind ABB interface's connect routine")
        }
        Why::Goto => "restructure the jump".into(),
        Why::WaitCall => "assign the function's value to a variable and wait on that".into(),
        Why::Load => "give the payload in the tooldata's tload, or with GripLoad".into(),
        Why::MessageText => "pass the text".into(),
        Why::BitwiseNot => {
            "use BitNeg on a byte value".into()
        }
    }
}
