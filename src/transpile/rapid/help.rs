//! What to do instead, in RAPID, for each construct no target can express.

use crate::transpile::ir::why::KukaOnly;
use crate::transpile::ir::why::Lacked;
use crate::transpile::ir::why::Part;
use crate::transpile::ir::{Component, Why};

pub(super) fn help(why: &Why) -> String {
    crate::transpile::render::help::help(why, own)
}

/// The help that differs from every target's shared one.
fn own(why: &Why) -> Option<String> {
    Some(match why {
        Why::Advance => "remove it; add WaitTime \\InPos, 0; where the robot must have arrived".into(),
        Why::TimeBlock => "give the motion time with \\T per move instead".into(),
        Why::Resume => {
            "end the TRAP and handle the rest in the main routine (StorePath/ClearPath and an error handler)".into()
        }
        Why::CircAngle => "compute the arc's end point and use MoveC to it".into(),
        Why::ReadOnly(_) => "write an output or a variable instead".into(),
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
        Why::Bas(_) => "give speed, zone, tool and work object in the motions".into(),
        Why::Structure(_) => {
            "declare a RECORD and port by hand".into()
        }
        Why::Aggregate(_) => "compute the robtarget with Offs/RelTool by hand, or use literal values".into(),
        Why::Component(_) => "compute the whole value and assign it".into(),
        Why::MotionTarget(_) => "move to a robtarget or a jointtarget".into(),
        Why::RelativeTurn { .. } | Why::RelativeExternal => "split it into a shift and one turn about one tool axis, or compute the target with PoseMult".into(),
        Why::RelativeOffset | Why::RelativeCirc => {
            "compute the target with Offs/RelTool and move to it".into()
        }
        Why::SplOutsideSpline => "use MoveL with a zone, and check the path".into(),
        Why::PulseSignal => "pulse an output ($OUT[n])".into(),
        Why::PulseLevel | Why::PulseLow => "use SetDO sig, 0; WaitTime t; SetDO sig, 1; (this waits, PULSE does not)".into(),
        Why::NoInterrupts | Why::InterruptCondition | Why::InterruptHandler => {
            "watch the condition with ISignalDI on one input, or poll it with WaitUntil".into()
        }
        Why::TimerFlag => "compare ClkRead(clock) with the limit where the flag is read".into(),
        Why::VisionServer { help, .. } => {
            help.replace(crate::transpile::ir::why::INIT_CALL, "the Mech-Mind ABB interface's connect routine")
        }
        Why::Goto => "restructure the jump".into(),
        Why::Load => "give the payload in the tooldata's tload, or with GripLoad".into(),
        Why::NoJointMap { .. } => super::expr::JOINT_MAP_HELP.into(),
        Why::MmInterface { .. } => super::stmt::MM_HELP.into(),
        Why::Lacks(Lacked::PathAcceleration) => "set AccSet percentages by hand".into(),
        Why::Lacks(Lacked::InvPos) => "invert the frame with PoseInv on a pose by hand".into(),
        Why::SignalGroup => {
            "configure a group signal and read it with GInput / write it with SetGO".into()
        }
        Why::BitwiseNot => "compute the bits with BitNeg on a byte, or port by hand".into(),
        Why::Lacks(Lacked::Load) => {
            "give the payload in the tooldata's tload, or with GripLoad".into()
        }
        Why::Lacks(Lacked::Geo) => "compose the poses with PoseMult by hand".into(),
        Why::Lacks(Lacked::Bitwise) => {
            "BitAnd/BitOr work on bytes: port by hand with BitAnd/BitOr on byte values".into()
        }
        Why::Lacks(Lacked::Timers | Lacked::TimerStop) => {
            "use a clock: ClkReset, ClkStart and ClkRead (seconds)".into()
        }
        Why::Part { part: Part::Character, .. } => "build the string with StrPart and +".into(),
        Why::Part { part: Part::Component(Component::Axis(_)), .. } => {
            "read the jointtarget's robax by hand (its values are ABB's, after the joint map)".into()
        }
        Why::FrameValue { .. } => {
            "declare a tooldata/wobjdata with the frame and use it".into()
        }
        _ => return None,
    })
}
