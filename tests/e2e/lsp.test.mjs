// End-to-end tests of `gloc lsp` with the protocol layer VS Code itself uses
// (vscode-languageserver-protocol / vscode-jsonrpc), over the real binary's stdio.
// Positions are checked against JavaScript strings, which are UTF-16 like LSP.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import {
  createProtocolConnection,
  StreamMessageReader,
  StreamMessageWriter,
} from 'vscode-languageserver-protocol/node';

const GLOC_BIN = process.env.GLOC_BIN;
if (!GLOC_BIN) throw new Error('GLOC_BIN must name the gloc binary (tests/e2e/run sets it)');

const FIG3 = [
  'label: state1', 'if m_depth > 15.0 then', '  SCI_RUHP_BEHS = 128', '  goto state2', 'endif',
  'yield', 'goto state1', 'label: state2', 'if m_depth < 5.0 then', '  SCI_RUHP_BEHS = 0',
  '  goto state3', 'endif', 'yield', 'goto state2', 'label: state3', 'yield', 'goto state3', '',
].join('\n');

const FIG2 = [
  'nregs 8', 'nblbs 7', 'ninstr 27', 'label 0', 'loads 444,r0', 'loadd 15.0,r1', 'cmpgt r0,r1,r2',
  'cbr r2,3,4', 'label 3', 'loadi 128,r3', 'stores r3,1387', 'jumpi 1', 'label 4', 'yield', 'jumpi 0',
  'label 1', 'loads 444,r4', 'loadd 5.0,r5', 'cmplt r4,r5,r6', 'cbr r6,5,6', 'label 5', 'loadi 0,r7',
  'stores r7,1387', 'jumpi 2', 'label 6', 'yield', 'jumpi 1', 'label 2', 'yield', 'jumpi 2', '',
].join('\n');

/** Starts the server and returns a connection plus helpers. */
async function start() {
  const child = spawn(GLOC_BIN, ['lsp'], { stdio: ['pipe', 'pipe', 'inherit'] });
  const exited = new Promise((resolve) => child.on('exit', (code) => resolve(code)));
  const connection = createProtocolConnection(
    new StreamMessageReader(child.stdout),
    new StreamMessageWriter(child.stdin),
  );
  const published = new Map(); // uri -> list of params, in arrival order
  const waiters = [];
  connection.onNotification('textDocument/publishDiagnostics', (params) => {
    if (!published.has(params.uri)) published.set(params.uri, []);
    published.get(params.uri).push(params);
    for (const waiter of [...waiters]) waiter();
  });
  connection.listen();
  const init = await connection.sendRequest('initialize', {
    processId: process.pid,
    rootUri: null,
    // Markdown hover as VS Code asks for it (the server sends plain text to a client that
    // does not list markdown).
    capabilities: {
      general: { positionEncodings: ['utf-16'] },
      textDocument: { hover: { contentFormat: ['markdown', 'plaintext'] } },
    },
  });
  await connection.sendNotification('initialized', {});
  /** Waits for diagnostics of `uri` with `version` (or any, when undefined). */
  function diagnostics(uri, version) {
    return new Promise((resolve, reject) => {
      const timer = setTimeout(() => reject(new Error(`no diagnostics for ${uri} v${version}`)), 10000);
      const check = () => {
        const found = (published.get(uri) || []).find((p) => version === undefined || p.version === version);
        if (found) {
          clearTimeout(timer);
          waiters.splice(waiters.indexOf(check), 1);
          resolve(found);
        }
      };
      waiters.push(check);
      check();
    });
  }
  async function stop() {
    await connection.sendRequest('shutdown');
    await connection.sendNotification('exit');
    const code = await exited;
    connection.dispose();
    return code;
  }
  return { connection, init, diagnostics, stop, child };
}

test('a GBASIC session: diagnostics, completion, hover, definition, rename, compiled GLOC', async () => {
  const { connection, init, diagnostics, stop } = await start();
  assert.equal(init.capabilities.positionEncoding, 'utf-16');
  assert.equal(init.capabilities.textDocumentSync.change, 2);
  const uri = 'file:///e2e/fig3.gbas';
  await connection.sendNotification('textDocument/didOpen', {
    textDocument: { uri, languageId: 'gbasic', version: 1, text: FIG3 },
  });
  assert.deepEqual((await diagnostics(uri, 1)).diagnostics, []);

  const completion = await connection.sendRequest('textDocument/completion', {
    textDocument: { uri }, position: { line: 3, character: 9 },
  });
  assert.deepEqual(completion.items.map((item) => item.label), ['state1', 'state2', 'state3']);

  const hover = await connection.sendRequest('textDocument/hover', {
    textDocument: { uri }, position: { line: 1, character: 5 },
  });
  assert.match(hover.contents.value, /^\*\*m_depth\*\* \(m\)\n\nsensor 444 · read-only/);

  const definition = await connection.sendRequest('textDocument/definition', {
    textDocument: { uri }, position: { line: 13, character: 7 },
  });
  assert.deepEqual(definition.range, { start: { line: 7, character: 7 }, end: { line: 7, character: 13 } });

  const rename = await connection.sendRequest('textDocument/rename', {
    textDocument: { uri }, position: { line: 7, character: 8 }, newName: 'climb',
  });
  assert.equal(rename.changes[uri].length, 3);

  const gloc = await connection.sendRequest('workspace/executeCommand', {
    command: 'gloc.compiledGloc', arguments: [uri],
  });
  assert.equal(gloc, FIG2);
  assert.equal(await stop(), 0, 'exit code 0 after shutdown and exit');
});

/** Applies an LSP edit to a JS string (UTF-16 offsets, as LSP counts). */
function applyEdit(text, range, newText) {
  const lines = text.split('\n');
  const offset = ({ line, character }) =>
    lines.slice(0, line).reduce((sum, l) => sum + l.length + 1, 0) + character;
  return text.slice(0, offset(range.start)) + newText + text.slice(offset(range.end));
}

/** The UTF-16 position of the first `needle` in `text`. */
function positionOf(text, needle) {
  const index = text.indexOf(needle);
  assert.ok(index >= 0, `${needle} in text`);
  const before = text.slice(0, index).split('\n');
  return { line: before.length - 1, character: before[before.length - 1].length };
}

test('incremental edits with non-ASCII text keep UTF-16 positions right', async () => {
  const { connection, diagnostics, stop } = await start();
  const uri = 'file:///e2e/umlaut.gbas';
  let text = 'dim zähler as integer\nprint "Zürich 𝄞", zähler\nyield\n';
  // `zähler` is not a valid GBASIC name: the first diagnostic is on it.
  await connection.sendNotification('textDocument/didOpen', {
    textDocument: { uri, languageId: 'gbasic', version: 1, text },
  });
  await diagnostics(uri, 1);

  // Replace the whole program piece by piece with edits whose ranges sit after
  // multi-unit characters, checking the server's view after each.
  const replace = (needle, newText) => (current) => {
    const at = positionOf(current, needle);
    return { range: { start: at, end: { line: at.line, character: at.character + needle.length } }, text: newText };
  };
  const insertAfter = (needle, newText) => (current) => {
    const at = positionOf(current, needle);
    const end = needle.endsWith('\n')
      ? { line: at.line + 1, character: 0 }
      : { line: at.line, character: at.character + needle.length };
    return { range: { start: end, end }, text: newText };
  };
  const edits = [
    replace('zähler', 'count'),
    replace('zähler', 'count'),
    // Right after '𝄞', which is two UTF-16 units.
    insertAfter('𝄞', ' ✓'),
    // A new line that uses an undeclared name after non-ASCII text.
    insertAfter('count\n', 'print "ü𝄞é", missing\n'),
  ];
  let version = 1;
  for (const makeEdit of edits) {
    version += 1;
    const edit = makeEdit(text);
    text = applyEdit(text, edit.range, edit.text);
    await connection.sendNotification('textDocument/didChange', {
      textDocument: { uri, version }, contentChanges: [edit],
    });
  }
  assert.equal(text, 'dim count as integer\nprint "Zürich 𝄞 ✓", count\nprint "ü𝄞é", missing\nyield\n');
  const published = await diagnostics(uri, version);
  assert.equal(published.diagnostics.length, 1, JSON.stringify(published.diagnostics));
  const [problem] = published.diagnostics;
  assert.equal(problem.code, 'E2101');
  const missingAt = positionOf(text, 'missing');
  assert.deepEqual(problem.range, { start: missingAt, end: { line: missingAt.line, character: missingAt.character + 7 } });

  // Hover right after the surrogate pair lands on `count`.
  const hover = await connection.sendRequest('textDocument/hover', {
    textDocument: { uri }, position: positionOf(text, 'count\nprint'),
  });
  assert.match(hover.contents.value, /^variable `count`: dim count as integer/);

  // Fix it; no diagnostics remain, and the compiled GLOC prints the edited text.
  version += 1;
  const fix = { range: { start: positionOf(text, 'missing'), end: { ...positionOf(text, 'missing'), character: positionOf(text, 'missing').character + 7 } }, text: 'count' };
  text = applyEdit(text, fix.range, fix.text);
  await connection.sendNotification('textDocument/didChange', { textDocument: { uri, version }, contentChanges: [fix] });
  assert.deepEqual((await diagnostics(uri, version)).diagnostics, []);
  const gloc = await connection.sendRequest('workspace/executeCommand', { command: 'gloc.compiledGloc', arguments: [uri] });
  assert.match(gloc, /prints "ü𝄞é"|writes "ü𝄞é"/);
  assert.equal(await stop(), 0);
});

test('a GLOC session: sensor index hover and inlay hints, malformed input survives', async () => {
  const { connection, diagnostics, stop, child } = await start();
  const uri = 'file:///e2e/fig2.gloc';
  await connection.sendNotification('textDocument/didOpen', {
    textDocument: { uri, languageId: 'gloc', version: 1, text: FIG2 },
  });
  assert.deepEqual((await diagnostics(uri, 1)).diagnostics, []);
  // A broken frame from a misbehaving client does not end the session.
  child.stdin.write('Content-Length: 9\r\n\r\n{ broken ');
  const hover = await connection.sendRequest('textDocument/hover', {
    textDocument: { uri }, position: { line: 4, character: 7 },
  });
  assert.match(hover.contents.value, /^\*\*m_depth\*\*/);
  const hints = await connection.sendRequest('textDocument/inlayHint', {
    textDocument: { uri }, range: { start: { line: 0, character: 0 }, end: { line: 30, character: 0 } },
  });
  const labels = hints.map((hint) => hint.label);
  assert.ok(labels.includes(':m_depth') && labels.includes(':sci_ruhp_behs'), labels.join(' | '));
  assert.ok(labels.includes('first cycle ≤ 15 instr'), labels.join(' | '));
  assert.equal(await stop(), 0);
});
