//! Angles of tabulated BSDFs: the face frame, the incidence plane, the lobe axis (mirror or
//! refraction direction) and the two grid coordinate systems (absolute and specular-relative).
//!
//! Conventions (materials/README.md): a face's frame has z along the normal on the side the light
//! arrives from; the back face's frame is the front's rotated by pi about x. The *plane frame* is
//! the face frame rotated about z so that the incident direction is (-sin ti, 0, cos ti): the
//! mirror direction then lies at +x ("forward"), and phi = 0 of both grids points forward.

use std::f32::consts::TAU;

use glam::Vec3;

/// Maps a local-frame direction to the frame of the front (`back = false`) or back face: the back
/// face's frame is the front's rotated by pi about x, (x, y, z) -> (x, -y, -z). An involution.
#[inline]
pub(crate) fn to_face(v: Vec3, back: bool) -> Vec3 {
    if back { Vec3::new(v.x, -v.y, -v.z) } else { v }
}

/// An incident direction (face frame, z >= 0): its polar angle, azimuth and the rotation about z
/// by psi = phi + pi that takes the face frame to the plane frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Incidence {
    /// Polar angle from the normal (radians).
    pub theta: f32,
    /// Azimuth in [0, 2 pi) (0 at normal incidence).
    pub phi: f32,
    cos_psi: f32,
    sin_psi: f32,
}

impl Incidence {
    /// The incidence of face-frame direction `d` (pointing towards the light, `d.z >= 0`).
    pub fn of(d: Vec3) -> Self {
        let r = (d.x * d.x + d.y * d.y).sqrt();
        let theta = r.atan2(d.z);
        if r > 0.0 {
            let mut phi = d.y.atan2(d.x);
            if phi < 0.0 {
                phi += TAU;
            }
            Self { theta, phi: if phi >= TAU { 0.0 } else { phi }, cos_psi: -d.x / r, sin_psi: -d.y / r }
        } else {
            Self { theta, phi: 0.0, cos_psi: -1.0, sin_psi: 0.0 }
        }
    }

    /// Face frame -> plane frame (rotation about z by -psi).
    #[inline]
    pub fn face_to_plane(self, v: Vec3) -> Vec3 {
        Vec3::new(self.cos_psi * v.x + self.sin_psi * v.y, -self.sin_psi * v.x + self.cos_psi * v.y, v.z)
    }

    /// Plane frame -> face frame.
    #[inline]
    pub fn plane_to_face(self, v: Vec3) -> Vec3 {
        Vec3::new(self.cos_psi * v.x - self.sin_psi * v.y, self.sin_psi * v.x + self.cos_psi * v.y, v.z)
    }
}

/// The axis of a specular-relative lobe in the plane frame for incidence angle `theta_i`: the
/// mirror direction (sin ti, 0, cos ti), or for transmission the Snell refraction direction
/// (sin tt, 0, -cos tt) with sin tt = min(sin ti / eta, 1) (`eta` = IOR of the far side over the
/// incident side). Beyond the critical angle the axis stays at the horizon, where a rough
/// interface's transmitted light leaves, so the lobe moves continuously with the incidence.
#[inline]
pub(crate) fn lobe_axis(theta_i: f32, transmit: bool, eta: f32) -> Vec3 {
    let (s, c) = theta_i.sin_cos();
    if !transmit {
        return Vec3::new(s, 0.0, c);
    }
    let st = if eta > 0.0 { (s / eta).clamp(0.0, 1.0) } else { 1.0 };
    Vec3::new(st, 0.0, -(1.0 - st * st).max(0.0).sqrt())
}

/// The tangent basis (e1, e2) around a lobe axis `c = (sx, 0, cz)` of the plane frame: e1 points
/// from the axis towards the normal line on the lobe's side (phi = 0 of Zemax-style
/// specular-relative data), e2 = +y.
#[inline]
fn axis_basis(c: Vec3, transmit: bool) -> (Vec3, Vec3) {
    let sign = if transmit { -1.0 } else { 1.0 };
    (Vec3::new(-c.z.abs(), 0.0, sign * c.x), Vec3::Y)
}

/// Grid coordinates (theta, phi in [0, 2 pi)) of plane-frame direction `v`: around `axis` for a
/// specular-relative grid, else the polar angle from the normal on the lobe's side (reflection:
/// +z, transmission: -z) and the azimuth from +x. Small angles are computed with atan2 (exact
/// for lobes far narrower than 1 degree).
#[inline]
pub(crate) fn grid_coords(v: Vec3, axis: Option<Vec3>, transmit: bool) -> (f32, f32) {
    let (x0, x1, x2) = match axis {
        Some(c) => {
            let (e1, e2) = axis_basis(c, transmit);
            (v.dot(c), v.dot(e1), v.dot(e2))
        }
        None => (if transmit { -v.z } else { v.z }, v.x, v.y),
    };
    let theta = (x1 * x1 + x2 * x2).sqrt().atan2(x0);
    let mut phi = x2.atan2(x1);
    if phi < 0.0 {
        phi += TAU;
    }
    (theta, if phi >= TAU { 0.0 } else { phi })
}

/// The plane-frame direction at grid coordinates (theta, phi) where `h = sin^2(theta / 2)`
/// (sin theta = 2 sqrt(h (1 - h)), cos theta = 1 - 2 h: precise for tiny angles); the inverse of
/// [`grid_coords`].
#[inline]
pub(crate) fn grid_direction(h: f32, phi: f32, axis: Option<Vec3>, transmit: bool) -> Vec3 {
    let h = h.clamp(0.0, 1.0);
    let sin_t = 2.0 * (h * (1.0 - h)).sqrt();
    let cos_t = 1.0 - 2.0 * h;
    let (sp, cp) = phi.sin_cos();
    match axis {
        Some(c) => {
            let (e1, e2) = axis_basis(c, transmit);
            cos_t * c + sin_t * (cp * e1 + sp * e2)
        }
        None => Vec3::new(sin_t * cp, sin_t * sp, if transmit { -cos_t } else { cos_t }),
    }
}

/// sin^2(theta / 2) = (1 - cos theta) / 2: the solid angle of a polar cap is 4 pi h.
#[inline]
pub(crate) fn half_versine(theta: f32) -> f32 {
    let s = (0.5 * theta).sin();
    s * s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_frame_puts_incidence_at_minus_x() {
        let d = Vec3::new(0.3, -0.5, 0.7).normalize();
        let inc = Incidence::of(d);
        let p = inc.face_to_plane(d);
        assert!((p.x + inc.theta.sin()).abs() < 1e-6 && p.y.abs() < 1e-6, "{p}");
        assert!((inc.plane_to_face(p) - d).length() < 1e-6);
    }

    #[test]
    fn grid_coordinates_round_trip_and_resolve_tiny_angles() {
        for (axis, transmit) in [
            (None, false),
            (None, true),
            (Some(lobe_axis(0.6, false, 1.5)), false),
            (Some(lobe_axis(0.6, true, 1.5)), true),
            (Some(lobe_axis(0.0, true, 0.7)), true),
            (Some(lobe_axis(1.2, true, 0.7)), true),
        ] {
            for (theta, phi) in [(1e-5f32, 0.3f32), (0.01, 5.0), (0.4, 1.0), (1.2, 3.5)] {
                let v = grid_direction(half_versine(theta), phi, axis, transmit);
                assert!((v.length() - 1.0).abs() < 1e-5);
                let (t, p) = grid_coords(v, axis, transmit);
                assert!((t - theta).abs() < 1e-4 * theta.max(1e-3), "{axis:?} {theta} -> {t}");
                assert!((p - phi).abs() < 1e-3, "{axis:?} {phi} -> {p}");
            }
        }
    }

    #[test]
    fn specular_phi_zero_points_towards_the_normal() {
        let c = lobe_axis(0.5, false, 1.0);
        let v = grid_direction(half_versine(0.1), 0.0, Some(c), false);
        assert!(v.z > c.z && v.y.abs() < 1e-6, "phi = 0 turns the axis towards the normal: {v}");
        let t = lobe_axis(1.2, true, 1.0 / 1.5);
        assert!(t.z == 0.0 && t.x == 1.0, "beyond the critical angle the axis is at the horizon: {t}");
    }
}
