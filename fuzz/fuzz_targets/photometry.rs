//! Fuzz target: bytes as an IES LM-63 and as a EULUMDAT file -> parse -> evaluate the intensity
//! in a spread of directions (finite and >= 0 where the file parses). Must never panic, hang or
//! allocate without bound; errors carry the file name.
#![no_main]

use std::path::Path;

use glam::Vec3;
use libfuzzer_sys::fuzz_target;
use quasar::importers::photometry::{PhotometricWeb, eulumdat, ies};

fn probe(web: &PhotometricWeb) {
    for i in 0..64 {
        let t = i as f32 * 0.37;
        let d = Vec3::new(t.sin() * (2.0 * t).cos(), (3.0 * t).sin(), t.cos()).normalize_or(Vec3::NEG_Z);
        let v = web.intensity(d);
        assert!(v.is_finite() && v >= 0.0, "intensity {v} towards {d}");
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    match ies::parse_ies(text, Path::new("fuzz.ies")) {
        Ok(f) => probe(&f.web),
        Err(e) => assert!(e.to_string().starts_with("fuzz.ies"), "{e}"),
    }
    match eulumdat::parse_ldt(text, Path::new("fuzz.ldt")) {
        Ok(f) => probe(&f.web),
        Err(e) => assert!(e.to_string().starts_with("fuzz.ldt"), "{e}"),
    }
});
