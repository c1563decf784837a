-- The default `gloc lsp` configuration for Neovim 0.11's vim.lsp.config: with this plugin on the
-- runtimepath, `vim.lsp.enable("gloc")` alone starts the server for GBASIC and GLOC buffers and
-- Slocum mission files (.mi, .ma).
-- require("gloc").setup() adds your options (gloc_path, masterdata) on top of it.
return {
  cmd = { "gloc", "lsp" },
  filetypes = { "gbasic", "gloc", "slocum_mission", "slocum_ma" },
  root_markers = { "gloc.toml", ".git" },
}
