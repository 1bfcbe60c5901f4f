//! Measuring the `[[sensor]]`s of a scene (docs/photometry.md): every meter's illuminance in lux,
//! E_v = 683 lm/W x integral of E ybar = 72 983 x Y(E), with its standard error, and the
//! lighting-practice statistics of each sensor (Emin, Eavg, Emax, uniformities U0 = Emin/Eavg
//! and Emin/Emax) with their standard errors, written as CSV.

use glam::Vec3;
use quasar_importers::photometric::LUMINANCE_PER_Y;
use quasar_importers::{SensorDesc, SensorQuantity};
use quasar_materials::spectrum::SampledWavelengths;
use rayon::prelude::*;

use crate::core::sampling::Sampler;
use crate::core::scene::Scene;
use crate::integrator::illuminance::illuminance_sample;

/// What one sensor measured.
#[derive(Clone, Debug)]
pub struct SensorReading {
    /// The sensor's name.
    pub name: String,
    /// Measuring points (metres).
    pub points: Vec<Vec3>,
    /// The points' normal (planar illuminance).
    pub normal: Vec3,
    /// Illuminance per point (lx).
    pub lux: Vec<f64>,
    /// Standard error of each value (lx).
    pub stderr: Vec<f64>,
    /// Samples per point.
    pub samples: u32,
    /// What the points measure.
    pub quantity: SensorQuantity,
}

/// Emin, Eavg, Emax (lx) and the uniformities Emin/Eavg (U0) and Emin/Emax.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorStats {
    /// Smallest value.
    pub min: f64,
    /// Mean value.
    pub avg: f64,
    /// Largest value.
    pub max: f64,
    /// Emin / Eavg (0 when Eavg is 0).
    pub u0: f64,
    /// Emin / Emax (0 when Emax is 0).
    pub min_over_max: f64,
}

impl SensorStats {
    /// The statistics of `values` (lx).
    pub fn of(values: &[f64]) -> Self {
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let max = values.iter().copied().fold(0.0, f64::max);
        let avg = values.iter().sum::<f64>() / values.len().max(1) as f64;
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        Self { min, avg, max, u0: ratio(min, avg), min_over_max: ratio(min, max) }
    }
}

/// Draws of the parametric bootstrap behind [`SensorReading::stats_stderr`].
const BOOTSTRAP_DRAWS: u32 = 400;

/// Measures `sensor` in `scene` (meters in parallel; meter k, sample s uses the random numbers
/// of `(seed, k, s)`).
pub fn measure(scene: &Scene, sensor: &SensorDesc, seed: u64) -> SensorReading {
    let points = sensor.points();
    let n = sensor.samples.max(1);
    let (lux, stderr): (Vec<f64>, Vec<f64>) = points
        .par_iter()
        .enumerate()
        .map(|(k, &p)| {
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for s in 0..n {
                let v = lux_sample(scene, p, None, Sampler::new(seed, k as u64, u64::from(s)), |sampler| {
                    match sensor.quantity {
                        SensorQuantity::Planar => sensor.normal,
                        // the mean over horizontal normals of the vertical illuminance
                        SensorQuantity::Cylindrical => {
                            let phi = 2.0 * std::f32::consts::PI * sampler.get_1d();
                            Vec3::new(phi.cos(), 0.0, phi.sin())
                        }
                        // the mean over the half-cylinder's normals, cos(psi) facing + sin(psi)
                        // side with psi uniform in [-pi/2, pi/2], of the vertical illuminance
                        SensorQuantity::SemiCylindrical { facing } => {
                            let psi = std::f32::consts::PI * (sampler.get_1d() - 0.5);
                            psi.cos() * facing + psi.sin() * Vec3::Y.cross(facing)
                        }
                    }
                });
                sum += v;
                sum2 += v * v;
            }
            let mean = sum / f64::from(n);
            let var = (sum2 / f64::from(n) - mean * mean).max(0.0) / f64::from((n - 1).max(1));
            (mean, var.sqrt())
        })
        .unzip();
    SensorReading {
        name: sensor.name.clone(),
        points,
        normal: sensor.normal,
        lux,
        stderr,
        samples: n,
        quantity: sensor.quantity,
    }
}

/// One sample of the illuminance (lx) at `p` (rounding bound `p_err`, None in free space) on the
/// plane whose normal `normal` picks (after the wavelengths, from the same `sampler`); 0 for a
/// non-finite sample.
fn lux_sample(
    scene: &Scene,
    p: Vec3,
    p_err: Option<Vec3>,
    mut sampler: Sampler,
    normal: impl FnOnce(&mut Sampler) -> Vec3,
) -> f64 {
    let mut wl = SampledWavelengths::sample_visible(sampler.get_1d());
    let n = normal(&mut sampler);
    let e = illuminance_sample(scene, p, p_err, n, &mut wl, &mut sampler);
    let v = f64::from(wl.luminance(e) * LUMINANCE_PER_Y);
    if v.is_finite() { v } else { 0.0 }
}

impl SensorReading {
    /// The statistics of the values.
    pub fn stats(&self) -> SensorStats {
        SensorStats::of(&self.lux)
    }

    /// The standard error of each statistic, by a parametric bootstrap: the statistics of
    /// [`BOOTSTRAP_DRAWS`] readings whose every point is drawn from a normal distribution of the
    /// point's value and standard error (independent points: each has its own samples), and
    /// their standard deviation over the draws. Emin and Emax are order statistics, so where
    /// several points lie within their errors of the minimum the spread also says how much the
    /// noise picks the smallest one (deterministic: the draws' random numbers are fixed).
    pub fn stats_stderr(&self) -> SensorStats {
        let mut draws: Vec<SensorStats> = Vec::with_capacity(BOOTSTRAP_DRAWS as usize);
        let mut values = vec![0.0; self.lux.len()];
        for d in 0..BOOTSTRAP_DRAWS {
            for (k, ((v, &e), &se)) in values.iter_mut().zip(&self.lux).zip(&self.stderr).enumerate() {
                let mut sampler = Sampler::new(0x5e45_57a7, k as u64, u64::from(d));
                let [u1, u2] = sampler.get_2d().to_array().map(f64::from);
                // Box-Muller, u1 kept away from 0
                let g = (-2.0 * (1.0 - u1).max(1e-300).ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
                *v = (e + se * g).max(0.0);
            }
            draws.push(SensorStats::of(&values));
        }
        let sd = |f: fn(&SensorStats) -> f64| {
            let n = draws.len() as f64;
            let mean = draws.iter().map(f).sum::<f64>() / n;
            (draws.iter().map(|s| (f(s) - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
        };
        SensorStats {
            min: sd(|s| s.min),
            avg: sd(|s| s.avg),
            max: sd(|s| s.max),
            u0: sd(|s| s.u0),
            min_over_max: sd(|s| s.min_over_max),
        }
    }

    /// The CSV: `#` header lines (name, normal, samples, the statistics with their standard
    /// errors), then `x_m,y_m,z_m,E_lx,stderr_lx` per point.
    pub fn csv(&self) -> String {
        let (s, e) = (self.stats(), self.stats_stderr());
        let n = self.normal;
        let what = match self.quantity {
            SensorQuantity::Planar => format!("illuminance (lx) at points with normal ({}, {}, {})", n.x, n.y, n.z),
            SensorQuantity::Cylindrical => "cylindrical illuminance (lx, vertical axis +Y)".to_string(),
            SensorQuantity::SemiCylindrical { facing: f } => {
                format!("semi-cylindrical illuminance (lx, vertical axis +Y, facing ({}, {}, {}))", f.x, f.y, f.z)
            }
        };
        let mut out = format!(
            "# quasar sensor {}: {what}, {} point{}, {} samples each\n",
            self.name,
            self.points.len(),
            if self.points.len() == 1 { "" } else { "s" },
            self.samples
        );
        out += &format!(
            "# Emin {:.4} +- {:.4} lx, Eavg {:.4} +- {:.4} lx, Emax {:.4} +- {:.4} lx, U0 = Emin/Eavg {:.4} +- {:.4}, Emin/Emax {:.4} +- {:.4} (+- one standard error)\n",
            s.min, e.min, s.avg, e.avg, s.max, e.max, s.u0, e.u0, s.min_over_max, e.min_over_max
        );
        out += "x_m,y_m,z_m,E_lx,stderr_lx\n";
        for ((p, e), se) in self.points.iter().zip(&self.lux).zip(&self.stderr) {
            out += &format!("{},{},{},{e:.6},{se:.6}\n", p.x, p.y, p.z);
        }
        out
    }

    /// One line for the terminal.
    pub fn summary(&self) -> String {
        let (s, e) = (self.stats(), self.stats_stderr());
        format!(
            "sensor {}: {} point{}, Emin {:.1} +- {:.1} lx, Eavg {:.1} +- {:.1} lx, Emax {:.1} +- {:.1} lx, U0 {:.3} +- {:.3}",
            self.name,
            self.points.len(),
            if self.points.len() == 1 { "" } else { "s" },
            s.min,
            e.min,
            s.avg,
            e.avg,
            s.max,
            e.max,
            s.u0,
            e.u0
        )
    }
}

/// The `illuminance.Y` layer and its standard errors: the illuminance (lx) at the first surface
/// each camera ray hits, on the side facing the camera (the geometric normal turned towards the
/// eye), averaged over `samples` rays jittered over the pixel as the beauty's are (0 for a ray
/// that hits nothing), one sample of the sensor estimator each; and the standard error of that
/// mean, sqrt(s^2 / n) from the samples' variance (position within the pixel and light
/// sampling). A meter there sees the light the surface receives, the surface itself being no
/// obstacle to the half-space above it. Render share `shard` = (K, N) takes the global samples
/// K + N j below `samples` (as the per-pixel methods do), so that `quasar merge` of the shards
/// pools them into the full layer; the count it took is returned with the channels.
pub fn illuminance_pass(
    scene: &Scene,
    camera: &crate::core::camera::Camera,
    samples: u32,
    seed: u64,
    shard: (u32, u32),
) -> (Vec<f32>, Vec<f32>, u32) {
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    let (k, shards) = (shard.0, shard.1.max(1));
    let n = samples.saturating_sub(k).div_ceil(shards);
    let (mean, stderr) = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for j in 0..n {
                let s = k + shards * j;
                let mut sampler = Sampler::new(seed ^ 0x111u64, i as u64, u64::from(s));
                let jitter = sampler.get_2d();
                let ray = camera.ray(glam::Vec2::new((i % w) as f32, (i / w) as f32) + jitter);
                let Some(si) = scene.intersect(&ray) else { continue };
                let normal = if si.ng.dot(ray.dir) > 0.0 { -si.ng } else { si.ng };
                let v = lux_sample(scene, si.p, Some(si.p_err), sampler, |_| normal);
                sum += v;
                sum2 += v * v;
            }
            let nf = f64::from(n.max(1));
            let mean = sum / nf;
            let var = if n > 1 { ((sum2 - sum * mean) / (nf - 1.0)).max(0.0) } else { 0.0 };
            (mean as f32, (var / nf).sqrt() as f32)
        })
        .unzip();
    (mean, stderr, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(lux: Vec<f64>, stderr: Vec<f64>) -> SensorReading {
        SensorReading {
            name: "grid".into(),
            points: vec![Vec3::ZERO; lux.len()],
            normal: Vec3::Y,
            lux,
            stderr,
            samples: 64,
            quantity: SensorQuantity::Planar,
        }
    }

    /// The bootstrap's standard errors match the first-order ones where those are known: Eavg's
    /// is sqrt(sum se^2) / N; with one point far below the others, Emin's is that point's and
    /// U0's about se_min / Eavg. Exact values have none.
    #[test]
    fn statistics_carry_their_standard_errors() {
        let mut lux = vec![100.0; 50];
        let mut se = vec![2.0; 50];
        lux[7] = 40.0;
        se[7] = 1.0;
        let r = reading(lux, se);
        let (s, e) = (r.stats(), r.stats_stderr());
        let avg_se = (49.0 * 4.0 + 1.0f64).sqrt() / 50.0;
        assert!((e.avg / avg_se - 1.0).abs() < 0.12, "{} vs {avg_se}", e.avg);
        assert!((e.min - 1.0).abs() < 0.12, "{}", e.min);
        assert!((e.u0 / (1.0 / s.avg) - 1.0).abs() < 0.15, "{} vs {}", e.u0, 1.0 / s.avg);
        // the largest of 49 standard normals has a standard deviation of 0.466
        assert!((e.max / (0.466 * 2.0) - 1.0).abs() < 0.12, "{}", e.max);
        let exact = reading(vec![3.0, 5.0], vec![0.0, 0.0]).stats_stderr();
        assert_eq!((exact.min, exact.avg, exact.max, exact.u0), (0.0, 0.0, 0.0, 0.0));
        let csv = r.csv();
        assert!(csv.contains("50 points") && csv.contains("U0 = Emin/Eavg") && csv.contains(" +- "), "{csv}");
        assert!(r.summary().contains("50 points, Emin 40.0 +- 1.0 lx"), "{}", r.summary());
    }
}
