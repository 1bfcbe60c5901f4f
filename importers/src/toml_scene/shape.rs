//! The `transform` and `emission` tables shared by shapes and includes, and the shapes' size
//! limits (the tessellation itself is [`crate::tessellation`]).

use glam::{Affine3A, Mat3, Vec3};
use toml::de::DeValue;

use super::spectrum::{SpectrumUse, spectrum};
use crate::error::{ImportError, ImportErrorKind};
use crate::scene_desc::EmissionDesc;
use crate::toml_reader::{Tbl, float, floats};
use crate::transform::trs;

/// Default icosphere subdivision level of `type = "sphere"` (20 * 4^4 = 5120 triangles).
pub const DEFAULT_SPHERE_SUBDIVISIONS: u32 = 4;
/// Largest sphere subdivision level (20 * 4^8 = 1,310,720 triangles).
pub const MAX_SPHERE_SUBDIVISIONS: u32 = 8;
/// Default number of rim segments of `type = "disk"`.
pub const DEFAULT_DISK_SEGMENTS: u32 = 128;
/// Largest number of rim segments of a disk.
pub const MAX_DISK_SEGMENTS: u32 = 1 << 20;

/// Reads a `transform` table: `scale` (number or [x, y, z], non-zero), then `rotate_deg = [x, y, z]`
/// (about X, then Y, then Z) or `rotate = { axis = [x, y, z], angle_deg = a }`, then `translate`
/// (a length, converted with `unit`).
pub(crate) fn transform(t: &Tbl<'_>, unit: f32) -> Result<Affine3A, ImportError> {
    let doc = t.doc;
    t.check_keys(&["translate", "rotate_deg", "rotate", "scale"])?;
    t.exclusive(&["rotate_deg", "rotate"])?;
    let translate = t.opt_point("translate", unit)?.unwrap_or(Vec3::ZERO);
    let scale = match t.get("scale") {
        None => Vec3::ONE,
        Some(v) => {
            let what = t.key_path("scale");
            let s = match v.get_ref() {
                DeValue::Array(_) => Vec3::from(floats::<3>(doc, v, &what)?),
                _ => Vec3::splat(float(doc, v, &what)?),
            };
            if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
                return Err(doc.invalid(&v.span(), format!("`{what}` must be non-zero, got {s}")));
            }
            s
        }
    };
    let mut m = trs(translate, t.opt_vec3("rotate_deg")?.unwrap_or(Vec3::ZERO), scale);
    if let Some(r) = t.opt_table("rotate")? {
        r.check_keys(&["axis", "angle_deg"])?;
        let axis = r.opt_dir("axis")?.ok_or_else(|| r.missing("axis"))?;
        let angle = r.opt_f32("angle_deg")?.ok_or_else(|| r.missing("angle_deg"))?;
        let rot = Mat3::from_axis_angle(axis.normalize(), angle.to_radians());
        m = Affine3A::from_mat3_translation(rot * Mat3::from_diagonal(scale), translate);
    }
    let lin = Mat3::from(m.matrix3);
    if !lin.is_finite() || !lin.determinant().is_finite() || lin.determinant() == 0.0 {
        return Err(doc.invalid(&t.span, format!("`{}` is degenerate or overflows", t.path)));
    }
    Ok(m)
}

/// Reads an `emission = { spectrum, scale, two_sided }` table.
pub(crate) fn emission(t: &Tbl<'_>) -> Result<EmissionDesc, ImportError> {
    t.check_keys(&["spectrum", "scale", "two_sided"])?;
    let s = spectrum(t.doc, t.req("spectrum")?, &t.key_path("spectrum"), SpectrumUse::Emission)?;
    let scale = t.opt_f32_where("scale", "finite and >= 0", |s| s >= 0.0)?.unwrap_or(1.0);
    Ok(EmissionDesc { spectrum: s, scale, two_sided: t.opt_bool("two_sided")?.unwrap_or(false), texture: None })
}

/// Checks a size-like value: finite and > 0 (after unit conversion).
pub(crate) fn positive_length(t: &Tbl<'_>, key: &str, unit: f32) -> Result<f32, ImportError> {
    let v = t.req(key)?;
    let x = float(t.doc, v, &t.key_path(key))?;
    let m = x * unit;
    if x <= 0.0 || !m.is_finite() {
        return Err(t.doc.error(
            ImportErrorKind::InvalidValue,
            &v.span(),
            format!("`{}` must be > 0 and finite in metres, got {x}", t.key_path(key)),
        ));
    }
    Ok(m)
}
