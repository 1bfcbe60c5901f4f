//! Built-in shapes (quad, sphere, disk) tessellated to triangles, and the `transform` and
//! `emission` tables shared by shapes and includes.

use std::collections::HashMap;
use std::f32::consts::PI;

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

/// Triangles and vertices of a generated shape.
pub(crate) struct Tessellation {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub indices: Vec<[u32; 3]>,
}

/// An orthonormal in-plane frame (u, v) with u x v = n: u = normalize(ref x n), v = n x u, where
/// ref = +Y, or +Z when n is (nearly) parallel to Y.
pub(crate) fn plane_frame(n: Vec3) -> (Vec3, Vec3) {
    let n = n.normalize();
    let reference = if n.y.abs() > 0.999 { Vec3::Z } else { Vec3::Y };
    let u = reference.cross(n).normalize();
    (u, n.cross(u))
}

/// The parallelogram corner, corner + e1, corner + e1 + e2, corner + e2; normal e1 x e2.
pub(crate) fn quad(corner: Vec3, e1: Vec3, e2: Vec3) -> Tessellation {
    Tessellation {
        positions: vec![corner, corner + e1, corner + e1 + e2, corner + e2],
        normals: None,
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// A disk as a fan of `segments` triangles facing `normal`. The rim radius is enlarged slightly so
/// that the polygon's area equals pi r^2 (emitted power and irradiance match the true disk).
pub(crate) fn disk(center: Vec3, radius: f32, normal: Vec3, segments: u32) -> Tessellation {
    let (u, v) = plane_frame(normal);
    let n = segments as f32;
    let dphi = 2.0 * PI / n;
    let r = radius * (2.0 * PI / (n * dphi.sin())).sqrt();
    let mut positions = Vec::with_capacity(segments as usize + 1);
    positions.push(center);
    for i in 0..segments {
        let phi = i as f32 * dphi;
        positions.push(center + r * (phi.cos() * u + phi.sin() * v));
    }
    let indices = (0..segments).map(|i| [0, i + 1, (i + 1) % segments + 1]).collect();
    Tessellation { positions, normals: None, indices }
}

/// Unit icosphere: vertices on the unit sphere, outward counter-clockwise triangles.
fn unit_icosphere(subdivisions: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let p = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut verts: Vec<Vec3> = [
        [-1.0, p, 0.0],
        [1.0, p, 0.0],
        [-1.0, -p, 0.0],
        [1.0, -p, 0.0],
        [0.0, -1.0, p],
        [0.0, 1.0, p],
        [0.0, -1.0, -p],
        [0.0, 1.0, -p],
        [p, 0.0, -1.0],
        [p, 0.0, 1.0],
        [-p, 0.0, -1.0],
        [-p, 0.0, 1.0],
    ]
    .into_iter()
    .map(|c| Vec3::from(c).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    // make every base face outward-facing regardless of the table's convention
    for t in &mut tris {
        let [a, b, c] = t.map(|i| verts[i as usize]);
        if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
            t.swap(1, 2);
        }
    }
    for _ in 0..subdivisions {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(tris.len() * 3 / 2);
        let mut next = Vec::with_capacity(tris.len() * 4);
        let mut midpoint = |a: u32, b: u32, verts: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *mid.entry(key).or_insert_with(|| {
                verts.push((verts[a as usize] + verts[b as usize]).normalize());
                (verts.len() - 1) as u32
            })
        };
        for &[a, b, c] in &tris {
            let ab = midpoint(a, b, &mut verts);
            let bc = midpoint(b, c, &mut verts);
            let ca = midpoint(c, a, &mut verts);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    (verts, tris)
}

/// A sphere as an icosphere with smooth (radial) normals. The vertices are pushed out slightly so
/// the mesh's surface area equals 4 pi r^2 (emitted power and mean projected area match).
pub(crate) fn sphere(center: Vec3, radius: f32, subdivisions: u32) -> Tessellation {
    let (dirs, indices) = unit_icosphere(subdivisions);
    let area: f64 = indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| dirs[i as usize]);
            0.5 * (b - a).cross(c - a).length() as f64
        })
        .sum();
    let k = (4.0 * std::f64::consts::PI / area).sqrt() as f32;
    let positions = dirs.iter().map(|d| center + *d * (radius * k)).collect();
    Tessellation { positions, normals: Some(dirs), indices }
}

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
    Ok(EmissionDesc { spectrum: s, scale, two_sided: t.opt_bool("two_sided")?.unwrap_or(false) })
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

#[cfg(test)]
mod tests {
    use super::*;

    fn area(t: &Tessellation) -> f32 {
        t.indices
            .iter()
            .map(|i| {
                let [a, b, c] = i.map(|k| t.positions[k as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    #[test]
    fn sphere_is_closed_outward_and_area_preserving() {
        let s = sphere(Vec3::new(1.0, 2.0, 3.0), 2.0, DEFAULT_SPHERE_SUBDIVISIONS);
        assert_eq!(s.indices.len(), 5120);
        assert!((area(&s) - 4.0 * PI * 4.0).abs() < 1e-3 * 4.0 * PI * 4.0);
        for t in &s.indices {
            let [a, b, c] = t.map(|k| s.positions[k as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.dot((a + b + c) / 3.0 - Vec3::new(1.0, 2.0, 3.0)) > 0.0);
        }
        for (p, n) in s.positions.iter().zip(s.normals.as_ref().unwrap()) {
            assert!(((*p - Vec3::new(1.0, 2.0, 3.0)).normalize() - *n).length() < 1e-5);
            assert!(((*p - Vec3::new(1.0, 2.0, 3.0)).length() - 2.0).abs() < 0.01);
        }
        // every edge is shared by exactly two triangles: closed, manifold
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &s.indices {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        assert!(edges.values().all(|&c| c == 2));
        assert_eq!(sphere(Vec3::ZERO, 1.0, 0).indices.len(), 20);
    }

    #[test]
    fn disk_faces_its_normal_and_keeps_its_area() {
        let n = Vec3::new(0.0, -1.0, 0.0);
        let d = disk(Vec3::new(0.0, 3.0, 0.0), 0.5, n, 16);
        assert_eq!(d.indices.len(), 16);
        assert!((area(&d) - PI * 0.25).abs() < 1e-5);
        for t in &d.indices {
            let [a, b, c] = t.map(|k| d.positions[k as usize]);
            assert!((b - a).cross(c - a).normalize().dot(n) > 0.999);
        }
    }

    #[test]
    fn plane_frames_are_right_handed() {
        for n in [Vec3::Z, Vec3::NEG_Y, Vec3::Y, Vec3::new(1.0, 2.0, 3.0).normalize()] {
            let (u, v) = plane_frame(n);
            assert!((u.cross(v) - n).length() < 1e-5, "{n}");
        }
        let (u, v) = plane_frame(Vec3::Z);
        assert!((u - Vec3::X).length() < 1e-6 && (v - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn quad_normal_is_edge1_cross_edge2() {
        let q = quad(Vec3::ZERO, Vec3::X, Vec3::NEG_Z);
        for t in &q.indices {
            let [a, b, c] = t.map(|k| q.positions[k as usize]);
            assert!(((b - a).cross(c - a).normalize() - Vec3::Y).length() < 1e-6);
        }
    }
}
