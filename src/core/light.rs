//! Lights (docs/architecture.md §4): the closed set of emitters, their sampling, and power-proportional
//! light selection.

use std::f32::consts::PI;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use quasar_materials::Frame;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

use crate::core::alias_table::AliasTable;
use crate::core::emission::{Emission, bary_uv};
use crate::core::emission_grid::EmissionGrid;
use crate::core::env_map::EnvMap;
use crate::core::geometry::TriangleGeom;
use crate::core::luminaire::Luminaire;
use crate::core::sampling;

/// An emitter (closed set, enum dispatch).
#[derive(Clone, Debug)]
pub enum Light {
    /// One emissive triangle.
    Area {
        /// The triangle (a copy: the BVH may duplicate or reorder its own).
        tri: TriangleGeom,
        /// Index into the scene's emission table.
        emission: u32,
        /// The triangle's area ([`TriangleGeom::area`]), computed once (its unit normal is the
        /// triangle's own, `tri.n`).
        area: f32,
        /// Texture coordinates of the vertices (a textured emission's; zero otherwise).
        uv: [Vec2; 3],
        /// The triangle's emitted power relative to its emission's nominal colour (1 without a
        /// texture; with one, its texels' mean over the triangle over the texture's mean).
        weight: f32,
        /// Where on the triangle light samples and photons start, following its emissive
        /// texture (None: uniformly).
        grid: Option<Arc<EmissionGrid>>,
    },
    /// Isotropic point light, intensity scale * spectrum (W/(sr nm)).
    Point {
        /// Position.
        position: Vec3,
        /// Intensity spectrum.
        spectrum: Spectrum,
        /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
        /// spectra make it a luminance-equivalent value).
        scale: f32,
    },
    /// Spot light with smoothstep falloff between two cone angles.
    Spot {
        /// Position.
        position: Vec3,
        /// Frame whose z is the spot axis.
        frame: Frame,
        /// cos of the outer half-angle.
        cos_total: f32,
        /// cos of the inner (full-intensity) half-angle.
        cos_falloff_start: f32,
        /// On-axis intensity spectrum.
        spectrum: Spectrum,
        /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
        /// spectra make it a luminance-equivalent value).
        scale: f32,
    },
    /// Distant light arriving from `-direction` with irradiance scale * spectrum.
    Directional {
        /// Direction of travel (unit).
        direction: Vec3,
        /// Irradiance spectrum.
        spectrum: Spectrum,
        /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
        /// spectra make it a luminance-equivalent value).
        scale: f32,
        /// Radius of the scene's bounding sphere (for power).
        scene_radius: f32,
    },
    /// A point luminaire with a measured intensity distribution (IES / EULUMDAT).
    Luminaire(std::sync::Arc<Luminaire>),
    /// Radiance from every direction: constant (`spectrum`), or a lat-long `map`.
    Environment {
        /// Radiance spectrum (constant environments).
        spectrum: Spectrum,
        /// Factor on `spectrum`: the emitted quantity is scale x spectrum (luminance-normalised
        /// spectra make it a luminance-equivalent value).
        scale: f32,
        /// Radius of the scene's bounding sphere (for power).
        scene_radius: f32,
        /// A lat-long radiance map, importance-sampled.
        map: Option<std::sync::Arc<EnvMap>>,
    },
}

/// Incident light sampled at a point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Incident radiance (or intensity / r^2 and irradiance for delta lights).
    pub li: SampledSpectrum,
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Solid-angle density of `wi` (1 for delta lights).
    pub pdf: f32,
    /// Distance to the light sample (infinite for distant lights).
    pub dist: f32,
    /// True for point/spot/luminaire/directional lights (no MIS possible: a luminaire's opening
    /// is sampled by area but cannot be hit by rays).
    pub delta: bool,
}

/// Smoothstep 0 -> 1 between `a` and `b`.
fn smoothstep(x: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Light {
    /// The area light of triangle `tri` emitting `emission` (an index into the emission table),
    /// untextured.
    pub fn area_triangle(tri: TriangleGeom, emission: u32) -> Self {
        Self::Area { tri, emission, area: tri.area(), uv: [Vec2::ZERO; 3], weight: 1.0, grid: None }
    }

    /// The area light of triangle `tri` with a textured emission: vertex texture coordinates
    /// `uv`, relative power `weight` and the density its points are drawn from (see
    /// [`Light::Area`]).
    pub fn area_triangle_textured(
        tri: TriangleGeom,
        emission: u32,
        uv: [Vec2; 3],
        weight: f32,
        grid: Option<EmissionGrid>,
    ) -> Self {
        Self::Area { tri, emission, area: tri.area(), uv, weight, grid: grid.map(Arc::new) }
    }

    /// True for lights at infinity (seen by rays that escape the scene).
    pub fn is_infinite(&self) -> bool {
        matches!(self, Self::Directional { .. } | Self::Environment { .. })
    }

    /// Spot attenuation for a direction `w` leaving the light (local to the spot frame).
    fn spot_falloff(frame: &Frame, cos_total: f32, cos_start: f32, w: Vec3) -> f32 {
        let c = frame.to_local(w).z;
        smoothstep(c, cos_total, cos_start)
    }

    /// Emitted power (spectrally averaged, W/nm) used only for selection probabilities, so every
    /// light that emits anything has a non-zero chance of being chosen.
    pub fn power(&self, emissions: &[Emission]) -> f64 {
        let p = match self {
            Self::Area { emission, area, weight, .. } => {
                let e = &emissions[*emission as usize];
                let sides = if e.two_sided { 2.0 } else { 1.0 };
                PI * sides * area * weight * e.scale * e.spectrum.mean_value()
            }
            Self::Point { spectrum, scale, .. } => 4.0 * PI * scale * spectrum.mean_value(),
            Self::Spot { spectrum, scale, cos_total, cos_falloff_start, .. } => {
                2.0 * PI * scale * spectrum.mean_value() * (1.0 - 0.5 * (cos_falloff_start + cos_total))
            }
            Self::Directional { spectrum, scale, scene_radius, .. } => {
                PI * scene_radius * scene_radius * scale * spectrum.mean_value()
            }
            Self::Luminaire(l) => l.power(),
            Self::Environment { spectrum, scale, scene_radius, map } => {
                let mean = map.as_ref().map_or_else(|| spectrum.mean_value(), |m| m.mean_luminance() as f32);
                4.0 * PI * PI * scene_radius * scene_radius * scale * mean
            }
        };
        if p.is_finite() && p > 0.0 { p as f64 } else { 0.0 }
    }

    /// Samples incident light at point `p` (Li, direction, solid-angle pdf).
    #[inline(always)]
    pub fn sample_li(&self, p: Vec3, u: Vec2, wl: &SampledWavelengths, emissions: &[Emission]) -> Option<LightSample> {
        match self {
            Self::Area { tri, emission, area, uv, grid, .. } => {
                let (area, ng) = (*area, Vec3::from(tri.n));
                if area.is_nan() || area <= 0.0 {
                    return None;
                }
                let (b1, b2, density) = match grid {
                    None => {
                        let (b1, b2) = sampling::uniform_triangle(u);
                        (b1, b2, 1.0)
                    }
                    Some(g) => g.sample(u),
                };
                let pl = tri.point(b1, b2);
                let d = pl - p;
                let dist2 = d.length_squared();
                if dist2.is_nan() || dist2 <= 0.0 || !dist2.is_finite() {
                    return None;
                }
                let dist = dist2.sqrt();
                let wi = d / dist;
                let cos_l = ng.dot(-wi).abs();
                if cos_l <= 0.0 {
                    return None;
                }
                let li = emissions[*emission as usize].radiance(ng, -wi, bary_uv(uv, b1, b2), wl);
                if li.is_black() {
                    return None;
                }
                let pdf = dist2 * density / (cos_l * area);
                if !pdf.is_finite() {
                    return None;
                }
                Some(LightSample { li, wi, pdf, dist, delta: false })
            }
            Self::Point { position, spectrum, scale } => {
                let d = *position - p;
                let dist2 = d.length_squared();
                if dist2.is_nan() || dist2 <= 0.0 {
                    return None;
                }
                let dist = dist2.sqrt();
                let li = spectrum.sample(wl) * (*scale / dist2);
                Some(LightSample { li, wi: d / dist, pdf: 1.0, dist, delta: true })
            }
            Self::Spot { position, frame, cos_total, cos_falloff_start, spectrum, scale } => {
                let d = *position - p;
                let dist2 = d.length_squared();
                if dist2.is_nan() || dist2 <= 0.0 {
                    return None;
                }
                let dist = dist2.sqrt();
                let wi = d / dist;
                let fall = Self::spot_falloff(frame, *cos_total, *cos_falloff_start, -wi);
                if fall <= 0.0 {
                    return None;
                }
                let li = spectrum.sample(wl) * (*scale * fall / dist2);
                Some(LightSample { li, wi, pdf: 1.0, dist, delta: true })
            }
            Self::Luminaire(l) => {
                let d = l.emission_point(u) - p;
                let dist2 = d.length_squared();
                if dist2.is_nan() || dist2 <= 0.0 {
                    return None;
                }
                let dist = dist2.sqrt();
                let wi = d / dist;
                let li = l.intensity(-wi, wl) * (1.0 / dist2);
                if li.is_black() {
                    return None;
                }
                Some(LightSample { li, wi, pdf: 1.0, dist, delta: true })
            }
            Self::Directional { direction, spectrum, scale, .. } => Some(LightSample {
                li: spectrum.sample(wl) * *scale,
                wi: -*direction,
                pdf: 1.0,
                dist: f32::INFINITY,
                delta: true,
            }),
            Self::Environment { spectrum, scale, map, .. } => {
                let (wi, li, pdf) = match map {
                    Some(m) => {
                        let (wi, pdf, li) = m.sample(u, wl)?;
                        (wi, li, pdf)
                    }
                    None => (sampling::uniform_sphere(u), spectrum.sample(wl), sampling::UNIFORM_SPHERE_PDF),
                };
                Some(LightSample { li: li * *scale, wi, pdf, dist: f32::INFINITY, delta: false })
            }
        }
    }

    /// Solid-angle density with which [`sample_li`](Self::sample_li) at `p` would return the
    /// direction towards the surface point `pl` with unit normal `ng` on this area light.
    pub fn pdf_li_area(&self, p: Vec3, pl: Vec3, ng: Vec3) -> f32 {
        let Self::Area { area, tri, grid, .. } = self else { return 0.0 };
        let d = pl - p;
        let dist2 = d.length_squared();
        let cos_l = ng.dot(d).abs() / dist2.sqrt();
        let density = grid.as_ref().map_or(1.0, |g| g.density_at(tri, pl));
        let pdf = dist2 * density / (cos_l * *area);
        if pdf.is_finite() { pdf } else { 0.0 }
    }

    /// Radiance reaching a ray that escapes the scene in direction `w` (environment only;
    /// directional lights cannot be hit).
    #[inline]
    pub fn le_escaped(&self, w: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Self::Environment { spectrum, scale, map, .. } => {
                map.as_ref().map_or_else(|| spectrum.sample(wl), |m| m.radiance(w, wl)) * *scale
            }
            _ => SampledSpectrum::zero(),
        }
    }

    /// Solid-angle density with which [`sample_li`](Self::sample_li) returns escape direction
    /// `w` (environment only).
    pub fn pdf_li_escaped(&self, w: Vec3) -> f32 {
        match self {
            Self::Environment { map: Some(m), .. } => m.pdf(w),
            Self::Environment { .. } => sampling::UNIFORM_SPHERE_PDF,
            _ => 0.0,
        }
    }
}

/// A photon leaving a light: ray origin and direction and its spectral flux
/// Le |cos| / (pdf_position pdf_direction) (light selection not included).
#[derive(Clone, Copy, Debug)]
pub struct EmittedPhoton {
    /// Start of the photon's first segment (already offset off an emitting surface).
    pub origin: Vec3,
    /// Unit direction of travel.
    pub dir: Vec3,
    /// Flux weight at the sampled wavelengths.
    pub flux: SampledSpectrum,
}

impl Light {
    /// Samples a photon leaving this light (pbrt-v4 `SampleLe`): area lights pick a uniform
    /// point and a cosine-weighted direction (flux = pi A Le per side), point lights a uniform
    /// direction (4 pi I), spot lights a uniform direction in their cone (I falloff / pdf),
    /// luminaires a direction by their candela table (I / pdf),
    /// distant lights a uniform point on a disk of the scene's bounding sphere (centre `center`)
    /// perpendicular to the direction of travel (E pi R^2 and 4 pi Le pi R^2).
    pub fn sample_emission(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        wl: &SampledWavelengths,
        emissions: &[Emission],
        center: Vec3,
    ) -> Option<EmittedPhoton> {
        let photon = match self {
            Self::Area { tri, emission, area, uv, grid, .. } => {
                let e = &emissions[*emission as usize];
                let area = *area;
                if area.is_nan() || area <= 0.0 {
                    return None;
                }
                let (b1, b2, density) = match grid {
                    None => {
                        let (b1, b2) = sampling::uniform_triangle(u_pos);
                        (b1, b2, 1.0)
                    }
                    Some(g) => g.sample(u_pos),
                };
                let (p, p_err) = tri.point_with_error(b1, b2);
                let mut ng = Vec3::from(tri.n);
                // two-sided: the side is chosen by the first direction number, reused in [0, 1)
                let mut u = u_dir;
                let mut sides = 1.0;
                if e.two_sided {
                    sides = 2.0;
                    if u.x < 0.5 {
                        u.x *= 2.0;
                    } else {
                        u.x = 2.0 * u.x - 1.0;
                        ng = -ng;
                    }
                }
                let local = sampling::cosine_hemisphere(u);
                if local.z <= 0.0 {
                    return None;
                }
                let dir = Frame::from_z(ng).from_local(local);
                let le = e.radiance(ng, dir, bary_uv(uv, b1, b2), wl);
                EmittedPhoton {
                    origin: crate::core::geometry::offset_origin(p, p_err, ng, dir),
                    dir,
                    flux: le * (PI * area * sides / density),
                }
            }
            Self::Point { position, spectrum, scale } => EmittedPhoton {
                origin: *position,
                dir: sampling::uniform_sphere(u_dir),
                flux: spectrum.sample(wl) * (*scale * 4.0 * PI),
            },
            Self::Spot { position, frame, cos_total, cos_falloff_start, spectrum, scale } => {
                let local = sampling::uniform_cone(u_dir, *cos_total);
                let dir = frame.from_local(local);
                let pdf = 1.0 / (2.0 * PI * (1.0 - *cos_total));
                let fall = Self::spot_falloff(frame, *cos_total, *cos_falloff_start, dir);
                EmittedPhoton { origin: *position, dir, flux: spectrum.sample(wl) * (*scale * fall / pdf) }
            }
            Self::Luminaire(l) => {
                let (dir, pdf) = l.sample_direction(u_dir)?;
                EmittedPhoton { origin: l.emission_point(u_pos), dir, flux: l.intensity(dir, wl) * (1.0 / pdf) }
            }
            Self::Directional { direction, spectrum, scale, scene_radius } => {
                let origin = disk_origin(center, *scene_radius, *direction, u_pos);
                let flux = spectrum.sample(wl) * (*scale * PI * scene_radius * scene_radius);
                EmittedPhoton { origin, dir: *direction, flux }
            }
            Self::Environment { spectrum, scale, scene_radius, map } => {
                // the photon travels against the direction the light arrives from
                let (from, le, pdf) = match map {
                    Some(m) => {
                        let (from, pdf, le) = m.sample(u_dir, wl)?;
                        (from, le, pdf)
                    }
                    None => (sampling::uniform_sphere(u_dir), spectrum.sample(wl), sampling::UNIFORM_SPHERE_PDF),
                };
                let dir = -from;
                let origin = disk_origin(center, *scene_radius, dir, u_pos);
                let area = PI * scene_radius * scene_radius;
                EmittedPhoton { origin, dir, flux: le * (*scale * area / pdf) }
            }
        };
        (photon.flux.is_finite() && !photon.flux.is_black() && photon.dir.is_finite()).then_some(photon)
    }
}

/// A uniform point on the disk of radius `r` through `center` perpendicular to `dir`, moved back
/// by `r` against `dir`, so that rays along `dir` from it cover the bounding sphere.
fn disk_origin(center: Vec3, r: f32, dir: Vec3, u: Vec2) -> Vec3 {
    let d = sampling::concentric_disk(u);
    let f = Frame::from_z(dir);
    center + r * (f.from_local(Vec3::new(d.x, d.y, 0.0)) - dir)
}

/// Chooses lights with probability proportional to [`Light::power`], in constant time per
/// choice (an [`AliasTable`], as pbrt-v4's power light sampler), however many emissive
/// triangles a scene has.
#[derive(Clone, Debug, Default)]
pub struct LightSampler {
    dist: AliasTable,
}

impl LightSampler {
    /// Builds the selection distribution.
    pub fn new(lights: &[Light], emissions: &[Emission]) -> Self {
        let w: Vec<f64> = lights.iter().map(|l| l.power(emissions)).collect();
        Self { dist: AliasTable::new(&w) }
    }

    /// (light index, probability) for a uniform 64-bit integer `r` ([`Sampler::get_u64`](crate::core::sampling::Sampler::get_u64)),
    /// or None without lights.
    #[inline]
    pub fn sample(&self, r: u64) -> Option<(usize, f32)> {
        self.dist.sample(r)
    }

    /// Probability of choosing light `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.dist.pmf(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_materials::spectrum::SampledWavelengths;

    #[test]
    fn area_light_irradiance_matches_analytic_disk_limit() {
        // Irradiance at distance h below the centre of a unit square emitter of radiance 1,
        // facing down: E = integral L cos cos' / r^2 dA; compare MC estimate with a fine quadrature.
        let h = 0.5;
        let tris = [
            TriangleGeom::new(Vec3::new(-0.5, h, -0.5), Vec3::new(0.5, h, -0.5), Vec3::new(0.5, h, 0.5)),
            TriangleGeom::new(Vec3::new(-0.5, h, -0.5), Vec3::new(0.5, h, 0.5), Vec3::new(-0.5, h, 0.5)),
        ];
        for t in &tris {
            assert!(t.normal_unnormalised().y < 0.0);
        }
        let em = [Emission { spectrum: Spectrum::Constant(1.0), scale: 1.0, two_sided: false, texture: None }];
        let lights = [Light::area_triangle(tris[0], 0), Light::area_triangle(tris[1], 0)];
        let sampler = LightSampler::new(&lights, &em);
        let wl = SampledWavelengths::sample_uniform(0.3);
        let n = 200_000;
        let mut e = 0.0f64;
        let mut s = crate::core::sampling::Sampler::new(7, 0, 0);
        for _ in 0..n {
            let (i, pmf) = sampler.sample(s.get_u64()).unwrap();
            if let Some(ls) = lights[i].sample_li(Vec3::ZERO, s.get_2d(), &wl, &em) {
                e += (ls.li[0] * ls.wi.y.max(0.0) / (ls.pdf * pmf)) as f64;
            }
        }
        e /= n as f64;
        // quadrature
        let m = 400;
        let mut q = 0.0f64;
        for i in 0..m {
            for j in 0..m {
                let x = -0.5 + (i as f64 + 0.5) / m as f64;
                let z = -0.5 + (j as f64 + 0.5) / m as f64;
                let r2 = x * x + z * z + h as f64 * h as f64;
                q += (h as f64 / r2.sqrt()).powi(2) / r2 / (m * m) as f64;
            }
        }
        assert!((e - q).abs() / q < 0.01, "mc {e} vs quadrature {q}");
    }
}
