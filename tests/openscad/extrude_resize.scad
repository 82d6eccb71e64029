// resize of 2-D shapes uses their x and y extent.
// fragments: 1000000
linear_extrude(1) resize([4, 0], auto = true) square([1, 2]);
translate([6, 0, 0]) linear_extrude(2) resize([3, 5]) square([1, 2]);
