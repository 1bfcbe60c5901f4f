//! Named optical materials: glasses by their published Sellmeier fits ([`Ior::named`]), their
//! bulk absorption by measured extinction coefficients ([`Absorption::named`]) and metals by
//! their measured complex indices ([`ConductorFresnel::named`]), each with its source.

use crate::absorption::Absorption;
use crate::material::{ConductorFresnel, Ior};
use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN, Spectrum};

impl Ior {
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

/// (wavelength nm, k) rows of a transparent material's measured extinction coefficient.
type KTable = &'static [(f32, f32)];

/// PMMA (Mitsubishi): Zhang, Qiu, Li, Zhao & Liu, "Complex refractive indices measurements of
/// polymers in visible and near-infrared bands", Appl. Opt. 59, 2337 (2020), rows 400..830 nm as
/// transcribed in the CC0 refractiveindex.info database (organic/PMMA/nk/Zhang-Mitsubishi).
#[rustfmt::skip]
const PMMA_ZHANG_2020: KTable = &[
    (400.0, 2.34e-7), (410.0, 2.12e-7), (420.0, 2.05e-7), (430.0, 1.92e-7), (440.0, 1.68e-7), (450.0, 1.74e-7),
    (460.0, 1.46e-7), (470.0, 1.35e-7), (480.0, 1.51e-7), (490.0, 1.46e-7), (500.0, 1.55e-7), (510.0, 1.49e-7),
    (520.0, 1.53e-7), (530.0, 1.56e-7), (540.0, 1.66e-7), (550.0, 1.74e-7), (560.0, 1.78e-7), (570.0, 1.86e-7),
    (580.0, 1.92e-7), (590.0, 1.78e-7), (600.0, 2.43e-7), (610.0, 2.11e-7), (620.0, 1.98e-7), (630.0, 1.77e-7),
    (640.0, 1.79e-7), (650.0, 1.58e-7), (660.0, 1.48e-7), (670.0, 1.33e-7), (680.0, 1.15e-7), (690.0, 1.23e-7),
    (700.0, 1.36e-7), (710.0, 1.31e-7), (720.0, 1.53e-7), (730.0, 1.62e-7), (740.0, 1.62e-7), (750.0, 1.49e-7),
    (760.0, 1.04e-7), (770.0, 6.31e-8), (780.0, 1.40e-7), (790.0, 1.13e-7), (800.0, 9.92e-8), (810.0, 8.90e-8),
    (820.0, 1.26e-7), (830.0, 3.68e-8),
];

/// Polycarbonate: the same paper (Zhang et al. 2020; refractiveindex.info organic/PC/nk/Zhang),
/// rows 400..830 nm; the rise towards 400 nm is its yellowness.
#[rustfmt::skip]
const PC_ZHANG_2020: KTable = &[
    (400.0, 1.12e-5), (410.0, 2.28e-6), (420.0, 6.31e-7), (430.0, 3.55e-7), (440.0, 2.88e-7), (450.0, 2.63e-7),
    (460.0, 2.43e-7), (470.0, 2.39e-7), (480.0, 2.49e-7), (490.0, 2.64e-7), (500.0, 2.95e-7), (510.0, 2.97e-7),
    (520.0, 3.16e-7), (530.0, 3.39e-7), (540.0, 3.85e-7), (550.0, 4.08e-7), (560.0, 4.27e-7), (570.0, 4.45e-7),
    (580.0, 4.81e-7), (590.0, 4.80e-7), (600.0, 4.80e-7), (610.0, 4.37e-7), (620.0, 3.95e-7), (630.0, 3.48e-7),
    (640.0, 3.03e-7), (650.0, 2.36e-7), (660.0, 1.76e-7), (670.0, 1.26e-7), (680.0, 9.54e-8), (690.0, 7.08e-8),
    (700.0, 5.22e-8), (710.0, 6.91e-8), (720.0, 3.53e-8), (730.0, 2.76e-8), (740.0, 4.45e-8), (750.0, 3.44e-8),
    (760.0, 3.53e-8), (770.0, 1.20e-8), (780.0, 5.95e-9), (790.0, 1.97e-9), (800.0, 6.27e-9), (810.0, 1.17e-8),
    (820.0, 6.81e-8), (830.0, 2.71e-7),
];

/// Schott N-BK7: the k column of SCHOTT's Zemax catalogue 2017-01-20b (from its internal
/// transmittance data; refractiveindex.info glass/schott/N-BK7), rows 350..1060 nm.
#[rustfmt::skip]
const N_BK7_SCHOTT_2017: KTable = &[
    (350.0, 9.2894e-8), (365.0, 3.4191e-8), (370.0, 2.7405e-8), (380.0, 2.0740e-8), (390.0, 1.3731e-8),
    (400.0, 1.0227e-8), (405.0, 9.0558e-9), (420.0, 9.3912e-9), (436.0, 1.1147e-8), (460.0, 1.0286e-8),
    (500.0, 9.5781e-9), (546.0, 6.9658e-9), (580.0, 9.2541e-9), (620.0, 1.1877e-8), (660.0, 1.2643e-8),
    (700.0, 8.9305e-9), (1060.0, 1.0137e-8),
];

impl Absorption {
    /// A named material's measured bulk absorption (case-insensitive; the names of
    /// [`Ior::named`] that have data): "acrylic"/"PMMA" and "polycarbonate"/"PC" (Zhang et al.,
    /// Appl. Opt. 59, 2337 (2020)), "BK7"/"N-BK7" (SCHOTT catalogue 2017). The coefficient is
    /// sigma_a(lambda) = 4 pi k(lambda) / lambda (1/m), piecewise linear between the published
    /// wavelengths; below the first (400 nm for the polymers) it holds the first value, which
    /// understates the polymers' absorption towards their UV edge.
    pub fn named(name: &str) -> Option<Absorption> {
        let table = match name.trim().to_ascii_lowercase().replace(['_', ' '], "-").as_str() {
            "acrylic" | "pmma" => PMMA_ZHANG_2020,
            "polycarbonate" | "pc" => PC_ZHANG_2020,
            "bk7" | "n-bk7" => N_BK7_SCHOTT_2017,
            _ => return None,
        };
        let sigma_a = |(lambda, k): (f32, f32)| 4.0 * std::f32::consts::PI * k / (lambda * 1e-9);
        let mut rows: Vec<(f32, f32)> = table.iter().map(|&r| (r.0, sigma_a(r))).collect();
        if rows[0].0 > LAMBDA_MIN {
            rows.insert(0, (LAMBDA_MIN, rows[0].1));
        }
        debug_assert!(rows.last().is_some_and(|r| r.0 >= LAMBDA_MAX));
        Some(Absorption::Coefficient(Spectrum::PiecewiseLinear {
            lambda: rows.iter().map(|r| r.0).collect(),
            values: rows.iter().map(|r| r.1).collect(),
        }))
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
    use crate::material::Material;

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
    fn named_absorption_is_the_published_extinction() {
        use crate::spectrum::SampledWavelengths;
        let at = |name: &str, l: f32| {
            let a = Absorption::named(name).unwrap();
            a.validate().unwrap();
            a.sigma_a(&SampledWavelengths::from_parts([l; 4], [1.0; 4])).0[0]
        };
        // sigma_a = 4 pi k / lambda at a published row: PMMA k = 1.74e-7 at 550 nm (3.98 /m: a
        // 24 cm light guide transmits exp(-0.95) = 39%), PC 4.08e-7 there, N-BK7 6.9658e-9 at 546 nm.
        assert!((at("PMMA", 550.0) - 3.976).abs() < 0.01, "{}", at("PMMA", 550.0));
        assert!((at("polycarbonate", 550.0) - 9.322).abs() < 0.01);
        assert!((at("N-BK7", 546.0) - 0.1603).abs() < 1e-3);
        // covered over the whole rendered range, never zero inside it
        for name in ["acrylic", "PC", "bk7"] {
            for l in [LAMBDA_MIN, 380.0, 555.0, 700.0, LAMBDA_MAX] {
                assert!(at(name, l) > 0.0, "{name} at {l}");
            }
        }
        // PC yellows: it absorbs blue far more than red; PMMA's k is nearly flat (the 1/lambda
        // of sigma_a makes blue 1.6x red)
        assert!(at("PC", 400.0) > 50.0 * at("PC", 650.0));
        assert!(at("PMMA", 450.0) / at("PMMA", 650.0) < 2.0);
        assert_eq!(Absorption::named("acrylic"), Absorption::named("PMMA"));
        assert!(Absorption::named("water").is_none());
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
}
