//! glTF images and samplers -> [`TextureDesc`], decoded by [`crate::texture_decode`] under its
//! limits. PNG and JPEG are supported.

use std::collections::HashMap;
use std::path::Path;

use gltf::texture::{MagFilter, WrappingMode};

use super::err;
use super::source::uri_bytes;
use crate::error::{ImportError, ImportErrorKind};
use crate::importer::ImportOptions;
use crate::scene_desc::SourceLocation;
use crate::texture_decode::decode_image;
use crate::texture_desc::{TextureDesc, TextureRef, TextureWrap};

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
    /// The glTF document (textures by index, for extensions the gltf crate gives as JSON).
    pub doc: &'a gltf::Document,
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
    /// The scene texture of a `textureInfo` given as JSON (an extension's), at JSON pointer
    /// `pointer`: its `index` must name a texture; `texCoord` other than 0 and
    /// `KHR_texture_transform` are not read there (a warning says so).
    pub fn reference_json(&mut self, info: &serde_json::Value, pointer: &str) -> Result<TextureRef, ImportError> {
        let index = info.get("index").and_then(serde_json::Value::as_u64);
        let Some(tex) = index.and_then(|i| self.doc.textures().nth(i as usize)) else {
            return Err(err(
                ImportErrorKind::InvalidValue,
                self.file,
                &format!("{pointer}/index"),
                "a texture reference needs the index of one of the file's textures",
            ));
        };
        if info.get("texCoord").and_then(serde_json::Value::as_u64).is_some_and(|c| c != 0)
            || info.get("extensions").is_some()
        {
            self.warnings.push(format!(
                "{}: {pointer}: only TEXCOORD_0 without KHR_texture_transform is read for this texture",
                self.file.display()
            ));
        }
        Ok(TextureRef::new(self.load(&tex, pointer)?))
    }

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
