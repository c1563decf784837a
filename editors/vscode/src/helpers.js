// @ts-check
// Pure helpers of the extension: they build command lines, protocol parameters and debug
// configurations from plain values. They do not import `vscode`, so the end-to-end tests run
// them directly against the real `gloc` binary.
'use strict';

const path = require('path');

/** The languages the extension serves; their ids are also the debugger's languages. */
const LANGUAGE_IDS = ['gbasic', 'gloc'];

/** The LSP command (workspace/executeCommand) that returns the compiled GLOC of a GBASIC document. */
const COMPILED_GLOC_COMMAND = 'gloc.compiledGloc';

/** The URI scheme of the read-only "compiled GLOC" documents shown beside a GBASIC source. */
const COMPILED_SCHEME = 'gloc-compiled';

/**
 * Resolves a path from a setting: `~/` is the home directory, a relative path is taken from the
 * workspace folder (or left as it is when there is none). An empty setting gives `undefined`.
 * @param {string | undefined} value
 * @param {string | undefined} workspaceFolder
 * @param {string} homeDirectory
 * @returns {string | undefined}
 */
function resolveSettingPath(value, workspaceFolder, homeDirectory) {
  const trimmed = (value || '').trim();
  if (trimmed === '') {
    return undefined;
  }
  if (trimmed === '~' || trimmed.startsWith('~/')) {
    return path.join(homeDirectory, trimmed.slice(1));
  }
  if (path.isAbsolute(trimmed) || workspaceFolder === undefined) {
    return trimmed;
  }
  return path.join(workspaceFolder, trimmed);
}

/**
 * Resolves the `gloc.path` setting. A bare name (`gloc`) stays bare so the operating system looks
 * it up on PATH; anything with a directory part is resolved like other paths.
 * @param {string | undefined} value
 * @param {string | undefined} workspaceFolder
 * @param {string} homeDirectory
 * @returns {string}
 */
function resolveBinaryPath(value, workspaceFolder, homeDirectory) {
  const trimmed = (value || '').trim();
  if (trimmed === '') {
    return 'gloc';
  }
  if (!trimmed.includes('/') && !trimmed.includes('\\') && trimmed !== '~') {
    return trimmed;
  }
  return resolveSettingPath(trimmed, workspaceFolder, homeDirectory) || 'gloc';
}

/**
 * The arguments of `gloc run` for "Run mission in simulator".
 * @param {{ script: string, plot: string, masterdata?: string }} options
 * @returns {string[]}
 */
function runMissionArguments(options) {
  const args = ['run', options.script, '--plot', options.plot];
  if (options.masterdata) {
    args.push('--masterdata', options.masterdata);
  }
  return args;
}

/**
 * The parameters of the `workspace/executeCommand` request that asks `gloc lsp` for the compiled
 * GLOC of the GBASIC document at `documentUri`.
 * @param {string} documentUri
 */
function compiledGlocRequest(documentUri) {
  return { command: COMPILED_GLOC_COMMAND, arguments: [documentUri] };
}

/**
 * The GLOC text in the language server's answer to `compiledGlocRequest`: a string (see
 * /work/coord/api-lsp.md; a program with errors is answered with an error, not a result).
 * `undefined` when the answer is not a string.
 * @param {unknown} result
 * @returns {string | undefined}
 */
function compiledGlocText(result) {
  return typeof result === 'string' ? result : undefined;
}

/**
 * The URI path of the virtual "compiled GLOC" document of a GBASIC file: the file's path with
 * `.gloc` appended, so VS Code gives the document the GLOC language and highlighting.
 * @param {string} sourcePath
 */
function compiledDocumentPath(sourcePath) {
  return `${sourcePath}.gloc`;
}

/**
 * Completes a launch configuration the way a user expects when pressing F5:
 * - no launch.json at all (an empty configuration) flies the active GBASIC/GLOC file;
 * - an empty `mission`, `masterdata` or `profile` means the default;
 * - a missing `masterdata` takes the `gloc.masterdata` setting.
 * Returns a message instead when there is nothing to fly.
 * @param {Record<string, unknown>} configuration
 * @param {{ activeFile?: string, activeLanguage?: string, masterdata?: string }} context
 * @returns {{ configuration: Record<string, unknown> } | { error: string }}
 */
function completeLaunchConfiguration(configuration, context) {
  const result = { ...configuration };
  const isEmpty = !result.type && !result.request && !result.name;
  if (isEmpty) {
    if (!context.activeFile || !LANGUAGE_IDS.includes(context.activeLanguage || '')) {
      return { error: 'Open a .gbas or .gloc script to fly it in the simulator, or add a "gloc" configuration to launch.json.' };
    }
    Object.assign(result, {
      type: 'gloc',
      request: 'launch',
      name: 'Fly the current script',
      program: context.activeFile,
      stopOnEntry: true,
      history: true,
    });
  }
  if (typeof result.program !== 'string' || result.program.trim() === '') {
    return { error: 'The launch configuration needs "program": the .gbas or .gloc script to fly.' };
  }
  // An empty optional path means "the default", as it does in the settings.
  for (const key of ['mission', 'masterdata', 'profile']) {
    if (typeof result[key] === 'string' && result[key].trim() === '') {
      delete result[key];
    }
  }
  if (result.masterdata === undefined && context.masterdata) {
    result.masterdata = context.masterdata;
  }
  return { configuration: result };
}

/**
 * The first lines of a failed command's error output, for a notification (the whole output goes
 * to the output channel).
 * @param {string} stderr
 * @param {number} maxLines
 */
function firstLines(stderr, maxLines) {
  return stderr
    .split(/\r?\n/)
    .filter((line) => line.trim() !== '')
    .slice(0, maxLines)
    .join(' ');
}

/**
 * The two facts of `gloc run`'s summary (printed on stderr) a notification shows: how the mission
 * ended (`mission end   completed at cycle 900 (1 h) at 0.4 m`) and, when the script trapped,
 * where (`script        TRAPPED at fig3.gbas:4: …`). Missing lines give `undefined`.
 * @param {string} output
 * @returns {{ missionEnd?: string, scriptTrap?: string }}
 */
function runSummary(output) {
  /** @type {{ missionEnd?: string, scriptTrap?: string }} */
  const summary = {};
  for (const line of output.split(/\r?\n/)) {
    const missionEnd = /^mission end\s+(.+)$/.exec(line);
    if (missionEnd) {
      summary.missionEnd = missionEnd[1].trim();
    }
    const script = /^script\s+(TRAPPED.*)$/.exec(line);
    if (script) {
      summary.scriptTrap = script[1].trim();
    }
  }
  return summary;
}

module.exports = {
  COMPILED_GLOC_COMMAND,
  COMPILED_SCHEME,
  LANGUAGE_IDS,
  compiledDocumentPath,
  compiledGlocRequest,
  compiledGlocText,
  completeLaunchConfiguration,
  firstLines,
  resolveBinaryPath,
  resolveSettingPath,
  runMissionArguments,
  runSummary,
};
