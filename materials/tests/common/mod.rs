//! Shared helpers of the statistical BSDF tests: a seeded generator, spherical quadrature, the
//! chi-square goodness-of-fit test with pooling, and the chi-square survival function.
#![allow(dead_code)]

use std::f64::consts::{PI, TAU};

use glam::{Vec2, Vec3};
use quasar_materials::{Bsdf, TransportMode};

/// SplitMix64 (Steele, Lea & Flood 2014): a small, fixed-seed generator for reproducible tests.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// Next uniform f32 in [0, 1) (24 random bits).
    pub fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }
}

/// Unit direction with cos(theta) = `cos_theta`, in the xz plane.
pub fn dir(cos_theta: f32) -> Vec3 {
    Vec3::new((1.0 - cos_theta * cos_theta).max(0.0).sqrt(), 0.0, cos_theta)
}

/// Direction of spherical coordinates (theta, phi).
fn spherical(theta: f64, phi: f64) -> Vec3 {
    Vec3::new((theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32)
}

/// A (theta, phi) grid over the whole sphere: theta in [0, pi] (the horizon is a bin edge when
/// `n_theta` is even), phi in [0, 2 pi).
pub struct SphereGrid {
    /// Bins in theta.
    pub n_theta: usize,
    /// Bins in phi.
    pub n_phi: usize,
}

impl SphereGrid {
    /// Number of bins.
    pub fn len(&self) -> usize {
        self.n_theta * self.n_phi
    }

    /// Bin index of a direction.
    pub fn bin(&self, w: Vec3) -> usize {
        let theta = f64::from(w.z.clamp(-1.0, 1.0)).acos();
        let mut phi = f64::from(w.y).atan2(f64::from(w.x));
        if phi < 0.0 {
            phi += TAU;
        }
        let i = ((theta / PI * self.n_theta as f64) as usize).min(self.n_theta - 1);
        let j = ((phi / TAU * self.n_phi as f64) as usize).min(self.n_phi - 1);
        i * self.n_phi + j
    }

    /// Integral of `f` over bin (i, j) (solid angle measure): composite 3-point Gauss–Legendre
    /// with `sub` intervals per dimension. The nodes are interior, so a density that jumps at a
    /// bin edge (the horizon) is integrated on the correct side only. Also reports whether `f`
    /// was zero at some node and whether it was positive at some node.
    fn integrate_bin(&self, i: usize, j: usize, sub: usize, f: &impl Fn(Vec3) -> f64) -> (f64, bool, bool) {
        const X: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4]; // -sqrt(3/5), 0, sqrt(3/5)
        const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
        let (dt, dp) = (PI / self.n_theta as f64, TAU / self.n_phi as f64);
        let nodes = |start: f64, h: f64| {
            (0..sub).flat_map(move |k| (0..3).map(move |q| (start + h * (k as f64 + 0.5 + 0.5 * X[q]), 0.5 * h * W[q])))
        };
        let (mut s, mut zero, mut positive) = (0.0, false, false);
        for (theta, wt) in nodes(i as f64 * dt, dt / sub as f64) {
            let st = theta.sin();
            for (phi, wp) in nodes(j as f64 * dp, dp / sub as f64) {
                let v = f(spherical(theta, phi));
                if v > 0.0 {
                    positive = true;
                } else {
                    zero = true;
                }
                s += wt * wp * st * v;
            }
        }
        (s, zero, positive)
    }

    /// Integral of `f` over each bin. Bins that a support boundary (a jump from 0) may cross,
    /// i.e. with zero and positive nodes, or positive nodes next to a bin with zero nodes on the
    /// same side of the horizon, use 16 x 16 intervals: there successive estimates can agree by
    /// chance. Other bins are refined (doubling the intervals from 1 up to 32 per dimension)
    /// until two successive estimates agree to 1e-4 relative (or 1e-8 absolute).
    pub fn integrate(&self, f: impl Fn(Vec3) -> f64) -> Vec<f64> {
        let (nt, np) = (self.n_theta as isize, self.n_phi as isize);
        let coarse: Vec<(f64, bool, bool)> =
            (0..self.len()).map(|b| self.integrate_bin(b / self.n_phi, b % self.n_phi, 1, &f)).collect();
        let zero_near = |i: isize, j: isize| {
            (-1..=1).any(|di| {
                let k = i + di;
                (0..nt).contains(&k)
                    && (k < nt / 2) == (i < nt / 2)
                    && (-1..=1).any(|dj| coarse[(k * np + (j + dj).rem_euclid(np)) as usize].1)
            })
        };
        let mut out = vec![0.0; self.len()];
        for (b, &(first, zero, positive)) in coarse.iter().enumerate() {
            let (i, j) = (b / self.n_phi, b % self.n_phi);
            if positive && (zero || zero_near(i as isize, j as isize)) {
                out[b] = self.integrate_bin(i, j, 16, &f).0;
                continue;
            }
            let (mut sub, mut prev) = (1, first);
            while sub < 32 {
                sub *= 2;
                let (next, z, p) = self.integrate_bin(i, j, sub, &f);
                if z && p {
                    prev = self.integrate_bin(i, j, 16.max(sub), &f).0;
                    break;
                }
                let converged = (next - prev).abs() <= 1e-4 * next.abs() + 1e-8;
                prev = next;
                if converged {
                    break;
                }
            }
            out[b] = prev;
        }
        out
    }
}

/// Integral of `f` over the sphere (solid angle), adaptive per bin of a 20 x 40 grid.
pub fn integrate_sphere(f: impl Fn(Vec3) -> f64) -> f64 {
    SphereGrid { n_theta: 20, n_phi: 40 }.integrate(f).iter().sum()
}

/// ln Gamma(x) for x > 0: recurrence up to x >= 10, then Stirling's series to 1/x^7.
pub fn ln_gamma(mut x: f64) -> f64 {
    let mut shift = 0.0;
    while x < 10.0 {
        shift -= x.ln();
        x += 1.0;
    }
    let x2 = x * x;
    let series =
        1.0 / (12.0 * x) - 1.0 / (360.0 * x * x2) + 1.0 / (1260.0 * x * x2 * x2) - 1.0 / (1680.0 * x * x2 * x2 * x2);
    shift + (x - 0.5) * x.ln() - x + 0.5 * TAU.ln() + series
}

/// Regularised upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a): power series of P for
/// x < a + 1, else the continued fraction of Q (modified Lentz).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (1.0 - sum * log_prefactor.exp()).clamp(0.0, 1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            d = if d.abs() < tiny { tiny } else { d };
            c = b + an / c;
            c = if c.abs() < tiny { tiny } else { c };
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (log_prefactor.exp() * h).clamp(0.0, 1.0)
    }
}

/// Outcome of a chi-square test.
#[derive(Debug)]
pub struct Chi2 {
    /// The statistic.
    pub stat: f64,
    /// Degrees of freedom (cells after pooling - 1).
    pub dof: usize,
    /// P-value: probability of a statistic at least this large if the sampler matches the pdf.
    pub p: f64,
}

/// Pearson's chi-square test of observed against expected counts. Cells expecting fewer than 5
/// are pooled into one cell; if the pool still expects fewer than 5 it joins the smallest cell.
pub fn chi2(observed: &[f64], expected: &[f64]) -> Chi2 {
    let mut cells: Vec<(f64, f64)> = Vec::new();
    let mut pool = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pool.0 += o;
            pool.1 += e;
        } else {
            cells.push((o, e));
        }
    }
    if pool.1 >= 5.0 {
        cells.push(pool);
    } else if pool.0 > 0.0 || pool.1 > 0.0 {
        let k = (0..cells.len()).min_by(|&a, &b| cells[a].1.total_cmp(&cells[b].1)).expect("no cell expects 5 samples");
        cells[k].0 += pool.0;
        cells[k].1 += pool.1;
    }
    let stat: f64 = cells.iter().map(|&(o, e)| (o - e) * (o - e) / e).sum();
    let dof = cells.len().saturating_sub(1).max(1);
    Chi2 { stat, dof, p: gamma_q(dof as f64 / 2.0, stat / 2.0) }
}

/// Per-test significance so that `n_tests` independent tests together reject a correct
/// sampler with probability 0.01 (Sidak correction).
pub fn sidak(n_tests: usize) -> f64 {
    1.0 - 0.99f64.powf(1.0 / n_tests as f64)
}

/// Goodness of fit of `sample` (uc, u -> direction or None) against the density `pdf` with
/// `n` samples on a 40 x 80 (theta, phi) grid; failed samples form one more cell that expects
/// n (1 - integral of pdf).
pub fn chi2_directions(
    n: usize,
    seed: u64,
    sample: impl Fn(f32, Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
) -> Chi2 {
    let grid = SphereGrid { n_theta: 40, n_phi: 80 };
    let mut obs = vec![0.0; grid.len() + 1];
    let mut rng = SplitMix(seed);
    for _ in 0..n {
        let uc = rng.next_f32();
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        match sample(uc, u) {
            Some(w) => obs[grid.bin(w)] += 1.0,
            None => obs[grid.len()] += 1.0,
        }
    }
    let mut exp: Vec<f64> = grid.integrate(pdf).into_iter().map(|p| p * n as f64).collect();
    let total: f64 = exp.iter().sum();
    exp.push((n as f64 - total).max(0.0));
    chi2(&obs, &exp)
}

/// Chi-square test of a BSDF's `sample_f` against its own `pdf` for outgoing direction `wo`.
pub fn chi2_bsdf(b: &Bsdf, wo: Vec3, n: usize, seed: u64) -> Chi2 {
    let mode = TransportMode::Radiance;
    chi2_directions(
        n,
        seed,
        |uc, u| {
            let s = b.sample_f(wo, uc, u, mode)?;
            assert!(!s.specular && s.pdf > 0.0 && s.f.is_finite());
            Some(s.wi)
        },
        |wi| f64::from(b.pdf(wo, wi, mode)),
    )
}
