//! The poses the vision server sent, read from the generated package's point store after each
//! `MM_*` routine, so the trace (and the report) shows every pose the server sent, also those
//! the program never fetches with `MM_Get_Pose`.
//!
//! The store is the package's globals `MM_Pt_Count`, `MM_Pt_Kind`, `MM_Plan_Jps_Pos`,
//! `MM_Pt_Val[n, 6]` and `MM_Pt_Label[n]` (`templates/krl/comm.dat`); a program run with
//! another package simply has none, and nothing is traced.

use super::Machine;
use crate::generate::view::{KIND_PLAN, KIND_TCP};
use crate::interp::value::Value;
use crate::interp::{Event, VisionPose};

impl Machine<'_> {
    fn global_int(&self, name: &str) -> Option<i64> {
        match self.scopes.globals.get(name)? {
            Value::Int(i) => Some(*i),
            _ => None,
        }
    }

    /// The Cartesian poses in the point store, in store order (empty when it holds joints or
    /// custom data, or nothing).
    fn stored_poses(&self) -> Vec<VisionPose> {
        let kind = self.global_int("MM_PT_KIND");
        let tcp = kind == Some(KIND_TCP.into());
        let plan_tcp = kind == Some(KIND_PLAN.into())
            && self.global_int("MM_PLAN_JPS_POS") == Some(KIND_TCP.into());
        if !(tcp || plan_tcp) {
            return Vec::new();
        }
        let count = self.global_int("MM_PT_COUNT").unwrap_or(0).max(0) as usize;
        let Some(Value::Array { dims, items }) = self.scopes.globals.get("MM_PT_VAL") else {
            return Vec::new();
        };
        if dims.len() != 2 || dims[1] != 6 {
            return Vec::new();
        }
        let labels = match self.scopes.globals.get("MM_PT_LABEL") {
            Some(Value::Array { items, .. }) if tcp => Some(items),
            _ => None,
        };
        (0..count.min(dims[0]))
            .map_while(|i| {
                let mut pose = [0.0; 6];
                for (j, slot) in pose.iter_mut().enumerate() {
                    *slot = items.get(i * 6 + j)?.as_f64()?;
                }
                let label = labels.and_then(|l| match l.get(i) {
                    Some(Value::Int(n)) => Some(*n),
                    _ => None,
                });
                Some(VisionPose { pose, label })
            })
            .collect()
    }

    /// After `routine` returned: trace the store if it changed since it was last traced.
    pub(super) fn trace_stored_poses(&mut self, routine: &str) {
        let poses = self.stored_poses();
        if poses.is_empty() || poses == self.trace.vision_poses {
            return;
        }
        self.trace.vision_poses = poses.clone();
        self.emit(Event::Vision {
            routine: routine.to_string(),
            poses,
        });
    }
}
