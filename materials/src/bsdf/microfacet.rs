//! The Trowbridge–Reitz (GGX) microfacet distribution (Trowbridge & Reitz 1975; Walter et al.
//! 2007), isotropic, with Smith's height-correlated masking-shadowing (Heitz 2014, "Understanding
//! the masking-shadowing function in microfacet-based BRDFs") and visible-normal sampling (Heitz
//! 2018, "Sampling the GGX distribution of visible normals").
//!
//! All directions are in the local frame (z = macro-surface normal) and unit length. The Smith
//! terms are written with a(w) = sqrt(cos^2 + alpha^2 sin^2) = |cos| (1 + 2 Lambda(w)), which
//! stays finite at grazing angles where tan(theta) overflows.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

/// Roughness below which a surface is treated as perfectly smooth (a Dirac delta), like pbrt-v4's
/// `TrowbridgeReitzDistribution::EffectivelySmooth` (alpha < 1e-3).
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// Smith's masking-shadowing function G(wo, wi) of a microfacet BSDF.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Masking {
    /// G = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014): the statistically consistent form,
    /// pbrt-v4's and quasar's default.
    #[default]
    HeightCorrelated,
    /// G = G1(wo) G1(wi): masking and shadowing treated as independent, the form of Mitsuba 3's
    /// `roughconductor`/`roughdielectric` and pbrt-v3 (slightly darker where both directions
    /// are near grazing); for comparisons with them.
    Separable,
}

impl Masking {
    /// Names as in scene files and on the command line.
    pub const NAMES: [&str; 2] = ["height-correlated", "separable"];

    /// Looks a masking form up by name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "height-correlated" => Some(Self::HeightCorrelated),
            "separable" => Some(Self::Separable),
            _ => None,
        }
    }

    /// The name of this form.
    pub fn name(self) -> &'static str {
        match self {
            Self::HeightCorrelated => Self::NAMES[0],
            Self::Separable => Self::NAMES[1],
        }
    }
}

/// Isotropic Trowbridge–Reitz (GGX) distribution of microfacet normals with width `alpha`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    alpha: f32,
    masking: Masking,
}

impl TrowbridgeReitz {
    /// A distribution with roughness `alpha` (used directly, no remapping); a negative or
    /// non-finite alpha is treated as 0 (smooth).
    pub fn new(alpha: f32) -> Self {
        Self { alpha: if alpha.is_finite() && alpha > 0.0 { alpha } else { 0.0 }, masking: Masking::HeightCorrelated }
    }

    /// This distribution with the masking-shadowing form `masking`.
    pub fn with_masking(self, masking: Masking) -> Self {
        Self { masking, ..self }
    }

    /// The roughness alpha.
    #[inline]
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// True when `alpha` < [`SMOOTH_ALPHA`]: the lobe is narrower than what f32 sampling resolves
    /// and the surface is rendered as a perfect specular interface.
    #[inline]
    pub fn effectively_smooth(&self) -> bool {
        self.alpha < SMOOTH_ALPHA
    }

    /// Normal distribution D(wm) = alpha^2 / (pi (sin^2 + alpha^2 cos^2)^2), the usual
    /// 1 / (pi alpha^2 cos^4 (1 + tan^2 / alpha^2)^2) rewritten without tangents;
    /// normalised so that the integral of D(wm) cos(theta_m) over the hemisphere is 1.
    #[inline]
    pub fn d(&self, wm: Vec3) -> f32 {
        let a2 = self.alpha * self.alpha;
        let t = wm.x * wm.x + wm.y * wm.y + a2 * wm.z * wm.z;
        if t <= 0.0 {
            return 0.0;
        }
        a2 / (PI * t * t)
    }

    /// a(w) = sqrt(cos^2 + alpha^2 sin^2) = |cos| (1 + 2 Lambda(w)).
    #[inline]
    fn a(&self, w: Vec3) -> f32 {
        let a2 = self.alpha * self.alpha;
        (w.z * w.z + a2 * (w.x * w.x + w.y * w.y)).sqrt()
    }

    /// Smith's auxiliary function Lambda(w) = (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2
    /// (infinite at cos theta = 0).
    pub fn lambda(&self, w: Vec3) -> f32 {
        let c = w.z.abs();
        if c == 0.0 {
            return f32::INFINITY;
        }
        0.5 * (self.a(w) / c - 1.0)
    }

    /// Smith masking G1(w) = 1 / (1 + Lambda(w)) = 2 |cos| / (|cos| + a(w)).
    pub fn g1(&self, w: Vec3) -> f32 {
        let c = w.z.abs();
        let d = c + self.a(w);
        if d > 0.0 { 2.0 * c / d } else { 0.0 }
    }

    /// Masking-shadowing G(wo, wi): height-correlated 1 / (1 + Lambda(wo) + Lambda(wi))
    /// = 2 |cos o| |cos i| / (a(wo) |cos i| + a(wi) |cos o|), or separable G1(wo) G1(wi).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.g_over_cos(wo, wi) * wo.z.abs() * wi.z.abs()
    }

    /// G(wo, wi) / (|cos o| |cos i|): height-correlated 2 / (a(wo) |cos i| + a(wi) |cos o|),
    /// separable 4 / ((|cos o| + a(wo)) (|cos i| + a(wi))). The factor every microfacet BSDF
    /// needs, finite at grazing angles (0 when both cosines vanish).
    #[inline]
    pub fn g_over_cos(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        let (n, d) = match self.masking {
            Masking::HeightCorrelated => (2.0, self.a(wo) * ci + self.a(wi) * co),
            Masking::Separable => (4.0, (co + self.a(wo)) * (ci + self.a(wi))),
        };
        if d > 0.0 && d.is_finite() { n / d } else { 0.0 }
    }

    /// Density of visible normals seen from `w` (Heitz 2014, Heitz 2018):
    /// D_w(wm) = G1(w) / |cos w| * D(wm) * max(0, w . wm) = 2 D(wm) max(0, w . wm) / (|cos w| + a(w)),
    /// a density over wm (solid angle) that integrates to 1 over the upper hemisphere. A `w` below
    /// the surface (inside a dielectric) sees the normals visible from -w, as in
    /// [`sample_wm`](Self::sample_wm).
    #[inline]
    pub fn pdf_wm(&self, w: Vec3, wm: Vec3) -> f32 {
        let d = w.z.abs() + self.a(w);
        let cos_m = if w.z < 0.0 { -w.dot(wm) } else { w.dot(wm) };
        if d > 0.0 && cos_m > 0.0 { 2.0 * self.d(wm) * cos_m / d } else { 0.0 }
    }

    /// Samples a microfacet normal (upper hemisphere) with density [`pdf_wm`](Self::pdf_wm),
    /// by spherical caps (Dupuy & Benyoub 2023, "Sound and efficient sampling of visible GGX
    /// normals"): stretch `w` to the configuration with alpha = 1 (flipped to the upper
    /// hemisphere), where the visible normals are distributed as h = c + w with c uniform on
    /// the spherical cap z >= -w.z of the unit sphere, then unstretch h. The same density as
    /// Heitz's (2018) projected-disk construction with fewer dependent steps: no tangent frame,
    /// one square root between the numbers and h.
    #[inline(always)]
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        let mut wh = Vec3::new(a * w.x, a * w.y, w.z).normalize_or(Vec3::Z);
        if wh.z < 0.0 {
            wh = -wh;
        }
        // uniform on the cap: z uniform in [-wh.z, 1] (Archimedes), azimuth uniform
        let z = (1.0 - u.x) * (1.0 + wh.z) - wh.z;
        let sin_t = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
        let (sin_phi, cos_phi) = crate::warp::sin_cos_turns(u.y);
        let h = Vec3::new(sin_t * cos_phi, sin_t * sin_phi, z) + wh;
        Vec3::new(a * h.x, a * h.y, h.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Midpoint-rule integral over the upper hemisphere in (theta, phi), with a finer grid near
    /// the pole where narrow distributions live.
    fn hemisphere_integral(f: impl Fn(Vec3) -> f64) -> f64 {
        let (nt, np) = (2000, 64);
        let mut s = 0.0;
        for i in 0..nt {
            // theta = (pi/2) t^2 concentrates samples near the pole; d theta = pi t dt.
            let t = (i as f64 + 0.5) / nt as f64;
            let theta = std::f64::consts::FRAC_PI_2 * t * t;
            let dtheta = std::f64::consts::PI * t / nt as f64;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                let w =
                    Vec3::new((theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32);
                s += f(w) * theta.sin() * dtheta * std::f64::consts::TAU / np as f64;
            }
        }
        s
    }

    #[test]
    fn projected_normal_area_is_one() {
        for alpha in [0.05f32, 0.3, 1.0] {
            let m = TrowbridgeReitz::new(alpha);
            let i = hemisphere_integral(|wm| (m.d(wm) * wm.z) as f64);
            assert!((i - 1.0).abs() < 2e-3, "alpha {alpha}: {i}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        for alpha in [0.05f32, 0.3, 1.0] {
            let m = TrowbridgeReitz::new(alpha);
            for cz in [1.0f32, 0.7, 0.2, 0.02, -0.5] {
                let w = Vec3::new((1.0 - cz * cz).sqrt(), 0.0, cz);
                let i = hemisphere_integral(|wm| m.pdf_wm(w, wm) as f64);
                assert!((i - 1.0).abs() < 3e-3, "alpha {alpha} cos {cz}: {i}");
            }
        }
    }

    #[test]
    fn smith_terms_are_bounded_and_match_lambda() {
        let m = TrowbridgeReitz::new(0.4);
        for cz in [1.0f32, 0.5, 0.1, 1e-6, 0.0] {
            let w = Vec3::new((1.0 - cz * cz).sqrt(), 0.0, cz);
            let g1 = m.g1(w);
            assert!((0.0..=1.0).contains(&g1));
            if cz > 0.0 {
                assert!((g1 - 1.0 / (1.0 + m.lambda(w))).abs() < 1e-5);
            }
            assert!(m.g(w, w) <= g1 + 1e-6);
        }
        assert_eq!(m.g1(Vec3::X), 0.0);
        assert_eq!(m.g_over_cos(Vec3::X, Vec3::Y), 0.0);
        // separable = G1 G1 <= height-correlated (equal at normal incidence)
        let s = m.with_masking(Masking::Separable);
        for (a, b) in [(0.9f32, 0.7f32), (0.3, 0.1), (1.0, 1.0)] {
            let (wo, wi) = (Vec3::new((1.0 - a * a).sqrt(), 0.0, a), Vec3::new(0.0, (1.0 - b * b).sqrt(), b));
            assert!((s.g(wo, wi) - m.g1(wo) * m.g1(wi)).abs() < 1e-5);
            assert!(s.g(wo, wi) <= m.g(wo, wi) + 1e-6);
        }
    }

    #[test]
    fn sampled_normals_are_unit_and_upper() {
        let m = TrowbridgeReitz::new(0.2);
        for w in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.6, 0.0, -0.8)] {
            for &(a, b) in &[(0.0f32, 0.0f32), (1.0, 1.0), (0.5, 0.25), (0.999, 0.001)] {
                let wm = m.sample_wm(w, Vec2::new(a, b));
                assert!(wm.is_finite() && (wm.length() - 1.0).abs() < 1e-5 && wm.z > 0.0);
            }
        }
    }
}
