//! Scene analysis for `--method auto` and `quasar info` (docs/architecture.md §7.6): what the scene
//! requires (narrow lobes, specular chains, dispersion, light types) and which method models
//! exactly that.

use std::collections::BTreeSet;

use quasar_materials::Material;

use super::bidir::methods::QUASI;
use super::entry::MethodEntry;
use super::pt::PT;
use crate::core::light::Light;
use crate::core::scene::Scene;

/// Non-uniformity kappa (at 45 degrees incidence) above which a material counts as a narrow
/// lobe: its photon density estimates would be noisy, so gathering should move elsewhere
/// (adaptive depth) and its lobe should be traced through (quasi-specular methods).
pub use quasar_materials::NARROW_KAPPA;

/// What a scene contains that matters for the choice of method.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneAnalysis {
    /// Materials used by triangles whose kappa at 45 degrees exceeds [`NARROW_KAPPA`] (name, kappa).
    pub narrow: Vec<(String, f32)>,
    /// Materials used by triangles that are perfectly specular (smooth mirrors and glass).
    pub specular: Vec<String>,
    /// Materials with a wavelength-dependent IOR (secondary wavelengths are terminated there).
    pub dispersive: Vec<String>,
    /// Light counts: area triangles, point (and luminaire), spot, directional, environment.
    pub lights: [usize; 5],
    /// True when light can reach a non-specular surface through specular or narrow events
    /// (caustics), i.e. a specular or narrow material and at least one light exist.
    pub caustic_paths: bool,
}

impl SceneAnalysis {
    /// Analyses a compiled scene.
    pub fn of(scene: &Scene) -> Self {
        let used: BTreeSet<u32> = scene.accel.info.iter().map(|t| t.material).collect();
        let mut narrow = Vec::new();
        let mut specular = Vec::new();
        let mut dispersive = Vec::new();
        for &m in &used {
            let (name, material) = (&scene.material_names[m as usize], &scene.materials[m as usize]);
            let kappa = scene.non_uniformity()[m as usize].typical();
            if material.is_specular() || kappa.is_infinite() {
                specular.push(name.clone());
            } else if kappa > NARROW_KAPPA {
                narrow.push((name.clone(), kappa));
            }
            if let Material::Dielectric { ior, .. } = material
                && ior.is_dispersive()
            {
                dispersive.push(name.clone());
            }
        }
        let mut lights = [0usize; 5];
        for l in &scene.lights {
            let k = match l {
                Light::Area { .. } => 0,
                Light::Point { .. } | Light::Luminaire(_) => 1,
                Light::Spot { .. } => 2,
                Light::Directional { .. } => 3,
                Light::Environment { .. } => 4,
            };
            lights[k] += 1;
        }
        let caustic_paths = (!specular.is_empty() || !narrow.is_empty()) && lights.iter().sum::<usize>() > 0;
        Self { narrow, specular, dispersive, lights, caustic_paths }
    }

    /// The method `auto` runs: `pt` when nothing is narrow or specular (path tracing handles
    /// diffuse and moderately glossy scenes best); otherwise `quasi`, which traces narrow lobes
    /// and quasi-specular cones through and gathers at the first vertex beyond them. It reached
    /// every error of the benchmark family as soon as `adaptive+quasi` or sooner, up to 3.3x on
    /// the rough-bottom plates, where the adaptive depth chose the floor under the plate and left
    /// the bottom's reflection back into the glass to BSDF sampling (BENCHMARKS.md, "quasi for
    /// auto").
    pub fn auto_method(&self) -> &'static MethodEntry {
        if self.narrow.is_empty() && !self.caustic_paths { &PT } else { &QUASI }
    }

    /// A human-readable report (for `quasar info`).
    pub fn report(&self) -> String {
        let mut s = String::new();
        let list = |v: &[String]| if v.is_empty() { "none".to_string() } else { v.join(", ") };
        let narrow: Vec<String> = self.narrow.iter().map(|(n, k)| format!("{n} (kappa {k:.0} at 45 deg)")).collect();
        s += &format!("narrow lobes (kappa > {NARROW_KAPPA}): {}\n", list(&narrow));
        s += &format!("specular surfaces: {}\n", list(&self.specular));
        s += &format!(
            "caustic paths (light via specular/narrow events): {}\n",
            if self.caustic_paths { "yes" } else { "no" }
        );
        s += &format!(
            "dispersion: {}\n",
            if self.dispersive.is_empty() {
                "none (all wavelengths of a path kept)".to_string()
            } else {
                format!("{} (secondary wavelengths terminated there)", self.dispersive.join(", "))
            }
        );
        let [a, p, sp, d, e] = self.lights;
        s += &format!(
            "lights: {a} emissive triangles, {p} point or luminaire, {sp} spot, {d} directional, {e} environment\n"
        );
        s += &format!("auto method: {}\n", self.auto_method().name);
        s
    }
}
