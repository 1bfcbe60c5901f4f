//! Sheen (glTF `KHR_materials_sheen`): a layer of fibres (velvet, cloth, dust) over a base, the
//! "Charlie" distribution of Estevez & Kulla (2017) with the Ashikhmin visibility of Neubelt &
//! Pettineo (2013), layered by albedo scaling as the extension specifies:
//!
//! f = c D(h) V(wo, wi) / N + f_base(wo, wi) (1 - c_max max(Ê(cos o), Ê(cos i))),
//!
//! D(h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi), V = 1 / (4 (cos o + cos i - cos o cos i)),
//! c the sheen colour per wavelength, c_max its largest value, E(mu) the directional albedo of
//! D V (tabulated over roughness and cosine, [`SheenAlbedo`]), Ê = min(E, 1) and
//! N = max(1, E(cos o), E(cos i)). D V alone reflects more than it receives at grazing angles
//! (E = 3.3 at cos 0.02 for roughness 0.07): N scales the lobe down there, symmetrically. So the
//! model is reciprocal and never gains energy: the albedo is at most
//! c Ê(cos o) + (1 - c_max Ê(cos o)) <= 1 over a white base. Sampling picks the sheen lobe
//! (cosine-weighted) or the base by their albedos; the pdf is the mixture's.

use std::f32::consts::PI;
use std::sync::LazyLock;

use glam::{Vec2, Vec3};

use super::{BsdfSample, CoatBase, Lobe, TransportMode, mirror_z, reflecting_side};
use crate::spectrum::SampledSpectrum;

/// Smallest sheen alpha (the extension's renderers clamp similarly; below it D overflows f32).
pub const MIN_SHEEN_ALPHA: f32 = 0.07 * 0.07;
const N_ALPHA: usize = 17;
const N_MU: usize = 32;

/// The directional albedo E(mu) of the Charlie sheen lobe (colour 1, unnormalised: it exceeds 1
/// at grazing angles) over alpha and cosine.
pub struct SheenAlbedo {
    e: [[f32; N_MU]; N_ALPHA],
}

/// The alpha of row `k`: sqrt(alpha) (the perceptual roughness) uniform in [0.07, 1].
fn row_alpha(k: usize) -> f32 {
    let r = 0.07 + (1.0 - 0.07) * k as f32 / (N_ALPHA - 1) as f32;
    r * r
}

/// Charlie D(h) for the cosine of the half vector `cos_h`.
#[inline]
fn charlie(alpha: f32, cos_h: f32) -> f32 {
    let inv = 1.0 / alpha;
    let sin2 = (1.0 - cos_h * cos_h).max(0.0);
    (2.0 + inv) * sin2.powf(0.5 * inv) / (2.0 * PI)
}

/// D V for unit wo, wi above the surface.
#[inline]
fn lobe(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    let h = (wo + wi).normalize_or_zero();
    let d = 4.0 * (wo.z + wi.z - wo.z * wi.z);
    if h == Vec3::ZERO || d <= 0.0 {
        return 0.0;
    }
    charlie(alpha, h.z) / d
}

impl SheenAlbedo {
    fn build() -> Self {
        const G: f64 = 1.324_717_957_244_746;
        let n = 4096;
        let mut e = [[0.0f32; N_MU]; N_ALPHA];
        for (k, row) in e.iter_mut().enumerate() {
            let alpha = row_alpha(k);
            for (m, v) in row.iter_mut().enumerate() {
                let mu = (m as f32 / (N_MU - 1) as f32).max(1e-3);
                let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                // cosine-weighted quasi-Monte Carlo: E = pi mean(D V)
                let mut sum = 0.0f64;
                for i in 0..n {
                    let u = Vec2::new((0.5 + i as f64 / G).fract() as f32, (0.5 + i as f64 / (G * G)).fract() as f32);
                    let wi = crate::warp::cosine_hemisphere(u);
                    if wi.z > 0.0 {
                        sum += f64::from(lobe(alpha, wo, wi));
                    }
                }
                *v = (std::f64::consts::PI * sum / n as f64).max(0.0) as f32;
            }
        }
        Self { e }
    }

    /// The table (built on first use).
    pub fn get() -> &'static SheenAlbedo {
        static TABLE: LazyLock<SheenAlbedo> = LazyLock::new(SheenAlbedo::build);
        &TABLE
    }

    /// E(mu) at `alpha` (bilinear in sqrt(alpha) and mu).
    pub fn albedo(&self, alpha: f32, mu: f32) -> f32 {
        let r = if alpha.is_finite() { alpha.clamp(MIN_SHEEN_ALPHA, 1.0) } else { 1.0 }.sqrt();
        let x = ((r - 0.07) / (1.0 - 0.07)).clamp(0.0, 1.0) * (N_ALPHA - 1) as f32;
        let k = (x as usize).min(N_ALPHA - 2);
        let t = x - k as f32;
        let y = mu.clamp(0.0, 1.0) * (N_MU - 1) as f32;
        let m = (y as usize).min(N_MU - 2);
        let s = y - m as f32;
        let at = |row: &[f32; N_MU]| row[m] + s * (row[m + 1] - row[m]);
        let (a, b) = (at(&self.e[k]), at(&self.e[k + 1]));
        a + t * (b - a)
    }
}

/// A sheen layer over a base at one set of wavelengths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheenBsdf<'a> {
    color: SampledSpectrum,
    color_max: f32,
    alpha: f32,
    base_weight: f32,
    two_sided: bool,
    base: CoatBase<'a>,
}

impl<'a> SheenBsdf<'a> {
    /// Sheen of colour `color` (in [0, 1] per wavelength; `color_max` its largest value over
    /// the spectrum) and alpha (clamped to [`MIN_SHEEN_ALPHA`], 1) over `base`.
    pub fn new(color: SampledSpectrum, color_max: f32, alpha: f32, base: CoatBase<'a>, two_sided: bool) -> Self {
        let alpha = if alpha.is_finite() { alpha.clamp(MIN_SHEEN_ALPHA, 1.0) } else { 1.0 };
        let base_weight = base.mean_albedo();
        let color = color.clamp_unit();
        let color_max = if color_max.is_finite() { color_max.clamp(color.max_component(), 1.0) } else { 1.0 };
        Self { color, color_max, alpha, base_weight, two_sided, base }
    }

    /// Probability of sampling the sheen lobe at cosine `mu`.
    fn sheen_probability(&self, mu: f32) -> f32 {
        let s = self.color_max * SheenAlbedo::get().albedo(self.alpha, mu).min(1.0);
        let d = s + (1.0 - s) * self.base_weight;
        (if d > 0.0 { s / d } else { 1.0 }).clamp(0.1, 0.9)
    }

    fn eval_upper(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, f32) {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (SampledSpectrum::zero(), 0.0);
        }
        let table = SheenAlbedo::get();
        let (eo, ei) = (table.albedo(self.alpha, wo.z), table.albedo(self.alpha, wi.z));
        let scale = 1.0 - self.color_max * eo.max(ei).min(1.0);
        let norm = eo.max(ei).max(1.0);
        let (fb, pb) = self.base.f_pdf(wo, wi, mode);
        let f = self.color * (lobe(self.alpha, wo, wi) / norm) + fb * scale.max(0.0);
        let p = self.sheen_probability(wo.z);
        let pdf = p * wi.z / PI + (1.0 - p) * pb;
        if !(f.is_finite() && pdf.is_finite()) {
            return (SampledSpectrum::zero(), 0.0);
        }
        (f, pdf)
    }

    /// f and pdf together.
    pub fn f_pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, f32) {
        match reflecting_side(wo, self.two_sided) {
            Some(fl) => self.eval_upper(mirror_z(wo, fl), mirror_z(wi, fl), mode),
            None => (SampledSpectrum::zero(), 0.0),
        }
    }

    /// The sheen lobe (cosine-weighted) with probability P(cos o), else the base's sample.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let fl = reflecting_side(wo, self.two_sided)?;
        let wo_u = mirror_z(wo, fl);
        let p = self.sheen_probability(wo_u.z);
        let wi = if uc < p {
            crate::warp::cosine_hemisphere(u)
        } else {
            let uc = ((uc - p) / (1.0 - p)).min(1.0 - f32::EPSILON);
            self.base.sample_f(wo_u, uc, u, mode)?.wi
        };
        if wi.z <= 0.0 {
            return None;
        }
        let (f, pdf) = self.eval_upper(wo_u, wi, mode);
        if pdf.is_nan() || pdf <= 0.0 || f.is_black() {
            return None;
        }
        Some(BsdfSample { f, wi: mirror_z(wi, fl), pdf, lobe: Lobe::Reflection, specular: false, eta: 1.0 })
    }

    /// The same BSDF over a base that borrows nothing (None for a tabulated base).
    pub(crate) fn detached(self) -> Option<SheenBsdf<'static>> {
        let base = self.base.detached()?;
        Some(SheenBsdf {
            color: self.color,
            color_max: self.color_max,
            alpha: self.alpha,
            base_weight: self.base_weight,
            two_sided: self.two_sided,
            base,
        })
    }
}
