//! Building tabulated BSDFs from functions: the material library's generator, the GGX
//! consistency tests and the `quasar bsdf` tools tabulate analytic models with it.

use std::f32::consts::TAU;

use glam::Vec3;

use super::geometry::{Incidence, grid_direction, half_versine, lobe_axis};
use super::{BackFace, Face, ScatterGrid, ScatterTable, TabulatedSpec};
use crate::bsdf::TransportMode;
use crate::material::Material;
use crate::spectrum::SampledWavelengths;

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
/// them near 0: fine steps inside a narrow lobe, coarse ones in its tail).
pub fn power_spaced(n: usize, max: f32, p: f32) -> Vec<f32> {
    (0..n).map(|i| max * (i as f32 / (n - 1) as f32).powf(p)).collect()
}

/// `n` azimuths uniformly over [0, 2 pi).
pub fn uniform_phi(n: usize) -> Vec<f32> {
    (0..n).map(|i| TAU * i as f32 / n as f32).collect()
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
}

impl Tabulation {
    /// Tabulates `f(lambda_nm, d_in, d_out)` (light arriving from unit `d_in` on the front,
    /// z > 0, leaving along `d_out`; local frame); the back face is the same as the front.
    pub fn tabulate(&self, f: impl Fn(f32, Vec3, Vec3) -> f32) -> TabulatedSpec {
        let eta = self.ior.unwrap_or(1.0);
        let table = |g: &GridSpec, transmit: bool| {
            let mut values = Vec::new();
            for &l in &self.wavelengths {
                for &pi in &self.phi_i {
                    for &ti in &self.theta_i {
                        let (st, ct) = ti.sin_cos();
                        let d_in = Vec3::new(st * pi.cos(), st * pi.sin(), ct);
                        let inc = Incidence::of(d_in);
                        let axis = match g.grid {
                            ScatterGrid::Absolute => Some(None),
                            ScatterGrid::SpecularRelative => lobe_axis(ti, transmit, eta).map(Some),
                        };
                        for &t in &g.theta {
                            for &p in &g.phi {
                                let v =
                                    axis.map(|a| inc.plane_to_face(grid_direction(half_versine(t), p, a, transmit)));
                                let ok = v.filter(|v| (v.z < 0.0) == transmit && v.z != 0.0);
                                values.push(ok.map_or(0.0, |d_out| f(l, d_in, d_out.normalize()).max(0.0)));
                            }
                        }
                    }
                }
            }
            ScatterTable { grid: g.grid, theta: g.theta.clone(), phi: g.phi.clone(), values }
        };
        TabulatedSpec {
            name: self.name.clone(),
            wavelengths: self.wavelengths.clone(),
            theta_i: self.theta_i.clone(),
            phi_i: self.phi_i.clone(),
            ior: self.ior,
            front: Face {
                brdf: self.brdf.as_ref().map(|g| table(g, false)),
                btdf: self.btdf.as_ref().map(|g| table(g, true)),
            },
            back: BackFace::Same,
        }
    }
}

/// f of an analytic `material` as a tabulation function: f(d_in -> d_out) = its radiance-mode
/// f(wo = d_out, wi = d_in) at one wavelength.
pub fn material_fn(material: &Material) -> impl Fn(f32, Vec3, Vec3) -> f32 + '_ {
    move |l, d_in, d_out| {
        let mut wl = SampledWavelengths::from_parts([l; 4], [1.0; 4]);
        material.bsdf(&mut wl).f(d_out, d_in, TransportMode::Radiance)[0]
    }
}
