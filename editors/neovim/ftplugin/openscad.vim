" OpenSCAD (.scad) files get the qcsg buffer settings unless another plugin set them up first.
runtime! ftplugin/qcsg.vim
