// The VS Code extension against the real simulator: "Run mission in simulator" through a real
// `gloc run`, and the debugger contribution's initial configuration through a real `gloc dap`.
// VS Code itself cannot run here (it is downloaded at test time), so the extension runs against
// the stand-in in helpers/fake-vscode.cjs; everything it talks to is real.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { DebugClient } from '@vscode/debugadapter-testsupport';
import { fig3 } from './helpers/paper-figures.mjs';
import { schemaChecker } from './helpers/dap-schema.mjs';

const require = createRequire(import.meta.url);
const here = path.dirname(fileURLToPath(import.meta.url));
const extensionDir = path.resolve(here, '../../editors/vscode');
const manifest = JSON.parse(fs.readFileSync(path.join(extensionDir, 'package.json'), 'utf8'));
const { createFakeVscode, fakeContext, loadExtension } = require('./helpers/fake-vscode.cjs');
const glocBin = process.env.GLOC_BIN || path.resolve(here, '../../target/debug/gloc');

// Every message `gloc dap` sends in these sessions is validated against the DAP schema, as in
// dap.test.mjs.
const schema = schemaChecker();
after(() => {
  // Each of the two sessions gets at least initialize's response, launch's, the initialized
  // and stopped events and configurationDone's: 5 messages each.
  assert.ok(schema.count >= 10, `only ${schema.count} messages were validated`);
  assert.deepEqual(schema.violations, [], 'messages that violate the DAP schema');
});

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

test('Run mission in simulator runs gloc run, shows its output and opens the flight profile', async () => {
  const workspace = workspaceWith({ 'fig3.gbas': fig3 });
  const script = path.join(workspace, 'fig3.gbas');
  const fakes = createFakeVscode({
    workspace,
    activeFile: script,
    settings: { 'gloc.path': glocBin },
    documents: { [script]: { languageId: 'gbasic', text: fig3 } },
  });
  const extension = loadExtension(path.join(extensionDir, manifest.main), fakes);
  await extension.activate(fakeContext());
  await fakes.record.commands.get('gloc.runMission')();
  const errors = fakes.record.messages.filter((message) => message.kind !== 'information');
  assert.deepEqual(errors, [], 'no error or warning');
  const notification = fakes.record.messages.find((message) => message.kind === 'information');
  assert.match(notification?.text ?? '', /^GLOC: fig3\.gbas: (completed|ABORTED|still running)/, 'the summary\'s mission end');
  const output = fakes.record.outputs.get('GLOC Run').text;
  assert.ok(output.startsWith(`$ ${glocBin} run ${script} --plot `), output);
  const opened = fakes.record.executed.find((command) => command.id === 'vscode.open');
  assert.ok(opened, 'the flight profile is opened');
  const plot = opened.args[0].fsPath;
  assert.match(plot, /fig3\.svg$/);
  assert.match(fs.readFileSync(plot, 'utf8'), /<svg/);
  assert.equal(opened.args[1].viewColumn, fakes.vscode.ViewColumn.Beside);
  await extension.deactivate();
});

test('F5 with the initial configuration starts gloc dap and stops on entry', async () => {
  const workspace = workspaceWith({ 'fig3.gbas': fig3 });
  const script = path.join(workspace, 'fig3.gbas');
  const fakes = createFakeVscode({
    workspace,
    activeFile: script,
    settings: { 'gloc.path': glocBin },
    documents: { [script]: { languageId: 'gbasic', text: fig3 } },
  });
  const extension = loadExtension(path.join(extensionDir, manifest.main), fakes);
  await extension.activate(fakeContext());
  const initial = manifest.contributes.debuggers[0].initialConfigurations[0];
  // VS Code substitutes ${file} after resolveDebugConfiguration; do the same.
  const resolved = await fakes.record.debugProviders.get('gloc').resolveDebugConfiguration(undefined, { ...initial });
  const launchArguments = JSON.parse(JSON.stringify(resolved).replaceAll('${file}', script));
  const descriptor = fakes.record.debugFactories.get('gloc').createDebugAdapterDescriptor({ workspaceFolder: undefined });
  assert.deepEqual(descriptor.args, ['dap']);
  const client = schema.validated(new DebugClient(descriptor.command, descriptor.args[0], 'gloc', { cwd: workspace }));
  client.defaultTimeout = 30000; // a debug build on a busy 2-core CI machine
  await client.start();
  try {
    await Promise.all([
      client.configurationSequence(),
      client.launch(launchArguments),
      client.assertStoppedLocation('entry', {}),
    ]);
  } finally {
    await client.stop();
  }
  await extension.deactivate();
});

test('gloc dap accepts a launch with every attribute package.json declares, each of its declared type', async () => {
  // A masterdata file with the embedded list's names in its order (so Fig. 3's indices hold), a
  // temperature profile, and the paper's Fig. 2 mission from examples/.
  const repo = path.resolve(here, '../..');
  const sensors = fs
    .readFileSync(path.join(repo, 'engine/data/sensors-2008.txt'), 'utf8')
    .split('\n')
    .filter((line) => line.trim() !== '')
    // Units do not matter here, and some hold spaces and parentheses: every unit is nodim.
    .map((line) => `sensor: ${line.split(/\s+/)[1]}(nodim) 0`);
  const workspace = workspaceWith({
    'fig3.gbas': fig3,
    masterdata: `${sensors.join('\n')}\n`,
    'profile.csv': 'depth_m,temp_degC\n0,24.0\n10,20.0\n20,12.0\n30,9.0\n',
    'depths.csv': 'm_depth\n1\n2\n3\n',
  });
  const properties = manifest.contributes.debuggers[0].configurationAttributes.launch.properties;
  const values = {
    program: path.join(workspace, 'fig3.gbas'),
    mission: path.join(repo, 'examples/fig2.mi'),
    masterdata: path.join(workspace, 'masterdata'),
    profile: path.join(workspace, 'profile.csv'),
    seed: 7,
    stopOnEntry: true,
    cycleBudget: 5000,
    maxCycles: 50,
    history: 100,
    // With `replay`, the recorded cycles stand in for the mission (which is then unused).
    replay: [path.join(workspace, 'depths.csv')],
    sensorCache: workspace,
  };
  // `token` belongs to `gloc dap --port` (the TCP tests launch with it); this session is on stdio.
  const declared = Object.keys(properties).filter((name) => name !== 'token');
  assert.deepEqual(Object.keys(values).sort(), declared.sort(), 'a value for every declared attribute');
  for (const [name, value] of Object.entries(values)) {
    const jsonType = Array.isArray(value) ? 'array' : typeof value === 'number' ? 'integer' : typeof value;
    assert.ok([properties[name].type].flat().includes(jsonType), `${name}: ${jsonType} is a declared type`);
  }
  const client = schema.validated(new DebugClient(glocBin, 'dap', 'gloc', { cwd: workspace }));
  client.defaultTimeout = 30000; // a debug build on a busy 2-core CI machine
  await client.start();
  try {
    await Promise.all([
      client.configurationSequence(),
      client.launch({ type: 'gloc', request: 'launch', name: 'all attributes', ...values }),
      client.assertStoppedLocation('entry', {}),
    ]);
  } finally {
    await client.stop();
  }
});
