// Number formatting in echo and str, as OpenSCAD 2021.01 prints them.
echo(1/3, 1e6, 1e-5, 123456789, 1234567, 0.1 + 0.2, -0, 1e21, 1/0, -1/0, 2/3*1e10, 100000, 3.0, 1.5e-7);
echo(str(1/3), str(1e20), str(1.0), str(0.000001), str(1e-7), str(123456.7), str(1234567.8));
echo(1234565, 0.1234565, 99999.95, 999999.5, -1.5e-300, 123.456e3, 12345678901, -2.5, PI);
echo("s", [1, "a", [2, undef]], true, false, undef, [], [[]]);
echo(a = 1, b = "two", c = [3]);
echo(str("x", 1, [1, 2], true, undef), str());
