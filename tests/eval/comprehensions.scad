// Ranges, for loops and list comprehensions.
echo([for (i = [0 : -1 : 3]) i], [for (i = [3 : -1 : 0]) i], [for (i = [0 : 0.1 : 0.3]) i]);
echo([for (i = [0 : 0.1 : 1]) i], [for (i = [3 : 0]) i], [2 : 1 : 0], [0 : 5], [1 : 0.5 : 2]);
echo([for (i = 5) i], [for (i = undef) i], [each "ab"], [each 3], [each [1, 2], each [0 : 1]]);
echo([for (c = "ab") c], [0 : 2][1], "abc"[1], [1, 2, 3].y, [1, 2][5], [1, 2][-1], [1, 2][1.7]);
echo([for (i = 0, j = 1; i < 3; i = i + 1, j = j * 2) [i, j]]);
echo([for (i = [0 : 3]) if (i % 2) i else -i], [for (i = [1, 2]) let (k = i * i) k]);
echo([for (i = [1 : 2]) for (j = [1 : 2]) [i, j]], [for (i = [1 : 2], j = [0 : i]) [i, j]]);
echo([for (i = [0 : 4]) if (i > 1) if (i < 4) i], [for (a = [[1, 2], [3, 4]]) each a]);
echo([for (i = [0 : 2]) (i)], [if (true) 1], [if (false) 1], [let (a = 1, b = a + 1) [a, b]]);
for (i = [0 : 1], j = [5, 6]) echo(i = i, j = j);
echo(len([for (i = [0 : 999]) i]), [for (x = [1, 2, 3]) x * x]);
