//! The files generated programs `include` and `use`, written once per run into its directory.
//!
//! They cover what loading must survive: an ordinary library of modules, functions and
//! variables, a `.scad` file, a pair of files that include each other, a file that includes
//! itself, one with syntax errors, an empty one, one that is not UTF-8, and a directory where a
//! file is expected ([`crate::generate::INCLUDE_PATHS`] also names paths that are no file).

use std::io;
use std::path::Path;

/// The library files, by name relative to the run's directory.
const FILES: &[(&str, &[u8])] = &[
    (
        "lib.qcsg",
        b"// A small library.\n\
          lib_size = 3;\n\
          /// A rounded rod.\n\
          module rod(h = 4, r = 1) { cylinder(h = h, r = r); translate([0, 0, h]) sphere(r); }\n\
          module ring(n = 6) for (i = [0 : n - 1]) rotate([0, 0, i * 360 / n]) translate([4, 0, 0]) children();\n\
          function twice(x) = 2 * x;\n\
          function fact(n) = n <= 1 ? 1 : n * fact(n - 1);\n\
          echo(\"lib loaded\");\n\
          rod();\n",
    ),
    (
        "shapes.scad",
        b"module shell(r = 5, t = 1) difference() { sphere(r); sphere(r - t); }\n\
          function area(r) = PI * r * r;\n\
          shape_count = 2;\n",
    ),
    ("loop_a.qcsg", b"include <loop_b.qcsg>\nmodule a() cube(1);\n"),
    ("loop_b.qcsg", b"include <loop_a.qcsg>\nmodule b() sphere(1);\n"),
    ("self.qcsg", b"use <self.qcsg>\ninclude <self.qcsg>\nself_value = 1;\n"),
    (
        "broken.qcsg",
        b"module broken( { cube(; }\nfunction = ;\n\"unterminated\n",
    ),
    ("empty.qcsg", b""),
    (
        "binary.qcsg",
        b"cube(1);\n// \xff\xfe not UTF-8 \xc3\x28 \xed\xa0\x80\nsphere(2);\n",
    ),
];

/// Writes the library files (and an empty directory, `subdir`) into `dir`.
pub fn write(dir: &Path) -> io::Result<()> {
    std::fs::create_dir_all(dir.join("subdir"))?;
    for (name, bytes) in FILES {
        std::fs::write(dir.join(name), bytes)?;
    }
    Ok(())
}
