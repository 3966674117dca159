//! SARIF 2.1.0: one run, the rule metadata the caller passes (diag knows no rule registry), one
//! result per finding.
//!
//! Artifact locations are URIs, as SARIF requires (§3.4.3): a relative path is a percent-encoded
//! relative reference against the `SRCROOT` base (the working directory, named in
//! `originalUriBaseIds` when known), an absolute path a `file://` URI.

use std::io::{self, Write};
use std::path::Path;

use percent_encoding::{AsciiSet, NON_ALPHANUMERIC, utf8_percent_encode};
use serde::ser::{Serialize, SerializeMap, Serializer};
use serde_json::{Value, json};

use crate::diag::{Diagnostic, FileReport, LineIndex, Severity};

const SCHEMA: &str = "https://json.schemastore.org/sarif-2.1.0.json";

fn level(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Info => "note",
    }
}

/// What SARIF says about one rule.
#[derive(Debug, Clone, Copy)]
pub struct RuleMeta<'a> {
    pub code: &'a str,
    pub name: &'a str,
    pub severity: Severity,
    pub summary: &'a str,
    pub doc: &'a str,
}

/// The base relative artifact URIs are resolved against.
pub const SRCROOT: &str = "SRCROOT";

/// Bytes a path segment keeps as they are (RFC 3986 unreserved characters); `/` separates
/// segments. Everything else is percent-encoded as UTF-8.
const SEGMENT: &AsciiSet = &NON_ALPHANUMERIC
    .remove(b'-')
    .remove(b'.')
    .remove(b'_')
    .remove(b'~')
    .remove(b'/');

/// The `artifactLocation` of a file named `path` as the user gave it (`\` read as `/`).
pub fn artifact_location(path: &str) -> Value {
    let slashed = path.replace('\\', "/");
    if Path::new(path).is_absolute()
        && let Ok(url) = url::Url::from_file_path(path)
    {
        return json!({ "uri": url.as_str() });
    }
    let relative = slashed.strip_prefix("./").unwrap_or(&slashed);
    // `:` is encoded too, so a first segment never reads as a scheme (`a:b.src`).
    let uri = utf8_percent_encode(relative, SEGMENT).to_string();
    json!({ "uri": uri, "uriBaseId": SRCROOT })
}

/// The whole SARIF log for `reports` with the metadata of `rules` (the caller's: the lint
/// registry's, the translation's), then a newline; `root` is the directory relative paths start
/// from (the working directory), named as `SRCROOT` when given.
///
/// The log around the results is a `Value`; the results are made one at a time as the log is
/// written (pretty, by serde_json), so only one of them is ever held.
pub fn write<W: Write + ?Sized>(
    reports: &[FileReport],
    rule_meta: &[RuleMeta],
    root: Option<&Path>,
    out: &mut W,
) -> io::Result<()> {
    let rules: Vec<Value> = rule_meta
        .iter()
        .map(|r| {
            json!({
                "id": r.code,
                "name": r.name,
                "shortDescription": { "text": r.summary },
                "fullDescription": { "text": first_paragraph(r.doc) },
                "help": { "text": r.doc, "markdown": r.doc },
                "defaultConfiguration": { "level": level(r.severity) },
            })
        })
        .collect();
    let mut run = json!({
        "tool": { "driver": {
            "name": "krlkit",
            "version": env!("CARGO_PKG_VERSION"),
            "informationUri": "https://github.com/krlkit/krlkit",
            "rules": rules,
        }},
        // Written by `Results`, in this entry's place.
        "results": [],
    });
    if let Some(base) = root.and_then(|r| url::Url::from_directory_path(r).ok()) {
        run["originalUriBaseIds"] = json!({ SRCROOT: { "uri": base.as_str() } });
    }
    let log = json!({
        "$schema": SCHEMA,
        "version": "2.1.0",
        // Written as `[run]`, in this entry's place.
        "runs": [],
    });
    let run = Splice {
        object: &run,
        key: "results",
        value: Results { reports, rule_meta },
    };
    let log = Splice {
        object: &log,
        key: "runs",
        value: [run],
    };
    serde_json::to_writer_pretty(&mut *out, &log)?;
    out.write_all(b"\n")
}

/// A JSON object written as `object` is (its keys in its order), except that the entry `key`
/// is `value`.
struct Splice<'a, T> {
    object: &'a Value,
    key: &'static str,
    value: T,
}

impl<T: Serialize> Serialize for Splice<'_, T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let object = self.object.as_object().expect("an object");
        let mut map = serializer.serialize_map(Some(object.len()))?;
        for (k, v) in object {
            if k == self.key {
                map.serialize_entry(k, &self.value)?;
            } else {
                map.serialize_entry(k, v)?;
            }
        }
        map.end()
    }
}

/// The `results` array: one result per finding, each made as it is written.
struct Results<'a> {
    reports: &'a [FileReport],
    rule_meta: &'a [RuleMeta<'a>],
}

impl Serialize for Results<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let results = self
            .reports
            .iter()
            .filter(|report| !report.diagnostics.is_empty())
            .flat_map(|report| {
                let index = LineIndex::new(&report.text);
                let location = artifact_location(&report.path);
                report
                    .diagnostics
                    .iter()
                    .map(move |d| self.result(report, &index, &location, d))
            });
        serializer.collect_seq(results)
    }
}

impl Results<'_> {
    fn result(
        &self,
        report: &FileReport,
        index: &LineIndex,
        location: &Value,
        d: &Diagnostic,
    ) -> Value {
        let (line, col) = index.line_col(&report.text, d.span.start as usize);
        let (end_line, end_col) = index.line_col(&report.text, d.span.end as usize);
        let mut text = d.message.to_string();
        if let Some(h) = &d.help {
            text.push_str(" (help: ");
            text.push_str(h);
            text.push(')');
        }
        json!({
            "ruleId": d.code,
            "ruleIndex": self.rule_meta.iter().position(|r| r.code == d.code),
            "level": level(d.severity),
            "message": { "text": text },
            "locations": [{
                "physicalLocation": {
                    "artifactLocation": location,
                    "region": {
                        "startLine": line,
                        "startColumn": col,
                        "endLine": end_line,
                        "endColumn": end_col,
                    }
                }
            }]
        })
    }
}

/// The "What it checks" section of a rule doc, as one line of plain text.
fn first_paragraph(doc: &str) -> String {
    let body = doc.strip_prefix("## What it checks\n").unwrap_or(doc);
    let para = body.split("\n\n").next().unwrap_or(body);
    para.lines().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// The log [`write`] writes, read back.
    fn written(reports: &[FileReport], root: Option<&Path>) -> Value {
        let mut out = Vec::new();
        write(reports, &[], root, &mut out).unwrap();
        serde_json::from_slice(&out).unwrap()
    }

    /// Resolve an artifact location as a SARIF consumer does.
    fn resolve(location: &Value, root: &url::Url) -> PathBuf {
        let uri = location["uri"].as_str().expect("uri");
        let url = match location.get("uriBaseId") {
            Some(base) => {
                assert_eq!(base, SRCROOT);
                assert!(url::Url::parse(uri).is_err(), "relative reference: {uri}");
                root.join(uri).expect("joins the base")
            }
            None => url::Url::parse(uri).expect("absolute URI"),
        };
        assert_eq!(url.scheme(), "file");
        url.to_file_path().expect("a file path")
    }

    #[test]
    fn artifact_uris_are_percent_encoded_and_resolve_to_the_file() {
        let root = PathBuf::from("/work/cell 1");
        let base = url::Url::from_directory_path(&root).unwrap();
        for name in [
            "pick.src",
            "./pick.src",
            "R1/Program/pick.src",
            "my programs/pick #2.src",
            "100%/a?b.src",
            "a:b.src",
            "Zelle_Größe/prüfen.src",
            "[x]{y} 'z'.dat",
            "../other/x.src",
            "<stdin>",
        ] {
            let location = artifact_location(name);
            let uri = location["uri"].as_str().unwrap();
            assert!(
                uri.bytes().all(|b| b.is_ascii_graphic() && b != b'\\'),
                "{name} -> {uri}"
            );
            let want = root.join(name.strip_prefix("./").unwrap_or(name));
            let want: PathBuf = want.components().collect();
            let got = resolve(&location, &base);
            // `..` is resolved by the URL, not by the path join.
            if name.starts_with("../") {
                assert_eq!(got, PathBuf::from("/work/other/x.src"));
            } else {
                assert_eq!(got, want, "{name} -> {uri}");
            }
        }
        let abs = artifact_location("/srv/krc/R1/my pick.src");
        assert_eq!(abs["uri"], "file:///srv/krc/R1/my%20pick.src");
        assert!(abs.get("uriBaseId").is_none());
        assert_eq!(
            resolve(&abs, &base),
            PathBuf::from("/srv/krc/R1/my pick.src")
        );
    }

    #[test]
    fn the_log_names_the_base_when_the_root_is_known() {
        let report = FileReport {
            path: "a b.src".into(),
            text: "x\n".into(),
            diagnostics: vec![crate::diag::Diagnostic::error(
                "KRL001",
                crate::diag::Span::new(0, 1),
                "m",
            )],
        };
        let log = written(std::slice::from_ref(&report), Some(Path::new("/w")));
        let run = &log["runs"][0];
        assert_eq!(run["originalUriBaseIds"][SRCROOT]["uri"], "file:///w/");
        let location = &run["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"];
        assert_eq!(location["uri"], "a%20b.src");
        assert_eq!(location["uriBaseId"], SRCROOT);
        let log = written(&[report], None);
        assert!(log["runs"][0].get("originalUriBaseIds").is_none());
    }
}
