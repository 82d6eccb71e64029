// A block left open at the end of the file is reported at its opening brace.
module part() {
//            ^ error[E0008]: unclosed `{`
    cube(1);
    sphere(2);
part();
