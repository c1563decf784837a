-- The real nvim-dap (GLOC_NVIM_DAP, default ../shared/vendor/nvim-dap) against `gloc dap --port 0`, as
-- setup({ dap_transport = "tcp" }) wires it: the plugin starts the adapter, reads its port and
-- session token, connects as a `server` adapter and adds the token to the launch; the session
-- stops on entry, steps one cycle, and a session with a wrong token is refused.
local H = dofile(vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h") .. "/helpers/gloc_plugin.lua")

local nvim_dap = H.nvim_dap
if vim.fn.isdirectory(nvim_dap .. "/lua/dap") == 0 then
  H.check(false, H.nvim_dap_missing, nvim_dap)
  H.finish()
end
vim.opt.runtimepath:append(nvim_dap)
H.load_plugin_as_readme_says({ gloc_path = H.gloc_bin, dap_transport = "tcp", lsp = false })
local dap = require("dap")
H.equal(type(dap.adapters.gloc), "function", "dap.adapters.gloc is the TCP server adapter")

local stops = {}
dap.listeners.after.event_stopped["gloc-test"] = function(_, body)
  stops[#stops + 1] = body
end

local program = H.repo .. "/dap/tests/fixtures/fig3.gbas"
vim.cmd.edit(program)
dap.run({ type = "gloc", request = "launch", name = "tcp", program = program, stopOnEntry = true, history = false })
H.check(vim.wait(20000, function() return #stops >= 1 end, 50), "stops on entry over TCP", stops)
local session = dap.session()
H.check(session ~= nil, "a session is open")
if session then
  H.equal(stops[1] and stops[1].reason, "entry", "the stop is the entry")
  local frames = nil
  session:request("stackTrace", { threadId = 1 }, function(err, response)
    frames = err and { error = err } or response.stackFrames
  end)
  H.check(vim.wait(10000, function() return frames ~= nil end, 50), "stackTrace answers")
  local name = frames and frames[1] and frames[1].name or ""
  H.check(name:find("^cycle 0 ") ~= nil, "cycle 0 on entry", name)
  dap.step_over()
  H.check(vim.wait(20000, function() return #stops >= 2 end, 50), "step over stops again")
  frames = nil
  session:request("stackTrace", { threadId = 1 }, function(err, response)
    frames = err and { error = err } or response.stackFrames
  end)
  vim.wait(10000, function() return frames ~= nil end, 50)
  name = frames and frames[1] and frames[1].name or ""
  H.check(name:find("^cycle 1 ") ~= nil, "step over advances one cycle", name)
  dap.terminate()
  H.check(vim.wait(10000, function() return dap.session() == nil end, 50), "the session ends")
end

-- The token is what opens a session: the same adapter with a wrong one refuses the launch.
local refused = nil
dap.adapters.gloc_wrong_token = function(callback, config)
  dap.adapters.gloc(function(adapter)
    local wrong = vim.deepcopy(adapter)
    wrong.enrich_config = function(launch, on_config)
      local enriched = vim.deepcopy(launch)
      enriched.token = "0123456789abcdef0123456789abcdef"
      on_config(enriched)
    end
    callback(wrong)
  end, config)
end
dap.listeners.after.launch["gloc-test"] = function(_, err)
  refused = err ~= nil
end
dap.run({ type = "gloc_wrong_token", request = "launch", name = "wrong", program = program, stopOnEntry = true })
H.check(vim.wait(10000, function() return refused ~= nil end, 50), "the launch with a wrong token is answered")
H.equal(refused, true, "a wrong token is refused")
H.finish()
