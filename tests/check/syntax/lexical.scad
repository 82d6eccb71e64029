// Lexical errors: a run of invalid characters is one error; bad escapes point at the escape.
cube(3 @@ 4);
//     ^^ error[E0001]: invalid character
label = "a\qb";
//        ^^ error[E0004]: invalid escape
code = "\x4";
//      ^^^ error[E0004]
star = "\u263A ok";
echo(label, code, star);
