//! Textures as plain data: decoded 8-bit RGBA images, references with a texture-coordinate
//! transform (KHR_texture_transform), and the textures of a glTF material. The lookup functions
//! are plain code (no trait objects) so the renderer can call them on its hot path.

use std::sync::OnceLock;

use glam::Vec2;

use crate::pbr::PbrParams;
use crate::scene_desc::SourceLocation;

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

impl TextureWrap {
    /// Maps integer texel coordinate `i` into `0..n`.
    #[inline]
    fn apply(self, i: i64, n: u32) -> usize {
        let n = i64::from(n.max(1));
        let j = match self {
            Self::Repeat => i.rem_euclid(n),
            Self::ClampToEdge => i.clamp(0, n - 1),
            Self::MirroredRepeat => {
                let k = i.rem_euclid(2 * n);
                if k < n { k } else { 2 * n - 1 - k }
            }
        };
        j as usize
    }
}

/// A decoded image: `width * height` RGBA texels, row 0 at the top, values as stored in the file
/// (colour textures are sRGB-encoded; see [`srgb_to_linear`]).
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

/// The sRGB transfer function decoded: 8-bit sRGB value -> linear value in [0, 1].
#[inline]
pub fn srgb_to_linear(v: u8) -> f32 {
    static LUT: OnceLock<[f32; 256]> = OnceLock::new();
    LUT.get_or_init(|| {
        std::array::from_fn(|i| {
            let c = i as f32 / 255.0;
            if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
        })
    })[usize::from(v)]
}

impl TextureDesc {
    /// The texel at integer coordinates (wrapped), each channel decoded by `decode`.
    #[inline]
    fn texel(&self, x: i64, y: i64, srgb: bool) -> [f32; 4] {
        let (x, y) = (self.wrap_u.apply(x, self.width), self.wrap_v.apply(y, self.height));
        let t = self.texels.get(y * self.width as usize + x).copied().unwrap_or([0; 4]);
        let c = |v: u8| if srgb { srgb_to_linear(v) } else { f32::from(v) / 255.0 };
        [c(t[0]), c(t[1]), c(t[2]), f32::from(t[3]) / 255.0]
    }

    /// The filtered value at texture coordinates `uv` (glTF convention: (0, 0) = top-left),
    /// RGBA in [0, 1]; with `srgb` the colour channels are decoded to linear first.
    pub fn sample(&self, uv: Vec2, srgb: bool) -> [f32; 4] {
        if self.width == 0 || self.height == 0 || !uv.is_finite() {
            return [0.0; 4];
        }
        // clamp far-away coordinates so the integer conversion stays exact (wrap is periodic)
        let x = (uv.x.clamp(-1e6, 1e6) as f64) * f64::from(self.width) - 0.5;
        let y = (uv.y.clamp(-1e6, 1e6) as f64) * f64::from(self.height) - 0.5;
        if self.nearest {
            return self.texel((x + 0.5).floor() as i64, (y + 0.5).floor() as i64, srgb);
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let a = self.texel(x0, y0, srgb);
        let b = self.texel(x0 + 1, y0, srgb);
        let c = self.texel(x0, y0 + 1, srgb);
        let d = self.texel(x0 + 1, y0 + 1, srgb);
        std::array::from_fn(|k| (a[k] * (1.0 - fx) + b[k] * fx) * (1.0 - fy) + (c[k] * (1.0 - fx) + d[k] * fx) * fy)
    }

    /// The mean of the texels (linear when `srgb`), RGBA.
    pub fn mean(&self, srgb: bool) -> [f32; 4] {
        let mut s = [0.0f64; 4];
        for t in &self.texels {
            for k in 0..4 {
                s[k] += f64::from(if srgb && k < 3 { srgb_to_linear(t[k]) } else { f32::from(t[k]) / 255.0 });
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

    /// The texture's coordinates of mesh coordinates `uv`.
    #[inline]
    pub fn map(&self, uv: Vec2) -> Vec2 {
        let m = &self.transform;
        Vec2::new(m[0][0] * uv.x + m[0][1] * uv.y + m[0][2], m[1][0] * uv.x + m[1][1] * uv.y + m[1][2])
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
}

impl MaterialTextures {
    /// True when no texture is used.
    pub fn is_empty(&self) -> bool {
        self.pbr.is_none()
    }

    /// The tangent-space normal at mesh texture coordinates `uv` (not normalised; `None`
    /// without a normal map).
    pub fn normal_at(&self, textures: &[TextureDesc], uv: Vec2) -> Option<glam::Vec3> {
        let r = self.normal.as_ref()?;
        let c = textures.get(r.texture)?.sample(r.map(uv), false);
        let s = self.normal_scale;
        Some(glam::Vec3::new((2.0 * c[0] - 1.0) * s, (2.0 * c[1] - 1.0) * s, 2.0 * c[2] - 1.0))
    }

    /// The glTF parameters at mesh texture coordinates `uv` (factors times texels).
    pub fn params_at(&self, textures: &[TextureDesc], uv: Vec2) -> Option<PbrParams> {
        let mut p = self.pbr?;
        if let Some(r) = &self.base_color
            && let Some(t) = textures.get(r.texture)
        {
            let c = t.sample(r.map(uv), true);
            for (b, c) in p.base_color.iter_mut().zip(c) {
                *b *= c;
            }
        }
        if let Some(r) = &self.metallic_roughness
            && let Some(t) = textures.get(r.texture)
        {
            let c = t.sample(r.map(uv), false);
            p.roughness *= c[1];
            p.metallic *= c[2];
        }
        Some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tex(wrap: TextureWrap) -> TextureDesc {
        TextureDesc {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![[0, 0, 0, 255], [255, 255, 255, 255]],
            wrap_u: wrap,
            wrap_v: wrap,
            nearest: true,
            source: SourceLocation::default(),
        }
    }

    #[test]
    fn wrap_modes_and_filtering() {
        let t = tex(TextureWrap::Repeat);
        assert_eq!(t.sample(Vec2::new(0.25, 0.5), false)[0], 0.0);
        assert_eq!(t.sample(Vec2::new(0.75, 0.5), false)[0], 1.0);
        assert_eq!(t.sample(Vec2::new(1.25, 0.5), false)[0], 0.0);
        let c = tex(TextureWrap::ClampToEdge);
        assert_eq!(c.sample(Vec2::new(1.25, 0.5), false)[0], 1.0);
        let m = tex(TextureWrap::MirroredRepeat);
        assert_eq!(m.sample(Vec2::new(1.25, 0.5), false)[0], 1.0);
        let mut b = tex(TextureWrap::ClampToEdge);
        b.nearest = false;
        assert!((b.sample(Vec2::new(0.5, 0.5), false)[0] - 0.5).abs() < 1e-6);
        assert_eq!(b.sample(Vec2::new(f32::NAN, 0.5), false), [0.0; 4]);
        assert!((srgb_to_linear(128) - 0.2158605).abs() < 1e-5);
        let r = TextureRef { texture: 0, transform: [[2.0, 0.0, 0.5], [0.0, 1.0, 0.0]] };
        assert_eq!(r.map(Vec2::new(1.0, 1.0)), Vec2::new(2.5, 1.0));
    }
}
