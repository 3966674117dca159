//! What to do instead, in the Python script, for each construct no target can express.

use crate::transpile::ir::why::AxisUse;
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
        Why::Confirm => "remove it".into(),
        Why::Advance => "remove it: the script waits for every move".into(),
        Why::OnErrorProceed => "catch the exception in Python (try/except) by hand".into(),
        Why::TimeBlock => "set the move speeds by hand".into(),
        Why::Resume => "restructure without interrupts".into(),
        Why::Analog => "analog I/O is not in the RDK API used here; port by hand".into(),
        Why::CircAngle => "replace the arc by LIN moves".into(),
        Why::ReadOnly(_) => "write an output instead".into(),
        Why::CycFlag => "compute the condition where it is needed".into(),
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
        Why::Bas(_) | Why::BasArguments => {
            "set KRL.vel_cp, KRL.vel_ptp or the tool explicitly".into()
        }
        Why::Structure(_) => {
            "split the structure into separate variables (numbers, strings, poses)".into()
        }
        Why::Aggregate(_) => "compute the pose with Pose(...) by hand, or use literal values".into(),
        Why::Component(_) => "compute the whole value and assign it".into(),
        Why::MotionTarget(_) => "move to a pose (E6POS) or axis values (E6AXIS)".into(),
        Why::RelativeTurn { .. } | Why::RelativeExternal => "split it into a position change and a separate reorientation".into(),
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
        Why::TimerFlag => "compare timer_get(n) with the limit where the flag is read".into(),
        Why::VisionServer { help, .. } => {
            help.replace(crate::transpile::ir::why::INIT_CALL, "mm.init_socket")
        }
        Why::Goto => "restructure the jump with a loop (while/break) or IF".into(),
        Why::Load => "set mass, centre of mass and inertia in the tool (Flexiv Elements)".into(),
        Why::BitwiseNot => "use ~ on an integer by hand".into(),
        Why::MmMoves(_) => "run the hand-eye calibration with Mech-Vision's Flexiv support, or port the handshake (command 701) by hand".into(),
        Why::NoJointMap { at, .. } => match at {
            AxisUse::Values => "give --joint-map (e.g. A1,A2,0,A3,A4,A5,A6), or teach the pose on the Rizon and move there with MoveJ",
            AxisUse::Relative => "give --joint-map (e.g. A1,A2,0,A3,A4,A5,A6)",
            AxisUse::Read => "give --joint-map (e.g. A1,A2,0,A3,A4,A5,A6), or read robot.states().q yourself",
        }
        .into(),
        Why::Lacks(Lacked::Load) => {
            "the payload is part of the tool on a Flexiv robot: set mass, centre of mass and inertia in the tool (Flexiv Elements or ToolParams)".into()
        }
        Why::Lacks(Lacked::Brake) => {
            "every move has ended before the next statement runs: remove it, or call robot.Stop() where the robot must stop".into()
        }
        Why::Lacks(Lacked::Circ) => {
            "no verified Flexiv primitive (MoveL with a waypoint would be two straight lines): replace the arc by LIN moves through points on it".into()
        }
        Why::Part { part: Part::Component(Component::Status | Component::Turn), .. } => {
            "a Rizon chooses its own posture: remove the use of S/T".into()
        }
        Why::Part { part: Part::Component(Component::Ext(_)), .. } => {
            "drop the external axis".into()
        }
        Why::Part { part: Part::Character, .. } => {
            "Python strings are immutable: build the new string with slices and +".into()
        }
        Why::FrameValue { tool: true } => {
            "define the tool in Flexiv Elements and call switch_tool(name)".into()
        }
        Why::FrameValue { tool: false } => {
            "define a work coordinate in Flexiv Elements and set KRL.base = [\"WORK\", name]".into()
        }
        Why::PortRange { list: true, .. } => "wire the signal to a port of the robot and set --output-offset/--input-offset, or port by hand".into(),
        _ => return None,
    })
}
