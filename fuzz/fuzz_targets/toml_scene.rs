//! Fuzz target: TOML scene text -> import -> (if it imports) compile and a 2x2 render with pt and
//! adaptive+quasi. Must never panic, hang or allocate without bound.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use quasar::importers::{ImportOptions, parse_toml_scene};
use quasar::render::job::{JobOverrides, render_desc};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(desc) = parse_toml_scene(text, Path::new("/nonexistent/fuzz/scene.toml"), &ImportOptions::default()) else {
        return;
    };
    if desc.meshes.iter().map(|m| m.indices.len()).sum::<usize>() > 200_000 {
        return; // valid but too slow to render per input
    }
    for method in ["pt", "adaptive+quasi"] {
        let mut ov = JobOverrides {
            width: Some(2),
            height: Some(2),
            spp: Some(1),
            threads: Some(1),
            method: Some(method.into()),
            ..Default::default()
        };
        if method != "pt" {
            ov = ov.with_param("iterations", 1u32).with_param("photons_per_iteration", 64u64);
        }
        if let Ok(out) = render_desc(&desc, &ov, false) {
            for c in out.image.channels.iter().filter(|c| c.name != "depth.Z") {
                assert!(c.values.iter().all(|v| v.is_finite()), "non-finite {}", c.name);
            }
        }
    }
});
