//! UsdGeom `PointInstancer`: one copy of a prototype per instance. Instance k draws the
//! prototype `prototypes[protoIndices[k]]` (the relationship's targets, in order) with the
//! transform T(`positions[k]`) R(`orientations[k]`) S(`scales[k]`) (scale, then orientation, then
//! translation, as `UsdGeomPointInstancer::ComputeInstanceTransformsAtTime`; the quaternion
//! enters the rotation matrix unnormalised, as Pixar's `GfMatrix4d::SetRotate`, so `quath`
//! rounding gives the same matrix), applied after the
//! prototype root's own transform and before the instancer's world transform; the prims between
//! the instancer and a prototype (a `Prototypes` scope) contribute nothing. Instances whose id
//! (`ids[k]`, else k) is in `invisibleIds` are skipped. Prototypes are drawn only through their
//! instances. Each instance's geometry is copied into the scene (the BVH holds every copy).

use glam::{DMat4, DQuat, DVec3};
use openusd::sdf;
use openusd::usd::Prim;

use super::value::{self, AttrError};

/// The instances of the `PointInstancer` `prim`: (prototype path, instance transform in the
/// instancer's space), in instance order.
pub(super) fn instances(prim: &Prim) -> Result<Vec<(sdf::Path, DMat4)>, AttrError> {
    let protos = prim.relationship("prototypes").targets().map_err(|e| ("prototypes".to_string(), format!("{e:#}")))?;
    let Some(indices) = value::int_array(prim, "protoIndices")? else {
        return Ok(Vec::new());
    };
    let n = indices.len();
    let positions = value::vec3_array(prim, "positions")?.unwrap_or_default();
    if positions.len() != n {
        return Err((
            "positions".into(),
            format!("{} positions for {n} protoIndices (one per instance is required)", positions.len()),
        ));
    }
    let orientations = match value::quat_array(prim, "orientations")? {
        Some(q) => Some(q),
        None => value::quat_array(prim, "orientationsf")?,
    };
    let scales = value::vec3_array(prim, "scales")?;
    for (attr, len) in
        [("orientations", orientations.as_ref().map(Vec::len)), ("scales", scales.as_ref().map(Vec::len))]
    {
        if let Some(len) = len
            && len != n
        {
            return Err((attr.into(), format!("{len} values for {n} instances")));
        }
    }
    let ids = value::int64_array(prim, "ids")?;
    let invisible = value::int64_array(prim, "invisibleIds")?.unwrap_or_default();
    let mut out = Vec::with_capacity(n);
    for (k, &pi) in indices.iter().enumerate() {
        let id = ids.as_ref().and_then(|ids| ids.get(k).copied()).unwrap_or(k as i64);
        if invisible.contains(&id) {
            continue;
        }
        let proto = usize::try_from(pi).ok().and_then(|i| protos.get(i)).ok_or_else(|| {
            (
                "protoIndices".to_string(),
                format!("index {pi} of instance {k} is out of range ({} prototypes)", protos.len()),
            )
        })?;
        let q = orientations.as_ref().map_or(DQuat::IDENTITY, |o| o[k]);
        if !q.is_finite() {
            return Err(("orientations".into(), format!("instance {k}: {q} is not finite")));
        }
        let s = scales.as_ref().map_or(DVec3::ONE, |s| s[k].as_dvec3());
        let t = positions[k].as_dvec3();
        if !(s.is_finite() && t.is_finite()) {
            return Err(("positions".into(), format!("instance {k}: position {t} or scale {s} is not finite")));
        }
        out.push((proto.clone(), DMat4::from_scale_rotation_translation(s, q, t)));
    }
    Ok(out)
}
