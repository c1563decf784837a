" gloc lsp for ALE: one definition for the five filetypes, each under its own
" language id (the server reads a file with one of gloc's extensions by its
" extension in any case). The binary is g:gloc_path (default `gloc`, looked up
" on PATH); the project root is the nearest folder with a gloc.toml or .git,
" else the file's folder.

function! gloc#ale#ProjectRoot(buffer) abort
    for l:marker in ['gloc.toml', '.git']
        let l:found = ale#path#FindNearestFile(a:buffer, l:marker)
        if empty(l:found)
            let l:found = ale#path#FindNearestDirectory(a:buffer, l:marker)
        endif
        if !empty(l:found)
            return fnamemodify(substitute(l:found, '/$', '', ''), ':h')
        endif
    endfor
    return expand('#' . a:buffer . ':p:h')
endfunction

function! gloc#ale#Define(filetype) abort
    call ale#linter#Define(a:filetype, {
    \   'name': 'gloc',
    \   'lsp': 'stdio',
    \   'executable': {buffer -> get(g:, 'gloc_path', 'gloc')},
    \   'command': '%e lsp',
    \   'language': a:filetype,
    \   'project_root': function('gloc#ale#ProjectRoot'),
    \})
endfunction
