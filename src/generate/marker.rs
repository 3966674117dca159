//! The header line that marks a file as written by `krlkit gen`, with a hash of the rest of
//! the file.
//!
//! `gen` removes only files that carry the marker (a user's file never does), and a marker
//! whose hash no longer matches the file means someone edited the generated file by hand. The
//! hash is a function of the content alone, so output stays byte-identical for the same spec.

use sha2::{Digest, Sha256};

/// What every marker line contains, whatever the comment syntax around it.
const TAG: &str = "krlkit:generated ";
/// Hex digits of the content hash in the marker (64 bits: plenty to notice an edit).
const HASH_LEN: usize = 16;
/// The marker is looked for in this many first lines.
const HEADER_LINES: usize = 12;

/// Where a file's marker goes and how it is commented, by extension.
fn line_for(ext: &str, hash: &str) -> Option<(Placement, String)> {
    let text = match ext {
        "src" | "dat" | "sub" => format!("; {TAG}{hash} (edits are lost: change the spec, rerun)"),
        "as" => format!("  ; {TAG}{hash} (edits are lost: change the spec, rerun)"),
        "xml" => format!("<!-- {TAG}{hash} (edits are lost: change the spec, rerun) -->"),
        "md" => format!("<!-- {TAG}{hash} -->"),
        _ => return None,
    };
    let placement = match ext {
        // After the `&` lines and the DEF/DEFDAT line: KSS expects those first.
        "src" | "dat" | "sub" => Placement::AfterHeader,
        // Inside the first .PROGRAM (AS allows comments only there), after the XML declaration.
        "as" | "xml" => Placement::AfterFirstLine,
        _ => Placement::First,
    };
    Some((placement, text))
}

enum Placement {
    First,
    AfterFirstLine,
    AfterHeader,
}

/// Add the marker to a generated file's bytes (`eol` is the file's line ending). Files of a
/// kind without a comment syntax are returned unchanged.
pub fn stamp(path: &std::path::Path, contents: &[u8], eol: &str) -> Vec<u8> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let hash = content_hash(contents);
    let Some((placement, line)) = line_for(&ext, &hash) else {
        return contents.to_vec();
    };
    let at = match placement {
        Placement::First => 0,
        Placement::AfterFirstLine => line_end(contents, 0),
        Placement::AfterHeader => {
            let mut at = 0;
            while contents[at..].starts_with(b"&") {
                at = line_end(contents, at);
            }
            line_end(contents, at)
        }
    };
    let mut out = Vec::with_capacity(contents.len() + line.len() + eol.len());
    out.extend_from_slice(&contents[..at]);
    out.extend_from_slice(line.as_bytes());
    out.extend_from_slice(eol.as_bytes());
    out.extend_from_slice(&contents[at..]);
    out
}

/// Offset just past the line starting at `at` (its LF included), or the end.
fn line_end(bytes: &[u8], at: usize) -> usize {
    memchr::memchr(b'\n', &bytes[at..]).map_or(bytes.len(), |i| at + i + 1)
}

/// What the marker says about a file on disk.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Mark {
    /// No marker: not written by `gen` (a user's file, or one from a krlkit without markers).
    None,
    /// Written by `gen` and unchanged since.
    Intact,
    /// Written by `gen`, then edited.
    Edited,
}

/// Read the marker of a file's bytes and check its hash.
pub fn read(bytes: &[u8]) -> Mark {
    let mut at = 0;
    for _ in 0..HEADER_LINES {
        if at >= bytes.len() {
            break;
        }
        let end = line_end(bytes, at);
        let line = &bytes[at..end];
        if let Some(pos) = memchr::memmem::find(line, TAG.as_bytes()) {
            let hash = &line[pos + TAG.len()..];
            let Some(hash) = hash.get(..HASH_LEN) else {
                return Mark::Edited;
            };
            let mut rest = Vec::with_capacity(bytes.len() - line.len());
            rest.extend_from_slice(&bytes[..at]);
            rest.extend_from_slice(&bytes[end..]);
            return if content_hash(&rest).as_bytes() == hash {
                Mark::Intact
            } else {
                Mark::Edited
            };
        }
        at = end;
    }
    Mark::None
}

fn content_hash(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest[..HASH_LEN / 2]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn krl_marker_goes_after_the_def_line_and_verifies() {
        let src = b"&ACCESS RVP\r\n&REL 1\r\nDEF a()\r\nEND\r\n";
        let out = stamp(Path::new("a.src"), src, "\r\n");
        let text = String::from_utf8(out.clone()).unwrap();
        let lines: Vec<&str> = text.split("\r\n").collect();
        assert_eq!(lines[2], "DEF a()");
        assert!(lines[3].starts_with("; krlkit:generated "), "{text}");
        assert_eq!(read(&out), Mark::Intact);
        let edited = text.replace("END", "HALT\r\nEND");
        assert_eq!(read(edited.as_bytes()), Mark::Edited);
        assert_eq!(read(src), Mark::None);
    }

    #[test]
    fn every_kind_is_marked_where_its_syntax_allows() {
        let xml = stamp(Path::new("c.xml"), b"<?xml version=\"1.0\"?>\n<A/>\n", "\n");
        assert!(xml.starts_with(b"<?xml version=\"1.0\"?>\n<!-- krlkit:generated "));
        let md = stamp(Path::new("INSTALL.md"), b"# x\n", "\n");
        assert!(md.starts_with(b"<!-- krlkit:generated "));
        let as_ = stamp(Path::new("p.as"), b".PROGRAM a()\n.END\n", "\n");
        assert!(as_.starts_with(b".PROGRAM a()\n  ; krlkit:generated "));
        for f in [xml, md, as_] {
            assert_eq!(read(&f), Mark::Intact);
        }
        assert_eq!(stamp(Path::new("x.bin"), b"ab", "\n"), b"ab");
    }

    #[test]
    fn a_damaged_marker_reads_as_edited() {
        assert_eq!(read(b"; krlkit:generated 12\n"), Mark::Edited);
    }
}
