//! `quasar bench gltf-import`: writes a large glTF (a triangulated grid with normals and uvs, as
//! a `.glb`) and measures its import (and compile) time and peak memory. A benchmark, not a
//! timed test; figures go to BENCHMARKS.md.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use quasar_importers::gltf::writer::{GltfWriter, Prim};
use quasar_importers::{ImportOptions, import_scene};

use crate::core::scene::Scene;

/// What [`run`] measured.
#[derive(Clone, Debug)]
pub struct ImportReport {
    /// Triangles in the file.
    pub triangles: u64,
    /// File size in bytes.
    pub file_bytes: u64,
    /// Wall time of `import_scene` (seconds).
    pub import_s: f64,
    /// Wall time of `Scene::compile` (BVH build; seconds).
    pub compile_s: f64,
    /// Resident memory before the import (MiB), when the OS reports it.
    pub rss_before_mib: Option<f64>,
    /// Peak resident memory during the import (MiB), when the OS can reset and report it.
    pub peak_import_mib: Option<f64>,
    /// Peak resident memory during import + compile (MiB).
    pub peak_total_mib: Option<f64>,
}

/// Writes a `k` x `k` quad grid (2 k^2 triangles, 1 m wide, with normals and uvs) as a `.glb`.
pub fn write_grid_glb(path: &Path, k: u32) -> Result<u64> {
    let n = k as usize + 1;
    let mut p = Vec::with_capacity(n * n);
    let mut uv = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let (u, v) = (i as f32 / k as f32, j as f32 / k as f32);
            // a gentle wave so the BVH is not degenerate-flat
            p.push([u - 0.5, 0.02 * (20.0 * u).sin() * (17.0 * v).cos(), v - 0.5]);
            uv.push([u, v]);
        }
    }
    let mut idx = Vec::with_capacity(6 * (k as usize).pow(2));
    for j in 0..k {
        for i in 0..k {
            let a = j * (k + 1) + i;
            let b = a + k + 1;
            idx.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    let mut w = GltfWriter::new();
    let position = w.positions(&p);
    let normal = Some(w.normals(&vec![[0.0, 1.0, 0.0]; p.len()]));
    let uv = Some(w.uvs(&uv));
    let indices = Some(w.indices(&idx));
    drop((p, idx));
    let m = w.mesh("grid", &[Prim { position, normal, uv, indices, material: None, mode: None }]);
    let node = GltfWriter::push(&mut w.nodes, &format!("{{\"mesh\":{m}}}"));
    w.roots.push(node);
    let glb = w.to_glb();
    std::fs::write(path, &glb).with_context(|| path.display().to_string())?;
    Ok(glb.len() as u64)
}

/// Peak resident set size of this process (MiB), from /proc/self/status (Linux).
fn peak_rss_mib() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Current resident set size (MiB).
fn rss_mib() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Resets the peak RSS counter to the current RSS (Linux >= 4.0); false when unsupported.
fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Imports and compiles `path`, measuring time and peak memory.
pub fn run(path: &Path, triangles: u64) -> Result<ImportReport> {
    let file_bytes = std::fs::metadata(path)?.len();
    let resettable = reset_peak_rss();
    let rss_before_mib = rss_mib();
    let t = Instant::now();
    let desc = import_scene(path, &ImportOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))?;
    let import_s = t.elapsed().as_secs_f64();
    let peak_import_mib = if resettable { peak_rss_mib() } else { None };
    let t = Instant::now();
    let scene = Scene::compile(&desc)?;
    let compile_s = t.elapsed().as_secs_f64();
    let peak_total_mib = if resettable { peak_rss_mib() } else { None };
    anyhow::ensure!(scene.triangle_count() as u64 == triangles, "compiled {} triangles", scene.triangle_count());
    Ok(ImportReport { triangles, file_bytes, import_s, compile_s, rss_before_mib, peak_import_mib, peak_total_mib })
}

/// `quasar bench gltf-import`: writes a `grid` x `grid` glTF (at `file`, or in a temporary
/// folder removed afterwards), imports and compiles it, and returns the report.
pub fn bench(grid: u32, file: Option<&Path>) -> Result<String> {
    anyhow::ensure!((1..=16384).contains(&grid), "--grid must be in 1..=16384");
    let tmp = std::env::temp_dir().join(format!("quasar-bench-{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    let path = file.map_or_else(|| tmp.join("grid.glb"), Path::to_path_buf);
    let triangles = 2 * u64::from(grid) * u64::from(grid);
    let t = Instant::now();
    let bytes = write_grid_glb(&path, grid)?;
    let mut s = format!(
        "wrote {} ({triangles} triangles, {bytes} bytes) in {:.2} s\n",
        path.display(),
        t.elapsed().as_secs_f64()
    );
    let r = run(&path, triangles)?;
    let _ = std::fs::remove_dir_all(&tmp);
    let mib = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.0} MiB"));
    s += &format!("triangles: {}\n", r.triangles);
    s += &format!("file: {:.1} MiB\n", r.file_bytes as f64 / (1 << 20) as f64);
    s += &format!("import: {:.3} s ({:.2} M triangles/s)\n", r.import_s, r.triangles as f64 / r.import_s / 1e6);
    s += &format!("compile (BVH): {:.3} s\n", r.compile_s);
    s += &format!("rss before import: {}\n", mib(r.rss_before_mib));
    s += &format!("peak rss during import: {}\n", mib(r.peak_import_mib));
    s += &format!("peak rss during import + compile: {}\n", mib(r.peak_total_mib));
    Ok(s)
}
