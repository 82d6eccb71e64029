// Recursion: plain and tail recursion, functions as values.
function fact(n) = n <= 1 ? 1 : n * fact(n - 1);
function count(n, acc = 0) = n == 0 ? acc : count(n - 1, acc + 1);
function sum(v, i = 0) = i >= len(v) ? 0 : v[i] + sum(v, i + 1);
function fib(n) = n < 2 ? n : fib(n - 1) + fib(n - 2);
echo(fact(10), count(100000), sum([1, 2, 3, 4]), fib(15));
function map(f, v) = [for (x = v) f(x)];
echo(map(function(x) x * x, [1, 2, 3]));
function compose(f, g) = function(x) f(g(x));
echo(compose(function(x) x + 1, function(x) x * 2)(5));
module tree(n) { if (n > 0) { echo(n = n); tree(n - 1); } }
tree(3);
echo(let (a = 2) a * 3, assert(true) 5, echo("inner") 6);
