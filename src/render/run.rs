//! The middle step of a render job: `auto`'s pilot where it measures a choice
//! (render/pilot.rs), the checkpoint to resume and its key, and the method's passes under the
//! driver (budgets, shards, checkpoints, interruption).

use anyhow::{Result, bail};

use super::driver::{self, DriverOptions, RenderResult};
use super::overrides::JobOverrides;
use super::prepare::PreparedJob;
use crate::film::SpectralBins;
use crate::integrator::method::{Build, Built, MethodChoice, MethodEntry, instantiate};

/// What [`run`] rendered: the driver's result, the method that rendered it and `auto`'s pilot.
pub struct RenderRun {
    /// The film, the depth pass, the method's channels and header, warnings and statistics.
    pub result: RenderResult,
    /// The method that rendered.
    pub entry: &'static MethodEntry,
    /// `auto`'s pilot report (None without a pilot).
    pub pilot_report: Option<String>,
}

/// Renders a prepared job: `auto`'s pilot where it measures a choice, the checkpoint to resume,
/// and the method's passes under the driver (budgets, shards, checkpoints, interruption).
pub fn run(job: &PreparedJob<'_>, ov: &JobOverrides, progress: bool) -> Result<RenderRun> {
    let (scene, camera, params) = (&job.scene, &job.camera, &job.params);
    let (seed, shard, isa, choice, entry) = (job.seed, job.shard, job.isa, job.choice, job.entry);
    let (spp, open_ended, time_s, (width, height)) = (job.spp, job.open_ended, job.time_s, job.size);
    let build =
        Build { scene, camera, seed, shard, spp: if open_ended { ov.spp.unwrap_or(u32::MAX / 2) } else { spp }, isa };
    // `auto` between the path tracer and a bidirectional method: measured (render/pilot.rs),
    // unless the command line sets a parameter the path tracer does not read, or the render
    // resumes a checkpoint (whose method the resume key names), or the budget is one unit (no
    // variance to measure: the analysis's choice stands)
    let pt_reads_params = instantiate(&crate::integrator::pt::PT, params, &build).is_ok();
    let pilot = if choice == MethodChoice::Auto
        && entry.name != crate::integrator::pt::PT.name
        && pt_reads_params
        && ov.resume.is_none()
        && (open_ended || spp >= 2)
    {
        let budget = if open_ended { u32::MAX } else { spp };
        Some(
            crate::render::pilot::choose(
                &crate::integrator::pt::PT,
                entry,
                params,
                scene,
                camera,
                seed,
                isa,
                shard,
                budget,
                ov.threads,
                job.spectral_bins,
            )
            .map_err(anyhow::Error::msg)?,
        )
    } else {
        None
    };
    let entry = pilot.as_ref().map_or(entry, |p| p.entry);
    let Built { mut method, units } = instantiate(entry, params, &build).map_err(anyhow::Error::msg)?;
    // what must match for a resume: the scene's content (the fingerprint `merge` checks too)
    // and every setting but the sample budget
    let resume_key = if ov.resume.is_some() || ov.checkpoint.is_some() {
        let budget = "iterations";
        let mut budgetless = params.clone();
        budgetless.remove(budget);
        let mut key = vec![
            ("scene".to_string(), format!("{:016x}", job.fingerprint)),
            ("method".into(), entry.name.to_string()),
            ("size".into(), format!("{width}x{height}")),
            ("seed".into(), seed.to_string()),
            ("shard".into(), format!("{}/{}", shard.0, shard.1)),
            ("masking".into(), scene.masking().name().to_string()),
        ];
        if let Some(b) = job.spectral_bins {
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
        target_error: job.target_error,
        threads: ov.threads,
        progress,
        resume,
        checkpoint: ov.checkpoint.clone().map(|p| (p, resume_key)),
        spectral: job.spectral_bins,
    };
    // the scene's content without the places it was read from (a render of the same scene from
    // another directory has the same one), so that `quasar merge` can refuse unrelated renders
    let mut result = driver::run(method.as_mut(), scene, camera, &opts).map_err(anyhow::Error::msg)?;
    result.seconds += pilot_seconds;
    Ok(RenderRun { result, entry, pilot_report: pilot.map(|p| p.report) })
}

/// The bins as the header and the resume key state them: `N x D nm over MIN:MAX nm`.
pub(super) fn spectral_description(b: &SpectralBins) -> String {
    let (min, max) = b.range_nm();
    format!("{} x {} nm over {min}:{max} nm", b.count(), b.width_nm())
}
