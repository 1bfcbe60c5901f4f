//! The per-pixel noise estimate (`stderr.Y`), `--target-error`, and `quasar compare`.

mod common;

use std::path::Path;
use std::process::Command;

use common::{rel_mse, render_file};
use quasar::render::job::{JobOverrides, write_outputs};

fn cornell() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box/cornell-box.toml")
}

fn ov(spp: Option<u32>, target: Option<f64>, seed: u64) -> JobOverrides {
    JobOverrides {
        width: Some(32),
        height: Some(32),
        spp,
        target_error: target,
        seed: Some(seed),
        method: Some("pt".into()),
        ..Default::default()
    }
}

/// The image's estimated RMS relative error (from per-pixel sample variances) predicts its actual
/// error against a converged reference within 25% at 256 spp. The estimate is low where a
/// pixel's rare large samples have not been drawn yet: over 12 seeds (`quasar render
/// scenes/cornell-box/cornell-box.toml --width 32 --height 32 --spp N --seed S` against 8192-spp
/// references) estimated / actual was 0.61-0.91 at 16 spp, 0.71-1.00 at 64 and 0.85-1.00 at
/// 256, so the test's former 16-spp case passed only for some seeds.
#[test]
fn stderr_predicts_the_actual_error() {
    let reference = render_file(&cornell(), &ov(Some(8192), None, 1)).image;
    let r = reference.channel(quasar::film::LUMINANCE).unwrap();
    let spp = 256;
    let img = render_file(&cornell(), &ov(Some(spp), None, 2));
    let actual = rel_mse(img.image.channel(quasar::film::LUMINANCE).unwrap(), r).sqrt();
    let estimated = img.result.film.estimated_rel_error();
    eprintln!("{spp} spp: estimated {estimated:.4}, actual {actual:.4}");
    assert!((estimated / actual - 1.0).abs() < 0.25, "{spp} spp: estimated {estimated}, actual {actual}");
    let stderr = img.image.channel("stderr.Y").unwrap();
    assert!(stderr.iter().all(|v| v.is_finite() && *v >= 0.0));
}

/// `--target-error` stops as soon as the estimate reaches the target, for pt and a bidirectional
/// method; the achieved error is close to it (within 20%). The pt case is rendered at 64x64:
/// at 32x32 the achieved error over 24 seeds (`quasar render scenes/cornell-box/cornell-box.toml
/// --width 32 --height 32 --target-error 0.05 --seed S`, S = 3 + 1000 q) was 0.045-0.062 against
/// an 8192-spp reference, above 0.06 for one seed: the estimate, an average over the image's
/// pixels of their sample variances, is low while their rare large samples are undrawn, and 1024
/// pixels average that out less than 4096 do (0.044-0.054 over the same 24 seeds at 64x64).
#[test]
fn target_error_stops_the_render() {
    let at_64 = |o: JobOverrides| JobOverrides { width: Some(64), height: Some(64), ..o };
    let reference = render_file(&cornell(), &at_64(ov(Some(8192), None, 1))).image;
    let r = reference.channel(quasar::film::LUMINANCE).unwrap();
    let img = render_file(&cornell(), &at_64(ov(None, Some(0.05), 3)));
    let est = img.result.film.estimated_rel_error();
    let actual = rel_mse(img.image.channel(quasar::film::LUMINANCE).unwrap(), r).sqrt();
    eprintln!("pt: {} spp, estimated {est:.4}, actual {actual:.4}", img.result.spp);
    assert!(est <= 0.05);
    assert!(actual < 0.06, "actual error {actual}");
    assert!(img.result.spp > 16 && img.result.spp < 10_000);
    assert_eq!(img.image.meta("target_error"), Some("0.05"));

    let mut v = ov(None, Some(0.05), 3);
    v.method = Some("vismap".into());
    let img = render_file(&cornell(), &v);
    let est = img.result.film.estimated_rel_error();
    eprintln!("vismap: {} iterations, estimated {est:.4}", img.result.spp);
    assert!(est <= 0.05);
    assert!(img.result.spp >= 2 && img.result.spp < 100_000);
}

fn quasar() -> Command {
    Command::new(env!("CARGO_BIN_EXE_quasar"))
}

/// `quasar compare` reports zero error for an image against itself, a positive one against
/// another seed, writes the difference PNG, and refuses images of different sizes.
#[test]
fn compare_command() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, o: &JobOverrides| {
        let p = dir.path().join(name);
        write_outputs(&render_file(&cornell(), o), &p, None).unwrap();
        p
    };
    let a = write("a.exr", &ov(Some(4), None, 1));
    let b = write("b.exr", &ov(Some(4), None, 2));
    let small = write("small.exr", &JobOverrides { width: Some(8), ..ov(Some(1), None, 1) });
    let out = quasar().arg("compare").arg(&a).arg(&a).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let beauty = text.lines().find(|l| l.starts_with("beauty")).unwrap();
    assert!(beauty.split_whitespace().nth(2).unwrap().parse::<f64>().unwrap() == 0.0, "{beauty}");
    let png = dir.path().join("diff.png");
    let out =
        quasar().arg("compare").arg(&b).arg(&a).arg("--layer").arg("direct").arg("--diff").arg(&png).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let direct = text.lines().find(|l| l.starts_with("direct")).unwrap();
    assert!(direct.split_whitespace().nth(2).unwrap().parse::<f64>().unwrap() > 0.0, "{direct}");
    assert!(!text.contains("indirect"));
    assert!(png.exists());
    let out = quasar().arg("compare").arg(&small).arg(&a).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("sizes differ"));
}

/// `quasar bench convergence` writes the curves (CSV: one row per method and budget), the table
/// and the plot.
#[test]
fn bench_convergence_command() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, png) = (dir.path().join("c.csv"), dir.path().join("c.png"));
    let out = quasar()
        .args(["bench", "convergence"])
        .arg(cornell())
        .args(["--width", "16", "--height", "12", "--reference-spp", "256", "--time", "0.2", "--steps", "2"])
        .args(["--methods", "pt,vismap:1,adaptive+quasi:20", "--csv"])
        .arg(&csv)
        .arg("--plot")
        .arg(&png)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 6, "{text}");
    for r in rows {
        let e: f64 = r.rsplit(',').next().unwrap().parse().unwrap();
        assert!(e.is_finite() && e > 0.0, "{r}");
    }
    assert!(png.exists());
    assert!(String::from_utf8_lossy(&out.stdout).contains("| adaptive+quasi:20 |"));
    let bad = quasar().args(["bench", "convergence"]).arg(cornell()).args(["--methods", "pt:2"]).output().unwrap();
    assert!(!bad.status.success());
}
