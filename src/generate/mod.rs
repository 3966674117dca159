//! `krlkit gen`: render the KUKA package (KRL + EKI XML + install note) and the Kawasaki AS
//! package (one `.as` file + install note) for a spec, write them atomically, or compare them
//! with what is on disk (`--check`).
//!
//! Invariants: output is a pure function of the spec and the catalog (byte-identical runs);
//! every KRL and AS file is ASCII with the spec's line endings; nothing is written until
//! everything rendered.

pub mod as_view;
mod channel;
mod framing;
mod hex_view;
mod install;
mod kawasaki;
mod krl;
pub mod marker;
mod output;
pub mod srci;
pub mod view;
mod writer;

use std::path::PathBuf;

pub use framing::replaced_mismatches;
pub use output::{Drift, check, write_atomic};

use crate::catalog::catalog;
use crate::spec::{LineEnding, Spec};
use view::{Package, Routine};

/// Where the KRL files go, relative to the output directory (→ `KRC:\R1\mm\`).
pub const KRL_DIR: &str = "krl/R1/mm";
/// Where the channel XML goes (→ `C:\KRC\ROBOTER\Config\User\Common\EthernetKRL\`).
pub const XML_DIR: &str = "xml/Config/User/Common/EthernetKRL";
/// The install note.
pub const INSTALL_PATH: &str = "krl/INSTALL.md";
/// Name of the helper + global data module.
pub const COMM_MODULE: &str = "MM_Comm";
/// The reply parser `MM_Comm` declares in an ASCII package (`templates/krl/comm.src`).
pub const PARSER_ASCII: &str = "MM_Parse";
/// The reply parser `MM_Comm` declares in a HEX package (`templates/krl/comm.src`).
pub const PARSER_HEX: &str = "MM_Parse_Hex";
/// The package's modules besides the catalog's subprograms.
pub const PACKAGE_MODULES: &[&str] = &[COMM_MODULE, srci::SRCI_MODULE];
/// Where the Kawasaki package goes, relative to the output directory.
pub const AS_DIR: &str = "as";
/// The Kawasaki AS file (all programs and the data section; load it into the controller).
pub const AS_PATH: &str = "as/mm_package.as";
/// The Kawasaki install note.
pub const AS_INSTALL_PATH: &str = "as/INSTALL.md";

/// Which robot package(s) to generate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Kuka,
    Kawasaki,
    All,
}

/// One generated file: path relative to the output directory, and its bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GeneratedFile {
    pub path: PathBuf,
    pub contents: Vec<u8>,
}

#[derive(Debug, thiserror::Error)]
pub enum GenError {
    #[error("rendering {file}: {source}")]
    Render {
        file: String,
        #[source]
        source: askama::Error,
    },
    #[error("{0}")]
    Io(String),
    /// The spec asks a package for what it does not implement.
    #[error("{0}")]
    Unsupported(String),
}

/// The Kawasaki AS package and the Flexiv script's client implement Mech-Mind's ASCII codec and
/// 1.x interface only (the vendor documents no other for those robots): a spec asking `who`
/// for another is refused rather than silently ignored.
pub fn ascii_1x_only(spec: &Spec, who: &str) -> Result<(), String> {
    use crate::catalog::{Codec, Interface};
    let mut asked = Vec::new();
    if spec.codec != Codec::Ascii {
        asked.push(format!("codec = \"{}\"", spec.codec.as_str()));
    }
    if spec.interface != Interface::V1 {
        asked.push(format!("interface = \"{}\"", spec.interface.as_str()));
    }
    if asked.is_empty() {
        return Ok(());
    }
    Err(format!(
        "{who} supports codec = \"ascii\" and interface = \"1.x\" only, but the spec sets {}",
        asked.join(" and ")
    ))
}

impl GeneratedFile {
    /// A generated file with its `krlkit:generated` marker (see [`marker`]).
    fn new(path: PathBuf, contents: Vec<u8>, eol: LineEnding) -> GeneratedFile {
        let contents = marker::stamp(&path, &contents, eol.as_str());
        GeneratedFile { path, contents }
    }
}

fn krl_file(name: &str, ext: &str, text: &str, eol: LineEnding) -> GeneratedFile {
    GeneratedFile::new(
        PathBuf::from(KRL_DIR).join(format!("{name}.{ext}")),
        writer::normalise(text, eol),
        eol,
    )
}

/// Render the whole package for `spec`, in a fixed order (helper module, then the routines in
/// catalog order, then XML and install note).
pub fn generate(spec: &Spec) -> Result<Vec<GeneratedFile>, GenError> {
    let pkg = Package::new(spec);
    let eol = spec.line_endings;
    let render_err = |file: &str| {
        let file = file.to_string();
        move |source| GenError::Render { file, source }
    };
    let mut files = vec![
        krl_file(
            COMM_MODULE,
            "src",
            &krl::render_comm_src(&pkg).map_err(render_err("MM_Comm.src"))?,
            eol,
        ),
        krl_file(
            COMM_MODULE,
            "dat",
            &krl::render_comm_dat(&pkg).map_err(render_err("MM_Comm.dat"))?,
            eol,
        ),
    ];
    for sp in catalog()
        .subprograms_of(spec.interface)
        .iter()
        .filter(|s| spec.emits(&s.name))
    {
        let r = Routine::new(sp, spec);
        let text = krl::render_routine(&r, &pkg).map_err(render_err(&sp.name))?;
        files.push(krl_file(&sp.name, "src", &text, eol));
    }
    if spec.srci_status {
        let packer = srci::Packer::new(spec);
        let (src, dat) = krl::render_srci(&packer).map_err(render_err(srci::SRCI_MODULE))?;
        files.push(krl_file(srci::SRCI_MODULE, "src", &src, eol));
        files.push(krl_file(srci::SRCI_MODULE, "dat", &dat, eol));
    }
    files.push(GeneratedFile::new(
        PathBuf::from(XML_DIR).join(spec.xml_file_name()),
        writer::normalise(&channel::channel(spec, &pkg).to_xml(), eol),
        eol,
    ));
    files.push(GeneratedFile::new(
        PathBuf::from(INSTALL_PATH),
        writer::normalise(
            &install::render(spec, &pkg).map_err(render_err("INSTALL.md"))?,
            LineEnding::Lf,
        ),
        LineEnding::Lf,
    ));
    Ok(files)
}

/// Render the Kawasaki AS package for `spec`: the `.as` file and its install note.
pub fn generate_kawasaki(spec: &Spec) -> Result<Vec<GeneratedFile>, GenError> {
    ascii_1x_only(spec, "the Kawasaki AS package").map_err(GenError::Unsupported)?;
    let pkg = as_view::AsPackage::new(spec);
    let text = kawasaki::render_package(&pkg)
        .map_err(|(file, source)| GenError::Render { file, source })?;
    let note = install::render_as(spec, &pkg).map_err(|source| GenError::Render {
        file: "as/INSTALL.md".into(),
        source,
    })?;
    Ok(vec![
        GeneratedFile::new(
            PathBuf::from(AS_PATH),
            writer::normalise_dense(&text, spec.line_endings),
            spec.line_endings,
        ),
        GeneratedFile::new(
            PathBuf::from(AS_INSTALL_PATH),
            writer::normalise(&note, LineEnding::Lf),
            LineEnding::Lf,
        ),
    ])
}

/// Render the package(s) of `target`: KUKA first, then Kawasaki.
pub fn generate_target(spec: &Spec, target: Target) -> Result<Vec<GeneratedFile>, GenError> {
    let mut files = Vec::new();
    if matches!(target, Target::Kuka | Target::All) {
        files.extend(generate(spec)?);
    }
    if matches!(target, Target::Kawasaki | Target::All) {
        files.extend(generate_kawasaki(spec)?);
    }
    Ok(files)
}

#[cfg(test)]
mod parser_names {
    use super::*;
    use crate::spec::Codec;

    /// lint (MM009) tells a package's framing by these names: each codec's `MM_Comm`
    /// declares its own parser and not the other's.
    #[test]
    fn each_codec_declares_its_parser() {
        for (codec, own, other) in [
            (Codec::Ascii, PARSER_ASCII, PARSER_HEX),
            (Codec::HexLe, PARSER_HEX, PARSER_ASCII),
        ] {
            let spec = Spec {
                codec,
                ..Spec::default()
            };
            let files = generate(&spec).expect("generates");
            let comm = files
                .iter()
                .find(|f| f.path.ends_with(format!("{COMM_MODULE}.src")))
                .expect("MM_Comm.src");
            let text = String::from_utf8_lossy(&comm.contents).to_ascii_uppercase();
            // `GLOBAL DEF name(` or `GLOBAL DEFFCT type name(`.
            let defines = |name: &str| {
                let call = format!(" {}(", name.to_ascii_uppercase());
                text.lines()
                    .any(|l| l.trim_start().starts_with("GLOBAL DEF") && l.contains(&call))
            };
            assert!(defines(own), "{codec:?}: {own}");
            assert!(!defines(other), "{codec:?}: {other}");
        }
    }
}
