// Modifiers: `*` is not evaluated, `%` and `#` are, `!` too.
*echo("disabled");
%echo("background");
#echo("highlighted");
module m() { echo(kids = $children); children(); }
m() { *echo("x"); echo("y"); }
intersection_for(i = [0 : 2]) echo(i = i);
if (false) echo("no"); else echo("else");
echo(concat([for (i = [0 : 2]) i * i], [for (i = [10 : -5 : 0]) i]));
x = [for (i = [0 : 0.25 : 1]) i];
echo(x, len(x), x[len(x) - 1] == 1);
