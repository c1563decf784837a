" ALE loads this for slocum_ma buffers: gloc lsp (editors/vim/autoload/gloc/ale.vim).
call gloc#ale#Define('slocum_ma')
