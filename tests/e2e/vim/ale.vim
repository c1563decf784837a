" Vim with ALE, set up as docs/editors.md says. Run by tests/e2e/run as
"   vim -N -u SETUP -i NONE -es -S tests/e2e/vim/ale.vim
" with SETUP the guide's `vim-ale' block word for word (so it is the vimrc, and
" Vim loads ALE and the gloc plugin as at a normal start), `gloc' on PATH and
" GLOC_REPO the repository. Completion is typed: `A<C-x><C-o>`, `<C-n>` to the
" wanted word, `<C-y>`, through :normal.

let s:failures = 0
let s:repo = $GLOC_REPO

" Vim in Ex mode has no reliable stdout for scripts: the report goes to
" $GLOC_TEST_LOG, which tests/e2e/run prints.
function! s:Say(line) abort
    call writefile([a:line], $GLOC_TEST_LOG, 'a')
endfunction

function! s:Check(ok, what, ...) abort
    if a:ok
        call s:Say('ok: ' . a:what)
    else
        let s:failures += 1
        call s:Say('FAILED: ' . a:what . (a:0 ? ' (' . string(a:1) . ')' : ''))
    endif
endfunction

function! s:Wait(condition, seconds) abort
    let l:deadline = reltimefloat(reltime()) + a:seconds
    while !eval(a:condition) && reltimefloat(reltime()) < l:deadline
        sleep 50m
    endwhile
    return eval(a:condition)
endfunction

" A scratch project: Fig. 2, Fig. 3, comet's nsb3.mi and its .ma files.
let s:root = tempname()
call mkdir(s:root . '/missions', 'p')
call system('cp ' . shellescape(s:repo . '/examples/fig2.gloc') . ' ' . shellescape(s:repo . '/examples/fig3.gbas') . ' ' . shellescape(s:root))
call system('cp ' . shellescape(s:repo . '/data/comet/missions/nsb3.mi') . ' ' . shellescape(s:root . '/missions/'))
call system('cp -r ' . shellescape(s:repo . '/data/comet/mafiles') . ' ' . shellescape(s:root . '/'))

" The errors ALE shows for the current buffer, after it has linted.
function! s:Errors() abort
    return filter(copy(ale#engine#GetLoclist(bufnr(''))), 'v:val.type is# "E"')
endfunction

function! s:Open(file, filetype) abort
    execute 'edit ' . fnameescape(s:root . '/' . a:file)
    call s:Check(&filetype is# a:filetype, a:file . ' has filetype ' . a:filetype, &filetype)
    call s:Check(&omnifunc is# 'ale#completion#OmniFunc', 'the omnifunc is ALE''s', &omnifunc)
    ALELint
    call s:Check(s:Wait('!ale#engine#IsCheckingBuffer(bufnr("")) && has_key(get(g:ale_buffer_info, bufnr(""), {}), "loclist")', 20),
    \   'ALE linted ' . a:file)
    " The server's diagnostics come after ALE's first pass: give them time.
    sleep 2
endfunction

" Types TEXT on a new line after line AFTER (0: at the end), the cursor after it.
function! s:Type(after, text) abort
    let l:after = a:after == 0 ? line('$') : a:after
    call append(l:after, a:text)
    call cursor(l:after + 1, 1)
endfunction

" What the menu offers, read while it is open (from <C-r>=).
function! GlocRecordMenu() abort
    let s:menu = map(copy(complete_info(['items']).items), 'v:val.word')
    return ''
endfunction

" <C-x><C-o> at the end of the line, as a user types it: the words the menu
" offers, and the line with the first one inserted, as Vim inserts it. (Moving
" down the menu with <C-n> in the same :normal does not work: the keys are read
" before ALE's answer arrives.)
function! s:Complete() abort
    let s:menu = []
    execute "normal! A\<C-x>\<C-o>\<C-r>=GlocRecordMenu()\<CR>"
    return [s:menu, getline('.')]
endfunction

function! s:Main() abort
    " GBASIC
    call s:Open('fig3.gbas', 'gbasic')
    call s:Check(empty(s:Errors()), 'Fig. 3 has no errors', s:Errors())
    call s:Type(0, 'x = m_dep')
    let [l:words, l:line] = s:Complete()
    call s:Check(index(l:words, 'm_depth') >= 0, '`m_dep` offers m_depth in GBASIC', l:words[:9])
    call s:Check(l:line is# 'x = m_depth', 'choosing it gives `x = m_depth`', l:line)
    set nomodified

    " GLOC
    call s:Open('fig2.gloc', 'gloc')
    call s:Check(empty(s:Errors()), 'Fig. 2 has no errors', s:Errors())
    " GLOC takes sensor names: completion inserts the name, which ALE filters by.
    call s:Type(0, 'loads m_dep')
    let [l:words, l:line] = s:Complete()
    call s:Check(index(l:words, 'm_depth') >= 0, '`loads m_dep` offers m_depth in GLOC', l:words[:9])
    call s:Check(l:line is# 'loads m_depth', 'choosing it gives `loads m_depth`', l:line)
    " A typo: the server's diagnostic reaches ALE's list.
    call setline('.', 'lodd 1.0,r0')
    ALELint
    call s:Check(s:Wait('!empty(filter(s:Errors(), ''v:val.text =~# "did you mean `loadd`"''))', 20),
    \   'typing `lodd` gets the server''s "did you mean `loadd`"', s:Errors())
    set nomodified

    " A mission
    call s:Open('missions/nsb3.mi', 'slocum_mission')
    call s:Check(empty(s:Errors()), 'nsb3.mi has no errors', s:Errors())
    " Line 67 is yo's `args_from_file` line; a new argument of yo under it.
    call s:Type(67, '    b_arg: d_t')
    let [l:words, l:line] = s:Complete()
    call s:Check(index(l:words, 'd_target_depth') >= 0, '`b_arg: d_t` offers d_target_depth', l:words)
    call setline('.', '    b_arg: d_ta')
    let [l:words, l:line] = s:Complete()
    call s:Check(l:line is# '    b_arg: d_target_depth', '`b_arg: d_ta` completes the name (ALE cuts the inserted text at `(`)', l:line)
    set nomodified
endfunction

try
    call s:Main()
catch /.*/
    call s:Check(0, 'the test ran to its end', v:exception . ' at ' . v:throwpoint . ' ' . v:errmsg)
endtry

call s:Say(s:failures == 0 ? 'all passed' : s:failures . ' failed')
if s:failures == 0
    qall!
else
    cquit!
endif
