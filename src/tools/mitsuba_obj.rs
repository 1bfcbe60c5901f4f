//! The OBJ files of the Mitsuba export (`super::mitsuba_export`): a mesh as it is, and the
//! physical layer of a coated mesh (Mitsuba has no coated BSDF of quasar's model, so a coat is
//! written as the surface it stands for).

use std::fmt::Write as _;

/// A triangle mesh as OBJ text: its positions, its vertex normals when it has them, its faces.
pub fn obj_text(positions: &[glam::Vec3], normals: Option<&[glam::Vec3]>, indices: &[[u32; 3]]) -> String {
    let mut obj = String::new();
    for p in positions {
        let _ = writeln!(obj, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in normals.unwrap_or_default() {
        let _ = writeln!(obj, "vn {} {} {}", n.x, n.y, n.z);
    }
    for t in indices {
        let [a, b, c] = t.map(|v| v + 1);
        if normals.is_some() {
            let _ = writeln!(obj, "f {a}//{a} {b}//{b} {c}//{c}");
        } else {
            let _ = writeln!(obj, "f {a} {b} {c}");
        }
    }
    obj
}

/// The coat of a coated mesh as its own surface for Mitsuba: the mesh moved along its normals
/// (the vertex normals, else the area-weighted normals of the faces around each vertex) by
/// [`COAT_GAP`] (1 + the largest coordinate), as an OBJ. Under it the base is the layer's floor,
/// so Mitsuba traces every bounce between coat and base: an independent, exact reference. quasar's
/// position-free model reproduces it for a smooth coat over a Lambertian base (its
/// interreflection term is exact there), up to the light's sideways travel in the layer; for rough
/// coats and conductor bases the difference is the model's error (docs/validation.md).
pub fn coat_shape(m: &quasar_importers::MeshDesc) -> String {
    /// Mitsuba 3 moves a ray's origin off its surface by about 9e-5 (1 + |p|) in single precision
    /// (`math::RayEpsilon`); a thinner layer is crossed unseen (measured: a coated sphere with a
    /// 1e-4 gap rendered 2.3 times too dark). The gap is about 20 times that offset.
    const COAT_GAP: f32 = 2e-3;
    let mut normals = vec![glam::Vec3::ZERO; m.positions.len()];
    match &m.normals {
        Some(ns) => normals.clone_from(ns),
        None => {
            for t in &m.indices {
                let [a, b, c] = t.map(|v| v as usize);
                let n = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
                for v in [a, b, c] {
                    normals[v] += n;
                }
            }
        }
    }
    let (lo, hi) = quasar_importers::framing::mesh_bounds(std::slice::from_ref(m)).unwrap_or_default();
    let d = COAT_GAP * (1.0 + lo.abs().max(hi.abs()).max_element());
    let moved: Vec<glam::Vec3> =
        m.positions.iter().zip(&normals).map(|(p, n)| *p + d * n.normalize_or_zero()).collect();
    obj_text(&moved, m.normals.as_deref(), &m.indices)
}
