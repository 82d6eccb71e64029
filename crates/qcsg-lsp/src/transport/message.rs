//! Checking that a message body is a JSON-RPC 2.0 message the server can take, and the error
//! reply when it is not.
//!
//! JSON-RPC 2.0 (§5.1) answers a body that is not JSON with `-32700 Parse error` and JSON that
//! is not a request object with `-32600 Invalid Request`, with the request's `id` when one can
//! be read and `null` otherwise. Batches (arrays) are not supported, as LSP never sends them: an
//! array, empty or not, gets one `-32600` with `id` null. A response (to a request of the
//! server) that is malformed gets one too, with `id` null, since its `id` names a request of the
//! server, not of the client.
//!
//! What passes is handed on re-serialised, so that the server's own decoder, which stops the
//! server at the first message it cannot decode, only ever sees what it accepts: a body with a
//! key twice, which `serde_json` reads as its last value, reaches it once. As a last guard, a
//! message is accepted only if `tower-lsp-server`'s own [`Request`] or [`Response`] type
//! decodes it.

use serde::Deserialize;
use serde_json::{Map, Value, json};
use tower_lsp_server::jsonrpc::{Request, Response};

/// JSON-RPC 2.0's code for a body that is not JSON.
pub const PARSE_ERROR: i64 = -32700;
/// JSON-RPC 2.0's code for JSON that is not a valid request object.
pub const INVALID_REQUEST: i64 = -32600;

/// The verdict on one message body.
#[derive(Debug)]
pub enum Checked {
    /// A request (with an `id`) or a notification (without), ready to hand to the server.
    Request {
        /// Its method.
        method: String,
        /// Its `id`; `None` for a notification.
        id: Option<Value>,
        /// The message, re-serialised.
        json: Vec<u8>,
    },
    /// A response to a request of the server, ready to hand to it.
    Response {
        /// The message, re-serialised.
        json: Vec<u8>,
    },
    /// Not a message the server can take: the error reply for it.
    Rejected(Rejection),
}

/// An error reply to a message.
#[derive(Debug, Clone, PartialEq)]
pub struct Rejection {
    /// [`PARSE_ERROR`] or [`INVALID_REQUEST`].
    pub code: i64,
    /// The `id` of the message when one could be read, `null` otherwise.
    pub id: Value,
    /// What was wrong.
    pub message: String,
}

impl Rejection {
    fn invalid(id: Value, why: &str) -> Self {
        Self {
            code: INVALID_REQUEST,
            id,
            message: format!("Invalid Request: {why}"),
        }
    }

    /// The JSON-RPC error response.
    pub fn reply(&self) -> Value {
        json!({
            "jsonrpc": "2.0",
            "id": self.id,
            "error": { "code": self.code, "message": self.message },
        })
    }
}

/// Checks one message body.
pub fn check(body: &[u8]) -> Checked {
    let value: Value = match serde_json::from_slice(body) {
        Ok(value) => value,
        Err(error) => {
            return Checked::Rejected(Rejection {
                code: PARSE_ERROR,
                id: Value::Null,
                message: format!("Parse error: {error}"),
            });
        }
    };
    match check_value(&value) {
        Ok(kind) => {
            let json = serde_json::to_vec(&value).unwrap_or_default();
            match kind {
                Kind::Request { method, id } => Checked::Request { method, id, json },
                Kind::Response => Checked::Response { json },
            }
        }
        Err(rejection) => Checked::Rejected(rejection),
    }
}

/// What a valid message is.
enum Kind {
    Request { method: String, id: Option<Value> },
    Response,
}

/// Checks a parsed body against JSON-RPC 2.0's request and response objects.
fn check_value(value: &Value) -> Result<Kind, Rejection> {
    let object = match value {
        Value::Object(object) => object,
        Value::Array(elements) if elements.is_empty() => {
            return Err(Rejection::invalid(Value::Null, "an empty batch"));
        }
        Value::Array(_) => {
            return Err(Rejection::invalid(Value::Null, "batches are not supported"));
        }
        _ => return Err(Rejection::invalid(Value::Null, "not an object")),
    };
    let is_response = !object.contains_key("method")
        && (object.contains_key("result") || object.contains_key("error"));
    if is_response {
        check_response(object, value)?;
        return Ok(Kind::Response);
    }
    // The id to answer with, when the request has one that is valid.
    let id = object.get("id").filter(|id| is_valid_id(id));
    let reply_id = id.cloned().unwrap_or(Value::Null);
    check_version(object).map_err(|why| Rejection::invalid(reply_id.clone(), why))?;
    let method = match object.get("method") {
        Some(Value::String(method)) => method.clone(),
        Some(_) => return Err(Rejection::invalid(reply_id, "`method` is not a string")),
        None => {
            return Err(Rejection::invalid(
                reply_id,
                "neither a `method` nor a `result` or `error`",
            ));
        }
    };
    if object.contains_key("result") || object.contains_key("error") {
        return Err(Rejection::invalid(
            reply_id,
            "both a `method` and a `result` or `error`",
        ));
    }
    if object.contains_key("id") && id.is_none() {
        return Err(Rejection::invalid(
            Value::Null,
            "`id` is not an integer, a string or null",
        ));
    }
    if !matches!(
        object.get("params"),
        None | Some(Value::Null | Value::Object(_) | Value::Array(_))
    ) {
        return Err(Rejection::invalid(
            reply_id,
            "`params` is not an object or an array",
        ));
    }
    if Request::deserialize(value).is_err() {
        return Err(Rejection::invalid(reply_id, "not a request"));
    }
    Ok(Kind::Request {
        method,
        id: id.cloned(),
    })
}

/// Checks a response object; a rejection always has `id` null.
fn check_response(object: &Map<String, Value>, value: &Value) -> Result<(), Rejection> {
    let invalid = |why| Err(Rejection::invalid(Value::Null, why));
    if let Err(why) = check_version(object) {
        return invalid(why);
    }
    if !object.get("id").is_some_and(is_valid_id) {
        return invalid("a response's `id` is not an integer, a string or null");
    }
    match (object.get("result"), object.get("error")) {
        (Some(_), Some(_)) => return invalid("a response with both `result` and `error`"),
        (None, Some(error)) if !is_error_object(error) => {
            return invalid("a response's `error` is not an object with `code` and `message`");
        }
        _ => {}
    }
    if Response::deserialize(value).is_err() {
        return invalid("not a response");
    }
    Ok(())
}

/// Whether `jsonrpc` is `"2.0"`.
fn check_version(object: &Map<String, Value>) -> Result<(), &'static str> {
    match object.get("jsonrpc") {
        Some(Value::String(version)) if version == "2.0" => Ok(()),
        Some(_) => Err("`jsonrpc` is not \"2.0\""),
        None => Err("no `jsonrpc` member"),
    }
}

/// An `id` the server can answer to: null, a string, or an integer within 64 bits (JSON-RPC
/// discourages fractions; LSP allows integers and strings only).
fn is_valid_id(id: &Value) -> bool {
    match id {
        Value::Null | Value::String(_) => true,
        Value::Number(number) => number.is_i64(),
        _ => false,
    }
}

/// An error object: an integer `code` and a string `message`.
fn is_error_object(error: &Value) -> bool {
    error.get("code").is_some_and(Value::is_i64)
        && error.get("message").is_some_and(Value::is_string)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rejected(body: &str) -> Rejection {
        match check(body.as_bytes()) {
            Checked::Rejected(rejection) => rejection,
            other => panic!("{body} was accepted: {other:?}"),
        }
    }

    #[test]
    fn bodies_that_are_not_json_are_parse_errors() {
        for body in [
            "",
            "{",
            "{\"jsonrpc\": \"2.0\", \"method\": \"x\",}",
            "Content-Length: 5",
            "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"params\":{\"s\":\"\\ud800\"}}",
        ] {
            let rejection = rejected(body);
            assert_eq!((rejection.code, rejection.id), (PARSE_ERROR, Value::Null));
        }
        let invalid_utf8 = b"{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"params\":{\"s\":\"\xff\"}}";
        assert!(matches!(check(invalid_utf8), Checked::Rejected(r) if r.code == PARSE_ERROR));
        let deep = format!("{}{}", "[".repeat(10_000), "]".repeat(10_000));
        assert_eq!(rejected(&deep).code, PARSE_ERROR);
    }

    #[test]
    fn json_that_is_not_a_request_is_an_invalid_request() {
        for (body, id) in [
            ("5", Value::Null),
            ("\"initialize\"", Value::Null),
            ("null", Value::Null),
            ("[]", Value::Null),
            (
                "[{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":1}]",
                Value::Null,
            ),
            ("{}", Value::Null),
            ("{\"method\":\"initialize\",\"id\":3}", json!(3)),
            (
                "{\"jsonrpc\":\"1.0\",\"method\":\"x\",\"id\":\"a\"}",
                json!("a"),
            ),
            ("{\"jsonrpc\":2.0,\"method\":\"x\",\"id\":4}", json!(4)),
            ("{\"jsonrpc\":\"2.0\",\"method\":7,\"id\":5}", json!(5)),
            ("{\"jsonrpc\":\"2.0\",\"method\":null}", Value::Null),
            ("{\"jsonrpc\":\"2.0\",\"id\":6}", json!(6)),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":1.5}",
                Value::Null,
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":1e3}",
                Value::Null,
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":{}}",
                Value::Null,
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":[1]}",
                Value::Null,
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":true}",
                Value::Null,
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":18446744073709551615}",
                Value::Null,
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":7,\"params\":3}",
                json!(7),
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":8,\"result\":3}",
                json!(8),
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"id\":9,\"result\":1,\"error\":{}}",
                Value::Null,
            ),
            ("{\"jsonrpc\":\"2.0\",\"id\":1.5,\"result\":1}", Value::Null),
            ("{\"jsonrpc\":\"2.0\",\"result\":1}", Value::Null),
            (
                "{\"jsonrpc\":\"2.0\",\"id\":2,\"error\":{\"code\":\"x\"}}",
                Value::Null,
            ),
            ("{\"id\":2,\"result\":null}", Value::Null),
        ] {
            let rejection = rejected(body);
            assert_eq!(
                (rejection.code, &rejection.id),
                (INVALID_REQUEST, &id),
                "{body}"
            );
        }
    }

    #[test]
    fn valid_messages_pass_in_a_form_the_server_decodes() {
        for (body, method, id) in [
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"initialize\",\"params\":{},\"id\":0}",
                "initialize",
                Some(json!(0)),
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"shutdown\",\"id\":\"s\"}",
                "shutdown",
                Some(json!("s")),
            ),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"shutdown\",\"params\":null,\"id\":-2}",
                "shutdown",
                Some(json!(-2)),
            ),
            ("{\"jsonrpc\":\"2.0\",\"method\":\"exit\"}", "exit", None),
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"id\":null}",
                "x",
                Some(Value::Null),
            ),
            // A key twice: the last value counts, and the server sees the key once.
            (
                "{\"jsonrpc\":\"2.0\",\"method\":\"a\",\"method\":\"b\",\"id\":1,\"id\":2}",
                "b",
                Some(json!(2)),
            ),
        ] {
            let Checked::Request {
                method: found,
                id: found_id,
                json,
            } = check(body.as_bytes())
            else {
                panic!("{body} was not accepted as a request");
            };
            assert_eq!((found.as_str(), found_id), (method, id), "{body}");
            let decoded: Request = serde_json::from_slice(&json).expect("the server decodes it");
            assert_eq!(decoded.method(), method);
        }
        for body in [
            "{\"jsonrpc\":\"2.0\",\"id\":1,\"result\":null}",
            "{\"jsonrpc\":\"2.0\",\"id\":\"x\",\"result\":[1]}",
            "{\"jsonrpc\":\"2.0\",\"id\":null,\"error\":{\"code\":-1,\"message\":\"m\",\"data\":[]}}",
        ] {
            let Checked::Response { json } = check(body.as_bytes()) else {
                panic!("{body} was not accepted as a response");
            };
            let _: Response = serde_json::from_slice(&json).expect("the server decodes it");
        }
    }
}
