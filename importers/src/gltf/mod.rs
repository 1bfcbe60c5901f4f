//! glTF 2.0 importer (`.gltf` with external or `data:` buffers, and `.glb`), built on the `gltf`
//! crate's JSON model; buffers, accessors and images are read here with bounds checks.
//!
//! Full reference: `docs/gltf.md`. In short:
//! - **Geometry**: the default scene (else the first, else every root node), node hierarchy with
//!   TRS or matrix transforms, triangle / strip / fan primitives with indices, normals and
//!   `TEXCOORD_0`; every primitive becomes one world-space [`MeshDesc`](crate::MeshDesc) named
//!   `node:mesh:material` (instances are copied). Lengths are metres times
//!   [`ImportOptions::units_scale`].
//! - **Materials**: metallic-roughness mapped by [`quasar_materials::pbr`]; base colour and
//!   metallic-roughness textures are kept for the renderer ([`MaterialTextures`]); emissive
//!   factor x KHR_materials_emissive_strength (x the emissive texture, per point) is an area
//!   light whose luminance in cd/m^2 is that value (see [`crate::photometric`]).
//! - **Cameras**: perspective cameras in [`SceneDesc::cameras`]; the first is the scene camera,
//!   else the framing camera of [`crate::framing`]; orthographic ones are replaced by a perspective camera (warning).
//! - **Lights**: KHR_lights_punctual, candela / lux converted by [`crate::photometric`].
//! - **Extensions**: [`SUPPORTED_EXTENSIONS`]; others that are used give a warning, others that
//!   are required give an error.
//! - **Errors** name the file and a JSON pointer (`/meshes/0/primitives/1/indices`).

mod accessor;
mod material;
mod nodes;
mod precheck;
mod source;
mod texture;
pub mod writer;

use std::collections::HashMap;
use std::path::Path;

use glam::{Affine3A, Vec3};

pub use crate::texture_decode::{MAX_TEXTURE_ALLOC, MAX_TEXTURE_SIDE, decode_image};
pub use accessor::{MAX_ACCESSOR_COUNT, MAX_ZERO_ACCESSOR_COUNT};
pub use nodes::{MAX_NODE_DEPTH, MAX_NODE_VISITS};
pub use source::MAX_GLTF_BUFFER_BYTES;

use self::accessor::Buffers;
use self::nodes::{Walker, finish_cameras};
use self::texture::TextureLoader;
use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::importer::{Formats, ImportOptions, Importer};
use crate::scene_desc::{MaterialDesc, NamedCamera, SceneDesc};
use crate::texture_desc::MaterialTextures;

/// glTF extensions the importer understands (mapped or approximated as documented).
pub const SUPPORTED_EXTENSIONS: [&str; 9] = [
    "KHR_lights_punctual",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_texture_transform",
];

/// The glTF importer of the registry (`.gltf`, `.glb`).
#[derive(Clone, Copy, Debug, Default)]
pub struct GltfImporter;

impl Importer for GltfImporter {
    fn extensions(&self) -> &[&str] {
        &["gltf", "glb"]
    }

    fn import(&self, path: &Path, opts: &ImportOptions, _: Formats<'_>) -> Result<SceneDesc, ImportError> {
        import_gltf(path, opts)
    }
}

/// An error about `file` at JSON pointer `pointer` (empty: the whole file).
pub(crate) fn err(kind: ImportErrorKind, file: &Path, pointer: &str, msg: impl Into<String>) -> ImportError {
    let msg = msg.into();
    let message = if pointer.is_empty() { msg } else { format!("{pointer}: {msg}") };
    ImportError::new(kind, ErrorPlace::file(file), message)
}

/// `meshes[0].primitives[1].indices` (the `gltf` crate's validation path) as a JSON pointer.
fn json_pointer(path: &str) -> String {
    let mut out = String::from("/");
    for c in path.chars() {
        match c {
            '.' | '[' => out.push('/'),
            ']' | '"' => {}
            c => out.push(c),
        }
    }
    out.replace("//", "/")
}

fn parse_error(path: &Path, e: gltf::Error) -> ImportError {
    match e {
        gltf::Error::Deserialize(j) => {
            let place =
                if j.line() > 0 { ErrorPlace::line_col(path, j.line(), j.column()) } else { ErrorPlace::file(path) };
            ImportError::new(ImportErrorKind::Syntax, place, format!("invalid glTF JSON: {j}"))
        }
        gltf::Error::Binary(b) => err(ImportErrorKind::Syntax, path, "", format!("invalid GLB container: {b}")),
        gltf::Error::Validation(v) => {
            let list: Vec<String> =
                v.iter().take(8).map(|(p, e)| format!("{}: {e}", json_pointer(p.as_str()))).collect();
            let more = if v.len() > 8 { format!(" (and {} more)", v.len() - 8) } else { String::new() };
            err(ImportErrorKind::InvalidValue, path, "", format!("invalid glTF: {}{more}", list.join("; ")))
        }
        other => err(ImportErrorKind::Syntax, path, "", format!("invalid glTF: {other}")),
    }
}

/// Loads every buffer's bytes (GLB chunk, data URI or file) and checks their lengths.
fn load_buffers(
    doc: &gltf::Document,
    blob: Option<Vec<u8>>,
    path: &Path,
    opts: &ImportOptions,
) -> Result<Vec<Vec<u8>>, ImportError> {
    let mut blob = blob;
    let mut out = Vec::new();
    for b in doc.buffers() {
        let ptr = format!("/buffers/{}", b.index());
        let data = match b.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                err(
                    ImportErrorKind::MissingFile,
                    path,
                    &ptr,
                    "buffer has no `uri` and the file has no GLB binary chunk",
                )
            })?,
            gltf::buffer::Source::Uri(uri) => source::uri_bytes(path, uri, &format!("{ptr}/uri"), opts)?,
        };
        if (data.len() as u64) < b.length() as u64 {
            return Err(err(
                ImportErrorKind::InvalidValue,
                path,
                &format!("{ptr}/byteLength"),
                format!("byteLength is {} but the data has only {} bytes", b.length(), data.len()),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// Imports a `.gltf` or `.glb` file (see the module documentation).
pub fn import_gltf(path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    let scale = opts.scale(path)?;
    let bytes = source::read_bounded(path, "glTF file")?;
    precheck::glb_header(path, &bytes)?;
    let g = gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| parse_error(path, e))?;
    drop(bytes);
    let gltf::Gltf { document, blob } = g;
    let mut root = document.into_json();
    if let Some((i, ext)) =
        root.extensions_required.iter().enumerate().find(|(_, e)| !SUPPORTED_EXTENSIONS.contains(&e.as_str()))
    {
        return Err(err(
            ImportErrorKind::Unsupported,
            path,
            &format!("/extensionsRequired/{i}"),
            format!(
                "the file requires extension `{ext}`, which quasar does not support (supported: {})",
                SUPPORTED_EXTENSIONS.join(", ")
            ),
        ));
    }
    let mut warnings = Vec::new();
    let unsupported: Vec<&str> =
        root.extensions_used.iter().map(String::as_str).filter(|e| !SUPPORTED_EXTENSIONS.contains(e)).collect();
    if !unsupported.is_empty() {
        warnings.push(format!(
            "{}: /extensionsUsed: extensions used but not supported (ignored): {}",
            path.display(),
            unsupported.join(", ")
        ));
    }
    // checked above (the `gltf` crate's own list lacks some extensions we approximate)
    root.extensions_required.clear();
    precheck::before_validation(path, &root)?;
    let doc = gltf::Document::from_json(root).map_err(|e| parse_error(path, e))?;
    let buffers = load_buffers(&doc, blob, path, opts)?;

    let roots: Vec<gltf::Node<'_>> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => {
            let mut child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !child[n.index()]).collect()
        }
    };
    let mut walker = Walker {
        buffers: Buffers { file: path, data: &buffers },
        cache: HashMap::new(),
        triangles: 0,
        out: Default::default(),
        warned_modes: Vec::new(),
        warned_features: Vec::new(),
    };
    if doc.animations().len() > 0 {
        warnings.push(format!(
            "{}: {} animation(s) ignored: the static pose (node transforms, default morph weights) is rendered",
            path.display(),
            doc.animations().len()
        ));
    }
    walker.walk(roots, Affine3A::from_scale(Vec3::splat(scale)))?;
    let collected = std::mem::take(&mut walker.out);
    drop(walker);
    warnings.extend(collected.warnings);
    if collected.meshes.is_empty() && collected.lights.is_empty() {
        return Err(err(
            ImportErrorKind::InvalidValue,
            path,
            "",
            "the glTF scene has no triangle meshes and no lights",
        ));
    }

    // materials used by the meshes, in glTF order, then the default material if needed
    let mut loader = TextureLoader {
        file: path,
        doc: &doc,
        opts,
        buffers: &buffers,
        textures: Vec::new(),
        cache: HashMap::new(),
        warnings: Vec::new(),
    };
    let mut materials: Vec<MaterialDesc> = Vec::new();
    let mut emissions = Vec::new();
    let mut params = Vec::new();
    let mut index_of: HashMap<Option<usize>, usize> = HashMap::new();
    let mut names: std::collections::HashSet<String> = std::collections::HashSet::new();
    let gltf_materials: Vec<gltf::Material<'_>> = doc.materials().collect();
    let mut meshes = Vec::with_capacity(collected.meshes.len());
    for (mut mesh, gm) in collected.meshes {
        let si = match index_of.get(&gm) {
            Some(&i) => i,
            None => {
                let m = gm.and_then(|i| gltf_materials.get(i));
                let c = material::convert(m, path, &mut loader, &|n| names.contains(n), scale)?;
                names.insert(c.desc.name.clone());
                materials.push(c.desc);
                emissions.push(c.emission);
                params.push(c.params);
                index_of.insert(gm, materials.len() - 1);
                materials.len() - 1
            }
        };
        mesh.material = si;
        mesh.emission = emissions[si].clone();
        // vertex colours multiply the base colour per point (white ones change nothing)
        if mesh.colors.as_ref().is_some_and(|c| c.iter().all(|&c| c == [1.0; 3])) {
            mesh.colors = None;
        }
        let t = &mut materials[si].textures;
        if mesh.colors.is_some() && t.pbr.is_none() {
            t.pbr = Some(params[si]);
        }
        let has_texture = t.base_color.is_some() || t.metallic_roughness.is_some() || t.normal.is_some();
        if mesh.uvs.is_none() && has_texture {
            let at = mesh.source.item.clone().unwrap_or_default();
            warnings.push(format!(
                "{}: {at}: material `{}` is textured but the primitive has no TEXCOORD_0; the texel at (0, 0) is used",
                path.display(),
                materials[si].name
            ));
        }
        meshes.push(mesh);
    }
    if materials.is_empty() {
        // lights only: meshes refer to nothing, but keep the table non-empty for consistency
        materials.push(MaterialDesc {
            name: "gltf-default".into(),
            material: quasar_materials::pbr_material(&Default::default()),
            absorption: None,
            scattering: None,
            textures: MaterialTextures::default(),
            source: Default::default(),
        });
    }
    warnings.extend(std::mem::take(&mut loader.warnings));

    // (the positions are finite: checked after the node transforms)
    let center = crate::framing::mesh_bounds(&meshes).map_or(Vec3::ZERO, |(lo, hi)| 0.5 * (lo + hi));
    let cameras: Vec<NamedCamera> = {
        let mut names: Vec<String> = Vec::new();
        finish_cameras(collected.cameras, center)
            .into_iter()
            .map(|(name, camera, aspect)| {
                let name = crate::names::unique_name(&name, |n| names.iter().any(|x| x == n));
                names.push(name.clone());
                NamedCamera { name, camera, aspect }
            })
            .collect()
    };
    let mut render = crate::scene_desc::RenderSettings::default();
    let camera = crate::framing::scene_camera(&cameras, &meshes, &mut render);
    Ok(SceneDesc {
        materials,
        meshes,
        lights: collected.lights,
        camera,
        cameras,
        textures: loader.textures,
        warnings,
        render,
        source: path.to_owned(),
        sensors: Vec::new(),
        import_summary: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_paths_become_json_pointers() {
        assert_eq!(json_pointer("meshes[0].primitives[1].indices"), "/meshes/0/primitives/1/indices");
        assert_eq!(
            json_pointer("meshes[0].primitives[0].attributes[\"POSITION\"]"),
            "/meshes/0/primitives/0/attributes/POSITION"
        );
    }
}
