//! A render job: import a scene file, then prepare (render/prepare.rs: settings validated, the
//! scene compiled once), run (here: `auto`'s pilot, the checkpoint, the driver) and assemble
//! (render/assemble.rs: channels, header, warnings), and write the EXR (and preview).
//! This is the whole data flow of docs/architecture.md §2 in one place:
//! import -> SceneDesc -> compile -> integrate -> film -> EXR.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use quasar_importers::{ImportOptions, SceneDesc, import_scene};

pub use super::assemble::JobOutput;
use super::assemble::assemble;
pub use super::overrides::JobOverrides;
use super::prepare::prepare;
use super::run::run;
use crate::film::{LUMINANCE, SpectralBins};
use crate::output::preview::{Exposure, View, exposure_scale};
use crate::output::{write_exr_atomic, write_preview_png};

/// Loads a scene file through the importer registry (default options).
pub fn load_scene(path: &Path) -> Result<SceneDesc> {
    load_scene_with(path, &ImportOptions::default())
}

/// Loads a scene file through the importer registry (its import warnings are in
/// `SceneDesc::warnings`).
pub fn load_scene_with(path: &Path, opts: &ImportOptions) -> Result<SceneDesc> {
    import_scene(path, opts).map_err(|e| anyhow::anyhow!("{e}"))
}

/// Renders a scene description with overrides applied: [`prepare`] (settings validated, the
/// scene compiled), [`run`] (the method's passes), [`assemble`] (channels and header).
pub fn render_desc(desc: &SceneDesc, ov: &JobOverrides, progress: bool) -> Result<JobOutput> {
    let job = prepare(desc, ov)?;
    let run = run(&job, ov, progress)?;
    Ok(assemble(job, run))
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
