//! The server loop: one thread owns all state and handles messages in order; no locks.
//!
//! Edits are applied to the open document at once. Analysis of changed documents waits for a
//! quiet moment: every message already queued is handled first (so a burst of keystrokes is
//! analysed once), then the configured delay must pass without a new message. Any request
//! first brings the analysis up to date, so answers always describe the text the editor sent.
//! Findings of the edited files are published first; the other files whose findings may have
//! changed ([`crate::lint::Affected`]) are checked afterwards in small batches between
//! messages, so hovers and edits never wait for the whole workspace.

use std::collections::{HashMap, HashSet, VecDeque};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError, Sender, TryRecvError};
use lsp_server::{Connection, ErrorCode, Message, Notification, Request, Response};
use lsp_types::notification::{self as note, Notification as _};
use lsp_types::request::{self as req, Request as _};
use lsp_types::{
    FileChangeType, InitializeParams, PublishDiagnosticsParams, ServerCapabilities,
    TextDocumentSyncCapability, TextDocumentSyncKind, Uri,
};
use serde_json::Value;

use super::documents::{Document, Documents};
use super::workspace::{self, Workspace};
use super::{diagnostics, features, paths};
use crate::lint::Affected;

/// Settings an editor can pass in `initializationOptions` (all optional).
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(rename_all = "camelCase", default)]
pub struct Options {
    /// Quiet time after the last edit before a changed document is analysed, in ms.
    pub debounce_ms: u64,
    /// Files checked per step of the background re-check.
    pub batch: usize,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            debounce_ms: 0,
            batch: 16,
        }
    }
}

pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(
            TextDocumentSyncKind::INCREMENTAL,
        )),
        ..features::capabilities()
    }
}

/// Run the server on `connection` until the client says `exit` (or goes away). Returns an
/// error only when the protocol itself failed (no `initialize`, broken channel).
pub fn serve(connection: Connection) -> anyhow::Result<()> {
    let (id, params) = connection.initialize_start()?;
    let params: InitializeParams = serde_json::from_value(params)?;
    let options: Options = params
        .initialization_options
        .clone()
        .and_then(|v| serde_json::from_value(v).ok())
        .unwrap_or_default();
    let result = serde_json::json!({
        "capabilities": capabilities(),
        "serverInfo": { "name": "krlkit", "version": env!("CARGO_PKG_VERSION") },
    });
    connection.initialize_finish(id, result)?;
    let mut server = Server::new(connection.sender.clone(), root_of(&params), options);
    server.main_loop(&connection)
}

/// The workspace folder: the first of `workspaceFolders`, else `rootUri`, else `rootPath`.
#[allow(deprecated)] // rootUri/rootPath: older clients send only these.
fn root_of(params: &InitializeParams) -> Option<PathBuf> {
    params
        .workspace_folders
        .as_ref()
        .and_then(|f| f.first())
        .and_then(|f| paths::path_of(&f.uri))
        .or_else(|| params.root_uri.as_ref().and_then(paths::path_of))
        .or_else(|| params.root_path.as_ref().map(PathBuf::from))
}

enum Next {
    Message(Message),
    Work,
    Closed,
}

pub struct Server {
    sender: Sender<Message>,
    options: Options,
    root: Option<PathBuf>,
    pub(super) docs: Documents,
    pub(super) ws: Workspace,
    /// Documents changed since the last analysis, and when the last change came.
    dirty: HashSet<String>,
    last_change: Instant,
    /// Files waiting for a background re-check (and the same as a set).
    queue: VecDeque<String>,
    queued: HashSet<String>,
    /// What was last published per file (to publish only changes).
    published: HashMap<String, Vec<lsp_types::Diagnostic>>,
    /// The current findings per file, as krlkit data (hover and code actions read them).
    pub(super) findings: HashMap<String, Vec<crate::diag::Diagnostic>>,
    shutting_down: bool,
    failures: usize,
}

impl Server {
    pub fn new(sender: Sender<Message>, root: Option<PathBuf>, options: Options) -> Server {
        let (ws, _) = Workspace::load(None);
        Server {
            sender,
            options,
            root,
            docs: Documents::default(),
            ws,
            dirty: HashSet::new(),
            last_change: Instant::now(),
            queue: VecDeque::new(),
            queued: HashSet::new(),
            published: HashMap::new(),
            findings: HashMap::new(),
            shutting_down: false,
            failures: 0,
        }
    }

    fn main_loop(&mut self, connection: &Connection) -> anyhow::Result<()> {
        self.guarded("reading the workspace", Server::load_workspace);
        loop {
            match self.next(&connection.receiver) {
                Next::Closed => return Ok(()),
                Next::Message(m) => {
                    if self.guarded("a message", |s| s.handle(m)) == Some(true) {
                        return Ok(());
                    }
                }
                Next::Work => {
                    self.guarded("checking files", Server::step);
                }
            }
        }
    }

    /// What to do next: a message already sent comes first (so a burst of edits is analysed
    /// once), then changed documents once the debounce time has passed, then queued checks.
    fn next(&self, rx: &Receiver<Message>) -> Next {
        match rx.try_recv() {
            Ok(m) => return Next::Message(m),
            Err(TryRecvError::Disconnected) => return Next::Closed,
            Err(TryRecvError::Empty) => {}
        }
        if !self.dirty.is_empty() {
            let due = self.last_change + Duration::from_millis(self.options.debounce_ms);
            let left = due.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Next::Work;
            }
            return match rx.recv_timeout(left) {
                Ok(m) => Next::Message(m),
                Err(RecvTimeoutError::Timeout) => Next::Work,
                Err(RecvTimeoutError::Disconnected) => Next::Closed,
            };
        }
        if !self.queue.is_empty() {
            return Next::Work;
        }
        rx.recv().map_or(Next::Closed, Next::Message)
    }

    /// One unit of analysis: the changed documents, else a batch of queued files.
    pub fn step(&mut self) {
        if !self.dirty.is_empty() {
            self.flush();
        } else if !self.queue.is_empty() {
            self.background_step();
        }
    }

    /// Run `f`; if krlkit fails inside (a bug), say so in the editor's log and carry on, so
    /// one bad file cannot take the editor's server down.
    fn guarded<T>(&mut self, what: &str, f: impl FnOnce(&mut Server) -> T) -> Option<T> {
        match catch_unwind(AssertUnwindSafe(|| f(self))) {
            Ok(v) => Some(v),
            Err(_) => {
                self.failures += 1;
                self.log(&format!(
                    "krlkit failed while handling {what}; please report it"
                ));
                None
            }
        }
    }

    /// How many times krlkit failed inside (tests require 0).
    pub fn failures(&self) -> usize {
        self.failures
    }

    /// Read the workspace folder and queue every file for its first check.
    pub fn load_workspace(&mut self) {
        let (ws, problems) = Workspace::load(self.root.clone());
        self.ws = ws;
        for p in problems {
            self.log(&p);
        }
        let ids: Vec<String> = self.ws.files().iter().map(|f| f.path.clone()).collect();
        for id in ids {
            self.enqueue(id);
        }
    }

    fn enqueue(&mut self, id: String) {
        if self.queued.insert(id.clone()) {
            self.queue.push_back(id);
        }
    }

    /// Handle one message; `true` when the server should stop.
    pub fn handle(&mut self, msg: Message) -> bool {
        match msg {
            Message::Request(r) => {
                let response = self.on_request(r);
                self.send(response.into());
                false
            }
            Message::Notification(n) => self.on_notification(n),
            Message::Response(_) => false,
        }
    }

    fn send(&self, msg: Message) {
        // The client went away: the loop ends at the next receive.
        let _ = self.sender.send(msg);
    }

    fn notify<N: lsp_types::notification::Notification>(&self, params: N::Params) {
        self.send(Notification::new(N::METHOD.to_owned(), params).into());
    }

    fn log(&self, message: &str) {
        self.notify::<note::LogMessage>(lsp_types::LogMessageParams {
            typ: lsp_types::MessageType::WARNING,
            message: message.to_owned(),
        });
    }

    fn on_request(&mut self, r: Request) -> Response {
        let id = r.id.clone();
        if r.method == req::Shutdown::METHOD {
            self.shutting_down = true;
            return Response::new_ok(id, Value::Null);
        }
        if self.shutting_down {
            return error(id, ErrorCode::InvalidRequest, "the server is shutting down");
        }
        // Answers describe the text the editor sent last.
        if !self.dirty.is_empty() {
            self.flush();
        }
        let method = r.method.clone();
        match catch_unwind(AssertUnwindSafe(|| features::dispatch(self, r))) {
            Ok(Some(Ok(v))) => Response::new_ok(id, v),
            Ok(Some(Err(e))) => Response {
                id,
                response_result: Err(e),
            },
            Ok(None) => error(
                id,
                ErrorCode::MethodNotFound,
                &format!("unknown method {method}"),
            ),
            Err(_) => {
                self.failures += 1;
                error(
                    id,
                    ErrorCode::InternalError,
                    &format!("krlkit failed on {method}; please report it with the file"),
                )
            }
        }
    }

    /// `true` on `exit`.
    fn on_notification(&mut self, n: Notification) -> bool {
        let params = n.params;
        match n.method.as_str() {
            note::Exit::METHOD => return true,
            note::DidOpenTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(params)
                {
                    let d = p.text_document;
                    let id = paths::id_of(&d.uri);
                    if is_krl(&id, &d.language_id) {
                        self.docs.open(
                            id.clone(),
                            Document {
                                uri: d.uri,
                                text: d.text,
                                version: d.version,
                            },
                        );
                        self.touch(id);
                    }
                }
            }
            note::DidChangeTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(params)
                {
                    let id = paths::id_of(&p.text_document.uri);
                    if self
                        .docs
                        .change(&id, p.text_document.version, p.content_changes)
                    {
                        self.touch(id);
                    }
                }
            }
            note::DidCloseTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(params)
                {
                    let id = paths::id_of(&p.text_document.uri);
                    if let Some(doc) = self.docs.close(&id) {
                        self.dirty.remove(&id);
                        let affected = self.ws.reload(&id);
                        if self.ws.file(&id).is_some() {
                            self.enqueue(id);
                        } else {
                            self.clear(&id, Some(doc.uri));
                        }
                        self.affect(affected);
                    }
                }
            }
            note::DidSaveTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidSaveTextDocumentParams>(params)
                    && let Some(path) = paths::path_of(&p.text_document.uri)
                {
                    self.file_changed_on_disk(&path);
                }
            }
            note::DidChangeWatchedFiles::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidChangeWatchedFilesParams>(params)
                {
                    for change in p.changes {
                        if let Some(path) = paths::path_of(&change.uri) {
                            if change.typ == FileChangeType::DELETED {
                                let id = path.display().to_string();
                                self.docs.close(&id);
                            }
                            self.file_changed_on_disk(&path);
                        }
                    }
                }
            }
            _ => {}
        }
        false
    }

    /// A document's text changed: analyse it once the editor is quiet.
    fn touch(&mut self, id: String) {
        self.dirty.insert(id);
        self.last_change = Instant::now();
    }

    /// A file changed outside the editor's open buffers (or was saved): the config, the EKI
    /// channels or a KRL file that is not open is read again.
    fn file_changed_on_disk(&mut self, path: &std::path::Path) {
        if workspace::is_config(path) {
            if let Err(e) = self.ws.reload_config() {
                self.log(&e);
            }
            self.affect(Affected::All);
        } else if workspace::is_xml(path) {
            self.ws.reload_channels();
            self.affect(Affected::All);
        } else {
            let id = path.display().to_string();
            if self.docs.get(&id).is_none() {
                let affected = self.ws.reload(&id);
                if self.ws.file(&id).is_some() {
                    self.enqueue(id);
                } else {
                    self.clear(&id, None);
                }
                self.affect(affected);
            }
        }
    }

    fn affect(&mut self, affected: Affected) {
        let ids: Vec<String> = match affected {
            // Open documents first: they are what the user looks at.
            Affected::All => {
                let mut open: Vec<String> = self.docs.ids().cloned().collect();
                open.sort();
                let rest = self
                    .ws
                    .files()
                    .iter()
                    .map(|f| f.path.clone())
                    .filter(|p| self.docs.get(p).is_none());
                open.into_iter().chain(rest).collect()
            }
            Affected::Files(v) => v,
        };
        for id in ids {
            self.enqueue(id);
        }
    }

    /// Analyse the changed documents, publish their findings, queue the files they affect.
    pub fn flush(&mut self) {
        let mut ids: Vec<String> = self.dirty.drain().collect();
        ids.sort();
        let texts: Vec<(String, String)> = ids
            .iter()
            .filter_map(|id| self.docs.get(id).map(|d| (id.clone(), d.text.clone())))
            .collect();
        let affected = self.ws.set_texts(texts);
        for id in &ids {
            self.recheck(id);
        }
        self.affect(affected);
    }

    /// Check a few queued files (in parallel) and publish what changed.
    pub fn background_step(&mut self) {
        use rayon::prelude::*;
        let n = self.options.batch.max(1).min(self.queue.len());
        let ids: Vec<String> = self.queue.drain(..n).collect();
        for id in &ids {
            self.queued.remove(id);
        }
        let ws = &self.ws;
        let reports: Vec<_> = ids.par_iter().map(|id| (id, ws.check(id))).collect();
        for (id, report) in reports {
            match report {
                Some(r) => self.publish(id, r),
                None => self.clear(id, None),
            }
        }
    }

    /// Files waiting for a check.
    pub fn pending(&self) -> usize {
        self.queue.len() + self.dirty.len()
    }

    fn recheck(&mut self, id: &str) {
        if self.queued.remove(id) {
            self.queue.retain(|q| q != id);
        }
        match self.ws.check(id) {
            Some(r) => self.publish(id, r),
            None => self.clear(id, None),
        }
    }

    /// A location in any file: a workspace file's text as analysed, else the file read from
    /// disk (an EKI XML a finding points to).
    pub(super) fn locate(
        &self,
        path: &str,
        span: crate::diag::Span,
    ) -> Option<lsp_types::Location> {
        let uri = self.uri(path)?;
        let range = match self.ws.file(path) {
            Some(f) => super::position::Lines::new(&f.text).range(span),
            None => {
                let text = std::fs::read(path)
                    .map(|b| crate::syntax::decode(&b).text)
                    .unwrap_or_default();
                super::position::Lines::new(&text).range(span)
            }
        };
        Some(lsp_types::Location::new(uri, range))
    }

    /// The text the server analysed for a file (after [`Server::flush`], the editor's text).
    pub fn analysed_text(&self, id: &str) -> Option<&str> {
        self.ws.file(id).map(|f| f.text.as_str())
    }

    /// The text of an open document as the server holds it.
    pub fn document_text(&self, id: &str) -> Option<&str> {
        self.docs.get(id).map(|d| d.text.as_str())
    }

    /// The URI of a file: an open document's own, else the file's.
    pub(super) fn uri(&self, id: &str) -> Option<Uri> {
        match self.docs.get(id) {
            Some(d) => Some(d.uri.clone()),
            None => paths::uri_of(id),
        }
    }

    fn publish(&mut self, id: &str, report: crate::diag::FileReport) {
        let diags = diagnostics::of_report(&report, &|path, span| self.locate(path, span));
        self.findings.insert(id.to_owned(), report.diagnostics);
        // Nothing new to say (a clean file that was clean, or unchanged findings).
        if self
            .published
            .get(id)
            .map_or(diags.is_empty(), |p| *p == diags)
        {
            return;
        }
        let Some(uri) = self.uri(id) else { return };
        let version = self.docs.get(id).map(|d| d.version);
        self.published.insert(id.to_owned(), diags.clone());
        self.notify::<note::PublishDiagnostics>(PublishDiagnosticsParams {
            uri,
            diagnostics: diags,
            version,
        });
    }

    /// The file left the workspace: take its findings back.
    fn clear(&mut self, id: &str, uri: Option<Uri>) {
        self.findings.remove(id);
        if self.published.remove(id).is_some_and(|d| !d.is_empty())
            && let Some(uri) = uri.or_else(|| self.uri(id))
        {
            self.notify::<note::PublishDiagnostics>(PublishDiagnosticsParams {
                uri,
                diagnostics: Vec::new(),
                version: None,
            });
        }
    }
}

/// A document the server analyses: KRL by language id or by extension.
fn is_krl(id: &str, language_id: &str) -> bool {
    language_id.eq_ignore_ascii_case("krl") || crate::files::has_krl_extension(id.as_ref())
}

pub(super) fn error(id: lsp_server::RequestId, code: ErrorCode, message: &str) -> Response {
    Response::new_err(id, code as i32, message.to_owned())
}
