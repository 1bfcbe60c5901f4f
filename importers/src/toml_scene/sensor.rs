//! `[[sensor]]`: virtual illuminance meters (docs/photometry.md).
//!
//! | key | meaning | default |
//! |---|---|---|
//! | `name` | name of the sensor (its CSV is `<image stem>.<name>.csv`) | required |
//! | `type` | `"grid"` or `"point"` | required |
//! | `position` | a point meter's position; a grid's centre | required |
//! | `size` | a grid's side lengths [w, h] | required for grids |
//! | `resolution` | meters along each side [nx, ny] (cell centres) | required for grids |
//! | `normal` | the meters' normal: [0, 1, 0] horizontal illuminance, a horizontal vector vertical illuminance | [0, 1, 0] |
//! | `u_axis` | a grid's first side (projected onto its plane) | +X, or +Z for a normal along X |
//! | `samples` | samples per meter | 1024 |
//! | `quantity` | `"planar"` (on the plane of `normal`), `"cylindrical"` (mean vertical illuminance over all horizontal directions) or `"semi-cylindrical"` (mean illuminance on a vertical half-cylinder facing `facing`); for the last two `normal` is the grid's plane only | `"planar"` |
//! | `facing` | the direction a semi-cylindrical meter faces (projected onto the horizontal plane; typically towards the observer's approach) | required for `"semi-cylindrical"` only |

use glam::Vec3;

use crate::error::ImportError;
use crate::sensor_desc::{SensorDesc, SensorLayout, SensorQuantity};
use crate::toml_reader::Tbl;

/// Most meters of one grid.
pub const MAX_SENSOR_POINTS: u64 = 1 << 20;

/// Reads one `[[sensor]]` table; lengths in scene units converted with `unit`.
pub(super) fn sensor(t: &Tbl<'_>, unit: f32) -> Result<SensorDesc, ImportError> {
    let doc = t.doc;
    t.check_keys(&[
        "name",
        "type",
        "position",
        "size",
        "resolution",
        "normal",
        "u_axis",
        "samples",
        "quantity",
        "facing",
    ])?;
    let name = match t.get("name") {
        Some(v) => crate::toml_reader::string(doc, v, &t.key_path("name"))?.to_owned(),
        None => return Err(t.missing("name")),
    };
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        return Err(
            doc.invalid(&t.key_span("name"), format!("`{}`: a sensor name is letters, digits, _ and -", t.path))
        );
    }
    let Some((ty, _)) = t.choice("type", &["grid", "point"])? else { return Err(t.missing("type")) };
    let position = t.opt_point("position", unit)?.ok_or_else(|| t.missing("position"))?;
    let normal = t.opt_dir("normal")?.unwrap_or(Vec3::Y).normalize();
    let samples = t.opt_int("samples", 1, 1 << 24)?.unwrap_or(1024) as u32;
    let quantity = match t.choice("quantity", &["planar", "cylindrical", "semi-cylindrical"])? {
        Some(("cylindrical", _)) => SensorQuantity::Cylindrical,
        Some(("semi-cylindrical", _)) => {
            let f = t.opt_dir("facing")?.ok_or_else(|| t.missing("facing"))?;
            let facing = Vec3::new(f.x, 0.0, f.z).normalize_or_zero();
            if facing == Vec3::ZERO {
                return Err(doc.invalid(
                    &t.key_span("facing"),
                    format!(
                        "`{}`: `facing` is vertical: a semi-cylindrical meter faces a horizontal direction",
                        t.path
                    ),
                ));
            }
            SensorQuantity::SemiCylindrical { facing }
        }
        _ => SensorQuantity::Planar,
    };
    if t.has("facing") && !matches!(quantity, SensorQuantity::SemiCylindrical { .. }) {
        return Err(doc
            .invalid(&t.key_span("facing"), format!("`{}`: `facing` is for quantity = \"semi-cylindrical\"", t.path)));
    }
    let layout = if ty == "point" {
        for k in ["size", "resolution", "u_axis"] {
            if t.has(k) {
                return Err(doc.invalid(&t.key_span(k), format!("`{}`: `{k}` is for grid sensors", t.path)));
            }
        }
        SensorLayout::Point { position }
    } else {
        let size = crate::toml_reader::floats::<2>(doc, t.req("size")?, &t.key_path("size"))?;
        if !size.iter().all(|s| s.is_finite() && *s > 0.0) {
            return Err(doc.invalid(&t.key_span("size"), format!("`{}`: sizes must be > 0", t.path)));
        }
        let res = crate::toml_reader::floats::<2>(doc, t.req("resolution")?, &t.key_path("resolution"))?;
        let ok =
            res.iter().all(|r| r.fract() == 0.0 && *r >= 1.0) && (res[0] as u64) * (res[1] as u64) <= MAX_SENSOR_POINTS;
        if !ok {
            return Err(doc.invalid(
                &t.key_span("resolution"),
                format!(
                    "`{}`: resolution must be two whole numbers >= 1 with at most {MAX_SENSOR_POINTS} meters",
                    t.path
                ),
            ));
        }
        let default_u = if normal.x.abs() > 0.9 { Vec3::Z } else { Vec3::X };
        let u = t.opt_dir("u_axis")?.unwrap_or(default_u);
        let u_axis = (u - u.dot(normal) * normal).normalize_or_zero();
        if u_axis == Vec3::ZERO {
            return Err(doc.invalid(&t.key_span("u_axis"), format!("`{}`: u_axis is parallel to the normal", t.path)));
        }
        SensorLayout::Grid {
            center: position,
            u_axis,
            size: size.map(|s| s * unit),
            resolution: [res[0] as u32, res[1] as u32],
        }
    };
    Ok(SensorDesc { name, layout, normal, samples, quantity })
}
