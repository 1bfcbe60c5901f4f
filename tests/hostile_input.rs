//! Hostile input: thousands of randomly mutated scene, OBJ and glTF files (byte flips, deletions,
//! duplicated lines, special numbers and keys spliced in) must load with a clear error or render
//! without a panic and without NaN/inf pixels. A cheap, deterministic, stable-Rust cousin of the
//! fuzz targets; every mutation is reproducible from its seed.

mod common;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use quasar::core::sampling::mix64;
use quasar::render::job::{JobOverrides, load_scene, render_desc};

/// Pieces spliced into files: numbers at and beyond the limits, and structure.
const TOKENS: [&str; 24] = [
    "nan",
    "inf",
    "-inf",
    "1e39",
    "-1e39",
    "1e-45",
    "0",
    "-0",
    "-1",
    "4294967296",
    "99999999999999999999",
    "[[shape]]",
    "[render]",
    "[camera]",
    "]",
    "[",
    "{",
    "}",
    "\"",
    "=",
    ",",
    "\n",
    "f 1 2 3\n",
    "v 1e38 -1e38 nan\n",
];

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = mix64(self.0.wrapping_add(0x9e37_79b9_7f4a_7c15));
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn mutate(text: &str, seed: u64) -> String {
    let mut rng = Rng(seed);
    let mut b = text.as_bytes().to_vec();
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(b.len());
        match rng.below(5) {
            0 => b[at] = rng.next() as u8 & 0x7f,
            1 => {
                let end = (at + 1 + rng.below(20)).min(b.len());
                b.drain(at..end);
            }
            2 | 3 => {
                let t = TOKENS[rng.below(TOKENS.len())].as_bytes();
                // replace a number-ish run when we hit one, else insert
                let mut end = at;
                while end < b.len() && (b[end].is_ascii_digit() || b[end] == b'.') {
                    end += 1;
                }
                b.splice(at..end, t.iter().copied());
            }
            _ => {
                let lines: Vec<&[u8]> = b.split(|&c| c == b'\n').collect();
                let l = lines[rng.below(lines.len())].to_vec();
                b.splice(at..at, l.into_iter().chain([b'\n']));
            }
        }
        if b.is_empty() {
            break;
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}

/// Loads and (when it loads) renders `scene` tiny with pt and adaptive+quasi; panics propagate.
fn exercise(path: &Path) {
    let Ok(desc) = load_scene(path) else { return };
    for method in ["pt", "adaptive+quasi"] {
        let ov0 = JobOverrides {
            width: Some(4),
            height: Some(3),
            spp: Some(1),
            seed: Some(1),
            threads: Some(1),
            method: Some(method.into()),
            ..Default::default()
        };
        let ov = if method == "pt" { ov0 } else { ov0.with_param("photons_per_iteration", 200u32) };
        if let Ok(out) = render_desc(&desc, &ov, false) {
            for c in out.image.channels.iter().filter(|c| c.name != "depth.Z") {
                assert!(c.values.iter().all(|v| v.is_finite()), "{}: non-finite {}", path.display(), c.name);
            }
        }
    }
}

fn run_mutations(scene_dir: &str, main: &str, also: &[&str], count: u64) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(scene_dir);
    let original = std::fs::read_to_string(root.join(main)).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for f in std::fs::read_dir(&root).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, dir.path().join(f.file_name().unwrap())).unwrap();
    }
    let mut failures = Vec::new();
    for seed in 0..count {
        // mutate the scene file, or one of the files it refers to
        let (name, text) = if also.is_empty() || seed % 2 == 0 {
            (main, original.clone())
        } else {
            let n = also[(seed / 2) as usize % also.len()];
            (n, std::fs::read_to_string(root.join(n)).unwrap())
        };
        let mutated = mutate(&text, seed * 7919 + 1);
        std::fs::write(dir.path().join(name), &mutated).unwrap();
        let path = dir.path().join(main);
        if catch_unwind(AssertUnwindSafe(|| exercise(&path))).is_err() {
            failures.push((seed, name, mutated));
        }
        std::fs::write(dir.path().join(name), &text).unwrap();
    }
    for (seed, name, text) in failures.iter().take(3) {
        eprintln!("--- seed {seed}, {name}:\n{text}");
    }
    assert!(failures.is_empty(), "{} of {count} mutations panicked", failures.len());
}

#[test]
fn mutated_cornell_box_scene_and_objs_never_panic() {
    let prev = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    run_mutations("cornell-box", "cornell-box.toml", &["blocks.obj", "light.obj", "white.csv"], 400);
    std::panic::set_hook(prev);
}

#[test]
fn mutated_glass_plate_and_lightguide_scenes_never_panic() {
    let prev = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    run_mutations("glass-plate", "glass-plate.toml", &[], 300);
    run_mutations("lightguide", "lightguide.toml", &[], 300);
    std::panic::set_hook(prev);
}

#[test]
fn mutated_gltf_showcase_never_panics() {
    let prev = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    run_mutations("gltf-showcase", "showcase.gltf", &[], 200);
    std::panic::set_hook(prev);
}
