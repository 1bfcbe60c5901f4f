//! Pinhole perspective camera (look-at, field of view along a chosen image axis).

use glam::{Vec2, Vec3};
use quasar_importers::{CameraDesc, FovAxis};

use crate::core::geometry::Ray;

/// A pinhole camera: image row 0 at the top, image right = forward x up.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// tan(half field of view) along x and y.
    tan_half: Vec2,
    width: u32,
    height: u32,
}

/// Error for a camera that cannot form an image.
#[derive(Debug, thiserror::Error)]
#[error("invalid camera: {0}")]
pub struct CameraError(pub String);

impl Camera {
    /// From a description and the image size.
    pub fn new(desc: &CameraDesc, width: u32, height: u32) -> Result<Self, CameraError> {
        let forward = (desc.target - desc.position).normalize_or_zero();
        if forward == Vec3::ZERO || !forward.is_finite() {
            return Err(CameraError("target equals position".into()));
        }
        let right = forward.cross(desc.up).normalize_or_zero();
        if right == Vec3::ZERO || !right.is_finite() {
            return Err(CameraError("up is parallel to the view direction".into()));
        }
        if !(desc.fov_deg > 0.0 && desc.fov_deg < 180.0) {
            return Err(CameraError(format!("fov_deg must be in (0, 180), got {}", desc.fov_deg)));
        }
        if width == 0 || height == 0 {
            return Err(CameraError("image size must be positive".into()));
        }
        let up = right.cross(forward);
        let t = (desc.fov_deg.to_radians() * 0.5).tan();
        let aspect = width as f32 / height as f32;
        let tan_half = match desc.fov_axis {
            FovAxis::X => Vec2::new(t, t / aspect),
            FovAxis::Y => Vec2::new(t * aspect, t),
        };
        Ok(Self { position: desc.position, forward, right, up, tan_half, width, height })
    }

    /// The primary ray through image position (x, y) in pixels (continuous: pixel (i, j) spans
    /// [i, i+1) x [j, j+1); y grows downwards).
    pub fn ray(&self, film: Vec2) -> Ray {
        let sx = (2.0 * film.x / self.width as f32 - 1.0) * self.tan_half.x;
        let sy = (1.0 - 2.0 * film.y / self.height as f32) * self.tan_half.y;
        let d = (self.forward + self.right * sx + self.up * sy).normalize();
        Ray::new(self.position, d)
    }

    /// Eye position.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Solid angle subtended by one pixel at the image centre (steradians), for footprint estimates.
    pub fn pixel_solid_angle(&self) -> f32 {
        (2.0 * self.tan_half.x / self.width as f32) * (2.0 * self.tan_half.y / self.height as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(axis: FovAxis) -> Camera {
        let d = CameraDesc { position: Vec3::ZERO, target: -Vec3::Z, up: Vec3::Y, fov_deg: 90.0, fov_axis: axis };
        Camera::new(&d, 200, 100).unwrap()
    }

    #[test]
    fn image_orientation_and_fov_axis() {
        let c = cam(FovAxis::X);
        // centre looks at target
        assert!((c.ray(Vec2::new(100.0, 50.0)).dir - -Vec3::Z).length() < 1e-6);
        // right edge at 45 degrees horizontally (fov_x = 90), +x is image right
        let r = c.ray(Vec2::new(200.0, 50.0)).dir;
        assert!((r.x - r.z.abs()).abs() < 1e-6 && r.x > 0.0);
        // row 0 is the top (+y)
        assert!(c.ray(Vec2::new(100.0, 0.0)).dir.y > 0.0);
        let c = cam(FovAxis::Y);
        let t = c.ray(Vec2::new(100.0, 0.0)).dir;
        assert!((t.y - t.z.abs()).abs() < 1e-6);
    }

    #[test]
    fn degenerate_cameras_are_errors() {
        let mut d = CameraDesc::default();
        d.up = d.target - d.position;
        assert!(Camera::new(&d, 10, 10).is_err());
        let d = CameraDesc { fov_deg: 180.0, ..CameraDesc::default() };
        assert!(Camera::new(&d, 10, 10).is_err());
    }
}
