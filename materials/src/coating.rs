//! A dielectric coating (clear coat, lacquer, varnish) as material data: the coat is a GGX-rough
//! dielectric interface of relative IOR eta >= 1 over a layer that may absorb (sigma_a at a
//! thickness d, optical depth tau = sigma_a d at normal incidence). The coated BSDF
//! ([`crate::bsdf::CoatedBsdf`]) reads its IOR's albedo tables ([`CoatAlbedo`]; docs/architecture.md
//! §5, "Coated materials").

use std::sync::LazyLock;

use crate::bsdf::coat_albedo::{CoatAlbedo, CoatRow, MAX_TABLE_IOR};
use crate::bsdf::fresnel::fr_dielectric;
use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN, Spectrum};

/// Largest coat IOR accepted (glass-like coatings are 1.3 to 1.7).
pub const MAX_COAT_IOR: f32 = MAX_TABLE_IOR;

/// A coat's absorbing layer: absorption coefficient sigma_a (1/m) over a thickness (m).
#[derive(Clone, Debug, PartialEq)]
pub struct CoatAbsorption {
    /// Optical depth at normal incidence, tau = sigma_a d (dimensionless).
    pub depth: Spectrum,
    /// How much of the coat's internal reflectance survives the absorption of the way up and
    /// down for light that leaves a Lambertian base, K(tau) / K(0) with
    /// K(tau) = 2 integral_0^1 F_int(mu) exp(-2 tau / mu) mu dmu and F_int the smooth interface's
    /// reflectance seen from inside (exact for a smooth coat; the same ratio is applied to a rough
    /// coat's internal reflectance), tabulated on the 1 nm grid.
    pub interreflection: Spectrum,
}

impl CoatAbsorption {
    /// The layer of absorption coefficient `sigma_a` (1/m) and thickness `thickness` (m) under
    /// an interface of relative IOR `eta`.
    pub fn new(sigma_a: &Spectrum, thickness: f32, eta: f32) -> Self {
        // midpoint rule in mu over 512 intervals
        let n = 512;
        let k = |tau: f64| -> f64 {
            (0..n)
                .map(|j| {
                    let mu = (j as f64 + 0.5) / n as f64;
                    f64::from(fr_dielectric(-(mu as f32), eta)) * (-2.0 * tau / mu).exp() * mu
                })
                .sum::<f64>()
                * 2.0
                / n as f64
        };
        let k0 = k(0.0);
        let mut lambdas = Vec::new();
        let (mut depth, mut inter) = (Vec::new(), Vec::new());
        let mut l = LAMBDA_MIN;
        while l <= LAMBDA_MAX {
            let tau = (sigma_a.value(l) * thickness).max(0.0);
            lambdas.push(l);
            depth.push(tau);
            inter.push(if k0 > 0.0 { (k(f64::from(tau)) / k0) as f32 } else { 1.0 });
            l += 1.0;
        }
        let curve = |v: Vec<f32>| Spectrum::piecewise_linear(lambdas.clone(), v).unwrap_or(Spectrum::Constant(0.0));
        Self { depth: curve(depth), interreflection: curve(inter) }
    }
}

/// A dielectric coating: relative IOR, GGX roughness and an optional absorbing layer.
#[derive(Clone, Debug, PartialEq)]
pub struct Coating {
    /// IOR of the coat relative to the outside, in [1, [`MAX_COAT_IOR`]].
    pub ior: f32,
    /// GGX alpha of the coat's top interface (below the smooth threshold 1e-3 it is rendered at
    /// 1e-3: a coat is never a perfect mirror).
    pub alpha: f32,
    /// The coat's absorption (None: clear).
    pub absorption: Option<CoatAbsorption>,
    /// The albedo table of `ior`.
    albedo: &'static CoatAlbedo,
}

/// The table of the glTF clear coat's IOR, 1.5, built once.
static IOR_1_5: LazyLock<&'static CoatAlbedo> = LazyLock::new(|| CoatAlbedo::for_eta(1.5));

impl Coating {
    /// A coat of relative IOR `ior`, GGX `alpha` and absorption (builds or finds the IOR's
    /// albedo table: call it when a material is made, not per hit).
    pub fn new(ior: f32, alpha: f32, absorption: Option<CoatAbsorption>) -> Self {
        let albedo = if ior == 1.5 { *IOR_1_5 } else { CoatAlbedo::for_eta(ior) };
        Self { ior, alpha, absorption, albedo }
    }

    /// A clear coat of IOR 1.5 (the glTF clearcoat layer's) with GGX `alpha`: cheap enough to
    /// make per shading point.
    pub fn clear(alpha: f32) -> Self {
        Self { ior: 1.5, alpha, absorption: None, albedo: *IOR_1_5 }
    }

    /// This coat with the absorbing layer `absorption`.
    pub fn with_absorption(self, absorption: Option<CoatAbsorption>) -> Self {
        Self { absorption, ..self }
    }

    /// The row of the albedo table for this coat's roughness.
    #[inline]
    pub fn albedo_row(&self) -> CoatRow {
        self.albedo.row(self.alpha)
    }

    /// Checks the IOR (finite, in [1, 4]) and alpha (finite, >= 0).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.ior.is_finite() && (1.0..=MAX_COAT_IOR).contains(&self.ior)) {
            return Err(format!("coat IOR must be within [1, {MAX_COAT_IOR}], got {}", self.ior));
        }
        if !(self.alpha.is_finite() && self.alpha >= 0.0) {
            return Err(format!("coat roughness alpha must be finite and >= 0, got {}", self.alpha));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interreflection_falls_with_depth() {
        let a = CoatAbsorption::new(&Spectrum::Constant(1000.0), 1e-3, 1.5);
        assert!((a.depth.value(550.0) - 1.0).abs() < 1e-6);
        let r = a.interreflection.value(550.0);
        // below the two-way loss of a cosine-weighted beam (2 E_3(2) = 0.0603): TIR light is grazing
        assert!(r > 0.0 && r < 0.0603, "{r}");
        let clear = CoatAbsorption::new(&Spectrum::Constant(0.0), 1e-3, 1.5);
        assert!((clear.interreflection.value(400.0) - 1.0).abs() < 1e-6);
        // index matched: no internal reflection to absorb
        assert_eq!(CoatAbsorption::new(&Spectrum::Constant(5.0), 1.0, 1.0).interreflection.value(500.0), 1.0);
    }
}
