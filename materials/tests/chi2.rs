//! Chi-square goodness-of-fit tests of every non-delta BSDF's `sample_f` against its `pdf`
//! (in the style of the pbrt-v4 and Mitsuba chi2 tests): directions binned on a (theta, phi)
//! grid over the whole sphere, expected counts from Simpson integration of the pdf per bin,
//! cells expecting < 5 pooled, one extra cell for failed samples, significance 0.01 over all
//! tests (Sidak). The tests at the end check that the test rejects wrong pdfs and samplers.

mod common;

use common::{Chi2, chi2_bsdf, chi2_directions, dir, gamma_q, sidak};
use glam::Vec3;
use quasar_materials::TransportMode;
use quasar_materials::bsdf::{ConductorBsdf, DielectricBsdf, DiffuseBsdf, SampledFresnel, TrowbridgeReitz};
use quasar_materials::spectrum::SampledSpectrum;
use quasar_materials::spectrum::{SampledWavelengths, Spectrum};
use quasar_materials::tabulated::ScatterGrid;
use quasar_materials::tabulation::{GridSpec, Tabulation, material_fn, power_spaced, uniform_phi};
use quasar_materials::{Bsdf, ConductorFresnel, HenyeyGreenstein, Ior, Material, TabulatedBsdf, TabulatedTable};

/// Samples per configuration.
const N: usize = 500_000;
/// Number of configurations tested below (for the Sidak correction).
const N_TESTS: usize = 28 + 9 + 6;

fn diffuse(two_sided: bool) -> Bsdf<'static> {
    Bsdf::Diffuse(DiffuseBsdf::new(SampledSpectrum::splat(0.8), two_sided))
}

fn conductor(alpha: f32, two_sided: bool) -> Bsdf<'static> {
    let gold = SampledFresnel::Complex {
        eta: SampledSpectrum([1.4, 0.4, 0.2, 0.15]),
        k: SampledSpectrum([1.9, 2.5, 3.3, 4.5]),
    };
    Bsdf::Conductor(ConductorBsdf::new(TrowbridgeReitz::new(alpha), gold, two_sided))
}

fn dielectric(eta: f32, alpha: f32) -> Bsdf<'static> {
    Bsdf::Dielectric(DielectricBsdf::new(eta, TrowbridgeReitz::new(alpha)))
}

fn check(name: &str, r: Chi2) {
    let alpha = sidak(N_TESTS);
    println!("{name}: chi2 = {:.1}, dof = {}, p = {:.4}", r.stat, r.dof, r.p);
    assert!(r.p > alpha, "{name}: sampling does not match pdf: {r:?} (significance {alpha:.2e})");
}

#[test]
fn chi2_diffuse() {
    for (k, (two_sided, cz)) in [(false, 1.0f32), (false, 0.05), (true, -0.6)].into_iter().enumerate() {
        check(
            &format!("diffuse two_sided={two_sided} cos={cz}"),
            chi2_bsdf(&diffuse(two_sided), dir(cz), N, 100 + k as u64),
        );
    }
}

#[test]
fn chi2_rough_conductor() {
    let mut seed = 200;
    for alpha in [0.05f32, 0.3, 1.0] {
        for cz in [1.0f32, 0.5, 0.05] {
            seed += 1;
            check(&format!("conductor alpha={alpha} cos={cz}"), chi2_bsdf(&conductor(alpha, false), dir(cz), N, seed));
        }
    }
    check("conductor two-sided from below", chi2_bsdf(&conductor(0.3, true), dir(-0.7), N, 299));
}

fn chi2_dielectric_eta_1_5(cosines: [f32; 3], seed: u64) {
    for (k, alpha) in [0.05f32, 0.3].into_iter().enumerate() {
        for (l, cz) in cosines.into_iter().enumerate() {
            let seed = seed + 10 * k as u64 + l as u64;
            check(
                &format!("dielectric eta=1.5 alpha={alpha} cos={cz}"),
                chi2_bsdf(&dielectric(1.5, alpha), dir(cz), N, seed),
            );
        }
    }
}

#[test]
fn chi2_rough_dielectric_from_outside() {
    chi2_dielectric_eta_1_5([0.9, 0.4, 0.05], 300);
    check("dielectric eta=0.7 alpha=1 cos=0.3", chi2_bsdf(&dielectric(0.7, 1.0), dir(0.3), N, 330));
}

#[test]
fn chi2_rough_dielectric_from_inside() {
    // |cos| < 0.745 is beyond the critical angle of eta = 1.5.
    chi2_dielectric_eta_1_5([-0.9, -0.4, -0.05], 350);
    for (k, cz) in [0.6f32, -0.95].into_iter().enumerate() {
        check(
            &format!("dielectric eta=4 alpha=0.3 cos={cz}"),
            chi2_bsdf(&dielectric(4.0, 0.3), dir(cz), N, 380 + k as u64),
        );
    }
}

/// The Henyey-Greenstein phase function's sampling against its value (issue 49): isotropic,
/// forward and backward, from two directions; the sample's own pdf is the value.
#[test]
fn chi2_henyey_greenstein() {
    for (k, (g, cz)) in
        [(0.0f32, 0.3f32), (0.3, 1.0), (0.9, 0.3), (-0.7, -0.5), (0.0005, 0.8), (-0.95, 0.9)].into_iter().enumerate()
    {
        let hg = HenyeyGreenstein::new(g);
        let wo = dir(cz);
        let r = chi2_directions(
            N,
            600 + k as u64,
            |_, u| {
                let (wi, pdf) = hg.sample(wo, u);
                assert!((pdf - hg.eval(wo, wi)).abs() <= 1e-3 * pdf, "g {g}: pdf {pdf} vs {}", hg.eval(wo, wi));
                Some(wi)
            },
            |wi| f64::from(hg.eval(wo, wi)),
        );
        check(&format!("henyey-greenstein g={g} cos={cz}"), r);
    }
    // g is the mean cosine between the light's directions before (-wi) and after (wo)
    let hg = HenyeyGreenstein::new(0.8);
    let wo = dir(0.2);
    let n = 100_000;
    let mean: f32 = (0..n)
        .map(|i| {
            let u = glam::Vec2::new((i as f32 + 0.5) / n as f32, ((i * 7919) % n) as f32 / n as f32);
            -wo.dot(hg.sample(wo, u).0)
        })
        .sum::<f32>()
        / n as f32;
    assert!((mean - 0.8).abs() < 0.01, "mean cosine {mean}");
}

#[test]
fn survival_function_matches_closed_forms() {
    // Q(1, x) = exp(-x) (2 degrees of freedom); Q(1/2, x) = erfc(sqrt x).
    for x in [0.01f64, 0.5, 1.0, 3.0, 10.0, 40.0] {
        assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-12 * (1.0 + (-x).exp()) + 1e-14, "{x}");
    }
    assert!((gamma_q(0.5, 1.0) - 0.157_299_207_050_285).abs() < 1e-10);
    // Median of chi-square with 100 dof is about 99.33.
    assert!((gamma_q(50.0, 99.334_1 / 2.0) - 0.5).abs() < 1e-3);
}

/// The test must be able to fail: a pdf 1.2 times too large on half the sphere, a sampler with a
/// slightly different roughness and a dielectric pdf with the wrong IOR are all rejected.
#[test]
fn chi2_rejects_wrong_pdfs_and_samplers() {
    let alpha = sidak(N_TESTS);
    let mode = TransportMode::Radiance;
    let wo = dir(0.5);
    let b = conductor(0.3, false);
    let biased = chi2_directions(
        N,
        500,
        |uc, u| b.sample_f(wo, uc, u, mode).map(|s| s.wi),
        |wi: Vec3| f64::from(b.pdf(wo, wi, mode)) * if wi.y > 0.0 { 1.2 } else { 1.0 },
    );
    println!("biased pdf: {biased:?}");
    assert!(biased.p < alpha * 1e-3, "{biased:?}");

    let other = conductor(0.33, false);
    let wrong_alpha = chi2_directions(
        N,
        501,
        |uc, u| other.sample_f(wo, uc, u, mode).map(|s| s.wi),
        |wi: Vec3| f64::from(b.pdf(wo, wi, mode)),
    );
    println!("alpha 0.33 sampler vs 0.3 pdf: {wrong_alpha:?}");
    assert!(wrong_alpha.p < alpha * 1e-3, "{wrong_alpha:?}");

    let (glass, denser) = (dielectric(1.5, 0.3), dielectric(1.6, 0.3));
    let wrong_eta = chi2_directions(
        N,
        502,
        |uc, u| glass.sample_f(wo, uc, u, mode).map(|s| s.wi),
        |wi: Vec3| f64::from(denser.pdf(wo, wi, mode)),
    );
    println!("eta 1.5 sampler vs 1.6 pdf: {wrong_eta:?}");
    assert!(wrong_eta.p < alpha * 1e-3, "{wrong_eta:?}");
}

fn deg(v: impl IntoIterator<Item = f32>) -> Vec<f32> {
    v.into_iter().map(f32::to_radians).collect()
}

/// Tabulated tables of three kinds: an absolute-grid glossy conductor, a specular-relative rough
/// dielectric (BRDF + BTDF) and an anisotropic lobe.
fn tables() -> Vec<(&'static str, TabulatedTable)> {
    let conductor = Material::Conductor {
        alpha: 0.3,
        fresnel: ConductorFresnel::Constant(Spectrum::Constant(0.8)),
        two_sided: true,
    };
    let absolute = Tabulation {
        name: "absolute".into(),
        wavelengths: vec![450.0, 650.0],
        theta_i: deg((0..=6).map(|i| i as f32 * 15.0)),
        phi_i: vec![0.0],
        ior: None,
        brdf: Some(GridSpec {
            grid: ScatterGrid::Absolute,
            theta: deg((0..=18).map(|i| i as f32 * 5.0)),
            phi: deg((0..=12).map(|i| i as f32 * 15.0)),
        }),
        btdf: None,
        both_faces: false,
    }
    .tabulate(material_fn(&conductor));
    let glass = Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.3, transmittance: None };
    let spec_grid = GridSpec {
        grid: ScatterGrid::SpecularRelative,
        theta: power_spaced(60, std::f32::consts::PI, 1.8),
        phi: uniform_phi(24),
    };
    let specular = Tabulation {
        name: "specular".into(),
        wavelengths: vec![550.0],
        theta_i: deg((0..=8).map(|i| i as f32 * 10.0).chain([85.0])),
        phi_i: vec![0.0],
        ior: Some(1.5),
        brdf: Some(spec_grid.clone()),
        btdf: Some(spec_grid),
        both_faces: true,
    }
    .tabulate(material_fn(&glass));
    let aniso = Tabulation {
        name: "anisotropic".into(),
        wavelengths: vec![550.0],
        theta_i: deg([0.0, 30.0, 60.0, 85.0]),
        phi_i: deg([0.0, 90.0, 180.0, 270.0]),
        ior: None,
        brdf: Some(GridSpec {
            grid: ScatterGrid::SpecularRelative,
            theta: power_spaced(24, 1.2, 1.5),
            phi: uniform_phi(24),
        }),
        btdf: None,
        both_faces: false,
    }
    .tabulate(|_, d_in, d_out| {
        // A lobe around the mirror direction, wider along x than along y (brushed finish).
        let m = glam::Vec3::new(-d_in.x, -d_in.y, d_in.z);
        let d = d_out - m;
        0.5 * (-(d.x / 0.3).powi(2) - (d.y / 0.1).powi(2)).exp()
    });
    [("absolute", absolute), ("specular", specular), ("anisotropic", aniso)]
        .into_iter()
        .map(|(n, s)| (n, TabulatedTable::new(s).unwrap_or_else(|e| panic!("{n}: {e}"))))
        .collect()
}

#[test]
fn chi2_tabulated() {
    let mut wl = SampledWavelengths::from_parts([500.0, 550.0, 600.0, 650.0], [1.0; 4]);
    let mut seed = 900;
    for (name, t) in tables() {
        let b = Bsdf::Tabulated(TabulatedBsdf::new(&t, &wl));
        for cz in [0.9f32, 0.3, -0.6] {
            seed += 1;
            check(&format!("tabulated {name} cos={cz}"), chi2_bsdf(&b, dir(cz), N, seed));
        }
    }
    wl.terminate_secondary();
}
