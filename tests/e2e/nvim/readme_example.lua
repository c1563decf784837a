-- Headless Neovim test of the editors/nvim plugin set up word for word as the README's
-- "Neovim" section tells a newcomer: `gloc` on PATH, the plugin folder on the runtimepath and
-- `require("gloc").setup({})` with no options. On the repository's own example
-- examples/thermocline.gbas it checks the filetype, the highlighting, LSP diagnostics as the user
-- types, and completion. The example is edited in the buffer only, never written.
-- Run: GLOC_BIN=target/debug/gloc nvim --headless -u NONE -l tests/e2e/nvim/readme_example.lua
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

H.check(vim.fn.executable(H.gloc_bin) == 1, "the gloc binary exists (GLOC_BIN)", H.gloc_bin)
-- The user installed gloc somewhere on PATH.
vim.env.PATH = vim.fn.fnamemodify(H.gloc_bin, ":h") .. ":" .. vim.env.PATH
H.equal(vim.fn.exepath("gloc"), H.gloc_bin, "`gloc` is found on PATH")

-- The README's init.lua, exactly.
vim.opt.runtimepath:append(H.repo .. "/editors/nvim")
require("gloc").setup({})
-- What a normal start does after init.lua (skipped by -u NONE).
vim.cmd("filetype plugin indent on")
vim.cmd("syntax on")

local example = H.repo .. "/examples/thermocline.gbas"
local buffer = H.edit(example)
H.equal(vim.bo[buffer].filetype, "gbasic", "examples/thermocline.gbas has filetype gbasic")

-- Line 17 of the example is `const NBINS = 45`: `const` is a declaration keyword.
local name, linked = H.syntax_at(17, 1)
H.equal({ name, linked }, { "gbasicDeclaration", "Keyword" }, "`const` is highlighted as a declaration keyword")

local attached = vim.wait(10000, function()
  local client = vim.lsp.get_clients({ bufnr = buffer, name = "gloc" })[1]
  return client ~= nil and client.initialized
end, 50)
H.check(attached, "gloc lsp attaches to the example")
local client = vim.lsp.get_clients({ bufnr = buffer, name = "gloc" })[1]
if client then
  H.equal(client.config.cmd, { "gloc", "lsp" }, "the server is started as `gloc lsp` from PATH")
end

-- The user types a store to the read-only m_depth at the end (the 0-based line after the
-- file's last: its line count, read with Lua's own io.lines) and a half-written name on the
-- next line.
local file_lines = 0
for _ in io.lines(example) do
  file_lines = file_lines + 1
end
local last = vim.api.nvim_buf_line_count(buffer)
H.equal(last, file_lines, "the buffer has the example's lines")
vim.api.nvim_buf_set_lines(buffer, last, last, false, { "m_depth = 1.0", "bin = int(m_dep" })
local function errors_on(line)
  return vim.tbl_filter(function(diagnostic)
    return diagnostic.lnum == line and diagnostic.severity == vim.diagnostic.severity.ERROR
  end, vim.diagnostic.get(buffer))
end
vim.wait(10000, function()
  return #errors_on(last) > 0
end, 50)
local read_only = errors_on(last)[1]
H.check(read_only ~= nil and read_only.message:find("m_depth", 1, true) ~= nil,
  "typing `m_depth = 1.0` gives an error naming m_depth", vim.diagnostic.get(buffer))
local elsewhere = vim.tbl_filter(function(diagnostic)
  return diagnostic.lnum < last and diagnostic.severity == vim.diagnostic.severity.ERROR
end, vim.diagnostic.get(buffer))
H.equal(#elsewhere, 0, "the example itself has no errors")

local labels = H.completion_labels(buffer, last + 1, #"bin = int(m_dep")
H.check(vim.tbl_contains(labels, "m_depth"), "completion after `m_dep` offers m_depth", #labels)

H.check(vim.bo[buffer].modified, "the example was changed in the buffer only")
H.finish()
