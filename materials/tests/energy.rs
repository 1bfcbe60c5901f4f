//! Energy tests of the BSDFs: the pdf integrates to the probability that `sample_f` returns a
//! direction, and white-furnace albedos (integral of f |cos| over the sphere, by adaptive
//! quadrature, cross-checked by importance sampling) stay below 1 for Fresnel = 1.

mod common;

use common::{SplitMix, dir, integrate_sphere};
use glam::{Vec2, Vec3};
use quasar_materials::bsdf::{ConductorBsdf, DielectricBsdf, DiffuseBsdf, SampledFresnel, TrowbridgeReitz};
use quasar_materials::spectrum::SampledSpectrum;
use quasar_materials::{Bsdf, Lobe, TransportMode};

const MC_SAMPLES: usize = 100_000;

fn white_conductor(alpha: f32) -> Bsdf<'static> {
    Bsdf::Conductor(ConductorBsdf::new(
        TrowbridgeReitz::new(alpha),
        SampledFresnel::Constant(SampledSpectrum::one()),
        false,
    ))
}

fn dielectric(eta: f32, alpha: f32) -> Bsdf<'static> {
    Bsdf::Dielectric(DielectricBsdf::new(eta, TrowbridgeReitz::new(alpha)))
}

/// (fraction of `sample_f` calls that return a direction, mean weight f |cos| / pdf over all calls).
fn sample_stats(b: &Bsdf, wo: Vec3, mode: TransportMode, seed: u64) -> (f64, f64) {
    let mut rng = SplitMix(seed);
    let (mut some, mut weight) = (0usize, 0.0f64);
    for _ in 0..MC_SAMPLES {
        let uc = rng.next_f32();
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        if let Some(s) = b.sample_f(wo, uc, u, mode) {
            some += 1;
            weight += f64::from(s.f[0] * s.wi.z.abs() / s.pdf);
        }
    }
    (some as f64 / MC_SAMPLES as f64, weight / MC_SAMPLES as f64)
}

/// Directional albedo integral of f(wo, wi) |cos wi| over the sphere (first wavelength).
fn albedo(b: &Bsdf, wo: Vec3, mode: TransportMode) -> f64 {
    integrate_sphere(|wi| f64::from(b.f(wo, wi, mode)[0] * wi.z.abs()))
}

#[test]
fn pdf_integrates_to_the_sampled_fraction() {
    let mut cases: Vec<(String, Bsdf<'static>, f32)> = vec![
        ("diffuse".into(), Bsdf::Diffuse(DiffuseBsdf::new(SampledSpectrum::splat(0.5), false)), 0.7),
        ("diffuse two-sided".into(), Bsdf::Diffuse(DiffuseBsdf::new(SampledSpectrum::splat(0.5), true)), -0.3),
    ];
    for alpha in [0.05f32, 0.3, 1.0] {
        for cz in [0.5f32, 0.05] {
            cases.push((format!("conductor alpha={alpha}"), white_conductor(alpha), cz));
        }
    }
    for alpha in [0.05f32, 0.3] {
        for cz in [0.5f32, -0.5, -0.05] {
            cases.push((format!("dielectric eta=1.5 alpha={alpha}"), dielectric(1.5, alpha), cz));
        }
    }
    for (k, (name, b, cz)) in cases.iter().enumerate() {
        let wo = dir(*cz);
        let integral = integrate_sphere(|wi| f64::from(b.pdf(wo, wi, TransportMode::Radiance)));
        let (p_some, _) = sample_stats(b, wo, TransportMode::Radiance, 700 + k as u64);
        let sigma = (p_some * (1.0 - p_some) / MC_SAMPLES as f64).sqrt();
        println!("{name} cos={cz}: integral of pdf {integral:.5}, sampled fraction {p_some:.5}");
        assert!(integral <= 1.0 + 1e-3, "{name} cos={cz}: {integral}");
        assert!((integral - p_some).abs() <= 5.0 * sigma + 1e-3, "{name} cos={cz}: {integral} vs {p_some}");
        if name.starts_with("diffuse") {
            assert!((integral - 1.0).abs() < 1e-3 && p_some == 1.0);
        }
    }
}

#[test]
fn white_furnace_lambertian_returns_its_albedo() {
    for (two_sided, cz) in [(false, 0.8f32), (false, 0.05), (true, -0.6)] {
        let b = Bsdf::Diffuse(DiffuseBsdf::new(SampledSpectrum::splat(0.8), two_sided));
        let a = albedo(&b, dir(cz), TransportMode::Radiance);
        let (_, mc) = sample_stats(&b, dir(cz), TransportMode::Radiance, 1);
        println!("lambertian R=0.8 cos={cz}: quadrature {a:.5}, sampled {mc:.5}");
        assert!((a - 0.8).abs() < 1e-3 && (mc - 0.8).abs() < 1e-5);
    }
}

#[test]
fn white_furnace_rough_conductor() {
    let cosines = [1.0f32, 0.5, 0.2, 0.05];
    let mut table = Vec::new();
    for alpha in [0.05f32, 0.3, 1.0] {
        let b = white_conductor(alpha);
        let mut row = Vec::new();
        for (k, &cz) in cosines.iter().enumerate() {
            let a = albedo(&b, dir(cz), TransportMode::Radiance);
            let (_, mc) = sample_stats(&b, dir(cz), TransportMode::Radiance, 10 + k as u64);
            println!("conductor F=1 alpha={alpha} cos={cz}: quadrature {a:.4}, sampled {mc:.4}");
            assert!(a <= 1.0 + 1e-3, "alpha {alpha} cos {cz}: {a}");
            assert!((a - mc).abs() < 5e-3, "alpha {alpha} cos {cz}: {a} vs {mc}");
            row.push(a);
        }
        table.push(row);
    }
    // Single scattering loses energy only at high roughness (and grazing incidence).
    for k in 0..3 {
        assert!(table[0][k] > 0.95, "alpha 0.05 cos {}: {}", cosines[k], table[0][k]);
    }
    // Away from grazing incidence (where the narrow lobe's shadowing dominates) the loss grows
    // with roughness.
    for k in 0..3 {
        assert!(table[2][k] < table[1][k] && table[1][k] < table[0][k], "cos {}", cosines[k]);
    }
}

#[test]
fn white_furnace_rough_dielectric() {
    // Importance mode: no 1/eta^2 radiance scaling, so reflection + transmission <= 1.
    let mode = TransportMode::Importance;
    let cases = [(1.5f32, 0.05f32), (1.5, 0.3), (1.5, 1.0), (4.0, 0.05), (4.0, 1.0)];
    for (eta, alpha) in cases {
        let b = dielectric(eta, alpha);
        let cosines: &[f32] = if eta == 1.5 { &[0.99, 0.5, 0.2, -0.99, -0.5, -0.2] } else { &[0.5, -0.5] };
        for (k, &cz) in cosines.iter().enumerate() {
            let a = albedo(&b, dir(cz), mode);
            let (_, mc) = sample_stats(&b, dir(cz), mode, 40 + k as u64);
            println!("dielectric eta={eta} alpha={alpha} cos={cz}: quadrature {a:.4}, sampled {mc:.4}");
            assert!(a <= 1.0 + 1e-3, "eta {eta} alpha {alpha} cos {cz}: {a}");
            assert!((a - mc).abs() < 5e-3, "eta {eta} alpha {alpha} cos {cz}: {a} vs {mc}");
            if alpha == 0.05 && cz.abs() > 0.4 {
                assert!(a > 0.95, "eta {eta} alpha {alpha} cos {cz}: {a}");
            }
        }
    }
}

#[test]
fn smooth_models_conserve_energy_exactly() {
    for eta in [1.0001f32, 1.5, 4.0] {
        let b = dielectric(eta, 0.0);
        for cz in [1.0f32, 0.6, 0.1, -0.1, -0.6, -1.0] {
            let wo = dir(cz);
            let mut total = 0.0;
            let mut seen_reflection = false;
            for uc in [0.0f32, 0.999_999_9] {
                let Some(s) = b.sample_f(wo, uc, Vec2::splat(0.5), TransportMode::Importance) else { continue };
                if s.lobe == Lobe::Reflection && std::mem::replace(&mut seen_reflection, true) {
                    continue;
                }
                total += s.f[0] * s.wi.z.abs();
            }
            assert!((total - 1.0).abs() < 1e-5, "eta {eta} cos {cz}: R + T = {total}");
        }
    }
    let mirror = white_conductor(0.0);
    let s = mirror.sample_f(dir(0.3), 0.5, Vec2::splat(0.5), TransportMode::Radiance).unwrap();
    assert!((s.f[0] * s.wi.z.abs() / s.pdf - 1.0).abs() < 1e-6);
}
