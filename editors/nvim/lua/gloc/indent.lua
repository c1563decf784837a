-- The indent function behind indent/gbasic.lua. It mirrors the VS Code language configuration's
-- indentationRules (editors/vscode/language-configuration/gbasic.json).
local M = {}

-- A line that opens a block: a block `if … then` (nothing but a comment after `then`), elseif,
-- else, while, do, for. Case-insensitive, like the language.
local opens = vim.regex([[\c^\s*\(if\>.*\<then\s*\('.*\|rem\>.*\)\=$\|elseif\>\|else\s*\('.*\|rem\>.*\)\=$\|while\>\|do\>\|for\>\)]])
-- A line that closes a block (or continues it at the opening level).
local closes = vim.regex([[\c^\s*\(endif\|end\s\+if\|elseif\|else\|wend\|loop\|next\)\>]])

--- The indent of line `lnum` (1-based) of the current buffer.
--- @param lnum integer
--- @return integer
function M.gbasic(lnum)
  local previous = vim.fn.prevnonblank(lnum - 1)
  if previous == 0 then
    return 0
  end
  local width = vim.fn.shiftwidth()
  local indent = vim.fn.indent(previous)
  if opens:match_str(vim.fn.getline(previous)) then
    indent = indent + width
  end
  if closes:match_str(vim.fn.getline(lnum)) then
    indent = indent - width
  end
  return math.max(indent, 0)
end

return M
