//! Byte-level mutation of corpus files.
//!
//! [`mutate`] stacks a few random [`Mutation`]s: bit flips, byte insertions and deletions,
//! chunk duplication (repeated in place it grows nesting such as `union() {` × n and line
//! length), splicing in part of another file, inserting delimiters, keywords and tokens, and
//! inserting invalid UTF-8. The result is capped at [`MAX_LEN`] bytes.

use crate::dice::Dice;

/// The largest mutated input, in bytes: enough for lines past 65,536 columns and for the
/// quadratic blow-ups a long input shows, small enough that a linear stage stays fast.
pub const MAX_LEN: usize = 1 << 20;

/// Tokens worth inserting: delimiters, keywords, operators and awkward literals.
const TOKENS: &[&str] = &[
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    ";",
    ",",
    "=",
    "<",
    ">",
    "\"",
    "/*",
    "*/",
    "//",
    "\n",
    ":",
    "?",
    "!",
    "#",
    "%",
    "*",
    "$",
    ".",
    "^",
    "module ",
    "function ",
    "if ",
    "else ",
    "for ",
    "let ",
    "each ",
    "true",
    "false",
    "undef",
    "include <",
    "use <",
    "include <lib.qcsg>\n",
    "use <missing.scad>\n",
    "include </dev/null>\n",
    "union() {",
    "difference() {",
    "children();",
    "echo(",
    "assert(",
    "1e308",
    "-1e308",
    "0/0",
    "1e-320",
    "999999999999999999999",
    "[0 : 1e9]",
    "[0 : 0 : 1]",
    "sphere(1);",
    "cube(1e9);",
    "$fn = 1e9;",
    "\u{fffd}",
    "é",
    "😀",
    "\u{202e}",
    "\t",
    "\r\n",
    "\r",
    "\u{0}",
    "\\u263A",
    "\\x00",
];

/// Byte sequences that are not UTF-8: stray continuation bytes, truncated and overlong
/// sequences, surrogates, values past U+10FFFF.
const INVALID_UTF8: &[&[u8]] = &[
    b"\xff",
    b"\xfe",
    b"\x80",
    b"\xbf",
    b"\xc3",
    b"\xc3\x28",
    b"\xe2\x82",
    b"\xf0\x9f\x98",
    b"\xc0\xaf",
    b"\xe0\x80\xaf",
    b"\xed\xa0\x80",
    b"\xf4\x90\x80\x80",
    b"\xf8\x88\x80\x80\x80",
];

/// One kind of mutation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mutation {
    /// Flip one bit.
    BitFlip,
    /// Replace a byte by a random one.
    ByteSet,
    /// Insert a random byte.
    ByteInsert,
    /// Delete a byte.
    ByteDelete,
    /// Delete a chunk.
    ChunkDelete,
    /// Copy a chunk elsewhere.
    ChunkCopy,
    /// Repeat a chunk in place, up to thousands of times.
    ChunkRepeat,
    /// Replace the tail by part of another file.
    Splice,
    /// Insert a token.
    TokenInsert,
    /// Insert invalid UTF-8.
    InvalidUtf8,
    /// Swap two lines.
    LineSwap,
}

/// Every mutation, for drawing one.
pub const ALL: &[Mutation] = &[
    Mutation::BitFlip,
    Mutation::ByteSet,
    Mutation::ByteInsert,
    Mutation::ByteDelete,
    Mutation::ChunkDelete,
    Mutation::ChunkCopy,
    Mutation::ChunkRepeat,
    Mutation::Splice,
    Mutation::TokenInsert,
    Mutation::TokenInsert,
    Mutation::InvalidUtf8,
    Mutation::LineSwap,
];

/// `bytes` after one to eight random mutations; `other` is the file a splice takes from.
pub fn mutate(dice: &mut Dice, bytes: &[u8], other: &[u8]) -> (Vec<u8>, Vec<Mutation>) {
    let mut out = bytes.to_vec();
    let count = dice.skewed(8);
    let mut applied = Vec::with_capacity(count);
    for _ in 0..count {
        let mutation = *dice.pick(ALL);
        apply(dice, mutation, &mut out, other);
        out.truncate(MAX_LEN);
        applied.push(mutation);
    }
    (out, applied)
}

/// Applies one mutation in place.
pub fn apply(dice: &mut Dice, mutation: Mutation, out: &mut Vec<u8>, other: &[u8]) {
    let len = out.len();
    let at = dice.between(0, len);
    match mutation {
        Mutation::BitFlip if len > 0 => {
            let i = dice.below(len);
            out[i] ^= 1 << dice.below(8);
        }
        Mutation::ByteSet if len > 0 => {
            let i = dice.below(len);
            out[i] = dice.byte();
        }
        Mutation::ByteDelete if len > 0 => {
            out.remove(dice.below(len));
        }
        Mutation::ChunkDelete if len > 0 => {
            let end = (at + dice.skewed(len)).min(len);
            out.drain(at..end);
        }
        Mutation::ChunkCopy if len > 0 => {
            let (start, end) = chunk(dice, len);
            let piece = out[start..end].to_vec();
            let to = dice.between(0, len);
            out.splice(to..to, piece);
        }
        Mutation::ChunkRepeat if len > 0 => {
            let (start, end) = chunk(dice, len);
            let piece = out[start..end].to_vec();
            let times = dice.skewed(MAX_LEN / piece.len().max(1)).min(20_000);
            let mut grown = Vec::with_capacity(piece.len() * times);
            for _ in 0..times {
                grown.extend_from_slice(&piece);
                if grown.len() > MAX_LEN {
                    break;
                }
            }
            out.splice(end..end, grown);
        }
        Mutation::Splice if !other.is_empty() => {
            let from = dice.below(other.len());
            out.truncate(at);
            out.extend_from_slice(&other[from..]);
        }
        Mutation::TokenInsert => {
            let token = dice.pick(TOKENS).as_bytes();
            out.splice(at..at, token.iter().copied());
        }
        Mutation::InvalidUtf8 => {
            let bad = *dice.pick(INVALID_UTF8);
            out.splice(at..at, bad.iter().copied());
        }
        Mutation::LineSwap => swap_lines(dice, out),
        // Anything that needs bytes on an empty input, and byte insertion.
        _ => out.insert(at, dice.byte()),
    }
}

/// A chunk `start..end` of a text of `len > 0` bytes, short more often than long.
fn chunk(dice: &mut Dice, len: usize) -> (usize, usize) {
    let start = dice.below(len);
    let end = (start + dice.skewed(64.min(len))).min(len);
    (start, end.max(start + 1).min(len))
}

/// Swaps two random lines.
fn swap_lines(dice: &mut Dice, out: &mut Vec<u8>) {
    let mut lines: Vec<Vec<u8>> = out
        .split_inclusive(|&b| b == b'\n')
        .map(<[u8]>::to_vec)
        .collect();
    if lines.len() < 2 {
        return;
    }
    let a = dice.below(lines.len());
    let b = dice.below(lines.len());
    lines.swap(a, b);
    *out = lines.concat();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mutation_changes_a_text_and_stays_under_the_cap() {
        let text =
            b"union() { cube(1); sphere(2); }\ntranslate([1, 2, 3]) cylinder(h = 1, r = 2);\n";
        let other = b"module m() children();\n";
        let mut dice = Dice::new(3);
        for &mutation in ALL {
            let mut changed = false;
            for _ in 0..20 {
                let mut out = text.to_vec();
                apply(&mut dice, mutation, &mut out, other);
                out.truncate(MAX_LEN);
                changed |= out != text;
            }
            assert!(changed, "{mutation:?} never changed the text");
        }
    }

    #[test]
    fn mutations_make_invalid_utf8_and_long_lines() {
        let text = b"union() { cube(1); }\n";
        let mut dice = Dice::new(9);
        let outputs: Vec<Vec<u8>> = (0..500).map(|_| mutate(&mut dice, text, text).0).collect();
        assert!(outputs.iter().any(|o| std::str::from_utf8(o).is_err()));
        assert!(outputs.iter().any(|o| o.len() > 10_000));
        assert!(outputs.iter().all(|o| o.len() <= MAX_LEN));
    }
}
