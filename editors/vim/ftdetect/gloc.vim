" Filetypes of the gloc files, for Vim (Neovim's plugin does the same in Lua):
" `.gbas` GBASIC, `.gloc` GLOC, `.mi` missions, `.ma` mission arguments, `.cac`
" and files named `masterdata` sensor lists.
autocmd BufRead,BufNewFile *.gbas,*.gbasic setfiletype gbasic
autocmd BufRead,BufNewFile *.gloc setfiletype gloc
" Vim's own detection makes `.mi` Modula-2: these override it.
autocmd BufRead,BufNewFile *.mi,*.MI set filetype=slocum_mission
autocmd BufRead,BufNewFile *.ma,*.MA set filetype=slocum_ma
autocmd BufRead,BufNewFile *.cac,*.CAC,masterdata setfiletype slocum_masterdata
