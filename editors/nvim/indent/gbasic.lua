-- GBASIC indentation: one level inside if/elseif/else, while, do and for blocks; the closing
-- keyword (endif, end if, wend, loop, next) and elseif/else go back one level as you type them.
if vim.b.did_indent then
  return
end
vim.b.did_indent = true

vim.bo.indentexpr = "v:lua.require'gloc.indent'.gbasic(v:lnum)"
vim.bo.indentkeys = "0=~endif,0=~end,0=~else,0=~elseif,0=~wend,0=~loop,0=~next,o,O,!^F"
vim.bo.autoindent = true
vim.b.undo_indent = "setlocal indentexpr< indentkeys< autoindent<"
