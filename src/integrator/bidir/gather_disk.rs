//! A visibility point's gather disk (docs/architecture.md §7.4): the region around the point in
//! which a photon hit counts there, a flattened disk of radius r (Jensen 2001, 7.2), and the
//! box around it the grid enters the point with.

use super::grid::GatherRegion;

/// Cosine of the largest angle (60 degrees) between the surface normals of a photon hit and a
/// visibility point for the photon to count there: keeps photons on one side of a thin object
/// (a plate on a table) or on the other wall of a corner from lighting the other. The excluded
/// set shrinks to the surfaces' creases as the radius shrinks, so the estimate stays consistent.
pub const MIN_NORMAL_COS: f32 = 0.5;
/// Largest distance of a photon hit from the visibility point's tangent plane, as a fraction of
/// the gather radius: the gather region is a flattened disk, not a ball (Jensen 2001, 7.2), so a
/// photon on a nearby parallel surface (the inside of a thin wall, an object within an object)
/// is not counted. A sphere of radius R deviates from its tangent plane by s^2 / (2R) at distance
/// s, so nothing of a curved surface is excluded while r < R / 2.
pub const MAX_PLANE_DISTANCE: f32 = 0.25;

/// A visibility point's gather disk in the current iteration: centre, normal and radii, 32
/// bytes in one cache line, what a photon's first tests read. Most of a grid cell's
/// candidates are out of a photon's reach; testing them here instead of in the points (a few
/// cache lines each) and their radii keeps the photon pass from waiting on memory once the
/// points outgrow the caches (`auto`, glossy room, 1024x768: the photon pass took 1.8x the time
/// per pixel of 128x96; BENCHMARKS.md "Photon look-ups at large images").
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GatherDisk {
    /// The visibility point's position.
    pub p: glam::Vec3,
    /// Radius for photons that bounced off non-specular surfaces before.
    pub indirect: f32,
    /// The point's unit geometric normal.
    pub ng: glam::Vec3,
    /// Radius for caustic photons.
    pub caustic: f32,
}

/// The region a photon must land in: within the larger radius r of the point and within
/// h = [`MAX_PLANE_DISTANCE`] r of its tangent plane. Along a unit axis e its box reaches
/// max(d . e) over |d| <= r, |d . n| <= h: r where r |n . e| <= h, else
/// h |n . e| + sqrt(r^2 - h^2) sqrt(1 - (n . e)^2) (the maximum on the slab's face), taken 0.1%
/// wider for the rounding of n and of the photon's test, and never more than r. A floor's or
/// a wall's disk is entered in the cells of a box a quarter of the radius thick instead of the
/// ball's.
impl GatherRegion for GatherDisk {
    #[inline]
    fn centre_radius_extent(&self) -> (glam::Vec3, f32, glam::Vec3) {
        let r = self.indirect.max(self.caustic);
        let h = MAX_PLANE_DISTANCE * r;
        let n = self.ng.abs();
        let slab = (n * h + (1.0 - n * n).max(glam::Vec3::ZERO).map(f32::sqrt) * (r * r - h * h).sqrt()) * 1.001;
        let extent = glam::Vec3::select(
            (n * r).cmple(glam::Vec3::splat(h)),
            glam::Vec3::splat(r),
            slab.min(glam::Vec3::splat(r)),
        );
        (self.p, r, extent)
    }
}

impl GatherDisk {
    /// Whether a photon hit at `p` on a surface with unit geometric normal `ng` lies in the
    /// disk: within the class's radius (caustic or indirect), its surface normal within
    /// [`MIN_NORMAL_COS`] of the disk's, within [`MAX_PLANE_DISTANCE`] r of its tangent plane.
    #[inline(always)]
    pub fn holds(&self, p: glam::Vec3, ng: glam::Vec3, caustic: bool) -> bool {
        let r = if caustic { self.caustic } else { self.indirect };
        let d = p - self.p;
        !(d.length_squared() > r * r
            || self.ng.dot(ng) < MIN_NORMAL_COS
            || d.dot(self.ng).abs() > MAX_PLANE_DISTANCE * r)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use glam::Vec3;

    use super::*;
    use crate::core::sampling::{Sampler, uniform_sphere};
    use crate::integrator::bidir::grid::VisibilityGrid;

    /// Normals along the axes, just off them, at 45 degrees and random (also the points of
    /// `arrival`'s test).
    pub(in crate::integrator::bidir) fn normals(s: &mut Sampler) -> Vec<Vec3> {
        let mut n = vec![Vec3::X, Vec3::NEG_Y, Vec3::Z, Vec3::new(1.0, 1e-4, 0.0).normalize(), Vec3::ONE.normalize()];
        n.extend((0..200).map(|_| uniform_sphere(s.get_2d())));
        n
    }

    #[test]
    fn a_disks_box_holds_the_region_tightly() {
        // the farthest reach of {|d| <= r, |d . n| <= h} along each axis, found by brute force
        // over the region's boundary, is inside the box and at least 95% of it (a box no
        // larger than needed), and the box is never larger than the ball's
        let mut s = Sampler::new(3, 1, 4);
        for n in normals(&mut s) {
            let disk = GatherDisk { p: Vec3::new(1.0, -2.0, 3.0), indirect: 0.2, ng: n, caustic: 0.1 };
            let (p, r, e) = disk.centre_radius_extent();
            assert_eq!((p, r), (disk.p, 0.2));
            let h = MAX_PLANE_DISTANCE * r;
            let mut reach = Vec3::ZERO;
            for _ in 0..20_000 {
                let dir = uniform_sphere(s.get_2d());
                // the ray from the centre along dir leaves the region at the sphere or at the slab
                let t = if dir.dot(n).abs() * r > h { h / dir.dot(n).abs() } else { r };
                reach = reach.max((dir * t).abs());
            }
            assert!(reach.cmple(e).all(), "n {n}: reach {reach} outside the box {e}");
            assert!(e.cmple(Vec3::splat(r)).all(), "n {n}: box {e}");
            assert!((reach / e).cmpge(Vec3::splat(0.95)).all(), "n {n}: reach {reach}, box {e}");
        }
    }

    #[test]
    fn every_photon_a_disk_accepts_finds_it_in_the_grid() {
        // disks on random planes with radii spread over 10x; photons inside each disk's region,
        // half of them at its rim, must find the point among the grid's candidates
        let mut s = Sampler::new(5, 9, 2);
        let ns = normals(&mut s);
        let disks: Vec<GatherDisk> = (0..3000)
            .map(|k| {
                let r = 0.01 + 0.1 * s.get_1d();
                let p = Vec3::new(s.get_1d(), s.get_1d(), s.get_1d()) * 4.0 - 2.0;
                GatherDisk { p, indirect: r, ng: ns[k % ns.len()], caustic: 0.5 * r }
            })
            .collect();
        let grid = VisibilityGrid::build(&disks);
        let mut tested = 0;
        for (i, disk) in disks.iter().enumerate() {
            let r = disk.indirect;
            let h = MAX_PLANE_DISTANCE * r;
            for _ in 0..30 {
                let dir = uniform_sphere(s.get_2d());
                let t = if dir.dot(disk.ng).abs() * r > h { h / dir.dot(disk.ng).abs() } else { r };
                let d = dir * t * if s.get_1d() < 0.5 { 1.0 - 1e-6 } else { s.get_1d() };
                if d.length_squared() <= r * r && d.dot(disk.ng).abs() <= h {
                    tested += 1;
                    assert!(grid.candidates(disk.p + d).contains(&(i as u32)), "disk {i} missing at {d}");
                }
            }
        }
        assert!(tested > 80_000, "{tested}");
    }
}
