//! Askama templates of the KRL package: one template per routine shape, all extending
//! `templates/krl/routine.src`.

use askama::Template;

use super::srci::{Packer, Step};
use super::view::{Package, Routine};
use crate::catalog::RoutineShape;

macro_rules! routine_templates {
    ($($ty:ident => $path:literal),* $(,)?) => {
        $(
            #[derive(Template)]
            #[template(path = $path, escape = "none")]
            struct $ty<'a> {
                r: &'a Routine,
                p: &'a Package,
            }
        )*
    };
}

routine_templates! {
    InitSocket => "krl/init_socket.src",
    Simple => "krl/simple.src",
    Batch => "krl/batch.src",
    BatchAll => "krl/batch_all.src",
    StartVis => "krl/start_vis.src",
    StartViz => "krl/start_viz.src",
    GetPose => "krl/get_pose.src",
    GetJps => "krl/get_jps.src",
    GetDoList => "krl/get_dolist.src",
    SetDoList => "krl/set_dolist.src",
    GetDyData => "krl/get_dy_data.src",
    GetDyPose => "krl/get_dypose.src",
    GetPlanData => "krl/get_plandata.src",
    GetPlanDataV2 => "krl/get_plandata_v2.src",
    GetProperty => "krl/get_property.src",
    GetNotify => "krl/get_notify.src",
    GetWobj => "krl/get_wobj.src",
    GetPlanJps => "krl/get_planjps.src",
    GetPlanPose => "krl/get_planpose.src",
    Calib => "krl/calib.src",
}

#[derive(Template)]
#[template(path = "krl/comm.src", escape = "none")]
struct CommSrc<'a> {
    p: &'a Package,
}

#[derive(Template)]
#[template(path = "krl/comm.dat", escape = "none")]
struct CommDat<'a> {
    p: &'a Package,
}

#[derive(Template)]
#[template(path = "krl/srci_status.src", escape = "none")]
struct SrciSrc<'a> {
    p: &'a Packer,
}

#[derive(Template)]
#[template(path = "krl/srci_status.dat", escape = "none")]
struct SrciDat<'a> {
    p: &'a Packer,
}

/// The SRCI status packer's `.src` and `.dat`.
pub fn render_srci(p: &Packer) -> askama::Result<(String, String)> {
    Ok((SrciSrc { p }.render()?, SrciDat { p }.render()?))
}

/// Render one routine with the template of its catalog shape.
pub fn render_routine(r: &Routine, p: &Package) -> askama::Result<String> {
    match r.shape {
        RoutineShape::InitSocket => InitSocket { r, p }.render(),
        RoutineShape::Simple => Simple { r, p }.render(),
        RoutineShape::StartVis => StartVis { r, p }.render(),
        RoutineShape::StartViz => StartViz { r, p }.render(),
        RoutineShape::Batch if r.fetch_all => BatchAll { r, p }.render(),
        RoutineShape::Batch => Batch { r, p }.render(),
        RoutineShape::GetPose => GetPose { r, p }.render(),
        RoutineShape::GetJps => GetJps { r, p }.render(),
        RoutineShape::GetDoList => GetDoList { r, p }.render(),
        RoutineShape::SetDoList => SetDoList { r, p }.render(),
        RoutineShape::GetDyData => GetDyData { r, p }.render(),
        RoutineShape::GetDyPose => GetDyPose { r, p }.render(),
        RoutineShape::GetPlanData if r.alt_cmd != 0 => GetPlanDataV2 { r, p }.render(),
        RoutineShape::GetPlanData => GetPlanData { r, p }.render(),
        RoutineShape::GetProperty => GetProperty { r, p }.render(),
        RoutineShape::GetNotify => GetNotify { r, p }.render(),
        RoutineShape::GetWobj => GetWobj { r, p }.render(),
        RoutineShape::GetPlanJps => GetPlanJps { r, p }.render(),
        RoutineShape::GetPlanPose => GetPlanPose { r, p }.render(),
        RoutineShape::Calib => Calib { r, p }.render(),
    }
}

pub fn render_comm_src(p: &Package) -> askama::Result<String> {
    CommSrc { p }.render()
}

pub fn render_comm_dat(p: &Package) -> askama::Result<String> {
    CommDat { p }.render()
}
