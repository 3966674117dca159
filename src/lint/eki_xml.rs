//! EKI channel files as the lint sees them: a file's channel name (its stem) and path beside
//! the [`eki::Channel`] that [`eki::read`] (the one reader, shared with `run`) made of it.

use crate::eki::{self, ReadError};

/// One EKI channel as the lint needs it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EkiChannel {
    /// File stem, case preserved (EKI channel names are case-sensitive).
    pub name: String,
    pub path: String,
    pub config: eki::Channel,
}

impl EkiChannel {
    /// `CONFIGURATION/INTERNAL/ALIVE@Set_Flag`.
    pub fn alive_flag(&self) -> Option<i64> {
        self.config.alive_flag.map(i64::from)
    }

    /// The receive flag: the `Set_Flag` of the last `RECEIVE/RAW/ELEMENT` that has one.
    pub fn receive_flag(&self) -> Option<i64> {
        self.config
            .receive
            .iter()
            .rev()
            .find_map(|e| e.set_flag)
            .map(i64::from)
    }

    /// `CONFIGURATION/EXTERNAL/IP`, when given.
    pub fn ip(&self) -> Option<&str> {
        Some(self.config.ip.as_str()).filter(|ip| !ip.is_empty())
    }
}

/// The EKI configs among `paths` and the EthernetKRL files EKI would reject.
#[derive(Debug, Default)]
pub struct Scan {
    pub channels: Vec<EkiChannel>,
    /// `path: why`, for each file with an `ETHERNETKRL` root that does not read.
    pub rejected: Vec<String>,
}

/// EKI configs among `paths` (XML files named or found by walking, see
/// [`crate::files::walk_xml`]); files that cannot be read or are not EKI XML are skipped.
pub fn scan(paths: &[std::path::PathBuf]) -> Scan {
    use rayon::prelude::*;
    let read: Vec<Result<EkiChannel, String>> = crate::files::walk_xml(paths)
        .par_iter()
        .filter_map(|p| {
            let bytes = std::fs::read(p).ok()?;
            let text = crate::syntax::decode(&bytes).text;
            let path = p.display().to_string();
            match read(&channel_name(p), &path, &text) {
                Ok(ch) => Some(Ok(ch)),
                Err(ReadError::NotEki) => None,
                Err(e) => Some(Err(format!("{path}: {e}"))),
            }
        })
        .collect();
    let mut scan = Scan::default();
    for r in read {
        match r {
            Ok(ch) => scan.channels.push(ch),
            Err(e) => scan.rejected.push(e),
        }
    }
    scan
}

/// The channel a config file defines: its file stem, case preserved.
pub fn channel_name(path: &std::path::Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Read a channel from XML text.
pub fn read(name: &str, path: &str, xml: &str) -> Result<EkiChannel, ReadError> {
    Ok(EkiChannel {
        name: name.to_owned(),
        path: path.to_owned(),
        config: eki::read(xml)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scan_keeps_channels_skips_other_xml_and_names_rejected_eki_files() {
        let dir = tempfile::tempdir().expect("tempdir");
        let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/eki");
        for (from, to) in [
            ("ok_byte.xml", "Cell_A.xml"),
            ("port_out_of_range.xml", "Cell_B.xml"),
            ("root_not_ethernetkrl.xml", "Other.xml"),
        ] {
            std::fs::copy(fixtures.join(from), dir.path().join(to)).expect("copy");
        }
        let scan = scan(&[dir.path().to_path_buf()]);
        let names: Vec<&str> = scan.channels.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["Cell_A"]);
        assert_eq!(scan.channels[0].alive_flag(), Some(873));
        assert_eq!(scan.channels[0].receive_flag(), Some(871));
        assert_eq!(scan.channels[0].ip(), Some("192.168.10.20"));
        assert_eq!(scan.rejected.len(), 1);
        assert!(
            scan.rejected[0]
                .ends_with("Cell_B.xml: EXTERNAL PORT `65535` is not a number 1 … 65534"),
            "{:?}",
            scan.rejected
        );
    }
}
