-- The gloc plugin's commands, defined when Neovim loads the plugin (no `setup()` needed):
-- :GlocShowCompiled, :GlocRun, and for nvim-dap sessions :GlocStepBack and :GlocReverseContinue.
-- Also registers the `gloc` debug adapter with nvim-dap (default options) when `setup()` has not.
if vim.g.loaded_gloc then
  return
end
vim.g.loaded_gloc = true

local function gloc()
  return require("gloc")
end

local commands = {
  GlocShowCompiled = {
    function()
      gloc().show_compiled(0)
    end,
    "Show the compiled GLOC of this GBASIC buffer beside it",
  },
  GlocRun = {
    function()
      gloc().run(0)
    end,
    "Fly this script in the simulator and open its flight profile",
  },
  GlocStepBack = {
    function()
      gloc().dap_step("step_back")
    end,
    "Debugger: back to the previous cycle boundary (nvim-dap step_back)",
  },
  GlocReverseContinue = {
    function()
      gloc().dap_step("reverse_continue")
    end,
    "Debugger: run backwards to the previous breakpoint or the start (nvim-dap reverse_continue)",
  },
}
for name, command in pairs(commands) do
  vim.api.nvim_create_user_command(name, command[1], { desc = command[2] })
end

-- nvim-dap may be loaded after this plugin: register the adapter once everything is loaded.
vim.api.nvim_create_autocmd("VimEnter", {
  once = true,
  callback = function()
    gloc().setup_dap_unless_configured()
  end,
})
if vim.v.vim_did_enter == 1 then
  gloc().setup_dap_unless_configured()
end
