//! Splitting a byte stream into LSP message bodies by their `Content-Length` headers, whatever
//! the stream holds.
//!
//! A message is a block of header lines (`Name: value`, each ended by `\r\n`; a bare `\n` is
//! accepted too), an empty line, and a body of exactly `Content-Length` bytes. Header names are
//! compared ignoring ASCII case; headers other than `Content-Length` (`Content-Type`) are
//! ignored, since LSP allows only UTF-8 and the body's check says whether it is.
//!
//! What cannot be framed (a line that is not a header, a header block without a valid
//! `Content-Length`) is reported once as [`Frame::Unframeable`], and the reader then skips to
//! the next `Content-Length:` anywhere in the stream, even in the middle of a line: a body
//! shorter than its header said leaves the next message's header right after its last byte.
//! A body longer than the limit is reported as [`Frame::Oversized`] and read past without being
//! buffered. A partial message at the end of the input is dropped.
//!
//! Every byte is looked at a bounded number of times, and the buffer holds at most one body
//! (within the limit), one header line or one read's worth beyond that.

use std::fmt;

use tokio::io::{AsyncRead, AsyncReadExt};

/// The longest header line accepted; real ones are a few dozen bytes.
const MAX_HEADER_LINE: usize = 8 * 1024;
/// How much room each read is given.
const READ_CHUNK: usize = 64 * 1024;
/// What resynchronisation looks for, compared ignoring ASCII case.
const CONTENT_LENGTH: &[u8] = b"content-length:";

/// What the reader found next in the stream.
#[derive(Debug, PartialEq, Eq)]
pub enum Frame {
    /// A message's body: exactly the bytes its `Content-Length` announced.
    Body(Vec<u8>),
    /// A message whose `Content-Length` exceeds the limit; its body is skipped unread.
    Oversized {
        /// The announced length.
        length: u64,
    },
    /// Bytes that cannot be framed; everything up to the next `Content-Length:` is skipped.
    Unframeable(Unframeable),
}

/// Why bytes could not be framed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unframeable {
    /// A line where a header (`Name: value`) was expected.
    NotAHeader,
    /// A header line longer than [`MAX_HEADER_LINE`] bytes.
    LongLine,
    /// A header block that ended without a `Content-Length`.
    MissingLength,
    /// A `Content-Length` that is not a decimal number of bytes (its value, shortened).
    InvalidLength(String),
    /// Two `Content-Length` headers in one block that disagree.
    ConflictingLengths,
}

impl fmt::Display for Unframeable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotAHeader => f.write_str("a line that is not a header (`Name: value`)"),
            Self::LongLine => write!(f, "a header line longer than {MAX_HEADER_LINE} bytes"),
            Self::MissingLength => f.write_str("a header block without `Content-Length`"),
            Self::InvalidLength(value) => {
                write!(f, "`Content-Length: {value}` is not a number of bytes")
            }
            Self::ConflictingLengths => {
                f.write_str("a header block with two different `Content-Length`s")
            }
        }
    }
}

/// Where the reader is in the stream.
#[derive(Clone, Copy, Debug)]
enum State {
    /// Reading a header block: its `Content-Length` so far and whether a header line was read.
    Headers { length: Option<u64>, started: bool },
    /// Skipping bytes up to the next `Content-Length:`.
    Resynchronising,
    /// Waiting for a body of this many bytes.
    Body(usize),
    /// Skipping an oversized body: this many bytes of it remain.
    Discarding(u64),
}

/// The block-start state.
const NEW_BLOCK: State = State::Headers {
    length: None,
    started: false,
};

/// Reads [`Frame`]s from a byte stream.
#[derive(Debug)]
pub struct FrameReader<R> {
    input: R,
    /// Bytes read and not yet consumed start at `start`; those before it are dead.
    buffer: Vec<u8>,
    start: usize,
    /// How many bytes from `start` are known to hold no line end (a header line in progress).
    scanned: usize,
    state: State,
    max_body: u64,
    ended: bool,
}

impl<R: AsyncRead + Unpin> FrameReader<R> {
    /// A reader of `input` that refuses bodies longer than `max_body` bytes.
    pub fn new(input: R, max_body: usize) -> Self {
        Self {
            input,
            buffer: Vec::new(),
            start: 0,
            scanned: 0,
            state: NEW_BLOCK,
            max_body: u64::try_from(max_body).unwrap_or(u64::MAX),
            ended: false,
        }
    }

    /// The next frame; `None` at the end of the input or on a read error.
    pub async fn next(&mut self) -> Option<Frame> {
        loop {
            let progress = match self.state {
                State::Headers { length, started } => self.header_line(length, started),
                State::Resynchronising => self.resynchronise(),
                State::Body(length) => self.body(length),
                State::Discarding(remaining) => self.discard(remaining),
            };
            match progress {
                Progress::Frame(frame) => return Some(frame),
                Progress::Continue => {}
                Progress::NeedInput(wanted) => {
                    if !self.fill(wanted).await {
                        return None;
                    }
                }
            }
        }
    }

    /// Reads one header line, or ends the block at an empty one.
    fn header_line(&mut self, length: Option<u64>, started: bool) -> Progress {
        let available = &self.buffer[self.start..];
        let searched = &available[self.scanned..available.len().min(MAX_HEADER_LINE + 1)];
        let Some(offset) = searched.iter().position(|&b| b == b'\n') else {
            if available.len() > MAX_HEADER_LINE {
                return self.unframeable_line(Unframeable::LongLine);
            }
            self.scanned = available.len();
            return Progress::NeedInput(READ_CHUNK);
        };
        let end = self.scanned + offset;
        let line = available[..end]
            .strip_suffix(b"\r")
            .unwrap_or(&available[..end]);
        if line.is_empty() {
            self.consume(end + 1);
            if !started {
                // A stray line end between messages.
                return Progress::Continue;
            }
            return match length {
                None => {
                    self.state = State::Resynchronising;
                    Progress::Frame(Frame::Unframeable(Unframeable::MissingLength))
                }
                Some(length) if length > self.max_body => {
                    self.state = State::Discarding(length);
                    Progress::Frame(Frame::Oversized { length })
                }
                Some(length) => {
                    // Within `max_body`, which came from a `usize`.
                    self.state = State::Body(usize::try_from(length).unwrap_or(usize::MAX));
                    Progress::Continue
                }
            };
        }
        let Some((name, value)) = header(line) else {
            return self.unframeable_line(Unframeable::NotAHeader);
        };
        let length = if name.eq_ignore_ascii_case(b"content-length") {
            match (decimal(value), length) {
                (None, _) => {
                    let shown = String::from_utf8_lossy(&value[..value.len().min(40)]);
                    return self.unframeable_line(Unframeable::InvalidLength(shown.into_owned()));
                }
                (Some(new), Some(old)) if new != old => {
                    return self.unframeable_line(Unframeable::ConflictingLengths);
                }
                (Some(new), _) => Some(new),
            }
        } else {
            length
        };
        self.consume(end + 1);
        self.state = State::Headers {
            length,
            started: true,
        };
        Progress::Continue
    }

    /// Gives up the header block at the line starting at `start`, skipping that line's first
    /// byte so that resynchronisation cannot find the same `Content-Length:` again.
    fn unframeable_line(&mut self, why: Unframeable) -> Progress {
        self.consume(1);
        self.state = State::Resynchronising;
        Progress::Frame(Frame::Unframeable(why))
    }

    /// Skips to the next `Content-Length:`, keeping a tail that may be the start of one.
    fn resynchronise(&mut self) -> Progress {
        let available = &self.buffer[self.start..];
        let found = available
            .windows(CONTENT_LENGTH.len())
            .position(|window| window.eq_ignore_ascii_case(CONTENT_LENGTH));
        match found {
            Some(offset) => {
                self.consume(offset);
                self.state = NEW_BLOCK;
                Progress::Continue
            }
            None => {
                let keep = available.len().min(CONTENT_LENGTH.len() - 1);
                self.consume(available.len() - keep);
                Progress::NeedInput(READ_CHUNK)
            }
        }
    }

    /// Takes the body once all of it is there.
    fn body(&mut self, length: usize) -> Progress {
        let available = self.buffer.len() - self.start;
        if available < length {
            return Progress::NeedInput(length - available);
        }
        let body = self.buffer[self.start..self.start + length].to_vec();
        self.consume(length);
        self.state = NEW_BLOCK;
        Progress::Frame(Frame::Body(body))
    }

    /// Drops what is buffered of an oversized body, then asks for more.
    fn discard(&mut self, remaining: u64) -> Progress {
        let available = self.buffer.len() - self.start;
        let dropped = usize::try_from(remaining).map_or(available, |r| r.min(available));
        self.consume(dropped);
        let remaining = remaining - dropped as u64;
        if remaining == 0 {
            self.state = NEW_BLOCK;
            return Progress::Continue;
        }
        self.state = State::Discarding(remaining);
        Progress::NeedInput(READ_CHUNK)
    }

    /// Marks `count` buffered bytes as consumed.
    fn consume(&mut self, count: usize) {
        self.start += count;
        self.scanned = 0;
    }

    /// Reads at least one more byte, making room for `wanted`; `false` at the end of the input.
    async fn fill(&mut self, wanted: usize) -> bool {
        if self.ended {
            return false;
        }
        // Moving the live bytes down only when the dead ones are at least as many keeps the
        // copying linear in the input.
        if self.start > 0 && 2 * self.start >= self.buffer.len() {
            self.buffer.drain(..self.start);
            self.start = 0;
        }
        self.buffer.reserve(wanted.max(READ_CHUNK));
        match self.input.read_buf(&mut self.buffer).await {
            Ok(0) | Err(_) => {
                self.ended = true;
                false
            }
            Ok(_) => true,
        }
    }
}

/// What one step of the reader achieved.
enum Progress {
    Frame(Frame),
    Continue,
    /// More input is needed; room for this many bytes helps.
    NeedInput(usize),
}

/// The name and the trimmed value of a header line, if it is one: a name made of HTTP's token
/// characters (RFC 9110 §5.6.2), a colon, and a value. The strict name makes the rest of an
/// overlong JSON body (`}Content-Length: 52`) garbage, which resynchronisation then recovers
/// from, rather than a header of an unknown name.
fn header(line: &[u8]) -> Option<(&[u8], &[u8])> {
    let colon = line.iter().position(|&b| b == b':')?;
    let (name, value) = (&line[..colon], &line[colon + 1..]);
    let is_token = |b: &u8| b.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(b);
    if name.is_empty() || !name.iter().all(is_token) {
        return None;
    }
    Some((name, value.trim_ascii()))
}

/// A non-empty string of ASCII digits as a number, if it fits.
fn decimal(text: &[u8]) -> Option<u64> {
    if text.is_empty() || !text.iter().all(u8::is_ascii_digit) {
        return None;
    }
    std::str::from_utf8(text).ok()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use std::io;
    use std::pin::Pin;
    use std::task::{Context, Poll};

    use tokio::io::ReadBuf;

    use super::*;

    /// Hands out its bytes at most `step` at a time, as a pipe may.
    struct Trickle {
        bytes: Vec<u8>,
        at: usize,
        step: usize,
    }

    impl AsyncRead for Trickle {
        fn poll_read(
            mut self: Pin<&mut Self>,
            _: &mut Context<'_>,
            buf: &mut ReadBuf<'_>,
        ) -> Poll<io::Result<()>> {
            let end = (self.at.saturating_add(self.step))
                .min(self.bytes.len())
                .min(self.at + buf.remaining());
            buf.put_slice(&self.bytes[self.at..end]);
            self.at = end;
            Poll::Ready(Ok(()))
        }
    }

    async fn frames_with(bytes: &[u8], step: usize, max_body: usize) -> Vec<Frame> {
        let input = Trickle {
            bytes: bytes.to_vec(),
            at: 0,
            step,
        };
        let mut reader = FrameReader::new(input, max_body);
        let mut frames = Vec::new();
        while let Some(frame) = reader.next().await {
            frames.push(frame);
        }
        frames
    }

    /// The frames of `bytes`, checked to be the same whether read whole or byte by byte.
    async fn frames(bytes: &[u8]) -> Vec<Frame> {
        let whole = frames_with(bytes, usize::MAX, 1024).await;
        let trickled = frames_with(bytes, 1, 1024).await;
        assert_eq!(whole, trickled, "reading in pieces changes the frames");
        whole
    }

    fn message(body: &str) -> String {
        format!("Content-Length: {}\r\n\r\n{body}", body.len())
    }

    fn body(text: &str) -> Frame {
        Frame::Body(text.as_bytes().to_vec())
    }

    #[tokio::test]
    async fn splits_messages_by_length() {
        let input = format!("{}{}", message("{\"a\":1}"), message("[]"));
        assert_eq!(
            frames(input.as_bytes()).await,
            [body("{\"a\":1}"), body("[]")]
        );
    }

    #[tokio::test]
    async fn accepts_other_headers_any_case_and_bare_line_feeds() {
        let input = "Content-Type: application/vscode-jsonrpc\r\nCONTENT-length:  2 \n\n{}\
                     \r\n\r\ncontent-length: 1\r\nX-Extra: y\r\n\r\n7";
        assert_eq!(frames(input.as_bytes()).await, [body("{}"), body("7")]);
    }

    #[tokio::test]
    async fn skips_garbage_to_the_next_content_length() {
        let input = format!("hello\r\nworld{}", message("{}"));
        assert_eq!(
            frames(input.as_bytes()).await,
            [Frame::Unframeable(Unframeable::NotAHeader), body("{}")]
        );
    }

    #[tokio::test]
    async fn a_block_without_length_is_skipped_with_its_body() {
        let input = format!("Content-Type: x\r\n\r\n{{\"x\":1}}{}", message("{}"));
        assert_eq!(
            frames(input.as_bytes()).await,
            [Frame::Unframeable(Unframeable::MissingLength), body("{}")]
        );
    }

    #[tokio::test]
    async fn invalid_and_conflicting_lengths_are_skipped() {
        for (header, why) in [
            (
                "Content-Length: abc",
                Unframeable::InvalidLength("abc".into()),
            ),
            (
                "Content-Length: -5",
                Unframeable::InvalidLength("-5".into()),
            ),
            ("Content-Length:", Unframeable::InvalidLength(String::new())),
            (
                "Content-Length: 99999999999999999999999",
                Unframeable::InvalidLength("99999999999999999999999".into()),
            ),
            (
                "Content-Length: 2\r\nContent-Length: 3",
                Unframeable::ConflictingLengths,
            ),
        ] {
            let input = format!("{header}\r\n\r\n{{}}{}", message("[1]"));
            assert_eq!(
                frames(input.as_bytes()).await,
                [Frame::Unframeable(why), body("[1]")],
                "{header}"
            );
        }
    }

    #[tokio::test]
    async fn a_short_body_loses_only_itself() {
        // The first body is one byte longer than announced: its read takes the `C` of the next
        // header, which is lost; resynchronisation finds the one after.
        let input = format!(
            "Content-Length: 8\r\n\r\n{{\"a\":1}}{}{}",
            message("[1]"),
            message("[2]")
        );
        let found = frames(input.as_bytes()).await;
        assert_eq!(
            found,
            [
                body("{\"a\":1}C"),
                Frame::Unframeable(Unframeable::MissingLength),
                body("[2]")
            ]
        );
        // One byte shorter than announced: the next header is found in the middle of a line.
        let input = format!("Content-Length: 6\r\n\r\n{{\"a\":1}}{}", message("[1]"));
        assert_eq!(
            frames(input.as_bytes()).await,
            [
                body("{\"a\":1"),
                Frame::Unframeable(Unframeable::NotAHeader),
                body("[1]")
            ]
        );
    }

    #[tokio::test]
    async fn a_long_line_is_skipped() {
        let input = format!("{}{}", "x".repeat(3 * MAX_HEADER_LINE), message("{}"));
        assert_eq!(
            frames(input.as_bytes()).await,
            [Frame::Unframeable(Unframeable::LongLine), body("{}")]
        );
        let input = format!(
            "Content-Length: {}\r\n\r\n{}",
            "0".repeat(2 * MAX_HEADER_LINE),
            message("{}")
        );
        assert_eq!(
            frames(input.as_bytes()).await,
            [Frame::Unframeable(Unframeable::LongLine), body("{}")]
        );
    }

    #[tokio::test]
    async fn an_oversized_body_is_skipped_without_buffering_it() {
        let big = "x".repeat(1 << 20);
        let input = format!("{}{}", message(&big), message("{}"));
        let mut reader = FrameReader::new(input.as_bytes(), 1024);
        assert_eq!(
            reader.next().await,
            Some(Frame::Oversized {
                length: big.len() as u64
            })
        );
        assert_eq!(reader.next().await, Some(body("{}")));
        assert_eq!(reader.next().await, None);
        assert!(
            reader.buffer.capacity() < 4 * READ_CHUNK,
            "the buffer grew to {} bytes",
            reader.buffer.capacity()
        );
    }

    #[tokio::test]
    async fn a_partial_message_at_the_end_is_dropped() {
        for input in [
            "Content-Length: 10\r\n\r\n{}",
            "Content-Length: 10\r\n",
            "Content-Len",
            "garbage",
        ] {
            assert_eq!(frames(input.as_bytes()).await, [], "{input:?}");
        }
        assert_eq!(frames(b"").await, []);
        assert_eq!(frames(b"\r\n\r\n").await, []);
    }
}
