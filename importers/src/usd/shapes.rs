//! UsdGeom implicit shapes -> triangle meshes in the prim's local space, with the schema
//! defaults (usd-core 26.11; the `openusd` crate supplies none):
//!
//! | prim | attributes (default) | quasar |
//! |---|---|---|
//! | `Cube` | `size` (2) | a box of edge `size` centred at the origin, flat faces |
//! | `Sphere` | `radius` (1) | an icosphere of 5120 triangles, smooth normals, true area |
//! | `Cylinder` | `radius` (1), `height` (2), `axis` (Z) | closed: side with smooth normals and two flat caps |
//! | `Cone` | `radius` (1), `height` (2), `axis` (Z) | apex at +height/2 along `axis`, closed by its base |
//! | `Capsule` | `radius` (0.5), `height` (1, the cylinder part), `axis` (Z) | cylinder with hemispherical ends |
//! | `Cylinder_1` | `radiusBottom` (1), `radiusTop` (1), `height` (2), `axis` (Z) | closed truncated cone: `radiusBottom` at -height/2, `radiusTop` at +height/2 along `axis` |
//! | `Capsule_1` | `radiusBottom` (0.5), `radiusTop` (0.5), `height` (1), `axis` (Z) | the truncated cone of `Cylinder_1` closed by the spherical caps tangent to it at each end (Pixar's extent; hemispheres when the radii are equal) |
//! | `Plane` | `width` (2), `length` (2), `axis` (Z, the normal) | a quad facing +`axis`; width along X (axis Y, Z) or Z (axis X), length along Y (axis X, Z) or Z (axis Y) |
//!
//! Round shapes use 64 segments around and keep their true area ([`crate::tessellation`]).

use glam::Vec3;
use openusd::usd::Prim;

use super::value::{self, AttrError};
use crate::scene_desc::MeshDesc;
use crate::tessellation::{self, Tessellation};

/// The implicit shape prim types this module reads.
pub(super) const SHAPE_TYPES: [&str; 8] =
    ["Cube", "Sphere", "Cylinder", "Cone", "Capsule", "Plane", "Cylinder_1", "Capsule_1"];

/// Segments around a round shape.
const SEGMENTS: u32 = 64;

/// A positive finite length attribute, or its schema default.
fn length(prim: &Prim, name: &str, default: f64) -> Result<f32, AttrError> {
    let v = value::scalar(prim, name)?.unwrap_or(default);
    if v.is_finite() && v > 0.0 && v < f64::from(f32::MAX) {
        Ok(v as f32)
    } else {
        Err((name.to_string(), format!("{v} is not a positive length")))
    }
}

/// The `axis` token as 0 (X), 1 (Y) or 2 (Z, the default).
fn axis(prim: &Prim) -> Result<usize, AttrError> {
    match value::token(prim, "axis")?.as_deref() {
        None | Some("Z") => Ok(2),
        Some("X") => Ok(0),
        Some("Y") => Ok(1),
        Some(other) => Err(("axis".into(), format!("`{other}` is not X, Y or Z"))),
    }
}

/// The implicit shape `prim` of type `ty` (one of [`SHAPE_TYPES`]) as a mesh named `name` in
/// its local space (material 0, no emission: the caller binds them).
pub(super) fn read_shape(prim: &Prim, ty: &str, name: String) -> Result<MeshDesc, AttrError> {
    let t: Tessellation = match ty {
        "Cube" => tessellation::cuboid(Vec3::splat(length(prim, "size", 2.0)?)),
        "Sphere" => tessellation::sphere(Vec3::ZERO, length(prim, "radius", 1.0)?, 4),
        "Cylinder" => tessellation::cylinder(length(prim, "radius", 1.0)?, length(prim, "height", 2.0)?, SEGMENTS)
            .along(axis(prim)?),
        "Cone" => {
            tessellation::cone(length(prim, "radius", 1.0)?, length(prim, "height", 2.0)?, SEGMENTS).along(axis(prim)?)
        }
        "Capsule" => tessellation::capsule(length(prim, "radius", 0.5)?, length(prim, "height", 1.0)?, SEGMENTS, 16)
            .along(axis(prim)?),
        "Cylinder_1" => tessellation::frustum(
            length(prim, "radiusBottom", 1.0)?,
            length(prim, "radiusTop", 1.0)?,
            length(prim, "height", 2.0)?,
            SEGMENTS,
        )
        .along(axis(prim)?),
        "Capsule_1" => tessellation::capsule_tapered(
            length(prim, "radiusBottom", 0.5)?,
            length(prim, "radiusTop", 0.5)?,
            length(prim, "height", 1.0)?,
            SEGMENTS,
            16,
        )
        .along(axis(prim)?),
        _ => {
            let (w, l) = (length(prim, "width", 2.0)?, length(prim, "length", 2.0)?);
            // (width direction, length direction) per normal axis, as Pixar's extents give them
            let (wd, ld, n) = match axis(prim)? {
                0 => (Vec3::Z, Vec3::Y, Vec3::X),
                1 => (Vec3::X, Vec3::Z, Vec3::Y),
                _ => (Vec3::X, Vec3::Y, Vec3::Z),
            };
            let (e1, e2) = if wd.cross(ld).dot(n) > 0.0 { (wd * w, ld * l) } else { (ld * l, wd * w) };
            tessellation::quad(-0.5 * (e1 + e2), e1, e2)
        }
    };
    Ok(MeshDesc {
        name,
        positions: t.positions,
        normals: t.normals,
        uvs: None,
        colors: None,
        indices: t.indices,
        material: 0,
        emission: None,
        source: Default::default(),
    })
}
