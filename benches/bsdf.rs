//! BSDF throughput: eval (f), sample (sample_f) and pdf calls per second of tabulated BSDFs
//! against the analytic models they were tabulated from (a GGX conductor, alpha 0.3, and the
//! narrow PMMA lightguide interface, alpha 0.02, from the material library), plus the load time of
//! a library file (parse, validation, energy check, sampling distributions). Results go into
//! BENCHMARKS.md.
//!
//! Run: `cargo bench --bench bsdf`.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use quasar::core::sampling::uniform_sphere;
use quasar::materials::spectrum::SampledWavelengths;
use quasar::materials::tabulation::{Tabulation, material_fn};
use quasar::materials::{Bsdf, ConductorFresnel, Ior, Material, TabulatedTable, TransportMode};

const N: usize = 4096;

/// `N` (wo, wi, uc, u) tuples: wo in the upper hemisphere, wi anywhere (half of the evaluations
/// land in a lobe's tail or the wrong hemisphere, as in a renderer's light sampling).
fn inputs() -> Vec<(Vec3, Vec3, f32, Vec2)> {
    let mut s = 0x9e37_79b9_u64;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..N)
        .map(|_| {
            let mut wo = uniform_sphere(Vec2::new(next(), next()));
            wo.z = wo.z.abs().max(1e-3);
            let wi = uniform_sphere(Vec2::new(next(), next()));
            (wo.normalize(), wi, next(), Vec2::new(next(), next()))
        })
        .collect()
}

fn bench_pair(c: &mut Criterion, name: &str, analytic: &Material, tabulated: &Material) {
    let mut wl = SampledWavelengths::from_parts([450.0, 520.0, 590.0, 660.0], [1.0; 4]);
    let input = inputs();
    let mut g = c.benchmark_group(format!("bsdf/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    for (kind, m) in [("analytic", analytic), ("tabulated", tabulated)] {
        let b: Bsdf<'_> = m.bsdf(&mut wl);
        g.bench_function(format!("{kind}/eval"), |bn| {
            bn.iter(|| input.iter().map(|&(wo, wi, _, _)| b.f(wo, wi, TransportMode::Radiance)[0]).sum::<f32>())
        });
        g.bench_function(format!("{kind}/sample"), |bn| {
            bn.iter(|| {
                input
                    .iter()
                    .filter_map(|&(wo, _, uc, u)| b.sample_f(wo, uc, u, TransportMode::Radiance))
                    .map(|s| s.pdf)
                    .sum::<f32>()
            })
        });
        g.bench_function(format!("{kind}/pdf"), |bn| {
            bn.iter(|| input.iter().map(|&(wo, wi, _, _)| b.pdf(wo, wi, TransportMode::Radiance)).sum::<f32>())
        });
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    let ggx = Material::Conductor {
        alpha: 0.3,
        fresnel: ConductorFresnel::Constant(quasar::materials::spectrum::Spectrum::Constant(0.9)),
        two_sided: true,
    };
    let spec = Tabulation::isotropic_brdf("ggx").tabulate(material_fn(&ggx));
    let tab = Material::Tabulated(std::sync::Arc::new(TabulatedTable::new(spec).unwrap()));
    bench_pair(c, "ggx-conductor-0.3", &ggx, &tab);

    let lib = Path::new(env!("CARGO_MANIFEST_DIR")).join("materials/library/lightguide-narrow.toml");
    let narrow = Material::Dielectric { ior: Ior::Constant(1.49), alpha: 0.02, transmittance: None };
    let table = quasar::importers::bsdf_file::load_tabulated_bsdf(&lib).unwrap();
    bench_pair(c, "pmma-interface-0.02", &narrow, &Material::Tabulated(table));

    let mut g = c.benchmark_group("bsdf/load");
    g.sample_size(10);
    g.bench_function("lightguide-narrow.toml", |bn| {
        bn.iter(|| black_box(quasar::importers::bsdf_file::load_tabulated_bsdf(&lib).unwrap()))
    });
    g.finish();
}

criterion_group!(bsdf, benches);
criterion_main!(bsdf);
