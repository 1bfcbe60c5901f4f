//! The native TOML scene format (DESIGN.md section 7; full reference in `docs/scene-format.md`).
//!
//! The document is parsed into a span-preserving tree (`toml::de::DeTable`) and read with typed,
//! span-aware accessors, so every error — syntax, unknown key, wrong type, out-of-range value,
//! unknown material, invalid material parameters, missing referenced file — names the scene
//! file, line and column of the offending key, value or table.

mod material;
pub(crate) mod reader;
mod settings;
mod shape;
mod spectrum;

use std::collections::HashMap;
use std::path::Path;

use glam::{Affine3A, Vec3};
use quasar_materials::Material;
use quasar_materials::spectrum::Spectrum;
use toml::de::DeValue;

pub use material::MATERIAL_TYPES;
pub use shape::{DEFAULT_DISK_SEGMENTS, DEFAULT_SPHERE_SUBDIVISIONS, MAX_DISK_SEGMENTS, MAX_SPHERE_SUBDIVISIONS};
pub use spectrum::{MAX_SPECTRUM_ENTRIES, csv_spectrum};

use self::reader::{Doc, Tbl, Val, parse_document, string};
use crate::error::{ErrorPlace, ImportError, ImportErrorKind, did_you_mean};
use crate::glob::glob_match;
use crate::obj::{ObjMaterials, import_obj, read_small_text, unique_name};
use crate::registry::{ImportOptions, Importer, importer_for, supported_extensions};
use crate::scene_desc::{
    CameraDesc, LightDesc, MaterialDesc, MeshDesc, NamedCamera, SceneDesc, SourceLocation, TextureDesc,
};
use crate::transform::{flip_mesh, transform_camera, transform_light, transform_mesh};

/// Integration methods accepted by `[render] method`.
/// Length units accepted by `units`, with their size in metres.
pub const UNITS: [(&str, f32); 5] = [("m", 1.0), ("cm", 0.01), ("mm", 0.001), ("in", 0.0254), ("ft", 0.3048)];
/// How deep TOML scenes may include TOML scenes (guards against include cycles).
pub const MAX_INCLUDE_DEPTH: u32 = 8;
/// Largest number of triangles in one scene (shapes and includes together).
pub const MAX_SCENE_TRIANGLES: u64 = 1 << 28;
/// Shape types of `[[shape]]`.
pub const SHAPE_TYPES: [&str; 4] = ["mesh", "quad", "sphere", "disk"];
/// Light types of `[[light]]`.
pub const LIGHT_TYPES: [&str; 4] = ["point", "spot", "directional", "environment"];

const TOP_KEYS: [&str; 8] = ["units", "render", "camera", "materials", "shape", "light", "include", "override"];

/// The TOML scene importer of the registry (`.toml`).
#[derive(Clone, Copy, Debug, Default)]
pub struct TomlSceneImporter;

impl Importer for TomlSceneImporter {
    fn extensions(&self) -> &[&str] {
        &["toml"]
    }

    fn import(&self, path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
        import_toml_scene(path, opts)
    }
}

/// Reads and imports the TOML scene file at `path`.
pub fn import_toml_scene(path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    import_at_depth(path, opts, 0)
}

/// Imports TOML scene text as if it were the file `path` (used for messages and to resolve
/// relative file names against `path`'s directory).
pub fn parse_toml_scene(text: &str, path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    parse_at_depth(text, path, opts, 0)
}

fn import_at_depth(path: &Path, opts: &ImportOptions, depth: u32) -> Result<SceneDesc, ImportError> {
    let text = read_small_text(path, "scene file")?;
    parse_at_depth(&text, path, opts, depth)
}

fn parse_at_depth(text: &str, path: &Path, opts: &ImportOptions, depth: u32) -> Result<SceneDesc, ImportError> {
    let extra = opts.scale(path)?;
    let root = parse_document(text, path)?;
    let doc = Doc::new(path, text);
    let top = Tbl::root(&doc, &root);
    top.check_keys(&TOP_KEYS)?;
    let scene_unit = units(&top, "units")?.unwrap_or(1.0);
    let mut b = Builder {
        doc: &doc,
        scene_unit,
        extra,
        unit: scene_unit * extra,
        depth,
        materials: Vec::new(),
        by_name: HashMap::new(),
        toml_materials: HashMap::new(),
        meshes: Vec::new(),
        orig_material: Vec::new(),
        lights: Vec::new(),
        black: None,
        triangles: 0,
        cameras: Vec::new(),
        textures: Vec::new(),
        warnings: Vec::new(),
    };
    if let Some(m) = top.opt_table("materials")? {
        b.materials(&m)?;
    }
    for (i, s) in tables(&top, "shape")?.into_iter().enumerate() {
        b.shape(i, &s)?;
    }
    for inc in tables(&top, "include")? {
        b.include(&inc)?;
    }
    for l in tables(&top, "light")? {
        b.lights.push(settings::light(&l, b.unit)?);
    }
    let camera = b.camera(top.opt_table("camera")?)?;
    let render = settings::render(top.opt_table("render")?, b.unit)?;
    for o in tables(&top, "override")? {
        b.override_(&o)?;
    }
    if b.meshes.is_empty() && b.lights.is_empty() {
        return Err(ImportError::new(
            ImportErrorKind::InvalidValue,
            ErrorPlace::line_col(path, 1, 1),
            "the scene is empty: it has no [[shape]], [[include]] or [[light]]",
        ));
    }
    Ok(SceneDesc {
        materials: b.materials,
        meshes: b.meshes,
        lights: b.lights,
        camera,
        cameras: b.cameras,
        textures: b.textures,
        warnings: b.warnings,
        render,
        source: path.to_owned(),
    })
}

/// The elements of an array of tables `[[key]]` (none when absent).
fn tables<'a>(top: &Tbl<'a>, key: &str) -> Result<Vec<Tbl<'a>>, ImportError> {
    let Some(v) = top.get(key) else { return Ok(Vec::new()) };
    match v.get_ref() {
        DeValue::Array(a) => a.iter().enumerate().map(|(i, e)| Tbl::of(top.doc, e, format!("{key}[{i}]"))).collect(),
        DeValue::Table(_) => Err(top.doc.invalid(
            &v.span(),
            format!("`{key}` must be an array of tables: write [[{key}]] (double brackets) for each entry"),
        )),
        other => Err(top.doc.invalid(
            &v.span(),
            format!("`{key}` must be an array of tables ([[{key}]]), got {}", reader::type_name(other)),
        )),
    }
}

/// A `units` value in metres per unit.
fn units(t: &Tbl<'_>, key: &str) -> Result<Option<f32>, ImportError> {
    let names: Vec<&str> = UNITS.iter().map(|u| u.0).collect();
    Ok(t.choice(key, &names)?.map(|(s, _)| UNITS.iter().find(|u| u.0 == s).map_or(1.0, |u| u.1)))
}

/// Accumulates the scene while the document is read.
struct Builder<'a> {
    doc: &'a Doc<'a>,
    /// Metres per scene unit.
    scene_unit: f32,
    /// Extra scale from [`ImportOptions::units_scale`].
    extra: f32,
    /// `scene_unit * extra`: converts scene lengths to output metres.
    unit: f32,
    depth: u32,
    materials: Vec<MaterialDesc>,
    /// Every material name in `materials` -> index.
    by_name: HashMap<String, usize>,
    /// `[materials.NAME]` names -> index (what `material = "NAME"` may refer to).
    toml_materials: HashMap<String, usize>,
    meshes: Vec<MeshDesc>,
    /// Per mesh: the material name it had in its source (OBJ/MTL name), for `[[override]]`.
    orig_material: Vec<String>,
    lights: Vec<LightDesc>,
    /// Index of the implicit black material of emitters without `material`.
    black: Option<usize>,
    /// Triangles so far (limited by [`MAX_SCENE_TRIANGLES`]).
    triangles: u64,
    /// Cameras of included files (glTF), in include order.
    cameras: Vec<NamedCamera>,
    /// Textures of included files.
    textures: Vec<TextureDesc>,
    /// Warnings of included files.
    warnings: Vec<String>,
}

impl<'a> Builder<'a> {
    fn source(&self, t: &Tbl<'_>, item: String) -> SourceLocation {
        SourceLocation { file: self.doc.file.to_owned(), line: Some(self.doc.line(&t.span)), item: Some(item) }
    }

    fn add_material(&mut self, desc: MaterialDesc) -> usize {
        self.by_name.insert(desc.name.clone(), self.materials.len());
        self.materials.push(desc);
        self.materials.len() - 1
    }

    fn materials(&mut self, m: &Tbl<'a>) -> Result<(), ImportError> {
        for (k, v) in m.entries() {
            let name: &str = k.get_ref();
            let t = Tbl::of(self.doc, v, format!("materials.{name}"))?;
            let material = material::material(&t)?;
            let source = self.source(&t, name.to_owned());
            let i = self.add_material(MaterialDesc {
                name: name.to_owned(),
                material,
                textures: Default::default(),
                source,
            });
            self.toml_materials.insert(name.to_owned(), i);
        }
        Ok(())
    }

    /// Resolves `material = "NAME"` against the `[materials]` table.
    fn material_ref(&self, t: &Tbl<'_>, key: &str) -> Result<Option<usize>, ImportError> {
        let Some(v) = t.get(key) else { return Ok(None) };
        let name = string(self.doc, v, &t.key_path(key))?;
        match self.toml_materials.get(name) {
            Some(&i) => Ok(Some(i)),
            None => {
                let mut known: Vec<&str> = self.toml_materials.keys().map(String::as_str).collect();
                known.sort_unstable();
                let list = if known.is_empty() {
                    "none are defined".to_owned()
                } else {
                    format!("defined: {}", known.join(", "))
                };
                Err(self.doc.error(
                    ImportErrorKind::UnresolvedReference,
                    &v.span(),
                    format!("unknown material `{name}` ({list}){}", did_you_mean(name, known.iter().copied())),
                ))
            }
        }
    }

    fn black(&mut self) -> usize {
        if let Some(i) = self.black {
            return i;
        }
        let name = unique_name("emitter-black", |n| self.by_name.contains_key(n));
        let material = Material::Diffuse { reflectance: Spectrum::Constant(0.0), two_sided: true };
        let source = SourceLocation { file: self.doc.file.to_owned(), line: None, item: None };
        let i = self.add_material(MaterialDesc { name, material, textures: Default::default(), source });
        self.black = Some(i);
        i
    }

    /// Counts `n` more triangles against [`MAX_SCENE_TRIANGLES`] (before they are generated).
    fn reserve_triangles(&mut self, t: &Tbl<'_>, n: u64) -> Result<(), ImportError> {
        self.triangles = self.triangles.saturating_add(n);
        if self.triangles > MAX_SCENE_TRIANGLES {
            return Err(self.doc.error(
                ImportErrorKind::TooLarge,
                &t.span,
                format!("`{}`: the scene would have more than {MAX_SCENE_TRIANGLES} triangles", t.path),
            ));
        }
        Ok(())
    }

    /// Adds a mesh after checking that its positions are finite.
    fn push_mesh(&mut self, t: &Tbl<'_>, mesh: MeshDesc, orig: String) -> Result<(), ImportError> {
        if mesh.positions.iter().any(|p| !p.is_finite()) {
            return Err(self.doc.invalid(
                &t.span,
                format!("`{}`: vertex positions overflow (not finite) after units and transform", t.path),
            ));
        }
        self.meshes.push(mesh);
        self.orig_material.push(orig);
        Ok(())
    }

    fn transform(&self, t: &Tbl<'_>) -> Result<Affine3A, ImportError> {
        t.opt_table("transform")?.map_or(Ok(Affine3A::IDENTITY), |x| shape::transform(&x, self.unit))
    }

    fn shape(&mut self, i: usize, t: &Tbl<'a>) -> Result<(), ImportError> {
        let doc = self.doc;
        let Some((ty, _)) = t.choice("type", &SHAPE_TYPES)? else {
            return Err(
                doc.invalid(&t.span, format!("`{}`: missing key `type` (one of: {})", t.path, SHAPE_TYPES.join(", ")))
            );
        };
        let own: &[&str] = match ty {
            "mesh" => &["file", "units"],
            "quad" => &["corner", "edge1", "edge2", "center", "size", "normal"],
            "sphere" => &["center", "radius", "subdivisions"],
            _ => &["center", "radius", "normal", "segments"],
        };
        let common = ["type", "name", "material", "transform", "emission", "flip_normals"];
        t.check_keys(&[&common[..], own].concat())?;
        let name = match t.opt_str("name")? {
            Some(n) => n.to_owned(),
            None => format!("shape[{i}]:{ty}"),
        };
        let emission = t.opt_table("emission")?.map(|e| shape::emission(&e)).transpose()?;
        let flip = t.opt_bool("flip_normals")?.unwrap_or(false);
        let xf = self.transform(t)?;
        let material = self.material_ref(t, "material")?;
        if ty == "mesh" {
            let (meshes, lights) = self.import_file(t, material, xf)?;
            self.reserve_triangles(t, meshes.iter().map(|(m, _)| m.indices.len() as u64).sum())?;
            for (mut m, orig) in meshes {
                if t.has("name") {
                    m.name = format!("{name}:{}", m.name);
                }
                if emission.is_some() {
                    m.emission = emission.clone();
                }
                if flip {
                    flip_mesh(&mut m);
                }
                self.push_mesh(t, m, orig)?;
            }
            self.lights.extend(lights);
            return Ok(());
        }
        let material = match material {
            Some(m) => m,
            None if emission.is_some() => self.black(),
            None => return Err(t.missing("material")),
        };
        let unit = self.unit;
        let tess = match ty {
            "quad" => {
                self.reserve_triangles(t, 2)?;
                self.quad(t)?
            }
            "sphere" => {
                let center = t.opt_point("center", unit)?.unwrap_or(Vec3::ZERO);
                let radius = shape::positive_length(t, "radius", unit)?;
                let sub = t.opt_int("subdivisions", 0, MAX_SPHERE_SUBDIVISIONS as i128)?;
                let sub = sub.unwrap_or(DEFAULT_SPHERE_SUBDIVISIONS);
                self.reserve_triangles(t, 20 << (2 * sub))?;
                shape::sphere(center, radius, sub)
            }
            _ => {
                let center = t.opt_point("center", unit)?.unwrap_or(Vec3::ZERO);
                let radius = shape::positive_length(t, "radius", unit)?;
                let normal = t.opt_dir("normal")?.unwrap_or(Vec3::Z);
                let seg = t.opt_int("segments", 3, MAX_DISK_SEGMENTS as i128)?.unwrap_or(DEFAULT_DISK_SEGMENTS);
                self.reserve_triangles(t, seg as u64)?;
                shape::disk(center, radius, normal, seg)
            }
        };
        let mut mesh = MeshDesc {
            name: name.clone(),
            positions: tess.positions,
            normals: tess.normals,
            uvs: None,
            indices: tess.indices,
            material,
            emission,
            source: self.source(t, name),
        };
        transform_mesh(&mut mesh, &xf);
        if flip {
            flip_mesh(&mut mesh);
        }
        let orig = self.materials[material].name.clone();
        self.push_mesh(t, mesh, orig)
    }

    /// A quad from `corner`/`edge1`/`edge2`, or from `center`/`size`/`normal`.
    fn quad(&self, t: &Tbl<'_>) -> Result<shape::Tessellation, ImportError> {
        let doc = self.doc;
        let unit = self.unit;
        let explicit = ["corner", "edge1", "edge2"];
        let centred = ["center", "size", "normal"];
        let uses_explicit = explicit.iter().any(|k| t.has(k));
        if uses_explicit {
            if let Some(k) = centred.iter().find(|k| t.has(k)) {
                return Err(doc.invalid(
                    &t.key_span(k),
                    format!("`{}`: use either corner/edge1/edge2 or center/size/normal, not both", t.path),
                ));
            }
            let corner = t.opt_point("corner", unit)?.ok_or_else(|| t.missing("corner"))?;
            let e1 = t.opt_point("edge1", unit)?.ok_or_else(|| t.missing("edge1"))?;
            let e2 = t.opt_point("edge2", unit)?.ok_or_else(|| t.missing("edge2"))?;
            let (d1, d2) = (e1.as_dvec3(), e2.as_dvec3());
            if d1.cross(d2).length() <= 1e-6 * d1.length() * d2.length() {
                return Err(doc.invalid(
                    &t.span,
                    format!("`{}`: edge1 and edge2 must be non-zero and not parallel (the quad has no area)", t.path),
                ));
            }
            return Ok(shape::quad(corner, e1, e2));
        }
        let center = t.opt_point("center", unit)?.unwrap_or(Vec3::ZERO);
        let size = t.opt_vec2("size")?.ok_or_else(|| {
            doc.invalid(
                &t.span,
                format!("`{}`: give `corner`, `edge1`, `edge2`, or `center` and `size = [w, h]`", t.path),
            )
        })?;
        let sv = t.get("size").map_or(t.span.clone(), |v| v.span());
        let size = size * unit;
        if size.x <= 0.0 || size.y <= 0.0 || !size.is_finite() {
            return Err(doc.invalid(&sv, format!("`{}.size` must be > 0 and finite, got {size}", t.path)));
        }
        let normal = t.opt_dir("normal")?.unwrap_or(Vec3::Z);
        let (u, v) = shape::plane_frame(normal);
        let (e1, e2) = (u * size.x, v * size.y);
        Ok(shape::quad(center - 0.5 * (e1 + e2), e1, e2))
    }

    /// Imports the file named by `t.file` (OBJ, TOML or any registered format) and places it:
    /// file units, then `xf`. Returns the meshes (with their source material names) and lights.
    #[allow(clippy::type_complexity)]
    fn import_file(
        &mut self,
        t: &Tbl<'_>,
        material: Option<usize>,
        xf: Affine3A,
    ) -> Result<(Vec<(MeshDesc, String)>, Vec<LightDesc>), ImportError> {
        let doc = self.doc;
        let fv: &Val<'_> = t.req("file")?;
        let name = string(doc, fv, &t.key_path("file"))?;
        let path = doc.resolve(name);
        let here = doc.place(&fv.span());
        if !path.is_file() {
            return Err(doc.error(
                ImportErrorKind::MissingFile,
                &fv.span(),
                format!("`{}`: cannot find `{name}` (looked for {})", t.key_path("file"), path.display()),
            ));
        }
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let plain = ImportOptions::default();
        let sub = if ext == "toml" {
            if t.has("units") {
                return Err(doc.invalid(
                    &t.key_span("units"),
                    format!("`{}`: an included TOML scene declares its own `units`", t.path),
                ));
            }
            if self.depth >= MAX_INCLUDE_DEPTH {
                return Err(doc.error(
                    ImportErrorKind::TooLarge,
                    &fv.span(),
                    format!("TOML scenes nested more than {MAX_INCLUDE_DEPTH} deep (an include cycle?)"),
                ));
            }
            import_at_depth(&path, &plain, self.depth + 1)
        } else if ext == "obj" {
            let mode = if material.is_some() { ObjMaterials::NamesOnly } else { ObjMaterials::FromMtl };
            import_obj(&path, &plain, mode)
        } else if let Some(imp) = importer_for(&path) {
            imp.import(&path, &plain)
        } else {
            let exts: Vec<String> = supported_extensions().iter().map(|e| format!(".{e}")).collect();
            return Err(doc.error(
                ImportErrorKind::Unsupported,
                &fv.span(),
                format!("`{name}`: unsupported file type; supported: {}", exts.join(", ")),
            ));
        }
        .map_err(|e| e.included_from(here))?;
        // OBJ has no units: it uses the scene's unless `units` says otherwise.
        // Other formats (TOML, later glTF) are already in metres.
        let file_unit = match units(t, "units")? {
            Some(u) => u,
            None if ext == "obj" => self.scene_unit,
            None => 1.0,
        };
        let m = xf * Affine3A::from_scale(Vec3::splat(file_unit * self.extra));
        let file_name = path.file_name().map_or_else(|| name.to_owned(), |n| n.to_string_lossy().into_owned());
        let orig_names: Vec<String> = sub.materials.iter().map(|m| m.name.clone()).collect();
        let mut remap = Vec::with_capacity(sub.materials.len());
        let tex_base = self.textures.len();
        if material.is_none() {
            self.textures.extend(sub.textures);
        }
        for mut md in sub.materials {
            if material.is_some() {
                remap.push(usize::MAX);
                continue;
            }
            for r in [&mut md.textures.base_color, &mut md.textures.metallic_roughness].into_iter().flatten() {
                r.texture += tex_base;
            }
            let nm = unique_name(&format!("{file_name}:{}", md.name), |n| self.by_name.contains_key(n));
            remap.push(self.add_material(MaterialDesc { name: nm, ..md }));
        }
        for mut c in sub.cameras {
            transform_camera(&mut c.camera, &m);
            self.cameras.push(c);
        }
        self.warnings.extend(sub.warnings);
        let mut meshes = Vec::with_capacity(sub.meshes.len());
        for mut mesh in sub.meshes {
            let Some(orig) = orig_names.get(mesh.material).cloned() else {
                return Err(
                    doc.invalid(&fv.span(), format!("`{name}`: mesh `{}` refers to a missing material", mesh.name))
                );
            };
            mesh.material = material.unwrap_or(remap[mesh.material]);
            transform_mesh(&mut mesh, &m);
            meshes.push((mesh, orig));
        }
        let mut lights = sub.lights;
        for l in &mut lights {
            transform_light(l, &m);
        }
        Ok((meshes, lights))
    }

    fn include(&mut self, t: &Tbl<'a>) -> Result<(), ImportError> {
        t.check_keys(&["file", "transform", "units", "material"])?;
        let xf = self.transform(t)?;
        let material = self.material_ref(t, "material")?;
        let (meshes, lights) = self.import_file(t, material, xf)?;
        self.reserve_triangles(t, meshes.iter().map(|(m, _)| m.indices.len() as u64).sum())?;
        for (m, orig) in meshes {
            self.push_mesh(t, m, orig)?;
        }
        self.lights.extend(lights);
        Ok(())
    }

    /// The scene camera: `[camera]` with `name` or `index` picks a camera of an included file
    /// (glTF); other keys describe one; without `[camera]`, the first included camera if any.
    fn camera(&self, t: Option<Tbl<'_>>) -> Result<CameraDesc, ImportError> {
        let t = match t {
            Some(t) if t.has("name") || t.has("index") => t,
            None if !self.cameras.is_empty() => return Ok(self.cameras[0].camera.clone()),
            t => return settings::camera(t, self.unit),
        };
        t.check_keys(&["name", "index"])?;
        let names: Vec<&str> = self.cameras.iter().map(|c| c.name.as_str()).collect();
        let list = if names.is_empty() { "the included files define none".to_owned() } else { names.join(", ") };
        if t.has("name") && t.has("index") {
            return Err(self.doc.invalid(&t.key_span("index"), "`camera`: give `name` or `index`, not both"));
        }
        if let Some(name) = t.opt_str("name")? {
            return match self.cameras.iter().find(|c| c.name == name) {
                Some(c) => Ok(c.camera.clone()),
                None => Err(self.doc.error(
                    ImportErrorKind::UnresolvedReference,
                    &t.key_span("name"),
                    format!(
                        "no included camera is named `{name}` (cameras: {list}){}",
                        did_you_mean(name, names.iter().copied())
                    ),
                )),
            };
        }
        let max = self.cameras.len().saturating_sub(1) as i128;
        if self.cameras.is_empty() {
            return Err(self.doc.error(
                ImportErrorKind::UnresolvedReference,
                &t.key_span("index"),
                "`camera.index`: the included files define no cameras",
            ));
        }
        let i: usize = t.opt_int("index", 0, max)?.unwrap_or(0);
        Ok(self.cameras[i].camera.clone())
    }

    fn override_(&mut self, t: &Tbl<'_>) -> Result<(), ImportError> {
        t.check_keys(&["match", "material"])?;
        let pattern = t.opt_str("match")?.ok_or_else(|| t.missing("match"))?;
        let material = self.material_ref(t, "material")?.ok_or_else(|| t.missing("material"))?;
        let mut hits = 0usize;
        for (m, orig) in self.meshes.iter_mut().zip(&self.orig_material) {
            let current = &self.materials[m.material].name;
            if glob_match(pattern, &m.name) || glob_match(pattern, orig) || glob_match(pattern, current) {
                m.material = material;
                hits += 1;
            }
        }
        if hits == 0 {
            let mut names: Vec<&str> = self.meshes.iter().map(|m| m.name.as_str()).take(8).collect();
            if self.meshes.len() > 8 {
                names.push("...");
            }
            return Err(self.doc.error(
                ImportErrorKind::UnresolvedReference,
                &t.key_span("match"),
                format!("override `{pattern}` matches no mesh or material name (meshes: {})", names.join(", ")),
            ));
        }
        Ok(())
    }
}
