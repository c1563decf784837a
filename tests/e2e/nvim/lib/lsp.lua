-- Shared set-up for the Neovim LSP tests: configures gloc like a user's init.lua
-- would (Neovim 0.11 `vim.lsp.config` / `vim.lsp.enable`), and small assertion helpers
-- that end Neovim with a non-zero exit code on failure.
local M = {}

local gloc_bin = os.getenv("GLOC_BIN")
if not gloc_bin or gloc_bin == "" then
  io.stderr:write("GLOC_BIN must name the gloc binary\n")
  os.exit(2)
end

function M.fail(message)
  io.stderr:write("FAIL: " .. message .. "\n")
  os.exit(1)
end

function M.check(condition, message)
  if not condition then
    M.fail(message)
  end
end

function M.eq(actual, expected, message)
  if not vim.deep_equal(actual, expected) then
    M.fail(message .. "\n  expected: " .. vim.inspect(expected) .. "\n  actual:   " .. vim.inspect(actual))
  end
end

function M.setup()
  -- `-u NONE` starts without filetype detection; a user config has it on.
  vim.cmd("filetype on")
  vim.filetype.add({ extension = { gloc = "gloc", gbas = "gbasic" } })
  vim.lsp.config("gloc", {
    cmd = { gloc_bin, "lsp" },
    filetypes = { "gloc", "gbasic" },
    root_markers = { "gloc.toml", ".git" },
  })
  vim.lsp.enable("gloc")
end

--- Writes `lines` to a fresh file in a temporary project and opens it with :edit.
function M.open(name, lines)
  local dir = vim.fn.tempname()
  vim.fn.mkdir(dir, "p")
  local path = dir .. "/" .. name
  vim.fn.writefile(lines, path)
  vim.cmd.edit(path)
  local buf = vim.api.nvim_get_current_buf()
  local attached = vim.wait(10000, function()
    local clients = vim.lsp.get_clients({ bufnr = buf, name = "gloc" })
    return #clients > 0 and clients[1].initialized
  end, 20)
  M.check(attached, "the gloc server attached to " .. name)
  return buf, path
end

--- Waits until `predicate()` holds (polling), or fails with `message`.
function M.wait(message, predicate)
  M.check(vim.wait(10000, predicate, 20), "timed out waiting: " .. message)
end

--- One synchronous request on the buffer's gloc client; returns the result.
function M.request(buf, method, params)
  local responses = vim.lsp.buf_request_sync(buf, method, params, 10000)
  M.check(responses ~= nil, method .. " answered")
  for _, response in pairs(responses) do
    M.check(response.err == nil, method .. " failed: " .. vim.inspect(response.err))
    return response.result
  end
  M.fail(method .. ": no response")
end

function M.position(buf, line, character)
  return { textDocument = { uri = vim.uri_from_bufnr(buf) }, position = { line = line, character = character } }
end

function M.finish()
  for _, client in ipairs(vim.lsp.get_clients({ name = "gloc" })) do
    client:stop()
  end
  vim.wait(5000, function()
    return #vim.lsp.get_clients({ name = "gloc" }) == 0
  end, 20)
  io.stdout:write("ok: " .. vim.fn.fnamemodify(arg[0] or "", ":t") .. "\n")
  vim.cmd("qa!")
end

return M
