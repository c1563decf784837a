" Vim syntax file
" Language: GBASIC, the BASIC-like language of the gloc glider toolchain (.gbas)
" Case-insensitive. Sensor names are recognised by their Masterdata prefix; the language
" server's semantic tokens refine this with the real sensor list.

if exists("b:current_syntax")
  finish
endif

let s:cpo_save = &cpo
set cpo&vim

syn case ignore

" Later-defined matches win when two start at the same place, so the specific forms come after
" the general ones (a float literal after an integer, `end if` after `end`, a built-in call
" after the type name it shares with `float`).
syn match   gbasicIdentifier    "\<\h\w*\>"
syn match   gbasicSensor        "\<\%(sci\|xs\|cc\|dc\|dhs\|[cfus]\)_\w\+\>"
syn match   gbasicSensorReadOnly "\<[mx]_\w\+\>"

syn keyword gbasicConditional   if then elseif else endif
syn keyword gbasicRepeat        while wend do loop until for to step next exit
syn keyword gbasicStatement     yield print let
syn keyword gbasicDeclaration   dim const as
syn keyword gbasicOperator      and or not mod
syn match   gbasicStatement     "\<end\>"
syn match   gbasicConditional   "\<end\s\+if\>"
syn match   gbasicType          "\<\%(integer\|float\)\>"
syn match   gbasicBuiltin       "\<\%(abs\|sqrt\|min\|max\|int\|float\)\>\ze\s*("

syn match   gbasicLabelKeyword  "\<label\s*:" nextgroup=gbasicLabelName skipwhite
syn match   gbasicGoto          "\<goto\>" nextgroup=gbasicLabelName skipwhite
syn match   gbasicLabelName     "\h\w*" contained

syn match   gbasicOperator      "<>\|<=\|>=\|[-+*/\\<>=]"
syn match   gbasicNumber        "\<\d\+\>"
syn match   gbasicFloat         "\<\d\+\.\d*\%([eE][-+]\=\d\+\)\=\|\.\d\+\%([eE][-+]\=\d\+\)\=\>\|\<\d\+[eE][-+]\=\d\+\>"

syn region  gbasicString        start=+"+ skip=+""+ end=+"+ oneline contains=gbasicQuote
syn match   gbasicQuote         +""+ contained

syn keyword gbasicTodo          TODO FIXME XXX NOTE contained
syn match   gbasicComment       "'.*$" contains=gbasicTodo,@Spell
syn match   gbasicComment       "\<rem\>.*$" contains=gbasicTodo,@Spell

hi def link gbasicConditional    Conditional
hi def link gbasicRepeat         Repeat
hi def link gbasicStatement      Statement
hi def link gbasicDeclaration    Keyword
hi def link gbasicType           Type
hi def link gbasicBuiltin        Function
hi def link gbasicOperator       Operator
hi def link gbasicLabelKeyword   Label
hi def link gbasicGoto           Statement
hi def link gbasicLabelName      Label
hi def link gbasicSensor         Special
hi def link gbasicSensorReadOnly gbasicSensor
hi def link gbasicIdentifier     Identifier
hi def link gbasicNumber         Number
hi def link gbasicFloat          Float
hi def link gbasicString         String
hi def link gbasicQuote          SpecialChar
hi def link gbasicComment        Comment
hi def link gbasicTodo           Todo

let b:current_syntax = "gbasic"

let &cpo = s:cpo_save
unlet s:cpo_save
