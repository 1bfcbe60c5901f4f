//! Fuzz target: tabulated-BSDF files. The first byte picks the reader (even: TOML
//! `quasar-bsdf`, odd: Zemax tabular `.bsdf`); a table that loads must give finite, non-negative
//! f, pdf and samples (`quasar::tools::bsdf_report::check_finite`).
//! Must never panic, hang or allocate without bound.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use quasar::importers::bsdf_file::{parse_tabulated_bsdf, zemax::parse_zemax_bsdf};
use quasar::materials::TabulatedTable;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, rest)) = data.split_first() else { return };
    let Ok(text) = std::str::from_utf8(rest) else { return };
    let table = if kind % 2 == 0 {
        parse_tabulated_bsdf(text, Path::new("fuzz.toml")).ok()
    } else {
        parse_zemax_bsdf(text, Path::new("fuzz.bsdf"))
            .ok()
            .and_then(|c| TabulatedTable::new(c.spec).ok().map(std::sync::Arc::new))
    };
    let Some(table) = table else { return };
    if let Err(e) = quasar::tools::bsdf_report::check_finite(&table) {
        panic!("{e}");
    }
});
