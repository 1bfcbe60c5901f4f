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
//! | `clearcoat` (0) >= 0.5, `clearcoatRoughness` (0.01) | a coat of IOR 1.5 over the surface, GGX alpha = clearcoatRoughness² |
//!
//! Textured inputs ([`super::texture`]): `diffuseColor` (base colour texture, `scale` as the
//! factor), `roughness` and `metallic` (packed as glTF's metallic-roughness texture), `normal`
//! (tangent-space normal map), `emissiveColor` (the emission follows the image per point, its
//! mean the light's nominal colour, as for glTF). Other textured inputs (`opacity`, `ior`, `clearcoat`, ...),
//! `specularColor` (the specular workflow) and `opacityThreshold` are not read: the default is
//! used and a warning names the material. Materials that are not UsdPreviewSurface (MDL,
//! MaterialX) get the fallback grey diffuse with a warning.

use std::collections::HashMap;

use openusd::schemas::shade;
use openusd::sdf;
use openusd::usd::{Collection, MembershipQuery, is_collection_api_path};
use openusd::usd::{Prim, Stage};
use quasar_materials::spectrum::Spectrum;
use quasar_materials::{Material, PbrParams, pbr_material};

use super::texture::{self, TextureSet, UvTexture};
use crate::error::ImportError;
use crate::photometric::photometric_scale;
use crate::scene_desc::EmissionDesc;
use crate::texture_desc::MaterialTextures;

/// A converted UsdShade material.
pub(super) struct Converted {
    /// The material of the constant inputs (textured inputs at their factors).
    pub material: Material,
    /// Its textures (empty when none is read).
    pub textures: MaterialTextures,
    /// The emission of `emissiveColor`.
    pub emission: Option<EmissionDesc>,
    /// What was not read, for warnings (each naming the material or texture).
    pub notes: Vec<String>,
}

/// The material bound to `prim` for rendering, as Pixar's `ComputeBoundMaterial` resolves it:
/// the `full` purpose first, then all-purpose bindings; up the namespace from `prim`, the closest
/// prim with a binding wins unless an ancestor's is `strongerThanDescendants` (the topmost such
/// then wins); at one prim, a collection binding whose collection includes `prim` beats the
/// direct binding (in property order). Resolved here rather than by openusd 0.6, which reads
/// `bindMaterialAs` only as a token (a `.usda` file writes it as a string) and resolves only for
/// a queried prim that carries `MaterialBindingAPI` (a collection's members need not).
pub(super) fn bound_material(stage: &Stage, prim: &Prim) -> Option<sdf::Path> {
    let mut members: HashMap<sdf::Path, Option<MembershipQuery>> = HashMap::new();
    for purpose in [RENDER_PURPOSE, ""] {
        let mut winner = None;
        let mut at = Some(prim.path().clone());
        while let Some(p) = at {
            if !p.is_abs_root()
                && let Some((m, stronger)) = binding_at(stage, &p, prim.path(), purpose, &mut members)
                && (winner.is_none() || stronger)
            {
                winner = Some(m);
            }
            at = p.parent();
        }
        if winner.is_some() {
            return winner;
        }
    }
    None
}

/// The binding of `purpose` ("" for all-purpose) that wins at the prim `p` for the queried prim
/// `queried`, with whether it is `strongerThanDescendants`: a collection binding whose
/// collection includes `queried`, else the direct binding.
fn binding_at(
    stage: &Stage,
    p: &sdf::Path,
    queried: &sdf::Path,
    purpose: &str,
    members: &mut HashMap<sdf::Path, Option<MembershipQuery>>,
) -> Option<(sdf::Path, bool)> {
    let prefix = "material:binding:collection:";
    for name in stage.prim(p.clone()).property_names().ok()? {
        let Some(rest) = name.as_str().strip_prefix(prefix) else { continue };
        // `<purpose>:<name>` is purpose-restricted, a plain `<name>` all-purpose
        let binding_purpose = match rest.split(':').collect::<Vec<_>>().as_slice() {
            [pur, _] => *pur,
            _ => "",
        };
        if binding_purpose != purpose {
            continue;
        }
        let Ok(rel) = p.append_property(name.as_str()) else { continue };
        let Ok(targets) = stage.relationship(rel.clone()).targets() else { continue };
        let [collection, material] = targets.as_slice() else { continue };
        let query = members.entry(collection.clone()).or_insert_with(|| {
            let (owner, c) = is_collection_api_path(collection)?;
            Collection::new(owner, c).compute_membership_query(stage).ok()
        });
        if query.as_ref().is_some_and(|q| q.is_path_included(queried)) {
            return Some((material.clone(), stronger_than_descendants(stage, &rel)));
        }
    }
    let rel = if purpose.is_empty() { "material:binding".to_string() } else { format!("material:binding:{purpose}") };
    let rel = p.append_property(rel.as_str()).ok()?;
    let material = stage.relationship(rel.clone()).targets().ok()?.into_iter().next()?;
    Some((material, stronger_than_descendants(stage, &rel)))
}

/// Whether the binding relationship `rel` is `strongerThanDescendants` (its `bindMaterialAs`
/// metadata, a token or a string).
fn stronger_than_descendants(stage: &Stage, rel: &sdf::Path) -> bool {
    match stage.attribute(rel.clone()).get_metadata::<sdf::Value>("bindMaterialAs") {
        Ok(Some(sdf::Value::Token(t))) => t.as_str() == "strongerThanDescendants",
        Ok(Some(sdf::Value::String(s))) => s == "strongerThanDescendants",
        _ => false,
    }
}

/// The material purpose a final render resolves first (UsdShade's `full`; `preview` bindings are
/// for viewports).
const RENDER_PURPOSE: &str = "full";

/// The fallback material of prims without a (readable) material: grey diffuse 0.18, the
/// UsdPreviewSurface default colour.
pub(super) fn fallback() -> Material {
    pbr_material(&PbrParams { base_color: [0.18; 3], metallic: 0.0, roughness: 0.5, ..Default::default() })
}

/// The quasar material, textures and emission of the UsdShade material at `path` (images
/// decoded into `textures`; `file` is the stage's file), plus notes about what was not read.
/// A texture that cannot be read is an error naming the file, the texture prim and its file.
pub(super) fn convert(
    stage: &Stage,
    path: &sdf::Path,
    file: &std::path::Path,
    textures: &mut TextureSet,
) -> Result<Converted, ImportError> {
    let mut warnings = Vec::new();
    let at = path.as_str();
    let fallback_result = |warnings| Converted {
        material: fallback(),
        textures: MaterialTextures::default(),
        emission: None,
        notes: warnings,
    };
    let ps = match shade::read_preview_surface(stage, path) {
        Ok(Some(ps)) => ps,
        Ok(None) => {
            warnings.push(format!(
                "{at}: not a UsdPreviewSurface material (MDL or MaterialX shaders are not read); grey diffuse used"
            ));
            return Ok(fallback_result(warnings));
        }
        Err(e) => {
            warnings.push(format!("{at}: the material cannot be read ({e:#}); grey diffuse used"));
            return Ok(fallback_result(warnings));
        }
    };
    let shader = sdf::Path::new(&ps.shader).ok().map(|p| stage.prim(p));
    let find = |input: &str, notes: &mut Vec<String>| -> Option<UvTexture> {
        texture::find(stage, shader.as_ref()?, input, file, notes)
    };
    let tex_base = find("diffuseColor", &mut warnings);
    let tex_rough = find("roughness", &mut warnings);
    let tex_metal = find("metallic", &mut warnings);
    let tex_normal = find("normal", &mut warnings);
    let tex_emissive = find("emissiveColor", &mut warnings);
    let read = ["diffuseColor", "roughness", "metallic", "normal", "emissiveColor"];
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
    let mut base = color(&ps.diffuse_color, "diffuseColor", [0.18; 3], &mut textured);
    let mut emissive = color(&ps.emissive_color, "emissiveColor", [0.0; 3], &mut textured);
    let mut metallic = scalar(&ps.metallic, "metallic", 0.0, &mut textured);
    let mut roughness = scalar(&ps.roughness, "roughness", 0.5, &mut textured);
    let opacity = scalar(&ps.opacity, "opacity", 1.0, &mut textured);
    let ior = scalar(&ps.ior, "ior", 1.5, &mut textured);
    let clearcoat = scalar(&ps.clearcoat, "clearcoat", 0.0, &mut textured);
    let clearcoat_roughness = scalar(&ps.clearcoat_roughness, "clearcoatRoughness", 0.01, &mut textured);
    let _ = color(&ps.normal, "normal", [0.0; 3], &mut textured);
    let mut maps = MaterialTextures::default();
    let ignored_bias = |t: &UvTexture, w: &mut Vec<String>| {
        if t.bias.iter().any(|&b| b != 0.0) {
            w.push(format!("{}: inputs:bias is ignored (only normal maps' standard bias is read)", t.at));
        }
    };
    if let Some(t) = &tex_base {
        maps.base_color = Some(textures.image(t, file)?);
        base = [t.scale[0], t.scale[1], t.scale[2]];
        ignored_bias(t, &mut warnings);
        if t.raw {
            warnings.push(format!("{}: sourceColorSpace `raw` on a colour: the image is decoded as sRGB", t.at));
        }
    }
    for t in [&tex_rough, &tex_metal].into_iter().flatten() {
        ignored_bias(t, &mut warnings);
    }
    maps.metallic_roughness = textures.metallic_roughness(tex_rough.as_ref(), tex_metal.as_ref(), file)?;
    if let Some(t) = &tex_rough {
        roughness = t.scale[t.channel.unwrap_or(0)];
    }
    if let Some(t) = &tex_metal {
        metallic = t.scale[t.channel.unwrap_or(0)];
    }
    if let Some(t) = &tex_normal {
        maps.normal = Some(textures.image(t, file)?);
        maps.normal_scale = 1.0;
        let standard =
            t.scale[..3].iter().all(|&s| (s - 2.0).abs() < 1e-3) && t.bias[..3].iter().all(|&b| (b + 1.0).abs() < 1e-3);
        if !standard {
            warnings.push(format!(
                "{}: a normal map with scale {:?} and bias {:?}: read with the standard encoding (scale 2, bias -1)",
                t.at, t.scale, t.bias
            ));
        }
    }
    let mut emissive_texture = None;
    if let Some(t) = &tex_emissive {
        let r = textures.image(t, file)?;
        let mean = textures.descs[r.texture].mean(true);
        emissive_texture =
            Some(crate::scene_desc::EmissiveTexture { texture: r, factor: [t.scale[0], t.scale[1], t.scale[2]] });
        emissive = [0, 1, 2].map(|k| t.scale[k] * mean[k]);
    }
    textured.retain(|n| {
        !read.contains(n)
            || match *n {
                "diffuseColor" => tex_base.is_none(),
                "roughness" => tex_rough.is_none(),
                "metallic" => tex_metal.is_none(),
                "normal" => tex_normal.is_none(),
                _ => tex_emissive.is_none(),
            }
    });
    if !textured.is_empty() {
        warnings.push(format!("{at}: textured inputs not read ({}); their defaults are used", textured.join(", ")));
    }
    let unread: Vec<&str> = [
        (ps.specular_color.is_set(), "specularColor (specular workflow)"),
        (ps.opacity_threshold.is_set(), "opacityThreshold"),
    ]
    .into_iter()
    .filter_map(|(set, n)| set.then_some(n))
    .collect();
    if !unread.is_empty() {
        warnings.push(format!("{at}: {} not supported; ignored", unread.join(", ")));
    }
    let params = PbrParams {
        base_color: base,
        metallic,
        roughness,
        transmission: (1.0 - opacity).clamp(0.0, 1.0),
        ior: if ior.is_finite() && ior >= 1.0 { ior } else { 1.5 },
        clearcoat,
        clearcoat_roughness,
        ..PbrParams::default()
    };
    if maps.base_color.is_some() || maps.metallic_roughness.is_some() || maps.normal.is_some() {
        maps.pbr = Some(params);
    }
    let material = pbr_material(&params);
    let emission =
        (emissive.iter().any(|&c| c > 0.0) && emissive.iter().all(|c| c.is_finite())).then(|| EmissionDesc {
            spectrum: Spectrum::rgb_illuminant(emissive).unwrap_or(Spectrum::Constant(0.0)),
            scale: photometric_scale(1.0),
            two_sided: false,
            texture: emissive_texture,
        });
    Ok(Converted { material, textures: maps, emission, notes: warnings })
}
