//! SIGINT and SIGTERM: the run stops at the library's next checkpoint, its
//! temporary files are removed as they are dropped, nothing is renamed into place,
//! and the tool exits with 128 + the signal's number (130, 143). A second signal
//! ends the process at once.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::sync::OnceLock;

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::flag;

/// The number of the signal received, 0 before any.
static RECEIVED: OnceLock<Arc<AtomicUsize>> = OnceLock::new();

/// Catch SIGINT and SIGTERM.
pub fn install() -> std::io::Result<()> {
    let received = RECEIVED.get_or_init(|| Arc::new(AtomicUsize::new(0)));
    let once = Arc::new(std::sync::atomic::AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM] {
        // The second signal, whichever, ends the process with its status.
        flag::register_conditional_shutdown(signal, 128 + signal, Arc::clone(&once))?;
        flag::register(signal, Arc::clone(&once))?;
        flag::register_usize(signal, Arc::clone(received), signal as usize)?;
    }
    Ok(())
}

/// The signal received, if one was.
pub fn received() -> Option<i32> {
    let number = RECEIVED.get()?.load(Ordering::Relaxed);
    (number != 0).then_some(number as i32)
}
