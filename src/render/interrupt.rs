//! Interruption: a stop request (the command line's Ctrl-C / SIGTERM handler calls [`request`])
//! makes the running render stop; `pt` finishes the rows it is on, the bidirectional methods
//! finish the current iteration, and the image of everything done so far is written, marked
//! `partial` in its header (docs/architecture.md §8).

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks the running render to stop (what the signal handler does).
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// True once a stop was requested.
#[inline]
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}
