//! Is the reported standard error honest? 20 renders with independent seeds are compared with a
//! long `pt` reference: the z-scores (difference over the combined standard error) of their
//! pixels (`stderr.Y`) and of their 4 x 4 blocks (for the bidirectional methods the batch
//! statistics of `stderr.block4`, see `quasar::film::BlockBatches`) must have an RMS in
//! [0.8, 1.25]: smaller would mean the error is overstated, larger that it is understated (and
//! `--target-error` would stop too early).

mod common;

use common::{bidir_ov, pt_ov, render_file, shipped};
use quasar::film::Quantity;
use quasar::render::job::JobOverrides;
use quasar::tools::ztest::{Estimate, ZTest};

/// RMS z of 20 seeds against `reference`: per pixel, and per block at every block size.
fn rms_z(scene: &std::path::Path, ov: impl Fn(u64) -> JobOverrides, reference: &Estimate) -> (f64, Vec<(usize, f64)>) {
    let (mut pixel_sq, mut pixel_n) = (0.0, 0usize);
    let mut scales: Vec<(usize, f64, usize)> = Vec::new();
    for seed in 0..20 {
        let out = render_file(scene, &ov(1000 + seed));
        let e = Estimate::from_film(&out.result.film, Quantity::Beauty);
        for i in 0..e.values.len() {
            let v = e.pixel_var[i] + reference.pixel_var[i];
            if v > 0.0 {
                pixel_sq += (e.values[i] - reference.values[i]).powi(2) / v;
                pixel_n += 1;
            }
        }
        let r = ZTest::default().run(&e, reference).unwrap();
        if scales.is_empty() {
            scales = r.scales.iter().map(|s| (s.size, 0.0, 0)).collect();
        }
        for (acc, s) in scales.iter_mut().zip(&r.scales) {
            acc.1 += s.blocks.iter().map(|b| b.z * b.z).sum::<f64>();
            acc.2 += s.blocks.len();
        }
    }
    ((pixel_sq / pixel_n as f64).sqrt(), scales.iter().map(|&(s, sq, n)| (s, (sq / n as f64).sqrt())).collect())
}

fn check(scene: &str, ov: impl Fn(u64) -> JobOverrides) {
    let path = shipped(scene);
    let reference = render_file(&path, &pt_ov(16, 16, 16384, 1));
    let reference = Estimate::from_film(&reference.result.film, Quantity::Beauty);
    let (pixel, scales) = rms_z(&path, ov, &reference);
    eprintln!("{scene}: rms z per pixel {pixel:.3}, per block size {scales:.3?}");
    assert!((0.8..=1.25).contains(&pixel), "{scene}: rms z per pixel {pixel}");
    let block = scales[0].1;
    assert!((0.8..=1.25).contains(&block), "{scene}: rms z of 4 x 4 blocks {block}");
}

/// `pt` on the Cornell box, 256 samples per pixel.
#[test]
fn pt_standard_errors_are_honest() {
    check("cornell-box/cornell-box.toml", |seed| pt_ov(16, 16, 256, seed));
}

/// `quasi` (what `auto` runs) and `adaptive+quasi` on the glass plate, 256 iterations of 4096
/// photons: pixels of one iteration share wavelengths and photons, so their errors are
/// correlated; the blocks' batch statistics see that, the per-pixel errors need not.
#[test]
fn bidirectional_standard_errors_are_honest() {
    for method in ["quasi", "adaptive+quasi"] {
        check("glass-plate/glass-plate.toml", |seed| bidir_ov(16, 16, method, 256, 4096, seed));
    }
}
