// version(), version_num(), parent_module(n), $parent_modules, and identifiers that start with
// digits, as OpenSCAD 2021.01 has them.
echo(version = version(), num = version_num());
echo(version()[0] >= 2019);

module c() { echo(parent_module(0), parent_module(1), parent_module(), $parent_modules); }
module d() { children(); }
module e() { c(); }
d() c();
d() e();
d() translate([1, 0, 0]) { c(); }
module f(n) { if (n > 0) f(n - 1); else echo(parent_module(3), parent_module(1.7), $parent_modules); }
f(3);

8bit = 3;
1e = 2;
0x10 = 7;
echo(8bit, 1e, 0x10, 1e5, 2.5, 1.e2);
