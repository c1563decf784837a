-- Filetype detection: `.gbas` is GBASIC, `.gloc` is GLOC, `.mi` a Slocum mission (slocum_mission)
-- and `.ma` a mission argument file (slocum_ma). Neovim sources this file when filetype detection
-- is enabled (the default), for every plugin on the runtimepath.
vim.filetype.add({ extension = { gbas = "gbasic", gloc = "gloc", mi = "slocum_mission", ma = "slocum_ma" } })
