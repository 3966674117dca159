//! What to do instead, in the Python script, for each construct no target can express.

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
        Why::Confirm => "remove it".into(),
        Why::Advance => "remove it: the script waits for every move".into(),
        Why::OnErrorProceed => "catch the exception in Python (try/except) by hand".into(),
        Why::TimeBlock => "set the move speeds by hand".into(),
        Why::Skip => "port by hand".into(),
        Why::Resume => "restructure without interrupts".into(),
        Why::Analog => "analog I/O is not in the RDK API used here; port by hand".into(),
        Why::Other(_) | Why::SystemVariable(_) => "port by hand".into(),
        Why::CircAngle => "replace the arc by LIN moves".into(),
        Why::ReadOnly(_) => "write an output instead".into(),
        Why::CycFlag => "compute the condition where it is needed".into(),
        Why::PathType => "check the orientation along the path by hand".into(),
        Why::CellFrame => "express the poses in the robot's world frame".into(),
        Why::PathAcceleration => "set MoveL's acc in move_l by hand if it matters".into(),
        Why::KukaRoutine(_, family) => match family {
            KukaOnly::Eki => {
                "EthernetKRL channels do not exist on the host; use Python's socket module"
            }
            KukaOnly::Channel => "CWRITE/CREAD channels do not exist on the host; port by hand",
            KukaOnly::Serial => "serial channels: use a Python serial library by hand",
            KukaOnly::Swrite => "format the string with Python's % operator or str.format",
            KukaOnly::Sread => "parse the string with Python (split, int, float)",
            KukaOnly::StrCopy => "assign the string (a = b)",
            KukaOnly::StrAdd => "concatenate with + (a = a + b)",
            KukaOnly::StrClear => "assign an empty string (a = \"\")",
            KukaOnly::KrlMsg => "KUKA system messages do not exist on the host; use print",
            KukaOnly::Kinematics => {
                "kinematics functions: the Rizon's kinematics differ; port by hand"
            }
        }
        .into(),
        Why::Dialog(_) => "ask with input() and test the answer".into(),
        Why::NotAFunction(_) => "call it as a statement".into(),
        Why::Arity { .. } | Why::OmittedArgument => "pass every argument".into(),
        Why::OutArgument => "pass a variable".into(),
        Why::Bas(_) | Why::BasArguments => {
            "set KRL.vel_cp, KRL.vel_ptp or the tool explicitly".into()
        }
        Why::NotMm(_) => "check the name (krlkit check reports the nearest one)".into(),
        Why::MmArity { signature, .. } => format!("call it as {signature}"),
        Why::UnknownEnum(_) => {
            "replace it with its number, or declare the ENUM in the program or its .dat".into()
        }
        Why::InvalidLiteral(_) => "fix the literal in the KRL source".into(),
        Why::Structure(_) => {
            "split the structure into separate variables (numbers, strings, poses)".into()
        }
        Why::Aggregate(_) => "compute the pose with Pose(...) by hand, or use literal values".into(),
        Why::Component(_) => "compute the whole value and assign it".into(),
        Why::ComputedIndex => "assign the value to a variable first".into(),
        Why::AssignTarget => "port by hand".into(),
        Why::MotionTarget(_) => "move to a pose (E6POS) or axis values (E6AXIS)".into(),
        Why::RelativeOffset | Why::RelativeCirc => "compute the target pose and move to it".into(),
        Why::SplOutsideSpline => "replace it by LIN moves, and check the path".into(),
        Why::PulseSignal => "pulse an output ($OUT[n])".into(),
        Why::PulseLevel => "use a literal TRUE or FALSE".into(),
        Why::InterruptNumber | Why::NoInterruptDecl(_) => {
            "poll the condition where the program can react".into()
        }
        Why::NoInterrupts => {
            "poll the condition where the program can react, or port the interrupt to a thread by hand".into()
        }
        Why::InterruptCondition | Why::InterruptHandler => {
            "poll the condition where the program can react, or port the interrupt to a thread by hand".into()
        }
        Why::ReturnWithoutValue => "return a value".into(),
        Why::TimerFlag => "compare timer_get(n) with the limit where the flag is read".into(),
        Why::VisionServer { help, .. } => {
            help.replace(crate::transpile::ir::why::INIT_CALL, "mm.init_socket")
        }
        Why::Goto => "restructure the jump with a loop (while/break) or IF".into(),
        Why::WaitCall => "assign the function's value to a variable and wait on that".into(),
        Why::Load => "set mass, centre of mass and inertia in the tool (Flexiv Elements)".into(),
        Why::MessageText => "pass the text".into(),
        Why::BitwiseNot => "use ~ on an integer by hand".into(),
    }
}
