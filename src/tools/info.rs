//! `quasar info`: what a scene contains (meshes, triangles, materials, textures, cameras, lights,
//! bounds) and the scene analysis behind `auto`.

use std::fmt::Write as _;
use std::path::Path;

use quasar_importers::SceneDesc;
use quasar_materials::spectrum::Spectrum;
use quasar_materials::{ConductorFresnel, Ior, Material};

use super::report_format::{num, vec3};
use crate::core::scene::Scene;
use crate::integrator::analysis::SceneAnalysis;

/// The report of the scene file `path`, imported as `desc` and compiled as `compiled`.
pub fn report(path: &Path, desc: &SceneDesc, compiled: &Scene) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "scene: {}", path.display());
    let _ = writeln!(s, "meshes: {}, triangles: {}", desc.meshes.len(), compiled.triangle_count());
    let _ = writeln!(s, "materials: {}", desc.materials.len());
    for m in &desc.materials {
        let tex = if m.textures.is_empty() { "" } else { " (textured)" };
        let _ = writeln!(s, "  {}: {}{tex}{}", m.name, describe_material(&m.material), describe_medium(m));
    }
    if !desc.textures.is_empty() {
        let t: Vec<String> = desc.textures.iter().map(|t| format!("{} {}x{}", t.name, t.width, t.height)).collect();
        let _ = writeln!(s, "textures: {}", t.join(", "));
    }
    let c = &desc.camera;
    let axis = match c.fov_axis {
        quasar_importers::FovAxis::X => "horizontal",
        quasar_importers::FovAxis::Y => "vertical",
    };
    let _ = writeln!(
        s,
        "camera: from {} towards {}, {}° {axis} field of view",
        vec3(c.position),
        vec3(c.target),
        num(c.fov_deg)
    );
    if !desc.cameras.is_empty() {
        let names: Vec<&str> = desc.cameras.iter().map(|c| c.name.as_str()).collect();
        let _ = writeln!(s, "cameras in the file: {}", names.join(", "));
    }
    for line in super::light_summary::light_lines(desc) {
        let _ = writeln!(s, "{line}");
    }
    for sensor in &desc.sensors {
        let _ = writeln!(
            s,
            "sensor {}: {} point(s), normal {}, {} samples each",
            sensor.name,
            sensor.points().len(),
            vec3(sensor.normal),
            sensor.samples
        );
    }
    if let Some((lo, hi)) = quasar_importers::framing::mesh_bounds(&desc.meshes) {
        let _ = writeln!(s, "bounds: {} to {} m (size {} m)", vec3(lo), vec3(hi), vec3(hi - lo));
    }
    let _ = writeln!(s, "bounding sphere: centre {}, radius {}", vec3(compiled.center), compiled.radius);
    for line in &desc.import_summary {
        let _ = writeln!(s, "{line}");
    }
    s + &SceneAnalysis::of(compiled).report()
}

/// One line on a spectral curve: `0.8`, `table 400-700 nm, 76 points, mean 0.71`,
/// `RGB (0.63, 0.065, 0.05)`, `blackbody 2700 K`, `CIE D65`.
pub fn describe_spectrum(s: &Spectrum) -> String {
    match s {
        Spectrum::Constant(v) => num(*v),
        Spectrum::PiecewiseLinear { lambda, values } => {
            let mean = values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len().max(1) as f64;
            format!(
                "table {}-{} nm, {} points, mean {}",
                num(lambda[0]),
                num(*lambda.last().unwrap_or(&lambda[0])),
                values.len(),
                num(mean as f32)
            )
        }
        Spectrum::Blackbody { kelvin, .. } => format!("blackbody {} K", num(*kelvin)),
        Spectrum::Illuminant { illuminant, .. } => format!("CIE {illuminant:?}"),
        Spectrum::RgbReflectance(r) => format!("RGB ({}, {}, {})", num(r.rgb[0]), num(r.rgb[1]), num(r.rgb[2])),
        Spectrum::RgbIlluminant { rgb, .. } => format!("RGB light ({}, {}, {})", num(rgb[0]), num(rgb[1]), num(rgb[2])),
        Spectrum::Dense(d) => describe_spectrum(d.curve()),
    }
}

/// The medium inside a material, as a suffix of its line (`; inside: absorption 2 /m,
/// scattering 40 /m, g 0.7`); empty for a clear one.
pub fn describe_medium(m: &quasar_importers::MaterialDesc) -> String {
    let mut parts = Vec::new();
    match &m.absorption {
        Some(quasar_materials::Absorption::Coefficient(c)) => {
            parts.push(format!("absorption {} /m", describe_spectrum(c)))
        }
        Some(quasar_materials::Absorption::Transmittance { transmittance, thickness }) => {
            parts.push(format!("internal transmittance {} at {} m", describe_spectrum(transmittance), num(*thickness)))
        }
        None => {}
    }
    if let Some(sc) = &m.scattering {
        parts.push(format!("scattering {} /m, g {}", describe_spectrum(&sc.coefficient), num(sc.g)));
    }
    if parts.is_empty() { String::new() } else { format!("; inside: {}", parts.join(", ")) }
}

/// One line on a material: its model and key parameters
/// (`diffuse, reflectance table 400-700 nm, 76 points, mean 0.71, two-sided`).
pub fn describe_material(m: &Material) -> String {
    let sided = |two: bool| if two { ", two-sided" } else { "" };
    let roughness = |alpha: f32| if alpha == 0.0 { "smooth".to_string() } else { format!("GGX alpha {}", num(alpha)) };
    match m {
        Material::Diffuse { reflectance, two_sided } => {
            format!("diffuse, reflectance {}{}", describe_spectrum(reflectance), sided(*two_sided))
        }
        Material::Conductor { alpha, fresnel, two_sided } => {
            let f = match fresnel {
                ConductorFresnel::Constant(r) => format!("reflectance {}", describe_spectrum(r)),
                ConductorFresnel::Complex { eta, k } => {
                    format!("eta {}, k {}", describe_spectrum(eta), describe_spectrum(k))
                }
            };
            format!("conductor, {}, {f}{}", roughness(*alpha), sided(*two_sided))
        }
        Material::Dielectric { ior, alpha, transmittance } => {
            let n = match ior {
                Ior::Constant(n) => format!("ior {}", num(*n)),
                Ior::Cauchy { a, b } => format!("ior Cauchy a {} b {} um^2", num(*a), num(*b)),
                Ior::Sellmeier { .. } => "ior Sellmeier".to_string(),
            };
            let tint =
                transmittance.as_ref().map_or(String::new(), |t| format!(", transmittance {}", describe_spectrum(t)));
            format!("dielectric, {}, {n}{tint}", roughness(*alpha))
        }
        Material::Coated { coating, base, two_sided } => {
            let absorbs = if coating.absorption.is_some() { ", absorbing" } else { "" };
            format!(
                "coated (ior {}, {}{absorbs}) over [{}]{}",
                num(coating.ior),
                roughness(coating.alpha),
                describe_material(base),
                sided(*two_sided)
            )
        }
        Material::Sheen { color, alpha, base } => {
            format!("sheen {} (alpha {}) over [{}]", describe_spectrum(color), num(*alpha), describe_material(base))
        }
        Material::Tabulated(t) => {
            let spec = t.spec();
            format!(
                "tabulated BSDF `{}`, {} wavelengths, {} x {} incidences",
                spec.name,
                spec.wavelengths.len(),
                spec.theta_i.len(),
                spec.phi_i.len()
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn materials_and_spectra_read_as_one_line() {
        let table = Spectrum::piecewise_linear(vec![400.0, 550.0, 700.0], vec![0.5, 0.7, 0.9]).unwrap();
        assert_eq!(describe_spectrum(&table), "table 400-700 nm, 3 points, mean 0.7");
        let m = Material::Diffuse { reflectance: table, two_sided: true };
        assert_eq!(describe_material(&m), "diffuse, reflectance table 400-700 nm, 3 points, mean 0.7, two-sided");
        let g = Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.05, transmittance: None };
        assert_eq!(describe_material(&g), "dielectric, GGX alpha 0.05, ior 1.5");
        let mut milk = quasar_importers::MaterialDesc {
            name: "milk".into(),
            material: g.clone(),
            absorption: Some(quasar_materials::Absorption::Coefficient(Spectrum::Constant(2.0))),
            scattering: Some(quasar_materials::Scattering { coefficient: Spectrum::Constant(40.0), g: 0.7 }),
            textures: Default::default(),
            source: Default::default(),
        };
        assert_eq!(describe_medium(&milk), "; inside: absorption 2 /m, scattering 40 /m, g 0.7");
        (milk.absorption, milk.scattering) = (None, None);
        assert_eq!(describe_medium(&milk), "");
        assert_eq!(num(480.3702), "480.4");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(2.5e-6), "2.500e-6");
    }
}
