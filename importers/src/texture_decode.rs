//! Encoded images (PNG, JPEG) decoded to RGBA8 with the `image` crate under limits (no
//! decompression bombs): at most [`MAX_TEXTURE_SIDE`] texels per side and [`MAX_TEXTURE_ALLOC`]
//! bytes of decoder memory per image. Used by the glTF and USD importers.

use std::io::Cursor;
use std::path::Path;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};

fn err(kind: ImportErrorKind, file: &Path, place: &str, msg: impl Into<String>) -> ImportError {
    let msg = msg.into();
    let message = if place.is_empty() { msg } else { format!("{place}: {msg}") };
    ImportError::new(kind, ErrorPlace::file(file), message)
}

/// Largest width or height of a texture (texels).
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// Largest decoder allocation per image (bytes).
pub const MAX_TEXTURE_ALLOC: u64 = 1 << 30;

/// Decodes an encoded image (PNG/JPEG) to RGBA8 under the limits; errors name `file` and the
/// place in it (`pointer`: a glTF JSON pointer, a USD prim and attribute).
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
