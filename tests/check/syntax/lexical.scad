// Lexical errors: a run of invalid characters is one error. In a `.scad` file an escape that
// OpenSCAD 2021.01 reads its own way keeps OpenSCAD's meaning, with a warning at the escape
// (lexical.qcsg: the same escapes are errors in a `.qcsg` file).
cube(3 @@ 4);
//     ^^ error[E0001]: invalid character
label = "a\qb\0";
//        ^^ warning[W0004]: OpenSCAD drops the backslash of `\q`
//           ^^ warning[W0004]
code = "\x4|\x80";
//      ^^^ warning[W0004]: reads `x4`
//          ^^^^ warning[W0004]
nul = "\x00|\u0000|\uD800|\U110000";
//     ^^^^ warning[W0004]: as a space
//          ^^^^^^ warning[W0004]
//                 ^^^^^^ warning[W0004]
//                        ^^^^^^^^ warning[W0004]
lines = "a
b";
//@ 17:11 warning[W0004]: line break
star = "\u263A \U01F600 ok";
echo(label, code, nul, lines, star);
