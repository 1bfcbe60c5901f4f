//! The render driver: the one loop every method runs in (Mitsuba 3's `SamplingIntegrator::render`,
//! pbrt-v4's `ImageTileIntegrator::Render`). A method ([`RenderMethod`]) renders *units* —
//! samples per pixel for `pt`, iterations for the bidirectional methods — in passes; the driver
//! owns everything around them: the unit budget of this shard, the time budget and the error target, the
//! interruption (Ctrl-C), the progress bar (plain lines when stderr is no terminal), periodic and final checkpoints (the film plus the
//! method's opaque state), the thread pool and the depth layer. Determinism is the methods'
//! business: every unit has its own random streams and the film sums them in unit order, so a
//! pass's size never changes the image.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use glam::Vec2;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use super::checkpoint::{self, RenderState};
use crate::core::camera::Camera;
use crate::core::scene::Scene;
use crate::film::{Channel, Film, SpectralBins};
use crate::integrator::pass::{PassControl, PassEnd, RenderMethod};

/// Seconds between two checkpoint writes (one is always written when the render completes).
pub const CHECKPOINT_INTERVAL_S: f64 = 30.0;

/// The budget and side conditions of a render.
#[derive(Clone, Debug, Default)]
pub struct DriverOptions {
    /// Units this shard renders at most.
    pub units: u32,
    /// Stop starting new passes after this many seconds (at least one unit always runs).
    pub time_limit: Option<f64>,
    /// Stop once the image's estimated RMS relative error ([`Film::estimated_rel_error`]) is at
    /// most this.
    pub target_error: Option<f64>,
    /// Worker threads (None = all cores).
    pub threads: Option<usize>,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Continue from this state (`--resume`).
    pub resume: Option<RenderState>,
    /// Write checkpoints here, with this resume key (`--checkpoint`).
    pub checkpoint: Option<(PathBuf, checkpoint::ResumeKey)>,
    /// Accumulate the beauty's spectral radiance in these bins (`--spectral-bins`).
    pub spectral: Option<SpectralBins>,
}

/// What a render produced.
#[derive(Clone, Debug)]
pub struct RenderResult {
    /// Accumulated layers.
    pub film: Film,
    /// Camera distance of the first hit along the pixel-centre ray (infinity for misses).
    pub depth: Vec<f32>,
    /// Method-specific AOV channels (e.g. `trace_depth.Y`).
    pub extra: Vec<Channel>,
    /// Method-specific header entries.
    pub header: Vec<(String, String)>,
    /// Problems that did not stop the render (a checkpoint that could not be written: a render
    /// is not lost for it).
    pub warnings: Vec<String>,
    /// The render was stopped by [`super::interrupt`] before its budget was spent.
    pub interrupted: bool,
    /// Units (samples per pixel, iterations) every pixel has.
    pub spp: u32,
    /// Wall-clock seconds spent rendering (excluding scene loading).
    pub seconds: f64,
    /// Threads used.
    pub threads: usize,
}

/// Runs `method` over the image until its budget is spent. Errors only for a checkpoint that
/// does not fit the method (its state fails to restore).
pub fn run(
    method: &mut dyn RenderMethod,
    scene: &Scene,
    camera: &Camera,
    opts: &DriverOptions,
) -> Result<RenderResult, String> {
    let threads = opts.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| format!("thread pool: {e}"))?;
    pool.install(|| run_in_pool(method, scene, camera, opts, threads))
}

fn run_in_pool(
    method: &mut dyn RenderMethod,
    scene: &Scene,
    camera: &Camera,
    opts: &DriverOptions,
    threads: usize,
) -> Result<RenderResult, String> {
    let (w, h) = (camera.width(), camera.height());
    let start = Instant::now();
    let (mut film, mut done) = match &opts.resume {
        Some(st) => {
            method.restore_state(&st.method_state)?;
            (st.film.clone(), st.done)
        }
        None => {
            let film = method.new_film(w, h);
            (if let Some(bins) = opts.spectral { film.with_spectral(bins) } else { film }, 0)
        }
    };
    let total = opts.units.max(1);
    let pixels = w as u64 * h as u64;
    let kind = Progress::of(opts, pixels * total.saturating_sub(done) as u64);
    let unit = method.unit_name();
    let progress = opts.progress.then(|| std::io::stderr().is_terminal()).and_then(|t| t.then(|| kind.bar()));
    // without a terminal (a log file, a batch job): a plain line after the first pass, then
    // every PROGRESS_LINE_INTERVAL_S (the elapsed time of the next line is kept here)
    let mut next_line = (opts.progress && progress.is_none()).then_some(0.0f64);
    let (mut rendered, render_start) = (0u32, Instant::now());
    let inc = |n: u64| {
        if let Some(b) = &progress {
            match kind {
                Progress::Samples(_) => b.inc(n),
                Progress::Time(ms) => b.set_position((render_start.elapsed().as_millis() as u64).min(ms)),
                Progress::Open => b.tick(),
            }
        }
    };
    let control = PassControl { progress: &inc, stop: &super::interrupt::requested };
    let max_pass = method.max_pass().max(1);
    let mut pass = 1u32;
    let mut interrupted = false;
    let mut consistent = true;
    let mut last_checkpoint = Instant::now();
    let mut warnings = Vec::new();
    if done > total {
        warnings.push(format!(
            "the checkpoint already holds {done} units (samples or iterations per pixel) of this render share, more than the {total} asked for: nothing was rendered and the image has all {done} (give a larger count or --time to extend it)"
        ));
    }
    let mut save = |film: &Film, done: u32, method: &dyn RenderMethod| {
        if let Some((path, key)) = &opts.checkpoint {
            let state = RenderState { film: film.clone(), done, method_state: method.save_state() };
            if let Err(e) = checkpoint::write(path, key, &state) {
                warnings.push(format!("checkpoint not written: {e}"));
            }
        }
    };
    while done < total {
        let n = pass.min(total - done);
        let end = method.render_pass(&mut film, done, n, &control);
        if end == PassEnd::Partial {
            interrupted = true;
            consistent = false;
            break;
        }
        done += n;
        rendered += n;
        if let Some(b) = &progress {
            b.set_message(progress_message(done, unit, film.estimated_rel_error(), opts.target_error));
        }
        let elapsed = render_start.elapsed().as_secs_f64();
        if let Some(next) = &mut next_line
            && elapsed >= *next
        {
            *next = elapsed + PROGRESS_LINE_INTERVAL_S;
            let share = match opts.time_limit {
                Some(t) => (elapsed / t).min(1.0),
                None => f64::from(rendered) / f64::from(total.saturating_sub(done - rendered).max(1)),
            };
            eprintln!(
                "{}",
                progress_line(
                    share,
                    elapsed,
                    &progress_message(done, unit, film.estimated_rel_error(), opts.target_error),
                    kind
                )
            );
        }
        if super::interrupt::requested() {
            interrupted = true;
            break;
        }
        if opts.target_error.is_some_and(|e| film.estimated_rel_error() <= e) {
            break;
        }
        if last_checkpoint.elapsed().as_secs_f64() >= CHECKPOINT_INTERVAL_S {
            save(&film, done, &*method);
            last_checkpoint = Instant::now();
        }
        let elapsed = render_start.elapsed().as_secs_f64();
        let per_unit = elapsed / rendered.max(1) as f64;
        if let Some(limit) = opts.time_limit {
            if elapsed + per_unit >= limit {
                break;
            }
            // next pass: as many units as fit in the remaining time, at most doubling
            pass = (((limit - elapsed) / per_unit) as u32).clamp(1, rendered.max(1).min(max_pass));
        } else {
            pass = (pass * 2).min(max_pass);
        }
    }
    if let Some(b) = &progress {
        b.finish_and_clear();
    }
    // after a partial pass the last periodic checkpoint stands
    if consistent {
        save(&film, done, &*method);
    }
    Ok(RenderResult {
        warnings,
        depth: depth_pass(scene, camera),
        extra: method.extra_channels(),
        header: method.header(),
        film,
        interrupted,
        spp: done,
        seconds: start.elapsed().as_secs_f64(),
        threads,
    })
}

/// A progress bar with ETA on stderr over `total` units of work (none unless `show`).
/// What the progress bar measures.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Progress {
    /// Pixel samples of a fixed budget (with an ETA).
    Samples(u64),
    /// Milliseconds of a `--time` budget.
    Time(u64),
    /// No bound known in advance (`--target-error` alone): a spinner with the error reached.
    Open,
}

impl Progress {
    /// The bar of a render with `samples` pixel samples to go under `opts`.
    fn of(opts: &DriverOptions, samples: u64) -> Self {
        match (opts.time_limit, opts.target_error) {
            (Some(t), _) => Progress::Time((t * 1000.0).ceil() as u64),
            (None, Some(_)) => Progress::Open,
            (None, None) => Progress::Samples(samples),
        }
    }

    fn bar(self) -> ProgressBar {
        let (bar, template) = match self {
            Progress::Samples(n) => {
                (ProgressBar::new(n), "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% ETA {eta} {msg}")
            }
            Progress::Time(ms) => {
                (ProgressBar::new(ms), "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% of the time {msg}")
            }
            Progress::Open => (ProgressBar::new_spinner(), "{spinner} [{elapsed_precise}] {msg}"),
        };
        bar.set_style(ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()));
        bar.enable_steady_tick(Duration::from_millis(200));
        bar
    }
}

/// Seconds between two progress lines when stderr is not a terminal (the first comes after the
/// first pass).
const PROGRESS_LINE_INTERVAL_S: f64 = 10.0;

/// The bar's message after a pass: units done, with their unit, and the image's estimated error
/// (against the target when there is one).
fn progress_message(done: u32, unit: &str, error: f64, target: Option<f64>) -> String {
    let error = if error.is_finite() { format!("error {error:.4}") } else { "error not estimated yet".into() };
    match target {
        Some(t) => format!("{done} {unit} done, {error} (target {t})"),
        None => format!("{done} {unit} done, {error}"),
    }
}

/// A plain progress line for logs: the share of the budget done (of the time under `--time`),
/// the time elapsed, the time left where the budget is known, and the bar's message.
fn progress_line(share: f64, elapsed: f64, message: &str, kind: Progress) -> String {
    let left = match kind {
        Progress::Open => String::new(),
        _ if share > 0.0 => format!(", about {:.0} s left", elapsed * (1.0 - share) / share),
        _ => String::new(),
    };
    format!("progress: {:.1}% after {elapsed:.0} s{left}; {message}", 100.0 * share)
}

/// Distance to the first surface along each pixel-centre ray (infinity for misses).
pub fn depth_pass(scene: &Scene, camera: &Camera) -> Vec<f32> {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(time_limit: Option<f64>, target_error: Option<f64>) -> DriverOptions {
        DriverOptions {
            units: 10,
            time_limit,
            target_error,
            threads: None,
            progress: false,
            resume: None,
            checkpoint: None,
            spectral: None,
        }
    }

    #[test]
    fn the_bar_measures_what_bounds_the_render() {
        // --time: the share of the time (the sample cap of an open-ended render is no bound)
        assert_eq!(Progress::of(&opts(Some(2.5), None), 1 << 40), Progress::Time(2500));
        assert_eq!(Progress::of(&opts(Some(1.0), Some(0.01)), 1 << 40), Progress::Time(1000));
        assert_eq!(Progress::of(&opts(None, Some(0.01)), 1 << 40), Progress::Open);
        assert_eq!(Progress::of(&opts(None, None), 640), Progress::Samples(640));
        assert_eq!(
            progress_message(12, "iterations", 0.01234, Some(0.01)),
            "12 iterations done, error 0.0123 (target 0.01)"
        );
        assert_eq!(
            progress_line(0.25, 10.0, "4 samples per pixel done, error 0.1000", Progress::Samples(64)),
            "progress: 25.0% after 10 s, about 30 s left; 4 samples per pixel done, error 0.1000"
        );
        assert!(!progress_line(0.5, 10.0, "m", Progress::Open).contains("left"));
        assert!(progress_message(1, "iterations", f64::INFINITY, None).ends_with("error not estimated yet"));
    }
}
