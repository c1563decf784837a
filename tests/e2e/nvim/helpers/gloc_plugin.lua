-- Shared set-up of the headless Neovim tests of editors/nvim: loads the plugin exactly as the
-- README's "Neovim" section tells a user, and offers small check/wait helpers.
local H = {}

H.repo = vim.fn.fnamemodify(debug.getinfo(1, "S").source:sub(2), ":p:h:h:h:h:h")
-- Absolute and without `..` (tests/e2e/run passes tests/e2e/../../target/debug/gloc), as the
-- plugin resolves paths.
-- The real nvim-dap, which no package registry ships: GLOC_NVIM_DAP names its folder (a clone
-- of mfussenegger/nvim-dap); by default the vendored copy in ../shared/vendor/nvim-dap.
H.nvim_dap = vim.fn.fnamemodify(os.getenv("GLOC_NVIM_DAP") or (H.repo .. "/../shared/vendor/nvim-dap"), ":p")
H.nvim_dap_missing = "nvim-dap is not at " .. H.nvim_dap
  .. ": set GLOC_NVIM_DAP to a checkout of nvim-dap (mfussenegger/nvim-dap; see README.md, The two commands)"
H.gloc_bin = vim.fn.fnamemodify(os.getenv("GLOC_BIN") or (H.repo .. "/target/debug/gloc"), ":p")
H.failures = 0
H.passes = 0

--- One line on stdout (`print` in `nvim -l` puts the line break before a message, not after).
function H.say(line)
  io.stdout:write(line, "\n")
  io.stdout:flush()
end

function H.check(condition, description, detail)
  if condition then
    H.passes = H.passes + 1
    H.say("ok   " .. description)
  else
    H.failures = H.failures + 1
    H.say("FAIL " .. description .. (detail and (": " .. vim.inspect(detail)) or ""))
  end
  return condition
end

function H.equal(actual, expected, description)
  return H.check(vim.deep_equal(actual, expected), description, { actual = actual, expected = expected })
end

--- Loads the plugin as the README says: the plugin folder on the runtimepath and
--- require("gloc").setup({...}) in init.lua. Then what a normal start does after init.lua and
--- `-u NONE` skips: the plugin scripts of the runtimepath (`plugin/`), `filetype plugin indent on`
--- and `syntax on` (Neovim's defaults).
function H.load_plugin_as_readme_says(options)
  vim.opt.runtimepath:append(H.repo .. "/editors/nvim")
  require("gloc").setup(options)
  vim.cmd("runtime! plugin/**/*.lua")
  vim.cmd("filetype plugin indent on")
  vim.cmd("syntax on")
end

--- The lower-cased labels that `textDocument/completion` offers at 0-based `line`, `character`.
function H.completion_labels(buffer, line, character)
  local response = vim.lsp.buf_request_sync(buffer, "textDocument/completion", {
    textDocument = { uri = vim.uri_from_bufnr(buffer) },
    position = { line = line, character = character },
  }, 10000)
  local labels = {}
  for _, answer in pairs(response or {}) do
    local result = answer.result or {}
    for _, item in ipairs(result.items or result) do
      labels[#labels + 1] = item.label:lower()
    end
  end
  return labels
end

function H.write_file(path, lines)
  vim.fn.mkdir(vim.fn.fnamemodify(path, ":h"), "p")
  vim.fn.writefile(lines, path)
end

--- Opens `path` as a user would (`:edit`) and returns its buffer.
function H.edit(path)
  vim.cmd.edit(vim.fn.fnameescape(path))
  return vim.api.nvim_get_current_buf()
end

--- The syntax group at 1-based `line`, `column` of the current buffer, and the standard group it
--- links to (`hi def link` in the syntax file; colour schemes style the standard groups).
function H.syntax_at(line, column)
  local name = vim.fn.synIDattr(vim.fn.synID(line, column, 1), "name")
  local link = vim.api.nvim_get_hl(0, { name = name, link = true }).link
  -- One more step for groups linked through another plugin group (gbasicSensorReadOnly).
  if link and link:match("^gbasic") or link and link:match("^gloc") then
    link = vim.api.nvim_get_hl(0, { name = link, link = true }).link
  end
  return name, link
end

--- The paper's Fig. 3 (GBASIC) and Fig. 2 (the GLOC it compiles to), as printed.
H.fig3 = {
  "label: state1",
  "if m_depth > 15.0 then",
  "  SCI_RUHP_BEHS = 128",
  "  goto state2",
  "endif",
  "yield",
  "goto state1",
  "label: state2",
  "if m_depth < 5.0 then",
  "  SCI_RUHP_BEHS = 0",
  "  goto state3",
  "endif",
  "yield",
  "goto state2",
  "label: state3",
  "yield",
  "goto state3",
}

H.fig2 = {
  "nregs 8", "nblbs 7", "ninstr 27", "label 0", "loads 444,r0", "loadd 15.0,r1", "cmpgt r0,r1,r2",
  "cbr r2,3,4", "label 3", "loadi 128,r3", "stores r3,1387", "jumpi 1", "label 4", "yield", "jumpi 0",
  "label 1", "loads 444,r4", "loadd 5.0,r5", "cmplt r4,r5,r6", "cbr r6,5,6", "label 5", "loadi 0,r7",
  "stores r7,1387", "jumpi 2", "label 6", "yield", "jumpi 1", "label 2", "yield", "jumpi 2",
}

--- Stops every language server, prints the tally and exits non-zero on any failure.
function H.finish()
  local get = vim.lsp.get_clients or vim.lsp.get_active_clients
  for _, client in ipairs(get()) do
    client:stop()
  end
  vim.wait(2000, function()
    return #get() == 0
  end, 50)
  H.say(("%d passed, %d failed"):format(H.passes, H.failures))
  if H.failures == 0 then
    vim.cmd("qall!")
  else
    vim.cmd("cquit 1")
  end
end

return H
