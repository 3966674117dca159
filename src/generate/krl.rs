//! Askama templates of the KRL package: one template per routine shape, all extending
//! `templates/krl/routine.src`.

use askama::Template;

use super::srci::{Packer, Step};
use super::view::{Package, Routine};

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

/// Render one routine. The routine's shape is chosen by name; names come from the catalog.
pub fn render_routine(r: &Routine, p: &Package) -> askama::Result<String> {
    match r.name.as_str() {
        "MM_Init_Socket" => InitSocket { r, p }.render(),
        "MM_Start_Vis" => StartVis { r, p }.render(),
        "MM_Start_Viz" => StartViz { r, p }.render(),
        "MM_Get_VisData" | "MM_Get_VizData" | "MM_Get_VisPath" if r.fetch_all => {
            BatchAll { r, p }.render()
        }
        "MM_Get_VisData" | "MM_Get_VizData" | "MM_Get_VisPath" => Batch { r, p }.render(),
        "MM_Get_Pose" => GetPose { r, p }.render(),
        "MM_Get_Jps" => GetJps { r, p }.render(),
        "MM_Get_DoList" => GetDoList { r, p }.render(),
        "MM_Set_DoList" => SetDoList { r, p }.render(),
        "MM_Get_Dy_Data" => GetDyData { r, p }.render(),
        "MM_Get_DyPose" => GetDyPose { r, p }.render(),
        "MM_Get_PlanData" if r.alt_cmd != 0 => GetPlanDataV2 { r, p }.render(),
        "MM_Get_PlanData" => GetPlanData { r, p }.render(),
        "MM_Get_Property" => GetProperty { r, p }.render(),
        "MM_Get_Notify" => GetNotify { r, p }.render(),
        "MM_Get_Wobj" => GetWobj { r, p }.render(),
        "MM_Get_PlanJps" => GetPlanJps { r, p }.render(),
        "MM_Get_PlanPose" => GetPlanPose { r, p }.render(),
        "MM_CALIB" => Calib { r, p }.render(),
        // Send the IN arguments, store the status: MM_Switch_Model, MM_Set_Branch,
        // MM_Set_Index, MM_Get_Status, MM_Set_BoxSize, MM_Set_Pos, MM_Stop_Viz,
        // MM_Set_Property.
        _ => Simple { r, p }.render(),
    }
}

pub fn render_comm_src(p: &Package) -> askama::Result<String> {
    CommSrc { p }.render()
}

pub fn render_comm_dat(p: &Package) -> askama::Result<String> {
    CommDat { p }.render()
}
