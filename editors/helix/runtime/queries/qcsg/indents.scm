; Indentation for qcsg: the queries of Helix's OpenSCAD grammar.
; inherits: openscad
