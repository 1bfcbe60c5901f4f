//! `vismap`: bidirectional stochastic ray tracing with visibility maps (DESIGN.md section 3.2;
//! Zhdanov, Ershov & Voloboy 2015). Each iteration shares one hero-wavelength set between a
//! backward pass (one camera path per pixel, ending in a [`VisibilityPoint`] at the gather depth)
//! and a forward pass of photons whose hits after >= 1 bounce add
//! L^I = beta f(wo, wi) Phi / (N_F pi r^2) at the visibility points within radius r. The image is
//! the average of the iterations' L^V + L^D + L^I. Radii shrink as progressive photon mapping's
//! r_k^2 = r_{k-1}^2 (k - 1 + alpha) / k (Knaus & Zwicker 2011), so the average converges to the
//! path tracer's image. The adaptive-depth (3.3) and quasi-specular (3.4) methods are the same
//! passes with a per-pixel gather depth and a cone C around ideal directions.

pub mod coverage;
pub mod grid;
pub mod photon_pass;
pub mod quasi_cone;
pub mod visibility_point;

use std::f64::consts::PI;
use std::time::Instant;

use glam::Vec2;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};
use rayon::prelude::*;

use self::grid::VisibilityGrid;
use self::photon_pass::{GatherRadii, PhotonSums, trace_photons};
use self::visibility_point::{CameraPathResult, GatherRule, VisibilityPoint, pilot_gather_depth, trace_camera_path};
use crate::core::camera::Camera;
use crate::core::sampling::{Sampler, mix64};
use crate::core::scene::Scene;
use crate::film::{Channel, Film};
use crate::render::driver::{RenderResult, depth_pass, progress_bar};

/// Where camera paths gather photons.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GatherDepth {
    /// Every pixel at this depth (`vismap --gather-depth D`; 0 = first non-specular vertex).
    Fixed(u32),
    /// Per pixel and iteration, the depth of least non-uniformity kappa (DESIGN.md 3.3), up to
    /// `max_depth`.
    Adaptive {
        /// Deepest depth considered.
        max_depth: u32,
        /// The paper's variant: the depth comes from the iteration's own first camera ray (biased:
        /// the choice depends on the estimate's own path). Otherwise: the mode of the depths
        /// chosen by independent pilot paths of earlier iterations (unbiased per iteration).
        paper: bool,
    },
}

/// Settings of the bidirectional methods: `vismap`, `adaptive`, `quasi`, `adaptive+quasi`
/// (CLI: `--iterations --photons-per-iteration --gather-depth --radius --alpha --cone`).
#[derive(Clone, Copy, Debug)]
pub struct VismapSettings {
    /// Number of iterations (each: one camera path per pixel and one photon pass).
    pub iterations: u32,
    /// Photons per iteration (None: one per pixel).
    pub photons_per_iteration: Option<u64>,
    /// How the gather depth is chosen.
    pub depth: GatherDepth,
    /// Half-angle in degrees of the quasi-specular cone (None: no quasi-specular tracing).
    pub cone_deg: Option<f32>,
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
            depth: GatherDepth::Fixed(0),
            cone_deg: None,
            radius: None,
            radius_pixels: 3.0,
            caustic_ratio: 0.5,
            alpha: 2.0 / 3.0,
            max_specular: 64,
        }
    }
}

/// Most depths an adaptive histogram tracks (0..=MAX_ADAPTIVE_DEPTH).
pub const MAX_ADAPTIVE_DEPTH: u32 = 7;

/// Per-pixel histograms of the depths chosen by pilot paths (DESIGN.md 3.3).
struct DepthHistogram {
    counts: Vec<[u32; MAX_ADAPTIVE_DEPTH as usize + 1]>,
}

impl DepthHistogram {
    fn new(n: usize) -> Self {
        Self { counts: vec![[0; MAX_ADAPTIVE_DEPTH as usize + 1]; n] }
    }

    /// The most frequent depth of pixel `i` (ties: the smaller depth; none seen: 0).
    fn mode(&self, i: usize) -> u32 {
        let c = &self.counts[i];
        let mut best = 0;
        for d in 1..c.len() {
            if c[d] > c[best] {
                best = d;
            }
        }
        best as u32
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
    /// Most visibility points of an iteration.
    pub max_points: usize,
}

/// Options of a `vismap` render that are not method settings.
#[derive(Clone, Debug)]
pub struct VismapRun {
    /// Seed of every random stream.
    pub seed: u64,
    /// Stop after this many seconds (at least one iteration runs).
    pub time_limit: Option<f64>,
    /// Stop once the image's estimated RMS relative error is at most this (per-iteration
    /// variance; see [`Film::estimated_rel_error`]).
    pub target_error: Option<f64>,
    /// Show a progress bar.
    pub progress: bool,
    /// Render only iterations k with (k - 1) mod n = share (`--shard K/N`); pilot paths of every
    /// iteration are still traced, so adaptive depths match the unsharded render.
    pub shard: (u32, u32),
    /// Continue from this state (`--resume`).
    pub resume: Option<crate::render::checkpoint::RenderState>,
    /// Write checkpoints here, with this fingerprint (`--checkpoint`).
    pub checkpoint: Option<(std::path::PathBuf, u64)>,
}

/// Renders `scene` with a bidirectional method. Deterministic for a seed: every camera path,
/// pilot path and photon has its own stream and all reductions run in a fixed order.
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

/// The gather depth of every pixel for iteration `k`, and the pilot depths it learned.
#[allow(clippy::too_many_arguments)]
fn iteration_depths(
    scene: &Scene,
    camera: &Camera,
    settings: &VismapSettings,
    rule: &GatherRule,
    wl: SampledWavelengths,
    seed: u64,
    k: u32,
    histogram: &mut DepthHistogram,
) -> Vec<Option<u32>> {
    let w = camera.width() as usize;
    let n = histogram.counts.len();
    let pilot = |i: usize, stream_seed: u64, k: u32, max_depth: u32| {
        let mut sampler = Sampler::new(stream_seed, i as u64, k as u64);
        let film_pos = Vec2::new((i % w) as f32, (i / w) as f32) + sampler.get_2d();
        pilot_gather_depth(scene, camera.ray(film_pos), wl, &mut sampler, rule, max_depth)
    };
    match settings.depth {
        GatherDepth::Fixed(d) => vec![Some(d); n],
        GatherDepth::Adaptive { max_depth, paper: true } => {
            // the iteration's own stream: the same first camera ray as the estimate
            (0..n).into_par_iter().map(|i| pilot(i, seed, k, max_depth)).collect()
        }
        GatherDepth::Adaptive { max_depth, paper: false } => {
            let pilot_seed = mix64(seed ^ 0x0070_696c_6f74);
            if k == 1 {
                let first: Vec<Option<u32>> =
                    (0..n).into_par_iter().map(|i| pilot(i, pilot_seed, 0, max_depth)).collect();
                for (c, d) in histogram.counts.iter_mut().zip(first) {
                    if let Some(d) = d {
                        c[d as usize] += 1;
                    }
                }
            }
            let chosen: Vec<Option<u32>> = (0..n).map(|i| Some(histogram.mode(i))).collect();
            // this iteration's pilot paths only inform later iterations
            let next: Vec<Option<u32>> = (0..n).into_par_iter().map(|i| pilot(i, pilot_seed, k, max_depth)).collect();
            for (c, d) in histogram.counts.iter_mut().zip(next) {
                if let Some(d) = d {
                    c[d as usize] += 1;
                }
            }
            chosen
        }
    }
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
    let mut film = Film::with_block_batches(w, h);
    let n_photons = settings.photons_per_iteration.unwrap_or(n_pixels as u64).max(1);
    let pixel_angle = camera.pixel_solid_angle().sqrt();
    let alpha = settings.alpha.clamp(1e-3, 1.0) as f64;
    let photon_seed = mix64(run.seed ^ 0x7068_6f74_6f6e);
    let cone_cos = settings.cone_deg.map(|d| d.clamp(0.0, 90.0).to_radians().cos());
    let base_rule = GatherRule { depth: 0, cone_cos, max_specular: settings.max_specular };
    let iterations = settings.iterations.max(1);
    let bar = progress_bar(run.progress, iterations.div_ceil(run.shard.1.max(1)) as u64);
    let mut stats = VismapStats::default();
    let mut histogram = DepthHistogram::new(n_pixels);
    let mut depth_sum = vec![0u64; n_pixels];
    let mut depth_count = vec![0u32; n_pixels];
    let mut radius_scales: Option<Vec<f32>> = None;
    let mut done = 0;
    let mut first = 1;
    if let Some(st) = &run.resume {
        film = st.film.clone();
        done = st.done;
        first = st.next.max(1);
        if st.histogram.len() == n_pixels {
            histogram.counts.clone_from(&st.histogram);
        }
        if st.depth_sum.len() == n_pixels {
            depth_sum.clone_from(&st.depth_sum);
            depth_count.clone_from(&st.depth_count);
        }
        if st.radius_scales.len() == n_pixels {
            radius_scales = Some(st.radius_scales.clone());
        }
    }
    let mut last_checkpoint = Instant::now();
    let mut interrupted = false;
    let mut next = first;
    let (shard_k, shard_n) = (run.shard.0, run.shard.1.max(1));
    for k in first..=iterations {
        next = k + 1;
        let wl = SampledWavelengths::sample_visible(iteration_wavelength_u(run.seed, k));
        let depths = iteration_depths(scene, camera, settings, &base_rule, wl, run.seed, k, &mut histogram);
        if (k - 1) % shard_n != shard_k {
            continue;
        }
        let scales = radius_scales.get_or_insert_with(|| {
            radius_pilot(scene, camera, settings, &base_rule, &depths, run.seed, photon_seed, n_photons)
        });
        let it = Iteration { seed: run.seed, photon_seed, k, wl, n_photons };
        let radius_of = |i: usize, vp: &VisibilityPoint| {
            settings.radius.unwrap_or(settings.radius_pixels * pixel_angle * vp.footprint_distance * scales[i])
                * radius2_factor(k, alpha).sqrt() as f32
        };
        let t_photons = Instant::now();
        let IterationResult { paths, owners, points, radii, photons, grid_bytes } =
            it.run(scene, camera, settings, &base_rule, &depths, radius_of);
        for (i, d) in depths.iter().enumerate() {
            if let Some(d) = d {
                depth_sum[i] += *d as u64;
                depth_count[i] += 1;
            }
        }
        stats.grid_bytes = stats.grid_bytes.max(grid_bytes);
        stats.max_points = stats.max_points.max(points.len());
        stats.photon_seconds += t_photons.elapsed().as_secs_f64();
        stats.photons += n_photons;
        stats.lookups += photons.lookups;
        // estimate and accumulate
        let mut estimates: Vec<_> = paths.iter().map(|p| (p.radiance, p.wl)).collect();
        for (j, &i) in owners.iter().enumerate() {
            let vp = &points[j];
            let g = gathered_radiance(&photons.sums[j], &radii[j], n_photons, vp.beta);
            let (l, _) = &mut estimates[i];
            l.add_indirect(g.caustic_radius, false);
            l.add_indirect(g.indirect_radius, false);
            // the caustic layer: light -> specular+ -> this first non-specular vertex -> eye
            if vp.class.nonspecular == 0 {
                l.caustic += g.specular_only;
            }
        }
        film.add_batch(&estimates);
        done += 1;
        if let Some(b) = &bar {
            b.inc(1);
        }
        if let Some((path, fingerprint)) = &run.checkpoint
            && last_checkpoint.elapsed().as_secs_f64() >= crate::render::driver::CHECKPOINT_INTERVAL_S
        {
            write_state(
                path,
                *fingerprint,
                &film,
                done,
                k + 1,
                &histogram,
                &depth_sum,
                &depth_count,
                radius_scales.as_deref(),
            );
            last_checkpoint = Instant::now();
        }
        if crate::render::interrupt::requested() {
            interrupted = true;
            break;
        }
        if run.target_error.is_some_and(|e| film.estimated_rel_error() <= e) {
            break;
        }
        if let Some(limit) = run.time_limit {
            let elapsed = start.elapsed().as_secs_f64();
            if elapsed + elapsed / done as f64 >= limit {
                break;
            }
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    // the bidirectional methods stop between iterations: the state is always consistent
    if let Some((path, fingerprint)) = &run.checkpoint {
        write_state(
            path,
            *fingerprint,
            &film,
            done,
            next,
            &histogram,
            &depth_sum,
            &depth_count,
            radius_scales.as_deref(),
        );
    }
    let depth = depth_pass(scene, camera);
    let trace_depth =
        depth_sum.iter().zip(&depth_count).map(|(&s, &c)| if c > 0 { s as f32 / c as f32 } else { 0.0 }).collect();
    let extra = vec![Channel { name: "trace_depth.Y".into(), values: trace_depth }];
    let result =
        RenderResult { film, depth, extra, interrupted, spp: done, seconds: start.elapsed().as_secs_f64(), threads };
    (result, stats)
}

/// Photons a gather disk should hold in an iteration: the automatic radius is shrunk (never
/// grown) until the pilot pass's photon density puts this many photons in it.
pub const RADIUS_PILOT_PHOTONS: f32 = 8.0;
/// The automatic radius is not shrunk below this share of its pixel-footprint default.
pub const MIN_RADIUS_SCALE: f32 = 0.1;

/// One iteration's passes: camera paths with their visibility points, the grid over them and
/// the photon pass at the iteration's wavelengths, all keyed by iteration number `k`.
struct Iteration {
    seed: u64,
    photon_seed: u64,
    k: u32,
    wl: SampledWavelengths,
    n_photons: u64,
}

/// What [`Iteration::run`] produced.
struct IterationResult<'s> {
    paths: Vec<CameraPathResult<'s>>,
    /// The pixel of every visibility point.
    owners: Vec<usize>,
    points: Vec<VisibilityPoint<'s>>,
    radii: Vec<GatherRadii>,
    photons: photon_pass::PhotonPassResult,
    grid_bytes: usize,
}

impl Iteration {
    /// Traces one camera path per pixel at gather depths `depths`, gives every visibility
    /// point the indirect radius `radius_of(pixel, point)` (caustic radius: the settings' ratio
    /// of it) and gathers the iteration's photons.
    fn run<'s>(
        &self,
        scene: &'s Scene,
        camera: &Camera,
        settings: &VismapSettings,
        base_rule: &GatherRule,
        depths: &[Option<u32>],
        radius_of: impl Fn(usize, &VisibilityPoint) -> f32 + Sync,
    ) -> IterationResult<'s> {
        let w = camera.width() as usize;
        let paths: Vec<CameraPathResult> = (0..depths.len())
            .into_par_iter()
            .map(|i| {
                let mut sampler = Sampler::new(self.seed, i as u64, self.k as u64);
                let film_pos = Vec2::new((i % w) as f32, (i / w) as f32) + sampler.get_2d();
                let rule = GatherRule { depth: depths[i].unwrap_or(0), ..*base_rule };
                trace_camera_path(scene, camera.ray(film_pos), self.wl, &mut sampler, &rule)
            })
            .collect();
        let mut owners = Vec::new();
        let mut points = Vec::new();
        let mut point_wl = Vec::new();
        for (i, p) in paths.iter().enumerate() {
            for vp in &p.points {
                owners.push(i);
                points.push(*vp);
                point_wl.push(p.wl);
            }
        }
        let radii: Vec<GatherRadii> = (0..points.len())
            .into_par_iter()
            .map(|j| {
                let (i, vp) = (owners[j], &points[j]);
                let r = radius_of(i, vp);
                let rc = r * settings.caustic_ratio;
                let rotation = (mix64(self.seed ^ mix64(((self.k as u64) << 40) ^ j as u64)) >> 40) as f32
                    * (std::f32::consts::TAU / (1u64 << 24) as f32);
                let (ci, cc) = coverage::disk_coverage(scene, vp, r, rc, rotation);
                GatherRadii { indirect: r, caustic: rc, indirect_coverage: ci, caustic_coverage: cc }
            })
            .collect();
        let grid_input: Vec<_> = points.iter().zip(&radii).map(|(p, r)| (p.p, r.indirect)).collect();
        let grid = VisibilityGrid::build(&grid_input);
        let photons = trace_photons(
            scene,
            &self.wl,
            &points,
            &point_wl,
            &radii,
            &grid,
            self.n_photons,
            self.photon_seed,
            self.k,
            base_rule.cone_cos,
        );
        IterationResult { paths, owners, points, radii, photons, grid_bytes: grid.memory_bytes() }
    }
}

/// The per-pixel scale of the automatic gather radius, from a pilot iteration (number 0, not
/// part of the image) at the default radius: where its photon count M exceeds
/// [`RADIUS_PILOT_PHOTONS`] the radius is scaled by sqrt(RADIUS_PILOT_PHOTONS / M), so that
/// a disk holds about that many photons; dim pixels keep the default (scale 1). The
/// photon-mapping bias grows with the radius squared, so many photons per iteration buy a
/// small radius instead of a needlessly precise blur. Every shard computes the same pilot.
#[allow(clippy::too_many_arguments)]
fn radius_pilot(
    scene: &Scene,
    camera: &Camera,
    settings: &VismapSettings,
    base_rule: &GatherRule,
    depths: &[Option<u32>],
    seed: u64,
    photon_seed: u64,
    n_photons: u64,
) -> Vec<f32> {
    if settings.radius.is_some() {
        return vec![1.0; depths.len()];
    }
    let wl = SampledWavelengths::sample_visible(iteration_wavelength_u(seed, 0));
    let pixel_angle = camera.pixel_solid_angle().sqrt();
    let it = Iteration { seed, photon_seed, k: 0, wl, n_photons };
    let radius_of = |_: usize, vp: &VisibilityPoint| settings.radius_pixels * pixel_angle * vp.footprint_distance;
    let r = it.run(scene, camera, settings, base_rule, depths, radius_of);
    // photons per fully covered disk
    let mut count = vec![(0.0f32, 0u32); depths.len()];
    for (j, &i) in r.owners.iter().enumerate() {
        count[i].0 += r.photons.sums[j].photons as f32 / r.radii[j].indirect_coverage;
        count[i].1 += 1;
    }
    count
        .iter()
        .map(|&(m, n)| {
            let m = m / n.max(1) as f32;
            if m > RADIUS_PILOT_PHOTONS { (RADIUS_PILOT_PHOTONS / m).sqrt().max(MIN_RADIUS_SCALE) } else { 1.0 }
        })
        .collect()
}

/// Writes a checkpoint of the state after `done` iterations, next iteration `next`.
#[allow(clippy::too_many_arguments)]
fn write_state(
    path: &std::path::Path,
    fingerprint: u64,
    film: &Film,
    done: u32,
    next: u32,
    histogram: &DepthHistogram,
    depth_sum: &[u64],
    depth_count: &[u32],
    radius_scales: Option<&[f32]>,
) {
    let state = crate::render::checkpoint::RenderState {
        film: film.clone(),
        done,
        next,
        histogram: histogram.counts.clone(),
        depth_sum: depth_sum.to_vec(),
        depth_count: depth_count.to_vec(),
        radius_scales: radius_scales.map_or_else(Vec::new, <[f32]>::to_vec),
    };
    crate::render::checkpoint::save(path, fingerprint, &state);
}

/// L^I of one visibility point by photon class.
struct Gathered {
    /// Photons with a non-specular bounce: beta sum / (N pi r_i^2).
    indirect_radius: SampledSpectrum,
    /// Caustic photons: beta sum / (N pi r_c^2).
    caustic_radius: SampledSpectrum,
    /// The purely specular part of `caustic_radius`.
    specular_only: SampledSpectrum,
}

/// L^I of one visibility point: beta * sum(f Phi) / (N pi r^2 c) for the indirect and caustic
/// photon classes, each with its own radius r and covered share c of its disk.
fn gathered_radiance(sums: &PhotonSums, radii: &GatherRadii, n_photons: u64, beta: SampledSpectrum) -> Gathered {
    let estimate = |s: &[f64; 4], r: f32, coverage: f32| {
        let area = PI * (r as f64) * (r as f64) * coverage as f64 * n_photons as f64;
        if !(area > 0.0 && area.is_finite()) {
            return SampledSpectrum::zero();
        }
        SampledSpectrum(std::array::from_fn(|k| (s[k] / area) as f32)) * beta
    };
    Gathered {
        indirect_radius: estimate(&sums.indirect, radii.indirect, radii.indirect_coverage),
        caustic_radius: estimate(&sums.caustic, radii.caustic, radii.caustic_coverage),
        specular_only: estimate(&sums.specular_only, radii.caustic, radii.caustic_coverage),
    }
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
