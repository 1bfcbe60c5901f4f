//! Every input kept in `fuzz/regressions/` (crashers found by the fuzz targets of `fuzz/`, once
//! fixed, and hand-written hostile inputs) goes through the same path as its fuzz target: import,
//! compile, a tiny render. Each must end in a clean error or a finite image, never a panic.

mod common;

use std::path::{Path, PathBuf};

use quasar::importers::{ImportOptions, ObjMaterials, import_gltf, import_obj, parse_toml_scene};
use quasar::render::job::{JobOverrides, render_desc};

fn inputs(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/regressions").join(target);
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    v.sort();
    assert!(!v.is_empty());
    v
}

#[test]
fn toml_scene_regressions() {
    for p in inputs("toml_scene") {
        let text = std::fs::read_to_string(&p).unwrap();
        let Ok(desc) = parse_toml_scene(&text, &p, &ImportOptions::default()) else { continue };
        let ov = JobOverrides { width: Some(2), height: Some(2), spp: Some(1), threads: Some(1), ..Default::default() };
        if let Ok(out) = render_desc(&desc, &ov, false) {
            for c in out.image.channels.iter().filter(|c| c.name != "depth.Z") {
                assert!(c.values.iter().all(|v| v.is_finite()), "{}: non-finite {}", p.display(), c.name);
            }
        }
    }
}

#[test]
fn obj_regressions() {
    for p in inputs("obj") {
        match import_obj(&p, &ImportOptions::default(), ObjMaterials::FromMtl) {
            Ok(desc) => {
                quasar::core::scene::Scene::compile(&desc).unwrap();
            }
            Err(e) => assert!(e.to_string().contains(&*p.file_name().unwrap().to_string_lossy()), "{e}"),
        }
    }
}

#[test]
fn gltf_regressions() {
    let mut errors = 0;
    for p in inputs("gltf") {
        match import_gltf(&p, &ImportOptions::default()) {
            Ok(desc) => {
                let ov = JobOverrides {
                    width: Some(2),
                    height: Some(2),
                    spp: Some(1),
                    threads: Some(1),
                    ..Default::default()
                };
                if let Ok(out) = render_desc(&desc, &ov, false) {
                    for c in out.image.channels.iter().filter(|c| c.name != "depth.Z") {
                        assert!(c.values.iter().all(|v| v.is_finite()), "{}: non-finite {}", p.display(), c.name);
                    }
                }
            }
            Err(e) => {
                errors += 1;
                let s = e.to_string();
                assert!(s.contains(&*p.file_name().unwrap().to_string_lossy()), "{s}");
            }
        }
    }
    assert!(errors > 0, "the hand-written hostile inputs are refused");
}

#[test]
fn bsdf_regressions() {
    use quasar::importers::bsdf_file::{parse_tabulated_bsdf, zemax::parse_zemax_bsdf};
    for p in inputs("bsdf") {
        let data = std::fs::read(&p).unwrap();
        let Some((&kind, rest)) = data.split_first() else { continue };
        let Ok(text) = std::str::from_utf8(rest) else { continue };
        let table = if kind % 2 == 0 {
            parse_tabulated_bsdf(text, &p).ok()
        } else {
            parse_zemax_bsdf(text, &p)
                .ok()
                .and_then(|c| quasar::materials::TabulatedTable::new(c.spec).ok().map(std::sync::Arc::new))
        };
        if let Some(t) = table {
            quasar::tools::bsdf_report::check_finite(&t).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        }
    }
}

/// USD inputs the importer reads in this process; `reader-abort-*` files make openusd 0.6 abort
/// the process that reads them (an allocation failure, a stack overflow) and `reader-hang-*`
/// files make its composition loop, so both are read through the `quasar` binary, which
/// isolates the reader in a child process with a time limit (`src/cli/usd_isolation.rs`; 2 s
/// here).
#[test]
fn usd_regressions() {
    for p in inputs("usd") {
        let name = p.file_name().unwrap().to_str().unwrap().to_owned();
        let isolated = [("reader-abort", "aborted on this stage"), ("reader-hang", "did not finish this stage in 2 s")];
        if let Some((_, says)) = isolated.iter().find(|(prefix, _)| name.starts_with(prefix)) {
            let o = std::process::Command::new(env!("CARGO_BIN_EXE_quasar"))
                .env("QUASAR_USD_READER_TIMEOUT_S", "2")
                .arg("info")
                .arg(&p)
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{name}: {stderr}");
            assert!(stderr.contains(&name) && stderr.contains(says), "{stderr}");
            continue;
        }
        let result = std::panic::catch_unwind(|| quasar::importers::import_usd(&p, &ImportOptions::default()));
        match result {
            Ok(Ok(desc)) => {
                quasar::core::scene::Scene::compile(&desc).unwrap();
            }
            Ok(Err(e)) => assert!(e.to_string().contains(p.file_name().unwrap().to_str().unwrap()), "{e}"),
            Err(_) => panic!("{}: the USD importer panicked", p.display()),
        }
    }
}

/// Photometric files the fuzzer found (`fuzz/fuzz_targets/photometry.rs`): each parses as IES
/// and as EULUMDAT to an error naming the file, or to a web whose intensity is finite and >= 0.
#[test]
fn photometry_regressions() {
    use quasar::importers::photometry::{eulumdat::parse_ldt, ies::parse_ies};
    for p in inputs("photometry") {
        let text = std::fs::read_to_string(&p).unwrap();
        let name = p.file_name().unwrap().to_str().unwrap();
        let webs = [parse_ies(&text, &p).map(|f| f.web), parse_ldt(&text, &p).map(|f| f.web)];
        for w in webs {
            match w {
                Ok(w) => {
                    for d in [glam::Vec3::NEG_Z, glam::Vec3::X, glam::Vec3::new(-0.71, -0.7, 0.066).normalize()] {
                        let v = w.intensity(d);
                        assert!(v.is_finite() && v >= 0.0, "{name}: {v} towards {d}");
                    }
                }
                Err(e) => assert!(e.to_string().contains(name), "{e}"),
            }
        }
    }
}
