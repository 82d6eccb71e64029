// text()'s halign, valign and spacing: each variant beside a marker at its origin.
$fn = 128;
linear_extrude(height = 2) {
    for (i = [0 : 2]) translate([0, 30 * i])
        text("Hog", size = 7, halign = ["left", "center", "right"][i]);
    for (i = [0 : 3]) translate([60, 25 * i])
        text("Tyg", size = 7, valign = ["baseline", "top", "center", "bottom"][i]);
    translate([0, -25]) text("AVAWAY", size = 6, spacing = 1.4);
    translate([0, -45]) text("wave", size = 6, spacing = 0.8, halign = "center");
}
