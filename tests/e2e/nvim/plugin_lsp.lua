-- Headless Neovim test of the editors/nvim plugin with the real `gloc lsp`: the
-- plugin, loaded as the README says, attaches the server to a GBASIC file, shows its diagnostics,
-- completes sensor names and shows the compiled GLOC.
-- Run: GLOC_BIN=target/debug/gloc nvim --headless -u NONE -l tests/e2e/nvim/plugin_lsp.lua
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

H.check(vim.fn.executable(H.gloc_bin) == 1, "the gloc binary exists (GLOC_BIN)", H.gloc_bin)
H.load_plugin_as_readme_says({ gloc_path = H.gloc_bin })

local dir = vim.fn.tempname()
-- A GBASIC file with two mistakes a pilot makes: a store to a read-only sensor and a name that
-- was never declared. Line numbers below are 0-based, as in LSP.
local broken_path = dir .. "/broken.gbas"
H.write_file(broken_path, {
  "dim depth as float", -- 0
  "depth = m_depth", -- 1
  "m_depth = 3.0", -- 2: m_ sensors are read-only to scripts
  "depth = undeclared_name + 1.0", -- 3: never declared, not a sensor
  "yield", -- 4
  "depth = m_dep", -- 5: completion after m_dep
})
local fig3_path = dir .. "/fig3.gbas"
H.write_file(fig3_path, H.fig3)

local function gloc_client(bufnr)
  return vim.lsp.get_clients({ bufnr = bufnr, name = "gloc" })[1]
end

-- Diagnostics -----------------------------------------------------------------------------------
local broken = H.edit(broken_path)
H.equal(vim.bo[broken].filetype, "gbasic", "broken.gbas has filetype gbasic")
local attached = vim.wait(10000, function()
  local client = gloc_client(broken)
  return client ~= nil and client.initialized
end, 50)
H.check(attached, "gloc lsp attaches to the GBASIC buffer")
local client = gloc_client(broken)
if client then
  H.equal(client.config.cmd, { H.gloc_bin, "lsp" }, "the server command is `gloc lsp` from gloc_path")
end

local function diagnostics_on(line)
  return vim.tbl_filter(function(diagnostic)
    return diagnostic.lnum == line
  end, vim.diagnostic.get(broken))
end
vim.wait(10000, function()
  return #diagnostics_on(2) > 0 and #diagnostics_on(3) > 0
end, 50)
local read_only = diagnostics_on(2)[1]
H.check(read_only ~= nil and read_only.severity == vim.diagnostic.severity.ERROR,
  "an error on the store to the read-only sensor m_depth (line 3)", vim.diagnostic.get(broken))
H.check(read_only ~= nil and read_only.message:lower():find("m_depth", 1, true) ~= nil,
  "the read-only diagnostic names m_depth", read_only)
local undeclared = diagnostics_on(3)[1]
H.check(undeclared ~= nil and undeclared.severity == vim.diagnostic.severity.ERROR,
  "an error on the undeclared name (line 4)", vim.diagnostic.get(broken))
H.check(undeclared ~= nil and undeclared.message:find("undeclared_name", 1, true) ~= nil,
  "the undeclared-name diagnostic names it", undeclared)
H.equal(#diagnostics_on(0) + #diagnostics_on(1) + #diagnostics_on(4), 0, "no diagnostic on the correct lines")

-- Semantic tokens keep the syntax file's colours -------------------------------------------------
-- Line 1 is `depth = m_depth`; the server marks m_depth a read-only sensor (property, readonly).
local function semantic_groups(line, column)
  local groups = {}
  for _, token in ipairs(vim.inspect_pos(broken, line, column).semantic_tokens) do
    groups[#groups + 1] = token.opts.hl_group
  end
  return groups
end
vim.wait(10000, function()
  return #semantic_groups(1, 9) > 0
end, 50)
local groups = semantic_groups(1, 9)
H.check(vim.tbl_contains(groups, "@lsp.typemod.property.readonly.gbasic"),
  "gloc lsp's semantic token for m_depth is a read-only property", groups)
H.equal(vim.api.nvim_get_hl(0, { name = "@lsp.typemod.property.readonly.gbasic", link = true }).link,
  "gbasicSensorReadOnly", "the read-only sensor token is linked to the syntax group gbasicSensorReadOnly")

-- Completion ------------------------------------------------------------------------------------
local labels = H.completion_labels(broken, 5, #"depth = m_dep")
H.check(vim.tbl_contains(labels, "m_depth"), "completion after m_dep offers m_depth", labels)

-- Show compiled GLOC: Fig. 3 compiles to the paper's Fig. 2 ------------------------------------
local fig3 = H.edit(fig3_path)
vim.wait(10000, function()
  local fig3_client = gloc_client(fig3)
  return fig3_client ~= nil and fig3_client.initialized
end, 50)
local compiled = nil
require("gloc").show_compiled(fig3, function(lines)
  compiled = lines
end)
vim.wait(10000, function()
  return compiled ~= nil
end, 50)
H.equal(compiled, H.fig2, ":GlocShowCompiled shows Fig. 3 compiled to the paper's Fig. 2")
local compiled_buffer = vim.fn.bufnr("gloc://compiled/fig3.gbas.gloc")
H.check(compiled_buffer ~= -1 and vim.fn.bufwinid(compiled_buffer) ~= -1, "the compiled GLOC is shown in a split")
if compiled_buffer ~= -1 then
  H.equal(vim.bo[compiled_buffer].filetype, "gloc", "the compiled GLOC split has filetype gloc")
end

H.finish()
