// TextMate grammar tests of the VS Code extension, run with vscode-tmgrammar-test (the
// vscode-textmate engine VS Code uses) over editors/vscode/test/syntax: keywords, sensors,
// registers, labels, numbers, strings and comments in GBASIC and GLOC.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const extensionDir = path.resolve(here, '../../editors/vscode');
const syntaxDir = path.join(extensionDir, 'test/syntax');
const tool = path.join(here, 'node_modules/.bin/vscode-tmgrammar-test');

function runGrammarTest(pattern) {
  return spawnSync(tool, ['--config', path.join(extensionDir, 'package.json'), pattern], {
    cwd: extensionDir,
    encoding: 'utf8',
  });
}

test('the grammar test tool is installed (tests/e2e/setup)', () => {
  assert.ok(fs.existsSync(tool), `${tool} is missing: run tests/e2e/setup`);
});

for (const [language, file] of [
  ['GBASIC', 'gbasic.test.gbas'],
  ['GLOC', 'gloc.test.gloc'],
  ['Slocum mission', 'mission.test.mi'],
  ['Slocum mission arguments', 'args.test.ma'],
]) {
  test(`${language} scopes match the assertions in test/syntax/${file}`, () => {
    const result = runGrammarTest(path.join(syntaxDir, file));
    assert.equal(result.status, 0, `vscode-tmgrammar-test failed:\n${result.stdout}\n${result.stderr}`);
    assert.match(result.stdout, /run successfu/);
  });
}

// The fixtures must cover every kind of token the issue names; a fixture that lost its sensor or
// register assertions would pass silently otherwise.
const requiredScopes = {
  'gbasic.test.gbas': [
    'keyword.control.conditional.gbasic',
    'keyword.control.loop.gbasic',
    'keyword.declaration.dim.gbasic',
    'support.variable.sensor.gbasic',
    'support.variable.sensor.readonly.gbasic',
    'entity.name.label.gbasic',
    'constant.numeric.integer.decimal.gbasic',
    'constant.numeric.float.gbasic',
    'string.quoted.double.gbasic',
    'comment.line.apostrophe.gbasic',
    'comment.line.rem.gbasic',
    'support.function.builtin.gbasic',
  ],
  'gloc.test.gloc': [
    'keyword.other.directive.header.gloc',
    'keyword.other.instruction.gloc',
    'keyword.control.gloc',
    'variable.other.register.gloc',
    'variable.other.sensor.gloc',
    'entity.name.label.gloc',
    'constant.numeric.integer.decimal.gloc',
    'constant.numeric.float.gloc',
    'string.quoted.double.gloc',
    'comment.line.number-sign.gloc',
  ],
  'mission.test.mi': [
    'keyword.other.sensor.slocum_mission',
    'support.variable.sensor.slocum_mission',
    'keyword.other.behavior.slocum_mission',
    'entity.name.function.behavior.slocum_mission',
    'keyword.other.b-arg.slocum_mission',
    'variable.parameter.argument.slocum_mission',
    'support.type.units.slocum_mission',
    'constant.numeric.slocum_mission',
    'comment.line.number-sign.slocum_mission',
  ],
  'args.test.ma': [
    'keyword.other.behavior-name.slocum_ma',
    'entity.name.function.behavior.slocum_ma',
    'keyword.control.section.slocum_ma',
    'keyword.other.b-arg.slocum_ma',
    'variable.parameter.argument.slocum_ma',
    'support.type.units.slocum_ma',
    'constant.numeric.slocum_ma',
    'constant.numeric.longitude.slocum_ma',
    'comment.line.number-sign.slocum_ma',
  ],
};

for (const [file, scopes] of Object.entries(requiredScopes)) {
  test(`test/syntax/${file} asserts every kind of token`, () => {
    const text = fs.readFileSync(path.join(syntaxDir, file), 'utf8');
    const asserted = new Set(
      text
        .split('\n')
        .filter((line) => /^\s*['#]\s*(\^|<-)/.test(line))
        .flatMap((line) => line.replace(/^[^a-z]*/, '').split(/\s+/)),
    );
    for (const scope of scopes) {
      assert.ok(asserted.has(scope), `${file} has no assertion for ${scope}`);
    }
  });
}

test('a wrong scope assertion makes the grammar test fail', () => {
  // The same tool on a copy of the GLOC fixture where a register is claimed to be a label: it
  // must fail, or the tests above prove nothing.
  const directory = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-grammar-'));
  const broken = path.join(directory, 'broken.gloc');
  fs.writeFileSync(
    broken,
    ['# SYNTAX TEST "source.gloc" "deliberately wrong"', 'loads 444,r0', '#         ^^ entity.name.label.gloc', ''].join(
      '\n',
    ),
  );
  const result = runGrammarTest(broken);
  assert.notEqual(result.status, 0, 'vscode-tmgrammar-test accepted a wrong assertion');
  assert.match(result.stdout + result.stderr, /missing required scopes: entity\.name\.label\.gloc/);
});

// Every mnemonic and header word that docs/gloc.md documents is highlighted as a keyword, so the
// grammar follows the language as it grows. The expected scope per word is the grammar's
// category for it (control flow, sensor access, header, label, other instruction).
test('the GLOC grammar knows every mnemonic and header word of docs/gloc.md', () => {
  const doc = fs.readFileSync(path.resolve(here, '../../docs/gloc.md'), 'utf8');
  const words = [...new Set([...doc.matchAll(/^\| `([a-z][a-z0-9]*)[ `]/gm)].map((match) => match[1]))];
  assert.ok(words.length >= 40, `docs/gloc.md lists the header words and 39 mnemonics, found ${words.length}`);
  const scopeOf = (word) => {
    if (['nregs', 'nblbs', 'nlbls', 'ninstr', 'nmem'].includes(word)) return 'keyword.other.directive.header.gloc';
    if (word === 'label') return 'keyword.other.label.gloc';
    if (word === 'cbr') return 'keyword.control.branch.gloc';
    if (['jumpi', 'jump'].includes(word)) return 'keyword.control.jump.gloc';
    if (['yield', 'halt'].includes(word)) return 'keyword.control.gloc';
    if (['loads', 'stores'].includes(word)) return 'keyword.other.instruction.sensor.gloc';
    return 'keyword.other.instruction.gloc';
  };
  const lines = ['# SYNTAX TEST "source.gloc" "every word of docs/gloc.md"'];
  for (const word of words) {
    lines.push(word, `# <${'-'.repeat(word.length)} ${scopeOf(word)}`);
    lines.push(word.toUpperCase(), `# <${'-'.repeat(word.length)} ${scopeOf(word)}`);
  }
  const directory = fs.mkdtempSync(path.join(os.tmpdir(), 'gloc-grammar-'));
  const file = path.join(directory, 'mnemonics.gloc');
  fs.writeFileSync(file, `${lines.join('\n')}\n`);
  const result = runGrammarTest(file);
  assert.equal(result.status, 0, `a documented word is not highlighted:\n${result.stdout}\n${result.stderr}`);
});
