// @ts-check
// The VS Code extension: a thin client. It starts `gloc lsp` for diagnostics, completion and the
// rest, `gloc dap` for debugging, and `gloc run` for "Run mission in simulator". All knowledge of
// GLOC and GBASIC lives in the gloc binary; this file only wires VS Code to it.
'use strict';

const childProcess = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');
const helpers = require('./helpers');

/** @type {LanguageClient | undefined} */
let client;

/** Where "Run mission" writes its flight profiles (the extension's storage, not a temp folder). */
/** @type {string} */
let runsDirectory = path.join(os.tmpdir(), 'gloc-runs');

/**
 * @param {vscode.ExtensionContext} context
 */
async function activate(context) {
  runsDirectory = path.join((context.storageUri || context.globalStorageUri).fsPath, 'runs');
  const runOutput = vscode.window.createOutputChannel('GLOC Run');
  const serverOutput = vscode.window.createOutputChannel('GLOC Language Server');
  context.subscriptions.push(runOutput, serverOutput);

  const compiledProvider = new CompiledGlocProvider();
  context.subscriptions.push(
    vscode.workspace.registerTextDocumentContentProvider(helpers.COMPILED_SCHEME, compiledProvider),
    vscode.workspace.onDidChangeTextDocument((event) => compiledProvider.sourceChanged(event.document)),
    compiledProvider,
  );

  context.subscriptions.push(
    vscode.commands.registerCommand('gloc.restartServer', () => restartClient(serverOutput)),
    vscode.commands.registerCommand('gloc.showCompiledGloc', (/** @type {vscode.Uri | undefined} */ uri) =>
      showCompiledGloc(uri),
    ),
    vscode.commands.registerCommand('gloc.runMission', (/** @type {vscode.Uri | string | undefined} */ uri) =>
      runMission(/** @type {vscode.Uri | undefined} */ (helpers.commandUri(uri, vscode.Uri.parse)), runOutput),
    ),
    vscode.commands.registerCommand('gloc.debugScript', (/** @type {vscode.Uri | string | undefined} */ uri) =>
      debugScript(/** @type {vscode.Uri | undefined} */ (helpers.commandUri(uri, vscode.Uri.parse))),
    ),
    vscode.debug.registerDebugAdapterDescriptorFactory('gloc', new GlocDebugAdapterFactory()),
    vscode.debug.registerDebugConfigurationProvider('gloc', new GlocDebugConfigurationProvider()),
    vscode.workspace.onDidChangeConfiguration((event) => {
      // A new binary needs a new server process; the server applies the other settings live: it
      // asks for them again (workspace/configuration, answered by `resolvedConfiguration`).
      if (event.affectsConfiguration('gloc.path')) {
        restartClient(serverOutput);
      } else if (event.affectsConfiguration('gloc') && client) {
        void client.sendNotification('workspace/didChangeConfiguration', { settings: null });
      }
    }),
    { dispose: () => void stopClient() },
  );

  await startClient(serverOutput);
}

function deactivate() {
  return stopClient();
}

/** The first workspace folder holding `uri`, else the first folder of the window. */
function workspaceFolderPath(/** @type {vscode.Uri | undefined} */ uri) {
  const folder = (uri && vscode.workspace.getWorkspaceFolder(uri)) || vscode.workspace.workspaceFolders?.[0];
  return folder?.uri.scheme === 'file' ? folder.uri.fsPath : undefined;
}

/**
 * The gloc binary from the `gloc.path` setting (see helpers.locateBinary), or undefined after one
 * notification that says it is missing.
 */
function glocBinary(/** @type {vscode.Uri | undefined} */ uri) {
  const setting = vscode.workspace.getConfiguration('gloc', uri).get('path', 'gloc');
  const found = helpers.locateBinary(setting, {
    workspaceFolder: workspaceFolderPath(uri),
    homeDirectory: os.homedir(),
    pathVariable: process.env.PATH,
    isExecutable,
  });
  if ('binary' in found) {
    return found.binary;
  }
  void reportMissingBinary(found.missing, found.searched);
  return undefined;
}

function isExecutable(/** @type {string} */ file) {
  try {
    fs.accessSync(file, fs.constants.X_OK);
    return fs.statSync(file).isFile();
  } catch {
    return false;
  }
}

/** The masterdata file from the `gloc.masterdata` setting, or undefined for the default list. */
function masterdataPath(/** @type {vscode.Uri | undefined} */ uri) {
  const setting = vscode.workspace.getConfiguration('gloc', uri).get('masterdata', '');
  return helpers.resolveSettingPath(setting, workspaceFolderPath(uri), os.homedir());
}

/** The missing binaries whose notification is on screen: one cause, one notification. */
const missingShown = new Set();

/** Says the gloc binary was not found, once while the notice is open, with a button to the setting. */
async function reportMissingBinary(/** @type {string} */ binary, /** @type {string[]} */ searched) {
  if (missingShown.has(binary)) {
    return;
  }
  missingShown.add(binary);
  const where = searched.length === 1 && searched[0] === binary ? '' : ` (looked in ${searched.join(', ')})`;
  try {
    const choice = await vscode.window.showErrorMessage(
      `GLOC: the gloc binary "${binary}" was not found${where}. Install it (cargo install --locked --path cli) or set "gloc.path" to it.`,
      'Open Settings',
    );
    if (choice === 'Open Settings') {
      await vscode.commands.executeCommand('workbench.action.openSettings', 'gloc.path');
    }
  } finally {
    missingShown.delete(binary);
  }
}

/**
 * The `gloc` section for the server's workspace/configuration requests, with `masterdata` resolved
 * as the setting says (relative to the workspace folder, `~/`), so the server applies it live.
 * @type {import('vscode-languageclient/node').ConfigurationMiddleware['configuration']}
 */
async function resolvedConfiguration(params, token, next) {
  const values = await next(params, token);
  if (!Array.isArray(values)) {
    return values;
  }
  return values.map((value, index) => {
    const item = params.items[index];
    if (item?.section !== 'gloc' || !value || typeof value !== 'object') {
      return value;
    }
    const scope = item.scopeUri ? vscode.Uri.parse(item.scopeUri) : undefined;
    return { ...value, masterdata: masterdataPath(scope) || '' };
  });
}

// ---------------------------------------------------------------------------------------------
// Language server

async function startClient(/** @type {vscode.OutputChannel} */ outputChannel) {
  const binary = glocBinary(undefined);
  if (!binary) {
    return;
  }
  const masterdata = masterdataPath(undefined);
  /** @type {import('vscode-languageclient/node').ServerOptions} */
  const serverOptions = { command: binary, args: ['lsp'], options: { cwd: workspaceFolderPath(undefined) } };
  /** @type {import('vscode-languageclient/node').LanguageClientOptions} */
  const clientOptions = {
    // Only real files and unsaved buffers: the read-only "compiled GLOC" views are not scripts
    // the user edits and must not collect diagnostics of their own.
    documentSelector: helpers.SERVED_LANGUAGE_IDS.flatMap((language) => [
      { scheme: 'file', language },
      { scheme: 'untitled', language },
    ]),
    initializationOptions: masterdata ? { masterdata } : {},
    middleware: { workspace: { configuration: resolvedConfiguration } },
    outputChannel,
  };
  client = new LanguageClient('gloc', 'GLOC Language Server', serverOptions, clientOptions);
  // Tell the server which code lens commands this extension runs ("Run", "Debug").
  client.registerFeature({
    fillClientCapabilities(capabilities) {
      capabilities.experimental = { ...(capabilities.experimental || {}), commands: { commands: helpers.CODE_LENS_COMMANDS } };
    },
    initialize() {},
    getState() {
      return { kind: 'static' };
    },
    clear() {},
  });
  try {
    await client.start();
  } catch (error) {
    outputChannel.appendLine(`Could not start "${binary} lsp": ${errorMessage(error)}`);
    client = undefined;
    await vscode.window.showErrorMessage(`GLOC: could not start "${binary} lsp": ${errorMessage(error)}`);
  }
}

async function stopClient() {
  const running = client;
  client = undefined;
  if (running) {
    try {
      await running.stop();
    } catch {
      // The server is already gone (it crashed or was never started): nothing left to stop.
    }
  }
}

async function restartClient(/** @type {vscode.OutputChannel} */ outputChannel) {
  await stopClient();
  await startClient(outputChannel);
}

function errorMessage(/** @type {unknown} */ error) {
  return error instanceof Error ? error.message : String(error);
}

// ---------------------------------------------------------------------------------------------
// Show compiled GLOC: a read-only document beside the GBASIC source, refreshed as the user types.

/** @implements {vscode.TextDocumentContentProvider} */
class CompiledGlocProvider {
  constructor() {
    /** @type {vscode.EventEmitter<vscode.Uri>} */
    this.changed = new vscode.EventEmitter();
    this.onDidChange = this.changed.event;
    /** @type {Map<string, NodeJS.Timeout>} */
    this.pending = new Map();
  }

  /** The virtual URI of the compiled GLOC of `source`; its query holds the source URI. */
  static uriFor(/** @type {vscode.Uri} */ source) {
    return vscode.Uri.from({
      scheme: helpers.COMPILED_SCHEME,
      path: helpers.compiledDocumentPath(source.path),
      query: source.toString(),
    });
  }

  /** @param {vscode.Uri} uri */
  async provideTextDocumentContent(uri) {
    const source = vscode.Uri.parse(uri.query);
    const name = path.basename(source.path);
    if (!client) {
      return `# The GLOC language server is not running, so ${name} cannot be compiled.\n# Check the "gloc.path" setting, then run "GLOC: Restart language server".\n`;
    }
    try {
      const request = helpers.compiledGlocRequest(client.code2ProtocolConverter.asUri(source));
      const result = await client.sendRequest('workspace/executeCommand', request);
      const text = helpers.compiledGlocText(result);
      if (text === undefined) {
        return `# gloc lsp answered without GLOC text for ${name}; is the gloc binary older than this extension?\n`;
      }
      return text;
    } catch (error) {
      // The server answers a program with errors with an error whose message says so ("the
      // program has 2 errors; fix them to see its GLOC"); the view updates as they are fixed.
      return `# ${name}: ${errorMessage(error)}\n# The Problems panel lists the errors; this view updates as you fix them.\n`;
    }
  }

  /** Refreshes an open compiled view shortly after its source changes (debounced). */
  sourceChanged(/** @type {vscode.TextDocument} */ document) {
    if (document.languageId !== 'gbasic') {
      return;
    }
    const target = CompiledGlocProvider.uriFor(document.uri);
    const key = target.toString();
    if (!vscode.workspace.textDocuments.some((open) => open.uri.toString() === key)) {
      return;
    }
    clearTimeout(this.pending.get(key));
    this.pending.set(
      key,
      setTimeout(() => {
        this.pending.delete(key);
        this.changed.fire(target);
      }, 300),
    );
  }

  dispose() {
    for (const timer of this.pending.values()) {
      clearTimeout(timer);
    }
    this.changed.dispose();
  }
}

async function showCompiledGloc(/** @type {vscode.Uri | undefined} */ uri) {
  const source = uri || vscode.window.activeTextEditor?.document.uri;
  const document = source && (await vscode.workspace.openTextDocument(source));
  if (!document || document.languageId !== 'gbasic') {
    await vscode.window.showWarningMessage('GLOC: "Show compiled GLOC" needs a GBASIC (.gbas) file.');
    return;
  }
  const compiled = await vscode.workspace.openTextDocument(CompiledGlocProvider.uriFor(document.uri));
  await vscode.languages.setTextDocumentLanguage(compiled, 'gloc');
  await vscode.window.showTextDocument(compiled, {
    viewColumn: vscode.ViewColumn.Beside,
    preserveFocus: true,
    preview: false,
  });
}

// ---------------------------------------------------------------------------------------------
// Run mission in simulator: `gloc run FILE --plot FILE.svg --summary json`, the output in an output
// channel, the flight profile (in the extension's storage, replaced by the next run of the same
// script) opened beside the script.

/** Starts the debugger on a script (the "Debug" code lens; the launch is completed as for F5). */
async function debugScript(/** @type {vscode.Uri | undefined} */ uri) {
  const source = uri || vscode.window.activeTextEditor?.document.uri;
  if (!source || source.scheme !== 'file') {
    await vscode.window.showWarningMessage('GLOC: "Debug" needs a .gbas or .gloc script saved to a file.');
    return;
  }
  await vscode.debug.startDebugging(vscode.workspace.getWorkspaceFolder(source), {
    type: 'gloc',
    request: 'launch',
    name: `Debug ${path.basename(source.fsPath)}`,
    program: source.fsPath,
  });
}

async function runMission(
  /** @type {vscode.Uri | undefined} */ uri,
  /** @type {vscode.OutputChannel} */ output,
) {
  const source = uri || vscode.window.activeTextEditor?.document.uri;
  const document = source && (await vscode.workspace.openTextDocument(source));
  if (!document || !helpers.LANGUAGE_IDS.includes(document.languageId)) {
    await vscode.window.showWarningMessage('GLOC: "Run mission in simulator" needs a .gbas or .gloc script.');
    return;
  }
  if (document.uri.scheme !== 'file') {
    await vscode.window.showWarningMessage('GLOC: save the script to a file first; gloc run reads it from disk.');
    return;
  }
  if (document.isDirty && !(await document.save())) {
    await vscode.window.showWarningMessage('GLOC: the script was not saved, so it was not run.');
    return;
  }
  const script = document.uri.fsPath;
  const binary = glocBinary(document.uri);
  if (!binary) {
    return;
  }
  fs.mkdirSync(runsDirectory, { recursive: true });
  const plot = path.join(runsDirectory, `${path.basename(script, path.extname(script))}.svg`);
  fs.rmSync(plot, { force: true });
  const args = helpers.runMissionArguments({ script, plot, masterdata: masterdataPath(document.uri) });
  const cwd = workspaceFolderPath(document.uri) || path.dirname(script);

  output.clear();
  output.appendLine(`$ ${[binary, ...args].join(' ')}`);
  output.show(true);

  const outcome = await vscode.window.withProgress(
    {
      location: vscode.ProgressLocation.Notification,
      title: `Flying ${path.basename(script)} in the simulator`,
      cancellable: true,
    },
    (_progress, token) =>
      /** @type {Promise<{ code: number | null, stderr: string, error?: NodeJS.ErrnoException }>} */ (
        new Promise((resolve) => {
          let stderr = '';
          const child = childProcess.spawn(binary, args, { cwd });
          child.stdout.on('data', (chunk) => output.append(chunk.toString()));
          child.stderr.on('data', (chunk) => {
            stderr += chunk.toString();
            output.append(chunk.toString());
          });
          token.onCancellationRequested(() => child.kill());
          child.on('error', (error) => resolve({ code: null, stderr, error }));
          child.on('close', (code) => resolve({ code, stderr }));
        })
      ),
  );

  if (outcome.error) {
    await vscode.window.showErrorMessage(`GLOC: could not run "${binary}": ${outcome.error.message}`);
    return;
  }
  // Exit status 5: the run worked and the mission aborted (abend); its plot is drawn.
  if (outcome.code !== 0 && outcome.code !== 5) {
    const choice = await vscode.window.showErrorMessage(
      `GLOC: gloc run failed: ${helpers.firstLines(outcome.stderr, 2) || `exit status ${outcome.code}`}`,
      'Show Output',
    );
    if (choice === 'Show Output') {
      output.show();
    }
    return;
  }
  if (!fs.existsSync(plot)) {
    await vscode.window.showWarningMessage(`GLOC: the run finished but wrote no flight profile at ${plot}.`);
    return;
  }
  output.appendLine(`Flight profile: ${plot}`);
  await vscode.commands.executeCommand('vscode.open', vscode.Uri.file(plot), {
    viewColumn: vscode.ViewColumn.Beside,
    preview: false,
  });
  // Not awaited: a notification's promise settles only when the user dismisses it.
  const summary = helpers.runSummary(outcome.stderr);
  const name = path.basename(script);
  const notification = summary?.trapped
    ? vscode.window.showWarningMessage(`GLOC: ${name}: ${summary.headline}`, 'Show Output')
    : vscode.window.showInformationMessage(`GLOC: ${name}: ${summary?.headline || 'the flight finished'}`, 'Show Output');
  void notification.then((choice) => {
    if (choice === 'Show Output') {
      output.show();
    }
  });
}

// ---------------------------------------------------------------------------------------------
// Debugging: `gloc dap` on stdio.

/** @implements {vscode.DebugAdapterDescriptorFactory} */
class GlocDebugAdapterFactory {
  /** @param {vscode.DebugSession} session */
  createDebugAdapterDescriptor(session) {
    const folder = session.workspaceFolder?.uri;
    const binary = glocBinary(folder);
    if (!binary) {
      // The notification is on screen; VS Code shows this message in the debug console.
      throw new Error('the gloc binary was not found; set "gloc.path"');
    }
    return new vscode.DebugAdapterExecutable(binary, ['dap'], { cwd: workspaceFolderPath(folder) });
  }
}

/** @implements {vscode.DebugConfigurationProvider} */
class GlocDebugConfigurationProvider {
  /**
   * @param {vscode.WorkspaceFolder | undefined} folder
   * @param {vscode.DebugConfiguration} configuration
   */
  async resolveDebugConfiguration(folder, configuration) {
    const editor = vscode.window.activeTextEditor;
    const activeDocument = editor?.document.uri.scheme === 'file' ? editor.document : undefined;
    const completed = helpers.completeLaunchConfiguration(configuration, {
      activeFile: activeDocument?.uri.fsPath,
      activeLanguage: activeDocument?.languageId,
      masterdata: masterdataPath(folder?.uri),
    });
    if ('error' in completed) {
      await vscode.window.showErrorMessage(`GLOC: ${completed.error}`);
      return undefined;
    }
    // F5 with a missing binary: the notification instead of a session that never starts
    // (undefined ends the launch quietly; the factory below checks again).
    if (!glocBinary(folder?.uri)) {
      return undefined;
    }
    return /** @type {vscode.DebugConfiguration} */ (completed.configuration);
  }
}

module.exports = { activate, deactivate };
