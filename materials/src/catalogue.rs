//! Named optical materials: glasses by their published Sellmeier fits ([`Ior::named`]) and
//! metals by their measured complex indices ([`ConductorFresnel::named`]), each with its source.

use crate::material::{ConductorFresnel, Ior};
use crate::spectrum::Spectrum;

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
