" Filetype detection: *.qcsg is qcsg; *.scad is OpenSCAD (`openscad`) unless something else
" already claimed it. The qcsg language server serves both (see lua/qcsg.lua).
autocmd BufRead,BufNewFile *.qcsg setfiletype qcsg
autocmd BufRead,BufNewFile *.scad setfiletype openscad
