" ALE loads this for gloc buffers: gloc lsp (editors/vim/autoload/gloc/ale.vim).
call gloc#ale#Define('gloc')
