//! A render job: import a scene file, compile it, render, and write the EXR (and preview).
//! This is the whole data flow of DESIGN.md section 1 in one place:
//! import -> SceneDesc -> compile -> integrate -> film -> EXR.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use quasar_importers::{ImportOptions, SceneDesc, import_scene};

use crate::camera::Camera;
use crate::film::Channel;
use crate::integrator::PtSettings;
use crate::integrator::vismap::{self, VismapRun, VismapSettings};
use crate::output::{ExrImage, write_exr_atomic, write_preview_png};
use crate::render::{RenderOptions, RenderResult, render};
use crate::scene::Scene;

/// Integration methods the renderer offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Scene analysis picks the method (DESIGN.md 3.5); with only `pt` implemented, it picks `pt`.
    Auto,
    /// Reference path tracer.
    Pt,
    /// Bidirectional tracing with visibility maps at a fixed gather depth.
    Vismap,
}

impl Method {
    /// Parses a method name.
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "auto" => Ok(Self::Auto),
            "pt" => Ok(Self::Pt),
            "vismap" => Ok(Self::Vismap),
            "adaptive" | "quasi" | "adaptive+quasi" => {
                bail!("method '{name}' is not available in this build yet (available: auto, pt, vismap)")
            }
            _ => bail!("unknown method '{name}' (expected auto, pt, vismap, adaptive, quasi or adaptive+quasi)"),
        }
    }

    /// The method actually run.
    pub fn resolve(self, _scene: &Scene) -> Self {
        match self {
            Self::Auto => Self::Pt,
            m => m,
        }
    }

    /// Name as written in headers.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Pt => "pt",
            Self::Vismap => "vismap",
        }
    }
}

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
    /// Seed.
    pub seed: Option<u64>,
    /// Threads.
    pub threads: Option<usize>,
    /// Maximum path depth.
    pub max_depth: Option<u32>,
    /// Method name.
    pub method: Option<String>,
    /// `vismap`: iterations (default: the scene's spp).
    pub iterations: Option<u32>,
    /// `vismap`: photons per iteration (default: one per pixel).
    pub photons_per_iteration: Option<u64>,
    /// `vismap`: gather depth.
    pub gather_depth: Option<u32>,
    /// `vismap`: initial gather radius in scene units (default: from the pixel footprint).
    pub radius: Option<f32>,
    /// `vismap`: radius reduction alpha.
    pub alpha: Option<f32>,
}

/// A finished render with everything needed to write it.
pub struct JobOutput {
    /// The rendered image with metadata.
    pub image: ExrImage,
    /// The raw render result.
    pub result: RenderResult,
}

/// Loads a scene file through the importer registry.
pub fn load_scene(path: &Path) -> Result<SceneDesc> {
    import_scene(path, &ImportOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))
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
    let seed = ov.seed.unwrap_or(r.seed);
    let max_depth = ov.max_depth.or(r.max_depth);
    let method = Method::from_name(ov.method.as_deref().unwrap_or(&r.method))?;

    let vismap_cfg = if method == Method::Vismap {
        Some(vismap_settings(ov, if time_s.is_some() { u32::MAX / 2 } else { spp })?)
    } else if vismap_flags_given(ov) {
        bail!("--iterations, --photons-per-iteration, --gather-depth, --radius and --alpha apply to --method vismap");
    } else {
        None
    };
    let scene = Scene::compile(desc).context("compiling the scene")?;
    let camera = Camera::new(&desc.camera, width, height).with_context(|| desc.source.display().to_string())?;
    let resolved = method.resolve(&scene);
    let opts = RenderOptions {
        // with a time budget, spp is only a cap
        spp: if time_s.is_some() { ov.spp.unwrap_or(u32::MAX / 2) } else { spp },
        time_limit: time_s,
        seed,
        threads: ov.threads,
        pt: PtSettings { max_depth, ..PtSettings::default() },
        progress,
    };
    let threads = opts.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let mut metadata = Vec::new();
    let result = match (resolved, vismap_cfg) {
        (Method::Vismap, Some(v)) => {
            let run = VismapRun { seed, time_limit: time_s, progress };
            let (result, stats) = vismap::render(&scene, &camera, &v, &run, threads);
            metadata.extend([
                ("iterations".to_string(), result.spp.to_string()),
                (
                    "photons_per_iteration".into(),
                    v.photons_per_iteration.unwrap_or(width as u64 * height as u64).to_string(),
                ),
                ("photons".into(), stats.photons.to_string()),
                ("gather_depth".into(), v.gather_depth.to_string()),
                (
                    "radius".into(),
                    v.radius.map_or(format!("auto ({} pixel footprints)", v.radius_pixels), |r| r.to_string()),
                ),
                ("caustic_radius_ratio".into(), v.caustic_ratio.to_string()),
                ("alpha".into(), v.alpha.to_string()),
            ]);
            result
        }
        _ => render(&scene, &camera, &opts),
    };
    let mut channels = result.film.channels();
    channels.push(Channel { name: "depth.Z".into(), values: result.depth.clone() });
    let mut header = vec![
        ("software".into(), concat!("quasar ", env!("CARGO_PKG_VERSION")).to_string()),
        ("scene".into(), desc.source.display().to_string()),
        ("method".into(), resolved.name().to_string()),
        ("method_requested".into(), method.name().to_string()),
        ("spp".into(), result.spp.to_string()),
        ("seed".into(), seed.to_string()),
        ("max_depth".into(), max_depth.map_or("unbounded".into(), |d| d.to_string())),
        ("width".into(), width.to_string()),
        ("height".into(), height.to_string()),
        ("wavelengths".into(), "hero, 4 per path, 360-830 nm, visible-importance pdf".into()),
        ("units".into(), "XYZ normalised so a flat spectral radiance of 1 gives Y = 1".into()),
        ("rejected_samples".into(), result.film.rejected_samples().to_string()),
        ("threads".into(), result.threads.to_string()),
        ("render_time_s".into(), format!("{:.3}", result.seconds)),
    ];
    header.extend(metadata);
    let metadata = header;
    let image = ExrImage { width: width as usize, height: height as usize, channels, metadata };
    Ok(JobOutput { image, result })
}

fn vismap_flags_given(ov: &JobOverrides) -> bool {
    ov.iterations.is_some()
        || ov.photons_per_iteration.is_some()
        || ov.gather_depth.is_some()
        || ov.radius.is_some()
        || ov.alpha.is_some()
}

/// `vismap` settings from the overrides; iterations default to the scene's spp.
fn vismap_settings(ov: &JobOverrides, spp: u32) -> Result<VismapSettings> {
    let mut v = VismapSettings { iterations: ov.iterations.unwrap_or(spp).max(1), ..VismapSettings::default() };
    if let Some(n) = ov.photons_per_iteration {
        if n == 0 || n > 1 << 32 {
            bail!("--photons-per-iteration must be in 1..=2^32, got {n}");
        }
        v.photons_per_iteration = Some(n);
    }
    if let Some(d) = ov.gather_depth {
        if d > 64 {
            bail!("--gather-depth must be in 0..=64, got {d}");
        }
        v.gather_depth = d;
    }
    if let Some(r) = ov.radius {
        if !(r > 0.0 && r.is_finite()) {
            bail!("--radius must be a positive length, got {r}");
        }
        v.radius = Some(r);
    }
    if let Some(a) = ov.alpha {
        if !(a > 0.0 && a < 1.0) {
            bail!("--alpha must be in (0, 1), got {a}");
        }
        v.alpha = a;
    }
    Ok(v)
}

/// Writes the EXR (atomically) and an optional PNG preview.
pub fn write_outputs(out: &JobOutput, exr: &Path, preview: Option<&PathBuf>) -> Result<()> {
    write_exr_atomic(&out.image, exr)?;
    if let Some(p) = preview {
        let img = &out.image;
        let get = |n: &str| img.channel(n).context("beauty channel missing");
        write_preview_png(p, img.width as u32, img.height as u32, [get("R")?, get("G")?, get("B")?], 0.0)
            .map_err(|e| anyhow::anyhow!(e))?;
    }
    Ok(())
}
