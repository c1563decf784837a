//! LSP features over the language-neutral [`Analysis`]: each function takes a
//! document and its analysis and returns protocol types. Positions go through
//! `position` only.

use std::collections::HashMap;

use gloc_engine::{Severity, Span};
use ropey::Rope;
use serde_json::Value;
use tower_lsp_server::jsonrpc;
use tower_lsp_server::ls_types::*;

use crate::document::{Document, Language};
use crate::position::{end_position, offset_of, position_of, range_of, span_of, PositionWalker};
use crate::server::COMPILED_GLOC_COMMAND;
use gloc_ide::analysis::{Analysis, CompletionKind, Context, SymbolKind as Kind, TokenKind};
use gloc_ide::{completion, lang, lens, links, selection};

/// What the client said it can show (`initialize`'s capabilities); answers follow it.
/// Before `initialize`, and for a client that says nothing, the protocol's defaults:
/// no snippets, flat symbols; markdown unless the client lists formats without it.
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
            formats.is_none_or(|formats| formats.contains(&MarkupKind::Markdown))
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
/// marks, emphasis and code fences.
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
        .map(|line| line.replace("**", "").replace('`', ""))
        .collect();
    MarkupContent {
        kind: MarkupKind::PlainText,
        value: plain.join("\n"),
    }
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

/// Semantic token types, in legend order.
const TOKEN_TYPES: [SemanticTokenType; 10] = [
    SemanticTokenType::KEYWORD,
    SemanticTokenType::MACRO,
    SemanticTokenType::FUNCTION,
    SemanticTokenType::VARIABLE,
    SemanticTokenType::NUMBER,
    SemanticTokenType::STRING,
    SemanticTokenType::COMMENT,
    SemanticTokenType::OPERATOR,
    SemanticTokenType::PROPERTY,
    SemanticTokenType::new("label"),
];
/// Semantic token modifiers, in legend order (bit positions).
const TOKEN_MODIFIERS: [SemanticTokenModifier; 4] = [
    SemanticTokenModifier::READONLY,
    SemanticTokenModifier::MODIFICATION,
    SemanticTokenModifier::DEFAULT_LIBRARY,
    SemanticTokenModifier::new("register"),
];

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
                    token_types: TOKEN_TYPES.to_vec(),
                    token_modifiers: TOKEN_MODIFIERS.to_vec(),
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

pub fn diagnostics(document: &Document, analysis: &Analysis) -> Vec<Diagnostic> {
    diagnostics_for(document.rope(), &document.uri, &analysis.diagnostics)
}

/// Converts core diagnostics; labels become related information in the same file.
pub fn diagnostics_for(
    rope: &Rope,
    uri: &Uri,
    diagnostics: &[gloc_engine::Diagnostic],
) -> Vec<Diagnostic> {
    diagnostics
        .iter()
        .map(|diagnostic| {
            let mut message = diagnostic.message.clone();
            if let Some(help) = &diagnostic.help {
                message.push_str("\nhelp: ");
                message.push_str(help);
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
                related_information: (!related.is_empty()).then_some(related),
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
    let candidates = lang::completions(
        document.language,
        document.text(),
        offset,
        analysis,
        context,
    );
    let (_, typed) = completion::typed_word(document.text(), offset);
    let (ranked, cut) = completion::rank(candidates, typed, limit);
    let items = ranked
        .into_iter()
        .enumerate()
        .map(|(rank, completion)| {
            let mut item = completion_item(completion, client);
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

fn completion_item(
    completion: gloc_ide::analysis::Completion,
    client: ClientFeatures,
) -> CompletionItem {
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
        insert_text_format: completion
            .snippet
            .as_ref()
            .filter(|_| client.snippets)
            .map(|_| InsertTextFormat::SNIPPET),
        insert_text: match completion.snippet {
            Some(snippet) if client.snippets => Some(snippet),
            Some(snippet) => Some(snippet_text(&snippet)),
            None => completion.insert_text,
        },
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
    let found = lang::completions(
        document.language,
        document.text(),
        offset,
        analysis,
        context,
    )
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
    let token = analysis.token_at(offset)?;
    let word = document.text().get(token.span.range()).unwrap_or_default();
    let markdown = match token.kind {
        TokenKind::SensorRead | TokenKind::SensorWrite => {
            let id = token.sensor?;
            lang::sensor_markdown(&context.sensors, id)
        }
        TokenKind::Label | TokenKind::Variable | TokenKind::Constant => {
            let (symbol, _) = analysis.symbol_at(offset)?;
            let what = match symbol.kind {
                Kind::Label => "label",
                Kind::Variable => "variable",
                Kind::Array => "array",
                Kind::Constant => "constant",
                Kind::Sensor => "sensor",
            };
            let uses = symbol.references.len();
            let mut text = format!("{what} `{}`", symbol.name);
            if !symbol.detail.is_empty() {
                text.push_str(&format!(": {}", symbol.detail));
            }
            text.push_str(&format!(
                "\n\n{uses} use{}",
                if uses == 1 { "" } else { "s" }
            ));
            if symbol.definition.is_none() {
                text.push_str("; never defined");
            }
            text
        }
        _ => lang::word_markdown(document.language, word, token.kind)?,
    };
    Some(Hover {
        contents: HoverContents::Markup(markup(markdown, client.hover_markdown)),
        range: Some(range_of(document.rope(), token.span)),
    })
}

pub fn signature_help(document: &Document, position: Position) -> Option<SignatureHelp> {
    let offset = offset_of(document.rope(), position);
    let signature = lang::signature(document.language, document.text(), offset)?;
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
    position: Position,
) -> Option<GotoDefinitionResponse> {
    let offset = offset_of(document.rope(), position);
    let (symbol, _) = analysis.symbol_at(offset)?;
    let definition = symbol.definition?;
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
    let (symbol, _) = analysis.symbol_at(offset)?;
    let spans: Vec<Span> = if include_declaration {
        symbol.occurrences().collect()
    } else {
        symbol.references.clone()
    };
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
    let (symbol, _) = analysis.symbol_at(offset)?;
    let mut highlights: Vec<DocumentHighlight> = symbol
        .definition
        .iter()
        .map(|span| DocumentHighlight {
            range: range_of(document.rope(), *span),
            kind: Some(DocumentHighlightKind::WRITE),
        })
        .collect();
    highlights.extend(symbol.references.iter().map(|span| DocumentHighlight {
        range: range_of(document.rope(), *span),
        kind: Some(DocumentHighlightKind::READ),
    }));
    Some(highlights)
}

pub fn prepare_rename(
    document: &Document,
    analysis: &Analysis,
    position: Position,
) -> Option<PrepareRenameResponse> {
    let offset = offset_of(document.rope(), position);
    let (symbol, span) = analysis.symbol_at(offset)?;
    if !symbol.renamable {
        return None;
    }
    Some(PrepareRenameResponse::RangeWithPlaceholder {
        range: range_of(document.rope(), span),
        placeholder: document
            .text()
            .get(span.range())
            .unwrap_or_default()
            .to_string(),
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
    let Some((symbol, _)) = analysis.symbol_at(offset) else {
        return Ok(None);
    };
    if !symbol.renamable {
        return Err(format!("`{}` cannot be renamed", symbol.name));
    }
    let new_name = new_name.trim();
    lang::check_new_name(
        document.language,
        symbol,
        new_name,
        analysis,
        context,
        document.text(),
    )?;
    let edits = symbol
        .occurrences()
        .map(|span| TextEdit {
            range: range_of(document.rope(), span),
            new_text: new_name.to_string(),
        })
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
    let symbols = analysis
        .symbols
        .iter()
        .filter_map(|symbol| {
            let definition = symbol.definition?;
            let extent = symbol.extent.cover(definition);
            Some(DocumentSymbol {
                name: symbol.name.clone(),
                detail: (!symbol.detail.is_empty()).then(|| symbol.detail.clone()),
                kind: symbol_kind(symbol.kind),
                tags: None,
                deprecated: None,
                range: range_of(rope, extent),
                selection_range: range_of(rope, definition),
                children: None,
            })
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
    analysis
        .folds
        .iter()
        .filter_map(|span| {
            let start = position_of(rope, span.start as usize);
            let end = position_of(rope, span.end as usize);
            (end.line > start.line).then_some(FoldingRange {
                start_line: start.line,
                start_character: None,
                end_line: end.line,
                end_character: None,
                kind: Some(FoldingRangeKind::Region),
                collapsed_text: None,
            })
        })
        .collect()
}

pub fn semantic_tokens(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
) -> SemanticTokens {
    semantic_tokens_of(document, &analysis.tokens, context)
}

/// The tokens that start within `range` (`semanticTokens/range`).
pub fn semantic_tokens_range(
    document: &Document,
    analysis: &Analysis,
    context: &Context,
    range: Range,
) -> SemanticTokens {
    let wanted = span_of(document.rope(), range);
    let tokens = &analysis.tokens;
    let first = tokens.partition_point(|token| token.span.start < wanted.start);
    let last = tokens.partition_point(|token| token.span.start < wanted.end);
    semantic_tokens_of(document, &tokens[first..last.max(first)], context)
}

/// The edit that turns `previous` into `current` (`semanticTokens/full/delta`):
/// one replacement between their common beginning and end, in the protocol's
/// units (integers of the flat array, five per token). None when equal.
pub fn semantic_tokens_edits(
    previous: &[SemanticToken],
    current: &[SemanticToken],
) -> Vec<SemanticTokensEdit> {
    let prefix = previous
        .iter()
        .zip(current)
        .take_while(|(old, new)| old == new)
        .count();
    let suffix = previous[prefix..]
        .iter()
        .rev()
        .zip(current[prefix..].iter().rev())
        .take_while(|(old, new)| old == new)
        .count();
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
    tokens: &[gloc_ide::analysis::Token],
    context: &Context,
) -> SemanticTokens {
    // The tokens are sorted by start and do not overlap: one walk over the text.
    let mut walker = PositionWalker::new(document.rope(), document.text());
    let mut data = Vec::with_capacity(tokens.len());
    let (mut previous_line, mut previous_start) = (0u32, 0u32);
    for token in tokens {
        let start = walker.position(token.span.start as usize);
        let end = walker.position(token.span.end as usize);
        // Our tokens never span lines; a client cannot show one that does.
        if end.line != start.line || end.character <= start.character {
            continue;
        }
        let read_only = token
            .sensor
            .and_then(|id| context.sensors.get(id))
            .map(|sensor| sensor.access() == gloc_engine::sensors::Access::ReadOnly);
        let (token_type, modifiers) = token_style(token.kind, read_only);
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
            token_type,
            token_modifiers_bitset: modifiers,
        });
        previous_line = start.line;
        previous_start = start.character;
    }
    SemanticTokens {
        result_id: None,
        data,
    }
}

/// (index into `TOKEN_TYPES`, modifier bits).
fn token_style(kind: TokenKind, read_only_sensor: Option<bool>) -> (u32, u32) {
    const READONLY: u32 = 1;
    const MODIFICATION: u32 = 2;
    const DEFAULT_LIBRARY: u32 = 4;
    const REGISTER: u32 = 8;
    let read_only = if read_only_sensor == Some(true) {
        READONLY
    } else {
        0
    };
    match kind {
        TokenKind::Keyword => (0, 0),
        TokenKind::Directive => (1, 0),
        TokenKind::Function => (2, DEFAULT_LIBRARY),
        TokenKind::Variable => (3, 0),
        TokenKind::Constant => (3, READONLY),
        TokenKind::Register => (3, REGISTER),
        TokenKind::Number => (4, 0),
        TokenKind::String => (5, 0),
        TokenKind::Comment => (6, 0),
        TokenKind::Operator => (7, 0),
        TokenKind::SensorRead => (8, DEFAULT_LIBRARY | read_only),
        TokenKind::SensorWrite => (8, DEFAULT_LIBRARY | MODIFICATION),
        TokenKind::Label => (9, 0),
    }
}

pub fn inlay_hints(document: &Document, analysis: &Analysis, range: Range) -> Vec<InlayHint> {
    let rope = document.rope();
    let first = offset_of(rope, range.start);
    let last = offset_of(rope, range.end);
    analysis
        .hints
        .iter()
        .filter(|hint| hint.offset >= first && hint.offset <= last)
        .map(|hint| InlayHint {
            position: position_of(rope, hint.offset),
            label: InlayHintLabel::String(hint.label.clone()),
            kind: None,
            text_edits: None,
            tooltip: hint.tooltip.clone().map(InlayHintTooltip::String),
            padding_left: Some(hint.padding_left),
            padding_right: None,
            data: None,
        })
        .collect()
}

/// Quick fixes carried by the diagnostics that touch `range`.
pub fn code_actions(document: &Document, analysis: &Analysis, range: Range) -> CodeActionResponse {
    let rope = document.rope();
    let wanted = span_of(rope, range);
    let converted = diagnostics(document, analysis);
    let mut actions = Vec::new();
    for (diagnostic, lsp_diagnostic) in analysis.diagnostics.iter().zip(converted) {
        let touches = diagnostic.span.start <= wanted.end && wanted.start <= diagnostic.span.end;
        if !touches {
            continue;
        }
        for fix in &diagnostic.fixes {
            let edit = TextEdit {
                range: range_of(rope, fix.span),
                new_text: fix.replacement.clone(),
            };
            actions.push(CodeActionOrCommand::CodeAction(CodeAction {
                title: fix.title.clone(),
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![lsp_diagnostic.clone()]),
                edit: Some(WorkspaceEdit {
                    changes: Some(HashMap::from([(document.uri.clone(), vec![edit])])),
                    ..WorkspaceEdit::default()
                }),
                is_preferred: Some(diagnostic.fixes.len() == 1),
                ..CodeAction::default()
            }));
        }
    }
    actions
}

/// The edit that formats the document: only the changed lines are replaced,
/// so the cursor stays where it is elsewhere.
pub fn formatting(document: &Document) -> Option<Vec<TextEdit>> {
    let text = document.text();
    let formatted = formatted_text(document)?;
    if formatted == text {
        return Some(Vec::new());
    }
    let old_lines: Vec<&str> = text.split_inclusive('\n').collect();
    let new_lines: Vec<&str> = formatted.split_inclusive('\n').collect();
    let common_prefix = old_lines
        .iter()
        .zip(&new_lines)
        .take_while(|(old, new)| old == new)
        .count();
    let common_suffix = old_lines[common_prefix..]
        .iter()
        .rev()
        .zip(new_lines[common_prefix..].iter().rev())
        .take_while(|(old, new)| old == new)
        .count();
    let start: usize = old_lines[..common_prefix]
        .iter()
        .map(|line| line.len())
        .sum();
    let end: usize = text.len()
        - old_lines[old_lines.len() - common_suffix..]
            .iter()
            .map(|line| line.len())
            .sum::<usize>();
    let replacement: String = new_lines[common_prefix..new_lines.len() - common_suffix].concat();
    let rope = document.rope();
    let end_position = if end == text.len() {
        end_position(rope)
    } else {
        position_of(rope, end)
    };
    Some(vec![TextEdit {
        range: Range {
            start: position_of(rope, start),
            end: end_position,
        },
        new_text: replacement,
    }])
}

/// The document's canonical form, with the document's line ends (the formatters
/// write LF; a CRLF document keeps CRLF).
fn formatted_text(document: &Document) -> Option<String> {
    let text = document.text();
    let formatted = lang::format(document.language, text)?;
    Some(if text.contains("\r\n") {
        formatted.replace("\r\n", "\n").replace('\n', "\r\n")
    } else {
        formatted
    })
}

/// Formats the lines `range` touches. The formatters re-indent line by line, so
/// when the line count stays the same each changed line in the range is
/// replaced; when it does not (GLOC's canonical form can join or split lines),
/// the one whole-document change is applied only if it lies within the range.
pub fn range_formatting(document: &Document, range: Range) -> Option<Vec<TextEdit>> {
    let text = document.text();
    let formatted = formatted_text(document)?;
    let old_lines: Vec<&str> = text.split_inclusive('\n').collect();
    let new_lines: Vec<&str> = formatted.split_inclusive('\n').collect();
    let (first, last) = (range.start.line as usize, range.end.line as usize);
    if old_lines.len() != new_lines.len() {
        let edits = formatting(document)?;
        let inside = edits.iter().all(|edit| {
            edit.range.start.line as usize >= first && edit.range.end.line as usize <= last + 1
        });
        return Some(if inside { edits } else { Vec::new() });
    }
    let rope = document.rope();
    let mut start = 0;
    let mut edits = Vec::new();
    for (index, (old, new)) in old_lines.iter().zip(&new_lines).enumerate() {
        if index >= first && index <= last && old != new {
            let content = |line: &str| line.trim_end_matches(['\n', '\r']).len();
            edits.push(TextEdit {
                range: Range {
                    start: position_of(rope, start),
                    end: position_of(rope, start + content(old)),
                },
                new_text: new[..content(new)].to_string(),
            });
        }
        start += old.len();
    }
    Some(edits)
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
    for (wanted, title, command) in [
        (client.run_command, "▶ Run in simulator", RUN_COMMAND),
        (client.debug_command, "Debug", DEBUG_COMMAND),
    ] {
        if wanted {
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

/// Document links: the paths of a `gloc.toml`.
pub fn document_links(document: &Document) -> Vec<DocumentLink> {
    if document.language != Language::Config {
        return Vec::new();
    }
    let Some(path) = document.path() else {
        return Vec::new();
    };
    let folder = path.parent().unwrap_or(std::path::Path::new("."));
    let rope = document.rope();
    links::config_links(document.text(), folder)
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
                    range: range_of(rope, symbol.definition?),
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
    }
}

/// The answer to `gloc.compiledGloc`: the GLOC text (a GLOC document is its
/// own GLOC), or an error saying why there is none (the program has errors).
pub fn compiled_gloc(document: &Document, analysis: &Analysis) -> jsonrpc::Result<Value> {
    match document.language {
        Language::Gbasic => {}
        Language::Gloc => return Ok(Value::String(document.text().to_string())),
        Language::Config => {
            return Err(jsonrpc::Error::invalid_params(
                "`gloc.compiledGloc` takes a GBASIC document, not gloc.toml",
            ))
        }
    }
    match &analysis.compiled {
        Some(gloc) => Ok(Value::String(gloc.clone())),
        None => {
            let errors = analysis
                .diagnostics
                .iter()
                .filter(|diagnostic| diagnostic.is_error())
                .count();
            Err(jsonrpc::Error::invalid_params(format!(
                "the program has {errors} error{}; fix {} to see its GLOC",
                if errors == 1 { "" } else { "s" },
                if errors == 1 { "it" } else { "them" }
            )))
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;
    use std::sync::Arc;

    use gloc_engine::sensors::SensorList;

    use super::*;
    use crate::document::Language;

    /// The tokens as they were computed before the one-pass walk: two rope look-ups
    /// per token through `position_of`, for comparison.
    fn reference_tokens(document: &Document, analysis: &Analysis, context: &Context) -> Vec<u32> {
        let rope = document.rope();
        let mut data = Vec::new();
        let (mut previous_line, mut previous_start) = (0u32, 0u32);
        for token in &analysis.tokens {
            let start = position_of(rope, token.span.start as usize);
            let end = position_of(rope, token.span.end as usize);
            if end.line != start.line || end.character <= start.character {
                continue;
            }
            let read_only = token
                .sensor
                .and_then(|id| context.sensors.get(id))
                .map(|sensor| sensor.access() == gloc_engine::sensors::Access::ReadOnly);
            let (token_type, modifiers) = token_style(token.kind, read_only);
            let delta_line = start.line - previous_line;
            let delta_start = if delta_line == 0 {
                start.character - previous_start
            } else {
                start.character
            };
            data.extend([
                delta_line,
                delta_start,
                end.character - start.character,
                token_type,
                modifiers,
            ]);
            previous_line = start.line;
            previous_start = start.character;
        }
        data
    }

    fn flat(tokens: &SemanticTokens) -> Vec<u32> {
        tokens
            .data
            .iter()
            .flat_map(|token| {
                [
                    token.delta_line,
                    token.delta_start,
                    token.length,
                    token.token_type,
                    token.token_modifiers_bitset,
                ]
            })
            .collect()
    }

    #[test]
    fn one_pass_tokens_equal_per_token_look_ups_on_every_fixture() {
        let context = Context {
            sensors: Arc::new(SensorList::embedded()),
            cycle_budget: None,
            list_folders: Vec::new(),
        };
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
            assert_eq!(flat(&tokens), expected, "{name}");
            tokens_seen += tokens.data.len();
        }
        assert!(tokens_seen > 5_000, "{tokens_seen} tokens");
    }
}
