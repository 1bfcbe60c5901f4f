//! glTF materials -> [`MaterialDesc`] (via [`pbr_material`]) plus area emission and textures.
//! The mapping is documented in `quasar_materials::pbr` and `docs/gltf.md`.

use std::path::Path;

use quasar_materials::spectrum::Spectrum;

use super::texture::TextureLoader;
use crate::error::ImportError;
use crate::names::unique_name;
use crate::photometric::photometric_scale;
use crate::scene_desc::{EmissionDesc, EmissiveTexture, MaterialDesc, SourceLocation};
use crate::texture_desc::MaterialTextures;
use quasar_materials::{Absorption, PbrParams, pbr_material};

/// A converted material with the emission its meshes get.
pub(super) struct Converted {
    /// The material.
    pub desc: MaterialDesc,
    /// Its glTF factors (what a per-point evaluation multiplies texels and vertex colours into).
    pub params: PbrParams,
    /// Area emission of meshes using it.
    pub emission: Option<EmissionDesc>,
}

/// The error for the value `v` at JSON pointer `at` of `file`: it must be `what`.
fn invalid_value(file: &Path, at: &str, what: &str, v: &serde_json::Value) -> ImportError {
    super::err(crate::error::ImportErrorKind::InvalidValue, file, at, format!("must be {what}, got {v}"))
}

/// The number `obj[key]` (`default` when absent), which `ok` must accept; else an error at
/// `ptr/key` of `file` saying it must be `what`.
fn number(
    obj: &serde_json::Value,
    (ptr, key): (&str, &str),
    file: &Path,
    default: f32,
    what: &str,
    ok: impl Fn(f64) -> bool,
) -> Result<f32, ImportError> {
    match obj.get(key) {
        None => Ok(default),
        Some(v) => match v.as_f64() {
            Some(x) if ok(x) => Ok(x as f32),
            _ => Err(invalid_value(file, &format!("{ptr}/{key}"), what, v)),
        },
    }
}

/// Keeps finite values, replacing others by `default`.
fn finite(v: f32, default: f32) -> f32 {
    if v.is_finite() { v } else { default }
}

/// Reads KHR_materials_clearcoat (the JSON object `cc` at `ptr`) into the factors and textures:
/// `clearcoatFactor`, `clearcoatRoughnessFactor` (numbers in [0, 1], 0 by default),
/// `clearcoatTexture` (red), `clearcoatRoughnessTexture` (green) and `clearcoatNormalTexture`
/// (with its `scale`: the coated surface's shading normal).
fn clearcoat(
    cc: &serde_json::Value,
    ptr: &str,
    p: &mut PbrParams,
    textures: &mut MaterialTextures,
    loader: &mut TextureLoader<'_>,
) -> Result<(), ImportError> {
    let factor = |key| number(cc, (ptr, key), loader.file, 0.0, "a number in [0, 1]", |x| (0.0..=1.0).contains(&x));
    p.clearcoat = factor("clearcoatFactor")?;
    p.clearcoat_roughness = factor("clearcoatRoughnessFactor")?;
    if let Some(t) = cc.get("clearcoatTexture") {
        textures.clearcoat = Some(loader.reference_json(t, &format!("{ptr}/clearcoatTexture"))?);
    }
    if let Some(t) = cc.get("clearcoatRoughnessTexture") {
        textures.clearcoat_roughness = Some(loader.reference_json(t, &format!("{ptr}/clearcoatRoughnessTexture"))?);
    }
    if let Some(t) = cc.get("clearcoatNormalTexture") {
        let at = format!("{ptr}/clearcoatNormalTexture");
        textures.clearcoat_normal = Some(loader.reference_json(t, &at)?);
        textures.clearcoat_normal_scale = number(t, (&at, "scale"), loader.file, 1.0, "a number", f64::is_finite)?;
    }
    Ok(())
}

/// Reads KHR_materials_sheen (the JSON object `sh` at `ptr`) into the factors and textures:
/// `sheenColorFactor` (three numbers in [0, 1], black by default), `sheenRoughnessFactor` (a
/// number in [0, 1], 0 by default), `sheenColorTexture` (RGB, sRGB) and
/// `sheenRoughnessTexture` (alpha), which multiply them.
fn sheen(
    sh: &serde_json::Value,
    ptr: &str,
    p: &mut PbrParams,
    textures: &mut MaterialTextures,
    loader: &mut TextureLoader<'_>,
) -> Result<(), ImportError> {
    if let Some(v) = sh.get("sheenColorFactor") {
        let c: Option<Vec<f64>> = v.as_array().map(|a| a.iter().filter_map(serde_json::Value::as_f64).collect());
        match c {
            Some(c)
                if c.len() == 3
                    && v.as_array().is_some_and(|a| a.len() == 3)
                    && c.iter().all(|x| (0.0..=1.0).contains(x)) =>
            {
                p.sheen_color = [c[0] as f32, c[1] as f32, c[2] as f32];
            }
            _ => {
                let at = format!("{ptr}/sheenColorFactor");
                return Err(invalid_value(loader.file, &at, "three numbers in [0, 1]", v));
            }
        }
    }
    let unit = |x: f64| (0.0..=1.0).contains(&x);
    p.sheen_roughness =
        number(sh, (ptr, "sheenRoughnessFactor"), loader.file, p.sheen_roughness, "a number in [0, 1]", unit)?;
    if let Some(t) = sh.get("sheenColorTexture") {
        textures.sheen_color = Some(loader.reference_json(t, &format!("{ptr}/sheenColorTexture"))?);
    }
    if let Some(t) = sh.get("sheenRoughnessTexture") {
        textures.sheen_roughness = Some(loader.reference_json(t, &format!("{ptr}/sheenRoughnessTexture"))?);
    }
    Ok(())
}

/// Converts glTF material `m` (`None` = the glTF default material). `taken` tells which names
/// are already used; `metres` is the length of one glTF unit in metres (`--units`).
pub(super) fn convert(
    m: Option<&gltf::Material<'_>>,
    file: &Path,
    loader: &mut TextureLoader<'_>,
    taken: &dyn Fn(&str) -> bool,
    metres: f32,
) -> Result<Converted, ImportError> {
    let Some(m) = m else {
        // glTF 2.0 section 3.9.6: base colour 1, metallic 1, roughness 1
        let p = PbrParams::default();
        return Ok(Converted {
            params: p,
            desc: MaterialDesc {
                name: unique_name("gltf-default", taken),
                material: pbr_material(&p),
                absorption: None,
                scattering: None,
                textures: MaterialTextures::default(),
                source: SourceLocation { file: file.to_owned(), line: None, item: None },
            },
            emission: None,
        });
    };
    let i = m.index().unwrap_or(0);
    let ptr = format!("/materials/{i}");
    let pbr = m.pbr_metallic_roughness();
    let bc = pbr.base_color_factor();
    let mut p = PbrParams {
        base_color: [finite(bc[0], 1.0), finite(bc[1], 1.0), finite(bc[2], 1.0)],
        metallic: finite(pbr.metallic_factor(), 1.0),
        roughness: finite(pbr.roughness_factor(), 1.0),
        transmission: 0.0,
        ior: 1.5,
        ..PbrParams::default()
    };
    if let Some(t) = m.transmission() {
        p.transmission = finite(t.transmission_factor(), 0.0);
        if t.transmission_texture().is_some() {
            loader.warnings.push(format!(
                "{}: {ptr}: transmission textures are not supported; the transmission factor is used",
                file.display()
            ));
        }
    }
    if let Some(ior) = m.ior() {
        if ior.is_finite() && ior >= 1.0 {
            p.ior = ior;
        } else {
            loader
                .warnings
                .push(format!("{}: {ptr}: KHR_materials_ior {ior} is not >= 1; 1.5 is used", file.display()));
        }
    }
    // KHR_materials_volume: the medium inside absorbs, white light turning into attenuationColor
    // over attenuationDistance (world units); thicknessFactor (for thin-walled rendering) and
    // the thickness texture do not apply to a renderer that traces the volume itself.
    // KHR_materials_specular: the dielectric specular layer is not modelled (see
    // quasar_materials::pbr), so specular factors do not change the mapped material.
    let absorption = m.volume().and_then(|v| {
        let (c, d) = (v.attenuation_color().map(|c| finite(c, 1.0).clamp(0.0, 1.0)), v.attenuation_distance() * metres);
        (d.is_finite() && d > 0.0 && c.iter().any(|&x| x < 1.0)).then(|| Absorption::Transmittance {
            transmittance: Spectrum::rgb_reflectance_interpolated(c),
            thickness: d,
        })
    });
    let mut textures = MaterialTextures::default();
    if let Some(info) = pbr.base_color_texture() {
        textures.base_color = Some(loader.reference(&info, &format!("{ptr}/pbrMetallicRoughness/baseColorTexture"))?);
    }
    if let Some(info) = pbr.metallic_roughness_texture() {
        textures.metallic_roughness =
            Some(loader.reference(&info, &format!("{ptr}/pbrMetallicRoughness/metallicRoughnessTexture"))?);
    }
    if let Some(n) = m.normal_texture() {
        let np = format!("{ptr}/normalTexture");
        let r = loader.load(&n.texture(), &np)?;
        if n.tex_coord() != 0 {
            loader.warnings.push(format!(
                "{}: {np}: uses TEXCOORD_{}; only TEXCOORD_0 is supported, it is used instead",
                file.display(),
                n.tex_coord()
            ));
        }
        textures.normal = Some(crate::texture_desc::TextureRef::new(r));
        textures.normal_scale = finite(n.scale(), 1.0);
    }
    if let Some(cc) = m.extensions().and_then(|e| e.get("KHR_materials_clearcoat")) {
        clearcoat(cc, &format!("{ptr}/extensions/KHR_materials_clearcoat"), &mut p, &mut textures, loader)?;
        if p.clearcoat >= quasar_materials::pbr::PBR_LOBE_THRESHOLD
            && p.transmission >= quasar_materials::pbr::PBR_LOBE_THRESHOLD
            && p.metallic < quasar_materials::pbr::PBR_LOBE_THRESHOLD
        {
            loader.warnings.push(format!(
                "{}: {ptr}: a clear coat over a transmissive material is not rendered (the glass is)",
                file.display()
            ));
        }
    }
    if let Some(sh) = m.extensions().and_then(|e| e.get("KHR_materials_sheen")) {
        sheen(sh, &format!("{ptr}/extensions/KHR_materials_sheen"), &mut p, &mut textures, loader)?;
        if p.sheen_color.iter().any(|&c| c > 0.0) && p.clearcoat >= quasar_materials::pbr::PBR_LOBE_THRESHOLD {
            loader
                .warnings
                .push(format!("{}: {ptr}: sheen under a clear coat is not rendered (the coat is)", file.display()));
        }
    }
    if textures.has_references() {
        textures.pbr = Some(p);
    }
    let strength = finite(m.emissive_strength().unwrap_or(1.0), 1.0).max(0.0);
    let mut e = m.emissive_factor().map(|c| finite(c, 0.0).max(0.0) * strength);
    let mut texture = None;
    if let Some(info) = m.emissive_texture() {
        // the emission follows the texture at every point; its mean colour is the light's
        // nominal colour (for its power and for what needs one colour)
        let r = loader.reference(&info, &format!("{ptr}/emissiveTexture"))?;
        texture = Some(EmissiveTexture { texture: r, factor: e });
        let mean = loader.textures[r.texture].mean(true);
        for (e, m) in e.iter_mut().zip(mean) {
            *e *= m;
        }
    }
    let emission = if e.iter().any(|&c| c > 0.0) && e.iter().all(|c| c.is_finite()) {
        let spectrum = Spectrum::rgb_illuminant(e).unwrap_or(Spectrum::Constant(0.0));
        Some(EmissionDesc { spectrum, scale: photometric_scale(1.0), two_sided: m.double_sided(), texture })
    } else {
        None
    };
    let base = m.name().map_or_else(|| format!("material{i}"), str::to_owned);
    Ok(Converted {
        params: p,
        desc: MaterialDesc {
            name: unique_name(&base, taken),
            material: pbr_material(&p),
            absorption,
            scattering: None,
            textures,
            source: SourceLocation { file: file.to_owned(), line: None, item: Some(ptr) },
        },
        emission,
    })
}
