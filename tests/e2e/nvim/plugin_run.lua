-- Headless Neovim test of :GlocRun with the real `gloc run`: the plugin, loaded as the README
-- says, saves the script, flies it in the simulator, shows what the run printed and opens the
-- flight-profile SVG with vim.ui.open.
-- Run: GLOC_BIN=target/debug/gloc nvim --headless -u NONE -l tests/e2e/nvim/plugin_run.lua
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

H.check(vim.fn.executable(H.gloc_bin) == 1, "the gloc binary exists (GLOC_BIN)", H.gloc_bin)
H.load_plugin_as_readme_says({ gloc_path = H.gloc_bin })

local fig3_path = vim.fn.tempname() .. "/fig3.gbas"
H.write_file(fig3_path, H.fig3)
local fig3 = H.edit(fig3_path)

-- Run mission in simulator ----------------------------------------------------------------------
local opened = {}
vim.ui.open = function(path)
  opened[#opened + 1] = path
end
local run_result = nil
require("gloc").run(fig3, function(result)
  run_result = result
end)
vim.wait(120000, function()
  return run_result ~= nil
end, 100)
H.check(run_result ~= nil and run_result.code == 0, ":GlocRun finishes with exit status 0", run_result)
if run_result then
  local svg = vim.fn.filereadable(run_result.plot) == 1 and table.concat(vim.fn.readfile(run_result.plot), "\n") or ""
  H.check(svg:find("<svg", 1, true) ~= nil, ":GlocRun writes an SVG flight profile", run_result.plot)
  H.equal(opened, { run_result.plot }, ":GlocRun opens the flight profile with vim.ui.open")
end

H.check(run_result ~= nil and run_result.lines[1]:find("$ " .. H.gloc_bin .. " run " .. fig3_path .. " --plot ", 1, true) == 1,
  "the run split starts with the command line", run_result and run_result.lines)
H.check(vim.fn.bufnr("gloc://run/fig3.gbas") ~= -1, "the run output is shown in a split")
H.check(run_result ~= nil and require("gloc").run_headline(run_result.lines):match("^completed") ~= nil
  or run_result ~= nil and require("gloc").run_headline(run_result.lines):match("^still running") ~= nil,
  "the summary says how the mission ended", run_result and run_result.lines)
H.equal(require("gloc").run_headline({
  "warning: something",
  '{"mission_end":"still running","script_state":"TRAPPED at a.gbas:4: x","trap_line":4}',
}), "script TRAPPED at a.gbas:4: x", "a trap is the headline (from the JSON summary)")
H.equal(require("gloc").run_headline({ "mission end   completed at cycle 9 (36 s) at 0.3 m" }),
  "the flight finished", "the text summary is not scraped")
H.check(vim.tbl_contains(run_result and run_result.lines or {}, function(line)
  return line:find('"mission_end"', 1, true) ~= nil
end, { predicate = true }), ":GlocRun asks gloc run for its JSON summary", run_result and run_result.lines)

H.finish()
