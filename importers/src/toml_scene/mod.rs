//! The native TOML scene format (reference: `docs/scene-format.md`).
//!
//! The document is parsed into a span-preserving tree (`toml::de::DeTable`) and read with typed,
//! span-aware accessors, so every error — syntax, unknown key, wrong type, out-of-range value,
//! unknown material, invalid material parameters, missing referenced file — names the scene
//! file, line and column of the offending key, value or table.

mod include;
mod luminaire;
mod material;
mod sensor;
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
pub use settings::{RENDER_KEYS, RenderKey};
pub use shape::{DEFAULT_DISK_SEGMENTS, DEFAULT_SPHERE_SUBDIVISIONS, MAX_DISK_SEGMENTS, MAX_SPHERE_SUBDIVISIONS};
pub use spectrum::{MAX_SPECTRUM_ENTRIES, csv_spectrum};

use crate::error::{ErrorPlace, ImportError, ImportErrorKind, did_you_mean};
use crate::importer::{Formats, ImportOptions, Importer};
use crate::names::unique_name;
use crate::scene_desc::{
    CameraDesc, LightDesc, MAX_SCENE_TRIANGLES, MaterialDesc, MeshDesc, NamedCamera, SceneDesc, SourceLocation,
    TextureDesc,
};
use crate::small_text::read_small_text;
use crate::toml_reader::{Doc, Tbl, parse_document, string};
use crate::transform::{flip_mesh, transform_mesh};

/// Length units accepted by `units`, with their size in metres.
pub const UNITS: [(&str, f32); 5] = [("m", 1.0), ("cm", 0.01), ("mm", 0.001), ("in", 0.0254), ("ft", 0.3048)];
/// How deep TOML scenes may include TOML scenes (guards against include cycles).
pub const MAX_INCLUDE_DEPTH: u32 = 8;
/// Shape types of `[[shape]]`.
pub const SHAPE_TYPES: [&str; 4] = ["mesh", "quad", "sphere", "disk"];
/// Light types of `[[light]]`.
pub const LIGHT_TYPES: [&str; 5] = ["point", "spot", "directional", "luminaire", "environment"];

const TOP_KEYS: [&str; 9] =
    ["units", "render", "camera", "materials", "shape", "light", "sensor", "include", "override"];

/// The TOML scene importer of the registry (`.toml`).
#[derive(Clone, Copy, Debug, Default)]
pub struct TomlSceneImporter;

impl Importer for TomlSceneImporter {
    fn extensions(&self) -> &[&str] {
        &["toml"]
    }

    fn import(&self, path: &Path, opts: &ImportOptions, formats: Formats<'_>) -> Result<SceneDesc, ImportError> {
        import_at_depth(path, opts, formats, 0)
    }
}

/// Imports TOML scene text as if it were the file `path` (used for messages and to resolve
/// relative file names against `path`'s directory); included files are imported with `formats`.
pub fn parse_toml_scene(
    text: &str,
    path: &Path,
    opts: &ImportOptions,
    formats: Formats<'_>,
) -> Result<SceneDesc, ImportError> {
    parse_at_depth(text, path, opts, formats, 0)
}

fn import_at_depth(
    path: &Path,
    opts: &ImportOptions,
    formats: Formats<'_>,
    depth: u32,
) -> Result<SceneDesc, ImportError> {
    let text = read_small_text(path, "scene file")?;
    parse_at_depth(&text, path, opts, formats, depth)
}

fn parse_at_depth(
    text: &str,
    path: &Path,
    opts: &ImportOptions,
    formats: Formats<'_>,
    depth: u32,
) -> Result<SceneDesc, ImportError> {
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
        formats,
        time_code: opts.time_code,
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
    let sensors = tables(&top, "sensor")?.iter().map(|t| sensor::sensor(t, b.unit)).collect::<Result<Vec<_>, _>>()?;
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
        sensors,
        import_summary: Vec::new(),
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
            format!("`{key}` must be an array of tables ([[{key}]]), got {}", crate::toml_reader::type_name(other)),
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
    /// How deep this file is included (0: the scene file itself).
    depth: u32,
    /// The formats an include may have.
    formats: Formats<'a>,
    /// The USD time code included stages are read at (the command line's).
    time_code: Option<f64>,
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
            let (material, interior) = material::material(&t, self.unit)?;
            let source = self.source(&t, name.to_owned());
            let i = self.add_material(MaterialDesc {
                name: name.to_owned(),
                material,
                absorption: interior.absorption,
                scattering: interior.scattering,
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
        let i = self.add_material(MaterialDesc {
            name,
            material,
            absorption: None,
            scattering: None,
            textures: Default::default(),
            source,
        });
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
                crate::tessellation::sphere(center, radius, sub)
            }
            _ => {
                let center = t.opt_point("center", unit)?.unwrap_or(Vec3::ZERO);
                let radius = shape::positive_length(t, "radius", unit)?;
                let normal = t.opt_dir("normal")?.unwrap_or(Vec3::Z);
                let seg = t.opt_int("segments", 3, MAX_DISK_SEGMENTS as i128)?.unwrap_or(DEFAULT_DISK_SEGMENTS);
                self.reserve_triangles(t, seg as u64)?;
                crate::tessellation::disk(center, radius, normal, seg)
            }
        };
        let mut mesh = MeshDesc {
            name: name.clone(),
            positions: tess.positions,
            normals: tess.normals,
            uvs: None,
            colors: None,
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
    fn quad(&self, t: &Tbl<'_>) -> Result<crate::tessellation::Tessellation, ImportError> {
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
            return Ok(crate::tessellation::quad(corner, e1, e2));
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
        let (u, v) = crate::tessellation::plane_frame(normal);
        let (e1, e2) = (u * size.x, v * size.y);
        Ok(crate::tessellation::quad(center - 0.5 * (e1 + e2), e1, e2))
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
}
