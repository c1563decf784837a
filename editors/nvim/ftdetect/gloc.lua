-- Filetype detection: `.gbas` is GBASIC, `.gloc` is GLOC. Neovim sources this file when
-- filetype detection is enabled (the default), for every plugin on the runtimepath.
vim.filetype.add({ extension = { gbas = "gbasic", gloc = "gloc" } })
