//! String literal bodies: escape sequences decoded, in the reading of the file's [`Dialect`].
//!
//! Both dialects decode `\" \\ \n \t \r`, `\xHH` (01–7F), `\uHHHH` and `\UHHHHHH` (a Unicode
//! scalar value other than 0). A `.qcsg` file rejects anything else (error `E0004`). A `.scad`
//! file means what OpenSCAD 2021.01's lexer makes of it, with warning `W0004` at the spot:
//! a backslash that starts no escape is dropped and the next character read as usual (`\q` is
//! `q`, `\x80` is `x80`), `\x00` and a `\u`/`\U` naming no character are a space, and a line
//! break inside the literal is dropped.

use qcsg_diag::{Diagnostic, FileId, Span};

use crate::codes;

/// Which language a file is read as: `.scad` files take OpenSCAD's lenient reading where `.qcsg`
/// is strict.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// A `.qcsg` file (and any file not named `.scad`).
    #[default]
    Qcsg,
    /// A `.scad` file: OpenSCAD 2021.01's reading, with warnings where it differs.
    Scad,
}

impl Dialect {
    /// The dialect of a file by its name: `.scad` (any case) is [`Dialect::Scad`].
    pub fn of_file(name: &str) -> Self {
        let is_scad = name
            .rsplit_once('.')
            .is_some_and(|(_, ext)| ext.eq_ignore_ascii_case("scad"));
        if is_scad {
            Dialect::Scad
        } else {
            Dialect::Qcsg
        }
    }
}

const VALID_ESCAPES: &str = "valid escapes: \\\" \\\\ \\n \\t \\r \\xHH \\uHHHH \\UHHHHHH";

/// Decodes the body of a string literal (the text between the quotes), reporting what the
/// dialect refuses or reads differently with exact spans. `offset` is the byte offset of the
/// body in the file.
pub fn unescape(
    body: &str,
    offset: usize,
    file: FileId,
    dialect: Dialect,
    diagnostics: &mut Vec<Diagnostic>,
) -> String {
    let scad = dialect == Dialect::Scad;
    let span = |from: usize, to: usize| Span::new(offset + from, offset + to);
    let mut out = String::with_capacity(body.len());
    let mut chars = body.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if scad && (c == '\n' || c == '\r') {
            // OpenSCAD's string state swallows line breaks; warn once per break (`\r\n` is one).
            if c == '\r' && chars.peek().is_some_and(|&(_, n)| n == '\n') {
                chars.next();
            }
            let end = chars.peek().map_or(body.len(), |&(j, _)| j);
            diagnostics.push(
                Diagnostic::warning(
                    codes::SCAD_STRING_READING,
                    "OpenSCAD drops a line break inside a string literal",
                    file,
                    span(i, end),
                )
                .with_help("write `\\n` where a line break is meant"),
            );
            continue;
        }
        if c != '\\' {
            out.push(c);
            continue;
        }
        let Some(&(_, e)) = chars.peek() else {
            // Only an unterminated literal ends in a backslash (`\"` escapes the quote), and
            // that is reported already; OpenSCAD drops the backslash.
            if !scad {
                diagnostics.push(Diagnostic::error(
                    codes::INVALID_ESCAPE,
                    "invalid escape: `\\` at the end of the string",
                    file,
                    span(i, i + 1),
                ));
            }
            break;
        };
        let simple = match e {
            '"' => Some('"'),
            '\\' => Some('\\'),
            'n' => Some('\n'),
            't' => Some('\t'),
            'r' => Some('\r'),
            _ => None,
        };
        if let Some(decoded) = simple {
            chars.next();
            out.push(decoded);
            continue;
        }
        if let Some((want, len)) = hex_escape(&body[i..]) {
            // `len` digits follow the letter; all of them are ASCII.
            for _ in 0..=len {
                chars.next();
            }
            let end = i + 2 + len;
            match want {
                Ok(ch) => out.push(ch),
                Err(what) if scad => {
                    out.push(' ');
                    diagnostics.push(Diagnostic::warning(
                        codes::SCAD_STRING_READING,
                        format!("OpenSCAD reads `{}` as a space: {what}", &body[i..end]),
                        file,
                        span(i, end),
                    ));
                }
                Err(what) => diagnostics.push(Diagnostic::error(
                    codes::INVALID_ESCAPE,
                    format!("invalid escape `{}`: {what}", &body[i..end]),
                    file,
                    span(i, end),
                )),
            }
            continue;
        }
        let shown = shown_escape(&body[i..]);
        let end = i + shown.len();
        if scad {
            // The backslash is dropped; the character after it is read as usual (it may be a
            // line break or start another escape), so it is not consumed here.
            diagnostics.push(
                Diagnostic::warning(
                    codes::SCAD_STRING_READING,
                    format!(
                        "OpenSCAD drops the backslash of `{shown}` and reads `{}`",
                        &shown[1..]
                    ),
                    file,
                    span(i, end),
                )
                .with_help(format!("write `\\\\` for a backslash; {VALID_ESCAPES}")),
            );
            continue;
        }
        let message =
            match e {
                'x' => "invalid escape: expected two hex digits 01-7F after `\\x`".to_owned(),
                'u' => "invalid escape: expected four hex digits after `\\u` naming a character"
                    .to_owned(),
                'U' => "invalid escape: expected six hex digits after `\\U` naming a character"
                    .to_owned(),
                other => format!("invalid escape `\\{other}`"),
            };
        diagnostics.push(
            Diagnostic::error(codes::INVALID_ESCAPE, message, file, span(i, end))
                .with_help(VALID_ESCAPES),
        );
        // Keep the character after the backslash, as OpenSCAD does.
        chars.next();
        out.push(e);
    }
    out
}

/// A complete hex escape at the start of `text` (which starts with `\`), as OpenSCAD's lexer
/// matches them: `\x` with a digit 0-7 then a hex digit, `\u` with four hex digits, `\U` with
/// six. Returns the character (or why it names none) and the number of digits.
fn hex_escape(text: &str) -> Option<(Result<char, &'static str>, usize)> {
    let bytes = text.as_bytes();
    let (len, max) = match bytes.get(1)? {
        b'x' => (2, 0x7f),
        b'u' => (4, u32::MAX),
        b'U' => (6, u32::MAX),
        _ => return None,
    };
    let digits = bytes.get(2..2 + len)?;
    if !digits.iter().all(u8::is_ascii_hexdigit) || (len == 2 && digits[0] > b'7') {
        return None;
    }
    // The digits are ASCII hex, so this parse cannot fail.
    let value = u32::from_str_radix(std::str::from_utf8(digits).ok()?, 16).ok()?;
    debug_assert!(value <= max);
    let decoded = match char::from_u32(value) {
        Some('\0') => Err("the code 0 names no character"),
        Some(ch) => Ok(ch),
        None => Err("the code names no Unicode character"),
    };
    Some((decoded, len))
}

/// The text of an unusable escape for messages and spans: the backslash and the letter, plus
/// the hex digits that follow `x`, `u` or `U` (as many as the escape could take).
fn shown_escape(text: &str) -> &str {
    let mut chars = text.char_indices().skip(1);
    let Some((_, letter)) = chars.next() else {
        return text;
    };
    let take = match letter {
        'x' => 2,
        'u' => 4,
        'U' => 6,
        _ => 0,
    };
    let mut end = 1 + letter.len_utf8();
    for (j, c) in chars.take(take) {
        if !c.is_ascii_hexdigit() {
            break;
        }
        end = j + 1;
    }
    &text[..end]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(body: &str, dialect: Dialect) -> (String, Vec<Diagnostic>) {
        let mut diags = Vec::new();
        let s = unescape(body, 0, FileId::default(), dialect, &mut diags);
        (s, diags)
    }

    #[test]
    fn dialect_of_file() {
        assert_eq!(Dialect::of_file("a/b.scad"), Dialect::Scad);
        assert_eq!(Dialect::of_file("B.SCAD"), Dialect::Scad);
        assert_eq!(Dialect::of_file("b.qcsg"), Dialect::Qcsg);
        assert_eq!(Dialect::of_file("<stdin>"), Dialect::Qcsg);
        assert_eq!(Dialect::of_file("scad"), Dialect::Qcsg);
    }

    #[test]
    fn valid_escapes_in_both_dialects() {
        for dialect in [Dialect::Qcsg, Dialect::Scad] {
            let (s, diags) = read(r#"a\"\\\n\t\r\x41\x7f\u263A\U01F600\u00410"#, dialect);
            assert_eq!(s, "a\"\\\n\t\r\u{41}\u{7f}\u{263A}\u{1F600}A0");
            assert!(diags.is_empty(), "{diags:?}");
        }
    }

    #[test]
    fn qcsg_rejects_other_escapes() {
        let mut diags = Vec::new();
        unescape(r"\q\x4", 10, FileId::default(), Dialect::Qcsg, &mut diags);
        assert_eq!(diags.len(), 2);
        assert_eq!(diags[0].span, Span::new(10, 12));
        assert_eq!(diags[1].span, Span::new(12, 15));
        assert!(
            diags
                .iter()
                .all(|d| d.code == codes::INVALID_ESCAPE && d.is_error())
        );
        for bad in [
            r"\x00",
            r"\x80",
            r"\u0000",
            r"\uD800",
            r"\U110000",
            r"\0",
            "\\\u{e9}",
        ] {
            let (_, diags) = read(bad, Dialect::Qcsg);
            assert_eq!(diags.len(), 1, "{bad}");
            assert_eq!(diags[0].span, Span::new(0, bad.len()), "{bad}");
        }
    }

    /// The values OpenSCAD 2021.01 prints for these escapes (`echo` of each literal).
    #[test]
    fn scad_reads_as_openscad() {
        let cases = [
            (r"a\0b\qc", "a0bqc", 2),
            (r"\a|\b|\v|\f|\e|\'|\?", "a|b|v|f|e|'|?", 7),
            (r"\x41|\x80|\x4|\x4g|\x00|\x0A", "A|x80|x4|x4g| |\n", 4),
            (
                r"\u263A|\u263|\u0000|\uD800|\u00e9",
                "\u{263A}|u263| | |\u{e9}",
                3,
            ),
            (
                r"\U01F600|\U0263A|\U110000|\U000041",
                "\u{1F600}|U0263A| |A",
                2,
            ),
            (r"\x7|\xA", "x7|xA", 2),
            ("a\nb\r\nc", "abc", 2),
            ("\\\u{e9}", "\u{e9}", 1),
            (r"\\x41", r"\x41", 0),
        ];
        for (body, want, warnings) in cases {
            let (s, diags) = read(body, Dialect::Scad);
            assert_eq!(s, want, "{body}");
            assert_eq!(diags.len(), warnings, "{body}: {diags:?}");
            assert!(
                diags
                    .iter()
                    .all(|d| d.code == codes::SCAD_STRING_READING && !d.is_error())
            );
        }
        let (_, diags) = read(r"ab\x4g", Dialect::Scad);
        assert_eq!(diags[0].span, Span::new(2, 5));
        let (_, diags) = read(r"\uD800", Dialect::Scad);
        assert_eq!(diags[0].span, Span::new(0, 6));
    }

    #[test]
    fn a_trailing_backslash_is_reported_in_qcsg_only() {
        assert_eq!(read("a\\", Dialect::Qcsg).1.len(), 1);
        let (s, diags) = read("a\\", Dialect::Scad);
        assert_eq!(s, "a");
        assert!(diags.is_empty());
    }
}
