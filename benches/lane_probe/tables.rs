//! The scene's spectra, materials, lights and triangles in flat tables that lanes fetch from.

use super::*;

/// The scene's spectra on a 1 nm grid, its materials and its lights, in the form the lanes
/// gather from.
pub(crate) struct Tables {
    /// Per material: Lambertian or dielectric.
    pub(crate) dielectric: Vec<bool>,
    /// Reflectance per material, one row of GRID values each (clamped to [0, 1] as
    /// `DiffuseBsdf::new` does; zero for dielectrics).
    pub(crate) refl_flat: Vec<f32>,
    pub(crate) two_sided: Vec<bool>,
    /// Relative IOR and GGX alpha of the dielectrics (1 and 0 elsewhere).
    pub(crate) eta: Vec<f32>,
    pub(crate) alpha: Vec<f32>,
    /// Emitted radiance (spectrum times scale), one row per emission record and, last, the
    /// environment's.
    pub(crate) emit_flat: Vec<f32>,
    pub(crate) emit_two_sided: Vec<bool>,
    /// Per light: first vertex, edges, unit normal, area, emission record (of an area light), or
    /// the environment (`env`), and its selection probability.
    pub(crate) light_v0: Vec<Vec3>,
    pub(crate) light_e1: Vec<Vec3>,
    pub(crate) light_e2: Vec<Vec3>,
    pub(crate) light_n: Vec<Vec3>,
    pub(crate) light_area: Vec<f32>,
    pub(crate) light_emission: Vec<u32>,
    pub(crate) light_env: Vec<bool>,
    pub(crate) light_sel: Vec<f32>,
    /// The environment's row of `emit_flat` and selection probability, if the scene has one.
    pub(crate) env: Option<(u32, f32)>,
}

/// Values of `f` at the four wavelengths of `wl`, at every grid point.
pub(crate) fn tabulate(f: impl Fn(&SampledWavelengths) -> SampledSpectrum) -> [f32; GRID] {
    let mut t = [0.0; GRID];
    for j in (0..GRID).step_by(NW) {
        let lambda: [f32; NW] = std::array::from_fn(|k| LAMBDA_MIN + (j + k).min(GRID - 1) as f32);
        let v = f(&SampledWavelengths::from_parts(lambda, [1.0; NW]));
        for k in 0..NW {
            if j + k < GRID {
                t[j + k] = v.0[k];
            }
        }
    }
    t
}

impl Tables {
    /// True when the hand-written Lambertian lanes can render the scene: no dielectric, no
    /// environment.
    pub(crate) fn all_diffuse(&self) -> bool {
        !self.dielectric.iter().any(|&d| d) && self.env.is_none()
    }

    /// The tables of `scene`, or why the probe cannot render it.
    pub(crate) fn new(scene: &Scene) -> Result<Self, String> {
        if scene.material_textures.iter().any(Option::is_some) || !scene.normals.is_empty() {
            return Err("textures and shading normals are not supported".into());
        }
        if scene.lights.is_empty() {
            return Err("the scene has no lights".into());
        }
        let mut t = Self {
            dielectric: Vec::new(),
            refl_flat: Vec::new(),
            two_sided: Vec::new(),
            eta: Vec::new(),
            alpha: Vec::new(),
            emit_flat: Vec::new(),
            emit_two_sided: scene.emissions.iter().map(|e| e.two_sided).collect(),
            light_v0: Vec::new(),
            light_e1: Vec::new(),
            light_e2: Vec::new(),
            light_n: Vec::new(),
            light_area: Vec::new(),
            light_emission: Vec::new(),
            light_env: Vec::new(),
            light_sel: Vec::new(),
            env: None,
        };
        for (m, name) in scene.materials.iter().zip(&scene.material_names) {
            let (dielectric, refl, two_sided, eta, alpha) = match m {
                Material::Diffuse { reflectance, two_sided } => {
                    (false, tabulate(|wl| reflectance.sample(wl).clamp_unit()), *two_sided, 1.0, 0.0)
                }
                Material::Dielectric { ior, alpha } if !ior.is_dispersive() => {
                    let eta = ior.at(550.0);
                    (true, [0.0; GRID], false, if eta.is_finite() && eta > 1e-4 { eta } else { 1.0 }, *alpha)
                }
                _ => return Err(format!("material {name} is neither diffuse nor a non-dispersive dielectric")),
            };
            t.dielectric.push(dielectric);
            t.refl_flat.extend_from_slice(&refl);
            t.two_sided.push(two_sided);
            t.eta.push(eta);
            t.alpha.push(alpha);
        }
        for e in &scene.emissions {
            t.emit_flat.extend_from_slice(&tabulate(|wl| e.spectrum.sample(wl) * e.scale));
        }
        for (i, l) in scene.lights.iter().enumerate() {
            let sel = scene.light_sampler.pmf(i);
            match l {
                Light::Area { tri, emission, area } => {
                    t.light_v0.push(Vec3::from(tri.v0));
                    t.light_e1.push(Vec3::from(tri.e1));
                    t.light_e2.push(Vec3::from(tri.e2));
                    t.light_n.push(Vec3::from(tri.n));
                    t.light_area.push(*area);
                    t.light_emission.push(*emission);
                    t.light_env.push(false);
                }
                Light::Environment { spectrum, scale, map: None, .. } if t.env.is_none() => {
                    let row = (t.emit_flat.len() / GRID) as u32;
                    t.emit_flat.extend_from_slice(&tabulate(|wl| spectrum.sample(wl) * *scale));
                    t.emit_two_sided.push(true);
                    t.env = Some((row, sel));
                    t.light_v0.push(Vec3::ZERO);
                    t.light_e1.push(Vec3::ZERO);
                    t.light_e2.push(Vec3::ZERO);
                    t.light_n.push(Vec3::Z);
                    t.light_area.push(1.0);
                    t.light_emission.push(row);
                    t.light_env.push(true);
                }
                _ => return Err("only area lights and one constant environment are supported".into()),
            }
            t.light_sel.push(sel);
        }
        Ok(t)
    }
}

/// The value of row `row` of the flat 1 nm tables `t` at `lambda` (linear between grid points).
#[inline(always)]
pub(crate) fn lookup(t: &[f32], row: u32, lambda: f32) -> f32 {
    let x = (lambda - LAMBDA_MIN).clamp(0.0, (GRID - 1) as f32);
    let c = (x as usize).min(GRID - 2);
    let f = x - c as f32;
    let base = row as usize * GRID + c;
    let (a, b) = (t[base], t[base + 1]);
    a + f * (b - a)
}

/// The scene's triangles in structure-of-arrays form, for lane gathers by triangle index.
pub(crate) struct TriTable {
    pub(crate) v0: [Vec<f32>; 3],
    pub(crate) e1: [Vec<f32>; 3],
    pub(crate) e2: [Vec<f32>; 3],
    pub(crate) n: [Vec<f32>; 3],
    pub(crate) material: Vec<u32>,
    pub(crate) light: Vec<u32>,
}

impl TriTable {
    /// The triangles of `scene`, indexed as `Hit::prim` indexes them.
    pub(crate) fn new(scene: &Scene) -> Self {
        let g = &scene.accel.geom;
        let col = |f: &dyn Fn(&quasar::core::geometry::TriangleGeom) -> f32| g.iter().map(f).collect::<Vec<f32>>();
        Self {
            v0: [col(&|t| t.v0.x), col(&|t| t.v0.y), col(&|t| t.v0.z)],
            e1: [col(&|t| t.e1.x), col(&|t| t.e1.y), col(&|t| t.e1.z)],
            e2: [col(&|t| t.e2.x), col(&|t| t.e2.y), col(&|t| t.e2.z)],
            n: [col(&|t| t.n.x), col(&|t| t.n.y), col(&|t| t.n.z)],
            material: scene.accel.info.iter().map(|i| i.material).collect(),
            light: scene.accel.info.iter().map(|i| i.light).collect(),
        }
    }
}

/// [`lookup`] in every lane.
#[inline(always)]
pub(crate) fn lookup_lanes<const W: usize>(t: &[f32], row: &[u32; W], lambda: &L<W>) -> L<W> {
    let mut out = [0.0; W];
    for i in 0..W {
        out[i] = lookup(t, row[i], lambda[i]);
    }
    out
}
