//! Surface emission (docs/architecture.md §4): the spectral radiance of an emissive mesh, uniform
//! or following an emissive texture, and the relative power of a textured triangle for
//! power-proportional light selection.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use quasar_importers::TextureRef;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

use crate::core::texture::{ImageTexture, mapped};

/// Spectral emission shared by the triangles of one emissive mesh: L = scale * spectrum, or with
/// a texture L = scale * the light colour of factor x texel at the point.
#[derive(Clone, Debug)]
pub struct Emission {
    /// Spectral shape (with a texture: its mean colour's).
    pub spectrum: Spectrum,
    /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
    /// spectra make it a luminance-equivalent value).
    pub scale: f32,
    /// Emits from both faces.
    pub two_sided: bool,
    /// The texture the emission follows over the surface (glTF `emissiveTexture`).
    pub texture: Option<EmissionTexture>,
}

/// An emissive texture: the light colour at a point is `factor` times the texel (sRGB decoded)
/// at its texture coordinates, uplifted per point (interpolated RGB-to-spectrum table).
#[derive(Clone, Debug)]
pub struct EmissionTexture {
    /// The image (shared with the scene's texture table).
    pub image: Arc<ImageTexture>,
    /// Its coordinate transform.
    pub reference: TextureRef,
    /// Linear RGB factor on the texel.
    pub factor: [f32; 3],
}

impl EmissionTexture {
    /// The linear RGB emission colour (before the emission's scale) at mesh coordinates `uv`.
    #[inline]
    pub fn rgb(&self, uv: Vec2) -> [f32; 3] {
        let t = self.image.sample(mapped(&self.reference, uv), true);
        [self.factor[0] * t[0], self.factor[1] * t[1], self.factor[2] * t[2]]
    }
}

impl Emission {
    /// The emission of an imported mesh's `desc`, its texture's image taken from the scene's
    /// `images`; a texture needs the mesh's texture coordinates (`has_uvs`), else the mean colour
    /// (`desc.spectrum`) is emitted everywhere.
    pub fn new(desc: &quasar_importers::EmissionDesc, images: &[Arc<ImageTexture>], has_uvs: bool) -> Self {
        let texture = desc.texture.filter(|_| has_uvs).and_then(|t| {
            Some(EmissionTexture {
                image: images.get(t.texture.texture)?.clone(),
                reference: t.texture,
                factor: t.factor,
            })
        });
        Self { spectrum: desc.spectrum.densified(), scale: desc.scale, two_sided: desc.two_sided, texture }
    }

    /// Radiance leaving a surface with unit geometric normal `ng` in direction `w`, at mesh
    /// texture coordinates `uv` (used with a texture).
    #[inline(always)]
    pub fn radiance(&self, ng: Vec3, w: Vec3, uv: Vec2, wl: &SampledWavelengths) -> SampledSpectrum {
        if !self.two_sided && ng.dot(w) <= 0.0 {
            return SampledSpectrum::zero();
        }
        match &self.texture {
            None => self.spectrum.sample(wl) * self.scale,
            Some(t) => {
                let rgb = t.rgb(uv);
                if rgb == [0.0; 3] {
                    return SampledSpectrum::zero();
                }
                Spectrum::rgb_illuminant_interpolated(rgb).sample(wl) * self.scale
            }
        }
    }
}

/// The texture coordinates at barycentrics (b1, b2) of a triangle with vertex coordinates `uv`.
#[inline]
pub fn bary_uv(uv: &[Vec2; 3], b1: f32, b2: f32) -> Vec2 {
    uv[0] * (1.0 - b1 - b2) + uv[1] * b1 + uv[2] * b2
}

/// Luminance of linear sRGB (Rec. 709 weights).
#[inline]
pub(crate) fn rgb_luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Texels read inside one triangle's texture-space bounding box at most, to find light that the
/// stratified samples of [`textured_weight`] miss.
const MAX_BOX_TEXELS: u64 = 4096;

/// The emitted power of a triangle of texture coordinates `uv` relative to its emission's nominal
/// (mean) colour of luminance `nominal`: the mean over a stratified 8 x 8 barycentric grid of the
/// luminance of factor x texel, over `nominal`. A triangle whose samples are all black but whose
/// texture-space bounding box holds a lit texel keeps 1e-3 of that texel's luminance, so every
/// triangle that emits can be chosen (the light samples and photons of a triangle never chosen
/// would be missing).
pub fn textured_weight(t: &EmissionTexture, uv: &[Vec2; 3], nominal: f32) -> f32 {
    if !(nominal > 0.0 && nominal.is_finite()) {
        return 1.0;
    }
    let n = 8;
    let mut sum = 0.0f64;
    let mut count = 0usize;
    for i in 0..n {
        for j in 0..n - i {
            // the centroids of the grid's upright sub-triangles
            let b1 = (i as f32 + 1.0 / 3.0) / n as f32;
            let b2 = (j as f32 + 1.0 / 3.0) / n as f32;
            sum += f64::from(rgb_luminance(t.rgb(bary_uv(uv, b1, b2))));
            count += 1;
        }
    }
    let mean = (sum / count as f64) as f32;
    if mean > 0.0 {
        return mean / nominal;
    }
    // every sample black: look at the texels of the bounding box
    let (w, h) = t.image.size();
    let m: [Vec2; 3] = uv.map(|p| mapped(&t.reference, p));
    let (lo, hi) = (m[0].min(m[1]).min(m[2]), m[0].max(m[1]).max(m[2]));
    let (x0, x1) = ((lo.x * w as f32).floor() as i64, (hi.x * w as f32).ceil() as i64);
    let (y0, y1) = ((lo.y * h as f32).floor() as i64, (hi.y * h as f32).ceil() as i64);
    let texels = ((x1 - x0).max(0) as u64).saturating_mul((y1 - y0).max(0) as u64);
    if !lo.is_finite() || !hi.is_finite() || texels > MAX_BOX_TEXELS {
        return 1e-3;
    }
    let mut max = 0.0f32;
    for y in y0..=y1 {
        for x in x0..=x1 {
            let c = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let texel = t.image.sample(c, true);
            max = max.max(rgb_luminance([t.factor[0] * texel[0], t.factor[1] * texel[1], t.factor[2] * texel[2]]));
        }
    }
    if max > 0.0 { 1e-3 * max / nominal } else { 0.0 }
}
