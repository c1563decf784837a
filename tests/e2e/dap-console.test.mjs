// The debug console and Watch panel of `gloc dap` through VS Code's own debug-adapter test
// client (@vscode/debugadapter-testsupport): completions, evaluate with children,
// setExpression, goto, hex values, exception filter conditions and cancel. Every
// message is validated against the official DAP schema. Expected values are worked out
// by hand from the fixtures (dap/tests/fixtures/README.md).
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { join, dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { DebugClient } from '@vscode/debugadapter-testsupport';
import { schemaChecker } from './helpers/dap-schema.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, '../..');
const GLOC_BIN = process.env.GLOC_BIN;
assert.ok(GLOC_BIN, 'GLOC_BIN must name the gloc binary (tests/e2e/run sets it)');
const fixture = (name) => join(root, 'dap/tests/fixtures', name);
const WATCH = fixture('watch.gbas');

const schema = schemaChecker();
after(() => {
  assert.ok(schema.count > 30, `only ${schema.count} messages were validated`);
  assert.deepEqual(schema.violations, [], 'messages that violate the DAP schema');
});
const clients = [];
after(() => Promise.all(clients.map((dc) => dc.stop())));

/// Launched and stopped on entry (cycle 0, before the script ran).
async function atEntry(args, initialize = {}) {
  const dc = schema.validated(new DebugClient(GLOC_BIN, 'dap', 'gloc'));
  dc.defaultTimeout = 20000;
  // Stopped by its test and again by the `after` hook (for a test that failed first):
  // the second call returns the first one's promise instead of writing to a closed pipe.
  const stop = dc.stop.bind(dc);
  let stopping;
  dc.stop = () => (stopping ??= stop());
  clients.push(dc);
  await dc.start();
  const init = await dc.initializeRequest({
    adapterID: 'gloc', linesStartAt1: true, columnsStartAt1: true, ...initialize,
  });
  const initialized = dc.waitForEvent('initialized');
  // launchRequest, not DebugClient.launch: that one sends a second, default `initialize`.
  await dc.launchRequest({ ...args, stopOnEntry: true });
  await initialized;
  const stopped = dc.waitForEvent('stopped');
  await dc.configurationDoneRequest();
  assert.equal((await stopped).body.reason, 'entry');
  return { dc, capabilities: init.body };
}

async function stopAfter(dc, request) {
  const stopped = dc.waitForEvent('stopped');
  await request;
  return (await stopped).body;
}
const next = (dc) => stopAfter(dc, dc.nextRequest({ threadId: 1 }));
const watch = async (dc, expression, format) =>
  (await dc.evaluateRequest({ expression, context: 'watch', frameId: 1, format })).body;

test('the console completes sensors, variables, constants and built-ins', async () => {
  const { dc, capabilities } = await atEntry({ program: WATCH });
  assert.equal(capabilities.supportsCompletionsRequest, true);
  let body = (await dc.completionsRequest({ frameId: 1, text: 'm_dep', column: 6 })).body;
  assert.equal(body.targets[0].label, 'm_depth');
  assert.ok(body.targets.every((item) => item.label.includes('dep')));
  assert.deepEqual([body.targets[0].start, body.targets[0].length], [1, 5]);
  body = (await dc.completionsRequest({ frameId: 1, text: 'grad(1) + ab', column: 13 })).body;
  assert.deepEqual(body.targets.map((item) => item.label), ['abs']);
  body = (await dc.completionsRequest({ frameId: 1, text: 'N', column: 2 })).body;
  assert.equal(body.targets.find((item) => item.label === 'N').detail, 'const N = 4');
  // Hundreds of `m_` sensors: capped at 100.
  body = (await dc.completionsRequest({ frameId: 1, text: 'm_', column: 3 })).body;
  assert.equal(body.targets.length, 100);
  await dc.stop();
});

test('a watched array expands; setExpression edits grad(3) and reverse keeps it', async () => {
  const { dc, capabilities } = await atEntry({ program: WATCH });
  assert.equal(capabilities.supportsSetExpression, true);
  for (let cycle = 0; cycle < 4; cycle++) await next(dc);
  const tsum = await watch(dc, 'tsum');
  // float(i) * 0.1 for i = 0..3; 3 × 0.1 is the double 0.30000000000000004.
  assert.equal(tsum.result, '[0.0, 0.1, 0.2, 0.30000000000000004]');
  assert.equal(tsum.indexedVariables, 4);
  const children = await dc.variablesRequest({ variablesReference: tsum.variablesReference });
  assert.deepEqual(children.body.variables.map((v) => v.value), ['0.0', '0.1', '0.2', '0.30000000000000004']);
  const set = await dc.customRequest('setExpression', { expression: 'grad(3)', value: '7', frameId: 1 });
  assert.equal(set.body.value, '7');
  await stopAfter(dc, dc.stepBackRequest({ threadId: 1 }));
  assert.equal((await watch(dc, 'grad(3)')).result, '0');
  await next(dc);
  assert.equal((await watch(dc, 'grad(3)')).result, '7');
  await dc.stop();
});

test('hex shows bits 64 and 128 of sci_ruhp_behs', async () => {
  const { dc, capabilities } = await atEntry({ program: WATCH });
  assert.equal(capabilities.supportsValueFormattingOptions, true);
  for (let cycle = 0; cycle < 4; cycle++) await next(dc);
  // Cycle 4 stores 192 = 0xc0 (seen before the hook behavior answers it at the next boundary).
  await stopAfter(dc, dc.stepOutRequest({ threadId: 1 }));
  assert.equal((await watch(dc, 'sci_ruhp_behs', { hex: true })).result, '0xc0');
  assert.equal((await watch(dc, 'sci_ruhp_behs')).result, '192.0');
  const sensors = await dc.variablesRequest({ variablesReference: 3, format: { hex: true } });
  assert.equal(sensors.body.variables.find((v) => v.name === 'sci_ruhp_behs').value, '0xc0');
  await dc.stop();
});

test('goto jumps to a label within the cycle', async () => {
  const { dc, capabilities } = await atEntry({ program: WATCH });
  assert.equal(capabilities.supportsGotoTargetsRequest, true);
  // Line 11 is `label: done`; its code is the store on line 12.
  const targets = (await dc.gotoTargetsRequest({ source: { path: WATCH }, line: 11 })).body.targets;
  assert.equal(targets.length, 1);
  assert.equal(targets[0].line, 12);
  const stop = await stopAfter(dc, dc.gotoRequest({ threadId: 1, targetId: targets[0].id }));
  assert.equal(stop.reason, 'goto');
  const trace = await dc.stackTraceRequest({ threadId: 1 });
  assert.equal(trace.body.stackFrames[0].line, 12);
  await next(dc);
  await next(dc);
  // The loop never ran: grad(1) would be 3.
  assert.equal((await watch(dc, 'grad(1)')).result, '0');
  await stopAfter(dc, dc.stepOutRequest({ threadId: 1 }));
  await assert.rejects(dc.gotoRequest({ threadId: 1, targetId: targets[0].id }), /yielded/);
  await dc.stop();
});

test('an exception filter stops only where its condition holds', async () => {
  // trap.gbas traps in cycle 3 with left = 0.
  for (const [condition, expected] of [['left = 0', 'stopped'], ['left = 5', 'terminated']]) {
    const { dc, capabilities } = await atEntry({ program: fixture('trap.gbas'), maxCycles: 6 });
    assert.equal(capabilities.supportsExceptionFilterOptions, true);
    const set = await dc.setExceptionBreakpointsRequest({
      filters: [], filterOptions: [{ filterId: 'trap', condition }],
    });
    assert.equal(set.body.breakpoints[0].verified, true);
    // Listeners, not waitForEvent: the event that does not come must leave no timer.
    const outcome = new Promise((done) => {
      dc.once('stopped', (event) => done(['stopped', event.body.reason]));
      dc.once('terminated', () => done(['terminated']));
    });
    await dc.continueRequest({ threadId: 1 });
    const [event, reason] = await outcome;
    assert.equal(event, expected, condition);
    if (reason) assert.equal(reason, 'exception');
    await dc.stop();
  }
});

test('cancel stops a long run through its progress', async () => {
  const { dc, capabilities } = await atEntry(
    { program: fixture('fig3.gbas'), mission: fixture('endless.mi') },
    { supportsProgressReporting: true },
  );
  assert.equal(capabilities.supportsCancelRequest, true);
  const progress = dc.waitForEvent('progressStart');
  const stopped = dc.waitForEvent('stopped');
  await dc.continueRequest({ threadId: 1 });
  const start = (await progress).body;
  assert.equal(start.cancellable, true);
  const ended = dc.waitForEvent('progressEnd');
  await dc.customRequest('cancel', { progressId: start.progressId });
  const stop = (await stopped).body;
  assert.equal(stop.reason, 'pause');
  assert.match(stop.description, /cancelled/);
  assert.equal((await ended).body.progressId, start.progressId);
  await dc.stop();
});

test('cancel names a reverseContinue by its request', async () => {
  const { dc } = await atEntry(
    { program: fixture('fig3.gbas'), mission: fixture('endless.mi') },
    { supportsProgressReporting: true },
  );
  await dc.setFunctionBreakpointsRequest({ breakpoints: [{ name: 'cycle 3000' }] });
  const reached = await stopAfter(dc, dc.continueRequest({ threadId: 1 }));
  assert.equal(reached.reason, 'function breakpoint');
  await dc.setFunctionBreakpointsRequest({ breakpoints: [] });
  // A reverse run from cycle 3000 takes some 20 ms here, less than a round trip may, so
  // the `cancel` goes first, naming the seq the reverseContinue will carry: the adapter
  // reads it first, and the reverse run gives up at its first look, where it started.
  const stopped = dc.waitForEvent('stopped');
  const cancel = dc.customRequest('cancel', { requestId: dc.sequence + 1 });
  const reverse = dc.reverseContinueRequest({ threadId: 1 });
  const progress = (await dc.waitForEvent('progressStart')).body;
  assert.equal(progress.cancellable, true);
  await cancel;
  await reverse;
  const stop = (await stopped).body;
  assert.equal(stop.reason, 'pause', JSON.stringify(stop));
  assert.match(stop.description, /Reverse run cancelled at cycle 3000/);
  // Not cancelled, the same run goes back to the start.
  const back = await stopAfter(dc, dc.reverseContinueRequest({ threadId: 1 }));
  assert.equal(back.reason, 'entry');
  await dc.stop();
});
