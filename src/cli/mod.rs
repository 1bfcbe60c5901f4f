//! The `quasar` command line: argument definitions (clap) and their dispatch to the library.
//! No rendering, conversion or report logic lives here.

mod interrupt;
mod parse;
mod render;
pub mod usd_isolation;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};
use quasar::core::scene::Scene;
use quasar::render::job::load_scene_with;
use quasar::tools::import_bench;
use quasar_importers::ImportOptions;

use self::parse::{parse_units, same_file};

#[derive(Parser)]
#[command(name = "quasar", version, about = "Physically based spectral renderer for lighting and CAD engineers")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
#[allow(clippy::large_enum_variant)] // parsed once per process; size does not matter
enum Command {
    /// Render a scene (.toml, .obj, .gltf, .glb, .usd, .usda, .usdc, .usdz) to a multi-layer OpenEXR file.
    Render(render::RenderArgs),
    /// Compare an image with a reference: RMSE, relMSE, mean relative and max error per layer.
    Compare {
        /// The image.
        image: PathBuf,
        /// The reference image.
        reference: PathBuf,
        /// Only this layer ("beauty", "direct", "indirect", ...).
        #[arg(long)]
        layer: Option<String>,
        /// Write a false-colour PNG of the relative luminance difference (red: brighter).
        #[arg(long)]
        diff: Option<PathBuf>,
        /// Also run the block z-test of the beauty's luminance against the reference with both
        /// images' standard errors (exit code 1 when it fails).
        #[arg(long)]
        z_test: bool,
    },
    /// Merge independent renders of one scene (e.g. `--shard K/N` shards) into one image,
    /// weighting every pixel by its sample counts.
    Merge {
        /// The renders.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// The merged EXR.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Benchmarks.
    Bench {
        #[command(subcommand)]
        what: BenchCommand,
    },
    /// Report on a tabulated BSDF (.toml, or a Zemax .bsdf): albedo per incidence and
    /// wavelength, kappa, energy verdict; `quasar bsdf convert` converts a Zemax .bsdf file.
    #[command(args_conflicts_with_subcommands = true)]
    Bsdf {
        #[command(subcommand)]
        action: Option<BsdfCommand>,
        /// The material file.
        file: Option<PathBuf>,
        /// Write a polar plot of the lobes (PNG).
        #[arg(long)]
        plot: Option<PathBuf>,
    },
    /// Write a scene as a Mitsuba 3 scene (scene.xml and OBJ meshes in DIR) with quasar's
    /// conventions, for the independent cross-check (tests/crosscheck/, docs/validation.md).
    ExportMitsuba {
        /// Scene file.
        scene: PathBuf,
        /// Output folder.
        #[arg(short, long)]
        output: PathBuf,
        /// Image width (default: the scene's).
        #[arg(long)]
        width: Option<u32>,
        /// Image height (default: the scene's).
        #[arg(long)]
        height: Option<u32>,
        /// Samples per pixel written into the scene (default: the scene's spp).
        #[arg(long)]
        spp: Option<u32>,
    },
    /// Print what a scene contains and which method `auto` would use.
    Info {
        /// Scene file.
        scene: PathBuf,
        /// Let glTF files refer to files by absolute paths or outside their folder.
        #[arg(long)]
        allow_external_paths: bool,
        /// Extra length unit of the scene file (as for `render`).
        #[arg(long, value_parser = parse_units)]
        units: Option<f32>,
        /// The USD time code (as for `render`).
        #[arg(long, value_parser = parse::parse_time_code)]
        time_code: Option<f64>,
    },
}

#[derive(Subcommand)]
enum BsdfCommand {
    /// Convert a Zemax/Radiant tabular .bsdf file to the TOML tabulated-BSDF format.
    Convert {
        /// The .bsdf file.
        input: PathBuf,
        /// The TOML file to write.
        #[arg(short, long)]
        output: PathBuf,
    },
}

#[derive(Subcommand)]
enum BenchCommand {
    /// Error-vs-time curves: every method renders SCENE for a series of time budgets and is
    /// compared with a converged reference (relMSE of the luminance).
    Convergence {
        /// Scene file.
        scene: PathBuf,
        /// Methods: pt, vismap[:DEPTH], adaptive[:paper], quasi[:CONE], adaptive+quasi[:CONE].
        #[arg(long, default_value = "pt,vismap,vismap:1,adaptive,quasi,adaptive+quasi")]
        methods: String,
        /// The longest time budget in seconds.
        #[arg(long, default_value_t = 8.0)]
        time: f64,
        /// Number of budgets: time / 2^(steps-1), ..., time / 2, time.
        #[arg(long, default_value_t = 4)]
        steps: u32,
        /// Reference EXR (its size is the render size); default: a pt render of --reference-spp.
        #[arg(long)]
        reference: Option<PathBuf>,
        /// Samples per pixel of the pt reference made when no --reference is given.
        #[arg(long, default_value_t = 16384)]
        reference_spp: u32,
        /// Image width (without --reference).
        #[arg(long, default_value_t = 64)]
        width: u32,
        /// Image height (without --reference).
        #[arg(long, default_value_t = 48)]
        height: u32,
        /// Photons per iteration of the bidirectional methods (default: 4 per pixel).
        #[arg(long)]
        photons_per_iteration: Option<u64>,
        /// The error whose reaching time is reported.
        #[arg(long, default_value_t = 0.01)]
        target: f64,
        /// Seed of the renders.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Write the curves as CSV.
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Write a log-log plot as PNG.
        #[arg(long)]
        plot: Option<PathBuf>,
    },
    /// Import time and peak memory of a large generated glTF (a k x k grid as .glb).
    GltfImport {
        /// Grid side k: 2 k^2 triangles (708 gives 1 002 528).
        #[arg(long, default_value_t = 708)]
        grid: u32,
        /// Where to write the .glb (default: a temporary directory).
        #[arg(long)]
        file: Option<PathBuf>,
    },
    /// Import time and peak memory of a large generated USD crate file (a k x k quad grid as .usdc).
    UsdImport {
        /// Grid side k: k^2 quads, 2 k^2 triangles (708 gives 1 002 528).
        #[arg(long, default_value_t = 708)]
        grid: u32,
        /// Where to write the stage (default: a temporary directory); a `.usda` name writes text.
        #[arg(long)]
        file: Option<PathBuf>,
        /// Measure this existing scene file instead of writing one (e.g. a Pixar-written .usdc).
        #[arg(long, conflicts_with = "file")]
        input: Option<PathBuf>,
    },
}

/// Loads `scene`, printing its import warnings.
fn load(scene: &std::path::Path, opts: &ImportOptions) -> Result<quasar_importers::SceneDesc> {
    let desc = load_scene_with(scene, opts)?;
    for w in &desc.warnings {
        eprintln!("warning: {w}");
    }
    Ok(desc)
}

/// Exit code of a render that was interrupted (Ctrl-C, SIGTERM) and wrote the partial image:
/// scripts and job schedulers can tell it from a finished render (0) and a failure (1).
pub const EXIT_PARTIAL: u8 = 3;

/// Parses the command line and runs it; the exit code of a successful run.
pub fn run() -> Result<ExitCode> {
    match Cli::parse().command {
        Command::Render(args) => render::render(args),
        other => run_tool(other).map(|()| ExitCode::SUCCESS),
    }
}

/// Runs every command but `render`.
fn run_tool(command: Command) -> Result<()> {
    match command {
        Command::Render(_) => unreachable!("run() handles render"),
        Command::Compare { image, reference, layer, diff, z_test } => {
            use quasar::tools::{compare, ztest};
            if z_test && layer.as_deref().is_some_and(|l| l != "beauty") {
                // EXR files carry standard errors of the beauty only
                anyhow::bail!(
                    "--z-test tests the beauty (the EXR has standard errors of the beauty only); drop --layer"
                );
            }
            let a = quasar::output::read_exr(&image)?;
            let r = quasar::output::read_exr(&reference)?;
            let errors = compare::compare(&a, &r, layer.as_deref()).map_err(anyhow::Error::msg)?;
            print!("{}", compare::table(&errors));
            if let Some(p) = diff {
                compare::write_difference_png(&a, &r, &p).map_err(anyhow::Error::msg)?;
            }
            if z_test {
                let est = |img, path: &PathBuf| {
                    ztest::Estimate::from_exr(img).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
                };
                let report = ztest::ZTest::default()
                    .run(&est(&a, &image)?, &est(&r, &reference)?)
                    .map_err(anyhow::Error::msg)?;
                print!("{report}");
                if report.failed() {
                    anyhow::bail!(
                        "{} differs from {} beyond its standard errors",
                        image.display(),
                        reference.display()
                    );
                }
            }
            Ok(())
        }
        Command::Merge { inputs, output } => {
            if inputs.iter().any(|i| same_file(i, &output)) {
                anyhow::bail!("{}: the output is one of the inputs", output.display());
            }
            let images = inputs.iter().map(|p| quasar::output::read_exr(p)).collect::<Result<Vec<_>, _>>()?;
            let merged = quasar::tools::merge::merge(&images).map_err(anyhow::Error::msg)?;
            quasar::output::write_exr_atomic(&merged, &output)?;
            Ok(())
        }
        Command::Bench { what } => match what {
            BenchCommand::GltfImport { grid, file } => {
                print!("{}", import_bench::bench(import_bench::GridFormat::Glb, grid, file.as_deref(), None)?);
                Ok(())
            }
            BenchCommand::UsdImport { grid, file, input } => {
                let format = import_bench::GridFormat::Usdc;
                print!("{}", import_bench::bench(format, grid, file.as_deref(), input.as_deref())?);
                Ok(())
            }
            BenchCommand::Convergence {
                scene,
                methods,
                time,
                steps,
                reference,
                reference_spp,
                width,
                height,
                photons_per_iteration,
                target,
                seed,
                csv,
                plot,
            } => {
                let desc = load(&scene, &ImportOptions::default())?;
                let settings = quasar::tools::convergence::BenchSettings {
                    methods,
                    time,
                    steps,
                    reference,
                    reference_spp,
                    width,
                    height,
                    photons_per_iteration,
                    target,
                    seed,
                    csv,
                    plot,
                };
                print!("{}", quasar::tools::convergence::bench(&desc, &settings, |l| eprintln!("{l}"))?);
                Ok(())
            }
        },
        Command::Bsdf { action, file, plot } => {
            use quasar::tools::bsdf_report;
            if let Some(BsdfCommand::Convert { input, output }) = action {
                if same_file(&input, &output) {
                    anyhow::bail!("{}: the output would overwrite the input", output.display());
                }
                for w in bsdf_report::convert_zemax(&input, &output)? {
                    eprintln!("warning: {}: {w}", input.display());
                }
                eprintln!("wrote {}", output.display());
                return Ok(());
            }
            let Some(file) = file else { anyhow::bail!("give a material file: quasar bsdf FILE [--plot out.png]") };
            let (table, warnings) = quasar_importers::bsdf_file::load_for_inspection(&file)?;
            for w in &warnings {
                eprintln!("warning: {}: {w}", file.display());
            }
            let r = bsdf_report::report(&table, &file);
            print!("{}", r.text);
            if let Some(p) = plot {
                print!("{}", bsdf_report::write_lobe_plot(&table, &p)?);
            }
            if !r.energy_ok {
                anyhow::bail!("{}: the table fails the energy check (max albedo {:.4})", file.display(), r.max_albedo);
            }
            Ok(())
        }
        Command::ExportMitsuba { scene, output, width, height, spp } => {
            let desc = load(&scene, &ImportOptions::default())?;
            let r = &desc.render;
            quasar::tools::mitsuba_export::write(
                &desc,
                &output,
                width.unwrap_or(r.width),
                height.unwrap_or(r.height),
                spp.unwrap_or(r.spp),
            )
            .map_err(|e| anyhow::anyhow!("{}: cannot be written for Mitsuba: {e}", scene.display()))
        }
        Command::Info { scene, allow_external_paths, units, time_code } => {
            let desc = load(&scene, &ImportOptions { allow_external_paths, units_scale: units, time_code })?;
            let compiled = Scene::compile(&desc)?;
            print!("{}", quasar::tools::info::report(&scene, &desc, &compiled));
            Ok(())
        }
    }
}
