//! Materials: plain data (spectral parameters) that produce a [`Bsdf`] at a path's wavelengths.

use crate::bsdf::microfacet::Masking;
use crate::bsdf::{Bsdf, ConductorBsdf, DielectricBsdf, DiffuseBsdf, SampledFresnel, TrowbridgeReitz};
use std::sync::Arc;

use crate::bsdf::coat_albedo::coat_alpha;
use crate::bsdf::microfacet::SMOOTH_ALPHA;
use crate::bsdf::{CoatBase, CoatedBsdf, TabulatedBsdf};
use crate::coating::{CoatAbsorption, Coating};
use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN, SampledSpectrum, SampledWavelengths, Spectrum};
use crate::tabulated::TabulatedTable;

/// Fresnel reflectance model of a conductor.
#[derive(Clone, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Angle-independent reflectance (spectrum in [0, 1]).
    Constant(Spectrum),
    /// Spectral complex index of refraction eta + i k (relative to the outside medium).
    Complex {
        /// Real part.
        eta: Spectrum,
        /// Imaginary part (absorption).
        k: Spectrum,
    },
}

/// Index of refraction of a dielectric as a function of wavelength.
#[derive(Clone, Debug, PartialEq)]
pub enum Ior {
    /// Same IOR at every wavelength (no dispersion).
    Constant(f32),
    /// Cauchy: n(lambda) = a + b / lambda^2, lambda in micrometres, b in um^2.
    Cauchy {
        /// Constant term.
        a: f32,
        /// Coefficient of 1/lambda^2 (um^2).
        b: f32,
    },
    /// Sellmeier: n^2 = 1 + sum_i B_i lambda^2 / (lambda^2 - C_i), lambda in micrometres, C_i in um^2.
    Sellmeier {
        /// B coefficients.
        b: [f32; 3],
        /// C coefficients (um^2).
        c: [f32; 3],
    },
}

/// A surface material (docs/architecture.md §5): the closed set of analytic models.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflector with albedo `reflectance`; black from behind unless `two_sided`.
    Diffuse {
        /// Albedo spectrum in [0, 1].
        reflectance: Spectrum,
        /// Reflect on both sides of the surface.
        two_sided: bool,
    },
    /// Smooth (alpha = 0) or GGX-rough conductor.
    Conductor {
        /// GGX alpha (used directly; 0 = smooth mirror).
        alpha: f32,
        /// Fresnel model.
        fresnel: ConductorFresnel,
        /// Reflect on both sides of the surface.
        two_sided: bool,
    },
    /// Smooth (alpha = 0) or GGX-rough dielectric interface.
    Dielectric {
        /// IOR of the inside (the side the geometric normal points away from) relative to outside.
        ior: Ior,
        /// GGX alpha (used directly; 0 = smooth).
        alpha: f32,
        /// Factor in [0, 1] on the light transmitted at each crossing (a coloured glass's tint:
        /// glTF's base colour of a transmissive material, Mitsuba's `specular_transmittance`);
        /// None = clear.
        transmittance: Option<Spectrum>,
    },
    /// Tabulated spectral BRDF/BTDF (validated on load, shared between threads).
    Tabulated(Arc<TabulatedTable>),
    /// A dielectric coat (clear coat, lacquer, varnish) over an opaque `base`: a diffuse, a
    /// conductor (rendered at alpha >= 1e-3 under a coat) or a tabulated reflector
    /// ([`CoatedBsdf`], Weidlich & Wilkie 2007).
    Coated {
        /// The coat.
        coating: Coating,
        /// What lies under it.
        base: Box<Material>,
        /// Coated on both sides (else black from behind).
        two_sided: bool,
    },
    /// A sheen (velvet, cloth) over an opaque `base` (diffuse, conductor or opaque tabulated):
    /// glTF `KHR_materials_sheen` ([`crate::bsdf::SheenBsdf`]).
    Sheen {
        /// Sheen colour, a spectrum in [0, 1].
        color: Spectrum,
        /// The Charlie distribution's alpha (glTF sheenRoughness^2).
        alpha: f32,
        /// What lies under it.
        base: Box<Material>,
    },
}

/// The layer base a material makes under a coat or a sheen: a diffuse, a conductor (at alpha >=
/// 1e-3) or an opaque tabulated BSDF; None for anything else.
fn coat_base<'a>(base: &'a Material, wl: &SampledWavelengths, masking: Masking) -> Option<CoatBase<'a>> {
    Some(match base {
        Material::Diffuse { reflectance, .. } => CoatBase::Diffuse(DiffuseBsdf::new(reflectance.sample(wl), true)),
        Material::Conductor { alpha, fresnel, .. } => CoatBase::Conductor(ConductorBsdf::new(
            TrowbridgeReitz::new(alpha.max(SMOOTH_ALPHA)).with_masking(masking),
            sampled_fresnel(fresnel, wl),
            true,
        )),
        Material::Tabulated(t) if !t.has_transmission() => CoatBase::Tabulated(TabulatedBsdf::new(t, wl)),
        _ => return None,
    })
}

/// A conductor's Fresnel model at the path's wavelengths.
fn sampled_fresnel(fresnel: &ConductorFresnel, wl: &SampledWavelengths) -> SampledFresnel {
    match fresnel {
        ConductorFresnel::Constant(r) => SampledFresnel::Constant(r.sample(wl)),
        ConductorFresnel::Complex { eta, k } => SampledFresnel::Complex { eta: eta.sample(wl), k: k.sample(wl) },
    }
}

/// Smallest IOR (and |eta + i k|) accepted by [`Material::validate`]: below it 1/eta overflows
/// the Fresnel and refraction formulas' useful range.
const MIN_IOR: f32 = 1e-4;

/// Calls `f` at every whole nanometre of the simulated range (360..=830 nm).
fn for_each_nm(mut f: impl FnMut(f32) -> Result<(), String>) -> Result<(), String> {
    let mut l = LAMBDA_MIN;
    while l <= LAMBDA_MAX {
        f(l)?;
        l += 1.0;
    }
    Ok(())
}

/// Checks that `s` is finite and within [lo, hi] over the simulated range (1 nm grid plus
/// [`Spectrum::max_value`] for table knots).
fn check_spectrum(what: &str, s: &Spectrum, lo: f32, hi: f32) -> Result<(), String> {
    for_each_nm(|l| {
        let v = s.value(l);
        if !v.is_finite() || v < lo || v > hi {
            return Err(format!("{what} must be finite and within [{lo}, {hi}], got {v} at {l} nm"));
        }
        Ok(())
    })?;
    let m = s.max_value();
    if m > hi {
        return Err(format!("{what} must be within [{lo}, {hi}], its maximum is {m}"));
    }
    Ok(())
}

fn check_alpha(what: &str, alpha: f32) -> Result<(), String> {
    if !alpha.is_finite() || alpha < 0.0 {
        return Err(format!("{what} roughness alpha must be finite and >= 0, got {alpha}"));
    }
    Ok(())
}

impl Material {
    /// The BSDF at the path's wavelengths. A dispersive IOR is evaluated at the hero wavelength
    /// `wl.lambda(0)` and terminates the secondary wavelengths (the refracted direction depends on
    /// the wavelength). Out-of-range parameters (see [`validate`](Self::validate)) are sanitised
    /// rather than propagated: reflectances clamped to [0, 1], bad alpha -> 0, bad IOR -> 1.
    pub fn bsdf(&self, wl: &mut SampledWavelengths) -> Bsdf<'_> {
        self.bsdf_with(wl, Masking::HeightCorrelated)
    }

    /// [`bsdf`](Self::bsdf) with the microfacet masking-shadowing form `masking`.
    #[inline(always)]
    pub fn bsdf_with(&self, wl: &mut SampledWavelengths, masking: Masking) -> Bsdf<'_> {
        match self {
            Material::Diffuse { reflectance, two_sided } => {
                Bsdf::Diffuse(DiffuseBsdf::new(reflectance.sample(wl), *two_sided))
            }
            Material::Conductor { alpha, fresnel, two_sided } => {
                let fresnel = match fresnel {
                    ConductorFresnel::Constant(r) => SampledFresnel::Constant(r.sample(wl)),
                    ConductorFresnel::Complex { eta, k } => {
                        SampledFresnel::Complex { eta: eta.sample(wl), k: k.sample(wl) }
                    }
                };
                Bsdf::Conductor(ConductorBsdf::new(
                    TrowbridgeReitz::new(*alpha).with_masking(masking),
                    fresnel,
                    *two_sided,
                ))
            }
            Material::Dielectric { ior, alpha, transmittance } => {
                let eta = ior.at(wl.lambda(0));
                if ior.is_dispersive() {
                    wl.terminate_secondary();
                }
                let eta = if eta.is_finite() && eta > MIN_IOR { eta } else { 1.0 };
                let b = DielectricBsdf::new(eta, TrowbridgeReitz::new(*alpha).with_masking(masking));
                Bsdf::Dielectric(match transmittance {
                    Some(t) => b.with_tint(t.sample(wl)),
                    None => b,
                })
            }
            Material::Tabulated(t) => Bsdf::Tabulated(TabulatedBsdf::new(t, wl)),
            Material::Sheen { color, alpha, base } => match coat_base(base, wl, masking) {
                Some(b) => {
                    Bsdf::Sheen(crate::bsdf::SheenBsdf::new(color.sample(wl), color.max_value(), *alpha, b, true))
                }
                None => Bsdf::Black,
            },
            Material::Coated { coating, base, two_sided } => {
                let Some(base) = coat_base(base, wl, masking) else { return Bsdf::Black };
                let (depth, interreflection) = match &coating.absorption {
                    Some(a) => (a.depth.sample(wl), a.interreflection.sample(wl)),
                    None => (SampledSpectrum::zero(), SampledSpectrum::one()),
                };
                Bsdf::Coated(CoatedBsdf::new(
                    TrowbridgeReitz::new(coat_alpha(coating.alpha)).with_masking(masking),
                    coating.ior,
                    coating.albedo_row(),
                    depth,
                    interreflection,
                    base,
                    *two_sided,
                ))
            }
        }
    }

    /// The material as rendering should hold it: its spectra pre-sampled on the 1 nm grid
    /// where the grid reproduces them ([`Spectrum::densified`]), everything else unchanged.
    pub fn densified(&self) -> Self {
        match self {
            Material::Diffuse { reflectance, two_sided } => {
                Material::Diffuse { reflectance: reflectance.densified(), two_sided: *two_sided }
            }
            Material::Conductor { alpha, fresnel, two_sided } => Material::Conductor {
                alpha: *alpha,
                fresnel: match fresnel {
                    ConductorFresnel::Constant(r) => ConductorFresnel::Constant(r.densified()),
                    ConductorFresnel::Complex { eta, k } => {
                        ConductorFresnel::Complex { eta: eta.densified(), k: k.densified() }
                    }
                },
                two_sided: *two_sided,
            },
            Material::Dielectric { ior, alpha, transmittance } => Material::Dielectric {
                ior: ior.clone(),
                alpha: *alpha,
                transmittance: transmittance.as_ref().map(Spectrum::densified),
            },
            Material::Tabulated(_) => self.clone(),
            Material::Sheen { color, alpha, base } => {
                Material::Sheen { color: color.densified(), alpha: *alpha, base: Box::new(base.densified()) }
            }
            Material::Coated { coating, base, two_sided } => Material::Coated {
                coating: coating.clone().with_absorption(coating.absorption.as_ref().map(|a| CoatAbsorption {
                    depth: a.depth.densified(),
                    interreflection: a.interreflection.densified(),
                })),
                base: Box::new(base.densified()),
                two_sided: *two_sided,
            },
        }
    }

    /// Checks the parameters: alpha finite and >= 0; reflectances finite and within [0, 1] over
    /// 360..830 nm; conductor eta, k finite and >= 0 with |eta + i k| > 1e-4 everywhere in the
    /// range (a table that stops short is zero outside it); dielectric IOR finite and > 1e-4 at
    /// every nanometre (catches Sellmeier poles and negative n^2). The message names the
    /// parameter and the offending value.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            Material::Diffuse { reflectance, .. } => check_spectrum("diffuse reflectance", reflectance, 0.0, 1.0),
            Material::Conductor { alpha, fresnel, .. } => {
                check_alpha("conductor", *alpha)?;
                match fresnel {
                    ConductorFresnel::Constant(r) => check_spectrum("conductor reflectance", r, 0.0, 1.0),
                    ConductorFresnel::Complex { eta, k } => {
                        check_spectrum("conductor eta", eta, 0.0, f32::MAX)?;
                        check_spectrum("conductor k", k, 0.0, f32::MAX)?;
                        for_each_nm(|l| {
                            let (e, kk) = (eta.value(l), k.value(l));
                            if e.hypot(kk) <= MIN_IOR {
                                return Err(format!(
                                    "conductor complex IOR must have |eta + ik| > {MIN_IOR} at every wavelength in \
                                     {LAMBDA_MIN}..{LAMBDA_MAX} nm, got eta = {e}, k = {kk} at {l} nm"
                                ));
                            }
                            Ok(())
                        })
                    }
                }
            }
            Material::Dielectric { ior, alpha, transmittance } => {
                check_alpha("dielectric", *alpha)?;
                if let Some(t) = transmittance {
                    check_spectrum("dielectric transmittance", t, 0.0, 1.0)?;
                }
                for_each_nm(|l| {
                    let n = ior.at(l);
                    if !n.is_finite() || n <= MIN_IOR {
                        return Err(format!(
                            "dielectric IOR must be finite and > {MIN_IOR}, got {n} at {l} nm ({ior:?})"
                        ));
                    }
                    Ok(())
                })
            }
            // Validated when the table was built (TabulatedTable::new).
            Material::Tabulated(_) => Ok(()),
            Material::Sheen { color, alpha, base } => {
                check_spectrum("sheen colour", color, 0.0, 1.0)?;
                check_alpha("sheen", *alpha)?;
                if coat_base(base, &SampledWavelengths::sample_uniform(0.5), Masking::HeightCorrelated).is_none() {
                    return Err("a sheen's base must be a diffuse, conductor or opaque tabulated reflector".into());
                }
                base.validate().map_err(|e| format!("sheen base: {e}"))
            }
            Material::Coated { coating, base, .. } => {
                coating.validate()?;
                match base.as_ref() {
                    Material::Diffuse { .. } | Material::Conductor { .. } => {}
                    Material::Tabulated(t) if !t.has_transmission() => {}
                    Material::Tabulated(_) => {
                        return Err("a coat's base must be opaque: this tabulated BSDF transmits".into());
                    }
                    Material::Dielectric { .. } | Material::Coated { .. } | Material::Sheen { .. } => {
                        return Err("a coat's base must be a diffuse, conductor or tabulated reflector".into());
                    }
                }
                base.validate().map_err(|e| format!("coat base: {e}"))
            }
        }
    }

    /// True when [`bsdf`](Self::bsdf) always produces a Dirac-delta BSDF: a conductor or
    /// dielectric with effectively smooth alpha (< 1e-3), or an index-matched (IOR 1) dielectric.
    pub fn is_specular(&self) -> bool {
        match self {
            Material::Diffuse { .. } | Material::Tabulated(_) | Material::Coated { .. } | Material::Sheen { .. } => {
                false
            }
            Material::Conductor { alpha, .. } => TrowbridgeReitz::new(*alpha).effectively_smooth(),
            Material::Dielectric { ior, alpha, .. } => {
                TrowbridgeReitz::new(*alpha).effectively_smooth() || *ior == Ior::Constant(1.0)
            }
        }
    }
}

impl Ior {
    /// The IOR at `lambda_nm` (Cauchy and Sellmeier take lambda in micrometres). NaN where a
    /// Sellmeier n^2 is negative (beyond a resonance); [`Material::validate`] rejects that.
    pub fn at(&self, lambda_nm: f32) -> f32 {
        let l = lambda_nm * 1e-3;
        match *self {
            Ior::Constant(n) => n,
            Ior::Cauchy { a, b } => a + b / (l * l),
            Ior::Sellmeier { b, c } => {
                let l2 = l * l;
                let n2 = 1.0 + (0..3).map(|i| b[i] * l2 / (l2 - c[i])).sum::<f32>();
                if n2 >= 0.0 { n2.sqrt() } else { f32::NAN }
            }
        }
    }

    /// True when the IOR varies with wavelength (refraction then depends on the wavelength).
    pub fn is_dispersive(&self) -> bool {
        match *self {
            Ior::Constant(_) => false,
            Ior::Cauchy { b, .. } => b != 0.0,
            Ior::Sellmeier { b, .. } => b.iter().any(|&v| v != 0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::TransportMode;
    use crate::spectrum::SampledSpectrum;

    fn wl() -> SampledWavelengths {
        SampledWavelengths::sample_uniform(0.37)
    }

    #[test]
    fn validate_names_the_parameter_and_value() {
        let metal = |alpha, r| Material::Conductor {
            alpha,
            fresnel: ConductorFresnel::Constant(Spectrum::Constant(r)),
            two_sided: false,
        };
        let glass = |ior, alpha| Material::Dielectric { ior, alpha, transmittance: None };
        // Complex IOR tables that stop at 400..700 nm are zero (|eta + ik| = 0) outside.
        let short = |v: f32| Spectrum::PiecewiseLinear { lambda: vec![400.0, 700.0], values: vec![v, v] };
        let bad = [
            (Material::Diffuse { reflectance: Spectrum::Constant(1.2), two_sided: false }, "diffuse reflectance"),
            (Material::Diffuse { reflectance: Spectrum::Constant(f32::NAN), two_sided: false }, "NaN"),
            (metal(-0.1, 0.5), "alpha"),
            (metal(f32::INFINITY, 0.5), "inf"),
            (metal(0.1, 1.5), "conductor reflectance"),
            (
                Material::Conductor {
                    alpha: 0.1,
                    fresnel: ConductorFresnel::Complex { eta: short(1.0), k: short(2.0) },
                    two_sided: false,
                },
                "|eta + ik|",
            ),
            (glass(Ior::Constant(0.0), 0.0), "dielectric IOR"),
            (glass(Ior::Constant(f32::NAN), 0.0), "NaN"),
            (glass(Ior::Sellmeier { b: [1.0, 0.0, 0.0], c: [0.25, 0.0, 0.0] }, 0.0), "dielectric IOR"),
            (glass(Ior::Constant(1.5), f32::NAN), "dielectric roughness alpha"),
        ];
        for (m, needle) in bad {
            let e = m.validate().unwrap_err();
            assert!(e.contains(needle), "{e}");
        }
        for m in [
            Material::Diffuse { reflectance: Spectrum::rgb_reflectance([1.0, 0.5, 0.0]).unwrap(), two_sided: true },
            Material::Dielectric { ior: Ior::Constant(1.0001), alpha: 1e-4, transmittance: None },
            Material::Dielectric { ior: Ior::Constant(4.0), alpha: 1.0, transmittance: None },
            Material::Dielectric { ior: Ior::named("BK7").unwrap(), alpha: 0.3, transmittance: None },
        ] {
            m.validate().unwrap();
        }
    }

    #[test]
    fn bsdf_terminates_secondaries_only_for_dispersive_iors() {
        let mut w = wl();
        let m = Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.0, transmittance: None };
        let b = m.bsdf(&mut w);
        assert!(!w.secondary_terminated() && b.is_specular() && m.is_specular() && b.has_transmission());
        let m = Material::Dielectric { ior: Ior::named("BK7").unwrap(), alpha: 0.2, transmittance: None };
        let b = m.bsdf(&mut w);
        assert!(w.secondary_terminated() && !b.is_specular() && !m.is_specular());
        let Bsdf::Dielectric(d) = b else { unreachable!() };
        assert_eq!(d.eta, Ior::named("BK7").unwrap().at(w.lambda(0)));
    }

    #[test]
    fn material_and_bsdf_agree_on_specularity() {
        let c =
            |alpha| Material::Conductor { alpha, fresnel: ConductorFresnel::named("Au").unwrap(), two_sided: false };
        let d = |alpha, n| Material::Dielectric { ior: Ior::Constant(n), alpha, transmittance: None };
        for m in [c(0.0), c(1e-4), c(1e-3), c(0.5), d(0.0, 1.5), d(0.2, 1.5), d(0.2, 1.0), d(5e-4, 1.3)] {
            assert_eq!(m.is_specular(), m.bsdf(&mut wl()).is_specular(), "{m:?}");
        }
        let diffuse = Material::Diffuse { reflectance: Spectrum::Constant(0.5), two_sided: false };
        let b = diffuse.bsdf(&mut wl());
        assert!(!diffuse.is_specular() && !b.is_specular());
        let f = b.f(glam::Vec3::Z, glam::Vec3::Z, TransportMode::Radiance);
        assert!((f - SampledSpectrum::splat(0.5 * std::f32::consts::FRAC_1_PI)).0.iter().all(|v| v.abs() < 1e-7));
    }
}
