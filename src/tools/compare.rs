//! Image comparison (`quasar compare`): error metrics of one EXR against a reference, per layer,
//! and a false-colour difference image.

use std::path::Path;

use crate::film::LUMINANCE;
use crate::output::ExrImage;

/// Error metrics of one layer of an image against a reference.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerError {
    /// Layer name ("" for the beauty channels R, G, B; else e.g. "indirect").
    pub layer: String,
    /// Root mean squared error over the layer's channels and pixels.
    pub rmse: f64,
    /// Relative MSE: mean over channels and pixels of (a - r)^2 / (r^2 + 1e-3) (the usual
    /// denoising-literature relMSE; the 1e-3 keeps black reference pixels finite).
    pub rel_mse: f64,
    /// Mean relative error |a - r| / (|r| + 1e-3).
    pub mean_rel_error: f64,
    /// Largest absolute difference.
    pub max_error: f64,
    /// Mean of the image's layer and of the reference's.
    pub means: (f64, f64),
}

pub use crate::film::REL_EPS;

/// Relative MSE of `a` against `r` (see [`LayerError::rel_mse`]).
pub fn rel_mse(a: &[f32], r: &[f32]) -> f64 {
    let n = a.len().min(r.len()).max(1);
    a.iter().zip(r).map(|(&a, &r)| (a as f64 - r as f64).powi(2) / ((r as f64).powi(2) + REL_EPS)).sum::<f64>()
        / n as f64
}

/// Mean relative error of `a` against `r` (see [`LayerError::mean_rel_error`]): an L1 measure, which
/// a single bright outlier pixel moves far less than relMSE.
pub fn mean_rel_error(a: &[f32], r: &[f32]) -> f64 {
    let n = a.len().min(r.len()).max(1);
    a.iter().zip(r).map(|(&a, &r)| (a as f64 - r as f64).abs() / ((r as f64).abs() + REL_EPS)).sum::<f64>() / n as f64
}

/// The layer of a channel name: the part before the last '.', or "" for bare beauty channels.
fn layer_of(name: &str) -> &str {
    name.rsplit_once('.').map_or("", |(l, _)| l)
}

/// Compares `img` against `reference` for every layer present in both (or only `only`), over
/// channels with the same name. Errors when the sizes differ or nothing is shared.
pub fn compare(img: &ExrImage, reference: &ExrImage, only: Option<&str>) -> Result<Vec<LayerError>, String> {
    if (img.width, img.height) != (reference.width, reference.height) {
        return Err(format!(
            "image sizes differ: {}x{} vs reference {}x{}",
            img.width, img.height, reference.width, reference.height
        ));
    }
    let mut shared: Vec<&str> = Vec::new();
    for c in &img.channels {
        let l = layer_of(&c.name);
        // the output table says which channels are statistics of the render, not images of the
        // scene; a channel it does not know (another renderer's) is compared
        let statistic = crate::film::outputs::group_of(&c.name).is_some_and(|g| !g.compared);
        if statistic || reference.channel(&c.name).is_none() || shared.contains(&l) {
            continue;
        }
        shared.push(l);
    }
    let name = |l: &str| if l.is_empty() { "beauty".to_string() } else { l.to_string() };
    let layers: Vec<&str> =
        shared.iter().copied().filter(|&l| only.is_none_or(|o| o == l || (o == "beauty" && l.is_empty()))).collect();
    if layers.is_empty() {
        return Err(match only {
            Some(o) if !shared.is_empty() => format!(
                "layer '{o}' is not in both images; the layers they share: {}",
                shared.iter().map(|&l| name(l)).collect::<Vec<_>>().join(", ")
            ),
            _ => "the images share no layer".into(),
        });
    }
    let mut out = Vec::new();
    for l in layers {
        let (mut se, mut rel, mut mre, mut max, mut n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0usize);
        let (mut sum_a, mut sum_r) = (0.0f64, 0.0f64);
        for c in img.channels.iter().filter(|c| layer_of(&c.name) == l) {
            let Some(r) = reference.channel(&c.name) else { continue };
            for (&a, &r) in c.values.iter().zip(r) {
                let (a, r) = (a as f64, r as f64);
                if !a.is_finite() || !r.is_finite() {
                    continue;
                }
                let d = a - r;
                se += d * d;
                rel += d * d / (r * r + REL_EPS);
                mre += d.abs() / (r.abs() + REL_EPS);
                max = max.max(d.abs());
                sum_a += a;
                sum_r += r;
                n += 1;
            }
        }
        let nf = n.max(1) as f64;
        out.push(LayerError {
            layer: name(l),
            rmse: (se / nf).sqrt(),
            rel_mse: rel / nf,
            mean_rel_error: mre / nf,
            max_error: max,
            means: (sum_a / nf, sum_r / nf),
        });
    }
    Ok(out)
}

/// A number in scientific notation with 5 significant digits and a signed two-digit exponent,
/// as C's `%.4e` writes it ("3.4516e-01"; Rust's `{:e}` writes "3.4516e-1").
pub fn scientific(v: f64) -> String {
    if !v.is_finite() {
        return v.to_string();
    }
    let s = format!("{v:.4e}");
    let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    format!("{mantissa}e{}{:02}", if exp < 0 { '-' } else { '+' }, exp.abs())
}

/// `quasar compare`'s table of [`compare`]'s metrics.
pub fn table(errors: &[LayerError]) -> String {
    let mut s = format!(
        "{:<12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n",
        "layer", "rmse", "relmse", "mean_rel", "max", "mean", "ref_mean"
    );
    for e in errors {
        let v = [e.rmse, e.rel_mse, e.mean_rel_error, e.max_error, e.means.0, e.means.1].map(scientific);
        s +=
            &format!("{:<12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n", e.layer, v[0], v[1], v[2], v[3], v[4], v[5]);
    }
    s
}

/// False colour of a signed relative difference: blue (image darker) through black (equal) to red
/// (image brighter), saturating at +-`full_scale`.
fn false_colour(rel: f64, full_scale: f64) -> [u8; 3] {
    let t = (rel / full_scale).clamp(-1.0, 1.0);
    let v = (t.abs().sqrt() * 255.0 + 0.5) as u8;
    if t >= 0.0 { [v, (v as f32 * 0.25) as u8, 0] } else { [0, (v as f32 * 0.25) as u8, v] }
}

/// Writes a PNG of the per-pixel relative difference of luminance `Y` (image - reference) /
/// (reference + 1e-3), in false colour saturating at +-100%.
pub fn write_difference_png(img: &ExrImage, reference: &ExrImage, path: &Path) -> Result<(), String> {
    let (Some(a), Some(r)) = (img.channel(LUMINANCE), reference.channel(LUMINANCE)) else {
        return Err("both images need an XYZ.Y channel for the difference image".into());
    };
    let mut buf = Vec::with_capacity(a.len() * 3);
    for (&a, &r) in a.iter().zip(r) {
        let rel = (a as f64 - r as f64) / (r.abs() as f64 + REL_EPS);
        buf.extend(false_colour(if rel.is_finite() { rel } else { 0.0 }, 1.0));
    }
    let png = image::RgbImage::from_raw(img.width as u32, img.height as u32, buf).ok_or("image size mismatch")?;
    crate::output::write_png_atomic(path, &png).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::film::Channel;

    #[test]
    fn scientific_notation_has_a_signed_two_digit_exponent() {
        assert_eq!(scientific(0.345158), "3.4516e-01");
        assert_eq!(scientific(3.45158), "3.4516e+00");
        assert_eq!(scientific(12345.0), "1.2345e+04");
        assert_eq!(scientific(0.0), "0.0000e+00");
        assert_eq!(scientific(-2.5e-120), "-2.5000e-120");
    }

    fn image(values: &[f32]) -> ExrImage {
        let ch = |n: &str| Channel { name: n.into(), values: values.to_vec() };
        ExrImage {
            width: values.len(),
            height: 1,
            channels: vec![ch("XYZ.Y"), ch("R"), ch("direct.R"), ch("spp.Y")],
            metadata: vec![],
        }
    }

    #[test]
    fn metrics_of_known_differences() {
        let r = image(&[1.0, 2.0, 0.0, 4.0]);
        let a = image(&[1.0, 3.0, 0.0, 2.0]);
        let e = compare(&a, &r, None).unwrap();
        let names: Vec<_> = e.iter().map(|l| l.layer.as_str()).collect();
        assert_eq!(names, ["XYZ", "beauty", "direct"]);
        let d = &e[2];
        assert!((d.rmse - (5.0f64 / 4.0).sqrt()).abs() < 1e-12);
        assert!((d.rel_mse - (1.0 / (4.0 + REL_EPS) + 4.0 / (16.0 + REL_EPS)) / 4.0).abs() < 1e-12);
        assert_eq!(d.max_error, 2.0);
        assert_eq!(d.means, (1.5, 1.75));
        assert_eq!(compare(&r, &r, Some("direct")).unwrap()[0].rel_mse, 0.0);
        let err = compare(&r, &r, Some("caustic")).unwrap_err();
        assert!(err.contains("the layers they share: XYZ, beauty, direct"), "{err}");
        assert!(compare(&image(&[1.0]), &r, None).is_err());
        // the slice forms agree with the layer's
        let (a, r) = ([1.0f32, 3.0, 0.0, 2.0], [1.0f32, 2.0, 0.0, 4.0]);
        assert!((rel_mse(&a, &r) - d.rel_mse).abs() < 1e-12);
        assert!((mean_rel_error(&a, &r) - d.mean_rel_error).abs() < 1e-12);
        assert!((d.mean_rel_error - (1.0 / (2.0 + REL_EPS) + 2.0 / (4.0 + REL_EPS)) / 4.0).abs() < 1e-12);
    }
}
