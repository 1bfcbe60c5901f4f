//! The visual importance density used by [`SampledWavelengths::sample_visible`](super::SampledWavelengths::sample_visible).
//!
//! The target is pbrt-v4's p(lambda) = sech^2(A (lambda - C)) / N with
//! N = (tanh(A (LAMBDA_MAX - C)) - tanh(A (LAMBDA_MIN - C))) / A, whose inverse CDF is
//! lambda = C + atanh(t) / A for t = T0 + u (T1 - T0). Sampling uses that inverse CDF tabulated at
//! [`SEGMENTS`] + 1 equally spaced u and interpolated linearly in between: a table look-up
//! instead of a logarithm per wavelength. The density of that map is piecewise constant,
//! 1 / (SEGMENTS (lambda_{j+1} - lambda_j)) on segment j, and that exact density is what a
//! sample carries, so the estimate stays unbiased; it differs from the target by less than 0.7%
//! (half a segment of about 0.46 nm times the target's logarithmic slope).

use std::sync::LazyLock;

use glam::Vec4;

use super::{LAMBDA_MAX, LAMBDA_MIN};

const A: f64 = 0.0072;
const C: f64 = 538.0;
/// Segments of the tabulated inverse CDF.
pub const SEGMENTS: usize = 1024;

/// The inverse CDF at u = j / SEGMENTS (the ends exactly LAMBDA_MIN and LAMBDA_MAX) and the
/// density on each segment.
pub struct Table {
    lambda: [f32; SEGMENTS + 1],
    pdf: [f32; SEGMENTS],
}

static TABLE: LazyLock<Table> = LazyLock::new(|| {
    let (t0, t1) = ((A * (LAMBDA_MIN as f64 - C)).tanh(), (A * (LAMBDA_MAX as f64 - C)).tanh());
    let lambda: [f32; SEGMENTS + 1] = std::array::from_fn(|j| match j {
        0 => LAMBDA_MIN,
        SEGMENTS => LAMBDA_MAX,
        _ => (C + (t0 + (j as f64 / SEGMENTS as f64) * (t1 - t0)).atanh() / A) as f32,
    });
    let pdf = std::array::from_fn(|j| (1.0 / (SEGMENTS as f64 * (lambda[j + 1] - lambda[j]) as f64)) as f32);
    Table { lambda, pdf }
});

/// The target density (1/nm) at `lambda`; 0 outside [LAMBDA_MIN, LAMBDA_MAX].
#[cfg_attr(not(test), allow(dead_code))]
pub fn target_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let (t0, t1) = ((A * (LAMBDA_MIN as f64 - C)).tanh(), (A * (LAMBDA_MAX as f64 - C)).tanh());
    let t = (A * (lambda as f64 - C)).tanh();
    ((1.0 - t * t) * A / (t1 - t0)) as f32
}

/// The table (built on first use).
#[inline]
pub fn table() -> &'static Table {
    &TABLE
}

impl Table {
    /// Samples of the tabulated inverse CDF at four values of u in [0, 1] (one per lane; a NaN
    /// becomes segment 0) and their exact densities: (lambda, p(lambda)) per lane.
    #[inline]
    pub fn sample(&self, u: Vec4) -> (Vec4, Vec4) {
        // SSE's max returns its second operand where either is a NaN
        let x = u.max(Vec4::ZERO).min(Vec4::ONE) * SEGMENTS as f32;
        let j: [usize; 4] = x.to_array().map(|x| super::floor_index(x, SEGMENTS - 1));
        let f = x - Vec4::from_array(j.map(|j| j as f32));
        let a = Vec4::from_array(j.map(|j| self.lambda[j]));
        let b = Vec4::from_array(j.map(|j| self.lambda[j + 1]));
        let lambda = (a + f * (b - a)).clamp(Vec4::splat(LAMBDA_MIN), Vec4::splat(LAMBDA_MAX));
        (lambda, Vec4::from_array(j.map(|j| self.pdf[j])))
    }
}

/// [`Table::sample`] of the table at one u.
#[cfg(test)]
fn sample(u: f32) -> (f32, f32) {
    let (lambda, pdf) = table().sample(Vec4::splat(u));
    (lambda.x, pdf.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_density_carried_is_the_density_of_the_map() {
        // p = du / dlambda of the map, measured by finite differences inside each segment
        let h = 0.25 / SEGMENTS as f32;
        for j in (0..SEGMENTS).step_by(7) {
            let u = (j as f32 + 0.375) / SEGMENTS as f32;
            let ((l0, p), (l1, _)) = (sample(u), sample(u + h));
            let measured = h / (l1 - l0);
            assert!((measured - p).abs() <= 2e-3 * p, "segment {j}: {p} vs {measured}");
            assert!((p - target_pdf(l0)).abs() <= 7e-3 * p, "segment {j}: {p} vs target {}", target_pdf(l0));
        }
    }

    #[test]
    fn every_lane_is_the_scalar_look_up() {
        // the look-up written one wavelength at a time, as it was before the lanes
        let scalar = |u: f32| {
            let x = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) } * SEGMENTS as f32;
            let j = (x as usize).min(SEGMENTS - 1);
            let f = x - j as f32;
            let (a, b) = (TABLE.lambda[j], TABLE.lambda[j + 1]);
            ((a + f * (b - a)).clamp(LAMBDA_MIN, LAMBDA_MAX), TABLE.pdf[j])
        };
        let edges = [0.0, 1.0, f32::NAN, -0.5, 2.0, 1.0 - f32::EPSILON, 0.5 / SEGMENTS as f32, 1e-30];
        let us: Vec<f32> = (0..4000).map(|k| (k as f32 * 0.618_034).fract()).chain(edges).collect();
        for u in us.chunks_exact(4) {
            let (lambda, pdf) = table().sample(Vec4::from_slice(u));
            for (k, &u) in u.iter().enumerate() {
                let (l, p) = scalar(u);
                assert_eq!((lambda[k].to_bits(), pdf[k].to_bits()), (l.to_bits(), p.to_bits()), "u = {u}");
            }
        }
    }

    #[test]
    fn the_table_spans_the_range_and_its_density_integrates_to_one() {
        assert_eq!(sample(0.0).0, LAMBDA_MIN);
        assert_eq!(sample(1.0).0, LAMBDA_MAX);
        let t = &*TABLE;
        let total: f64 = t.pdf.iter().zip(t.lambda.windows(2)).map(|(&p, w)| p as f64 * (w[1] - w[0]) as f64).sum();
        assert!((total - 1.0).abs() < 1e-5, "{total}");
    }
}
