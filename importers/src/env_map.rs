//! Lat-long (equirectangular) environment maps: `.exr` (the `exr` crate: the first layer's R, G,
//! B channels, or Y for a grey map) and Radiance `.hdr` (the `image` crate), read into linear RGB
//! radiance texels. Errors name the file; sizes are checked before anything is decoded.
//!
//! The mapping (documented in docs/scene-format.md): row 0 is the zenith (+Y), the last row the
//! nadir; u = 0.5 + atan2(d.x, -d.z) / (2 pi), so the image centre looks along -Z (where the
//! default camera looks), and u increases towards +X.

use std::io::{Read, Seek};
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
    let ext = crate::asset::file_name(path)
        .and_then(|n| Path::new(&n).extension().map(|e| e.to_string_lossy().to_ascii_lowercase()));
    if !matches!(ext.as_deref(), Some("exr" | "hdr")) {
        return Err(err(path, ImportErrorKind::Unsupported, "environment maps must be .exr or .hdr (lat-long)"));
    }
    let (width, height, texels) = if crate::asset::package_entry(path).is_some() {
        // an entry of a .usdz package: read whole (under the limit), decoded from memory
        let bytes = crate::asset::read_asset(path, MAX_ENV_MAP_BYTES)
            .map_err(|(kind, msg)| err(path, kind, format!("cannot read the environment map: {msg}")))?;
        let bytes = std::io::Cursor::new(bytes);
        if ext.as_deref() == Some("exr") { read_exr(path, bytes)? } else { read_hdr(path, bytes)? }
    } else {
        let meta = std::fs::metadata(path).map_err(|e| {
            let kind = if e.kind() == std::io::ErrorKind::NotFound {
                ImportErrorKind::MissingFile
            } else {
                ImportErrorKind::Io
            };
            err(path, kind, format!("cannot read the environment map: {e}"))
        })?;
        if meta.len() > MAX_ENV_MAP_BYTES {
            return Err(err(path, ImportErrorKind::TooLarge, format!("{} bytes is more than 2 GiB", meta.len())));
        }
        let file = std::fs::File::open(path).map_err(|e| err(path, ImportErrorKind::Io, e.to_string()))?;
        let file = std::io::BufReader::new(file);
        if ext.as_deref() == Some("exr") { read_exr(path, file)? } else { read_hdr(path, file)? }
    };
    if let Some((i, t)) = texels.iter().enumerate().find(|(_, t)| t.iter().any(|v| !v.is_finite() || *v < 0.0)) {
        return Err(err(
            path,
            ImportErrorKind::InvalidValue,
            format!("texel ({}, {}) is not finite and >= 0: {t:?}", i % width, i / width),
        ));
    }
    Ok(EnvMapDesc { file: path.to_path_buf(), width, height, texels, frame: glam::Mat3::IDENTITY })
}

type Texels = (usize, usize, Vec<[f32; 3]>);

/// The pixels of the OpenEXR file `path` read from `source`.
fn read_exr<R: Read + Seek + Send>(path: &Path, mut source: R) -> Result<Texels, ImportError> {
    use exr::prelude::*;
    let bad = |e: exr::error::Error| err(path, ImportErrorKind::Syntax, format!("not a readable OpenEXR file: {e}"));
    // the header first: refuse huge images before decoding any pixel
    let meta = MetaData::read_from_buffered(&mut source, false).map_err(bad)?;
    source.seek(std::io::SeekFrom::Start(0)).map_err(|e| err(path, ImportErrorKind::Io, e.to_string()))?;
    let header = meta.headers.first().ok_or_else(|| err(path, ImportErrorKind::Syntax, "no image in the file"))?;
    let size = header.layer_size;
    check_size(path, size.0, size.1)?;
    let image = read().no_deep_data().largest_resolution_level().all_channels().first_valid_layer().all_attributes();
    let image = image.from_buffered(source).map_err(bad)?;
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

/// The pixels of the Radiance HDR file `path` read from `source`.
fn read_hdr<R: std::io::BufRead>(path: &Path, source: R) -> Result<Texels, ImportError> {
    let decoder = image::codecs::hdr::HdrDecoder::new(source)
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

    /// A map inside a `.usdz` package (`pkg.usdz[sky.exr]`) reads to the texels of the loose file.
    #[test]
    fn maps_inside_packages_read_like_files() {
        use std::io::Write;
        let dir = tempfile::tempdir().unwrap();
        let sky = dir.path().join("sky.exr");
        exr::prelude::write_rgb_file(&sky, 4, 2, |x, y| (x as f32, y as f32, 0.5)).unwrap();
        let pkg = dir.path().join("pkg.usdz");
        let mut z = zip::ZipWriter::new(std::fs::File::create(&pkg).unwrap());
        z.start_file("sky.exr", zip::write::SimpleFileOptions::default()).unwrap();
        z.write_all(&std::fs::read(&sky).unwrap()).unwrap();
        z.finish().unwrap();
        let loose = load_env_map(&sky).unwrap();
        let packed = load_env_map(Path::new(&format!("{}[sky.exr]", pkg.display()))).unwrap();
        assert_eq!((packed.width, packed.height, &packed.texels), (4, 2, &loose.texels));
        assert_eq!(loose.texels[5], [1.0, 1.0, 0.5]);
        let missing = load_env_map(Path::new(&format!("{}[none.exr]", pkg.display()))).unwrap_err();
        assert_eq!(missing.kind, ImportErrorKind::MissingFile);
    }
}
