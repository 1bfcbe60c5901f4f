//! Whether the surfaces that bound a medium close (issue 49): a path tracks the media it is in
//! by the surfaces it crosses (the renderer's `core::medium`), so a medium whose surfaces leave a
//! gap lets a path out without crossing one, and that path then absorbs and scatters in air.
//! Every edge of a closed surface is shared by an even number of its triangles; an edge used
//! once (or an odd number of times) is open. The check matches positions, not indices, so that a
//! body made of separate meshes (six quads of a box) counts as closed, within a grid of 1e-6 of
//! the bounds' diagonal; and it takes together the materials whose interiors are equal (one
//! medium, as the renderer's media table merges them), so a body whose faces have different
//! finishes is one surface.

use std::collections::HashMap;

use glam::Vec3;

use crate::scene_desc::SceneDesc;

/// One warning per medium (absorption or scattering) whose triangles leave open edges, naming
/// its materials, the count and one open edge's midpoint (the smallest).
pub fn open_medium_boundaries(desc: &SceneDesc) -> Vec<String> {
    let mut warnings = Vec::new();
    let interior = |m: &crate::scene_desc::MaterialDesc| (m.absorption.clone(), m.scattering.clone());
    for (m, mat) in desc.materials.iter().enumerate() {
        if mat.absorption.is_none() && mat.scattering.is_none() {
            continue;
        }
        // the first material of each medium checks the medium's surfaces
        let same: Vec<usize> =
            (0..desc.materials.len()).filter(|&k| interior(&desc.materials[k]) == interior(mat)).collect();
        if same[0] != m {
            continue;
        }
        let names = same.iter().map(|&k| format!("`{}`", desc.materials[k].name)).collect::<Vec<_>>().join(", ");
        let meshes: Vec<_> = desc.meshes.iter().filter(|mesh| same.contains(&mesh.material)).collect();
        if meshes.is_empty() {
            continue;
        }
        let (lo, hi) = meshes
            .iter()
            .flat_map(|mesh| mesh.positions.iter())
            .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let cell = ((hi - lo).length() * 1e-6).max(f32::MIN_POSITIVE);
        let key = |p: Vec3| {
            let q = ((p - lo) / cell).round();
            (q.x as i64, q.y as i64, q.z as i64)
        };
        let mut edges: HashMap<_, (u32, Vec3)> = HashMap::new();
        for mesh in &meshes {
            for t in &mesh.indices {
                for k in 0..3 {
                    let (a, b) = (mesh.positions[t[k] as usize], mesh.positions[t[(k + 1) % 3] as usize]);
                    let (ka, kb) = (key(a), key(b));
                    if ka == kb {
                        continue;
                    }
                    let e = edges.entry(if ka < kb { (ka, kb) } else { (kb, ka) }).or_insert((0, (a + b) / 2.0));
                    e.0 += 1;
                }
            }
        }
        let open: Vec<Vec3> = edges.values().filter(|(n, _)| n % 2 == 1).map(|&(_, mid)| mid).collect();
        // the same edge named on every run: the smallest midpoint (x, then y, then z)
        let first =
            open.iter().min_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap_or(std::cmp::Ordering::Equal));
        if let Some(mid) = first {
            warnings.push(format!(
                "the medium inside {} (absorption or scattering) is not closed by its surfaces: {} open edge{} (one at [{:.4}, {:.4}, {:.4}] m); a path that leaves through a gap stays in the medium",
                names,
                open.len(),
                if open.len() == 1 { "" } else { "s" },
                mid.x,
                mid.y,
                mid.z
            ));
        }
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_desc::{MaterialDesc, MeshDesc};
    use quasar_materials::{Absorption, Ior, Material, spectrum::Spectrum};

    fn glass(absorbs: bool) -> MaterialDesc {
        MaterialDesc {
            name: "glass".into(),
            material: Material::Dielectric { ior: Ior::Constant(1.5), alpha: 0.0, transmittance: None },
            absorption: absorbs.then_some(Absorption::Coefficient(Spectrum::Constant(1.0))),
            scattering: None,
            textures: Default::default(),
            source: Default::default(),
        }
    }

    fn mesh(positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> MeshDesc {
        MeshDesc {
            name: "m".into(),
            positions,
            normals: None,
            uvs: None,
            colors: None,
            indices,
            material: 0,
            emission: None,
            source: Default::default(),
        }
    }

    /// A tetrahedron closes; one face fewer leaves three open edges; a clear material is not
    /// checked; a tetrahedron of four separate triangles whose shared corners differ by 1e-8 m
    /// (two ways of computing one corner) closes too.
    #[test]
    fn open_edges_of_a_medium_are_reported() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let faces = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let scene = |meshes, absorbs| SceneDesc { materials: vec![glass(absorbs)], meshes, ..Default::default() };
        assert!(open_medium_boundaries(&scene(vec![mesh(p.clone(), faces.clone())], true)).is_empty());
        let w = open_medium_boundaries(&scene(vec![mesh(p.clone(), faces[..3].to_vec())], true));
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("`glass`") && w[0].contains("3 open edges"), "{w:?}");
        assert!(open_medium_boundaries(&scene(vec![mesh(p.clone(), faces[..3].to_vec())], false)).is_empty());
        let separate: Vec<MeshDesc> = faces
            .iter()
            .enumerate()
            .map(|(k, f)| {
                let jitter = Vec3::splat(1e-8 * k as f32);
                mesh(f.iter().map(|&i| p[i as usize] + jitter).collect(), vec![[0, 1, 2]])
            })
            .collect();
        assert!(open_medium_boundaries(&scene(separate, true)).is_empty());
    }
}
