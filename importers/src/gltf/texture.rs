//! glTF images and samplers -> [`TextureDesc`], decoded with the `image` crate under limits (no
//! decompression bombs): at most [`MAX_TEXTURE_SIDE`] texels per side and [`MAX_TEXTURE_ALLOC`]
//! bytes of decoder memory per image. PNG and JPEG are supported.

use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

use gltf::texture::{MagFilter, WrappingMode};

use super::err;
use super::source::uri_bytes;
use crate::error::{ImportError, ImportErrorKind};
use crate::importer::ImportOptions;
use crate::scene_desc::SourceLocation;
use crate::texture_desc::{TextureDesc, TextureRef, TextureWrap};

/// Largest width or height of a texture (texels).
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// Largest decoder allocation per image (bytes).
pub const MAX_TEXTURE_ALLOC: u64 = 1 << 30;

/// Decodes an encoded image (PNG/JPEG) to RGBA8 under the limits; `what` names it in errors.
pub fn decode_image(bytes: &[u8], file: &Path, pointer: &str) -> Result<(u32, u32, Vec<[u8; 4]>), ImportError> {
    let bad = |msg: String| err(ImportErrorKind::InvalidValue, file, pointer, msg);
    let mut reader =
        image::ImageReader::new(Cursor::new(bytes)).with_guessed_format().map_err(|e| bad(format!("image: {e}")))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(MAX_TEXTURE_ALLOC);
    reader.limits(limits);
    if reader.format().is_none() {
        return Err(err(ImportErrorKind::Unsupported, file, pointer, "image is neither PNG nor JPEG"));
    }
    let img = reader.decode().map_err(|e| match e {
        image::ImageError::Limits(l) => err(
            ImportErrorKind::TooLarge,
            file,
            pointer,
            format!(
                "image exceeds the decoder limits ({MAX_TEXTURE_SIDE} texels per side, {MAX_TEXTURE_ALLOC} bytes): {l}"
            ),
        ),
        e => bad(format!("cannot decode image: {e}")),
    })?;
    let rgba = img.to_rgba8();
    let (w, h) = rgba.dimensions();
    if w == 0 || h == 0 {
        return Err(bad("image is empty".into()));
    }
    let texels = rgba.into_raw().chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
    Ok((w, h, texels))
}

fn wrap(m: WrappingMode) -> TextureWrap {
    match m {
        WrappingMode::ClampToEdge => TextureWrap::ClampToEdge,
        WrappingMode::MirroredRepeat => TextureWrap::MirroredRepeat,
        WrappingMode::Repeat => TextureWrap::Repeat,
    }
}

/// Loads glTF textures on first use and caches them by glTF texture index.
pub(super) struct TextureLoader<'a> {
    /// The glTF file.
    pub file: &'a Path,
    /// Import options (path policy).
    pub opts: &'a ImportOptions,
    /// Buffer data by index.
    pub buffers: &'a [Vec<u8>],
    /// Decoded textures (the scene's texture table).
    pub textures: Vec<TextureDesc>,
    /// glTF texture index -> index in `textures`.
    pub cache: HashMap<usize, usize>,
    /// Warnings for the scene.
    pub warnings: Vec<String>,
}

impl TextureLoader<'_> {
    /// The scene texture for a glTF texture reference (`pointer` = the JSON pointer of the
    /// `textureInfo`), with its KHR_texture_transform.
    pub fn reference(&mut self, info: &gltf::texture::Info<'_>, pointer: &str) -> Result<TextureRef, ImportError> {
        let mut tex_coord = info.tex_coord();
        let mut r = TextureRef::new(self.load(&info.texture(), pointer)?);
        if let Some(t) = info.texture_transform() {
            let ([ox, oy], rot, [sx, sy]) = (t.offset(), t.rotation(), t.scale());
            let (s, c) = rot.sin_cos();
            let m = [[c * sx, s * sy, ox], [-s * sx, c * sy, oy]];
            if m.iter().flatten().all(|v| v.is_finite()) {
                r.transform = m;
            } else {
                self.warnings
                    .push(format!("{}: {pointer}: non-finite KHR_texture_transform ignored", self.file.display()));
            }
            tex_coord = t.tex_coord().unwrap_or(tex_coord);
        }
        if tex_coord != 0 {
            self.warnings.push(format!(
                "{}: {pointer}: uses TEXCOORD_{tex_coord}; only TEXCOORD_0 is supported, it is used instead",
                self.file.display()
            ));
        }
        Ok(r)
    }

    /// The scene texture index of glTF texture `tex` (decoded on first use).
    pub fn load(&mut self, tex: &gltf::Texture<'_>, pointer: &str) -> Result<usize, ImportError> {
        if let Some(&i) = self.cache.get(&tex.index()) {
            return Ok(i);
        }
        let image = tex.source();
        let ip = format!("/images/{}", image.index());
        let bytes = match image.source() {
            gltf::image::Source::Uri { uri, .. } => uri_bytes(self.file, uri, &format!("{ip}/uri"), self.opts)?,
            gltf::image::Source::View { view, .. } => {
                let data = self.buffers.get(view.buffer().index()).map(Vec::as_slice).unwrap_or(&[]);
                let (s, l) = (view.offset(), view.length());
                match s.checked_add(l).and_then(|e| data.get(s..e)) {
                    Some(b) => b.to_vec(),
                    None => {
                        return Err(err(
                            ImportErrorKind::InvalidValue,
                            self.file,
                            &format!("{ip}/bufferView"),
                            format!("buffer view {} lies outside its buffer", view.index()),
                        ));
                    }
                }
            }
        };
        let (width, height, texels) = decode_image(&bytes, self.file, &ip).map_err(|mut e| {
            e.message = format!("{} (used by {pointer})", e.message);
            e
        })?;
        let sampler = tex.sampler();
        let name = image.name().map_or_else(|| format!("image{}", image.index()), str::to_owned);
        self.textures.push(TextureDesc {
            name,
            width,
            height,
            texels,
            wrap_u: wrap(sampler.wrap_s()),
            wrap_v: wrap(sampler.wrap_t()),
            nearest: sampler.mag_filter() == Some(MagFilter::Nearest),
            source: SourceLocation { file: self.file.to_owned(), line: None, item: Some(ip) },
        });
        self.cache.insert(tex.index(), self.textures.len() - 1);
        Ok(self.textures.len() - 1)
    }
}
