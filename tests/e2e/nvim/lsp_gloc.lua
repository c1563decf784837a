-- A user opens GLOC (the paper's Fig. 2) in Neovim 0.11 with gloc configured:
-- diagnostics, completion of sensors by name, hover on a numeric sensor index,
-- go to definition of a label and rename (renumber) it.
package.path = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":h") .. "/lib/?.lua;" .. package.path
local t = require("lsp")
t.setup()

local buf = t.open("fig2.gloc", {
  "nregs 8", "nblbs 7", "ninstr 27", "label 0", "loads 444,r0", "loadd 15.0,r1", "cmpgt r0,r1,r2",
  "cbr r2,3,4", "label 3", "loadi 128,r3", "stores r3,1387", "jumpi 1", "label 4", "yield", "jumpi 0",
  "label 1", "loads 444,r4", "loadd 5.0,r5", "cmplt r4,r5,r6", "cbr r6,5,6", "label 5", "loadi 0,r7",
  "stores r7,1387", "jumpi 2", "label 6", "yield", "jumpi 1", "label 2", "yield", "jumpi 2",
})
t.eq(vim.bo[buf].filetype, "gloc", "filetype")

-- A store to a read-only sensor (m_depth is 444) is an error on that operand.
vim.api.nvim_buf_set_text(buf, 10, 10, 10, 14, { "444" })
t.wait("a diagnostic for the read-only store", function()
  return #vim.diagnostic.get(buf) > 0
end)
local diagnostic = vim.diagnostic.get(buf)[1]
t.eq(diagnostic.code, "E0108", "read-only store code")
t.eq(diagnostic.lnum, 10, "on the stores line")
vim.api.nvim_buf_set_text(buf, 10, 10, 10, 13, { "1387" })
t.wait("diagnostics cleared", function()
  return #vim.diagnostic.get(buf) == 0
end)

-- Completing the sensor operand of `stores` (nothing typed): the server cuts the list at 100,
-- writable sensors first, so read-only m_depth is not among them.
local result = t.request(buf, "textDocument/completion", t.position(buf, 10, 10))
t.check(result.isIncomplete == true, "a list cut at the limit says it is incomplete")
local depth
for _, item in ipairs(result.items or result) do
  if item.label == "m_depth" then depth = item end
end
t.check(depth == nil, "read-only m_depth not among the first items for a store")
-- With `1387` typed, the sensor is offered by name and inserts its name (GLOC takes both).
result = t.request(buf, "textDocument/completion", t.position(buf, 10, 14))
local behs
for _, item in ipairs(result.items or result) do
  if item.label == "sci_ruhp_behs" then behs = item end
end
t.check(behs ~= nil and behs.textEdit and behs.textEdit.newText == "sci_ruhp_behs",
  "sci_ruhp_behs offered, inserting its name through its text edit")

-- Hover on the numeric index names the sensor.
local hover = t.request(buf, "textDocument/hover", t.position(buf, 4, 7))
t.check(hover.contents.value:find("**m_depth** (m)", 1, true) == 1, "hover: " .. hover.contents.value)

-- Go to definition of label 3 from `cbr r2,3,4`.
vim.api.nvim_win_set_cursor(0, { 8, 7 })
vim.lsp.buf.definition()
t.wait("the cursor at label 3", function()
  local cursor = vim.api.nvim_win_get_cursor(0)
  return cursor[1] == 9 and cursor[2] == 6
end)

-- Renaming label 3 to 7 is refused while the header says `nblbs 7` (labels 0 to 6): it would
-- break the program. With `nblbs 8` it renumbers the label and every jump to it.
local messages = {}
local notify = vim.notify
vim.notify = function(message, ...)
  messages[#messages + 1] = message
  return notify(message, ...)
end
vim.lsp.buf.rename("7")
t.wait("the rename past nblbs refused", function()
  return vim.iter(messages):any(function(message)
    return message:find("out of range: `nblbs 7`", 1, true) ~= nil
  end)
end)
t.eq(vim.api.nvim_buf_get_lines(buf, 8, 9, false)[1], "label 3", "the refused rename changed nothing")
local header = vim.iter(vim.api.nvim_buf_get_lines(buf, 0, -1, false)):enumerate():find(function(_, line)
  return line == "nblbs 7"
end)
vim.api.nvim_buf_set_lines(buf, header - 1, header, false, { "nblbs 8" })
vim.api.nvim_win_set_cursor(0, { 9, 6 })
vim.lsp.buf.rename("7")
t.wait("label 3 renumbered", function()
  return vim.api.nvim_buf_get_lines(buf, 8, 9, false)[1] == "label 7"
end)
t.eq(vim.api.nvim_buf_get_lines(buf, 7, 8, false)[1], "cbr r2,7,4", "the branch follows")
vim.notify = notify

t.finish()
