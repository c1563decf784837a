" ALE loads this for slocum_masterdata buffers: gloc lsp (editors/vim/autoload/gloc/ale.vim).
call gloc#ale#Define('slocum_masterdata')
