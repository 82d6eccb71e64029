" OpenSCAD (.scad) files use the qcsg highlighting unless another syntax file is loaded first.
if exists('b:current_syntax')
  finish
endif
runtime! syntax/qcsg.vim
let b:current_syntax = 'openscad'
