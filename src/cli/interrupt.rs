//! The command line's signal handler: the first Ctrl-C (SIGINT) or SIGTERM asks the render to
//! stop ([`quasar::render::interrupt::request`]) and the partial image is written; a second one
//! exits at once without writing.

use std::sync::Once;

static INSTALL: Once = Once::new();

/// Installs the handler (once per process).
pub fn install_handler() {
    INSTALL.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if quasar::render::interrupt::requested() {
                eprintln!("interrupted twice: exiting without writing");
                std::process::exit(130);
            }
            quasar::render::interrupt::request();
            eprintln!("interrupted: finishing the current pass, then writing the partial image");
        });
    });
}
