-- Headless Neovim 0.11 with the real nvim-dap (GLOC_NVIM_DAP, default ../shared/vendor/nvim-dap) and the gloc plugin set
-- up as the README says: whole debugging sessions of `gloc dap` driven through nvim-dap's API
-- and the plugin's commands, on stdio and over TCP (`gloc dap --port 0` and its session token).
-- Run: GLOC_BIN=target/debug/gloc nvim --headless -u NONE -l tests/e2e/nvim/dap_nvim_dap.lua
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

local nvim_dap = H.nvim_dap
if not H.check(vim.fn.isdirectory(nvim_dap .. "/lua/dap") == 1, H.nvim_dap_missing, nvim_dap) then
  H.finish()
end
H.check(vim.fn.executable(H.gloc_bin) == 1, "the gloc binary exists (GLOC_BIN)", H.gloc_bin)

-- Without setup(): a Neovim that merely has the plugin and nvim-dap on its runtimepath (a
-- plugin manager's doing) gets the commands and the adapter from plugin/gloc.lua.
local probe = [[lua vim.schedule(function()
  io.stdout:write(vim.fn.exists(":GlocRun"), vim.fn.exists(":GlocShowCompiled"), vim.fn.exists(":GlocStepBack"),
    vim.fn.exists(":GlocReverseContinue"), " ", type(require("dap").adapters.gloc))
  vim.cmd("qall!")
end)]]
local without_setup = vim.system({ vim.v.progpath, "--headless", "--clean", "--cmd",
  "set runtimepath^=" .. H.repo .. "/editors/nvim," .. nvim_dap, "-c", probe }, { text = true }):wait(30000)
H.equal(without_setup.stdout, "2222 table", "without setup(): the four commands and the nvim-dap adapter")

-- nvim-dap installed the usual way (on the runtimepath), then the plugin as the README says.
vim.opt.runtimepath:append(nvim_dap)
H.load_plugin_as_readme_says({ gloc_path = H.gloc_bin, lsp = false })
local dap = require("dap")

local workspace = vim.fn.tempname()
local fig3_path = workspace .. "/fig3.gbas"
H.write_file(fig3_path, H.fig3)
local thermocline_path = workspace .. "/thermocline.gbas"
H.write_file(thermocline_path, vim.fn.readfile(H.repo .. "/examples/thermocline.gbas"))

-- What the adapter sent: stops and output events, in order.
local stops, outputs = {}, {}
dap.listeners.after.event_stopped.gloc_test = function(_, body)
  stops[#stops + 1] = body
end
dap.listeners.after.event_output.gloc_test = function(_, body)
  outputs[#outputs + 1] = body.output
end

local function wait(what, condition, timeout)
  local ok = vim.wait(timeout or 30000, condition, 20)
  if not ok then
    H.check(false, "timed out waiting for " .. what)
  end
  return ok
end

--- One request on the current session, answered synchronously: the body, or nil and the error.
local function request(command, arguments)
  local session = dap.session()
  if not session then
    return nil, "no session"
  end
  local done, error, body = false, nil, nil
  session:request(command, arguments, function(err, result)
    done, error, body = true, err, result
  end)
  wait(command .. " to be answered", function()
    return done
  end)
  return body, error
end

--- The top frame after the next stop: { cycle, phase, line, name }.
local function next_stop(what, count_before)
  if not wait(what, function()
    return #stops > count_before and dap.session() ~= nil and dap.session().stopped_thread_id ~= nil
  end, 60000) then
    return {}
  end
  local trace = request("stackTrace", { threadId = dap.session().stopped_thread_id }) or { stackFrames = {} }
  local frame = trace.stackFrames[1] or {}
  local cycle, phase = (frame.name or ""):match("^cycle (%d+) %(([^)]+)%)")
  local stop = stops[#stops]
  return { cycle = tonumber(cycle), phase = phase, line = frame.line, name = frame.name, reason = stop.reason, text = stop.text }
end

--- Runs `action` (an nvim-dap function or a command) and returns the frame of the stop it causes.
local function stop_after(what, action)
  local before = #stops
  action()
  return next_stop(what, before)
end

local function evaluate(expression, context)
  local frame = dap.session() and dap.session().current_frame
  local body, err = request("evaluate", { expression = expression, context = context or "watch", frameId = frame and frame.id })
  return body and body.result, err
end

local function set_breakpoint_at(buffer, line, condition, hit, log)
  vim.api.nvim_set_current_buf(buffer)
  vim.api.nvim_win_set_cursor(0, { line, 0 })
  dap.set_breakpoint(condition, hit, log)
end

local function terminate(what)
  dap.terminate()
  wait("the session to end (" .. what .. ")", function()
    return dap.session() == nil
  end)
end

local function launch(path, overrides)
  local before = #stops
  vim.cmd.edit(vim.fn.fnameescape(path))
  local buffer = vim.api.nvim_get_current_buf()
  -- The plugin's first configuration, as `:DapContinue` offers it (program = ${file}).
  local configuration = vim.tbl_extend("force", dap.configurations[vim.bo[buffer].filetype][1], overrides or {})
  dap.run(configuration)
  return buffer, before
end

-- Session 1: stop on entry, stepping forwards and backwards, a line breakpoint, reverse continue.
local fig3, before = launch(fig3_path)
local frame = next_stop("the stop on entry", before)
H.equal({ frame.cycle, frame.reason }, { 0, "entry" }, "launch stops on entry at the boundary of cycle 0")

frame = stop_after("step over", dap.step_over)
H.equal({ frame.cycle, frame.phase }, { 1, "boundary" }, "step over moves exactly one cycle (0 -> 1)")
frame = stop_after("step over", dap.step_over)
H.equal(frame.cycle, 2, "step over again: cycle 2")

-- Fig. 3 in state1, shallower than 15 m: each cycle runs `if m_depth > 15.0` (line 2), which is
-- false, then `yield` (line 6).
frame = stop_after("step into", dap.step_into)
H.equal({ frame.cycle, frame.line, frame.phase }, { 2, 2, "script" }, "step into: the cycle's first statement, line 2")
frame = stop_after("step into", dap.step_into)
H.equal({ frame.cycle, frame.line }, { 2, 6 }, "step into again: the if is false, so `yield` (line 6)")
frame = stop_after("step into", dap.step_into)
H.equal({ frame.cycle, frame.phase }, { 3, "boundary" }, "step into a yield: the next cycle's boundary")
frame = stop_after("step into", dap.step_into)
frame = stop_after("step out", dap.step_out)
H.equal({ frame.cycle, frame.line, frame.phase }, { 3, 6, "after yield" },
  "step out from line 2: the end of the cycle's script, at its `yield` (line 6), before the vehicle moves")

frame = stop_after(":GlocStepBack", function()
  vim.cmd("GlocStepBack")
end)
H.equal({ frame.cycle, frame.phase }, { 3, "boundary" }, ":GlocStepBack from inside cycle 3: its boundary")
frame = stop_after("step back", dap.step_back)
H.equal(frame.cycle, 2, "step back: the boundary of cycle 2")

set_breakpoint_at(fig3, 3, nil, nil, nil)
frame = stop_after("continue to line 3", dap.continue)
H.check(frame.line == 3 and frame.cycle ~= nil and frame.cycle > 2, "continue stops at the breakpoint on line 3", frame)
local depth = tonumber(evaluate("m_depth"))
H.check(depth ~= nil and depth > 15, "the breakpoint on line 3 is hit with m_depth > 15", depth)
local hit_cycle = frame.cycle

frame = stop_after(":GlocReverseContinue", function()
  vim.cmd("GlocReverseContinue")
end)
H.check(frame.cycle ~= nil and frame.cycle < hit_cycle, ":GlocReverseContinue goes back before the breakpoint's cycle", frame)
frame = stop_after("reverse continue", dap.reverse_continue)
H.equal(frame.cycle, 0, "reverse continue again: back to the start (cycle 0)")
frame = stop_after("continue", dap.continue)
H.equal({ frame.line, frame.cycle }, { 3, hit_cycle }, "continue flies the same run again to the same hit")

-- The REPL: an expression typed in nvim-dap's REPL buffer is evaluated by gloc dap.
local repl = require("dap.repl")
repl.open()
repl.execute("m_depth * 2")
local repl_buffer = vim.fn.bufnr("[dap-repl-")
for _, b in ipairs(vim.api.nvim_list_bufs()) do
  if vim.bo[b].filetype == "dap-repl" then
    repl_buffer = b
  end
end
local repl_value = nil
wait("the REPL's answer", function()
  local lines = vim.api.nvim_buf_get_lines(repl_buffer, 0, -1, false)
  for index, line in ipairs(lines) do
    if line:find("m_depth * 2", 1, true) and lines[index + 1] then
      repl_value = tonumber(lines[index + 1])
      return repl_value ~= nil
    end
  end
  return false
end)
H.check(repl_value ~= nil and math.abs(repl_value - 2 * depth) < 1e-6, "the REPL evaluates m_depth * 2", { repl_value, depth })
repl.close()

dap.clear_breakpoints()
terminate("session 1")
H.check(dap.session() == nil, "terminate ends the session")

-- Session 2: a logpoint on line 2 and a hit count of 5 on line 6 (the yield of state1). Line 6
-- runs once per cycle from cycle 0 while the glider is shallower than 15 m, so the 5th hit is in
-- cycle 4, after 5 log lines.
outputs = {}
fig3 = vim.fn.bufnr(fig3_path)
set_breakpoint_at(fig3, 2, nil, nil, "depth {m_depth}")
set_breakpoint_at(fig3, 6, nil, "5", nil)
_, before = launch(fig3_path, { stopOnEntry = false })
frame = next_stop("the hit-count breakpoint", before)
H.equal({ frame.line, frame.cycle }, { 6, 4 }, "hit count 5 on line 6 stops in cycle 4")
local logged = vim.tbl_filter(function(line)
  return line:match("^depth %-?[%d.]+") ~= nil
end, outputs)
H.equal(#logged, 5, "the logpoint on line 2 printed 5 times and never stopped")

-- A conditional breakpoint: the first yield with m_depth > 10.
dap.clear_breakpoints()
set_breakpoint_at(fig3, 6, "m_depth > 10", nil, nil)
frame = stop_after("the conditional breakpoint", dap.continue)
local deep = tonumber(evaluate("m_depth"))
H.check(frame.line == 6 and deep ~= nil and deep > 10, "condition m_depth > 10 stops on line 6 with m_depth > 10", { frame, deep })
local condition_cycle = frame.cycle
frame = stop_after("step back", dap.step_back)
frame = stop_after("step back", dap.step_back)
local shallower = tonumber(evaluate("m_depth"))
H.check(frame.cycle == condition_cycle - 1 and shallower ~= nil and shallower <= 10,
  "one cycle earlier m_depth <= 10: the condition stopped at its first true cycle", { frame, shallower })
dap.clear_breakpoints()
terminate("session 2")

-- Session 3: thermocline.gbas, 300 cycles in: scopes, variables, and every evaluateName.
local thermocline
thermocline, before = launch(thermocline_path, { stopOnEntry = false, mission = H.repo .. "/examples/thermocline.mi" })
local function_breakpoints = request("setFunctionBreakpoints", { breakpoints = { { name = "cycle 300" } } })
H.check(function_breakpoints and function_breakpoints.breakpoints[1].verified, "a cycle breakpoint is accepted", function_breakpoints)
frame = next_stop("cycle 300", before)
H.equal({ frame.cycle, frame.reason }, { 300, "function breakpoint" }, "the cycle breakpoint stops at cycle 300")
local scopes = request("scopes", { frameId = dap.session().current_frame.id }) or { scopes = {} }
local scope_names = vim.tbl_map(function(scope)
  return scope.name
end, scopes.scopes)
H.equal(scope_names, { "Variables", "Registers", "Sensors", "Vehicle", "Navigation" }, "five scopes")

local entity = require("dap.entity")
local function children(reference)
  local result = nil
  entity.variable.fetch_children({ variablesReference = reference }, function(variables)
    result = variables
  end)
  wait("variables " .. reference, function()
    return result ~= nil
  end)
  return result or {}
end

local variables = children(scopes.scopes[1].variablesReference)
H.check(#variables >= 8, "the Variables scope lists the script's variables", #variables)
local checked, mismatches = 0, {}
local function check_evaluates(variable)
  if variable.evaluateName == nil then
    mismatches[#mismatches + 1] = variable.name .. " has no evaluateName"
    return
  end
  local value, err = evaluate(variable.evaluateName)
  checked = checked + 1
  if value ~= variable.value then
    mismatches[#mismatches + 1] = { name = variable.name, evaluateName = variable.evaluateName, shown = variable.value, evaluated = value, err = err }
  end
end
local tsum_children = nil
for _, variable in ipairs(variables) do
  if variable.variablesReference > 0 then
    local elements = children(variable.variablesReference)
    if variable.name == "tsum" then
      tsum_children = elements
    end
    for _, element in ipairs(elements) do
      check_evaluates(element)
    end
  else
    check_evaluates(variable)
  end
end
H.check(checked > 100 and #mismatches == 0, "every evaluateName of the Variables scope evaluates to the value shown",
  { checked = checked, mismatches = mismatches })
local names = vim.tbl_map(function(variable)
  return variable.name
end, tsum_children or {})
H.equal({ names[1], names[2], names[3], names[11], names[12] }, { "[0]", "[1]", "[2]", "[10]", "[11]" },
  "nvim-dap orders the array children of tsum numerically")
local positive = vim.tbl_filter(function(variable)
  return tonumber(variable.value) and tonumber(variable.value) > 0
end, tsum_children or {})
H.check(#positive > 0, "after 300 cycles some temperature bins hold sums", #positive)
terminate("session 3")

-- Session 3b: the journey. examples/goto.mi with the `surfacing` and `waypoint` filters turned on
-- through nvim-dap's own function; the stops' reasons are the adapter's own words. The cycles are
-- those of `gloc run dap/tests/fixtures/journey.gbas --mission examples/goto.mi --no-optimize --log F
-- --log-sensors x_hit_a_waypoint,x_dr_state` (seed 1, row N = cycle N): x_dr_state reads 2
-- from the boundary of cycle 2447, x_hit_a_waypoint 1 at 4495 (re-read from that log after
-- the turns' pump lead and ballast delay; before them 2398 and 4275, before the force
-- balance 2410 and 4249).
local journey_path = workspace .. "/journey.gbas"
H.write_file(journey_path, vim.fn.readfile(H.repo .. "/dap/tests/fixtures/journey.gbas"))
_, before = launch(journey_path, { stopOnEntry = true, mission = H.repo .. "/examples/goto.mi" })
frame = next_stop("the stop on entry of the journey", before)
H.equal(frame.cycle, 0, "the journey stops on entry")
dap.set_exception_breakpoints({ "surfacing", "waypoint" })
frame = stop_after("the first surfacing", dap.continue)
H.equal({ frame.cycle, frame.reason }, { 2447, "surfacing" }, "the surfacing filter stops where the glider came up")
scopes = request("scopes", { frameId = dap.session().current_frame.id }) or { scopes = {} }
local navigation = {}
for _, variable in ipairs(children(scopes.scopes[5].variablesReference)) do
  navigation[variable.name] = variable.value
end
H.equal(navigation.x_dr_state, "2.0", "the Navigation scope shows x_dr_state 2 (surfaced)")
frame = stop_after("the first waypoint", dap.continue)
H.equal({ frame.cycle, frame.reason }, { 4495, "waypoint" }, "the waypoint filter stops after the waypoint is reached")
terminate("the journey")

-- Session 4: over TCP. dap_transport = "tcp" starts one `gloc dap --port 0`; the plugin reads
-- its port and token and adds the token to each launch.
require("gloc").setup({ gloc_path = H.gloc_bin, lsp = false, dap_transport = "tcp" })
H.equal(type(dap.adapters.gloc), "function", "dap_transport = tcp registers a server adapter")
_, before = launch(fig3_path)
frame = next_stop("the stop on entry over TCP", before)
H.equal({ frame.cycle, frame.reason }, { 0, "entry" }, "TCP: launch stops on entry")
frame = stop_after("step over over TCP", dap.step_over)
H.equal(frame.cycle, 1, "TCP: step over moves one cycle")
frame = stop_after("step back over TCP", dap.step_back)
H.equal(frame.cycle, 0, "TCP: step back")
terminate("TCP session 1")
_, before = launch(fig3_path)
frame = next_stop("a second session on the same server", before)
H.equal(frame.cycle, 0, "TCP: a second launch on the same gloc dap --port server")
terminate("TCP session 2")

H.finish()
