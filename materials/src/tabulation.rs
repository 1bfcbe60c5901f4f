//! Building tabulated BSDFs from functions: the material library's generator, the GGX
//! consistency tests and the `quasar bsdf` tools tabulate analytic models with it.

use std::f32::consts::TAU;

use glam::Vec3;

use crate::bsdf::TransportMode;
use crate::material::Material;
use crate::spectrum::SampledWavelengths;
use crate::tabulated::geometry::{Incidence, grid_direction, half_versine, lobe_axis, to_face};
use crate::tabulated::{BackFace, Face, ScatterGrid, ScatterTable, TabulatedSpec};

/// The grid of one generated scatter table.
#[derive(Clone, Debug, PartialEq)]
pub struct GridSpec {
    /// Grid kind.
    pub grid: ScatterGrid,
    /// Scatter polar angles (radians).
    pub theta: Vec<f32>,
    /// Scatter azimuths (radians).
    pub phi: Vec<f32>,
}

/// `n` polar angles from 0 to `max` (radians) spaced by a power law (exponent `p` > 1 packs
/// them near 0: fine steps inside a narrow lobe, coarse ones in its tail). Each angle is an f32
/// number of degrees converted to radians, so a table written in degrees reads back exactly.
pub fn power_spaced(n: usize, max: f32, p: f32) -> Vec<f32> {
    let max_deg = max.to_degrees();
    (0..n).map(|i| (max_deg * (i as f32 / (n - 1) as f32).powf(p)).to_radians()).collect()
}

/// `n` azimuths uniformly over [0, 2 pi) (degrees converted to radians, see [`power_spaced`]).
pub fn uniform_phi(n: usize) -> Vec<f32> {
    (0..n).map(|i| (360.0 * i as f32 / n as f32).to_radians()).collect()
}

/// What to tabulate: wavelengths, incidences and the scatter grids of the front face.
#[derive(Clone, Debug, PartialEq)]
pub struct Tabulation {
    /// Material name.
    pub name: String,
    /// Wavelengths (nm).
    pub wavelengths: Vec<f32>,
    /// Incidence polar angles (radians).
    pub theta_i: Vec<f32>,
    /// Incidence azimuths (radians); `[0]` = isotropic (sampled in the plane y = 0 only).
    pub phi_i: Vec<f32>,
    /// Relative IOR (axis of specular-relative BTDFs).
    pub ior: Option<f32>,
    /// Reflection grid, if any.
    pub brdf: Option<GridSpec>,
    /// Transmission grid, if any.
    pub btdf: Option<GridSpec>,
    /// Tabulate the back face too (light arriving from below, e.g. inside a dielectric);
    /// otherwise the back face is the same as the front.
    pub both_faces: bool,
}

impl Tabulation {
    /// An isotropic, spectrally flat (550 nm) reflector's grid: incidence 0..85 degrees in 5
    /// degree steps plus 89, a specular-relative BRDF grid of 48 polar angles over the whole
    /// sphere (packed near the mirror direction) and azimuths 0..180 in 15 degree steps.
    pub fn isotropic_brdf(name: &str) -> Self {
        Self {
            name: name.to_owned(),
            wavelengths: vec![550.0],
            theta_i: (0..=17).map(|i| (i as f32 * 5.0).to_radians()).chain([89f32.to_radians()]).collect(),
            phi_i: vec![0.0],
            ior: None,
            brdf: Some(GridSpec {
                grid: ScatterGrid::SpecularRelative,
                theta: power_spaced(48, std::f32::consts::PI, 2.0),
                phi: (0..=12).map(|i| (i as f32 * 15.0).to_radians()).collect(),
            }),
            btdf: None,
            both_faces: false,
        }
    }

    /// Tabulates `f(lambda_nm, d_in, d_out)` (light arriving from unit `d_in`, leaving along
    /// `d_out`; local frame) on the front face, and on the back face when `both_faces`.
    pub fn tabulate(&self, f: impl Fn(f32, Vec3, Vec3) -> f32) -> TabulatedSpec {
        let table = |g: &GridSpec, transmit: bool, back: bool| {
            let n = self.ior.unwrap_or(1.0);
            let eta = if back { 1.0 / n } else { n };
            let mut values = Vec::new();
            for &l in &self.wavelengths {
                for &pi in &self.phi_i {
                    for &ti in &self.theta_i {
                        let (st, ct) = ti.sin_cos();
                        let d_in = Vec3::new(st * pi.cos(), st * pi.sin(), ct);
                        let inc = Incidence::of(d_in);
                        let axis = match g.grid {
                            ScatterGrid::Absolute => None,
                            ScatterGrid::SpecularRelative => Some(lobe_axis(ti, transmit, eta)),
                        };
                        for &t in &g.theta {
                            for &p in &g.phi {
                                let v = inc.plane_to_face(grid_direction(half_versine(t), p, axis, transmit));
                                let ok = Some(v).filter(|v| (v.z < 0.0) == transmit && v.z != 0.0);
                                let (a, b) = (to_face(d_in, back), ok.map(|v| to_face(v.normalize(), back)));
                                values.push(b.map_or(0.0, |d_out| f(l, a, d_out).max(0.0)));
                            }
                        }
                    }
                }
            }
            ScatterTable { grid: g.grid, theta: g.theta.clone(), phi: g.phi.clone(), values }
        };
        let face = |back: bool| Face {
            brdf: self.brdf.as_ref().map(|g| table(g, false, back)),
            btdf: self.btdf.as_ref().map(|g| table(g, true, back)),
        };
        TabulatedSpec {
            name: self.name.clone(),
            wavelengths: self.wavelengths.clone(),
            theta_i: self.theta_i.clone(),
            phi_i: self.phi_i.clone(),
            ior: self.ior,
            front: face(false),
            back: if self.both_faces { BackFace::Own(face(true)) } else { BackFace::Same },
        }
    }
}

impl Tabulation {
    /// Like [`tabulate`](Self::tabulate), then scales each lobe's values per face, incidence
    /// and wavelength so that the interpolated table's directional albedo equals the function's
    /// (computed by a fine quadrature around the lobe axis): the tabulated counterpart of a
    /// measurement normalised to its total integrated scatter. Bilinear interpolation of a
    /// narrow lobe's convex tail otherwise overestimates its energy by a few per cent.
    pub fn tabulate_energy_matched(&self, f: impl Fn(f32, Vec3, Vec3) -> f32) -> TabulatedSpec {
        let mut spec = self.tabulate(&f);
        let Ok(table) = super::TabulatedTable::new_without_energy_check(spec.clone()) else { return spec };
        let faces: &[bool] = if self.both_faces { &[false, true] } else { &[false] };
        for &back in faces {
            let eta = if back { 1.0 / self.ior.unwrap_or(1.0) } else { self.ior.unwrap_or(1.0) };
            for (pi, &phi_i) in self.phi_i.iter().enumerate() {
                for (ti, &theta_i) in self.theta_i.iter().enumerate() {
                    let (st, ct) = theta_i.sin_cos();
                    let d_face = Vec3::new(st * phi_i.cos(), st * phi_i.sin(), ct);
                    let inc = Incidence::of(d_face);
                    for (l, &lambda) in self.wavelengths.iter().enumerate() {
                        let (r_true, t_true) = quadrature(
                            |d_plane| f(lambda, to_face(d_face, back), to_face(inc.plane_to_face(d_plane), back)),
                            theta_i,
                            eta,
                        );
                        let (r_tab, t_tab) = table.albedo(back, l, pi, ti);
                        let face = match (back, &mut spec.back) {
                            (true, BackFace::Own(b)) => b,
                            _ => &mut spec.front,
                        };
                        for (t, want, have) in [(&mut face.brdf, r_true, r_tab), (&mut face.btdf, t_true, t_tab)] {
                            let Some(t) = t.as_mut() else { continue };
                            if have > 0.0 && want > 0.0 {
                                let n = t.theta.len() * t.phi.len();
                                let slice = (l * self.phi_i.len() + pi) * self.theta_i.len() + ti;
                                let scale = (f64::from(want) / f64::from(have)) as f32;
                                t.values[slice * n..(slice + 1) * n].iter_mut().for_each(|v| *v *= scale);
                            }
                        }
                    }
                }
            }
        }
        spec
    }
}

/// (R, T): the integrals of `f(d_out) |cos|` over the upper and lower hemispheres, `d_out` in the
/// plane frame of incidence `theta_i`, by a midpoint rule in polar coordinates
/// around the mirror and the refraction directions with cubic spacing (fine near each axis).
fn quadrature(f: impl Fn(Vec3) -> f32, theta_i: f32, eta: f32) -> (f32, f32) {
    const N_THETA: usize = 3000;
    const N_PHI: usize = 96;
    let mut out = [0.0f64; 2];
    for (k, transmit) in [false, true].into_iter().enumerate() {
        // Integrate each hemisphere around its own lobe axis (the normal when there is none).
        let axis = lobe_axis(theta_i, transmit, eta);
        let (e1, e2) = {
            let a = if axis.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
            let e1 = (a - axis * a.dot(axis)).normalize();
            (e1, axis.cross(e1))
        };
        let mut s = 0.0f64;
        for i in 0..N_THETA {
            let (u0, u1) = (i as f64 / N_THETA as f64, (i + 1) as f64 / N_THETA as f64);
            let (t0, t1) = (u0.powi(3) * std::f64::consts::PI, u1.powi(3) * std::f64::consts::PI);
            let t = 0.5 * (t0 + t1);
            let d_omega = (t0.cos() - t1.cos()) * std::f64::consts::TAU / N_PHI as f64;
            let (st, ct) = (t.sin() as f32, t.cos() as f32);
            for j in 0..N_PHI {
                let p = (j as f32 + 0.5) / N_PHI as f32 * TAU;
                let d = ct * axis + st * (p.cos() * e1 + p.sin() * e2);
                if (d.z < 0.0) != transmit || d.z == 0.0 {
                    continue;
                }
                s += f64::from(f(d).max(0.0) * d.z.abs()) * d_omega;
            }
        }
        out[k] = s;
    }
    (out[0] as f32, out[1] as f32)
}

/// f of an analytic `material` as a tabulation function: f(d_in -> d_out) = its radiance-mode
/// f(wo = d_out, wi = d_in) at one wavelength.
pub fn material_fn(material: &Material) -> impl Fn(f32, Vec3, Vec3) -> f32 + '_ {
    move |l, d_in, d_out| {
        let mut wl = SampledWavelengths::from_parts([l; 4], [1.0; 4]);
        material.bsdf(&mut wl).f(d_out, d_in, TransportMode::Radiance)[0]
    }
}
