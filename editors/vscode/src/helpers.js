// @ts-check
// Pure helpers of the extension: they build command lines, protocol parameters and debug
// configurations from plain values. They do not import `vscode`, so the end-to-end tests run
// them directly against the real `gloc` binary.
'use strict';

const path = require('path');

/** The script languages the extension serves; their ids are also the debugger's languages. */
const LANGUAGE_IDS = ['gbasic', 'gloc'];

/**
 * The commands this extension runs for the language server's "Run" and "Debug" code lenses (each
 * takes the script's URI as a string). The client lists them in `experimental.commands.commands`
 * (rust-analyzer's convention); the server shows those lenses only to a client that does.
 */
const CODE_LENS_COMMANDS = ['gloc.runMission', 'gloc.debugScript'];

/**
 * A command's URI argument as a vscode.Uri-like value: code lenses pass the URI as a string, menus
 * pass a Uri. `parse` is vscode.Uri.parse.
 * @template T
 * @param {unknown} argument
 * @param {(text: string) => T} parse
 * @returns {T | object | undefined}
 */
function commandUri(argument, parse) {
  if (typeof argument === 'string') {
    return parse(argument);
  }
  return argument && typeof argument === 'object' ? argument : undefined;
}

/** Slocum mission files (`.mi`), mission argument files (`.ma`) and sensor lists (masterdata,
 * `.cac`): served by gloc lsp, not flown. */
const MISSION_LANGUAGE_IDS = ['slocum_mission', 'slocum_ma', 'slocum_masterdata'];

/** Every language the language client hands to gloc lsp. */
const SERVED_LANGUAGE_IDS = [...LANGUAGE_IDS, ...MISSION_LANGUAGE_IDS];

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
 * Finds the gloc binary named by the `gloc.path` setting. A path with a directory part is taken as
 * it is (relative to the workspace folder, `~/` the home directory); a bare name is looked up on
 * `pathVariable` (the PATH the editor was started with), then in `~/.cargo/bin`, where
 * `cargo install` puts it (an editor started from a desktop menu often has neither on its PATH).
 * Returns the absolute path of the binary, or `missing` with the places searched.
 * @param {string | undefined} setting
 * @param {{ workspaceFolder?: string, homeDirectory: string, pathVariable?: string, isExecutable: (file: string) => boolean }} context
 * @returns {{ binary: string } | { missing: string, searched: string[] }}
 */
function locateBinary(setting, context) {
  const wanted = resolveBinaryPath(setting, context.workspaceFolder, context.homeDirectory);
  const bare = !wanted.includes('/') && !wanted.includes('\\');
  if (!bare) {
    return context.isExecutable(wanted) ? { binary: wanted } : { missing: wanted, searched: [wanted] };
  }
  const directories = (context.pathVariable || '')
    .split(path.delimiter)
    .filter((directory) => directory !== '' && path.isAbsolute(directory));
  directories.push(path.join(context.homeDirectory, '.cargo', 'bin'));
  for (const directory of directories) {
    const candidate = path.join(directory, wanted);
    if (context.isExecutable(candidate)) {
      return { binary: candidate };
    }
  }
  return { missing: wanted, searched: directories };
}

/**
 * The arguments of `gloc run` for "Run mission in simulator".
 * @param {{ script: string, plot: string, masterdata?: string }} options
 * @returns {string[]}
 */
function runMissionArguments(options) {
  const args = ['run', options.script, '--plot', options.plot, '--summary', 'json'];
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
 * What a notification says about a finished `gloc run --summary json`: its summary is the last line
 * of its error output, one JSON object (docs/simulator.md). `headline` is how the script or the
 * mission ended, `trapped` whether the script trapped; `undefined` when there is no summary.
 * @param {string} stderr
 * @returns {{ headline: string, trapped: boolean } | undefined}
 */
function runSummary(stderr) {
  const last = stderr.trimEnd().split(/\r?\n/).pop() || '';
  let summary;
  try {
    summary = JSON.parse(last);
  } catch {
    return undefined;
  }
  if (!summary || typeof summary !== 'object' || typeof summary.mission_end !== 'string') {
    return undefined;
  }
  const trapped = typeof summary.trap_line === 'number';
  return {
    headline: trapped ? `script ${summary.script_state}` : summary.mission_end,
    trapped,
  };
}

module.exports = {
  CODE_LENS_COMMANDS,
  COMPILED_GLOC_COMMAND,
  commandUri,
  COMPILED_SCHEME,
  LANGUAGE_IDS,
  MISSION_LANGUAGE_IDS,
  SERVED_LANGUAGE_IDS,
  compiledDocumentPath,
  compiledGlocRequest,
  compiledGlocText,
  completeLaunchConfiguration,
  firstLines,
  locateBinary,
  resolveBinaryPath,
  resolveSettingPath,
  runMissionArguments,
  runSummary,
};
