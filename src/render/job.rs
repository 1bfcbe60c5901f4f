//! A render job: import a scene file, compile it, render, and write the EXR (and preview).
//! This is the whole data flow of DESIGN.md section 1 in one place:
//! import -> SceneDesc -> compile -> integrate -> film -> EXR.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use quasar_importers::{ImportOptions, SceneDesc, import_scene};

use crate::core::camera::Camera;
use crate::core::scene::Scene;
use crate::film::Channel;
use crate::integrator::PtSettings;
use crate::integrator::bidir::{self, GatherDepth, VismapRun};
use crate::integrator::method::{BidirectionalOptions, Method, bidirectional_settings};
use crate::output::{ExrImage, write_exr_atomic, write_preview_png};
use crate::render::driver::{RenderOptions, RenderResult, render};

/// Settings that override the scene file's `[render]` table (None = keep the scene's).
#[derive(Clone, Debug, Default)]
pub struct JobOverrides {
    /// Image width.
    pub width: Option<u32>,
    /// Image height.
    pub height: Option<u32>,
    /// Samples per pixel.
    pub spp: Option<u32>,
    /// Time budget in seconds.
    pub time_s: Option<f64>,
    /// Stop at this estimated RMS relative error of the image (or at the time budget or sample
    /// cap, whichever comes first).
    pub target_error: Option<f64>,
    /// Seed.
    pub seed: Option<u64>,
    /// Threads.
    pub threads: Option<usize>,
    /// Maximum path depth.
    pub max_depth: Option<u32>,
    /// Method name.
    pub method: Option<String>,
    /// Settings of the bidirectional methods.
    pub bidir: BidirectionalOptions,
    /// Render share k of n of the samples / iterations (`--shard K/N`, merged by `quasar merge`).
    pub shard: Option<(u32, u32)>,
    /// Write checkpoints to this file.
    pub checkpoint: Option<PathBuf>,
    /// Continue the render stored in this checkpoint.
    pub resume: Option<PathBuf>,
    /// Microfacet masking-shadowing form (default: the scene's, height-correlated).
    pub masking: Option<quasar_materials::Masking>,
}

/// A finished render with everything needed to write it.
pub struct JobOutput {
    /// The rendered image with metadata.
    pub image: ExrImage,
    /// The raw render result.
    pub result: RenderResult,
}

/// Loads a scene file through the importer registry (default options).
pub fn load_scene(path: &Path) -> Result<SceneDesc> {
    load_scene_with(path, &ImportOptions::default())
}

/// Loads a scene file through the importer registry and prints its import warnings to stderr.
pub fn load_scene_with(path: &Path, opts: &ImportOptions) -> Result<SceneDesc> {
    let desc = import_scene(path, opts).map_err(|e| anyhow::anyhow!("{e}"))?;
    for w in &desc.warnings {
        eprintln!("warning: {w}");
    }
    Ok(desc)
}

/// Renders a scene description with overrides applied.
pub fn render_desc(desc: &SceneDesc, ov: &JobOverrides, progress: bool) -> Result<JobOutput> {
    let r = &desc.render;
    let width = ov.width.unwrap_or(r.width);
    let height = ov.height.unwrap_or(r.height);
    if width == 0 || height == 0 || width > 65_536 || height > 65_536 || width as u64 * height as u64 > 1 << 28 {
        bail!("image size {width}x{height} is out of range (1..=65536 per side, at most 2^28 pixels)");
    }
    let spp = ov.spp.unwrap_or(r.spp).max(1);
    let time_s = ov.time_s.or(if ov.spp.is_some() { None } else { r.time_s });
    if let Some(t) = time_s
        && !(t > 0.0 && t.is_finite())
    {
        bail!("time budget must be a positive number of seconds, got {t}");
    }
    let shard = ov.shard.unwrap_or((0, 1));
    if shard.1 == 0 || shard.0 >= shard.1 {
        bail!("shard {}/{} is out of range (K/N with 0 <= K < N)", shard.0, shard.1);
    }
    let target_error = ov.target_error.or(r.target_error);
    if let Some(e) = target_error
        && !(e > 0.0 && e.is_finite())
    {
        bail!("target error must be a positive number, got {e}");
    }
    // with a time budget or an error target, the sample (iteration) count is only a cap
    let open_ended = time_s.is_some() || target_error.is_some();
    let seed = ov.seed.unwrap_or(r.seed);
    let max_depth = ov.max_depth.or(r.max_depth);
    let method = Method::from_name(ov.method.as_deref().unwrap_or(&r.method))?;

    let mut scene = Scene::compile(desc).context("compiling the scene")?;
    scene.masking = ov.masking.unwrap_or(r.masking);
    let camera = Camera::new(&desc.camera, width, height).with_context(|| desc.source.display().to_string())?;
    let resolved = method.resolve(&scene);
    let bidir = if resolved.is_bidirectional() {
        // command-line options override the scene's `[render]` ones that apply to the method
        let options = ov.bidir.or(&BidirectionalOptions::from_scene(&r.bidirectional).applicable_to(resolved));
        Some(bidirectional_settings(resolved, &options, if open_ended { ov.spp.unwrap_or(u32::MAX / 2) } else { spp })?)
    } else if ov.bidir.any() {
        bail!(
            "the bidirectional options (--iterations, --photons-per-iteration, --gather-depth, ...) do not apply to {}",
            resolved.name()
        );
    } else {
        None
    };
    // what must match for a resume: the scene and every setting but the sample budget (hashed
    // only when checkpoints are used: it walks the whole scene description)
    let fingerprint = if ov.resume.is_some() || ov.checkpoint.is_some() {
        let bidir_fp = bidir.map(|mut v| {
            v.iterations = 0;
            format!("{v:?}")
        });
        crate::render::checkpoint::Fingerprint::of(&[
            desc,
            &resolved.name(),
            &(width, height, seed, max_depth, shard, scene.masking),
            &bidir_fp,
        ])
    } else {
        0
    };
    let resume = match &ov.resume {
        Some(p) => {
            let st = crate::render::checkpoint::read(p, fingerprint).map_err(anyhow::Error::msg)?;
            if (st.film.width, st.film.height) != (width, height) {
                bail!("{}: checkpoint of a {}x{} render", p.display(), st.film.width, st.film.height);
            }
            Some(st)
        }
        None => None,
    };
    let checkpoint = ov.checkpoint.clone().map(|p| (p, fingerprint));
    let opts = RenderOptions {
        spp: if open_ended { ov.spp.unwrap_or(u32::MAX / 2) } else { spp },
        time_limit: time_s,
        target_error,
        shard,
        seed,
        threads: ov.threads,
        pt: PtSettings { max_depth, ..PtSettings::default() },
        progress,
        resume: resume.clone(),
        checkpoint: checkpoint.clone(),
    };
    let threads = opts.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let mut metadata = Vec::new();
    let result = match bidir {
        Some(v) => {
            let run = VismapRun { seed, time_limit: time_s, target_error, progress, shard, resume, checkpoint };
            let (result, stats) = bidir::render(&scene, &camera, &v, &run, threads);
            let depth = match v.depth {
                GatherDepth::Fixed(d) => d.to_string(),
                GatherDepth::Adaptive { max_depth, paper } => {
                    format!(
                        "adaptive (0..={max_depth}, {})",
                        if paper { "paper variant" } else { "earlier iterations" }
                    )
                }
            };
            metadata.extend([
                ("iterations".to_string(), result.spp.to_string()),
                (
                    "photons_per_iteration".into(),
                    v.photons_per_iteration.unwrap_or(width as u64 * height as u64).to_string(),
                ),
                ("photons".into(), stats.photons.to_string()),
                ("gather_depth".into(), depth),
                ("cone_deg".into(), v.cone_deg.map_or("none".into(), |c| c.to_string())),
                (
                    "radius".into(),
                    v.radius.map_or(format!("auto ({} pixel footprints)", v.radius_pixels), |r| r.to_string()),
                ),
                ("caustic_radius_ratio".into(), v.caustic_ratio.to_string()),
                ("alpha".into(), v.alpha.to_string()),
            ]);
            result
        }
        None => render(&scene, &camera, &opts),
    };
    let mut channels = result.film.channels();
    channels.push(Channel { name: "depth.Z".into(), values: result.depth.clone() });
    channels.extend(result.extra.iter().cloned());
    let mut header = vec![
        ("software".into(), concat!("quasar ", env!("CARGO_PKG_VERSION")).to_string()),
        ("scene".into(), desc.source.display().to_string()),
        ("method".into(), resolved.name().to_string()),
        ("method_requested".into(), method.name().to_string()),
        ("spp".into(), result.spp.to_string()),
        ("seed".into(), seed.to_string()),
        ("max_depth".into(), max_depth.map_or("unbounded".into(), |d| d.to_string())),
        ("masking".into(), scene.masking.name().to_string()),
        ("width".into(), width.to_string()),
        ("height".into(), height.to_string()),
        ("wavelengths".into(), "hero, 4 per path, 360-830 nm, visible-importance pdf".into()),
        ("units".into(), "XYZ normalised so a flat spectral radiance of 1 gives Y = 1".into()),
        ("partial".into(), result.interrupted.to_string()),
        ("shard".into(), format!("{}/{}", shard.0, shard.1)),
        ("rejected_samples".into(), result.film.rejected_samples().to_string()),
        ("target_error".into(), target_error.map_or("none".into(), |e| e.to_string())),
        ("estimated_rel_error".into(), format!("{:.6}", result.film.estimated_rel_error())),
        ("threads".into(), result.threads.to_string()),
        ("render_time_s".into(), format!("{:.3}", result.seconds)),
    ];
    header.extend(metadata);
    let metadata = header;
    let image = ExrImage { width: width as usize, height: height as usize, channels, metadata };
    Ok(JobOutput { image, result })
}

/// Writes the EXR (atomically) and an optional PNG preview.
pub fn write_outputs(out: &JobOutput, exr: &Path, preview: Option<&PathBuf>) -> Result<()> {
    write_outputs_with_exposure(out, exr, preview, 0.0)
}

/// [`write_outputs`] with the preview scaled by 2^`exposure` (photometric scenes, e.g. glTF
/// lights in candela, have small radiometric values; see docs/gltf.md).
pub fn write_outputs_with_exposure(
    out: &JobOutput,
    exr: &Path,
    preview: Option<&PathBuf>,
    exposure: f32,
) -> Result<()> {
    write_exr_atomic(&out.image, exr)?;
    if let Some(p) = preview {
        let img = &out.image;
        let get = |n: &str| img.channel(n).context("beauty channel missing");
        write_preview_png(p, img.width as u32, img.height as u32, [get("R")?, get("G")?, get("B")?], exposure)
            .map_err(|e| anyhow::anyhow!(e))?;
    }
    Ok(())
}
