//! `exit` ends the session at once, even while the analysis of an edit is still evaluating.
//!
//! `tower-lsp-server` lets notification handlers run to their end after `exit`; a `didOpen` or
//! `didChange` handler evaluates the document, which may take seconds (far more on a loaded
//! machine), and the session used to wait for it: a client saw a server that did not stop after
//! `exit`. This document's evaluation takes seconds in a release build and tens of seconds in a
//! debug one; the session must end within [`PROMPT`] of `exit`.
//!
//! The server runs in its own runtime, given back with `shutdown_background`: the evaluation
//! left running on a blocking thread must not hold the test (the test binary exits under it).

use std::time::{Duration, Instant};

use qcsg_lsp::transport::{self, Ending, Options};
use serde_json::{Value, json};
use tokio::io::{AsyncBufReadExt, AsyncReadExt, AsyncWriteExt, BufReader, DuplexStream};

/// How long the session may take to end after `exit`: nothing is left to compute then.
const PROMPT: Duration = Duration::from_secs(1);
/// Long enough for a debug build on a loaded machine.
const PATIENCE: Duration = Duration::from_secs(60);

/// 9·10⁸ multiply-adds in list products: seconds of evaluation, within the editor's limits.
const SLOW: &str = "v = [for (i = [0 : 29999]) i];\n\
                    w = [for (i = [0 : 29999]) v * v];\n\
                    echo(len(w));\n\
                    cube(1);\n";

fn frame(message: &Value) -> Vec<u8> {
    let body = message.to_string();
    format!("Content-Length: {}\r\n\r\n{body}", body.len()).into_bytes()
}

async fn read_message(from: &mut BufReader<DuplexStream>) -> Value {
    let mut length = None;
    loop {
        let mut line = String::new();
        let read = from.read_line(&mut line).await.unwrap();
        assert!(read > 0, "the server's output ended");
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(value) = line.strip_prefix("Content-Length: ") {
            length = Some(value.parse::<usize>().unwrap());
        }
    }
    let mut body = vec![0; length.expect("a Content-Length header")];
    from.read_exact(&mut body).await.unwrap();
    serde_json::from_slice(&body).expect("the server sends JSON")
}

/// Reads until a message for which `done` holds; returns every message read.
async fn read_until(
    from: &mut BufReader<DuplexStream>,
    done: impl Fn(&Value) -> bool,
) -> Vec<Value> {
    let mut seen = Vec::new();
    let wait = async {
        loop {
            let message = read_message(from).await;
            let stop = done(&message);
            seen.push(message);
            if stop {
                return;
            }
        }
    };
    tokio::time::timeout(PATIENCE, wait)
        .await
        .expect("the server answers");
    seen
}

/// Whether `message` publishes the evaluation's `echo` (which comes after the check's
/// diagnostics, once the evaluation is done).
fn echoed(message: &Value) -> bool {
    message["method"] == "textDocument/publishDiagnostics"
        && message["params"]["diagnostics"]
            .as_array()
            .is_some_and(|d| d.iter().any(|d| d.to_string().contains("ECHO")))
}

#[test]
fn exit_ends_the_session_while_an_evaluation_runs() {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_stack_size(32 * 1024 * 1024)
        .enable_all()
        .build()
        .unwrap();
    let (ending, after_exit) = runtime.block_on(async {
        let (mut to_server, server_input) = tokio::io::duplex(1 << 16);
        let (server_output, from_server) = tokio::io::duplex(1 << 16);
        let session = tokio::spawn(transport::serve(
            server_input,
            server_output,
            Options::default(),
        ));
        let mut from = BufReader::new(from_server);
        let mut send = async |message: Value| to_server.write_all(&frame(&message)).await.unwrap();
        send(json!({
            "jsonrpc": "2.0", "id": 1, "method": "initialize",
            "params": { "capabilities": {} },
        }))
        .await;
        read_until(&mut from, |m| m["id"] == 1).await;
        send(json!({ "jsonrpc": "2.0", "method": "initialized", "params": {} })).await;
        send(json!({
            "jsonrpc": "2.0", "method": "textDocument/didOpen",
            "params": { "textDocument": {
                "uri": "file:///tmp/slow.qcsg", "languageId": "qcsg", "version": 1, "text": SLOW,
            }},
        }))
        .await;
        // The check's diagnostics come first; the evaluation runs after them.
        let before = read_until(&mut from, |m| {
            m["method"] == "textDocument/publishDiagnostics"
        })
        .await;
        send(json!({ "jsonrpc": "2.0", "id": 2, "method": "shutdown" })).await;
        let answered = read_until(&mut from, |m| m["id"] == 2).await;
        assert!(
            !before.iter().chain(&answered).any(echoed),
            "the evaluation ended before `exit`: the document is too quick for this test"
        );
        let exit = Instant::now();
        send(json!({ "jsonrpc": "2.0", "method": "exit" })).await;
        let ending = tokio::time::timeout(PATIENCE, session)
            .await
            .expect("the session ends after `exit`")
            .expect("the session does not panic");
        (ending, exit.elapsed())
    });
    runtime.shutdown_background();
    assert_eq!(
        ending,
        Ending::Exit {
            after_shutdown: true
        }
    );
    assert!(
        after_exit < PROMPT,
        "the session took {after_exit:?} to end after `exit`"
    );
}
