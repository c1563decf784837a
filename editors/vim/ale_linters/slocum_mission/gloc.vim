" ALE loads this for slocum_mission buffers: gloc lsp (editors/vim/autoload/gloc/ale.vim).
call gloc#ale#Define('slocum_mission')
