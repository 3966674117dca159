//! What to do instead, in AS, for each construct no target can express.

use crate::transpile::ir::why::KukaOnly;
use crate::transpile::ir::why::Lacked;
use crate::transpile::ir::why::{Part, Reach};
use crate::transpile::ir::{Component, Why};

pub(super) fn help(why: &Why) -> String {
    crate::transpile::render::help::help(why, own)
}

/// The help that differs from every target's shared one.
fn own(why: &Why) -> Option<String> {
    Some(match why {
        Why::Advance => "remove it; add BREAK where the robot must have arrived".into(),
        Why::TimeBlock => "set SPEED … S (motion time) per move instead".into(),
        Why::Resume => {
            "end the interrupt program with RETURN and handle the rest in the main program".into()
        }
        Why::CircAngle => "compute the arc's end point and use C1MOVE/C2MOVE to it".into(),
        Why::ReadOnly(_) => "write an output or an internal signal instead".into(),
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
        Why::Bas(_) => "set SPEED/ACCURACY/TOOL/BASE explicitly".into(),
        Why::Structure(_) => {
            "split the structure into separate variables (reals, strings, poses)".into()
        }
        Why::Aggregate(_) => "compute the pose with TRANS() by hand, or use literal values".into(),
        Why::Component(_) => "compute the whole value (TRANS / #PPOINT) and assign it".into(),
        Why::MotionTarget(_) => "move to a pose (E6POS) or joint value (E6AXIS)".into(),
        Why::RelativeTurn { .. } | Why::RelativeExternal => {
            "split it into a DRAW/TDRAW for the position and a separate reorientation".into()
        }
        Why::RelativeOffset | Why::RelativeCirc => {
            "compute the target (e.g. #PPOINT or SHIFT/TRANS) and move to it".into()
        }
        Why::SplOutsideSpline => "use LMOVE with ACCURACY, and check the path".into(),
        Why::PulseSignal => "pulse an output ($OUT[n]) or flag".into(),
        Why::PulseLevel | Why::PulseLow => {
            "use SIGNAL -n, TWAIT t, SIGNAL n (this waits, PULSE does not)".into()
        }
        Why::NoInterrupts | Why::InterruptCondition | Why::InterruptHandler => {
            "watch the condition with a PC program, or poll it with SIG()".into()
        }
        Why::TimerFlag => "compare TIMER(n) with the limit where the flag is read".into(),
        Why::VisionServer { help, .. } => {
            help.replace(crate::transpile::ir::why::INIT_CALL, "mm_init_skt")
        }
        Why::Goto => "restructure the jump".into(),
        Why::Load => "set the payload with WEIGHT mass, cx, cy, cz".into(),
        Why::NoJointMap { .. } => super::expr::JOINT_MAP_HELP.into(),
        Why::Lacks(Lacked::PathAcceleration) => "set ACCEL/DECEL percentages by hand".into(),
        Why::MmNoCommand { name, .. } => match name.as_str() {
            "MM_Get_Status" => {
                "remove the check; mm_init_skt fails when the vision system is not reachable"
            }
            "MM_Set_Pos" => {
                "send the pose with the Mech-Vision External Move settings by hand, or restructure the cycle"
            }
            _ => "port by hand",
        }
        .into(),
        Why::BitwiseNot => {
            "use BXOR with a mask of the bits you need (e.g. x BXOR ^HFF for 8 bits)".into()
        }
        Why::Lacks(Lacked::Override) => {
            "the program override is a monitor setting in AS: set the monitor speed on the controller (MC SPEED n), or scale SPEED".into()
        }
        Why::Lacks(Lacked::TimerStop) => {
            "AS timers cannot be stopped: store TIMER(n) in a variable where KRL stopped the timer".into()
        }
        Why::Part { part: Part::Component(Component::Pose(3..=5)), reach: Reach::Read } => {
            "AS uses O,A,T: DECOMPOSE the pose into an array and convert O,A,T to A,B,C by hand".into()
        }
        Why::Part { part: Part::Component(Component::Axis(_)), reach: Reach::Read } => {
            "DECOMPOSE the joint value into an array and read the element".into()
        }
        Why::Part { part: Part::Component(_), reach: Reach::Read } => {
            "drop the status/turn or external axis".into()
        }
        Why::Part { part: Part::Component(_), reach: Reach::Assign } => {
            "compute the whole value (TRANS / #PPOINT) and assign it".into()
        }
        Why::Part { part: Part::Character, .. } => {
            "build the string with $LEFT/$MID/$RIGHT and +".into()
        }
        Why::ComputedAngles => {
            "compute the pose with TRANS() by hand, or use literal values".into()
        }
        Why::Lacks(Lacked::LoadTable) => {
            "write WEIGHT mass, cx, cy, cz with the load's values".into()
        }
        _ => return None,
    })
}
