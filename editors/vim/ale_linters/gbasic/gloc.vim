" ALE loads this for gbasic buffers: gloc lsp (editors/vim/autoload/gloc/ale.vim).
call gloc#ale#Define('gbasic')
