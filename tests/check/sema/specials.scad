// Special variables are dynamically scoped and never undefined.

$fn = 64;
//@ 3:1 hint[H0101]: `$fn` has no effect
sphere(1, $fa = 2, $fs = 0.5);
//        ^^^ hint[H0101]
//                 ^^^ hint[H0101]

module ring(r = 1) {
    echo(r, $children, $t, $preview, $vpr, $fn);
    // A user special variable set by a caller.
    translate([$offset, 0, 0]) children();
}
ring($offset = 2) sphere(1);

// Read but set nowhere: always `undef`.
echo($never_set);
//   ^^^^^^^^^^ warning[W0108]: `$never_set` is never set

module fine($fn = 10) sphere(1);
//          ^^^ hint[H0101]
fine();
x = let ($fs = 1) 2;
//       ^^^ hint[H0101]
echo(x);
