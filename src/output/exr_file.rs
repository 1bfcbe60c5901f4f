//! Single-part, multi-layer float32 OpenEXR files with `layer.channel` names (docs/architecture.md §6),
//! written atomically (temporary file in the same directory, then rename). Header entries
//! `cryptomatte/...` are written as string attributes of those names (`output::cryptomatte`).
//! An image with
//! spectral channels `S0.<lambda>nm` also gets the header attributes of the spectral layout
//! (`spectralLayoutVersion`, `emissiveUnits`; [`SpectralBins::attributes`]).

use std::path::{Path, PathBuf};

use exr::meta::attribute::Chromaticities;
use exr::prelude::*;

use crate::film::{Channel, SpectralBins};

/// An image as named float channels plus text metadata.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Channels (any order; written sorted by name as EXR requires).
    pub channels: Vec<Channel>,
    /// Render metadata as ordered key/value pairs, stored in one text attribute `quasar` as
    /// `key=value` lines (read back by [`read_exr`]) and each as a typed attribute
    /// `quasar:key` for other tools (see [`typed_attribute`]).
    pub metadata: Vec<(String, String)>,
}

/// Error reading or writing an EXR file.
#[derive(Debug, thiserror::Error)]
pub enum ExrError {
    /// I/O or encoding error, with the file.
    #[error("{path}: {msg}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        msg: String,
    },
}

impl ExrImage {
    /// The channel called `name`.
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels.iter().find(|c| c.name == name).map(|c| c.values.as_slice())
    }

    /// The metadata value for `key`.
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.metadata.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }
}

/// The primaries and white point of the `R, G, B` channels: linear sRGB / Rec. 709 with D65
/// (IEC 61966-2-1), as the standard `chromaticities` attribute.
pub const SRGB_CHROMATICITIES: Chromaticities = Chromaticities {
    red: Vec2(0.64, 0.33),
    green: Vec2(0.30, 0.60),
    blue: Vec2(0.15, 0.06),
    white: Vec2(0.3127, 0.3290),
};

/// A metadata value as the EXR attribute other tools (Nuke, OpenImageIO, Blender) show typed:
/// an integer that fits in i32 as `int`, another finite number as `float`, anything else
/// (booleans, seeds beyond i32, lists) as `string`.
pub fn typed_attribute(value: &str) -> AttributeValue {
    if let Ok(i) = value.parse::<i32>() {
        return AttributeValue::I32(i);
    }
    let integer = value.trim_start_matches('-').chars().all(|c| c.is_ascii_digit());
    match value.parse::<f32>() {
        Ok(f) if f.is_finite() && !integer => AttributeValue::F32(f),
        _ => AttributeValue::Text(Text::from(value)),
    }
}

/// Writes `img` to `path` via a temporary file and a rename, so `path` is either the old file or
/// the complete new one, never a truncated file.
pub fn write_exr_atomic(img: &ExrImage, path: &Path) -> std::result::Result<(), ExrError> {
    let err = |msg: String| ExrError::Io { path: path.to_path_buf(), msg };
    for c in &img.channels {
        if c.values.len() != img.width * img.height {
            return Err(err(format!(
                "channel {} has {} values for {}x{}",
                c.name,
                c.values.len(),
                img.width,
                img.height
            )));
        }
    }
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> =
        img.channels.iter().map(|c| AnyChannel::new(c.name.as_str(), FlatSamples::F32(c.values.clone()))).collect();
    let mut attrs = LayerAttributes {
        software_name: Some(Text::from(concat!("quasar ", env!("CARGO_PKG_VERSION")))),
        ..LayerAttributes::default()
    };
    let meta: String = img.metadata.iter().map(|(k, v)| format!("{k}={v}\n")).collect();
    attrs.other.insert(Text::from("quasar"), AttributeValue::Text(Text::from(meta.as_str())));
    for (k, v) in &img.metadata {
        if k.starts_with("cryptomatte/") {
            // the Cryptomatte decoders read these string attributes under their own names
            attrs.other.insert(Text::from(k.as_str()), AttributeValue::Text(Text::from(v.as_str())));
        } else {
            attrs.other.insert(Text::from(format!("quasar:{k}").as_str()), typed_attribute(v));
        }
    }
    // an image with spectral channels is an emissive spectral image of Fichet et al. 2021
    if img.channels.iter().any(|c| SpectralBins::is_channel(&c.name)) {
        for (k, v) in SpectralBins::attributes() {
            attrs.other.insert(Text::from(k), AttributeValue::Text(Text::from(v)));
        }
    }
    let layer = Layer::new((img.width, img.height), attrs, Encoding::SMALL_LOSSLESS, AnyChannels::sort(channels));
    let mut image = Image::from_layer(layer);
    image.attributes.chromaticities = Some(SRGB_CHROMATICITIES);
    super::write_atomic(path, |tmp| image.write().to_file(tmp).map_err(|e| e.to_string()))
        .map_err(|e| ExrError::Io { path: e.path, msg: e.msg })
}

/// Reads a single-part EXR written by quasar (or any flat EXR) into named f32 channels.
pub fn read_exr(path: &Path) -> std::result::Result<ExrImage, ExrError> {
    let err = |msg: String| ExrError::Io { path: path.to_path_buf(), msg };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| err(e.to_string()))?;
    let layer = &image.layer_data;
    let size = layer.size;
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| Channel { name: c.name.to_string(), values: c.sample_data.values_as_f32().collect() })
        .collect();
    let mut metadata = Vec::new();
    if let Some(AttributeValue::Text(t)) = layer.attributes.other.get(&Text::from("quasar")) {
        for line in t.to_string().lines() {
            if let Some((k, v)) = line.split_once('=') {
                metadata.push((k.to_string(), v.to_string()));
            }
        }
    }
    Ok(ExrImage { width: size.0, height: size.1, channels, metadata })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_atomic_failure() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let img = ExrImage {
            width: 3,
            height: 2,
            channels: vec![
                Channel { name: "R".into(), values: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0] },
                Channel { name: "direct.R".into(), values: vec![0.5; 6] },
                Channel { name: "depth.Z".into(), values: vec![f32::INFINITY; 6] },
            ],
            metadata: vec![("method".into(), "pt".into()), ("spp".into(), "4".into())],
        };
        write_exr_atomic(&img, &path).unwrap();
        let back = read_exr(&path).unwrap();
        assert_eq!(back.width, 3);
        assert_eq!(back.channel("R").unwrap(), &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(back.channel("direct.R").unwrap(), &[0.5; 6]);
        assert_eq!(back.meta("spp"), Some("4"));
        // typed attributes and the standard chromaticities, as other tools read them
        let raw = read().no_deep_data().largest_resolution_level().all_channels().first_valid_layer().all_attributes();
        let raw = raw.from_file(&path).unwrap();
        let other = &raw.layer_data.attributes.other;
        assert_eq!(other.get(&Text::from("quasar:spp")), Some(&AttributeValue::I32(4)));
        assert_eq!(other.get(&Text::from("quasar:method")), Some(&AttributeValue::Text(Text::from("pt"))));
        assert_eq!(raw.attributes.chromaticities, Some(SRGB_CHROMATICITIES));
        assert_eq!(typed_attribute("0.25"), AttributeValue::F32(0.25));
        assert_eq!(typed_attribute("18446744073709551615"), AttributeValue::Text(Text::from("18446744073709551615")));
        assert_eq!(typed_attribute("true"), AttributeValue::Text(Text::from("true")));
        assert_eq!(typed_attribute("inf"), AttributeValue::Text(Text::from("inf")));
        // A failing write leaves the existing file untouched and no temporary behind.
        let before = std::fs::read(&path).unwrap();
        let mut bad = img.clone();
        bad.channels[0].values.pop();
        assert!(write_exr_atomic(&bad, &path).is_err());
        assert_eq!(std::fs::read(&path).unwrap(), before);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
