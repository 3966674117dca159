//! The transpile fixtures as every target's fixture test reads them: the programs of
//! `tests/fixtures/transpile/`, each file as a `Source`, and the EKI channels of the XML files
//! beside them (as `krlkit transpile` finds them).

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use krlkit::transpile::{Options, Source};

pub fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/transpile")
}

pub fn source(p: &Path) -> Source {
    let bytes = std::fs::read(p).expect("read fixture");
    Source {
        path: p.file_name().expect("name").to_string_lossy().into_owned(),
        text: krlkit::syntax::decode(&bytes).text,
    }
}

/// The `.src` programs, sorted.
pub fn programs() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir())
        .expect("fixture dir")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "src"))
        .collect();
    v.sort();
    v
}

/// Default options with the channels of every EKI XML file of the fixture folder.
pub fn options() -> Options {
    let mut channels = Vec::new();
    for e in std::fs::read_dir(dir()).expect("fixture dir") {
        let p = e.expect("entry").path();
        if p.extension().is_some_and(|e| e == "xml") {
            let text = std::fs::read_to_string(&p).expect("xml");
            let stem = p.file_stem().expect("stem").to_string_lossy().into_owned();
            let name = p.file_name().expect("name").to_string_lossy().into_owned();
            channels.extend(krlkit::lint::eki_xml::read(&stem, &name, &text));
        }
    }
    channels.sort_by(|a, b| a.name.cmp(&b.name));
    Options {
        channels,
        ..Options::default()
    }
}
