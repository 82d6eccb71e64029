//! The language server answers malformed JSON-RPC and keeps serving: each malformed input is
//! followed by a valid `initialize`, which must still be answered. Also the exit status of
//! `exit` with and without `shutdown`.
//!
//! The real server (transport and backend) runs in process, over in-memory pipes.

use std::time::Duration;

use qcsg_lsp::transport::{self, Ending, Options};
use serde_json::{Value, json};
use tokio::io::{AsyncBufReadExt, AsyncReadExt, AsyncWriteExt, BufReader, DuplexStream};
use tokio::task::JoinHandle;

/// Long enough for a debug build on a loaded machine; a server that stopped never answers.
const PATIENCE: Duration = Duration::from_secs(20);

/// A client talking to a server running in its own task.
struct Client {
    to_server: Option<DuplexStream>,
    from_server: BufReader<DuplexStream>,
    session: JoinHandle<Ending>,
    /// Every message received so far.
    received: Vec<Value>,
}

impl Client {
    fn start(options: Options) -> Self {
        let (to_server, server_input) = tokio::io::duplex(1 << 16);
        let (server_output, from_server) = tokio::io::duplex(1 << 16);
        let session = tokio::spawn(transport::serve(server_input, server_output, options));
        Self {
            to_server: Some(to_server),
            from_server: BufReader::new(from_server),
            session,
            received: Vec::new(),
        }
    }

    async fn send_bytes(&mut self, bytes: &[u8]) {
        let pipe = self.to_server.as_mut().expect("input still open");
        pipe.write_all(bytes).await.expect("server reads its input");
    }

    async fn send(&mut self, message: &Value) {
        self.send_bytes(&frame(message.to_string().as_bytes()))
            .await;
    }

    /// Reads messages until the response to `id`, and returns it.
    async fn response(&mut self, id: &Value) -> Value {
        let wait = async {
            loop {
                let message = self.read_message().await;
                self.received.push(message.clone());
                if message.get("method").is_none() && message.get("id") == Some(id) {
                    return message;
                }
            }
        };
        tokio::time::timeout(PATIENCE, wait)
            .await
            .unwrap_or_else(|_| panic!("no response to {id}; received {:?}", self.received))
    }

    async fn read_message(&mut self) -> Value {
        let mut length = None;
        loop {
            let mut line = String::new();
            let read = self.from_server.read_line(&mut line).await.unwrap();
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
        self.from_server.read_exact(&mut body).await.unwrap();
        serde_json::from_slice(&body).expect("the server sends JSON")
    }

    async fn initialize(&mut self, id: i64) -> Value {
        self.send(&json!({
            "jsonrpc": "2.0", "id": id, "method": "initialize",
            "params": { "capabilities": {} },
        }))
        .await;
        self.response(&json!(id)).await
    }

    /// Closes the input and waits for the session to end.
    async fn end(mut self) -> Ending {
        drop(self.to_server.take());
        tokio::time::timeout(PATIENCE, self.session)
            .await
            .expect("the session ends")
            .expect("the session does not panic")
    }

    /// Sends `exit` and waits for the session to end, keeping the input open as an editor may.
    async fn exit(mut self) -> Ending {
        self.send(&json!({ "jsonrpc": "2.0", "method": "exit" }))
            .await;
        let ending = tokio::time::timeout(PATIENCE, &mut self.session)
            .await
            .expect("the session ends at `exit` with its input still open")
            .expect("the session does not panic");
        drop(self.to_server.take());
        ending
    }

    /// Whether a `window/logMessage` containing `text` was received.
    fn logged(&self, text: &str) -> bool {
        self.received.iter().any(|m| {
            m["method"] == "window/logMessage"
                && m["params"]["message"]
                    .as_str()
                    .is_some_and(|s| s.contains(text))
        })
    }
}

fn frame(body: &[u8]) -> Vec<u8> {
    let mut bytes = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
    bytes.extend_from_slice(body);
    bytes
}

fn shutdown(id: i64) -> Value {
    json!({ "jsonrpc": "2.0", "id": id, "method": "shutdown" })
}

/// Sends `malformed`, then runs a whole session: `initialize`, `shutdown`, `exit`. Returns the
/// client after `initialize` was answered, with what it received before.
async fn survives(malformed: &[u8], options: Options) -> Vec<Value> {
    let mut client = Client::start(options);
    client.send_bytes(malformed).await;
    let initialized = client.initialize(1).await;
    assert!(
        initialized["result"]["capabilities"].is_object(),
        "{initialized}"
    );
    let received = client.received.clone();
    client.send(&shutdown(2)).await;
    assert_eq!(client.response(&json!(2)).await["result"], Value::Null);
    assert_eq!(
        client.exit().await,
        Ending::Exit {
            after_shutdown: true
        }
    );
    received
}

/// The error codes and ids of the error responses in `received`.
fn errors(received: &[Value]) -> Vec<(i64, Value)> {
    received
        .iter()
        .filter_map(|m| Some((m["error"]["code"].as_i64()?, m["id"].clone())))
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn malformed_bodies_are_answered_and_serving_goes_on() {
    let cases: Vec<(&str, Vec<u8>, i64, Value)> = vec![
        (
            "invalid JSON",
            b"{\"jsonrpc\":".to_vec(),
            -32700,
            Value::Null,
        ),
        (
            "invalid UTF-8",
            b"{\"jsonrpc\":\"2.0\",\"method\":\"x\xff\xfe\"}".to_vec(),
            -32700,
            Value::Null,
        ),
        (
            "too deeply nested",
            format!("{}{}", "[".repeat(5000), "]".repeat(5000)).into_bytes(),
            -32700,
            Value::Null,
        ),
        ("empty body", Vec::new(), -32700, Value::Null),
        ("a bare number", b"42".to_vec(), -32600, Value::Null),
        (
            "a bare string",
            b"\"initialize\"".to_vec(),
            -32600,
            Value::Null,
        ),
        ("an empty batch", b"[]".to_vec(), -32600, Value::Null),
        (
            "a batch",
            br#"[{"jsonrpc":"2.0","id":5,"method":"shutdown"}]"#.to_vec(),
            -32600,
            Value::Null,
        ),
        (
            "no jsonrpc",
            br#"{"id":7,"method":"initialize","params":{"capabilities":{}}}"#.to_vec(),
            -32600,
            json!(7),
        ),
        (
            "jsonrpc 1.0",
            br#"{"jsonrpc":"1.0","id":"seven","method":"shutdown"}"#.to_vec(),
            -32600,
            json!("seven"),
        ),
        (
            "a float id",
            br#"{"jsonrpc":"2.0","id":1.5,"method":"shutdown"}"#.to_vec(),
            -32600,
            Value::Null,
        ),
        (
            "an object id",
            br#"{"jsonrpc":"2.0","id":{"a":1},"method":"shutdown"}"#.to_vec(),
            -32600,
            Value::Null,
        ),
        (
            "an array id",
            br#"{"jsonrpc":"2.0","id":[3],"method":"shutdown"}"#.to_vec(),
            -32600,
            Value::Null,
        ),
        (
            "a boolean id",
            br#"{"jsonrpc":"2.0","id":true,"method":"shutdown"}"#.to_vec(),
            -32600,
            Value::Null,
        ),
        (
            "a numeric method",
            br#"{"jsonrpc":"2.0","id":8,"method":5}"#.to_vec(),
            -32600,
            json!(8),
        ),
        (
            "a malformed response",
            br#"{"jsonrpc":"2.0","id":9,"error":{"code":"bad"}}"#.to_vec(),
            -32600,
            Value::Null,
        ),
    ];
    for (what, body, code, id) in cases {
        let received = survives(&frame(&body), Options::default()).await;
        assert_eq!(errors(&received), [(code, id)], "{what}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unframeable_input_is_logged_and_skipped() {
    let valid_body = br#"{"jsonrpc":"2.0","method":"$/setTrace","params":{"value":"off"}}"#;
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "no Content-Length",
            b"Content-Type: application/vscode-jsonrpc\r\n\r\n{\"jsonrpc\":\"2.0\"}".to_vec(),
            "without `Content-Length`",
        ),
        (
            "a non-numeric Content-Length",
            b"Content-Length: twelve\r\n\r\n{\"jsonrpc\":\"2.0\"}".to_vec(),
            "`Content-Length: twelve`",
        ),
        (
            "raw garbage",
            b"\x00\xff\xfe garbage {\"jsonrpc\"\r\n\r\n\x01".to_vec(),
            "not a header",
        ),
        (
            "a stray byte before the next header",
            [frame(valid_body).as_slice(), b"}"].concat(),
            "not a header",
        ),
    ];
    for (what, bytes, logged) in cases {
        let mut client = Client::start(Options::default());
        client.send_bytes(&bytes).await;
        let initialized = client.initialize(1).await;
        assert!(initialized["result"].is_object(), "{what}: {initialized}");
        assert!(
            client.logged(logged),
            "{what}: no log saying {logged:?} in {:?}",
            client.received
        );
        client.send(&shutdown(2)).await;
        client.response(&json!(2)).await;
        assert_eq!(client.exit().await.exit_code(), 0, "{what}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_oversized_message_is_refused_unread() {
    let options = Options {
        max_message_bytes: 4096,
    };
    let text = "x".repeat(100_000);
    let big = json!({ "jsonrpc": "2.0", "id": 3, "method": "initialize", "params": { "t": text } });
    let received = survives(&frame(big.to_string().as_bytes()), options).await;
    assert_eq!(errors(&received), [(-32600, Value::Null)]);
    let message = received[0]["error"]["message"].as_str().unwrap();
    assert!(message.contains("4096"), "{message}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_short_body_at_the_end_of_input_ends_normally() {
    let mut client = Client::start(Options::default());
    client.initialize(1).await;
    client
        .send_bytes(b"Content-Length: 100\r\n\r\n{\"jsonrpc\":")
        .await;
    assert_eq!(client.end().await, Ending::EndOfInput);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn exit_without_shutdown_exits_with_status_1() {
    let mut client = Client::start(Options::default());
    client.initialize(1).await;
    let ending = client.exit().await;
    assert_eq!(
        ending,
        Ending::Exit {
            after_shutdown: false
        }
    );
    assert_eq!(ending.exit_code(), 1);

    // Before `initialize`, too.
    assert_eq!(
        Client::start(Options::default()).exit().await.exit_code(),
        1
    );

    // A `shutdown` the server refused (before `initialize`) does not count.
    let mut client = Client::start(Options::default());
    client.send(&shutdown(1)).await;
    assert!(client.response(&json!(1)).await["error"].is_object());
    assert_eq!(client.exit().await.exit_code(), 1);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn exit_after_shutdown_exits_with_status_0() {
    let mut client = Client::start(Options::default());
    client.initialize(1).await;
    client.send(&shutdown(2)).await;
    client.response(&json!(2)).await;
    assert_eq!(client.exit().await.exit_code(), 0);

    // `exit` right behind `shutdown`, without waiting for its answer: the server would cancel
    // the `shutdown` at `exit` if `exit` reached it first.
    for _ in 0..20 {
        let mut client = Client::start(Options::default());
        client.initialize(1).await;
        let pipelined = [
            frame(shutdown(2).to_string().as_bytes()),
            frame(br#"{"jsonrpc":"2.0","method":"exit"}"#),
        ]
        .concat();
        client.send_bytes(&pipelined).await;
        let ending = tokio::time::timeout(PATIENCE, &mut client.session)
            .await
            .expect("the session ends")
            .expect("the session does not panic");
        assert_eq!(
            ending,
            Ending::Exit {
                after_shutdown: true
            }
        );
    }
}
