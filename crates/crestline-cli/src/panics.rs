//! Panics never print their text: the tool's errors are one `error:` line.
//!
//! A panic the library catches (a DICOM decoder's on corrupt pixel data, on the
//! main thread or a worker) becomes the library's error about the file; one that
//! reaches `main` (a bug) is reported as one `error:` line with where it arose,
//! and the tool exits with 1 like any failed run. The hook is the process's, so it
//! covers every thread (the rayon workers included).

use std::panic::{catch_unwind, AssertUnwindSafe, PanicHookInfo};
use std::sync::Mutex;

/// The message and place of the last panic, for the error line of one that
/// reaches `main`.
static LAST: Mutex<Option<String>> = Mutex::new(None);

/// Replace the default hook (which prints "thread '…' panicked at …") with one
/// that only keeps the message.
pub fn silence() {
    std::panic::set_hook(Box::new(|info| {
        if let Ok(mut last) = LAST.lock() {
            *last = Some(describe(info));
        }
    }));
}

/// Run `command`; a panic that escapes it becomes an error naming where it arose.
pub fn catch(command: impl FnOnce() -> crestline::Result<()>) -> crestline::Result<()> {
    catch_unwind(AssertUnwindSafe(command)).unwrap_or_else(|_| {
        let last = LAST.lock().ok().and_then(|mut last| last.take());
        Err(crestline::Error::Stage {
            stage: "crestline".to_string(),
            message: format!(
                "an internal error ({}); please report it with the input that caused it",
                last.unwrap_or_else(|| "no message".to_string())
            ),
        })
    })
}

/// A panic's message and its place in the source, on one line.
fn describe(info: &PanicHookInfo<'_>) -> String {
    let payload = info.payload();
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".to_string());
    match info.location() {
        Some(at) => format!("{message} at {}:{}", at.file(), at.line()),
        None => message,
    }
}
