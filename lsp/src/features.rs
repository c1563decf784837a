//! LSP features: each function converts a request's positions to byte
//! offsets, asks gloc-ide, and converts the answer to protocol types. What a
//! feature answers is decided in gloc-ide; positions go through `position` only.

use std::collections::HashMap;

use gloc_engine::Severity;
use ropey::Rope;
use serde_json::Value;
use tower_lsp_server::jsonrpc;
use tower_lsp_server::ls_types::*;

use crate::document::Document;
use crate::position::{offset_of, position_of, range_of, span_of, PositionWalker};
use crate::server::COMPILED_GLOC_COMMAND;
use gloc_ide::analysis::{Analysis, CompletionKind, Context, Insert, SymbolKind as Kind};
use gloc_ide::references::HighlightKind;
use gloc_ide::tokens::TokenType;
use gloc_ide::{completion, lens, links, selection};

/// What the client said it can show (`initialize`'s capabilities); answers follow it.
/// Before `initialize`, and for a client that says nothing, the protocol's defaults:
/// no snippets, flat symbols, plain text (markdown only to a client that lists it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClientFeatures {
    pub snippets: bool,
    pub completion_markdown: bool,
    pub hover_markdown: bool,
    pub hierarchical_symbols: bool,
    /// Completion items may come without documentation, filled by `completionItem/resolve`.
    pub resolve_documentation: bool,
    /// The client pulls diagnostics (`textDocument/diagnostic`): no push for scripts.
    pub pull_diagnostics: bool,
    /// The client shows a diagnostic's related locations (`relatedInformation`);
    /// without it they are written into the message.
    pub related_information: bool,
    /// The client accepts `workspace/diagnostic/refresh`.
    pub diagnostic_refresh: bool,
    /// The client runs the code lens command `gloc.runMission` (it lists it in
    /// `experimental.commands.commands`, rust-analyzer's convention).
    pub run_command: bool,
    /// The same for `gloc.debugScript`.
    pub debug_command: bool,
}

/// The client command a "Run" code lens invokes (argument: the document URI).
pub const RUN_COMMAND: &str = "gloc.runMission";
/// The client command a "Debug" code lens invokes (argument: the document URI).
pub const DEBUG_COMMAND: &str = "gloc.debugScript";

impl Default for ClientFeatures {
    fn default() -> Self {
        ClientFeatures::from_capabilities(&ClientCapabilities::default())
    }
}

impl ClientFeatures {
    pub fn from_capabilities(capabilities: &ClientCapabilities) -> ClientFeatures {
        let text = capabilities.text_document.as_ref();
        let item = text
            .and_then(|text| text.completion.as_ref())
            .and_then(|completion| completion.completion_item.as_ref());
        let markdown = |formats: Option<&Vec<MarkupKind>>| {
            formats.is_some_and(|formats| formats.contains(&MarkupKind::Markdown))
        };
        ClientFeatures {
            snippets: item.and_then(|item| item.snippet_support).unwrap_or(false),
            completion_markdown: markdown(item.and_then(|item| item.documentation_format.as_ref())),
            hover_markdown: markdown(
                text.and_then(|text| text.hover.as_ref())
                    .and_then(|hover| hover.content_format.as_ref()),
            ),
            hierarchical_symbols: text
                .and_then(|text| text.document_symbol.as_ref())
                .and_then(|symbols| symbols.hierarchical_document_symbol_support)
                .unwrap_or(false),
            resolve_documentation: item
                .and_then(|item| item.resolve_support.as_ref())
                .is_some_and(|support| support.properties.iter().any(|p| p == "documentation")),
            pull_diagnostics: text.is_some_and(|text| text.diagnostic.is_some()),
            related_information: if text.is_some_and(|text| text.diagnostic.is_some()) {
                text.and_then(|text| text.diagnostic.as_ref())
                    .and_then(|pull| pull.related_information)
                    .unwrap_or(false)
            } else {
                text.and_then(|text| text.publish_diagnostics.as_ref())
                    .and_then(|push| push.related_information)
                    .unwrap_or(false)
            },
            diagnostic_refresh: capabilities
                .workspace
                .as_ref()
                .and_then(|workspace| workspace.diagnostics.as_ref())
                .and_then(|diagnostics| diagnostics.refresh_support)
                .unwrap_or(false),
            run_command: client_runs(capabilities, RUN_COMMAND),
            debug_command: client_runs(capabilities, DEBUG_COMMAND),
        }
    }
}

/// Whether the client lists `command` in `experimental.commands.commands`.
fn client_runs(capabilities: &ClientCapabilities, command: &str) -> bool {
    capabilities
        .experimental
        .as_ref()
        .and_then(|experimental| experimental.get("commands"))
        .and_then(|commands| commands.get("commands"))
        .and_then(Value::as_array)
        .is_some_and(|commands| commands.iter().any(|listed| listed == command))
}

/// `text` (markdown) as the client can show it: plain text drops the inline code
/// marks, emphasis (`**strong**`, `*emphasis*`) and code fences.
fn markup(text: String, markdown: bool) -> MarkupContent {
    if markdown {
        return MarkupContent {
            kind: MarkupKind::Markdown,
            value: text,
        };
    }
    let plain: Vec<String> = text
        .lines()
        .filter(|line| !line.trim_start().starts_with("```"))
        .map(|line| without_emphasis(&line.replace("**", "").replace('`', "")))
        .collect();
    MarkupContent {
        kind: MarkupKind::PlainText,
        value: plain.join("\n"),
    }
}

/// `line` without the `*` that open or close an emphasis (`*from the paper*`);
/// a `*` between spaces (`a * b`) is text and stays.
fn without_emphasis(line: &str) -> String {
    let chars: Vec<char> = line.chars().collect();
    let mut out = String::with_capacity(line.len());
    for (index, &c) in chars.iter().enumerate() {
        if c == '*' {
            let before = index.checked_sub(1).map(|i| chars[i]);
            let after = chars.get(index + 1).copied();
            let opens = before.is_none_or(|b| b.is_whitespace() || "([".contains(b))
                && after.is_some_and(|a| !a.is_whitespace() && a != '*');
            let closes = before.is_some_and(|b| !b.is_whitespace() && b != '*')
                && after.is_none_or(|a| a.is_whitespace() || ".,;:)]".contains(a));
            if opens || closes {
                continue;
            }
        }
        out.push(c);
    }
    out
}

/// A snippet's text without its tab stops (`${1:r0}` gives `r0`, `$1` nothing),
/// for a client without snippet support.
fn snippet_text(snippet: &str) -> String {
    let mut out = String::with_capacity(snippet.len());
    let mut rest = snippet;
    while let Some(at) = rest.find('$') {
        out.push_str(&rest[..at]);
        rest = &rest[at + 1..];
        if let Some(inner) = rest.strip_prefix('{') {
            // `${N:default}` or `${N}`: keep the default.
            let end = inner.find('}').unwrap_or(inner.len());
            let body = &inner[..end];
            if let Some((_, default)) = body.split_once(':') {
                out.push_str(default);
            }
            rest = inner.get(end + 1..).unwrap_or("");
        } else {
            let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
            if digits == 0 {
                out.push('$');
            }
            rest = &rest[digits..];
        }
    }
    out.push_str(rest);
    out
}

/// The protocol's name of a highlight type; the legend lists them in
/// `TokenType::ALL` order, so a token's type is its `TokenType as u32`.
fn token_type_name(token_type: TokenType) -> SemanticTokenType {
    match token_type {
        TokenType::Keyword => SemanticTokenType::KEYWORD,
        TokenType::Macro => SemanticTokenType::MACRO,
        TokenType::Function => SemanticTokenType::FUNCTION,
        TokenType::Variable => SemanticTokenType::VARIABLE,
        TokenType::Number => SemanticTokenType::NUMBER,
        TokenType::String => SemanticTokenType::STRING,
        TokenType::Comment => SemanticTokenType::COMMENT,
        TokenType::Operator => SemanticTokenType::OPERATOR,
        TokenType::Property => SemanticTokenType::PROPERTY,
        TokenType::Label => SemanticTokenType::new("label"),
    }
}

pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        position_encoding: Some(PositionEncodingKind::UTF16),
        text_document_sync: Some(TextDocumentSyncCapability::Options(
            TextDocumentSyncOptions {
                open_close: Some(true),
                change: Some(TextDocumentSyncKind::INCREMENTAL),
                save: Some(TextDocumentSyncSaveOptions::Supported(true)),
                ..TextDocumentSyncOptions::default()
            },
        )),
        completion_provider: Some(CompletionOptions {
            // Not a space: every space would fetch a list.
            trigger_characters: Some(vec![",".into(), "(".into()]),
            resolve_provider: Some(true),
            ..CompletionOptions::default()
        }),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        signature_help_provider: Some(SignatureHelpOptions {
            trigger_characters: Some(vec!["(".into(), ",".into()]),
            retrigger_characters: None,
            work_done_progress_options: WorkDoneProgressOptions::default(),
        }),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        document_highlight_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Right(RenameOptions {
            prepare_provider: Some(true),
            work_done_progress_options: WorkDoneProgressOptions::default(),
        })),
        document_symbol_provider: Some(OneOf::Left(true)),
        folding_range_provider: Some(FoldingRangeProviderCapability::Simple(true)),
        semantic_tokens_provider: Some(SemanticTokensServerCapabilities::SemanticTokensOptions(
            SemanticTokensOptions {
                legend: SemanticTokensLegend {
                    token_types: TokenType::ALL.map(token_type_name).to_vec(),
                    token_modifiers: gloc_ide::tokens::modifiers::NAMES
                        .map(SemanticTokenModifier::new)
                        .to_vec(),
                },
                full: Some(SemanticTokensFullOptions::Delta { delta: Some(true) }),
                range: Some(true),
                work_done_progress_options: WorkDoneProgressOptions::default(),
            },
        )),
        inlay_hint_provider: Some(OneOf::Left(true)),
        code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
            code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
            ..CodeActionOptions::default()
        })),
        document_formatting_provider: Some(OneOf::Left(true)),
        document_range_formatting_provider: Some(OneOf::Left(true)),
        selection_range_provider: Some(SelectionRangeProviderCapability::Simple(true)),
        code_lens_provider: Some(CodeLensOptions {
            resolve_provider: Some(false),
        }),
        document_link_provider: Some(DocumentLinkOptions {
            resolve_provider: Some(false),
            work_done_progress_options: WorkDoneProgressOptions::default(),
        }),
        workspace_symbol_provider: Some(OneOf::Left(true)),
        diagnostic_provider: Some(DiagnosticServerCapabilities::Options(DiagnosticOptions {
            identifier: Some("gloc".to_string()),
            inter_file_dependencies: false,
            workspace_diagnostics: false,
            work_done_progress_options: WorkDoneProgressOptions::default(),
        })),
        execute_command_provider: Some(ExecuteCommandOptions {
            commands: vec![COMPILED_GLOC_COMMAND.to_string()],
            work_done_progress_options: WorkDoneProgressOptions::default(),
        }),
        ..ServerCapabilities::default()
    }
}

pub fn diagnostics(
    document: &Document,
    analysis: &Analysis,
    client: ClientFeatures,
) -> Vec<Diagnostic> {
    diagnostics_for(
        document.rope(),
        &document.uri,
        &analysis.diagnostics,
        client,
    )
}

/// Converts core diagnostics; labels become related information in the same file
/// for a client that shows it, else lines of the message (`3:5: label`).
pub fn diagnostics_for(
    rope: &Rope,
    uri: &Uri,
    diagnostics: &[gloc_engine::Diagnostic],
    client: ClientFeatures,
) -> Vec<Diagnostic> {
    diagnostics
        .iter()
        .map(|diagnostic| {
            let mut message = diagnostic.message.clone();
            if let Some(help) = &diagnostic.help {
                message.push_str("\nhelp: ");
                message.push_str(help);
            }
            if !client.related_information {
                for label in &diagnostic.labels {
                    let at = range_of(rope, label.span).start;
                    message.push_str(&format!(
                        "\n{}:{}: {}",
                        at.line + 1,
                        at.character + 1,
                        label.message
                    ));
                }
            }
            let related: Vec<DiagnosticRelatedInformation> = diagnostic
                .labels
                .iter()
                .map(|label| DiagnosticRelatedInformation {
                    location: Location {
                        uri: uri.clone(),
                        range: range_of(rope, label.span),
                    },
                    message: label.message.clone(),
                })
                .collect();
            Diagnostic {
                range: range_of(rope, diagnostic.span),
                severity: Some(match diagnostic.severity {
                    Severity::Error => DiagnosticSeverity::ERROR,
                    Severity::Warning => DiagnosticSeverity::WARNING,
                    Severity::Note => DiagnosticSeverity::INFORMATION,
                }),
                code: Some(NumberOrString::String(diagnostic.code.to_string())),
                source: Some("gloc".to_string()),
                message,
                related_information: (client.related_information && !related.is_empty())
                    .then_some(related),
                ..Diagnostic::default()
            }
        })
        .collect()
}

/// The completion list at `position`: the language's candidates that match the
/// word being typed, best first, at most `limit` (`is_incomplete` when cut, so
/// the client asks again as the word grows). Clients that resolve documentation
/// get it from `completion_resolve`, not in the list.
pub fn completion(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    position: Position,
    client: ClientFeatures,
    limit: usize,
) -> Option<CompletionResponse> {
    let offset = offset_of(document.rope(), position);
    let candidates = candidates_at(document, analysis, context, offset);
    let (start, typed) = completion::typed_word(document.text(), offset);
    let (ranked, cut) = completion::rank(candidates, typed, limit);
    // Every item replaces the typed word through a text edit: clients that filter
    // by what the item inserts (Emacs's eglot) match the label, which is what the
    // user types, while the edit inserts what the file needs (a GLOC index).
    let typed_range = Range {
        start: position_of(document.rope(), start),
        end: position_of(document.rope(), offset),
    };
    let items = ranked
        .into_iter()
        .enumerate()
        .map(|(rank, completion)| {
            let mut item = completion_item(completion, client, typed_range);
            // The client sorts by `sort_text`: keep the server's order.
            item.sort_text = Some(format!("{rank:05}"));
            if client.resolve_documentation && item.documentation.is_some() {
                item.documentation = None;
                item.data = Some(serde_json::json!({
                    "uri": document.uri.as_str(),
                    "line": position.line,
                    "character": position.character,
                }));
            }
            item
        })
        .collect();
    Some(CompletionResponse::List(CompletionList {
        is_incomplete: cut,
        items,
    }))
}

/// One item: the label and filter text are what the user types; what goes into
/// the file (a snippet for a client that declared snippets, else plain text) is
/// the new text of an edit over `typed_range`, never `insertText`.
fn completion_item(
    completion: gloc_ide::analysis::Completion,
    client: ClientFeatures,
    typed_range: Range,
) -> CompletionItem {
    let snippet = matches!(completion.insert, Some(Insert::Snippet(_))) && client.snippets;
    let new_text = match &completion.insert {
        Some(Insert::Snippet(snippet)) if client.snippets => snippet.clone(),
        Some(Insert::Snippet(snippet)) => snippet_text(snippet),
        Some(Insert::Text(text)) => text.clone(),
        None => completion.label.clone(),
    };
    CompletionItem {
        label: completion.label,
        kind: Some(match completion.kind {
            CompletionKind::Sensor => CompletionItemKind::FIELD,
            CompletionKind::Keyword => CompletionItemKind::KEYWORD,
            CompletionKind::Instruction => CompletionItemKind::OPERATOR,
            CompletionKind::Variable => CompletionItemKind::VARIABLE,
            CompletionKind::Constant => CompletionItemKind::CONSTANT,
            CompletionKind::Label => CompletionItemKind::REFERENCE,
            CompletionKind::Function => CompletionItemKind::FUNCTION,
            CompletionKind::Register => CompletionItemKind::VARIABLE,
        }),
        detail: completion.detail,
        documentation: completion
            .documentation
            .map(|text| Documentation::MarkupContent(markup(text, client.completion_markdown))),
        insert_text_format: snippet.then_some(InsertTextFormat::SNIPPET),
        text_edit: Some(CompletionTextEdit::Edit(TextEdit {
            range: typed_range,
            new_text,
        })),
        filter_text: completion.filter_text,
        sort_text: completion.sort_text,
        ..CompletionItem::default()
    }
}

/// Where a resolved completion item was offered (its `data`).
pub fn resolve_origin(item: &CompletionItem) -> Option<(Uri, Position)> {
    let data = item.data.as_ref()?;
    let uri = data.get("uri")?.as_str()?.parse().ok()?;
    let line = u32::try_from(data.get("line")?.as_u64()?).ok()?;
    let character = u32::try_from(data.get("character")?.as_u64()?).ok()?;
    Some((uri, Position { line, character }))
}

/// Every completion of the document at byte `offset`, unranked.
fn candidates_at(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    offset: usize,
) -> Vec<gloc_ide::analysis::Completion> {
    completion::completions(
        document.language,
        document.text(),
        offset,
        analysis,
        context,
    )
}

/// Fills the documentation of an item offered at `position`: the candidate of
/// the same label there now (the item is returned as it came when the text
/// changed so that it is no longer offered).
pub fn completion_resolve(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    position: Position,
    client: ClientFeatures,
    mut item: CompletionItem,
) -> CompletionItem {
    let offset = offset_of(document.rope(), position);
    let found = candidates_at(document, analysis, context, offset)
        .into_iter()
        .find(|candidate| candidate.label == item.label);
    if let Some(documentation) = found.and_then(|candidate| candidate.documentation) {
        item.documentation = Some(Documentation::MarkupContent(markup(
            documentation,
            client.completion_markdown,
        )));
    }
    item
}

pub fn hover(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    position: Position,
    client: ClientFeatures,
) -> Option<Hover> {
    let offset = offset_of(document.rope(), position);
    let answer = gloc_ide::hover::hover(
        document.language,
        document.text(),
        analysis,
        context,
        offset,
    )?;
    Some(Hover {
        contents: HoverContents::Markup(markup(answer.markdown, client.hover_markdown)),
        range: Some(range_of(document.rope(), answer.span)),
    })
}

pub fn signature_help(document: &Document, position: Position) -> Option<SignatureHelp> {
    let offset = offset_of(document.rope(), position);
    let signature =
        gloc_ide::signature::signature_help(document.language, document.text(), offset)?;
    let utf16 = |byte: usize| {
        signature.label[..byte.min(signature.label.len())]
            .encode_utf16()
            .count() as u32
    };
    Some(SignatureHelp {
        signatures: vec![SignatureInformation {
            label: signature.label.clone(),
            documentation: Some(Documentation::MarkupContent(MarkupContent {
                kind: MarkupKind::Markdown,
                value: signature.documentation.clone(),
            })),
            parameters: Some(
                signature
                    .parameters
                    .iter()
                    .map(|(start, end)| ParameterInformation {
                        label: ParameterLabel::LabelOffsets([utf16(*start), utf16(*end)]),
                        documentation: None,
                    })
                    .collect(),
            ),
            active_parameter: Some(signature.active_parameter as u32),
        }],
        active_signature: Some(0),
        active_parameter: Some(signature.active_parameter as u32),
    })
}

pub fn definition(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    position: Position,
) -> Option<GotoDefinitionResponse> {
    let offset = offset_of(document.rope(), position);
    if document.language == gloc_ide::Language::Mission {
        // `args_from_file(enum) N` goes to the `.ma` file it loads.
        let target =
            gloc_ide::mission::definition(document.text(), offset, &document.path()?, context)?;
        return Some(GotoDefinitionResponse::Scalar(Location {
            uri: Uri::from_file_path(&target)?,
            range: Range::default(),
        }));
    }
    let definition = gloc_ide::references::definition(analysis, offset)?;
    Some(GotoDefinitionResponse::Scalar(Location {
        uri: document.uri.clone(),
        range: range_of(document.rope(), definition),
    }))
}

pub fn references(
    document: &Document,
    analysis: &Analysis,
    position: Position,
    include_declaration: bool,
) -> Option<Vec<Location>> {
    let offset = offset_of(document.rope(), position);
    let spans = gloc_ide::references::references(analysis, offset, include_declaration)?;
    Some(
        spans
            .into_iter()
            .map(|span| Location {
                uri: document.uri.clone(),
                range: range_of(document.rope(), span),
            })
            .collect(),
    )
}

pub fn highlights(
    document: &Document,
    analysis: &Analysis,
    position: Position,
) -> Option<Vec<DocumentHighlight>> {
    let offset = offset_of(document.rope(), position);
    let highlights = gloc_ide::references::highlights(analysis, offset)?;
    Some(
        highlights
            .into_iter()
            .map(|(span, kind)| DocumentHighlight {
                range: range_of(document.rope(), span),
                kind: Some(match kind {
                    HighlightKind::Write => DocumentHighlightKind::WRITE,
                    HighlightKind::Read => DocumentHighlightKind::READ,
                }),
            })
            .collect(),
    )
}

pub fn prepare_rename(
    document: &Document,
    analysis: &Analysis,
    position: Position,
) -> Option<PrepareRenameResponse> {
    let offset = offset_of(document.rope(), position);
    let (span, placeholder) = gloc_ide::rename::prepare_rename(document.text(), analysis, offset)?;
    Some(PrepareRenameResponse::RangeWithPlaceholder {
        range: range_of(document.rope(), span),
        placeholder,
    })
}

/// The edit renaming the symbol under the cursor, `Ok(None)` when there is no
/// symbol there, or why the new name is not allowed.
pub fn rename(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    position: Position,
    new_name: &str,
) -> Result<Option<WorkspaceEdit>, String> {
    let offset = offset_of(document.rope(), position);
    let Some(edits) = gloc_ide::rename::rename(
        document.language,
        document.text(),
        analysis,
        context,
        offset,
        new_name,
    )?
    else {
        return Ok(None);
    };
    let edits = edits
        .into_iter()
        .map(|edit| text_edit(document.rope(), edit))
        .collect();
    Ok(Some(WorkspaceEdit {
        changes: Some(HashMap::from([(document.uri.clone(), edits)])),
        ..WorkspaceEdit::default()
    }))
}

/// The document's symbols: nested `DocumentSymbol`s when the client supports them,
/// else the flat `SymbolInformation` list of the protocol's first form.
#[allow(deprecated)] // `DocumentSymbol::deprecated` must still be written out.
pub fn document_symbols(
    document: &Document,
    analysis: &Analysis,
    client: ClientFeatures,
) -> DocumentSymbolResponse {
    let rope = document.rope();
    let symbols = gloc_ide::symbols::document_symbols(analysis)
        .into_iter()
        .map(|symbol| DocumentSymbol {
            name: symbol.name,
            detail: symbol.detail,
            kind: symbol_kind(symbol.kind),
            tags: None,
            deprecated: None,
            range: range_of(rope, symbol.extent),
            selection_range: range_of(rope, symbol.selection),
            children: None,
        })
        .collect::<Vec<DocumentSymbol>>();
    if client.hierarchical_symbols {
        return DocumentSymbolResponse::Nested(symbols);
    }
    DocumentSymbolResponse::Flat(
        symbols
            .into_iter()
            .map(|symbol| SymbolInformation {
                name: symbol.name,
                kind: symbol.kind,
                tags: None,
                deprecated: None,
                location: Location {
                    uri: document.uri.clone(),
                    range: symbol.selection_range,
                },
                container_name: None,
            })
            .collect(),
    )
}

pub fn folding_ranges(document: &Document, analysis: &Analysis) -> Vec<FoldingRange> {
    let rope = document.rope();
    gloc_ide::folding::folding_ranges(document.text(), analysis)
        .into_iter()
        .map(|span| FoldingRange {
            start_line: position_of(rope, span.start as usize).line,
            start_character: None,
            end_line: position_of(rope, span.end as usize).line,
            end_character: None,
            kind: Some(FoldingRangeKind::Region),
            collapsed_text: None,
        })
        .collect()
}

pub fn semantic_tokens(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
) -> SemanticTokens {
    semantic_tokens_of(
        document,
        gloc_ide::tokens::semantic_tokens(analysis, context),
    )
}

/// The tokens that start within `range` (`semanticTokens/range`).
pub fn semantic_tokens_range(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    range: Range,
) -> SemanticTokens {
    let wanted = span_of(document.rope(), range);
    semantic_tokens_of(
        document,
        gloc_ide::tokens::semantic_tokens_within(analysis, context, wanted),
    )
}

/// The edit that turns `previous` into `current` (`semanticTokens/full/delta`):
/// one replacement between their common beginning and end, in the protocol's
/// units (integers of the flat array, five per token). None when equal.
pub fn semantic_tokens_edits(
    previous: &[SemanticToken],
    current: &[SemanticToken],
) -> Vec<SemanticTokensEdit> {
    let (prefix, suffix) = gloc_ide::format::common_ends(previous, current);
    let deleted = previous.len() - prefix - suffix;
    let inserted = &current[prefix..current.len() - suffix];
    if deleted == 0 && inserted.is_empty() {
        return Vec::new();
    }
    vec![SemanticTokensEdit {
        start: (prefix * 5) as u32,
        delete_count: (deleted * 5) as u32,
        data: Some(inserted.to_vec()),
    }]
}

fn semantic_tokens_of(
    document: &Document,
    tokens: impl Iterator<Item = gloc_ide::tokens::HighlightedToken>,
) -> SemanticTokens {
    // The tokens are sorted by start and do not overlap: one walk over the text.
    let mut walker = PositionWalker::new(document.rope(), document.text());
    let mut data = Vec::with_capacity(tokens.size_hint().0);
    let (mut previous_line, mut previous_start) = (0u32, 0u32);
    for token in tokens {
        let start = walker.position(token.span.start as usize);
        let end = walker.position(token.span.end as usize);
        // Our tokens never span lines; a client cannot show one that does.
        if end.line != start.line || end.character <= start.character {
            continue;
        }
        let delta_line = start.line - previous_line;
        let delta_start = if delta_line == 0 {
            start.character - previous_start
        } else {
            start.character
        };
        data.push(SemanticToken {
            delta_line,
            delta_start,
            length: end.character - start.character,
            token_type: token.token_type as u32,
            token_modifiers_bitset: token.modifiers,
        });
        previous_line = start.line;
        previous_start = start.character;
    }
    SemanticTokens {
        result_id: None,
        data,
    }
}

pub fn inlay_hints(document: &Document, analysis: &Analysis, range: Range) -> Vec<InlayHint> {
    let rope = document.rope();
    let first = offset_of(rope, range.start);
    let last = offset_of(rope, range.end);
    gloc_ide::hints::inlay_hints(analysis, first, last)
        .into_iter()
        .map(|hint| InlayHint {
            position: position_of(rope, hint.offset),
            label: InlayHintLabel::String(hint.label),
            kind: None,
            text_edits: None,
            tooltip: hint.tooltip.map(InlayHintTooltip::String),
            padding_left: Some(hint.padding_left),
            padding_right: None,
            data: None,
        })
        .collect()
}

/// Quick fixes carried by the diagnostics that touch `range`.
pub fn code_actions(
    document: &Document,
    analysis: &Analysis,
    range: Range,
    client: ClientFeatures,
) -> CodeActionResponse {
    let rope = document.rope();
    let wanted = span_of(rope, range);
    let converted = diagnostics(document, analysis, client);
    gloc_ide::actions::quick_fixes(analysis, wanted)
        .into_iter()
        .map(|fix| {
            CodeActionOrCommand::CodeAction(CodeAction {
                title: fix.title,
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: converted
                    .get(fix.diagnostic)
                    .cloned()
                    .map(|diagnostic| vec![diagnostic]),
                edit: Some(WorkspaceEdit {
                    changes: Some(HashMap::from([(
                        document.uri.clone(),
                        vec![text_edit(rope, fix.edit)],
                    )])),
                    ..WorkspaceEdit::default()
                }),
                is_preferred: Some(fix.preferred),
                ..CodeAction::default()
            })
        })
        .collect()
}

fn text_edit(rope: &Rope, edit: gloc_ide::analysis::TextEdit) -> TextEdit {
    TextEdit {
        range: range_of(rope, edit.span),
        new_text: edit.new_text,
    }
}

/// The edit that formats the document: only the changed lines are replaced,
/// so the cursor stays where it is elsewhere.
pub fn formatting(document: &Document) -> Option<Vec<TextEdit>> {
    let edits = gloc_ide::format::formatting(document.language, document.text())?;
    Some(
        edits
            .into_iter()
            .map(|edit| text_edit(document.rope(), edit))
            .collect(),
    )
}

/// Formats the lines `range` touches (`gloc_ide::format::range_formatting`).
pub fn range_formatting(document: &Document, range: Range) -> Option<Vec<TextEdit>> {
    let edits = gloc_ide::format::range_formatting(
        document.language,
        document.text(),
        range.start.line as usize,
        range.end.line as usize,
    )?;
    Some(
        edits
            .into_iter()
            .map(|edit| text_edit(document.rope(), edit))
            .collect(),
    )
}

/// Pull diagnostics: the same list push would publish, as a full report.
pub fn diagnostic_report(items: Vec<Diagnostic>) -> DocumentDiagnosticReportResult {
    DocumentDiagnosticReportResult::Report(DocumentDiagnosticReport::Full(
        RelatedFullDocumentDiagnosticReport {
            related_documents: None,
            full_document_diagnostic_report: FullDocumentDiagnosticReport {
                result_id: None,
                items,
            },
        },
    ))
}

/// Code lenses: at each label, its cycle figure (`lens::label_cycles`); on the
/// first line, "Run" and "Debug" when the client runs those commands.
pub fn code_lenses(
    document: &Document,
    analysis: &Analysis,
    client: ClientFeatures,
) -> Vec<CodeLens> {
    let rope = document.rope();
    let mut lenses = Vec::new();
    let top = Range::default();
    let argument = Value::String(document.uri.as_str().to_string());
    // Scripts run and debug; mission files are flown with a script, not on their own.
    let script = matches!(
        document.language,
        gloc_ide::Language::Gloc | gloc_ide::Language::Gbasic
    );
    for (wanted, title, command) in [
        (client.run_command, "▶ Run in simulator", RUN_COMMAND),
        (client.debug_command, "Debug", DEBUG_COMMAND),
    ] {
        if wanted && script {
            lenses.push(CodeLens {
                range: top,
                command: Some(Command {
                    title: title.to_string(),
                    command: command.to_string(),
                    arguments: Some(vec![argument.clone()]),
                }),
                data: None,
            });
        }
    }
    for figure in lens::label_cycles(analysis) {
        lenses.push(CodeLens {
            range: range_of(rope, figure.definition),
            // No command: the lens is a figure to read, not a button.
            command: Some(Command {
                title: figure.title(),
                command: String::new(),
                arguments: None,
            }),
            data: None,
        });
    }
    lenses
}

/// Selection ranges at each position, innermost first, as linked parents.
pub fn selection_ranges(
    document: &Document,
    analysis: &Analysis,
    positions: &[Position],
) -> Vec<SelectionRange> {
    let rope = document.rope();
    positions
        .iter()
        .map(|position| {
            let offset = offset_of(rope, *position);
            let spans = selection::selection_ranges(document.text(), analysis, offset);
            let mut range: Option<SelectionRange> = None;
            for span in spans.iter().rev() {
                range = Some(SelectionRange {
                    range: range_of(rope, *span),
                    parent: range.map(Box::new),
                });
            }
            range.unwrap_or(SelectionRange {
                range: Range {
                    start: *position,
                    end: *position,
                },
                parent: None,
            })
        })
        .collect()
}

/// Document links: the paths of a `gloc.toml`, a mission's `args_from_file` targets.
pub fn document_links(document: &Document, context: &Context) -> Vec<DocumentLink> {
    let Some(path) = document.path() else {
        return Vec::new();
    };
    let links = match document.language {
        gloc_ide::Language::Config => {
            let folder = path.parent().unwrap_or(std::path::Path::new("."));
            links::config_links(document.text(), folder)
        }
        gloc_ide::Language::Mission => links::mission_links(document.text(), &path, context),
        _ => return Vec::new(),
    };
    let rope = document.rope();
    links
        .into_iter()
        .filter_map(|link| {
            Some(DocumentLink {
                range: range_of(rope, link.span),
                target: Some(Uri::from_file_path(&link.target)?),
                tooltip: Some(format!("{}: {}", link.key, link.target.display())),
                data: None,
            })
        })
        .collect()
}

/// A workspace symbol found in a document's analysis.
#[allow(deprecated)] // `SymbolInformation::deprecated` must still be written out.
pub fn workspace_symbols(rope: &Rope, uri: &Uri, analysis: &Analysis) -> Vec<SymbolInformation> {
    gloc_ide::workspace::listed(analysis)
        .filter_map(|symbol| {
            Some(SymbolInformation {
                name: symbol.name.clone(),
                kind: symbol_kind(symbol.kind),
                tags: None,
                deprecated: None,
                location: Location {
                    uri: uri.clone(),
                    range: range_of(rope, symbol.occurrences.definition?),
                },
                container_name: None,
            })
        })
        .collect()
}

fn symbol_kind(kind: Kind) -> SymbolKind {
    match kind {
        Kind::Label => SymbolKind::FUNCTION,
        Kind::Variable => SymbolKind::VARIABLE,
        Kind::Array => SymbolKind::ARRAY,
        Kind::Constant => SymbolKind::CONSTANT,
        Kind::Sensor => SymbolKind::FIELD,
        Kind::Behavior => SymbolKind::OBJECT,
    }
}

/// The answer to `gloc.compiledGloc`: the GLOC text (a GLOC document is its
/// own GLOC), or an error saying why there is none (the program has errors).
pub fn compiled_gloc(document: &Document, analysis: &Analysis) -> jsonrpc::Result<Value> {
    gloc_ide::actions::compiled_gloc(document.language, document.text(), analysis)
        .map(Value::String)
        .map_err(jsonrpc::Error::invalid_params)
}

#[cfg(test)]
mod tests {
    use std::path::Path;
    use std::sync::Arc;

    use gloc_engine::sensors::SensorList;

    use super::*;
    use crate::document::Language;

    /// The tokens' absolute places (line, start, length, type, modifiers) found with two
    /// rope look-ups per token through `position_of`, for comparison with the one-pass walk.
    fn reference_tokens(
        document: &Document,
        analysis: &Analysis,
        context: &Context,
    ) -> Vec<[u32; 5]> {
        let rope = document.rope();
        gloc_ide::tokens::semantic_tokens(analysis, context)
            .filter_map(|token| {
                let start = position_of(rope, token.span.start as usize);
                let end = position_of(rope, token.span.end as usize);
                (end.line == start.line && end.character > start.character).then_some([
                    start.line,
                    start.character,
                    end.character - start.character,
                    token.token_type as u32,
                    token.modifiers,
                ])
            })
            .collect()
    }

    /// The LSP's relative encoding decoded back to absolute places.
    fn absolute(tokens: &SemanticTokens) -> Vec<[u32; 5]> {
        let (mut line, mut start) = (0u32, 0u32);
        tokens
            .data
            .iter()
            .map(|token| {
                line += token.delta_line;
                start = if token.delta_line == 0 {
                    start + token.delta_start
                } else {
                    token.delta_start
                };
                [
                    line,
                    start,
                    token.length,
                    token.token_type,
                    token.token_modifiers_bitset,
                ]
            })
            .collect()
    }

    #[test]
    fn plain_text_drops_emphasis_but_keeps_multiplication() {
        let plain = markup(
            "```gloc\nmul r,r,r\n```\n`dst := a * b`\n\n*from the paper (Fig. 2)*, **bold** and *x*."
                .to_string(),
            false,
        );
        assert_eq!(plain.kind, MarkupKind::PlainText);
        assert_eq!(
            plain.value,
            "mul r,r,r\ndst := a * b\n\nfrom the paper (Fig. 2), bold and x."
        );
    }

    #[test]
    fn one_pass_tokens_equal_per_token_look_ups_on_every_fixture() {
        let context = Context::new(Arc::new(SensorList::embedded()));
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let folders = [
            "examples",
            "dap/tests/fixtures",
            "tests/fixtures/gbasic/ok",
            "tests/fixtures/gbasic/err",
            "tests/fixtures/gbasic/run",
            "tests/fixtures/gloc/ok",
            "tests/fixtures/gloc/err",
            "tests/perf/programs",
        ];
        let mut texts = Vec::new();
        for folder in folders {
            let Ok(entries) = std::fs::read_dir(root.join(folder)) else {
                panic!("no fixture folder {folder}");
            };
            for entry in entries.flatten() {
                let path = entry.path();
                let language = match path.extension().and_then(|e| e.to_str()) {
                    Some("gbas") => Language::Gbasic,
                    Some("gloc") => Language::Gloc,
                    _ => continue,
                };
                let text = std::fs::read_to_string(&path).expect("a fixture");
                // Each as written, with CRLF line ends, and with non-ASCII text in its
                // comments and strings.
                let crlf = text.replace('\n', "\r\n");
                let wide = text.replace("' ", "' é𝄞 ").replace("# ", "# ☃𝄞 ");
                texts.push((path.display().to_string(), language, text));
                texts.push((format!("{} (CRLF)", path.display()), language, crlf));
                texts.push((format!("{} (wide)", path.display()), language, wide));
            }
        }
        assert!(texts.len() > 150, "{} fixtures", texts.len());
        let mut tokens_seen = 0;
        for (name, language, text) in texts {
            let uri = "file:///fixture".parse().expect("uri");
            let document = Document::new(uri, language, 1, &text);
            let analysis = gloc_ide::lang::analyze(language, &text, &context);
            let tokens = semantic_tokens(&document, &analysis, &context);
            let expected = reference_tokens(&document, &analysis, &context);
            assert_eq!(absolute(&tokens), expected, "{name}");
            tokens_seen += tokens.data.len();
        }
        assert!(tokens_seen > 5_000, "{tokens_seen} tokens");
    }
}
