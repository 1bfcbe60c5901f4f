//! The directional albedo tables of a dielectric coat, per relative IOR, over the coat's
//! roughness and the incidence cosine, that the coated BSDF ([`super::CoatedBsdf`]) reads at
//! every evaluation: E(mu), the coat's internal reflectance, and the trapped light of a glossy
//! base (docs/architecture.md §5, "Coated materials").

use std::sync::{LazyLock, Mutex};

use glam::{Vec2, Vec3};

use super::TrowbridgeReitz;
use super::fresnel::fr_dielectric;
use super::microfacet::SMOOTH_ALPHA;

/// Roughness grid of [`CoatAlbedo`]: r = sqrt(alpha) in [0, 1] at this many points.
const N_ROUGHNESS: usize = 17;
/// Incidence-cosine grid of [`CoatAlbedo`]: mu in [0, 1] at this many points.
const N_MU: usize = 32;
/// Visible normals per table entry (quasi-Monte Carlo, the R2 sequence).
const ALBEDO_SAMPLES: usize = 1024;
/// Largest relative IOR a table is built for (coat IORs are clamped to it).
pub const MAX_TABLE_IOR: f32 = 4.0;

/// The directional albedo E(mu) of a coat's GGX reflection (height-correlated Smith masking) for
/// one relative IOR, over roughness and incidence cosine, and the coat's hemispherical internal
/// reflectance F_int, defined so that energy is conserved exactly over a white Lambertian base:
/// F_int = 1 - (2 / eta^2) integral_0^1 (1 - E(mu)) mu dmu (for a smooth coat this is the
/// classic internal diffuse reflectance, 0.596 at eta = 1.5).
///
/// For glossy bases it also holds the trapped fraction t(mu', alpha_b): the part of the light
/// arriving at cosine mu' under the coat that a white GGX conductor (roughness alpha_b) reflects
/// beyond the critical angle (cos < sqrt(1 - 1 / eta^2)), where the coat totally reflects it
/// back; its normalisation N(alpha_c, alpha_b) = (2 / eta^2) integral_0^1 (1 - E(mu)) t(mu') mu
/// dmu; the white conductor's directional albedo w(mu', alpha_b); and, for light already
/// trapped (arriving beyond the critical angle), the cosine-weighted means over those angles of w
/// and of t, and the mean internal reflectance F_c of the coat inside its escape cone.
#[derive(PartialEq)]
pub struct CoatAlbedo {
    eta: f32,
    e: [[f32; N_MU]; N_ROUGHNESS],
    f_int: [f32; N_ROUGHNESS],
    trapped: [[f32; N_MU]; N_ROUGHNESS],
    trapped_norm: [[f32; N_ROUGHNESS]; N_ROUGHNESS],
    white: [[f32; N_MU]; N_ROUGHNESS],
    trapped_white: [f32; N_ROUGHNESS],
    trapped_trapped: [f32; N_ROUGHNESS],
    cone_reflectance: f32,
}

impl std::fmt::Debug for CoatAlbedo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "CoatAlbedo(eta = {})", self.eta)
    }
}

/// A position in the roughness grid of a [`CoatAlbedo`]: a row and the weight of the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughnessPos {
    row: u8,
    t: f32,
}

impl RoughnessPos {
    /// The position of GGX `alpha` (clamped as [`coat_alpha`] does).
    pub fn of(alpha: f32) -> Self {
        let x = coat_alpha(alpha).sqrt() * (N_ROUGHNESS - 1) as f32;
        let row = (x as usize).min(N_ROUGHNESS - 2);
        Self { row: row as u8, t: (x - row as f32).clamp(0.0, 1.0) }
    }

    /// Linear interpolation between rows of `v`.
    #[inline]
    fn lerp(self, v: &[f32; N_ROUGHNESS]) -> f32 {
        let r = self.row as usize;
        v[r] + self.t * (v[r + 1] - v[r])
    }

    /// Bilinear interpolation in a (roughness, mu) table.
    #[inline]
    fn lerp_mu(self, table: &[[f32; N_MU]; N_ROUGHNESS], mu: f32) -> f32 {
        let x = mu.clamp(0.0, 1.0) * (N_MU - 1) as f32;
        let k = (x as usize).min(N_MU - 2);
        let s = x - k as f32;
        let (a, b) = (&table[self.row as usize], &table[self.row as usize + 1]);
        let lo = a[k] + s * (a[k + 1] - a[k]);
        let hi = b[k] + s * (b[k + 1] - b[k]);
        lo + self.t * (hi - lo)
    }
}

/// Where a coat's roughness falls in its IOR's [`CoatAlbedo`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatRow {
    table: &'static CoatAlbedo,
    pos: RoughnessPos,
}

/// The R2 low-discrepancy sequence (Roberts 2018): point `i` in [0, 1)^2.
fn r2(i: usize) -> Vec2 {
    const G: f64 = 1.324_717_957_244_746;
    Vec2::new((0.5 + i as f64 / G).fract() as f32, (0.5 + i as f64 / (G * G)).fract() as f32)
}

/// The coat alpha used for roughness `r` = sqrt(alpha): never below [`SMOOTH_ALPHA`], so that a
/// coat is never a Dirac delta (a coated BSDF has one non-delta lobe set).
pub fn coat_alpha(alpha: f32) -> f32 {
    if alpha.is_finite() { alpha.clamp(SMOOTH_ALPHA, 1.0) } else { SMOOTH_ALPHA }
}

/// The cosine of the grid's entry `k` (0 replaced by 1e-4).
fn grid_mu(k: usize) -> f32 {
    (k as f32 / (N_MU - 1) as f32).max(1e-4)
}

/// Trapezoid rule over the mu grid of `g(k)`.
fn trapezoid(g: impl Fn(usize) -> f64) -> f64 {
    let h = 1.0 / (N_MU - 1) as f64;
    h * ((1..N_MU - 1).map(&g).sum::<f64>() + 0.5 * (g(0) + g(N_MU - 1)))
}

/// The mean over GGX visible normals seen from `wo` of `weight(wi) G2(wo, wi) / G1(wo)` for the
/// mirror reflections wi above the surface (the reflected energy, weighted).
fn reflected(d: &TrowbridgeReitz, wo: Vec3, weight: impl Fn(Vec3, Vec3) -> f32) -> f64 {
    let g1 = d.g1(wo);
    if g1 <= 0.0 {
        return 0.0;
    }
    let mut sum = 0.0f64;
    for i in 0..ALBEDO_SAMPLES {
        let wm = d.sample_wm(wo, r2(i));
        let wi = 2.0 * wo.dot(wm) * wm - wo;
        if wi.z > 0.0 {
            sum += f64::from(weight(wm, wi) * d.g(wo, wi) / g1);
        }
    }
    sum / ALBEDO_SAMPLES as f64
}

impl CoatAlbedo {
    fn build(eta: f32) -> Self {
        let mut e = [[0.0f32; N_MU]; N_ROUGHNESS];
        let mut f_int = [0.0f32; N_ROUGHNESS];
        let mut trapped = [[0.0f32; N_MU]; N_ROUGHNESS];
        let mut white = [[0.0f32; N_MU]; N_ROUGHNESS];
        let cos_critical = (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt();
        for ri in 0..N_ROUGHNESS {
            let r = ri as f32 / (N_ROUGHNESS - 1) as f32;
            let d = TrowbridgeReitz::new(coat_alpha(r * r));
            for k in 0..N_MU {
                let mu = grid_mu(k);
                let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                e[ri][k] = reflected(&d, wo, |wm, _| fr_dielectric(wo.dot(wm), eta)).clamp(0.0, 1.0) as f32;
                white[ri][k] = reflected(&d, wo, |_, _| 1.0).clamp(0.0, 1.0) as f32;
                let beyond = reflected(&d, wo, |_, wi| if wi.z < cos_critical { 1.0 } else { 0.0 });
                trapped[ri][k] = beyond.clamp(0.0, 1.0) as f32;
            }
            let integral = trapezoid(|k| (1.0 - f64::from(e[ri][k])) * f64::from(grid_mu(k)));
            f_int[ri] = (1.0 - 2.0 * integral / f64::from(eta * eta)).clamp(0.0, 1.0) as f32;
        }
        let mut trapped_norm = [[0.0f32; N_ROUGHNESS]; N_ROUGHNESS];
        for (c, row) in trapped_norm.iter_mut().enumerate() {
            for (b, v) in row.iter_mut().enumerate() {
                let base =
                    RoughnessPos { row: b.min(N_ROUGHNESS - 2) as u8, t: if b == N_ROUGHNESS - 1 { 1.0 } else { 0.0 } };
                let integral = trapezoid(|k| {
                    let mu = grid_mu(k);
                    let inside = (1.0 - (1.0 - mu * mu) / (eta * eta)).max(0.0).sqrt();
                    (1.0 - f64::from(e[c][k])) * f64::from(base.lerp_mu(&trapped, inside)) * f64::from(mu)
                });
                *v = (2.0 * integral / f64::from(eta * eta)) as f32;
            }
        }
        // cosine-weighted means over mu' in [0, cos_critical) (midpoint rule)
        let beyond_mean = |v: &[f32; N_MU]| -> f32 {
            let n = 256;
            let mut sum = 0.0;
            for j in 0..n {
                let mu = cos_critical * (j as f32 + 0.5) / n as f32;
                sum += RoughnessPos { row: 0, t: 0.0 }.lerp_mu(&[*v; N_ROUGHNESS], mu) * mu;
            }
            if cos_critical > 0.0 { 2.0 * sum * cos_critical / n as f32 / (cos_critical * cos_critical) } else { 0.0 }
        };
        let trapped_white = std::array::from_fn(|b| beyond_mean(&white[b]));
        let trapped_trapped = std::array::from_fn(|b| beyond_mean(&trapped[b]));
        // F_int averaged over the cone cos in [cos_critical, 1], cosine-weighted
        let n = 512;
        let mut cone = 0.0f64;
        for j in 0..n {
            let mu = cos_critical + (1.0 - cos_critical) * (j as f32 + 0.5) / n as f32;
            cone += f64::from(fr_dielectric(-mu, eta) * mu);
        }
        let cone_measure = f64::from(1.0 - cos_critical * cos_critical) / 2.0;
        let cone_reflectance = if cone_measure > 0.0 {
            (cone * f64::from(1.0 - cos_critical) / n as f64 / cone_measure) as f32
        } else {
            0.0
        };
        Self { eta, e, f_int, trapped, trapped_norm, white, trapped_white, trapped_trapped, cone_reflectance }
    }

    /// The table for relative IOR `eta` (>= 1), built on first use and kept for the process (one
    /// per distinct IOR; a scene has few). Takes a lock: call it when a material is made, not per hit.
    pub fn for_eta(eta: f32) -> &'static CoatAlbedo {
        static TABLES: LazyLock<Mutex<Vec<&'static CoatAlbedo>>> = LazyLock::new(|| Mutex::new(Vec::new()));
        let eta = if eta.is_finite() { eta.clamp(1.0, MAX_TABLE_IOR) } else { 1.5 };
        let mut tables = TABLES.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = tables.iter().find(|t| t.eta == eta) {
            return t;
        }
        let t: &'static CoatAlbedo = Box::leak(Box::new(Self::build(eta)));
        tables.push(t);
        t
    }

    /// The relative IOR the table was built for.
    pub fn eta(&self) -> f32 {
        self.eta
    }

    /// The grid position of a coat of GGX `alpha` (clamped as [`coat_alpha`] does).
    pub fn row(&'static self, alpha: f32) -> CoatRow {
        CoatRow { table: self, pos: RoughnessPos::of(alpha) }
    }
}

impl CoatRow {
    /// E(mu) for the incidence cosine `mu` in [0, 1] (bilinear in roughness and mu).
    #[inline]
    pub fn albedo(&self, mu: f32) -> f32 {
        self.pos.lerp_mu(&self.table.e, mu)
    }

    /// The hemispherical internal reflectance F_int of [`CoatAlbedo`] at this roughness.
    #[inline]
    pub fn internal_reflectance(&self) -> f32 {
        self.pos.lerp(&self.table.f_int)
    }

    /// The trapped fraction t(mu') of a glossy base at `base` for light arriving under the coat
    /// at cosine `mu_inside`.
    #[inline]
    pub fn trapped(&self, base: RoughnessPos, mu_inside: f32) -> f32 {
        base.lerp_mu(&self.table.trapped, mu_inside)
    }

    /// The directional albedo w(mu') of a white conductor at `base` (single-scattering GGX).
    #[inline]
    pub fn white(&self, base: RoughnessPos, mu_inside: f32) -> f32 {
        base.lerp_mu(&self.table.white, mu_inside)
    }

    /// For trapped light on a white conductor at `base`: (the mean albedo, the mean fraction
    /// reflected beyond the critical angle again) (see [`CoatAlbedo`]).
    pub fn trapped_bounce(&self, base: RoughnessPos) -> (f32, f32) {
        (base.lerp(&self.table.trapped_white), base.lerp(&self.table.trapped_trapped))
    }

    /// The coat's mean internal reflectance inside its escape cone.
    pub fn cone_reflectance(&self) -> f32 {
        self.table.cone_reflectance
    }

    /// The normalisation N(alpha_c, alpha_b) of the trapped light's exit (see [`CoatAlbedo`]).
    pub fn trapped_norm(&self, base: RoughnessPos) -> f32 {
        let n = &self.table.trapped_norm;
        let (c, b) = (self.pos.row as usize, base.row as usize);
        let at = |c: usize| n[c][b] + base.t * (n[c][b + 1] - n[c][b]);
        at(c) + self.pos.t * (at(c + 1) - at(c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_coat_albedo_is_fresnel_and_internal_reflectance_is_classic() {
        let t = CoatAlbedo::for_eta(1.5);
        let row = t.row(0.0);
        for mu in [1.0f32, 0.7, 0.3, 0.1] {
            let e = row.albedo(mu);
            assert!((e - fr_dielectric(mu, 1.5)).abs() < 3e-3, "mu {mu}: {e} vs {}", fr_dielectric(mu, 1.5));
        }
        // the internal diffuse reflectance of eta = 1.5 (e.g. d'Eon & Irving 2011): 0.596
        assert!((row.internal_reflectance() - 0.596).abs() < 5e-3, "{}", row.internal_reflectance());
        assert!(std::ptr::eq(t, CoatAlbedo::for_eta(1.5)));
    }

    #[test]
    fn rough_coat_albedo_is_bounded_and_interpolates() {
        let t = CoatAlbedo::for_eta(1.5);
        for alpha in [0.01f32, 0.1, 0.3, 1.0, 7.0, f32::NAN] {
            let row = t.row(alpha);
            for k in 0..=20 {
                let e = row.albedo(k as f32 / 20.0);
                assert!((0.0..=1.0).contains(&e), "{alpha}: {e}");
            }
            let f = row.internal_reflectance();
            assert!((0.0..=1.0).contains(&f), "{alpha}: {f}");
        }
        // index matched: nothing reflects
        let one = CoatAlbedo::for_eta(1.0).row(0.1);
        assert!(one.albedo(0.5) < 1e-6 && one.internal_reflectance().abs() < 1e-3);
    }
}
