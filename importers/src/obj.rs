//! Wavefront OBJ/MTL importer (via `tobj`, triangulated, single-indexed).
//!
//! Every file is first checked line by line (module `obj_lint`) so malformed input always gets
//! an error naming the file and line; `tobj` then builds the meshes.
//!
//! # Meshes
//! Each OBJ object/group with its own material becomes one [`MeshDesc`] named
//! `"file.obj:object:material"`. Vertex normals (`vn`) are used when every vertex of the mesh has
//! a finite, non-zero one; otherwise the mesh is flat-shaded (`normals = None`). Degenerate
//! triangles are kept; NaN or infinite coordinates are errors. Lengths are taken as metres (times
//! [`ImportOptions::units_scale`]).
//!
//! # MTL -> material mapping
//! One analytic model per material, so a Kd + Ks blend keeps only its dominant lobe:
//! - **Transparent** (`illum` 4, 6, 7 or 9, or `d` < 1, or `Tr` > 0 when `d` is absent) ->
//!   [`Material::Dielectric`] with `ior = Ni` (when `Ni` > 1, else 1.5), tinted by `Tf` (the
//!   transmission filter, in [0, 1]) at each crossing. `Tf` alone does not make a material
//!   transparent (many exporters write `Tf 1 1 1` for opaque materials).
//! - **Specular-dominant** (mean(Ks) > 0 and mean(Kd) < 0.1 * mean(Ks), i.e. Kd is ~black
//!   relative to Ks) -> [`Material::Conductor`] with the angle-independent Fresnel reflectance
//!   `Ks` (RGB reflectance uplift), two-sided.
//! - **Otherwise** -> [`Material::Diffuse`] with reflectance `Kd` (RGB reflectance uplift),
//!   two-sided; the specular lobe is dropped. Without `Kd` and `Ks` the reflectance is 0.8 grey.
//! - Roughness: the Phong exponent `Ns` becomes the GGX alpha `sqrt(2 / (Ns + 2))` (clamped to
//!   at most 1); `Ns` >= 1000 (the top of the MTL range) and a missing `Ns` give a smooth surface.
//! - **Emission**: a non-zero `Ke` makes the mesh an area light with spectrum
//!   `Spectrum::rgb_illuminant(Ke)`, scale 1, emitting only to the front (counter-clockwise) side.
//! - Textures, `Ka` and `illum` models other than the transparent ones are ignored.
//!
//! # Camera
//! OBJ has no cameras: the scene camera frames the model ([`crate::framing`]: its bounding sphere
//! from the front, or through the open side of an open model such as a Cornell box).
//!
//! Without any `mtllib`, every mesh gets a default grey diffuse material (reflectance 0.8,
//! two-sided) named after its `usemtl` name (or `default`). With an `mtllib`, a `usemtl` name
//! that no library defines is an error (with the nearest name); a missing library file is a
//! warning naming the OBJ line, and the names it should define get the grey default, as in
//! Blender and tinyobjloader.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Cursor, Read};
use std::path::{Path, PathBuf};

use glam::Vec3;
use quasar_materials::{ConductorFresnel, Ior, Material, spectrum::Spectrum};

use crate::error::{ErrorPlace, ImportError, ImportErrorKind, did_you_mean};
use crate::importer::{Formats, ImportOptions, Importer};
use crate::names::unique_name;
use crate::obj_lint::{self, MAX_OBJ_BYTES, MtlEntry};
use crate::obj_text;
use crate::scene_desc::{EmissionDesc, MaterialDesc, MeshDesc, SceneDesc, SourceLocation};
use crate::small_text::read_small_text;

/// The OBJ importer of the registry (`.obj`).
#[derive(Clone, Copy, Debug, Default)]
pub struct ObjImporter;

impl Importer for ObjImporter {
    fn extensions(&self) -> &[&str] {
        &["obj"]
    }

    fn import(&self, path: &Path, opts: &ImportOptions, _: Formats<'_>) -> Result<SceneDesc, ImportError> {
        import_obj(path, opts, ObjMaterials::FromMtl)
    }
}

/// How [`import_obj`] treats the OBJ's materials.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ObjMaterials {
    /// Read the `mtllib` files and map each material (see the module documentation).
    #[default]
    FromMtl,
    /// Do not read `mtllib` files: every `usemtl` name gets a grey diffuse placeholder (the caller
    /// replaces the materials, e.g. a TOML include with `material = ...`). No `Ke` emission.
    NamesOnly,
}

/// Grey used when an OBJ has no material information.
pub const DEFAULT_GREY: f32 = 0.8;

/// A material name `tobj` will never see in a real file: the material table is handed to `tobj`
/// through a synthetic first line `mtllib <SENTINEL>`.
const SENTINEL: &str = "<quasar-material-table>";

fn grey_diffuse() -> Material {
    Material::Diffuse { reflectance: Spectrum::Constant(DEFAULT_GREY), two_sided: true }
}

/// Opens `file` for buffered reading, past a UTF-8 byte order mark if there is one.
fn open_skipping_bom(file: &Path) -> Result<BufReader<File>, ImportError> {
    let f = File::open(file).map_err(|e| ImportError::io(file, "cannot open OBJ file", e))?;
    let mut r = BufReader::new(f);
    let bom = r.fill_buf().map_err(|e| ImportError::io(file, "cannot read OBJ file", e))?.starts_with(b"\xEF\xBB\xBF");
    if bom {
        r.consume(3);
    }
    Ok(r)
}

/// One material of a loaded MTL library.
struct MtlMaterial {
    tobj: tobj::Material,
    entry: MtlEntry,
    file: PathBuf,
}

/// Resolves an `mtllib` argument: the whole text as one file name if it exists, else each
/// whitespace-separated name. Returns the files found and a warning per missing one (naming the
/// OBJ line: Blender and tinyobjloader warn and go on, and so does quasar).
fn resolve_mtllib(obj: &Path, lib: &obj_lint::MtlLib) -> (Vec<PathBuf>, Vec<String>) {
    let dir = obj.parent().unwrap_or(Path::new(""));
    let whole = dir.join(&lib.names);
    if whole.is_file() {
        return (vec![whole], Vec::new());
    }
    let (mut found, mut missing) = (Vec::new(), Vec::new());
    for name in lib.names.split_whitespace() {
        let p = dir.join(name);
        if p.is_file() {
            found.push(p);
        } else {
            missing.push(format!(
                "{}:{}: material library `{name}` not found (looked for {}); materials it should define render as grey diffuse",
                obj.display(),
                lib.line,
                p.display()
            ));
        }
    }
    (found, missing)
}

/// Loads and checks one MTL file.
fn load_mtl(file: &Path) -> Result<Vec<MtlMaterial>, ImportError> {
    let text = read_small_text(file, "material library")?;
    let lint = obj_lint::lint_mtl(file, &text)?;
    let (mats, _) = tobj::load_mtl_buf(&mut Cursor::new(lint.normalized.as_bytes())).map_err(|e| {
        ImportError::new(ImportErrorKind::Syntax, ErrorPlace::file(file), format!("MTL parse error: {e}"))
    })?;
    if mats.len() != lint.entries.len() {
        return Err(ImportError::new(
            ImportErrorKind::Syntax,
            ErrorPlace::file(file),
            format!("MTL parse error: found {} materials, expected {}", mats.len(), lint.entries.len()),
        ));
    }
    Ok(mats
        .into_iter()
        .zip(lint.entries)
        .map(|(tobj, entry)| MtlMaterial { tobj, entry, file: file.to_owned() })
        .collect())
}

/// The GGX alpha of a Phong exponent (see the module documentation); `None` = smooth.
pub fn phong_to_alpha(ns: Option<f32>) -> f32 {
    match ns {
        Some(ns) if ns < 1000.0 => (2.0 / (ns.max(0.0) + 2.0)).sqrt().min(1.0),
        _ => 0.0,
    }
}

fn mean3(c: [f32; 3]) -> f32 {
    (c[0] + c[1] + c[2]) / 3.0
}

/// Maps one MTL material to a quasar material and optional emission (module documentation).
fn convert_mtl(m: &MtlMaterial) -> Result<(Material, Option<EmissionDesc>), ImportError> {
    let t = &m.tobj;
    let e = &m.entry;
    let err = |key: &str, msg: String| {
        ImportError::new(
            ImportErrorKind::InvalidValue,
            ErrorPlace::line(&m.file, e.line_of(key)),
            format!("material `{}`: {msg}", e.name),
        )
    };
    if let Some(ns) = t.shininess.filter(|&ns| ns < 0.0) {
        return Err(err("Ns", format!("Ns (Phong exponent) must be >= 0, got {ns}")));
    }
    let transparent = matches!(t.illumination_model, Some(4 | 6 | 7 | 9))
        || t.dissolve.is_some_and(|d| d < 1.0)
        || (t.dissolve.is_none() && e.tr.is_some_and(|tr| tr > 0.0));
    let alpha = phong_to_alpha(t.shininess);
    let material = if transparent {
        let ior = match t.optical_density {
            Some(n) if n > 1.0 => n,
            _ => 1.5,
        };
        // `Tf`, the transmission filter, tints the transmitted light (white: clear)
        let transmittance = match e.tf.filter(|&tf| tf != [1.0; 3]) {
            Some(tf) => Some(Spectrum::rgb_reflectance(tf).map_err(|x| err("Tf", format!("Tf: {x}")))?),
            None => None,
        };
        Material::Dielectric { ior: Ior::Constant(ior), alpha, transmittance }
    } else {
        let ks = t.specular.unwrap_or([0.0; 3]);
        let kd = t.diffuse.unwrap_or(if t.specular.is_some() { [0.0; 3] } else { [DEFAULT_GREY; 3] });
        if mean3(ks) > 0.0 && mean3(kd) < 0.1 * mean3(ks) {
            let r = Spectrum::rgb_reflectance(ks).map_err(|x| err("Ks", format!("Ks: {x}")))?;
            Material::Conductor { alpha, fresnel: ConductorFresnel::Constant(r), two_sided: true }
        } else {
            let r = Spectrum::rgb_reflectance(kd).map_err(|x| err("Kd", format!("Kd: {x}")))?;
            Material::Diffuse { reflectance: r, two_sided: true }
        }
    };
    material.validate().map_err(|x| err("newmtl", x))?;
    let emission = match t.emissive {
        Some(ke) if ke.iter().any(|&c| c != 0.0) => {
            let s = Spectrum::rgb_illuminant(ke).map_err(|x| err("Ke", format!("Ke: {x}")))?;
            Some(EmissionDesc { spectrum: s, scale: 1.0, two_sided: false, texture: None })
        }
        _ => None,
    };
    Ok((material, emission))
}

/// A material of the scene being built, with the emission its meshes get.
struct SceneMaterial {
    desc: MaterialDesc,
    emission: Option<EmissionDesc>,
}

/// Imports an OBJ file (and its MTL libraries, unless `materials` is [`ObjMaterials::NamesOnly`])
/// into a [`SceneDesc`] with materials and meshes, the framing camera of [`crate::framing`] and
/// default settings (no lights but emissive `Ke` meshes).
pub fn import_obj(path: &Path, opts: &ImportOptions, materials: ObjMaterials) -> Result<SceneDesc, ImportError> {
    let scale = opts.scale(path)?;
    let len = std::fs::metadata(path).map_err(|e| ImportError::io(path, "cannot open OBJ file", e))?.len();
    if len > MAX_OBJ_BYTES {
        return Err(ImportError::new(
            ImportErrorKind::TooLarge,
            ErrorPlace::file(path),
            format!("OBJ file is {len} bytes, more than the limit of {MAX_OBJ_BYTES}"),
        ));
    }
    let summary = obj_lint::lint_obj(path, &mut open_skipping_bom(path)?)?;
    if summary.triangles == 0 {
        return Err(ImportError::new(ImportErrorKind::InvalidValue, ErrorPlace::file(path), "OBJ file has no faces"));
    }
    let mut warnings = crate::obj_keywords::ignored_warnings(path, &summary.ignored);

    // Material libraries: name -> material (a later definition wins, as in tobj).
    let mut libs: Vec<MtlMaterial> = Vec::new();
    let mut lib_files: Vec<PathBuf> = Vec::new();
    let mut libs_missing = false;
    if materials == ObjMaterials::FromMtl {
        for lib in &summary.mtllibs {
            let (found, missing) = resolve_mtllib(path, lib);
            libs_missing |= !missing.is_empty();
            warnings.extend(missing);
            for file in found {
                libs.extend(load_mtl(&file).map_err(|e| e.included_from(ErrorPlace::line(path, lib.line)))?);
                lib_files.push(file);
            }
        }
    }
    let by_name: HashMap<&str, usize> = libs.iter().enumerate().map(|(i, m)| (m.entry.name.as_str(), i)).collect();

    // The scene's materials, one per distinct `usemtl` name, plus a default when needed.
    let mut scene_mats: Vec<SceneMaterial> = Vec::new();
    let mut scene_index: HashMap<String, usize> = HashMap::new();
    let mut key_to_scene: Vec<usize> = Vec::new();
    let mut tobj_table: Vec<tobj::Material> = Vec::new();
    let mut tobj_keys: HashMap<String, usize> = HashMap::new();
    for u in &summary.usemtls {
        if tobj_keys.contains_key(&u.tobj_key) {
            continue;
        }
        let si = match scene_index.get(&u.name) {
            Some(&i) => i,
            None => {
                let source = SourceLocation { file: path.to_owned(), line: Some(u.line), item: Some(u.name.clone()) };
                let (material, emission, source) = match (materials, by_name.get(u.name.as_str())) {
                    (ObjMaterials::FromMtl, Some(&li)) => {
                        let m = &libs[li];
                        let (mat, em) = convert_mtl(m)?;
                        let src = SourceLocation {
                            file: m.file.clone(),
                            line: Some(m.entry.line),
                            item: Some(m.entry.name.clone()),
                        };
                        (mat, em, src)
                    }
                    // with every library read, an undefined name is a typo worth an error; with
                    // one missing, its materials are grey (the warning above says so)
                    (ObjMaterials::FromMtl, None) if !summary.mtllibs.is_empty() && !libs_missing => {
                        let names: Vec<&str> = libs.iter().map(|m| m.entry.name.as_str()).collect();
                        let files: Vec<String> = lib_files.iter().map(|f| f.display().to_string()).collect();
                        return Err(ImportError::new(
                            ImportErrorKind::UnresolvedReference,
                            ErrorPlace::line(path, u.line),
                            format!(
                                "material `{}` is not defined in the material libraries ({}){}",
                                u.name,
                                files.join(", "),
                                did_you_mean(&u.name, names)
                            ),
                        ));
                    }
                    _ => (grey_diffuse(), None, source),
                };
                scene_mats.push(SceneMaterial {
                    desc: MaterialDesc {
                        name: u.name.clone(),
                        material,
                        absorption: None,
                        scattering: None,
                        textures: Default::default(),
                        source,
                    },
                    emission,
                });
                scene_index.insert(u.name.clone(), scene_mats.len() - 1);
                scene_mats.len() - 1
            }
        };
        tobj_keys.insert(u.tobj_key.clone(), tobj_table.len());
        tobj_table.push(tobj::Material { name: u.tobj_key.clone(), ..Default::default() });
        key_to_scene.push(si);
    }

    let load_opts =
        tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    let header = format!("mtllib {SENTINEL}\n");
    let mut reader =
        BufReader::new(Cursor::new(header.into_bytes()).chain(obj_text::CommentFree::new(open_skipping_bom(path)?)));
    let (models, _) = tobj::load_obj_buf(&mut reader, &load_opts, |p| {
        if p == Path::new(SENTINEL) {
            Ok((tobj_table.clone(), tobj_keys.iter().map(|(k, v)| (k.clone(), *v)).collect()))
        } else {
            Ok((Vec::new(), Default::default()))
        }
    })
    .map_err(|e| ImportError::new(ImportErrorKind::Syntax, ErrorPlace::file(path), format!("OBJ parse error: {e}")))?;

    let file_name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
    let mut default_index = None;
    let mut meshes = Vec::new();
    for model in models {
        let mesh = model.mesh;
        if mesh.indices.is_empty() {
            continue;
        }
        let si = match mesh.material_id.and_then(|i| key_to_scene.get(i)) {
            Some(&si) => si,
            None => *default_index.get_or_insert_with(|| {
                let name = unique_name("default", |n| scene_index.contains_key(n));
                scene_mats.push(SceneMaterial {
                    desc: MaterialDesc {
                        name,
                        material: grey_diffuse(),
                        absorption: None,
                        scattering: None,
                        textures: Default::default(),
                        source: SourceLocation { file: path.to_owned(), line: None, item: None },
                    },
                    emission: None,
                });
                scene_mats.len() - 1
            }),
        };
        let positions: Vec<Vec3> =
            mesh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2]) * scale).collect();
        if positions.iter().any(|p| !p.is_finite()) {
            return Err(ImportError::new(
                ImportErrorKind::InvalidValue,
                ErrorPlace::file(path),
                format!("object `{}`: coordinates overflow after scaling by {scale}", model.name),
            ));
        }
        let normals = if mesh.normals.len() == mesh.positions.len() {
            let ns: Vec<Vec3> = mesh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
            ns.iter()
                .all(|n| n.is_finite() && n.length_squared() > 0.0)
                .then(|| ns.iter().map(|n| n.normalize()).collect())
        } else {
            None
        };
        let indices: Vec<[u32; 3]> = mesh.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let mat = &scene_mats[si];
        meshes.push(MeshDesc {
            name: format!("{file_name}:{}:{}", model.name, mat.desc.name),
            positions,
            normals,
            uvs: None,
            colors: None,
            indices,
            material: si,
            emission: mat.emission.clone(),
            source: SourceLocation { file: path.to_owned(), line: None, item: Some(model.name.clone()) },
        });
    }
    Ok(SceneDesc {
        materials: scene_mats.into_iter().map(|m| m.desc).collect(),
        camera: crate::framing::framing_camera(&meshes).unwrap_or_default(),
        meshes,
        warnings,
        source: path.to_owned(),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phong_exponent_to_alpha() {
        assert_eq!(phong_to_alpha(None), 0.0);
        assert_eq!(phong_to_alpha(Some(1000.0)), 0.0);
        assert!((phong_to_alpha(Some(0.0)) - 1.0).abs() < 1e-6);
        assert!((phong_to_alpha(Some(98.0)) - 0.141_421_36).abs() < 1e-6);
    }
}
