// OpenSCAD's deprecated child() and assign(), and its reading of string escapes, in a .scad file.
a = 10;
// assign computes every value in the enclosing scope before binding any.
assign(a = 1, b = a + 1) echo(a = a, b = b);
assign(c = 5) {
    echo(c = c);
    assign(c = c + 1) echo(c2 = c);
}
assign(q = 1, q = 2) echo(q = q);
$v = 1;
module show() echo(v = $v);
assign($v = 7) show();
show();
// Special variables are looked up dynamically: a `$`-binding is seen by the values after it.
assign(s = $v, $v = 5, t = $v) echo(s = s, t = t);
assign() echo("empty");
module twice() assign(n = $children) { echo(n = n); children(); children(); }
twice() echo("child of twice");
// child() is children(0); child(i) reads the first argument, whatever its name.
module pick() {
    child();
    child(1);
    child(index = 1);
    child(1.7);
    echo(count = $children);
}
pick() {
    echo("first");
    echo("second");
}
module nested() child(0);
module outer() nested() child(1);
outer() {
    echo("outer 0");
    echo("outer 1");
}
// Escapes: OpenSCAD drops a backslash that starts no escape.
echo("a\0b\qc");
echo("\a|\b|\v|\f|\e|\'|\?");
echo("\x41|\x80|\x4|\x4g|\x00|\x0A");
echo("\u263A|\u263|\u0000|\uD800|\u00e9");
echo("\U01F600|\U0263A|\U110000|\U000041");
echo(len("\U01F600"), len("\x4"), len("\u263"), len("a\\b"));
echo("line
break");

// group() is a union: its children are evaluated in order, without a warning.
group() { echo("in a group"); group() echo("in a nested group"); }
