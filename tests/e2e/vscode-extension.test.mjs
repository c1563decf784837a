// Tests of the VS Code extension (editors/vscode): its package.json contributions are consistent
// with each other and with the files they name, `vsce package` builds a .vsix offline that holds
// the grammars, and the extension wires the commands, the language client and the debugger to
// the gloc binary.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const require = createRequire(import.meta.url);
const here = path.dirname(fileURLToPath(import.meta.url));
const extensionDir = path.resolve(here, '../../editors/vscode');
const manifest = JSON.parse(fs.readFileSync(path.join(extensionDir, 'package.json'), 'utf8'));
const contributes = manifest.contributes;
const languageIds = contributes.languages.map((language) => language.id);
// The script languages: the ones the debugger flies and breakpoints go in (not mission files).
const scriptLanguageIds = ['gbasic', 'gloc'];
const { createFakeVscode, fakeContext, loadExtension } = require('./helpers/fake-vscode.cjs');
const helpers = require(path.join(extensionDir, 'src/helpers.js'));

// The launch attributes `gloc dap` accepts (issue 6 and /work/coord/api-dap.md).
const launchAttributes = [
  'program',
  'mission',
  'masterdata',
  'profile',
  'seed',
  'stopOnEntry',
  'cycleBudget',
  'maxCycles',
  'history',
  'replay',
  'sensorCache',
  'token',
];

function readJson(relativePath) {
  const file = path.join(extensionDir, relativePath);
  assert.ok(fs.existsSync(file), `${relativePath} is named in package.json but does not exist`);
  return JSON.parse(fs.readFileSync(file, 'utf8'));
}

// --- package.json consistency ---------------------------------------------------------------

test('languages: gbasic (.gbas), gloc (.gloc), the mission files (.mi, .ma) and sensor lists (.cac, masterdata), each with a language configuration that loads', () => {
  assert.deepEqual(
    contributes.languages.map((language) => [language.id, language.extensions]),
    [
      ['gbasic', ['.gbas']],
      ['gloc', ['.gloc']],
      ['slocum_mission', ['.mi']],
      ['slocum_ma', ['.ma']],
      ['slocum_masterdata', ['.cac']],
    ],
  );
  assert.deepEqual(contributes.languages.find((language) => language.id === 'slocum_masterdata').filenames, ['masterdata']);
  for (const language of contributes.languages) {
    const configuration = readJson(language.configuration);
    assert.ok(configuration.comments.lineComment, `${language.id} has a line comment`);
    const wordPattern = new RegExp(configuration.wordPattern);
    assert.equal('sci_ruhp_behs = 1'.match(wordPattern)[0], 'sci_ruhp_behs', `${language.id}: a sensor name is one word`);
  }
});

test('gbasic indentation rules indent blocks and dedent their closing keywords', () => {
  const rules = readJson('language-configuration/gbasic.json').indentationRules;
  const increase = new RegExp(rules.increaseIndentPattern.pattern, rules.increaseIndentPattern.flags);
  const decrease = new RegExp(rules.decreaseIndentPattern.pattern, rules.decreaseIndentPattern.flags);
  for (const line of ['if m_depth > 15.0 then', "  If x Then ' note", 'elseif x then', 'else', 'while x < 3', 'do', 'do until x', 'for i = 0 to 9']) {
    assert.ok(increase.test(line), `indents after: ${line}`);
  }
  for (const line of ['if x then goto s2', 'yield', 'label: state1', 'done = 1', 'format = 2', 'endif']) {
    assert.ok(!increase.test(line), `does not indent after: ${line}`);
  }
  for (const line of ['endif', '  End If', 'else', 'elseif y then', 'wend', 'loop until x', 'next i']) {
    assert.ok(decrease.test(line), `dedents: ${line}`);
  }
  for (const line of ['end', 'nextstate = 1', 'if x then', 'endless = 1']) {
    assert.ok(!decrease.test(line), `does not dedent: ${line}`);
  }
});

test('grammars: one per language, scope names match the grammar files', () => {
  assert.deepEqual(contributes.grammars.map((grammar) => grammar.language).sort(), [...languageIds].sort());
  for (const grammar of contributes.grammars) {
    const file = readJson(grammar.path);
    assert.equal(file.scopeName, grammar.scopeName, `${grammar.path} declares ${grammar.scopeName}`);
    assert.equal(grammar.scopeName, `source.${grammar.language}`);
    for (const include of JSON.stringify(file).matchAll(/"include":"#([^"]+)"/g)) {
      assert.ok(file.repository[include[1]], `${grammar.path}: #${include[1]} is defined in the repository`);
    }
  }
});

test('snippets: valid JSON for declared languages, including the three shapes the issue asks for', () => {
  for (const snippet of contributes.snippets) {
    assert.ok(languageIds.includes(snippet.language));
    readJson(snippet.path);
  }
  const gbasic = readJson('snippets/gbasic.json');
  const bodies = Object.values(gbasic).map((snippet) => snippet.body.join('\n'));
  assert.ok(bodies.some((body) => /label: /.test(body) && /goto /.test(body) && /yield/.test(body)), 'a state machine');
  assert.ok(bodies.some((body) => /^dim .*\(.*\) as/m.test(body) && /^for .* to /m.test(body) && /^next/m.test(body)), 'a for loop over an array');
  const yo = bodies.find((body) => /sci_ruhp_behs = 64/.test(body));
  assert.ok(yo, 'a yo through the hook (dive with bit 64)');
  assert.match(yo, /sci_ruhp_behs = 128/, 'the yo climbs with bit 128');
  assert.match(yo, /sci_ruhp_dive_depth = /);
  assert.match(yo, /sci_ruhp_climb_depth = /);
  assert.match(yo, /sci_ruhp_behs = 0/, 'the yo hands control back to the mission');
});

test('configuration: gloc.path and gloc.masterdata are string settings', () => {
  const properties = contributes.configuration.properties;
  assert.equal(properties['gloc.path'].type, 'string');
  assert.equal(properties['gloc.path'].default, 'gloc');
  assert.equal(properties['gloc.masterdata'].type, 'string');
  assert.deepEqual(properties['gloc.trace.server'].enum, ['off', 'messages', 'verbose']);
});

test('debuggers: type gloc with exactly the launch attributes gloc dap accepts', () => {
  assert.equal(contributes.debuggers.length, 1);
  const debuggerContribution = contributes.debuggers[0];
  assert.equal(debuggerContribution.type, 'gloc');
  assert.deepEqual([...debuggerContribution.languages].sort(), [...scriptLanguageIds].sort());
  const launch = debuggerContribution.configurationAttributes.launch;
  assert.deepEqual(Object.keys(launch.properties).sort(), [...launchAttributes].sort());
  for (const [name, property] of Object.entries(launch.properties)) {
    const types = [property.type].flat();
    assert.ok(types.length > 0 && types.every((type) => ['string', 'integer', 'boolean', 'array'].includes(type)), `${name} has a type`);
    if (types.includes('array')) {
      assert.equal(property.items?.type, 'string', `${name}: a list of strings`);
    }
    assert.ok(property.description, `${name} has a description for launch.json completion`);
  }
  for (const required of launch.required) {
    assert.ok(launch.properties[required], `required attribute ${required} is declared`);
  }
  const configurations = [
    ...debuggerContribution.initialConfigurations,
    ...debuggerContribution.configurationSnippets.map((snippet) => snippet.body),
  ];
  assert.ok(debuggerContribution.initialConfigurations.length > 0);
  for (const configuration of configurations) {
    assert.equal(configuration.type, 'gloc');
    assert.equal(configuration.request, 'launch');
    for (const key of Object.keys(configuration)) {
      assert.ok(['type', 'request', 'name'].includes(key) || launch.properties[key], `${configuration.name}: ${key} is declared`);
    }
    for (const required of launch.required) {
      assert.ok(configuration[required] !== undefined, `${configuration.name}: has ${required}`);
    }
  }
});

test('breakpoints are allowed in both script languages', () => {
  assert.deepEqual(contributes.breakpoints.map((breakpoint) => breakpoint.language).sort(), [...scriptLanguageIds].sort());
});

test('commands: every menu entry names a declared command', () => {
  const declared = new Set(contributes.commands.map((command) => command.command));
  assert.ok(declared.has('gloc.showCompiledGloc'));
  assert.ok(declared.has('gloc.runMission'));
  for (const [menu, entries] of Object.entries(contributes.menus)) {
    for (const entry of entries) {
      assert.ok(declared.has(entry.command), `${menu}: ${entry.command} is declared`);
    }
  }
});

test('engines.vscode satisfies what vscode-languageclient needs; main exists', () => {
  const clientManifest = JSON.parse(
    fs.readFileSync(path.join(extensionDir, 'node_modules/vscode-languageclient/package.json'), 'utf8'),
  );
  assert.equal(clientManifest.version, '9.0.1');
  assert.equal(manifest.engines.vscode, clientManifest.engines.vscode);
  assert.ok(fs.existsSync(path.join(extensionDir, manifest.main)));
  for (const event of manifest.activationEvents) {
    const [kind, argument] = event.split(':');
    if (kind === 'onLanguage') {
      assert.ok(languageIds.includes(argument), `${event} names a declared language`);
    } else if (kind.startsWith('onDebug')) {
      assert.equal(argument, 'gloc', `${event} names the gloc debugger`);
    }
  }
});

test('activation: the extension starts on every language it serves, and serves every language it declares', () => {
  for (const language of helpers.SERVED_LANGUAGE_IDS) {
    assert.ok(manifest.activationEvents.includes(`onLanguage:${language}`), `onLanguage:${language}`);
  }
  assert.deepEqual([...helpers.SERVED_LANGUAGE_IDS].sort(), [...languageIds].sort());
});

// --- vsce package -----------------------------------------------------------------------------

/** The entries of a zip archive, read from its central directory: name → contents (Buffer). */
function zipEntries(file) {
  const data = fs.readFileSync(file);
  let end = data.length - 22;
  while (end >= 0 && data.readUInt32LE(end) !== 0x06054b50) {
    end -= 1;
  }
  assert.ok(end >= 0, `${file} is not a zip archive`);
  const count = data.readUInt16LE(end + 10);
  let offset = data.readUInt32LE(end + 16);
  const entries = new Map();
  for (let index = 0; index < count; index += 1) {
    assert.equal(data.readUInt32LE(offset), 0x02014b50, 'central directory entry');
    const method = data.readUInt16LE(offset + 10);
    const compressedSize = data.readUInt32LE(offset + 20);
    const nameLength = data.readUInt16LE(offset + 28);
    const extraLength = data.readUInt16LE(offset + 30);
    const commentLength = data.readUInt16LE(offset + 32);
    const localHeader = data.readUInt32LE(offset + 42);
    const name = data.toString('utf8', offset + 46, offset + 46 + nameLength);
    const start = localHeader + 30 + data.readUInt16LE(localHeader + 26) + data.readUInt16LE(localHeader + 28);
    const raw = data.subarray(start, start + compressedSize);
    entries.set(name, () => (method === 8 ? zlib.inflateRawSync(raw) : raw));
    offset += 46 + nameLength + extraLength + commentLength;
  }
  return entries;
}

test('vsce package builds a .vsix offline with grammars, configurations, snippets and the client', () => {
  const vsce = path.join(extensionDir, 'node_modules/.bin/vsce');
  assert.ok(fs.existsSync(vsce), `${vsce} is missing: run tests/e2e/setup (npm ci in editors/vscode)`);
  const out = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-vsix-')), 'gloc.vsix');
  const result = spawnSync(vsce, ['package', '--allow-missing-repository', '--out', out], {
    cwd: extensionDir,
    encoding: 'utf8',
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  assert.equal(result.status, 0, `vsce package failed:\n${result.stdout}\n${result.stderr}`);
  assert.ok(fs.existsSync(out), 'the .vsix exists');
  const entries = zipEntries(out);
  for (const name of [
    'extension/package.json',
    'extension/src/extension.js',
    'extension/src/helpers.js',
    'extension/syntaxes/gbasic.tmLanguage.json',
    'extension/syntaxes/gloc.tmLanguage.json',
    'extension/language-configuration/gbasic.json',
    'extension/language-configuration/gloc.json',
    'extension/snippets/gbasic.json',
    'extension/snippets/gloc.json',
    'extension/node_modules/vscode-languageclient/package.json',
    'extension/node_modules/vscode-languageclient/lib/node/main.js',
    'extension.vsixmanifest',
  ]) {
    assert.ok(entries.has(name), `${name} is in the .vsix`);
  }
  for (const name of entries.keys()) {
    assert.ok(!name.startsWith('extension/test/'), `test files stay out of the .vsix: ${name}`);
    assert.ok(!name.startsWith('extension/node_modules/@vscode/vsce'), `dev dependencies stay out: ${name}`);
  }
  // The packaged manifest is the one tested above.
  const packed = JSON.parse(entries.get('extension/package.json')().toString('utf8'));
  assert.deepEqual(packed.contributes, contributes);
  const grammar = JSON.parse(entries.get('extension/syntaxes/gbasic.tmLanguage.json')().toString('utf8'));
  assert.equal(grammar.scopeName, 'source.gbasic');
});

// --- the extension's glue, driven through a stand-in VS Code ---------------------------------

/** An executable stand-in for the gloc binary at `file` (the extension checks that it exists). */
function fakeBinary(file) {
  fs.mkdirSync(path.dirname(file), { recursive: true });
  fs.writeFileSync(file, '#!/bin/sh\nexit 0\n', { mode: 0o755 });
  return file;
}

function activateWithFakes(options) {
  const fakes = createFakeVscode(options);
  const extension = loadExtension(path.join(extensionDir, manifest.main), fakes);
  return { fakes, extension, record: fakes.record };
}

test('activate registers every contributed command, the debugger and the compiled-GLOC view', async () => {
  const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-ws-'));
  const binary = fakeBinary(path.join(workspace, 'bin/gloc'));
  const { fakes, extension, record } = activateWithFakes({
    workspace,
    // A relative gloc.path is taken from the workspace folder.
    settings: { 'gloc.path': 'bin/gloc', 'gloc.masterdata': 'data/masterdata' },
  });
  await extension.activate(fakeContext());
  assert.deepEqual(
    [...record.commands.keys()].sort(),
    contributes.commands.map((command) => command.command).sort(),
  );
  assert.ok(record.debugFactories.has('gloc'));
  assert.ok(record.debugProviders.has('gloc'));
  assert.ok(record.contentProviders.has(helpers.COMPILED_SCHEME));

  // The language client starts `gloc lsp` from gloc.path, for the scripts and the mission files, with the masterdata.
  assert.equal(record.clients.length, 1);
  const client = record.clients[0];
  assert.equal(client.id, 'gloc', 'client id gloc makes gloc.trace.server work');
  assert.deepEqual([client.serverOptions.command, client.serverOptions.args], [binary, ['lsp']]);
  assert.equal(client.serverOptions.transport, undefined, 'no --stdio argument is added');
  assert.deepEqual(
    [...new Set(client.clientOptions.documentSelector.map((selector) => selector.language))].sort(),
    ['gbasic', 'gloc', 'slocum_ma', 'slocum_masterdata', 'slocum_mission'],
  );
  assert.ok(client.clientOptions.documentSelector.every((selector) => ['file', 'untitled'].includes(selector.scheme)));
  assert.deepEqual(client.clientOptions.initializationOptions, { masterdata: path.join(workspace, 'data/masterdata') });
  // The client tells the server it runs the "Run" and "Debug" code lens commands.
  const capabilities = {};
  client.features.forEach((feature) => feature.fillClientCapabilities(capabilities));
  assert.deepEqual(capabilities.experimental, { commands: { commands: ['gloc.runMission', 'gloc.debugScript'] } });
  // The "Debug" lens passes the script's URI as a string: the debugger starts on that file.
  await record.commands.get('gloc.debugScript')('file:///ws/missions/a.gbas');
  assert.deepEqual(record.debugStarts.map((start) => start.configuration), [
    { type: 'gloc', request: 'launch', name: 'Debug a.gbas', program: '/ws/missions/a.gbas' },
  ]);

  // The debugger runs `gloc dap`.
  const descriptor = record.debugFactories.get('gloc').createDebugAdapterDescriptor({ workspaceFolder: undefined });
  assert.deepEqual([descriptor.command, descriptor.args], [binary, ['dap']]);

  // gloc.masterdata applies live: no new server, a didChangeConfiguration, and the server's
  // workspace/configuration request answered with the resolved path.
  fakes.settings['gloc.masterdata'] = '~/other.cac';
  fakes.fireConfigurationChange(['gloc', 'gloc.masterdata']);
  assert.equal(record.clients.length, 1, 'a masterdata change does not restart the server');
  assert.deepEqual(client.notifications, [{ method: 'workspace/didChangeConfiguration', params: { settings: null } }]);
  const answer = await client.clientOptions.middleware.workspace.configuration(
    { items: [{ section: 'gloc' }] },
    undefined,
    () => [{ path: 'bin/gloc', masterdata: '~/other.cac' }],
  );
  assert.deepEqual(answer, [{ path: 'bin/gloc', masterdata: path.join(os.homedir(), 'other.cac') }]);
  // A new binary needs a new server.
  fakes.settings['gloc.path'] = binary;
  fakes.fireConfigurationChange(['gloc', 'gloc.path']);
  for (let waited = 0; record.clients.length < 2 && waited < 2000; waited += 20) {
    await new Promise((resolve) => setTimeout(resolve, 20));
  }
  assert.equal(record.clients.length, 2, 'a gloc.path change restarts the server');
  await extension.deactivate();
});

test('F5 without launch.json flies the active script; a configuration without program is refused', async () => {
  const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-ws-'));
  const script = path.join(workspace, 'fig3.gbas');
  const { extension, record } = activateWithFakes({
    workspace,
    activeFile: script,
    settings: { 'gloc.path': fakeBinary(path.join(workspace, 'gloc')) },
    documents: { [script]: { languageId: 'gbasic', text: 'yield\n' } },
  });
  await extension.activate(fakeContext());
  const provider = record.debugProviders.get('gloc');
  const resolved = await provider.resolveDebugConfiguration(undefined, {});
  assert.equal(resolved.type, 'gloc');
  assert.equal(resolved.request, 'launch');
  assert.equal(resolved.program, script);
  assert.equal(resolved.stopOnEntry, true);
  const refused = await provider.resolveDebugConfiguration(undefined, { type: 'gloc', request: 'launch', name: 'x' });
  assert.equal(refused, undefined);
  assert.match(record.messages.at(-1).text, /needs "program"/);
  await extension.deactivate();
});

test('Show compiled GLOC asks the server with workspace/executeCommand gloc.compiledGloc and opens it beside', async () => {
  const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-ws-'));
  const script = path.join(workspace, 'fig3.gbas');
  const { extension, record } = activateWithFakes({
    workspace,
    activeFile: script,
    settings: { 'gloc.path': fakeBinary(path.join(workspace, 'gloc')) },
    documents: { [script]: { languageId: 'gbasic', text: 'yield\n' } },
    onRequest: (method, params) => (method === 'workspace/executeCommand' ? 'nregs 0\n' : null),
  });
  await extension.activate(fakeContext());
  await record.commands.get('gloc.showCompiledGloc')();
  assert.equal(record.shown.length, 1);
  const { document, options } = record.shown[0];
  assert.equal(options.viewColumn, -2, 'beside the source');
  assert.equal(document.uri.scheme, helpers.COMPILED_SCHEME);
  assert.equal(document.languageId, 'gloc');
  const text = await record.contentProviders.get(helpers.COMPILED_SCHEME).provideTextDocumentContent(document.uri);
  assert.equal(text, 'nregs 0\n');
  assert.deepEqual(record.requests, [
    { method: 'workspace/executeCommand', params: { command: 'gloc.compiledGloc', arguments: [`file://${script}`] } },
  ]);
  await extension.deactivate();
});

test('an open compiled-GLOC view refreshes shortly after its GBASIC source changes', async () => {
  const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-ws-'));
  const script = path.join(workspace, 'fig3.gbas');
  const { fakes, extension, record } = activateWithFakes({
    workspace,
    activeFile: script,
    settings: { 'gloc.path': fakeBinary(path.join(workspace, 'gloc')) },
    documents: { [script]: { languageId: 'gbasic', text: 'yield\n' } },
    onRequest: () => 'nregs 0\n',
  });
  await extension.activate(fakeContext());
  await record.commands.get('gloc.showCompiledGloc')();
  const compiled = record.shown[0].document;
  const provider = record.contentProviders.get(helpers.COMPILED_SCHEME);
  const refreshed = [];
  provider.onDidChange((uri) => refreshed.push(uri.toString()));
  const source = fakes.documentFor(fakes.vscode.Uri.file(script));
  const notify = () => record.changeListeners.forEach((listener) => listener({ document: source }));

  notify(); // the view is not open yet in the editor: nothing to refresh
  await new Promise((resolve) => setTimeout(resolve, 400));
  assert.deepEqual(refreshed, []);

  fakes.vscode.workspace.textDocuments.push(compiled);
  notify();
  notify();
  notify(); // three quick edits: one refresh
  assert.deepEqual(refreshed, [], 'debounced, not at once');
  // The debounce is 300 ms; allow a loaded machine up to 3 s, then make sure no second one comes.
  for (let waited = 0; refreshed.length === 0 && waited < 3000; waited += 50) {
    await new Promise((resolve) => setTimeout(resolve, 50));
  }
  await new Promise((resolve) => setTimeout(resolve, 400));
  assert.deepEqual(refreshed, [compiled.uri.toString()]);
  await extension.deactivate();
});

test('a missing binary: one notification with a button to gloc.path, for the server, Run mission and F5', async () => {
  const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-ws-'));
  const script = path.join(workspace, 'fig3.gbas');
  fs.writeFileSync(script, 'yield\n');
  let dismiss;
  const { extension, record } = activateWithFakes({
    workspace,
    activeFile: script,
    settings: { 'gloc.path': path.join(workspace, 'no-such-gloc') },
    documents: { [script]: { languageId: 'gbasic', text: 'yield\n' } },
    // The notification stays on screen until the test dismisses it.
    choose: () => new Promise((resolve) => (dismiss = resolve)),
  });
  await extension.activate(fakeContext());
  assert.equal(record.clients.length, 0, 'no language client for a binary that is not there');
  const missing = () => record.messages.filter((entry) => entry.kind === 'error' && /was not found/.test(entry.text));
  assert.equal(missing().length, 1, JSON.stringify(record.messages));
  assert.match(missing()[0].text, /no-such-gloc/);
  assert.match(missing()[0].text, /gloc\.path/);
  assert.deepEqual(missing()[0].items, ['Open Settings']);
  // While it is on screen, Run mission and F5 add no second notification for the same cause.
  await record.commands.get('gloc.runMission')();
  const provider = record.debugProviders.get('gloc');
  assert.equal(await provider.resolveDebugConfiguration(undefined, {}), undefined, 'F5 starts nothing');
  assert.throws(() => record.debugFactories.get('gloc').createDebugAdapterDescriptor({ workspaceFolder: undefined }), /gloc\.path/);
  assert.equal(missing().length, 1, JSON.stringify(record.messages));
  // Dismissed: F5 says it again; its button opens the setting.
  dismiss(undefined);
  await new Promise((resolve) => setTimeout(resolve, 10));
  assert.equal(await provider.resolveDebugConfiguration(undefined, {}), undefined);
  assert.equal(missing().length, 2);
  dismiss('Open Settings');
  await new Promise((resolve) => setTimeout(resolve, 10));
  assert.deepEqual(record.executed.at(-1), { id: 'workbench.action.openSettings', args: ['gloc.path'] });
  await extension.deactivate();
});

// --- pure helpers ------------------------------------------------------------------------------

test('helpers: setting paths, run arguments and launch defaults', () => {
  assert.equal(helpers.resolveBinaryPath('', '/ws', '/home/u'), 'gloc');
  assert.equal(helpers.resolveBinaryPath('gloc', '/ws', '/home/u'), 'gloc', 'a bare name is looked up on PATH');
  assert.equal(helpers.resolveBinaryPath('target/release/gloc', '/ws', '/home/u'), '/ws/target/release/gloc');
  assert.equal(helpers.resolveBinaryPath('~/bin/gloc', '/ws', '/home/u'), '/home/u/bin/gloc');
  assert.equal(helpers.resolveSettingPath('  ', '/ws', '/home/u'), undefined);
  assert.equal(helpers.resolveSettingPath('/abs/md', '/ws', '/home/u'), '/abs/md');
  assert.deepEqual(helpers.runMissionArguments({ script: 'a.gbas', plot: '/t/a.svg' }), ['run', 'a.gbas', '--plot', '/t/a.svg', '--summary', 'json']);
  assert.deepEqual(helpers.runMissionArguments({ script: 'a.gbas', plot: 'p.svg', masterdata: 'm.cac' }), [
    'run',
    'a.gbas',
    '--plot',
    'p.svg',
    '--summary',
    'json',
    '--masterdata',
    'm.cac',
  ]);
  assert.deepEqual(helpers.completeLaunchConfiguration({}, { activeFile: 'x.txt', activeLanguage: 'plaintext' }).error !== undefined, true);
  const kept = helpers.completeLaunchConfiguration(
    { type: 'gloc', request: 'launch', name: 'n', program: 'p.gloc', masterdata: 'own' },
    { masterdata: 'setting' },
  );
  assert.equal(kept.configuration.masterdata, 'own', 'launch.json wins over the setting');
  const emptied = helpers.completeLaunchConfiguration(
    { type: 'gloc', request: 'launch', name: 'n', program: 'p.gloc', mission: '', masterdata: ' ', profile: '' },
    { masterdata: '/setting/md' },
  );
  assert.deepEqual(emptied.configuration, { type: 'gloc', request: 'launch', name: 'n', program: 'p.gloc', masterdata: '/setting/md' });
  // The JSON summary is the last line; warnings may come before it.
  assert.deepEqual(
    helpers.runSummary('warning: x\n{"mission_end":"completed at cycle 899 (1 h) at 0.4 m","script_state":"ran to the end of the run","trap_line":null}\n'),
    { headline: 'completed at cycle 899 (1 h) at 0.4 m', trapped: false },
  );
  assert.deepEqual(
    helpers.runSummary('{"mission_end":"still running","script_state":"TRAPPED at a.gbas:4: division by zero","trap_line":4}'),
    { headline: 'script TRAPPED at a.gbas:4: division by zero', trapped: true },
  );
  assert.equal(helpers.runSummary('mission end   completed at cycle 3\n'), undefined, 'text is not scraped');
});

test('helpers.locateBinary: PATH, then ~/.cargo/bin; paths relative to the workspace; what was searched', () => {
  const present = new Set(['/usr/bin/gloc', '/home/u/.cargo/bin/gloc', '/ws/target/release/gloc']);
  const context = (pathVariable, files = present) => ({
    workspaceFolder: '/ws',
    homeDirectory: '/home/u',
    pathVariable,
    isExecutable: (file) => files.has(file),
  });
  assert.deepEqual(helpers.locateBinary('gloc', context('/opt/x:/usr/bin')), { binary: '/usr/bin/gloc' });
  assert.deepEqual(helpers.locateBinary('', context('/usr/local/bin:/bin')), { binary: '/home/u/.cargo/bin/gloc' },
    'a login PATH without ~/.cargo/bin still finds cargo install\'s gloc');
  assert.deepEqual(helpers.locateBinary('target/release/gloc', context('')), { binary: '/ws/target/release/gloc' });
  assert.deepEqual(helpers.locateBinary('~/.cargo/bin/gloc', context('')), { binary: '/home/u/.cargo/bin/gloc' });
  assert.deepEqual(helpers.locateBinary('gloc', context('relative/dir:/bin', new Set())), {
    missing: 'gloc',
    searched: ['/bin', '/home/u/.cargo/bin'],
  });
  assert.deepEqual(helpers.locateBinary('/nope/gloc', context('/usr/bin')), { missing: '/nope/gloc', searched: ['/nope/gloc'] });
});