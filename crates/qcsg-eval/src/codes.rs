//! Stable codes of the evaluation (runtime) diagnostics.
//!
//! Runtime codes live in `E0550`–`E0599` and `W0550`–`W0599` (the lower half of `E05xx` is the
//! static checker's type codes); the output of `echo` is the information code [`ECHO`]. Tools and
//! tests match on these codes, never on messages. [`ALL`] lists every code with a one-line
//! description for the documentation's table.

/// An operator applied at run time to values it is not defined for (OpenSCAD: `undef` and a
/// warning).
pub const OPERATOR_TYPE: &str = "E0550";
/// A built-in function given arguments it cannot use (OpenSCAD: `undef` and a warning).
pub const FUNCTION_ARGUMENT: &str = "E0551";
/// A built-in module given an argument it cannot use.
pub const MODULE_ARGUMENT: &str = "E0552";
/// A name that is not defined when evaluation reaches it.
pub const UNDEFINED_NAME: &str = "E0553";
/// A call of a value that is not a function.
pub const NOT_CALLABLE: &str = "E0554";
/// An `assert` whose condition is false.
pub const ASSERTION_FAILED: &str = "E0555";
/// Calls nested deeper than the recursion limit.
pub const RECURSION_LIMIT: &str = "E0556";
/// More loop iterations and function calls than the iteration limit.
pub const ITERATION_LIMIT: &str = "E0557";
/// A vector longer than the vector-length limit (a range spliced or a string split into a
/// vector counts its elements).
pub const VECTOR_LIMIT: &str = "E0558";
/// More primitive instances than the instance limit.
pub const INSTANCE_LIMIT: &str = "E0559";
/// A construct that qcsg cannot evaluate (an unsupported module reached at run time).
pub const UNSUPPORTED: &str = "E0560";
/// A `-D name=value` override whose value is not an expression.
pub const BAD_DEFINE: &str = "E0561";
/// A module instantiated as a function or a function as a module, found at run time.
pub const WRONG_KIND: &str = "E0562";
/// A string (`str`, `chr`) longer than the string-length limit, in bytes.
pub const STRING_LIMIT: &str = "E0563";
/// `rotate_extrude` of a shape with points on both sides of the axis (x < 0 and x > 0), which
/// OpenSCAD refuses.
pub const BOTH_SIDES_OF_AXIS: &str = "E0564";
/// A `polyhedron` or imported mesh whose faces bound no solid: a face of fewer than three
/// distinct points, an index naming no point, an open, non-manifold or inconsistently oriented
/// edge, a coordinate that is not finite.
pub const INVALID_MESH: &str = "E0565";
/// An `import` whose file cannot be read: missing, a directory or device, unreadable.
pub const IMPORT_UNREADABLE: &str = "E0566";
/// An `import` whose file is not a well-formed file of its format (the line or record named).
pub const IMPORT_MALFORMED: &str = "E0567";
/// An `import` of a file larger than the import size limit (`--max-import-bytes`).
pub const IMPORT_SIZE_LIMIT: &str = "E0568";
/// A `hull` or `minkowski` of more distinct points than the hull point limit
/// (`--max-hull-points`).
pub const HULL_POINT_LIMIT: &str = "E0570";
/// A convex part of a `hull` or `minkowski` with more faces than the part plane limit
/// (`--max-part-planes`).
pub const PART_PLANE_LIMIT: &str = "E0571";
/// A `minkowski` that is a union of more convex parts than the Minkowski part limit
/// (`--max-minkowski-parts`).
pub const MINKOWSKI_PART_LIMIT: &str = "E0572";
/// A `text()` font that cannot be used exactly (cubic CFF outlines) or cannot be read.
pub const FONT_UNUSABLE: &str = "E0569";

/// A transform with a singular or non-finite matrix: the object is removed, as in OpenSCAD.
pub const SINGULAR_TRANSFORM: &str = "W0550";
/// A range `[begin : end]` with `begin > end`: OpenSCAD swaps the ends (deprecated).
pub const REVERSED_RANGE: &str = "W0551";
/// An argument that OpenSCAD ignores (`r` beside `d`, `v` beside a vector angle, …).
pub const IGNORED_ARGUMENT: &str = "W0552";
/// A primitive with zero or negative size: it is empty, as in OpenSCAD.
pub const EMPTY_PRIMITIVE: &str = "W0553";
/// More than one `!` (root) modifier: the first one is used.
pub const SEVERAL_ROOTS: &str = "W0554";
/// A colour that is not recognised (no effect on geometry).
pub const UNKNOWN_COLOR: &str = "W0555";
/// `resize` along an axis in which the child is flat, or of an unbounded child.
pub const RESIZE_IGNORED: &str = "W0556";
/// A `text()` font with no installed face of its family: the default font is used.
pub const FONT_NOT_FOUND: &str = "W0566";
/// Characters of a `text()` the font has no glyph for: the font's missing-glyph shape is drawn.
pub const MISSING_GLYPH: &str = "W0567";
/// A malformed entry in a `search` table: OpenSCAD returns `[]`.
pub const SEARCH_TABLE: &str = "W0557";
/// `echo` output past the echo-output limit: the line is cut, later output left out.
pub const ECHO_LIMIT: &str = "W0558";
/// Objects of both dimensions in one group or operation: those of the dimension that the first
/// object does not have are ignored, as in OpenSCAD.
pub const MIXED_DIMENSIONS: &str = "W0559";
/// A 2-D shape at the top level: it is made a plate 1 unit thick, as OpenSCAD's preview shows it.
pub const TOP_LEVEL_2D: &str = "W0560";
/// A `polygon` whose outline crosses itself (filled with the even–odd rule, as OpenSCAD does) or
/// has a path of fewer than three distinct points (which encloses nothing).
pub const POLYGON_OUTLINE: &str = "W0561";
/// A `polyhedron` or imported mesh with a non-planar face (split into a fan of triangles, as
/// OpenSCAD does) or with every face inside out (the enclosed solid is built, not its
/// complement).
pub const MESH_FACES: &str = "W0562";
/// A deprecated argument OpenSCAD still accepts with a warning (`polyhedron(triangles = …)`).
pub const DEPRECATED_ARGUMENT: &str = "W0563";
/// An imported DXF drawing with an open path (closed by a straight edge, as OpenSCAD closes it),
/// entities OpenSCAD does not read (skipped, as OpenSCAD skips them), or what OpenSCAD 2021.01
/// reads otherwise than DXF means it (bulges, an ELLIPSE with `origin` or `scale`).
pub const DRAWING_SKIPPED: &str = "W0564";
/// `dxf_dim` or `dxf_cross` found no such dimension or cross in the drawing: `undef`, as OpenSCAD
/// returns it.
pub const DRAWING_LOOKUP: &str = "W0565";

/// The output of `echo`, formatted exactly as OpenSCAD prints it (`ECHO: …`).
pub const ECHO: &str = "I0550";

/// Every evaluation code with a one-line description, in code order.
pub const ALL: &[(&str, &str)] = &[
    (
        OPERATOR_TYPE,
        "operator applied to values of the wrong types",
    ),
    (
        FUNCTION_ARGUMENT,
        "built-in function given an unusable argument",
    ),
    (
        MODULE_ARGUMENT,
        "built-in module given an unusable argument",
    ),
    (UNDEFINED_NAME, "name not defined at run time"),
    (NOT_CALLABLE, "call of a value that is not a function"),
    (ASSERTION_FAILED, "assertion failed"),
    (RECURSION_LIMIT, "recursion limit reached"),
    (ITERATION_LIMIT, "iteration limit reached"),
    (VECTOR_LIMIT, "vector length limit reached"),
    (INSTANCE_LIMIT, "primitive instance limit reached"),
    (UNSUPPORTED, "construct that cannot be evaluated"),
    (BAD_DEFINE, "`-D` value that is not an expression"),
    (
        WRONG_KIND,
        "module used as a function or function as a module",
    ),
    (STRING_LIMIT, "string length limit reached"),
    (
        BOTH_SIDES_OF_AXIS,
        "`rotate_extrude` of a shape on both sides of the axis",
    ),
    (INVALID_MESH, "mesh whose faces bound no solid"),
    (IMPORT_UNREADABLE, "imported file that cannot be read"),
    (IMPORT_MALFORMED, "imported file that is not well-formed"),
    (
        IMPORT_SIZE_LIMIT,
        "imported file size limit reached (`--max-import-bytes`)",
    ),
    (
        HULL_POINT_LIMIT,
        "hull point limit reached (`--max-hull-points`)",
    ),
    (
        PART_PLANE_LIMIT,
        "faces of one convex part of a hull limit reached (`--max-part-planes`)",
    ),
    (
        MINKOWSKI_PART_LIMIT,
        "Minkowski sum part limit reached (`--max-minkowski-parts`)",
    ),
    (
        FONT_UNUSABLE,
        "`text()` font with cubic (CFF) outlines or that cannot be read",
    ),
    (
        SINGULAR_TRANSFORM,
        "singular transform: the object is removed",
    ),
    (
        REVERSED_RANGE,
        "range with begin > end: the ends are swapped",
    ),
    (IGNORED_ARGUMENT, "argument that has no effect"),
    (
        EMPTY_PRIMITIVE,
        "primitive with zero or negative size is empty",
    ),
    (
        SEVERAL_ROOTS,
        "more than one `!` modifier: the first is used",
    ),
    (UNKNOWN_COLOR, "unrecognised colour"),
    (RESIZE_IGNORED, "resize not applied"),
    (SEARCH_TABLE, "malformed `search` table entry"),
    (ECHO_LIMIT, "echo output limit reached: output cut"),
    (
        MIXED_DIMENSIONS,
        "2-D and 3-D objects mixed: those of the other dimension than the first are ignored",
    ),
    (
        TOP_LEVEL_2D,
        "2-D shape at the top level: shown as a plate 1 unit thick",
    ),
    (
        POLYGON_OUTLINE,
        "polygon outline that crosses itself or has a path enclosing nothing",
    ),
    (
        MESH_FACES,
        "mesh with a non-planar face or with its faces inside out",
    ),
    (
        DEPRECATED_ARGUMENT,
        "deprecated argument (`polyhedron(triangles)`)",
    ),
    (
        DRAWING_SKIPPED,
        "imported DXF drawing with an open path, skipped entities, or read otherwise than OpenSCAD reads it",
    ),
    (
        DRAWING_LOOKUP,
        "`dxf_dim` or `dxf_cross` found nothing in the drawing: undef",
    ),
    (
        FONT_NOT_FOUND,
        "`text()` font family not installed: Liberation Sans is used",
    ),
    (
        MISSING_GLYPH,
        "`text()` characters without a glyph in the font: its missing-glyph shape is drawn",
    ),
    (ECHO, "output of `echo`"),
];

#[cfg(test)]
mod tests {
    use super::ALL;

    #[test]
    fn codes_are_unique_and_well_formed() {
        let mut seen = std::collections::HashSet::new();
        for (code, description) in ALL {
            assert!(seen.insert(*code), "duplicate code {code}");
            assert_eq!(code.len(), 5);
            assert!(matches!(&code[..1], "E" | "W" | "I"));
            assert!(code[1..].bytes().all(|b| b.is_ascii_digit()));
            assert!(!description.is_empty());
        }
    }
}
