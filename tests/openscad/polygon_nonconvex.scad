// A non-convex outline (an arrow with a notch), extruded: polygon's convex cells must fill
// fragments: 1000000
// exactly the outline, reflex corners included.
linear_extrude(3) polygon([[0, 0], [12, 0], [12, 3], [18, 3], [10, 10], [2, 3], [6, 3], [6, 1], [0, 1]]);
