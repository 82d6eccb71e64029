//! A random edit session with the real language server, in process.
//!
//! The server is `qcsg_lsp`'s backend behind its transport layer, as `qcsg lsp` runs it
//! ([`serve`] mirrors `qcsg_lsp::run_stdio`), talking over a
//! `tokio::io::duplex` pipe to a small client here that frames messages itself. A session opens
//! the input as a document, then makes a random series of incremental edits (UTF-16 ranges, as
//! editors send them; now and then a whole-text change, a range past the end, or a malformed
//! message) with requests in between: hover, completion, semantic tokens, formatting, signature
//! help, symbols, inlay hints, folding, definition, references, code actions and rename
//! preparation, at positions inside the text and now and then past a line's end.
//!
//! A session fails when the server answers a request with an internal error, logs an error
//! (other than about a malformed message the client sent on purpose), stops answering, sends a
//! semantic token, a diagnostic or a formatting edit outside the document, or does not stop
//! after `exit`. Its panics are recorded whoever catches them ([`crate::panics`]).

use std::path::Path;
use std::time::Duration;

use serde_json::{Value, json};
use tokio::io::{
    AsyncBufReadExt, AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, BufReader, DuplexStream,
    ReadHalf, WriteHalf,
};

use crate::dice::Dice;
use crate::protocol::FailureKind;
use crate::stages::Problem;

/// The JSON-RPC code of an internal error: what the server answers when a handler panicked.
const INTERNAL_ERROR: i64 = -32603;

/// Replacement texts for edits: what typing, pasting and deleting produce.
const SNIPPETS: &[&str] = &[
    "",
    "",
    "",
    "(",
    ")",
    "{",
    "}",
    "[",
    "]",
    ";",
    ",",
    "\n",
    " ",
    "cube(1);",
    "sphere(",
    "module m() {",
    "function f(x) = x;",
    "x = ",
    "\"",
    "/*",
    "*/",
    "//",
    "é",
    "😀",
    "\r\n",
    "include <lib.qcsg>\n",
    "use <",
    "for (i = [0 : 3]) ",
    "translate([1, 0, 0]) ",
    "$fn = 8;",
    "let (a = 1) ",
    "children();",
    "1e308",
    "0/0",
    "\t",
    "\u{fffd}",
];

/// Malformed messages the client sends on purpose: the server must keep serving.
const MALFORMED: &[(&str, &[u8])] = &[
    ("invalid JSON", b"Content-Length: 1\r\n\r\n{"),
    ("a bare number", b"Content-Length: 2\r\n\r\n42"),
    ("an empty batch", b"Content-Length: 2\r\n\r\n[]"),
    ("invalid UTF-8", b"Content-Length: 4\r\n\r\n\"\xff\xfe\""),
    (
        "no jsonrpc field",
        b"Content-Length: 32\r\n\r\n{\"id\": 99999, \"method\": \"hover\"}",
    ),
    (
        "a non-numeric Content-Length",
        b"Content-Length: abc\r\n\r\n",
    ),
];

/// The runtime sessions run on: as `qcsg lsp`'s, with large stacks for deep trees.
pub struct Runtime {
    runtime: tokio::runtime::Runtime,
}

impl Runtime {
    /// A multi-threaded runtime with two workers.
    pub fn new() -> std::io::Result<Self> {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            // As `qcsg_lsp::run_stdio`: analyses walk trees recursively.
            .thread_stack_size(32 * 1024 * 1024)
            .enable_all()
            .build()?;
        Ok(Self { runtime })
    }
}

/// Serves LSP on `input` and `output` until the client exits, as `qcsg lsp` does on standard
/// input and output: the server behind its transport layer, which frames and checks messages.
async fn serve(input: impl AsyncRead + Unpin, output: impl AsyncWrite + Unpin) {
    qcsg_lsp::transport::serve(input, output, qcsg_lsp::transport::Options::default()).await;
}

/// Runs one session on `text`, opened as the file `path`.
pub fn run(runtime: &Runtime, path: &Path, text: &str, seed: u64) -> Result<(), Problem> {
    runtime
        .runtime
        .block_on(session(path, text, seed, true, SNIPPETS))
}

/// A session; `malformed`: whether it may send malformed messages; `snippets`: what its edits
/// insert.
async fn session(
    path: &Path,
    text: &str,
    seed: u64,
    malformed: bool,
    snippets: &'static [&'static str],
) -> Result<(), Problem> {
    let (client_end, server_end) = tokio::io::duplex(1 << 16);
    let (server_read, server_write) = tokio::io::split(server_end);
    let server = tokio::spawn(serve(server_read, server_write));
    let (read, write) = tokio::io::split(client_end);
    let mut client = Client {
        writer: write,
        reader: BufReader::new(read),
        next_id: 1,
        uri: file_uri(path),
        text: text.to_owned(),
        version: 1,
        dice: Dice::new(seed),
        malformed_sent: None,
        malformed,
        snippets,
        last: "initialize".to_owned(),
    };
    client.script().await?;
    drop(client);
    match tokio::time::timeout(Duration::from_secs(5), server).await {
        Ok(_) => Ok(()),
        Err(_) => Err(server_problem(
            "the server did not stop after `exit`",
            "did not stop after exit",
        )),
    }
}

/// A failure of the server.
fn server_problem(message: impl Into<String>, signature: &str) -> Problem {
    Problem {
        kind: FailureKind::Server,
        message: message.into(),
        signature: signature.to_owned(),
    }
}

/// A `file://` URI for a path (bytes other than unreserved ones percent-encoded).
fn file_uri(path: &Path) -> String {
    let mut uri = String::from("file://");
    for &b in path.to_string_lossy().as_bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            uri.push(char::from(b));
        } else {
            uri.push_str(&format!("%{b:02X}"));
        }
    }
    uri
}

/// The UTF-16 length of each line (split at `\n`).
fn line_lengths(text: &str) -> Vec<u32> {
    text.split('\n')
        .map(|line| line.encode_utf16().count() as u32)
        .collect()
}

/// The LSP position of a byte offset (on a character boundary).
fn position(text: &str, offset: usize) -> Value {
    let before = &text[..offset];
    let line = before.matches('\n').count();
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let character = before[line_start..].encode_utf16().count();
    json!({ "line": line, "character": character })
}

/// Whether an LSP position lies in a text whose lines have these lengths.
fn inside(lines: &[u32], position: &Value) -> bool {
    let (Some(line), Some(character)) = (
        position.get("line").and_then(Value::as_u64),
        position.get("character").and_then(Value::as_u64),
    ) else {
        return false;
    };
    lines
        .get(line as usize)
        .is_some_and(|&length| character <= u64::from(length))
}

/// The client side of a session.
struct Client {
    writer: WriteHalf<DuplexStream>,
    reader: BufReader<ReadHalf<DuplexStream>>,
    next_id: i64,
    uri: String,
    /// The document as the client has edited it.
    text: String,
    version: i32,
    dice: Dice,
    /// The malformed message the client sent, if it did: logged errors are expected after it.
    malformed_sent: Option<&'static str>,
    /// Whether the session may send malformed messages.
    malformed: bool,
    /// What edits insert.
    snippets: &'static [&'static str],
    /// The last thing sent, for reports.
    last: String,
}

impl Client {
    /// The whole session.
    async fn script(&mut self) -> Result<(), Problem> {
        self.request(
            "initialize",
            json!({ "processId": null, "capabilities": {} }),
        )
        .await?;
        self.notify("initialized", json!({})).await?;
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": {
                "uri": self.uri, "languageId": "qcsg", "version": self.version, "text": self.text,
            }}),
        )
        .await?;
        let steps = if self.text.len() > 200_000 {
            3
        } else {
            self.dice.between(4, 16)
        };
        for _ in 0..steps {
            match self.dice.below(20) {
                0..=8 => self.edit().await?,
                9 if self.malformed && self.dice.chance(0.3) => self.malformed().await?,
                _ => self.query().await?,
            }
        }
        self.query().await?;
        self.request("shutdown", Value::Null).await?;
        self.notify("exit", Value::Null).await
    }

    /// Sends raw bytes.
    async fn send_raw(&mut self, bytes: &[u8]) -> Result<(), Problem> {
        self.writer
            .write_all(bytes)
            .await
            .map_err(|error| self.stopped(&error.to_string()))
    }

    /// Sends one message.
    async fn send(&mut self, message: &Value) -> Result<(), Problem> {
        let body = message.to_string();
        let frame = format!("Content-Length: {}\r\n\r\n{body}", body.len());
        self.send_raw(frame.as_bytes()).await
    }

    fn stopped(&self, why: &str) -> Problem {
        match self.malformed_sent {
            Some(what) => server_problem(
                format!(
                    "the server stopped answering ({why}) after a malformed message ({what}), \
                     then {}",
                    self.last
                ),
                "stopped answering after a malformed message",
            ),
            None => server_problem(
                format!("the server stopped answering ({why}) after {}", self.last),
                "stopped answering",
            ),
        }
    }

    async fn notify(&mut self, method: &str, params: Value) -> Result<(), Problem> {
        self.last = method.to_owned();
        self.send(&json!({ "jsonrpc": "2.0", "method": method, "params": params }))
            .await
    }

    /// Sends a request and reads messages until its response, checking each on the way.
    async fn request(&mut self, method: &str, params: Value) -> Result<Value, Problem> {
        let id = self.next_id;
        self.next_id += 1;
        self.last = method.to_owned();
        self.send(&json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }))
            .await?;
        loop {
            let message = self.read_message().await?;
            if message.get("method").is_some() {
                self.incoming(&message).await?;
                continue;
            }
            if message.get("id").and_then(Value::as_i64) != Some(id) {
                // An answer to a malformed message (id null), or a stale one.
                continue;
            }
            if let Some(error) = message.get("error") {
                if error.get("code").and_then(Value::as_i64) == Some(INTERNAL_ERROR) {
                    return Err(server_problem(
                        format!("`{method}` was answered with an internal error: {error}"),
                        &format!("internal error on {method}"),
                    ));
                }
                return Ok(Value::Null);
            }
            return Ok(message.get("result").cloned().unwrap_or(Value::Null));
        }
    }

    /// Reads one framed message.
    async fn read_message(&mut self) -> Result<Value, Problem> {
        let mut length = None;
        loop {
            let mut line = String::new();
            let n = self
                .reader
                .read_line(&mut line)
                .await
                .map_err(|error| self.stopped(&error.to_string()))?;
            if n == 0 {
                return Err(self.stopped("end of its output"));
            }
            let line = line.trim_end();
            if line.is_empty() {
                break;
            }
            if let Some(value) = line.strip_prefix("Content-Length:") {
                length = value.trim().parse::<usize>().ok();
            }
        }
        let Some(length) = length else {
            return Err(server_problem(
                "the server sent a message without a Content-Length",
                "unframed message",
            ));
        };
        let mut body = vec![0; length];
        self.reader
            .read_exact(&mut body)
            .await
            .map_err(|error| self.stopped(&error.to_string()))?;
        serde_json::from_slice(&body).map_err(|error| {
            server_problem(
                format!("the server sent a message that is not JSON: {error}"),
                "invalid JSON from the server",
            )
        })
    }

    /// Handles a notification or request from the server.
    async fn incoming(&mut self, message: &Value) -> Result<(), Problem> {
        let method = message.get("method").and_then(Value::as_str).unwrap_or("");
        let params = message.get("params").cloned().unwrap_or(Value::Null);
        if let Some(id) = message.get("id") {
            // A request of the server's (capability registration, progress): accept it.
            let reply = json!({ "jsonrpc": "2.0", "id": id, "result": null });
            return self.send(&reply).await;
        }
        match method {
            "window/logMessage" | "window/showMessage" => {
                let error = params.get("type").and_then(Value::as_i64) == Some(1);
                if error && self.malformed_sent.is_none() {
                    let text = params.get("message").and_then(Value::as_str).unwrap_or("");
                    let signature: String = text
                        .split(':')
                        .next()
                        .unwrap_or("")
                        .chars()
                        .filter(|c| !c.is_ascii_digit())
                        .collect();
                    return Err(server_problem(
                        format!("the server logged an error after {}: {text}", self.last),
                        &format!("logged: {signature}"),
                    ));
                }
                Ok(())
            }
            "textDocument/publishDiagnostics" => {
                let current = params.get("version").and_then(Value::as_i64)
                    == Some(i64::from(self.version))
                    && params.get("uri").and_then(Value::as_str) == Some(self.uri.as_str());
                if current {
                    let lines = line_lengths(&self.text);
                    for diagnostic in params
                        .get("diagnostics")
                        .and_then(Value::as_array)
                        .into_iter()
                        .flatten()
                    {
                        let range = &diagnostic["range"];
                        if !(inside(&lines, &range["start"]) && inside(&lines, &range["end"])) {
                            return Err(Problem::invariant(
                                "a published diagnostic lies outside the document",
                                format!("{diagnostic} in a document of {} lines", lines.len()),
                            ));
                        }
                    }
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// A random byte offset on a character boundary.
    fn offset(&mut self) -> usize {
        let at = self.dice.between(0, self.text.len());
        self.text.floor_char_boundary(at)
    }

    /// A position for a request: mostly in the text, now and then past a line's end or the
    /// last line (which a client may send for a document it has just changed).
    fn request_position(&mut self) -> Value {
        match self.dice.below(20) {
            0 => json!({ "line": 0, "character": 100_000 }),
            1 => json!({ "line": self.text.matches('\n').count() + 3, "character": 0 }),
            _ => {
                let at = self.offset();
                position(&self.text, at)
            }
        }
    }

    /// One incremental edit (sometimes a whole-text change or a range past the end).
    async fn edit(&mut self) -> Result<(), Problem> {
        self.version += 1;
        let change = match self.dice.below(30) {
            0 => {
                // The whole text, replaced by a part of itself.
                let cut = self.offset();
                self.text.truncate(cut);
                json!({ "text": self.text })
            }
            1 => {
                // A range past the end: the server may clamp it or ignore it, but must not fail;
                // the whole text follows to agree on the document again.
                let far = json!({ "line": self.text.len() + 5, "character": 7 });
                let bad = json!({ "range": { "start": far, "end": far }, "text": "x" });
                self.send_change(bad).await?;
                self.version += 1;
                json!({ "text": self.text })
            }
            _ => {
                let start = self.offset();
                let end = self
                    .text
                    .ceil_char_boundary((start + self.dice.skewed(64)).min(self.text.len()));
                let end = if self.dice.chance(0.4) { start } else { end };
                let replacement = if self.dice.chance(0.15) && !self.text.is_empty() {
                    // Paste a piece of the document.
                    let from = self.offset();
                    let to = self
                        .text
                        .ceil_char_boundary((from + self.dice.skewed(200)).min(self.text.len()));
                    self.text[from..to].to_owned()
                } else {
                    (*self.dice.pick(self.snippets)).to_owned()
                };
                let range = json!({
                    "start": position(&self.text, start),
                    "end": position(&self.text, end),
                });
                self.text.replace_range(start..end, &replacement);
                json!({ "range": range, "text": replacement })
            }
        };
        self.send_change(change).await?;
        if self.dice.chance(0.5) {
            // A request racing the analysis of the new version.
            self.query().await?;
        }
        Ok(())
    }

    async fn send_change(&mut self, change: Value) -> Result<(), Problem> {
        self.notify(
            "textDocument/didChange",
            json!({
                "textDocument": { "uri": self.uri, "version": self.version },
                "contentChanges": [change],
            }),
        )
        .await
    }

    /// A malformed message, then a request that must still be answered.
    async fn malformed(&mut self) -> Result<(), Problem> {
        let (what, bytes) = *self.dice.pick(MALFORMED);
        self.malformed_sent = Some(what);
        self.last = format!("a malformed message ({what})");
        self.send_raw(bytes).await?;
        self.query().await
    }

    /// One request about the document, its answer checked where there is something to check.
    async fn query(&mut self) -> Result<(), Problem> {
        let document = json!({ "uri": self.uri });
        let at = self.request_position();
        let whole = json!({
            "start": { "line": 0, "character": 0 },
            "end": position(&self.text, self.text.len()),
        });
        let at_params = json!({ "textDocument": document, "position": at });
        let (method, params) = match self.dice.below(12) {
            0 | 1 => ("textDocument/hover", at_params),
            2 | 3 => ("textDocument/completion", at_params),
            4 | 5 => (
                "textDocument/semanticTokens/full",
                json!({ "textDocument": document }),
            ),
            6 => (
                "textDocument/formatting",
                json!({ "textDocument": document,
                        "options": { "tabSize": 4, "insertSpaces": true } }),
            ),
            7 => ("textDocument/signatureHelp", at_params),
            8 => (
                *self
                    .dice
                    .pick(&["textDocument/documentSymbol", "textDocument/foldingRange"]),
                json!({ "textDocument": document }),
            ),
            9 => (
                "textDocument/inlayHint",
                json!({ "textDocument": document, "range": whole }),
            ),
            10 => (
                *self
                    .dice
                    .pick(&["textDocument/definition", "textDocument/prepareRename"]),
                at_params,
            ),
            _ => match self.dice.below(2) {
                0 => (
                    "textDocument/references",
                    json!({ "textDocument": document, "position": at,
                            "context": { "includeDeclaration": true } }),
                ),
                _ => (
                    "textDocument/codeAction",
                    json!({ "textDocument": document, "range": whole,
                            "context": { "diagnostics": [] } }),
                ),
            },
        };
        let result = self.request(method, params).await?;
        match method {
            "textDocument/semanticTokens/full" => self.check_tokens(&result),
            "textDocument/formatting" => self.check_edits(&result),
            _ => Ok(()),
        }
    }

    /// Every semantic token on one line of the document, inside it.
    fn check_tokens(&self, result: &Value) -> Result<(), Problem> {
        let Some(data) = result.get("data").and_then(Value::as_array) else {
            return Ok(());
        };
        let numbers: Vec<u64> = data.iter().filter_map(Value::as_u64).collect();
        let lines = line_lengths(&self.text);
        let (mut line, mut start) = (0u64, 0u64);
        for token in numbers.chunks_exact(5) {
            let (delta_line, delta_start, length) = (token[0], token[1], token[2]);
            line += delta_line;
            start = if delta_line == 0 {
                start + delta_start
            } else {
                delta_start
            };
            let fits = lines
                .get(line as usize)
                .is_some_and(|&len| start + length <= u64::from(len));
            if !fits {
                return Err(Problem::invariant(
                    "a semantic token lies outside its line",
                    format!(
                        "token at line {line}, column {start}, length {length}; the document has \
                         {} lines",
                        lines.len()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Every formatting edit's range inside the document.
    fn check_edits(&self, result: &Value) -> Result<(), Problem> {
        let lines = line_lengths(&self.text);
        for edit in result.as_array().into_iter().flatten() {
            let range = &edit["range"];
            if !(inside(&lines, &range["start"]) && inside(&lines, &range["end"])) {
                return Err(Problem::invariant(
                    "a formatting edit lies outside the document",
                    edit.to_string(),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_utf16_units() {
        let text = "a😀b\ncé";
        assert_eq!(position(text, 5), json!({ "line": 0, "character": 3 }));
        assert_eq!(
            position(text, text.len()),
            json!({ "line": 1, "character": 2 })
        );
        let lines = line_lengths(text);
        assert!(inside(&lines, &json!({ "line": 1, "character": 2 })));
        assert!(!inside(&lines, &json!({ "line": 1, "character": 3 })));
        assert!(!inside(&lines, &json!({ "line": 2, "character": 0 })));
    }

    #[test]
    fn sessions_on_a_small_program_run_clean() {
        let runtime = Runtime::new().unwrap();
        let text = "module m(a) { cube(a); }\nm(2);\nx = 1;\n/* comment */ sphere(x);\n";
        let path = Path::new("/tmp/qcsg-fuzz-test/main.qcsg");
        for seed in 0..6 {
            // ASCII edits only: this tests the session, not the server's handling of text.
            let ascii = &[
                "", "(", ")", "{", "}", ";", "\n", "cube(1);", "x = ", "/*", "*/",
            ];
            let outcome = runtime
                .runtime
                .block_on(session(path, text, seed, false, ascii));
            assert_eq!(outcome, Ok(()), "seed {seed}");
        }
    }
}
