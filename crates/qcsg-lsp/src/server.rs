//! The LSP request and notification handlers.
//!
//! Every handler takes the document's analysis (cached per version, computed on a blocking
//! thread otherwise), runs one `qcsg-ide` query on it and converts the answer. Analyses and
//! queries run inside `catch_unwind`: a panic is logged and answered with an internal error, and
//! the server keeps serving.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Arc, Mutex, MutexGuard};

use qcsg_ide as ide;
use tower_lsp_server::jsonrpc::{Error, Result};
use tower_lsp_server::ls_types::*;
use tower_lsp_server::{Client, LanguageServer};

use crate::convert;
use crate::documents::{Analyzed, Documents, document_path};

/// The server's state: the client handle, the open documents and what was published.
#[derive(Debug)]
pub struct Backend {
    client: Client,
    documents: Arc<Documents>,
    published: Mutex<Published>,
}

/// The diagnostics last published, by the document whose analysis found them.
#[derive(Debug, Default)]
struct Published {
    /// Each document's diagnostics of itself.
    own: HashMap<Uri, Vec<Diagnostic>>,
    /// Each document's diagnostics located in other open files (included or used).
    foreign: HashMap<Uri, HashMap<Uri, Vec<Diagnostic>>>,
    /// The files each document's analysis read besides itself, by path.
    dependencies: HashMap<Uri, Vec<String>>,
}

impl Published {
    /// What a file shows: its own diagnostics and those other documents found in it, each once.
    fn merged(&self, uri: &Uri) -> Vec<Diagnostic> {
        let mut merged: Vec<Diagnostic> = self.own.get(uri).cloned().unwrap_or_default();
        for found in self.foreign.values().filter_map(|f| f.get(uri)) {
            for diagnostic in found {
                if !merged.contains(diagnostic) {
                    merged.push(diagnostic.clone());
                }
            }
        }
        merged
    }

    /// Forgets what a closed document published.
    fn forget(&mut self, uri: &Uri) -> Vec<Uri> {
        self.own.remove(uri);
        self.dependencies.remove(uri);
        self.foreign
            .remove(uri)
            .map(|f| f.into_keys().collect())
            .unwrap_or_default()
    }
}

/// `found` for every open file other than the main one, keyed by the file's URI.
fn foreign_diagnostics(
    open: &HashMap<String, Uri>,
    found: impl Fn(&str) -> Vec<ide::IdeDiagnostic>,
    main_path: &str,
    main_uri: &Uri,
) -> HashMap<Uri, Vec<Diagnostic>> {
    open.iter()
        .filter(|(path, _)| path.as_str() != main_path)
        .filter_map(|(path, uri)| {
            let diagnostics: Vec<_> = found(path)
                .iter()
                .map(|d| convert::diagnostic(d, main_path, main_uri))
                .collect();
            (!diagnostics.is_empty()).then(|| (uri.clone(), diagnostics))
        })
        .collect()
}

impl Backend {
    /// A server talking to `client`.
    pub fn new(client: Client) -> Self {
        Self {
            client,
            documents: Arc::new(Documents::default()),
            published: Mutex::default(),
        }
    }

    /// Runs `query` on the current analysis of `uri`; `Ok(None)` when the document is not open.
    pub(crate) async fn query<T: Send + 'static>(
        &self,
        uri: &Uri,
        query: impl FnOnce(&Analyzed) -> T + Send + 'static,
    ) -> Result<Option<T>> {
        Ok(self
            .query_versioned(uri, query)
            .await?
            .map(|(value, _)| value))
    }

    /// Like [`Backend::query`], also saying whether the document is still at the version
    /// analysed.
    async fn query_versioned<T: Send + 'static>(
        &self,
        uri: &Uri,
        query: impl FnOnce(&Analyzed) -> T + Send + 'static,
    ) -> Result<Option<(T, bool)>> {
        let Some(cached) = self.documents.analysis_or_snapshot(uri) else {
            return Ok(None);
        };
        let (documents, document) = (self.documents.clone(), uri.clone());
        let outcome = tokio::task::spawn_blocking(move || {
            catch_unwind(AssertUnwindSafe(move || match cached {
                Ok(analysis) => (query(&analysis), None),
                Err(snapshot) => {
                    let (analysis, made_from) = documents.analyze_in_turn(&document, snapshot);
                    (query(&analysis), made_from.map(|s| (s, analysis)))
                }
            }))
        })
        .await;
        match outcome {
            Ok(Ok((value, computed))) => {
                let current = match computed {
                    Some((snapshot, analysis)) => self.documents.store(uri, &snapshot, &analysis),
                    None => true,
                };
                Ok(Some((value, current)))
            }
            Ok(Err(panic)) => {
                let message = panic
                    .downcast_ref::<&str>()
                    .map(|s| (*s).to_owned())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".to_owned());
                self.client
                    .log_message(
                        MessageType::ERROR,
                        format!("internal error on {}: {message}", uri.as_str()),
                    )
                    .await;
                Err(Error::internal_error())
            }
            Err(join) => {
                self.client
                    .log_message(MessageType::ERROR, format!("analysis task failed: {join}"))
                    .await;
                Err(Error::internal_error())
            }
        }
    }

    /// Checks a document and publishes its diagnostics, unless it changed meanwhile (a newer
    /// change publishes its own): first the checker's, at once; then, for a program without
    /// static errors, again with the evaluator's (runtime errors, warnings, `echo`) once the
    /// evaluation is done. Diagnostics located in files it includes that are open are published
    /// to those files too.
    async fn publish_diagnostics(&self, uri: Uri) {
        let Some(version) = self.documents.version(&uri) else {
            return;
        };
        let open = self.open_paths();
        let (main_uri, path) = (uri.clone(), document_path(&uri));
        let checked = self
            .query_versioned(&uri, move |a| {
                let convert = |d: &ide::IdeDiagnostic| convert::diagnostic(d, &path, &main_uri);
                let own: Vec<_> = a.diagnostics().iter().map(convert).collect();
                let foreign = foreign_diagnostics(&open, |p| a.diagnostics_in(p), &path, &main_uri);
                let dependencies = a.dependencies();
                (own, foreign, dependencies, a.sema().has_errors())
            })
            .await;
        let Ok(Some(((own, foreign, dependencies, has_errors), true))) = checked else {
            return;
        };
        if self.documents.version(&uri) != Some(version) {
            return;
        }
        self.lock_published()
            .dependencies
            .insert(uri.clone(), dependencies);
        self.publish_merged(&uri, own.clone(), foreign.clone(), version)
            .await;
        if has_errors || self.documents.version(&uri) != Some(version) {
            return;
        }
        let open = self.open_paths();
        let (main_uri, path) = (uri.clone(), document_path(&uri));
        let evaluated = self
            .query_versioned(&uri, move |a| {
                let Some(geometry) = a.geometry() else {
                    return (Vec::new(), HashMap::new());
                };
                let convert = |d: &ide::IdeDiagnostic| convert::diagnostic(d, &path, &main_uri);
                let own: Vec<_> = geometry.diagnostics(a).iter().map(convert).collect();
                let foreign =
                    foreign_diagnostics(&open, |p| geometry.diagnostics_in(a, p), &path, &main_uri);
                (own, foreign)
            })
            .await;
        if let Ok(Some(((more_own, more_foreign), true))) = evaluated
            && self.documents.version(&uri) == Some(version)
            && !(more_own.is_empty() && more_foreign.is_empty())
        {
            let mut own = own;
            own.extend(more_own);
            let mut foreign = foreign;
            for (target, diagnostics) in more_foreign {
                foreign.entry(target).or_default().extend(diagnostics);
            }
            self.publish_merged(&uri, own, foreign, version).await;
        }
    }

    /// Records `uri`'s own diagnostics and those it found in other open files, then publishes
    /// to `uri` and to every file it reports on now or did before.
    async fn publish_merged(
        &self,
        uri: &Uri,
        own: Vec<Diagnostic>,
        foreign: HashMap<Uri, Vec<Diagnostic>>,
        version: i32,
    ) {
        let mut targets: Vec<Uri> = foreign.keys().cloned().collect();
        let foreign = foreign
            .into_iter()
            .map(|(target, found)| (target, convert::capped(found)))
            .collect();
        {
            let mut published = self.lock_published();
            published.own.insert(uri.clone(), convert::capped(own));
            if let Some(before) = published.foreign.insert(uri.clone(), foreign) {
                targets.extend(before.into_keys());
            }
        }
        let merged = self.lock_published().merged(uri);
        self.client
            .publish_diagnostics(uri.clone(), merged, Some(version))
            .await;
        targets.sort_by(|a, b| a.as_str().cmp(b.as_str()));
        targets.dedup();
        for target in targets.into_iter().filter(|t| t != uri) {
            if let Some(version) = self.documents.version(&target) {
                let merged = self.lock_published().merged(&target);
                self.client
                    .publish_diagnostics(target, merged, Some(version))
                    .await;
            }
        }
    }

    /// Re-checks every other open document that includes or uses `uri` (their diagnostics
    /// depend on its unsaved text).
    async fn publish_dependents(&self, uri: &Uri) {
        let path = document_path(uri);
        let dependents: Vec<Uri> = self
            .lock_published()
            .dependencies
            .iter()
            .filter(|(d, files)| *d != uri && files.contains(&path))
            .map(|(d, _)| d.clone())
            .collect();
        for dependent in dependents {
            if self.documents.version(&dependent).is_some() {
                self.publish_diagnostics(dependent).await;
            }
        }
    }

    /// Every open document by its path.
    fn open_paths(&self) -> HashMap<String, Uri> {
        self.documents
            .uris()
            .into_iter()
            .map(|uri| (document_path(&uri), uri))
            .collect()
    }

    fn lock_published(&self) -> MutexGuard<'_, Published> {
        // Every update is a single insertion or removal: a poisoned lock is still consistent.
        self.published
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    fn location_converter(
        uri: &Uri,
    ) -> impl Fn(&ide::FileRange) -> Option<Location> + Send + 'static {
        let main_uri = uri.clone();
        let main_path = document_path(uri);
        move |file_range| convert::location(file_range, &main_path, &main_uri)
    }
}

fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(
            TextDocumentSyncKind::INCREMENTAL,
        )),
        position_encoding: Some(PositionEncodingKind::UTF16),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Right(RenameOptions {
            prepare_provider: Some(true),
            work_done_progress_options: WorkDoneProgressOptions::default(),
        })),
        document_symbol_provider: Some(OneOf::Left(true)),
        workspace_symbol_provider: Some(OneOf::Left(true)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec![
                "<".into(),
                "/".into(),
                "(".into(),
                ",".into(),
                "$".into(),
            ]),
            ..CompletionOptions::default()
        }),
        signature_help_provider: Some(SignatureHelpOptions {
            trigger_characters: Some(vec!["(".into(), ",".into()]),
            retrigger_characters: None,
            work_done_progress_options: WorkDoneProgressOptions::default(),
        }),
        semantic_tokens_provider: Some(SemanticTokensServerCapabilities::SemanticTokensOptions(
            SemanticTokensOptions {
                legend: convert::semantic_legend(),
                full: Some(SemanticTokensFullOptions::Bool(true)),
                range: None,
                work_done_progress_options: WorkDoneProgressOptions::default(),
            },
        )),
        inlay_hint_provider: Some(OneOf::Left(true)),
        document_formatting_provider: Some(OneOf::Left(true)),
        folding_range_provider: Some(FoldingRangeProviderCapability::Simple(true)),
        code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
            code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
            ..CodeActionOptions::default()
        })),
        ..ServerCapabilities::default()
    }
}

impl LanguageServer for Backend {
    async fn initialize(&self, _: InitializeParams) -> Result<InitializeResult> {
        Ok(InitializeResult {
            capabilities: capabilities(),
            server_info: Some(ServerInfo {
                name: "qcsg".to_owned(),
                version: Some(env!("CARGO_PKG_VERSION").to_owned()),
            }),
            offset_encoding: None,
        })
    }

    async fn initialized(&self, _: InitializedParams) {
        self.client
            .log_message(MessageType::INFO, "qcsg language server ready")
            .await;
    }

    async fn shutdown(&self) -> Result<()> {
        Ok(())
    }

    async fn did_open(&self, params: DidOpenTextDocumentParams) {
        let document = params.text_document;
        self.documents
            .open(document.uri.clone(), document.text, document.version);
        self.publish_diagnostics(document.uri.clone()).await;
        self.publish_dependents(&document.uri).await;
    }

    async fn did_change(&self, params: DidChangeTextDocumentParams) {
        let uri = params.text_document.uri;
        // Applied before the first `.await`, so edits apply in the order they arrive.
        if self
            .documents
            .change(&uri, params.text_document.version, params.content_changes)
        {
            self.publish_diagnostics(uri.clone()).await;
            self.publish_dependents(&uri).await;
        }
    }

    async fn did_close(&self, params: DidCloseTextDocumentParams) {
        let uri = params.text_document.uri;
        self.documents.close(&uri);
        let targets = self.lock_published().forget(&uri);
        self.client
            .publish_diagnostics(uri.clone(), Vec::new(), None)
            .await;
        // Files it reported on lose those diagnostics; files including it see it from disk now.
        for target in targets {
            if let Some(version) = self.documents.version(&target) {
                let merged = self.lock_published().merged(&target);
                self.client
                    .publish_diagnostics(target, merged, Some(version))
                    .await;
            }
        }
        self.publish_dependents(&uri).await;
    }

    async fn hover(&self, params: HoverParams) -> Result<Option<Hover>> {
        let at = params.text_document_position_params;
        let position = convert::line_col(at.position);
        let hover = self
            .query(&at.text_document.uri, move |a| {
                a.hover_with(position, Some(a as &dyn ide::HoverExtension))
            })
            .await?
            .flatten();
        Ok(hover.map(|hover| Hover {
            contents: HoverContents::Markup(MarkupContent {
                kind: MarkupKind::Markdown,
                value: hover.markdown,
            }),
            range: Some(convert::range(hover.range)),
        }))
    }

    async fn goto_definition(
        &self,
        params: GotoDefinitionParams,
    ) -> Result<Option<GotoDefinitionResponse>> {
        let at = params.text_document_position_params;
        let position = convert::line_col(at.position);
        let to_location = Self::location_converter(&at.text_document.uri);
        let location = self
            .query(&at.text_document.uri, move |a| {
                a.goto_definition(position).and_then(|r| to_location(&r))
            })
            .await?
            .flatten();
        Ok(location.map(GotoDefinitionResponse::Scalar))
    }

    async fn references(&self, params: ReferenceParams) -> Result<Option<Vec<Location>>> {
        let at = params.text_document_position;
        let position = convert::line_col(at.position);
        let include_declaration = params.context.include_declaration;
        let to_location = Self::location_converter(&at.text_document.uri);
        self.query(&at.text_document.uri, move |a| {
            a.references(position, include_declaration)
                .iter()
                .filter_map(&to_location)
                .collect()
        })
        .await
    }

    async fn prepare_rename(
        &self,
        params: TextDocumentPositionParams,
    ) -> Result<Option<PrepareRenameResponse>> {
        let position = convert::line_col(params.position);
        match self
            .query(&params.text_document.uri, move |a| {
                a.prepare_rename(position)
            })
            .await?
        {
            Some(Ok(target)) => Ok(Some(PrepareRenameResponse::RangeWithPlaceholder {
                range: convert::range(target.range),
                placeholder: target.name,
            })),
            Some(Err(error)) => Err(Error::invalid_params(error.to_string())),
            None => Ok(None),
        }
    }

    async fn rename(&self, params: RenameParams) -> Result<Option<WorkspaceEdit>> {
        let at = params.text_document_position;
        let position = convert::line_col(at.position);
        let to_location = Self::location_converter(&at.text_document.uri);
        let new_name = params.new_name;
        let result = self
            .query(&at.text_document.uri, move |a| {
                a.rename(position, &new_name).map(|ranges| {
                    let mut changes: HashMap<Uri, Vec<TextEdit>> = Default::default();
                    for location in ranges.iter().filter_map(&to_location) {
                        changes
                            .entry(location.uri)
                            .or_default()
                            .push(TextEdit::new(location.range, new_name.clone()));
                    }
                    WorkspaceEdit {
                        changes: Some(changes),
                        ..WorkspaceEdit::default()
                    }
                })
            })
            .await?;
        match result {
            Some(Ok(edit)) => Ok(Some(edit)),
            Some(Err(error)) => Err(Error::invalid_params(error.to_string())),
            None => Ok(None),
        }
    }

    async fn document_symbol(
        &self,
        params: DocumentSymbolParams,
    ) -> Result<Option<DocumentSymbolResponse>> {
        let symbols = self
            .query(&params.text_document.uri, |a| a.document_symbols())
            .await?;
        Ok(symbols.map(|symbols| {
            DocumentSymbolResponse::Nested(symbols.iter().map(document_symbol).collect())
        }))
    }

    async fn symbol(
        &self,
        params: WorkspaceSymbolParams,
    ) -> Result<Option<WorkspaceSymbolResponse>> {
        let mut found: Vec<WorkspaceSymbol> = Vec::new();
        for uri in self.documents.uris() {
            let query = params.query.clone();
            let to_location = Self::location_converter(&uri);
            let symbols = self
                .query(&uri, move |a| {
                    a.workspace_symbols(&query)
                        .into_iter()
                        .filter_map(|s| {
                            Some(WorkspaceSymbol {
                                name: s.name.clone(),
                                kind: symbol_kind(s.kind),
                                tags: None,
                                container_name: s.container.clone(),
                                location: OneOf::Left(to_location(&s.location)?),
                                data: None,
                            })
                        })
                        .collect::<Vec<_>>()
                })
                .await?
                .unwrap_or_default();
            for symbol in symbols {
                if !found
                    .iter()
                    .any(|f| f.name == symbol.name && f.location == symbol.location)
                {
                    found.push(symbol);
                }
            }
        }
        Ok(Some(WorkspaceSymbolResponse::Nested(found)))
    }

    async fn completion(&self, params: CompletionParams) -> Result<Option<CompletionResponse>> {
        let at = params.text_document_position;
        let position = convert::line_col(at.position);
        let items = self
            .query(&at.text_document.uri, move |a| a.completions(position))
            .await?;
        Ok(items.map(|items| {
            CompletionResponse::Array(items.into_iter().map(completion_item).collect())
        }))
    }

    async fn signature_help(&self, params: SignatureHelpParams) -> Result<Option<SignatureHelp>> {
        let at = params.text_document_position_params;
        let position = convert::line_col(at.position);
        let help = self
            .query(&at.text_document.uri, move |a| a.signature_help(position))
            .await?
            .flatten();
        Ok(help.map(|help| SignatureHelp {
            signatures: vec![SignatureInformation {
                label: help.label.clone(),
                documentation: help.doc.clone().map(Documentation::String),
                parameters: Some(
                    help.params
                        .iter()
                        .map(|p| ParameterInformation {
                            label: ParameterLabel::LabelOffsets([
                                utf16_len(&help.label[..p.label_range.0 as usize]),
                                utf16_len(&help.label[..p.label_range.1 as usize]),
                            ]),
                            documentation: p.doc.clone().map(Documentation::String),
                        })
                        .collect(),
                ),
                active_parameter: help.active_param.map(|i| i as u32),
            }],
            active_signature: Some(0),
            active_parameter: help.active_param.map(|i| i as u32),
        }))
    }

    async fn semantic_tokens_full(
        &self,
        params: SemanticTokensParams,
    ) -> Result<Option<SemanticTokensResult>> {
        let tokens = self
            .query(&params.text_document.uri, |a| {
                convert::semantic_tokens(&a.semantic_tokens())
            })
            .await?;
        Ok(tokens.map(|data| {
            SemanticTokensResult::Tokens(SemanticTokens {
                result_id: None,
                data,
            })
        }))
    }

    async fn inlay_hint(&self, params: InlayHintParams) -> Result<Option<Vec<InlayHint>>> {
        let range = convert::text_range(params.range);
        let hints = self
            .query(&params.text_document.uri, move |a| a.inlay_hints(range))
            .await?;
        Ok(hints.map(|hints| {
            hints
                .into_iter()
                .map(|hint| InlayHint {
                    position: convert::position(hint.position),
                    label: InlayHintLabel::String(hint.label),
                    kind: Some(match hint.kind {
                        ide::InlayKind::Parameter => InlayHintKind::PARAMETER,
                        ide::InlayKind::Value => InlayHintKind::TYPE,
                    }),
                    text_edits: None,
                    tooltip: None,
                    padding_left: Some(hint.padding_left),
                    padding_right: Some(hint.padding_right),
                    data: None,
                })
                .collect()
        }))
    }

    async fn formatting(&self, params: DocumentFormattingParams) -> Result<Option<Vec<TextEdit>>> {
        let Some((text, _)) = self.documents.text(&params.text_document.uri) else {
            return Ok(None);
        };
        let path = document_path(&params.text_document.uri);
        let formatted = tokio::task::spawn_blocking(move || {
            catch_unwind(AssertUnwindSafe(|| {
                (ide::format::format_file(&path, &text), text)
            }))
        })
        .await;
        match formatted {
            Ok(Ok((Ok(formatted), text))) if formatted != text => {
                let index = qcsg_diag::LineIndex::new(&text);
                let end = index.line_col(&text, text.len());
                Ok(Some(vec![TextEdit::new(
                    Range::new(Position::new(0, 0), convert::position(end)),
                    formatted,
                )]))
            }
            Ok(Ok((Ok(_), _))) => Ok(Some(Vec::new())),
            // A file with syntax errors is left alone; its diagnostics say why.
            Ok(Ok((Err(_), _))) => Ok(None),
            _ => Err(Error::internal_error()),
        }
    }

    async fn folding_range(&self, params: FoldingRangeParams) -> Result<Option<Vec<FoldingRange>>> {
        let ranges = self
            .query(&params.text_document.uri, |a| a.folding_ranges())
            .await?;
        Ok(ranges.map(|ranges| {
            ranges
                .into_iter()
                .map(|r| FoldingRange {
                    start_line: r.start_line,
                    end_line: r.end_line,
                    kind: Some(match r.kind {
                        ide::FoldKind::Region => FoldingRangeKind::Region,
                        ide::FoldKind::Comment => FoldingRangeKind::Comment,
                    }),
                    ..FoldingRange::default()
                })
                .collect()
        }))
    }

    async fn code_action(&self, params: CodeActionParams) -> Result<Option<CodeActionResponse>> {
        let uri = params.text_document.uri;
        let range = convert::text_range(params.range);
        let actions = self.query(&uri, move |a| a.code_actions(range)).await?;
        Ok(actions.map(|actions| {
            actions
                .into_iter()
                .map(|action| {
                    let edits = action
                        .edits
                        .into_iter()
                        .map(|e| TextEdit::new(convert::range(e.range), e.new_text))
                        .collect();
                    CodeActionOrCommand::CodeAction(CodeAction {
                        title: action.title,
                        kind: Some(CodeActionKind::QUICKFIX),
                        edit: Some(WorkspaceEdit {
                            changes: Some([(uri.clone(), edits)].into_iter().collect()),
                            ..WorkspaceEdit::default()
                        }),
                        is_preferred: Some(action.preferred),
                        ..CodeAction::default()
                    })
                })
                .collect()
        }))
    }
}

fn utf16_len(text: &str) -> u32 {
    text.encode_utf16().count() as u32
}

fn symbol_kind(kind: ide::SymbolKind) -> SymbolKind {
    match kind {
        ide::SymbolKind::Module => SymbolKind::MODULE,
        ide::SymbolKind::Function => SymbolKind::FUNCTION,
        ide::SymbolKind::Variable => SymbolKind::VARIABLE,
    }
}

#[allow(deprecated)] // `DocumentSymbol::deprecated` must still be written.
fn document_symbol(symbol: &ide::Symbol) -> DocumentSymbol {
    DocumentSymbol {
        name: symbol.name.clone(),
        detail: symbol.detail.clone(),
        kind: symbol_kind(symbol.kind),
        tags: None,
        deprecated: None,
        range: convert::range(symbol.location.range),
        selection_range: convert::range(symbol.selection),
        children: (!symbol.children.is_empty())
            .then(|| symbol.children.iter().map(document_symbol).collect()),
    }
}

fn completion_item(item: ide::CompletionItem) -> CompletionItem {
    let kind = match item.kind {
        ide::CompletionKind::Module => CompletionItemKind::MODULE,
        ide::CompletionKind::Function => CompletionItemKind::FUNCTION,
        ide::CompletionKind::Variable => CompletionItemKind::VARIABLE,
        ide::CompletionKind::Parameter => CompletionItemKind::PROPERTY,
        ide::CompletionKind::Keyword => CompletionItemKind::KEYWORD,
        ide::CompletionKind::File => CompletionItemKind::FILE,
        ide::CompletionKind::Folder => CompletionItemKind::FOLDER,
    };
    let text_edit = item.replace.map(|range| {
        CompletionTextEdit::Edit(TextEdit::new(
            convert::range(range),
            item.insert_text
                .clone()
                .unwrap_or_else(|| item.label.clone()),
        ))
    });
    CompletionItem {
        label: item.label,
        kind: Some(kind),
        sort_text: item.sort_text,
        text_edit,
        detail: item.detail,
        documentation: item.doc.map(|value| {
            Documentation::MarkupContent(MarkupContent {
                kind: MarkupKind::Markdown,
                value,
            })
        }),
        insert_text: item.insert_text,
        ..CompletionItem::default()
    }
}
