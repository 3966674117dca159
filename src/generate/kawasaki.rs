//! The Kawasaki AS package: askama templates under `templates/as/` (one per program shape, all
//! extending `as/program.as`, plus the helper programs, the about program and the `.REALS`
//! data section), assembled into one `.as` file.

use askama::Template;

use super::as_view::{AsPackage, AsProgram, Shape};
use crate::catalog::catalog;

macro_rules! program_templates {
    ($($ty:ident => $path:literal),* $(,)?) => {
        $(
            #[derive(Template)]
            #[template(path = $path, escape = "none")]
            struct $ty<'a> {
                r: &'a AsProgram,
                p: &'a AsPackage,
            }
        )*
    };
}

program_templates! {
    InitSkt => "as/init_skt.as",
    Simple => "as/simple.as",
    StartVis => "as/start_vis.as",
    StartViz => "as/start_viz.as",
    Fetch => "as/fetch.as",
    GetPose => "as/get_pose.as",
    GetJps => "as/get_jps.as",
    DyData => "as/dydata.as",
    GetDoList => "as/get_dolist.as",
    SetDoList => "as/set_dolist.as",
    PlanData => "as/plandata.as",
    Notify => "as/notify.as",
    Calibrate => "as/calibrate.as",
}

macro_rules! package_templates {
    ($($ty:ident => $path:literal),* $(,)?) => {
        $(
            #[derive(Template)]
            #[template(path = $path, escape = "none")]
            struct $ty<'a> {
                p: &'a AsPackage,
            }
        )*
    };
}

package_templates! {
    About => "as/about.as",
    Helpers => "as/helpers.as",
}

/// The data section: the package's state after loading (no setting of the spec in it).
#[derive(Template)]
#[template(path = "as/reals.as", escape = "none")]
struct Reals;

fn render_program(r: &AsProgram, p: &AsPackage) -> askama::Result<String> {
    match r.shape {
        Shape::InitSkt => InitSkt { r, p }.render(),
        Shape::Simple => Simple { r, p }.render(),
        Shape::StartVis => StartVis { r, p }.render(),
        Shape::StartViz => StartViz { r, p }.render(),
        Shape::Fetch => Fetch { r, p }.render(),
        Shape::GetPose => GetPose { r, p }.render(),
        Shape::GetJps => GetJps { r, p }.render(),
        Shape::DyData => DyData { r, p }.render(),
        Shape::GetDoList => GetDoList { r, p }.render(),
        Shape::SetDoList => SetDoList { r, p }.render(),
        Shape::PlanData => PlanData { r, p }.render(),
        Shape::Notify => Notify { r, p }.render(),
        Shape::Calibrate => Calibrate { r, p }.render(),
    }
}

/// The whole `.as` file: the about program, the 20 `mm_*` programs in catalog (seed) order,
/// the helper programs, the data section.
pub fn render_package(p: &AsPackage) -> Result<String, (String, askama::Error)> {
    let mut out = About { p }
        .render()
        .map_err(|e| ("mm_about".to_string(), e))?;
    out.push('\n');
    for k in &catalog().kawasaki {
        let r = AsProgram::new(k);
        out.push_str(&render_program(&r, p).map_err(|e| (k.name.clone(), e))?);
        out.push('\n');
    }
    out.push_str(
        &Helpers { p }
            .render()
            .map_err(|e| ("helpers".to_string(), e))?,
    );
    out.push('\n');
    out.push_str(&Reals.render().map_err(|e| (".REALS".to_string(), e))?);
    out.push('\n');
    Ok(out)
}
