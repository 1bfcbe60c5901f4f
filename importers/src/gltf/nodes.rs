//! The glTF node hierarchy -> world-space meshes, cameras and punctual lights.
//!
//! Every node's world transform is the product of its ancestors' local transforms (TRS or
//! matrix); the importer's units scale is applied at the root. A mesh used by several nodes
//! (instancing) is read once and copied, transformed, for each node: `SceneDesc` holds world-space
//! meshes, so instances cost memory like separate meshes.

use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

use glam::{Affine3A, Mat4, Vec2, Vec3};
use gltf::mesh::Mode;

use super::accessor::Buffers;
use super::err;
use crate::error::{ImportError, ImportErrorKind};
use crate::photometric::photometric_scale;
use crate::scene_desc::MAX_SCENE_TRIANGLES;
use crate::scene_desc::{CameraDesc, FovAxis, LightDesc, MeshDesc, SourceLocation};
use crate::transform::transform_mesh;
use quasar_materials::spectrum::Spectrum;

/// Deepest node hierarchy accepted (deeper ones are almost certainly cycles).
pub const MAX_NODE_DEPTH: usize = 256;
/// Most node visits (instances counted) in one scene.
pub const MAX_NODE_VISITS: usize = 1 << 20;

/// A primitive read in its mesh's local space.
pub(super) struct LocalPrim {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    colors: Option<Vec<[f32; 3]>>,
    indices: Vec<[u32; 3]>,
}

/// A camera found on a node, before the scene bounds are known.
pub(super) struct PendingCamera {
    /// glTF camera index.
    pub index: usize,
    /// Name (glTF name or `camera<index>`).
    pub name: String,
    /// Eye position (world).
    pub position: Vec3,
    /// Unit view direction (world).
    pub forward: Vec3,
    /// Unit up direction (world).
    pub up: Vec3,
    /// Vertical field of view (degrees), or `None` for an orthographic camera.
    pub yfov_deg: Option<f32>,
    /// Orthographic half height (world units), for the perspective fallback.
    pub ymag: f32,
    /// glTF `aspectRatio`.
    pub aspect: Option<f32>,
}

/// What the traversal produces.
#[derive(Default)]
pub(super) struct Collected {
    /// Meshes with their glTF material index (`None` = default material).
    pub meshes: Vec<(MeshDesc, Option<usize>)>,
    /// Cameras in traversal order.
    pub cameras: Vec<PendingCamera>,
    /// Punctual lights.
    pub lights: Vec<LightDesc>,
    /// Warnings.
    pub warnings: Vec<String>,
}

/// Walks the scene graph from `roots`.
pub(super) struct Walker<'a> {
    /// Buffers for accessor reads.
    pub buffers: Buffers<'a>,
    /// Primitives already read, by (mesh, primitive, morph weights' bits).
    pub cache: HashMap<(usize, usize, Vec<u32>), Rc<LocalPrim>>,
    /// Triangles so far (instances counted).
    pub triangles: u64,
    /// Output.
    pub out: Collected,
    /// Primitive modes already warned about.
    pub warned_modes: Vec<Mode>,
    /// Features already warned about (`skin`, `COLOR_0`): one warning per file each.
    pub warned_features: Vec<&'static str>,
}

fn file_err(file: &Path, pointer: &str, msg: String) -> ImportError {
    err(ImportErrorKind::InvalidValue, file, pointer, msg)
}

impl<'a> Walker<'a> {
    /// Traverses the scene rooted at `roots` with the root transform `root`.
    pub fn walk(&mut self, roots: Vec<gltf::Node<'a>>, root: Affine3A) -> Result<(), ImportError> {
        let file = self.buffers.file;
        let mut stack: Vec<(gltf::Node<'a>, Affine3A, usize)> = roots.into_iter().rev().map(|n| (n, root, 0)).collect();
        let mut visits = 0usize;
        while let Some((node, parent, depth)) = stack.pop() {
            let ptr = format!("/nodes/{}", node.index());
            visits += 1;
            if depth > MAX_NODE_DEPTH || visits > MAX_NODE_VISITS {
                return Err(err(
                    ImportErrorKind::TooLarge,
                    file,
                    &ptr,
                    format!(
                        "node hierarchy deeper than {MAX_NODE_DEPTH} or more than {MAX_NODE_VISITS} node instances (a cycle?)"
                    ),
                ));
            }
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            if !local.is_finite() {
                return Err(file_err(file, &ptr, "transform is not finite".into()));
            }
            let world = parent * Affine3A::from_mat4(local);
            if !world.is_finite() {
                return Err(file_err(file, &ptr, "world transform overflows (not finite)".into()));
            }
            let node_name = node.name().map_or_else(|| format!("node{}", node.index()), str::to_owned);
            if let Some(mesh) = node.mesh() {
                if node.skin().is_some() {
                    self.warn_once(
                        "skin",
                        format!("{ptr}: the skin is ignored; the mesh is rendered as stored (its bind pose) with the node's transform"),
                    );
                }
                // a node's weights override its mesh's (glTF 2.0 §3.7.2.2)
                let weights = node.weights().or(mesh.weights()).unwrap_or(&[]).to_vec();
                self.mesh(&mesh, &world, &node_name, &weights)?;
            }
            if let Some(cam) = node.camera() {
                self.camera(&cam, &world, &ptr);
            }
            if let Some(light) = node.light() {
                self.light(&light, &world, &ptr);
            }
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child, world, depth + 1));
            }
        }
        Ok(())
    }

    /// Adds `msg` (prefixed by the file) to the warnings unless `feature` was warned about.
    fn warn_once(&mut self, feature: &'static str, msg: String) {
        if !self.warned_features.contains(&feature) {
            self.warned_features.push(feature);
            self.out.warnings.push(format!("{}: {msg}", self.buffers.file.display()));
        }
    }

    fn triangle_count(&self, prim: &gltf::Primitive<'_>) -> u64 {
        let n = match prim.indices() {
            Some(a) => a.count(),
            None => prim.get(&gltf::Semantic::Positions).map_or(0, |a| a.count()),
        } as u64;
        match prim.mode() {
            Mode::Triangles => n / 3,
            _ => n.saturating_sub(2),
        }
    }

    /// Reads a primitive with its morph targets applied at `weights` (missing weights are 0):
    /// p = p0 + sum_t w_t dp_t, n = normalize(n0 + sum_t w_t dn_t) (glTF 2.0 §3.7.2.2).
    fn read_prim(&self, prim: &gltf::Primitive<'_>, ptr: &str, weights: &[f32]) -> Result<LocalPrim, ImportError> {
        let file = self.buffers.file;
        let pos = prim.get(&gltf::Semantic::Positions).ok_or_else(|| {
            file_err(file, &format!("{ptr}/attributes"), "primitive has no POSITION attribute".into())
        })?;
        let mut positions = self.buffers.vec3(&pos, &format!("{ptr}/attributes/POSITION"))?;
        let n = positions.len();
        let read_n = |a: &gltf::Accessor<'_>, at: String, what: &str| {
            let v = self.buffers.vec3(a, &at)?;
            if v.len() == n { Ok(v) } else { Err(file_err(file, &at, format!("{} {what} for {n} positions", v.len()))) }
        };
        let mut normals = match prim.get(&gltf::Semantic::Normals) {
            Some(a) => Some(read_n(&a, format!("{ptr}/attributes/NORMAL"), "normals")?),
            None => None,
        };
        for (t, target) in prim.morph_targets().enumerate() {
            let w = weights.get(t).copied().unwrap_or(0.0);
            if !w.is_finite() {
                return Err(file_err(file, ptr, format!("morph target weight {t} is not finite")));
            }
            if w == 0.0 {
                continue;
            }
            if let Some(a) = target.positions() {
                let d = read_n(&a, format!("{ptr}/targets/{t}/POSITION"), "position displacements")?;
                positions.iter_mut().zip(d).for_each(|(p, d)| *p += w * d);
            }
            if let (Some(ns), Some(a)) = (normals.as_mut(), target.normals()) {
                let d = read_n(&a, format!("{ptr}/targets/{t}/NORMAL"), "normal displacements")?;
                ns.iter_mut().zip(d).for_each(|(v, d)| *v += w * d);
            }
        }
        let normals = normals.and_then(|ns| {
            ns.iter()
                .all(|v| v.is_finite() && v.length_squared() > 0.0)
                .then(|| ns.iter().map(|v| v.normalize()).collect())
        });
        let uvs = match prim.get(&gltf::Semantic::TexCoords(0)) {
            Some(a) => {
                let uv = self.buffers.vec2(&a, &format!("{ptr}/attributes/TEXCOORD_0"))?;
                if uv.len() != n {
                    return Err(file_err(
                        file,
                        &format!("{ptr}/attributes/TEXCOORD_0"),
                        format!("{} texture coordinates for {n} positions", uv.len()),
                    ));
                }
                Some(uv)
            }
            None => None,
        };
        let colors = match prim.get(&gltf::Semantic::Colors(0)) {
            Some(a) => {
                let at = format!("{ptr}/attributes/COLOR_0");
                let c = self.buffers.colors(&a, &at)?;
                if c.len() != n {
                    return Err(file_err(file, &at, format!("{} vertex colours for {n} positions", c.len())));
                }
                Some(c)
            }
            None => None,
        };
        let idx: Vec<u32> = match prim.indices() {
            Some(a) => self.buffers.indices(&a, &format!("{ptr}/indices"), n)?,
            None => (0..n as u32).collect(),
        };
        let indices = match prim.mode() {
            Mode::Triangles => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            Mode::TriangleStrip => (0..idx.len().saturating_sub(2))
                .map(|i| if i % 2 == 0 { [idx[i], idx[i + 1], idx[i + 2]] } else { [idx[i + 1], idx[i], idx[i + 2]] })
                .collect(),
            _ => (1..idx.len().saturating_sub(1)).map(|i| [idx[0], idx[i], idx[i + 1]]).collect(),
        };
        Ok(LocalPrim { positions, normals, uvs, colors, indices })
    }

    fn mesh(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        world: &Affine3A,
        node_name: &str,
        weights: &[f32],
    ) -> Result<(), ImportError> {
        let file = self.buffers.file;
        let mesh_name = mesh.name().map_or_else(|| format!("mesh{}", mesh.index()), str::to_owned);
        for prim in mesh.primitives() {
            let ptr = format!("/meshes/{}/primitives/{}", mesh.index(), prim.index());
            let mode = prim.mode();
            if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
                if !self.warned_modes.contains(&mode) {
                    self.warned_modes.push(mode);
                    self.out.warnings.push(format!(
                        "{}: {ptr}: primitive mode {mode:?} has no surface; such primitives are skipped",
                        file.display()
                    ));
                }
                continue;
            }
            self.triangles = self.triangles.saturating_add(self.triangle_count(&prim));
            if self.triangles > MAX_SCENE_TRIANGLES {
                return Err(err(
                    ImportErrorKind::TooLarge,
                    file,
                    &ptr,
                    format!("the scene would have more than {MAX_SCENE_TRIANGLES} triangles (instances counted)"),
                ));
            }
            let key = (mesh.index(), prim.index(), weights.iter().map(|w| w.to_bits()).collect());
            let local = match self.cache.get(&key) {
                Some(p) => p.clone(),
                None => {
                    let p = Rc::new(self.read_prim(&prim, &ptr, weights)?);
                    self.cache.insert(key, p.clone());
                    p
                }
            };
            if local.indices.is_empty() {
                continue;
            }
            let material = prim.material().index();
            let mat_name = prim
                .material()
                .name()
                .map_or_else(|| material.map_or("default".into(), |i| format!("material{i}")), str::to_owned);
            let mut m = MeshDesc {
                name: format!("{node_name}:{mesh_name}:{mat_name}"),
                positions: local.positions.clone(),
                normals: local.normals.clone(),
                uvs: local.uvs.clone(),
                colors: local.colors.clone(),
                indices: local.indices.clone(),
                material: 0,
                emission: None,
                source: SourceLocation { file: file.to_owned(), line: None, item: Some(ptr.clone()) },
            };
            transform_mesh(&mut m, world);
            if m.positions.iter().any(|p| !p.is_finite()) {
                return Err(file_err(
                    file,
                    &ptr,
                    "vertex positions overflow (not finite) after the node transforms".into(),
                ));
            }
            self.out.meshes.push((m, material));
        }
        Ok(())
    }

    fn camera(&mut self, cam: &gltf::Camera<'_>, world: &Affine3A, node_ptr: &str) {
        let file = self.buffers.file;
        let name = cam.name().map_or_else(|| format!("camera{}", cam.index()), str::to_owned);
        let position = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(-Vec3::Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
        if forward == Vec3::ZERO || up == Vec3::ZERO || forward.cross(up).length() < 1e-4 {
            self.out.warnings.push(format!(
                "{}: {node_ptr}: camera `{name}` has a degenerate transform; it is ignored",
                file.display()
            ));
            return;
        }
        let (yfov_deg, ymag, aspect) = match cam.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let f = p.yfov().to_degrees();
                if !(f > 0.0 && f < 180.0) {
                    self.out.warnings.push(format!(
                        "{}: /cameras/{}/perspective/yfov: {} rad is not in (0, pi); camera `{name}` is ignored",
                        file.display(),
                        cam.index(),
                        p.yfov()
                    ));
                    return;
                }
                (Some(f), 0.0, p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0))
            }
            gltf::camera::Projection::Orthographic(o) => {
                self.out.warnings.push(format!(
                    "{}: /cameras/{}: camera `{name}` is orthographic, which quasar does not support; it is \
                     replaced by a perspective camera at the same pose whose view spans the same height at the \
                     scene's centre",
                    file.display(),
                    cam.index()
                ));
                let (ymag, xmag) = (o.ymag().abs(), o.xmag().abs());
                let aspect = (ymag > 0.0 && xmag > 0.0).then(|| xmag / ymag).filter(|a| a.is_finite());
                (None, ymag * world.matrix3.y_axis.length(), aspect)
            }
        };
        self.out.cameras.push(PendingCamera {
            index: cam.index(),
            name,
            position,
            forward,
            up,
            yfov_deg,
            ymag,
            aspect,
        });
    }

    fn light(&mut self, light: &gltf::khr_lights_punctual::Light<'_>, world: &Affine3A, node_ptr: &str) {
        use gltf::khr_lights_punctual::Kind;
        let file = self.buffers.file;
        let c = light.color();
        let i = light.intensity();
        if !(c.iter().all(|v| v.is_finite() && *v >= 0.0) && i.is_finite() && i >= 0.0) {
            self.out.warnings.push(format!(
                "{}: /extensions/KHR_lights_punctual/lights/{}: colour or intensity is negative or not finite; the light \
                 (used by {node_ptr}) is ignored",
                file.display(),
                light.index()
            ));
            return;
        }
        if i == 0.0 || c.iter().all(|&v| v == 0.0) {
            return;
        }
        let spectrum = Spectrum::rgb_illuminant(c).unwrap_or(Spectrum::Constant(0.0));
        // candela (point, spot) and lux (directional) -> W/(sr nm) and W/(m^2 nm)
        let scale = photometric_scale(i);
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(-Vec3::Z);
        self.out.lights.push(match light.kind() {
            Kind::Point => LightDesc::Point { position, spectrum, scale },
            Kind::Directional => LightDesc::Directional { direction, spectrum, scale },
            Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                let outer = outer_cone_angle.to_degrees().clamp(0.0, 90.0);
                LightDesc::Spot {
                    position,
                    direction,
                    cone_deg: outer,
                    falloff_start_deg: inner_cone_angle.to_degrees().clamp(0.0, outer),
                    spectrum,
                    scale,
                }
            }
        });
    }
}

/// Resolves pending cameras against the scene bounds (orthographic fallback) into camera
/// descriptions, ordered by glTF camera index (then node order).
pub(super) fn finish_cameras(mut cams: Vec<PendingCamera>, center: Vec3) -> Vec<(String, CameraDesc, Option<f32>)> {
    cams.sort_by_key(|c| c.index);
    cams.into_iter()
        .map(|c| {
            let fov_deg = c.yfov_deg.unwrap_or_else(|| {
                let d = (center - c.position).dot(c.forward).max(1e-6);
                (2.0 * (c.ymag / d).atan().to_degrees()).clamp(0.01, 179.0)
            });
            let camera = CameraDesc {
                position: c.position,
                target: c.position + c.forward,
                up: c.up,
                fov_deg,
                fov_axis: FovAxis::Y,
            };
            (c.name, camera, c.aspect)
        })
        .collect()
}
