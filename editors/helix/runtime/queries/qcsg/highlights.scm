; Highlighting for qcsg: the queries of Helix's OpenSCAD grammar (qcsg's syntax is OpenSCAD's).
; inherits: openscad
