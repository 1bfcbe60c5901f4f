//! Helpers shared by the integration tests: write a scene into a temporary directory and render it.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use quasar::job::{JobOutput, JobOverrides, load_scene, render_desc};

/// A temporary directory holding one scene file.
pub struct TempScene {
    /// Keeps the directory alive.
    pub dir: tempfile::TempDir,
    /// The scene file.
    pub path: PathBuf,
}

/// Writes `toml` as `scene.toml` (plus extra files) into a fresh temporary directory.
pub fn write_scene(toml: &str, extra: &[(&str, &str)]) -> TempScene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, toml).unwrap();
    for (name, text) in extra {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    TempScene { dir, path }
}

/// Renders a scene file with the given overrides.
pub fn render_file(path: &Path, ov: &JobOverrides) -> JobOutput {
    let desc = load_scene(path).unwrap_or_else(|e| panic!("{e:#}"));
    render_desc(&desc, ov, false).unwrap_or_else(|e| panic!("{e:#}"))
}

/// Relative mean squared error of `a` against reference `r` (per pixel (a-r)^2 / (r^2 + eps)),
/// averaged: the usual relMSE of rendering papers.
pub fn rel_mse(a: &[f32], r: &[f32]) -> f64 {
    assert_eq!(a.len(), r.len());
    let eps = 1e-3;
    a.iter().zip(r).map(|(&a, &r)| ((a - r) as f64).powi(2) / ((r as f64).powi(2) + eps)).sum::<f64>() / a.len() as f64
}

/// Mean of a slice.
pub fn mean(v: &[f32]) -> f64 {
    v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64
}

/// Luminance of layer `name` from its `name.R/G/B` channels.
pub fn layer_luminance(img: &quasar::output::ExrImage, name: &str) -> Vec<f32> {
    let c = |k: &str| img.channel(&format!("{name}.{k}")).unwrap();
    let (r, g, b) = (c("R"), c("G"), c("B"));
    (0..r.len()).map(|i| quasar::materials::spectrum::color::srgb_luminance([r[i], g[i], b[i]])).collect()
}
