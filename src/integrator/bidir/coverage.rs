//! The share of a gather disk that can receive photons: the geometry-aware normalisation of the
//! photon density estimate.
//!
//! L^I = sum(f Phi) / (N pi r^2) assumes that the whole disk of radius r around a visibility
//! point is surface the photons could land on. Near an edge of the surface (the side of a wall,
//! the rim of a plate), at a contact with another object (a box standing on the floor) or in a
//! corner, part of the disk lies off the surface or under something, receives no photon that
//! passes the gather tests, and the estimate is too dark there by that share (a first-order
//! bias in r, the largest of photon mapping at practical radii). The covered share c is
//! measured with probe rays along the normal at points spread evenly over the disk (a Vogel
//! spiral), accepting the same surfaces a photon would be accepted on (normal within 60
//! degrees, within a quarter radius of the tangent plane), and the estimate divides by
//! pi r^2 c. Where the four outermost probes are all covered the disk is taken as fully
//! covered (one ray each for the interior of a surface).

use glam::Vec3;
use quasar_materials::Frame;

use super::gather_disk::{MAX_PLANE_DISTANCE, MIN_NORMAL_COS};
use super::visibility_point::VisibilityPoint;
use crate::core::geometry::Ray;
use crate::core::scene::Scene;

/// Probe points per disk.
pub const PROBES: usize = 16;
/// Probes that lie inside half the radius (the caustic disk): j < PROBES / 4.
const INNER_PROBES: usize = PROBES / 4;
/// The golden angle (radians): successive probes of the spiral turn by it.
const GOLDEN_ANGLE: f32 = 2.399_963_2;

/// Whether a surface a photon could be gathered from lies along the normal at probe `j` of the
/// disk of radius `r` around `vp` (turned by `rotation` radians).
fn covered(scene: &Scene, vp: &VisibilityPoint, frame: &Frame, side: f32, r: f32, j: usize, rotation: f32) -> bool {
    let rho = r * ((j as f32 + 0.5) / PROBES as f32).sqrt();
    let phi = j as f32 * GOLDEN_ANGLE + rotation;
    let q = vp.p + frame.from_local(Vec3::new(rho * phi.cos(), rho * phi.sin(), 0.0));
    let h = MAX_PLANE_DISTANCE * r;
    let dir = -vp.ng * side;
    let mut origin = q + vp.ng * (side * h);
    let mut left = 2.0 * h;
    // surfaces a photon would not be gathered from (the underside of an object overhanging the
    // disk, a wall across it) are passed: photons reach the surface below them sideways
    for _ in 0..4 {
        let mut ray = Ray::new(origin, dir);
        ray.t_max = left;
        let Some(hit) = scene.intersect_geometry(&ray) else { return false };
        if hit.ng.dot(vp.ng) >= MIN_NORMAL_COS {
            return true;
        }
        left -= hit.t;
        origin = hit.spawn_ray(dir).origin;
    }
    false
}

/// Covered shares (indirect disk of radius `r`, caustic disk of radius `r_caustic` <= r / 2)
/// of the gather disks of `vp`, each at least one probe's share.
#[inline(always)]
pub fn disk_coverage(scene: &Scene, vp: &VisibilityPoint, r: f32, r_caustic: f32, rotation: f32) -> (f32, f32) {
    if !(r > 0.0 && r.is_finite()) {
        return (1.0, 1.0);
    }
    let frame = Frame::from_z(vp.ng);
    let side = if vp.viewer_above { 1.0 } else { -1.0 };
    // the four outermost probes first, up to the first one that misses (kept for the share)
    let mut hits = [false; PROBES];
    let mut traced = PROBES - 4..PROBES - 4;
    for (j, hit) in hits.iter_mut().enumerate().skip(PROBES - 4) {
        *hit = covered(scene, vp, &frame, side, r, j, rotation);
        traced.end = j + 1;
        if !*hit {
            break;
        }
    }
    if hits[PROBES - 4..].iter().all(|&h| h) {
        return (1.0, 1.0);
    }
    for j in (0..PROBES).filter(|j| !traced.contains(j)) {
        hits[j] = covered(scene, vp, &frame, side, r, j, rotation);
    }
    let share = |h: &[bool]| (h.iter().filter(|&&b| b).count().max(1) as f32) / h.len() as f32;
    let indirect = share(&hits);
    // the caustic disk: probes within its radius (r_c = r / 2 by default)
    let caustic = if r_caustic * 2.0 <= r * 1.0001 {
        share(&hits[..INNER_PROBES])
    } else {
        let hits: [bool; PROBES] = std::array::from_fn(|j| covered(scene, vp, &frame, side, r_caustic, j, rotation));
        share(&hits)
    };
    (indirect, caustic)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::PathClass;
    use quasar_importers::ImportOptions;
    use quasar_importers::parse_toml_scene;
    use quasar_materials::Bsdf;
    use quasar_materials::spectrum::SampledSpectrum;

    /// A 2 x 2 floor and a small panel 0.5 above it, lengths times `scale`.
    fn floor_with_panel(scale: f32) -> Scene {
        let text = r#"
[materials.white]
type = "diffuse"
reflectance = 0.5
[[shape]]
type = "quad"
center = [0, 0, 0]
size = [2, 2]
normal = [0, 1, 0]
material = "white"
[[shape]]
type = "quad"
center = [0.5, 0.5, 0.5]
size = [0.2, 0.2]
normal = [0, -1, 0]
material = "white"
"#;
        let opts = ImportOptions { units_scale: Some(scale), ..ImportOptions::default() };
        let desc = parse_toml_scene(text, std::path::Path::new("t.toml"), &opts).unwrap();
        Scene::compile(&desc).unwrap()
    }

    fn point(p: Vec3) -> VisibilityPoint<'static> {
        VisibilityPoint {
            p,
            ng: Vec3::Y,
            frame: Frame::from_z(Vec3::Y),
            wo_local: Vec3::Z,
            bsdf: Bsdf::Black,
            beta: SampledSpectrum::one(),
            class: PathClass::default(),
            depth: 0,
            footprint_distance: 1.0,
            cone: None,
            viewer_above: true,
        }
    }

    #[test]
    fn shares_equal_those_of_every_probe_traced() {
        // the early exit and the reuse of the outer probes change nothing: the shares are those
        // of all probes traced one by one, on disks inside, across edges and corners, and under
        // the panel
        let scene = floor_with_panel(1.0);
        let mut n_partial = 0;
        for k in 0..400 {
            let u = |m: u32| ((k * m + 7) % 101) as f32 / 100.0;
            let p = Vec3::new(2.4 * u(37) - 1.2, 0.0, 2.4 * u(53) - 1.2);
            let (r, rotation) = (0.05 + 0.3 * u(29), 6.0 * u(11));
            let r_caustic = if k % 2 == 0 { r / 2.0 } else { r * 0.7 };
            let vp = point(p);
            let frame = Frame::from_z(vp.ng);
            let all = |r: f32| -> [bool; PROBES] {
                std::array::from_fn(|j| covered(&scene, &vp, &frame, 1.0, r, j, rotation))
            };
            let share = |h: &[bool]| (h.iter().filter(|&&b| b).count().max(1) as f32) / h.len() as f32;
            let hits = all(r);
            let expected = if hits[PROBES - 4..].iter().all(|&h| h) {
                (1.0, 1.0)
            } else {
                n_partial += 1;
                let caustic = if k % 2 == 0 { share(&hits[..INNER_PROBES]) } else { share(&all(r_caustic)) };
                (share(&hits), caustic)
            };
            assert_eq!(disk_coverage(&scene, &vp, r, r_caustic, rotation), expected, "disk {k} at {p} radius {r}");
        }
        assert!(n_partial > 50, "only {n_partial} partly covered disks");
    }

    #[test]
    fn coverage_of_interior_edge_and_corner_disks() {
        for scale in [1.0, 1e-4, 1e5] {
            coverage_at_scale(scale);
        }
    }

    fn coverage_at_scale(k: f32) {
        let scene = floor_with_panel(k);
        let c = |p: Vec3, r: f32| disk_coverage(&scene, &point(p * k), r * k, r * k / 2.0, 0.3);
        assert_eq!(c(Vec3::new(-0.5, 0.0, -0.5), 0.1), (1.0, 1.0));
        // on the edge x = 1: half the disk is off the floor
        let (ci, cc) = c(Vec3::new(1.0, 0.0, -0.5), 0.1);
        assert!((ci - 0.5).abs() <= 0.125, "{ci}");
        assert!((cc - 0.5).abs() <= 0.25, "{cc}");
        // a corner: a quarter
        let (ci, _) = c(Vec3::new(1.0, 0.0, 1.0), 0.1);
        assert!((ci - 0.25).abs() <= 0.125, "{ci}");
        // a panel 0.5 above the floor is not within a quarter radius of its plane: not in the way
        assert_eq!(c(Vec3::new(0.5, 0.0, 0.5), 0.1), (1.0, 1.0));
    }
}
