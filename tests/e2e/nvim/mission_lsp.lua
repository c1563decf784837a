-- Headless Neovim test of the editors/nvim plugin on Slocum mission files with the real
-- `gloc lsp`: `.mi` and `.ma` get their filetypes and syntax, the server attaches, shows the
-- simulator's diagnostics, hovers an argument and goes from `args_from_file` to the `.ma` file.
-- Run: GLOC_BIN=target/debug/gloc nvim --headless -u NONE -l tests/e2e/nvim/mission_lsp.lua
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

H.check(vim.fn.executable(H.gloc_bin) == 1, "the gloc binary exists (GLOC_BIN)", H.gloc_bin)
H.load_plugin_as_readme_says({ gloc_path = H.gloc_bin })

local dir = vim.fn.resolve(vim.fn.tempname())
local mission_path = dir .. "/missions/m.mi"
local yo_path = dir .. "/mafiles/yo10.ma"
H.write_file(mission_path, {
  "behavior: abend", -- 1
  "    b_arg: overdepth(m)    deep   # not a number", -- 2
  "behavior: yo", -- 3
  "    b_arg: args_from_file(enum) 10", -- 4
})
H.write_file(yo_path, {
  "behavior_name=Yo", -- 1
  "<start:b_arg>", -- 2
  "\tb_arg: d_target_depth(m) 25 # turn here", -- 3
  "<end:b_arg>", -- 4
  "<start:waypoints>", -- 5
  "713.000 5433.500", -- 6
  "<end:waypoints>", -- 7
})

local function expect_syntax(line, column, group, link)
  local name, linked = H.syntax_at(line, column)
  H.equal({ name, linked }, { group, link }, ("line %d column %d is %s (%s)"):format(line, column, group, link))
end

local function gloc_client(bufnr)
  return vim.lsp.get_clients({ bufnr = bufnr, name = "gloc" })[1]
end

-- The mission file -------------------------------------------------------------------------------
local mission = H.edit(mission_path)
H.equal(vim.bo[mission].filetype, "slocum_mission", ".mi has filetype slocum_mission")
H.equal(vim.b[mission].current_syntax, "slocum_mission", "syntax/slocum_mission.vim is loaded")
H.equal(vim.bo[mission].commentstring, "# %s", "mission commentstring is # %s")
expect_syntax(1, 1, "slocumMissionBehaviorKeyword", "Keyword") -- behavior:
expect_syntax(1, 11, "slocumMissionBehavior", "Function") -- abend
expect_syntax(2, 5, "slocumMissionArgKeyword", "Keyword") -- b_arg:
expect_syntax(2, 12, "slocumMissionArgument", "Identifier") -- overdepth
expect_syntax(2, 21, "slocumMissionUnits", "Type") -- (m)
expect_syntax(4, 33, "slocumMissionNumber", "Number") -- 10
expect_syntax(2, 35, "slocumMissionComment", "Comment") -- # not a number

local attached = vim.wait(10000, function()
  local client = gloc_client(mission)
  return client ~= nil and client.initialized
end, 50)
H.check(attached, "gloc lsp attaches to the mission buffer")
vim.wait(10000, function()
  return #vim.diagnostic.get(mission) > 0
end, 50)
local diagnostics = vim.diagnostic.get(mission)
H.equal(
  vim.tbl_map(function(d)
    return { d.lnum, d.col, d.code }
  end, diagnostics),
  { { 1, 27, "S0015" } },
  "one diagnostic: S0015 on `deep` (0-based line 1, column 27), as gloc run reports it"
)

local hover = vim.lsp.buf_request_sync(mission, "textDocument/hover", {
  textDocument = { uri = vim.uri_from_bufnr(mission) },
  position = { line = 1, character = 13 },
}, 10000)
local hover_text = ""
for _, answer in pairs(hover or {}) do
  hover_text = answer.result and answer.result.contents.value or hover_text
end
H.check(hover_text:find("**overdepth**(m) · abend · default 10000", 1, true) == 1, "hover on overdepth: units, behavior, default", hover_text)

local definition = vim.lsp.buf_request_sync(mission, "textDocument/definition", {
  textDocument = { uri = vim.uri_from_bufnr(mission) },
  position = { line = 3, character = 15 },
}, 10000)
local target
for _, answer in pairs(definition or {}) do
  local result = answer.result
  if result then
    target = (result.uri or (result[1] and (result[1].uri or result[1].targetUri)))
  end
end
H.equal(target, vim.uri_from_fname(yo_path), "go to definition on args_from_file opens mafiles/yo10.ma")

local labels = H.completion_labels(mission, 3, 11)
H.check(vim.tbl_contains(labels, "d_target_depth"), "b_arg completion under yo offers d_target_depth", #labels)

-- The argument file ------------------------------------------------------------------------------
local yo = H.edit(yo_path)
H.equal(vim.bo[yo].filetype, "slocum_ma", ".ma has filetype slocum_ma")
H.equal(vim.b[yo].current_syntax, "slocum_ma", "syntax/slocum_ma.vim is loaded")
expect_syntax(1, 1, "slocumMaBehaviorKeyword", "Keyword") -- behavior_name=
expect_syntax(1, 15, "slocumMaBehavior", "Function") -- Yo
expect_syntax(2, 1, "slocumMaSection", "PreProc") -- <start:b_arg>
expect_syntax(3, 2, "slocumMaArgKeyword", "Keyword") -- b_arg:
expect_syntax(3, 9, "slocumMaArgument", "Identifier") -- d_target_depth
expect_syntax(3, 27, "slocumMaNumber", "Number") -- 25
expect_syntax(3, 30, "slocumMaComment", "Comment") -- # turn here
expect_syntax(6, 1, "slocumMaWaypoint", "Number") -- 713.000 5433.500
local ma_attached = vim.wait(10000, function()
  local client = gloc_client(yo)
  return client ~= nil and client.initialized
end, 50)
H.check(ma_attached, "gloc lsp attaches to the .ma buffer")
vim.wait(3000, function()
  return false
end, 50)
H.equal(vim.diagnostic.get(yo), {}, "the .ma file has no problems")

H.finish()
