//! Document URIs ↔ the file names the rest of krlkit uses.
//!
//! A file is known inside the server by its id: the absolute path of a `file:` URI (as
//! [`std::path::Path::display`] prints it, which is also what diagnostics and lint see), or the
//! URI text itself for documents that are not files (`untitled:…`). The conversions use the
//! `url` crate, which knows the percent-encoding and Windows drive-letter rules.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use lsp_types::Uri;

/// The id of the document at `uri`.
pub fn id_of(uri: &Uri) -> String {
    match path_of(uri) {
        Some(p) => p.display().to_string(),
        None => uri.as_str().to_owned(),
    }
}

/// The file path of a `file:` URI.
pub fn path_of(uri: &Uri) -> Option<PathBuf> {
    let url = url::Url::parse(uri.as_str()).ok()?;
    if url.scheme() != "file" {
        return None;
    }
    url.to_file_path().ok().map(normalise)
}

/// The URI of a file id (see the module doc).
pub fn uri_of(id: &str) -> Option<Uri> {
    let path = Path::new(id);
    if path.is_absolute() {
        let url = url::Url::from_file_path(path).ok()?;
        return Uri::from_str(url.as_str()).ok();
    }
    Uri::from_str(id).ok()
}

/// Windows editors send drive letters in either case; the walker reports them upper case.
fn normalise(path: PathBuf) -> PathBuf {
    if cfg!(windows) {
        let s = path.display().to_string();
        let mut chars = s.chars();
        if let (Some(d), Some(':')) = (chars.next(), chars.next())
            && d.is_ascii_lowercase()
        {
            return PathBuf::from(format!("{}{}", d.to_ascii_uppercase(), &s[1..]));
        }
    }
    path
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn file_uris_round_trip_with_escapes() {
        let uri = Uri::from_str("file:///tmp/a%20b/%24config.dat").unwrap();
        assert_eq!(id_of(&uri), "/tmp/a b/$config.dat");
        let back = uri_of("/tmp/a b/$config.dat").unwrap();
        assert_eq!(id_of(&back), "/tmp/a b/$config.dat");
    }

    #[test]
    fn other_schemes_keep_their_text() {
        let uri = Uri::from_str("untitled:Untitled-1").unwrap();
        assert_eq!(id_of(&uri), "untitled:Untitled-1");
        assert_eq!(uri_of("untitled:Untitled-1").unwrap(), uri);
    }
}
