//! Luminous intensity distributions of luminaires (photometric webs) read from IES LM-63
//! ([`ies`]) and EULUMDAT ([`eulumdat`]) files, as plain data: candela on a grid of the file's
//! angles, with the file's symmetry kept and resolved when evaluating. Conventions (docs/photometry.md):
//!
//! The luminaire's own frame has +z up, the nadir -z, and +x the C0 (type C) direction; a
//! direction d of that frame is, for
//! - type C (vertical axis; C counter-clockwise seen from above, gamma from the nadir):
//!   d = (sin g cos C, sin g sin C, -cos g);
//! - type B (horizontal axis +x; V from the nadir towards +x, H the plane's turn about +x,
//!   clockwise seen along +x): d = (sin V, -cos V sin H, -cos V cos H);
//! - type A (vertical axis; V the elevation, -90 the nadir; H clockwise seen from above):
//!   d = (cos V cos H, -cos V sin H, sin V).
//!
//! [`PhotometricWeb::intensity`] interpolates the candela bilinearly in the two angles of the
//! file's type (non-negative, exact at the measured angles, continuous); directions outside the
//! measured vertical range have zero intensity.

pub mod eulumdat;
pub mod ies;

use std::path::PathBuf;

use glam::Vec3;

/// Largest luminous intensity accepted (cd) after the file's multipliers: far above any
/// luminaire (a lighthouse is about 1e7 cd), small enough that interpolation and flux sums stay
/// finite in f32.
pub const MAX_CANDELA: f64 = 1e20;

/// The angle system of a photometric file (IES `photometric type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhotometricType {
    /// Type C: vertical polar axis (architectural and road luminaires; all EULUMDAT files).
    C,
    /// Type B: horizontal polar axis (floodlights).
    B,
    /// Type A: vertical planes, elevation angles (automotive).
    A,
}

/// How the measured horizontal angles cover the full circle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HorizontalSymmetry {
    /// One plane: the distribution is the same in every plane.
    Axial,
    /// 0..90 (type C) or 0..90 of a type A/B file: mirrored into every quadrant.
    Quadrant,
    /// 0..180 (type C): mirrored about the C0-C180 plane; -90..90 or 0..90 of A/B: H and -H alike.
    Bilateral,
    /// 90..270 (type C): mirrored about the C90-C270 plane.
    BilateralC90,
    /// The measured angles cover the whole range.
    Full,
}

/// A luminous intensity distribution: `candela[h][v]` at `horizontal_deg[h]`,
/// `vertical_deg[v]`, with every multiplier of the file applied (cd).
#[derive(Clone, Debug, PartialEq)]
pub struct PhotometricWeb {
    /// The file it came from (for messages and the render header).
    pub file: PathBuf,
    /// The angle system.
    pub kind: PhotometricType,
    /// How the horizontal angles extend to the full circle.
    pub symmetry: HorizontalSymmetry,
    /// Vertical angles (degrees, increasing).
    pub vertical_deg: Vec<f32>,
    /// Horizontal angles (degrees, increasing).
    pub horizontal_deg: Vec<f32>,
    /// Candela, `horizontal_deg.len()` rows of `vertical_deg.len()` values.
    pub candela: Vec<f32>,
    /// Lamp lumens the file states (all lamps; None for absolute photometry).
    pub lamp_lumens: Option<f32>,
    /// Luminaire lumens the file states, when it does (EULUMDAT's LOR times lamp flux).
    pub luminaire_lumens: Option<f32>,
    /// The product of the file's multipliers applied to `candela` (candela multiplier, ballast
    /// factor, tilt factor, ...), for the record.
    pub multiplier: f32,
    /// Free-text identification (manufacturer, catalogue number, luminaire name).
    pub label: String,
}

impl PhotometricWeb {
    /// The file's native (horizontal, vertical) angles in degrees of the unit direction `d` of
    /// the luminaire's frame (module documentation).
    pub fn angles(&self, d: Vec3) -> (f32, f32) {
        let deg = f32::to_degrees;
        match self.kind {
            PhotometricType::C => {
                let g = deg((-d.z).clamp(-1.0, 1.0).acos());
                let c = deg(d.y.atan2(d.x)).rem_euclid(360.0);
                (c, g)
            }
            PhotometricType::B => {
                let v = deg(d.x.clamp(-1.0, 1.0).asin());
                let h = deg((-d.y).atan2(-d.z));
                (h, v)
            }
            PhotometricType::A => {
                let v = deg(d.z.clamp(-1.0, 1.0).asin());
                let h = deg((-d.y).atan2(d.x));
                (h, v)
            }
        }
    }

    /// Folds a horizontal angle (degrees; type C in [0, 360), types A/B in [-180, 180]) into the
    /// measured range by the file's symmetry.
    fn fold_horizontal(&self, h: f32) -> f32 {
        let (first, last) = (self.horizontal_deg[0], *self.horizontal_deg.last().unwrap_or(&0.0));
        match (self.kind, self.symmetry) {
            (_, HorizontalSymmetry::Axial) => first,
            (PhotometricType::C, HorizontalSymmetry::Quadrant) => {
                let h = h.rem_euclid(180.0);
                if h > 90.0 { 180.0 - h } else { h }
            }
            (PhotometricType::C, HorizontalSymmetry::Bilateral) => {
                if h > 180.0 {
                    360.0 - h
                } else {
                    h
                }
            }
            (PhotometricType::C, HorizontalSymmetry::BilateralC90) => {
                // mirror about the 90-270 plane: C -> 180 - C (mod 360)
                if (90.0..=270.0).contains(&h) { h } else { (180.0 - h).rem_euclid(360.0) }
            }
            (PhotometricType::C, _) => h,
            // types A and B: H in [-180, 180]; behind the luminaire (|H| > 90) nothing is measured
            (_, HorizontalSymmetry::Quadrant | HorizontalSymmetry::Bilateral) => h.abs().clamp(first, last.max(first)),
            _ => h,
        }
    }

    /// Luminous intensity (cd) towards the unit direction `d` of the luminaire's frame.
    pub fn intensity(&self, d: Vec3) -> f32 {
        let (h, v) = self.angles(d);
        self.intensity_at(h, v)
    }

    /// Luminous intensity (cd) at the file's angles `h`, `v` (degrees), by symmetry and bilinear
    /// interpolation; 0 outside the measured range.
    pub fn intensity_at(&self, h: f32, v: f32) -> f32 {
        let nv = self.vertical_deg.len();
        if nv == 0 || self.horizontal_deg.is_empty() || !h.is_finite() || !v.is_finite() {
            return 0.0;
        }
        let h = self.fold_horizontal(h);
        // types A and B measured from V = 0 only: symmetric about the V = 0 plane
        let v = if self.kind != PhotometricType::C && self.vertical_deg[0] >= 0.0 { v.abs() } else { v };
        let Some((v0, tv)) = bracket(&self.vertical_deg, v) else { return 0.0 };
        let (h0, h1, th) = match bracket(&self.horizontal_deg, h) {
            Some((h0, th)) => (h0, (h0 + 1).min(self.horizontal_deg.len() - 1), th),
            None if self.symmetry == HorizontalSymmetry::Axial => (0, 0, 0.0),
            None => return 0.0,
        };
        let v1 = (v0 + 1).min(nv - 1);
        let at = |hi: usize, vi: usize| self.candela[hi * nv + vi];
        let a = at(h0, v0) + tv * (at(h0, v1) - at(h0, v0));
        let b = at(h1, v0) + tv * (at(h1, v1) - at(h1, v0));
        (a + th * (b - a)).max(0.0)
    }

    /// Luminous flux (lm) of the interpolated distribution: the integral of [`intensity`](Self::intensity)
    /// over the sphere, by the midpoint rule on a 0.25 degree grid of the luminaire's frame.
    pub fn flux(&self) -> f64 {
        let (nt, np) = (720usize, 1440usize);
        let (dt, dp) = (std::f64::consts::PI / nt as f64, 2.0 * std::f64::consts::PI / np as f64);
        let mut sum = 0.0f64;
        for i in 0..nt {
            let t = (i as f64 + 0.5) * dt;
            let (st, ct) = t.sin_cos();
            let mut row = 0.0f64;
            for j in 0..np {
                let p = (j as f64 + 0.5) * dp;
                let d = Vec3::new((st * p.cos()) as f32, (st * p.sin()) as f32, -ct as f32);
                row += f64::from(self.intensity(d));
            }
            sum += row * st;
        }
        sum * dt * dp
    }

    /// Largest candela value of the table.
    pub fn max_candela(&self) -> f32 {
        self.candela.iter().copied().fold(0.0, f32::max)
    }
}

/// Reads the photometric file at `path` by its extension (`.ies`: IES LM-63, `.ldt`: EULUMDAT):
/// its web and, for an IES file with tilt data, the tilt table.
pub fn read_photometric_file(
    path: &std::path::Path,
) -> Result<(PhotometricWeb, Option<ies::TiltTable>), crate::ImportError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("ies") => ies::read_ies(path).map(|f| (f.web, f.tilt)),
        Some("ldt") => eulumdat::read_ldt(path).map(|f| (f.web, None)),
        _ => Err(crate::ImportError::new(
            crate::ImportErrorKind::Unsupported,
            crate::ErrorPlace::file(path),
            "photometric files must be .ies (IES LM-63) or .ldt (EULUMDAT)",
        )),
    }
}

/// The luminaire frame (columns C0, C90, up) of a luminaire aimed along `aim` (its nadir points
/// there) and turned by `roll_deg` about the aim: the frame of a luminaire hanging straight down
/// (C0 along world +X, C90 along -Z, up +Y) turned by the shortest rotation taking -Y to `aim`,
/// then rolled counter-clockwise seen from behind the luminaire (looking along `aim`).
pub fn aim_frame(aim: Vec3, roll_deg: f32) -> glam::Mat3 {
    let a = aim.normalize();
    let hanging = glam::Mat3::from_cols(Vec3::X, Vec3::NEG_Z, Vec3::Y);
    let turn = glam::Quat::from_rotation_arc(Vec3::NEG_Y, a);
    let roll = glam::Quat::from_axis_angle(a, -roll_deg.to_radians());
    glam::Mat3::from_quat(roll * turn) * hanging
}

/// The interval of the increasing `xs` holding `x`: (index of its lower end, fraction); None
/// outside [first, last] (a single value brackets only itself).
fn bracket(xs: &[f32], x: f32) -> Option<(usize, f32)> {
    let (first, last) = (*xs.first()?, *xs.last()?);
    const EPS: f32 = 1e-4;
    if x < first - EPS || x > last + EPS {
        return None;
    }
    if xs.len() == 1 {
        return Some((0, 0.0));
    }
    let i = xs.partition_point(|&a| a <= x).clamp(1, xs.len() - 1) - 1;
    let w = xs[i + 1] - xs[i];
    let t = if w > 0.0 { ((x - xs[i]) / w).clamp(0.0, 1.0) } else { 0.0 };
    Some((i, t))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A type C web of `f(C, gamma)` at the angles `h` x `v`, its symmetry read from `h`.
    pub(crate) fn web_c(h: Vec<f32>, v: Vec<f32>, f: impl Fn(f32, f32) -> f32) -> PhotometricWeb {
        let symmetry = match (h.first(), h.last()) {
            _ if h.len() == 1 => HorizontalSymmetry::Axial,
            (Some(&0.0), Some(&90.0)) => HorizontalSymmetry::Quadrant,
            (Some(&0.0), Some(&180.0)) => HorizontalSymmetry::Bilateral,
            (Some(&90.0), Some(&270.0)) => HorizontalSymmetry::BilateralC90,
            _ => HorizontalSymmetry::Full,
        };
        let candela = h.iter().flat_map(|&c| v.iter().map(move |&g| (c, g))).map(|(c, g)| f(c, g)).collect();
        PhotometricWeb {
            file: "test.ies".into(),
            kind: PhotometricType::C,
            symmetry,
            vertical_deg: v,
            horizontal_deg: h,
            candela,
            lamp_lumens: None,
            luminaire_lumens: None,
            multiplier: 1.0,
            label: String::new(),
        }
    }

    fn steps(a: f32, b: f32, s: f32) -> Vec<f32> {
        let n = ((b - a) / s).round() as usize;
        (0..=n).map(|i| a + i as f32 * s).collect()
    }

    /// A Lambertian downlight I = I0 cos(gamma) has flux pi I0, whatever symmetry stores it.
    #[test]
    fn flux_of_a_cosine_distribution_is_pi_i0() {
        let f = |_: f32, g: f32| if g <= 90.0 { 1000.0 * g.to_radians().cos() } else { 0.0 };
        for h in [vec![0.0], steps(0.0, 90.0, 15.0), steps(0.0, 180.0, 15.0), steps(0.0, 360.0, 15.0)] {
            let w = web_c(h, steps(0.0, 180.0, 2.5), f);
            let flux = w.flux();
            assert!((flux / (std::f64::consts::PI * 1000.0) - 1.0).abs() < 2e-3, "{:?}: {flux}", w.symmetry);
        }
    }

    /// Symmetric storage answers for the whole circle: C and its mirror images agree with the
    /// full table of the same distribution.
    #[test]
    fn symmetries_unfold_to_the_full_table() {
        let f = |c: f32, g: f32| (1.0 + c.to_radians().cos().powi(2)) * (g / 10.0 + 1.0);
        let full = web_c(steps(0.0, 360.0, 10.0), steps(0.0, 90.0, 10.0), f);
        let quad = web_c(steps(0.0, 90.0, 10.0), steps(0.0, 90.0, 10.0), f);
        let bi = web_c(steps(0.0, 180.0, 10.0), steps(0.0, 90.0, 10.0), f);
        for c in [0.0f32, 20.0, 95.0, 170.0, 200.0, 290.0, 355.0] {
            for g in [0.0f32, 33.0, 89.0] {
                let want = full.intensity_at(c, g);
                assert!((quad.intensity_at(c, g) - want).abs() < 1e-3 * want, "quadrant C{c} g{g}");
                assert!((bi.intensity_at(c, g) - want).abs() < 1e-3 * want, "bilateral C{c} g{g}");
            }
        }
        assert_eq!(full.intensity_at(10.0, 120.0), 0.0, "beyond the measured gamma");
    }

    /// Interpolation is exact at the measured angles and linear between them; directions map to
    /// the angles of the module documentation.
    #[test]
    fn directions_map_to_the_documented_angles() {
        let w = web_c(steps(0.0, 360.0, 90.0), vec![0.0, 90.0, 180.0], |c, g| c + g);
        assert_eq!(w.intensity(Vec3::NEG_Z), 0.0 + 0.0);
        assert!((w.intensity(Vec3::X) - 90.0).abs() < 1e-3, "C0 horizontal");
        assert!((w.intensity(Vec3::Y) - 180.0).abs() < 1e-3, "C90 horizontal");
        assert!((w.intensity(Vec3::NEG_Y) - 360.0).abs() < 1e-3, "C270 horizontal");
        assert!((w.intensity_at(45.0, 45.0) - 90.0).abs() < 1e-3);
        let mut b = w.clone();
        b.kind = PhotometricType::B;
        assert_eq!(b.angles(Vec3::NEG_Z), (0.0, 0.0));
        let (h, v) = b.angles(Vec3::X);
        assert!((v - 90.0).abs() < 1e-4, "{h} {v}");
        let mut a = w;
        a.kind = PhotometricType::A;
        assert_eq!(a.angles(Vec3::X), (0.0, 0.0));
        assert!((a.angles(Vec3::NEG_Z).1 + 90.0).abs() < 1e-4);
    }

    #[test]
    fn aimed_frames_stay_orthonormal_and_point_their_nadir() {
        let down = aim_frame(Vec3::NEG_Y, 0.0);
        assert!((down.x_axis - Vec3::X).length() < 1e-6 && (down.y_axis - Vec3::NEG_Z).length() < 1e-6);
        for (aim, roll) in [(Vec3::new(1.0, -1.0, 0.0), 30.0), (Vec3::Y, 0.0), (Vec3::new(0.0, 0.0, -1.0), -90.0)] {
            let f = aim_frame(aim, roll);
            assert!((-f.z_axis - aim.normalize()).length() < 1e-5, "{aim}: nadir {}", -f.z_axis);
            assert!((f.determinant() - 1.0).abs() < 1e-5 && f.x_axis.dot(f.y_axis).abs() < 1e-5);
        }
        // rolling by 90 degrees about straight down turns C0 from +X to -Z (counter-clockwise
        // seen from behind, i.e. from above)
        let rolled = aim_frame(Vec3::NEG_Y, 90.0);
        assert!((rolled.x_axis - Vec3::NEG_Z).length() < 1e-5, "{}", rolled.x_axis);
    }
}
