//! [`TabulatedBsdf`]: a [`TabulatedTable`] at a path's four wavelengths.
//!
//! The tables store f(light direction -> viewing direction) as measured. Radiance transport
//! evaluates f(wi -> wo), importance transport (photons) f(wo -> wi), so both modes see the
//! physical BSDF without assuming reciprocity. Sampling always draws the unknown direction from
//! the table indexed by the known one (`wo`): exact for photons, and for camera paths proportional
//! to f wherever the table is reciprocal (Helmholtz); `pdf` is the density of that procedure.

use glam::{Vec2, Vec3};

use super::{BsdfSample, Lobe, TransportMode};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::tabulated::distribution::{Bilinear, cell_bounds, locate, solid_angle};
use crate::tabulated::geometry::{Incidence, grid_coords, grid_direction, lobe_axis, to_face};
use crate::tabulated::{ScatterGrid, TabulatedTable, bracket};

/// A tabulated BSDF at four wavelengths: a borrowed table plus the wavelength interpolation.
#[derive(Clone, Copy, Debug)]
pub struct TabulatedBsdf<'a> {
    table: &'a TabulatedTable,
    /// Per wavelength: (lower index, upper index, fraction) in the table's wavelengths.
    lambda: [(u32, u32, f32); 4],
}

impl PartialEq for TabulatedBsdf<'_> {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self.table, other.table) && self.lambda == other.lambda
    }
}

/// Where a direction pair falls in the table: face, lobe and grid coordinates.
struct Lookup {
    back: bool,
    transmit: bool,
    inc: Incidence,
    theta: f32,
    phi: f32,
}

impl<'a> TabulatedBsdf<'a> {
    /// The BSDF of `table` at the wavelengths `wl`.
    pub fn new(table: &'a TabulatedTable, wl: &SampledWavelengths) -> Self {
        let lambda = std::array::from_fn(|k| {
            let (i0, i1, t) = bracket(&table.spec().wavelengths, wl.lambda(k));
            (i0 as u32, i1 as u32, t)
        });
        Self { table, lambda }
    }

    /// The table.
    pub fn table(&self) -> &'a TabulatedTable {
        self.table
    }

    /// Face, lobe and grid coordinates of `d_out` for light arriving from `d_in` (None: no lobe).
    fn lookup(&self, d_in: Vec3, d_out: Vec3) -> Option<Lookup> {
        if d_in.z == 0.0 || d_out.z == 0.0 || !d_in.is_finite() || !d_out.is_finite() {
            return None;
        }
        let back = d_in.z < 0.0;
        let di = to_face(d_in, back);
        let v = to_face(d_out, back);
        let transmit = v.z < 0.0;
        let t = self.table.lobe_table(back, transmit)?;
        let inc = Incidence::of(di);
        let axis = match t.grid {
            ScatterGrid::Absolute => None,
            ScatterGrid::SpecularRelative => Some(lobe_axis(inc.theta, transmit, self.table.eta(back))),
        };
        let (theta, phi) = grid_coords(inc.face_to_plane(v), axis, transmit);
        Some(Lookup { back, transmit, inc, theta, phi })
    }

    /// f(d_in -> d_out) in 1/sr: light arriving from `d_in`, leaving along `d_out`.
    fn eval(&self, d_in: Vec3, d_out: Vec3) -> SampledSpectrum {
        let Some(q) = self.lookup(d_in, d_out) else { return SampledSpectrum::zero() };
        let Some(t) = self.table.lobe_table(q.back, q.transmit) else { return SampledSpectrum::zero() };
        let Some(bl) = Bilinear::at(t, q.theta, q.phi) else { return SampledSpectrum::zero() };
        let (slices, n) = self.table.slices(q.inc.theta, q.inc.phi);
        let n_slices = self.table.n_slices();
        let mut out = [0.0f32; 4];
        for (k, o) in out.iter_mut().enumerate() {
            let (l0, l1, fl) = self.lambda[k];
            let at =
                |l: u32| -> f32 { slices[..n].iter().map(|&(s, w)| w * bl.value(t, l as usize, s, n_slices)).sum() };
            let v0 = at(l0);
            *o = if fl > 0.0 { v0 + (at(l1) - v0) * fl } else { v0 };
        }
        SampledSpectrum(out)
    }

    /// f(wo, wi) in 1/sr (see the module documentation for the direction of light flow).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        match mode {
            TransportMode::Radiance => self.eval(wi, wo),
            TransportMode::Importance => self.eval(wo, wi),
        }
    }

    /// Solid-angle density with which [`sample_f`](Self::sample_f) returns `wi` given `wo`:
    /// sum over incidence slices s of w_s (total_lobe,s / total_s) P_s(cell) / Omega(cell).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        let Some(q) = self.lookup(wo, wi) else { return 0.0 };
        let (Some(t), Some(d)) = (self.table.lobe_table(q.back, q.transmit), self.table.dist(q.back, q.transmit))
        else {
            return 0.0;
        };
        let Some(k) = locate(t, q.theta, q.phi) else { return 0.0 };
        let (h0, h1, p0, p1) = cell_bounds(t, k);
        let omega = solid_angle(h0, h1, p0, p1);
        if omega.is_nan() || omega <= 0.0 {
            return 0.0;
        }
        let other = self.table.dist(q.back, !q.transmit);
        let (slices, n) = self.table.slices(q.inc.theta, q.inc.phi);
        let mut pdf = 0.0;
        for &(s, w) in &slices[..n] {
            let lobe = d.total(s);
            let all = lobe + other.map_or(0.0, |o| o.total(s));
            if lobe > 0.0 {
                pdf += w * (lobe / all) * d.prob(s, k);
            }
        }
        pdf / omega
    }

    /// Samples `wi` given `wo`: an incidence slice by its interpolation weight, the reflection or
    /// transmission lobe by its weight in that slice (both with `uc`), a cell from the slice's
    /// distribution and a direction uniform in solid angle within it (with `u`).
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.is_finite() {
            return None;
        }
        let back = wo.z < 0.0;
        let inc = Incidence::of(to_face(wo, back));
        let (slices, n) = self.table.slices(inc.theta, inc.phi);
        let mut uc = uc.clamp(0.0, 1.0 - f32::EPSILON);
        let mut slice = slices[n - 1].0;
        for &(s, w) in &slices[..n] {
            if uc < w {
                slice = s;
                uc /= w;
                break;
            }
            uc -= w;
        }
        let uc = uc.clamp(0.0, 1.0 - f32::EPSILON);
        let tr = self.table.dist(back, false).map_or(0.0, |d| d.total(slice));
        let tt = self.table.dist(back, true).map_or(0.0, |d| d.total(slice));
        if tr + tt <= 0.0 {
            return None;
        }
        let transmit = uc >= tr / (tr + tt);
        let t = self.table.lobe_table(back, transmit)?;
        let d = self.table.dist(back, transmit)?;
        let (k, ux) = d.sample(slice, u.x)?;
        let axis = match t.grid {
            ScatterGrid::Absolute => None,
            ScatterGrid::SpecularRelative => Some(lobe_axis(inc.theta, transmit, self.table.eta(back))),
        };
        let (h0, h1, p0, p1) = cell_bounds(t, k);
        let v = grid_direction(h0 + (h1 - h0) * ux, p0 + (p1 - p0) * u.y, axis, transmit);
        if (v.z < 0.0) != transmit || v.z == 0.0 {
            return None;
        }
        let wi = to_face(inc.plane_to_face(v), back).normalize();
        let pdf = self.pdf(wo, wi, mode);
        if pdf.is_nan() || pdf <= 0.0 || !wi.is_finite() {
            return None;
        }
        let eta = if transmit { self.table.eta(back) } else { 1.0 };
        Some(BsdfSample {
            f: self.f(wo, wi, mode),
            wi,
            pdf,
            lobe: if transmit { Lobe::Transmission } else { Lobe::Reflection },
            specular: false,
            eta,
        })
    }

    /// True when some face transmits.
    pub fn has_transmission(&self) -> bool {
        self.table.has_transmission()
    }

    /// Relative IOR for the refraction axis seen from `wo`'s side (1 without `ior`).
    pub fn eta(&self) -> f32 {
        self.table.eta(false)
    }
}
