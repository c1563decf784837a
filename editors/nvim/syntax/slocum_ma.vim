" Vim syntax file
" Language: Slocum glider mission argument file (.ma): `behavior_name=NAME`, `<start:b_arg>`
" `b_arg: NAME(UNITS) VALUE` lines `<end:b_arg>`, `<start:waypoints>` `LON LAT` lines
" `<end:waypoints>`, `#` comments (docs/simulator.md).

if exists("b:current_syntax")
  finish
endif

let s:cpo_save = &cpo
set cpo&vim

syn case ignore

syn match   slocumMaBehaviorKeyword "^\s*behavior_name=" nextgroup=slocumMaBehavior
syn match   slocumMaBehavior        "\w\+" contained
syn match   slocumMaSection         "^\s*<\%(start\|end\):\%(b_arg\|waypoints\)>"
syn match   slocumMaArgKeyword      "^\s*b_arg:" nextgroup=slocumMaArgument skipwhite
syn match   slocumMaArgument        "\w\+" contained nextgroup=slocumMaUnits
syn match   slocumMaUnits           "([^)[:space:]#]*)" contained nextgroup=slocumMaNumber skipwhite
syn match   slocumMaNumber          "[-+]\=\%(\d\+\.\=\d*\|\.\d\+\)\%([eE][-+]\=\d\+\)\=" contained
syn match   slocumMaWaypoint        "^\s*[-+]\=\d\+\%(\.\d\+\)\=\s\+[-+]\=\d\+\%(\.\d\+\)\=\ze\s*\%(#\|$\)"

syn keyword slocumMaTodo            TODO FIXME XXX NOTE contained
syn match   slocumMaComment         "#.*$" contains=slocumMaTodo,@Spell

hi def link slocumMaBehaviorKeyword Keyword
hi def link slocumMaBehavior        Function
hi def link slocumMaSection         PreProc
hi def link slocumMaArgKeyword      Keyword
hi def link slocumMaArgument        Identifier
hi def link slocumMaUnits           Type
hi def link slocumMaNumber          Number
hi def link slocumMaWaypoint        Number
hi def link slocumMaComment         Comment
hi def link slocumMaTodo            Todo

let b:current_syntax = "slocum_ma"

let &cpo = s:cpo_save
unlet s:cpo_save
