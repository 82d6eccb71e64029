// Scoping: the last assignment wins for the whole scope, at the position of the first.
a = 1;
b = a;
echo(a = a, b = b);
a = 2;
{ x = 5; }
echo(x = x);
module m(p = 1, q = a) echo(p = p, q = q);
m(p = 5);
function f(p = 1, q = a) = [p, q];
echo(f(p = 5), f(7));
c = 3;
module sc() { echo(in_c = c); c = 4; echo(after = c); }
sc();
module outer() { y = 10; module inner() echo(y = y); inner(); }
outer();
g = function(x, y = 2) let(z = x) z * y;
echo(g(3), g);
function h(x) = x;
h = function(x) 2 * x;
echo(h(3));
adder = function(n) function(x) x + n;
add2 = adder(2);
echo(add2(5), adder(10)(1));
if (true) { ifv = 1; echo(ifv = ifv); }
for (i = [0 : 1]) { loopv = i * 10; echo(loopv = loopv); }
let (l = 7) echo(l = l);
