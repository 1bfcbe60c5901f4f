//! Measuring the `[[sensor]]`s of a scene (docs/photometry.md): every meter's illuminance in lux,
//! E_v = 683 lm/W x integral of E ybar = 72 983 x Y(E), with its standard error, and the
//! lighting-practice statistics of each sensor (Emin, Eavg, Emax, uniformities U0 = Emin/Eavg
//! and Emin/Emax), written as CSV.

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
    /// Meter positions (metres).
    pub points: Vec<Vec3>,
    /// The meters' normal.
    pub normal: Vec3,
    /// Illuminance per meter (lx).
    pub lux: Vec<f64>,
    /// Standard error of each value (lx).
    pub stderr: Vec<f64>,
    /// Samples per meter.
    pub samples: u32,
    /// What the meters measure.
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
        let min = self.lux.iter().copied().fold(f64::INFINITY, f64::min);
        let max = self.lux.iter().copied().fold(0.0, f64::max);
        let avg = self.lux.iter().sum::<f64>() / self.lux.len().max(1) as f64;
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        SensorStats { min, avg, max, u0: ratio(min, avg), min_over_max: ratio(min, max) }
    }

    /// The CSV: `#` header lines (name, normal, samples, the statistics), then
    /// `x_m,y_m,z_m,E_lx,stderr_lx` per meter.
    pub fn csv(&self) -> String {
        let s = self.stats();
        let n = self.normal;
        let what = match self.quantity {
            SensorQuantity::Planar => format!("illuminance (lx) on meters with normal ({}, {}, {})", n.x, n.y, n.z),
            SensorQuantity::Cylindrical => "cylindrical illuminance (lx, vertical axis +Y)".to_string(),
            SensorQuantity::SemiCylindrical { facing: f } => {
                format!("semi-cylindrical illuminance (lx, vertical axis +Y, facing ({}, {}, {}))", f.x, f.y, f.z)
            }
        };
        let mut out = format!("# quasar sensor {}: {what}, {} samples each\n", self.name, self.samples);
        out += &format!(
            "# Emin {:.4} lx, Eavg {:.4} lx, Emax {:.4} lx, U0 = Emin/Eavg {:.4}, Emin/Emax {:.4}\n",
            s.min, s.avg, s.max, s.u0, s.min_over_max
        );
        out += "x_m,y_m,z_m,E_lx,stderr_lx\n";
        for ((p, e), se) in self.points.iter().zip(&self.lux).zip(&self.stderr) {
            out += &format!("{},{},{},{e:.6},{se:.6}\n", p.x, p.y, p.z);
        }
        out
    }

    /// One line for the terminal.
    pub fn summary(&self) -> String {
        let s = self.stats();
        format!(
            "sensor {}: {} meter{}, Emin {:.1} lx, Eavg {:.1} lx, Emax {:.1} lx, U0 {:.3}",
            self.name,
            self.points.len(),
            if self.points.len() == 1 { "" } else { "s" },
            s.min,
            s.avg,
            s.max,
            s.u0
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
