//! `quasar bench gltf-import` and `quasar bench usd-import`: write a large grid mesh (normals
//! and uvs; a triangulated `.glb`, or a quad-polygon `.usdc` crate file) and measure its import
//! (and compile) time and peak memory. A benchmark, not a timed test; figures go to
//! BENCHMARKS.md.

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

/// The file format a benchmark grid is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GridFormat {
    /// Binary glTF, triangles.
    Glb,
    /// USD crate file, quads (`faceVertexCounts` 4), triangulated by the importer.
    Usdc,
}

/// The (k+1)^2 points and uvs of a `k` x `k` grid 1 m wide, with a gentle wave so the BVH is
/// not degenerate-flat.
fn grid_points(k: u32) -> (Vec<[f32; 3]>, Vec<[f32; 2]>) {
    let n = k as usize + 1;
    let mut p = Vec::with_capacity(n * n);
    let mut uv = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let (u, v) = (i as f32 / k as f32, j as f32 / k as f32);
            p.push([u - 0.5, 0.02 * (20.0 * u).sin() * (17.0 * v).cos(), v - 0.5]);
            uv.push([u, v]);
        }
    }
    (p, uv)
}

/// Writes a `k` x `k` quad grid (2 k^2 triangles after triangulation) with vertex normals and
/// `primvars:st` as a `.usdc` (openusd's crate writer), or as `.usda` text when `path` ends in
/// `.usda`; returns the file size. Pixar's USD 26.11 does not read openusd 0.6.0's crate files
/// (it finds no prims in them), so a Pixar-written crate file is made from the `.usda` with
/// `usdcat` and measured with `--input` (BENCHMARKS.md).
pub fn write_grid_usdc(path: &Path, k: u32) -> Result<u64> {
    use quasar_importers::usd::writer::{PolygonMesh, mesh_stage_text, write_mesh_usdc};
    let (points, st) = grid_points(k);
    let normals = vec![[0.0, 1.0, 0.0]; points.len()];
    let face_counts = vec![4u32; (k as usize).pow(2)];
    let mut face_indices = Vec::with_capacity(4 * face_counts.len());
    for j in 0..k {
        for i in 0..k {
            let a = j * (k + 1) + i;
            // counter-clockwise seen from +Y (USD's rightHanded orientation)
            face_indices.extend_from_slice(&[a, a + k + 1, a + k + 2, a + 1]);
        }
    }
    let mesh = PolygonMesh {
        points: &points,
        normals: &normals,
        st: &st,
        face_counts: &face_counts,
        face_indices: &face_indices,
    };
    if path.extension().is_some_and(|e| e == "usda") {
        std::fs::write(path, mesh_stage_text("Grid", &mesh)).with_context(|| path.display().to_string())?;
    } else {
        write_mesh_usdc(path, "Grid", &mesh).map_err(anyhow::Error::msg)?;
    }
    Ok(std::fs::metadata(path)?.len())
}

/// Writes a `k` x `k` quad grid (2 k^2 triangles, 1 m wide, with normals and uvs) as a `.glb`.
pub fn write_grid_glb(path: &Path, k: u32) -> Result<u64> {
    let (p, uv) = grid_points(k);
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

/// Imports and compiles `path`, measuring time and peak memory; checks the triangle count when
/// `expected` is given.
pub fn run(path: &Path, expected: Option<u64>) -> Result<ImportReport> {
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
    let triangles = scene.triangle_count() as u64;
    anyhow::ensure!(expected.is_none_or(|n| n == triangles), "compiled {triangles} triangles, not {expected:?}");
    Ok(ImportReport { triangles, file_bytes, import_s, compile_s, rss_before_mib, peak_import_mib, peak_total_mib })
}

/// `quasar bench gltf-import` / `usd-import`: writes a `grid` x `grid` mesh in `format` (at
/// `file`, or in a temporary folder removed afterwards), imports and compiles it, and returns
/// the report. With `input`, measures that existing scene file instead (any format).
pub fn bench(format: GridFormat, grid: u32, file: Option<&Path>, input: Option<&Path>) -> Result<String> {
    if let Some(input) = input {
        let r = run(input, None)?;
        return Ok(format!("measured {}\n{}", input.display(), report(&r)));
    }
    anyhow::ensure!((1..=16384).contains(&grid), "--grid must be in 1..=16384");
    let tmp = std::env::temp_dir().join(format!("quasar-bench-{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    let name = match format {
        GridFormat::Glb => "grid.glb",
        GridFormat::Usdc => "grid.usdc",
    };
    let path = file.map_or_else(|| tmp.join(name), Path::to_path_buf);
    let triangles = 2 * u64::from(grid) * u64::from(grid);
    let t = Instant::now();
    let bytes = match format {
        GridFormat::Glb => write_grid_glb(&path, grid),
        GridFormat::Usdc => write_grid_usdc(&path, grid),
    };
    let r = bytes.and_then(|bytes| {
        let wrote = format!(
            "wrote {} ({triangles} triangles, {bytes} bytes) in {:.2} s\n",
            path.display(),
            t.elapsed().as_secs_f64()
        );
        Ok((wrote, run(&path, Some(triangles))?))
    });
    let _ = std::fs::remove_dir_all(&tmp);
    let (wrote, r) = r?;
    Ok(wrote + &report(&r))
}

/// The lines of `r` as `quasar bench` prints them.
fn report(r: &ImportReport) -> String {
    let mut s = String::new();
    let mib = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.0} MiB"));
    s += &format!("triangles: {}\n", r.triangles);
    s += &format!("file: {:.1} MiB\n", r.file_bytes as f64 / (1 << 20) as f64);
    s += &format!("import: {:.3} s ({:.2} M triangles/s)\n", r.import_s, r.triangles as f64 / r.import_s / 1e6);
    s += &format!("compile (BVH): {:.3} s\n", r.compile_s);
    s += &format!("rss before import: {}\n", mib(r.rss_before_mib));
    s += &format!("peak rss during import: {}\n", mib(r.peak_import_mib));
    s += &format!("peak rss during import + compile: {}\n", mib(r.peak_total_mib));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small grid in both formats imports to its 2 k^2 triangles (the bench's own check), and the
    /// USD quads come out facing +Y like the glTF triangles.
    #[test]
    fn small_grids_import_in_both_formats() {
        let dir = tempfile::tempdir().unwrap();
        for (format, name) in [(GridFormat::Glb, "g.glb"), (GridFormat::Usdc, "g.usdc")] {
            let path = dir.path().join(name);
            let report = bench(format, 6, Some(&path), None).unwrap();
            assert_eq!(bench(format, 1, None, Some(&path)).unwrap().lines().nth(1), Some("triangles: 72"));
            assert!(report.contains("triangles: 72"), "{report}");
            let desc = import_scene(&path, &ImportOptions::default()).unwrap();
            let m = &desc.meshes[0];
            let [a, b, c] = m.indices[0];
            let p = |i: u32| m.positions[i as usize];
            let n = (p(b) - p(a)).cross(p(c) - p(a));
            assert!(n.y > 0.0, "{name}: the first triangle faces {n}");
        }
    }
}
