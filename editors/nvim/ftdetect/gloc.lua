-- Filetype detection: `.gbas` is GBASIC, `.gloc` is GLOC, `.mi` a Slocum mission (slocum_mission),
-- `.ma` a mission argument file (slocum_ma), `masterdata` and `.cac` a sensor list
-- (slocum_masterdata). Neovim sources this file when filetype detection is enabled (the default),
-- for every plugin on the runtimepath.
vim.filetype.add(require("gloc").filetype_detection)
