//! The continued set C of docs/architecture.md §7.5: directions within theta_c of a glossy
//! BSDF's ideal mirror or refraction direction (the quasi-specular cone), and the whole
//! hemisphere of a narrow lobe whose other lobe is gathered (the narrow refraction of a rough
//! glass face whose reflection is wide). Paths continue through C without gathering; direct
//! light and photons are gathered over the complement C' only.

use glam::Vec3;
use quasar_materials::Bsdf;

/// The continued set C of one vertex, in its local frame: cone(s) around the ideal scattering
/// directions and, optionally, one whole hemisphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuasiCone {
    /// Unit cone axes: the mirror direction and, for dielectrics, the refraction direction.
    axes: [Option<Vec3>; 2],
    /// cos(theta_c).
    cos_half_angle: f32,
    /// The sign of the local z of the continued hemisphere (+1 or -1), or 0 when no hemisphere
    /// is continued.
    hemisphere: f32,
}

impl QuasiCone {
    /// The cone of a vertex with BSDF `bsdf` seen from `wo` (local), half-angle acos(`cos_half_angle`).
    /// None for BSDFs without a lobe around an ideal direction (Lambertian, black): every event
    /// there is an ordinary non-specular one.
    pub fn at(bsdf: &Bsdf, wo: Vec3, cos_half_angle: f32) -> Option<Self> {
        let (m, t) = bsdf.ideal_directions(wo);
        if m.is_none() && t.is_none() {
            return None;
        }
        Some(Self { axes: [m, t], cos_half_angle, hemisphere: 0.0 })
    }

    /// The set of `cone` (or no cone) with the hemisphere on the side `z_sign` (+1: local z > 0)
    /// of the local frame added.
    pub fn with_hemisphere(cone: Option<Self>, z_sign: f32) -> Self {
        let hemisphere = z_sign.signum();
        match cone {
            Some(c) => Self { hemisphere, ..c },
            None => Self { axes: [None, None], cos_half_angle: 1.0, hemisphere },
        }
    }

    /// True when the local direction `w` lies inside the cone(s) or the continued hemisphere.
    #[inline]
    pub fn contains(&self, w: Vec3) -> bool {
        w.z * self.hemisphere > 0.0 || self.axes.iter().flatten().any(|a| a.dot(w) > self.cos_half_angle * w.length())
    }
}

/// Whether direction `w` (local) is excluded from an estimate restricted to C'.
#[inline]
pub fn in_cone(cone: &Option<QuasiCone>, w: Vec3) -> bool {
    cone.as_ref().is_some_and(|c| c.contains(w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_materials::Material;
    use quasar_materials::spectrum::{SampledWavelengths, Spectrum};

    #[test]
    fn cone_contains_directions_near_the_mirror_and_refraction_directions() {
        let mut wl = SampledWavelengths::sample_uniform(0.5);
        let glass =
            Material::Dielectric { ior: quasar_materials::Ior::Constant(1.5), alpha: 0.05, transmittance: None }
                .bsdf(&mut wl);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let cone = QuasiCone::at(&glass, wo, 10f32.to_radians().cos()).unwrap();
        assert!(cone.contains(Vec3::new(-0.6, 0.0, 0.8)));
        assert!(cone.contains(Vec3::new(-0.62, 0.05, 0.78).normalize()));
        assert!(!cone.contains(Vec3::new(0.0, 0.0, 1.0)));
        // Snell: sin t = 0.6 / 1.5 = 0.4
        let t = Vec3::new(-0.4, 0.0, -(1.0f32 - 0.16).sqrt());
        assert!(cone.contains(t));
        assert!(!cone.contains(Vec3::new(0.0, 0.0, -1.0)));
        // the refraction hemisphere added: every transmitted direction, no other reflected one
        let split = QuasiCone::with_hemisphere(Some(cone), -1.0);
        assert!(split.contains(Vec3::new(0.0, 0.0, -1.0)) && split.contains(Vec3::new(0.9, 0.0, -0.1)));
        assert!(split.contains(Vec3::new(-0.6, 0.0, 0.8)) && !split.contains(Vec3::new(0.0, 0.0, 1.0)));
        let hemisphere_only = QuasiCone::with_hemisphere(None, 1.0);
        assert!(hemisphere_only.contains(Vec3::new(0.3, 0.0, 0.1)) && !hemisphere_only.contains(-Vec3::Z));
        let diffuse = Material::Diffuse { reflectance: Spectrum::Constant(0.5), two_sided: true }.bsdf(&mut wl);
        assert!(QuasiCone::at(&diffuse, wo, 0.9).is_none());
    }
}
