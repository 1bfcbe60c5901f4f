//! `quasar render`: its arguments (the method parameters as one flag each, from the method
//! table) and the run.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Arg, ArgAction, ArgMatches, Args, Command, FromArgMatches};
use quasar::film::SpectralBins;
use quasar::integrator::method::{METHODS, all_params, method_names, users_of};
use quasar::integrator::params::{MethodParams, ParamKind};
use quasar::output::false_colour::{ColourScale, FalseColour};
use quasar::output::preview::{Exposure, View};
use quasar::render::default_light::{DefaultLight, add_default_light};
use quasar::render::job::{JobOverrides, render_desc, write_outputs_with_preview};
use quasar_importers::ImportOptions;
use quasar_materials::spectrum::{LAMBDA_MAX, LAMBDA_MIN};

use super::parse::{
    IsaArg, parse_exposure, parse_isa, parse_masking, parse_method, parse_positive, parse_range, parse_shard,
    parse_threads, parse_time_code, parse_units, same_file,
};

/// The arguments of `quasar render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// Scene file: quasar TOML (.toml), OBJ (.obj), glTF (.gltf, .glb) or USD (.usd, .usda,
    /// .usdc, .usdz).
    pub scene: PathBuf,
    /// Output EXR (default: the scene's name with .exr, in the current directory).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Integration method (default: the scene's, else auto).
    #[arg(long, long_help = method_help(), value_parser = parse_method)]
    pub method: Option<String>,
    /// Render through the scene file's camera of this name (a glTF or USD camera, or one of a
    /// TOML scene's included files; `quasar info` lists them) instead of the scene camera.
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,
    /// Samples per pixel (at least 1).
    #[arg(long, conflicts_with = "time", value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: Option<u32>,
    /// Render for this many seconds instead of a fixed sample count.
    #[arg(long, value_parser = parse_positive)]
    pub time: Option<f64>,
    /// Stop when the estimated RMS relative error of the image (sqrt of the mean over pixels
    /// of stderr^2 / (Y^2 + 1e-3)) is at most this, or at --time, whichever comes first.
    #[arg(long, value_parser = parse_positive)]
    pub target_error: Option<f64>,
    /// Image width in pixels.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    pub height: Option<u32>,
    /// Worker threads (default, and 0: all cores; at most 4 per core).
    #[arg(long, value_parser = parse_threads)]
    pub threads: Option<usize>,
    /// Seed of the random streams.
    #[arg(long)]
    pub seed: Option<u64>,
    #[command(flatten)]
    pub params: MethodArgs,
    /// Render share K of N (0 <= K < N) of the samples or iterations, with streams disjoint
    /// from the other shares; `quasar merge` combines the shards into the full render.
    #[arg(long, value_parser = parse_shard)]
    pub shard: Option<(u32, u32)>,
    /// Write the accumulated state to this file periodically and at the end.
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Continue the render stored in this checkpoint (same scene and settings; a larger
    /// --spp / --iterations or a new --time extends it).
    #[arg(long)]
    pub resume: Option<PathBuf>,
    /// Add the `illuminance.Y` layer (lux at the first surface of each pixel-centre ray) with N
    /// samples per pixel (default: the scene's `illuminance_samples`, else no layer).
    #[arg(long, value_name = "N")]
    pub illuminance_samples: Option<u32>,
    /// Also write the beauty's spectral radiance in N equal bins as `S0.<lambda>nm` channels
    /// (the OpenEXR spectral layout of Fichet et al. 2021, as pbrt-v4 writes it; 1 to 940) into
    /// `<stem>.spectral.exr` beside the image, a complete image with every layer; the image
    /// itself keeps the standard layers only, so that every EXR reader opens it.
    #[arg(long, value_name = "N")]
    pub spectral_bins: Option<u32>,
    /// Auxiliary outputs, comma-separated (over the scene's `aovs`): normal, normal_geometric,
    /// position, albedo, material_id, object_id, crypto_material, crypto_object (Cryptomatte);
    /// the README's channel table says what each holds.
    #[arg(long = "aov", value_name = "NAME,...", value_delimiter = ',')]
    pub aovs: Option<Vec<String>>,
    /// Rays per pixel of the auxiliary outputs (default: the scene's `aov_samples`, else 16).
    #[arg(long, value_name = "N")]
    pub aov_samples: Option<u32>,
    /// Wavelength range MIN:MAX in nm of --spectral-bins (default 360:830, the sampled range).
    #[arg(long, value_name = "MIN:MAX", value_parser = parse_range, requires = "spectral_bins")]
    pub spectral_range: Option<(f64, f64)>,
    /// A uniform white environment of luminance 1 beside the scene's lights: `auto` (default)
    /// adds it only to a scene without light (glTF and OBJ models often have none), with a
    /// warning; `env` adds it to every scene; `none` never (a scene without light renders black,
    /// with a warning).
    #[arg(long, default_value = "auto", value_parser = DefaultLight::from_name)]
    pub default_light: DefaultLight,
    /// Exposure of the PNG preview: `auto` (default: the log-average luminance becomes mid-grey
    /// 0.18) or stops EV (the image is scaled by 2^EV; 0 shows the values as they are).
    #[arg(long, default_value = "auto", allow_negative_numbers = true, value_parser = parse_exposure)]
    pub exposure: Exposure,
    /// View transform of the PNG preview: `filmic` (default: hue-preserving curve, bright colours
    /// bleach to white) or `standard` (each channel clipped to 1).
    #[arg(long, default_value = "filmic", value_parser = View::from_name)]
    pub view: View,
    /// Also write a tone-mapped PNG preview.
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Also write a false-colour PNG with a legend of `luminance` (cd/m², the luminance.Y layer)
    /// or `illuminance` (lx, the illuminance.Y layer: needs --illuminance-samples) as
    /// `<stem>.<quantity>.png` beside the EXR.
    #[arg(long, value_name = "QUANTITY", value_parser = ["luminance", "illuminance"])]
    pub false_colour: Option<String>,
    /// Scale of the false-colour maps (this flag's and the sensor grids'): `log` or `linear`
    /// (default: log for --false-colour, linear for sensor grids).
    #[arg(long, value_parser = ColourScale::from_name)]
    pub false_colour_scale: Option<ColourScale>,
    /// Value range MIN:MAX of the --false-colour map (default: fitted to the image).
    #[arg(long, value_parser = parse_range)]
    pub false_colour_range: Option<(f64, f64)>,
    /// Let glTF files refer to files by absolute paths or outside their folder.
    #[arg(long)]
    pub allow_external_paths: bool,
    /// Extra length unit of the scene file (m, cm, mm, in, ft, or a factor in metres), e.g.
    /// `--units mm` for a glTF exported in millimetres (applies on top of a TOML `units`).
    #[arg(long, value_parser = parse_units)]
    pub units: Option<f32>,
    /// The USD time code animated attributes and transforms are read at (default: the earliest
    /// time sample).
    #[arg(long, value_parser = parse_time_code)]
    pub time_code: Option<f64>,
    /// Instruction set of the render kernels: auto (default: x86-64-v3 where the CPU has AVX2
    /// and FMA, else the portable baseline), baseline or x86-64-v3. Both give the same image.
    #[arg(long, value_name = "ISA", default_value = "auto", value_parser = parse_isa)]
    pub isa: IsaArg,
    /// Microfacet masking-shadowing of the GGX materials: height-correlated (default) or
    /// separable (Mitsuba 3's and pbrt-v3's form, for comparisons with them).
    #[arg(long, value_parser = parse_masking)]
    pub masking: Option<quasar_materials::Masking>,
    /// Do not show a progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// The method parameters: one flag per parameter of the method table.
#[derive(Clone, Debug, Default)]
pub struct MethodArgs(pub MethodParams);

impl FromArgMatches for MethodArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut p = MethodParams::default();
        for spec in all_params() {
            match spec.kind {
                ParamKind::Bool => {
                    if m.get_flag(spec.key) {
                        p.set(spec.key, true);
                    }
                }
                ParamKind::Int { .. } => {
                    if let Some(v) = m.get_one::<i128>(spec.key) {
                        p.set(spec.key, *v);
                    }
                }
                ParamKind::Real { .. } | ParamKind::Length => {
                    if let Some(v) = m.get_one::<f64>(spec.key) {
                        p.set(spec.key, *v);
                    }
                }
            }
        }
        Ok(Self(p))
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl Args for MethodArgs {
    fn augment_args(cmd: Command) -> Command {
        all_params().into_iter().fold(cmd, |cmd, spec| {
            let help = format!("{}: {} (default: {})", users_of(spec.key).join(", "), spec.doc, spec.default);
            let arg = Arg::new(spec.key).long(spec.flag).help(help);
            cmd.arg(match spec.kind {
                ParamKind::Bool => arg.action(ArgAction::SetTrue),
                ParamKind::Int { .. } => arg.value_parser(clap::value_parser!(i128)).allow_negative_numbers(true),
                ParamKind::Real { .. } | ParamKind::Length => {
                    arg.value_parser(clap::value_parser!(f64)).allow_negative_numbers(true)
                }
            })
        })
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

/// `--method` values and their summaries, for the help text.
pub fn method_help() -> String {
    let mut s = format!(
        "Integration method: {} (auto: pt for diffuse scenes; otherwise short pilots of pt and quasi, and the one with the lower relative error per ray continues).",
        method_names().join(" | ")
    );
    for m in METHODS {
        s += &format!("\n  {}: {}", m.name, m.summary);
    }
    s
}

/// Runs `quasar render`: exit code 0, or [`super::EXIT_PARTIAL`] when it was interrupted and
/// wrote the partial image.
pub fn render(args: RenderArgs) -> Result<ExitCode> {
    let RenderArgs {
        scene,
        allow_external_paths,
        units,
        time_code,
        output,
        method,
        camera,
        spp,
        time,
        target_error,
        width,
        height,
        threads,
        isa,
        seed,
        params,
        shard,
        checkpoint,
        resume,
        masking,
        illuminance_samples,
        aovs,
        aov_samples,
        spectral_bins,
        spectral_range,
        default_light,
        preview,
        false_colour,
        false_colour_scale,
        false_colour_range,
        exposure,
        view,
        quiet,
    } = args;
    let mut desc = super::load(&scene, &ImportOptions { allow_external_paths, units_scale: units, time_code })?;
    if let Some(name) = &camera {
        desc.use_camera(name).map_err(anyhow::Error::msg)?;
    }
    if let Some(w) = add_default_light(&mut desc, default_light) {
        eprintln!("warning: {w}");
    }
    let spectral_bins = match spectral_bins {
        Some(n) => {
            let (min, max) = spectral_range.unwrap_or((LAMBDA_MIN as f64, LAMBDA_MAX as f64));
            Some(SpectralBins::new(n, min as f32, max as f32).map_err(anyhow::Error::msg)?)
        }
        None => None,
    };
    super::interrupt::install_handler();
    let ov = JobOverrides {
        width,
        height,
        spp,
        time_s: time,
        target_error,
        seed,
        threads,
        method,
        params: params.0,
        shard,
        checkpoint,
        resume,
        masking,
        illuminance_samples,
        spectral_bins,
        aovs,
        aov_samples,
        isa: isa.0,
    };
    let exr = output.unwrap_or_else(|| {
        PathBuf::from(scene.file_stem().map_or("out".into(), |s| s.to_string_lossy().into_owned()) + ".exr")
    });
    // every output is checked before the render, so that none fails after it
    let exr_is_stream = check_output(&scene, &exr, "exr", "-o")?;
    if let Some(p) = &preview {
        check_output(&scene, p, "png", "--preview")?;
    }
    if let Some(p) = &ov.checkpoint {
        check_output(&scene, p, "", "--checkpoint")?;
    }
    // the files written beside the image need a folder to be written in
    let beside = |path: PathBuf, flag: &str, what: &str| -> Result<()> {
        if exr_is_stream {
            anyhow::bail!(
                "{flag} writes {what} beside the image, and {} is a device or a pipe: give -o a file path",
                exr.display()
            );
        }
        check_output(&scene, &path, "", flag).map(drop)
    };
    if ov.spectral_bins.is_some() {
        beside(quasar::render::job::spectral_file_path(&exr), "--spectral-bins", "its bins")?;
    }
    if let Some(q) = &false_colour {
        beside(exr.with_file_name(format!("{}.{q}.png", file_stem(&exr))), "--false-colour", "its PNG")?;
    }
    let sensors_written = !desc.sensors.is_empty() && !exr_is_stream;
    if !desc.sensors.is_empty() && exr_is_stream {
        eprintln!(
            "warning: {}: the scene's sensor readings are written beside the image, and {} is a device or a pipe: they are not written",
            scene.display(),
            exr.display()
        );
    }
    if sensors_written {
        for sensor in &desc.sensors {
            check_output(&scene, &sensor_csv_path(&exr, &sensor.name), "", "the sensor readings")?;
        }
    }
    let false_colour_map = match false_colour.as_deref() {
        Some(q) => {
            let (layer, title) = if q == "luminance" {
                (quasar::film::outputs::LUMINANCE_CD, "luminance (cd/m²)")
            } else {
                (quasar::film::outputs::ILLUMINANCE_LX, "illuminance (lx)")
            };
            if layer == quasar::film::outputs::ILLUMINANCE_LX
                && ov.illuminance_samples.unwrap_or(desc.render.illuminance_samples) == 0
            {
                anyhow::bail!("--false-colour illuminance needs the illuminance.Y layer: give --illuminance-samples N");
            }
            let scale = false_colour_scale.unwrap_or(ColourScale::Log);
            // a given range is checked before the render; without one the range is fitted after it
            let fixed = false_colour_range.map(|(min, max)| FalseColour { min, max, scale, title: title.into() });
            if let Some(fc) = &fixed {
                fc.validate().map_err(|e| anyhow::anyhow!(e))?;
            }
            Some((q.to_string(), layer, title, scale, fixed))
        }
        None => None,
    };
    let out = render_desc(&desc, &ov, !quiet)?;
    for w in &out.result.warnings {
        eprintln!("warning: {w}");
    }
    write_outputs_with_preview(&out, &exr, preview.as_ref(), exposure, view)?;
    if let Some((q, layer, title, scale, fixed)) = false_colour_map {
        let img = &out.image;
        let values = img.channel(layer).with_context(|| format!("the image has no {layer} layer"))?;
        let fc = fixed.unwrap_or_else(|| FalseColour::fit(values, scale, title));
        let path = exr.with_file_name(format!("{}.{q}.png", file_stem(&exr)));
        quasar::output::write_png_atomic(&path, &fc.image(values, img.width, img.height))?;
        if !quiet {
            eprintln!("false colour of {layer} ({}..{}) -> {}", fc.min, fc.max, path.display());
        }
    }
    if sensors_written && !out.result.interrupted {
        let scale = false_colour_scale.unwrap_or(ColourScale::Linear);
        write_sensors(&desc, &out.scene, &exr, ov.seed.unwrap_or(desc.render.seed), scale, quiet)?;
    }
    if out.result.interrupted {
        eprintln!("interrupted: wrote the partial image {} ({} spp)", exr.display(), out.result.spp);
        return Ok(ExitCode::from(super::EXIT_PARTIAL));
    }
    if !quiet {
        let t = out.result.threads;
        eprintln!(
            "wrote {} ({}x{}, {} spp, {:.2} s, {t} thread{})",
            exr.display(),
            out.image.width,
            out.image.height,
            out.result.spp,
            out.result.seconds,
            if t == 1 { "" } else { "s" }
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Checks an output path before the render: not the scene file, an extension `ext` (none
/// checked when empty) unless it is a device or a pipe, and writable
/// ([`quasar::output::check_writable`]). Returns whether it is a device or a pipe.
fn check_output(scene: &std::path::Path, path: &std::path::Path, ext: &str, flag: &str) -> Result<bool> {
    if same_file(scene, path) {
        anyhow::bail!("{}: the output would overwrite the scene file", path.display());
    }
    let stream = quasar::output::OutputTarget::of(path).is_ok_and(|t| t == quasar::output::OutputTarget::Stream);
    let has_ext = path.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext));
    if !ext.is_empty() && !stream && !has_ext {
        let what = if ext == "exr" { "an OpenEXR image" } else { "a PNG image" };
        anyhow::bail!(
            "{}: {flag} writes {what}; give it a .{ext} path (the image is always OpenEXR, --preview adds a PNG)",
            path.display()
        );
    }
    quasar::output::check_writable(path)?;
    Ok(stream)
}

/// The file name of `path` without its extension (`out` when it has none).
fn file_stem(path: &std::path::Path) -> String {
    path.file_stem().map_or("out".into(), |s| s.to_string_lossy().into_owned())
}

/// The CSV path of sensor `name` for the image `exr`: `<stem>.<name>.csv` beside it.
pub fn sensor_csv_path(exr: &std::path::Path, name: &str) -> PathBuf {
    exr.with_file_name(format!("{}.{name}.csv", file_stem(exr)))
}

/// Measures the `[[sensor]]`s of `desc` in its compiled `scene` (the render's own, `--masking`
/// included) and writes each one's CSV beside the image, and for a
/// grid of more than one meter its false-colour map `<stem>.<name>.png` (plan view: the first
/// side to the right, the second side up).
fn write_sensors(
    desc: &quasar_importers::SceneDesc,
    scene: &quasar::core::scene::Scene,
    exr: &std::path::Path,
    seed: u64,
    scale: ColourScale,
    quiet: bool,
) -> Result<()> {
    for sensor in &desc.sensors {
        let reading = quasar::render::sensors::measure(scene, sensor, seed ^ 0x5e45_0125);
        let path = sensor_csv_path(exr, &sensor.name);
        quasar::output::atomic::write_atomic_bytes(&path, reading.csv().as_bytes())?;
        if !quiet {
            eprintln!("{} -> {}", reading.summary(), path.display());
        }
        if let quasar_importers::SensorLayout::Grid { resolution: [nx, ny], .. } = sensor.layout
            && nx * ny > 1
        {
            let (nx, ny) = (nx as usize, ny as usize);
            // rows of the CSV run along the second side from its start; the map puts that start at the bottom
            let values: Vec<f32> =
                (0..ny).rev().flat_map(|j| reading.lux[j * nx..(j + 1) * nx].iter().map(|&v| v as f32)).collect();
            let fc = FalseColour::fit(&values, scale, &format!("{}: {} (lx)", sensor.name, reading.quantity.name()));
            let png = exr.with_file_name(format!("{}.{}.png", file_stem(exr), sensor.name));
            quasar::output::write_png_atomic(&png, &fc.image(&values, nx, ny))?;
            if !quiet {
                eprintln!("{} map -> {}", sensor.name, png.display());
            }
        }
    }
    Ok(())
}
