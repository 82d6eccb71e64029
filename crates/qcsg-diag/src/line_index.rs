//! Byte offset ↔ (line, UTF-16 column) conversion, as LSP and the JSON diagnostics format use.
//!
//! Every conversion costs at most a block of [`BLOCK`] bytes of scanning plus a binary search,
//! however long the line: a one-line file with a diagnostic every few columns must not cost the
//! square of its length. For that the index keeps, every [`BLOCK`] bytes, how many characters and
//! UTF-16 code units come before.

/// Bytes between two checkpoints: the most a conversion scans.
const BLOCK: usize = 256;

/// A zero-based line and a zero-based column counted in UTF-16 code units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LineCol {
    /// Zero-based line.
    pub line: u32,
    /// Zero-based column in UTF-16 code units.
    pub character: u32,
}

/// Characters and UTF-16 code units before a byte offset.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Counts {
    chars: u32,
    utf16: u32,
}

/// Line starts of one text, for converting byte offsets to [`LineCol`] and back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LineIndex {
    /// Byte offset where each line starts; the first is always 0.
    line_starts: Vec<u32>,
    /// Entry `k`: the characters and UTF-16 units that start before byte `k * BLOCK`.
    checkpoints: Vec<Counts>,
    len: u32,
}

impl LineIndex {
    /// Indexes `text`. Lines end at `\n`; a `\r` before it belongs to the line it ends.
    pub fn new(text: &str) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(
            text.bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i as u32 + 1),
        );
        let mut checkpoints = Vec::with_capacity(text.len() / BLOCK + 1);
        let mut before = Counts::default();
        checkpoints.push(before);
        for block in text.as_bytes().chunks(BLOCK) {
            let counts = counts_in(block);
            before.chars += counts.chars;
            before.utf16 += counts.utf16;
            checkpoints.push(before);
        }
        Self {
            line_starts,
            checkpoints,
            len: text.len() as u32,
        }
    }

    /// Number of lines (a text ending in `\n` has an empty last line).
    pub fn line_count(&self) -> usize {
        self.line_starts.len()
    }

    /// Byte offset where zero-based `line` starts, if the line exists.
    pub fn line_start(&self, line: u32) -> Option<usize> {
        self.line_starts.get(line as usize).map(|&s| s as usize)
    }

    /// The zero-based line that byte `offset` is on (offsets past the end are on the last line).
    pub fn line_of(&self, offset: usize) -> u32 {
        let offset = offset.min(self.len as usize);
        (self.line_starts.partition_point(|&s| s as usize <= offset) - 1) as u32
    }

    /// The byte range of zero-based `line` without its `\n` (a `\r` before it is included), if
    /// the line exists.
    pub fn line_range(&self, line: u32) -> Option<std::ops::Range<usize>> {
        let start = self.line_start(line)?;
        let end = self
            .line_start(line + 1)
            .map_or(self.len as usize, |next| next - 1);
        Some(start..end)
    }

    /// The line and UTF-16 column of byte `offset` in `text` (the text this index was built from).
    /// Offsets past the end or inside a UTF-8 sequence are clamped to the previous character boundary.
    pub fn line_col(&self, text: &str, offset: usize) -> LineCol {
        let offset = floor_char_boundary(text, offset.min(self.len as usize));
        let line = self.line_of(offset);
        let start = self.line_starts[line as usize] as usize;
        LineCol {
            line,
            character: self.counts_before(text, offset).utf16
                - self.counts_before(text, start).utf16,
        }
    }

    /// The zero-based column of byte `offset` in `text` counted in characters (Unicode scalar
    /// values), as people count them; clamped as [`LineIndex::line_col`] clamps.
    pub fn char_column(&self, text: &str, offset: usize) -> u32 {
        let offset = floor_char_boundary(text, offset.min(self.len as usize));
        let start = self.line_starts[self.line_of(offset) as usize] as usize;
        self.counts_before(text, offset).chars - self.counts_before(text, start).chars
    }

    /// The byte offset of a line and UTF-16 column; columns past the end of the line clamp to it,
    /// and a column inside a surrogate pair goes to the end of its character.
    pub fn offset(&self, text: &str, position: LineCol) -> usize {
        let Some(range) = self.line_range(position.line) else {
            return text.len();
        };
        let target = self.counts_before(text, range.start).utf16 as u64 + position.character as u64;
        // The last checkpoint at or before the target, but not before the line.
        let block = self
            .checkpoints
            .partition_point(|c| c.utf16 as u64 <= target)
            - 1;
        let from = floor_char_boundary(text, (block * BLOCK).clamp(range.start, range.end));
        let mut units = self.counts_before(text, from).utf16 as u64;
        for (i, c) in text[from..range.end].char_indices() {
            if units >= target {
                return from + i;
            }
            units += c.len_utf16() as u64;
        }
        range.end
    }

    /// The characters and UTF-16 units that start before byte `offset` of `text`.
    fn counts_before(&self, text: &str, offset: usize) -> Counts {
        let block = (offset / BLOCK).min(self.checkpoints.len() - 1);
        let base = self.checkpoints[block];
        let rest = counts_in(&text.as_bytes()[block * BLOCK..offset]);
        Counts {
            chars: base.chars + rest.chars,
            utf16: base.utf16 + rest.utf16,
        }
    }
}

/// The characters and UTF-16 units that start in `bytes` (any byte range of UTF-8 text): every
/// byte that does not continue a sequence starts a character, and a four-byte one takes two
/// UTF-16 units.
fn counts_in(bytes: &[u8]) -> Counts {
    let mut counts = Counts::default();
    for &b in bytes {
        counts.chars += u32::from(b & 0xC0 != 0x80);
        counts.utf16 += u32::from(b & 0xC0 != 0x80) + u32::from(b >= 0xF0);
    }
    counts
}

/// `offset`, or the start of the character it falls inside.
fn floor_char_boundary(text: &str, mut offset: usize) -> usize {
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_columns_round_trip() {
        let text = "a = 1;\nb = \"é😀\"; c\n";
        let index = LineIndex::new(text);
        let c = text.find(" c").unwrap() + 1;
        // é is one UTF-16 unit, 😀 is two.
        assert_eq!(
            index.line_col(text, c),
            LineCol {
                line: 1,
                character: 11
            }
        );
        assert_eq!(
            index.offset(
                text,
                LineCol {
                    line: 1,
                    character: 11
                }
            ),
            c
        );
        assert_eq!(
            index.line_col(text, text.len()),
            LineCol {
                line: 2,
                character: 0
            }
        );
        assert_eq!(index.line_count(), 3);
        assert_eq!(index.char_column(text, c), 10);
    }

    /// The straightforward conversions, scanning from the line start, that the checkpoints must
    /// agree with.
    fn naive_line_col(text: &str, offset: usize) -> (LineCol, u32) {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
        let line = text[..start].matches('\n').count() as u32;
        let before = &text[start..offset];
        let character = before.chars().map(char::len_utf16).sum::<usize>() as u32;
        (LineCol { line, character }, before.chars().count() as u32)
    }

    fn naive_offset(text: &str, position: LineCol) -> usize {
        let starts: Vec<usize> = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        let Some(&start) = starts.get(position.line as usize) else {
            return text.len();
        };
        let end = starts
            .get(position.line as usize + 1)
            .map_or(text.len(), |next| next - 1);
        let mut units = 0;
        for (i, c) in text[start..end].char_indices() {
            if units >= position.character as usize {
                return start + i;
            }
            units += c.len_utf16();
        }
        end
    }

    #[test]
    fn conversions_agree_with_a_scan_across_block_boundaries() {
        // Long lines of mixed widths, so that checkpoints fall inside characters and lines.
        let line = "ab é 😀 日本 \t x".repeat(40);
        let text = format!("{line}\n\n{line}\r\n{}😀\n{line}", "x".repeat(BLOCK - 3));
        let index = LineIndex::new(&text);
        for offset in 0..=text.len() + 2 {
            let (expected, chars) = naive_line_col(&text, offset);
            assert_eq!(index.line_col(&text, offset), expected, "offset {offset}");
            assert_eq!(index.char_column(&text, offset), chars, "offset {offset}");
        }
        for line in 0..7 {
            for character in 0..1_300 {
                let position = LineCol { line, character };
                assert_eq!(
                    index.offset(&text, position),
                    naive_offset(&text, position),
                    "{position:?}"
                );
            }
        }
        assert_eq!(index.line_range(1), Some(line.len() + 1..line.len() + 1));
        assert_eq!(index.line_of(text.len() + 10), 4);
    }

    #[test]
    fn empty_text_has_one_empty_line() {
        let index = LineIndex::new("");
        assert_eq!(index.line_count(), 1);
        assert_eq!(index.line_range(0), Some(0..0));
        assert_eq!(index.line_range(1), None);
        assert_eq!(
            index.line_col("", 5),
            LineCol {
                line: 0,
                character: 0
            }
        );
        assert_eq!(
            index.offset(
                "",
                LineCol {
                    line: 3,
                    character: 1
                }
            ),
            0
        );
    }
}
