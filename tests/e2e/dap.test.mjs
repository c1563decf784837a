// End-to-end tests of `gloc dap` with VS Code's own debug-adapter test client
// (@vscode/debugadapter-testsupport). Every message the adapter sends is validated
// against the official DAP JSON schema (dap/tests/schema/debugAdapterProtocol.json)
// with ajv-draft-04. Expected cycles come from the simulator's own log (`gloc run
// --log`), a separate run, or are worked out by hand in the comments.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import { readFileSync, mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { DebugClient } from '@vscode/debugadapter-testsupport';
import { schemaChecker } from './helpers/dap-schema.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, '../..');
const GLOC_BIN = process.env.GLOC_BIN;
assert.ok(GLOC_BIN, 'GLOC_BIN must name the gloc binary (tests/e2e/run sets it)');
const FIG3 = join(root, 'dap/tests/fixtures/fig3.gbas');
const TRAP = join(root, 'dap/tests/fixtures/trap.gbas');
const ENDLESS = join(root, 'dap/tests/fixtures/endless.mi');
const scratch = mkdtempSync(join(tmpdir(), 'gloc-dap-e2e-'));

// ---------------------------------------------------------------------------------------
// Schema validation of every adapter message.

const schema = schemaChecker();

after(() => {
  assert.ok(schema.count > 50, `only ${schema.count} messages were validated`);
  assert.deepEqual(schema.violations, [], 'messages that violate the DAP schema');
});

// Every adapter a test started is stopped at the end, also when the test failed before
// its own `dc.stop()`: a live adapter would keep this file's process from ending.
const clients = [];
after(() => Promise.all(clients.map((dc) => dc.stop())));

async function client() {
  const dc = schema.validated(new DebugClient(GLOC_BIN, 'dap', 'gloc'));
  dc.defaultTimeout = 20000;
  clients.push(dc);
  await dc.start();
  return dc;
}

async function launched(args) {
  const dc = await client();
  const init = await dc.initializeRequest({ adapterID: 'gloc', linesStartAt1: true, columnsStartAt1: true });
  assert.equal(init.body.supportsConfigurationDoneRequest, true);
  const capabilities = args.history === false ? null : dc.waitForEvent('capabilities');
  const initialized = dc.waitForEvent('initialized');
  await dc.launch(args);
  if (capabilities) assert.equal((await capabilities).body.capabilities.supportsStepBack, true);
  await initialized;
  return dc;
}

async function vars(dc, reference) {
  const response = await dc.variablesRequest({ variablesReference: reference });
  return Object.fromEntries(response.body.variables.map((variable) => [variable.name, variable.value]));
}
const SENSORS = 3;
const VEHICLE = 4;
async function line(dc) {
  const trace = await dc.stackTraceRequest({ threadId: 1 });
  return trace.body.stackFrames[0].line;
}
async function cycle(dc) {
  return Number((await vars(dc, VEHICLE)).cycle);
}
async function stopAfter(dc, request, reason) {
  const stopped = dc.waitForEvent('stopped');
  await request;
  const event = await stopped;
  if (reason) assert.equal(event.body.reason, reason, JSON.stringify(event.body));
  return event;
}
async function snapshot(dc) {
  const all = await dc.variablesRequest({ variablesReference: 5 });
  return {
    variables: await vars(dc, 1),
    registers: await vars(dc, 2),
    sensors: await vars(dc, SENSORS),
    vehicle: await vars(dc, VEHICLE),
    all: all.body.variables.map((variable) => `${variable.name}=${variable.value}`),
    line: await line(dc),
  };
}

// ---------------------------------------------------------------------------------------
// The simulator's own log, from a separate `gloc run`.

function simulatorLog() {
  const log = join(scratch, 'fig3.csv');
  const run = spawnSync(GLOC_BIN, ['run', FIG3, '--log', log], { encoding: 'utf8' });
  assert.equal(run.status, 0, `gloc run failed: ${run.stderr}`);
  const [header, ...rows] = readFileSync(log, 'utf8').trim().split('\n');
  const columns = header.split(',');
  return rows.map((row) => {
    const cells = row.split(',');
    return Object.fromEntries(columns.map((name, index) => [name, Number(cells[index])]));
  });
}

// ---------------------------------------------------------------------------------------

test('stop on entry at the first statement of cycle 0', async () => {
  const dc = await launched({ program: FIG3, stopOnEntry: true });
  await stopAfter(dc, dc.configurationDoneRequest(), 'entry');
  // Line 1 is `label: state1`, which has no code.
  assert.equal(await line(dc), 2);
  assert.equal(await cycle(dc), 0);
  const threads = await dc.threadsRequest();
  assert.equal(threads.body.threads.length, 1);
  const scopes = await dc.scopesRequest({ frameId: 1 });
  assert.deepEqual(scopes.body.scopes.map((scope) => scope.name), ['Variables', 'Registers', 'Sensors', 'Vehicle', 'Navigation']);
  await dc.stop();
});

test('next advances exactly one cycle', async () => {
  // The period of each cycle, from the simulator's own log of the same script and seed:
  // u_cycle_time (4 s in fig2.mi) plus a seeded overrun, so no two need be equal.
  const log = simulatorLog();
  const time = (cycle) => log.find((row) => row.m_cycle_number === cycle).m_present_time;
  const dc = await launched({ program: FIG3, stopOnEntry: true });
  try {
    await stopAfter(dc, dc.configurationDoneRequest(), 'entry');
    let before = await vars(dc, VEHICLE);
    for (let step = 0; step < 4; step++) {
      await stopAfter(dc, dc.nextRequest({ threadId: 1 }), 'step');
      const now = await vars(dc, VEHICLE);
      const cycle = Number(now.cycle);
      assert.equal(cycle, Number(before.cycle) + 1);
      const period = Number(now.m_present_time) - Number(before.m_present_time);
      assert.ok(period >= 4, `a cycle of ${period} s is shorter than u_cycle_time`);
      assert.ok(Math.abs(period - (time(cycle) - time(cycle - 1))) < 1e-3, `${period} s`);
      before = now;
    }
  } finally {
    await dc.stop();
  }
});

test('line breakpoint in Fig. 3 hits in the cycle m_depth first exceeds 15', async () => {
  const log = simulatorLog();
  const expected = log.find((row) => row.m_depth > 15);
  assert.ok(expected, 'the simulator log goes below 15 m');
  const dc = await launched({ program: FIG3 });
  const set = await dc.setBreakpointsRequest({ source: { path: FIG3 }, breakpoints: [{ line: 3 }] });
  assert.equal(set.body.breakpoints[0].verified, true);
  await stopAfter(dc, dc.configurationDoneRequest(), 'breakpoint');
  assert.equal(await line(dc), 3);
  assert.equal(await cycle(dc), expected.m_cycle_number);
  // The log holds 4-byte floats, as the glider logs them.
  assert.ok(Math.abs(Number((await vars(dc, SENSORS)).m_depth) - expected.m_depth) < 1e-4);
  await dc.stop();
});

test('conditional breakpoint', async () => {
  const log = simulatorLog();
  // A row is written after its cycle: m_depth is what the script saw in that cycle, and
  // sci_ruhp_behs at a boundary is what the previous cycle left.
  const expected = log.find((row, index) => index > 0 && row.m_depth > 10 && log[index - 1].sci_ruhp_behs === 0);
  const dc = await launched({ program: FIG3 });
  await dc.setBreakpointsRequest({
    source: { path: FIG3 },
    breakpoints: [{ line: 2, condition: 'm_depth > 10 and sci_ruhp_behs = 0' }],
  });
  await stopAfter(dc, dc.configurationDoneRequest(), 'breakpoint');
  assert.equal(await cycle(dc), expected.m_cycle_number);
  const value = await dc.evaluateRequest({ expression: 'm_depth > 10 and sci_ruhp_behs = 0', context: 'watch', frameId: 1 });
  assert.equal(value.body.result, '1');
  await dc.stop();
});

test('data breakpoint on sci_ruhp_behs', async () => {
  const log = simulatorLog();
  // The script's store shows in the row of the cycle it ran in; the adapter stops at the
  // boundary of the next cycle.
  const changes = log.filter((row, index) => index > 0 && row.sci_ruhp_behs !== log[index - 1].sci_ruhp_behs);
  assert.ok(changes.length >= 1);
  const dc = await launched({ program: FIG3 });
  const info = await dc.dataBreakpointInfoRequest({ variablesReference: SENSORS, name: 'sci_ruhp_behs' });
  assert.ok(info.body.dataId);
  const set = await dc.setDataBreakpointsRequest({ breakpoints: [{ dataId: info.body.dataId, accessType: 'write' }] });
  assert.equal(set.body.breakpoints[0].verified, true);
  await stopAfter(dc, dc.configurationDoneRequest(), 'data breakpoint');
  assert.equal(await cycle(dc), changes[0].m_cycle_number + 1);
  assert.equal(Number((await vars(dc, SENSORS)).sci_ruhp_behs), changes[0].sci_ruhp_behs);
  await dc.stop();
});

test('stepBack returns to the same variables and sensors', async () => {
  const dc = await launched({ program: FIG3, stopOnEntry: true });
  await stopAfter(dc, dc.configurationDoneRequest(), 'entry');
  for (let step = 0; step < 30; step++) await stopAfter(dc, dc.nextRequest({ threadId: 1 }), 'step');
  const before = await snapshot(dc);
  await stopAfter(dc, dc.nextRequest({ threadId: 1 }), 'step');
  await stopAfter(dc, dc.nextRequest({ threadId: 1 }), 'step');
  assert.notDeepEqual(await snapshot(dc), before);
  await stopAfter(dc, dc.stepBackRequest({ threadId: 1 }), 'step');
  await stopAfter(dc, dc.stepBackRequest({ threadId: 1 }), 'step');
  assert.deepEqual(await snapshot(dc), before);
  await dc.stop();
});

test('setVariable on a sensor changes the script\'s course', async () => {
  const dc = await launched({ program: FIG3, stopOnEntry: true });
  await stopAfter(dc, dc.configurationDoneRequest(), 'entry');
  // At the surface m_depth is 0: unmodified, the script yields on line 6 and resumes on
  // line 7 (`goto state1`) in cycle 1.
  const set = await dc.setVariableRequest({ variablesReference: SENSORS, name: 'm_depth', value: '20' });
  assert.equal(set.body.value, '20.0');
  await stopAfter(dc, dc.nextRequest({ threadId: 1 }), 'step');
  // Seeing 20 m, it took the `then` branch (SCI_RUHP_BEHS = 128, goto state2) and now
  // resumes on line 14 (`goto state2`).
  assert.equal(await cycle(dc), 1);
  assert.equal(await line(dc), 14);
  await dc.stop();
});

test('a trap is reported as a stop on the GBASIC line', async () => {
  // trap.gbas: left = 3, 2, 1, 0 in cycles 0..3; `print 100 \ left` on line 7 traps in cycle 3.
  const dc = await launched({ program: TRAP });
  const event = await stopAfter(dc, dc.configurationDoneRequest(), 'exception');
  assert.match(event.body.text, /line 7/);
  assert.equal(await line(dc), 7);
  assert.equal(await cycle(dc), 3);
  assert.equal((await vars(dc, 1)).left, '0');
  await dc.stop();
});

test('disconnect without arguments ends the adapter', async () => {
  const dc = await launched({ program: FIG3, stopOnEntry: true });
  await stopAfter(dc, dc.configurationDoneRequest(), 'entry');
  const exited = new Promise((done) => dc._adapterProcess.once('exit', (code) => done(code)));
  // DebugClient sends `disconnect` with no `arguments` at all when given {}.
  const response = await dc.disconnectRequest({});
  assert.equal(response.success, true);
  assert.equal(await exited, 0);
});

// ---------------------------------------------------------------------------------------
// Raw protocol: malformed input, and a client that goes away mid-run.

function frame(text) {
  return `Content-Length: ${Buffer.byteLength(text, 'utf8')}\r\n\r\n${text}`;
}

function rawAdapter() {
  const child = spawn(GLOC_BIN, ['dap'], { stdio: ['pipe', 'pipe', 'inherit'] });
  let buffer = Buffer.alloc(0);
  const messages = [];
  const waiters = [];
  child.stdout.on('data', (data) => {
    buffer = Buffer.concat([buffer, data]);
    for (;;) {
      const end = buffer.indexOf('\r\n\r\n');
      if (end < 0) break;
      const length = Number(/Content-Length: (\d+)/.exec(buffer.subarray(0, end).toString())[1]);
      if (buffer.length < end + 4 + length) break;
      const message = JSON.parse(buffer.subarray(end + 4, end + 4 + length).toString());
      buffer = buffer.subarray(end + 4 + length);
      schema.check(message);
      messages.push(message);
      waiters.splice(0).forEach((wake) => wake());
    }
  });
  const exited = new Promise((done) => child.on('exit', (code, signal) => done({ code, signal })));
  async function next(predicate) {
    for (;;) {
      const index = messages.findIndex(predicate);
      if (index >= 0) return messages.splice(index, 1)[0];
      await new Promise((wake, fail) => {
        waiters.push(wake);
        setTimeout(() => fail(new Error('no message in time')), 20000).unref();
      });
    }
  }
  return { child, next, exited, send: (text) => child.stdin.write(frame(text)) };
}

test('malformed input gets an error response each and no crash', async () => {
  const adapter = rawAdapter();
  adapter.send('{"seq": 1, "type": "request", "command": "threads", ');
  let response = await adapter.next((message) => message.request_seq === 1);
  assert.equal(response.success, false);
  assert.match(response.message, /not valid JSON/);
  adapter.send(JSON.stringify({ seq: 2, type: 'request', command: 'initialize', arguments: { linesStartAt1: 'yes' } }));
  response = await adapter.next((message) => message.request_seq === 2);
  assert.equal(response.success, false);
  adapter.send(JSON.stringify({ seq: 3, type: 'request', command: 'gloc/frobnicate' }));
  response = await adapter.next((message) => message.request_seq === 3);
  assert.equal(response.success, false);
  assert.equal(response.command, 'gloc/frobnicate');
  adapter.send(JSON.stringify({ seq: 4, type: 'request', command: 'initialize', arguments: {} }));
  response = await adapter.next((message) => message.request_seq === 4);
  assert.equal(response.success, true);
  for (const [seq, command] of [[5, 'next'], [6, 'stackTrace'], [7, 'stepBack'], [8, 'variables']]) {
    adapter.send(JSON.stringify({ seq, type: 'request', command, arguments: { threadId: 1 } }));
    response = await adapter.next((message) => message.request_seq === seq);
    assert.equal(response.success, false, command);
    assert.match(response.message, /launch/);
  }
  adapter.send(JSON.stringify({ seq: 9, type: 'request', command: 'disconnect' }));
  response = await adapter.next((message) => message.request_seq === 9);
  assert.equal(response.success, true);
  const { code } = await adapter.exited;
  assert.equal(code, 0);
});

test('a client that disconnects mid-run leaves no process behind', async () => {
  const adapter = rawAdapter();
  adapter.send(JSON.stringify({ seq: 1, type: 'request', command: 'initialize', arguments: {} }));
  await adapter.next((message) => message.request_seq === 1);
  adapter.send(JSON.stringify({ seq: 2, type: 'request', command: 'launch', arguments: { program: FIG3, mission: ENDLESS } }));
  assert.equal((await adapter.next((message) => message.request_seq === 2)).success, true);
  adapter.send(JSON.stringify({ seq: 3, type: 'request', command: 'configurationDone' }));
  await adapter.next((message) => message.request_seq === 3);
  // The endless mission is running; the client goes away without a word.
  await new Promise((done) => setTimeout(done, 200));
  adapter.child.stdin.end();
  const timeout = new Promise((_, fail) => setTimeout(() => fail(new Error('the adapter is still running')), 10000).unref());
  const { code } = await Promise.race([adapter.exited, timeout]);
  assert.equal(code, 0);
});

test('--port serves DebugClient over TCP on 127.0.0.1', async () => {
  const server = spawn(GLOC_BIN, ['dap', '--port', '0'], { stdio: ['ignore', 'ignore', 'pipe'] });
  try {
    // The port and the session token come in one line (one write).
    const [port, token] = await new Promise((done, fail) => {
      let text = '';
      server.stderr.on('data', (data) => {
        text += data;
        const match = /listening on 127\.0\.0\.1:(\d+) token ([0-9a-f]+)\n/.exec(text);
        if (match) done([Number(match[1]), match[2]]);
      });
      setTimeout(() => fail(new Error(`no port announced: ${text}`)), 10000).unref();
    });
    const dc = schema.validated(new DebugClient(GLOC_BIN, 'dap', 'gloc'));
    await dc.start(port);
    await dc.initializeRequest({ adapterID: 'gloc' });
    const initialized = dc.waitForEvent('initialized');
    await dc.launch({ program: FIG3, stopOnEntry: true, history: false, token });
    await initialized;
    await stopAfter(dc, dc.configurationDoneRequest(), 'entry');
    assert.equal(await cycle(dc), 0);
    await dc.stop();
  } finally {
    server.kill();
  }
});
