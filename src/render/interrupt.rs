//! Interruption (DESIGN.md section 6): Ctrl-C (SIGINT) or SIGTERM asks the running render to
//! stop; `pt` finishes the rows it is on, the bidirectional methods finish the current iteration,
//! and the image of everything done so far is written, marked `partial` in its header. A second
//! signal exits at once.

use std::sync::Once;
use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);
static INSTALL: Once = Once::new();

/// Installs the signal handler (once per process). Without it (library use) nothing is ever
/// requested unless [`request`] is called.
pub fn install_handler() {
    INSTALL.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if REQUESTED.swap(true, Ordering::SeqCst) {
                eprintln!("interrupted twice: exiting without writing");
                std::process::exit(130);
            }
            eprintln!("interrupted: finishing the current pass, then writing the partial image");
        });
    });
}

/// Asks the running render to stop (what the signal handler does).
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// True once a stop was requested.
#[inline]
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}
