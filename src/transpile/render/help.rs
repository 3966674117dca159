//! The help for a [`Why`] that reads the same in every target; a target's own help (its
//! instructions, its words) comes first and falls back to this.

use crate::transpile::ir::Why;
use crate::transpile::ir::why::{DatArray, Reach};

/// `why`'s help in a target: the target's own text, else the one every target shares.
pub fn help(why: &Why, own: fn(&Why) -> Option<String>) -> String {
    own(why).unwrap_or_else(|| shared(why))
}

/// The help every target gives alike (a target whose language changes the advice says its
/// own first).
fn shared(why: &Why) -> String {
    match why {
        Why::DuplicateParameter(_) => "give each parameter its own name and translate again",
        Why::SyntaxError | Why::HeaderSyntaxError => {
            "fix the syntax error (krlkit check) and translate again"
        }
        Why::RepeatWithoutUntil => "close the loop with UNTIL",
        Why::ExitOutsideLoop => "remove it",
        Why::Confirm => "remove it, or acknowledge on the teach pendant",
        Why::OnErrorProceed => "check the error condition explicitly",
        Why::Analog => "read or write the analog value explicitly where it is needed",
        Why::CycFlag => "compute the condition where it is needed, or port it to a PC program",
        Why::PathType => "check the orientation along the path by hand",
        Why::CellFrame => "express the poses in the robot base frame",
        Why::NotAFunction(_) => "call it as a statement",
        Why::Arity { .. } | Why::OmittedArgument => "pass every argument",
        Why::OutArgument => "pass a variable",
        Why::NotMm(_) => "check the name (krlkit check reports the nearest one)",
        Why::MmArity { signature, .. } => return format!("call it as {signature}"),
        Why::UnknownEnum(_) => {
            "replace it with its number, or declare the ENUM in the program or its .dat"
        }
        Why::InvalidLiteral(_) => "fix the literal in the KRL source",
        Why::ComputedIndex => "assign the value to a variable first",
        Why::InterruptNumber => "use a literal number",
        Why::NoInterruptDecl(_) => {
            "translate the file that declares the interrupt, or declare it here"
        }
        Why::ReturnWithoutValue => "return a value",
        Why::ParamRead(_) => "keep the value in a variable where the program sets it",
        Why::RelativeTurn { .. } => "split it into a shift and a separate reorientation",
        Why::WaitCall => "assign the function's value to a variable and wait on that",
        Why::MessageText => "pass the text",
        Why::StringLength { .. } => "shorten the string, or build it from shorter parts",
        Why::NoJointMap { .. } => "give --joint-map",
        Why::MmArgument(_) => "pass every argument",
        Why::ExternalAxes { .. } => "move the external axes with their own program, or drop them",
        Why::ExternalAxisValue => "use literal values",
        Why::SignalGroup => "use one signal per bit",
        Why::OutputGroupRead => "keep the value in a variable where the program sets it",
        Why::ComputedSignal => "use a literal number, or an IF per signal",
        Why::MmNoCommand { .. } | Why::MmMoves(_) | Why::MmInterface { .. } => "port by hand",
        Why::LinearToAxes(_) => "move to a pose (E6POS)",
        Why::Part {
            reach: Reach::Read, ..
        } => "keep the part in a variable of its own",
        Why::Part {
            reach: Reach::Assign,
            ..
        } => "compute the whole value and assign it",
        Why::Part {
            reach: Reach::Pass, ..
        } => "pass a variable and assign the part from it after the call",
        Why::CharRows => "use one string variable per row",
        Why::FrameNumber => "use a literal number",
        Why::FrameNegative(_) => "use the number of a defined tool or base (1 or more)",
        Why::IncompleteLiteral { .. } => "write every component",
        Why::ComputedAngles | Why::ComputedAxes => "use literal values",
        Why::DataLiteral => "use a literal",
        Why::SignalValue => "remove it",
        Why::ForStep => "use a literal step",
        Why::DatArray(DatArray::Undeclared) => "declare the array in the .dat",
        Why::DatArray(DatArray::Shape | DatArray::Size) => "set the elements in the program",
        Why::DatArray(DatArray::Index) => "fix the index",
        Why::PortRange { .. } => "set --input-offset/--output-offset, or port by hand",
        Why::FrameValue { .. } => "define the frame on the robot and select it by its number",
        Why::NotAStructure(_) => "declare the variable with its STRUC type",
        Why::Skip
        | Why::Other(_)
        | Why::SystemVariable(_)
        | Why::AssignTarget
        | Why::BasArguments
        | Why::Advance
        | Why::TimeBlock
        | Why::Resume
        | Why::CircAngle
        | Why::ReadOnly(_)
        | Why::PathAcceleration
        | Why::KukaRoutine(..)
        | Why::Dialog(_)
        | Why::Bas(_)
        | Why::Structure(_)
        | Why::Aggregate(_)
        | Why::Component(_)
        | Why::MotionTarget(_)
        | Why::RelativeOffset
        | Why::RelativeCirc
        | Why::RelativeExternal
        | Why::SplOutsideSpline
        | Why::PulseSignal
        | Why::PulseLevel
        | Why::PulseLow
        | Why::InterruptCondition
        | Why::NoInterrupts
        | Why::InterruptHandler
        | Why::TimerFlag
        | Why::VisionServer { .. }
        | Why::Goto
        | Why::Load
        | Why::Lacks(_)
        | Why::BitwiseNot => "port by hand",
    }
    .into()
}
