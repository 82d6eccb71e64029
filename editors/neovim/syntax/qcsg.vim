" Syntax highlighting for qcsg (.qcsg and OpenSCAD-compatible .scad), without tree-sitter.
" The keyword and built-in lists follow crates/qcsg-syntax/src/lexer.rs and
" crates/qcsg-sema/src/builtins.rs.
if exists('b:current_syntax')
  finish
endif

syntax keyword qcsgConditional if else
syntax keyword qcsgRepeat for each
syntax keyword qcsgKeyword let
syntax keyword qcsgDefine module function
syntax keyword qcsgInclude include use nextgroup=qcsgIncludePath skipwhite
syntax keyword qcsgBoolean true false
syntax keyword qcsgConstant undef PI
syntax keyword qcsgSpecialForm assert echo

syntax keyword qcsgBuiltinModule cube sphere cylinder ellipsoid paraboloid hyperboloid cone
      \ halfspace quadric square circle polygon text polyhedron import import_stl import_off
      \ import_dxf surface linear_extrude rotate_extrude dxf_linear_extrude dxf_rotate_extrude
      \ projection hull minkowski offset translate rotate scale mirror multmatrix resize color
      \ group union intersection difference complement intersection_for render children child
      \ assign
syntax keyword qcsgBuiltinFunction abs sign sin cos tan asin acos atan atan2 floor ceil round
      \ ln log exp pow sqrt min max norm cross len concat lookup str chr ord search is_undef
      \ is_bool is_num is_string is_list is_function rands version version_num parent_module
      \ dxf_dim dxf_cross

syntax match qcsgSpecialVariable /\$[A-Za-z0-9_]*/
syntax match qcsgNumber /\<\d\+\%(\.\d*\)\=\%([eE][+-]\=\d\+\)\=/
syntax match qcsgNumber /\%(\<\|\W\)\zs\.\d\+\%([eE][+-]\=\d\+\)\=/
syntax match qcsgOperator /==\|!=\|<=\|>=\|&&\|||\|[-+*\/%^<>!?:=]/
" A modifier is `* ! # %` at the start of a statement: first on a line or after `;` `{` `}` `)`.
syntax match qcsgModifier /\%(^\|[;{})]\)\s*\zs[*!#%]\+\ze\s*[A-Za-z_{(]/

syntax match qcsgIncludePath /<[^>]*>/ contained
syntax region qcsgString start=/"/ skip=/\\\\\|\\"/ end=/"/ contains=qcsgEscape,qcsgBadEscape
syntax match qcsgBadEscape /\\./ contained
syntax match qcsgEscape /\\\%(["\\ntr]\|x\x\{2}\|u\x\{4}\)/ contained

syntax match qcsgModuleName /\%(\<module\s\+\)\@<=[A-Za-z_$][A-Za-z0-9_]*/
syntax match qcsgFunctionName /\%(\<function\s\+\)\@<=[A-Za-z_$][A-Za-z0-9_]*/

syntax keyword qcsgTodo TODO FIXME XXX NOTE contained
syntax region qcsgComment start=+//+ end=/$/ contains=qcsgTodo,@Spell
syntax region qcsgComment start=+/\*+ end=+\*/+ contains=qcsgTodo,@Spell
syntax region qcsgDocComment start=+///\%(/\)\@!+ end=/$/ contains=qcsgTodo,@Spell
syntax region qcsgDocComment start=+/\*\*\%([*/]\)\@!+ end=+\*/+ contains=qcsgTodo,@Spell

highlight default link qcsgConditional Conditional
highlight default link qcsgRepeat Repeat
highlight default link qcsgKeyword Keyword
highlight default link qcsgDefine Keyword
highlight default link qcsgInclude Include
highlight default link qcsgIncludePath String
highlight default link qcsgBoolean Boolean
highlight default link qcsgConstant Constant
highlight default link qcsgSpecialForm Statement
highlight default link qcsgBuiltinModule Function
highlight default link qcsgBuiltinFunction Function
highlight default link qcsgSpecialVariable Identifier
highlight default link qcsgNumber Number
highlight default link qcsgOperator Operator
highlight default link qcsgModifier Special
highlight default link qcsgString String
highlight default link qcsgEscape SpecialChar
highlight default link qcsgBadEscape Error
highlight default link qcsgModuleName Function
highlight default link qcsgFunctionName Function
highlight default link qcsgTodo Todo
highlight default link qcsgComment Comment
highlight default link qcsgDocComment SpecialComment

let b:current_syntax = 'qcsg'
