//! Lane probe (issue 15; BENCHMARKS.md "Sixth engine round: a lane probe"): how much faster
//! `pt`'s estimator runs when W paths advance together, one per SIMD lane, as Mitsuba's
//! `llvm_ad_spectral` runs its path tracer, measured before anyone rewrites the integrator, the
//! BSDFs and the lights that way, and which parts of the work lanes speed up.
//!
//! The probe is `pt`'s estimator (next-event estimation with the power heuristic against
//! cosine-weighted BSDF sampling, emission at BSDF-sampled hits with its MIS weight, Russian
//! roulette from the third scattering event, four hero wavelengths, quasar's ray offsets) for
//! the subset of scenes it needs: Lambertian materials and triangle area lights without an
//! environment (the Cornell box). It keeps W paths in structure-of-arrays form and gives a lane
//! the next (pixel, sample) as soon as its path ends. The path arithmetic (emission and its MIS
//! weight, the light sample, the BSDF sample, the frame, the ray offsets, Russian roulette) runs
//! as loops over the W lanes without branches, which the compiler turns into SIMD instructions of
//! the target's width. The variants differ in what else runs over lanes:
//!
//! - `lanes`: the rays are traced one at a time through quasar's BVH, the hit data, random
//!   numbers and spectra are fetched per lane through quasar's own types;
//! - `+gather`: random numbers (quasar's PCG32 streams, one per lane, advanced together), hit
//!   points, materials, emission and reflectance come from lane loops over flat tables;
//! - `+packets`: closest hits from a packet traversal of a binary BVH built here, all W rays
//!   against a node's box and a leaf's triangles at once (ray-parallel SIMD, as Embree's packet
//!   traversal serves Mitsuba's `rtcIntersect16`); `+shadow packets` traces the shadow rays so too.
//!
//! Every variant draws the random numbers `pt` draws for the same seed, in `pt`'s order, and
//! finds the same hits, so every variant's image mean is the same value bit for bit, and `pt`'s
//! differs from it only through the probe's 1 nm linear spectra (3e-5 on the Cornell box). Not a
//! test and not a second renderer: a measurement of what lanes buy.
//!
//! Run (the portable build, then one for this CPU, e.g. AVX-512):
//!   cargo bench --bench lane_probe -- [SCENE] [--size N] [--spp N] [--rounds R] [--stages]
//!   RUSTFLAGS="-C target-cpu=native" CARGO_TARGET_DIR=target/native cargo bench --bench lane_probe

// the lane loops index several arrays by the same lane, as the SIMD code they become does
#![allow(clippy::needless_range_loop)]

use std::f32::consts::FRAC_1_PI;
use std::path::Path;
use std::time::Instant;

use glam::{Vec2, Vec3};
use quasar::core::camera::Camera;
use quasar::core::geometry::{NONE, Ray, offset_origin};
use quasar::core::light::Light;
use quasar::core::sampling::{Sampler, cosine_hemisphere, mix64, power_heuristic};
use quasar::core::scene::Scene;
use quasar::integrator::per_pixel::PerPixel;
use quasar::integrator::pt::PtSettings;
use quasar::materials::spectrum::{LAMBDA_MAX, LAMBDA_MIN, SampledSpectrum, SampledWavelengths};
use quasar::materials::{Frame, Material};
use quasar::render::driver::{self, DriverOptions};
use quasar::render::job::load_scene;

/// Hero wavelengths per path.
const NW: usize = 4;
/// Points of the 1 nm tables.
const GRID: usize = (LAMBDA_MAX - LAMBDA_MIN) as usize + 1;
/// Parts of the loop timed with `--stages`.
const N_STAGES: usize = 5;
const STAGE_NAMES: [&str; N_STAGES] = ["shadow rays", "film, new paths", "closest hits", "gathers", "path arithmetic"];

/// The scene's spectra on a 1 nm grid and its area lights, in the form the lanes gather from.
struct Tables {
    /// Reflectance per material (clamped to [0, 1] as `DiffuseBsdf::new` does).
    refl: Vec<[f32; GRID]>,
    /// The same, one row of GRID values per material.
    refl_flat: Vec<f32>,
    two_sided: Vec<bool>,
    /// Emitted radiance (spectrum times scale), one row per emission record.
    emit_flat: Vec<f32>,
    emit_two_sided: Vec<bool>,
    /// Per light: first vertex, edges, unit normal, area, emission record, selection probability.
    light_v0: Vec<Vec3>,
    light_e1: Vec<Vec3>,
    light_e2: Vec<Vec3>,
    light_n: Vec<Vec3>,
    light_area: Vec<f32>,
    light_emission: Vec<u32>,
    light_sel: Vec<f32>,
}

/// Values of `f` at the four wavelengths of `wl`, at every grid point.
fn tabulate(f: impl Fn(&SampledWavelengths) -> SampledSpectrum) -> [f32; GRID] {
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
    /// The tables of `scene`, or why the probe cannot render it.
    fn new(scene: &Scene) -> Result<Self, String> {
        let mut refl = Vec::new();
        let mut two_sided = Vec::new();
        for (m, name) in scene.materials.iter().zip(&scene.material_names) {
            let Material::Diffuse { reflectance, two_sided: t } = m else {
                return Err(format!("material {name} is not diffuse"));
            };
            refl.push(tabulate(|wl| reflectance.sample(wl).clamp_unit()));
            two_sided.push(*t);
        }
        if scene.material_textures.iter().any(Option::is_some) || !scene.normals.is_empty() {
            return Err("textures and shading normals are not supported".into());
        }
        if !scene.infinite_lights.is_empty() {
            return Err("lights at infinity are not supported".into());
        }
        if scene.lights.is_empty() {
            return Err("the scene has no lights".into());
        }
        let emit: Vec<[f32; GRID]> =
            scene.emissions.iter().map(|e| tabulate(|wl| e.spectrum.sample(wl) * e.scale)).collect();
        let mut t = Self {
            refl_flat: refl.iter().flatten().copied().collect(),
            refl,
            two_sided,
            emit_flat: emit.iter().flatten().copied().collect(),
            emit_two_sided: scene.emissions.iter().map(|e| e.two_sided).collect(),
            light_v0: Vec::new(),
            light_e1: Vec::new(),
            light_e2: Vec::new(),
            light_n: Vec::new(),
            light_area: Vec::new(),
            light_emission: Vec::new(),
            light_sel: Vec::new(),
        };
        for (i, l) in scene.lights.iter().enumerate() {
            let Light::Area { tri, emission, area } = l else { return Err("only area lights are supported".into()) };
            t.light_v0.push(Vec3::from(tri.v0));
            t.light_e1.push(Vec3::from(tri.e1));
            t.light_e2.push(Vec3::from(tri.e2));
            t.light_n.push(Vec3::from(tri.n));
            t.light_area.push(*area);
            t.light_emission.push(*emission);
            t.light_sel.push(scene.light_sampler.pmf(i));
        }
        Ok(t)
    }
}

/// The value of a 1 nm table at `lambda` (linear between grid points).
#[inline(always)]
fn lookup(t: &[f32; GRID], lambda: f32) -> f32 {
    let x = (lambda - LAMBDA_MIN).clamp(0.0, (GRID - 1) as f32);
    let c = (x as usize).min(GRID - 2);
    let f = x - c as f32;
    t[c] + f * (t[c + 1] - t[c])
}

/// W floats, one per lane.
type L<const W: usize> = [f32; W];

/// Three lane vectors: x, y and z of W 3-vectors.
#[derive(Clone, Copy)]
struct V<const W: usize> {
    x: L<W>,
    y: L<W>,
    z: L<W>,
}

impl<const W: usize> V<W> {
    const ZERO: Self = Self { x: [0.0; W], y: [0.0; W], z: [0.0; W] };

    #[inline(always)]
    fn set(&mut self, i: usize, v: Vec3) {
        (self.x[i], self.y[i], self.z[i]) = (v.x, v.y, v.z);
    }

    #[inline(always)]
    fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }
}

/// `offset_origin(p, p_err, n, d)` for every lane.
#[inline(always)]
fn offset<const W: usize>(p: &V<W>, e: &V<W>, n: &V<W>, d: &V<W>, out: &mut V<W>) {
    for i in 0..W {
        out.set(i, offset_origin(p.get(i), e.get(i), n.get(i), d.get(i)));
    }
}

/// A binary BVH over the scene's triangles for the probe's packet traversal (median splits,
/// leaves of at most four triangles): W rays visit a node together when any of them enters it,
/// and a leaf's triangles are tested against all W rays at once (ray-parallel SIMD, the way
/// Embree's packet traversal serves `rtcIntersect16`).
struct PacketBvh {
    /// Per node: bounds and either (first child, 0) or (first triangle, count).
    nodes: Vec<([f32; 3], [f32; 3], u32, u32)>,
    /// Per triangle (in leaf order): v0, e1, e2, e1 x e2, index in the scene.
    tris: Vec<(Vec3, Vec3, Vec3, Vec3, u32)>,
}

impl PacketBvh {
    fn new(scene: &Scene) -> Self {
        let geom = &scene.accel.geom;
        let mut idx: Vec<u32> = (0..geom.len() as u32).collect();
        let mut bvh = Self { nodes: vec![([0.0; 3], [0.0; 3], 0, 0)], tris: Vec::new() };
        bvh.build(scene, 0, &mut idx);
        bvh
    }

    fn build(&mut self, scene: &Scene, node: usize, idx: &mut [u32]) {
        let g = |i: u32| &scene.accel.geom[i as usize];
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for &i in idx.iter() {
            let t = g(i);
            for v in [t.v0, t.v0 + t.e1, t.v0 + t.e2] {
                lo = lo.min(Vec3::from(v));
                hi = hi.max(Vec3::from(v));
            }
        }
        if idx.len() <= 4 {
            self.nodes[node] = (lo.to_array(), hi.to_array(), self.tris.len() as u32, idx.len() as u32);
            for &i in idx.iter() {
                let t = g(i);
                let (e1, e2) = (Vec3::from(t.e1), Vec3::from(t.e2));
                self.tris.push((Vec3::from(t.v0), e1, e2, e1.cross(e2), i));
            }
            return;
        }
        let axis = (hi - lo).max_position();
        let c = |i: u32| {
            let t = g(i);
            (t.v0 * 3.0 + t.e1 + t.e2)[axis]
        };
        idx.sort_by(|&a, &b| c(a).total_cmp(&c(b)));
        let first = self.nodes.len();
        self.nodes.push(([0.0; 3], [0.0; 3], 0, 0));
        self.nodes.push(([0.0; 3], [0.0; 3], 0, 0));
        self.nodes[node] = (lo.to_array(), hi.to_array(), first as u32, 0);
        let (a, b) = idx.split_at_mut(idx.len() / 2);
        self.build(scene, first, a);
        self.build(scene, first + 1, b);
    }

    /// Lanes whose ray (o, d) enters node `n` at t in [0, t_max].
    #[inline(always)]
    fn enter<const W: usize>(&self, n: usize, o: &V<W>, inv: &V<W>, t_max: &L<W>, live: &[bool; W]) -> [bool; W] {
        let (lo, hi, _, _) = &self.nodes[n];
        let mut m = [false; W];
        for i in 0..W {
            let (x0, x1) = ((lo[0] - o.x[i]) * inv.x[i], (hi[0] - o.x[i]) * inv.x[i]);
            let (y0, y1) = ((lo[1] - o.y[i]) * inv.y[i], (hi[1] - o.y[i]) * inv.y[i]);
            let (z0, z1) = ((lo[2] - o.z[i]) * inv.z[i], (hi[2] - o.z[i]) * inv.z[i]);
            let near = x0.min(x1).max(y0.min(y1)).max(z0.min(z1)).max(0.0);
            let far = x0.max(x1).min(y0.max(y1)).min(z0.max(z1)).min(t_max[i]) * (1.0 + 4.0 * f32::EPSILON);
            m[i] = live[i] & (near <= far);
        }
        m
    }

    /// Per lane: whether the ray hits triangle `k` before `t_max`, and (t, b1, b2): the
    /// Moeller-Trumbore test of quasar's `Triangle4` per lane, with one division per lane (a
    /// form without it, which divides only for a triangle that some lane hits, measured slower).
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn hits<const W: usize>(&self, k: usize, o: &V<W>, d: &V<W>, t_max: &L<W>) -> ([bool; W], L<W>, L<W>, L<W>) {
        let (v0, e1, e2, n, _) = self.tris[k];
        let (mut m, mut tt, mut bb1, mut bb2) = ([false; W], [0.0; W], [0.0; W], [0.0; W]);
        for i in 0..W {
            let (sx, sy, sz) = (o.x[i] - v0.x, o.y[i] - v0.y, o.z[i] - v0.z);
            let (rx, ry, rz) = (sy * d.z[i] - sz * d.y[i], sz * d.x[i] - sx * d.z[i], sx * d.y[i] - sy * d.x[i]);
            let det = -(d.x[i] * n.x + d.y[i] * n.y + d.z[i] * n.z);
            let inv = 1.0 / det;
            let b1 = (e2.x * rx + e2.y * ry + e2.z * rz) * inv;
            let b2 = -(e1.x * rx + e1.y * ry + e1.z * rz) * inv;
            let t = (sx * n.x + sy * n.y + sz * n.z) * inv;
            m[i] = det != 0.0 && b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 && t > 0.0 && t < t_max[i];
            (tt[i], bb1[i], bb2[i]) = (t, b1, b2);
        }
        (m, tt, bb1, bb2)
    }

    /// The nearest hit of every live lane's ray: (scene triangle or NONE, t, b1, b2) per lane.
    #[allow(clippy::type_complexity)]
    fn nearest<const W: usize>(&self, o: &V<W>, d: &V<W>, live: &[bool; W]) -> ([u32; W], L<W>, L<W>, L<W>) {
        let mut inv = V::<W>::ZERO;
        for i in 0..W {
            let f = |x: f32| 1.0 / if x.abs() < 1e-30 { 1e-30f32.copysign(x) } else { x };
            (inv.x[i], inv.y[i], inv.z[i]) = (f(d.x[i]), f(d.y[i]), f(d.z[i]));
        }
        let (mut prim, mut t_best, mut b1, mut b2) = ([NONE; W], [1e38f32; W], [0.0; W], [0.0; W]);
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let n = stack[sp] as usize;
            let m = self.enter(n, o, &inv, &t_best, live);
            if !m.iter().any(|&x| x) {
                continue;
            }
            let (_, _, first, count) = self.nodes[n];
            if count == 0 {
                // nearer child last (popped first), by the first entering lane's direction
                let lane = m.iter().position(|&x| x).unwrap_or(0);
                let (lo, hi, _, _) = &self.nodes[first as usize];
                let (lo2, hi2, _, _) = &self.nodes[first as usize + 1];
                let axis = (0..3)
                    .max_by(|&a, &b| {
                        (hi[a] + lo[a] - hi2[a] - lo2[a]).abs().total_cmp(&(hi[b] + lo[b] - hi2[b] - lo2[b]).abs())
                    })
                    .unwrap();
                let dir = [d.x[lane], d.y[lane], d.z[lane]][axis];
                let left_first = (hi[axis] + lo[axis] <= hi2[axis] + lo2[axis]) == (dir >= 0.0);
                let (a, b) = if left_first { (first + 1, first) } else { (first, first + 1) };
                stack[sp] = a;
                stack[sp + 1] = b;
                sp += 2;
            } else {
                for k in first as usize..(first + count) as usize {
                    let (h, t, u, v) = self.hits(k, o, d, &t_best);
                    let tri = self.tris[k].4;
                    for i in 0..W {
                        let h = h[i] & m[i];
                        t_best[i] = if h { t[i] } else { t_best[i] };
                        b1[i] = if h { u[i] } else { b1[i] };
                        b2[i] = if h { v[i] } else { b2[i] };
                        prim[i] = if h { tri } else { prim[i] };
                    }
                }
            }
        }
        (prim, t_best, b1, b2)
    }

    /// Per live lane: whether its ray is blocked before its `t_max`.
    fn occluded<const W: usize>(&self, o: &V<W>, d: &V<W>, t_max: &L<W>, live: &[bool; W]) -> [bool; W] {
        let mut inv = V::<W>::ZERO;
        for i in 0..W {
            let f = |x: f32| 1.0 / if x.abs() < 1e-30 { 1e-30f32.copysign(x) } else { x };
            (inv.x[i], inv.y[i], inv.z[i]) = (f(d.x[i]), f(d.y[i]), f(d.z[i]));
        }
        let mut blocked = [false; W];
        let mut open = *live;
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let n = stack[sp] as usize;
            let m = self.enter(n, o, &inv, t_max, &open);
            if !m.iter().any(|&x| x) {
                continue;
            }
            let (_, _, first, count) = self.nodes[n];
            if count == 0 {
                stack[sp] = first;
                stack[sp + 1] = first + 1;
                sp += 2;
            } else {
                for k in first as usize..(first + count) as usize {
                    let (h, ..) = self.hits(k, o, d, t_max);
                    for i in 0..W {
                        blocked[i] |= h[i] & m[i];
                        open[i] &= !blocked[i];
                    }
                }
                if !open.iter().any(|&x| x) {
                    break;
                }
            }
        }
        blocked
    }
}

/// Quasar's `Sampler` streams (PCG32 from `rand_pcg`, seeded as `Sampler::new` seeds it), one
/// per lane, advanced together: the probe draws the same numbers per path at every width.
struct LaneRng<const W: usize> {
    state: [u64; W],
    inc: [u64; W],
}

const PCG_MULT: u64 = 6_364_136_223_846_793_005;

impl<const W: usize> LaneRng<W> {
    /// Lane `i` starts the stream of `Sampler::new(seed, index, sample)`.
    fn start(&mut self, i: usize, seed: u64, index: u64, sample: u64) {
        let state = mix64(seed ^ mix64(index.wrapping_add(0x9e37_79b9_7f4a_7c15)));
        let stream = mix64(sample ^ mix64(seed.wrapping_add(0x632b_e59b_d9b4_e019)));
        self.inc[i] = (stream << 1) | 1;
        self.state[i] = state.wrapping_add(self.inc[i]).wrapping_mul(PCG_MULT).wrapping_add(self.inc[i]);
    }

    #[inline(always)]
    fn output(s: u64) -> u32 {
        let xsh = (((s >> 18) ^ s) >> 27) as u32;
        xsh.rotate_right((s >> 59) as u32)
    }

    /// The next number of lane `i` alone.
    #[inline(always)]
    fn next_one(&mut self, i: usize) -> u32 {
        let s = self.state[i];
        self.state[i] = s.wrapping_mul(PCG_MULT).wrapping_add(self.inc[i]);
        Self::output(s)
    }

    /// The next number of every lane in `on` (the others keep their state).
    #[inline(always)]
    fn next(&mut self, on: &[bool; W]) -> [u32; W] {
        let mut out = [0u32; W];
        for i in 0..W {
            let s = self.state[i];
            let n = s.wrapping_mul(PCG_MULT).wrapping_add(self.inc[i]);
            self.state[i] = if on[i] { n } else { s };
            out[i] = Self::output(s);
        }
        out
    }

    /// `Sampler::get_1d` in every lane of `on`.
    #[inline(always)]
    fn uniform(&mut self, on: &[bool; W]) -> L<W> {
        self.next(on).map(|u| (u >> 8) as f32 * (1.0 / 16_777_216.0))
    }
}

/// `Sampler::get_1d` from a raw number.
#[inline(always)]
fn unit(u: u32) -> f32 {
    (u >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The scene's triangles in structure-of-arrays form, for lane gathers by triangle index.
struct TriTable {
    v0: [Vec<f32>; 3],
    e1: [Vec<f32>; 3],
    e2: [Vec<f32>; 3],
    n: [Vec<f32>; 3],
    material: Vec<u32>,
    light: Vec<u32>,
}

impl TriTable {
    fn new(scene: &Scene) -> Self {
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

/// The value of the flat 1 nm tables `t` at row `row` and wavelength `lambda`, in every lane.
#[inline(always)]
fn lookup_lanes<const W: usize>(t: &[f32], row: &[u32; W], lambda: &L<W>) -> L<W> {
    let mut out = [0.0; W];
    for i in 0..W {
        let x = (lambda[i] - LAMBDA_MIN).clamp(0.0, (GRID - 1) as f32);
        let c = (x as usize).min(GRID - 2);
        let f = x - c as f32;
        let base = row[i] as usize * GRID + c;
        let (a, b) = (t[base], t[base + 1]);
        out[i] = a + f * (b - a);
    }
    out
}

/// What a probe variant does in lanes beyond the path arithmetic.
#[derive(Clone, Copy)]
struct Variant {
    /// Random numbers, hit points, material and light data gathered in lane loops (else per
    /// lane, through `Sampler` and the scene's own types).
    gather: bool,
    /// Closest hits by the packet traversal (else one ray at a time through quasar's BVH).
    packet: bool,
    /// Shadow rays by the packet traversal.
    shadow_packet: bool,
}

/// Sum of luminance over the image, from the probe at width W; `stages`, when given, receives
/// the seconds spent in each part of the loop (the clock read costs time of its own).
fn render_lanes<const W: usize>(
    scene: &Scene,
    probe: &Probe,
    camera: &Camera,
    spp: u32,
    seed: u64,
    v: Variant,
    mut stages: Option<&mut [f64; N_STAGES]>,
) -> f64 {
    let (tab, bvh, tris) = (&probe.tables, &probe.bvh, &probe.tris);
    let (w, h) = (camera.width() as u64, camera.height() as u64);
    let jobs = w * h * spp as u64;
    let mut next = 0u64;
    let mut sum_y = 0.0f64;
    let mut rng = LaneRng::<W> { state: [0; W], inc: [1; W] };
    let mut samplers: Vec<Sampler> = (0..W).map(|_| Sampler::new(0, 0, 0)).collect();
    let mut wls: Vec<SampledWavelengths> = (0..W).map(|_| SampledWavelengths::sample_visible(0.5)).collect();
    let mut busy = [false; W];
    let mut ending = [false; W];
    let mut lambda = [[500.0f32; W]; NW];
    let (mut o, mut d) = (V::<W>::ZERO, V::<W>::ZERO);
    let mut beta = [[0.0f32; W]; NW];
    let mut rad = [[0.0f32; W]; NW];
    let mut prev_p = V::<W>::ZERO;
    let mut prev_pdf = [0.0f32; W];
    let mut depth = [0u32; W];
    let mut pending = [false; W];
    let (mut shadow_o, mut shadow_d) = (V::<W>::ZERO, V::<W>::ZERO);
    let mut shadow_t = [0.0f32; W];
    let mut pc = [[0.0f32; W]; NW];
    // per-round data
    let mut hit = [false; W];
    let mut prim = [0u32; W];
    let (mut b1, mut b2) = ([0.0f32; W], [0.0f32; W]);
    let (mut p, mut pe, mut ng) = (V::<W>::ZERO, V::<W>::ZERO, V::<W>::ZERO);
    let mut mat = [0u32; W];
    let mut light = [NONE; W];
    let mut le = [[0.0f32; W]; NW];
    let mut le_pdf = [0.0f32; W];
    let mut r = [[0.0f32; W]; NW];
    let mut side = [0.0f32; W];
    let mut u_light = [0u64; W];
    let mut li = [0u32; W];
    let mut lsel = [0.0f32; W];
    let mut lle = [[0.0f32; W]; NW];
    let mut u_l = [[0.0f32; W]; 2];
    let mut u_b = [[0.0f32; W]; 2];
    let mut u_rr = [1.0f32; W];
    let mut wi = V::<W>::ZERO;
    let mut nee_ok = [false; W];
    let mut clock = stages.as_ref().map(|_| Instant::now());
    let mut lap = |k: usize, clock: &mut Option<Instant>| {
        if let (Some(s), Some(c)) = (stages.as_deref_mut(), clock.as_mut()) {
            let n = Instant::now();
            s[k] += (n - *c).as_secs_f64();
            *c = n;
        }
    };
    loop {
        // 1. pending shadow rays, then paths that ended: film; free lanes: the next samples
        let blocked = if v.shadow_packet {
            bvh.occluded(&shadow_o, &shadow_d, &shadow_t, &pending)
        } else {
            let mut b = [false; W];
            for i in 0..W {
                if pending[i] {
                    let mut ray = Ray::new(shadow_o.get(i), shadow_d.get(i));
                    ray.t_max = shadow_t[i];
                    b[i] = scene.occluded(&ray);
                }
            }
            b
        };
        lap(0, &mut clock);
        for i in 0..W {
            if pending[i] && !blocked[i] {
                for k in 0..NW {
                    rad[k][i] += pc[k][i];
                }
            }
            pending[i] = false;
            if ending[i] {
                ending[i] = false;
                busy[i] = false;
                let l = SampledSpectrum(std::array::from_fn(|k| rad[k][i]));
                let y = wls[i].xyz_weights().apply_vec(l).y;
                if y.is_finite() {
                    sum_y += y as f64;
                }
            }
            if !busy[i] && next < jobs {
                let (pixel, s) = (next / spp as u64, next % spp as u64);
                next += 1;
                let (u_wl, jitter) = if v.gather {
                    rng.start(i, seed, pixel, s);
                    let u = unit(rng.next_one(i));
                    (u, Vec2::new(unit(rng.next_one(i)), unit(rng.next_one(i))))
                } else {
                    samplers[i] = Sampler::new(seed, pixel, s);
                    (samplers[i].get_1d(), samplers[i].get_2d())
                };
                let wl = SampledWavelengths::sample_visible(u_wl);
                let ray = camera.ray(Vec2::new((pixel % w) as f32, (pixel / w) as f32) + jitter);
                busy[i] = true;
                for k in 0..NW {
                    lambda[k][i] = wl.lambda(k);
                    beta[k][i] = 1.0;
                    rad[k][i] = 0.0;
                }
                wls[i] = wl;
                o.set(i, ray.origin);
                d.set(i, ray.dir);
                prev_p.set(i, ray.origin);
                prev_pdf[i] = f32::INFINITY;
                depth[i] = 0;
            }
        }
        if !busy.iter().any(|&b| b) {
            break;
        }
        lap(1, &mut clock);
        // 2. closest hits
        if v.packet {
            let t;
            (prim, t, b1, b2) = bvh.nearest(&o, &d, &busy);
            let _ = t;
        } else {
            for i in 0..W {
                prim[i] = NONE;
                if busy[i]
                    && let Some(hh) = scene.accel.intersect(&Ray::new(o.get(i), d.get(i)))
                {
                    (prim[i], b1[i], b2[i]) = (hh.prim, hh.b1, hh.b2);
                }
            }
        }
        for i in 0..W {
            hit[i] = busy[i] && prim[i] != NONE;
            ending[i] = busy[i] && prim[i] == NONE;
        }
        lap(2, &mut clock);
        // 3. what the lanes gather: hit point, material, emission, random numbers, the light
        //    sample's light
        if v.gather {
            let mut idx = [0usize; W];
            for i in 0..W {
                idx[i] = if hit[i] { prim[i] as usize } else { 0 };
            }
            for i in 0..W {
                let j = idx[i];
                let v0 = [tris.v0[0][j], tris.v0[1][j], tris.v0[2][j]];
                let a = [tris.e1[0][j] * b1[i], tris.e1[1][j] * b1[i], tris.e1[2][j] * b1[i]];
                let b = [tris.e2[0][j] * b2[i], tris.e2[1][j] * b2[i], tris.e2[2][j] * b2[i]];
                // TriangleGeom::point_with_error
                let g7 = quasar::core::geometry::ray::gamma(7);
                p.x[i] = v0[0] + a[0] + b[0];
                p.y[i] = v0[1] + a[1] + b[1];
                p.z[i] = v0[2] + a[2] + b[2];
                pe.x[i] = g7 * (v0[0].abs() + a[0].abs() + b[0].abs());
                pe.y[i] = g7 * (v0[1].abs() + a[1].abs() + b[1].abs());
                pe.z[i] = g7 * (v0[2].abs() + a[2].abs() + b[2].abs());
                (ng.x[i], ng.y[i], ng.z[i]) = (tris.n[0][j], tris.n[1][j], tris.n[2][j]);
                mat[i] = tris.material[j];
                light[i] = if hit[i] { tris.light[j] } else { NONE };
            }
            for k in 0..NW {
                r[k] = lookup_lanes(&tab.refl_flat, &mat, &lambda[k]);
            }
            let hi = rng.next(&hit);
            let lo = rng.next(&hit);
            for i in 0..W {
                u_light[i] = ((hi[i] as u64) << 32) | lo[i] as u64;
            }
            u_l = [rng.uniform(&hit), rng.uniform(&hit)];
            let _uc = rng.uniform(&hit);
            u_b = [rng.uniform(&hit), rng.uniform(&hit)];
            let mut late = [false; W];
            for i in 0..W {
                late[i] = hit[i] && depth[i] + 1 >= 3;
            }
            let u = rng.uniform(&late);
            for i in 0..W {
                u_rr[i] = if late[i] { u[i] } else { 1.0 };
            }
        } else {
            for i in 0..W {
                if !hit[i] {
                    continue;
                }
                let g = &scene.accel.geom[prim[i] as usize];
                let (pp, pp_err) = g.point_with_error(b1[i], b2[i]);
                p.set(i, pp);
                pe.set(i, pp_err);
                ng.set(i, Vec3::from(g.n));
                mat[i] = scene.accel.info[prim[i] as usize].material;
                light[i] = scene.accel.info[prim[i] as usize].light;
                for k in 0..NW {
                    r[k][i] = lookup(&tab.refl[mat[i] as usize], lambda[k][i]);
                }
                let sampler = &mut samplers[i];
                u_light[i] = sampler.get_u64();
                let u = sampler.get_2d();
                (u_l[0][i], u_l[1][i]) = (u.x, u.y);
                let _uc = sampler.get_1d();
                let u = sampler.get_2d();
                (u_b[0][i], u_b[1][i]) = (u.x, u.y);
                u_rr[i] = if depth[i] + 1 >= 3 { sampler.get_1d() } else { 1.0 };
            }
        }
        // the light choice (Walker's alias table), per lane
        for i in 0..W {
            let (l, sel) = if hit[i] { scene.light_sampler.sample(u_light[i]).unwrap_or((0, 0.0)) } else { (0, 0.0) };
            (li[i], lsel[i]) = (l as u32, sel);
        }
        // the emission at the hit and of the chosen light, and the hit's side
        let mut emit_row = [0u32; W];
        let mut lemit_row = [0u32; W];
        for i in 0..W {
            let wo_n = -(d.x[i] * ng.x[i] + d.y[i] * ng.y[i] + d.z[i] * ng.z[i]);
            let two = tab.two_sided[mat[i] as usize];
            side[i] = if wo_n > 0.0 {
                1.0
            } else if wo_n < 0.0 && two {
                -1.0
            } else {
                0.0
            };
            let hl = if light[i] != NONE { light[i] as usize } else { 0 };
            let e = tab.light_emission[hl];
            let lit = light[i] != NONE && (tab.emit_two_sided[e as usize] || wo_n > 0.0);
            le_pdf[i] = if lit { tab.light_sel[hl] / tab.light_area[hl] } else { 0.0 };
            emit_row[i] = e;
            lemit_row[i] = tab.light_emission[li[i] as usize];
        }
        for k in 0..NW {
            le[k] = lookup_lanes(&tab.emit_flat, &emit_row, &lambda[k]);
            lle[k] = lookup_lanes(&tab.emit_flat, &lemit_row, &lambda[k]);
        }
        lap(3, &mut clock);
        // 4. emission found by the ray, weighted against the light sample that could have
        //    found it (pdf_li_area = dist^2 / (|cos| area), times the selection probability)
        for i in 0..W {
            let dx = p.x[i] - prev_p.x[i];
            let dy = p.y[i] - prev_p.y[i];
            let dz = p.z[i] - prev_p.z[i];
            let dist2 = dx * dx + dy * dy + dz * dz;
            let cos = (ng.x[i] * d.x[i] + ng.y[i] * d.y[i] + ng.z[i] * d.z[i]).abs();
            let p_light = le_pdf[i] * dist2 / cos;
            let mis = power_heuristic(prev_pdf[i], p_light);
            let m = if hit[i] && le_pdf[i] > 0.0 { mis } else { 0.0 };
            for k in 0..NW {
                rad[k][i] += beta[k][i] * le[k][i] * m;
            }
        }
        // 5. the light sample: a uniform point on the chosen triangle, its density in solid
        //    angle, the BSDF and its density, the power heuristic, the shadow ray
        for i in 0..W {
            let l = li[i] as usize;
            let (lv, e1, e2, ln) = (tab.light_v0[l], tab.light_e1[l], tab.light_e2[l], tab.light_n[l]);
            let su = u_l[0][i].sqrt();
            let (c1, c2) = (1.0 - su, u_l[1][i] * su);
            let dx = lv.x + c1 * e1.x + c2 * e2.x - p.x[i];
            let dy = lv.y + c1 * e1.y + c2 * e2.y - p.y[i];
            let dz = lv.z + c1 * e1.z + c2 * e2.z - p.z[i];
            let dist2 = dx * dx + dy * dy + dz * dz;
            let dist = dist2.sqrt();
            let inv = 1.0 / dist;
            let (wx, wy, wz) = (dx * inv, dy * inv, dz * inv);
            let cos_l_signed = -(ln.x * wx + ln.y * wy + ln.z * wz);
            let cos_l = cos_l_signed.abs();
            let pdf = dist2 / (cos_l * tab.light_area[l]);
            let p_light = lsel[i] * pdf;
            let cos_i = ng.x[i] * wx + ng.y[i] * wy + ng.z[i] * wz;
            let p_bsdf = cos_i.abs() * FRAC_1_PI;
            let ok = hit[i]
                && side[i] * cos_i > 0.0
                && (tab.emit_two_sided[tab.light_emission[l] as usize] || cos_l_signed > 0.0)
                && cos_l > 0.0
                && dist2 > 0.0
                && pdf.is_finite()
                && lsel[i] > 0.0;
            let f = if ok { p_bsdf * power_heuristic(p_light, p_bsdf) / p_light } else { 0.0 };
            nee_ok[i] = ok;
            for k in 0..NW {
                pc[k][i] = beta[k][i] * r[k][i] * lle[k][i] * f;
            }
            (shadow_d.x[i], shadow_d.y[i], shadow_d.z[i]) = (wx, wy, wz);
            shadow_t[i] = (dist * (1.0 - 1e-4)).max(0.0);
        }
        offset(&p, &pe, &ng, &shadow_d, &mut shadow_o);
        // 6. the BSDF sample: cosine-weighted (concentric disk), in the frame of the normal
        for i in 0..W {
            let mut local = cosine_hemisphere(Vec2::new(u_b[0][i], u_b[1][i]));
            local.z *= side[i];
            wi.set(i, Frame::from_z(ng.get(i)).from_local(local));
            let lz = local.z;
            let pdf = lz.abs() * FRAC_1_PI;
            let alive = hit[i] && side[i] != 0.0 && pdf > 0.0;
            let mut rr = 0.0f32;
            for k in 0..NW {
                beta[k][i] *= r[k][i];
                rr = rr.max(beta[k][i]);
            }
            // Russian roulette from the third scattering event
            let q = (1.0 - rr).max(0.05);
            let roulette = depth[i] + 1 >= 3 && rr < 1.0;
            let survive = !roulette || u_rr[i] >= q;
            let scale = if roulette { 1.0 / (1.0 - q) } else { 1.0 };
            for k in 0..NW {
                beta[k][i] *= scale;
            }
            prev_pdf[i] = pdf;
            ending[i] = ending[i] || (busy[i] && !(alive && survive));
            pending[i] = nee_ok[i];
            depth[i] += 1;
        }
        prev_p = p;
        d = wi;
        offset(&p, &pe, &ng, &d, &mut o);
        lap(4, &mut clock);
    }
    sum_y
}

/// What the probe gathers once per scene.
struct Probe {
    tables: Tables,
    bvh: PacketBvh,
    tris: TriTable,
}

fn main() {
    let mut args = std::env::args().skip(1).filter(|a| a != "--bench");
    let mut scene_path = "scenes/cornell-box/cornell-box.toml".to_string();
    let (mut spp, mut rounds, mut size, mut show_stages) = (64u32, 3usize, 128u32, false);
    let mut only: Option<String> = None;
    while let Some(a) = args.next() {
        let mut num = |flag: &str| args.next().and_then(|v| v.parse().ok()).unwrap_or_else(|| panic!("{flag} N"));
        match a.as_str() {
            "--spp" => spp = num("--spp"),
            "--rounds" => rounds = num("--rounds") as usize,
            "--size" => size = num("--size"),
            "--stages" => show_stages = true,
            "--only" => only = args.next(),
            _ => scene_path = a,
        }
    }
    let desc = load_scene(Path::new(&scene_path)).expect("scene loads");
    let scene = Scene::compile(&desc).expect("scene compiles");
    let camera = Camera::new(&desc.camera, size, size).expect("camera");
    let tables = match Tables::new(&scene) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("{scene_path}: the probe cannot render this scene: {e}");
            std::process::exit(2);
        }
    };
    let probe = Probe { tables, bvh: PacketBvh::new(&scene), tris: TriTable::new(&scene) };
    let samples = size as f64 * size as f64 * spp as f64;
    let none = Variant { gather: false, packet: false, shadow_packet: false };
    let gather = Variant { gather: true, ..none };
    let packet = Variant { packet: true, ..gather };
    let all = Variant { shadow_packet: true, ..packet };
    type Run<'a> = (&'a str, Box<dyn Fn(Option<&mut [f64; N_STAGES]>) -> f64 + 'a>);
    let seed = 1;
    let (scene, probe, camera) = (&scene, &probe, &camera);
    let mut probes: Vec<Run> = vec![
        ("W=1", Box::new(move |s| render_lanes::<1>(scene, probe, camera, spp, seed, none, s))),
        ("W=16 lanes", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, none, s))),
        ("W=1 +gather", Box::new(move |s| render_lanes::<1>(scene, probe, camera, spp, seed, gather, s))),
        ("W=16 +gather", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, gather, s))),
        ("W=8 +packets", Box::new(move |s| render_lanes::<8>(scene, probe, camera, spp, seed, packet, s))),
        ("W=16 +packets", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, packet, s))),
        ("W=16 +shadow packets", Box::new(move |s| render_lanes::<16>(scene, probe, camera, spp, seed, all, s))),
    ];
    probes.retain(|(name, _)| only.as_deref().is_none_or(|o| *name == o));
    // (name, best seconds, image mean)
    let mut best: Vec<(String, f64, f64)> = Vec::new();
    let mut record = |name: &str, s: f64, mean: f64| match best.iter_mut().find(|b| b.0 == name) {
        Some(b) => b.1 = b.1.min(s),
        None => best.push((name.to_string(), s, mean)),
    };
    for _ in 0..rounds {
        let t = Instant::now();
        let mut method = PerPixel::new(scene, camera, PtSettings::default(), seed, (0, 1));
        let opts = DriverOptions { units: spp, threads: Some(1), ..Default::default() };
        let r = driver::run(&mut method, scene, camera, &opts).expect("render runs");
        let s = t.elapsed().as_secs_f64();
        let n: u64 = r.film.pixels.iter().map(|p| p.samples).sum();
        let sum: f64 = r.film.pixels.iter().map(|p| p.sum_y(quasar::film::Quantity::Beauty)).sum();
        record("quasar pt", s, sum / n as f64);
        for (name, f) in &probes {
            let t = Instant::now();
            let mean = f(None) / samples;
            record(name, t.elapsed().as_secs_f64(), mean);
        }
    }
    println!("{scene_path}, {size}x{size}, {spp} spp, 1 thread, best of {rounds}:");
    let base = best[0].1;
    for (name, s, mean) in &best {
        println!(
            "  {name:<21} {s:>6.3} s  {:>6.3} M samples/s  {:>5.2}x quasar pt   mean Y {mean:.6}",
            samples / s / 1e6,
            base / s
        );
    }
    if show_stages {
        println!("seconds per part of the loop (one more run each, with the clock read in every round):");
        println!("  {:<21} {}", "", STAGE_NAMES.map(|n| format!("{n:>16}")).join(""));
        for (name, f) in &probes {
            let mut st = [0.0; N_STAGES];
            f(Some(&mut st));
            println!("  {name:<21} {}", st.map(|s| format!("{s:>16.3}")).join(""));
        }
    }
}
