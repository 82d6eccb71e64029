" Buffer settings for qcsg (and OpenSCAD) files: comments, indentation, include paths.
if exists('b:did_ftplugin')
  finish
endif
let b:did_ftplugin = 1

setlocal commentstring=//\ %s
setlocal comments=s1:/*,mb:*,ex:*/,:///,://
setlocal formatoptions-=t formatoptions+=croql
setlocal cindent cinkeys-=0# cinoptions+=j1,J1
setlocal suffixesadd=.qcsg,.scad
setlocal include=^\\s*\\%(include\\\|use\\)\\s*<

let b:undo_ftplugin = 'setlocal commentstring< comments< formatoptions< cindent< cinkeys< cinoptions< suffixesadd< include<'
