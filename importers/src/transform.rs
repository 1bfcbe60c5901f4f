//! Affine transforms of meshes and lights (positions, normals by the inverse transpose, winding).

use glam::{Affine3A, Mat3, Vec3};

use crate::scene_desc::{CameraDesc, LightDesc, LuminousOpening, MeshDesc};

/// `scale`, then rotation about X, Y, Z (in that order, fixed axes), then `translate`.
pub(crate) fn trs(translate: Vec3, rotate_deg_xyz: Vec3, scale: Vec3) -> Affine3A {
    let r = euler_xyz_deg(rotate_deg_xyz);
    Affine3A::from_mat3_translation(r * Mat3::from_diagonal(scale), translate)
}

/// Rotation about X by `deg.x`, then about Y by `deg.y`, then about Z by `deg.z` (fixed axes):
/// R = Rz * Ry * Rx.
pub(crate) fn euler_xyz_deg(deg: Vec3) -> Mat3 {
    Mat3::from_rotation_z(deg.z.to_radians())
        * Mat3::from_rotation_y(deg.y.to_radians())
        * Mat3::from_rotation_x(deg.x.to_radians())
}

/// Applies `m` to a mesh: positions, shading normals (inverse transpose, renormalised), and
/// the triangle winding (swapped when `m` mirrors, so the geometric normal keeps pointing to the
/// same side of the surface). Normals that become degenerate drop the mesh to flat shading.
pub(crate) fn transform_mesh(mesh: &mut MeshDesc, m: &Affine3A) {
    if *m == Affine3A::IDENTITY {
        return;
    }
    for p in &mut mesh.positions {
        *p = m.transform_point3(*p);
    }
    let lin = Mat3::from(m.matrix3);
    let det = lin.determinant();
    if let Some(ns) = &mut mesh.normals {
        let nm = if det != 0.0 && det.is_finite() { lin.inverse().transpose() } else { lin };
        let mut ok = true;
        for n in ns.iter_mut() {
            let t = (nm * *n).normalize_or_zero();
            ok &= t != Vec3::ZERO && t.is_finite();
            *n = t;
        }
        if !ok {
            mesh.normals = None;
        }
    }
    if det < 0.0 {
        for t in &mut mesh.indices {
            t.swap(1, 2);
        }
    }
}

/// Reverses a mesh's orientation: swaps the winding and negates the shading normals.
pub(crate) fn flip_mesh(mesh: &mut MeshDesc) {
    for t in &mut mesh.indices {
        t.swap(1, 2);
    }
    if let Some(ns) = &mut mesh.normals {
        for n in ns.iter_mut() {
            *n = -*n;
        }
    }
}

/// Applies `m` to a light: positions as points, directions as vectors.
pub(crate) fn transform_light(light: &mut LightDesc, m: &Affine3A) {
    match light {
        LightDesc::Point { position, .. } => *position = m.transform_point3(*position),
        LightDesc::Spot { position, direction, .. } => {
            *position = m.transform_point3(*position);
            *direction = m.transform_vector3(*direction);
        }
        LightDesc::Directional { direction, .. } => *direction = m.transform_vector3(*direction),
        LightDesc::Luminaire { position, frame, opening, .. } => {
            *position = m.transform_point3(*position);
            // the opening's sides scale with the transform along C0 and C90
            let (s0, s90) = (m.transform_vector3(frame.x_axis).length(), m.transform_vector3(frame.y_axis).length());
            *opening = match *opening {
                LuminousOpening::Point => LuminousOpening::Point,
                LuminousOpening::Rect { c0, c90 } => LuminousOpening::Rect { c0: c0 * s0, c90: c90 * s90 },
                LuminousOpening::Disk { diameter } => LuminousOpening::Disk { diameter: diameter * (s0 * s90).sqrt() },
            };
            // the turned frame, made orthonormal again (a scale does not change candela; a
            // mirror keeps the frame right-handed, C90 on the mirrored side of C0 and up)
            let up = m.transform_vector3(frame.z_axis).normalize_or(frame.z_axis);
            let c0 = m.transform_vector3(frame.x_axis);
            let c0 = (c0 - c0.dot(up) * up).normalize_or(frame.x_axis);
            *frame = glam::Mat3::from_cols(c0, up.cross(c0), up);
        }
        LightDesc::Environment { .. } => {}
    }
}

/// Applies `m` to a camera: position and target as points, up as a vector.
pub(crate) fn transform_camera(c: &mut CameraDesc, m: &Affine3A) {
    c.position = m.transform_point3(c.position);
    c.target = m.transform_point3(c.target);
    c.up = m.transform_vector3(c.up);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_desc::SourceLocation;

    fn tri() -> MeshDesc {
        MeshDesc {
            name: "t".into(),
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: Some(vec![Vec3::Z; 3]),
            uvs: None,
            colors: None,
            indices: vec![[0, 1, 2]],
            material: 0,
            emission: None,
            source: SourceLocation::default(),
        }
    }

    fn geometric_normal(m: &MeshDesc) -> Vec3 {
        let [a, b, c] = m.indices[0].map(|i| m.positions[i as usize]);
        (b - a).cross(c - a).normalize()
    }

    #[test]
    fn euler_order_is_x_then_y_then_z() {
        // X by 90 maps Y to Z; then Y by 90 maps Z to X.
        let r = euler_xyz_deg(Vec3::new(90.0, 90.0, 0.0));
        assert!((r * Vec3::Y - Vec3::X).length() < 1e-6);
    }

    #[test]
    fn normals_use_the_inverse_transpose() {
        let mut m = MeshDesc { normals: Some(vec![Vec3::new(1.0, 1.0, 0.0).normalize(); 3]), ..tri() };
        transform_mesh(&mut m, &trs(Vec3::ZERO, Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)));
        // a plane x + y = 0 scaled by 2 in x becomes x/2 + y = 0: normal (1/2, 1, 0)
        let n = m.normals.as_ref().unwrap()[0];
        assert!((n - Vec3::new(0.5, 1.0, 0.0).normalize()).length() < 1e-6, "{n}");
    }

    #[test]
    fn mirroring_keeps_the_geometric_normal_consistent_with_shading_normals() {
        let mut m = tri();
        transform_mesh(&mut m, &trs(Vec3::ONE, Vec3::ZERO, Vec3::new(1.0, 1.0, -1.0)));
        let n = m.normals.as_ref().unwrap()[0];
        assert!((n - Vec3::NEG_Z).length() < 1e-6);
        assert!((geometric_normal(&m) - Vec3::NEG_Z).length() < 1e-6);
        flip_mesh(&mut m);
        assert!((geometric_normal(&m) - Vec3::Z).length() < 1e-6);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::Z);
    }
}
