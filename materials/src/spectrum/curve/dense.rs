//! Spectra pre-sampled on the renderer's 1 nm grid over [LAMBDA_MIN, LAMBDA_MAX], so that a
//! path's four wavelengths look a curve up by index instead of evaluating it (pbrt-v4 keeps its
//! lights' spectra as `DenselySampledSpectrum` for the same reason).
//!
//! Each 1 nm cell [k, k + 1] holds a cubic c0 + t (c1 + t (c2 + t c3)) in the position t in
//! [0, 1] within the cell ([`GridPos`], computed once per path by [`SampledWavelengths`]):
//! - a piecewise-linear table whose knots inside the range all lie on whole nanometres is linear
//!   in every cell (its value at the cell's two ends, taken from the segment that covers the
//!   cell, so the step at a table's end stays a step): the curve itself, to rounding;
//! - a smooth curve (blackbody, CIE illuminant A, RGB uplift) gets the cubic through its values
//!   at t = 0, 1/3, 2/3, 1, whose error is of order f''''/(4! 3^3) per nm^4 (about 1e-9
//!   relative for these curves).
//!
//! A curve is only pre-sampled when the cubics reproduce it: [`DenseSpectrum::new`] compares
//! them with the curve at nine points per cell and gives up (the curve stays evaluated as it
//! is) when any differs by more than [`DENSE_TOLERANCE`] = 1e-5 of the curve's largest value.
//! Measured, the shipped kinds of curve stay within 2e-6 (the tests), the size of the curves'
//! own f32 evaluation error; a table with knots between whole nanometres (or a curve with a
//! kink inside a cell) is simply not pre-sampled.

use std::sync::Arc;

use super::Spectrum;
use crate::spectrum::sampled::{
    GridPos, LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths,
};

pub use crate::spectrum::sampled::GRID_CELLS;

/// Largest deviation of the cubics from the curve, relative to the curve's largest value, for
/// which a curve is pre-sampled.
pub const DENSE_TOLERANCE: f32 = 1e-5;

/// A curve and its cubics on the 1 nm grid.
#[derive(Debug, PartialEq)]
struct DenseData {
    /// [c0, c1, c2, c3] per cell.
    cells: Box<[[f32; 4]]>,
    /// The curve, for wavelengths outside the grid and for everything but sampling.
    curve: Spectrum,
}

/// A spectrum pre-sampled on the 1 nm grid (see the module documentation); cheap to clone.
#[derive(Clone, Debug, PartialEq)]
pub struct DenseSpectrum(Arc<DenseData>);

/// A cell's cubic c0 + t (c1 + t (c2 + t c3)) at t in [0, 1].
#[inline(always)]
fn cubic(c: &[f32; 4], t: f32) -> f32 {
    c[0] + t * (c[1] + t * (c[2] + t * c[3]))
}

impl DenseSpectrum {
    /// Pre-samples `curve`, or None when the cubics would not reproduce it within
    /// [`DENSE_TOLERANCE`] (or it is a constant, which needs no table).
    pub fn new(curve: &Spectrum) -> Option<Self> {
        let cells: Vec<[f32; 4]> = match curve {
            Spectrum::Constant(_) | Spectrum::Dense(_) => return None,
            Spectrum::PiecewiseLinear { lambda, values } => linear_cells(lambda, values)?,
            _ => (0..GRID_CELLS).map(|k| cubic_cell(curve, k)).collect(),
        };
        let dense = Self(Arc::new(DenseData { cells: cells.into_boxed_slice(), curve: curve.clone() }));
        dense.reproduces_curve().then_some(dense)
    }

    /// The curve it was made from.
    pub fn curve(&self) -> &Spectrum {
        &self.0.curve
    }

    /// Value at grid position `p` (the curve's own value outside the grid at `lambda`).
    #[inline(always)]
    fn at(&self, p: GridPos, lambda: f32) -> f32 {
        match self.0.cells.get(p.cell as usize) {
            Some(c) => cubic(c, p.t),
            None => self.0.curve.value(lambda),
        }
    }

    /// Values at the path's wavelengths.
    #[inline(always)]
    pub fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        let (pos, lambda) = (wl.grid(), wl.lambdas());
        let cells = &self.0.cells;
        // every wavelength inside the grid (the usual case): the four values are returned as
        // one vector, written in one store, because four scalar stores that the caller reads
        // back as one vector cannot be forwarded to its load (a stall of about a dozen cycles
        // per call: `Emission::radiance` 4.2% -> 2.5% of `pt`'s time in the Cornell box)
        if pos.iter().all(|p| (p.cell as usize) < cells.len()) {
            // the four cells' coefficients as the columns of a matrix, transposed so that each
            // column holds one coefficient of every lane: the cubic is then evaluated for the
            // four wavelengths at once, with the operations of `cubic` in its order per lane
            let cell = |p: &GridPos| glam::Vec4::from_array(cells[p.cell as usize]);
            let c = glam::Mat4::from_cols(cell(&pos[0]), cell(&pos[1]), cell(&pos[2]), cell(&pos[3])).transpose();
            let t = glam::Vec4::from_array(pos.map(|p| p.t));
            return SampledSpectrum((c.x_axis + t * (c.y_axis + t * (c.z_axis + t * c.w_axis))).to_array());
        }
        let mut out = [0.0; N_SPECTRUM_SAMPLES];
        for i in 0..N_SPECTRUM_SAMPLES {
            out[i] = self.at(pos[i], lambda[i]);
        }
        SampledSpectrum(out)
    }

    /// True when the cubics agree with the curve at eight points of every cell within
    /// [`DENSE_TOLERANCE`] of the curve's largest value.
    fn reproduces_curve(&self) -> bool {
        let curve = &self.0.curve;
        let mut scale = 0.0f32;
        let mut worst = 0.0f32;
        for k in 0..GRID_CELLS {
            for j in 0..=8 {
                let lambda = LAMBDA_MIN + k as f32 + j as f32 / 8.0;
                let p = GridPos { cell: k as u32, t: j as f32 / 8.0 };
                // the end of a cell is the curve's value there unless a step sits on it (a
                // table's end): compare just inside the cell instead
                let probe = if j == 8 {
                    lambda - 1e-3
                } else if j == 0 {
                    lambda + 1e-3
                } else {
                    lambda
                };
                let tp = GridPos { t: probe - (LAMBDA_MIN + k as f32), ..p };
                let v = curve.value(probe);
                scale = scale.max(v.abs());
                worst = worst.max((self.at(tp, probe) - v).abs());
                if !v.is_finite() {
                    return false;
                }
            }
        }
        worst <= DENSE_TOLERANCE * scale
    }
}

/// The cubic through the curve at t = 0, 1/3, 2/3, 1 of cell `k` (Lagrange form solved for the
/// power basis).
fn cubic_cell(curve: &Spectrum, k: usize) -> [f32; 4] {
    let y: [f64; 4] = std::array::from_fn(|j| curve.value(LAMBDA_MIN + k as f32 + j as f32 / 3.0) as f64);
    [
        y[0],
        (-11.0 * y[0] + 18.0 * y[1] - 9.0 * y[2] + 2.0 * y[3]) / 2.0,
        9.0 * (2.0 * y[0] - 5.0 * y[1] + 4.0 * y[2] - y[3]) / 2.0,
        9.0 * (-y[0] + 3.0 * y[1] - 3.0 * y[2] + y[3]) / 2.0,
    ]
    .map(|c| c as f32)
}

/// The linear pieces of a table on the grid, or None when a knot lies inside a cell (between
/// whole nanometres) or the table has a single knot.
fn linear_cells(lambda: &[f32], values: &[f32]) -> Option<Vec<[f32; 4]>> {
    if lambda.len() < 2 {
        return None;
    }
    let inside = |l: f32| l > LAMBDA_MIN && l < LAMBDA_MAX;
    if lambda.iter().any(|&l| inside(l) && l.fract() != 0.0) {
        return None;
    }
    let (first, last) = (lambda[0], lambda[lambda.len() - 1]);
    Some(
        (0..GRID_CELLS)
            .map(|k| {
                let (a, b) = (LAMBDA_MIN + k as f32, LAMBDA_MIN + k as f32 + 1.0);
                let mid = a + 0.5;
                if mid < first || mid > last {
                    return [0.0; 4];
                }
                // the segment covering the cell's interior, evaluated at the cell's ends
                let i = lambda.partition_point(|&x| x <= mid).clamp(1, lambda.len() - 1) - 1;
                let (l0, l1) = (lambda[i] as f64, lambda[i + 1] as f64);
                let (v0, v1) = (values[i] as f64, values[i + 1] as f64);
                let line = |x: f32| v0 + (v1 - v0) * ((x as f64 - l0) / (l1 - l0));
                let (ya, yb) = (line(a), line(b));
                [ya as f32, (yb - ya) as f32, 0.0, 0.0]
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::StandardIlluminant;

    fn worst_relative(d: &DenseSpectrum) -> f32 {
        let curve = d.curve();
        let mut worst = 0.0f32;
        let mut scale = 0.0f32;
        let mut l = LAMBDA_MIN + 0.0137;
        while l < LAMBDA_MAX {
            let v = curve.value(l);
            scale = scale.max(v.abs());
            worst = worst.max((d.at(GridPos::of(l), l) - v).abs());
            l += 0.0731;
        }
        worst / scale
    }

    #[test]
    fn whole_nanometre_tables_are_reproduced_with_their_steps() {
        // knots every 4 nm from 400 to 700: zero outside, a step at each end
        let lambda: Vec<f32> = (0..76).map(|i| 400.0 + 4.0 * i as f32).collect();
        let values: Vec<f32> = (0..76).map(|i| 0.2 + 0.5 * ((i as f32) * 0.37).sin().abs()).collect();
        let s = Spectrum::piecewise_linear(lambda, values).unwrap();
        let d = DenseSpectrum::new(&s).expect("integer knots are pre-sampled");
        assert!(worst_relative(&d) < 1e-6, "{}", worst_relative(&d));
        // the steps at the table's ends stay steps (a wavelength exactly on a cell boundary
        // belongs to the cell above it, so the end knot 700 itself reads the zero beyond it)
        for l in [399.999f32, 700.001, 359.0, 831.0] {
            assert_eq!(d.at(GridPos::of(l), l), s.value(l), "{l}");
        }
        for l in [400.0f32, 400.001, 699.999] {
            assert!((d.at(GridPos::of(l), l) - s.value(l)).abs() < 1e-6, "{l}");
            assert!(s.value(l) > 0.1);
        }
    }

    #[test]
    fn smooth_curves_are_reproduced_to_float_rounding() {
        for s in [
            Spectrum::blackbody(1000.0).unwrap(),
            Spectrum::blackbody(2700.0).unwrap(),
            Spectrum::blackbody(20000.0).unwrap(),
            Spectrum::illuminant(StandardIlluminant::A),
            Spectrum::illuminant(StandardIlluminant::D65),
            Spectrum::rgb_reflectance([0.9, 0.1, 0.05]).unwrap(),
            Spectrum::rgb_reflectance([0.05, 0.8, 0.1]).unwrap(),
            Spectrum::rgb_illuminant([0.2, 0.4, 1.0]).unwrap(),
        ] {
            let d = DenseSpectrum::new(&s).unwrap_or_else(|| panic!("{s:?} is pre-sampled"));
            // measured 1.8e-7 (illuminant A) to 1.7e-6 (a saturated green uplift): the size of the
            // curves' own f32 evaluation error (the wavelength's rounding times the slope)
            assert!(worst_relative(&d) < 2e-6, "{s:?}: {}", worst_relative(&d));
        }
    }

    #[test]
    fn four_lane_sampling_is_each_lane_looked_up_alone() {
        let d = DenseSpectrum::new(&Spectrum::blackbody(3200.0).unwrap()).unwrap();
        let mut u = 0.123f32;
        for round in 0..5000 {
            u = (u + 0.618_034).fract();
            let wl = if round % 50 == 0 {
                // wavelengths off the grid take the curve's own value
                SampledWavelengths::from_parts([LAMBDA_MIN - 1.0, 500.0, LAMBDA_MAX, 831.5], [1.0; 4])
            } else {
                SampledWavelengths::sample_visible(u)
            };
            let v = d.sample(&wl);
            for i in 0..N_SPECTRUM_SAMPLES {
                assert_eq!(v[i].to_bits(), d.at(wl.grid()[i], wl.lambda(i)).to_bits(), "{:?} lane {i}", wl.lambdas());
            }
        }
    }

    #[test]
    fn curves_the_grid_cannot_hold_are_left_alone() {
        // a knot between whole nanometres, a single knot, a constant
        let s = Spectrum::piecewise_linear(vec![400.0, 500.5, 700.0], vec![0.1, 0.9, 0.2]).unwrap();
        assert!(DenseSpectrum::new(&s).is_none());
        assert!(DenseSpectrum::new(&Spectrum::piecewise_linear(vec![500.0], vec![1.0]).unwrap()).is_none());
        assert!(DenseSpectrum::new(&Spectrum::Constant(0.5)).is_none());
        // knots outside the grid may lie anywhere
        let s = Spectrum::piecewise_linear(vec![300.25, 500.0, 900.5], vec![0.1, 0.9, 0.2]).unwrap();
        assert!(DenseSpectrum::new(&s).is_some());
    }
}
