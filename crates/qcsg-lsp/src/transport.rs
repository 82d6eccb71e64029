//! The layer between the client's byte stream and `tower-lsp-server`: framing, checking, error
//! replies, and the exit status.
//!
//! `tower-lsp-server` 0.23 stops serving, without a word, at the first message it cannot frame
//! or decode (its framed reader ends after an error), and `exit` ends it the same way whether
//! or not `shutdown` came first. So the server never reads the client directly:
//!
//! - [`framing`] splits the input into bodies by `Content-Length`, skipping what cannot be
//!   framed (reported to the client as a `window/logMessage` warning) and bodies over the limit
//!   ([`Options::max_message_bytes`], answered with `-32600`);
//! - [`message`] checks each body as a JSON-RPC 2.0 message and answers `-32700` or `-32600`
//!   itself; only valid messages reach the server, re-framed, through an in-memory pipe;
//! - the server's output comes back through another pipe and is re-framed whole, so that one
//!   writer interleaves it with this layer's replies frame by frame.
//!
//! `exit` ends the session with status 0 if the server answered a `shutdown` request with
//! success before, and 1 otherwise (LSP 3.17, `exit`). A client that sends `exit` without
//! waiting for the answer to its `shutdown` still gets 0: `exit` is held until every `shutdown`
//! handed to the server is answered, since the server cancels what is pending at `exit`. The end
//! of the input, even in the middle of a message, ends the session normally (status 0).
//!
//! Once `exit` is handed over the session ends at once: `tower-lsp-server` cancels pending
//! requests at `exit` but lets notification handlers run to their end, and a `didChange`
//! handler may be in the middle of an evaluation that takes seconds (more on a loaded
//! machine). The server is dropped instead, which ends its output; what it wrote before goes
//! out, and an analysis still running on a blocking thread finishes unseen.

pub mod framing;
pub mod message;

use serde_json::{Value, json};
use tokio::io::{AsyncRead, AsyncWrite, AsyncWriteExt, DuplexStream};
use tokio::sync::{mpsc, watch};
use tower_lsp_server::{LspService, Server};

use crate::server::Backend;
use framing::{Frame, FrameReader};
use message::{Checked, INVALID_REQUEST, Rejection};

/// The default of [`Options::max_message_bytes`]: 64 MiB, far above any real document.
pub const DEFAULT_MAX_MESSAGE_BYTES: usize = 64 * 1024 * 1024;

/// The capacity of each in-memory pipe to and from the server.
const PIPE_BYTES: usize = 256 * 1024;
/// How many frames may wait for the writer.
const FRAME_QUEUE: usize = 64;
/// `window/logMessage`'s type for a warning.
const LOG_WARNING: u8 = 2;

/// Settings of the transport.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// The largest message body accepted, in bytes; a longer one is skipped unread and answered
    /// with `-32600`.
    pub max_message_bytes: usize,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            max_message_bytes: DEFAULT_MAX_MESSAGE_BYTES,
        }
    }
}

/// How a session ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    /// The input ended (or could no longer be read).
    EndOfInput,
    /// The client sent `exit`.
    Exit {
        /// Whether the server had answered a `shutdown` request with success before.
        after_shutdown: bool,
    },
}

impl Ending {
    /// The process exit status LSP asks for: 1 for `exit` without `shutdown`, 0 otherwise.
    pub fn exit_code(self) -> u8 {
        match self {
            Self::Exit {
                after_shutdown: false,
            } => 1,
            Self::EndOfInput
            | Self::Exit {
                after_shutdown: true,
            } => 0,
        }
    }
}

/// The state of the shutdown handshake, shared by the reader and the relay of the server's
/// output.
#[derive(Debug, Default)]
struct Lifecycle {
    /// The ids of `shutdown` requests handed to the server and not yet answered.
    unanswered_shutdowns: Vec<Value>,
    /// Whether the server answered a `shutdown` with success.
    shut_down: bool,
    /// Whether the server's output has ended.
    server_gone: bool,
    /// Whether the reader handed `exit` to the server: serving stops there.
    exited: bool,
}

/// Serves LSP with the qcsg [`Backend`] over `input` and `output` until `exit` or the end of
/// `input`.
pub async fn serve<I, O>(input: I, output: O, options: Options) -> Ending
where
    I: AsyncRead + Unpin,
    O: AsyncWrite + Unpin,
{
    let (service, socket) = LspService::build(Backend::new)
        .custom_method("qcsg/frame", Backend::preview_frame)
        .custom_method("qcsg/pick", Backend::preview_pick)
        .custom_method("qcsg/partsAt", Backend::preview_parts_at)
        .finish();
    let (to_server, server_input) = tokio::io::duplex(PIPE_BYTES);
    let (server_output, from_server) = tokio::io::duplex(PIPE_BYTES);
    let (frames, queued_frames) = mpsc::channel(FRAME_QUEUE);
    let lifecycle = watch::Sender::new(Lifecycle::default());

    // Each future drops what it owns when it completes: the reader its end of the pipe into
    // the server, which ends the server; the server its output pipe, which ends the relay; the
    // reader and the relay their senders, which ends the writer.
    let server = Server::new(server_input, server_output, socket).serve(service);
    let serving = async {
        let mut state = lifecycle.subscribe();
        tokio::select! {
            () = server => {}
            _ = state.wait_for(|l| l.exited) => {}
        }
    };
    let reading = read_client(
        FrameReader::new(input, options.max_message_bytes),
        to_server,
        frames.clone(),
        &lifecycle,
        options,
    );
    let relaying = relay_server_output(
        FrameReader::new(from_server, usize::MAX),
        frames,
        &lifecycle,
    );
    let writing = write_frames(queued_frames, output);
    let (read_end, (), (), ()) = tokio::join!(reading, serving, relaying, writing);
    match read_end {
        ReadEnd::Exit => Ending::Exit {
            after_shutdown: lifecycle.borrow().shut_down,
        },
        ReadEnd::EndOfInput => Ending::EndOfInput,
    }
}

/// Why the reader stopped.
enum ReadEnd {
    /// It handed `exit` to the server.
    Exit,
    /// The input ended, or the server stopped taking it.
    EndOfInput,
}

/// Reads the client's messages, hands the valid ones to the server and answers the others,
/// until `exit` or the end of the input.
async fn read_client<I: AsyncRead + Unpin>(
    mut input: FrameReader<I>,
    mut to_server: DuplexStream,
    replies: mpsc::Sender<Vec<u8>>,
    lifecycle: &watch::Sender<Lifecycle>,
    options: Options,
) -> ReadEnd {
    while let Some(frame) = input.next().await {
        let (json, is_exit) = match frame {
            Frame::Body(body) => match message::check(&body) {
                Checked::Request { method, id, json } => {
                    if let (Some(id), "shutdown") = (id, method.as_str()) {
                        lifecycle.send_modify(|l| l.unanswered_shutdowns.push(id));
                    }
                    (json, method == "exit")
                }
                Checked::Response { json } => (json, false),
                Checked::Rejected(rejection) => {
                    send(&replies, &rejection.reply()).await;
                    continue;
                }
            },
            Frame::Oversized { length } => {
                let rejection = Rejection {
                    code: INVALID_REQUEST,
                    id: Value::Null,
                    message: format!(
                        "Invalid Request: a message of {length} bytes, over the limit of {} \
                         (`qcsg lsp --max-message-bytes`)",
                        options.max_message_bytes
                    ),
                };
                send(&replies, &rejection.reply()).await;
                continue;
            }
            Frame::Unframeable(why) => {
                let log = json!({
                    "jsonrpc": "2.0",
                    "method": "window/logMessage",
                    "params": {
                        "type": LOG_WARNING,
                        "message": format!(
                            "qcsg lsp: cannot frame a message ({why}); skipping to the next \
                             `Content-Length` header"
                        ),
                    },
                });
                send(&replies, &log).await;
                continue;
            }
        };
        if is_exit {
            // The server cancels what is pending at `exit`: let it answer `shutdown` first.
            let mut state = lifecycle.subscribe();
            let _ = state
                .wait_for(|l| l.unanswered_shutdowns.is_empty() || l.server_gone)
                .await;
        }
        if to_server.write_all(&frame_of(&json)).await.is_err() {
            return ReadEnd::EndOfInput;
        }
        if is_exit {
            lifecycle.send_modify(|l| l.exited = true);
            return ReadEnd::Exit;
        }
    }
    ReadEnd::EndOfInput
}

/// Passes the server's messages on to the writer, noting its answers to `shutdown`.
async fn relay_server_output(
    mut from_server: FrameReader<DuplexStream>,
    frames: mpsc::Sender<Vec<u8>>,
    lifecycle: &watch::Sender<Lifecycle>,
) {
    while let Some(frame) = from_server.next().await {
        // The server frames its output itself; nothing else can come.
        let Frame::Body(body) = frame else { continue };
        if !lifecycle.borrow().unanswered_shutdowns.is_empty() {
            note_shutdown_answer(&body, lifecycle);
        }
        // If the writer has gone (the client closed its input), keep reading so that the
        // server is never blocked on a full pipe.
        let _ = frames.send(frame_of(&body)).await;
    }
    lifecycle.send_modify(|l| l.server_gone = true);
}

/// Records the server's answer to an unanswered `shutdown`, if `body` is one.
fn note_shutdown_answer(body: &[u8], lifecycle: &watch::Sender<Lifecycle>) {
    let Ok(Value::Object(message)) = serde_json::from_slice::<Value>(body) else {
        return;
    };
    if message.contains_key("method") {
        return;
    }
    let Some(id) = message.get("id") else { return };
    lifecycle.send_if_modified(|l| {
        let Some(at) = l.unanswered_shutdowns.iter().position(|s| s == id) else {
            return false;
        };
        l.unanswered_shutdowns.swap_remove(at);
        l.shut_down |= message.contains_key("result");
        true
    });
}

/// Writes whole frames to the client, flushing whenever no other frame is waiting.
async fn write_frames<O: AsyncWrite + Unpin>(mut frames: mpsc::Receiver<Vec<u8>>, mut output: O) {
    while let Some(frame) = frames.recv().await {
        if output.write_all(&frame).await.is_err() {
            // The client is gone; dropping the receiver tells the senders.
            return;
        }
        if frames.is_empty() && output.flush().await.is_err() {
            return;
        }
    }
    let _ = output.flush().await;
}

/// Sends one message to the writer.
async fn send(frames: &mpsc::Sender<Vec<u8>>, message: &Value) {
    let json = serde_json::to_vec(message).unwrap_or_default();
    // The writer is gone only when the client is; then nothing can be told anyway.
    let _ = frames.send(frame_of(&json)).await;
}

/// `json` with its LSP header.
fn frame_of(json: &[u8]) -> Vec<u8> {
    let header = format!("Content-Length: {}\r\n\r\n", json.len());
    let mut frame = Vec::with_capacity(header.len() + json.len());
    frame.extend_from_slice(header.as_bytes());
    frame.extend_from_slice(json);
    frame
}
