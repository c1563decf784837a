//! The protocol shell: receives LSP messages, keeps the open documents, asks
//! the language adapters for answers and converts them with `features`.
//!
//! Ordering: the server runs with `concurrency_level(1)` and every handler
//! mutates state before its first `.await`, so a request always sees every
//! edit sent before it. State sits behind a `std` mutex that is never held
//! across an `.await`. Round trips to the client (`workspace/configuration`)
//! run in spawned tasks, never inside a handler.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use gloc_engine::codes::settings::{BAD_EDITOR_SETTING, SENSOR_LIST_UNLOADABLE};
use gloc_engine::sensors::{SensorList, SensorOrder};
use gloc_engine::{Diagnostic, Span};
use gloc_project::config::{Config, ConfigError};
use gloc_project::settings::{config_path_for, read_config, Settings as ProjectSettings, Sourced};
use gloc_project::{Overrides, Surface};
use serde_json::Value;
use tower_lsp_server::jsonrpc::{Error, Result};
use tower_lsp_server::ls_types::*;
use tower_lsp_server::{Client, LanguageServer};

use crate::document::{Document, Language};
use crate::features;
use gloc_ide::analysis::{Analysis, Context};
use gloc_ide::lang;

/// The command that returns the compiled GLOC of a GBASIC document.
pub const COMPILED_GLOC_COMMAND: &str = "gloc.compiledGloc";

pub struct Backend {
    client: Client,
    state: Arc<Mutex<State>>,
    shutdown_requested: Arc<AtomicBool>,
}

/// Overrides from the client (`initializationOptions`, `didChangeConfiguration`
/// or `workspace/configuration`, section `gloc`), as given: the project layer
/// checks them and makes them win over `gloc.toml` (`context_for`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Settings {
    pub masterdata: Option<PathBuf>,
    pub cycle_budget: Option<u64>,
    /// Most items in one completion answer (`completionLimit`; default
    /// `gloc_ide::completion::DEFAULT_LIMIT`).
    pub completion_limit: Option<usize>,
}

struct Open {
    document: Document,
    analysis: Arc<Analysis>,
    /// The document version `analysis` describes.
    analyzed_version: Option<i32>,
    /// The last version whose diagnostics were published.
    published_version: Option<i32>,
    context: Context,
    /// Problems with the project settings, reported on this document.
    context_problems: Vec<Diagnostic>,
}

#[derive(Default)]
struct State {
    documents: HashMap<Uri, Open>,
    settings: Settings,
    /// Loaded sensor lists by path (a failure is kept as its message).
    /// Sensor lists read from files, by path and numbering.
    sensor_lists:
        HashMap<(PathBuf, SensorOrder, String), std::result::Result<Arc<SensorList>, String>>,
    embedded: Option<Arc<SensorList>>,
    client_supports_configuration: bool,
    client_supports_watch_registration: bool,
    /// What the client can show (snippets, markdown, nested symbols).
    client_features: features::ClientFeatures,
    /// `gloc.toml` files that currently have problems (so clearing works).
    config_files_with_problems: Vec<PathBuf>,
    /// The workspace folders (from `initialize`), searched by workspace symbols.
    workspace_roots: Vec<PathBuf>,
    /// Symbols of scripts on disk, by path, with the size and time they were read at.
    disk_symbols: HashMap<PathBuf, DiskSymbols>,
    /// The last semantic tokens sent for each document, for `full/delta`.
    sent_tokens: HashMap<Uri, (String, Vec<SemanticToken>)>,
    next_tokens_id: u64,
}

struct DiskSymbols {
    bytes: u64,
    modified: Option<std::time::SystemTime>,
    symbols: Vec<SymbolInformation>,
}

/// Diagnostics to send once the state lock is released.
struct Publish {
    uri: Uri,
    diagnostics: Vec<tower_lsp_server::ls_types::Diagnostic>,
    version: Option<i32>,
}

impl Backend {
    pub fn new(client: Client, shutdown_requested: Arc<AtomicBool>) -> Backend {
        Backend {
            client,
            state: Arc::new(Mutex::new(State::default())),
            shutdown_requested,
        }
    }
}

fn lock(state: &Mutex<State>) -> MutexGuard<'_, State> {
    // A panic while holding the lock must not take the server down with it.
    state
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

async fn send(client: &Client, publishes: Vec<Publish>) {
    for publish in publishes {
        client
            .publish_diagnostics(publish.uri, publish.diagnostics, publish.version)
            .await;
    }
}

impl State {
    fn embedded(&mut self) -> Arc<SensorList> {
        self.embedded
            .get_or_insert_with(|| Arc::new(SensorList::embedded()))
            .clone()
    }

    /// The `gloc.toml` that applies to a document, preferring the editor's
    /// unsaved text when the file is open.
    fn config_for(&self, path: Option<&Path>) -> std::result::Result<Config, ConfigError> {
        let Some(config_path) = path.and_then(config_path_for) else {
            return Ok(Config::default());
        };
        // The open documents are keyed by URI: found without a scan of them all.
        let open_text = Uri::from_file_path(&config_path)
            .and_then(|uri| self.documents.get(&uri))
            .filter(|open| open.document.language == Language::Config)
            .map(|open| open.document.text().to_string());
        read_config(&config_path, open_text)
    }

    fn sensor_list(
        &mut self,
        masterdata: &Sourced<PathBuf>,
        order: SensorOrder,
    ) -> std::result::Result<Arc<SensorList>, String> {
        let key = (
            masterdata.value.clone(),
            order,
            masterdata.origin.to_string(),
        );
        if let Some(loaded) = self.sensor_lists.get(&key) {
            return loaded.clone();
        }
        let loaded = gloc_project::sensors::load_sensor_list_file(masterdata, order)
            .and_then(gloc_project::sensors::LoadedSensors::into_list)
            .map(Arc::new)
            .map_err(|error| error.to_string());
        self.sensor_lists.insert(key, loaded.clone());
        loaded
    }

    /// Resolves settings for a document through the project layer (the editor's
    /// settings over gloc.toml over the defaults). Returns the context plus problems
    /// to report on the script itself (a refused editor setting, an unreadable
    /// masterdata file).
    fn context_for(&mut self, path: Option<PathBuf>) -> (Context, Vec<Diagnostic>) {
        // A bad gloc.toml is reported on gloc.toml itself (`refresh_config_files`).
        let config = self.config_for(path.as_deref()).unwrap_or_default();
        let overrides = Overrides {
            masterdata: self.settings.masterdata.clone(),
            cycle_budget: self.settings.cycle_budget,
            ..Overrides::new(Surface::Editor)
        };
        let mut problems = Vec::new();
        let settings =
            ProjectSettings::from_config(config.clone(), overrides).unwrap_or_else(|error| {
                problems.push(
                    Diagnostic::error(
                        BAD_EDITOR_SETTING,
                        Span::default(),
                        format!("{error}; the editor's gloc settings are not used"),
                    )
                    .with_help("fix the setting in the editor's gloc settings"),
                );
                ProjectSettings::from_config(config, Overrides::new(Surface::Editor))
                    .unwrap_or_default()
            });
        let list_folders = settings.list_folders(path.as_deref());
        let sensors = match &settings.masterdata {
            None => self.embedded(),
            Some(masterdata) => self
                .sensor_list(masterdata, settings.sensor_order)
                .unwrap_or_else(|message| {
                    let unloadable = format!("{message}; using the embedded 2008 list");
                    problems.push(
                        Diagnostic::error(SENSOR_LIST_UNLOADABLE, Span::default(), unloadable)
                            .with_help(
                                "fix `masterdata` in gloc.toml or the editor's gloc settings",
                            ),
                    );
                    self.embedded()
                }),
        };
        (
            Context {
                sensors,
                // Always the resolved budget (the default one too), as the CLI holds
                // the script against it: W2302 is decided alike everywhere.
                cycle_budget: Some(settings.cycle_budget.value.get()),
                cycle_budget_from: Some(settings.cycle_budget.origin.to_string()),
                list_folders,
                mafiles: settings.mafiles.clone(),
            },
            problems,
        )
    }

    /// Re-reads the settings of one open document, re-analyses it and returns
    /// what to publish (its diagnostics and those of the `gloc.toml` files).
    fn refresh(&mut self, uri: &Uri) -> Vec<Publish> {
        let Some(open) = self.documents.get(uri) else {
            return Vec::new();
        };
        if open.document.language == Language::Config {
            return self.refresh_config_files();
        }
        let (context, problems) = self.context_for(open.document.path());
        if let Some(open) = self.documents.get_mut(uri) {
            open.context = context;
            open.context_problems = problems;
            open.analyzed_version = None;
            open.published_version = None;
        }
        let mut publishes: Vec<Publish> = self.analyzed_publish(uri).into_iter().collect();
        let config_path = self
            .documents
            .get(uri)
            .and_then(|open| open.document.path())
            .as_deref()
            .and_then(config_path_for);
        if let Some(config_path) = config_path {
            publishes.extend(self.refresh_config_file(&config_path));
        }
        publishes
    }

    /// Brings a document's analysis up to its current text (settings unchanged).
    fn ensure_analyzed(&mut self, uri: &Uri) {
        let Some(open) = self.documents.get_mut(uri) else {
            return;
        };
        if open.analyzed_version == Some(open.document.version)
            || open.document.language == Language::Config
        {
            return;
        }
        let mut analysis = lang::analyze_at(
            open.document.language,
            open.document.text(),
            open.document.path().as_deref(),
            &open.context,
        );
        analysis
            .diagnostics
            .extend(open.context_problems.iter().cloned());
        open.analysis = Arc::new(analysis);
        open.analyzed_version = Some(open.document.version);
    }

    /// The diagnostics of the current version, unless already published.
    fn analyzed_publish(&mut self, uri: &Uri) -> Option<Publish> {
        self.ensure_analyzed(uri);
        let pulled = self.client_features.pull_diagnostics;
        let open = self.documents.get_mut(uri)?;
        // A client that pulls gets scripts' diagnostics from `textDocument/diagnostic`
        // only (pushing too would show each problem twice).
        if open.document.language == Language::Config
            || open.published_version == Some(open.document.version)
            || pulled
        {
            return None;
        }
        open.published_version = Some(open.document.version);
        Some(Publish {
            uri: uri.clone(),
            diagnostics: features::diagnostics(
                &open.document,
                &open.analysis,
                self.client_features,
            ),
            version: Some(open.document.version),
        })
    }

    /// Publishes the problems of every `gloc.toml` that applies to an open
    /// script or is open itself, and clears files that became valid (for a change of
    /// a gloc.toml or of the settings: every open document's file is read).
    fn refresh_config_files(&mut self) -> Vec<Publish> {
        let mut config_paths: Vec<PathBuf> = self
            .documents
            .values()
            .filter_map(|open| match open.document.language {
                Language::Config => open.document.path(),
                _ => open.document.path().as_deref().and_then(config_path_for),
            })
            .collect();
        config_paths.sort();
        config_paths.dedup();
        // A file no open document uses any more is forgotten.
        self.config_files_with_problems
            .retain(|known| config_paths.binary_search(known).is_ok());
        config_paths
            .iter()
            .filter_map(|config_path| self.refresh_config_file(config_path))
            .collect()
    }

    /// Publishes the problem of one `gloc.toml` (the one a document just opened
    /// uses), or clears it when it became valid; `None` when nothing changed for the
    /// client. Opening a document reads only its own gloc.toml: reading every open
    /// document's made 4,000 opens take 15-28 s.
    fn refresh_config_file(&mut self, config_path: &Path) -> Option<Publish> {
        let uri = Uri::from_file_path(config_path)?;
        let error = self.config_for(Some(config_path)).err();
        let open = self.documents.get(&uri);
        let diagnostics = match (&error, open) {
            (Some(error), Some(open)) => features::diagnostics_for(
                open.document.rope(),
                &uri,
                &[(*error.diagnostic).clone()],
                self.client_features,
            ),
            (Some(error), None) => {
                let rope = ropey::Rope::from_str(error.text.as_deref().unwrap_or(""));
                features::diagnostics_for(
                    &rope,
                    &uri,
                    &[(*error.diagnostic).clone()],
                    self.client_features,
                )
            }
            (None, _) => Vec::new(),
        };
        let version = open.map(|open| open.document.version);
        let was_reported = self
            .config_files_with_problems
            .iter()
            .any(|known| known == config_path);
        match (error.is_some(), was_reported) {
            (true, false) => self
                .config_files_with_problems
                .push(config_path.to_path_buf()),
            (false, true) => self
                .config_files_with_problems
                .retain(|known| known != config_path),
            _ => {}
        }
        (error.is_some() || was_reported).then_some(Publish {
            uri,
            diagnostics,
            version,
        })
    }

    /// Analyses every open mission (`.mi`) again, for a `.ma` file saved.
    fn reanalyze_missions(&mut self) -> Vec<Publish> {
        let missions: Vec<Uri> = self
            .documents
            .iter()
            .filter(|(_, open)| open.document.language == Language::Mission)
            .map(|(uri, _)| uri.clone())
            .collect();
        let mut publishes = Vec::new();
        for uri in missions {
            if let Some(open) = self.documents.get_mut(&uri) {
                open.analyzed_version = None;
                open.published_version = None;
            }
            publishes.extend(self.analyzed_publish(&uri));
        }
        publishes
    }

    /// Workspace symbols matching `query`: open documents as edited, the other
    /// scripts of the workspace folders as on disk (bounded by
    /// `gloc_ide::workspace`), best match first.
    fn workspace_symbols(&mut self, query: &str) -> Vec<SymbolInformation> {
        use gloc_ide::workspace;
        let uris: Vec<Uri> = self.documents.keys().cloned().collect();
        let mut found = Vec::new();
        let mut open_paths = Vec::new();
        for uri in uris {
            self.ensure_analyzed(&uri);
            let Some(open) = self.documents.get(&uri) else {
                continue;
            };
            if open.document.language == Language::Config {
                continue;
            }
            open_paths.extend(open.document.path());
            found.extend(features::workspace_symbols(
                open.document.rope(),
                &uri,
                &open.analysis,
            ));
        }
        let files = workspace::script_files(&self.workspace_roots);
        let mut kept = HashMap::new();
        for file in files {
            if open_paths.contains(&file.path) {
                continue;
            }
            let cached = self
                .disk_symbols
                .remove(&file.path)
                .filter(|entry| entry.bytes == file.bytes && entry.modified == file.modified);
            let entry = match cached {
                Some(entry) => entry,
                None => {
                    let (Ok(text), Some(uri)) = (
                        std::fs::read_to_string(&file.path),
                        Uri::from_file_path(&file.path),
                    ) else {
                        continue;
                    };
                    // The file's own project settings, as if it were opened.
                    let (context, _) = self.context_for(Some(file.path.clone()));
                    let analysis = lang::analyze(file.language, &text, &context);
                    let rope = ropey::Rope::from_str(&text);
                    DiskSymbols {
                        bytes: file.bytes,
                        modified: file.modified,
                        symbols: features::workspace_symbols(&rope, &uri, &analysis),
                    }
                }
            };
            found.extend(entry.symbols.iter().cloned());
            kept.insert(file.path, entry);
        }
        // Files gone from disk (or from the bounds) leave the cache.
        self.disk_symbols = kept;
        let mut ranked: Vec<(u32, SymbolInformation)> = found
            .into_iter()
            .filter_map(|symbol| Some((workspace::query_class(query, &symbol.name)?, symbol)))
            .collect();
        ranked.sort_by(|(a, x), (b, y)| a.cmp(b).then_with(|| x.name.cmp(&y.name)));
        ranked.truncate(workspace::MAX_RESULTS);
        ranked.into_iter().map(|(_, symbol)| symbol).collect()
    }

    fn refresh_all(&mut self) -> Vec<Publish> {
        let uris: Vec<Uri> = self.documents.keys().cloned().collect();
        let mut publishes = Vec::new();
        for uri in uris {
            publishes.extend(self.refresh(&uri));
        }
        publishes
    }
}

impl Backend {
    /// Runs `answer` on an open document's latest analysis; unknown documents
    /// get `None` (never an error: clients race `didClose` with requests).
    fn with_document<T>(
        &self,
        uri: &Uri,
        answer: impl FnOnce(&Document, &Analysis, &Context) -> Option<T>,
    ) -> Option<T> {
        let mut state = lock(&self.state);
        state.ensure_analyzed(uri);
        let open = state.documents.get(uri)?;
        if open.document.language == Language::Config {
            return None;
        }
        // A bug in one answer must not take the whole session down.
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            answer(&open.document, &open.analysis, &open.context)
        }))
        .unwrap_or(None)
    }

    /// The answer to a request about one document, as [`Self::with_document`] gives
    /// it: a request never fails (an unknown or configuration document, or a bug in
    /// one answer, is no answer).
    fn answer<T>(
        &self,
        uri: &Uri,
        answer: impl FnOnce(&Document, &Analysis, &Context) -> Option<T>,
    ) -> Result<Option<T>> {
        Ok(self.with_document(uri, answer))
    }

    /// [`Self::answer`] for a request at a position in a document.
    fn answer_at<T>(
        &self,
        at: TextDocumentPositionParams,
        answer: impl FnOnce(&Document, &Analysis, &Context, Position) -> Option<T>,
    ) -> Result<Option<T>> {
        self.answer(&at.text_document.uri, |document, analysis, context| {
            answer(document, analysis, context, at.position)
        })
    }

    /// Gives `tokens` a new result id and keeps them for the next delta request.
    fn remember_tokens(&self, uri: Uri, mut tokens: SemanticTokens) -> SemanticTokens {
        let mut state = lock(&self.state);
        state.next_tokens_id += 1;
        let id = state.next_tokens_id.to_string();
        tokens.result_id = Some(id.clone());
        state.sent_tokens.insert(uri, (id, tokens.data.clone()));
        tokens
    }

    /// Analyses and publishes a changed document once the messages already
    /// waiting have been handled: a burst of edits is analysed once, for its
    /// last version, and an idle server answers at once. Requests never wait
    /// for this: they bring the analysis up to date themselves.
    fn publish_soon(&self, uri: Uri) {
        let client = self.client.clone();
        let state = self.state.clone();
        tokio::spawn(async move {
            tokio::task::yield_now().await;
            let publish = lock(&state).analyzed_publish(&uri);
            if let Some(publish) = publish {
                send(&client, vec![publish]).await;
            }
        });
    }

    /// Asks the client to report changes to `gloc.toml` and sensor-list files
    /// on disk (also when they are not open), in the background.
    fn watch_settings_files(&self) {
        if !lock(&self.state).client_supports_watch_registration {
            return;
        }
        let client = self.client.clone();
        tokio::spawn(async move {
            let watchers = ["**/gloc.toml", "**/*.cac", "**/masterdata*"]
                .into_iter()
                .map(|pattern| FileSystemWatcher {
                    glob_pattern: GlobPattern::String(pattern.to_string()),
                    kind: None,
                })
                .collect();
            let options = DidChangeWatchedFilesRegistrationOptions { watchers };
            let registration = Registration {
                id: "gloc-settings-files".to_string(),
                method: "workspace/didChangeWatchedFiles".to_string(),
                register_options: serde_json::to_value(options).ok(),
            };
            // A client that refuses simply keeps the settings of open files.
            let _ = client.register_capability(vec![registration]).await;
        });
    }

    /// Asks a client that pulls diagnostics to pull again (the settings changed),
    /// in the background.
    fn refresh_pulled(&self) {
        let features = lock(&self.state).client_features;
        if !(features.pull_diagnostics && features.diagnostic_refresh) {
            return;
        }
        let client = self.client.clone();
        tokio::spawn(async move {
            let _ = client.workspace_diagnostic_refresh().await;
        });
    }

    /// Fetches `workspace/configuration` in the background and re-analyses.
    fn fetch_client_settings(&self) {
        let client = self.client.clone();
        let state = self.state.clone();
        if !lock(&state).client_supports_configuration {
            return;
        }
        tokio::spawn(async move {
            let items = vec![ConfigurationItem {
                scope_uri: None,
                section: Some("gloc".to_string()),
            }];
            let Ok(values) = client.configuration(items).await else {
                return;
            };
            let Some(value) = values.into_iter().next() else {
                return;
            };
            let publishes = {
                let mut state = lock(&state);
                let settings = settings_from(&value);
                if settings == state.settings {
                    return;
                }
                state.settings = settings;
                state.sensor_lists.clear();
                state.refresh_all()
            };
            send(&client, publishes).await;
            let features = lock(&state).client_features;
            if features.pull_diagnostics && features.diagnostic_refresh {
                let _ = client.workspace_diagnostic_refresh().await;
            }
        });
    }
}

/// Reads `{ "masterdata": "...", "cycleBudget": N }`, also when wrapped in
/// `{ "gloc": { … } }`. Unknown keys and wrong types are ignored; a value out of range
/// (a budget of 0) is kept, so that the project layer refuses it in so many words.
pub fn settings_from(value: &Value) -> Settings {
    let section = value.get("gloc").unwrap_or(value);
    Settings {
        masterdata: section
            .get("masterdata")
            .and_then(Value::as_str)
            .filter(|text| !text.trim().is_empty())
            .map(PathBuf::from),
        cycle_budget: section
            .get("cycleBudget")
            .or_else(|| section.get("cycle_budget"))
            .and_then(Value::as_u64),
        completion_limit: section
            .get("completionLimit")
            .and_then(Value::as_u64)
            .filter(|limit| (1..=100_000).contains(limit))
            .map(|limit| limit as usize),
    }
}

/// Why the transport replaced a message, and the JSON-RPC error code to answer
/// with (see `transport`).
#[derive(serde::Deserialize)]
pub struct InvalidMessage {
    reason: String,
    code: i64,
}

impl Backend {
    /// A message the client sent broken: answer it with an error (its `id`, or
    /// `null` when it could not be read).
    pub async fn invalid_request(&self, params: InvalidMessage) -> Result<()> {
        Err(Error {
            code: tower_lsp_server::jsonrpc::ErrorCode::from(params.code),
            message: params.reason.into(),
            data: None,
        })
    }
}

impl LanguageServer for Backend {
    async fn initialize(&self, params: InitializeParams) -> Result<InitializeResult> {
        {
            let mut state = lock(&self.state);
            state.client_features =
                features::ClientFeatures::from_capabilities(&params.capabilities);
            state.client_supports_configuration = params
                .capabilities
                .workspace
                .as_ref()
                .and_then(|workspace| workspace.configuration)
                .unwrap_or(false);
            state.client_supports_watch_registration = params
                .capabilities
                .workspace
                .as_ref()
                .and_then(|workspace| workspace.did_change_watched_files.as_ref())
                .and_then(|watched| watched.dynamic_registration)
                .unwrap_or(false);
            if let Some(options) = &params.initialization_options {
                state.settings = settings_from(options);
            }
            let mut roots: Vec<Uri> = params
                .workspace_folders
                .iter()
                .flatten()
                .map(|folder| folder.uri.clone())
                .collect();
            if roots.is_empty() {
                #[allow(deprecated)] // `rootUri`: what a client without workspace folders sends.
                roots.extend(params.root_uri.clone());
            }
            state.workspace_roots = roots
                .iter()
                .filter_map(|uri| uri.to_file_path().map(|path| path.into_owned()))
                .collect();
        }
        Ok(InitializeResult {
            capabilities: features::capabilities(),
            server_info: Some(ServerInfo {
                name: "gloc".to_string(),
                version: Some(env!("CARGO_PKG_VERSION").to_string()),
            }),
            offset_encoding: None,
        })
    }

    async fn initialized(&self, _: InitializedParams) {
        self.fetch_client_settings();
        self.watch_settings_files();
    }

    async fn shutdown(&self) -> Result<()> {
        self.shutdown_requested.store(true, Ordering::SeqCst);
        Ok(())
    }

    async fn did_open(&self, params: DidOpenTextDocumentParams) {
        let item = params.text_document;
        let Some(language) = crate::document::detect_language(&item.language_id, &item.uri) else {
            return;
        };
        let publishes = {
            let mut state = lock(&self.state);
            let document = Document::new(item.uri.clone(), language, item.version, &item.text);
            let context = Context::new(state.embedded());
            state.documents.insert(
                item.uri.clone(),
                Open {
                    document,
                    analysis: Arc::new(Analysis::default()),
                    analyzed_version: None,
                    published_version: None,
                    context,
                    context_problems: Vec::new(),
                },
            );
            if language == Language::Config {
                state.sensor_lists.clear();
                state.refresh_all()
            } else {
                state.refresh(&item.uri)
            }
        };
        send(&self.client, publishes).await;
    }

    async fn did_change(&self, params: DidChangeTextDocumentParams) {
        let uri = params.text_document.uri;
        let version = params.text_document.version;
        let stale = {
            let state = lock(&self.state);
            state
                .documents
                .get(&uri)
                .map(|open| open.document.version)
                .filter(|known| version <= *known)
        };
        if let Some(known) = stale {
            // The spec makes versions increase with every change: an older or equal
            // one is a duplicated or reordered notification, and applying it again
            // would corrupt the text, so it is ignored (and said so).
            self.client
                .log_message(
                    MessageType::WARNING,
                    format!(
                        "gloc: ignored a change to {} with version {version}: the document is already at version {known} (versions must increase)",
                        uri.as_str()
                    ),
                )
                .await;
            return;
        }
        let publishes = {
            let mut state = lock(&self.state);
            let Some(open) = state.documents.get_mut(&uri) else {
                return;
            };
            open.document
                .apply_changes(params.text_document.version, params.content_changes);
            if open.document.language != Language::Config {
                drop(state);
                self.publish_soon(uri);
                return;
            }
            state.sensor_lists.clear();
            state.refresh_all()
        };
        send(&self.client, publishes).await;
    }

    async fn did_save(&self, params: DidSaveTextDocumentParams) {
        let publishes = {
            let mut state = lock(&self.state);
            let language = state
                .documents
                .get(&params.text_document.uri)
                .map(|open| open.document.language);
            match language {
                Some(Language::Config) => {
                    state.sensor_lists.clear();
                    state.refresh_all()
                }
                // The missions read their `.ma` files from disk: check them again.
                Some(Language::MissionArgs) => state.reanalyze_missions(),
                _ => return,
            }
        };
        send(&self.client, publishes).await;
        self.refresh_pulled();
    }

    async fn did_close(&self, params: DidCloseTextDocumentParams) {
        let uri = params.text_document.uri;
        let publishes = {
            let mut state = lock(&self.state);
            state.sent_tokens.remove(&uri);
            let Some(open) = state.documents.remove(&uri) else {
                return;
            };
            let mut publishes = vec![Publish {
                uri: uri.clone(),
                diagnostics: Vec::new(),
                version: None,
            }];
            if open.document.language == Language::Config {
                publishes.extend(state.refresh_all());
            }
            publishes
        };
        send(&self.client, publishes).await;
    }

    async fn did_change_configuration(&self, params: DidChangeConfigurationParams) {
        let publishes = {
            let mut state = lock(&self.state);
            if params.settings.is_object()
                && !params
                    .settings
                    .as_object()
                    .is_some_and(|map| map.is_empty())
            {
                state.settings = settings_from(&params.settings);
            }
            state.sensor_lists.clear();
            state.refresh_all()
        };
        send(&self.client, publishes).await;
        self.refresh_pulled();
        self.fetch_client_settings();
    }

    async fn did_change_watched_files(&self, _: DidChangeWatchedFilesParams) {
        let publishes = {
            let mut state = lock(&self.state);
            state.sensor_lists.clear();
            state.refresh_all()
        };
        send(&self.client, publishes).await;
        self.refresh_pulled();
    }

    async fn completion(&self, params: CompletionParams) -> Result<Option<CompletionResponse>> {
        let position = params.text_document_position;
        let (client, limit) = {
            let state = lock(&self.state);
            let limit = state
                .settings
                .completion_limit
                .unwrap_or(gloc_ide::completion::DEFAULT_LIMIT);
            (state.client_features, limit)
        };
        self.answer_at(position, |document, analysis, context, at| {
            features::completion(document, analysis, context, at, client, limit)
        })
    }

    async fn completion_resolve(&self, item: CompletionItem) -> Result<CompletionItem> {
        let Some((uri, position)) = features::resolve_origin(&item) else {
            return Ok(item);
        };
        let client = lock(&self.state).client_features;
        let fallback = item.clone();
        Ok(self
            .with_document(&uri, |document, analysis, context| {
                Some(features::completion_resolve(
                    document, analysis, context, position, client, item,
                ))
            })
            .unwrap_or(fallback))
    }

    async fn hover(&self, params: HoverParams) -> Result<Option<Hover>> {
        let position = params.text_document_position_params;
        let client = lock(&self.state).client_features;
        self.answer_at(position, |document, analysis, context, at| {
            features::hover(document, analysis, context, at, client)
        })
    }

    async fn signature_help(&self, params: SignatureHelpParams) -> Result<Option<SignatureHelp>> {
        self.answer_at(
            params.text_document_position_params,
            |document, _, _, at| features::signature_help(document, at),
        )
    }

    async fn goto_definition(
        &self,
        params: GotoDefinitionParams,
    ) -> Result<Option<GotoDefinitionResponse>> {
        self.answer_at(params.text_document_position_params, features::definition)
    }

    async fn references(&self, params: ReferenceParams) -> Result<Option<Vec<Location>>> {
        let include_declaration = params.context.include_declaration;
        self.answer_at(
            params.text_document_position,
            |document, analysis, _, at| {
                features::references(document, analysis, at, include_declaration)
            },
        )
    }

    async fn document_highlight(
        &self,
        params: DocumentHighlightParams,
    ) -> Result<Option<Vec<DocumentHighlight>>> {
        self.answer_at(
            params.text_document_position_params,
            |document, analysis, _, at| features::highlights(document, analysis, at),
        )
    }

    async fn prepare_rename(
        &self,
        params: TextDocumentPositionParams,
    ) -> Result<Option<PrepareRenameResponse>> {
        self.answer_at(params, |document, analysis, _, at| {
            features::prepare_rename(document, analysis, at)
        })
    }

    async fn rename(&self, params: RenameParams) -> Result<Option<WorkspaceEdit>> {
        let position = params.text_document_position;
        let outcome = self.with_document(
            &position.text_document.uri,
            |document, analysis, context| {
                Some(features::rename(
                    document,
                    analysis,
                    context,
                    position.position,
                    &params.new_name,
                ))
            },
        );
        match outcome {
            None => Ok(None),
            Some(Ok(edit)) => Ok(edit),
            Some(Err(message)) => Err(Error::invalid_params(message)),
        }
    }

    async fn document_symbol(
        &self,
        params: DocumentSymbolParams,
    ) -> Result<Option<DocumentSymbolResponse>> {
        let client = lock(&self.state).client_features;
        self.answer(&params.text_document.uri, |document, analysis, _| {
            Some(features::document_symbols(document, analysis, client))
        })
    }

    async fn folding_range(&self, params: FoldingRangeParams) -> Result<Option<Vec<FoldingRange>>> {
        self.answer(&params.text_document.uri, |document, analysis, _| {
            Some(features::folding_ranges(document, analysis))
        })
    }

    async fn semantic_tokens_full(
        &self,
        params: SemanticTokensParams,
    ) -> Result<Option<SemanticTokensResult>> {
        let uri = params.text_document.uri;
        let tokens = self.with_document(&uri, |document, analysis, context| {
            Some(features::semantic_tokens(document, analysis, context))
        });
        Ok(tokens.map(|tokens| SemanticTokensResult::Tokens(self.remember_tokens(uri, tokens))))
    }

    async fn semantic_tokens_full_delta(
        &self,
        params: SemanticTokensDeltaParams,
    ) -> Result<Option<SemanticTokensFullDeltaResult>> {
        let uri = params.text_document.uri;
        let Some(tokens) = self.with_document(&uri, |document, analysis, context| {
            Some(features::semantic_tokens(document, analysis, context))
        }) else {
            return Ok(None);
        };
        let previous = lock(&self.state)
            .sent_tokens
            .get(&uri)
            .filter(|(id, _)| *id == params.previous_result_id)
            .map(|(_, data)| features::semantic_tokens_edits(data, &tokens.data));
        let tokens = self.remember_tokens(uri, tokens);
        Ok(Some(match previous {
            Some(edits) => SemanticTokensFullDeltaResult::TokensDelta(SemanticTokensDelta {
                result_id: tokens.result_id,
                edits,
            }),
            // An unknown previous result: all of them.
            None => SemanticTokensFullDeltaResult::Tokens(tokens),
        }))
    }

    async fn semantic_tokens_range(
        &self,
        params: SemanticTokensRangeParams,
    ) -> Result<Option<SemanticTokensRangeResult>> {
        self.answer(&params.text_document.uri, |document, analysis, context| {
            Some(SemanticTokensRangeResult::Tokens(
                features::semantic_tokens_range(document, analysis, context, params.range),
            ))
        })
    }

    async fn diagnostic(
        &self,
        params: DocumentDiagnosticParams,
    ) -> Result<DocumentDiagnosticReportResult> {
        let client = lock(&self.state).client_features;
        let items = self
            .with_document(&params.text_document.uri, |document, analysis, _| {
                Some(features::diagnostics(document, analysis, client))
            })
            .unwrap_or_default();
        Ok(features::diagnostic_report(items))
    }

    async fn code_lens(&self, params: CodeLensParams) -> Result<Option<Vec<CodeLens>>> {
        let client = lock(&self.state).client_features;
        self.answer(&params.text_document.uri, |document, analysis, _| {
            Some(features::code_lenses(document, analysis, client))
        })
    }

    async fn selection_range(
        &self,
        params: SelectionRangeParams,
    ) -> Result<Option<Vec<SelectionRange>>> {
        self.answer(&params.text_document.uri, |document, analysis, _| {
            Some(features::selection_ranges(
                document,
                analysis,
                &params.positions,
            ))
        })
    }

    async fn document_link(&self, params: DocumentLinkParams) -> Result<Option<Vec<DocumentLink>>> {
        // Links are in gloc.toml, which `with_document` leaves out.
        let state = lock(&self.state);
        Ok(state
            .documents
            .get(&params.text_document.uri)
            .map(|open| features::document_links(&open.document, &open.context)))
    }

    async fn range_formatting(
        &self,
        params: DocumentRangeFormattingParams,
    ) -> Result<Option<Vec<TextEdit>>> {
        self.answer(&params.text_document.uri, |document, _, _| {
            features::range_formatting(document, params.range)
        })
    }

    async fn symbol(
        &self,
        params: WorkspaceSymbolParams,
    ) -> Result<Option<WorkspaceSymbolResponse>> {
        let symbols = lock(&self.state).workspace_symbols(&params.query);
        Ok(Some(WorkspaceSymbolResponse::Flat(symbols)))
    }

    async fn inlay_hint(&self, params: InlayHintParams) -> Result<Option<Vec<InlayHint>>> {
        self.answer(&params.text_document.uri, |document, analysis, _| {
            Some(features::inlay_hints(document, analysis, params.range))
        })
    }

    async fn code_action(&self, params: CodeActionParams) -> Result<Option<CodeActionResponse>> {
        let client = lock(&self.state).client_features;
        self.answer(&params.text_document.uri, |document, analysis, _| {
            Some(features::code_actions(
                document,
                analysis,
                params.range,
                client,
            ))
        })
    }

    async fn formatting(&self, params: DocumentFormattingParams) -> Result<Option<Vec<TextEdit>>> {
        self.answer(&params.text_document.uri, |document, _, _| {
            features::formatting(document)
        })
    }

    async fn execute_command(&self, params: ExecuteCommandParams) -> Result<Option<LSPAny>> {
        if params.command != COMPILED_GLOC_COMMAND {
            return Err(Error::invalid_params(format!(
                "unknown command `{}`; this server knows `{COMPILED_GLOC_COMMAND}`",
                params.command
            )));
        }
        let uri = params
            .arguments
            .first()
            .and_then(|argument| {
                argument
                    .as_str()
                    .or_else(|| argument.get("uri").and_then(Value::as_str))
            })
            .and_then(|text| text.parse::<Uri>().ok())
            .ok_or_else(|| {
                Error::invalid_params(format!(
                    "`{COMPILED_GLOC_COMMAND}` takes one argument: the URI of an open GBASIC document"
                ))
            })?;
        let mut state = lock(&self.state);
        state.ensure_analyzed(&uri);
        let open = state.documents.get(&uri).ok_or_else(|| {
            Error::invalid_params(format!("`{}` is not open in the server", uri.as_str()))
        })?;
        features::compiled_gloc(&open.document, &open.analysis).map(Some)
    }
}
