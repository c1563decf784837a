" Vim syntax file
" Language: Slocum glider mission file (.mi): `sensor: NAME(UNITS) VALUE`, `behavior: NAME`,
" `b_arg: NAME(UNITS) VALUE`, `#` comments (docs/simulator.md). Line-oriented, as the
" simulator's parser (gloc_sim::mission); the editor's diagnostics come from gloc lsp.

if exists("b:current_syntax")
  finish
endif

let s:cpo_save = &cpo
set cpo&vim

syn case ignore

syn match   slocumMissionBehaviorKeyword "^\s*behavior:" nextgroup=slocumMissionBehavior skipwhite
syn match   slocumMissionBehavior        "\w\+" contained
syn match   slocumMissionArgKeyword      "^\s*b_arg:" nextgroup=slocumMissionArgument skipwhite
syn match   slocumMissionArgument        "\w\+" contained nextgroup=slocumMissionUnits
syn match   slocumMissionSensorKeyword   "^\s*sensor:" nextgroup=slocumMissionSensor skipwhite
syn match   slocumMissionSensor          "\w\+" contained nextgroup=slocumMissionUnits
syn match   slocumMissionUnits           "([^)[:space:]#]*)" contained nextgroup=slocumMissionNumber skipwhite
syn match   slocumMissionNumber          "[-+]\=\%(\d\+\.\=\d*\|\.\d\+\)\%([eE][-+]\=\d\+\)\=" contained

syn keyword slocumMissionTodo            TODO FIXME XXX NOTE contained
syn match   slocumMissionComment         "#.*$" contains=slocumMissionTodo,@Spell

hi def link slocumMissionBehaviorKeyword Keyword
hi def link slocumMissionBehavior        Function
hi def link slocumMissionArgKeyword      Keyword
hi def link slocumMissionArgument        Identifier
hi def link slocumMissionSensorKeyword   Keyword
hi def link slocumMissionSensor          Special
hi def link slocumMissionUnits           Type
hi def link slocumMissionNumber          Number
hi def link slocumMissionComment         Comment
hi def link slocumMissionTodo            Todo

let b:current_syntax = "slocum_mission"

let &cpo = s:cpo_save
unlet s:cpo_save
