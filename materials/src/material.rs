//! Materials: plain data (spectral parameters) that produce a [`Bsdf`] at a path's wavelengths.

use crate::bsdf::microfacet::Masking;
use crate::bsdf::{Bsdf, ConductorBsdf, DielectricBsdf, DiffuseBsdf, SampledFresnel, TrowbridgeReitz};
use std::sync::Arc;

use crate::bsdf::microfacet::SMOOTH_ALPHA;
use crate::bsdf::{CoatBase, CoatedBsdf, TabulatedBsdf};
use crate::coating::{CoatAbsorption, Coating, coat_alpha};
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
            Material::Coated { coating, base, two_sided } => {
                let base = match base.as_ref() {
                    Material::Diffuse { reflectance, .. } => {
                        CoatBase::Diffuse(DiffuseBsdf::new(reflectance.sample(wl), true))
                    }
                    Material::Conductor { alpha, fresnel, .. } => CoatBase::Conductor(ConductorBsdf::new(
                        TrowbridgeReitz::new(alpha.max(SMOOTH_ALPHA)).with_masking(masking),
                        sampled_fresnel(fresnel, wl),
                        true,
                    )),
                    Material::Tabulated(t) if !t.has_transmission() => CoatBase::Tabulated(TabulatedBsdf::new(t, wl)),
                    _ => return Bsdf::Black,
                };
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
            Material::Coated { coating, base, .. } => {
                coating.validate()?;
                match base.as_ref() {
                    Material::Diffuse { .. } | Material::Conductor { .. } => {}
                    Material::Tabulated(t) if !t.has_transmission() => {}
                    Material::Tabulated(_) => {
                        return Err("a coat's base must be opaque: this tabulated BSDF transmits".into());
                    }
                    Material::Dielectric { .. } | Material::Coated { .. } => {
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
            Material::Diffuse { .. } | Material::Tabulated(_) | Material::Coated { .. } => false,
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

    /// A named optical material (case-insensitive), all Sellmeier fits with lambda in um:
    /// - "BK7" / "N-BK7": Schott N-BK7 datasheet, B = 1.03961212, 0.231792344, 1.01046945;
    ///   C = 0.00600069867, 0.0200179144, 103.560653 um^2 (n_d = 1.5168).
    /// - "fused-silica" / "silica" / "SiO2": Malitson, JOSA 55, 1205 (1965), B = 0.6961663,
    ///   0.4079426, 0.8974794; C = 0.0684043^2, 0.1162414^2, 9.896161^2 um^2 (n_d = 1.4585).
    /// - "water": constant 1.333 (no dispersion).
    /// - "acrylic" / "PMMA": Sultanova, Kasarova & Nikolov, Acta Phys. Pol. A 116, 585 (2009),
    ///   one-term Sellmeier B = 1.1819, C = 0.011313 um^2 (n_d = 1.4906; fit 437..1052 nm).
    /// - "polycarbonate" / "PC": same source, B = 1.4182, C = 0.021304 um^2 (n_d = 1.5848).
    pub fn named(name: &str) -> Option<Ior> {
        let sellmeier = |b: [f32; 3], c: [f32; 3]| Some(Ior::Sellmeier { b, c });
        match name.trim().to_ascii_lowercase().replace(['_', ' '], "-").as_str() {
            "bk7" | "n-bk7" => {
                sellmeier([1.039_612, 0.231_792_34, 1.010_469_5], [0.006_000_699, 0.020_017_914, 103.560_65])
            }
            "fused-silica" | "silica" | "sio2" => sellmeier(
                [0.696_166_3, 0.407_942_6, 0.897_479_4],
                [0.068_404_3 * 0.068_404_3, 0.116_241_4 * 0.116_241_4, 9.896_161 * 9.896_161],
            ),
            "water" => Some(Ior::Constant(1.333)),
            "acrylic" | "pmma" => sellmeier([1.1819, 0.0, 0.0], [0.011_313, 0.0, 0.0]),
            "polycarbonate" | "pc" => sellmeier([1.4182, 0.0, 0.0], [0.021_304, 0.0, 0.0]),
            _ => None,
        }
    }
}

/// (wavelength nm, eta, k) rows of a tabulated metal.
type NkTable = &'static [(f32, f32, f32)];

/// Aluminium: Rakic, Appl. Opt. 34, 4755 (1995), rows 326..838 nm as transcribed in the CC0
/// refractiveindex.info database (main/Al/nk/Rakic).
#[rustfmt::skip]
const AL_RAKIC_1995: NkTable = &[
    (326.28, 0.3147, 3.917), (364.66, 0.3988, 4.396), (413.28, 0.5214, 5.001), (442.80, 0.6079, 5.368),
    (476.87, 0.7278, 5.778), (516.60, 0.8734, 6.242), (563.57, 1.073, 6.784), (619.93, 1.366, 7.405),
    (652.25, 1.572, 7.735), (688.81, 1.830, 8.060), (729.32, 2.161, 8.357), (774.91, 2.615, 8.491),
    (794.78, 2.768, 8.387), (815.69, 2.767, 8.257), (837.74, 2.695, 8.188),
];

/// Silver: Johnson & Christy, Phys. Rev. B 6, 4370 (1972), rows 354..892 nm (refractiveindex.info
/// main/Ag/nk/Johnson).
#[rustfmt::skip]
const AG_JOHNSON_CHRISTY_1972: NkTable = &[
    (354.2, 0.10, 1.419), (367.9, 0.07, 1.657), (381.5, 0.05, 1.864), (397.4, 0.05, 2.070), (413.3, 0.05, 2.275),
    (430.5, 0.04, 2.462), (450.9, 0.04, 2.657), (471.4, 0.05, 2.869), (495.9, 0.05, 3.093), (520.9, 0.05, 3.324),
    (548.6, 0.06, 3.586), (582.1, 0.05, 3.858), (616.8, 0.06, 4.152), (659.5, 0.05, 4.483), (704.5, 0.04, 4.838),
    (756.0, 0.03, 5.242), (821.1, 0.04, 5.727), (892.0, 0.04, 6.312),
];

/// Gold: Johnson & Christy 1972, rows 354..892 nm (refractiveindex.info main/Au/nk/Johnson).
#[rustfmt::skip]
const AU_JOHNSON_CHRISTY_1972: NkTable = &[
    (354.2, 1.50, 1.866), (367.9, 1.48, 1.895), (381.5, 1.46, 1.933), (397.4, 1.47, 1.952), (413.3, 1.46, 1.958),
    (430.5, 1.45, 1.948), (450.9, 1.38, 1.914), (471.4, 1.31, 1.849), (495.9, 1.04, 1.833), (520.9, 0.62, 2.081),
    (548.6, 0.43, 2.455), (582.1, 0.29, 2.863), (616.8, 0.21, 3.272), (659.5, 0.14, 3.697), (704.5, 0.13, 4.103),
    (756.0, 0.14, 4.542), (821.1, 0.16, 5.083), (892.0, 0.17, 5.663),
];

/// Copper: Johnson & Christy 1972, rows 354..892 nm (refractiveindex.info main/Cu/nk/Johnson).
#[rustfmt::skip]
const CU_JOHNSON_CHRISTY_1972: NkTable = &[
    (354.2, 1.37, 1.916), (367.9, 1.36, 1.975), (381.5, 1.33, 2.045), (397.4, 1.32, 2.116), (413.3, 1.28, 2.207),
    (430.5, 1.25, 2.305), (450.9, 1.24, 2.397), (471.4, 1.25, 2.483), (495.9, 1.22, 2.564), (520.9, 1.18, 2.608),
    (548.6, 1.02, 2.577), (582.1, 0.70, 2.704), (616.8, 0.30, 3.205), (659.5, 0.22, 3.747), (704.5, 0.21, 4.205),
    (756.0, 0.24, 4.665), (821.1, 0.26, 5.180), (892.0, 0.30, 5.768),
];

impl ConductorFresnel {
    /// A metal's measured complex IOR as piecewise-linear spectra covering 360..830 nm
    /// (case-insensitive): "Al"/"aluminium"/"aluminum" (Rakic 1995), "Ag"/"silver", "Au"/"gold",
    /// "Cu"/"copper" (Johnson & Christy 1972); the published sample wavelengths are kept as knots.
    pub fn named(name: &str) -> Option<ConductorFresnel> {
        let table = match name.trim().to_ascii_lowercase().as_str() {
            "al" | "aluminium" | "aluminum" => AL_RAKIC_1995,
            "ag" | "silver" => AG_JOHNSON_CHRISTY_1972,
            "au" | "gold" => AU_JOHNSON_CHRISTY_1972,
            "cu" | "copper" => CU_JOHNSON_CHRISTY_1972,
            _ => return None,
        };
        let lambda: Vec<f32> = table.iter().map(|r| r.0).collect();
        let eta = Spectrum::PiecewiseLinear { lambda: lambda.clone(), values: table.iter().map(|r| r.1).collect() };
        let k = Spectrum::PiecewiseLinear { lambda, values: table.iter().map(|r| r.2).collect() };
        Some(ConductorFresnel::Complex { eta, k })
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
    fn named_glasses_match_published_indices_at_the_d_line() {
        // n_d at 587.56 nm from the sources cited on `Ior::named`.
        for (name, nd) in [("BK7", 1.5168), ("fused-silica", 1.4585), ("PMMA", 1.4906), ("polycarbonate", 1.5848)] {
            let ior = Ior::named(name).unwrap();
            assert!((ior.at(587.56) - nd).abs() < 5e-4, "{name}: {}", ior.at(587.56));
            assert!(ior.is_dispersive() && ior.at(400.0) > ior.at(700.0));
        }
        assert_eq!(Ior::named("Water"), Some(Ior::Constant(1.333)));
        assert_eq!(Ior::named("acrylic"), Ior::named("pmma"));
        assert!(Ior::named("unobtainium").is_none());
        assert!((Ior::Cauchy { a: 1.5, b: 0.01 }.at(500.0) - 1.54).abs() < 1e-6);
    }

    #[test]
    fn named_metals_cover_the_range_and_look_right() {
        for name in ["Al", "silver", "Au", "copper"] {
            let f = ConductorFresnel::named(name).unwrap();
            let m = Material::Conductor { alpha: 0.0, fresnel: f, two_sided: false };
            m.validate().unwrap();
        }
        // Normal-incidence reflectance: gold and copper are red-yellow, silver and aluminium bright.
        let r0 = |name: &str, l: f32| {
            let Some(ConductorFresnel::Complex { eta, k }) = ConductorFresnel::named(name) else { unreachable!() };
            crate::bsdf::fresnel::fr_complex(1.0, eta.value(l), k.value(l))
        };
        assert!(r0("Au", 650.0) > 0.9 && r0("Au", 450.0) < 0.45);
        assert!(r0("Cu", 700.0) > 0.9 && r0("Cu", 450.0) < 0.65);
        assert!(r0("Ag", 550.0) > 0.95 && r0("Al", 550.0) > 0.9);
        assert!(ConductorFresnel::named("Pt").is_none());
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
