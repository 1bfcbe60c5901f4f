//! The camera a model file gets when it defines none (glTF without cameras, every OBJ): it frames
//! the bounding sphere of the meshes with a 40° vertical field of view from about 19° above the
//! horizon (+Y up, the convention of both formats).
//!
//! # Which side
//! It looks from +Z (the front view of glTF and of most OBJ exports) unless the model is open to
//! another horizontal side. A side d's score is the area the meshes turn towards a viewer there,
//! S(d) = sum over triangles of A max(0, n . d) with the geometric normal n (counter-clockwise
//! winding), and its openness is O(d) = S(d) - S(-d): what faces a viewer at d but has no
//! counterpart facing the opposite side. A closed surface has O = 0 on every side (S(d) is its
//! projected area from either side), so only open models choose: a Cornell box modelled with
//! inward normals and its open side at -Z (the classic Cornell data in millimetres, as
//! tinyobjloader's `cornell_box.obj` has it) has its back wall unmatched, O(-Z) > 0, and is seen
//! from -Z, through its opening, instead of from behind its back wall. The most open side wins
//! when O is more than 10% of its S; otherwise +Z.

use glam::Vec3;

use crate::scene_desc::{CameraDesc, FovAxis, MeshDesc, NamedCamera, RenderSettings};

/// Vertical field of view of the framing camera, degrees.
pub const FRAMING_FOV_DEG: f32 = 40.0;

/// The candidate horizontal sides the camera may look from, +Z first (it wins ties).
const SIDES: [Vec3; 4] = [Vec3::Z, Vec3::NEG_Z, Vec3::X, Vec3::NEG_X];

/// Share of a side's score S(d) its openness O(d) must exceed for the side to be chosen.
const MIN_OPENNESS: f64 = 0.1;

/// The axis-aligned box (min, max corners) of the finite vertices of `meshes`, or None when they
/// have none.
pub fn mesh_bounds(meshes: &[MeshDesc]) -> Option<(Vec3, Vec3)> {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in meshes.iter().flat_map(|m| m.positions.iter()).filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo.x <= hi.x).then_some((lo, hi))
}

/// The framing camera of `meshes` (module documentation), or None when they have no finite
/// vertex.
pub fn framing_camera(meshes: &[MeshDesc]) -> Option<CameraDesc> {
    let (lo, hi) = mesh_bounds(meshes)?;
    Some(framing_camera_of_box(lo, hi, open_side(meshes)))
}

/// The scene camera of a model file: its first camera, whose aspect ratio (when the file gives
/// one) sets `render.width` for `render.height`, else the framing camera of `meshes`.
pub fn scene_camera(cameras: &[NamedCamera], meshes: &[MeshDesc], render: &mut RenderSettings) -> CameraDesc {
    match cameras.first() {
        Some(c) => {
            if let Some(a) = c.aspect {
                render.width = (render.height as f32 * a).round().clamp(1.0, 65536.0) as u32;
            }
            c.camera.clone()
        }
        None => framing_camera(meshes).unwrap_or_default(),
    }
}

/// The side (one of [`SIDES`]) to which the meshes are most open (module documentation).
fn open_side(meshes: &[MeshDesc]) -> Vec3 {
    // S(d) for d = +Z, -Z, +X, -X
    let mut score = [0.0f64; 4];
    for m in meshes {
        for t in &m.indices {
            let [a, b, c] = t.map(|i| m.positions.get(i as usize).copied().unwrap_or(Vec3::NAN));
            // twice the area times the unit normal
            let n = (b - a).cross(c - a);
            if !n.is_finite() {
                continue;
            }
            for (s, d) in score.iter_mut().zip(SIDES) {
                *s += 0.5 * f64::from(n.dot(d).max(0.0));
            }
        }
    }
    let opposite = [1, 0, 3, 2];
    let openness = |i: usize| score[i] - score[opposite[i]];
    let best = (0..SIDES.len()).fold(0, |b, i| if openness(i) > openness(b) { i } else { b });
    if openness(best) > MIN_OPENNESS * score[best] { SIDES[best] } else { SIDES[0] }
}

/// A camera that looks at the centre of the box `lo..hi` from `side` (a horizontal unit vector),
/// raised by atan(0.35) ~ 19°, at the distance where the box's bounding sphere fills the
/// vertical field of view with 5% margin.
pub fn framing_camera_of_box(lo: Vec3, hi: Vec3, side: Vec3) -> CameraDesc {
    let center = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-6);
    let dist = radius / (0.5 * FRAMING_FOV_DEG).to_radians().sin() * 1.05;
    let dir = (side + Vec3::new(0.0, 0.35, 0.0)).normalize();
    CameraDesc {
        position: center + dir * dist,
        target: center,
        up: Vec3::Y,
        fov_deg: FRAMING_FOV_DEG,
        fov_axis: FovAxis::Y,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(name: &str, corners: [Vec3; 4]) -> MeshDesc {
        MeshDesc {
            name: name.into(),
            positions: corners.to_vec(),
            normals: None,
            uvs: None,
            colors: None,
            indices: vec![[0, 1, 2], [0, 2, 3]],
            material: 0,
            emission: None,
            source: Default::default(),
        }
    }

    /// A unit box open at `-Z`, its five walls' normals pointing inwards.
    fn open_box() -> Vec<MeshDesc> {
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        vec![
            // back wall at z = 1, normal -Z
            quad("back", [v(0., 0., 1.), v(0., 1., 1.), v(1., 1., 1.), v(1., 0., 1.)]),
            // floor y = 0, normal +Y
            quad("floor", [v(0., 0., 0.), v(0., 0., 1.), v(1., 0., 1.), v(1., 0., 0.)]),
            // ceiling y = 1, normal -Y
            quad("ceiling", [v(0., 1., 0.), v(1., 1., 0.), v(1., 1., 1.), v(0., 1., 1.)]),
            // left x = 0, normal +X
            quad("left", [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)]),
            // right x = 1, normal -X
            quad("right", [v(1., 0., 0.), v(1., 0., 1.), v(1., 1., 1.), v(1., 1., 0.)]),
        ]
    }

    #[test]
    fn an_open_box_is_seen_through_its_opening() {
        let meshes = open_box();
        for m in &meshes {
            let [a, b, c] = m.indices[0].map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).dot(Vec3::splat(0.5) - a) > 0.0, "{} faces inwards", m.name);
        }
        let cam = framing_camera(&meshes).unwrap();
        assert!((cam.target - Vec3::splat(0.5)).length() < 1e-6);
        assert!(cam.position.z < -1.0 && cam.position.y > 0.5, "{:?}", cam.position);
    }

    #[test]
    fn closed_and_flat_models_are_seen_from_the_front() {
        // a closed box: the open box plus its front wall at z = 0 (normal +Z, inwards)
        let mut meshes = open_box();
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        meshes.push(quad("front", [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)]));
        let cam = framing_camera(&meshes).unwrap();
        assert!(cam.position.z > 1.0, "{:?}", cam.position);
        // a single triangle facing +Z
        let tri = quad("tri", [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 0.)]);
        assert!(framing_camera(&[tri]).unwrap().position.z > 0.5);
        assert!(framing_camera(&[]).is_none());
    }

    #[test]
    fn the_bounding_sphere_fills_the_field_of_view() {
        let cam = framing_camera_of_box(Vec3::splat(-1.0), Vec3::splat(1.0), Vec3::Z);
        let d = (cam.position - cam.target).length();
        let half = (3.0f32.sqrt() / d).asin().to_degrees();
        assert!(half < 0.5 * FRAMING_FOV_DEG && half > 0.45 * FRAMING_FOV_DEG, "{half}");
    }
}
