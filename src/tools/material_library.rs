//! The material library (`materials/library/*.toml`): tabulated BSDFs generated from documented
//! models, so every shipped file can be regenerated (`cargo run --release --example
//! material_library`) and a test checks the shipped files against this generator.
//!
//! The tables are "measured-like": the same models a lighting engineer would fit to goniometer
//! data (GGX microfacet interfaces with published optical constants, an anisotropic Beckmann lobe
//! for brushed metal, a diffuse base under a glossy clear coat), sampled on the grids a
//! measurement would use, values rounded to 5 significant digits.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3;
use quasar_materials::bsdf::fresnel::{fr_complex, fr_dielectric};
use quasar_materials::spectrum::Spectrum;
use quasar_materials::tabulated::{BackFace, Face, ScatterGrid};
use quasar_materials::tabulation::{GridSpec, Tabulation, material_fn, power_spaced};
use quasar_materials::{ConductorFresnel, Ior, Material, TabulatedSpec};

/// One library file.
pub struct LibraryEntry {
    /// File name in `materials/library/`.
    pub file: &'static str,
    /// One-line description written into the file.
    pub description: &'static str,
    /// Provenance entries (model, parameters, data sources).
    pub provenance: Vec<(&'static str, &'static str)>,
    /// The table.
    pub spec: TabulatedSpec,
}

fn deg(v: impl IntoIterator<Item = f32>) -> Vec<f32> {
    v.into_iter().map(f32::to_radians).collect()
}

/// Azimuths 0..=180 degrees in `step` (a mirror-symmetric isotropic table).
fn half_phi(step: f32) -> Vec<f32> {
    deg((0..=(180.0 / step) as usize).map(|i| i as f32 * step))
}

/// Incidence angles 0, 10, ..., 80, 89 degrees.
fn incidence() -> Vec<f32> {
    deg((0..=8).map(|i| i as f32 * 10.0).chain([89.0]))
}

fn round5(spec: &mut TabulatedSpec) {
    let r = |x: &mut f32| {
        if *x != 0.0 {
            let e = 4 - x.abs().log10().floor() as i32;
            let p = 10f64.powi(e);
            *x = ((f64::from(*x) * p).round() / p) as f32;
        }
    };
    let mut faces: Vec<&mut Face> = vec![&mut spec.front];
    if let BackFace::Own(b) = &mut spec.back {
        faces.push(b);
    }
    for f in faces {
        for t in [&mut f.brdf, &mut f.btdf].into_iter().flatten() {
            t.values.iter_mut().for_each(r);
        }
    }
}

fn dielectric_interface(
    name: &str,
    ior: f32,
    alpha: f32,
    theta_max_deg: f32,
    n: usize,
    p: f32,
    phi_step: f32,
) -> TabulatedSpec {
    let m = Material::Dielectric { ior: Ior::Constant(ior), alpha, transmittance: None };
    let grid = GridSpec {
        grid: ScatterGrid::SpecularRelative,
        theta: power_spaced(n, theta_max_deg.to_radians(), p),
        phi: half_phi(phi_step),
    };
    Tabulation {
        name: name.into(),
        wavelengths: vec![555.0],
        theta_i: incidence(),
        phi_i: vec![0.0],
        ior: Some(ior),
        brdf: Some(grid.clone()),
        btdf: Some(grid),
        both_faces: true,
    }
    .tabulate_energy_matched(material_fn(&m))
}

fn metal(name: &str, metal: &str, alpha: f32) -> TabulatedSpec {
    let m =
        Material::Conductor { alpha, fresnel: ConductorFresnel::named(metal).expect("known metal"), two_sided: true };
    Tabulation {
        name: name.into(),
        wavelengths: (0..7).map(|i| 400.0 + 50.0 * i as f32).collect(),
        theta_i: deg([0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0]),
        phi_i: vec![0.0],
        ior: None,
        brdf: Some(GridSpec {
            grid: ScatterGrid::SpecularRelative,
            theta: power_spaced(32, PI, 2.2),
            phi: half_phi(20.0),
        }),
        btdf: None,
        both_faces: false,
    }
    .tabulate_energy_matched(material_fn(&m))
}

/// Brushed aluminium: an anisotropic Beckmann lobe (alpha 0.3 across the brushing direction x,
/// 0.06 along y) with the Ashikhmin–Shirley denominator 4 (h . i) max(cos i, cos o), times the
/// Fresnel reflectance of aluminium at 555 nm.
fn brushed_aluminium() -> TabulatedSpec {
    let (ax, ay) = (0.3f32, 0.06f32);
    let Some(ConductorFresnel::Complex { eta, k }) = ConductorFresnel::named("Al") else {
        unreachable!("Al is tabulated")
    };
    let (eta, k) = (eta.value(555.0), k.value(555.0));
    Tabulation {
        name: "brushed aluminium".into(),
        wavelengths: vec![555.0],
        theta_i: deg([0.0, 20.0, 40.0, 60.0, 80.0]),
        phi_i: deg([0.0, 90.0, 180.0, 270.0]),
        ior: None,
        brdf: Some(GridSpec {
            grid: ScatterGrid::SpecularRelative,
            theta: power_spaced(28, PI, 2.0),
            phi: deg((0..24).map(|i| i as f32 * 15.0)),
        }),
        btdf: None,
        both_faces: false,
    }
    .tabulate_energy_matched(move |_, d_in: Vec3, d_out: Vec3| {
        let h = (d_in + d_out).normalize();
        if h.z <= 0.0 || d_out.z <= 0.0 {
            return 0.0;
        }
        let t2 = (h.x * h.x / (ax * ax) + h.y * h.y / (ay * ay)) / (h.z * h.z);
        let d = (-t2).exp() / (PI * ax * ay * h.z.powi(4));
        let hi = h.dot(d_in).max(1e-4);
        fr_complex(hi, eta, k) * d / (4.0 * hi * d_in.z.max(d_out.z))
    })
}

/// Red automotive-style paint: a GGX clear coat (n 1.5, alpha 0.05) over a Lambertian base of
/// linear sRGB (0.7, 0.05, 0.04); the base is seen through the coat's Fresnel transmission on
/// the way in and out: f = f_coat + (1 - F(i)) (1 - F(o)) rho / pi.
fn red_paint() -> TabulatedSpec {
    let coat = Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.05, transmittance: None };
    let base = Spectrum::rgb_reflectance([0.7, 0.05, 0.04]).expect("valid reflectance");
    let coat_f = material_fn(&coat);
    Tabulation {
        name: "red gloss paint".into(),
        wavelengths: (0..7).map(|i| 400.0 + 50.0 * i as f32).collect(),
        theta_i: deg([0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0]),
        phi_i: vec![0.0],
        ior: None,
        brdf: Some(GridSpec {
            grid: ScatterGrid::SpecularRelative,
            theta: power_spaced(32, PI, 2.2),
            phi: half_phi(20.0),
        }),
        btdf: None,
        both_faces: false,
    }
    .tabulate_energy_matched(move |l, d_in: Vec3, d_out: Vec3| {
        if d_out.z <= 0.0 {
            return 0.0;
        }
        let t = (1.0 - fr_dielectric(d_in.z, 1.5)) * (1.0 - fr_dielectric(d_out.z, 1.5));
        coat_f(l, d_in, d_out) + t * base.value(l) * FRAC_1_PI
    })
}

fn lambertian() -> TabulatedSpec {
    Tabulation {
        name: "white Lambertian reference".into(),
        wavelengths: vec![555.0],
        theta_i: deg([0.0, 30.0, 60.0, 89.0]),
        phi_i: vec![0.0],
        ior: None,
        brdf: Some(GridSpec { grid: ScatterGrid::Absolute, theta: deg([0.0, 30.0, 60.0, 90.0]), phi: vec![0.0] }),
        btdf: None,
        both_faces: false,
    }
    .tabulate_energy_matched(|_, _, _| 0.8 * FRAC_1_PI)
}

/// Every library material, in file order.
pub fn library() -> Vec<LibraryEntry> {
    let mut v = vec![
        LibraryEntry {
            file: "lambertian-white.toml",
            description: "Lambertian reference: f = 0.8 / pi at every wavelength and angle",
            provenance: vec![("model", "ideal diffuse reflector, reflectance 0.8")],
            spec: lambertian(),
        },
        LibraryEntry {
            file: "lightguide-narrow.toml",
            description: "Optically polished PMMA lightguide face: narrow reflection and transmission lobes, both sides",
            provenance: vec![("model", "GGX rough dielectric interface, alpha 0.02"), ("ior", "1.49 (PMMA at 555 nm)")],
            spec: dielectric_interface("PMMA lightguide face (narrow)", 1.49, 0.02, 40.0, 48, 3.0, 30.0),
        },
        LibraryEntry {
            file: "glass-plate-top.toml",
            description: "Glass plate top surface (Zhdanov et al. 2015): very narrow lobes around mirror and refraction",
            provenance: vec![
                ("model", "GGX rough dielectric interface, alpha 0.01"),
                ("ior", "1.517 (N-BK7 at 555 nm)"),
            ],
            spec: dielectric_interface("glass plate top (narrow)", 1.517, 0.01, 20.0, 48, 3.0, 30.0),
        },
        LibraryEntry {
            file: "glass-plate-bottom.toml",
            description: "Glass plate bottom surface (Zhdanov et al. 2015): ground (frosted) glass, wide lobes",
            provenance: vec![
                ("model", "GGX rough dielectric interface, alpha 0.5"),
                ("ior", "1.517 (N-BK7 at 555 nm)"),
            ],
            spec: dielectric_interface("glass plate bottom (wide)", 1.517, 0.5, 180.0, 24, 1.3, 15.0),
        },
        LibraryEntry {
            file: "gold-satin.toml",
            description: "Satin gold: GGX alpha 0.15 with the spectral complex IOR of gold",
            provenance: vec![
                ("model", "GGX conductor, alpha 0.15"),
                ("optical constants", "Au, quasar's built-in table"),
            ],
            spec: metal("satin gold", "Au", 0.15),
        },
        LibraryEntry {
            file: "copper-rough.toml",
            description: "Rough copper: GGX alpha 0.3 with the spectral complex IOR of copper",
            provenance: vec![
                ("model", "GGX conductor, alpha 0.3"),
                ("optical constants", "Cu, quasar's built-in table"),
            ],
            spec: metal("rough copper", "Cu", 0.3),
        },
        LibraryEntry {
            file: "aluminium-brushed.toml",
            description: "Brushed aluminium: anisotropic lobe, wide across the brushing direction (x), narrow along it",
            provenance: vec![
                ("model", "anisotropic Beckmann, alpha_x 0.3, alpha_y 0.06, Ashikhmin-Shirley denominator"),
                ("optical constants", "Al at 555 nm, quasar's built-in table"),
            ],
            spec: brushed_aluminium(),
        },
        LibraryEntry {
            file: "paint-red-gloss.toml",
            description: "Red gloss paint: Lambertian red base under a clear coat (n 1.5, GGX alpha 0.05)",
            provenance: vec![
                ("model", "f = f_coat + (1 - F(i)) (1 - F(o)) rho / pi"),
                ("base", "linear sRGB (0.7, 0.05, 0.04)"),
            ],
            spec: red_paint(),
        },
    ];
    for e in &mut v {
        round5(&mut e.spec);
    }
    v
}

/// The TOML text of a library entry.
pub fn entry_text(e: &LibraryEntry) -> String {
    quasar_importers::bsdf_file::to_toml(&e.spec, e.description, &e.provenance)
}
