//! Analytic shapes as triangles: quad, disk, icosphere, the surfaces of revolution (cylinder,
//! cone, capsule) and the box. Shared by the TOML shapes, the USD implicit prims (`Cube`,
//! `Sphere`, `Cylinder`, `Cone`, `Capsule`, `Plane`) and the UsdLux area lights. Every surface
//! faces outwards (counter-clockwise seen from outside, normal (v1 - v0) x (v2 - v0)), and round
//! shapes keep their true area (the disk's rim, the revolved profiles' radii and the sphere's
//! vertices are pushed out by the polygon's area deficit), so an emitter's power and a
//! surface's projected area match the analytic shape.

use std::collections::HashMap;
use std::f32::consts::PI;

use glam::{Vec2, Vec3};

/// Triangles and vertices of a generated shape.
pub(crate) struct Tessellation {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals, or None for flat shading.
    pub normals: Option<Vec<Vec3>>,
    /// Counter-clockwise triangles.
    pub indices: Vec<[u32; 3]>,
}

impl Tessellation {
    /// The shape built along Z turned to lie along `axis` (0 = X, 1 = Y, 2 = Z) by the cyclic
    /// permutation of the axes that takes Z there (a rotation: orientation is kept).
    pub(crate) fn along(mut self, axis: usize) -> Self {
        let turn = |v: Vec3| match axis {
            0 => Vec3::new(v.z, v.x, v.y),
            1 => Vec3::new(v.y, v.z, v.x),
            _ => v,
        };
        self.positions.iter_mut().for_each(|p| *p = turn(*p));
        if let Some(n) = &mut self.normals {
            n.iter_mut().for_each(|p| *p = turn(*p));
        }
        self
    }
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

/// The surface swept by rotating `profile` about the Z axis in `segments` steps. Each profile
/// point is (radius, z) with its outward normal (radial, axial); consecutive points span one
/// band. Two equal consecutive points make a crease (the band is skipped), a radius of 0 a pole
/// (its degenerate triangles are skipped). Radii are scaled by (pi/N) / sin(pi/N) so a band's
/// polygonal area equals the true surface's. Facing outwards when the profile runs with
/// increasing arc length counter-clockwise about +Y of the (radial, z) plane, i.e. bottom to top
/// on the outside.
pub(crate) fn revolve(profile: &[(Vec2, Vec2)], segments: u32) -> Tessellation {
    let n = segments.max(3);
    let k = (PI / n as f32) / (PI / n as f32).sin();
    let mut positions = Vec::with_capacity(profile.len() * n as usize);
    let mut normals = Vec::with_capacity(positions.capacity());
    for &(p, nrm) in profile {
        let nrm = nrm.normalize_or_zero();
        for i in 0..n {
            let (s, c) = (2.0 * PI * i as f32 / n as f32).sin_cos();
            positions.push(Vec3::new(k * p.x * c, k * p.x * s, p.y));
            normals.push(Vec3::new(nrm.x * c, nrm.x * s, nrm.y));
        }
    }
    let mut indices = Vec::new();
    for (j, w) in profile.windows(2).enumerate() {
        if w[0].0 == w[1].0 {
            continue;
        }
        let (row, next) = (j as u32 * n, (j as u32 + 1) * n);
        for i in 0..n {
            let i1 = (i + 1) % n;
            if w[0].0.x > 0.0 {
                indices.push([row + i, row + i1, next + i]);
            }
            if w[1].0.x > 0.0 {
                indices.push([row + i1, next + i1, next + i]);
            }
        }
    }
    Tessellation { positions, normals: Some(normals), indices }
}

/// A closed cylinder of `radius` and `height` along Z, centred at the origin (caps included).
pub(crate) fn cylinder(radius: f32, height: f32, segments: u32) -> Tessellation {
    let (r, h) = (radius, 0.5 * height);
    let (down, side, up) = (Vec2::new(0.0, -1.0), Vec2::X, Vec2::Y);
    let profile = [
        (Vec2::new(0.0, -h), down),
        (Vec2::new(r, -h), down),
        (Vec2::new(r, -h), side),
        (Vec2::new(r, h), side),
        (Vec2::new(r, h), up),
        (Vec2::new(0.0, h), up),
    ];
    revolve(&profile, segments)
}

/// A closed truncated cone along Z centred at the origin: radius `bottom` at z = -height/2 and
/// `top` at +height/2 (a cylinder when they are equal, a cone when one is 0), with flat caps.
pub(crate) fn frustum(bottom: f32, top: f32, height: f32, segments: u32) -> Tessellation {
    let h = 0.5 * height;
    let (down, up) = (Vec2::new(0.0, -1.0), Vec2::Y);
    // the side's outward normal in the (radial, z) plane
    let side = Vec2::new(height, bottom - top).normalize();
    let profile = [
        (Vec2::new(0.0, -h), down),
        (Vec2::new(bottom, -h), down),
        (Vec2::new(bottom, -h), side),
        (Vec2::new(top, h), side),
        (Vec2::new(top, h), up),
        (Vec2::new(0.0, h), up),
    ];
    revolve(&profile, segments)
}

/// A capsule along Z centred at the origin with ends of different radii (USD's `Capsule_1`):
/// the truncated cone of radius `bottom` at z = -height/2 and `top` at +height/2, closed at each
/// end by the spherical cap tangent to it there: with the cone's outward normal n = (n_r, n_z)
/// in the (radial, z) plane, the cap of ring radius r has radius r / n_r and its centre on the
/// axis where the normal at the ring is n (`rings` bands per cap). Equal radii give hemispheres.
pub(crate) fn capsule_tapered(bottom: f32, top: f32, height: f32, segments: u32, rings: u32) -> Tessellation {
    let h = 0.5 * height;
    let rings = rings.max(2);
    let n = Vec2::new(height, bottom - top).normalize();
    // the elevation of the rings' normal
    let at_ring = n.y.atan2(n.x);
    let mut profile = Vec::with_capacity(2 * rings as usize + 2);
    for (ring_z, ring_r, from, to) in [(-h, bottom, -0.5 * PI, at_ring), (h, top, at_ring, 0.5 * PI)] {
        let radius = ring_r / n.x;
        let centre = ring_z - radius * n.y;
        for i in 0..=rings {
            let t = from + (to - from) * i as f32 / rings as f32;
            let nrm = Vec2::new(t.cos(), t.sin());
            // exact zero radius at the poles, exact rings where the cone meets the caps
            let p = match (i, ring_z < 0.0) {
                (0, true) => Vec2::new(0.0, centre - radius),
                (i, false) if i == rings => Vec2::new(0.0, centre + radius),
                (i, true) if i == rings => Vec2::new(ring_r, ring_z),
                (0, false) => Vec2::new(ring_r, ring_z),
                _ => Vec2::new(radius * nrm.x, centre + radius * nrm.y),
            };
            profile.push((p, nrm));
        }
    }
    revolve(&profile, segments)
}

/// The side of a cylinder of `radius` and `height` along Z, centred at the origin (no caps).
pub(crate) fn cylinder_side(radius: f32, height: f32, segments: u32) -> Tessellation {
    let h = 0.5 * height;
    revolve(&[(Vec2::new(radius, -h), Vec2::X), (Vec2::new(radius, h), Vec2::X)], segments)
}

/// A closed cone of base `radius` and `height` along Z, centred at the origin: the base at
/// z = -height/2, the apex at +height/2.
pub(crate) fn cone(radius: f32, height: f32, segments: u32) -> Tessellation {
    let (r, h) = (radius, 0.5 * height);
    let down = Vec2::new(0.0, -1.0);
    let side = Vec2::new(height, radius);
    let profile =
        [(Vec2::new(0.0, -h), down), (Vec2::new(r, -h), down), (Vec2::new(r, -h), side), (Vec2::new(0.0, h), side)];
    revolve(&profile, segments)
}

/// A capsule along Z centred at the origin: a cylinder of `radius` and `height` with a
/// hemisphere of `radius` on each end (`rings` bands per hemisphere).
pub(crate) fn capsule(radius: f32, height: f32, segments: u32, rings: u32) -> Tessellation {
    let h = 0.5 * height;
    let rings = rings.max(2);
    let mut profile = Vec::with_capacity(2 * rings as usize + 2);
    for (z0, from, to) in [(-h, -0.5 * PI, 0.0), (h, 0.0, 0.5 * PI)] {
        for i in 0..=rings {
            let t = from + (to - from) * i as f32 / rings as f32;
            let nrm = Vec2::new(t.cos(), t.sin());
            // exact zero radius at the poles
            let r = if i == 0 && z0 < 0.0 || i == rings && z0 > 0.0 { 0.0 } else { radius * nrm.x };
            profile.push((Vec2::new(r, z0 + radius * nrm.y), nrm));
        }
    }
    revolve(&profile, segments)
}

/// An axis-aligned box of edge lengths `size` centred at the origin (flat faces).
pub(crate) fn cuboid(size: Vec3) -> Tessellation {
    let h = 0.5 * size;
    let mut out = Tessellation { positions: Vec::new(), normals: None, indices: Vec::new() };
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let n = Vec3::from({
                let mut a = [0.0; 3];
                a[axis] = sign;
                a
            });
            let (u, v) = plane_frame(n);
            let (e1, e2) = (2.0 * u * u.abs().dot(h), 2.0 * v * v.abs().dot(h));
            let q = quad(n * h - 0.5 * (e1 + e2), e1, e2);
            let base = out.positions.len() as u32;
            out.positions.extend(q.positions);
            out.indices.extend(q.indices.iter().map(|t| t.map(|i| i + base)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn closed(t: &Tessellation) -> bool {
        // every edge between distinct positions is shared by exactly two triangles
        let key = |p: Vec3| p.to_array().map(|c| (c * 1e5).round() as i64);
        let mut edges: HashMap<([i64; 3], [i64; 3]), i32> = HashMap::new();
        for tri in &t.indices {
            for k in 0..3 {
                let (a, b) = (key(t.positions[tri[k] as usize]), key(t.positions[tri[(k + 1) % 3] as usize]));
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        edges.values().all(|&c| c == 2)
    }

    /// The enclosed volume by the divergence theorem: positive when every triangle faces out.
    fn volume(t: &Tessellation) -> f32 {
        t.indices
            .iter()
            .map(|i| {
                let [a, b, c] = i.map(|k| t.positions[k as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

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
        let s = sphere(Vec3::new(1.0, 2.0, 3.0), 2.0, 4);
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

    #[test]
    fn solids_are_closed_outward_and_keep_their_areas() {
        let (r, h) = (0.7f32, 2.5f32);
        let cases: [(&str, Tessellation, f32, f32); 4] = [
            ("cylinder", cylinder(r, h, 64), 2.0 * PI * r * (r + h), PI * r * r * h),
            ("cone", cone(r, h, 64), PI * r * (r + (r * r + h * h).sqrt()), PI * r * r * h / 3.0),
            ("capsule", capsule(r, h, 64, 16), 2.0 * PI * r * h + 4.0 * PI * r * r, PI * r * r * (h + 4.0 / 3.0 * r)),
            ("box", cuboid(Vec3::new(1.0, 2.0, 3.0)), 22.0, 6.0),
        ];
        for (name, t, a, v) in cases {
            assert!(closed(&t), "{name} is not closed");
            // the side areas are exact; caps and hemispheres are polygons (within 0.5%)
            assert!((area(&t) / a - 1.0).abs() < 5e-3, "{name}: area {} vs {a}", area(&t));
            assert!(volume(&t) > 0.0 && (volume(&t) / v - 1.0).abs() < 1e-2, "{name}: volume {} vs {v}", volume(&t));
            if let Some(n) = &t.normals {
                assert_eq!(n.len(), t.positions.len());
                assert!(n.iter().all(|n| (n.length() - 1.0).abs() < 1e-5), "{name}");
            }
        }
        // the open side keeps the exact lateral area
        let s = cylinder_side(r, h, 16);
        assert!((area(&s) / (2.0 * PI * r * h) - 1.0).abs() < 1e-5);
        // the cone's apex is at +height/2
        let c = cone(r, h, 16);
        assert!(c.positions.iter().all(|p| p.z <= 0.5 * h + 1e-6) && c.positions.iter().any(|p| p.z == 0.5 * h));
    }
}
