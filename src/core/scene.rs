//! The compiled, render-time scene: BVH, materials, lights (docs/architecture.md §2: import ->
//! SceneDesc -> **compile** -> integrate). Nothing here knows about file formats.

use std::borrow::Cow;
use std::sync::{Arc, OnceLock};

use glam::{Vec2, Vec3};
use quasar_importers::{LightDesc, SceneDesc};
use quasar_materials::pbr_material_at;
use quasar_materials::spectrum::SampledWavelengths;
use quasar_materials::{Bsdf, Frame, Material, NonUniformity};
use rayon::prelude::*;

use crate::core::emission::Emission;
use crate::core::emission_grid::textured_triangle;
use crate::core::geometry::{Accel, Hit, NONE, Ray, TriangleGeom, TriangleInfo};
use crate::core::light::{Light, LightSampler};
use crate::core::texture::{ImageTexture, TexturedMaterial};

use super::interaction::normal_mapped;
pub use super::interaction::{GeometricHit, SurfaceInteraction};

std::thread_local! {
    /// Rays this thread has traced ([`Scene::intersect`], [`Scene::intersect_geometry`],
    /// [`Scene::occluded`]): the deterministic measure of work by which `auto` compares methods
    /// (`render::pilot`). One add to a thread-local per ray, against a BVH traversal.
    static RAYS_TRACED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Rays traced so far by the calling thread (see [`RAYS_TRACED`]); a difference of two
/// readings on every thread of a pool is the work done between them.
pub fn rays_traced_by_this_thread() -> u64 {
    RAYS_TRACED.with(|c| c.get())
}

#[inline(always)]
fn count_ray() {
    RAYS_TRACED.with(|c| c.set(c.get() + 1));
}

/// Error compiling a scene description.
#[derive(Debug, thiserror::Error)]
pub enum CompileError {
    /// A mesh refers to a material or vertex that does not exist.
    #[error("{location}: mesh '{name}': {msg}")]
    Mesh {
        /// Mesh name.
        name: String,
        /// Where it was defined.
        location: String,
        /// What is wrong.
        msg: String,
    },
    /// A light has invalid parameters.
    #[error("light {index}: {msg}")]
    Light {
        /// Index in the scene's light list.
        index: usize,
        /// What is wrong.
        msg: String,
    },
}

/// Largest |coordinate| (metres) of a vertex that is kept: triangles further out are dropped like
/// non-finite ones. Beyond it, squared extents in the BVH builder's surface-area costs overflow
/// f32 and obvhs builds an invalid tree (an index out of bounds, found by fuzzing); 1e15 m is ten
/// orders of magnitude past the largest scene scale quasar supports (1e5 m, docs/architecture.md §9).
pub const MAX_COORDINATE: f32 = 1e15;

/// A key equal for the same triangle with any rotation of its vertices (same orientation).
fn triangle_key(v: &[Vec3; 3]) -> [u32; 9] {
    let bits = |p: Vec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let r = [bits(v[0]), bits(v[1]), bits(v[2])];
    let first = (0..3).min_by_key(|&i| r[i]).unwrap_or(0);
    let mut k = [0u32; 9];
    for j in 0..3 {
        k[3 * j..3 * j + 3].copy_from_slice(&r[(first + j) % 3]);
    }
    k
}

/// The render-time scene.
pub struct Scene {
    /// Triangles and BVH.
    pub accel: Accel,
    /// Materials (indexed by [`TriangleInfo::material`]).
    pub materials: Vec<Material>,
    /// Material names (same order).
    pub material_names: Vec<String>,
    /// Non-uniformity coefficient kappa of each material over incidence (docs/architecture.md §5),
    /// tabulated on first use ([`Scene::non_uniformity`]): only the bidirectional methods and
    /// the scene analysis read it.
    non_uniformity: OnceLock<Vec<NonUniformity>>,
    /// Emission records of emissive meshes.
    pub emissions: Vec<Emission>,
    /// All lights.
    pub lights: Vec<Light>,
    /// Indices of lights at infinity.
    pub infinite_lights: Vec<usize>,
    /// Power-proportional light selection.
    pub light_sampler: LightSampler,
    /// Per-vertex shading normals, three per smooth triangle.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates, three per triangle with a textured material.
    pub uvs: Vec<Vec2>,
    /// Per-vertex linear RGB colours, three per triangle with vertex colours and a textured
    /// (glTF per-point) material.
    pub colors: Vec<[f32; 3]>,
    /// Image textures (shared with the textured emissions).
    pub textures: Vec<Arc<ImageTexture>>,
    /// The textured form of each material (same order as `materials`; None for most).
    pub material_textures: Vec<Option<TexturedMaterial>>,
    /// Centre of the bounding sphere.
    pub center: Vec3,
    /// Radius of the bounding sphere.
    pub radius: f32,
    /// Microfacet masking-shadowing form of the GGX materials.
    masking: quasar_materials::Masking,
    /// The distinct media and the one inside each material (`core::media`).
    media: super::media::MediaTable,
    /// Whether any material absorbs or scatters inside: paths track their media only then.
    has_media: bool,
    /// Number of triangles that were dropped because a vertex was not finite or beyond
    /// [`MAX_COORDINATE`], the area is 0, or the triangle repeats another.
    pub dropped_triangles: usize,
}

impl Scene {
    /// Compiles a scene description: validates indices, builds the BVH, the lights and the
    /// light-selection distribution.
    pub fn compile(desc: &SceneDesc) -> Result<Self, CompileError> {
        Self::compile_with_masking(desc, desc.render.masking)
    }

    /// The microfacet masking-shadowing form of the GGX materials.
    pub fn masking(&self) -> quasar_materials::Masking {
        self.masking
    }

    /// [`compile`](Self::compile) with the GGX materials' masking-shadowing form `masking`
    /// instead of the scene's (`--masking`).
    pub fn compile_with_masking(desc: &SceneDesc, masking: quasar_materials::Masking) -> Result<Self, CompileError> {
        let mut tris = Vec::new();
        let mut infos = Vec::new();
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        let mut colors = Vec::new();
        let images: Vec<Arc<ImageTexture>> = desc.textures.iter().map(|t| Arc::new(ImageTexture::new(t))).collect();
        let mut emissions = Vec::new();
        let mut lights = Vec::new();
        let mut dropped = 0usize;
        let mut seen = std::collections::HashSet::new();
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for (mi, m) in desc.meshes.iter().enumerate() {
            let err = |msg: String| CompileError::Mesh { name: m.name.clone(), location: m.source.to_string(), msg };
            if m.material >= desc.materials.len() {
                return Err(err(format!("material index {} out of range", m.material)));
            }
            if let Some(n) = &m.normals
                && n.len() != m.positions.len()
            {
                return Err(err(format!("{} normals for {} positions", n.len(), m.positions.len())));
            }
            if let Some(t) = &m.uvs
                && t.len() != m.positions.len()
            {
                return Err(err(format!("{} texture coordinates for {} positions", t.len(), m.positions.len())));
            }
            if let Some(c) = &m.colors
                && c.len() != m.positions.len()
            {
                return Err(err(format!("{} vertex colours for {} positions", c.len(), m.positions.len())));
            }
            let textured = !desc.materials[m.material].textures.is_empty();
            let emission = match &m.emission {
                Some(e) if e.scale > 0.0 && e.scale.is_finite() => {
                    emissions.push(Emission::new(e, &images, m.uvs.is_some()));
                    (emissions.len() - 1) as u32
                }
                _ => NONE,
            };
            let emission_texture = emissions.get(emission as usize).and_then(|e| e.texture.clone());
            let nominal = emissions.get(emission as usize).map_or(0.0, |e| e.spectrum.luminance());
            for (ti, idx) in m.indices.iter().enumerate() {
                let mut v = [Vec3::ZERO; 3];
                for k in 0..3 {
                    let i = idx[k] as usize;
                    if i >= m.positions.len() {
                        return Err(err(format!("triangle {ti} refers to vertex {i} of {}", m.positions.len())));
                    }
                    v[k] = m.positions[i];
                }
                // non-finite or zero-area (in f32) triangles can never be hit (the intersection
                // determinant is 0) or sampled; left in, masses of them (a sphere of radius 1e-45)
                // make the BVH build quadratic; too distant ones (MAX_COORDINATE) break the build
                if !v.iter().all(|p| p.is_finite() && p.abs().max_element() <= MAX_COORDINATE)
                    || (v[1] - v[0]).cross(v[2] - v[0]) == Vec3::ZERO
                {
                    dropped += 1;
                    continue;
                }
                // an exact copy of a triangle already in the scene adds nothing (z-fighting at
                // best) and masses of them make the BVH build quadratic
                if !seen.insert(triangle_key(&v)) {
                    dropped += 1;
                    continue;
                }
                let mut nidx = NONE;
                if let Some(ns) = &m.normals {
                    let n = [ns[idx[0] as usize], ns[idx[1] as usize], ns[idx[2] as usize]];
                    if n.iter().all(|n| n.is_finite() && n.length_squared() > 0.0) {
                        nidx = normals.len() as u32;
                        normals.extend(n.iter().map(|n| n.normalize()));
                    }
                }
                let mut uidx = NONE;
                if (textured || emission_texture.is_some())
                    && let Some(t) = &m.uvs
                {
                    uidx = uvs.len() as u32;
                    uvs.extend(idx.iter().map(|&i| t[i as usize]));
                }
                let mut cidx = NONE;
                if textured && let Some(c) = &m.colors {
                    cidx = colors.len() as u32;
                    colors.extend(
                        idx.iter().map(|&i| c[i as usize].map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })),
                    );
                }
                for p in v {
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
                let mut light = NONE;
                if emission != NONE {
                    light = lights.len() as u32;
                    let tri = TriangleGeom::new(v[0], v[1], v[2]);
                    lights.push(match (&emission_texture, &m.uvs) {
                        (Some(t), Some(uv)) => {
                            let uv = idx.map(|i| uv[i as usize]);
                            let (weight, grid) = textured_triangle(t, &uv, nominal);
                            Light::area_triangle_textured(tri, emission, uv, weight, grid)
                        }
                        _ => Light::area_triangle(tri, emission),
                    });
                }
                tris.push(v);
                infos.push(TriangleInfo {
                    material: m.material as u32,
                    light,
                    normals: nidx,
                    mesh: mi as u32,
                    uvs: uidx,
                    colors: cidx,
                });
            }
        }
        let (center, radius) = if tris.is_empty() {
            (Vec3::ZERO, 1.0)
        } else {
            let c = 0.5 * (lo + hi);
            (c, (0.5 * (hi - lo).length()).max(1e-6))
        };
        let accel = Accel::build(&tris, &infos, Accel::default_params());
        drop(tris);
        for (index, l) in desc.lights.iter().enumerate() {
            let lerr = |msg: &str| CompileError::Light { index, msg: msg.to_string() };
            let light = match l {
                LightDesc::Point { position, spectrum, scale } => {
                    Light::Point { position: *position, spectrum: spectrum.densified(), scale: *scale }
                }
                LightDesc::Spot { position, direction, cone_deg, falloff_start_deg, spectrum, scale } => {
                    let d = direction.normalize_or_zero();
                    if d == Vec3::ZERO || !d.is_finite() {
                        return Err(lerr("spot direction is zero"));
                    }
                    let total = cone_deg.clamp(0.0, 180.0).to_radians();
                    let start = falloff_start_deg.clamp(0.0, *cone_deg).to_radians();
                    Light::Spot {
                        position: *position,
                        frame: Frame::from_z(d),
                        cos_total: total.cos(),
                        cos_falloff_start: start.cos(),
                        spectrum: spectrum.densified(),
                        scale: *scale,
                    }
                }
                LightDesc::Directional { direction, spectrum, scale } => {
                    let d = direction.normalize_or_zero();
                    if d == Vec3::ZERO || !d.is_finite() {
                        return Err(lerr("directional light direction is zero"));
                    }
                    Light::Directional {
                        direction: d,
                        spectrum: spectrum.densified(),
                        scale: *scale,
                        scene_radius: radius,
                    }
                }
                LightDesc::Luminaire { position, frame, web, spectrum, scale, opening } => {
                    if !position.is_finite() || !frame.is_finite() || !scale.is_finite() || *scale < 0.0 {
                        return Err(lerr("luminaire position, orientation and scale must be finite"));
                    }
                    let l = crate::core::luminaire::Luminaire::new(
                        *position,
                        *frame,
                        web.clone(),
                        spectrum.densified(),
                        *scale,
                    )
                    .with_opening(*opening);
                    Light::Luminaire(std::sync::Arc::new(l))
                }
                LightDesc::Environment { spectrum, scale, map } => Light::Environment {
                    spectrum: spectrum.densified(),
                    scale: *scale,
                    scene_radius: radius,
                    map: map.as_ref().map(|m| std::sync::Arc::new(crate::core::env_map::EnvMap::new(m))),
                },
            };
            lights.push(light);
        }
        let infinite_lights = lights.iter().enumerate().filter(|(_, l)| l.is_infinite()).map(|(i, _)| i).collect();
        let light_sampler = LightSampler::new(&lights, &emissions);
        let media = super::media::MediaTable::new(&desc.materials);
        Ok(Self {
            accel,
            // spectra pre-sampled on the 1 nm grid (identical values to float rounding)
            materials: desc.materials.iter().map(|m| m.material.densified()).collect(),
            material_names: desc.materials.iter().map(|m| m.name.clone()).collect(),
            non_uniformity: OnceLock::new(),
            emissions,
            lights,
            infinite_lights,
            light_sampler,
            normals,
            uvs,
            colors,
            textures: images,
            material_textures: desc.materials.iter().map(|m| TexturedMaterial::new(&m.textures)).collect(),
            center,
            radius,
            masking,
            has_media: !media.is_empty(),
            media,
            dropped_triangles: dropped,
        })
    }

    /// Whether any material absorbs or scatters inside (paths track their media only then).
    #[inline(always)]
    pub fn has_media(&self) -> bool {
        self.has_media
    }

    /// The medium of id `id` (`core::media`); None for a clear material's.
    #[inline(always)]
    pub fn medium(&self, id: u32) -> Option<&super::media::Medium> {
        self.media.get(id)
    }

    /// The id of the medium inside material `m` (`core::media::CLEAR` for a clear one).
    #[inline(always)]
    pub fn medium_of(&self, m: u32) -> u32 {
        self.media.medium_of(m)
    }

    /// kappa of every material over incidence (indexed like [`Scene::materials`]), tabulated by
    /// the first call: about 400,000 BSDF evaluations on the glass plate, which a path tracer
    /// does not need. Inside a rayon worker the table is made serially: a parallel map there
    /// could steal a task that asks for the table again before it exists.
    pub fn non_uniformity(&self) -> &[NonUniformity] {
        self.non_uniformity.get_or_init(|| {
            if rayon::current_thread_index().is_some() {
                self.materials.iter().map(NonUniformity::of_material).collect()
            } else {
                self.materials.par_iter().map(NonUniformity::of_material).collect()
            }
        })
    }

    /// Closest surface hit along `ray`.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        count_ray();
        let h = self.accel.intersect(ray)?;
        Some(self.interaction(ray, &h))
    }

    /// The closest hit along `ray` with its geometry only (point, error bound, geometric normal):
    /// for probes that need no shading normal, texture coordinates or material.
    #[inline]
    pub fn intersect_geometry(&self, ray: &Ray) -> Option<GeometricHit> {
        count_ray();
        Some(self.geometry(&self.accel.intersect(ray)?))
    }

    /// Point, error bound and unit geometric normal of hit `h`.
    #[inline]
    fn geometry(&self, h: &Hit) -> GeometricHit {
        let g = &self.accel.geom[h.prim as usize];
        let (p, p_err) = g.point_with_error(h.b1, h.b2);
        GeometricHit { p, p_err, ng: Vec3::from(g.n), t: h.t }
    }

    /// True when the segment of `ray` up to `t_max` is blocked.
    #[inline(always)]
    pub fn occluded(&self, ray: &Ray) -> bool {
        count_ray();
        self.accel.occluded(ray)
    }

    #[inline(always)]
    fn interaction(&self, _ray: &Ray, h: &Hit) -> SurfaceInteraction {
        let g = &self.accel.geom[h.prim as usize];
        let info = &self.accel.info[h.prim as usize];
        let GeometricHit { p, p_err, ng, .. } = self.geometry(h);
        let mut ns = ng;
        if info.normals != NONE {
            let n = &self.normals[info.normals as usize..info.normals as usize + 3];
            let b0 = 1.0 - h.b1 - h.b2;
            let s = (n[0] * b0 + n[1] * h.b1 + n[2] * h.b2).normalize_or_zero();
            if s != Vec3::ZERO && s.is_finite() {
                ns = if s.dot(ng) < 0.0 { -s } else { s };
            }
        }
        let mut uv = Vec2::ZERO;
        if info.uvs != NONE {
            let t = &self.uvs[info.uvs as usize..info.uvs as usize + 3];
            uv = t[0] * (1.0 - h.b1 - h.b2) + t[1] * h.b1 + t[2] * h.b2;
            if let Some(n) =
                self.material_textures[info.material as usize].as_ref().and_then(|t| t.normal_at(&self.textures, uv))
            {
                ns = normal_mapped(g, t, ns, ng, n);
            }
        }
        let bary = Vec2::new(h.b1, h.b2);
        SurfaceInteraction {
            p,
            p_err,
            ng,
            ns,
            t: h.t,
            prim: h.prim,
            material: info.material,
            light: info.light,
            uv,
            bary,
        }
    }

    /// The material at a surface point: the material table's entry, or for a textured (glTF)
    /// material the one its factors times the texels at `si.uv` map to.
    #[inline]
    pub fn material_at(&self, si: &SurfaceInteraction) -> Cow<'_, Material> {
        let m = si.material as usize;
        match self.material_textures.get(m) {
            Some(Some(t)) => {
                let mut p = t.params_at(&self.textures, si.uv);
                if let Some(c) = self.vertex_color(si) {
                    for (b, c) in p.base_color.iter_mut().zip(c) {
                        *b *= c;
                    }
                }
                Cow::Owned(pbr_material_at(&p))
            }
            _ => Cow::Borrowed(&self.materials[m]),
        }
    }

    /// The vertex colour at a surface point, interpolated from its triangle's (None without).
    #[inline]
    pub fn vertex_color(&self, si: &SurfaceInteraction) -> Option<[f32; 3]> {
        let info = self.accel.info.get(si.prim as usize)?;
        if info.colors == NONE {
            return None;
        }
        let c = &self.colors[info.colors as usize..info.colors as usize + 3];
        let (b1, b2) = (si.bary.x, si.bary.y);
        let b0 = 1.0 - b1 - b2;
        Some(std::array::from_fn(|k| c[0][k] * b0 + c[1][k] * b1 + c[2][k] * b2))
    }

    /// The BSDF at a surface point for the path's wavelengths (see [`material_at`](Self::material_at)).
    /// It borrows the scene (tabulated tables), never the temporary textured material: textures
    /// only produce analytic materials, whose BSDFs borrow nothing.
    #[inline(always)]
    pub fn bsdf_at(&self, si: &SurfaceInteraction, wl: &mut SampledWavelengths) -> Bsdf<'_> {
        match self.material_at(si) {
            Cow::Borrowed(m) => m.bsdf_with(wl, self.masking),
            Cow::Owned(m) => m.bsdf_with(wl, self.masking).detached().unwrap_or(Bsdf::Black),
        }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.accel.geom.len()
    }
}
