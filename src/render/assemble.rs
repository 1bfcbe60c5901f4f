//! The last step of a render job: the warnings a user needs (no light, a black image, a camera
//! that sees nothing, an error target missed), the channels (the film's, photometry, the
//! illuminance pass, the auxiliary outputs, the depth pass, the method's) and the header
//! (render/header.rs).

use super::driver::RenderResult;
use super::prepare::PreparedJob;
use super::run::{RenderRun, spectral_description};
use crate::core::scene::Scene;
use crate::film::outputs::{DEPTH, ILLUMINANCE_LX, ILLUMINANCE_SAMPLES, ILLUMINANCE_STDERR_LX, LUMINANCE_CD};
use crate::film::{Channel, LUMINANCE};
use crate::output::ExrImage;

/// A finished render with everything needed to write it.
pub struct JobOutput {
    /// The rendered image with metadata.
    pub image: ExrImage,
    /// The raw render result.
    pub result: RenderResult,
    /// The compiled scene it rendered (for the sensors, which measure the same scene).
    pub scene: Scene,
}

/// The image of a finished render: channels, header and warnings.
pub fn assemble(job: PreparedJob<'_>, run: RenderRun) -> JobOutput {
    let RenderRun { mut result, entry, .. } = run;
    let (desc, scene, camera) = (job.desc, &job.scene, &job.camera);
    let (width, height) = job.size;
    let (target_error, time_s) = (job.target_error, job.time_s);
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
    let mut illuminance_taken = None;
    if job.illuminance_samples > 0 {
        let (values, stderr, taken) =
            crate::render::sensors::illuminance_pass(scene, camera, job.illuminance_samples, job.seed, job.shard);
        channels.push(Channel { name: ILLUMINANCE_LX.into(), values });
        channels.push(Channel { name: ILLUMINANCE_STDERR_LX.into(), values: stderr });
        illuminance_taken = Some(taken);
    }
    let mut aov_header = Vec::new();
    if !job.aovs.is_empty() {
        let objects: Vec<String> = desc.meshes.iter().map(|m| m.name.clone()).collect();
        let names = crate::render::aovs::IdNames { materials: &scene.material_names, objects: &objects };
        let (aov_channels, entries) =
            crate::render::aovs::aov_pass(scene, camera, &names, &job.aovs, job.aov_samples, job.seed);
        channels.extend(aov_channels);
        aov_header = entries;
    }
    channels.push(Channel { name: DEPTH.into(), values: result.depth.clone() });
    channels.extend(result.extra.iter().cloned());
    let mut header = vec![
        ("software".into(), concat!("quasar ", env!("CARGO_PKG_VERSION")).to_string()),
        ("scene".into(), desc.source.display().to_string()),
        ("scene_fingerprint".into(), format!("{:016x}", job.fingerprint)),
        ("method".into(), entry.name.to_string()),
        ("method_requested".into(), job.choice.name().to_string()),
        ("spp".into(), result.spp.to_string()),
        ("seed".into(), job.seed.to_string()),
        ("masking".into(), scene.masking().name().to_string()),
        ("width".into(), width.to_string()),
        ("height".into(), height.to_string()),
        ("wavelengths".into(), "hero, 4 per path, 360-830 nm, visible-importance pdf".into()),
        (
            "units".into(),
            "R,G,B: linear sRGB (D65); XYZ.*: CIE 1931 XYZ; both scaled so that a spectrally flat radiance of 1 gives Y = 1; luminance.Y: cd/m^2 = 72983 x Y, absolute when the scene's lights are in absolute units (photometric files, glTF/USD photometric lights, radiometric scales in W)".into(),
        ),
        ("partial".into(), result.interrupted.to_string()),
        ("shard".into(), format!("{}/{}", job.shard.0, job.shard.1)),
        ("rejected_samples".into(), result.film.rejected_samples().to_string()),
        ("target_error".into(), target_error.map_or("none".into(), |e| e.to_string())),
        ("target_error_reached".into(), target_reached.map_or("none".into(), |r| r.to_string())),
        ("estimated_rel_error".into(), format!("{estimated:.6}")),
        ("threads".into(), result.threads.to_string()),
        ("isa".into(), job.isa.name().to_string()),
        ("render_time_s".into(), format!("{:.3}", result.seconds)),
    ];
    if unit_name == "iterations" {
        header.push(("iterations".into(), result.spp.to_string()));
    }
    if let Some(n) = illuminance_taken {
        header.push((ILLUMINANCE_SAMPLES.into(), n.to_string()));
    }
    if let Some(b) = job.spectral_bins {
        header.push(("spectral_bins".into(), spectral_description(&b)));
        header.push((
            "spectral_units".into(),
            "S0.*: mean spectral radiance of the beauty over each bin, in the scene's radiance units per nm (W m^-2 sr^-1 nm^-1 when its lights are absolute), named after the bin centre".into(),
        ));
    }
    if let Some(report) = run.pilot_report {
        header.push(("auto_pilot".into(), report));
    }
    header.extend(result.header.iter().cloned());
    header.extend(aov_header);
    let image = ExrImage { width: width as usize, height: height as usize, channels, metadata: header };
    JobOutput { image, result, scene: job.scene }
}
