//! The non-uniformity coefficient kappa(wo) of a material (docs/architecture.md §5; Zhdanov et al.
//! 2015): how much more a BSDF scatters into its strongest direction than on average, for a
//! given incidence. Gathering photons where kappa is small (diffuse surfaces) keeps the noise of
//! the density estimate low; kappa is large for narrow lobes and infinite for specular surfaces.
//!
//! kappa(wo) = Omega max_wi Y[f(wo, wi)] / Y[integral f(wo, wi) |cos wi| dwi], with Y the
//! CIE-ybar-weighted mean over wavelengths and Omega the projected solid angle of the scattering
//! domain (pi for reflectors, 2 pi when the BSDF transmits). This is the design's "max of f cos
//! over its mean" with the mean taken in projected solid angle, which makes kappa exactly 1 for a
//! Lambertian surface (as the design requires) and of the order of 1 / (lobe solid angle) for a
//! narrow one.

use glam::{Vec2, Vec3};

use crate::bsdf::{Bsdf, TransportMode};
use crate::material::Material;
use crate::spectrum::{SampledWavelengths, cie};

/// kappa above which a lobe counts as narrow: photon density estimates there are noise (a
/// GGX lobe of alpha below about 0.1). The scene analysis calls such materials narrow, and the
/// quasi-specular methods never gather at a vertex whose kappa(wo) exceeds it.
pub const NARROW_KAPPA: f32 = 20.0;

/// Number of incidence cosines tabulated, uniformly over cos(theta_o) in [-1, 1].
pub const KAPPA_TABLE_SIZE: usize = 33;
/// Directions sampled per incidence to estimate the albedo and the maximum.
const KAPPA_SAMPLES: usize = 1024;
/// The wavelengths (nm) of the luminance weighting, in batches of four (one BSDF per batch).
const KAPPA_WAVELENGTHS: [[f32; 4]; 3] =
    [[420.0, 445.0, 470.0, 495.0], [520.0, 545.0, 570.0, 595.0], [620.0, 645.0, 670.0, 695.0]];

/// kappa tabulated over the incidence cosine (negative: incidence from the back side).
#[derive(Clone, Debug, PartialEq)]
pub struct NonUniformity {
    values: [f32; KAPPA_TABLE_SIZE],
    /// kappa of the reflection lobe alone.
    reflection: [f32; KAPPA_TABLE_SIZE],
    /// kappa of the transmission lobe alone.
    transmission: [f32; KAPPA_TABLE_SIZE],
}

/// The R2 low-discrepancy sequence (Roberts 2018): point `i` in [0, 1)^2.
fn r2(i: usize) -> Vec2 {
    const G: f64 = 1.324_717_957_244_746;
    let x = (0.5 + i as f64 / G).fract();
    let y = (0.5 + i as f64 / (G * G)).fract();
    Vec2::new(x as f32, y as f32)
}

/// kappa of `material` for the incidence direction `wo` (local frame, unit).
pub fn kappa(material: &Material, wo: Vec3) -> f32 {
    kappas(material, wo).whole
}

/// kappa of a whole BSDF and of each of its two lobes for one incidence direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeKappas {
    /// Over the whole scattering domain (the hemisphere of a reflector, the sphere otherwise).
    pub whole: f32,
    /// Over the reflection hemisphere alone (wi on `wo`'s side): Omega = pi and the reflected
    /// albedo in the denominator.
    pub reflection: f32,
    /// Over the transmission hemisphere alone; infinite for a BSDF that transmits nothing.
    pub transmission: f32,
}

/// kappa of `material` for `wo` (local frame, unit), whole and per lobe: a lobe's kappa is
/// pi max_{wi in lobe} Y[f] / Y[integral over the lobe's hemisphere of f |cos wi|], exactly 1
/// for a Lambertian reflector or transmitter. A lobe that scatters nothing (the refraction of a
/// dielectric under total internal reflection, the reflection of a reflector's back) is
/// infinite: nothing arrives there to gather, so a method passes it through like a narrow one.
pub fn kappas(material: &Material, wo: Vec3) -> LobeKappas {
    let bsdfs: Vec<(Bsdf, [f32; 4])> = KAPPA_WAVELENGTHS
        .iter()
        .map(|l| {
            let mut wl = SampledWavelengths::from_parts(*l, [1.0; 4]);
            let ybar = l.map(|x| cie::cmf(x)[1]);
            (material.bsdf(&mut wl), ybar)
        })
        .collect();
    if bsdfs.iter().any(|(b, _)| b.is_specular()) {
        return LobeKappas { whole: f32::INFINITY, reflection: f32::INFINITY, transmission: f32::INFINITY };
    }
    let y_norm: f32 = bsdfs.iter().flat_map(|(_, y)| y.iter()).sum();
    let y_of = |wi: Vec3| -> f32 {
        bsdfs
            .iter()
            .map(|(b, y)| (0..4).map(|k| b.f(wo, wi, TransportMode::Radiance)[k] * y[k]).sum::<f32>())
            .sum::<f32>()
            / y_norm
    };
    let sampler = &bsdfs[0].0;
    // per lobe (0 reflection, 1 transmission): the largest Y[f] and the albedo
    let mut max = [0.0f32; 2];
    let mut albedo = [0.0f64; 2];
    let lobe = |wi: Vec3| usize::from(wi.z * wo.z < 0.0);
    for i in 0..KAPPA_SAMPLES {
        let uc = (i as f32 + 0.5) / KAPPA_SAMPLES as f32;
        let Some(bs) = sampler.sample_f(wo, uc, r2(i), TransportMode::Radiance) else { continue };
        if bs.pdf <= 0.0 {
            continue;
        }
        let yf = y_of(bs.wi);
        if yf.is_finite() {
            let l = lobe(bs.wi);
            max[l] = max[l].max(yf);
            albedo[l] += (yf * bs.wi.z.abs() / bs.pdf) as f64;
        }
    }
    let (mirror, refracted) = sampler.ideal_directions(wo);
    for w in [mirror, refracted].into_iter().flatten() {
        let yf = y_of(w);
        if yf.is_finite() {
            let l = lobe(w);
            max[l] = max[l].max(yf);
        }
    }
    let albedo = albedo.map(|a| a / KAPPA_SAMPLES as f64);
    let pi = std::f64::consts::PI;
    let per_lobe = |l: usize| {
        if albedo[l].is_nan() || albedo[l] <= 0.0 || max[l] <= 0.0 {
            f32::INFINITY
        } else {
            (pi * max[l] as f64 / albedo[l]) as f32
        }
    };
    let (total, peak) = (albedo[0] + albedo[1], max[0].max(max[1]));
    let whole = if total.is_nan() || total <= 0.0 || peak <= 0.0 {
        1.0 // scatters nothing: nothing to gather either way
    } else {
        let omega = if sampler.has_transmission() { 2.0 * pi } else { pi };
        (omega * peak as f64 / total) as f32
    };
    LobeKappas { whole, reflection: per_lobe(0), transmission: per_lobe(1) }
}

impl NonUniformity {
    /// Tabulates kappa of `material` over the incidence cosine (azimuth-independent: all the
    /// analytic BSDFs are isotropic).
    pub fn of_material(material: &Material) -> Self {
        let mut values = [0.0f32; KAPPA_TABLE_SIZE];
        let mut reflection = [0.0f32; KAPPA_TABLE_SIZE];
        let mut transmission = [0.0f32; KAPPA_TABLE_SIZE];
        for i in 0..KAPPA_TABLE_SIZE {
            let c = -1.0 + 2.0 * i as f32 / (KAPPA_TABLE_SIZE - 1) as f32;
            // keep off exact grazing incidence, where every lobe degenerates
            let c =
                if c.abs() < 0.02 { 0.02f32.copysign(if i < KAPPA_TABLE_SIZE / 2 { -1.0 } else { 1.0 }) } else { c };
            let s = (1.0 - c * c).max(0.0).sqrt();
            let k = kappas(material, Vec3::new(s, 0.0, c));
            (values[i], reflection[i], transmission[i]) = (k.whole, k.reflection, k.transmission);
        }
        Self { values, reflection, transmission }
    }

    /// kappa at incidence cosine `cos_o` (linear interpolation; infinite stays infinite).
    pub fn at(&self, cos_o: f32) -> f32 {
        Self::interpolate(&self.values, cos_o)
    }

    /// kappa of the reflection and of the transmission lobe alone at incidence cosine `cos_o`
    /// ([`kappas`]; infinite for a lobe that scatters nothing).
    pub fn lobes_at(&self, cos_o: f32) -> (f32, f32) {
        (Self::interpolate(&self.reflection, cos_o), Self::interpolate(&self.transmission, cos_o))
    }

    fn interpolate(values: &[f32; KAPPA_TABLE_SIZE], cos_o: f32) -> f32 {
        let x = ((cos_o.clamp(-1.0, 1.0) + 1.0) * 0.5 * (KAPPA_TABLE_SIZE - 1) as f32).max(0.0);
        let i = (x as usize).min(KAPPA_TABLE_SIZE - 2);
        let t = x - i as f32;
        let (a, b) = (values[i], values[i + 1]);
        if a.is_infinite() || b.is_infinite() {
            return f32::INFINITY;
        }
        a + (b - a) * t
    }

    /// The largest tabulated kappa (how narrow the material can get; grazing incidence
    /// dominates for glossy lobes).
    pub fn max(&self) -> f32 {
        self.values.iter().copied().fold(0.0, f32::max)
    }

    /// kappa at 45 degrees incidence, the larger of the two sides: a representative value for
    /// classifying a material as narrow.
    pub fn typical(&self) -> f32 {
        self.at(std::f32::consts::FRAC_1_SQRT_2).max(self.at(-std::f32::consts::FRAC_1_SQRT_2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{ConductorFresnel, Ior};
    use crate::spectrum::Spectrum;

    fn conductor(alpha: f32) -> Material {
        Material::Conductor { alpha, fresnel: ConductorFresnel::Constant(Spectrum::Constant(0.9)), two_sided: true }
    }

    #[test]
    fn lambertian_is_one() {
        let m = Material::Diffuse { reflectance: Spectrum::Constant(0.5), two_sided: true };
        let t = NonUniformity::of_material(&m);
        for c in [-0.9, -0.3, 0.1, 0.5, 1.0] {
            assert!((t.at(c) - 1.0).abs() < 1e-3, "{c}: {}", t.at(c));
        }
    }

    #[test]
    fn specular_is_infinite_and_narrow_lobes_are_large() {
        assert!(NonUniformity::of_material(&conductor(0.0)).at(0.7).is_infinite());
        let narrow = NonUniformity::of_material(&conductor(0.02)).at(0.8);
        assert!(narrow > 100.0, "{narrow}");
        let glass = Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.02, transmittance: None };
        assert!(NonUniformity::of_material(&glass).at(0.8) > 100.0);
        assert!(NonUniformity::of_material(&glass).at(-0.8) > 100.0);
    }

    #[test]
    fn lobe_kappas_split_a_rough_glass_face() {
        // a Lambertian reflector: its reflection lobe is the whole BSDF; it transmits nothing
        let m = Material::Diffuse { reflectance: Spectrum::Constant(0.5), two_sided: true };
        let (r, t) = NonUniformity::of_material(&m).lobes_at(0.7);
        assert!((r - 1.0).abs() < 1e-3 && t.is_infinite(), "{r} {t}");
        // a rough conductor: the reflection lobe's kappa is the whole one's
        let c = NonUniformity::of_material(&conductor(0.3));
        assert!((c.lobes_at(0.8).0 - c.at(0.8)).abs() < 1e-3 * c.at(0.8));
        // the bottom face of a glass plate (alpha 0.3) seen from inside the glass at 37 degrees:
        // its reflection is a wide lobe, its refraction into air a narrow one (Fresnel leaves the
        // reflection a few percent of the light, but kappa is relative to each lobe's own albedo)
        let glass = NonUniformity::of_material(&Material::Dielectric {
            ior: Ior::Constant(1.5),
            alpha: 0.3,
            transmittance: None,
        });
        let (r, t) = glass.lobes_at(-0.8);
        assert!(r < NARROW_KAPPA && t > NARROW_KAPPA, "reflection {r}, transmission {t}");
        // beyond the critical angle only steep microfacets refract: a narrow lobe or none
        assert!(glass.lobes_at(-0.3).1 > NARROW_KAPPA);
        // a narrow top face (alpha 0.01): both lobes narrow from both sides
        let top = NonUniformity::of_material(&Material::Dielectric {
            ior: Ior::Constant(1.5),
            alpha: 0.01,
            transmittance: None,
        });
        for c in [-0.9, 0.5, 0.9] {
            let (r, t) = top.lobes_at(c);
            assert!(r > NARROW_KAPPA && t > NARROW_KAPPA, "{c}: {r} {t}");
        }
    }

    #[test]
    fn monotone_in_roughness() {
        let mut last = f32::INFINITY;
        for alpha in [0.01, 0.03, 0.1, 0.3, 0.6] {
            let k = NonUniformity::of_material(&conductor(alpha)).at(0.9);
            assert!(k < last && k >= 1.0, "alpha {alpha}: {k} (previous {last})");
            last = k;
        }
    }
}
