//! The `quasar` binary: the command line of [`cli`].

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    // A closed pipe (`quasar info scene.toml | head -1`) ends the process quietly, as it does
    // other command-line tools, instead of making the next print panic: Rust ignores SIGPIPE
    // by default, so restore the default action.
    #[cfg(unix)]
    // SAFETY: called before any other thread exists; SIG_DFL is a valid action for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if args.get(1).is_some_and(|a| a == cli::usd_isolation::CHILD_ARG) {
        return cli::usd_isolation::child(&args[2..]);
    }
    // every USD stage is read once in a child process first (cli/usd_isolation.rs)
    quasar_importers::set_usd_reader_guard(cli::usd_isolation::guard);
    match cli::run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
