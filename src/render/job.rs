//! A render job: import a scene file, compile it, render, and write the EXR (and preview).
//! This is the whole data flow of docs/architecture.md §2 in one place:
//! import -> SceneDesc -> compile -> integrate -> film -> EXR.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use quasar_importers::{ImportOptions, SceneDesc, import_scene};

use super::driver::{self, DriverOptions, RenderResult};
use crate::core::camera::Camera;
use crate::core::isa::Isa;
use crate::core::scene::Scene;
use crate::film::outputs::{DEPTH, ILLUMINANCE_LX, ILLUMINANCE_SAMPLES, ILLUMINANCE_STDERR_LX, LUMINANCE_CD};
use crate::film::{Channel, LUMINANCE, SpectralBins};
use crate::integrator::method::{Build, Built, MethodChoice, all_params, instantiate};
use crate::integrator::params::MethodParams;
use crate::output::preview::{Exposure, View, exposure_scale};
use crate::output::{ExrImage, write_exr_atomic, write_preview_png};

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
    /// Method name.
    pub method: Option<String>,
    /// Method parameters (keys of the method table: `cone_deg`, `iterations`, `max_depth`, ...),
    /// over the scene file's.
    pub params: MethodParams,
    /// Render share k of n of the samples / iterations (`--shard K/N`, merged by `quasar merge`).
    pub shard: Option<(u32, u32)>,
    /// Write checkpoints to this file.
    pub checkpoint: Option<PathBuf>,
    /// Continue the render stored in this checkpoint.
    pub resume: Option<PathBuf>,
    /// Microfacet masking-shadowing form (default: the scene's, height-correlated).
    pub masking: Option<quasar_materials::Masking>,
    /// Samples per pixel of the `illuminance.Y` layer (0: none), over the scene's setting.
    pub illuminance_samples: Option<u32>,
    /// Write the beauty's spectral radiance in these bins as `S0.<lambda>nm` channels.
    pub spectral_bins: Option<SpectralBins>,
    /// The auxiliary outputs to write (names of `--aov`), over the scene's `aovs`.
    pub aovs: Option<Vec<String>>,
    /// Rays per pixel of the auxiliary outputs, over the scene's `aov_samples`.
    pub aov_samples: Option<u32>,
    /// Instruction set of the render kernels (None: the best this CPU runs).
    pub isa: Option<Isa>,
}

impl JobOverrides {
    /// These overrides with method parameter `key` set (a key of the method table).
    pub fn with_param(mut self, key: &str, value: impl Into<crate::integrator::params::ParamValue>) -> Self {
        self.params.set(key, value);
        self
    }
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

/// Loads a scene file through the importer registry (its import warnings are in
/// `SceneDesc::warnings`).
pub fn load_scene_with(path: &Path, opts: &ImportOptions) -> Result<SceneDesc> {
    import_scene(path, opts).map_err(|e| anyhow::anyhow!("{e}"))
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
    let choice = match &ov.method {
        Some(m) => MethodChoice::from_name(m).map_err(anyhow::Error::msg)?,
        None => MethodChoice::from_name(&r.method).map_err(|e| match &r.method_place {
            Some(p) => anyhow::anyhow!("{p}: {e}"),
            None => anyhow::anyhow!(e),
        })?,
    };
    let known: Vec<&str> = all_params().iter().map(|p| p.key).collect();
    let params = ov.params.over_scene(&r.params, r.unit, &known).map_err(anyhow::Error::msg)?;

    let aovs = aov_rows(desc, ov)?;
    let isa = ov.isa.unwrap_or_else(Isa::best);
    if !isa.available() {
        bail!("this CPU lacks the instruction set {} asked for", isa.name());
    }
    let mut scene = Scene::compile(desc).context("compiling the scene")?;
    scene.masking = ov.masking.unwrap_or(r.masking);
    let camera = Camera::new(&desc.camera, width, height).with_context(|| desc.source.display().to_string())?;
    let entry = choice.resolve(&scene);
    let spectral_bytes = ov.spectral_bins.map_or(0, |b| 8 * b.count() as u64);
    crate::render::memory::check_memory(
        entry.name,
        entry.bytes_per_pixel + spectral_bytes,
        (width, height),
        crate::render::memory::available_memory(),
    )
    .map_err(anyhow::Error::msg)?;
    let build = Build {
        scene: &scene,
        camera: &camera,
        seed,
        shard,
        spp: if open_ended { ov.spp.unwrap_or(u32::MAX / 2) } else { spp },
        isa,
    };
    // `auto` between the path tracer and a bidirectional method: measured (render/pilot.rs),
    // unless the command line sets a parameter the path tracer does not read, or the render
    // resumes a checkpoint (whose method the resume key names)
    let pt_reads_params = instantiate(&crate::integrator::pt::PT, &params, &build).is_ok();
    let pilot = if choice == MethodChoice::Auto
        && entry.name != crate::integrator::pt::PT.name
        && pt_reads_params
        && ov.resume.is_none()
    {
        let budget = if open_ended { u32::MAX } else { spp };
        Some(
            crate::render::pilot::choose(
                &crate::integrator::pt::PT,
                entry,
                &params,
                &scene,
                &camera,
                seed,
                isa,
                shard,
                budget,
                ov.threads,
                ov.spectral_bins,
            )
            .map_err(anyhow::Error::msg)?,
        )
    } else {
        None
    };
    let entry = pilot.as_ref().map_or(entry, |p| p.entry);
    let Built { mut method, units } = instantiate(entry, &params, &build).map_err(anyhow::Error::msg)?;
    // what must match for a resume: the scene and every setting but the sample budget (the
    // scene is hashed only when checkpoints are used: it walks the whole scene description)
    let resume_key = if ov.resume.is_some() || ov.checkpoint.is_some() {
        let budget = "iterations";
        let mut budgetless = params.clone();
        budgetless.remove(budget);
        let mut key = vec![
            ("scene".to_string(), format!("{:016x}", crate::render::checkpoint::Fingerprint::of(&[desc]))),
            ("method".into(), entry.name.to_string()),
            ("size".into(), format!("{width}x{height}")),
            ("seed".into(), seed.to_string()),
            ("shard".into(), format!("{}/{}", shard.0, shard.1)),
            ("masking".into(), scene.masking.name().to_string()),
        ];
        if let Some(b) = ov.spectral_bins {
            key.push(("spectral_bins".into(), spectral_description(&b)));
        }
        key.extend(budgetless.entries());
        // a setting left at its default is keyed by the default, so that a checkpoint is not
        // resumed by a build whose default differs (the radius reduction alpha changed once);
        // a value given equal to the default matches it
        for p in entry.params.iter().filter(|p| p.key != budget && !params.contains(p.key)) {
            key.push((p.key.to_string(), p.default.to_string()));
        }
        crate::render::checkpoint::ResumeKey(key)
    } else {
        Default::default()
    };
    let pilot_seconds = pilot.as_ref().map_or(0.0, |p| p.seconds);
    let resume = match &ov.resume {
        None => pilot.as_ref().and_then(|p| p.resume.clone()),
        Some(p) => {
            let st = crate::render::checkpoint::read(p, &resume_key).map_err(anyhow::Error::msg)?;
            if (st.film.width, st.film.height) != (width, height) {
                bail!("{}: checkpoint of a {}x{} render", p.display(), st.film.width, st.film.height);
            }
            Some(st)
        }
    };
    let opts = DriverOptions {
        // this shard's units: global indices shard_k + shard_n * j below the requested count
        units: units.max(1).saturating_sub(shard.0).div_ceil(shard.1).max(1),
        // the pilots' time is the render's: a --time budget covers both
        time_limit: time_s.map(|t| (t - pilot_seconds).max(0.0)),
        target_error,
        threads: ov.threads,
        progress,
        resume,
        checkpoint: ov.checkpoint.clone().map(|p| (p, resume_key)),
        spectral: ov.spectral_bins,
    };
    // the scene's content without the places it was read from (a render of the same scene from
    // another directory has the same one), so that `quasar merge` can refuse unrelated renders
    let scene_fingerprint = {
        let materials: Vec<_> = desc.materials.iter().map(|m| (&m.material, &m.textures)).collect();
        let meshes: Vec<_> = desc
            .meshes
            .iter()
            .map(|m| (&m.positions, &m.normals, &m.uvs, &m.indices, m.material, &m.emission))
            .collect();
        let textures: Vec<_> =
            desc.textures.iter().map(|t| (t.width, t.height, &t.texels, &t.wrap_u, &t.wrap_v)).collect();
        crate::render::checkpoint::Fingerprint::of(&[&materials, &meshes, &textures, &desc.lights, &desc.camera])
    };
    let mut result = driver::run(method.as_mut(), &scene, &camera, &opts).map_err(anyhow::Error::msg)?;
    result.seconds += pilot_seconds;
    drop(method);
    if scene.lights.is_empty() {
        result.warnings.push(format!(
            "{}: the scene has no light (no emissive surface, light or environment), so the image is black: add a [[light]] (e.g. type = \"environment\") or an emissive material, or render with --default-light env",
            desc.source.display()
        ));
    } else if result.film.pixels.iter().all(|p| p.sum_y(crate::film::Quantity::Beauty) == 0.0) {
        result.warnings.push(format!(
            "{}: the image is black (every pixel 0): the camera sees no lit surface and no light",
            desc.source.display()
        ));
    } else if !desc.meshes.is_empty() && result.depth.iter().all(|d| !d.is_finite()) {
        result.warnings.push(format!(
            "{}: the camera sees none of the scene's geometry (every pixel-centre ray misses): check [camera]",
            desc.source.display()
        ));
    }
    let unit_name = if entry.params.iter().any(|p| p.key == "iterations") { "iterations" } else { "spp" };
    let estimated = result.film.estimated_rel_error();
    let target_reached = target_error.map(|e| estimated <= e);
    if let (Some(e), Some(false)) = (target_error, target_reached) {
        let stop = if result.interrupted {
            "the render was interrupted"
        } else if time_s.is_some() {
            "the time limit came first"
        } else {
            "the sample budget came first"
        };
        result.warnings.push(format!(
            "target error {e} not reached: the estimated error is {estimated:.6} after {} {unit_name} ({stop})",
            result.spp
        ));
    }
    let mut channels = result.film.channels();
    // photometric luminance: 683 lm/W x integral of L ybar = LUMINANCE_PER_Y x Y (docs/photometry.md)
    let luminance = channels.iter().find(|c| c.name == LUMINANCE).map(|c| {
        let values = c.values.iter().map(|&y| y * quasar_importers::photometric::LUMINANCE_PER_Y).collect();
        Channel { name: LUMINANCE_CD.into(), values }
    });
    channels.extend(luminance);
    let illuminance_samples = ov.illuminance_samples.unwrap_or(r.illuminance_samples);
    let mut illuminance_taken = None;
    if illuminance_samples > 0 {
        let (values, stderr, taken) =
            crate::render::sensors::illuminance_pass(&scene, &camera, illuminance_samples, seed, shard);
        channels.push(Channel { name: ILLUMINANCE_LX.into(), values });
        channels.push(Channel { name: ILLUMINANCE_STDERR_LX.into(), values: stderr });
        illuminance_taken = Some(taken);
    }
    let mut aov_header = Vec::new();
    if !aovs.is_empty() {
        let objects: Vec<String> = desc.meshes.iter().map(|m| m.name.clone()).collect();
        let names = crate::render::aovs::IdNames { materials: &scene.material_names, objects: &objects };
        let samples = ov.aov_samples.unwrap_or(r.aov_samples).max(1);
        let (aov_channels, entries) = crate::render::aovs::aov_pass(&scene, &camera, &names, &aovs, samples, seed);
        channels.extend(aov_channels);
        aov_header = entries;
    }
    channels.push(Channel { name: DEPTH.into(), values: result.depth.clone() });
    channels.extend(result.extra.iter().cloned());
    let mut header = vec![
        ("software".into(), concat!("quasar ", env!("CARGO_PKG_VERSION")).to_string()),
        ("scene".into(), desc.source.display().to_string()),
        ("scene_fingerprint".into(), format!("{scene_fingerprint:016x}")),
        ("method".into(), entry.name.to_string()),
        ("method_requested".into(), choice.name().to_string()),
        ("spp".into(), result.spp.to_string()),
        ("seed".into(), seed.to_string()),
        ("masking".into(), scene.masking.name().to_string()),
        ("width".into(), width.to_string()),
        ("height".into(), height.to_string()),
        ("wavelengths".into(), "hero, 4 per path, 360-830 nm, visible-importance pdf".into()),
        (
            "units".into(),
            "R,G,B: linear sRGB (D65); XYZ.*: CIE 1931 XYZ; both scaled so that a spectrally flat radiance of 1 gives Y = 1; luminance.Y: cd/m^2 = 72983 x Y, absolute when the scene's lights are in absolute units (photometric files, glTF/USD photometric lights, radiometric scales in W)".into(),
        ),
        ("partial".into(), result.interrupted.to_string()),
        ("shard".into(), format!("{}/{}", shard.0, shard.1)),
        ("rejected_samples".into(), result.film.rejected_samples().to_string()),
        ("target_error".into(), target_error.map_or("none".into(), |e| e.to_string())),
        ("target_error_reached".into(), target_reached.map_or("none".into(), |r| r.to_string())),
        ("estimated_rel_error".into(), format!("{estimated:.6}")),
        ("threads".into(), result.threads.to_string()),
        ("isa".into(), isa.name().to_string()),
        ("render_time_s".into(), format!("{:.3}", result.seconds)),
    ];
    if unit_name == "iterations" {
        header.push(("iterations".into(), result.spp.to_string()));
    }
    if let Some(n) = illuminance_taken {
        header.push((ILLUMINANCE_SAMPLES.into(), n.to_string()));
    }
    if let Some(b) = ov.spectral_bins {
        header.push(("spectral_bins".into(), spectral_description(&b)));
        header.push((
            "spectral_units".into(),
            "S0.*: mean spectral radiance of the beauty over each bin, in the scene's radiance units per nm (W m^-2 sr^-1 nm^-1 when its lights are absolute), named after the bin centre".into(),
        ));
    }
    if let Some(p) = &pilot {
        header.push(("auto_pilot".into(), p.report.clone()));
    }
    header.extend(result.header.iter().cloned());
    header.extend(aov_header);
    let image = ExrImage { width: width as usize, height: height as usize, channels, metadata: header };
    Ok(JobOutput { image, result })
}

/// The rows of the auxiliary outputs asked for (`--aov` over the scene's `aovs`), in the output
/// table's order; an unknown name is an error naming where it was given and the known ones.
fn aov_rows(desc: &SceneDesc, ov: &JobOverrides) -> Result<Vec<&'static crate::film::outputs::OutputGroup>> {
    use crate::film::outputs::{OUTPUTS, aov_names, aov_row};
    let (names, place) = match &ov.aovs {
        Some(list) => (list, "--aov".to_string()),
        None => (
            &desc.render.aovs,
            desc.render.aovs_place.as_ref().map_or_else(|| "[render] aovs".into(), |p| format!("{p}: `render.aovs`")),
        ),
    };
    for n in names {
        if aov_row(n).is_none() {
            bail!("{place}: unknown output '{n}' (known: {})", aov_names().join(", "));
        }
    }
    Ok(OUTPUTS.iter().filter(|r| r.aov.is_some_and(|a| names.iter().any(|n| n == a))).collect())
}

/// The bins as the header and the resume key state them: `N x D nm over MIN:MAX nm`.
fn spectral_description(b: &SpectralBins) -> String {
    let (min, max) = b.range_nm();
    format!("{} x {} nm over {min}:{max} nm", b.count(), b.width_nm())
}

/// Writes the EXR (atomically) and an optional PNG preview with automatic exposure and the
/// filmic view.
pub fn write_outputs(out: &JobOutput, exr: &Path, preview: Option<&PathBuf>) -> Result<()> {
    write_outputs_with_preview(out, exr, preview, Exposure::Auto, View::default())
}

/// Where a render with spectral bins (`--spectral-bins`) writes them: `<stem>.spectral.exr`
/// beside the image, a complete image (every layer and the `S0.<lambda>nm` channels of the
/// spectral layout) that spectral tools and `quasar merge` read, while the image itself keeps
/// only the standard layers (and names the spectral file in its `spectral_file` header entry).
pub fn spectral_file_path(exr: &Path) -> PathBuf {
    let stem = exr.file_stem().map_or_else(|| "out".into(), |s| s.to_string_lossy().into_owned());
    exr.with_file_name(format!("{stem}.spectral.exr"))
}

/// [`write_outputs`] with the preview's exposure and view transform given
/// (`crate::output::preview`).
pub fn write_outputs_with_preview(
    out: &JobOutput,
    exr: &Path,
    preview: Option<&PathBuf>,
    exposure: Exposure,
    view: View,
) -> Result<()> {
    let spectral = out.image.channels.iter().any(|c| SpectralBins::is_channel(&c.name));
    if spectral {
        // the spectral bins in a file of their own, the standard layers readable everywhere
        // (Blender refuses a whole file whose one layer has more than 24 channels)
        let side = spectral_file_path(exr);
        write_exr_atomic(&out.image, &side)?;
        let mut main = out.image.clone();
        main.channels.retain(|c| !SpectralBins::is_channel(&c.name));
        let name = side.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        main.metadata.push(("spectral_file".into(), name));
        write_exr_atomic(&main, exr)?;
    } else {
        write_exr_atomic(&out.image, exr)?;
    }
    if let Some(p) = preview {
        let img = &out.image;
        let get = |n: &str| img.channel(n).context("beauty channel missing");
        let scale = exposure_scale(exposure, get(LUMINANCE)?);
        write_preview_png(p, img.width as u32, img.height as u32, [get("R")?, get("G")?, get("B")?], scale, view)
            .map_err(|e| anyhow::anyhow!(e))?;
    }
    Ok(())
}
