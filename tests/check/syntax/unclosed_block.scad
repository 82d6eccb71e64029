// A block left open at the end of the file is reported at its opening brace. The block keeps
// what follows, as an editor shows it while the `}` is still to be typed: here the call to
// `part` is inside `part`'s own body.
module part() {
//            ^ error[E0008]: unclosed `{`
//     ^^^^ warning[W0103]: never instantiated
    cube(1);
    sphere(2);
part();
