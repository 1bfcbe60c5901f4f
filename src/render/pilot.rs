//! `auto`'s measured choice (docs/architecture.md §7.6): where the scene analysis finds narrow
//! or specular surfaces, the bidirectional method can reach an error many times sooner than the
//! path tracer, or several times later (an open scene whose light the path tracer's light
//! sampling reaches directly). So both render a short pilot of the same image, and `auto` keeps
//! the one whose measured error times work is smaller.
//!
//! The choice must be the same on every machine, thread count and shard (shards of one render
//! are merged; a resumed render must equal the uninterrupted one), so the work is counted, not
//! timed: rays traced ([`crate::core::scene::rays_traced_by_this_thread`], summed over the
//! pool), which both methods' cost is made of; the pilot's units are those of the unsharded
//! render (units 0..k of share 0/1), and its random streams are the render's own. The score of
//! a method is its pilot's relative MSE, the mean over pixels of stderr² / (d² + 1e-3) (the
//! race's measure), times the rays it traced: the inverse of the relative MSE one ray's worth of
//! the method buys. Both are divided by the same level d per pixel: the bidirectional pilot's
//! mean image averaged over the pixel's 5x5 neighbourhood. Never the path tracer's own mean: a
//! firefly raises a pixel's mean with its variance, so a pixel's own level hides the heavy tail
//! that makes the path tracer slow on the scenes the bidirectional methods are for (a median or
//! an average of both pilots did the same: on the benchmark family they put the path tracer
//! ahead where it is 9-600x behind). The photon estimate spreads every light path over a disk,
//! so its early image is the smooth one; where its own noise raises d, it lowers both methods'
//! scores alike. The pilot of the chosen method
//! becomes the render's first units (as a resumed checkpoint would), unless the render is a
//! shard of several.

use std::time::Instant;

use super::checkpoint::RenderState;
use crate::core::camera::Camera;
use crate::core::isa::Isa;
use crate::core::scene::{Scene, rays_traced_by_this_thread};
use crate::film::{Film, Quantity, REL_EPS, SpectralBins};
use crate::integrator::method::{Build, MethodEntry, instantiate};
use crate::integrator::params::MethodParams;
use crate::integrator::pass::{PassControl, PassEnd};

/// Samples per pixel of the path tracer's pilot. Where the path tracer's error is a rare firefly
/// (the shipped lightguide: its pilot's relMSE ranged 0.055-790 over seeds), a pilot that draws
/// none looks as good as the photon method's and wins; 16 spp did so on 4 seeds of 24 there,
/// 32 spp on 1 (BENCHMARKS.md, "The fix and what it bought"). The pilot is the render's first
/// units where `pt` wins, so the doubling costs only where the bidirectional method wins.
pub const PILOT_SPP: u32 = 32;
/// Iterations of the bidirectional method's pilot.
pub const PILOT_ITERATIONS: u32 = 8;
/// How much lower the bidirectional method's score must be for `auto` to choose it. Its pilot
/// measures the variance of its first iterations, whose gather radii are the largest; the radii
/// shrink as the render goes on (docs/architecture.md §7.4 step 4), the variance of the photon
/// estimate grows with them, and a look-up or a visibility point costs work that is no ray.
/// Calibrated on the benchmark family (BENCHMARKS.md, "The family"): the smallest factor for
/// which no scene's `auto` is slower to relMSE 0.01 than `pt`.
pub const BIDIR_MARGIN: f64 = 2.0;

/// What one method's pilot measured.
#[derive(Clone, Debug)]
pub struct PilotRun {
    /// The method.
    pub entry: &'static MethodEntry,
    /// Units rendered.
    pub units: u32,
    /// Relative MSE of the pilot image ([`relative_mse`]), set by [`choose`].
    pub rel_mse: f64,
    /// Rays traced.
    pub rays: u64,
    /// rel_mse x rays: lower is better; set by [`choose`].
    pub score: f64,
    /// The pilot's film and the method's state after it.
    state: RenderState,
}

/// The outcome of [`choose`].
pub struct PilotChoice {
    /// The method the render runs.
    pub entry: &'static MethodEntry,
    /// Its pilot as the render's first units (None for a shard of several).
    pub resume: Option<RenderState>,
    /// Wall-clock seconds the pilots took (part of the render's time).
    pub seconds: f64,
    /// What each pilot measured, for the header (`auto_pilot`).
    pub report: String,
}

/// Renders `units` units of `entry`'s method into a fresh film with `threads` threads, counting
/// the rays traced.
#[allow(clippy::too_many_arguments)]
fn pilot(
    entry: &'static MethodEntry,
    params: &MethodParams,
    scene: &Scene,
    camera: &Camera,
    seed: u64,
    isa: Isa,
    units: u32,
    spectral: Option<SpectralBins>,
    pool: &rayon::ThreadPool,
) -> Result<PilotRun, String> {
    let build = Build { scene, camera, seed, shard: (0, 1), spp: units, isa };
    let mut method = instantiate(entry, params, &build).map_err(|e| e.to_string())?.method;
    let film = method.new_film(camera.width(), camera.height());
    let mut film: Film = if let Some(b) = spectral { film.with_spectral(b) } else { film };
    let rays = || pool.broadcast(|_| rays_traced_by_this_thread()).iter().sum::<u64>();
    let before = rays();
    let control = PassControl { progress: &|_| {}, stop: &|| false };
    let step = method.max_pass().max(1);
    pool.install(|| {
        let mut done = 0;
        while done < units {
            let n = step.min(units - done);
            let end = method.render_pass(&mut film, done, n, &control);
            debug_assert_eq!(end, PassEnd::Complete);
            done += n;
        }
    });
    let rays = rays() - before;
    let state = RenderState { film, done: units, method_state: method.save_state() };
    Ok(PilotRun { entry, units, rel_mse: f64::NAN, rays, score: f64::NAN, state })
}

/// The mean over pixels of `film`'s squared standard error of the beauty luminance divided by
/// d² + 1e-3 (the race's relative MSE, `quasar compare`), d the pixel's entry of `levels`.
fn relative_mse(film: &Film, levels: &[f64]) -> f64 {
    let sum: f64 = film
        .pixels
        .iter()
        .zip(levels)
        .map(|(p, d)| {
            let e = p.stderr(Quantity::Beauty);
            e * e / (d * d + REL_EPS)
        })
        .sum();
    sum / film.pixels.len().max(1) as f64
}

/// Per pixel, the mean of `film`'s mean luminance over the pixel's 5x5 neighbourhood (fewer
/// at the image's edges), at least 0.
fn smoothed_levels(film: &Film) -> Vec<f64> {
    let mean: Vec<f64> = film.pixels.iter().map(|p| p.sum_y(Quantity::Beauty) / p.samples.max(1) as f64).collect();
    let w = film.width as usize;
    let h = mean.len() / w.max(1);
    (0..mean.len())
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let (ys, xs) = (y.saturating_sub(2)..(y + 3).min(h), x.saturating_sub(2)..(x + 3).min(w));
            let n = ys.len() * xs.len();
            let sum: f64 = ys.flat_map(|yy| xs.clone().map(move |xx| yy * w + xx)).map(|j| mean[j]).sum();
            (sum / n as f64).max(0.0)
        })
        .collect()
}

/// Chooses between `pt` and `bidir` by their pilots (module doc) for a render of `budget` units
/// in share `shard`; each pilot renders at most `budget` units.
#[allow(clippy::too_many_arguments)]
pub fn choose(
    pt: &'static MethodEntry,
    bidir: &'static MethodEntry,
    params: &MethodParams,
    scene: &Scene,
    camera: &Camera,
    seed: u64,
    isa: Isa,
    shard: (u32, u32),
    budget: u32,
    threads: Option<usize>,
    spectral: Option<SpectralBins>,
) -> Result<PilotChoice, String> {
    let start = Instant::now();
    let threads = threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| format!("thread pool: {e}"))?;
    let budget = budget.max(2);
    let mut p = pilot(pt, params, scene, camera, seed, isa, PILOT_SPP.min(budget), spectral, &pool)?;
    let mut b = pilot(bidir, params, scene, camera, seed, isa, PILOT_ITERATIONS.min(budget), spectral, &pool)?;
    let levels = smoothed_levels(&b.state.film);
    for r in [&mut p, &mut b] {
        r.rel_mse = relative_mse(&r.state.film, &levels);
        r.score = r.rel_mse * r.rays as f64;
    }
    let bidir_wins = b.score.is_finite() && (!p.score.is_finite() || b.score * BIDIR_MARGIN < p.score);
    let report = [&p, &b]
        .iter()
        .map(|r| {
            format!("{} {} units relMSE {:.3e} rays {} score {:.3e}", r.entry.name, r.units, r.rel_mse, r.rays, r.score)
        })
        .collect::<Vec<_>>()
        .join("; ");
    let winner = if bidir_wins { b } else { p };
    Ok(PilotChoice {
        entry: winner.entry,
        resume: (shard == (0, 1)).then_some(winner.state),
        seconds: start.elapsed().as_secs_f64(),
        report: format!("{report}; chose {} (bidirectional margin {BIDIR_MARGIN})", winner.entry.name),
    })
}
