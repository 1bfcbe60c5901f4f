//! The render driver: runs an integrator over the image in passes of samples, in parallel with
//! rayon, deterministically (every pixel's samples use their own hashed random streams and are
//! summed in sample order, so the result does not depend on the thread count or scheduling).

use std::time::{Duration, Instant};

use glam::Vec2;
use indicatif::{ProgressBar, ProgressStyle};
use quasar_materials::spectrum::SampledWavelengths;
use rayon::prelude::*;

use crate::core::camera::Camera;
use crate::core::sampling::Sampler;
use crate::core::scene::Scene;
use crate::film::{Film, PixelSum};
use crate::integrator::{PtSettings, pt};

/// How long to render and with what randomness.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Samples per pixel (the total, or the cap when `time_limit` is set).
    pub spp: u32,
    /// Stop starting new passes after this many seconds (at least one pass always runs).
    pub time_limit: Option<f64>,
    /// Stop once the image's estimated RMS relative error ([`Film::estimated_rel_error`]) is at
    /// most this.
    pub target_error: Option<f64>,
    /// Seed of all random streams.
    pub seed: u64,
    /// Worker threads (None = all cores).
    pub threads: Option<usize>,
    /// Path tracer settings.
    pub pt: PtSettings,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Render only share `k` of `n` (`--shard K/N`): the samples whose index is k mod n, so that
    /// shards of one render have disjoint random streams and merge into the full render.
    pub shard: (u32, u32),
    /// Continue from this state (`--resume`).
    pub resume: Option<crate::render::checkpoint::RenderState>,
    /// Write checkpoints here, with this fingerprint (`--checkpoint`).
    pub checkpoint: Option<(std::path::PathBuf, u64)>,
}

/// Seconds between two checkpoint writes (one is always written when the render completes).
pub const CHECKPOINT_INTERVAL_S: f64 = 30.0;

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            spp: 16,
            time_limit: None,
            target_error: None,
            seed: 0,
            threads: None,
            pt: PtSettings::default(),
            progress: false,
            shard: (0, 1),
            resume: None,
            checkpoint: None,
        }
    }
}

/// What a render produced.
#[derive(Clone, Debug)]
pub struct RenderResult {
    /// Accumulated layers.
    pub film: Film,
    /// Camera distance of the first hit along the pixel-centre ray (infinity for misses).
    pub depth: Vec<f32>,
    /// Method-specific AOV channels (e.g. `trace_depth.Y`).
    pub extra: Vec<crate::film::Channel>,
    /// The render was stopped by [`crate::render::interrupt`] before its budget was spent.
    pub interrupted: bool,
    /// Samples per pixel actually taken.
    pub spp: u32,
    /// Wall-clock seconds spent rendering (excluding scene loading).
    pub seconds: f64,
    /// Threads used.
    pub threads: usize,
}

/// One sample of pixel (x, y): jittered camera ray, fresh hero wavelengths, one path.
#[inline]
fn sample_pixel(scene: &Scene, camera: &Camera, opts: &RenderOptions, x: u32, y: u32, s: u32, acc: &mut PixelSum) {
    let index = y as u64 * camera.width() as u64 + x as u64;
    let mut sampler = Sampler::new(opts.seed, index, s as u64);
    let mut wl = SampledWavelengths::sample_visible(sampler.get_1d());
    let jitter = sampler.get_2d();
    let ray = camera.ray(Vec2::new(x as f32, y as f32) + jitter);
    let l = pt::radiance(scene, ray, &mut wl, &mut sampler, &opts.pt);
    acc.add(&l, &wl);
}

/// Renders `scene` through `camera`.
pub fn render(scene: &Scene, camera: &Camera, opts: &RenderOptions) -> RenderResult {
    let threads = opts.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    pool.install(|| render_in_pool(scene, camera, opts, threads))
}

fn render_in_pool(scene: &Scene, camera: &Camera, opts: &RenderOptions, threads: usize) -> RenderResult {
    let (w, h) = (camera.width(), camera.height());
    let start = Instant::now();
    let (mut film, mut done) = match &opts.resume {
        Some(st) => (st.film.clone(), st.done),
        None => (Film::new(w, h), 0u32),
    };
    let mut last_checkpoint = Instant::now();
    // this shard's samples: global indices shard_k + shard_n * s below the requested count
    let (shard_k, shard_n) = (opts.shard.0, opts.shard.1.max(1));
    let spp_total = opts.spp.max(1).saturating_sub(shard_k).div_ceil(shard_n).max(1);
    let bar = progress_bar(opts.progress, w as u64 * h as u64 * spp_total as u64);
    let mut pass = 1u32;
    let mut interrupted = false;
    while done < spp_total {
        let n = pass.min(spp_total - done);
        film.pixels.par_chunks_mut(w as usize).enumerate().for_each(|(y, row)| {
            // an interrupted pass leaves the remaining rows with fewer samples: every pixel is
            // the mean of its own samples, so the image stays valid
            if crate::render::interrupt::requested() {
                return;
            }
            for (x, acc) in row.iter_mut().enumerate() {
                for s in done..done + n {
                    sample_pixel(scene, camera, opts, x as u32, y as u32, shard_k + shard_n * s, acc);
                }
            }
            if let Some(b) = &bar {
                b.inc(w as u64 * n as u64);
            }
        });
        done += n;
        if crate::render::interrupt::requested() {
            // `spp` counts the samples every pixel has; the interrupted pass gave some pixels more
            // (`spp.Y` has the exact counts)
            done -= n;
            interrupted = true;
            break;
        }
        if opts.target_error.is_some_and(|e| film.estimated_rel_error() <= e) {
            break;
        }
        if let Some((path, fingerprint)) = &opts.checkpoint
            && last_checkpoint.elapsed().as_secs_f64() >= CHECKPOINT_INTERVAL_S
        {
            write_checkpoint(path, *fingerprint, &film, done);
            last_checkpoint = Instant::now();
        }
        let elapsed = start.elapsed().as_secs_f64();
        if let Some(limit) = opts.time_limit {
            let per_spp = elapsed / done as f64;
            if elapsed + per_spp >= limit {
                break;
            }
            // next pass: as many samples as fit in the remaining time, at most doubling
            pass = (((limit - elapsed) / per_spp) as u32).clamp(1, done.max(1));
        } else {
            pass = (pass * 2).min(64);
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    // an interrupted pass gave some pixels samples beyond `done`: the last checkpoint stands
    if let Some((path, fingerprint)) = &opts.checkpoint
        && !interrupted
    {
        write_checkpoint(path, *fingerprint, &film, done);
    }
    let depth = depth_pass(scene, camera);
    RenderResult {
        film,
        depth,
        extra: Vec::new(),
        interrupted,
        spp: done,
        seconds: start.elapsed().as_secs_f64(),
        threads,
    }
}

/// Writes a pt checkpoint.
fn write_checkpoint(path: &std::path::Path, fingerprint: u64, film: &Film, done: u32) {
    let state = crate::render::checkpoint::RenderState {
        film: film.clone(),
        done,
        next: done,
        histogram: Vec::new(),
        depth_sum: Vec::new(),
        depth_count: Vec::new(),
        radius_scales: Vec::new(),
    };
    crate::render::checkpoint::save(path, fingerprint, &state);
}

/// A progress bar with ETA on stderr over `total` units of work, or None when `show` is false.
pub(crate) fn progress_bar(show: bool, total: u64) -> Option<ProgressBar> {
    if !show {
        return None;
    }
    let bar = ProgressBar::new(total);
    let style = ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% ETA {eta}")
        .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.enable_steady_tick(Duration::from_millis(200));
    Some(bar)
}

/// Distance to the first surface along each pixel-centre ray (infinity for misses).
pub(crate) fn depth_pass(scene: &Scene, camera: &Camera) -> Vec<f32> {
    let (w, h) = (camera.width(), camera.height());
    (0..w as usize * h as usize)
        .into_par_iter()
        .map(|i| {
            let (x, y) = ((i % w as usize) as f32, (i / w as usize) as f32);
            let ray = camera.ray(Vec2::new(x + 0.5, y + 0.5));
            scene.intersect(&ray).map_or(f32::INFINITY, |si| si.t)
        })
        .collect()
}
