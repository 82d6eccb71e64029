//! Byte offset ↔ (line, UTF-16 column) conversion, as LSP and the JSON diagnostics format use.

/// A zero-based line and a zero-based column counted in UTF-16 code units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LineCol {
    /// Zero-based line.
    pub line: u32,
    /// Zero-based column in UTF-16 code units.
    pub character: u32,
}

/// Line starts of one text, for converting byte offsets to [`LineCol`] and back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LineIndex {
    /// Byte offset where each line starts; the first is always 0.
    line_starts: Vec<u32>,
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
        Self {
            line_starts,
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

    /// The line and UTF-16 column of byte `offset` in `text` (the text this index was built from).
    /// Offsets past the end or inside a UTF-8 sequence are clamped to the previous character boundary.
    pub fn line_col(&self, text: &str, offset: usize) -> LineCol {
        let mut offset = offset.min(self.len as usize);
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_starts.partition_point(|&s| s as usize <= offset) - 1;
        let start = self.line_starts[line] as usize;
        let character = text[start..offset]
            .chars()
            .map(char::len_utf16)
            .sum::<usize>();
        LineCol {
            line: line as u32,
            character: character as u32,
        }
    }

    /// The byte offset of a line and UTF-16 column; columns past the end of the line clamp to it.
    pub fn offset(&self, text: &str, position: LineCol) -> usize {
        let Some(start) = self.line_start(position.line) else {
            return text.len();
        };
        let end = self
            .line_start(position.line + 1)
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
    }
}
