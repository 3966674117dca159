//! Requests: which ones the server answers (capabilities) and the handlers. Handlers read the
//! analysed workspace and turn krlkit's answers into LSP shapes; the knowledge itself lives in
//! the catalog, the linter and the syntax tree.

use lsp_server::{ErrorCode, Request, ResponseError};
use lsp_types::request::{self as req, Request as _};
use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOptions, CodeActionOrCommand, CodeActionParams,
    CodeActionProviderCapability, CodeActionResponse, CompletionOptions, CompletionParams,
    CompletionResponse, DocumentSymbolParams, DocumentSymbolResponse, FoldingRange,
    FoldingRangeParams, FoldingRangeProviderCapability, Hover, HoverContents, HoverParams,
    HoverProviderCapability, MarkupContent, MarkupKind, OneOf, ServerCapabilities, SignatureHelp,
    SignatureHelpOptions, SignatureHelpParams, TextDocumentIdentifier, TextDocumentPositionParams,
    TextEdit, Uri, WorkspaceEdit,
};
use lsp_types::{
    GotoDefinitionParams, GotoDefinitionResponse, Location, PrepareRenameResponse, ReferenceParams,
    RenameOptions, RenameParams, WorkspaceSymbolParams, WorkspaceSymbolResponse,
};
use serde_json::Value;

use super::cursor::{self, Place};
use super::position::Lines;
use super::server::Server;
use super::{diagnostics, mm, outline, paths};
use crate::diag::{Applicability, Edit};
use crate::lint::context::Parsed;
use crate::sema::Resolved;

pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec!["$".into()]),
            ..CompletionOptions::default()
        }),
        signature_help_provider: Some(SignatureHelpOptions {
            trigger_characters: Some(vec!["(".into(), ",".into()]),
            retrigger_characters: None,
            work_done_progress_options: Default::default(),
        }),
        document_symbol_provider: Some(OneOf::Left(true)),
        folding_range_provider: Some(FoldingRangeProviderCapability::Simple(true)),
        code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
            code_action_kinds: Some(vec![CodeActionKind::QUICKFIX, fix_all()]),
            ..CodeActionOptions::default()
        })),
        document_formatting_provider: Some(OneOf::Left(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Right(RenameOptions {
            prepare_provider: Some(true),
            work_done_progress_options: Default::default(),
        })),
        workspace_symbol_provider: Some(OneOf::Left(true)),
        document_range_formatting_provider: Some(OneOf::Left(true)),
        execute_command_provider: Some(lsp_types::ExecuteCommandOptions {
            commands: vec![super::compare::COMMAND.into()],
            work_done_progress_options: Default::default(),
        }),
        ..ServerCapabilities::default()
    }
}

/// Answer `r`; `None` for a method the server does not know.
pub fn dispatch(s: &mut Server, r: Request) -> Option<Result<Value, ResponseError>> {
    let Request { method, params, .. } = r;
    let s = &*s;
    Some(match method.as_str() {
        req::HoverRequest::METHOD => call::<req::HoverRequest>(params, |p| hover(s, p)),
        req::Completion::METHOD => call::<req::Completion>(params, |p| completion(s, p)),
        req::SignatureHelpRequest::METHOD => {
            call::<req::SignatureHelpRequest>(params, |p| signature_help(s, p))
        }
        req::DocumentSymbolRequest::METHOD => {
            call::<req::DocumentSymbolRequest>(params, |p| document_symbols(s, p))
        }
        req::FoldingRangeRequest::METHOD => {
            call::<req::FoldingRangeRequest>(params, |p| folding_ranges(s, p))
        }
        req::GotoDefinition::METHOD => call::<req::GotoDefinition>(params, |p| definition(s, p)),
        req::References::METHOD => call::<req::References>(params, |p| references(s, p)),
        req::PrepareRenameRequest::METHOD => {
            return Some(prepare_rename(s, params));
        }
        req::Rename::METHOD => return Some(rename(s, params)),
        req::WorkspaceSymbolRequest::METHOD => {
            call::<req::WorkspaceSymbolRequest>(params, |p| workspace_symbols(s, p))
        }
        req::CodeActionRequest::METHOD => {
            call::<req::CodeActionRequest>(params, |p| code_actions(s, p))
        }
        req::Formatting::METHOD => {
            call::<req::Formatting>(params, |p| formatting(s, &p.text_document, None))
        }
        req::RangeFormatting::METHOD => {
            call::<req::RangeFormatting>(params, |p| formatting(s, &p.text_document, Some(p.range)))
        }
        req::ExecuteCommand::METHOD => {
            return Some(
                serde_json::from_value(params)
                    .map_err(|e| ResponseError {
                        code: ErrorCode::InvalidParams as i32,
                        message: format!("invalid parameters for {method}: {e}"),
                        data: None,
                    })
                    .and_then(|p| super::compare::execute(s.ws.root.as_deref(), p)),
            );
        }
        // Not LSP: how many files still wait for a check (tests and editors' status bars).
        STATUS => Ok(serde_json::json!({
            "pending": s.pending(),
            "files": s.ws.files().len(),
        })),
        _ => return None,
    })
}

/// The one request of krlkit's own: `{"pending": n, "files": m}`.
pub const STATUS: &str = "krlkit/status";

fn call<R: req::Request>(
    params: Value,
    f: impl FnOnce(R::Params) -> R::Result,
) -> Result<Value, ResponseError> {
    let p: R::Params = serde_json::from_value(params).map_err(|e| ResponseError {
        code: ErrorCode::InvalidParams as i32,
        message: format!("invalid parameters for {}: {e}", R::METHOD),
        data: None,
    })?;
    serde_json::to_value(f(p)).map_err(|e| ResponseError {
        code: ErrorCode::InternalError as i32,
        message: e.to_string(),
        data: None,
    })
}

/// The analysed file of a document.
fn file<'s>(s: &'s Server, doc: &TextDocumentIdentifier) -> Option<&'s Parsed> {
    s.ws.file(&paths::id_of(&doc.uri))
}

/// The file, its lines and the byte offset of a position.
fn at<'s>(s: &'s Server, p: &TextDocumentPositionParams) -> Option<(&'s Parsed, Lines<'s>, usize)> {
    let f = file(s, &p.text_document)?;
    let lines = Lines::new(&f.text);
    let offset = lines.offset(p.position);
    Some((f, lines, offset))
}

fn markdown(value: String) -> HoverContents {
    HoverContents::Markup(MarkupContent {
        kind: MarkupKind::Markdown,
        value,
    })
}

fn hover(s: &Server, p: HoverParams) -> Option<Hover> {
    let (f, lines, offset) = at(s, &p.text_document_position_params)?;
    let mut parts: Vec<String> = Vec::new();
    let mut range = None;
    if let (Place::Code, call) = cursor::context(&lines, offset) {
        let word = cursor::word_at(&f.text, offset);
        match word
            .and_then(|w| mm::subprogram(s.ws.interface(), &f.text[w.range()]).map(|sub| (w, sub)))
        {
            // On the name of an MM_ subprogram: the whole signature.
            Some((w, sub)) => {
                parts.push(mm::hover(sub, None));
                range = Some(lines.range(w));
            }
            // In its argument list: the parameter under the cursor.
            None => {
                if let Some(c) = call
                    && let Some(sub) = mm::subprogram(s.ws.interface(), &f.text[c.name.range()])
                {
                    parts.push(mm::hover(sub, Some(c.arg)));
                    range = word.map(|w| lines.range(w));
                }
            }
        }
    }
    // What the name under the cursor is, from the model (not for the catalog's own names).
    let model = s.ws.model();
    if let Some(fid) = model.file_id(&f.path)
        && let Some((span, r)) = model.at(fid, offset as u32)
        && let Some(text) = model.describe(r)
        && !(parts.len() == 1
            && range.is_some()
            && matches!(r, Resolved::Routine(_))
            && mm::subprogram(s.ws.interface(), &f.text[span.range()]).is_some())
    {
        parts.push(text);
        range.get_or_insert(lines.range(span));
    }
    // The rule behind each finding under the cursor.
    if let Some(found) = s.findings.get(&f.path) {
        for d in found
            .iter()
            .filter(|d| d.span.start as usize <= offset && offset <= d.span.end as usize)
        {
            if let Some(rule) = crate::lint::rule(d.code) {
                parts.push(format!(
                    "**{}** ({}): {}. `krlkit rule {}` explains it.",
                    rule.code, rule.name, rule.summary, rule.code
                ));
            }
        }
    }
    (!parts.is_empty()).then(|| Hover {
        contents: markdown(parts.join("\n---\n")),
        range,
    })
}

fn completion(s: &Server, p: CompletionParams) -> Option<CompletionResponse> {
    let (f, lines, offset) = at(s, &p.text_document_position)?;
    if cursor::context(&lines, offset).0 != Place::Code {
        return None;
    }
    let mut items = mm::completions(s.ws.interface());
    let model = s.ws.model();
    if let Some(fid) = model.file_id(&f.path) {
        // The package's own DEFs, if it is in the workspace, are the catalog's snippets.
        items.extend(
            model
                .completions(fid, offset as u32)
                .into_iter()
                .filter(|i| mm::subprogram(s.ws.interface(), &i.label).is_none()),
        );
    }
    Some(CompletionResponse::Array(items))
}

fn signature_help(s: &Server, p: SignatureHelpParams) -> Option<SignatureHelp> {
    let (f, lines, offset) = at(s, &p.text_document_position_params)?;
    let (Place::Code, Some(call)) = cursor::context(&lines, offset) else {
        return None;
    };
    let name = &f.text[call.name.range()];
    if let Some(sub) = mm::subprogram(s.ws.interface(), name) {
        return Some(mm::signature_help(sub, call.arg));
    }
    let model = s.ws.model();
    model.signature_help(model.file_id(&f.path)?, offset as u32, name, call.arg)
}

/// The model's answer at a position: the file id, the name's span and what it resolves to.
fn resolve_at(
    s: &Server,
    p: &TextDocumentPositionParams,
) -> Option<(crate::sema::FileId, crate::diag::Span, Resolved)> {
    let (f, _, offset) = at(s, p)?;
    let model = s.ws.model();
    let fid = model.file_id(&f.path)?;
    let (span, r) = model.at(fid, offset as u32)?;
    Some((fid, span, r))
}

fn definition(s: &Server, p: GotoDefinitionParams) -> Option<GotoDefinitionResponse> {
    let (_, _, r) = resolve_at(s, &p.text_document_position_params)?;
    let model = s.ws.model();
    let loc = model.sema.declaration(r)?;
    let uri_of = |path: &str| s.uri(path);
    Some(GotoDefinitionResponse::Scalar(
        model.location(loc, &uri_of)?,
    ))
}

fn references(s: &Server, p: ReferenceParams) -> Option<Vec<Location>> {
    let (_, _, r) = resolve_at(s, &p.text_document_position)?;
    let model = s.ws.model();
    let uri_of = |path: &str| s.uri(path);
    Some(
        model
            .occurrences(r, p.context.include_declaration)
            .into_iter()
            .filter_map(|l| model.location(l, &uri_of))
            .collect(),
    )
}

fn request_failed(message: String) -> ResponseError {
    ResponseError {
        code: ErrorCode::RequestFailed as i32,
        message,
        data: None,
    }
}

/// The name's range when it can be renamed, else an error saying why.
fn prepare_rename(s: &Server, params: Value) -> Result<Value, ResponseError> {
    let p: TextDocumentPositionParams =
        serde_json::from_value(params).map_err(|e| ResponseError {
            code: ErrorCode::InvalidParams as i32,
            message: format!("invalid parameters for textDocument/prepareRename: {e}"),
            data: None,
        })?;
    let Some((fid, span, _)) = resolve_at(s, &p) else {
        return Ok(Value::Null);
    };
    let model = s.ws.model();
    let f = &model.files[fid.index()];
    let name = &f.text[span.range()];
    let uri_of = |path: &str| s.uri(path);
    // Renaming to the same name checks everything but the new name.
    model
        .rename(fid, span.start, name, &uri_of)
        .map_err(|why| request_failed(format!("cannot rename: {why}")))?;
    let range = Lines::new(&f.text).range(span);
    serde_json::to_value(PrepareRenameResponse::Range(range))
        .map_err(|e| request_failed(e.to_string()))
}

fn rename(s: &Server, params: Value) -> Result<Value, ResponseError> {
    let p: RenameParams = serde_json::from_value(params).map_err(|e| ResponseError {
        code: ErrorCode::InvalidParams as i32,
        message: format!("invalid parameters for textDocument/rename: {e}"),
        data: None,
    })?;
    let tdp = &p.text_document_position;
    let (f, _, offset) = at(s, tdp).ok_or_else(|| request_failed("unknown document".into()))?;
    let model = s.ws.model();
    let fid = model
        .file_id(&f.path)
        .ok_or_else(|| request_failed("unknown document".into()))?;
    let uri_of = |path: &str| s.uri(path);
    let edit = model
        .rename(fid, offset as u32, &p.new_name, &uri_of)
        .map_err(|why| request_failed(format!("cannot rename: {why}")))?;
    serde_json::to_value(edit).map_err(|e| request_failed(e.to_string()))
}

fn workspace_symbols(s: &Server, p: WorkspaceSymbolParams) -> Option<WorkspaceSymbolResponse> {
    let uri_of = |path: &str| s.uri(path);
    Some(WorkspaceSymbolResponse::Flat(
        s.ws.model().workspace_symbols(&p.query, &uri_of),
    ))
}

fn document_symbols(s: &Server, p: DocumentSymbolParams) -> Option<DocumentSymbolResponse> {
    let f = file(s, &p.text_document)?;
    let lines = Lines::new(&f.text);
    Some(DocumentSymbolResponse::Nested(outline::document_symbols(
        &lines,
        &f.tree(),
    )))
}

fn folding_ranges(s: &Server, p: FoldingRangeParams) -> Option<Vec<FoldingRange>> {
    let f = file(s, &p.text_document)?;
    let lines = Lines::new(&f.text);
    Some(outline::folding_ranges(&lines, &f.tree()))
}

/// `source.fixAll.krlkit`: every safe fix of the file at once.
fn fix_all() -> CodeActionKind {
    CodeActionKind::new("source.fixAll.krlkit")
}

fn text_edits(lines: &Lines, edits: &[Edit]) -> Vec<TextEdit> {
    edits
        .iter()
        .map(|e| TextEdit::new(lines.range(e.span), e.replacement.clone()))
        .collect()
}

fn workspace_edit(uri: &Uri, edits: Vec<TextEdit>) -> WorkspaceEdit {
    WorkspaceEdit {
        changes: Some([(uri.clone(), edits)].into_iter().collect()),
        ..WorkspaceEdit::default()
    }
}

/// The fixes the rules attached to the findings in the range (quick fixes), and all safe fixes
/// of the file together (`source.fixAll.krlkit`). Nothing here decides what a fix is.
fn code_actions(s: &Server, p: CodeActionParams) -> Option<CodeActionResponse> {
    let f = file(s, &p.text_document)?;
    let lines = Lines::new(&f.text);
    let want = lines.span(p.range);
    let found = s.findings.get(&f.path)?;
    let wanted = |k: &CodeActionKind| {
        p.context.only.as_ref().is_none_or(|only| {
            only.iter().any(|o| {
                k.as_str() == o.as_str() || k.as_str().starts_with(&format!("{}.", o.as_str()))
            })
        })
    };
    let uri = &p.text_document.uri;
    let mut out: CodeActionResponse = Vec::new();
    if wanted(&CodeActionKind::QUICKFIX) {
        for d in found {
            let Some(fix) = &d.fix else { continue };
            if d.span.start > want.end || want.start > d.span.end {
                continue;
            }
            out.push(CodeActionOrCommand::CodeAction(CodeAction {
                title: fix.title.clone(),
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![diagnostics::convert(&lines, d)]),
                edit: Some(workspace_edit(uri, text_edits(&lines, &fix.edits))),
                is_preferred: Some(fix.applicability == Applicability::Safe),
                ..CodeAction::default()
            }));
        }
    }
    if wanted(&fix_all()) {
        let mut edits: Vec<Edit> = Vec::new();
        for fix in found.iter().filter_map(|d| d.fix.as_ref()) {
            if fix.applicability == Applicability::Safe
                && !crate::diag::fix::overlaps(&edits, &fix.edits)
            {
                edits.extend(fix.edits.iter().cloned());
            }
        }
        if !edits.is_empty() {
            edits.sort_by_key(|e| (e.span.start, e.span.end));
            out.push(CodeActionOrCommand::CodeAction(CodeAction {
                title: "Apply every safe krlkit fix".into(),
                kind: Some(fix_all()),
                edit: Some(workspace_edit(uri, text_edits(&lines, &edits))),
                ..CodeAction::default()
            }));
        }
    }
    Some(out)
}

/// `krlkit fmt` on the document (or the lines of a range), with the workspace's `[fmt]` options.
fn formatting(
    s: &Server,
    doc: &TextDocumentIdentifier,
    range: Option<lsp_types::Range>,
) -> Option<Vec<TextEdit>> {
    let f = file(s, doc)?;
    let lines = Lines::new(&f.text);
    let edits = match range {
        None => crate::fmt::format_edits(&f.text, &s.ws.fmt),
        Some(r) => crate::fmt::format_range(&f.text, lines.span(r).range(), &s.ws.fmt),
    };
    Some(text_edits(&lines, &edits))
}
