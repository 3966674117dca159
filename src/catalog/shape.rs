//! What each routine does, as the catalog names it (`shape = "…"`): the renderers pick their
//! template by it (the KRL package, the Flexiv client, the AS package), never by a routine's
//! name. Both enums are exhaustive and every catalog entry must name one, so a new command
//! without a shape does not load, and a new shape does not compile until every renderer has
//! decided what it renders.

use serde::Deserialize;

/// The shape of a KUKA `MM_*` routine (`[[subprogram]]`, `[[subprogram_v2]]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RoutineShape {
    /// Stores the channel, flags and timeout (`MM_Init_Socket`).
    InitSocket,
    /// Sends the IN arguments and stores the status.
    Simple,
    StartVis,
    StartViz,
    /// Fetches batches of points (`MM_Get_VisData`, `MM_Get_VizData`, `MM_Get_VisPath`).
    Batch,
    GetPose,
    GetJps,
    GetDoList,
    SetDoList,
    GetDyData,
    GetDyPose,
    GetPlanData,
    GetProperty,
    GetNotify,
    GetWobj,
    GetPlanJps,
    GetPlanPose,
    /// Hand-eye calibration: the routine moves the robot to the poses the server sends.
    Calib,
}

impl RoutineShape {
    /// A routine of this shape moves the robot.
    pub fn moves(self) -> bool {
        self == RoutineShape::Calib
    }
}

/// The shape of a Kawasaki AS `mm_*` program (`[[kawasaki]]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProgramShape {
    InitSkt,
    /// Sends the IN values and stores the status (and one value for `mm_get_property`).
    Simple,
    StartVis,
    StartViz,
    /// Fetches batches of points (`mm_get_visdata`, `mm_get_vispath`, `mm_get_vizdata`).
    Fetch,
    GetPose,
    GetJps,
    DyData,
    GetDoList,
    SetDoList,
    PlanData,
    Notify,
    Calibrate,
}
