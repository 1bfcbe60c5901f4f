//! Texture evaluation at surface hits: 8-bit RGBA images with glTF wrap modes and bilinear (or
//! nearest) filtering, and the textured glTF metallic-roughness material whose factors the texels
//! multiply (glTF 2.0 section 3.9; KHR_texture_transform for the coordinate maps). Compiled from
//! the importers' plain [`TextureDesc`] / [`MaterialTextures`] by
//! [`Scene::compile`](crate::core::scene::Scene::compile).

use std::borrow::Borrow;

use glam::{Vec2, Vec3};
use quasar_importers::{MaterialTextures, TextureDesc, TextureRef, TextureWrap};
use quasar_materials::PbrParams;
use quasar_materials::spectrum::color::srgb8_to_linear;

/// Maps integer texel coordinate `i` into `0..n` by `wrap`.
#[inline]
fn wrapped(wrap: TextureWrap, i: i64, n: u32) -> usize {
    let n = i64::from(n.max(1));
    let j = match wrap {
        TextureWrap::Repeat => i.rem_euclid(n),
        TextureWrap::ClampToEdge => i.clamp(0, n - 1),
        TextureWrap::MirroredRepeat => {
            let k = i.rem_euclid(2 * n);
            if k < n { k } else { 2 * n - 1 - k }
        }
    };
    j as usize
}

/// An image texture: `width * height` RGBA texels, row 0 at the top, as stored in the file
/// (colour textures sRGB-encoded, decoded per lookup).
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    width: u32,
    height: u32,
    texels: Vec<[u8; 4]>,
    wrap_u: TextureWrap,
    wrap_v: TextureWrap,
    nearest: bool,
}

impl ImageTexture {
    /// The texture of an imported image.
    pub fn new(desc: &TextureDesc) -> Self {
        Self {
            width: desc.width,
            height: desc.height,
            texels: desc.texels.clone(),
            wrap_u: desc.wrap_u,
            wrap_v: desc.wrap_v,
            nearest: desc.nearest,
        }
    }

    /// The texel at integer coordinates (wrapped); with `srgb` the colour channels decoded.
    #[inline]
    fn texel(&self, x: i64, y: i64, srgb: bool) -> [f32; 4] {
        let (x, y) = (wrapped(self.wrap_u, x, self.width), wrapped(self.wrap_v, y, self.height));
        let t = self.texels.get(y * self.width as usize + x).copied().unwrap_or([0; 4]);
        let c = |v: u8| if srgb { srgb8_to_linear(v) } else { f32::from(v) / 255.0 };
        [c(t[0]), c(t[1]), c(t[2]), f32::from(t[3]) / 255.0]
    }

    /// (width, height) in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// True when lookups take the nearest texel (glTF `magFilter` NEAREST), not four.
    pub fn is_nearest(&self) -> bool {
        self.nearest
    }

    /// The filtered value at texture coordinates `uv` (glTF convention: (0, 0) = top-left),
    /// RGBA in [0, 1]; with `srgb` the colour channels are decoded to linear before filtering.
    /// Non-finite coordinates give 0.
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
}

/// The texture's coordinates of mesh coordinates `uv`: the reference's affine map
/// `uv' = T * R * S * uv` (KHR_texture_transform, row-major 2x3).
#[inline]
pub fn mapped(r: &TextureRef, uv: Vec2) -> Vec2 {
    let m = &r.transform;
    Vec2::new(m[0][0] * uv.x + m[0][1] * uv.y + m[0][2], m[1][0] * uv.x + m[1][1] * uv.y + m[1][2])
}

/// A glTF metallic-roughness material with textures: its factors, multiplied per hit by the
/// base-colour texel (sRGB), the metallic (blue) / roughness (green) texel (linear), the
/// clear coat's factor (red) and roughness (green) texels (linear) and the sheen's colour
/// (sRGB) and roughness (alpha) texels, and its tangent-space normal map.
#[derive(Clone, Debug, PartialEq)]
pub struct TexturedMaterial {
    factors: PbrParams,
    base_color: Option<TextureRef>,
    metallic_roughness: Option<TextureRef>,
    normal: Option<TextureRef>,
    normal_scale: f32,
    clearcoat: Option<TextureRef>,
    clearcoat_roughness: Option<TextureRef>,
    clearcoat_normal: Option<TextureRef>,
    clearcoat_normal_scale: f32,
    sheen_color: Option<TextureRef>,
    sheen_roughness: Option<TextureRef>,
}

impl TexturedMaterial {
    /// The textured material of an imported material (None when it has no texture).
    pub fn new(t: &MaterialTextures) -> Option<Self> {
        Some(Self {
            factors: t.pbr?,
            base_color: t.base_color,
            metallic_roughness: t.metallic_roughness,
            normal: t.normal,
            normal_scale: t.normal_scale,
            clearcoat: t.clearcoat,
            clearcoat_roughness: t.clearcoat_roughness,
            clearcoat_normal: t.clearcoat_normal,
            clearcoat_normal_scale: t.clearcoat_normal_scale,
            sheen_color: t.sheen_color,
            sheen_roughness: t.sheen_roughness,
        })
    }

    /// The glTF parameters at mesh texture coordinates `uv`: factors times texels (a reference
    /// to a missing texture leaves its factor alone).
    pub fn params_at<T: Borrow<ImageTexture>>(&self, textures: &[T], uv: Vec2) -> PbrParams {
        let mut p = self.factors;
        let texel = |r: &Option<TextureRef>, srgb| texel_at(textures, r.as_ref()?, uv, srgb);
        let times = |factor: &mut [f32; 3], c: [f32; 4]| factor.iter_mut().zip(c).for_each(|(f, c)| *f *= c);
        if let Some(c) = texel(&self.base_color, true) {
            times(&mut p.base_color, c);
        }
        if let Some(c) = texel(&self.metallic_roughness, false) {
            p.roughness *= c[1];
            p.metallic *= c[2];
        }
        if let Some(c) = texel(&self.clearcoat, false) {
            p.clearcoat *= c[0];
        }
        if let Some(c) = texel(&self.clearcoat_roughness, false) {
            p.clearcoat_roughness *= c[1];
        }
        if let Some(c) = texel(&self.sheen_color, true) {
            times(&mut p.sheen_color, c);
        }
        if let Some(c) = texel(&self.sheen_roughness, false) {
            p.sheen_roughness *= c[3];
        }
        p
    }

    /// The tangent-space normal at mesh texture coordinates `uv`, (2 c - 1) with X and Y scaled
    /// by the map's `scale` (not normalised; None without a normal map): the clear coat's own
    /// map where the point is coated ([`quasar_materials::pbr::is_coated`] of the parameters
    /// there), else `normalTexture`. (The coated BSDF has one frame, so a coat's map stands for
    /// the whole coated surface; glTF's base map shows only where the coat has none.)
    pub fn normal_at<T: Borrow<ImageTexture>>(&self, textures: &[T], uv: Vec2) -> Option<Vec3> {
        let (r, s) = match &self.clearcoat_normal {
            Some(c) if quasar_materials::pbr::is_coated(&self.params_at(textures, uv)) => {
                (c, self.clearcoat_normal_scale)
            }
            _ => (self.normal.as_ref()?, self.normal_scale),
        };
        let c = texel_at(textures, r, uv, false)?;
        Some(Vec3::new((2.0 * c[0] - 1.0) * s, (2.0 * c[1] - 1.0) * s, 2.0 * c[2] - 1.0))
    }
}

/// The texel of reference `r` at mesh texture coordinates `uv` (None when `r` names no
/// texture of `textures`).
#[inline]
fn texel_at<T: Borrow<ImageTexture>>(textures: &[T], r: &TextureRef, uv: Vec2, srgb: bool) -> Option<[f32; 4]> {
    Some(textures.get(r.texture)?.borrow().sample(mapped(r, uv), srgb))
}

#[cfg(test)]
mod tests {
    use quasar_importers::SourceLocation;

    use super::*;

    fn tex(wrap: TextureWrap, nearest: bool) -> ImageTexture {
        ImageTexture::new(&TextureDesc {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![[0, 0, 0, 255], [255, 255, 255, 255]],
            wrap_u: wrap,
            wrap_v: wrap,
            nearest,
            source: SourceLocation::default(),
        })
    }

    #[test]
    fn wrap_modes_and_filtering() {
        let t = tex(TextureWrap::Repeat, true);
        assert_eq!(t.sample(Vec2::new(0.25, 0.5), false)[0], 0.0);
        assert_eq!(t.sample(Vec2::new(0.75, 0.5), false)[0], 1.0);
        assert_eq!(t.sample(Vec2::new(1.25, 0.5), false)[0], 0.0);
        assert_eq!(tex(TextureWrap::ClampToEdge, true).sample(Vec2::new(1.25, 0.5), false)[0], 1.0);
        assert_eq!(tex(TextureWrap::MirroredRepeat, true).sample(Vec2::new(1.25, 0.5), false)[0], 1.0);
        let b = tex(TextureWrap::ClampToEdge, false);
        assert!((b.sample(Vec2::new(0.5, 0.5), false)[0] - 0.5).abs() < 1e-6);
        // sRGB decoding before filtering: the mean of 0 and 1 either way
        assert!((b.sample(Vec2::new(0.5, 0.5), true)[0] - 0.5).abs() < 1e-6);
        assert_eq!(b.sample(Vec2::new(f32::NAN, 0.5), false), [0.0; 4]);
        assert_eq!(b.sample(Vec2::new(1e30, -1e30), false).map(f32::is_finite), [true; 4]);
    }

    #[test]
    fn factors_times_texels_through_the_transform() {
        let textures = [tex(TextureWrap::ClampToEdge, true)];
        let factors = PbrParams { base_color: [0.5, 0.25, 1.0], metallic: 0.8, roughness: 0.6, ..Default::default() };
        // the transform maps every uv to u = 0.75 (the white texel)
        let white = TextureRef { texture: 0, transform: [[0.0, 0.0, 0.75], [0.0, 0.0, 0.5]] };
        let black = TextureRef { texture: 0, transform: [[0.0, 0.0, 0.25], [0.0, 0.0, 0.5]] };
        let m = |bc, mr| MaterialTextures {
            pbr: Some(factors),
            base_color: bc,
            metallic_roughness: mr,
            normal: Some(white),
            normal_scale: 0.5,
            clearcoat: None,
            clearcoat_roughness: None,
            clearcoat_normal: None,
            clearcoat_normal_scale: 0.0,
            sheen_color: None,
            sheen_roughness: None,
        };
        let t = TexturedMaterial::new(&m(Some(white), Some(black))).unwrap();
        let p = t.params_at(&textures, Vec2::new(0.1, 0.9));
        assert_eq!((p.base_color, p.metallic, p.roughness), ([0.5, 0.25, 1.0], 0.0, 0.0));
        // the clear coat's factor (red) and roughness (green) texels
        let coat = PbrParams { clearcoat: 1.0, clearcoat_roughness: 0.5, ..factors };
        let t = TexturedMaterial::new(&MaterialTextures {
            pbr: Some(coat),
            clearcoat: Some(black),
            clearcoat_roughness: Some(white),
            ..m(None, None)
        })
        .unwrap();
        let p = t.params_at(&textures, Vec2::ZERO);
        assert_eq!((p.clearcoat, p.clearcoat_roughness), (0.0, 0.5));
        // the coat's own normal map where the point is coated, the base's elsewhere
        let coat_normal = |clearcoat| {
            TexturedMaterial::new(&MaterialTextures {
                pbr: Some(PbrParams { clearcoat, metallic: 0.0, ..factors }),
                clearcoat_normal: Some(black),
                clearcoat_normal_scale: 2.0,
                ..m(None, None)
            })
            .unwrap()
            .normal_at(&textures, Vec2::ZERO)
        };
        assert_eq!(coat_normal(1.0), Some(Vec3::new(-2.0, -2.0, -1.0)));
        assert_eq!(coat_normal(0.2), Some(Vec3::new(0.5, 0.5, 1.0)));
        // the sheen's colour (sRGB) and roughness (alpha) texels
        let sheen = PbrParams { sheen_color: [0.5, 1.0, 0.25], sheen_roughness: 0.7, ..factors };
        let sheen_with = |color, roughness| {
            TexturedMaterial::new(&MaterialTextures {
                pbr: Some(sheen),
                sheen_color: color,
                sheen_roughness: roughness,
                ..m(None, None)
            })
            .unwrap()
            .params_at(&textures, Vec2::ZERO)
        };
        let p = sheen_with(Some(white), Some(black));
        assert_eq!((p.sheen_color, p.sheen_roughness), ([0.5, 1.0, 0.25], 0.7), "black's alpha is 1");
        let p = sheen_with(Some(black), None);
        assert_eq!((p.sheen_color, p.sheen_roughness), ([0.0; 3], 0.7));
        assert_eq!(t.normal_at(&textures, Vec2::ZERO), Some(Vec3::new(0.5, 0.5, 1.0)));
        // a reference to a texture that is not there leaves the factor
        let missing = TextureRef::new(7);
        let p = TexturedMaterial::new(&m(Some(missing), None)).unwrap().params_at(&textures, Vec2::ZERO);
        assert_eq!(p, factors);
        assert!(TexturedMaterial::new(&MaterialTextures::default()).is_none());
    }
}
