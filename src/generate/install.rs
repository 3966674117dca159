//! The install note (`krl/INSTALL.md`).

use askama::Template;

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
}

pub fn render(spec: &Spec, pkg: &Package) -> askama::Result<String> {
    Install {
        s: spec,
        p: pkg,
        krl_dir: KRL_DIR,
        xml_dir: XML_DIR,
        xml_file: spec.xml_file_name(),
    }
    .render()
}
