//! Checks of the raw JSON model before the `gltf` crate's validation and accessors run: fields
//! that the crate indexes or unwraps without checking (each found by fuzzing) become errors with
//! a JSON pointer here.

use std::path::Path;

use gltf::json::validation::Checked;

use super::err;
use crate::error::{ImportError, ImportErrorKind};

/// Checks a GLB header's total length before the `gltf` crate subtracts the header size from it
/// (an overflow for lengths < 12, found by fuzzing).
pub(super) fn glb_header(path: &Path, bytes: &[u8]) -> Result<(), ImportError> {
    if bytes.len() < 12 || !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let length = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize;
    if length < 12 || length > bytes.len() {
        return Err(err(
            ImportErrorKind::Syntax,
            path,
            "",
            format!("invalid GLB container: the header's length {length} is not within 12..={}", bytes.len()),
        ));
    }
    Ok(())
}

/// Checks that every `POSITION` attribute names an existing accessor: the `gltf` crate's
/// validation indexes the accessor list with it unchecked (a panic, found by fuzzing).
fn position_accessors(path: &Path, root: &gltf::json::Root) -> Result<(), ImportError> {
    let n = root.accessors.len();
    for (mi, m) in root.meshes.iter().enumerate() {
        for (pi, p) in m.primitives.iter().enumerate() {
            for (sem, a) in &p.attributes {
                if a.value() >= n {
                    let name = match sem {
                        Checked::Valid(s) => s.to_string(),
                        Checked::Invalid => "(invalid)".into(),
                    };
                    return Err(err(
                        ImportErrorKind::InvalidValue,
                        path,
                        &format!("/meshes/{mi}/primitives/{pi}/attributes/{name}"),
                        format!("accessor {} does not exist (the file has {n})", a.value()),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Images need a `uri` or a `bufferView`, and a `mimeType` with a `bufferView` (the crate unwraps
/// both); cameras need the projection object their `type` names (the crate checks only that one of
/// the two exists, then unwraps the named one).
fn images_and_cameras(path: &Path, root: &gltf::json::Root) -> Result<(), ImportError> {
    let missing = |ptr: String, msg: &str| err(ImportErrorKind::InvalidValue, path, &ptr, msg);
    for (i, im) in root.images.iter().enumerate() {
        if im.buffer_view.is_some() && im.mime_type.is_none() {
            return Err(missing(format!("/images/{i}"), "an image in a bufferView needs a `mimeType`"));
        }
        if im.buffer_view.is_none() && im.uri.is_none() {
            return Err(missing(format!("/images/{i}"), "the image has neither `uri` nor `bufferView`"));
        }
    }
    for (i, c) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        let ok = match c.type_ {
            Checked::Valid(Type::Perspective) => c.perspective.is_some(),
            Checked::Valid(Type::Orthographic) => c.orthographic.is_some(),
            Checked::Invalid => true, // reported by validation
        };
        if !ok {
            return Err(missing(format!("/cameras/{i}"), "the camera lacks the projection object its `type` names"));
        }
    }
    Ok(())
}

/// Every check of this module on the JSON model (before `gltf::Document::from_json`).
pub(super) fn before_validation(path: &Path, root: &gltf::json::Root) -> Result<(), ImportError> {
    position_accessors(path, root)?;
    images_and_cameras(path, root)
}
