//! The render-time lat-long environment map: radiance per direction, importance sampling
//! proportional to luminance times the texels' solid angle, and the density of that sampling
//! (pbrt-v4 section 12.5.2, with a piecewise-constant map).
//!
//! Directions map to (u, v) in [0, 1)^2 as in `quasar_importers::EnvMapDesc`: theta = pi v from
//! the zenith +Y, phi = 2 pi (u - 0.5) from -Z towards +X, then rotated about +Y. The radiance
//! is constant over a texel (box reconstruction), so the sampling density is exactly
//! proportional to the luminance it integrates (MIS weights are exact). A texel of solid angle
//! dw = (2 pi / W)(cos theta_0 - cos theta_1) is picked with probability luminance x dw / total,
//! and a direction uniformly in the texel's (u, v) rectangle: p(w) = p_texel W H / (2 pi^2
//! sin theta).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};
use quasar_importers::EnvMapDesc;
use quasar_materials::spectrum::color::srgb_luminance;
use quasar_materials::spectrum::rgb_uplift::{RgbToSpectrumTable, SigmoidPolynomial};
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum, StandardIlluminant, cie};

use crate::core::sampling::Distribution1D;

/// One texel: a light colour as the uplift of rgb / max(rgb) times max(rgb).
#[derive(Clone, Copy, Debug)]
struct Texel {
    model: SigmoidPolynomial,
    max: f32,
}

/// A lat-long environment map ready for rendering.
#[derive(Debug)]
pub struct EnvMap {
    width: usize,
    height: usize,
    texels: Vec<Texel>,
    /// Row choice, by the rows' luminance x solid angle.
    rows: Distribution1D,
    /// Texel choice within each row.
    columns: Vec<Distribution1D>,
    /// Map frame -> world (orthonormal).
    frame: glam::Mat3,
    /// D65 normalised to luminance 1 (the light colour (1, 1, 1)).
    d65_norm: f32,
    /// Mean radiance over the sphere (luminance-weighted), for light selection.
    mean_luminance: f64,
}

impl EnvMap {
    /// Builds the map: texel colours uplifted (as light colours), sampling distributions.
    pub fn new(desc: &EnvMapDesc) -> Self {
        let (w, h) = (desc.width, desc.height);
        let table = RgbToSpectrumTable::get();
        let texels: Vec<Texel> = desc
            .texels
            .iter()
            .map(|rgb| {
                let m = rgb[0].max(rgb[1]).max(rgb[2]);
                if m > 0.0 && m.is_finite() {
                    Texel { model: table.lookup(rgb.map(|v| v / m)), max: m }
                } else {
                    Texel { model: SigmoidPolynomial::new([0.0; 3]), max: 0.0 }
                }
            })
            .collect();
        let mut row_weights = Vec::with_capacity(h);
        let mut columns = Vec::with_capacity(h);
        let mut total = 0.0f64;
        for y in 0..h {
            let (t0, t1) = (PI * y as f32 / h as f32, PI * (y + 1) as f32 / h as f32);
            let solid_angle = (2.0 * PI / w as f32) * (t0.cos() - t1.cos());
            let weights: Vec<f64> =
                (0..w).map(|x| (srgb_luminance(desc.texels[y * w + x]).max(0.0) * solid_angle) as f64).collect();
            let row: f64 = weights.iter().sum();
            total += row;
            row_weights.push(row);
            columns.push(Distribution1D::new(&weights));
        }
        let d65 = Spectrum::illuminant(StandardIlluminant::D65);
        let Spectrum::Illuminant { norm, .. } = d65 else { unreachable!("an illuminant") };
        Self {
            width: w,
            height: h,
            texels,
            rows: Distribution1D::new(&row_weights),
            columns,
            frame: desc.frame,
            d65_norm: norm,
            mean_luminance: total / (4.0 * std::f64::consts::PI),
        }
    }

    /// Mean luminance of the radiance over the sphere.
    pub fn mean_luminance(&self) -> f64 {
        self.mean_luminance
    }

    /// (u, v) of world direction `d` (unit).
    fn uv(&self, d: Vec3) -> Vec2 {
        // into the map's frame (orthonormal: the inverse is the transpose)
        let m = self.frame.transpose() * d;
        let u = 0.5 + m.x.atan2(-m.z) / (2.0 * PI);
        let v = m.y.clamp(-1.0, 1.0).acos() / PI;
        Vec2::new(u.rem_euclid(1.0), v)
    }

    /// World direction of (u, v).
    fn direction(&self, uv: Vec2) -> Vec3 {
        let (theta, phi) = (PI * uv.y, 2.0 * PI * (uv.x - 0.5));
        let (st, ct) = theta.sin_cos();
        self.frame * Vec3::new(st * phi.sin(), ct, -st * phi.cos())
    }

    fn texel_index(&self, uv: Vec2) -> usize {
        let x = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        y * self.width + x
    }

    /// Radiance arriving from direction `d` (towards the scene: the ray direction that escaped)
    /// at wavelengths `wl`, before the light's scale.
    pub fn radiance(&self, d: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.texel_radiance(self.texel_index(self.uv(d)), wl)
    }

    /// Radiance of texel `i` at wavelengths `wl`.
    fn texel_radiance(&self, i: usize, wl: &SampledWavelengths) -> SampledSpectrum {
        let t = self.texels[i];
        if t.max <= 0.0 {
            return SampledSpectrum::zero();
        }
        SampledSpectrum(std::array::from_fn(|i| {
            let l = wl.lambda(i);
            t.max * t.model.eval(l) * cie::d65(l) * self.d65_norm
        }))
    }

    /// Solid-angle density with which [`sample`](Self::sample) returns direction `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let uv = self.uv(d);
        let i = self.texel_index(uv);
        self.pdf_of_texel(i / self.width, i % self.width, uv.y)
    }

    /// The density at height `v` in texel (row `y`, column `x`).
    fn pdf_of_texel(&self, y: usize, x: usize, v: f32) -> f32 {
        let sin_theta = (PI * v).sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        let p = self.rows.pmf(y) * self.columns[y].pmf(x);
        p * (self.width * self.height) as f32 / (2.0 * PI * PI * sin_theta)
    }

    /// A direction by luminance x solid angle, its solid-angle density and the radiance from it
    /// at `wl` (the sampled texel's: within 1e-4 rad of the poles f32 directions can map back to
    /// a neighbour); None for a black map.
    pub fn sample(&self, u: Vec2, wl: &SampledWavelengths) -> Option<(Vec3, f32, SampledSpectrum)> {
        let (y, _, uy) = self.rows.sample_remapped(u.y)?;
        let (x, _, ux) = self.columns[y].sample_remapped(u.x)?;
        // off the texel borders: the direction maps back into this texel, never onto a pole
        let (ux, uy) = (ux.clamp(1e-4, 1.0 - 1e-4), uy.clamp(1e-4, 1.0 - 1e-4));
        let uv = Vec2::new((x as f32 + ux) / self.width as f32, (y as f32 + uy) / self.height as f32);
        // the density from (u, v), not from the direction: near the poles f32 cannot tell
        // cos theta from -1 or 1
        let pdf = self.pdf_of_texel(y, x, uv.y);
        (pdf > 0.0 && pdf.is_finite()).then(|| (self.direction(uv), pdf, self.texel_radiance(y * self.width + x, wl)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::sampling::Sampler;

    fn map(w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; 3]) -> EnvMap {
        let texels = (0..w * h).map(|i| f(i % w, i / w)).collect();
        EnvMap::new(&EnvMapDesc {
            file: "t.exr".into(),
            width: w,
            height: h,
            texels,
            frame: glam::Mat3::from_rotation_y(30f32.to_radians()),
        })
    }

    #[test]
    fn directions_and_uv_are_inverse() {
        let m = map(8, 4, |_, _| [1.0; 3]);
        for (u, v) in [(0.1f32, 0.2f32), (0.5, 0.5), (0.9, 0.7), (0.3, 0.95)] {
            let uv = m.uv(m.direction(Vec2::new(u, v)));
            assert!((uv.x - u).abs() < 1e-5 && (uv.y - v).abs() < 1e-5, "{u} {v} -> {uv}");
        }
        // unrotated: the image centre looks along -Z, the top row at +Y
        let m0 = EnvMap::new(&EnvMapDesc {
            file: "t.exr".into(),
            width: 4,
            height: 2,
            texels: vec![[1.0; 3]; 8],
            frame: glam::Mat3::IDENTITY,
        });
        assert!((m0.direction(Vec2::new(0.5, 0.5)) - Vec3::NEG_Z).length() < 1e-6);
        assert!((m0.direction(Vec2::new(0.75, 0.5)) - Vec3::X).length() < 1e-6);
        assert!((m0.direction(Vec2::new(0.3, 0.0)) - Vec3::Y).length() < 1e-6);
    }

    /// Sampled directions land in texels with the probability the density gives them
    /// (chi-square over the texels) and the density integrates to 1.
    #[test]
    fn sampling_matches_the_density() {
        let m = map(16, 8, |x, y| [0.1 + (x * 7 % 5) as f32, 0.2 * y as f32, 1.0]);
        let n = 200_000;
        let mut counts = vec![0usize; 16 * 8];
        let mut s = Sampler::new(3, 0, 0);
        let wl = SampledWavelengths::sample_uniform(0.4);
        let mut mapped_elsewhere = 0;
        for _ in 0..n {
            let (d, pdf, _) = m.sample(s.get_2d(), &wl).unwrap();
            let back = m.pdf(d);
            if (pdf - back).abs() > 1e-2 * pdf {
                mapped_elsewhere += 1; // a direction within 1e-4 rad of a pole
            }
            counts[m.texel_index(m.uv(d))] += 1;
        }
        assert!(mapped_elsewhere < n / 1000, "{mapped_elsewhere} of {n} samples change texel on the way back");
        let mut chi2 = 0.0;
        let mut dof = 0;
        for y in 0..8 {
            for x in 0..16 {
                let expected = m.rows.pmf(y) as f64 * m.columns[y].pmf(x) as f64 * n as f64;
                if expected > 5.0 {
                    chi2 += (counts[y * 16 + x] as f64 - expected).powi(2) / expected;
                    dof += 1;
                }
            }
        }
        // chi-square with ~127 degrees of freedom: mean 127, sd 16
        assert!(chi2 < dof as f64 + 6.0 * (2.0 * dof as f64).sqrt(), "chi2 {chi2} for {dof}");
        // integral of the density over the sphere (uniform sphere samples)
        let mut i = 0.0f64;
        for _ in 0..n {
            let d = crate::core::sampling::uniform_sphere(s.get_2d());
            i += m.pdf(d) as f64 / crate::core::sampling::UNIFORM_SPHERE_PDF as f64;
        }
        assert!((i / n as f64 - 1.0).abs() < 0.02, "{}", i / n as f64);
    }

    #[test]
    fn white_texels_are_d65_of_luminance_one() {
        let m = map(4, 2, |_, _| [1.0; 3]);
        let mut y = 0.0f64;
        let k = 2000;
        for j in 0..k {
            let wl = SampledWavelengths::sample_visible((j as f32 + 0.5) / k as f32);
            y += wl.luminance(m.radiance(Vec3::Y, &wl)) as f64;
        }
        assert!((y / k as f64 - 1.0).abs() < 5e-3, "{}", y / k as f64);
    }
}
