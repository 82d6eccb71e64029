// A library of shapes for the include/use cases.

/// Default wall thickness; a file including this one may override it.
wall = 2;
lib_version = 3;

/// A hollow box.
module shell(size = [10, 10, 10]) {
    difference() {
        cube(size, center = true);
        cube(size - [wall, wall, wall], center = true);
    }
}

/// The inner size of a shell.
function inner(size) = size - [wall, wall, wall];

module _helper() sphere(1);

// An unused definition in a library is not reported.
function library_only(x) = x;

// Statements of a library run when it is included, and only then.
shell([4, 4, 4]);
