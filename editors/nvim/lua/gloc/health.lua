-- `:checkhealth gloc`: is the gloc binary there and does it run, which Neovim features the plugin
-- uses, is the language server attached, is nvim-dap configured.
local M = {}

-- Neovim 0.10 renamed vim.health.report_ok & co. to vim.health.ok & co.
local health = vim.health
local report_start = health.start or health.report_start
local report_ok = health.ok or health.report_ok
local report_warn = health.warn or health.report_warn
local report_error = health.error or health.report_error
local report_info = health.info or health.report_info

function M.check()
  local gloc = require("gloc")
  local options = gloc.options

  report_start("gloc binary")
  local command = gloc.binary(options)
  if vim.fn.executable(command) == 1 then
    local version = vim.fn.system({ command, "--version" })
    if vim.v.shell_error == 0 then
      report_ok(("%s: %s"):format(vim.fn.exepath(command), vim.trim(version)))
    else
      report_error(("%s --version failed: %s"):format(command, vim.trim(version)))
    end
  else
    report_error(("%q is not an executable"):format(command), {
      "Install it: cargo install --path cli (from the gloc repository)",
      'Or point the plugin at it: require("gloc").setup({ gloc_path = "/path/to/gloc" })',
    })
  end
  if options.masterdata then
    local masterdata = vim.fn.fnamemodify(vim.fn.expand(options.masterdata), ":p")
    if vim.fn.filereadable(masterdata) == 1 then
      report_ok("masterdata: " .. masterdata)
    else
      report_error("masterdata file not readable: " .. masterdata)
    end
  else
    report_info("masterdata: the embedded 2008 sensor list (or gloc.toml found above the script)")
  end

  report_start("language server")
  if vim.fn.has("nvim-0.11") == 1 then
    report_ok("Neovim 0.11+: vim.lsp.config / vim.lsp.enable")
  elseif vim.fn.has("nvim-0.8") == 1 then
    report_ok("Neovim 0.8–0.10: vim.lsp.start from a FileType autocommand")
  else
    report_error("the language server needs Neovim 0.8 or later")
  end
  local get = vim.lsp.get_clients or vim.lsp.get_active_clients
  local clients = get({ name = "gloc" })
  if #clients > 0 then
    report_ok(("gloc lsp is running (%d client%s)"):format(#clients, #clients == 1 and "" or "s"))
  else
    report_info("gloc lsp is not running; it starts when a .gbas or .gloc file is opened")
  end

  report_start("debugger (nvim-dap)")
  local has_dap, dap = pcall(require, "dap")
  if not has_dap then
    report_info("nvim-dap is not installed; install it to debug scripts (see the README)")
  elseif dap.adapters.gloc then
    report_ok("dap.adapters.gloc is set: " .. table.concat({ dap.adapters.gloc.command, unpack(dap.adapters.gloc.args or {}) }, " "))
  else
    report_warn('nvim-dap is installed but the gloc adapter is not set; call require("gloc").setup_dap()')
  end
end

return M
