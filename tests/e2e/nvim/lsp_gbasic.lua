-- A user opens the paper's Fig. 3 (.gbas) in Neovim 0.11 with gloc configured:
-- diagnostics as they type, completion, hover, go to definition and rename.
package.path = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":h") .. "/lib/?.lua;" .. package.path
local t = require("lsp")
t.setup()

local buf = t.open("fig3.gbas", {
  "label: state1", "if m_depth > 15.0 then", "  SCI_RUHP_BEHS = 128", "  goto state2", "endif",
  "yield", "goto state1", "label: state2", "if m_depth < 5.0 then", "  SCI_RUHP_BEHS = 0",
  "  goto state3", "endif", "yield", "goto state2", "label: state3", "yield", "goto state3",
})
t.eq(vim.bo[buf].filetype, "gbasic", "filetype")

-- Typing a typo gives an error with a stable code; fixing it clears it.
vim.api.nvim_buf_set_text(buf, 1, 3, 1, 10, { "m_dpth" })
t.wait("a diagnostic for m_dpth", function()
  return #vim.diagnostic.get(buf) > 0
end)
local diagnostic = vim.diagnostic.get(buf)[1]
t.eq(diagnostic.code, "E2101", "undeclared-name code")
t.eq({ diagnostic.lnum, diagnostic.col, diagnostic.end_col }, { 1, 3, 9 }, "diagnostic position")
t.check(diagnostic.message:find("did you mean `m_depth`?", 1, true) ~= nil, "did-you-mean: " .. diagnostic.message)
t.eq(diagnostic.severity, vim.diagnostic.severity.ERROR, "severity")
vim.api.nvim_buf_set_text(buf, 1, 3, 1, 9, { "m_depth" })
t.wait("diagnostics cleared", function()
  return #vim.diagnostic.get(buf) == 0
end)

-- Completion after `goto` lists the labels.
local result = t.request(buf, "textDocument/completion", t.position(buf, 3, 9))
local labels = {}
for _, item in ipairs(result.items or result) do
  table.insert(labels, item.label)
end
t.eq(labels, { "state1", "state2", "state3" }, "labels after goto")

-- Hover on a sensor.
local hover = t.request(buf, "textDocument/hover", t.position(buf, 1, 5))
t.check(hover.contents.value:find("**m_depth** (m)", 1, true) == 1, "hover: " .. hover.contents.value)

-- Go to definition moves the cursor from `goto state2` to `label: state2`.
vim.api.nvim_win_set_cursor(0, { 4, 8 })
vim.lsp.buf.definition()
t.wait("the cursor at label: state2", function()
  local cursor = vim.api.nvim_win_get_cursor(0)
  return cursor[1] == 8 and cursor[2] == 7
end)

-- Rename the label under the cursor everywhere.
vim.lsp.buf.rename("climbing")
t.wait("the label renamed", function()
  return vim.api.nvim_buf_get_lines(buf, 7, 8, false)[1] == "label: climbing"
end)
t.eq(vim.api.nvim_buf_get_lines(buf, 3, 4, false)[1], "  goto climbing", "the goto renamed too")
t.eq(vim.api.nvim_buf_get_lines(buf, 13, 14, false)[1], "goto climbing", "the other goto renamed")
t.wait("still clean after the rename", function()
  return #vim.diagnostic.get(buf) == 0
end)

t.finish()
