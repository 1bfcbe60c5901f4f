//! Fuzz target: USD bytes, written as `.usda`, `.usdc` and `.usdz` (the importer picks the
//! parser from the file; a `.usdz` is read as a ZIP package), -> import -> compile. Must never
//! panic, hang or allocate without bound.
//!
//! openusd 0.6.0 panics on some malformed crate files; the importer turns a panic into an error
//! (`USD_READER_PANIC`). libFuzzer's panic hook would abort even on such a caught panic, so this
//! target replaces it with one that records where the panic happened: a caught panic inside
//! openusd is a known dependency bug (counted, not a crash); any other panic aborts.
#![no_main]

use std::sync::Mutex;

use libfuzzer_sys::fuzz_target;
use quasar::importers::{ImportOptions, import_usd};

static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);

fn install_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        std::panic::set_hook(Box::new(|info| {
            let at = info.location().map_or_else(String::new, |l| l.file().to_string());
            *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) = Some(at);
        }))
    });
}

fuzz_target!(|data: &[u8]| {
    install_hook();
    let dir = std::env::temp_dir().join(format!("quasar-fuzz-usd-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    for ext in ["usda", "usdc", "usdz"] {
        let path = dir.join(format!("input.{ext}"));
        if std::fs::write(&path, data).is_err() {
            return;
        }
        *LAST_PANIC.lock().unwrap() = None;
        match import_usd(&path, &ImportOptions::default()) {
            Ok(desc) => {
                let _ = quasar::core::scene::Scene::compile(&desc);
            }
            Err(e) if e.message.starts_with(quasar::importers::usd::USD_READER_PANIC) => {
                let at = LAST_PANIC.lock().unwrap().take().unwrap_or_default();
                if !at.contains("openusd-0.6.0") {
                    eprintln!("the USD import panicked outside openusd, at {at}: {e}");
                    std::process::abort();
                }
            }
            Err(_) => {}
        }
        if let Some(at) = LAST_PANIC.lock().unwrap().take() {
            eprintln!("a panic at {at} was caught somewhere other than the USD reader guard");
            std::process::abort();
        }
    }
});
