//! Stable codes of the syntax diagnostics (range E0001–E0099, warnings W0001–W0099).
//!
//! Tools and tests match on these codes, never on messages. [`ALL`] lists every code with a
//! one-line description; the documentation's table of codes is checked against it.

/// A character (or run of characters) that starts no token.
pub const INVALID_CHARACTER: &str = "E0001";
/// The parser expected something else here (a missing `;`, `)`, expression, …).
pub const EXPECTED: &str = "E0002";
/// A string literal without its closing `"`.
pub const UNTERMINATED_STRING: &str = "E0003";
/// An invalid escape sequence in a string literal.
pub const INVALID_ESCAPE: &str = "E0004";
/// A `/*` comment without its closing `*/`.
pub const UNTERMINATED_BLOCK_COMMENT: &str = "E0005";
/// Delimiters or prefix operators nested deeper than the parser accepts.
pub const NESTING_TOO_DEEP: &str = "E0006";
/// An `include <…` / `use <…` path without its closing `>` on the same line.
pub const UNTERMINATED_PATH: &str = "E0007";
/// An opening `(`, `[` or `{` that is never closed.
pub const UNCLOSED_DELIMITER: &str = "E0008";
/// A closing `)`, `]` or `}` that matches no opening delimiter.
pub const UNEXPECTED_CLOSING_DELIMITER: &str = "E0009";
/// `include` or `use` without a `<path>`.
pub const MISSING_PATH: &str = "E0010";

/// In a `.scad` file, an escape or line break in a string literal that OpenSCAD 2021.01 reads
/// its own way (a backslash starting no escape is dropped, `\x00` is a space, a line break is
/// dropped); a `.qcsg` file has error [`INVALID_ESCAPE`] there instead.
pub const SCAD_STRING_READING: &str = "W0004";

/// Every syntax code with a one-line description, in code order.
pub const ALL: &[(&str, &str)] = &[
    (INVALID_CHARACTER, "invalid character"),
    (
        EXPECTED,
        "unexpected token: something else was expected here",
    ),
    (UNTERMINATED_STRING, "unterminated string literal"),
    (
        INVALID_ESCAPE,
        "invalid escape sequence in a string literal",
    ),
    (UNTERMINATED_BLOCK_COMMENT, "unterminated block comment"),
    (NESTING_TOO_DEEP, "nesting too deep"),
    (UNTERMINATED_PATH, "unterminated `<path>` of include or use"),
    (UNCLOSED_DELIMITER, "unclosed delimiter"),
    (UNEXPECTED_CLOSING_DELIMITER, "unexpected closing delimiter"),
    (MISSING_PATH, "`include` or `use` without a `<path>`"),
    (
        SCAD_STRING_READING,
        "escape or line break in a `.scad` string literal, read as OpenSCAD reads it",
    ),
];

#[cfg(test)]
mod tests {
    #[test]
    fn codes_are_sorted_unique_and_in_range() {
        for pair in super::ALL.windows(2) {
            assert!(pair[0].0 < pair[1].0, "{} before {}", pair[0].0, pair[1].0);
        }
        for (code, description) in super::ALL {
            assert!(
                code.len() == 5 && (code.starts_with("E00") || code.starts_with("W00")),
                "{code}"
            );
            assert!(!description.is_empty());
        }
    }
}
