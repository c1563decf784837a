// The VS Code extension against a real `gloc lsp`: "Show compiled GLOC" on the paper's Fig. 3
// must show its Fig. 2, and a program with errors must get an explanation instead.
// VS Code itself cannot run here (it is downloaded at test time), so the extension runs against
// the stand-in in helpers/fake-vscode.cjs; everything it talks to is real.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { createProtocolConnection, StreamMessageReader, StreamMessageWriter } from 'vscode-languageserver-protocol/node';
import { fig2, fig3 } from './helpers/paper-figures.mjs';

const require = createRequire(import.meta.url);
const here = path.dirname(fileURLToPath(import.meta.url));
const extensionDir = path.resolve(here, '../../editors/vscode');
const manifest = JSON.parse(fs.readFileSync(path.join(extensionDir, 'package.json'), 'utf8'));
const { createFakeVscode, fakeContext, loadExtension } = require('./helpers/fake-vscode.cjs');
const helpers = require(path.join(extensionDir, 'src/helpers.js'));
const glocBin = process.env.GLOC_BIN || path.resolve(here, '../../target/debug/gloc');

function workspaceWith(files) {
  const workspace = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-live-'));
  for (const [name, text] of Object.entries(files)) {
    fs.writeFileSync(path.join(workspace, name), text);
  }
  return workspace;
}

test('the gloc binary exists (GLOC_BIN)', () => {
  assert.ok(fs.existsSync(glocBin), `${glocBin} is missing: cargo build -p gloc`);
});

test('Show compiled GLOC on the paper\'s Fig. 3 shows Fig. 2, through a real gloc lsp', async () => {
  const workspace = workspaceWith({ 'fig3.gbas': fig3, 'broken.gbas': 'x = 1\nyield\n' });
  const server = spawn(glocBin, ['lsp'], { cwd: workspace, stdio: ['pipe', 'pipe', 'inherit'] });
  const connection = createProtocolConnection(new StreamMessageReader(server.stdout), new StreamMessageWriter(server.stdin));
  connection.listen();
  try {
    await connection.sendRequest('initialize', {
      processId: process.pid,
      rootUri: pathToFileURL(workspace).href,
      capabilities: {},
      initializationOptions: {},
    });
    await connection.sendNotification('initialized', {});
    const documents = {};
    for (const name of ['fig3.gbas', 'broken.gbas']) {
      const file = path.join(workspace, name);
      documents[file] = { languageId: 'gbasic', text: fs.readFileSync(file, 'utf8') };
      await connection.sendNotification('textDocument/didOpen', {
        textDocument: { uri: pathToFileURL(file).href, languageId: 'gbasic', version: 1, text: documents[file].text },
      });
    }

    // The extension, its requests forwarded to the real server.
    const fakes = createFakeVscode({
      workspace,
      settings: { 'gloc.path': glocBin },
      activeFile: path.join(workspace, 'fig3.gbas'),
      documents,
      onRequest: (method, params) => connection.sendRequest(method, params),
    });
    const extension = loadExtension(path.join(extensionDir, manifest.main), fakes);
    await extension.activate(fakeContext());
    // The fake URIs print as file:///…; the server knows the documents by pathToFileURL, which
    // is the same string for these plain temporary paths.
    await fakes.record.commands.get('gloc.showCompiledGloc')();
    const shown = fakes.record.shown.at(-1);
    assert.equal(shown.document.languageId, 'gloc');
    const provider = fakes.record.contentProviders.get(helpers.COMPILED_SCHEME);
    const text = await provider.provideTextDocumentContent(shown.document.uri);
    assert.equal(text.replace(/\n?$/, '\n'), fig2, 'Fig. 3 compiles to the paper\'s Fig. 2');

    // A program with errors: the view explains instead of showing GLOC.
    await fakes.record.commands.get('gloc.showCompiledGloc')(fakes.vscode.Uri.file(path.join(workspace, 'broken.gbas')));
    const brokenText = await provider.provideTextDocumentContent(fakes.record.shown.at(-1).document.uri);
    assert.match(brokenText, /^# broken\.gbas: .*error/m);
    assert.ok(brokenText.split('\n').every((line) => line === '' || line.startsWith('#')), 'only GLOC comments');
    await extension.deactivate();

    await connection.sendRequest('shutdown');
    await connection.sendNotification('exit');
  } finally {
    connection.dispose();
    server.kill();
  }
});

// VS Code's built-in semantic token types and modifiers; anything else must be contributed.
const standardTokenTypes = ['namespace', 'class', 'enum', 'interface', 'struct', 'typeParameter', 'type', 'parameter', 'variable', 'property', 'enumMember', 'decorator', 'event', 'function', 'method', 'macro', 'label', 'comment', 'string', 'keyword', 'number', 'regexp', 'operator'];
const standardTokenModifiers = ['declaration', 'definition', 'readonly', 'static', 'deprecated', 'abstract', 'async', 'modification', 'documentation', 'defaultLibrary'];

test('every semantic token type and modifier gloc lsp uses is known to VS Code or contributed', async () => {
  const workspace = workspaceWith({});
  const server = spawn(glocBin, ['lsp'], { cwd: workspace, stdio: ['pipe', 'pipe', 'inherit'] });
  const connection = createProtocolConnection(new StreamMessageReader(server.stdout), new StreamMessageWriter(server.stdin));
  connection.listen();
  try {
    const result = await connection.sendRequest('initialize', { processId: process.pid, rootUri: null, capabilities: {} });
    const legend = result.capabilities.semanticTokensProvider?.legend;
    assert.ok(legend, 'gloc lsp offers semantic tokens');
    const contributedTypes = (manifest.contributes.semanticTokenTypes || []).map((type) => type.id);
    const contributedModifiers = (manifest.contributes.semanticTokenModifiers || []).map((modifier) => modifier.id);
    for (const type of legend.tokenTypes) {
      assert.ok(standardTokenTypes.includes(type) || contributedTypes.includes(type), `token type ${type}`);
    }
    for (const modifier of legend.tokenModifiers) {
      assert.ok(standardTokenModifiers.includes(modifier) || contributedModifiers.includes(modifier), `token modifier ${modifier}`);
    }
    // The scope mappings name only types and modifiers that exist.
    for (const mapping of manifest.contributes.semanticTokenScopes) {
      for (const selector of Object.keys(mapping.scopes)) {
        const [type, ...modifiers] = selector.split('.');
        assert.ok(legend.tokenTypes.includes(type), `${selector}: the server uses ${type}`);
        for (const modifier of modifiers) {
          assert.ok(legend.tokenModifiers.includes(modifier), `${selector}: the server uses ${modifier}`);
        }
      }
    }
    await connection.sendRequest('shutdown');
    await connection.sendNotification('exit');
  } finally {
    connection.dispose();
    server.kill();
  }
});
