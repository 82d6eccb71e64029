// Built-in functions against OpenSCAD's results.
echo(sin(30) == 0.5, cos(60) == 0.5, sin(60) == sqrt(3) / 2, sin(45) == sqrt(2) / 2, tan(45) == 1);
echo(sin(90), cos(90), cos(180), sin(180), sin(-90), cos(270), tan(90), sin(1e10), cos(-720));
echo(asin(1), acos(0), atan(1), atan2(1, 1), atan2(-1, -1), acos(2));
echo(abs(-3), sign(-3), sign(0), sign(2), floor(-1.5), ceil(-1.5), round(-2.5), round(2.5), round(0.4));
echo(ln(exp(1)), log(100), log(2, 8), exp(0), pow(2, 0.5), sqrt(16), sqrt(-1));
echo(min(4, 2, 8), max(1, 5, 3), min([3, 1, 2]), max([1, 5, 3]), max(1));
echo(norm([3, 4]), norm([]), norm([1, 2, 2]), cross([1, 0, 0], [0, 1, 0]), cross([1, 2], [3, 4]));
echo(len([1, [2, 3]]), len("abc"), len("é"), len([]), concat([1], [2, 3], 4), concat("ab", [1]), concat());
echo(chr(65), chr([72, 105]), chr(72, 105), ord("A"), ord("é"), chr(233));
echo(lookup(1.5, [[1, 10], [2, 20]]), lookup(0, [[1, 10], [2, 20]]), lookup(5, [[1, 10], [2, 20]]));
echo(lookup(2.5, [[3, 30], [1, 10], [2, 20]]), lookup(-1, [[-2, 0], [0, 4]]));
echo(search("a", "abcabc"), search("abc", "abcabc", 0), search([1, 2], [[1, "x"], [2, "y"], [1, "z"]]));
echo(search(1, [1, 2, 1], 0), search("b", "abcb", 0), search("zz", "abc"), search([[1, 2]], [[1, 2], [3, 4]]));
echo(search(3, [[1, "a", 3], [3, "b", 4]], 0, 2), search(["a", "b"], [["a", 1], ["b", 2]]));
echo(search("abc", "abcabc", 2), search([1, 5], [1, 2, 1], 0), search(5, [1, 2]));
echo(rands(0, 1, 3, 42), rands(0, 10, 2, 1), rands(5, 5, 2, 7), rands(1, 0, 2, 3));
echo(is_num(1), is_num(0 / 0), is_list([]), is_string(""), is_bool(1), is_undef(undef), is_function(function(x) x), is_list([0 : 1]));
