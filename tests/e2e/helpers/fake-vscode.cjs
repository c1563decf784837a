// A stand-in for the `vscode` module and for `vscode-languageclient/node`, recording what the
// extension registers and does. Real VS Code cannot be downloaded here (@vscode/test-electron
// fetches it at run time), so the extension's glue is driven through this, while the language
// server, debug adapter and simulator it talks to are the real gloc binary.
'use strict';

const Module = require('module');
const path = require('path');

class Uri {
  constructor(scheme, fsPath, query) {
    this.scheme = scheme;
    this.path = fsPath;
    this.fsPath = fsPath;
    this.query = query || '';
  }
  static file(fsPath) {
    return new Uri('file', path.resolve(fsPath), '');
  }
  static from({ scheme, path: uriPath, query }) {
    return new Uri(scheme, uriPath, query);
  }
  static parse(text) {
    const match = /^([a-z][a-z0-9+.-]*):(?:\/\/)?([^?]*)(?:\?(.*))?$/i.exec(text);
    if (!match) {
      throw new Error(`not a URI: ${text}`);
    }
    return new Uri(match[1], decodeURIComponent(match[2]), match[3] ? decodeURIComponent(match[3]) : '');
  }
  toString() {
    const base = `${this.scheme}://${encodeURI(this.path)}`;
    return this.query ? `${base}?${encodeURIComponent(this.query)}` : base;
  }
}

class EventEmitter {
  constructor() {
    this.listeners = [];
    this.event = (listener) => {
      this.listeners.push(listener);
      return { dispose: () => {} };
    };
  }
  fire(value) {
    for (const listener of this.listeners) {
      listener(value);
    }
  }
  dispose() {}
}

class DebugAdapterExecutable {
  constructor(command, args, options) {
    this.command = command;
    this.args = args;
    this.options = options;
  }
}

/**
 * Builds a fresh fake VS Code. `settings` are the `gloc.*` settings, `workspace` the folder path,
 * `documents` maps file paths to { languageId, text }, `activeFile` is the editor's file, and
 * `onRequest(method, params)` answers the language client's requests.
 */
function createFakeVscode({ settings = {}, workspace, documents = {}, activeFile, onRequest, choose } = {}) {
  const record = {
    commands: new Map(),
    executed: [],
    messages: [],
    debugFactories: new Map(),
    debugProviders: new Map(),
    debugStarts: [],
    contentProviders: new Map(),
    clients: [],
    requests: [],
    outputs: new Map(),
    shown: [],
    changeListeners: [],
    configurationListeners: [],
  };
  const disposable = { dispose() {} };
  const workspaceFolder = workspace ? { uri: Uri.file(workspace), name: path.basename(workspace), index: 0 } : undefined;

  function documentFor(uri) {
    const known = documents[uri.fsPath];
    return {
      uri,
      languageId: known ? known.languageId : uri.scheme === 'gloc-compiled' ? 'gloc' : 'plaintext',
      isDirty: false,
      isUntitled: false,
      getText: () => (known ? known.text : ''),
      save: async () => true,
    };
  }

  function message(kind) {
    return async (text, ...items) => {
      record.messages.push({ kind, text, items });
      return choose ? choose(text, items) : undefined;
    };
  }

  const vscode = {
    Uri,
    EventEmitter,
    DebugAdapterExecutable,
    ViewColumn: { Active: -1, Beside: -2, One: 1 },
    ProgressLocation: { Notification: 15 },
    window: {
      get activeTextEditor() {
        return activeFile ? { document: documentFor(Uri.file(activeFile)) } : undefined;
      },
      createOutputChannel(name) {
        const channel = {
          name,
          text: '',
          append(value) {
            channel.text += value;
          },
          appendLine(value) {
            channel.text += `${value}\n`;
          },
          clear() {
            channel.text = '';
          },
          show() {},
          dispose() {},
        };
        record.outputs.set(name, channel);
        return channel;
      },
      showErrorMessage: message('error'),
      showWarningMessage: message('warning'),
      showInformationMessage: message('information'),
      async withProgress(_options, task) {
        return task({ report() {} }, { onCancellationRequested: () => disposable });
      },
      async showTextDocument(document, options) {
        record.shown.push({ document, options });
        return { document };
      },
    },
    workspace: {
      workspaceFolders: workspaceFolder ? [workspaceFolder] : undefined,
      textDocuments: [],
      getWorkspaceFolder: () => workspaceFolder,
      getConfiguration(section) {
        return {
          get: (key, fallback) => {
            const value = settings[`${section}.${key}`];
            return value === undefined ? fallback : value;
          },
        };
      },
      registerTextDocumentContentProvider(scheme, provider) {
        record.contentProviders.set(scheme, provider);
        return disposable;
      },
      onDidChangeTextDocument(listener) {
        record.changeListeners.push(listener);
        return disposable;
      },
      onDidChangeConfiguration(listener) {
        record.configurationListeners.push(listener);
        return disposable;
      },
      async openTextDocument(uri) {
        return documentFor(uri);
      },
    },
    languages: {
      async setTextDocumentLanguage(document, languageId) {
        document.languageId = languageId;
        return document;
      },
    },
    commands: {
      registerCommand(id, callback) {
        record.commands.set(id, callback);
        return disposable;
      },
      async executeCommand(id, ...args) {
        record.executed.push({ id, args });
        if (record.commands.has(id)) {
          return record.commands.get(id)(...args);
        }
        return undefined;
      },
    },
    debug: {
      registerDebugAdapterDescriptorFactory(type, factory) {
        record.debugFactories.set(type, factory);
        return disposable;
      },
      registerDebugConfigurationProvider(type, provider) {
        record.debugProviders.set(type, provider);
        return disposable;
      },
      async startDebugging(folder, configuration) {
        record.debugStarts.push({ folder, configuration });
        return true;
      },
    },
  };

  class LanguageClient {
    constructor(id, name, serverOptions, clientOptions) {
      this.id = id;
      this.name = name;
      this.serverOptions = serverOptions;
      this.clientOptions = clientOptions;
      this.code2ProtocolConverter = { asUri: (uri) => uri.toString() };
      this.notifications = [];
      this.features = [];
      record.clients.push(this);
    }
    registerFeature(feature) {
      this.features.push(feature);
    }
    async start() {}
    async stop() {}
    async sendNotification(method, params) {
      this.notifications.push({ method, params });
    }
    async sendRequest(method, params) {
      record.requests.push({ method, params });
      return onRequest ? onRequest(method, params) : null;
    }
  }

  /** Tells the extension that the settings in `sections` (e.g. `gloc.masterdata`) changed. */
  function fireConfigurationChange(sections) {
    const event = { affectsConfiguration: (section) => sections.includes(section) };
    record.configurationListeners.forEach((listener) => listener(event));
  }

  return { vscode, languageClientModule: { LanguageClient }, record, documentFor, settings, fireConfigurationChange };
}

/** The ExtensionContext `activate` gets: its subscriptions and a fresh global storage folder. */
function fakeContext() {
  const fs = require('fs');
  const os = require('os');
  const storage = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-ext-storage-'));
  return { subscriptions: [], globalStorageUri: Uri.file(storage), storageUri: undefined };
}

/** Loads the extension's main module with `vscode` and the language client replaced. */
function loadExtension(mainPath, fakes) {
  const originalLoad = Module._load;
  Module._load = function load(request, parent, isMain) {
    if (request === 'vscode') {
      return fakes.vscode;
    }
    if (request === 'vscode-languageclient/node') {
      return fakes.languageClientModule;
    }
    return originalLoad.call(this, request, parent, isMain);
  };
  try {
    delete require.cache[require.resolve(mainPath)];
    return require(mainPath);
  } finally {
    Module._load = originalLoad;
  }
}

module.exports = { fakeContext, createFakeVscode, loadExtension, Uri };
