//! A hook that runs before this process opens a USD stage, so that a program can keep the USD
//! reader's aborts out of its own process. openusd 0.6 allocates buffers of sizes read from a
//! binary `.usdc` unchecked: a hostile file asks for 2^61 bytes and the allocation failure aborts
//! the process, which no `catch_unwind` can turn into an error (docs/reliability.md). The
//! `quasar` binary installs a guard that imports the stage once in a child process of itself
//! (`src/cli/usd_isolation.rs`): an abort there becomes an error here, naming the file. Library
//! users without a guard get no such protection.

use std::path::Path;
use std::sync::OnceLock;

use crate::ImportOptions;

/// A check of the stage at a path before it is opened here: `Err` with the reason to refuse it.
pub type UsdReaderGuard = fn(&Path, &ImportOptions) -> Result<(), String>;

static GUARD: OnceLock<UsdReaderGuard> = OnceLock::new();

/// Installs the process's guard (once; a second call changes nothing and returns false).
pub fn set_usd_reader_guard(guard: UsdReaderGuard) -> bool {
    GUARD.set(guard).is_ok()
}

/// Runs the installed guard, if any, on `path`.
pub(crate) fn check(path: &Path, opts: &ImportOptions) -> Result<(), String> {
    match GUARD.get() {
        Some(g) => g(path, opts),
        None => Ok(()),
    }
}
