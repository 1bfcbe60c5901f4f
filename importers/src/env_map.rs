//! Lat-long (equirectangular) environment maps: `.exr` (the `exr` crate: the first layer's R, G,
//! B channels, or Y for a grey map) and Radiance `.hdr` (the `image` crate), read into linear RGB
//! radiance texels. Errors name the file; sizes are checked before anything is decoded.
//!
//! The mapping (documented in docs/scene-format.md): row 0 is the zenith (+Y), the last row the
//! nadir; u = 0.5 + atan2(d.x, -d.z) / (2 pi), so the image centre looks along -Z (where the
//! default camera looks), and u increases towards +X.

use std::path::Path;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::scene_desc::EnvMapDesc;

/// Largest accepted map side in texels.
pub const MAX_ENV_MAP_SIDE: usize = 16_384;
/// Largest accepted number of texels (a 16k x 8k map).
pub const MAX_ENV_MAP_TEXELS: usize = 1 << 27;
/// Largest accepted file size.
pub const MAX_ENV_MAP_BYTES: u64 = 2 << 30;

fn err(path: &Path, kind: ImportErrorKind, msg: impl Into<String>) -> ImportError {
    ImportError::new(kind, ErrorPlace::file(path), msg)
}

fn check_size(path: &Path, w: usize, h: usize) -> Result<(), ImportError> {
    if w == 0 || h == 0 {
        return Err(err(path, ImportErrorKind::InvalidValue, "the environment map is empty"));
    }
    if w > MAX_ENV_MAP_SIDE || h > MAX_ENV_MAP_SIDE || w * h > MAX_ENV_MAP_TEXELS {
        return Err(err(
            path,
            ImportErrorKind::TooLarge,
            format!("a {w}x{h} environment map is larger than {MAX_ENV_MAP_SIDE} per side or 2^27 texels"),
        ));
    }
    Ok(())
}

/// Reads the lat-long map at `path` (`.exr` or `.hdr`). Non-finite or negative texels are an
/// error naming the first one.
pub fn load_env_map(path: &Path) -> Result<EnvMapDesc, ImportError> {
    let meta = std::fs::metadata(path).map_err(|e| {
        let kind =
            if e.kind() == std::io::ErrorKind::NotFound { ImportErrorKind::MissingFile } else { ImportErrorKind::Io };
        err(path, kind, format!("cannot read the environment map: {e}"))
    })?;
    if meta.len() > MAX_ENV_MAP_BYTES {
        return Err(err(path, ImportErrorKind::TooLarge, format!("{} bytes is more than 2 GiB", meta.len())));
    }
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let (width, height, texels) = match ext.as_deref() {
        Some("exr") => read_exr(path)?,
        Some("hdr") => read_hdr(path)?,
        _ => {
            return Err(err(path, ImportErrorKind::Unsupported, "environment maps must be .exr or .hdr (lat-long)"));
        }
    };
    if let Some((i, t)) = texels.iter().enumerate().find(|(_, t)| t.iter().any(|v| !v.is_finite() || *v < 0.0)) {
        return Err(err(
            path,
            ImportErrorKind::InvalidValue,
            format!("texel ({}, {}) is not finite and >= 0: {t:?}", i % width, i / width),
        ));
    }
    Ok(EnvMapDesc { file: path.to_path_buf(), width, height, texels, rotate_deg: 0.0 })
}

type Texels = (usize, usize, Vec<[f32; 3]>);

fn read_exr(path: &Path) -> Result<Texels, ImportError> {
    use exr::prelude::*;
    let bad = |e: exr::error::Error| err(path, ImportErrorKind::Syntax, format!("not a readable OpenEXR file: {e}"));
    // the header first: refuse huge images before decoding any pixel
    let meta = MetaData::read_from_file(path, false).map_err(bad)?;
    let header = meta.headers.first().ok_or_else(|| err(path, ImportErrorKind::Syntax, "no image in the file"))?;
    let size = header.layer_size;
    check_size(path, size.0, size.1)?;
    let image = read().no_deep_data().largest_resolution_level().all_channels().first_valid_layer().all_attributes();
    let image = image.from_file(path).map_err(bad)?;
    let layer = &image.layer_data;
    let (w, h) = (layer.size.0, layer.size.1);
    let find = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .map(|c| c.sample_data.values_as_f32().collect::<Vec<f32>>())
    };
    let texels = match (find("R"), find("G"), find("B"), find("Y")) {
        (Some(r), Some(g), Some(b), _) => (0..w * h).map(|i| [r[i], g[i], b[i]]).collect(),
        (_, _, _, Some(y)) => y.iter().map(|&v| [v; 3]).collect(),
        _ => return Err(err(path, ImportErrorKind::InvalidValue, "the first layer has no R, G, B or Y channels")),
    };
    Ok((w, h, texels))
}

fn read_hdr(path: &Path) -> Result<Texels, ImportError> {
    let file = std::fs::File::open(path).map_err(|e| err(path, ImportErrorKind::Io, e.to_string()))?;
    let decoder = image::codecs::hdr::HdrDecoder::new(std::io::BufReader::new(file))
        .map_err(|e| err(path, ImportErrorKind::Syntax, format!("not a readable Radiance HDR file: {e}")))?;
    let md = decoder.metadata();
    let (w, h) = (md.width as usize, md.height as usize);
    check_size(path, w, h)?;
    let img = image::DynamicImage::from_decoder(decoder)
        .map_err(|e| err(path, ImportErrorKind::Syntax, format!("not a readable Radiance HDR file: {e}")))?
        .into_rgb32f();
    Ok((w, h, img.pixels().map(|p| p.0).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_files_name_the_problem() {
        let dir = tempfile::tempdir().unwrap();
        let missing = load_env_map(&dir.path().join("none.exr")).unwrap_err();
        assert_eq!(missing.kind, ImportErrorKind::MissingFile);
        let junk = dir.path().join("junk.hdr");
        std::fs::write(&junk, "not an image").unwrap();
        let e = load_env_map(&junk).unwrap_err();
        assert!(e.to_string().contains("junk.hdr") && e.to_string().contains("Radiance HDR"), "{e}");
        let png = dir.path().join("sky.png");
        std::fs::write(&png, "x").unwrap();
        assert_eq!(load_env_map(&png).unwrap_err().kind, ImportErrorKind::Unsupported);
    }
}
