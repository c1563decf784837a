// Validation of every message `gloc dap` sends against the official DAP JSON schema
// (dap/tests/schema/debugAdapterProtocol.json) with ajv-draft-04, shared by the tests that
// drive the adapter with DebugClient. `validated(client)` hooks a DebugClient before
// `start()`; the test file asserts the checker's `violations` and `count` in an `after()`
// hook (a failing top-level `after` hook fails the `node --test` run: failureType
// 'hookFailed', exit status 1).
import { readFileSync } from 'node:fs';
import { join, dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import Ajv from 'ajv-draft-04';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../../..');
const schema = JSON.parse(readFileSync(join(root, 'dap/tests/schema/debugAdapterProtocol.json'), 'utf8'));
const ajv = new Ajv({ strict: false, allErrors: true });
// The schema's integer formats, checked for their ranges.
ajv.addFormat('int32', { type: 'number', validate: (x) => Number.isInteger(x) && x >= -(2 ** 31) && x < 2 ** 31 });
ajv.addFormat('uint32', { type: 'number', validate: (x) => Number.isInteger(x) && x >= 0 && x < 2 ** 32 });
ajv.addFormat('uint64', { type: 'number', validate: (x) => Number.isInteger(x) && x >= 0 });
ajv.addSchema(schema, 'dap');
const validators = new Map();
function validator(name) {
  if (!schema.definitions[name]) return null;
  if (!validators.has(name)) validators.set(name, ajv.getSchema(`dap#/definitions/${name}`));
  return validators.get(name);
}
const capital = (text) => text.charAt(0).toUpperCase() + text.slice(1);

export function schemaChecker() {
  const checker = {
    violations: [],
    count: 0,
    check(message) {
      const names = ['ProtocolMessage'];
      if (message.type === 'event') names.push('Event', `${capital(message.event)}Event`);
      else if (message.type === 'response') {
        names.push(message.success ? 'Response' : 'ErrorResponse');
        if (message.success) names.push(`${capital(message.command)}Response`);
      } else checker.violations.push(`unexpected message type: ${JSON.stringify(message)}`);
      for (const name of names) {
        const validate = validator(name);
        if (validate && !validate(message)) {
          checker.violations.push(`${name}: ${ajv.errorsText(validate.errors)} in ${JSON.stringify(message)}`);
        }
      }
      checker.count += 1;
    },
    // Routes every message the client receives through `check` first.
    validated(client) {
      const dispatch = client.dispatch;
      client.dispatch = function (body) {
        checker.check(JSON.parse(body));
        return dispatch.call(this, body);
      };
      return client;
    },
  };
  return checker;
}
