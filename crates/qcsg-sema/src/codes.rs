//! Stable codes of the static-checking diagnostics.
//!
//! Ranges: `E01xx` names, `E02xx` arguments, `E03xx` unsupported OpenSCAD constructs, `E04xx`
//! source files and `include` / `use`, `E05xx` static types, `W01xx` warnings, `H01xx` hints.
//! Tools and tests match on these codes, never on messages. [`ALL`] lists every code with a
//! one-line description; the documentation's table of codes is checked against it.

/// A variable that is defined nowhere in scope.
pub const UNDEFINED_VARIABLE: &str = "E0101";
/// A called function that is defined nowhere in scope.
pub const UNDEFINED_FUNCTION: &str = "E0102";
/// An instantiated module that is defined nowhere in scope.
pub const UNDEFINED_MODULE: &str = "E0103";
/// A module called in an expression, as if it were a function.
pub const MODULE_USED_AS_FUNCTION: &str = "E0104";
/// A function instantiated as a statement, as if it were a module.
pub const FUNCTION_USED_AS_MODULE: &str = "E0105";
/// A variable read by an assignment that comes before the variable's own assignment in the same
/// scope (OpenSCAD evaluates assignments in order and yields `undef`).
pub const USED_BEFORE_ASSIGNMENT: &str = "E0106";

/// A named argument that the callee has no parameter for.
pub const UNKNOWN_ARGUMENT: &str = "E0201";
/// More positional arguments than the callee has positional parameters.
pub const TOO_MANY_ARGUMENTS: &str = "E0202";
/// A parameter without a default value that the call does not supply.
pub const MISSING_ARGUMENT: &str = "E0203";
/// The same parameter supplied twice (by name twice, or by position and by name).
pub const DUPLICATE_ARGUMENT: &str = "E0204";
/// An argument whose type is definitely wrong for the parameter.
pub const ARGUMENT_TYPE: &str = "E0205";
/// A vector argument whose length is definitely wrong for the parameter.
pub const ARGUMENT_LENGTH: &str = "E0206";

/// An OpenSCAD module that no quadric solid can represent exactly.
pub const UNSUPPORTED_MODULE: &str = "E0301";
/// An OpenSCAD built-in function that the language does not provide.
pub const UNSUPPORTED_FUNCTION: &str = "E0302";

/// An `include <…>` or `use <…>` file that exists in none of the searched directories.
pub const FILE_NOT_FOUND: &str = "E0401";
/// An `include` that (directly or indirectly) includes the file it is in.
pub const INCLUDE_CYCLE: &str = "E0402";
/// An `include <…>` or `use <…>` path that names a directory, a device or anything else that is
/// not a regular file.
pub const NOT_A_FILE: &str = "E0403";
/// An included or used file larger than the limit on source files.
pub const FILE_TOO_LARGE: &str = "E0404";
/// An `include <…>` or `use <…>` file that exists but cannot be read (permission denied, …).
pub const UNREADABLE_FILE: &str = "E0405";
/// A source file that is not valid UTF-8 (reported once per file, at the first invalid byte).
pub const INVALID_UTF8: &str = "E0406";

/// An operator applied to operands of types it is not defined for.
pub const OPERATOR_TYPE: &str = "E0501";
/// A call of a value that is definitely not a function.
pub const NOT_CALLABLE: &str = "E0502";
/// An index into a value that cannot be indexed, or with an index that is not a number.
pub const NOT_INDEXABLE: &str = "E0503";
/// A member other than `.x`, `.y`, `.z` of a vector, or a member of a value that is no vector.
pub const UNKNOWN_MEMBER: &str = "E0504";

/// A variable that is assigned but never read.
pub const UNUSED_VARIABLE: &str = "W0101";
/// A parameter that the body never reads.
pub const UNUSED_PARAMETER: &str = "W0102";
/// A module that is defined but never instantiated.
pub const UNUSED_MODULE: &str = "W0103";
/// A function that is defined but never called.
pub const UNUSED_FUNCTION: &str = "W0104";
/// A variable assigned twice in one scope: the last assignment wins for the whole scope.
pub const REASSIGNMENT: &str = "W0105";
/// A `%` (background) subtree: shown, but not part of the solid.
pub const BACKGROUND_SUBTREE: &str = "W0106";
/// A `*` (disabled) subtree: not part of the solid.
pub const DISABLED_SUBTREE: &str = "W0107";
/// A user special variable (`$x`) that is read but set nowhere (it is always `undef`).
pub const SPECIAL_NEVER_SET: &str = "W0108";
/// OpenSCAD's deprecated `child()` or `assign()`: accepted with OpenSCAD's meaning.
pub const DEPRECATED_MODULE: &str = "W0109";

/// `$fn`, `$fa` or `$fs`: accepted, but surfaces are exact, so they change nothing.
pub const TESSELLATION_NO_OP: &str = "H0101";

/// Every static-checking code with a one-line description, in code order.
pub const ALL: &[(&str, &str)] = &[
    (UNDEFINED_VARIABLE, "undefined variable"),
    (UNDEFINED_FUNCTION, "undefined function"),
    (UNDEFINED_MODULE, "undefined module"),
    (MODULE_USED_AS_FUNCTION, "a module is called as a function"),
    (
        FUNCTION_USED_AS_MODULE,
        "a function is instantiated as a module",
    ),
    (
        USED_BEFORE_ASSIGNMENT,
        "variable read before its assignment in the same scope",
    ),
    (UNKNOWN_ARGUMENT, "unknown named argument"),
    (TOO_MANY_ARGUMENTS, "too many positional arguments"),
    (
        MISSING_ARGUMENT,
        "missing argument for a parameter without a default",
    ),
    (DUPLICATE_ARGUMENT, "argument supplied more than once"),
    (ARGUMENT_TYPE, "argument of the wrong type"),
    (ARGUMENT_LENGTH, "vector argument of the wrong length"),
    (
        UNSUPPORTED_MODULE,
        "OpenSCAD module with no exact quadric representation",
    ),
    (
        UNSUPPORTED_FUNCTION,
        "OpenSCAD built-in function that is not supported",
    ),
    (FILE_NOT_FOUND, "include or use file not found"),
    (INCLUDE_CYCLE, "include cycle"),
    (NOT_A_FILE, "include or use path is not a regular file"),
    (FILE_TOO_LARGE, "include or use file over the size limit"),
    (UNREADABLE_FILE, "include or use file cannot be read"),
    (INVALID_UTF8, "source file is not valid UTF-8"),
    (
        OPERATOR_TYPE,
        "operator applied to operands of the wrong types",
    ),
    (NOT_CALLABLE, "call of a value that is not a function"),
    (NOT_INDEXABLE, "index into a value that cannot be indexed"),
    (UNKNOWN_MEMBER, "unknown member"),
    (UNUSED_VARIABLE, "unused variable"),
    (UNUSED_PARAMETER, "unused parameter"),
    (UNUSED_MODULE, "unused module"),
    (UNUSED_FUNCTION, "unused function"),
    (
        REASSIGNMENT,
        "variable assigned more than once in one scope",
    ),
    (BACKGROUND_SUBTREE, "`%` subtree is not part of the solid"),
    (DISABLED_SUBTREE, "`*` subtree is not part of the solid"),
    (SPECIAL_NEVER_SET, "special variable read but never set"),
    (
        DEPRECATED_MODULE,
        "deprecated OpenSCAD module (`child`, `assign`)",
    ),
    (
        TESSELLATION_NO_OP,
        "`$fn`, `$fa` and `$fs` have no effect on exact surfaces",
    ),
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
            assert!(matches!(&code[..1], "E" | "W" | "H"));
            assert!(code[1..].bytes().all(|b| b.is_ascii_digit()));
            assert!(!description.is_empty());
        }
    }
}
