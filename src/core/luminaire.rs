//! A point luminaire with a measured intensity distribution (IES / EULUMDAT photometric web,
//! docs/photometry.md): radiant intensity I(w, lambda) = scale * spectrum(lambda) * I_v(w), with
//! I_v the web's candela towards w in the luminaire's frame. Photons leave by importance
//! sampling a 1-degree grid over the sphere whose cell weights bound the interpolated
//! distribution, mixed with 2% uniform directions so that every direction with light has a
//! density (the estimator is unbiased whatever the table holds).
//!
//! With a luminous opening (near field) the light leaves from a point x uniform over the
//! opening with the same distribution, radiance L(x, w) = I(w) / (A |cos theta|): next-event
//! estimation at p takes I(w_x) / |x - p|^2 towards a uniform x, the mean over the opening of
//! the point formula, which is the opening's exact illuminance (E = integral_A L cos theta_p
//! cos theta_x / d^2 dA = E_x[I(w_x) cos theta_p / d_x^2]); photons start at a uniform x. The
//! opening is not geometry: camera rays do not see it and it blocks nothing.

use std::f32::consts::PI;
use std::sync::Arc;

use glam::{Mat3, Vec2, Vec3};
use quasar_importers::LuminousOpening;
use quasar_importers::photometry::PhotometricWeb;
use quasar_materials::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

use crate::core::sampling::{self, Distribution1D};

/// Rows (polar angle from the nadir) and columns (azimuth) of the sampling grid.
const GRID: (usize, usize) = (180, 360);
/// Share of photon directions drawn uniformly over the sphere.
const UNIFORM_SHARE: f32 = 0.02;

/// A luminaire placed in the scene.
#[derive(Clone, Debug)]
pub struct Luminaire {
    /// Photometric centre.
    pub position: Vec3,
    /// Luminaire frame -> world (orthonormal columns: C0, C90, up).
    pub frame: Mat3,
    /// The intensity distribution (cd).
    pub web: Arc<PhotometricWeb>,
    /// Spectral shape (luminance 1).
    pub spectrum: Spectrum,
    /// Radiometric intensity per candela and unit spectrum (W/(sr nm) per cd).
    pub scale: f32,
    /// The web's luminous flux (lm), by quadrature.
    pub flux_lm: f64,
    /// Where the light leaves (the photometric centre or a luminous opening).
    pub opening: LuminousOpening,
    rows: Distribution1D,
    cols: Vec<Distribution1D>,
}

impl Luminaire {
    /// Places `web` at `position` with the luminaire frame `frame` (columns C0, C90, up) and
    /// builds its photon distribution.
    pub fn new(position: Vec3, frame: Mat3, web: Arc<PhotometricWeb>, spectrum: Spectrum, scale: f32) -> Self {
        let (nt, np) = GRID;
        let mut cols = Vec::with_capacity(nt);
        let mut row_w = Vec::with_capacity(nt);
        for i in 0..nt {
            let (t0, t1) = (i as f32 * PI / nt as f32, (i + 1) as f32 * PI / nt as f32);
            let omega = (t0.cos() - t1.cos()) * 2.0 * PI / np as f32;
            let w: Vec<f64> = (0..np)
                .map(|j| {
                    let (p0, p1) = (j as f32 * 2.0 * PI / np as f32, (j + 1) as f32 * 2.0 * PI / np as f32);
                    let mut m = 0.0f32;
                    for t in [t0, 0.5 * (t0 + t1), t1] {
                        for p in [p0, 0.5 * (p0 + p1), p1] {
                            m = m.max(web.intensity(polar(t.cos(), p)));
                        }
                    }
                    f64::from(m * omega)
                })
                .collect();
            row_w.push(w.iter().sum());
            cols.push(Distribution1D::new(&w));
        }
        let flux_lm = web.flux();
        Self {
            position,
            frame,
            web,
            spectrum,
            scale,
            flux_lm,
            opening: LuminousOpening::Point,
            rows: Distribution1D::new(&row_w),
            cols,
        }
    }

    /// This luminaire with its light leaving from `opening`.
    pub fn with_opening(mut self, opening: LuminousOpening) -> Self {
        self.opening = opening;
        self
    }

    /// A point where light leaves, uniform over the opening (the photometric centre for a point
    /// luminaire), from two uniform numbers.
    #[inline]
    pub fn emission_point(&self, u: Vec2) -> Vec3 {
        let local = match self.opening {
            LuminousOpening::Point => return self.position,
            LuminousOpening::Rect { c0, c90 } => Vec2::new((u.x - 0.5) * c0, (u.y - 0.5) * c90),
            LuminousOpening::Disk { diameter } => quasar_materials::warp::concentric_disk(u) * (0.5 * diameter),
        };
        self.position + self.frame.x_axis * local.x + self.frame.y_axis * local.y
    }

    /// Candela towards the world direction `w` (unit) leaving the luminaire.
    #[inline]
    pub fn candela(&self, w: Vec3) -> f32 {
        self.web.intensity(self.frame.transpose() * w)
    }

    /// Radiant intensity towards `w` at the sampled wavelengths (W/(sr nm)).
    #[inline]
    pub fn intensity(&self, w: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.spectrum.sample(wl) * (self.scale * self.candela(w))
    }

    /// Emitted power for light selection (W/nm, spectrally averaged).
    pub fn power(&self) -> f32 {
        (f64::from(self.scale * self.spectrum.mean_value()) * self.flux_lm) as f32
    }

    /// Solid-angle density of a photon direction `local` (luminaire frame, unit).
    pub fn pdf_local(&self, local: Vec3) -> f32 {
        let (nt, np) = GRID;
        let uniform = UNIFORM_SHARE * sampling::UNIFORM_SPHERE_PDF;
        let t = (-local.z).clamp(-1.0, 1.0).acos();
        let i = ((t / PI * nt as f32) as usize).min(nt - 1);
        let p = local.y.atan2(local.x).rem_euclid(2.0 * PI);
        let j = ((p / (2.0 * PI) * np as f32) as usize).min(np - 1);
        let (t0, t1) = (i as f32 * PI / nt as f32, (i + 1) as f32 * PI / nt as f32);
        let omega = (t0.cos() - t1.cos()) * 2.0 * PI / np as f32;
        let cell = self.rows.pmf(i) * self.cols[i].pmf(j);
        (1.0 - UNIFORM_SHARE) * cell / omega + uniform
    }

    /// A photon direction (world) and its density, from two uniform numbers.
    pub fn sample_direction(&self, u: Vec2) -> Option<(Vec3, f32)> {
        let local = if u.x < UNIFORM_SHARE || self.rows.total() <= 0.0 {
            sampling::uniform_sphere(Vec2::new((u.x / UNIFORM_SHARE).min(1.0 - f32::EPSILON), u.y))
        } else {
            let ux = (u.x - UNIFORM_SHARE) / (1.0 - UNIFORM_SHARE);
            let (nt, np) = GRID;
            let (i, _, r) = self.rows.sample_remapped(ux)?;
            let (j, _, s) = self.cols[i].sample_remapped(u.y)?;
            let (t0, t1) = (i as f32 * PI / nt as f32, (i + 1) as f32 * PI / nt as f32);
            // uniform in solid angle within the cell
            let cos_t = t0.cos() + r * (t1.cos() - t0.cos());
            let p = (j as f32 + s) * 2.0 * PI / np as f32;
            polar(cos_t, p)
        };
        let pdf = self.pdf_local(local);
        (pdf > 0.0 && pdf.is_finite()).then(|| ((self.frame * local).normalize(), pdf))
    }
}

/// The unit direction of the luminaire frame at polar angle acos(`cos_t`) from the nadir (-z)
/// and azimuth `p` from +x towards +y.
fn polar(cos_t: f32, p: f32) -> Vec3 {
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    Vec3::new(sin_t * p.cos(), sin_t * p.sin(), -cos_t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use quasar_importers::photometry::{HorizontalSymmetry, PhotometricType};

    /// A narrow, asymmetric type C web: a beam 10 degrees wide towards C90, gamma 30.
    fn beam() -> PhotometricWeb {
        let v: Vec<f32> = (0..=180).map(|g| g as f32).collect();
        let h: Vec<f32> = (0..=72).map(|c| c as f32 * 5.0).collect();
        let candela = h
            .iter()
            .flat_map(|&c| {
                v.iter().map(move |&g| {
                    let dc = ((c - 90.0 + 180.0).rem_euclid(360.0) - 180.0) / 10.0;
                    let dg = (g - 30.0) / 5.0;
                    1000.0 * (-(dc * dc + dg * dg)).exp() + if g < 90.0 { 5.0 } else { 0.0 }
                })
            })
            .collect();
        PhotometricWeb {
            file: "beam.ies".into(),
            kind: PhotometricType::C,
            symmetry: HorizontalSymmetry::Full,
            vertical_deg: v,
            horizontal_deg: h,
            candela,
            lamp_lumens: None,
            luminaire_lumens: None,
            multiplier: 1.0,
            label: String::new(),
        }
    }

    fn luminaire() -> Luminaire {
        let frame = Mat3::from_cols(Vec3::X, Vec3::NEG_Z, Vec3::Y);
        Luminaire::new(Vec3::ZERO, frame, Arc::new(beam()), Spectrum::Constant(1.0), 1.0)
    }

    /// E[I(w) / pdf(w)] over sampled photon directions is the web's flux (the sampler is
    /// unbiased), and its density integrates to 1 over the sphere.
    #[test]
    fn photon_directions_estimate_the_flux() {
        let l = luminaire();
        let mut s = crate::core::sampling::Sampler::new(3, 0, 0);
        let n = 400_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let (w, pdf) = l.sample_direction(s.get_2d()).unwrap();
            sum += f64::from(l.candela(w) / pdf);
        }
        let est = sum / n as f64;
        assert!((est / l.flux_lm - 1.0).abs() < 0.01, "photon flux {est} vs quadrature {}", l.flux_lm);
        // the density over a fine grid integrates to 1
        let (nt, np) = (400usize, 800usize);
        let mut total = 0.0f64;
        for i in 0..nt {
            let t = (i as f32 + 0.5) * PI / nt as f32;
            for j in 0..np {
                let p = (j as f32 + 0.5) * 2.0 * PI / np as f32;
                total += f64::from(l.pdf_local(polar(t.cos(), p)) * t.sin());
            }
        }
        total *= f64::from(PI / nt as f32 * 2.0 * PI / np as f32);
        assert!((total - 1.0).abs() < 2e-3, "{total}");
    }

    /// Chi-square test of the photon sampler against its density on a 10 x 20 grid of the sphere.
    #[test]
    fn photon_sampler_passes_a_chi_square_test() {
        let l = luminaire();
        let (nt, np) = (10usize, 20usize);
        let n = 200_000usize;
        let mut hist = vec![0f64; nt * np];
        let mut s = crate::core::sampling::Sampler::new(11, 0, 0);
        for _ in 0..n {
            let (w, _) = l.sample_direction(s.get_2d()).unwrap();
            let local = l.frame.transpose() * w;
            let t = (-local.z).clamp(-1.0, 1.0).acos();
            let p = local.y.atan2(local.x).rem_euclid(2.0 * PI);
            let i = ((t / PI * nt as f32) as usize).min(nt - 1);
            let j = ((p / (2.0 * PI) * np as f32) as usize).min(np - 1);
            hist[i * np + j] += 1.0;
        }
        let mut chi2 = 0.0f64;
        let mut dof = 0;
        for i in 0..nt {
            for j in 0..np {
                // expected count: the density integrated over the cell (fine midpoint rule)
                let mut e = 0.0f64;
                let k = 12;
                for a in 0..k {
                    let t = (i as f32 + (a as f32 + 0.5) / k as f32) * PI / nt as f32;
                    for b in 0..k {
                        let p = (j as f32 + (b as f32 + 0.5) / k as f32) * 2.0 * PI / np as f32;
                        e += f64::from(l.pdf_local(polar(t.cos(), p)) * t.sin());
                    }
                }
                e *= f64::from(PI / (nt * k) as f32 * 2.0 * PI / (np * k) as f32) * n as f64;
                if e > 5.0 {
                    chi2 += (hist[i * np + j] - e).powi(2) / e;
                    dof += 1;
                }
            }
        }
        // 99.9% quantile of chi-square with dof - 1 degrees of freedom (Wilson-Hilferty)
        let k = (dof - 1) as f64;
        let q = k * (1.0 - 2.0 / (9.0 * k) + 3.09 * (2.0 / (9.0 * k)).sqrt()).powi(3);
        assert!(chi2 < q, "chi2 {chi2} over {dof} cells (limit {q})");
    }

    /// Emission points are uniform over the opening: a rectangle's in its C0/C90 plane with the
    /// moments of a uniform rectangle (mean 0, variance side^2 / 12) and a chi-square test on a
    /// 4 x 4 grid; a disk's within its radius with mean squared radius R^2 / 2.
    #[test]
    fn emission_points_are_uniform_over_the_opening() {
        let rect = luminaire().with_opening(LuminousOpening::Rect { c0: 1.2, c90: 0.4 });
        let mut s = crate::core::sampling::Sampler::new(5, 0, 0);
        let n = 64_000usize;
        let (mut m, mut v, mut hist) = (Vec2::ZERO, Vec2::ZERO, [0f64; 16]);
        for _ in 0..n {
            let p = rect.emission_point(s.get_2d());
            // frame: C0 = +X, C90 = -Z, up = +Y; the plane through the centre
            assert_eq!(p.y, 0.0);
            let q = Vec2::new(p.x, -p.z);
            assert!(q.x.abs() <= 0.6 && q.y.abs() <= 0.2, "{q}");
            m += q;
            v += q * q;
            let (i, j) = ((((q.x / 1.2 + 0.5) * 4.0) as usize).min(3), (((q.y / 0.4 + 0.5) * 4.0) as usize).min(3));
            hist[i * 4 + j] += 1.0;
        }
        let (m, v) = (m / n as f32, v / n as f32);
        assert!(m.abs().max_element() < 0.01, "{m}");
        assert!((v.x / (1.44 / 12.0) - 1.0).abs() < 0.02 && (v.y / (0.16 / 12.0) - 1.0).abs() < 0.02, "{v}");
        let e = n as f64 / 16.0;
        let chi2: f64 = hist.iter().map(|h| (h - e).powi(2) / e).sum();
        assert!(chi2 < 37.7, "chi2 {chi2} over 16 cells (99.9% of 15 dof: 37.7)");
        let disk = luminaire().with_opening(LuminousOpening::Disk { diameter: 1.0 });
        let mut r2 = 0.0f64;
        for _ in 0..n {
            let p = disk.emission_point(s.get_2d());
            let d2 = f64::from(p.x * p.x + p.z * p.z);
            assert!(d2 <= 0.25 + 1e-6 && p.y == 0.0);
            r2 += d2;
        }
        assert!((r2 / n as f64 / 0.125 - 1.0).abs() < 0.02, "{}", r2 / n as f64);
        assert_eq!(luminaire().emission_point(Vec2::new(0.3, 0.7)), Vec3::ZERO);
    }

    /// The frame maps C90 of the default orientation (aim down) to world -Z.
    #[test]
    fn candela_follow_the_frame() {
        let l = luminaire();
        let peak = polar(30f32.to_radians().cos(), 90f32.to_radians());
        let world = l.frame * peak;
        assert!(world.z < -0.4 && world.y < -0.8, "{world}");
        assert!((l.candela(world) - 1005.0).abs() < 1.0, "{}", l.candela(world));
    }
}
