//! RGB -> reflectance spectrum uplift with the sigmoid-polynomial model of Jakob & Hanika 2019
//! ("A Low-Dimensional Function Space for Efficient Spectral Upsampling"):
//! rho(lambda) = S(c0 t^2 + c1 t + c2), S(z) = 1/2 + z / (2 sqrt(1 + z^2)), with
//! t = (lambda - 360 nm) / 470 nm. Every rho lies strictly between 0 and 1 (energy bounded) and is
//! smooth; the three coefficients are solved so that the reflectance lit by D65 (normalised to
//! luminance 1) and seen through quasar's own sensor (CIE 1931 tables, 1 nm quadrature, linear
//! sRGB) gives back exactly the requested RGB: the uplift round-trips.
//!
//! Constant colours are fitted once each ([`fit`]). Colours that change per shading point
//! (texels) go through [`RgbToSpectrumTable`]: coefficients fitted on a grid over the RGB cube
//! (indexed by the largest component, as in pbrt-v4's `RGBToSpectrumTable`) and interpolated
//! trilinearly, built once on first use.

use std::sync::OnceLock;

use super::cie;
use super::color::XYZ_TO_SRGB;
use super::sampled::{LAMBDA_MAX, LAMBDA_MIN};

/// Width in nm of the model's wavelength parameter t.
const RANGE: f64 = (LAMBDA_MAX - LAMBDA_MIN) as f64;
/// Quadrature step (nm) of [`fit`]: 1 nm midpoints, within 1e-6 of the continuous integral.
const FINE_STEP: f32 = 1.0;
/// Quadrature step (nm) of the table's fits: 5 nm midpoints (within 6e-4), five times faster.
const COARSE_STEP: f32 = 5.0;

/// A reflectance spectrum S(c0 t^2 + c1 t + c2) of the Jakob–Hanika model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidPolynomial {
    c: [f32; 3],
}

#[inline]
fn sigmoid(z: f64) -> f64 {
    if z.is_infinite() {
        return if z > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + z / (2.0 * (1.0 + z * z).sqrt())
}

impl SigmoidPolynomial {
    /// The model with coefficients `c` (of t in [0, 1] over 360..830 nm).
    pub const fn new(c: [f32; 3]) -> Self {
        Self { c }
    }

    /// The coefficients.
    pub fn coefficients(&self) -> [f32; 3] {
        self.c
    }

    /// Reflectance at `lambda` nm, in (0, 1).
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let t = (lambda - LAMBDA_MIN) / (LAMBDA_MAX - LAMBDA_MIN);
        let z = (self.c[0] * t + self.c[1]) * t + self.c[2];
        if z.is_infinite() {
            return if z > 0.0 { 1.0 } else { 0.0 };
        }
        0.5 + z / (2.0 * (1.0 + z * z).sqrt())
    }
}

/// Per quadrature wavelength: t and the linear-sRGB weights of a reflectance there under D65 of
/// luminance 1 (so that rho = 1 everywhere gives Y = 1).
struct Quadrature {
    t: Vec<f64>,
    w: Vec<[f64; 3]>,
}

/// The quadrature with midpoints every `step` nm ([`FINE_STEP`] or [`COARSE_STEP`]).
fn quadrature(step: f32) -> &'static Quadrature {
    static FINE: OnceLock<Quadrature> = OnceLock::new();
    static COARSE: OnceLock<Quadrature> = OnceLock::new();
    (if step == FINE_STEP { &FINE } else { &COARSE }).get_or_init(|| {
        let n = ((LAMBDA_MAX - LAMBDA_MIN) / step) as usize;
        let mut t = Vec::with_capacity(n);
        let mut xyz = Vec::with_capacity(n);
        let mut y_white = 0.0f64;
        for i in 0..n {
            let l = LAMBDA_MIN + (i as f32 + 0.5) * step;
            let e = cie::d65(l) as f64;
            let c = cie::cmf(l);
            t.push((l - LAMBDA_MIN) as f64 / RANGE);
            xyz.push(c.map(|v| v as f64 * e));
            y_white += c[1] as f64 * e;
        }
        let w = xyz
            .iter()
            .map(|v| {
                let v = v.map(|x| x / y_white);
                std::array::from_fn(|r| (0..3).map(|k| XYZ_TO_SRGB[r][k] as f64 * v[k]).sum())
            })
            .collect();
        Quadrature { t, w }
    })
}

/// Linear sRGB of the reflectance S(c . (t^2, t, 1)) under D65 of luminance 1, and its
/// Jacobian d rgb / d c.
fn rgb_and_jacobian(q: &Quadrature, c: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut rgb = [0.0; 3];
    let mut jac = [[0.0; 3]; 3];
    for (t, w) in q.t.iter().zip(&q.w) {
        let z = (c[0] * t + c[1]) * t + c[2];
        let s = sigmoid(z);
        let ds = 0.5 / (1.0 + z * z).powf(1.5);
        let dz = [t * t, *t, 1.0];
        for r in 0..3 {
            rgb[r] += s * w[r];
            for k in 0..3 {
                jac[r][k] += ds * dz[k] * w[r];
            }
        }
    }
    (rgb, jac)
}

/// Solves the 3 x 3 system a x = b (Cramer's rule); None when singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if d.abs() <= 1e-300 || !d.is_finite() {
        return None;
    }
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][k] = b[r];
        }
        *xk = det(m) / d;
    }
    Some(x)
}

/// Largest |rgb - target| component.
fn error(rgb: [f64; 3], target: [f64; 3]) -> f64 {
    (0..3).map(|k| (rgb[k] - target[k]).abs()).fold(0.0, f64::max)
}

/// Damped Newton iterations from `c` towards `target`; returns the coefficients and the
/// remaining error.
fn newton(q: &Quadrature, mut c: [f64; 3], target: [f64; 3], iterations: usize) -> ([f64; 3], f64) {
    let (mut rgb, mut jac) = rgb_and_jacobian(q, c);
    let mut err = error(rgb, target);
    for _ in 0..iterations {
        if err < 1e-9 {
            break;
        }
        let f = [rgb[0] - target[0], rgb[1] - target[1], rgb[2] - target[2]];
        let Some(step) = solve3(jac, f) else { break };
        let mut scale = 1.0;
        let mut improved = false;
        for _ in 0..12 {
            let trial = [c[0] - scale * step[0], c[1] - scale * step[1], c[2] - scale * step[2]];
            let (r, j) = rgb_and_jacobian(q, trial);
            let e = error(r, target);
            if e < err && trial.iter().all(|v| v.is_finite()) {
                (c, rgb, jac, err) = (trial, r, j, e);
                improved = true;
                break;
            }
            scale *= 0.5;
        }
        if !improved {
            break;
        }
    }
    (c, err)
}

/// The largest component error accepted from a fit.
pub const FIT_TOLERANCE: f64 = 1e-5;

/// The model whose reflectance under D65 has linear sRGB `rgb` (components in [0, 1]), fitted
/// from the flat grey of the same mean through intermediate colours (continuation keeps Newton's
/// method in its basin); None where no smooth reflectance of the model reaches the colour to
/// within [`FIT_TOLERANCE`] (colours at the edge of the cube: a reflectance cannot be fully
/// saturated and bounded by 1 at the same time).
pub fn fit(rgb: [f32; 3]) -> Option<SigmoidPolynomial> {
    fit_from(quadrature(FINE_STEP), rgb, None)
}

/// [`fit`] with quadrature `q`, Newton's method started at `start` (falling back to the
/// continuation from grey).
fn fit_from(q: &Quadrature, rgb: [f32; 3], start: Option<[f64; 3]>) -> Option<SigmoidPolynomial> {
    let target = rgb.map(|v| v as f64);
    if target.iter().any(|v| !v.is_finite() || *v < 0.0 || *v > 1.0) {
        return None;
    }
    let mut c = start.unwrap_or([0.0; 3]);
    let mut err = f64::INFINITY;
    if start.is_some() {
        (c, err) = newton(q, c, target, 20);
    }
    if err > FIT_TOLERANCE {
        let mean = (target[0] + target[1] + target[2]) / 3.0;
        let grey = mean.clamp(1e-4, 1.0 - 1e-4);
        // the flat reflectance of the grey: S(c2) = grey
        let z = (2.0 * grey - 1.0) / (1.0 - (2.0 * grey - 1.0).powi(2)).sqrt();
        c = [0.0, 0.0, z];
        const STEPS: usize = 8;
        for k in 1..=STEPS {
            let s = k as f64 / STEPS as f64;
            let t: [f64; 3] = std::array::from_fn(|i| grey + s * (target[i] - grey));
            (c, err) = newton(q, c, t, if k == STEPS { 50 } else { 12 });
        }
    }
    (err <= FIT_TOLERANCE && c.iter().all(|v| v.is_finite())).then(|| SigmoidPolynomial::new(c.map(|v| v as f32)))
}

/// The flat reflectance `v` (clamped to [1e-7, 1 - 1e-7]: the model's bounds are open).
fn flat(v: f64) -> SigmoidPolynomial {
    let x = 2.0 * v.clamp(1e-7, 1.0 - 1e-7) - 1.0;
    SigmoidPolynomial::new([0.0, 0.0, (x / (1.0 - x * x).sqrt()) as f32])
}

/// The model of `rgb` (components clamped to [0, 1]): [`fit`] where it succeeds; a grey (such
/// as white, which needs an infinite coefficient) as the flat spectrum; otherwise the fit of
/// the colour pulled towards its grey until it succeeds (bounded, smooth, the hue kept).
pub fn fit_or_nearest(rgb: [f32; 3]) -> SigmoidPolynomial {
    fit_or_nearest_with(quadrature(FINE_STEP), rgb, None)
}

fn fit_or_nearest_with(q: &Quadrature, rgb: [f32; 3], start: Option<[f64; 3]>) -> SigmoidPolynomial {
    let rgb = rgb.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 });
    if let Some(m) = fit_from(q, rgb, start) {
        return m;
    }
    let mean = (rgb[0] + rgb[1] + rgb[2]) / 3.0;
    if rgb.iter().all(|&v| (v - mean).abs() < 1e-6) {
        return flat(mean as f64);
    }
    let mut s = 1.0f32;
    for _ in 0..30 {
        s *= 0.97;
        let c = rgb.map(|v| mean + s * (v - mean));
        if let Some(m) = fit_from(q, c, None) {
            return m;
        }
    }
    flat(mean as f64)
}

/// Grid points per axis of [`RgbToSpectrumTable`].
pub const TABLE_RES: usize = 32;

/// Coefficients on a grid over the RGB cube, for colours that change per shading point.
/// Indexed by the largest component i: z = rgb\[i\] on a grid denser near 0 and 1, and
/// x, y = rgb[(i + 1) % 3] / z, rgb[(i + 2) % 3] / z on uniform grids.
pub struct RgbToSpectrumTable {
    z_nodes: [f32; TABLE_RES],
    /// [max component][z][y][x] coefficients.
    coeffs: Vec<[f32; 3]>,
}

impl RgbToSpectrumTable {
    fn index(i: usize, zi: usize, yi: usize, xi: usize) -> usize {
        ((i * TABLE_RES + zi) * TABLE_RES + yi) * TABLE_RES + xi
    }

    fn build() -> Self {
        let q = quadrature(COARSE_STEP);
        let smooth = |x: f32| x * x * (3.0 - 2.0 * x);
        let z_nodes: [f32; TABLE_RES] = std::array::from_fn(|k| smooth(smooth(k as f32 / (TABLE_RES - 1) as f32)));
        let mut coeffs = vec![[0.0f32; 3]; 3 * TABLE_RES * TABLE_RES * TABLE_RES];
        // the three largest-component tables in parallel
        std::thread::scope(|scope| {
            for (i, part) in coeffs.chunks_mut(TABLE_RES * TABLE_RES * TABLE_RES).enumerate() {
                scope.spawn(move || Self::build_part(q, &z_nodes, i, part));
            }
        });
        Self { z_nodes, coeffs }
    }

    /// Fits the coefficients of the sub-table of largest component `i` into `part`.
    fn build_part(q: &Quadrature, z_nodes: &[f32; TABLE_RES], i: usize, part: &mut [[f32; 3]]) {
        let index = |zi: usize, yi: usize, xi: usize| Self::index(0, zi, yi, xi);
        let coeffs = part;
        {
            for yi in 0..TABLE_RES {
                for xi in 0..TABLE_RES {
                    // along z from the middle outwards, each fit starting from its neighbour's
                    let mid = TABLE_RES / 5;
                    let mut prev: Option<[f64; 3]> = None;
                    let order: Vec<usize> = (mid..TABLE_RES).chain((0..mid).rev()).collect();
                    for (n, &zi) in order.iter().enumerate() {
                        if zi == mid - 1 {
                            prev = Some(coeffs[index(mid, yi, xi)].map(f64::from));
                        } else if n == 0 {
                            prev = None;
                        }
                        let z = z_nodes[zi];
                        let (x, y) = (xi as f32 / (TABLE_RES - 1) as f32, yi as f32 / (TABLE_RES - 1) as f32);
                        let mut rgb = [0.0f32; 3];
                        rgb[i] = z;
                        rgb[(i + 1) % 3] = x * z;
                        rgb[(i + 2) % 3] = y * z;
                        let m = fit_or_nearest_with(q, rgb, prev);
                        coeffs[index(zi, yi, xi)] = m.c;
                        prev = Some(m.c.map(f64::from));
                    }
                }
            }
        }
    }

    /// The table, built on first use (0.7 s on two cores).
    pub fn get() -> &'static Self {
        static T: OnceLock<RgbToSpectrumTable> = OnceLock::new();
        T.get_or_init(Self::build)
    }

    /// The model of `rgb` (components clamped to [0, 1]) by trilinear interpolation of the
    /// grid's coefficients.
    pub fn lookup(&self, rgb: [f32; 3]) -> SigmoidPolynomial {
        let rgb = rgb.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 });
        let i = if rgb[0] >= rgb[1] && rgb[0] >= rgb[2] {
            0
        } else if rgb[1] >= rgb[2] {
            1
        } else {
            2
        };
        let z = rgb[i];
        if z <= 0.0 {
            return SigmoidPolynomial::new(self.coeffs[Self::index(i, 0, 0, 0)]);
        }
        let scale = (TABLE_RES - 1) as f32 / z;
        let x = rgb[(i + 1) % 3] * scale;
        let y = rgb[(i + 2) % 3] * scale;
        let xi = (x as usize).min(TABLE_RES - 2);
        let yi = (y as usize).min(TABLE_RES - 2);
        let zi = self.z_nodes.partition_point(|&n| n <= z).clamp(1, TABLE_RES - 1) - 1;
        let (dx, dy) = (x - xi as f32, y - yi as f32);
        let dz = (z - self.z_nodes[zi]) / (self.z_nodes[zi + 1] - self.z_nodes[zi]);
        let mut c = [0.0f32; 3];
        for (oz, wz) in [(0, 1.0 - dz), (1, dz)] {
            for (oy, wy) in [(0, 1.0 - dy), (1, dy)] {
                for (ox, wx) in [(0, 1.0 - dx), (1, dx)] {
                    let v = self.coeffs[Self::index(i, zi + oz, yi + oy, xi + ox)];
                    for k in 0..3 {
                        c[k] += wz * wy * wx * v[k];
                    }
                }
            }
        }
        SigmoidPolynomial::new(c)
    }
}

/// Linear sRGB of a reflectance `rho` under D65 of luminance 1, integrated independently of the
/// fit (0.1 nm midpoints): what the sensor sees.
pub fn reflectance_rgb(rho: impl Fn(f32) -> f32) -> [f64; 3] {
    let (mut xyz, mut y_white) = ([0.0f64; 3], 0.0f64);
    let n = ((LAMBDA_MAX - LAMBDA_MIN) * 10.0) as usize;
    for i in 0..n {
        let l = LAMBDA_MIN + (i as f32 + 0.5) * 0.1;
        let (e, c) = (cie::d65(l) as f64, cie::cmf(l));
        let s = rho(l) as f64;
        for k in 0..3 {
            xyz[k] += s * e * c[k] as f64;
        }
        y_white += e * c[1] as f64;
    }
    std::array::from_fn(|r| (0..3).map(|k| XYZ_TO_SRGB[r][k] as f64 * xyz[k] / y_white).sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip_error(rgb: [f32; 3], m: &SigmoidPolynomial) -> f64 {
        let back = reflectance_rgb(|l| m.eval(l));
        (0..3).map(|k| (back[k] - rgb[k] as f64).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn the_issue_colour_round_trips() {
        let rgb = [0.2, 0.8, 0.2];
        let m = fit(rgb).expect("fits");
        assert!(round_trip_error(rgb, &m) < 1e-5, "{:?}", reflectance_rgb(|l| m.eval(l)));
        for l in (360..=830).step_by(10) {
            let v = m.eval(l as f32);
            assert!(v > 0.0 && v < 1.0);
        }
    }

    /// The round trip over the RGB cube (grid step 0.1, white included): the colour of every
    /// uplift under D65, integrated independently of the fit, is within 1e-3 of the RGB (in fact
    /// 3e-5), and the interpolated table within 7e-3.
    #[test]
    fn uplift_round_trips_over_the_rgb_cube() {
        let table = RgbToSpectrumTable::get();
        let (mut worst, mut worst_table) = (0.0f64, 0.0f64);
        for r in 0..=10 {
            for g in 0..=10 {
                for b in 0..=10 {
                    let rgb = [r as f32 / 10.0, g as f32 / 10.0, b as f32 / 10.0];
                    worst = worst.max(round_trip_error(rgb, &fit_or_nearest(rgb)));
                    worst_table = worst_table.max(round_trip_error(rgb, &table.lookup(rgb)));
                }
            }
        }
        eprintln!("largest round-trip error: fitted {worst:e}, table {worst_table:e}");
        assert!(worst < 1e-3, "{worst}");
        assert!(worst_table < 7e-3, "{worst_table}");
    }

    #[test]
    fn grey_is_nearly_flat() {
        let m = fit([0.5; 3]).unwrap();
        for l in (380..=780).step_by(20) {
            assert!((m.eval(l as f32) - 0.5).abs() < 0.01, "{l}: {}", m.eval(l as f32));
        }
    }
}
