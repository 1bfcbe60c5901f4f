//! UsdGeomMesh -> [`MeshDesc`]: polygons fan-triangulated (`holeIndices` skipped),
//! `leftHanded` orientation flipped to quasar's counter-clockwise winding, `normals` /
//! `primvars:normals` and `primvars:st` with `vertex`, `varying`, `faceVarying`, `uniform` and
//! `constant` interpolation (and `:indices` for indexed primvars). A mesh whose normals or uvs
//! are not per point is unwelded: one vertex per face corner. `subdivisionScheme` other than
//! `none` renders the control cage (the caller warns once). `GeomSubset`s of family
//! `materialBind` split the mesh by face ([`split_by_subsets`]).

use glam::{Vec2, Vec3};
use openusd::usd::Prim;

use super::value::{self, AttrError};
use crate::scene_desc::MeshDesc;

/// A mesh in its prim's local space, before the transform and the material are known.
pub(super) struct LocalMesh {
    /// The triangles, positions, normals and uvs (material index 0, no emission).
    pub mesh: MeshDesc,
    /// `subdivisionScheme` (schema default `catmullClark`).
    pub subdivision: String,
    /// The USD face each triangle of `mesh.indices` came from (for `GeomSubset`s).
    pub faces: Vec<u32>,
}

/// Per-corner values of a primvar-like attribute of `interpolation` with `values` (and optional
/// `indices`): the value at face `f`, face-vertex `c` (running corner index), point `p`.
struct Primvar<T> {
    values: Vec<T>,
    indices: Option<Vec<i32>>,
    interpolation: String,
}

impl<T: Copy> Primvar<T> {
    fn at(&self, face: usize, corner: usize, point: usize) -> Option<T> {
        let i = match self.interpolation.as_str() {
            "constant" => 0,
            "uniform" => face,
            "faceVarying" => corner,
            _ => point,
        };
        let i = match &self.indices {
            Some(ix) => usize::try_from(*ix.get(i)?).ok()?,
            None => i,
        };
        self.values.get(i).copied()
    }

    /// True when every corner of a point gets the point's value (no unwelding needed).
    fn per_point(&self) -> bool {
        matches!(self.interpolation.as_str(), "vertex" | "varying") && self.indices.is_none()
    }
}

/// A reader of an array attribute (`value::vec3_array`, `value::vec2_array`).
type ArrayReader<T> = fn(&Prim, &str) -> Result<Option<Vec<T>>, AttrError>;

/// The primvar `name` of `prim` with its indices and interpolation, if authored.
fn primvar<T>(prim: &Prim, name: &str, read: ArrayReader<T>) -> Result<Option<Primvar<T>>, AttrError> {
    let Some(values) = read(prim, name)? else { return Ok(None) };
    let indices = value::int_array(prim, &format!("{name}:indices"))?;
    Ok(Some(Primvar { values, indices, interpolation: value::interpolation(prim, name) }))
}

/// Reads the mesh `prim` (see the module documentation); errors name the attribute.
pub(super) fn read_mesh(prim: &Prim, name: String) -> Result<LocalMesh, AttrError> {
    let points = value::vec3_array(prim, "points")?.unwrap_or_default();
    let counts = value::int_array(prim, "faceVertexCounts")?.unwrap_or_default();
    let corners = value::int_array(prim, "faceVertexIndices")?.unwrap_or_default();
    let holes: std::collections::HashSet<i32> =
        value::int_array(prim, "holeIndices")?.unwrap_or_default().into_iter().collect();
    let left_handed = value::token(prim, "orientation")?.as_deref() == Some("leftHanded");
    let subdivision = value::token(prim, "subdivisionScheme")?.unwrap_or_else(|| "catmullClark".into());
    let total: i64 = counts.iter().map(|&c| i64::from(c)).sum();
    if counts.iter().any(|&c| c < 0) || total != corners.len() as i64 {
        return Err((
            "faceVertexCounts".into(),
            format!("the counts add up to {total}, but faceVertexIndices has {} entries", corners.len()),
        ));
    }
    if let Some(bad) = corners.iter().find(|&&i| i < 0 || i as usize >= points.len()) {
        return Err(("faceVertexIndices".into(), format!("index {bad} is out of range ({} points)", points.len())));
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(("points".into(), "a point is not finite".into()));
    }
    let normals = match primvar(prim, "primvars:normals", value::vec3_array)? {
        Some(n) => Some(n),
        None => primvar(prim, "normals", value::vec3_array)?,
    };
    let st = primvar(prim, "primvars:st", value::vec2_array)?;
    let weld = normals.as_ref().is_none_or(Primvar::per_point) && st.as_ref().is_none_or(Primvar::per_point);

    let mut positions: Vec<Vec3> = if weld { points.clone() } else { Vec::new() };
    let mut out_normals: Vec<Vec3> = Vec::new();
    let mut out_uvs: Vec<Vec2> = Vec::new();
    let mut normals_ok = normals.is_some();
    let mut uvs_ok = st.is_some();
    if weld {
        for p in 0..points.len() {
            if let Some(n) = &normals {
                let v = n.at(0, 0, p);
                normals_ok &= v.is_some_and(|v| v.is_finite() && v.length_squared() > 0.0);
                out_normals.push(v.unwrap_or(Vec3::Z).normalize_or_zero());
            }
            if let Some(s) = &st {
                let v = s.at(0, 0, p);
                uvs_ok &= v.is_some();
                // USD st has its origin at the image's bottom left; quasar's (glTF's) at the top left
                out_uvs.push(v.map_or(Vec2::ZERO, |v| Vec2::new(v.x, 1.0 - v.y)));
            }
        }
    }
    let mut indices: Vec<[u32; 3]> = Vec::new();
    let mut faces: Vec<u32> = Vec::new();
    let mut corner = 0usize;
    for (face, &count) in counts.iter().enumerate() {
        let count = count as usize;
        let face_corners: Vec<u32> = (0..count)
            .map(|k| {
                let point = corners[corner + k] as usize;
                if weld {
                    return point as u32;
                }
                let c = corner + k;
                positions.push(points[point]);
                if let Some(n) = &normals {
                    let v = n.at(face, c, point);
                    normals_ok &= v.is_some_and(|v| v.is_finite() && v.length_squared() > 0.0);
                    out_normals.push(v.unwrap_or(Vec3::Z).normalize_or_zero());
                }
                if let Some(s) = &st {
                    let v = s.at(face, c, point);
                    uvs_ok &= v.is_some();
                    out_uvs.push(v.map_or(Vec2::ZERO, |v| Vec2::new(v.x, 1.0 - v.y)));
                }
                (positions.len() - 1) as u32
            })
            .collect();
        corner += count;
        if count < 3 || holes.contains(&(face as i32)) {
            continue;
        }
        for k in 1..count - 1 {
            let t = [face_corners[0], face_corners[k], face_corners[k + 1]];
            indices.push(if left_handed { [t[0], t[2], t[1]] } else { t });
            faces.push(face as u32);
        }
    }
    let mesh = MeshDesc {
        name,
        positions,
        normals: normals_ok.then_some(out_normals),
        uvs: uvs_ok.then_some(out_uvs),
        colors: None,
        indices,
        material: 0,
        emission: None,
        source: Default::default(),
    };
    if mesh.positions.len() > u32::MAX as usize {
        return Err(("points".into(), "more than 2^32 vertices".into()));
    }
    Ok(LocalMesh { mesh, subdivision, faces })
}

/// The face sets of `mesh`'s `GeomSubset` children of family `materialBind` (or without a family)
/// and element type `face`: (subset prim, its face indices), in namespace order.
pub(super) fn material_subsets(mesh: &Prim) -> Result<Vec<(Prim, Vec<i32>)>, AttrError> {
    let mut out = Vec::new();
    for child in mesh.children().map_err(|e| ("GeomSubset".to_string(), format!("{e:#}")))? {
        if child.type_name().ok().flatten().is_none_or(|t| t.as_str() != "GeomSubset") {
            continue;
        }
        let family = value::token(&child, "familyName")?;
        let element = value::token(&child, "elementType")?.unwrap_or_else(|| "face".into());
        if family.as_deref().is_some_and(|f| f != "materialBind") || element != "face" {
            continue;
        }
        out.push((child.clone(), value::int_array(&child, "indices")?.unwrap_or_default()));
    }
    Ok(out)
}

/// Splits `local`'s triangles into the face sets `subsets` (a face claimed by an earlier subset
/// stays there) and the rest: (subset index or None for the rest, the mesh of those triangles).
/// Empty parts are left out; every part keeps all vertices.
pub(super) fn split_by_subsets(local: &LocalMesh, subsets: &[Vec<i32>]) -> Vec<(Option<usize>, MeshDesc)> {
    if subsets.is_empty() {
        return vec![(None, local.mesh.clone())];
    }
    let mut owner: std::collections::HashMap<u32, usize> = std::collections::HashMap::new();
    for (k, faces) in subsets.iter().enumerate() {
        for &f in faces {
            if f >= 0 {
                owner.entry(f as u32).or_insert(k);
            }
        }
    }
    let mut parts: Vec<(Option<usize>, MeshDesc)> = Vec::new();
    for part in (0..subsets.len()).map(Some).chain(std::iter::once(None)) {
        let indices: Vec<[u32; 3]> = local
            .mesh
            .indices
            .iter()
            .zip(&local.faces)
            .filter(|(_, f)| owner.get(f).copied() == part)
            .map(|(t, _)| *t)
            .collect();
        if !indices.is_empty() {
            parts.push((part, MeshDesc { indices, ..local.mesh.clone() }));
        }
    }
    parts
}
