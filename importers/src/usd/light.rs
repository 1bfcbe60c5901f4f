//! UsdLux -> quasar lights. Every light's luminance is L_v = `intensity` x 2^`exposure` in nits
//! (cd/m², UsdLux's unit; `DistantLight`: illuminance in lux), times `color` (linear sRGB, a
//! light colour whose luminance scales it), or a blackbody of `colorTemperature` kelvin when
//! `enableColorTemperature` is set; photometric values become radiometric scales as in glTF
//! ([`crate::photometric`]). Schema defaults (checked against Pixar's usd-core 26.11, which the
//! `openusd` crate does not supply): `intensity` 1 (`DistantLight` 50000), `exposure` 0, `color`
//! white, `normalize` false, `radius` 0.5, `width`/`height`/`length` 1, `angle` 0.53,
//! `shaping:cone:angle` 90, `shaping:cone:softness` 0.
//!
//! | UsdLux | quasar |
//! |---|---|
//! | `RectLight` (width along X, height along Y, emits towards -Z) | one-sided emissive quad |
//! | `DiskLight` (radius, emits towards -Z) | one-sided emissive disk (64 segments, true area) |
//! | `SphereLight` | emissive icosphere (1280 triangles, true area), outward; `treatAsPoint`: point light of intensity L_v π r² (the sphere's far field); with `ShapingAPI` cone: spot light (cone angle, falloff from angle x (1 - softness)) |
//! | `CylinderLight` (length along X, radius) | emissive cylinder side (64 segments), outward |
//! | `DistantLight` (towards -Z) | directional light of illuminance L_v lux (`angle` ignored: a delta light; warned above 2°) |
//! | `DomeLight` | constant environment of luminance L_v, or its lat-long `texture:file` (`.exr`, `.hdr`) times L_v in UsdLux's OpenEXR orientation ([`dome`]) |
//! | `DomeLight_1` | the same, its pole first aligned by `poleAxis` (`scene`: the stage's up axis; `Y`; `Z`: the dome turned 90 degrees about +X) |
//!
//! `normalize = true` divides an area light's luminance by its world-space area (the power no
//! longer depends on the size). `ShapingAPI` `shaping:ies:file` makes any of them but distant
//! and dome lights a luminaire (`ies_light.rs`, applied by the caller). A mesh with `MeshLightAPI`
//! emits from its front faces ([`mesh_light`]). `GeometryLight` and `PortalLight` are not supported (warning).

use glam::{Affine3A, Vec3};
use openusd::usd::Prim;
use quasar_materials::spectrum::Spectrum;

use super::value::{self, AttrError};
use crate::photometric::photometric_scale;
use crate::scene_desc::{EmissionDesc, LightDesc, MeshDesc};
use crate::tessellation::{self, Tessellation};
use crate::transform::transform_mesh;

/// What a UsdLux prim becomes.
pub(super) enum UsdLight {
    /// A light without a surface.
    Light(LightDesc),
    /// An emissive mesh (world space; the caller gives it the black light material), boxed: a
    /// mesh description is several times larger than the other variants.
    Mesh(Box<MeshDesc>),
    /// Not rendered, with the reason.
    Skipped(String),
}

/// The UsdLux light types this module reads or names as unsupported.
pub(super) const LIGHT_TYPES: [&str; 9] = [
    "RectLight",
    "DiskLight",
    "SphereLight",
    "CylinderLight",
    "DistantLight",
    "DomeLight",
    "DomeLight_1",
    "GeometryLight",
    "PortalLight",
];

/// A light input: `inputs:<name>` (UsdLux since 21.02), else the older bare `<name>`.
fn input(prim: &Prim, name: &str) -> Result<Option<f64>, AttrError> {
    match value::scalar(prim, &format!("inputs:{name}"))? {
        Some(v) => Ok(Some(v)),
        None => value::scalar(prim, name),
    }
}

fn input_bool(prim: &Prim, name: &str) -> Result<Option<bool>, AttrError> {
    match value::boolean(prim, &format!("inputs:{name}"))? {
        Some(v) => Ok(Some(v)),
        None => value::boolean(prim, name),
    }
}

/// Luminance (nits, or lux for a distant light) and spectral shape of `prim`.
fn emission(prim: &Prim, default_intensity: f64) -> Result<(f64, Spectrum, Vec<String>), AttrError> {
    let intensity = input(prim, "intensity")?.unwrap_or(default_intensity);
    let exposure = input(prim, "exposure")?.unwrap_or(0.0);
    let color = match value::vec3(prim, "inputs:color")? {
        Some(c) => Some(c),
        None => value::vec3(prim, "color")?,
    }
    .unwrap_or(Vec3::ONE);
    let lv = intensity * 2f64.powf(exposure);
    if !(lv.is_finite() && lv >= 0.0 && color.is_finite() && color.min_element() >= 0.0) {
        return Err((
            "inputs:intensity".into(),
            format!("intensity {intensity} x 2^{exposure} with colour {color} is not a light"),
        ));
    }
    let mut notes = Vec::new();
    let spectrum = if input_bool(prim, "enableColorTemperature")?.unwrap_or(false) {
        let k = input(prim, "colorTemperature")?.unwrap_or(6500.0) as f32;
        let luminance = 0.2126 * color.x + 0.7152 * color.y + 0.0722 * color.z;
        if (color - Vec3::ONE).abs().max_element() > 1e-6 {
            notes.push("the colour multiplies the colour temperature's blackbody by its luminance only".to_string());
        }
        let bb = Spectrum::blackbody(k).map_err(|e| ("inputs:colorTemperature".into(), e.to_string()))?;
        return Ok((lv * f64::from(luminance), bb, notes));
    } else {
        Spectrum::rgb_illuminant(color.to_array()).map_err(|e| ("inputs:color".into(), e.to_string()))?
    };
    Ok((lv, spectrum, notes))
}

/// The emission of the mesh `m` (in world space) of a prim with `MeshLightAPI`: the light's
/// luminance (`intensity` x 2^`exposure` nits of `color`, or of its colour temperature) from the
/// mesh's front faces, divided by the mesh's world area with `normalize`; None without the API.
pub(super) fn mesh_light(prim: &Prim, m: &MeshDesc) -> Result<Option<EmissionDesc>, AttrError> {
    if !prim.has_api_schema("MeshLightAPI").unwrap_or(false) {
        return Ok(None);
    }
    let (lv, spectrum, _) = emission(prim, 1.0)?;
    let mut scale = f64::from(photometric_scale(lv as f32));
    if input_bool(prim, "normalize")?.unwrap_or(false) && m.area() > 0.0 {
        scale /= m.area();
    }
    Ok(Some(EmissionDesc { spectrum, scale: scale as f32, two_sided: false, texture: None }))
}

/// The shape `t` in the light's local space, emitting `scale x spectrum` from its front.
fn local_mesh(name: &str, t: Tessellation, spectrum: Spectrum, scale: f32) -> MeshDesc {
    MeshDesc {
        name: name.to_string(),
        positions: t.positions,
        normals: t.normals,
        uvs: None,
        colors: None,
        indices: t.indices,
        material: 0,
        emission: Some(EmissionDesc { spectrum, scale, two_sided: false, texture: None }),
        source: Default::default(),
    }
}

/// A `DomeLight`: a constant environment, or the lat-long `texture:file` (`.exr` / `.hdr`) in
/// the OpenEXR orientation UsdLux specifies (longitude 0 at the image centre looks along the
/// dome's +Z, longitude pi/2 along +X, +Y the pole: quasar's map turned 180 degrees about +Y)
/// turned with the dome's rotation (a tilted pole included). The map's texels times the light's
/// luminance are the radiance; a non-white `color` scales it by its luminance.
fn dome(
    prim: &Prim,
    world: &Affine3A,
    spectrum: Spectrum,
    scale: f32,
    stage_file: &std::path::Path,
    notes: &mut Vec<String>,
) -> Result<UsdLight, AttrError> {
    let file = match value::raw(prim, "inputs:texture:file")? {
        Some(v) => Some(v),
        None => value::raw(prim, "texture:file")?,
    };
    let Some(openusd::sdf::Value::AssetPath(asset)) = file else {
        return Ok(UsdLight::Light(LightDesc::Environment { spectrum, scale, map: None }));
    };
    let path = value::asset_file(&asset, stage_file);
    let format = value::token(prim, "inputs:texture:format")?.unwrap_or_else(|| "automatic".into());
    if !matches!(format.as_str(), "automatic" | "latlong") {
        notes.push(format!("texture:format `{format}` is read as latlong"));
    }
    let mut map =
        crate::env_map::load_env_map(&path).map_err(|e| ("inputs:texture:file".to_string(), e.to_string()))?;
    // the dome's turn (its transform without scale or shear: the pole along its +Y, the image
    // centre along its +Z), after UsdLux's orientation: quasar's map turned 180 degrees about +Y
    let pole = world.transform_vector3(Vec3::Y).normalize_or(Vec3::Y);
    let z = world.transform_vector3(Vec3::Z);
    let z = (z - z.dot(pole) * pole).normalize_or(pole.any_orthonormal_vector());
    map.frame = glam::Mat3::from_cols(pole.cross(z), pole, z) * glam::Mat3::from_rotation_y(std::f32::consts::PI);
    let color = match value::vec3(prim, "inputs:color")? {
        Some(c) => Some(c),
        None => value::vec3(prim, "color")?,
    }
    .unwrap_or(Vec3::ONE);
    if (color - Vec3::ONE).abs().max_element() > 1e-6 {
        notes.push("the colour of a textured dome scales it by its luminance only".into());
    }
    let tint = 0.2126 * color.x + 0.7152 * color.y + 0.0722 * color.z;
    Ok(UsdLight::Light(LightDesc::Environment { spectrum, scale: scale * tint, map: Some(std::sync::Arc::new(map)) }))
}

/// The light of the UsdLux prim `prim` of type `ty` with local-to-world transform `world`
/// (`stage_file` anchors unresolved texture paths; `z_up`: the stage's up axis is Z, for
/// `DomeLight_1`'s `poleAxis = "scene"`), and notes for warnings.
pub(super) fn read_light(
    prim: &Prim,
    ty: &str,
    world: &Affine3A,
    stage_file: &std::path::Path,
    z_up: bool,
) -> Result<(UsdLight, Vec<String>), AttrError> {
    let name = prim.path().as_str().to_string();
    let size = |n: &str, default: f64| -> Result<f32, AttrError> {
        let v = input(prim, n)?.unwrap_or(default);
        if v.is_finite() && v >= 0.0 {
            Ok(v as f32)
        } else {
            Err((format!("inputs:{n}"), format!("{v} is not a size")))
        }
    };
    let default_intensity = if ty == "DistantLight" { 50000.0 } else { 1.0 };
    if matches!(ty, "GeometryLight" | "PortalLight") {
        return Ok((UsdLight::Skipped(format!("{ty} is not supported")), Vec::new()));
    }
    let (lv, spectrum, mut notes) = emission(prim, default_intensity)?;
    let normalize = input_bool(prim, "normalize")?.unwrap_or(false);
    let origin = world.transform_point3(Vec3::ZERO);
    let down = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let scale = photometric_scale(lv as f32);
    let area_light = |t: Tessellation| {
        let mut m = local_mesh(&name, t, spectrum.clone(), scale);
        transform_mesh(&mut m, world);
        if normalize {
            let a = m.area();
            if let Some(e) = &mut m.emission
                && a > 0.0
            {
                e.scale = (f64::from(e.scale) / a) as f32;
            }
        }
        UsdLight::Mesh(Box::new(m))
    };
    let light = match ty {
        "RectLight" => {
            let (w, h) = (0.5 * size("width", 1.0)?, 0.5 * size("height", 1.0)?);
            area_light(tessellation::quad(
                Vec3::new(-w, -h, 0.0),
                Vec3::new(0.0, 2.0 * h, 0.0),
                Vec3::new(2.0 * w, 0.0, 0.0),
            ))
        }
        "DiskLight" => area_light(tessellation::disk(Vec3::ZERO, size("radius", 0.5)?, Vec3::NEG_Z, 64)),
        "CylinderLight" => {
            if value::boolean(prim, "treatAsLine")?.unwrap_or(false) {
                notes.push("treatAsLine is ignored: the cylinder is rendered".into());
            }
            area_light(tessellation::cylinder_side(size("radius", 0.5)?, size("length", 1.0)?, 64).along(0))
        }
        "SphereLight" => {
            let r = size("radius", 0.5)?;
            if value::boolean(prim, "treatAsPoint")?.unwrap_or(false) {
                // the sphere's radius in world units: the mean of the transform's axis scales
                let s = (world.matrix3.x_axis.length() + world.matrix3.y_axis.length() + world.matrix3.z_axis.length())
                    / 3.0;
                let rw = r * s;
                let intensity = if rw > 0.0 { scale * std::f32::consts::PI * rw * rw } else { scale };
                let cone =
                    value::scalar(prim, "inputs:shaping:cone:angle")?.or(value::scalar(prim, "shaping:cone:angle")?);
                match cone {
                    Some(angle) if angle < 90.0 => {
                        let soft = value::scalar(prim, "inputs:shaping:cone:softness")?.unwrap_or(0.0).clamp(0.0, 1.0);
                        let cone_deg = angle.clamp(0.0, 90.0) as f32;
                        UsdLight::Light(LightDesc::Spot {
                            position: origin,
                            direction: down,
                            cone_deg,
                            falloff_start_deg: cone_deg * (1.0 - soft as f32),
                            spectrum,
                            scale: intensity,
                        })
                    }
                    _ => UsdLight::Light(LightDesc::Point { position: origin, spectrum, scale: intensity }),
                }
            } else {
                area_light(tessellation::sphere(Vec3::ZERO, r, 3))
            }
        }
        "DistantLight" => {
            let angle = input(prim, "angle")?.unwrap_or(0.53);
            if angle > 2.0 {
                notes.push(format!("angle {angle}° is ignored: the light is a delta (directional) light"));
            }
            UsdLight::Light(LightDesc::Directional { direction: down, spectrum, scale })
        }
        "DomeLight" => dome(prim, world, spectrum, scale, stage_file, &mut notes)?,
        "DomeLight_1" => {
            // the pole's starting alignment: Z turns the dome itself (not its children) by 90
            // degrees about +X, so that latitude +pi/2 is +Z and latitude 0, longitude 0 is -Y
            let pole_z = match value::token(prim, "poleAxis")?.as_deref().unwrap_or("scene") {
                "Y" => false,
                "Z" => true,
                "scene" => z_up,
                other => return Err(("poleAxis".into(), format!("`{other}` is not scene, Y or Z"))),
            };
            let turn = if pole_z { Affine3A::from_rotation_x(std::f32::consts::FRAC_PI_2) } else { Affine3A::IDENTITY };
            dome(prim, &(*world * turn), spectrum, scale, stage_file, &mut notes)?
        }
        other => UsdLight::Skipped(format!("{other} is not a light type quasar reads")),
    };
    Ok((light, notes))
}
