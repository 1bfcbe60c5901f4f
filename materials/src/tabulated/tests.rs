use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::*;
use crate::bsdf::TransportMode;
use crate::material::{ConductorFresnel, Material};
use crate::spectrum::{SampledWavelengths, Spectrum};
use crate::tabulation::{GridSpec, Tabulation, material_fn, power_spaced, uniform_phi};
use crate::{Bsdf, TabulatedBsdf};

fn deg(v: &[f32]) -> Vec<f32> {
    v.iter().map(|x| x.to_radians()).collect()
}

fn lambertian(rho: f32) -> TabulatedSpec {
    Tabulation {
        name: "lambert".into(),
        wavelengths: vec![400.0, 700.0],
        theta_i: deg(&[0.0, 45.0, 89.0]),
        phi_i: vec![0.0],
        ior: None,
        brdf: Some(GridSpec { grid: ScatterGrid::Absolute, theta: deg(&[0.0, 30.0, 60.0, 90.0]), phi: vec![0.0] }),
        btdf: None,
        both_faces: false,
    }
    .tabulate(|_, _, _| rho * FRAC_1_PI)
}

fn ggx(alpha: f32) -> (Material, TabulatedTable) {
    let m =
        Material::Conductor { alpha, fresnel: ConductorFresnel::Constant(Spectrum::Constant(0.9)), two_sided: true };
    let spec = Tabulation {
        name: "ggx".into(),
        wavelengths: vec![550.0],
        theta_i: deg(&(0..=18).map(|i| i as f32 * 5.0).collect::<Vec<_>>()),
        phi_i: vec![0.0],
        ior: None,
        brdf: Some(GridSpec {
            grid: ScatterGrid::SpecularRelative,
            theta: power_spaced(48, PI, 2.0),
            phi: deg(&(0..=18).map(|i| i as f32 * 10.0).collect::<Vec<_>>()),
        }),
        btdf: None,
        both_faces: false,
    }
    .tabulate(material_fn(&m));
    (m.clone(), TabulatedTable::new(spec).unwrap())
}

fn wl() -> SampledWavelengths {
    SampledWavelengths::from_parts([450.0, 550.0, 600.0, 650.0], [1.0; 4])
}

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

#[test]
fn lambertian_table_has_its_albedo_and_cosine_sampling_mass() {
    let t = TabulatedTable::new(lambertian(0.8)).unwrap();
    for ti in 0..3 {
        let (r, tr) = t.albedo(false, 0, 0, ti);
        assert!((r - 0.8).abs() < 2e-3 && tr == 0.0, "albedo {r} at slice {ti}");
    }
    let b = TabulatedBsdf::new(&t, &wl());
    let v = b.f(dir(30.0, 0.0), dir(10.0, 200.0), TransportMode::Radiance);
    assert!((v[1] - 0.8 * FRAC_1_PI).abs() < 1e-6);
    // The back face is the same as the front by default.
    let back = b.f(-dir(30.0, 0.0), -dir(10.0, 200.0), TransportMode::Radiance);
    assert!((back[1] - 0.8 * FRAC_1_PI).abs() < 1e-6);
}

#[test]
fn ggx_table_matches_the_analytic_lobe() {
    let (m, t) = ggx(0.2);
    let mut w = wl();
    let analytic = m.bsdf(&mut w);
    let tab = Bsdf::Tabulated(TabulatedBsdf::new(&t, &w));
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (ti, pi) in [(0.0f32, 0.0f32), (22.0, 40.0), (47.0, 200.0), (71.0, 300.0)] {
        let wo = dir(ti, pi);
        for k in 0..400 {
            let wi = dir((k % 20) as f32 * 4.4 + 0.5, (k / 20) as f32 * 18.0 + 3.0);
            let a = analytic.f(wo, wi, TransportMode::Radiance)[1];
            let b = tab.f(wo, wi, TransportMode::Radiance)[1];
            num += f64::from((a - b).abs() * wi.z);
            den += f64::from(a * wi.z);
        }
    }
    assert!(num / den < 0.05, "tabulated GGX differs from analytic by {:.3} (L1, cosine weighted)", num / den);
}

#[test]
fn pdf_matches_sampling_moments() {
    // E[g(wi) / pdf(wi)] over samples = integral of g over the sampled support: with g = pdf the
    // estimate of the sampled probability mass must equal the fraction of successful samples.
    let (_, t) = ggx(0.1);
    let b = TabulatedBsdf::new(&t, &wl());
    let wo = dir(35.0, 70.0);
    let mut rng = 0x1234_5678u64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 40) as f32 / (1u64 << 24) as f32
    };
    let n = 20_000;
    let mut ok = 0;
    for _ in 0..n {
        let uc = next();
        let u = Vec2::new(next(), next());
        if let Some(s) = b.sample_f(wo, uc, u, TransportMode::Radiance) {
            ok += 1;
            let p = b.pdf(wo, s.wi, TransportMode::Radiance);
            assert!((p - s.pdf).abs() <= 1e-4 * p, "pdf {p} vs sample pdf {}", s.pdf);
        }
    }
    assert!(ok > n * 9 / 10, "only {ok} of {n} samples succeeded");
}

#[test]
fn validation_names_the_table_and_entry() {
    let mut s = lambertian(0.5);
    s.front.brdf.as_mut().unwrap().values[5] = f32::NAN;
    let e = TabulatedTable::new(s).unwrap_err();
    assert_eq!(e.table, "front.brdf.values");
    assert_eq!(e.entry, Some(vec![0, 0, 1, 1, 0]), "slice 1 (45 deg), theta 1");

    let mut s = lambertian(0.5);
    s.front.brdf.as_mut().unwrap().values[3] = -1.0;
    assert!(TabulatedTable::new(s).unwrap_err().message.contains("non-negative"));

    let e = TabulatedTable::new(lambertian(3.0)).unwrap_err();
    assert!(e.message.contains("albedo") && e.table == "front", "{e}");

    let mut s = lambertian(0.5);
    s.theta_i = deg(&[0.0, 60.0, 45.0]);
    let e = TabulatedTable::new(s).unwrap_err();
    assert_eq!((e.table.as_str(), e.entry.clone()), ("incidence.theta", Some(vec![2])), "{e}");

    let mut s = lambertian(0.5);
    s.front.brdf.as_mut().unwrap().values.pop();
    assert!(TabulatedTable::new(s).unwrap_err().message.contains("the grid needs"));

    assert!(ScatterTable::expected_len("x", 100_000, 100_000, 100, 100).is_err());
    assert!(ScatterTable::expected_len("x", usize::MAX, 2, 2, 2).is_err());
}

#[test]
fn mirror_symmetric_half_tables_are_expanded() {
    let (_, t) = ggx(0.3);
    let b = TabulatedBsdf::new(&t, &wl());
    let wo = dir(40.0, 0.0);
    for (a, c) in [(dir(30.0, 160.0), dir(30.0, 200.0)), (dir(60.0, 100.0), dir(60.0, 260.0))] {
        let fa = b.f(wo, a, TransportMode::Radiance)[1];
        let fc = b.f(wo, c, TransportMode::Radiance)[1];
        assert!((fa - fc).abs() <= 1e-5 * fa.max(1e-6), "{fa} vs {fc}");
    }
}

#[test]
fn narrow_transmission_lobe_follows_refraction() {
    let spec = Tabulation {
        name: "narrow btdf".into(),
        wavelengths: vec![550.0],
        theta_i: deg(&[0.0, 30.0, 60.0, 89.0]),
        phi_i: vec![0.0],
        ior: Some(1.5),
        brdf: None,
        btdf: Some(GridSpec {
            grid: ScatterGrid::SpecularRelative,
            theta: power_spaced(40, 0.6f32.to_radians(), 1.5),
            phi: uniform_phi(1),
        }),
        both_faces: false,
    }
    .tabulate(|_, _, _| 0.0);
    // A lobe 0.2 degrees wide: f = A exp(-(theta/0.1deg)^2), A chosen for an albedo of ~0.9.
    let mut spec = spec;
    let sigma = 0.1f32.to_radians();
    let a = 0.9 / (PI * sigma * sigma);
    let th = spec.front.btdf.as_ref().unwrap().theta.clone();
    for (i, v) in spec.front.btdf.as_mut().unwrap().values.iter_mut().enumerate() {
        let t = th[i % th.len()];
        *v = a * (-(t / sigma).powi(2)).exp();
    }
    let t = TabulatedTable::new(spec).unwrap();
    let (_, tr) = t.albedo(false, 0, 0, 1);
    assert!(tr > 0.5 && tr < 1.0, "transmitted albedo {tr}");
    let b = TabulatedBsdf::new(&t, &wl());
    let wo = dir(30.0, 0.0);
    let s = b.sample_f(wo, 0.5, Vec2::new(0.3, 0.7), TransportMode::Importance).unwrap();
    // Snell: sin 30 / 1.5 = 0.3333 -> 19.47 degrees below, going forward (-x).
    let expect = Vec3::new(-(0.5f32 / 1.5), 0.0, -(1.0f32 - 0.25 / 2.25).sqrt());
    let angle = s.wi.dot(expect).clamp(-1.0, 1.0).acos().to_degrees();
    assert!(angle < 0.5, "sample {} is {angle} deg from the refraction direction", s.wi);
}
