//! USD importer (`.usd`, `.usda`, `.usdc`, `.usdz`) on the pure-Rust `openusd` crate, which
//! reads the three file formats and composes the stage (sublayers, references, payloads,
//! variants, inherits, specializes, instancing). Full mapping: `docs/usd.md`. In short:
//!
//! - **Stage**: `metersPerUnit` (0.01 when unauthored, the USD default) times
//!   [`ImportOptions::units_scale`]; `upAxis = "Z"` is rotated to quasar's +Y up
//!   ((x, y, z) -> (x, z, -y)).
//! - **Traversal**: active, defined prims; `visibility = "invisible"` and `purpose` `proxy` /
//!   `guide` prune a subtree; `Material` / `Shader` subtrees are not geometry. Instanceable prims
//!   are expanded through their prototype and copied per instance (world-space meshes).
//! - **Transforms**: `xformOpOrder` stacks (with `!invert!` and `!resetXformStack!`) composed by
//!   the crate; animated ops and attributes at [`ImportOptions::time_code`] (default: the
//!   earliest time sample).
//! - **Meshes** ([`mesh`], split by `materialBind` GeomSubsets), implicit **shapes**
//!   ([`shapes`]), **PointInstancer** instances ([`instancer`], copied), **materials**
//!   ([`material`]), **lights** ([`light`]) and **cameras** ([`camera`]).
//! - **Errors** name the file and the prim path (and attribute); limits on the file size, the
//!   prim count and the triangle count.

mod camera;
mod ies_light;
mod instancer;
mod light;
mod material;
mod materials;
mod mesh;
pub mod reader_guard;
mod shapes;
mod texture;
mod value;
pub mod writer;

use std::path::Path;

use glam::{Affine3A, DMat4, Mat3, Vec3};
use openusd::schemas::geom::{Imageable, Xformable};
use openusd::sdf;
use openusd::usd::{Prim, SchemaBase, SchemaKind, Stage};

use self::light::{LIGHT_TYPES, UsdLight};
use self::materials::Materials;
use self::shapes::SHAPE_TYPES;
use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::importer::{Formats, ImportOptions, Importer};
use crate::scene_desc::{MAX_SCENE_TRIANGLES, MeshDesc, NamedCamera, SceneDesc, SourceLocation};
use crate::transform::transform_mesh;

/// Largest USD file accepted (bytes).
pub const MAX_USD_BYTES: u64 = 1 << 30;
/// Most prims visited in one stage (instances counted).
pub const MAX_USD_PRIMS: usize = 1 << 22;
/// Deepest namespace accepted.
pub const MAX_USD_DEPTH: usize = 512;

/// The USD importer of the registry.
#[derive(Clone, Copy, Debug, Default)]
pub struct UsdImporter;

impl Importer for UsdImporter {
    fn extensions(&self) -> &[&str] {
        &["usd", "usda", "usdc", "usdz"]
    }

    fn import(&self, path: &Path, opts: &ImportOptions, _: Formats<'_>) -> Result<SceneDesc, ImportError> {
        import_usd(path, opts)
    }
}

/// A view of any prim as `Xformable`, so the crate composes its `xformOpOrder` (every prim
/// type quasar reads is Xformable).
struct AnyXformable(Prim);

impl SchemaBase for AnyXformable {
    const KIND: SchemaKind = SchemaKind::ConcreteTyped;
    fn prim(&self) -> &Prim {
        &self.0
    }
}
impl Imageable for AnyXformable {}
impl Xformable for AnyXformable {}

fn err(kind: ImportErrorKind, file: &Path, at: &str, msg: impl std::fmt::Display) -> ImportError {
    ImportError::new(kind, ErrorPlace::file(file), format!("prim <{at}>: {msg}"))
}

/// Counts `n` more triangles of the prim `at`, refusing a scene over [`MAX_SCENE_TRIANGLES`].
fn add_triangles(total: &mut u64, n: usize, file: &Path, at: &str) -> Result<(), ImportError> {
    *total += n as u64;
    if *total > MAX_SCENE_TRIANGLES {
        return Err(err(
            ImportErrorKind::TooLarge,
            file,
            at,
            format!("the scene would have more than {MAX_SCENE_TRIANGLES} triangles"),
        ));
    }
    Ok(())
}

fn attr_err(file: &Path, at: &str, (attr, msg): (String, String)) -> ImportError {
    err(ImportErrorKind::InvalidValue, file, at, format!("attribute `{attr}`: {msg}"))
}

/// A stage-level metadata value of the root layer.
fn layer_metadata(stage: &Stage, key: &str) -> Option<sdf::Value> {
    stage.root_layer().pseudo_root().and_then(|r| r.get::<sdf::Value>(key))
}

/// Prims drawn and skipped during an import, for `quasar info` ([`SceneDesc::import_summary`]).
#[derive(Default)]
struct PrimTally {
    /// Prims traversed past the skip rules (Xforms, Scopes and everything drawn).
    visited: usize,
    /// Meshes and implicit shapes drawn (each instance counted).
    drawn: usize,
    /// Lights read.
    lights: usize,
    /// Skipped prims (and their subtrees' roots) by reason.
    skipped: std::collections::BTreeMap<String, usize>,
}

impl PrimTally {
    fn skip(&mut self, reason: &str) {
        *self.skipped.entry(reason.to_string()).or_default() += 1;
    }

    /// The summary lines: prims drawn, skipped by reason, and the time code read.
    fn lines(&self, cameras: usize, time_code: Option<f64>) -> Vec<String> {
        let mut v = vec![format!(
            "USD prims: {} traversed, {} meshes or shapes drawn (instances counted), {} lights, {cameras} cameras",
            self.visited, self.drawn, self.lights
        )];
        if self.skipped.is_empty() {
            v.push("USD prims skipped: none".into());
        } else {
            let s: Vec<String> = self.skipped.iter().map(|(why, n)| format!("{n} {why}")).collect();
            v.push(format!("USD prims skipped (with their subtrees): {}", s.join(", ")));
        }
        v.push(match time_code {
            Some(t) => format!("USD time code: {t} (--time-code)"),
            None => "USD time code: the earliest time sample of each attribute (--time-code T for another)".into(),
        });
        v
    }
}

/// The message of an import that a panic in the USD reader ended (see [`import_usd`]).
pub const USD_READER_PANIC: &str = "the USD reader (openusd 0.6.0) failed on malformed data";

/// Imports the USD file `path` (see the module documentation), after the process's reader guard
/// ([`reader_guard`]; the `quasar` binary reads the stage in a child process first). openusd 0.6.0 panics on some
/// malformed crate files (unchecked table indices, found by `fuzz/fuzz_targets/usd.rs`); such a
/// panic ends the import with an error naming the file ([`USD_READER_PANIC`]) instead of the
/// process.
pub fn import_usd(path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    reader_guard::check(path, opts)
        .map_err(|msg| ImportError::new(ImportErrorKind::Unsupported, ErrorPlace::file(path), msg))?;
    // (a TimeScope set inside is restored by its Drop while unwinding)
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| import_stage(path, opts))).unwrap_or_else(|payload| {
        let msg = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("a panic");
        Err(ImportError::new(ImportErrorKind::Syntax, ErrorPlace::file(path), format!("{USD_READER_PANIC}: {msg}")))
    })
}

/// [`import_usd`] without the panic guard.
fn import_stage(path: &Path, opts: &ImportOptions) -> Result<SceneDesc, ImportError> {
    let len = std::fs::metadata(path).map_err(|e| ImportError::io(path, "cannot read USD file", e))?.len();
    if len > MAX_USD_BYTES {
        return Err(ImportError::new(
            ImportErrorKind::TooLarge,
            ErrorPlace::file(path),
            format!("USD file is {len} bytes, more than the limit of {MAX_USD_BYTES}"),
        ));
    }
    let text = path.to_str().ok_or_else(|| {
        ImportError::new(ImportErrorKind::Unsupported, ErrorPlace::file(path), "the path is not valid UTF-8")
    })?;
    if let Some(t) = opts.time_code
        && !t.is_finite()
    {
        return Err(ImportError::new(
            ImportErrorKind::InvalidValue,
            ErrorPlace::file(path),
            format!("time code {t} is not finite"),
        ));
    }
    let _time = value::TimeScope::new(opts.time_code);
    let stage = Stage::open(text).map_err(|e| {
        ImportError::new(ImportErrorKind::Syntax, ErrorPlace::file(path), format!("cannot open the stage: {e:#}"))
    })?;
    let meters_per_unit = match layer_metadata(&stage, "metersPerUnit") {
        Some(sdf::Value::Double(m)) => m,
        Some(sdf::Value::Float(m)) => f64::from(m),
        _ => 0.01,
    };
    if !(meters_per_unit.is_finite() && meters_per_unit > 0.0) {
        return Err(ImportError::new(
            ImportErrorKind::InvalidValue,
            ErrorPlace::file(path),
            format!("metersPerUnit = {meters_per_unit} is not a positive length"),
        ));
    }
    let z_up = matches!(layer_metadata(&stage, "upAxis"), Some(sdf::Value::Token(t)) if t.as_str() == "Z");
    let scale = meters_per_unit as f32 * opts.scale(path)?;
    let axes = if z_up { Mat3::from_cols(Vec3::X, Vec3::NEG_Z, Vec3::Y) } else { Mat3::IDENTITY };
    let root = Affine3A::from_mat3(axes * Mat3::from_diagonal(Vec3::splat(scale)));

    let mut warnings: Vec<String> = Vec::new();
    let mut warned: Vec<String> = Vec::new();
    let mut warn_once = |key: &str, msg: String, warnings: &mut Vec<String>| {
        if !warned.iter().any(|w| w == key) {
            warned.push(key.to_string());
            warnings.push(format!("{}: {msg}", path.display()));
        }
    };
    let mut mats = Materials::default();
    let mut light_material = None;
    let mut meshes: Vec<MeshDesc> = Vec::new();
    let mut lights = Vec::new();
    let mut cameras: Vec<NamedCamera> = Vec::new();
    let mut triangles = 0u64;
    let mut visits = 0usize;
    let mut tally = PrimTally::default();
    let pseudo_root = stage.prim(sdf::Path::abs_root());
    let children =
        |p: &Prim| p.children().map_err(|e| err(ImportErrorKind::Syntax, path, p.path().as_str(), format!("{e:#}")));
    // (prim, parent's local-to-world in stage units, depth, a PointInstancer's prototype root)
    let mut stack: Vec<(Prim, DMat4, usize, bool)> =
        children(&pseudo_root)?.into_iter().rev().map(|p| (p, DMat4::IDENTITY, 0, false)).collect();
    while let Some((prim, parent, depth, prototype)) = stack.pop() {
        let at = prim.path().as_str().to_string();
        visits += 1;
        if visits > MAX_USD_PRIMS || depth > MAX_USD_DEPTH {
            return Err(err(
                ImportErrorKind::TooLarge,
                path,
                &at,
                format!(
                    "more than {MAX_USD_PRIMS} prims (instances counted) or a namespace deeper than {MAX_USD_DEPTH}"
                ),
            ));
        }
        let ty = prim.type_name().ok().flatten().map(|t| t.as_str().to_string()).unwrap_or_default();
        // Pixar's default traversal: defined prims only (an `over` without a `def` and `class`
        // prims are not drawn), except the prototypes an instancer draws (often under an `over`).
        // An unauthored specifier is Sdf's fallback, `over`: a binary layer leaves it out for
        // the root `over` prims that UsdStage.Flatten() writes for instancing prototypes
        let defining = prim.specifier().ok().flatten() == Some(sdf::Specifier::Def);
        if matches!(ty.as_str(), "Material" | "Shader" | "NodeGraph" | "GeomSubset") {
            continue;
        }
        if !(defining || prototype) {
            tally.skip("not defined (an `over` or `class`)");
            continue;
        }
        if !prim.is_active().unwrap_or(true) {
            tally.skip("inactive");
            continue;
        }
        let view = AnyXformable(prim.clone());
        let visibility = value::token(&prim, "visibility").map_err(|e| attr_err(path, &at, e))?;
        let purpose = value::token(&prim, "purpose").map_err(|e| attr_err(path, &at, e))?;
        // rendered purposes: default and render (proxy, guide and unknown tokens are not drawn)
        if visibility.as_deref() == Some("invisible") {
            tally.skip("invisible");
            continue;
        }
        if !matches!(purpose.as_deref(), None | Some("default" | "render")) {
            tally.skip("purpose proxy or guide");
            continue;
        }
        tally.visited += 1;
        value::check_op_order(&prim).map_err(|e| attr_err(path, &at, e))?;
        let local = view
            .local_to_parent_transform(value::time())
            .map_err(|e| err(ImportErrorKind::InvalidValue, path, &at, format!("{e:#}")))?;
        let local = DMat4::from_cols_array(&local.0);
        let resets = view.resets_xform_stack().unwrap_or(false);
        let world = if resets { local } else { parent * local };
        if !world.is_finite() {
            return Err(err(ImportErrorKind::InvalidValue, path, &at, "the transform is not finite"));
        }
        let world_q = root * Affine3A::from_mat4(world.as_mat4());
        // (local-space mesh, its materialBind subsets) of a geometric prim
        let geometry = match ty.as_str() {
            "Mesh" => {
                let local_mesh = mesh::read_mesh(&prim, at.clone()).map_err(|e| attr_err(path, &at, e))?;
                if local_mesh.subdivision != "none" {
                    warn_once(
                        "subdivision",
                        format!(
                            "{at}: subdivisionScheme `{}`: the control cage is rendered (no subdivision)",
                            local_mesh.subdivision
                        ),
                        &mut warnings,
                    );
                }
                let subsets = mesh::material_subsets(&prim).map_err(|e| attr_err(path, &at, e))?;
                tally.drawn += 1;
                Some((local_mesh, subsets))
            }
            t if SHAPE_TYPES.contains(&t) => {
                let mesh = shapes::read_shape(&prim, t, at.clone()).map_err(|e| attr_err(path, &at, e))?;
                tally.drawn += 1;
                Some((mesh::LocalMesh { mesh, subdivision: "none".into(), faces: Vec::new() }, Vec::new()))
            }
            "Camera" => {
                let (camera, note) = camera::read_camera(&prim, &at, &world_q).map_err(|e| attr_err(path, &at, e))?;
                if let Some(note) = note {
                    warn_once("ortho", note, &mut warnings);
                }
                cameras.push(camera);
                None
            }
            "PointInstancer" => {
                // the prototypes are drawn through the instances only
                for (proto, m) in instancer::instances(&prim).map_err(|e| attr_err(path, &at, e))?.into_iter().rev() {
                    stack.push((stage.prim(proto), world * m, depth + 1, true));
                }
                continue;
            }
            t if LIGHT_TYPES.contains(&t) => {
                let (l, mut notes) =
                    light::read_light(&prim, t, &world_q, path, z_up).map_err(|e| attr_err(path, &at, e))?;
                let l = ies_light::with_ies_profile(&prim, t, l, &world_q, path, &mut notes)
                    .map_err(|e| attr_err(path, &at, e))?;
                for n in notes {
                    warnings.push(format!("{}: {at}: {n}", path.display()));
                }
                if !matches!(l, UsdLight::Skipped(_)) {
                    tally.lights += 1;
                }
                match l {
                    UsdLight::Light(l) => lights.push(l),
                    UsdLight::Mesh(mut m) => {
                        let mi = *light_material.get_or_insert_with(|| mats.light_material(path));
                        m.material = mi;
                        m.source = SourceLocation { file: path.to_owned(), line: None, item: Some(at.clone()) };
                        add_triangles(&mut triangles, m.indices.len(), path, &at)?;
                        meshes.push(*m);
                    }
                    UsdLight::Skipped(why) => {
                        tally.skip("a light quasar cannot draw");
                        warnings.push(format!("{}: {at}: {why}; skipped", path.display()))
                    }
                }
                None
            }
            "Points" | "BasisCurves" | "NurbsCurves" | "NurbsPatch" | "HermiteCurves" | "TetMesh" => {
                warn_once(&ty, format!("{at}: {ty} prims are not rendered (surfaces only)"), &mut warnings);
                tally.skip(&format!("{ty} (not a surface)"));
                None
            }
            _ => None,
        };
        if let Some((local_mesh, subsets)) = geometry {
            add_triangles(&mut triangles, local_mesh.mesh.indices.len(), path, &at)?;
            let bound = material::bound_material(&stage, &prim);
            if value::raw(&prim, "primvars:displayColor").ok().flatten().is_some() && bound.is_none() {
                warn_once(
                    "displayColor",
                    format!("{at}: primvars:displayColor is not used; the default grey is"),
                    &mut warnings,
                );
            }
            let face_sets: Vec<Vec<i32>> = subsets.iter().map(|(_, f)| f.clone()).collect();
            for (part, mut m) in mesh::split_by_subsets(&local_mesh, &face_sets) {
                let (material_path, name) = match part {
                    // a subset without its own binding keeps the mesh's material
                    Some(k) => (
                        material::bound_material(&stage, &subsets[k].0).or(bound.clone()),
                        subsets[k].0.path().as_str().to_string(),
                    ),
                    None => (bound.clone(), at.clone()),
                };
                let mi = mats.index(&stage, path, material_path, &mut warnings)?;
                m.material = mi;
                m.emission = mats.emission[mi].clone();
                m.source = SourceLocation { file: path.to_owned(), line: None, item: Some(name.clone()) };
                m.name = name;
                transform_mesh(&mut m, &world_q);
                m.emission = light::mesh_light(&prim, &m).map_err(|e| attr_err(path, &at, e))?.or(m.emission);
                if m.positions.iter().any(|p| !p.is_finite()) {
                    return Err(err(
                        ImportErrorKind::InvalidValue,
                        path,
                        &at,
                        "points overflow (not finite) after the transforms",
                    ));
                }
                meshes.push(m);
            }
        }
        // an instance's children live in its prototype
        let kids = match prim.prototype().ok().flatten() {
            Some(proto) if prim.is_instance().unwrap_or(false) => children(&stage.prim(proto))?,
            _ => children(&prim)?,
        };
        for c in kids.into_iter().rev() {
            stack.push((c, world, depth + 1, false));
        }
    }
    if meshes.is_empty() && lights.is_empty() {
        return Err(ImportError::new(
            ImportErrorKind::InvalidValue,
            ErrorPlace::file(path),
            "the USD stage has no Mesh and no light prims",
        ));
    }
    if mats.descs.is_empty() {
        mats.index(&stage, path, None, &mut warnings)?;
    }
    let mut render = crate::scene_desc::RenderSettings::default();
    let camera = crate::framing::scene_camera(&cameras, &meshes, &mut render);
    let cameras_len = cameras.len();
    Ok(SceneDesc {
        materials: mats.descs,
        meshes,
        lights,
        camera,
        cameras,
        textures: mats.textures.descs,
        warnings,
        render,
        source: path.to_owned(),
        sensors: Vec::new(),
        import_summary: tally.lines(cameras_len, opts.time_code),
    })
}
