//! UsdShade -> quasar materials: the material bound to a prim (`material:binding`, with
//! inheritance from ancestors and `bindMaterialAs = "strongerThanDescendants"`, resolved by the
//! `openusd` crate from the nearest prim that applies `MaterialBindingAPI`) and its
//! `UsdPreviewSurface`, mapped like glTF's metallic-roughness ([`quasar_materials::pbr`]):
//!
//! | UsdPreviewSurface (schema default) | quasar |
//! |---|---|
//! | `diffuseColor` (0.18 grey) | base colour |
//! | `metallic` (0) | metalness |
//! | `roughness` (0.5) | perceptual roughness (GGX alpha = roughness²) |
//! | `opacity` (1) < 1 with `ior` (1.5) | dielectric of that IOR (transmission = 1 - opacity) |
//! | `emissiveColor` (black) | an area light of luminance `emissiveColor` in cd/m² (as UsdLux's nits) |
//!
//! Textured inputs (`UsdUVTexture`), `specularColor` (the specular workflow), clearcoat and
//! normal maps are not read: the input's default is used and a warning names the material.
//! Materials that are not UsdPreviewSurface (MDL, MaterialX) get the fallback grey diffuse with
//! a warning.

use openusd::schemas::shade::{self, MaterialBindingAPI};
use openusd::sdf;
use openusd::usd::{Prim, Stage};
use quasar_materials::spectrum::Spectrum;
use quasar_materials::{Material, PbrParams, pbr_material};

use crate::photometric::photometric_scale;
use crate::scene_desc::EmissionDesc;

/// The material path bound to `prim` (all-purpose binding), if any.
pub(super) fn bound_material(stage: &Stage, prim: &Prim) -> Option<sdf::Path> {
    let mut at = Some(prim.path().clone());
    while let Some(p) = at {
        if let Ok(Some(api)) = MaterialBindingAPI::get(stage, p.clone()) {
            return api.compute_bound_material("").ok().flatten();
        }
        at = p.parent();
    }
    None
}

/// The fallback material of prims without a (readable) material: grey diffuse 0.18, the
/// UsdPreviewSurface default colour.
pub(super) fn fallback() -> Material {
    pbr_material(&PbrParams { base_color: [0.18; 3], metallic: 0.0, roughness: 0.5, ..Default::default() })
}

/// The quasar material and emission of the UsdShade material at `path`, plus the warnings
/// about what was not read (each naming the material).
pub(super) fn convert(stage: &Stage, path: &sdf::Path) -> (Material, Option<EmissionDesc>, Vec<String>) {
    let mut warnings = Vec::new();
    let at = path.as_str();
    let ps = match shade::read_preview_surface(stage, path) {
        Ok(Some(ps)) => ps,
        Ok(None) => {
            warnings.push(format!(
                "{at}: not a UsdPreviewSurface material (MDL or MaterialX shaders are not read); grey diffuse used"
            ));
            return (fallback(), None, warnings);
        }
        Err(e) => {
            warnings.push(format!("{at}: the material cannot be read ({e:#}); grey diffuse used"));
            return (fallback(), None, warnings);
        }
    };
    let mut textured: Vec<&str> = Vec::new();
    let color =
        |c: &shade::Channel<openusd::gf::Vec3f>, name: &'static str, default: [f32; 3], t: &mut Vec<&str>| match c {
            shade::Channel::Value(v) => [v.x, v.y, v.z],
            shade::Channel::Texture(_) => {
                t.push(name);
                default
            }
            shade::Channel::Unset => default,
        };
    let scalar = |c: &shade::Channel<f32>, name: &'static str, default: f32, t: &mut Vec<&str>| match c {
        shade::Channel::Value(v) => *v,
        shade::Channel::Texture(_) => {
            t.push(name);
            default
        }
        shade::Channel::Unset => default,
    };
    let base = color(&ps.diffuse_color, "diffuseColor", [0.18; 3], &mut textured);
    let emissive = color(&ps.emissive_color, "emissiveColor", [0.0; 3], &mut textured);
    let metallic = scalar(&ps.metallic, "metallic", 0.0, &mut textured);
    let roughness = scalar(&ps.roughness, "roughness", 0.5, &mut textured);
    let opacity = scalar(&ps.opacity, "opacity", 1.0, &mut textured);
    let ior = scalar(&ps.ior, "ior", 1.5, &mut textured);
    let _ = color(&ps.normal, "normal", [0.0; 3], &mut textured);
    if !textured.is_empty() {
        warnings
            .push(format!("{at}: textured inputs are not read yet ({}); their defaults are used", textured.join(", ")));
    }
    let unread: Vec<&str> = [
        (ps.specular_color.is_set(), "specularColor (specular workflow)"),
        (ps.clearcoat.is_set(), "clearcoat"),
        (ps.opacity_threshold.is_set(), "opacityThreshold"),
    ]
    .into_iter()
    .filter_map(|(set, n)| set.then_some(n))
    .collect();
    if !unread.is_empty() {
        warnings.push(format!("{at}: {} not supported; ignored", unread.join(", ")));
    }
    let material = pbr_material(&PbrParams {
        base_color: base,
        metallic,
        roughness,
        transmission: (1.0 - opacity).clamp(0.0, 1.0),
        ior: if ior.is_finite() && ior >= 1.0 { ior } else { 1.5 },
    });
    let emission =
        (emissive.iter().any(|&c| c > 0.0) && emissive.iter().all(|c| c.is_finite())).then(|| EmissionDesc {
            spectrum: Spectrum::rgb_illuminant(emissive).unwrap_or(Spectrum::Constant(0.0)),
            scale: photometric_scale(1.0),
            two_sided: false,
        });
    (material, emission, warnings)
}
