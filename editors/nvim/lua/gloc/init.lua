-- The gloc Neovim plugin: filetypes, the `gloc lsp` language server, the `gloc dap` debug adapter
-- for nvim-dap, and what the commands of plugin/gloc.lua call (:GlocShowCompiled, :GlocRun,
-- :GlocStepBack, :GlocReverseContinue). A thin client: all knowledge of GLOC and GBASIC lives in
-- the gloc binary.
local M = {}

--- Options of `setup()`; every field is optional.
--- @class gloc.Options
--- @field gloc_path? string     the gloc binary (default "gloc", looked up on PATH)
--- @field masterdata? string    a masterdata or .cac file replacing the embedded sensor list
--- @field root_markers? string[] files that mark a project root (default gloc.toml, .git)
--- @field lsp? boolean          start the language server (default true)
--- @field dap? boolean          configure nvim-dap when it is installed (default true)
--- @field dap_transport? string "stdio" (default) or "tcp": one `gloc dap --port 0` per Neovim,
---                              its session token added to each launch
M.defaults = {
  gloc_path = "gloc",
  masterdata = nil,
  root_markers = { "gloc.toml", ".git" },
  lsp = true,
  dap = true,
  dap_transport = "stdio",
}

--- The options in force (defaults until `setup()` is called).
M.options = vim.deepcopy(M.defaults)

--- The script filetypes: the ones the debugger flies and :GlocRun runs.
M.filetypes = { "gbasic", "gloc" }

--- Slocum mission files (`.mi`), mission argument files (`.ma`) and sensor lists (masterdata,
--- `.cac`): served by `gloc lsp`, not flown.
M.mission_filetypes = { "slocum_mission", "slocum_ma", "slocum_masterdata" }

--- Every filetype `gloc lsp` attaches to.
M.lsp_filetypes = vim.list_extend(vim.deepcopy(M.filetypes), M.mission_filetypes)

--- The filetypes the plugin detects, for vim.filetype.add (ftdetect/gloc.lua and setup()).
M.filetype_detection = {
  extension = { gbas = "gbasic", gloc = "gloc", mi = "slocum_mission", ma = "slocum_ma", cac = "slocum_masterdata" },
  filename = { masterdata = "slocum_masterdata" },
}

--- The LSP command that returns the compiled GLOC of a GBASIC document.
M.compiled_gloc_command = "gloc.compiledGloc"

local function has(version)
  return vim.fn.has("nvim-" .. version) == 1
end

local function expand_path(path)
  if path == nil or path == "" then
    return nil
  end
  return vim.fn.fnamemodify(vim.fn.expand(path), ":p")
end

--- A binary path stays bare (looked up on PATH) unless it names a directory.
local function binary(options)
  local path = options.gloc_path or "gloc"
  if path:find("/", 1, true) or path:find("\\", 1, true) or path:sub(1, 1) == "~" then
    return expand_path(path)
  end
  return path
end

--- The gloc binary of `options` (health.lua uses it too).
M.binary = binary

local function notify(message, level)
  vim.notify("gloc: " .. message, level or vim.log.levels.INFO)
end

--- The language server configuration shared by every Neovim version.
--- @param options gloc.Options
function M.lsp_config(options)
  local masterdata = expand_path(options.masterdata)
  -- Sent once: the server asks for the `gloc` section (workspace/configuration) when it starts
  -- and again after each didChangeConfiguration, so a changed path applies live.
  return {
    cmd = { binary(options), "lsp" },
    filetypes = M.lsp_filetypes,
    root_markers = options.root_markers,
    settings = { gloc = masterdata and { masterdata = masterdata } or vim.empty_dict() },
  }
end

local function start_lsp_for_buffer(options, bufnr)
  local config = M.lsp_config(options)
  local file = vim.api.nvim_buf_get_name(bufnr)
  local directory = file ~= "" and vim.fs.dirname(file) or vim.fn.getcwd()
  local marker = vim.fs.find(options.root_markers, { upward = true, path = directory })[1]
  vim.lsp.start({
    name = "gloc",
    cmd = config.cmd,
    root_dir = marker and vim.fs.dirname(marker) or directory,
    settings = config.settings,
  }, { bufnr = bufnr })
end

--- Starts `gloc lsp` for GBASIC and GLOC buffers: `vim.lsp.config`/`vim.lsp.enable` on Neovim 0.11
--- and later, `vim.lsp.start` from a FileType autocommand on 0.8 to 0.10.
--- @param options gloc.Options
function M.setup_lsp(options)
  if vim.lsp.config and vim.lsp.enable then
    vim.lsp.config("gloc", M.lsp_config(options))
    vim.lsp.enable("gloc")
    return
  end
  if not vim.lsp.start then
    notify("the language server needs Neovim 0.8 or later", vim.log.levels.WARN)
    return
  end
  local group = vim.api.nvim_create_augroup("gloc_lsp", { clear = true })
  vim.api.nvim_create_autocmd("FileType", {
    group = group,
    pattern = M.lsp_filetypes,
    callback = function(event)
      start_lsp_for_buffer(options, event.buf)
    end,
  })
  -- Buffers that were already open when setup() ran.
  for _, bufnr in ipairs(vim.api.nvim_list_bufs()) do
    if vim.api.nvim_buf_is_loaded(bufnr) and vim.tbl_contains(M.lsp_filetypes, vim.bo[bufnr].filetype) then
      start_lsp_for_buffer(options, bufnr)
    end
  end
end

--- The nvim-dap launch configurations for GBASIC and GLOC files. The attribute names are those
--- `gloc dap` accepts (the same as in the VS Code extension's launch.json).
--- @param options gloc.Options
function M.dap_configurations(options)
  local masterdata = expand_path(options.masterdata)
  return {
    {
      type = "gloc",
      request = "launch",
      name = "Fly the current script",
      program = "${file}",
      stopOnEntry = true,
      history = true,
      masterdata = masterdata,
    },
    {
      type = "gloc",
      request = "launch",
      name = "Fly the current script with a mission",
      program = "${file}",
      mission = function()
        return vim.fn.input("Mission file: ", vim.fn.getcwd() .. "/", "file")
      end,
      stopOnEntry = true,
      history = true,
      masterdata = masterdata,
    },
    {
      type = "gloc",
      request = "launch",
      name = "Replay the current script over recorded data",
      program = "${file}",
      -- A CSV file or glider logs (a deployment: .dbd with its .ebd, ...), separated by spaces.
      replay = function()
        local answer = vim.fn.input("Recorded files: ", vim.fn.getcwd() .. "/", "file")
        return vim.split(answer, "%s+", { trimempty = true })
      end,
      stopOnEntry = true,
      history = true,
      masterdata = masterdata,
    },
  }
end

--- The port and session token in `gloc dap --port`'s first stderr line
--- (`gloc dap: listening on 127.0.0.1:PORT token TOKEN`), or nil.
--- @param line string
--- @return integer?, string?
function M.parse_listening(line)
  local port, token = line:match("^gloc dap: listening on 127%.0%.0%.1:(%d+) token (%S+)$")
  if port == nil then
    return nil
  end
  return tonumber(port), token
end

-- The `gloc dap --port 0` server this Neovim started: { job, port?, token?, waiting }.
local dap_server = nil

--- An nvim-dap adapter (a function) that starts `gloc dap --port 0` once, reads its port and
--- token from stderr, and connects to it as a `server` adapter; `enrich_config` adds the
--- token to each launch configuration, which `gloc dap --port` requires.
--- @param options gloc.Options
function M.dap_server_adapter(options)
  return function(callback, _)
    local function connect()
      callback({
        type = "server",
        host = "127.0.0.1",
        port = dap_server.port,
        enrich_config = function(config, on_config)
          local enriched = vim.deepcopy(config)
          enriched.token = dap_server.token
          on_config(enriched)
        end,
      })
    end
    if dap_server ~= nil and dap_server.port ~= nil then
      connect()
      return
    end
    if dap_server ~= nil then
      table.insert(dap_server.waiting, connect)
      return
    end
    local received = ""
    local job = vim.fn.jobstart({ binary(options), "dap", "--port", "0" }, {
      on_stderr = function(_, data)
        if dap_server == nil or dap_server.port ~= nil then
          return
        end
        received = received .. table.concat(data, "\n")
        for line in received:gmatch("[^\n]+") do
          local port, token = M.parse_listening(line)
          if port ~= nil then
            dap_server.port, dap_server.token = port, token
            local waiting = dap_server.waiting
            dap_server.waiting = {}
            vim.schedule(function()
              for _, waiter in ipairs(waiting) do
                waiter()
              end
            end)
            return
          end
        end
      end,
      on_exit = function()
        dap_server = nil
      end,
    })
    if job <= 0 then
      vim.notify("gloc: cannot start `" .. binary(options) .. " dap --port 0`", vim.log.levels.ERROR)
      return
    end
    dap_server = { job = job, waiting = { connect } }
    vim.api.nvim_create_autocmd("VimLeavePre", {
      once = true,
      callback = function()
        pcall(vim.fn.jobstop, job)
      end,
    })
  end
end

--- Registers the `gloc` adapter and configurations with nvim-dap. Returns false, without an error,
--- when nvim-dap is not installed.
--- @param options? gloc.Options
--- @return boolean
function M.setup_dap(options)
  options = options or M.options
  local ok, dap = pcall(require, "dap")
  if not ok then
    return false
  end
  if options.dap_transport == "tcp" then
    dap.adapters.gloc = M.dap_server_adapter(options)
  else
    dap.adapters.gloc = { type = "executable", command = binary(options), args = { "dap" } }
  end
  local configurations = M.dap_configurations(options)
  for _, filetype in ipairs(M.filetypes) do
    dap.configurations[filetype] = configurations
  end
  return true
end

local function gloc_client(bufnr)
  local get = vim.lsp.get_clients or vim.lsp.get_active_clients
  return get({ bufnr = bufnr, name = "gloc" })[1]
end

-- Neovim 0.11 made client methods take `self` (`client:request`); 0.8 to 0.10 need the field call.
local function client_request(client, method, params, handler, bufnr)
  if has("0.11") then
    return client:request(method, params, handler, bufnr)
  end
  return client.request(method, params, handler, bufnr)
end

local function scratch_window(name, filetype)
  local existing = vim.fn.bufnr(name)
  local bufnr = existing ~= -1 and existing or vim.api.nvim_create_buf(false, true)
  if existing == -1 then
    vim.api.nvim_buf_set_name(bufnr, name)
    vim.bo[bufnr].buftype = "nofile"
    vim.bo[bufnr].bufhidden = "hide"
    vim.bo[bufnr].swapfile = false
    if filetype then
      vim.bo[bufnr].filetype = filetype
    end
  end
  if vim.fn.bufwinid(bufnr) == -1 then
    local current = vim.api.nvim_get_current_win()
    vim.cmd("vertical belowright sbuffer " .. bufnr)
    vim.api.nvim_set_current_win(current)
  end
  return bufnr
end

local function set_scratch_lines(bufnr, lines)
  vim.bo[bufnr].modifiable = true
  vim.api.nvim_buf_set_lines(bufnr, 0, -1, false, lines)
  vim.bo[bufnr].modifiable = false
end

--- The GLOC text in the server's answer (a string), or nil when the answer holds none. A program
--- with errors is answered with an error whose message says so.
function M.compiled_text(result)
  if type(result) == "string" then
    return result
  end
  return nil
end

--- Asks the language server for the compiled GLOC of GBASIC buffer `bufnr` and shows it in a
--- read-only split beside it, which follows the source as it changes. `on_done(lines)` is called
--- after each update (tests use it).
--- @param bufnr? integer
--- @param on_done? fun(lines: string[])
function M.show_compiled(bufnr, on_done)
  bufnr = (bufnr == nil or bufnr == 0) and vim.api.nvim_get_current_buf() or bufnr
  if vim.bo[bufnr].filetype ~= "gbasic" then
    notify(":GlocShowCompiled needs a GBASIC (.gbas) buffer", vim.log.levels.WARN)
    return
  end
  local client = gloc_client(bufnr)
  if not client then
    notify("the gloc language server is not attached to this buffer; check :checkhealth vim.lsp", vim.log.levels.ERROR)
    return
  end
  local source_name = vim.api.nvim_buf_get_name(bufnr)
  local target = scratch_window("gloc://compiled/" .. vim.fn.fnamemodify(source_name, ":t") .. ".gloc", "gloc")

  local function refresh()
    local params = { command = M.compiled_gloc_command, arguments = { vim.uri_from_bufnr(bufnr) } }
    client_request(client, "workspace/executeCommand", params, function(err, result)
      local lines
      local name = vim.fn.fnamemodify(source_name, ":t")
      local text = not err and M.compiled_text(result) or nil
      if text then
        lines = vim.split((text:gsub("\n$", "")), "\n", { plain = true })
      elseif err then
        -- A program with errors is answered with an error whose message says so.
        lines = {
          "# " .. name .. ": " .. tostring(err.message or err),
          "# :lua vim.diagnostic.setqflist() lists the errors; this view updates as you fix them.",
        }
      else
        lines = { "# gloc lsp answered without GLOC text for " .. name .. "; is the gloc binary up to date?" }
      end
      if vim.api.nvim_buf_is_valid(target) then
        set_scratch_lines(target, lines)
      end
      if on_done then
        on_done(lines)
      end
    end, bufnr)
  end

  refresh()
  local group = vim.api.nvim_create_augroup("gloc_compiled_" .. bufnr, { clear = true })
  local timer = nil
  vim.api.nvim_create_autocmd({ "TextChanged", "TextChangedI", "BufWritePost" }, {
    group = group,
    buffer = bufnr,
    callback = function()
      if not vim.api.nvim_buf_is_valid(target) or vim.fn.bufwinid(target) == -1 then
        vim.api.nvim_del_augroup_by_id(group)
        return
      end
      if timer then
        timer:stop()
      end
      timer = vim.defer_fn(refresh, 300)
    end,
  })
end

--- How the run ended, from `gloc run --summary json`'s summary: its last line that is a JSON
--- object (docs/simulator.md). A trapped script comes first, then how the mission ended.
--- @param lines string[]
--- @return string
function M.run_headline(lines)
  for index = #lines, 1, -1 do
    local ok, summary = pcall(vim.json.decode, lines[index])
    if ok and type(summary) == "table" and type(summary.mission_end) == "string" then
      if type(summary.trap_line) == "number" then
        return "script " .. summary.script_state
      end
      return summary.mission_end
    end
  end
  return "the flight finished"
end

--- Flies the script in buffer `bufnr` with `gloc run FILE --plot FILE.svg --summary json`, shows what the run
--- printed (its summary) in a split, and opens the flight profile with `vim.ui.open` (Neovim 0.10+;
--- older versions print the SVG's path). `on_done(result)` is called at the end (tests use it).
--- @param bufnr? integer
--- @param on_done? fun(result: { code: integer, plot: string, lines: string[] })
function M.run(bufnr, on_done)
  bufnr = (bufnr == nil or bufnr == 0) and vim.api.nvim_get_current_buf() or bufnr
  if not vim.tbl_contains(M.filetypes, vim.bo[bufnr].filetype) then
    notify(":GlocRun needs a .gbas or .gloc buffer", vim.log.levels.WARN)
    return
  end
  local script = vim.api.nvim_buf_get_name(bufnr)
  if script == "" then
    notify("save the script to a file first; gloc run reads it from disk", vim.log.levels.WARN)
    return
  end
  if vim.bo[bufnr].modified then
    vim.api.nvim_buf_call(bufnr, function()
      vim.cmd("silent write")
    end)
  end
  local plot = vim.fn.tempname() .. "-" .. vim.fn.fnamemodify(script, ":t:r") .. ".svg"
  local command = { binary(M.options), "run", script, "--plot", plot, "--summary", "json" }
  local masterdata = expand_path(M.options.masterdata)
  if masterdata then
    vim.list_extend(command, { "--masterdata", masterdata })
  end
  if vim.fn.executable(command[1]) == 0 then
    notify(("cannot run %q: set gloc_path in require('gloc').setup()"):format(command[1]), vim.log.levels.ERROR)
    return
  end
  local output = { "$ " .. table.concat(command, " ") }
  local function collect(_, data)
    for _, line in ipairs(data or {}) do
      if line ~= "" then
        table.insert(output, line)
      end
    end
  end
  notify("flying " .. vim.fn.fnamemodify(script, ":t") .. " in the simulator…")
  vim.fn.jobstart(command, {
    stdout_buffered = true,
    stderr_buffered = true,
    on_stdout = collect,
    on_stderr = collect,
    on_exit = function(_, code)
      local target = scratch_window("gloc://run/" .. vim.fn.fnamemodify(script, ":t"), nil)
      set_scratch_lines(target, output)
      -- Exit status 5: the run worked and the mission aborted (abend); its plot is drawn.
      if code ~= 0 and code ~= 5 then
        notify("gloc run failed (exit status " .. code .. "); see the split for its messages", vim.log.levels.ERROR)
      elseif vim.fn.filereadable(plot) == 1 then
        table.insert(output, "Flight profile: " .. plot)
        set_scratch_lines(target, output)
        notify(vim.fn.fnamemodify(script, ":t") .. ": " .. M.run_headline(output))
        if vim.ui.open then
          vim.ui.open(plot)
        else
          notify("flight profile: " .. plot)
        end
      end
      if on_done then
        on_done({ code = code, plot = plot, lines = output })
      end
    end,
  })
end

--- Links the highlight groups of the language server's semantic tokens to the syntax files'
--- groups, so a sensor, register or label keeps its colour when the server's tokens arrive
--- (Neovim 0.9+ paints them over the syntax). `default = true`: a colour scheme or the user wins.
function M.link_semantic_highlights()
  local links = {
    ["@lsp.type.property.gbasic"] = "gbasicSensor",
    ["@lsp.typemod.property.readonly.gbasic"] = "gbasicSensorReadOnly",
    ["@lsp.type.label.gbasic"] = "gbasicLabelName",
    ["@lsp.type.function.gbasic"] = "gbasicBuiltin",
    ["@lsp.type.property.gloc"] = "glocSensorIndex",
    ["@lsp.type.label.gloc"] = "glocLabelReference",
    ["@lsp.typemod.variable.register.gloc"] = "glocRegister",
    ["@lsp.type.macro.gloc"] = "glocHeader",
  }
  for group, target in pairs(links) do
    vim.api.nvim_set_hl(0, group, { link = target, default = true })
  end
end

--- Sets up the plugin. Call it once from your init.lua: `require("gloc").setup({})`.
--- @param options? gloc.Options
function M.setup(options)
  M.options = vim.tbl_deep_extend("force", vim.deepcopy(M.defaults), options or {})
  -- Also done by ftdetect/gloc.lua; repeated so that plugin managers that load the plugin late
  -- still get the filetypes.
  vim.filetype.add(M.filetype_detection)
  if M.options.lsp then
    M.setup_lsp(M.options)
    M.link_semantic_highlights()
    -- A colour scheme clears highlight groups; link again after each one.
    vim.api.nvim_create_autocmd("ColorScheme", {
      group = vim.api.nvim_create_augroup("gloc_semantic_highlights", { clear = true }),
      callback = M.link_semantic_highlights,
    })
  end
  if M.options.dap then
    M.setup_dap(M.options)
  end
  M.configured = true
end

--- Registers the nvim-dap adapter with the options in force unless `setup()` ran (it does that
--- itself); plugin/gloc.lua calls it at start-up so F5 works without `setup()`.
function M.setup_dap_unless_configured()
  if not M.configured then
    M.setup_dap(M.options)
  end
end

--- Runs nvim-dap's `step_back` or `reverse_continue` (the :GlocStepBack and :GlocReverseContinue
--- commands), or says that nvim-dap is missing or no session is stopped.
--- @param action "step_back"|"reverse_continue"
function M.dap_step(action)
  local ok, dap = pcall(require, "dap")
  if not ok then
    notify("debugging needs nvim-dap (https://codeberg.org/mfussenegger/nvim-dap)", vim.log.levels.ERROR)
    return
  end
  if dap.session() == nil then
    notify("no debug session: start one with require('dap').continue()", vim.log.levels.WARN)
    return
  end
  dap[action]()
end

return M
