//! Fuzz target: USD bytes, written as `.usda`, `.usdc` and `.usdz` (the importer picks the
//! parser from the file; a `.usdz` is read as a ZIP package), -> import -> compile. Must never
//! panic, hang or allocate without bound.
#![no_main]

use libfuzzer_sys::fuzz_target;
use quasar::importers::{ImportOptions, import_usd};

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("quasar-fuzz-usd-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    for ext in ["usda", "usdc", "usdz"] {
        let path = dir.join(format!("input.{ext}"));
        if std::fs::write(&path, data).is_err() {
            return;
        }
        if let Ok(desc) = import_usd(&path, &ImportOptions::default()) {
            let _ = quasar::core::scene::Scene::compile(&desc);
        }
    }
});
