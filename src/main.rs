//! The `quasar` command line (DESIGN.md section 6).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use quasar::core::scene::Scene;
use quasar::integrator::method::BidirectionalOptions;
use quasar::render::job::{JobOverrides, load_scene, load_scene_with, render_desc, write_outputs_with_exposure};
use quasar_importers::ImportOptions;

#[derive(Parser)]
#[command(name = "quasar", version, about = "Physically based spectral renderer for lighting and CAD engineers")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
#[allow(clippy::large_enum_variant)] // parsed once per process; size does not matter
enum Command {
    /// Render a scene (.toml, .obj, .gltf, .glb) to a multi-layer OpenEXR file.
    Render {
        /// Scene file.
        scene: PathBuf,
        /// Let glTF files refer to files by absolute paths or outside their folder.
        #[arg(long)]
        allow_external_paths: bool,
        /// Extra length unit of the scene file (m, cm, mm, in, ft, or a factor in metres), e.g.
        /// `--units mm` for a glTF exported in millimetres (applies on top of a TOML `units`).
        #[arg(long, value_parser = parse_units)]
        units: Option<f32>,
        /// Output EXR (default: the scene's name with .exr, in the current directory).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Integration method: auto | pt | vismap | adaptive | quasi | adaptive+quasi.
        #[arg(long)]
        method: Option<String>,
        /// Samples per pixel.
        #[arg(long, conflicts_with = "time")]
        spp: Option<u32>,
        /// Render for this many seconds instead of a fixed sample count.
        #[arg(long)]
        time: Option<f64>,
        /// Stop when the estimated RMS relative error of the image (sqrt of the mean over pixels
        /// of stderr^2 / (Y^2 + 1e-3)) is at most this, or at --time, whichever comes first.
        #[arg(long)]
        target_error: Option<f64>,
        /// Image width in pixels.
        #[arg(long)]
        width: Option<u32>,
        /// Image height in pixels.
        #[arg(long)]
        height: Option<u32>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Seed of the random streams.
        #[arg(long)]
        seed: Option<u64>,
        /// Maximum number of scattering events per path (default: unbounded).
        #[arg(long)]
        max_depth: Option<u32>,
        /// Bidirectional methods: number of iterations (default: the scene's spp).
        #[arg(long)]
        iterations: Option<u32>,
        /// Bidirectional methods: photons traced per iteration (default: one per pixel).
        #[arg(long)]
        photons_per_iteration: Option<u64>,
        /// vismap, quasi: non-specular camera-path vertex where photons are gathered (0 = first).
        #[arg(long)]
        gather_depth: Option<u32>,
        /// adaptive, adaptive+quasi: deepest gather depth considered (default 4).
        #[arg(long)]
        max_gather_depth: Option<u32>,
        /// adaptive, adaptive+quasi: choose the depth from the iteration's own first ray (the
        /// paper's variant; biased) instead of earlier iterations' pilot paths.
        #[arg(long)]
        adaptive_paper: bool,
        /// quasi, adaptive+quasi: half-angle in degrees of the quasi-specular cone (default 10).
        #[arg(long)]
        cone: Option<f32>,
        /// Bidirectional methods: initial gather radius in scene units (default: 3 pixel footprints).
        #[arg(long)]
        radius: Option<f32>,
        /// Bidirectional methods: radius reduction alpha in (0, 1) (default 2/3).
        #[arg(long)]
        alpha: Option<f32>,
        /// Render share K of N (0 <= K < N) of the samples or iterations, with streams disjoint
        /// from the other shares; `quasar merge` combines the shards into the full render.
        #[arg(long, value_parser = parse_shard)]
        shard: Option<(u32, u32)>,
        /// Write the accumulated state to this file periodically and at the end.
        #[arg(long)]
        checkpoint: Option<PathBuf>,
        /// Continue the render stored in this checkpoint (same scene and settings; a larger
        /// --spp / --iterations or a new --time extends it).
        #[arg(long)]
        resume: Option<PathBuf>,
        /// Microfacet masking-shadowing of the GGX materials: height-correlated (default) or
        /// separable (Mitsuba 3's and pbrt-v3's form, for comparisons with them).
        #[arg(long, value_parser = parse_masking)]
        masking: Option<quasar_materials::Masking>,
        /// Exposure of the PNG preview in stops (the preview is scaled by 2^EV before clipping).
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        exposure: f32,
        /// Also write a tone-mapped PNG preview.
        #[arg(long)]
        preview: Option<PathBuf>,
        /// Do not show a progress bar.
        #[arg(long)]
        quiet: bool,
    },
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
        /// Also run the block z-test of the luminance against the reference with both images'
        /// standard errors (exit code 1 when it fails).
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

fn bsdf(action: Option<BsdfCommand>, file: Option<PathBuf>, plot: Option<PathBuf>) -> anyhow::Result<()> {
    use quasar::importers::bsdf_file;
    if let Some(BsdfCommand::Convert { input, output }) = action {
        if same_file(&input, &output) {
            anyhow::bail!("{}: the output would overwrite the input", output.display());
        }
        let c = bsdf_file::zemax::convert_zemax_bsdf(&input)?;
        for w in &c.warnings {
            eprintln!("warning: {}: {w}", input.display());
        }
        quasar::materials::TabulatedTable::new(c.spec.clone())
            .map_err(|e| anyhow::anyhow!("{}: the converted table is invalid: {e}", input.display()))?;
        let source = input.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
        let mut prov: Vec<(&str, &str)> = vec![("converted_from", &source), ("converter", "quasar bsdf convert")];
        prov.extend(c.header.iter().map(|(k, v)| (k.as_str(), v.as_str())));
        let text = bsdf_file::to_toml(&c.spec, "converted from a Zemax tabular BSDF file", &prov);
        let tmp = output.with_extension("toml.tmp");
        std::fs::write(&tmp, text).map_err(|e| anyhow::anyhow!("{}: {e}", output.display()))?;
        std::fs::rename(&tmp, &output).map_err(|e| anyhow::anyhow!("{}: {e}", output.display()))?;
        eprintln!("wrote {}", output.display());
        return Ok(());
    }
    let Some(file) = file else { anyhow::bail!("give a material file: quasar bsdf FILE [--plot out.png]") };
    let (table, warnings) = bsdf_file::load_for_inspection(&file)?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", file.display());
    }
    let r = quasar::tools::bsdf_report::report(&table, &file);
    print!("{}", r.text);
    if let Some(p) = plot {
        print!("{}", quasar::tools::bsdf_report::write_lobe_plot(&table, &p)?);
    }
    if !r.energy_ok {
        anyhow::bail!("{}: the table fails the energy check (max albedo {:.4})", file.display(), r.max_albedo);
    }
    Ok(())
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
}

fn bench(cmd: BenchCommand) -> anyhow::Result<()> {
    let (grid, file) = match cmd {
        BenchCommand::GltfImport { grid, file } => (grid, file),
        c => return bench_convergence(c),
    };
    anyhow::ensure!((1..=16384).contains(&grid), "--grid must be in 1..=16384");
    let tmp = tempfile_dir()?;
    let path = file.unwrap_or_else(|| tmp.join("grid.glb"));
    let triangles = 2 * u64::from(grid) * u64::from(grid);
    let t = std::time::Instant::now();
    let bytes = quasar::tools::import_bench::write_grid_glb(&path, grid)?;
    eprintln!("wrote {} ({triangles} triangles, {bytes} bytes) in {:.2} s", path.display(), t.elapsed().as_secs_f64());
    let r = quasar::tools::import_bench::run(&path, triangles)?;
    let mib = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.0} MiB"));
    println!("triangles: {}", r.triangles);
    println!("file: {:.1} MiB", r.file_bytes as f64 / (1 << 20) as f64);
    println!("import: {:.3} s ({:.2} M triangles/s)", r.import_s, r.triangles as f64 / r.import_s / 1e6);
    println!("compile (BVH): {:.3} s", r.compile_s);
    println!("rss before import: {}", mib(r.rss_before_mib));
    println!("peak rss during import: {}", mib(r.peak_import_mib));
    println!("peak rss during import + compile: {}", mib(r.peak_total_mib));
    let _ = std::fs::remove_dir_all(&tmp);
    Ok(())
}

/// A fresh directory under the system temporary directory.
fn tempfile_dir() -> anyhow::Result<PathBuf> {
    let d = std::env::temp_dir().join(format!("quasar-bench-{}", std::process::id()));
    std::fs::create_dir_all(&d)?;
    Ok(d)
}

fn bench_convergence(cmd: BenchCommand) -> anyhow::Result<()> {
    let BenchCommand::Convergence {
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
    } = cmd
    else {
        anyhow::bail!("not a convergence benchmark");
    };
    use quasar::tools::convergence;
    let methods = convergence::parse_methods(&methods)?;
    if !(time > 0.0 && time.is_finite()) || steps == 0 || steps > 20 {
        anyhow::bail!("--time must be positive and --steps in 1..=20");
    }
    let desc = load_scene(&scene)?;
    let (w, h, reference) = match reference {
        Some(p) => {
            let img = quasar::output::read_exr(&p)?;
            let y = img.channel("Y").ok_or_else(|| anyhow::anyhow!("{}: no Y channel", p.display()))?.to_vec();
            (img.width as u32, img.height as u32, y)
        }
        None => {
            let t = std::time::Instant::now();
            let y = convergence::pt_reference(&desc, width, height, reference_spp, seed ^ 0x5eed, true)?;
            eprintln!("reference: pt {width}x{height}, {reference_spp} spp, {:.1} s", t.elapsed().as_secs_f64());
            (width, height, y)
        }
    };
    let budgets: Vec<f64> = (0..steps).rev().map(|k| time / 2f64.powi(k as i32)).collect();
    let base = JobOverrides {
        width: Some(w),
        height: Some(h),
        seed: Some(seed),
        bidir: BidirectionalOptions {
            photons_per_iteration: Some(photons_per_iteration.unwrap_or(4 * w as u64 * h as u64)),
            ..Default::default()
        },
        ..Default::default()
    };
    let points = convergence::run(&desc, &base, &methods, &budgets, &reference, |p| {
        eprintln!("{} {} s: relMSE {:.5} ({} samples/iterations)", p.label, p.budget, p.rel_mse, p.samples);
    })?;
    print!("{}", convergence::markdown_table(&points, target));
    if let Some(p) = csv {
        std::fs::write(&p, convergence::to_csv(&points)).map_err(|e| anyhow::anyhow!("{}: {e}", p.display()))?;
    }
    if let Some(p) = plot {
        print!("{}", convergence::write_plot(&points, &p)?);
    }
    Ok(())
}

/// Parses `--units`: a unit name of the TOML `units` key or a positive factor in metres.
fn parse_units(s: &str) -> Result<f32, String> {
    if let Some((_, m)) = quasar_importers::toml_scene::UNITS.iter().find(|(n, _)| *n == s) {
        return Ok(*m);
    }
    match s.parse::<f32>() {
        Ok(f) if f.is_finite() && f > 0.0 => Ok(f),
        _ => Err(format!("expected m, cm, mm, in, ft or a positive number of metres, got {s:?}")),
    }
}

/// Parses `--masking`.
fn parse_masking(s: &str) -> Result<quasar_materials::Masking, String> {
    quasar_materials::Masking::from_name(s)
        .ok_or_else(|| format!("expected one of {}, got {s:?}", quasar_materials::Masking::NAMES.join(", ")))
}

/// Parses `K/N` for `--shard`.
fn parse_shard(s: &str) -> Result<(u32, u32), String> {
    let (k, n) = s.split_once('/').ok_or("expected K/N, e.g. 0/4")?;
    let (k, n): (u32, u32) =
        (k.trim().parse().map_err(|_| "K is not a number")?, n.trim().parse().map_err(|_| "N is not a number")?);
    if n == 0 || k >= n {
        return Err(format!("{k}/{n}: need 0 <= K < N"));
    }
    Ok((k, n))
}

/// True when both paths name the same existing file.
fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

fn run() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Render {
            scene,
            allow_external_paths,
            units,
            output,
            method,
            spp,
            time,
            target_error,
            width,
            height,
            threads,
            seed,
            max_depth,
            iterations,
            photons_per_iteration,
            gather_depth,
            max_gather_depth,
            adaptive_paper,
            cone,
            radius,
            alpha,
            shard,
            checkpoint,
            resume,
            masking,
            preview,
            exposure,
            quiet,
        } => {
            let desc = load_scene_with(&scene, &ImportOptions { allow_external_paths, units_scale: units })?;
            quasar::render::interrupt::install_handler();
            let ov = JobOverrides {
                width,
                height,
                spp,
                time_s: time,
                target_error,
                seed,
                threads,
                max_depth,
                method,
                bidir: BidirectionalOptions {
                    iterations,
                    photons_per_iteration,
                    gather_depth,
                    max_gather_depth,
                    adaptive_paper,
                    cone_deg: cone,
                    radius,
                    alpha,
                },
                shard,
                checkpoint,
                resume,
                masking,
            };
            let out = render_desc(&desc, &ov, !quiet)?;
            let exr = output.unwrap_or_else(|| {
                PathBuf::from(scene.file_stem().map_or("out".into(), |s| s.to_string_lossy().into_owned()) + ".exr")
            });
            if same_file(&scene, &exr) || preview.as_ref().is_some_and(|p| same_file(&scene, p)) {
                anyhow::bail!("{}: the output would overwrite the scene file", exr.display());
            }
            write_outputs_with_exposure(&out, &exr, preview.as_ref(), exposure)?;
            if out.result.interrupted {
                eprintln!("interrupted: wrote the partial image {} ({} spp)", exr.display(), out.result.spp);
            }
            if !quiet {
                eprintln!(
                    "wrote {} ({}x{}, {} spp, {:.2} s, {} threads)",
                    exr.display(),
                    out.image.width,
                    out.image.height,
                    out.result.spp,
                    out.result.seconds,
                    out.result.threads
                );
            }
            Ok(())
        }
        Command::Compare { image, reference, layer, diff, z_test } => {
            let a = quasar::output::read_exr(&image)?;
            let r = quasar::output::read_exr(&reference)?;
            let errors = quasar::tools::compare::compare(&a, &r, layer.as_deref()).map_err(anyhow::Error::msg)?;
            println!(
                "{:<12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}",
                "layer", "rmse", "relmse", "mean_rel", "max", "mean", "ref_mean"
            );
            for e in errors {
                println!(
                    "{:<12} {:>12.5e} {:>12.5e} {:>12.5e} {:>12.5e} {:>12.5e} {:>12.5e}",
                    e.layer, e.rmse, e.rel_mse, e.mean_rel_error, e.max_error, e.means.0, e.means.1
                );
            }
            if let Some(p) = diff {
                quasar::tools::compare::write_difference_png(&a, &r, &p).map_err(anyhow::Error::msg)?;
            }
            if z_test {
                let est = |img, path: &PathBuf| {
                    quasar::tools::ztest::Estimate::from_exr(img)
                        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
                };
                let report = quasar::tools::ztest::ZTest::default()
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
        Command::Bench { what } => bench(what),
        Command::Bsdf { action, file, plot } => bsdf(action, file, plot),
        Command::ExportMitsuba { scene, output, width, height, spp } => {
            let desc = load_scene(&scene)?;
            let r = &desc.render;
            quasar::tools::mitsuba_export::write(
                &desc,
                &output,
                width.unwrap_or(r.width),
                height.unwrap_or(r.height),
                spp.unwrap_or(r.spp),
            )
            .map_err(|e| anyhow::anyhow!("{}: cannot be written for Mitsuba: {e}", scene.display()))?;
            Ok(())
        }
        Command::Info { scene, allow_external_paths, units } => {
            let desc = load_scene_with(&scene, &ImportOptions { allow_external_paths, units_scale: units })?;
            let compiled = Scene::compile(&desc)?;
            println!("scene: {}", scene.display());
            println!("meshes: {}, triangles: {}", desc.meshes.len(), compiled.triangle_count());
            println!("materials: {}", desc.materials.len());
            for m in &desc.materials {
                let tex = if m.textures.is_empty() { "" } else { " (textured)" };
                println!("  {}: {:?}{tex}", m.name, m.material);
            }
            if !desc.textures.is_empty() {
                let t: Vec<String> =
                    desc.textures.iter().map(|t| format!("{} {}x{}", t.name, t.width, t.height)).collect();
                println!("textures: {}", t.join(", "));
            }
            if !desc.cameras.is_empty() {
                let c: Vec<&str> = desc.cameras.iter().map(|c| c.name.as_str()).collect();
                println!(
                    "cameras in the file: {} (the scene camera looks from {})",
                    c.join(", "),
                    desc.camera.position
                );
            }
            println!(
                "lights: {} ({} emissive triangles)",
                compiled.lights.len(),
                compiled.lights.len() - desc.lights.len()
            );
            println!("bounding sphere: centre {:?}, radius {}", compiled.center, compiled.radius);
            print!("{}", quasar::integrator::analysis::SceneAnalysis::of(&compiled).report());
            Ok(())
        }
    }
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
