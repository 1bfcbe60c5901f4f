//! UsdGeom `Camera` -> a quasar camera: horizontal field of view 2 atan(`horizontalAperture` /
//! 2 `focalLength`), image aspect `horizontalAperture` / `verticalAperture`, looking along the
//! prim's -Z with +Y up. Schema defaults (usd-core 26.11): `focalLength` 50, apertures 20.955 x
//! 15.2908 (mm, the 35 mm Academy gate). `projection = "orthographic"` is rendered as perspective
//! (a note for a warning).

use glam::{Affine3A, Vec3};
use openusd::usd::Prim;

use super::value::{self, AttrError};
use crate::scene_desc::{CameraDesc, FovAxis, NamedCamera};

/// The camera `prim` (named by its path `at`) with local-to-world transform `world` (quasar's
/// frame), and a note when its projection is not rendered as authored.
pub(super) fn read_camera(prim: &Prim, at: &str, world: &Affine3A) -> Result<(NamedCamera, Option<String>), AttrError> {
    let focal = value::scalar(prim, "focalLength")?.unwrap_or(50.0);
    let h_ap = value::scalar(prim, "horizontalAperture")?.unwrap_or(20.955);
    let v_ap = value::scalar(prim, "verticalAperture")?.unwrap_or(15.2908);
    let note = (value::token(prim, "projection").ok().flatten().as_deref() == Some("orthographic"))
        .then(|| format!("{at}: orthographic projection is rendered as perspective"));
    if !(focal > 0.0 && h_ap > 0.0 && v_ap > 0.0 && (h_ap / v_ap).is_finite() && (h_ap / focal).is_finite()) {
        return Err((
            "focalLength".into(),
            format!("focalLength {focal} and apertures {h_ap} x {v_ap} must be positive"),
        ));
    }
    let fov_deg = (2.0 * (0.5 * h_ap / focal).atan()).to_degrees() as f32;
    let position = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
    let camera = CameraDesc {
        position,
        target: position + forward,
        up,
        fov_deg: fov_deg.clamp(0.01, 179.0),
        fov_axis: FovAxis::X,
    };
    Ok((NamedCamera { name: at.to_string(), camera, aspect: Some((h_ap / v_ap) as f32) }, note))
}
