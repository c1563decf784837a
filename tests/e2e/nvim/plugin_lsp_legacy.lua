-- Headless Neovim test of the plugin's path for Neovim 0.8–0.10 (vim.lsp.start from a FileType
-- autocommand): Neovim 0.11 runs it with vim.lsp.config / vim.lsp.enable hidden, as on an older
-- version, and the real `gloc lsp` must attach and report a diagnostic.
-- Run: GLOC_BIN=target/debug/gloc nvim --headless -u NONE -l tests/e2e/nvim/plugin_lsp_legacy.lua
local here = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h")
package.path = here .. "/helpers/?.lua;" .. package.path
local H = require("gloc_plugin")

-- What Neovim 0.8–0.10 lack.
vim.lsp.config = nil
vim.lsp.enable = nil
H.load_plugin_as_readme_says({ gloc_path = H.gloc_bin })

local dir = vim.fn.tempname()
local path = dir .. "/legacy.gbas"
H.write_file(path, { "m_depth = 3.0", "yield" })
local buffer = H.edit(path)
H.equal(vim.bo[buffer].filetype, "gbasic", "legacy.gbas has filetype gbasic")

local attached = vim.wait(10000, function()
  local client = vim.lsp.get_clients({ bufnr = buffer, name = "gloc" })[1]
  return client ~= nil and client.initialized
end, 50)
H.check(attached, "vim.lsp.start from the FileType autocommand attaches gloc lsp")
local client = vim.lsp.get_clients({ bufnr = buffer, name = "gloc" })[1]
if client then
  H.equal(client.config.root_dir, dir, "root_dir falls back to the file's folder without gloc.toml or .git")
end
vim.wait(10000, function()
  return #vim.diagnostic.get(buffer) > 0
end, 50)
local diagnostics = vim.diagnostic.get(buffer)
H.check(#diagnostics > 0 and diagnostics[1].lnum == 0, "the store to read-only m_depth gets a diagnostic", diagnostics)

H.finish()
