" Vim syntax file
" Language: Slocum glider sensor lists: masterdata (`sensor: NAME(UNITS) [DEFAULT] # comment`,
" `behavior:` sections of default `b_arg:`s, `#!` metadata, preprocessor lines) and `.cac` lists
" (`s: T|F INDEX COLUMN BYTES NAME UNITS`).

if exists("b:current_syntax")
  finish
endif

let s:cpo_save = &cpo
set cpo&vim

syn match   slocumMdSensorKeyword   "^\s*sensor:" nextgroup=slocumMdSensor skipwhite
syn match   slocumMdSensor          "\w\+" contained nextgroup=slocumMdUnits
syn match   slocumMdBehaviorKeyword "^\s*behavior:" nextgroup=slocumMdBehavior skipwhite
syn match   slocumMdBehavior        "\w\+" contained
syn match   slocumMdArgKeyword      "^\s*b_arg:" nextgroup=slocumMdArgument skipwhite
syn match   slocumMdArgument        "\w\+" contained nextgroup=slocumMdUnits
syn match   slocumMdUnits           "([^)[:space:]#]*)" contained nextgroup=slocumMdNumber skipwhite
syn match   slocumMdNumber          "[-+]\=\%(\d\+\.\=\d*\|\.\d\+\)\%([eE][-+]\=\d\+\)\=" contained
syn match   slocumMdCacKeyword      "^\s*s:" nextgroup=slocumMdCacFields skipwhite
syn match   slocumMdCacFields       "[TF]\s\+\d\+\s\+-\=\d\+\s\+\d\+\s\+" contained nextgroup=slocumMdSensor

syn keyword slocumMdTodo            TODO FIXME XXX NOTE contained
syn match   slocumMdComment         "#.*$" contains=slocumMdTodo,@Spell
syn match   slocumMdMetadata        "#!.*$"
syn match   slocumMdPreProc         "^\s*#\s*\%(if\|endif\|define\|else\|ifdef\|ifndef\|include\)\>.*$"

hi def link slocumMdSensorKeyword   Keyword
hi def link slocumMdSensor          Special
hi def link slocumMdBehaviorKeyword Keyword
hi def link slocumMdBehavior        Function
hi def link slocumMdArgKeyword      Keyword
hi def link slocumMdArgument        Identifier
hi def link slocumMdUnits           Type
hi def link slocumMdNumber          Number
hi def link slocumMdCacKeyword      Keyword
hi def link slocumMdCacFields       Number
hi def link slocumMdComment         Comment
hi def link slocumMdMetadata        SpecialComment
hi def link slocumMdPreProc         PreProc
hi def link slocumMdTodo            Todo

let b:current_syntax = "slocum_masterdata"

let &cpo = s:cpo_save
unlet s:cpo_save
