//! The sheen BSDF (issue 50, item 2): chi-square tests of its sampling, the white furnace (no
//! energy gain over a white base), reciprocity, and the pdf's consistency with its samples.

mod common;

use common::{SplitMix, chi2_bsdf, dir, integrate_sphere, sidak};
use glam::{Vec2, Vec3};
use quasar_materials::spectrum::{SampledWavelengths, Spectrum};
use quasar_materials::{ConductorFresnel, Material, TransportMode};

const N: usize = 500_000;
const N_TESTS: usize = 6;

fn sheen(color: f32, roughness: f32, base: Material) -> Material {
    let m = Material::Sheen { color: Spectrum::Constant(color), alpha: roughness * roughness, base: Box::new(base) };
    m.validate().unwrap();
    m
}

fn diffuse(r: f32) -> Material {
    Material::Diffuse { reflectance: Spectrum::Constant(r), two_sided: true }
}

fn wl() -> SampledWavelengths {
    SampledWavelengths::from_parts([450.0, 500.0, 550.0, 600.0], [1.0; 4])
}

#[test]
fn chi2_sheen() {
    let metal = Material::Conductor {
        alpha: 0.2,
        fresnel: ConductorFresnel::Constant(Spectrum::Constant(0.9)),
        two_sided: true,
    };
    let mut seed = 1200;
    for (m, cz) in [
        (sheen(1.0, 0.3, diffuse(0.5)), 0.8f32),
        (sheen(1.0, 0.3, diffuse(0.5)), 0.1),
        (sheen(0.6, 0.8, diffuse(0.2)), 0.5),
        (sheen(0.6, 0.8, diffuse(0.2)), -0.5),
        (sheen(1.0, 0.5, metal.clone()), 0.7),
        (sheen(1.0, 0.5, metal.clone()), 0.15),
    ] {
        seed += 1;
        let b = m.bsdf(&mut wl());
        let r = chi2_bsdf(&b, dir(cz), N, seed);
        println!("sheen cos={cz}: chi2 = {:.1}, dof = {}, p = {:.4}", r.stat, r.dof, r.p);
        assert!(r.p > sidak(N_TESTS), "cos {cz}: {r:?}");
    }
}

#[test]
fn white_furnace_and_reciprocity() {
    for roughness in [0.07f32, 0.3, 0.6, 1.0] {
        let m = sheen(1.0, roughness, diffuse(1.0));
        let b = m.bsdf(&mut wl());
        for cz in [1.0f32, 0.5, 0.1, 0.02] {
            let a = integrate_sphere(|wi| f64::from(b.f(dir(cz), wi, TransportMode::Radiance)[0] * wi.z.abs()));
            println!("sheen roughness {roughness} over white, cos={cz}: albedo {a:.4}");
            assert!(a <= 1.0 + 3e-3 && a > 0.5, "{roughness} {cz}: {a}");
        }
        let mut rng = SplitMix(3);
        for _ in 0..2000 {
            let v = |rng: &mut SplitMix| {
                let z = rng.next_f32();
                let phi = std::f32::consts::TAU * rng.next_f32();
                let s = (1.0 - z * z).sqrt();
                Vec3::new(s * phi.cos(), s * phi.sin(), z)
            };
            let (wo, wi) = (v(&mut rng), v(&mut rng));
            let (x, y) = (b.f(wo, wi, TransportMode::Radiance)[0], b.f(wi, wo, TransportMode::Radiance)[0]);
            assert!((x - y).abs() <= 1e-4 * x.max(y) + 1e-7, "{wo} {wi}: {x} {y}");
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            if let Some(s) = b.sample_f(wo, rng.next_f32(), u, TransportMode::Radiance) {
                let (f, p) = b.f_pdf(wo, s.wi, TransportMode::Radiance);
                assert!((p - s.pdf).abs() <= 1e-5 * p && f == s.f && !s.specular);
            }
        }
    }
}
