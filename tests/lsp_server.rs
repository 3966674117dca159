//! `krlkit lsp` over stdio, driven as an editor drives it: initialize, the workspace's
//! diagnostics, didOpen, didChange, each request, a config change on disk, shutdown and exit.
//! The steps are data (`tests/fixtures/lsp/session.toml`); every answer is snapshotted.

mod lsp_support;

use std::path::Path;

use lsp_support::{Client, copy_tree, uri};
use serde::Deserialize;
use serde_json::{Value, json};

#[derive(Deserialize)]
struct Session {
    step: Vec<Step>,
}

#[derive(Deserialize)]
struct Step {
    name: String,
    #[serde(rename = "do")]
    action: String,
    file: Option<String>,
    at: Option<String>,
    to: Option<String>,
    old: Option<String>,
    new: Option<String>,
    view: Option<String>,
    new_name: Option<String>,
    query: Option<String>,
}

/// LSP position (UTF-16 columns) of byte `offset`, computed independently of the server.
fn position(text: &str, offset: usize) -> Value {
    let before = &text[..offset];
    let line_start = before.rfind(['\n', '\r']).map_or(0, |i| i + 1);
    // CRLF, lone CR and lone LF each end one line.
    let line = before.matches('\r').count() + before.matches('\n').count()
        - before.matches("\r\n").count();
    let character = before[line_start..].encode_utf16().count();
    json!({ "line": line, "character": character })
}

fn read(path: &Path) -> String {
    krlkit::syntax::decode(&std::fs::read(path).expect("fixture file")).text
}

struct Editor {
    client: Client,
    /// Texts of the documents the editor has open.
    open: std::collections::HashMap<String, (String, i32)>,
}

impl Editor {
    fn text(&self, file: &str) -> String {
        match self.open.get(file) {
            Some((t, _)) => t.clone(),
            None => read(&self.client.root.join(file)),
        }
    }

    fn doc(&self, file: &str) -> Value {
        json!({ "uri": uri(&self.client.root.join(file)) })
    }

    fn cursor(&self, file: &str, at: &str) -> Value {
        let text = self.text(file);
        let bar = at.find('|').expect("`at` has a |");
        let needle = at.replace('|', "");
        let start = text
            .find(&needle)
            .unwrap_or_else(|| panic!("{needle:?} not in {file}"));
        position(&text, start + bar)
    }

    /// The last diagnostics published for `file` after notification number `since`.
    fn published_since(&self, since: usize, file: &str) -> Value {
        let want = uri(&self.client.root.join(file));
        self.client.notifications[since..]
            .iter()
            .rev()
            .find(|n| n.method == "textDocument/publishDiagnostics" && n.params["uri"] == want)
            .map_or(json!("unchanged"), |n| n.params["diagnostics"].clone())
    }

    fn step(&mut self, s: &Step) -> Value {
        let file = s.file.as_deref().unwrap_or_default();
        match s.action.as_str() {
            "diagnostics" => {
                self.client.wait_idle();
                let all: serde_json::Map<String, Value> = self
                    .client
                    .diagnostics()
                    .into_iter()
                    .map(|(k, v)| (k, v["diagnostics"].clone()))
                    .collect();
                Value::Object(all)
            }
            "open" => {
                let text = self.text(file);
                let since = self.client.notifications.len();
                self.client.notify(
                    "textDocument/didOpen",
                    json!({ "textDocument": {
                        "uri": uri(&self.client.root.join(file)),
                        "languageId": "krl", "version": 1, "text": text,
                    }}),
                );
                self.open.insert(file.to_owned(), (text, 1));
                self.client.wait_idle();
                self.published_since(since, file)
            }
            "change" => {
                let (old, new) = (s.old.as_deref().unwrap(), s.new.as_deref().unwrap());
                let (text, version) = self.open.get(file).cloned().expect("open first");
                let start = text.find(old).expect("old text present");
                let range = json!({
                    "start": position(&text, start),
                    "end": position(&text, start + old.len()),
                });
                let edited = text.replacen(old, new, 1);
                let since = self.client.notifications.len();
                self.client.notify(
                    "textDocument/didChange",
                    json!({
                        "textDocument": { "uri": uri(&self.client.root.join(file)), "version": version + 1 },
                        "contentChanges": [ { "range": range, "text": new } ],
                    }),
                );
                self.open.insert(file.to_owned(), (edited, version + 1));
                self.client.wait_idle();
                self.published_since(since, file)
            }
            "write" => {
                let path = self.client.root.join(file);
                let text =
                    read(&path).replacen(s.old.as_deref().unwrap(), s.new.as_deref().unwrap(), 1);
                std::fs::write(&path, text).unwrap();
                self.client.notify(
                    "workspace/didChangeWatchedFiles",
                    json!({ "changes": [ { "uri": uri(&path), "type": 2 } ] }),
                );
                self.client.wait_idle();
                json!("written")
            }
            method => {
                let mut params = match &s.query {
                    Some(q) => json!({ "query": q }),
                    None => json!({ "textDocument": self.doc(file) }),
                };
                if let Some(n) = &s.new_name {
                    params["newName"] = json!(n);
                }
                if method == "textDocument/references" {
                    params["context"] = json!({ "includeDeclaration": true });
                }
                if let Some(at) = &s.at {
                    params["position"] = self.cursor(file, at);
                }
                if method == "textDocument/codeAction" || method == "textDocument/rangeFormatting" {
                    let at = params["position"].take();
                    let to = s.to.as_ref().map_or(at.clone(), |to| self.cursor(file, to));
                    params.as_object_mut().unwrap().remove("position");
                    params["range"] = json!({ "start": at, "end": to });
                }
                if method == "textDocument/codeAction" {
                    params["context"] = json!({ "diagnostics": [] });
                }
                if method.ends_with("ormatting") {
                    params["options"] = json!({ "tabSize": 2, "insertSpaces": true });
                }
                let mut answer = self.client.request(method, params);
                match s.view.as_deref() {
                    Some(v) if v.starts_with("labels") => {
                        let prefix = v.strip_prefix("labels:").unwrap_or("").to_lowercase();
                        answer = answer
                            .as_array()
                            .map(|a| {
                                a.iter()
                                    .map(|i| i["label"].clone())
                                    .filter(|l| {
                                        l.as_str()
                                            .is_some_and(|l| l.to_lowercase().starts_with(&prefix))
                                    })
                                    .collect()
                            })
                            .unwrap_or_default();
                    }
                    Some(label) => {
                        answer = answer
                            .as_array()
                            .and_then(|a| a.iter().find(|i| i["label"] == label).cloned())
                            .unwrap_or_default();
                    }
                    None => {}
                }
                answer
            }
        }
    }
}

#[test]
fn editor_session_over_stdio() {
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lsp");
    let script: Session =
        toml::from_str(&std::fs::read_to_string(fixture.join("session.toml")).unwrap()).unwrap();
    let dir = copy_tree(&fixture.join("backup"));
    let root = dir.path().canonicalize().unwrap();
    let root_uri = uri(&root);
    let mut editor = Editor {
        client: Client::start(&root, json!({})),
        open: Default::default(),
    };
    for step in &script.step {
        let answer = editor.step(step);
        let text = serde_json::to_string_pretty(&answer)
            .unwrap()
            .replace(&root_uri, "file:///WORKSPACE")
            .replace(&root.display().to_string(), "/WORKSPACE");
        insta::assert_snapshot!(step.name.as_str(), text);
    }
    let status = editor.client.shutdown();
    assert!(status.success(), "exit status {status:?}");
}
