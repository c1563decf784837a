" Vim syntax file
" Language: GLOC, the glider's register assembly (.gloc)
" One label or instruction per line; the role of a numeric operand (sensor index, label number)
" depends on the mnemonic, so the operands of loads, stores, cbr and jumpi get their own groups.

if exists("b:current_syntax")
  finish
endif

let s:cpo_save = &cpo
set cpo&vim

syn case ignore

syn keyword glocHeader          nregs nblbs nlbls ninstr nmem
syn keyword glocInstruction     loadi loadd loadm storem mov add sub mul div mod neg abs sqrt
syn keyword glocInstruction     min max i2d d2i and or xor not cmpeq cmpne cmplt cmple cmpgt cmpge
syn keyword glocInstruction     print prints write writes nop
syn keyword glocSensorInstruction loads stores
syn keyword glocControl         cbr jumpi jump yield halt
syn keyword glocLabelKeyword    label nextgroup=glocLabelNumber skipwhite
syn match   glocLabelNumber     "\d\+" contained

syn match   glocRegister        "\<r\d\+\>"
syn match   glocNumber          "[-+]\=\<\d\+\>"
syn match   glocFloat           "[-+]\=\<\d\+\.\d*\%([eE][-+]\=\d\+\)\=\|[-+]\=\<\d\+[eE][-+]\=\d\+\>"

" Operands whose meaning comes from the mnemonic; defined after the numbers so they win.
syn match   glocSensorIndex     "\%(^\s*loads\s\+\)\@<=\d\+"
syn match   glocSensorIndex     "\%(^\s*stores\s\+r\d\+\s*,\s*\)\@<=\d\+"
syn match   glocLabelReference  "\%(^\s*jumpi\s\+\)\@<=\d\+"
syn match   glocLabelReference  "\%(^\s*cbr\s\+r\d\+\s*,\s*\)\@<=\d\+"
syn match   glocLabelReference  "\%(^\s*cbr\s\+r\d\+\s*,\s*\d\+\s*,\s*\)\@<=\d\+"

syn region  glocString          start=+"+ skip=+\\.+ end=+"+ oneline contains=glocEscape
syn match   glocEscape          +\\.+ contained

syn keyword glocTodo            TODO FIXME XXX NOTE contained
syn match   glocComment         "#.*$" contains=glocTodo,@Spell

hi def link glocHeader            PreProc
hi def link glocInstruction       Statement
hi def link glocSensorInstruction Statement
hi def link glocControl           Conditional
hi def link glocLabelKeyword      Label
hi def link glocLabelNumber       Label
hi def link glocLabelReference    Label
hi def link glocRegister          Identifier
hi def link glocSensorIndex       Special
hi def link glocNumber            Number
hi def link glocFloat             Float
hi def link glocString            String
hi def link glocEscape            SpecialChar
hi def link glocComment           Comment
hi def link glocTodo              Todo

let b:current_syntax = "gloc"

let &cpo = s:cpo_save
unlet s:cpo_save
