//! The glTF metallic-roughness model mapped onto quasar's analytic materials (one place, used by
//! the glTF importer for material factors and by the renderer for textured materials at hits,
//! with the parameters its textures give there).
//!
//! quasar has one analytic lobe per material, so the layered glTF model is reduced to its dominant
//! lobe (documented in `docs/gltf.md`):
//! - `transmission >= 0.5` and `metallic < 0.5` -> [`Material::Dielectric`] with the glTF `ior`
//!   (KHR_materials_ior, default 1.5) whose transmitted light the base colour tints at every
//!   crossing (the glTF specification's and Cycles' Principled BSDF's reading; a solid glass is
//!   crossed twice).
//! - `metallic >= 0.5` -> [`Material::Conductor`] with the angle-independent Fresnel reflectance
//!   F0 = base colour (bounded RGB uplift).
//! - otherwise -> [`Material::Diffuse`] (Lambertian) with reflectance = base colour; the
//!   dielectric specular layer (F0 = 0.04) is dropped.
//! - `clearcoat >= 0.5` (KHR_materials_clearcoat) puts the metal or the diffuse lobe under a
//!   [`Material::Coated`] coat of IOR 1.5 (the extension's) and GGX alpha
//!   `clearcoat_roughness^2`; a coat over glass is dropped (the importer warns). A factor below
//!   0.5 leaves the surface uncoated: as for the lobes above, the dominant layer is rendered.
//! - a non-black `sheen_color` (KHR_materials_sheen) puts the uncoated metal or diffuse lobe
//!   under a [`Material::Sheen`] of that colour and Charlie alpha `sheen_roughness^2`; with a
//!   clear coat the coat is rendered and the sheen dropped (the importer warns).
//!
//! In every case the GGX alpha is `roughness^2` (the glTF convention) and surfaces reflect on
//! both sides.

use crate::coating::Coating;
use crate::material::{ConductorFresnel, Ior, Material};
use crate::spectrum::Spectrum;

/// Threshold of `metallic` (and `transmission`) above which the metal (glass) lobe is chosen.
pub const PBR_LOBE_THRESHOLD: f32 = 0.5;

/// The glTF metallic-roughness parameters of one surface point (factors times texels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PbrParams {
    /// Linear base colour (RGB), clamped to [0, 1] by [`pbr_material`].
    pub base_color: [f32; 3],
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness in [0, 1] (GGX alpha = roughness^2).
    pub roughness: f32,
    /// KHR_materials_transmission factor in [0, 1].
    pub transmission: f32,
    /// KHR_materials_ior (relative IOR of the inside, >= 1).
    pub ior: f32,
    /// KHR_materials_clearcoat `clearcoatFactor` in [0, 1] (0: no coat).
    pub clearcoat: f32,
    /// KHR_materials_clearcoat `clearcoatRoughnessFactor` in [0, 1] (GGX alpha = its square).
    pub clearcoat_roughness: f32,
    /// KHR_materials_sheen `sheenColorFactor`, linear RGB in [0, 1] (black: no sheen).
    pub sheen_color: [f32; 3],
    /// KHR_materials_sheen `sheenRoughnessFactor` in [0, 1] (Charlie alpha = its square).
    pub sheen_roughness: f32,
}

impl Default for PbrParams {
    fn default() -> Self {
        Self {
            base_color: [1.0; 3],
            metallic: 1.0,
            roughness: 1.0,
            transmission: 0.0,
            ior: 1.5,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            sheen_color: [0.0; 3],
            sheen_roughness: 0.0,
        }
    }
}

/// True when [`pbr_material`] puts a clear coat over the parameters' surface: a clear coat
/// factor >= [`PBR_LOBE_THRESHOLD`] over a metal or a non-transmissive dielectric.
pub fn is_coated(p: &PbrParams) -> bool {
    unit(p.clearcoat) >= PBR_LOBE_THRESHOLD
        && !(unit(p.transmission) >= PBR_LOBE_THRESHOLD && unit(p.metallic) < PBR_LOBE_THRESHOLD)
}

/// Clamps to [0, 1]; NaN becomes 0.
fn unit(x: f32) -> f32 {
    if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
}

/// The analytic material for glTF parameters (see the module documentation), the base colour
/// uplift fitted for the colour: for materials of constant factors.
pub fn pbr_material(p: &PbrParams) -> Material {
    pbr_material_with(p, |rgb| Spectrum::rgb_reflectance(rgb).unwrap_or(Spectrum::Constant(0.0)))
}

/// [`pbr_material`] for parameters that change per shading point (texels): the base colour
/// uplift is interpolated in a table (fast, within 7e-3 of the colour).
pub fn pbr_material_at(p: &PbrParams) -> Material {
    pbr_material_with(p, Spectrum::rgb_reflectance_interpolated)
}

fn pbr_material_with(p: &PbrParams, uplift: impl Fn([f32; 3]) -> Spectrum) -> Material {
    let roughness = unit(p.roughness);
    let alpha = roughness * roughness;
    let metallic = unit(p.metallic);
    let colour = p.base_color.map(unit);
    if unit(p.transmission) >= PBR_LOBE_THRESHOLD && metallic < PBR_LOBE_THRESHOLD {
        let ior = if p.ior.is_finite() && p.ior >= 1.0 { p.ior } else { 1.5 };
        let transmittance = (colour != [1.0; 3]).then(|| uplift(colour));
        return Material::Dielectric { ior: Ior::Constant(ior), alpha, transmittance };
    }
    let base = uplift(colour);
    let base = if metallic >= PBR_LOBE_THRESHOLD {
        Material::Conductor { alpha, fresnel: ConductorFresnel::Constant(base), two_sided: true }
    } else {
        Material::Diffuse { reflectance: base, two_sided: true }
    };
    let sheen = p.sheen_color.map(unit);
    if is_coated(p) {
        let r = unit(p.clearcoat_roughness);
        Material::Coated { coating: Coating::clear(r * r), base: Box::new(base), two_sided: true }
    } else if sheen.iter().any(|&c| c > 0.0) {
        let r = unit(p.sheen_roughness);
        Material::Sheen { color: uplift(sheen), alpha: r * r, base: Box::new(base) }
    } else {
        base
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lobes_by_threshold() {
        let p = PbrParams { base_color: [0.2, 0.4, 0.6], metallic: 0.0, roughness: 0.5, ..Default::default() };
        assert_eq!(
            pbr_material(&p),
            Material::Diffuse { reflectance: Spectrum::rgb_reflectance([0.2, 0.4, 0.6]).unwrap(), two_sided: true }
        );
        let m = pbr_material(&PbrParams { metallic: 0.6, ..p });
        assert!(matches!(m, Material::Conductor { alpha, .. } if (alpha - 0.25).abs() < 1e-6));
        let g = pbr_material(&PbrParams { transmission: 1.0, ior: 1.33, ..p });
        let tint = Some(Spectrum::rgb_reflectance([0.2, 0.4, 0.6]).unwrap());
        assert_eq!(g, Material::Dielectric { ior: Ior::Constant(1.33), alpha: 0.25, transmittance: tint });
        // white glass is clear
        let clear = pbr_material(&PbrParams { transmission: 1.0, base_color: [1.0; 3], ..p });
        assert!(matches!(clear, Material::Dielectric { transmittance: None, .. }));
        // a metal does not transmit
        assert!(matches!(
            pbr_material(&PbrParams { transmission: 1.0, metallic: 1.0, ..p }),
            Material::Conductor { .. }
        ));
        // out-of-range input is clamped, never invalid
        let w = pbr_material(&PbrParams { base_color: [2.0, f32::NAN, -1.0], roughness: 7.0, metallic: 0.0, ..p });
        assert_eq!(
            w,
            Material::Diffuse { reflectance: Spectrum::rgb_reflectance([1.0, 0.0, 0.0]).unwrap(), two_sided: true }
        );
        assert!(w.validate().is_ok());
    }
}
