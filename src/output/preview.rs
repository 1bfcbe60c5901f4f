//! Tone-mapped 8-bit sRGB PNG previews of the beauty channels: an exposure (fixed or automatic),
//! a view transform, the sRGB transfer curve.
//!
//! - **Automatic exposure** ([`Exposure::Auto`], the default of `quasar render --preview`): the
//!   log-average luminance of the lit pixels, exp(mean ln Y) over the pixels with Y > 0, is
//!   scaled to 0.18, the mid-grey "key" of photographic tone reproduction (Reinhard et al. 2002,
//!   "Photographic tone reproduction for digital images", §3). A scene in photometric units
//!   (glTF: thousands of cd/m^2) and one of unit radiance then both preview readable.
//! - **Views**: [`View::Standard`] clips each channel to [0, 1] (Blender's "Standard"): a bright
//!   saturated red clips to (1, g, b) with g and b still rising, so it turns orange, then yellow.
//!   [`View::Filmic`] maps the largest channel m through a filmic curve f (Narkowicz's fit of the
//!   ACES reference rendering transform, f(x) = x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14),
//!   clamped to 1) and scales the pixel by f(m) / m, so the ratios of the channels, i.e. hue and
//!   saturation, are kept below the shoulder; over the last 20% of the output range the colour is
//!   blended towards white of the same value (as film bleaches), so very bright lights end white,
//!   never orange.

use std::path::Path;

/// The mid-grey key automatic exposure maps the log-average luminance to.
pub const AUTO_EXPOSURE_KEY: f32 = 0.18;

/// How the preview's exposure is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exposure {
    /// From the image (module documentation).
    Auto,
    /// Fixed: the image is scaled by 2^EV.
    Stops(f32),
}

/// The view transform: how scene-linear values become display values in [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum View {
    /// Hue-preserving filmic curve with a path to white (module documentation).
    #[default]
    Filmic,
    /// Per-channel clipping to [0, 1].
    Standard,
}

impl View {
    /// Every view with its command-line name.
    pub const ALL: [(&'static str, View); 2] = [("filmic", View::Filmic), ("standard", View::Standard)];

    /// The view named `name`.
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|&(_, v)| v).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|(n, _)| *n).collect();
            format!("unknown view `{name}` (expected one of: {})", names.join(", "))
        })
    }

    /// Display values in [0, 1] of the linear sRGB pixel `rgb` (already exposed).
    pub fn apply(self, rgb: [f32; 3]) -> [f32; 3] {
        let rgb = rgb.map(|c| if c.is_finite() { c.max(0.0) } else { 0.0 });
        match self {
            View::Standard => rgb.map(|c| c.min(1.0)),
            View::Filmic => {
                let m = rgb[0].max(rgb[1]).max(rgb[2]);
                if m <= 0.0 {
                    return [0.0; 3];
                }
                let t = aces_fit(m);
                let white = ((t - 0.8) / 0.2).clamp(0.0, 1.0);
                let w = white * white;
                rgb.map(|c| ((c * t / m) * (1.0 - w) + t * w).min(1.0))
            }
        }
    }
}

/// Narkowicz's fit of the ACES tone curve (module documentation), clamped to [0, 1].
fn aces_fit(x: f32) -> f32 {
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// The scale 2^EV that `exposure` gives for an image with luminance `y` (row-major).
pub fn exposure_scale(exposure: Exposure, y: &[f32]) -> f32 {
    match exposure {
        Exposure::Stops(ev) => 2f32.powf(ev),
        Exposure::Auto => {
            let (mut sum, mut n) = (0.0f64, 0u64);
            for &v in y.iter().filter(|v| v.is_finite() && **v > 0.0) {
                sum += f64::from(v).ln();
                n += 1;
            }
            if n == 0 {
                return 1.0;
            }
            let log_average = (sum / n as f64).exp() as f32;
            let s = AUTO_EXPOSURE_KEY / log_average;
            if s.is_finite() && s > 0.0 { s } else { 1.0 }
        }
    }
}

/// sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
fn srgb_encode(v: f32) -> f32 {
    if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }
}

/// Writes linear sRGB `r, g, b` (row-major) as a PNG: scaled by `scale` (from
/// [`exposure_scale`]), through `view`, the sRGB transfer curve and 8-bit rounding. Non-finite
/// values become 0. Atomic like the EXR writer.
pub fn write_preview_png(
    path: &Path,
    width: u32,
    height: u32,
    rgb: [&[f32]; 3],
    scale: f32,
    view: View,
) -> Result<(), String> {
    let mut buf = Vec::with_capacity(width as usize * height as usize * 3);
    let n = width as usize * height as usize;
    for ((&r, &g), &b) in rgb[0][..n].iter().zip(&rgb[1][..n]).zip(&rgb[2][..n]) {
        let px = view.apply([r * scale, g * scale, b * scale]);
        buf.extend(px.map(|v| (srgb_encode(v) * 255.0 + 0.5) as u8));
    }
    let img = image::RgbImage::from_raw(width, height, buf).ok_or("preview buffer size mismatch")?;
    super::write_png_atomic(path, &img).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_exposure_maps_the_log_average_to_the_key() {
        // log-average of 2 and 8 is 4; zeros and non-finite values are left out
        let s = exposure_scale(Exposure::Auto, &[2.0, 8.0, 0.0, f32::NAN, f32::INFINITY]);
        assert!((s - AUTO_EXPOSURE_KEY / 4.0).abs() < 1e-6, "{s}");
        assert_eq!(exposure_scale(Exposure::Auto, &[0.0, 0.0]), 1.0);
        assert_eq!(exposure_scale(Exposure::Stops(2.0), &[5.0]), 4.0);
    }

    #[test]
    fn filmic_keeps_hue_and_bleaches_to_white() {
        let hue = |c: [f32; 3]| (c[1] - c[2]) / (c[0] - c[2]);
        // a saturated red: standard clipping shifts it towards orange as it brightens
        let red = [1.0, 0.2, 0.05];
        let clipped = View::Standard.apply(red.map(|c| c * 4.0));
        assert!(hue(clipped) > 2.0 * hue(red), "{clipped:?}");
        // filmic: the same ratios below the shoulder
        for k in [0.05f32, 0.3, 0.8] {
            let f = View::Filmic.apply(red.map(|c| c * k));
            assert!((hue(f) - hue(red)).abs() < 1e-4, "{k}: {f:?}");
            assert!(f[0] < 1.0);
        }
        // far above the shoulder: white, and never above 1
        let f = View::Filmic.apply(red.map(|c| c * 1e4));
        assert!(f.iter().all(|&c| c > 0.99 && c <= 1.0), "{f:?}");
        // monotone in brightness, grey stays grey, black and NaN give black
        let mut last = 0.0;
        for i in 1..200 {
            let g = View::Filmic.apply([i as f32 * 0.05; 3]);
            assert!(g[0] >= last && g[0] == g[1] && g[1] == g[2]);
            last = g[0];
        }
        assert_eq!(View::Filmic.apply([0.0, f32::NAN, -1.0]), [0.0; 3]);
        assert_eq!(View::from_name("standard"), Ok(View::Standard));
        assert!(View::from_name("agx").unwrap_err().contains("filmic, standard"));
    }
}
