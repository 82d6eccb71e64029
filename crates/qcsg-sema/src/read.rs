//! Reading source files safely: the one way qcsg reads a program's files from disk, its sources
//! and the data files it imports ([`read_bytes_with_limit`], bytes under a caller's limit).
//!
//! A source must be a regular file (a device such as `/dev/zero`, a directory or a named pipe is
//! refused before it is opened), no larger than [`MAX_SOURCE_BYTES`] (the read itself is bounded,
//! so a file that grows or a file system that reports the wrong size cannot exhaust memory), and
//! UTF-8. Invalid UTF-8 does not stop the check: each invalid sequence reads as U+FFFD, and the
//! [`SourceText`] remembers where the first one is and how many there are, so the checker reports
//! one error at the first and analyses the rest.
//!
//! [`FileLoader::load`](crate::FileLoader::load) returns `std::io::Result<String>`; [`load_source`]
//! is this reader in that shape: what is wrong travels inside the `io::Error` as a
//! [`SourceError`], which [`SourceError::from_io`] takes back out.

use std::fmt;
use std::io::{self, Read};
use std::path::Path;

use qcsg_diag::Span;

/// The largest source file qcsg reads: 64 MiB, far above any hand-written program, and a bound
/// on what a mistaken `include` of a huge file costs.
pub const MAX_SOURCE_BYTES: u64 = 64 << 20;

/// The text of a source file, with what was wrong with its encoding.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SourceText {
    /// The text; each invalid UTF-8 sequence of the file is one U+FFFD here.
    pub text: String,
    /// The first invalid UTF-8 sequence, if any.
    pub invalid_utf8: Option<InvalidUtf8>,
}

/// Where a file stops being valid UTF-8.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidUtf8 {
    /// The U+FFFD that replaces the first invalid sequence, in [`SourceText::text`].
    pub span: Span,
    /// The bytes of that sequence (one to three).
    pub bytes: Vec<u8>,
    /// How many invalid sequences the file has, the first included.
    pub count: usize,
}

impl From<String> for SourceText {
    fn from(text: String) -> Self {
        SourceText {
            text,
            invalid_utf8: None,
        }
    }
}

impl SourceText {
    /// Decodes `bytes` as UTF-8, replacing each invalid sequence with U+FFFD as
    /// `String::from_utf8_lossy` does; valid UTF-8 is taken without a copy.
    pub fn decode(bytes: Vec<u8>) -> Self {
        let bytes = match String::from_utf8(bytes) {
            Ok(text) => return text.into(),
            Err(error) => error.into_bytes(),
        };
        let mut text = String::with_capacity(bytes.len() + bytes.len() / 2);
        let mut invalid_utf8: Option<InvalidUtf8> = None;
        for chunk in bytes.utf8_chunks() {
            text.push_str(chunk.valid());
            if chunk.invalid().is_empty() {
                continue;
            }
            match &mut invalid_utf8 {
                Some(first) => first.count += 1,
                None => {
                    invalid_utf8 = Some(InvalidUtf8 {
                        span: Span::new(text.len(), text.len() + '\u{FFFD}'.len_utf8()),
                        bytes: chunk.invalid().to_vec(),
                        count: 1,
                    });
                }
            }
            text.push('\u{FFFD}');
        }
        SourceText { text, invalid_utf8 }
    }
}

/// Why a source file cannot be read, or can be read only with replacements.
#[derive(Debug)]
pub enum SourceError {
    /// The path names something other than a regular file; `what` says what ("a directory").
    NotAFile {
        /// What the path names, with its article: "a character device".
        what: &'static str,
    },
    /// The file has more than `limit` bytes; `size` is its size when the file system knows it.
    TooLarge {
        /// Its size in bytes, when known.
        size: Option<u64>,
        /// The limit it exceeds.
        limit: u64,
    },
    /// The file is not valid UTF-8: its text as decoded, which is still worth checking.
    InvalidUtf8(SourceText),
    /// The file could not be opened or read (not found, permission denied, …).
    Io(io::Error),
}

impl SourceError {
    /// The [`SourceError`] an `io::Error` from [`load_source`] carries, or the error itself as
    /// [`SourceError::Io`] when it carries none (as from a loader that serves editor buffers).
    pub fn from_io(error: io::Error) -> Self {
        if error
            .get_ref()
            .is_some_and(|inner| inner.is::<SourceError>())
        {
            let inner = error.into_inner().expect("checked just above");
            return *inner.downcast::<SourceError>().expect("checked just above");
        }
        SourceError::Io(error)
    }

    /// Whether the file does not exist, so that a search may go on to the next directory.
    pub fn is_not_found(&self) -> bool {
        matches!(self, SourceError::Io(error) if error.kind() == io::ErrorKind::NotFound)
    }
}

impl fmt::Display for SourceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SourceError::NotAFile { what } => write!(f, "it is {what}, not a regular file"),
            SourceError::TooLarge { size, limit } => {
                let limit = byte_size(*limit);
                match size {
                    Some(size) => write!(
                        f,
                        "it is {} ({size} bytes), over the {limit} limit on source files",
                        byte_size(*size)
                    ),
                    None => write!(f, "it is over the {limit} limit on source files"),
                }
            }
            SourceError::InvalidUtf8(source) => match &source.invalid_utf8 {
                Some(invalid) => write!(f, "it is not valid UTF-8 ({})", describe(invalid)),
                None => f.write_str("it is not valid UTF-8"),
            },
            SourceError::Io(error) => write!(f, "{error}"),
        }
    }
}

impl std::error::Error for SourceError {}

impl From<io::Error> for SourceError {
    fn from(error: io::Error) -> Self {
        SourceError::Io(error)
    }
}

impl From<SourceError> for io::Error {
    /// An `io::Error` that carries the [`SourceError`] (or is the underlying one).
    fn from(error: SourceError) -> Self {
        let kind = match &error {
            SourceError::Io(_) => return unwrap_io(error),
            SourceError::NotAFile { .. } => io::ErrorKind::InvalidInput,
            SourceError::TooLarge { .. } => io::ErrorKind::FileTooLarge,
            SourceError::InvalidUtf8(_) => io::ErrorKind::InvalidData,
        };
        io::Error::new(kind, error)
    }
}

fn unwrap_io(error: SourceError) -> io::Error {
    match error {
        SourceError::Io(error) => error,
        other => io::Error::other(other),
    }
}

/// `"0xFF"`, or `"0xE2 0x82"`, and how many more there are.
pub(crate) fn describe(invalid: &InvalidUtf8) -> String {
    let bytes: Vec<String> = invalid.bytes.iter().map(|b| format!("0x{b:02X}")).collect();
    let more = match invalid.count - 1 {
        0 => String::new(),
        1 => "; 1 more invalid sequence follows".to_owned(),
        n => format!("; {n} more invalid sequences follow"),
    };
    let noun = if invalid.bytes.len() == 1 {
        "byte"
    } else {
        "bytes"
    };
    format!("{noun} {}{more}", bytes.join(" "))
}

/// `"64 MiB"`, `"1.5 GiB"`, `"900 bytes"`.
fn byte_size(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    let value = format!("{value:.1}");
    let value = value.strip_suffix(".0").unwrap_or(&value);
    format!("{value} {}", UNITS[unit])
}

/// What a file type is, for "it is a character device, not a regular file".
fn describe_file_type(file_type: std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_fifo() {
            return "a named pipe";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "something other than a file"
}

/// Reads the source file at `path`: a regular file of at most [`MAX_SOURCE_BYTES`], decoded
/// as UTF-8 with invalid sequences replaced (see [`SourceText`]).
pub fn read_source(path: &Path) -> Result<SourceText, SourceError> {
    read_source_with_limit(path, MAX_SOURCE_BYTES)
}

/// [`read_source`] with another size limit.
pub fn read_source_with_limit(path: &Path, limit: u64) -> Result<SourceText, SourceError> {
    let (file, size) = open_regular(path, limit)?;
    read_bounded(file, limit, Some(size))
}

/// The bytes of the data file at `path` (an imported mesh or drawing): a regular file of at most
/// `limit` bytes, refused as a source is (a device, a directory, a file over the limit), never
/// decoded. A [`SourceError::TooLarge`] here is over `limit`, not over [`MAX_SOURCE_BYTES`].
pub fn read_bytes_with_limit(path: &Path, limit: u64) -> Result<Vec<u8>, SourceError> {
    let (file, size) = open_regular(path, limit)?;
    read_bounded_bytes(file, limit, Some(size))
}

/// Opens `path` if it is a regular file of at most `limit` bytes, with its size.
fn open_regular(path: &Path, limit: u64) -> Result<(std::fs::File, u64), SourceError> {
    // Ask before opening: opening a named pipe waits for a writer, and a device never ends.
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        return Err(SourceError::NotAFile {
            what: describe_file_type(metadata.file_type()),
        });
    }
    if metadata.len() > limit {
        return Err(SourceError::TooLarge {
            size: Some(metadata.len()),
            limit,
        });
    }
    let file = std::fs::File::open(path)?;
    // The path may have been replaced since; what was opened is what counts.
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        return Err(SourceError::NotAFile {
            what: describe_file_type(metadata.file_type()),
        });
    }
    Ok((file, metadata.len()))
}

/// Reads a whole source from `reader` (standard input), at most `limit` bytes.
pub fn read_source_from(reader: impl Read, limit: u64) -> Result<SourceText, SourceError> {
    read_bounded(reader, limit, None)
}

/// Reads at most `limit` bytes, and one more to tell whether there were more; `size_hint` is
/// what the file system says the size is (never trusted beyond the limit).
fn read_bounded(
    reader: impl Read,
    limit: u64,
    size_hint: Option<u64>,
) -> Result<SourceText, SourceError> {
    read_bounded_bytes(reader, limit, size_hint).map(SourceText::decode)
}

/// The bytes of [`read_bounded`], undecoded.
fn read_bounded_bytes(
    reader: impl Read,
    limit: u64,
    size_hint: Option<u64>,
) -> Result<Vec<u8>, SourceError> {
    // Without a size, room for the limit: untouched pages cost no memory, and the buffer never
    // grows past the limit by doubling.
    let capacity = size_hint.unwrap_or(limit).min(limit).min(MAX_SOURCE_BYTES) as usize + 1;
    let mut bytes = Vec::with_capacity(capacity);
    reader
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(SourceError::TooLarge { size: None, limit });
    }
    Ok(bytes)
}

/// [`read_source`] in the shape of [`FileLoader::load`](crate::FileLoader::load): invalid UTF-8
/// is an error carrying the decoded text (see [`SourceError::from_io`]).
pub fn load_source(path: &Path) -> io::Result<String> {
    let source = read_source(path)?;
    if source.invalid_utf8.is_some() {
        return Err(SourceError::InvalidUtf8(source).into());
    }
    Ok(source.text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_sequences_read_as_replacement_characters() {
        let source = SourceText::decode(b"a = \"\xE9t\xE9\"; \xF0\x9F\x98;".to_vec());
        assert_eq!(source.text, "a = \"\u{FFFD}t\u{FFFD}\"; \u{FFFD};");
        assert_eq!(
            source.invalid_utf8,
            Some(InvalidUtf8 {
                span: Span::new(5, 8),
                bytes: vec![0xE9],
                count: 3,
            })
        );
        assert_eq!(
            describe(source.invalid_utf8.as_ref().unwrap()),
            "byte 0xE9; 2 more invalid sequences follow"
        );
        assert_eq!(
            SourceText::decode(b"ok".to_vec()),
            SourceText::from("ok".to_owned())
        );
    }

    #[test]
    fn the_limit_bounds_the_read() {
        let text = read_source_from(&b"12345"[..], 5).expect("at the limit");
        assert_eq!(text.text, "12345");
        let error = read_source_from(io::repeat(b'x'), 1000).unwrap_err();
        assert!(matches!(
            error,
            SourceError::TooLarge {
                size: None,
                limit: 1000
            }
        ));
        assert_eq!(
            error.to_string(),
            "it is over the 1000 bytes limit on source files"
        );
        let error = SourceError::TooLarge {
            size: Some(100 << 20),
            limit: MAX_SOURCE_BYTES,
        };
        assert_eq!(
            error.to_string(),
            "it is 100 MiB (104857600 bytes), over the 64 MiB limit on source files"
        );
        assert_eq!(byte_size(1536), "1.5 KiB");
    }

    #[cfg(unix)]
    #[test]
    fn devices_and_directories_are_refused_unopened() {
        let error = read_source(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(
            error.to_string(),
            "it is a character device, not a regular file"
        );
        let error = read_source(Path::new("/")).unwrap_err();
        assert!(matches!(
            error,
            SourceError::NotAFile {
                what: "a directory"
            }
        ));
        let missing = read_source(Path::new("/no/such/file.qcsg")).unwrap_err();
        assert!(missing.is_not_found());
        // Data files are refused the same way, under the caller's limit.
        let error = read_bytes_with_limit(Path::new("/dev/zero"), 1 << 30).unwrap_err();
        assert!(matches!(error, SourceError::NotAFile { .. }), "{error}");
        let error = read_bytes_with_limit(Path::new("/"), 1 << 30).unwrap_err();
        assert!(matches!(error, SourceError::NotAFile { .. }), "{error}");
    }

    #[test]
    fn data_files_are_read_as_bytes_under_the_limit() {
        let path = std::env::temp_dir().join(format!("qcsg-read-bytes-{}", std::process::id()));
        std::fs::write(&path, [0xFFu8, 0x00, 0x80]).expect("write a scratch file");
        let bytes = read_bytes_with_limit(&path, 3);
        let over = read_bytes_with_limit(&path, 2);
        let _ = std::fs::remove_file(&path);
        assert_eq!(bytes.expect("at the limit"), [0xFF, 0x00, 0x80]);
        assert!(matches!(
            over.unwrap_err(),
            SourceError::TooLarge {
                size: Some(3),
                limit: 2
            }
        ));
    }

    #[test]
    fn errors_survive_the_trip_through_io_error() {
        let source = SourceText::decode(vec![b'a', 0xFF]);
        let error: io::Error = SourceError::InvalidUtf8(source.clone()).into();
        assert_eq!(error.kind(), io::ErrorKind::InvalidData);
        match SourceError::from_io(error) {
            SourceError::InvalidUtf8(back) => assert_eq!(back, source),
            other => panic!("{other:?}"),
        }
        let not_found: io::Error = SourceError::Io(io::ErrorKind::NotFound.into()).into();
        assert_eq!(not_found.kind(), io::ErrorKind::NotFound);
        assert!(SourceError::from_io(not_found).is_not_found());
        let plain = io::Error::other("plain");
        assert!(matches!(SourceError::from_io(plain), SourceError::Io(_)));
    }
}
