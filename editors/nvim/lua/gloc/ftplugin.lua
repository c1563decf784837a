-- Buffer settings shared by the filetypes whose comments start with `#`: GLOC, Slocum mission
-- files (.mi, .ma) and sensor lists (masterdata, .cac).
local M = {}

function M.hash_comments()
  if vim.b.did_ftplugin then
    return
  end
  vim.b.did_ftplugin = true
  vim.bo.commentstring = "# %s"
  vim.bo.comments = ":#"
  vim.b.undo_ftplugin = "setlocal commentstring< comments<"
end

return M
