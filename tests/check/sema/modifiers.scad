// `%` and `*` subtrees are not part of the solid; `#` and `!` are.

%cube(1);
//@ 3:1 warning[W0106]: not part of the solid
*sphere(2);
//@ 5:1 warning[W0107]
translate([1, 0, 0]) %sphere(1);
//                   ^ warning[W0106]
#cube(2);
difference() {
    cube(3);
    # translate([1, 1, 1]) cube(3);
}
// Names inside modified subtrees are still checked.
translate([5, 0, 0]) *cube(undefined_size);
//                   ^ warning[W0107]
//                         ^^^^^^^^^^^^^^ error[E0101]
