//! The first step of a render job (docs/architecture.md §2): the scene's `[render]` settings
//! under the command line's, validated once; the method chosen and its parameters read; the
//! memory checked; the scene compiled once (the render, the sensors and the auxiliary outputs
//! all use this one [`Scene`]) and its content fingerprinted once (merge and resume keys).

use anyhow::{Context, Result, bail};
use quasar_importers::SceneDesc;

use super::overrides::JobOverrides;
use crate::core::camera::Camera;
use crate::core::isa::Isa;
use crate::core::scene::Scene;
use crate::film::SpectralBins;
use crate::film::outputs::{OUTPUTS, OutputGroup, aov_names, aov_row};
use crate::integrator::entry::MethodEntry;
use crate::integrator::method::{MethodChoice, all_params};
use crate::integrator::params::MethodParams;

/// A render job whose settings are validated and whose scene is compiled: what
/// [`super::run::run`] renders and [`super::assemble`] writes out.
pub struct PreparedJob<'d> {
    /// The scene description.
    pub desc: &'d SceneDesc,
    /// The compiled scene (its masking form the command line's over the scene's).
    pub scene: Scene,
    /// The camera at the image size.
    pub camera: Camera,
    /// Image width and height.
    pub size: (u32, u32),
    /// Samples per pixel (iterations) asked for; a cap when the render is open-ended.
    pub spp: u32,
    /// Time budget in seconds.
    pub time_s: Option<f64>,
    /// Estimated-error target.
    pub target_error: Option<f64>,
    /// The sample count is only a cap (a time budget or an error target bounds the render).
    pub open_ended: bool,
    /// Seed of the random streams.
    pub seed: u64,
    /// Share K of N of the samples.
    pub shard: (u32, u32),
    /// Instruction set of the render kernels.
    pub isa: Isa,
    /// The method asked for (`auto` among them).
    pub choice: MethodChoice,
    /// The method `choice` resolves to by the scene analysis (`auto`'s pilot may pick `pt`).
    pub entry: &'static MethodEntry,
    /// The method parameters, command line over scene file.
    pub params: MethodParams,
    /// Samples per pixel of the illuminance layer (0: none).
    pub illuminance_samples: u32,
    /// The auxiliary outputs asked for, in the output table's order.
    pub aovs: Vec<&'static OutputGroup>,
    /// Rays per pixel of the auxiliary outputs.
    pub aov_samples: u32,
    /// Spectral bins of the beauty.
    pub spectral_bins: Option<SpectralBins>,
    /// The scene's content without the places it was read from (a render of the same scene from
    /// another directory has the same one): `quasar merge` refuses images of other scenes and a
    /// checkpoint of another scene is not resumed.
    pub fingerprint: u64,
}

/// Validates the settings of a render of `desc` under `ov` and compiles the scene.
pub fn prepare<'d>(desc: &'d SceneDesc, ov: &JobOverrides) -> Result<PreparedJob<'d>> {
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
    let scene = Scene::compile_with_masking(desc, ov.masking.unwrap_or(r.masking)).context("compiling the scene")?;
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
    Ok(PreparedJob {
        desc,
        scene,
        camera,
        size: (width, height),
        spp,
        time_s,
        target_error,
        // with a time budget or an error target, the sample (iteration) count is only a cap
        open_ended: time_s.is_some() || target_error.is_some(),
        seed: ov.seed.unwrap_or(r.seed),
        shard,
        isa,
        choice,
        entry,
        params,
        illuminance_samples: ov.illuminance_samples.unwrap_or(r.illuminance_samples),
        aovs,
        aov_samples: ov.aov_samples.unwrap_or(r.aov_samples).max(1),
        spectral_bins: ov.spectral_bins,
        fingerprint: content_fingerprint(desc),
    })
}

/// The fingerprint of what `desc` renders: materials, meshes, textures, lights and camera,
/// without the files and lines they were read from.
fn content_fingerprint(desc: &SceneDesc) -> u64 {
    let materials: Vec<_> = desc.materials.iter().map(|m| (&m.material, &m.textures)).collect();
    let meshes: Vec<_> = desc
        .meshes
        .iter()
        .map(|m| (&m.positions, &m.normals, &m.uvs, &m.colors, &m.indices, m.material, &m.emission))
        .collect();
    let textures: Vec<_> = desc.textures.iter().map(|t| (t.width, t.height, &t.texels, &t.wrap_u, &t.wrap_v)).collect();
    crate::render::checkpoint::Fingerprint::of(&[&materials, &meshes, &textures, &desc.lights, &desc.camera])
}

/// The rows of the auxiliary outputs asked for (`--aov` over the scene's `aovs`), in the output
/// table's order; an unknown name is an error naming where it was given and the known ones.
fn aov_rows(desc: &SceneDesc, ov: &JobOverrides) -> Result<Vec<&'static OutputGroup>> {
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
