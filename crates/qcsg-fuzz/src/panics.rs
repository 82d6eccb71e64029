//! Panics in a worker: recorded, never printed.
//!
//! [`install`] replaces the panic hook with one that records each panic's message, location and
//! thread instead of printing it. A stage's own panic is caught by `catch_unwind`; a panic that
//! something else caught (the language server answers a panicking request with an internal
//! error and keeps serving, tokio turns a panicking task into a join error) is still recorded
//! here, so the stage that caused it fails too.

use std::panic::PanicHookInfo;
use std::sync::Mutex;

/// One recorded panic.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Panic {
    /// The panic message.
    pub message: String,
    /// `file:line:column` where it happened (paths relative to the workspace where possible).
    pub location: String,
    /// The name of the thread it happened on.
    pub thread: String,
}

/// At most this many panics are kept between two [`take`]s (a panic in a loop must not fill
/// memory).
const KEPT: usize = 16;

static RECORDED: Mutex<Vec<Panic>> = Mutex::new(Vec::new());

/// Installs the recording hook, for the rest of the process.
pub fn install() {
    std::panic::set_hook(Box::new(record));
}

fn record(info: &PanicHookInfo<'_>) {
    let message = payload_text(info.payload());
    let location = info.location().map_or_else(
        || "<unknown>".to_owned(),
        |l| format!("{}:{}:{}", relative(l.file()), l.line(), l.column()),
    );
    let thread = std::thread::current()
        .name()
        .unwrap_or("<unnamed>")
        .to_owned();
    let mut recorded = RECORDED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if recorded.len() < KEPT {
        recorded.push(Panic {
            message,
            location,
            thread,
        });
    }
}

/// The panics recorded since the last call, oldest first.
pub fn take() -> Vec<Panic> {
    std::mem::take(
        &mut *RECORDED
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner()),
    )
}

/// The text of a panic payload (`&str` or `String`; anything else has none).
pub fn payload_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "<non-string panic payload>".to_owned())
}

/// A source path from `crates/` on (or from the registry's crate directory), so that locations
/// read the same on every machine.
pub fn relative(file: &str) -> String {
    for marker in ["/crates/", "/registry/src/"] {
        if let Some(at) = file.rfind(marker) {
            return file[at + 1..].to_owned();
        }
    }
    file.to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_made_relative_to_the_crates_folder() {
        assert_eq!(
            relative("/work/main/crates/qcsg-syntax/src/parser.rs"),
            "crates/qcsg-syntax/src/parser.rs"
        );
        assert_eq!(relative("src/main.rs"), "src/main.rs");
    }
}
