//! The channel XML `gen` is about to replace: when it frames records otherwise than the
//! package (typically Mech-Mind's shipped `XML_Kuka_MMIND.xml`, HEX, against an ASCII package),
//! Mech-Vision is very likely set to the other format, and the user must hear it.

use std::path::Path;

use super::{GeneratedFile, XML_DIR};
use crate::eki;

/// One warning per generated channel XML whose existing file in `out` has the other framing.
pub fn replaced_mismatches(out: &Path, files: &[GeneratedFile]) -> Vec<String> {
    files
        .iter()
        .filter(|f| f.path.starts_with(XML_DIR))
        .filter_map(|f| {
            let old_path = out.join(&f.path);
            let old = std::fs::read(&old_path).ok()?;
            let old = eki::read(&crate::syntax::decode(&old).text).ok()?.framing()?;
            let new = eki::read(std::str::from_utf8(&f.contents).ok()?)
                .ok()?
                .framing()?;
            (!old.same_codec(new)).then(|| {
                format!(
                    "{} frames records as {old}; the package speaks {new} and `krlkit gen` replaces it: select {} in Mech-Vision's Robot Communication Configuration, or set `codec = \"{}\"` in the spec",
                    old_path.display(),
                    codec_word(new),
                    spec_codec(old),
                )
            })
        })
        .collect()
}

fn codec_word(f: eki::Framing) -> &'static str {
    match f {
        eki::Framing::Stream => "ASCII",
        eki::Framing::Byte { .. } => "HEX",
    }
}

/// The spec value that makes the package speak `f` (HEX: Mech-Vision's little-endian default).
fn spec_codec(f: eki::Framing) -> &'static str {
    match f {
        eki::Framing::Stream => "ascii",
        eki::Framing::Byte { .. } => "hex-le",
    }
}
