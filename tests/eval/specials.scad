// $-variables are dynamically scoped; children and $children.
module m2() { $y = 7; children(); }
m2() echo(dyn = $y);
$z = 1;
module m3() echo(inner = $z);
module m4() { $z = 2; m3(); }
m4();
m3();
module m5() { echo($children = $children, $x = $x); children(); }
m5($x = 3) { echo("c0"); echo("c1"); }
module pick() { children(1); children([0, 2]); children([2 : -1 : 1]); }
pick() { echo("a"); echo("b"); echo("c"); }
function dyn() = $w;
module setw() { $w = 42; echo(w = dyn()); }
setw();
echo(top_w = dyn());
echo($fn = $fn, $fa = $fa, $fs = $fs, $t = $t);
translate([1, 0, 0], $fn = 5) echo(fn = $fn);
module count() echo(n = $children);
count() { cube(); sphere(); }
count();
