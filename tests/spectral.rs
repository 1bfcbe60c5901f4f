//! Spectral EXR output (`--spectral-bins`, written to `<stem>.spectral.exr`): the `S0.<lambda>nm` channels against the exact bin
//! means of a known emission spectrum, their consistency with the film's CIE Y for a per-pixel
//! and a bidirectional method, and the layout's header attributes in the written file.

mod common;

use common::{bidir_ov, mean, pt_ov};
use quasar::film::SpectralBins;
use quasar::materials::spectrum::cie::{CIE_Y_INTEGRAL, ybar};
use quasar::output::ExrImage;
use quasar::render::job::{JobOverrides, write_outputs};

/// The emission spectrum of the test sphere: sharp features (a peak at 500 nm, a gap from 520 to
/// 600 nm) that a bin off by one or a wrong width would show.
const WAVELENGTHS: [f64; 7] = [360.0, 450.0, 500.0, 520.0, 600.0, 700.0, 830.0];
const VALUES: [f64; 7] = [0.2, 1.0, 3.0, 0.0, 0.0, 2.0, 0.5];

/// The camera inside a black sphere whose inner surface emits the test spectrum (a furnace of
/// albedo 0): every pixel sees that radiance exactly, so the only noise is the wavelength
/// sampling's.
fn emitting_sphere() -> common::TempScene {
    let list = |v: &[f64]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(", ");
    let spectrum = format!("{{ wavelengths = [{}], values = [{}] }}", list(&WAVELENGTHS), list(&VALUES));
    common::furnace_scene_emitting(0.0, &spectrum, 1.0, 8)
}

/// The test spectrum at `lambda` (piecewise linear).
fn spectrum(lambda: f64) -> f64 {
    let i = WAVELENGTHS.iter().rposition(|&w| w <= lambda).unwrap_or(0).min(WAVELENGTHS.len() - 2);
    let t = (lambda - WAVELENGTHS[i]) / (WAVELENGTHS[i + 1] - WAVELENGTHS[i]);
    VALUES[i] + t * (VALUES[i + 1] - VALUES[i])
}

/// The exact mean of the test spectrum over bin `b` (midpoint rule on 0.01 nm steps, exact to
/// far below the test's noise for a piecewise-linear function).
fn bin_mean(bins: &SpectralBins, b: usize) -> f64 {
    let d = bins.width_nm() as f64;
    let lo = bins.centre_nm(b) - d / 2.0;
    let steps = (d * 100.0) as usize;
    (0..steps).map(|k| spectrum(lo + (k as f64 + 0.5) * d / steps as f64)).sum::<f64>() / steps as f64
}

fn spectral_ov(ov: JobOverrides, bins: SpectralBins) -> JobOverrides {
    JobOverrides { spectral_bins: Some(bins), threads: Some(2), ..ov }
}

/// Pixel mean and its standard error over the (independent) pixels of a `pt` image.
fn mean_and_stderr(v: &[f32]) -> (f64, f64) {
    let m = mean(v);
    let var = v.iter().map(|&x| (x as f64 - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
    (m, (var / v.len() as f64).sqrt())
}

/// Y from the spectral channels, sum_b L_b ybar(centre_b) d / integral(ybar): the film's
/// estimator of Y with ybar held constant over each bin.
fn y_from_bins(img: &ExrImage, bins: &SpectralBins) -> Vec<f64> {
    let d = bins.width_nm() as f64;
    let mut y = vec![0.0f64; img.width * img.height];
    for b in 0..bins.count() {
        let w = ybar(bins.centre_nm(b) as f32) as f64 * d / CIE_Y_INTEGRAL as f64;
        for (acc, &v) in y.iter_mut().zip(img.channel(&bins.channel_name(b)).unwrap()) {
            *acc += v as f64 * w;
        }
    }
    y
}

#[test]
fn spectral_bins_converge_to_the_bin_means_of_the_emission() {
    let scene = emitting_sphere();
    let bins = SpectralBins::new(16, 400.0, 720.0).unwrap();
    let img = common::render_file(&scene.path, &spectral_ov(pt_ov(24, 24, 1024, 0), bins)).image;
    let (mut observed, mut expected, mut var) = (0.0, 0.0, 0.0);
    for b in 0..bins.count() {
        let (m, se) = mean_and_stderr(img.channel(&bins.channel_name(b)).unwrap());
        let e = bin_mean(&bins, b);
        eprintln!("{} nm: {m:.5} +- {se:.5}, exact {e:.5}", bins.centre_nm(b));
        // the gap's bins are exactly 0: no estimate may leak into them
        if e == 0.0 {
            assert_eq!(m, 0.0, "bin {b} of the gap");
            continue;
        }
        assert!((m - e).abs() < 4.5 * se, "bin {b} ({} nm): {m} +- {se}, exact {e}", bins.centre_nm(b));
        observed += m;
        expected += e;
        var += se * se;
    }
    // the sum over bins (the spectrum's integral over 400-720 nm) to 0.1%: a 1% scale error is
    // about 10 standard errors
    let se = var.sqrt();
    eprintln!("sum over bins {observed:.5} +- {se:.5}, exact {expected:.5}");
    let z = |exact: f64| (observed - exact) / se;
    assert!(z(expected).abs() < 4.0, "sum {observed} +- {se}, exact {expected}");
    assert!(z(1.01 * expected).abs() > 4.0 && z(0.99 * expected).abs() > 4.0, "the test cannot see a 1% bias");
}

#[test]
fn spectral_bins_hold_the_samples_of_the_films_y_for_per_pixel_and_bidirectional_methods() {
    let scene = emitting_sphere();
    // 1 nm bins over the sampled range. Y from the bins differs from the film's only by ybar's
    // change within half a bin: per sample |ybar(centre) - ybar(lambda)| <= 0.5 nm x max|ybar'|,
    // so |Y(bins) - Y| <= (sum_b L_b d) x 0.5 nm x max|ybar'| / integral(ybar), sum_b L_b d
    // being the same samples' estimate of the integral of L
    let bins = SpectralBins::new(470, 360.0, 830.0).unwrap();
    let slope = (0..47_000)
        .map(|k| 360.0 + k as f32 * 0.01)
        .map(|l| ((ybar(l + 0.01) - ybar(l)) / 0.01).abs())
        .fold(0.0f32, f32::max) as f64;
    for (label, ov) in [("pt", pt_ov(8, 8, 256, 3)), ("vismap", bidir_ov(8, 8, "vismap", 1024, 64, 3))] {
        let img = common::render_file(&scene.path, &spectral_ov(ov, bins)).image;
        let from_bins = y_from_bins(&img, &bins);
        let film = img.channel(quasar::film::LUMINANCE).unwrap();
        let m = mean(film);
        assert!(m > 0.1, "{label}: Y {m}");
        let mut worst = 0.0f64;
        for p in 0..film.len() {
            let integral: f64 = (0..bins.count()).map(|b| img.channel(&bins.channel_name(b)).unwrap()[p] as f64).sum();
            let bound = integral * bins.width_nm() as f64 * 0.5 * slope / CIE_Y_INTEGRAL as f64 + 1e-5 * m;
            worst = worst.max((from_bins[p] - film[p] as f64).abs() / bound);
        }
        // over the image the first-order term of ybar's change averages out (the samples lie
        // uniformly within their bins): a 1% scale error of the bins is 0.01 m
        let mean_diff = (from_bins.iter().sum::<f64>() / film.len() as f64 - m).abs();
        eprintln!(
            "{label}: Y mean {m:.5}, |mean Y(bins) - mean Y| {mean_diff:.2e}, worst |Y(bins) - Y| / bound {worst:.3} (max |ybar'| {slope:.4}/nm)"
        );
        assert!(worst <= 1.0, "{label}: Y from the bins differs from the film's by {worst} x the bound");
        assert!(mean_diff < 1e-3 * m, "{label}: the mean Y from the bins differs from the film's by {mean_diff}");
    }
}

#[test]
fn the_written_file_has_the_spectral_layout_attributes_and_channels() {
    let scene = emitting_sphere();
    let bins = SpectralBins::new(3, 400.0, 700.0).unwrap();
    let out = common::render_file(&scene.path, &spectral_ov(pt_ov(4, 4, 2, 0), bins));
    let image = scene.dir.path().join("image.exr");
    write_outputs(&out, &image, None).unwrap();
    // the bins are in a file of their own; the image keeps the standard layers (issue 52:
    // Blender refuses a whole file with more than 24 channels in one layer)
    let path = quasar::render::job::spectral_file_path(&image);
    assert_eq!(path, scene.dir.path().join("image.spectral.exr"));
    let main = quasar::output::read_exr(&image).unwrap();
    assert!(!main.channels.iter().any(|c| SpectralBins::is_channel(&c.name)));
    assert_eq!(main.meta("spectral_file"), Some("image.spectral.exr"));
    assert!(main.channel(quasar::film::LUMINANCE).is_some() && main.channel("indirect.R").is_some());
    use exr::prelude::{AttributeValue, ReadChannels, ReadLayers, Text};
    let raw = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(&path)
        .unwrap();
    let attrs = &raw.layer_data.attributes.other;
    let text = |k: &str| match attrs.get(&Text::from(k)) {
        Some(AttributeValue::Text(t)) => t.to_string(),
        other => panic!("{k}: {other:?}"),
    };
    assert_eq!(text("spectralLayoutVersion"), "1.0");
    assert_eq!(text("emissiveUnits"), "W.m^-2.sr^-1");
    let names: Vec<String> = raw.layer_data.channel_data.list.iter().map(|c| c.name.to_string()).collect();
    for n in ["S0.450,000000nm", "S0.550,000000nm", "S0.650,000000nm"] {
        assert!(names.iter().any(|c| c == n), "{n} missing from {names:?}");
    }
    assert_eq!(out.image.meta("spectral_bins"), Some("3 x 100 nm over 400:700 nm"));
    // without the flag: no spectral channel and no spectral attribute
    let plain = common::render_file(&scene.path, &pt_ov(4, 4, 2, 0));
    assert!(!plain.image.channels.iter().any(|c| SpectralBins::is_channel(&c.name)));
}
