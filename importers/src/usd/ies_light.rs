//! UsdLux `ShapingAPI` `shaping:ies:file`: a light with an IES profile becomes a point luminaire
//! at the light's origin (docs/usd.md), its nadir along the light's -Z (the way UsdLux lights
//! emit), C0 along its +X, tinted by the light's colour or colour temperature.
//!
//! - `shaping:ies:normalize` false (the schema default): the file's candela times 2^`exposure`
//!   are the luminous intensity in cd, as for a TOML luminaire; `intensity` is not used (a note
//!   says so).
//! - The light's shape is the luminaire's luminous opening (near field, docs/photometry.md): a
//!   `RectLight`'s `width` x `height` (along C0 = its +X and C90 = its +Y), a `DiskLight`'s
//!   disk, scaled by the light's transform; other lights are a point.
//! - `shaping:ies:normalize` true: the profile is rescaled so that the luminaire emits the flux of
//!   the light without the profile (UsdLux: "preserving the overall energy output"): pi L A for
//!   an area light of luminance L and area A, 4 pi I for a point light.
//!
//! `shaping:ies:angleScale` other than 0 is not applied (note). Distant and dome lights keep no
//! profile (note).

use std::sync::Arc;

use glam::{Affine3A, Mat3, Vec3};
use openusd::usd::Prim;

use super::light::UsdLight;
use super::value::{self, AttrError};
use crate::photometric::photometric_scale;
use crate::photometry::read_photometric_file;
use crate::scene_desc::{LightDesc, LuminousOpening};

/// The light `light` read from `prim` (of type `ty`) with its IES profile applied, when `prim`
/// has one.
pub(super) fn with_ies_profile(
    prim: &Prim,
    ty: &str,
    light: UsdLight,
    world: &Affine3A,
    stage_file: &std::path::Path,
    notes: &mut Vec<String>,
) -> Result<UsdLight, AttrError> {
    let file = match value::raw(prim, "inputs:shaping:ies:file")? {
        Some(v) => Some(v),
        None => value::raw(prim, "shaping:ies:file")?,
    };
    let Some(openusd::sdf::Value::AssetPath(asset)) = file else { return Ok(light) };
    let path = value::asset_file(&asset, stage_file);
    let attr = "inputs:shaping:ies:file".to_string();
    let (web, _) = read_photometric_file(&path).map_err(|e| (attr.clone(), e.to_string()))?;
    let web_flux = web.flux();
    if !(web_flux.is_finite() && web_flux > 0.0) {
        return Err((attr, format!("{}: the profile emits no light", path.display())));
    }
    let flag = |n: &str| -> Result<Option<bool>, AttrError> {
        Ok(value::boolean(prim, &format!("inputs:{n}"))?.or(value::boolean(prim, n)?))
    };
    let normalize = flag("shaping:ies:normalize")?.unwrap_or(false);
    let angle_scale = value::scalar(prim, "inputs:shaping:ies:angleScale")?.unwrap_or(0.0);
    if angle_scale != 0.0 {
        notes.push(format!("shaping:ies:angleScale {angle_scale} is not applied"));
    }
    // the unshaped light's flux in the units of its scale (x pi: Lambertian area emission)
    let (unshaped_flux, spectrum) = match &light {
        UsdLight::Mesh(m) => match &m.emission {
            Some(e) => (std::f64::consts::PI * f64::from(e.scale) * m.area(), e.spectrum.clone()),
            None => return Ok(light),
        },
        UsdLight::Light(LightDesc::Point { scale, spectrum, .. } | LightDesc::Spot { scale, spectrum, .. }) => {
            (4.0 * std::f64::consts::PI * f64::from(*scale), spectrum.clone())
        }
        UsdLight::Light(_) | UsdLight::Skipped(_) => {
            notes.push("an IES profile on a distant or dome light is not applied".into());
            return Ok(light);
        }
    };
    let scale = if normalize {
        (unshaped_flux / web_flux) as f32
    } else {
        let exposure = value::scalar(prim, "inputs:exposure")?.or(value::scalar(prim, "exposure")?).unwrap_or(0.0);
        notes.push("the IES profile gives the intensity in cd: `intensity` is not used".into());
        photometric_scale(2f64.powf(exposure) as f32)
    };
    let m = world.matrix3;
    let dim = |n: &str, default: f64| -> Result<f32, AttrError> {
        let v = value::scalar(prim, &format!("inputs:{n}"))?.or(value::scalar(prim, n)?).unwrap_or(default);
        Ok(if v.is_finite() && v > 0.0 { v as f32 } else { 0.0 })
    };
    let (sx, sy) = (Vec3::from(m.x_axis).length(), Vec3::from(m.y_axis).length());
    let opening = match (ty, &light) {
        ("RectLight", UsdLight::Mesh(_)) => {
            let (w, h) = (dim("width", 1.0)? * sx, dim("height", 1.0)? * sy);
            if w > 0.0 && h > 0.0 { LuminousOpening::Rect { c0: w, c90: h } } else { LuminousOpening::Point }
        }
        ("DiskLight", UsdLight::Mesh(_)) => {
            let d = 2.0 * dim("radius", 0.5)? * (sx * sy).sqrt();
            if d > 0.0 { LuminousOpening::Disk { diameter: d } } else { LuminousOpening::Point }
        }
        _ => LuminousOpening::Point,
    };
    let up = Vec3::from(m.z_axis).normalize_or(Vec3::Z);
    let c0 = Vec3::from(m.x_axis);
    let c0 = (c0 - c0.dot(up) * up).normalize_or(up.any_orthonormal_vector());
    Ok(UsdLight::Light(LightDesc::Luminaire {
        position: world.transform_point3(Vec3::ZERO),
        frame: Mat3::from_cols(c0, up.cross(c0), up),
        web: Arc::new(web),
        spectrum,
        scale,
        opening,
    }))
}
