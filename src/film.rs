//! The film: per-pixel accumulation of the radiance layers in CIE XYZ, and their conversion to
//! the output AOV channels (DESIGN.md section 5).

use quasar_materials::spectrum::SampledWavelengths;
use quasar_materials::spectrum::color::xyz_to_linear_srgb;

use crate::integrator::LayeredRadiance;

/// Number of radiance layers (emission, direct, indirect, caustic).
pub const N_LAYERS: usize = 4;
/// Names of the radiance layers, in accumulation order.
pub const LAYER_NAMES: [&str; N_LAYERS] = ["emission", "direct", "indirect", "caustic"];
/// The layers whose sum is the beauty image (`caustic` is a part of `indirect`).
pub const BEAUTY_LAYERS: usize = 3;

/// Sum of XYZ per layer for one pixel, in f64 so long renders do not lose precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelSum {
    /// [layer][X, Y, Z].
    pub xyz: [[f64; 3]; N_LAYERS],
    /// Sum of the squared beauty luminance of the samples (for the per-pixel noise estimate).
    pub y_sq: f64,
    /// Samples accumulated (including rejected non-finite ones, which count as zero).
    pub samples: u64,
    /// Samples whose value was not finite and was dropped.
    pub rejected: u64,
}

impl PixelSum {
    /// Adds one path's layered radiance at wavelengths `wl`. A sample with any non-finite
    /// component is replaced by zero (and counted), so no NaN/inf can reach a pixel.
    #[inline]
    pub fn add(&mut self, l: &LayeredRadiance, wl: &SampledWavelengths) {
        let layers = [wl.to_xyz(l.emission), wl.to_xyz(l.direct), wl.to_xyz(l.indirect), wl.to_xyz(l.caustic)];
        self.samples += 1;
        if layers.iter().flatten().any(|v| !v.is_finite()) {
            self.rejected += 1;
            return;
        }
        let y: f64 = layers[..BEAUTY_LAYERS].iter().map(|v| v[1] as f64).sum();
        self.y_sq += y * y;
        for (acc, v) in self.xyz.iter_mut().zip(layers) {
            for k in 0..3 {
                acc[k] += v[k] as f64;
            }
        }
    }

    /// Standard error of the pixel's mean beauty luminance, sqrt(s^2 / n) with the unbiased sample
    /// variance s^2 of the per-sample luminance; 0 with fewer than two samples.
    pub fn stderr_y(&self) -> f64 {
        if self.samples < 2 {
            return 0.0;
        }
        let n = self.samples as f64;
        let sum: f64 = self.xyz[..BEAUTY_LAYERS].iter().map(|l| l[1]).sum();
        let var = ((self.y_sq - sum * sum / n) / (n - 1.0)).max(0.0);
        (var / n).sqrt()
    }

    /// Adds another sum (same pixel, disjoint samples).
    pub fn merge(&mut self, o: &PixelSum) {
        for l in 0..N_LAYERS {
            for k in 0..3 {
                self.xyz[l][k] += o.xyz[l][k];
            }
        }
        self.y_sq += o.y_sq;
        self.samples += o.samples;
        self.rejected += o.rejected;
    }
}

/// An image of pixel sums, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixel sums.
    pub pixels: Vec<PixelSum>,
}

/// A named float channel of an output image.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// EXR channel name, `layer.channel` (Blender/Nuke convention) or a bare beauty channel.
    pub name: String,
    /// Row-major values, row 0 at the top.
    pub values: Vec<f32>,
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, pixels: vec![PixelSum::default(); width as usize * height as usize] }
    }

    /// Mean XYZ of `layer` at pixel `i`.
    pub fn mean_xyz(&self, i: usize, layer: usize) -> [f64; 3] {
        let p = &self.pixels[i];
        if p.samples == 0 {
            return [0.0; 3];
        }
        p.xyz[layer].map(|v| v / p.samples as f64)
    }

    /// Output channels: beauty `R,G,B`, luminance `Y`, and `<layer>.R/G/B` for every layer.
    /// Beauty is the sum of the emission, direct and indirect layers' RGB, so beauty = emission +
    /// direct + indirect exactly up to one float rounding per addition; `caustic` is the part of
    /// `indirect` that reached its diffuse vertex through specular events only.
    pub fn channels(&self) -> Vec<Channel> {
        let n = self.pixels.len();
        let mut beauty = [vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]];
        let mut y = vec![0.0f32; n];
        let mut layers: Vec<[Vec<f32>; 3]> =
            (0..N_LAYERS).map(|_| [vec![0.0; n], vec![0.0; n], vec![0.0; n]]).collect();
        for i in 0..n {
            let mut sum_rgb = [0.0f32; 3];
            let mut sum_y = 0.0f32;
            for (l, layer) in layers.iter_mut().enumerate() {
                let xyz = self.mean_xyz(i, l).map(|v| v as f32);
                let rgb = xyz_to_linear_srgb(xyz);
                for k in 0..3 {
                    layer[k][i] = rgb[k];
                }
                if l < BEAUTY_LAYERS {
                    for k in 0..3 {
                        sum_rgb[k] += rgb[k];
                    }
                    sum_y += xyz[1];
                }
            }
            for k in 0..3 {
                beauty[k][i] = sum_rgb[k];
            }
            y[i] = sum_y;
        }
        let mut out = Vec::new();
        for (k, c) in ["R", "G", "B"].iter().enumerate() {
            out.push(Channel { name: c.to_string(), values: std::mem::take(&mut beauty[k]) });
        }
        out.push(Channel { name: "Y".into(), values: y });
        for (l, layer) in layers.into_iter().enumerate() {
            for (k, values) in layer.into_iter().enumerate() {
                out.push(Channel { name: format!("{}.{}", LAYER_NAMES[l], ["R", "G", "B"][k]), values });
            }
        }
        out.push(Channel { name: "spp.Y".into(), values: self.pixels.iter().map(|p| p.samples as f32).collect() });
        out.push(Channel {
            name: "stderr.Y".into(),
            values: self.pixels.iter().map(|p| p.stderr_y() as f32).collect(),
        });
        out
    }

    /// The image's estimated RMS relative error: sqrt of the mean over pixels of
    /// stderr^2 / (Y^2 + 1e-3), the expected relMSE against the converged image (the relMSE of
    /// `quasar compare`) if the pixel estimates are unbiased. Infinite before every pixel has two
    /// samples.
    pub fn estimated_rel_error(&self) -> f64 {
        if self.pixels.iter().any(|p| p.samples < 2) {
            return f64::INFINITY;
        }
        let sum: f64 = self
            .pixels
            .iter()
            .map(|p| {
                let y: f64 = p.xyz[..BEAUTY_LAYERS].iter().map(|l| l[1]).sum::<f64>() / p.samples as f64;
                let e = p.stderr_y();
                e * e / (y * y + crate::compare::REL_EPS)
            })
            .sum();
        (sum / self.pixels.len().max(1) as f64).sqrt()
    }

    /// Total number of rejected (non-finite) samples.
    pub fn rejected_samples(&self) -> u64 {
        self.pixels.iter().map(|p| p.rejected).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths};

    #[test]
    fn standard_error_of_known_samples() {
        let wl = SampledWavelengths::from_parts([550.0; 4], [1.0; 4]);
        let mut p = PixelSum::default();
        let unit = wl.luminance(SampledSpectrum::one());
        for v in [1.0f32, 3.0] {
            let l = LayeredRadiance { direct: SampledSpectrum::one() * v, ..Default::default() };
            p.add(&l, &wl);
        }
        // samples y = unit, 3 unit: variance 2 unit^2, stderr sqrt(2 / 2) unit
        assert!((p.stderr_y() - unit as f64).abs() < 1e-4 * unit as f64);
        let mut film = Film::new(1, 1);
        assert!(film.estimated_rel_error().is_infinite());
        film.pixels[0] = p;
        let y = 2.0 * unit as f64;
        let expected = (unit as f64 * unit as f64 / (y * y + crate::compare::REL_EPS)).sqrt();
        assert!((film.estimated_rel_error() - expected).abs() < 1e-6);
    }
}
