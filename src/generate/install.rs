//! The install notes (`krl/INSTALL.md`, `as/INSTALL.md`).

use askama::Template;

use super::as_view::AsPackage;
use super::view::Package;
use super::{KRL_DIR, XML_DIR};
use crate::spec::Spec;

#[derive(Template)]
#[template(path = "install.md", escape = "none")]
struct Install<'a> {
    s: &'a Spec,
    p: &'a Package,
    krl_dir: &'a str,
    xml_dir: &'a str,
    xml_file: String,
    routine_assumptions: Vec<String>,
}

#[derive(Template)]
#[template(path = "as_install.md", escape = "none")]
struct AsInstall<'a> {
    p: &'a AsPackage,
    as_path: &'a str,
}

/// The Kawasaki install note (`as/INSTALL.md`).
pub fn render_as(_spec: &Spec, pkg: &AsPackage) -> askama::Result<String> {
    AsInstall {
        p: pkg,
        as_path: super::AS_PATH,
    }
    .render()
}

pub fn render(spec: &Spec, pkg: &Package) -> askama::Result<String> {
    Install {
        s: spec,
        p: pkg,
        krl_dir: KRL_DIR,
        xml_dir: XML_DIR,
        xml_file: spec.xml_file_name(),
        routine_assumptions: super::view::routine_assumptions(spec),
    }
    .render()
}
