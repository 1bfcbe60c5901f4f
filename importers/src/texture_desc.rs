//! Textures as plain data: decoded 8-bit RGBA images, references with a texture-coordinate
//! transform (KHR_texture_transform), and the textures of a glTF material. The renderer compiles
//! them into its own textures and evaluates them there (`quasar::core::texture`).

use quasar_materials::PbrParams;
use quasar_materials::spectrum::color::srgb8_to_linear;

use crate::source::SourceLocation;

/// How texture coordinates outside [0, 1] are mapped back into the image (glTF sampler wrap).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureWrap {
    /// Repeat the image (glTF default).
    #[default]
    Repeat,
    /// Repeat, mirroring every other copy.
    MirroredRepeat,
    /// Clamp to the edge texels.
    ClampToEdge,
}

/// A decoded image: `width * height` RGBA texels, row 0 at the top, values as stored in the file
/// (colour textures are sRGB-encoded).
#[derive(Clone, Debug, PartialEq)]
pub struct TextureDesc {
    /// Name (glTF image name or URI), for messages.
    pub name: String,
    /// Width in texels (> 0).
    pub width: u32,
    /// Height in texels (> 0).
    pub height: u32,
    /// Texels, row-major.
    pub texels: Vec<[u8; 4]>,
    /// Wrap mode along u.
    pub wrap_u: TextureWrap,
    /// Wrap mode along v.
    pub wrap_v: TextureWrap,
    /// Nearest-texel lookup instead of bilinear (glTF `magFilter` NEAREST).
    pub nearest: bool,
    /// Where it was defined.
    pub source: SourceLocation,
}

impl TextureDesc {
    /// The mean of the texels (linear when `srgb`), RGBA.
    pub fn mean(&self, srgb: bool) -> [f32; 4] {
        let mut s = [0.0f64; 4];
        for t in &self.texels {
            for k in 0..4 {
                s[k] += f64::from(if srgb && k < 3 { srgb8_to_linear(t[k]) } else { f32::from(t[k]) / 255.0 });
            }
        }
        let n = self.texels.len().max(1) as f64;
        s.map(|v| (v / n) as f32)
    }
}

/// A use of a texture: which one, and the affine map from mesh texture coordinates to the
/// texture's (KHR_texture_transform: `uv' = T * R * S * uv`, row-major 2x3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`crate::SceneDesc::textures`].
    pub texture: usize,
    /// Row-major 2x3 affine transform of the texture coordinates.
    pub transform: [[f32; 3]; 2],
}

impl TextureRef {
    /// A reference without a coordinate transform.
    pub fn new(texture: usize) -> Self {
        Self { texture, transform: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] }
    }
}

/// The textures of a glTF material with the factors they multiply. A material with no texture
/// has `pbr = None` and is rendered with its precomputed [`crate::MaterialDesc::material`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialTextures {
    /// The material's glTF factors; `Some` when at least one texture below is set.
    pub pbr: Option<PbrParams>,
    /// Base colour (sRGB), multiplies `pbr.base_color`.
    pub base_color: Option<TextureRef>,
    /// Metallic (blue channel) and roughness (green channel), linear; multiply the factors.
    pub metallic_roughness: Option<TextureRef>,
    /// Tangent-space normal map (linear, +X right, +Y up in the image, +Z out of the surface).
    pub normal: Option<TextureRef>,
    /// glTF `normalTexture.scale`: multiplies the map's X and Y.
    pub normal_scale: f32,
    /// KHR_materials_clearcoat `clearcoatTexture` (red channel, linear): multiplies
    /// `pbr.clearcoat`.
    pub clearcoat: Option<TextureRef>,
    /// KHR_materials_clearcoat `clearcoatRoughnessTexture` (green channel, linear): multiplies
    /// `pbr.clearcoat_roughness`.
    pub clearcoat_roughness: Option<TextureRef>,
    /// KHR_materials_clearcoat `clearcoatNormalTexture`: the coat's own tangent-space normal
    /// map, used in place of `normal` where the surface is coated.
    pub clearcoat_normal: Option<TextureRef>,
    /// Its `scale` (multiplies the map's X and Y).
    pub clearcoat_normal_scale: f32,
    /// KHR_materials_sheen `sheenColorTexture` (RGB, sRGB-encoded): multiplies
    /// `pbr.sheen_color`.
    pub sheen_color: Option<TextureRef>,
    /// KHR_materials_sheen `sheenRoughnessTexture` (alpha channel, linear): multiplies
    /// `pbr.sheen_roughness`.
    pub sheen_roughness: Option<TextureRef>,
}

impl MaterialTextures {
    /// True when no texture is used.
    pub fn is_empty(&self) -> bool {
        self.pbr.is_none()
    }

    /// Every texture reference (base colour, metallic-roughness, normal map, clear coat, sheen),
    /// for remapping texture indices when scenes are merged.
    pub fn references_mut(&mut self) -> impl Iterator<Item = &mut TextureRef> {
        [
            &mut self.base_color,
            &mut self.metallic_roughness,
            &mut self.normal,
            &mut self.clearcoat,
            &mut self.clearcoat_roughness,
            &mut self.clearcoat_normal,
            &mut self.sheen_color,
            &mut self.sheen_roughness,
        ]
        .into_iter()
        .flatten()
    }

    /// True when at least one texture reference is set (then `pbr` must carry the factors).
    pub fn has_references(&self) -> bool {
        [
            self.base_color,
            self.metallic_roughness,
            self.normal,
            self.clearcoat,
            self.clearcoat_roughness,
            self.clearcoat_normal,
            self.sheen_color,
            self.sheen_roughness,
        ]
        .iter()
        .any(Option::is_some)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_decodes_colour_channels_only() {
        let t = TextureDesc {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![[0, 0, 0, 0], [255, 128, 255, 255]],
            wrap_u: TextureWrap::Repeat,
            wrap_v: TextureWrap::Repeat,
            nearest: true,
            source: SourceLocation::default(),
        };
        let m = t.mean(true);
        assert!((m[0] - 0.5).abs() < 1e-6 && (m[1] - 0.215_860_5 / 2.0).abs() < 1e-5);
        assert!((m[3] - 0.5).abs() < 1e-6, "alpha stays linear");
        assert!((t.mean(false)[1] - 128.0 / 510.0).abs() < 1e-6);
    }
}
