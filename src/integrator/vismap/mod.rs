//! `vismap`: bidirectional stochastic ray tracing with visibility maps (DESIGN.md section 3.2;
//! Zhdanov, Ershov & Voloboy 2015). Each iteration shares one hero-wavelength set between a
//! backward pass (one camera path per pixel, ending in a [`VisibilityPoint`] at the gather depth)
//! and a forward pass of photons whose hits after >= 1 bounce add
//! L^I = beta f(wo, wi) Phi / (N_F pi r^2) at the visibility points within radius r. The image is
//! the average of the iterations' L^V + L^D + L^I. Radii shrink as progressive photon mapping's
//! r_k^2 = r_{k-1}^2 (k - 1 + alpha) / k (Knaus & Zwicker 2011), so the average converges to the
//! path tracer's image.

pub mod grid;
pub mod photon_pass;
pub mod visibility_point;

use std::f64::consts::PI;
use std::time::Instant;

use glam::Vec2;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use rayon::prelude::*;

use self::grid::VisibilityGrid;
use self::photon_pass::{GatherRadii, PhotonSums, trace_photons};
use self::visibility_point::{CameraPathResult, trace_camera_path};
use crate::camera::Camera;
use crate::film::Film;
use crate::render::{RenderResult, depth_pass, progress_bar};
use crate::sampling::{Sampler, mix64};
use crate::scene::Scene;

/// Settings of `vismap` (CLI: `--iterations --photons-per-iteration --gather-depth --radius
/// --alpha`).
#[derive(Clone, Copy, Debug)]
pub struct VismapSettings {
    /// Number of iterations (each: one camera path per pixel and one photon pass).
    pub iterations: u32,
    /// Photons per iteration (None: one per pixel).
    pub photons_per_iteration: Option<u64>,
    /// Non-specular vertex of the camera path where photons are gathered (0 = first).
    pub gather_depth: u32,
    /// Initial indirect gather radius in scene units (None: automatic from the pixel footprint).
    pub radius: Option<f32>,
    /// Automatic initial indirect radius, in pixel footprints at the path's first non-specular
    /// vertex (the visibility point itself at gather depth 0).
    pub radius_pixels: f32,
    /// Caustic radius / indirect radius (< 1: caustics are sharper than smooth indirect light).
    pub caustic_ratio: f32,
    /// Radius reduction parameter alpha in (0, 1) of progressive photon mapping.
    pub alpha: f32,
    /// Longest chain of specular events a camera path follows.
    pub max_specular: u32,
}

impl Default for VismapSettings {
    fn default() -> Self {
        Self {
            iterations: 64,
            photons_per_iteration: None,
            gather_depth: 0,
            radius: None,
            radius_pixels: 3.0,
            caustic_ratio: 0.5,
            alpha: 2.0 / 3.0,
            max_specular: 64,
        }
    }
}

/// Squared radius factor of iteration k (1-based): prod_{j=2..k} (j - 1 + alpha) / j.
pub fn radius2_factor(k: u32, alpha: f64) -> f64 {
    (2..=k).fold(1.0, |acc, j| acc * (j as f64 - 1.0 + alpha) / j as f64)
}

/// The hero wavelength number of iteration k: a golden-ratio sequence offset by the seed, so
/// iterations are stratified over the spectrum without knowing their count in advance.
fn iteration_wavelength_u(seed: u64, k: u32) -> f32 {
    let offset = (mix64(seed ^ 0x7761_7665) >> 40) as f64 / (1u64 << 24) as f64;
    ((offset + k as f64 * 0.618_033_988_749_894_8).fract()) as f32
}

/// Figures of a `vismap` render, for the header and benchmarks.
#[derive(Clone, Copy, Debug, Default)]
pub struct VismapStats {
    /// Photons traced in all.
    pub photons: u64,
    /// Photon hits looked up in the visibility grid.
    pub lookups: u64,
    /// Seconds spent in photon passes (tracing and gathering).
    pub photon_seconds: f64,
    /// Largest visibility-grid size of an iteration, bytes.
    pub grid_bytes: usize,
}

/// Options of a `vismap` render that are not method settings.
#[derive(Clone, Copy, Debug)]
pub struct VismapRun {
    /// Seed of every random stream.
    pub seed: u64,
    /// Stop after this many seconds (at least one iteration runs).
    pub time_limit: Option<f64>,
    /// Show a progress bar.
    pub progress: bool,
}

/// Renders `scene` with `vismap`. Deterministic for a seed: every camera path and photon has
/// its own stream and all reductions run in a fixed order.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    settings: &VismapSettings,
    run: &VismapRun,
    threads: usize,
) -> (RenderResult, VismapStats) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    pool.install(|| render_in_pool(scene, camera, settings, run, threads))
}

fn render_in_pool(
    scene: &Scene,
    camera: &Camera,
    settings: &VismapSettings,
    run: &VismapRun,
    threads: usize,
) -> (RenderResult, VismapStats) {
    let start = Instant::now();
    let (w, h) = (camera.width(), camera.height());
    let n_pixels = w as usize * h as usize;
    let mut film = Film::new(w, h);
    let n_photons = settings.photons_per_iteration.unwrap_or(n_pixels as u64).max(1);
    let pixel_angle = camera.pixel_solid_angle().sqrt();
    let alpha = settings.alpha.clamp(1e-3, 1.0) as f64;
    let photon_seed = mix64(run.seed ^ 0x7068_6f74_6f6e);
    let iterations = settings.iterations.max(1);
    let bar = progress_bar(run.progress, iterations as u64);
    let mut stats = VismapStats::default();
    let mut done = 0;
    for k in 1..=iterations {
        let wl = SampledWavelengths::sample_visible(iteration_wavelength_u(run.seed, k));
        // backward pass
        let paths: Vec<CameraPathResult> = (0..n_pixels)
            .into_par_iter()
            .map(|i| {
                let mut sampler = Sampler::new(run.seed, i as u64, k as u64);
                let jitter = sampler.get_2d();
                let film_pos = Vec2::new((i % w as usize) as f32, (i / w as usize) as f32) + jitter;
                let ray = camera.ray(film_pos);
                trace_camera_path(scene, ray, wl, &mut sampler, settings.gather_depth, settings.max_specular)
            })
            .collect();
        // visibility points and their radii for this iteration
        let shrink = radius2_factor(k, alpha).sqrt() as f32;
        let mut owners = Vec::new();
        let mut points = Vec::new();
        let mut point_wl = Vec::new();
        let mut radii = Vec::new();
        for (i, p) in paths.iter().enumerate() {
            if let Some(vp) = p.point {
                let r0 = settings.radius.unwrap_or(settings.radius_pixels * pixel_angle * vp.footprint_distance);
                let r = r0 * shrink;
                owners.push(i);
                points.push(vp);
                point_wl.push(p.wl);
                radii.push(GatherRadii { indirect: r, caustic: r * settings.caustic_ratio });
            }
        }
        let grid_input: Vec<_> = points.iter().zip(&radii).map(|(p, r)| (p.p, r.indirect)).collect();
        let grid = VisibilityGrid::build(&grid_input);
        stats.grid_bytes = stats.grid_bytes.max(grid.memory_bytes());
        // forward pass
        let t_photons = Instant::now();
        let photons = trace_photons(scene, &wl, &points, &point_wl, &radii, &grid, n_photons, photon_seed, k);
        stats.photon_seconds += t_photons.elapsed().as_secs_f64();
        stats.photons += n_photons;
        stats.lookups += photons.lookups;
        // estimate and accumulate
        let mut estimates: Vec<_> = paths.iter().map(|p| (p.radiance, p.wl)).collect();
        for (j, &i) in owners.iter().enumerate() {
            let vp = &points[j];
            let (l_ind, l_caus) = gathered_radiance(&photons.sums[j], &radii[j], n_photons, vp.beta);
            let (l, _) = &mut estimates[i];
            // caustic layer: light -> specular+ -> the first non-specular vertex -> eye
            l.add_indirect(l_caus, vp.depth == 0);
            l.add_indirect(l_ind, false);
        }
        film.pixels.par_iter_mut().zip(estimates.par_iter()).for_each(|(px, (l, wl))| px.add(l, wl));
        done = k;
        if let Some(b) = &bar {
            b.inc(1);
        }
        if let Some(limit) = run.time_limit {
            let elapsed = start.elapsed().as_secs_f64();
            if elapsed + elapsed / k as f64 >= limit {
                break;
            }
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let depth = depth_pass(scene, camera);
    let result = RenderResult { film, depth, spp: done, seconds: start.elapsed().as_secs_f64(), threads };
    (result, stats)
}

/// L^I of one visibility point: beta * sum(f Phi) / (N pi r^2) for the indirect and caustic
/// photon classes, each with its own radius.
fn gathered_radiance(
    sums: &PhotonSums,
    radii: &GatherRadii,
    n_photons: u64,
    beta: SampledSpectrum,
) -> (SampledSpectrum, SampledSpectrum) {
    let estimate = |s: &[f64; 4], r: f32| {
        let area = PI * (r as f64) * (r as f64) * n_photons as f64;
        if !(area > 0.0 && area.is_finite()) {
            return SampledSpectrum::zero();
        }
        SampledSpectrum(std::array::from_fn(|k| (s[k] / area) as f32)) * beta
    };
    (estimate(&sums.indirect, radii.indirect), estimate(&sums.caustic, radii.caustic))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_schedule_is_the_ppm_recurrence() {
        let a = 2.0 / 3.0;
        assert_eq!(radius2_factor(1, a), 1.0);
        for k in 2..50 {
            let ratio = radius2_factor(k, a) / radius2_factor(k - 1, a);
            assert!((ratio - (k as f64 - 1.0 + a) / k as f64).abs() < 1e-12);
        }
        // r_k^2 ~ k^(alpha - 1) / Gamma(1 + alpha): -> 0 (consistency), slowly enough that the
        // sum of r_k^2 diverges (variance -> 0); Gamma(5/3) = 0.9027
        let k = 10_000u32;
        let expected = (k as f64).powf(a - 1.0) / 0.902_745;
        assert!((radius2_factor(k, a) / expected - 1.0).abs() < 0.01);
    }

    #[test]
    fn iteration_wavelengths_are_stratified() {
        let mut u: Vec<f32> = (1..=100).map(|k| iteration_wavelength_u(7, k)).collect();
        u.sort_by(f32::total_cmp);
        for (i, v) in u.iter().enumerate() {
            assert!((v - (i as f32 + 0.5) / 100.0).abs() < 0.03, "{i}: {v}");
        }
    }
}
