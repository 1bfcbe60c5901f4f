//! Cells of a scatter table's (theta, phi) grid, their integrals and the piecewise-constant
//! sampling distribution built from them.
//!
//! Cell (a, b) spans theta in [theta_a, theta_a+1] and phi in [phi_b, phi_b+1] (the last phi cell
//! wraps to 2 pi). Within a cell, directions are sampled uniformly in solid angle (uniform in
//! h = sin^2(theta/2) and phi), so pdf(w) = P(cell) / Omega(cell) with
//! Omega = 2 (h_a+1 - h_a) (phi_b+1 - phi_b); P(cell) is proportional to the cell's integral of
//! f |cos theta_o| (ybar-weighted over the table's wavelengths), floored at 1e-4 of the cell's
//! peak so that no direction with f > 0 has pdf 0.

use std::f32::consts::TAU;

use super::geometry::{grid_direction, half_versine, lobe_axis};
use super::{ScatterGrid, ScatterTable, TabulatedTable, bracket, bracket_periodic};
use crate::spectrum::cie;

/// Quadrature points per cell and dimension.
const SUB: usize = 4;
/// Relative floor of a cell's sampling weight (times its peak value and solid angle).
const FLOOR: f64 = 1e-4;

/// Number of (theta, phi) cells.
#[inline]
pub(crate) fn n_cells(t: &ScatterTable) -> usize {
    (t.theta.len() - 1) * t.phi.len()
}

/// Bounds (h0, h1, phi0, phi1) of cell `k`, with h = sin^2(theta / 2).
#[inline]
pub(crate) fn cell_bounds(t: &ScatterTable, k: usize) -> (f32, f32, f32, f32) {
    let n_p = t.phi.len();
    let (a, b) = (k / n_p, k % n_p);
    let p1 = if b + 1 < n_p { t.phi[b + 1] } else { TAU };
    (half_versine(t.theta[a]), half_versine(t.theta[a + 1]), t.phi[b], p1)
}

/// Solid angle of a cell from its bounds.
#[inline]
pub(crate) fn solid_angle(h0: f32, h1: f32, p0: f32, p1: f32) -> f32 {
    2.0 * (h1 - h0) * (p1 - p0)
}

/// The cell holding grid coordinates (theta, phi), None beyond the last theta.
#[inline]
pub(crate) fn locate(t: &ScatterTable, theta: f32, phi: f32) -> Option<usize> {
    let n_t = t.theta.len();
    if theta.is_nan() || theta > t.theta[n_t - 1] {
        return None;
    }
    let a = (t.theta.partition_point(|&x| x <= theta).max(1) - 1).min(n_t - 2);
    let b = t.phi.partition_point(|&x| x <= phi).max(1) - 1;
    Some(a * t.phi.len() + b.min(t.phi.len() - 1))
}

/// Bilinear interpolation weights of grid coordinates (theta, phi) in a table: the four corner
/// offsets within a slice and their weights; computed once per direction and applied to every
/// (wavelength, incidence) slice.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bilinear {
    idx: [usize; 4],
    w: [f32; 4],
}

impl Bilinear {
    /// The weights at (theta, phi); None beyond the last theta (f = 0 there).
    #[inline]
    pub fn at(t: &ScatterTable, theta: f32, phi: f32) -> Option<Self> {
        let n_p = t.phi.len();
        if theta.is_nan() || theta > t.theta[t.theta.len() - 1] {
            return None;
        }
        let (a0, a1, ta) = bracket(&t.theta, theta);
        let (b0, b1, tb) = bracket_periodic(&t.phi, phi);
        Some(Self {
            idx: [a0 * n_p + b0, a0 * n_p + b1, a1 * n_p + b0, a1 * n_p + b1],
            w: [(1.0 - ta) * (1.0 - tb), (1.0 - ta) * tb, ta * (1.0 - tb), ta * tb],
        })
    }

    /// The interpolated value in slice `slice` of wavelength `l` (`n_slices` per wavelength).
    #[inline]
    pub fn value(&self, t: &ScatterTable, l: usize, slice: usize, n_slices: usize) -> f32 {
        let base = (l * n_slices + slice) * t.theta.len() * t.phi.len();
        let v = &t.values[base..];
        self.w[0] * v[self.idx[0]]
            + self.w[1] * v[self.idx[1]]
            + self.w[2] * v[self.idx[2]]
            + self.w[3] * v[self.idx[3]]
    }
}

/// The lobe axis of `t` for incidence slice `slice` (None: absolute grid).
fn slice_axis(
    table: &TabulatedTable,
    t: &ScatterTable,
    back: bool,
    transmit: bool,
    slice: usize,
) -> Option<glam::Vec3> {
    let n_ti = table.spec().theta_i.len();
    match t.grid {
        ScatterGrid::Absolute => None,
        ScatterGrid::SpecularRelative => Some(lobe_axis(table.spec().theta_i[slice % n_ti], transmit, table.eta(back))),
    }
}

/// Per cell, the integral of f |cos theta_o| over the cell (directions on the lobe's side only)
/// for incidence slice `slice`, with f = sum over `lweights` (wavelength index, weight) of the
/// table's values: SUB x SUB midpoints in (h, phi), each carrying Omega / SUB^2.
pub(crate) fn cell_integrals(
    table: &TabulatedTable,
    t: &ScatterTable,
    back: bool,
    transmit: bool,
    slice: usize,
    lweights: &[(usize, f32)],
) -> Vec<f64> {
    let n = n_cells(t);
    let mut out = vec![0.0f64; n];
    let axis = slice_axis(table, t, back, transmit, slice);
    let n_slices = table.n_slices();
    for (k, o) in out.iter_mut().enumerate() {
        let (h0, h1, p0, p1) = cell_bounds(t, k);
        let w = f64::from(solid_angle(h0, h1, p0, p1)) / (SUB * SUB) as f64;
        let mut s = 0.0f64;
        for i in 0..SUB {
            let h = h0 + (h1 - h0) * (i as f32 + 0.5) / SUB as f32;
            let theta = 2.0 * h.sqrt().min(1.0).asin();
            for j in 0..SUB {
                let phi = p0 + (p1 - p0) * (j as f32 + 0.5) / SUB as f32;
                let v = grid_direction(h, phi, axis, transmit);
                let cos = if transmit { -v.z } else { v.z };
                if cos <= 0.0 {
                    continue;
                }
                let Some(bl) = Bilinear::at(t, theta, phi) else { continue };
                let f: f32 = lweights.iter().map(|&(l, wl)| wl * bl.value(t, l, slice, n_slices)).sum();
                s += f64::from(f * cos);
            }
        }
        *o = s * w;
    }
    out
}

/// Sampling distribution of one face's reflection or transmission table: per incidence slice a
/// discrete distribution over the cells.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LobeDistribution {
    n_cells: usize,
    /// Per slice and cell: probability of the cell within the slice.
    prob: Vec<f32>,
    /// Per slice and cell: cumulative probability (inclusive).
    cdf: Vec<f32>,
    /// Per slice: total weight (about the ybar-weighted directional albedo of the lobe).
    total: Vec<f32>,
}

impl LobeDistribution {
    /// Builds the distribution of table `t` (face `back`, lobe `transmit`) of `table`.
    pub fn build(table: &TabulatedTable, t: &ScatterTable, back: bool, transmit: bool) -> Self {
        let wl = &table.spec().wavelengths;
        let mut lw: Vec<(usize, f32)> = wl.iter().enumerate().map(|(l, &x)| (l, cie::ybar(x) + 0.01)).collect();
        let norm: f32 = lw.iter().map(|x| x.1).sum();
        for x in &mut lw {
            x.1 /= norm;
        }
        let n = n_cells(t);
        let n_slices = table.n_slices();
        let (n_t, n_p) = (t.theta.len(), t.phi.len());
        let mut prob = Vec::with_capacity(n * n_slices);
        let mut cdf = Vec::with_capacity(n * n_slices);
        let mut total = Vec::with_capacity(n_slices);
        for slice in 0..n_slices {
            let mut w = cell_integrals(table, t, back, transmit, slice, &lw);
            for (k, wk) in w.iter_mut().enumerate() {
                let (a, b) = (k / n_p, k % n_p);
                let corners = [(a, b), (a, (b + 1) % n_p), (a + 1, b), (a + 1, (b + 1) % n_p)];
                let peak = corners
                    .iter()
                    .map(|&(i, j)| {
                        lw.iter().map(|&(l, x)| x * t.values[((l * n_slices + slice) * n_t + i) * n_p + j]).sum::<f32>()
                    })
                    .fold(0.0f32, f32::max);
                let (h0, h1, p0, p1) = cell_bounds(t, k);
                if peak > 0.0 {
                    *wk = wk.max(FLOOR * f64::from(peak) * f64::from(solid_angle(h0, h1, p0, p1)));
                }
            }
            let sum: f64 = w.iter().sum();
            total.push(sum as f32);
            let mut acc = 0.0f64;
            for wk in w {
                let p = if sum > 0.0 { wk / sum } else { 0.0 };
                acc += p;
                prob.push(p as f32);
                cdf.push(acc as f32);
            }
            if sum > 0.0 {
                let last = cdf.len() - 1;
                cdf[last] = 1.0;
            }
        }
        Self { n_cells: n, prob, cdf, total }
    }

    /// Total weight of slice `slice` (0: the lobe scatters nothing there).
    #[inline]
    pub fn total(&self, slice: usize) -> f32 {
        self.total[slice]
    }

    /// Probability of cell `k` in slice `slice`.
    #[inline]
    pub fn prob(&self, slice: usize, k: usize) -> f32 {
        self.prob[slice * self.n_cells + k]
    }

    /// Picks a cell of slice `slice` with `u` in [0, 1); returns it and `u` rescaled to [0, 1)
    /// within the cell. None when the slice is empty.
    #[inline]
    pub fn sample(&self, slice: usize, u: f32) -> Option<(usize, f32)> {
        if self.total[slice] <= 0.0 {
            return None;
        }
        let cdf = &self.cdf[slice * self.n_cells..(slice + 1) * self.n_cells];
        let k = cdf.partition_point(|&c| c <= u).min(self.n_cells - 1);
        let lo = if k == 0 { 0.0 } else { cdf[k - 1] };
        let p = cdf[k] - lo;
        if p <= 0.0 {
            return None;
        }
        Some((k, ((u - lo) / p).clamp(0.0, 1.0 - f32::EPSILON)))
    }
}
