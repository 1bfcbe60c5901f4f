//! Tabulated spectral BSDFs (docs/architecture.md §5): measured or generated BRDF/BTDF tables in 1/sr
//! over wavelength, incidence and scatter angles, on an absolute or a specular-relative grid.
//!
//! A [`TabulatedSpec`] is the plain data a loader reads (materials/README.md documents the TOML
//! form); [`TabulatedTable::new`] validates it (finite, non-negative, monotone grids, albedo <= 1)
//! and builds the sampling distributions; [`TabulatedBsdf`](crate::bsdf::TabulatedBsdf) evaluates and samples it at a path's
//! wavelengths. Interpolation: linear in wavelength (clamped to the table's range), incidence
//! polar angle (clamped), incidence azimuth (periodic, anisotropic tables) and bilinear in the
//! scatter (theta, phi) cell; zero beyond the last scatter theta.

use std::f32::consts::{FRAC_PI_2, PI, TAU};
use std::fmt;

pub(crate) mod distribution;
pub(crate) mod geometry;

use distribution::LobeDistribution;

/// Largest number of values one scatter table may hold (2^24 f32 = 64 MiB). Loaders check the
/// declared grid against it before allocating.
pub const MAX_TABLE_ENTRIES: usize = 1 << 24;
/// Largest number of entries of one grid axis.
pub const MAX_AXIS_LEN: usize = 1 << 16;
/// Directional albedo (reflected plus transmitted) allowed above 1 on load: the quadrature of the
/// interpolated table is exact to about 0.1 %, the rest is measurement noise a user may keep.
pub const ALBEDO_TOLERANCE: f32 = 0.02;

/// The coordinates of a scatter table's (theta, phi) grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScatterGrid {
    /// theta from the normal (on the lobe's side), phi from the forward half of the incidence plane.
    Absolute,
    /// theta from the mirror (BRDF) or refraction (BTDF) direction, phi around it, 0 towards the
    /// normal: narrow lobes need few samples.
    SpecularRelative,
}

/// One BRDF or BTDF table of one face: `values[wavelength][phi_i][theta_i][theta][phi]` in 1/sr.
#[derive(Clone, Debug, PartialEq)]
pub struct ScatterTable {
    /// Grid kind.
    pub grid: ScatterGrid,
    /// Scatter polar angles (radians): strictly increasing from 0; f = 0 beyond the last.
    pub theta: Vec<f32>,
    /// Scatter azimuths (radians): strictly increasing from 0, periodic (the last cell wraps to
    /// 2 pi); one entry = independent of phi. An isotropic table may end at pi: mirror symmetric.
    pub phi: Vec<f32>,
    /// The values, row-major in the order above.
    pub values: Vec<f32>,
}

/// The tables used when light arrives on one face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Face {
    /// Reflection (light leaves on the same side).
    pub brdf: Option<ScatterTable>,
    /// Transmission (light leaves on the other side).
    pub btdf: Option<ScatterTable>,
}

/// What the back face does.
#[derive(Clone, Debug, PartialEq)]
pub enum BackFace {
    /// The same tables as the front (a symmetric surface).
    Same,
    /// Nothing: light arriving from behind is absorbed.
    Black,
    /// Its own tables.
    Own(Face),
}

/// A tabulated BSDF as read from a file, before validation.
#[derive(Clone, Debug, PartialEq)]
pub struct TabulatedSpec {
    /// Name (for messages and reports).
    pub name: String,
    /// Wavelengths in nm, strictly increasing; values outside are clamped to the nearest.
    pub wavelengths: Vec<f32>,
    /// Incidence polar angles (radians) in [0, pi/2], strictly increasing.
    pub theta_i: Vec<f32>,
    /// Incidence azimuths (radians) in [0, 2 pi), strictly increasing from 0; `[0]` = isotropic.
    pub phi_i: Vec<f32>,
    /// Relative IOR (back side over front side); the axis of specular-relative BTDFs.
    pub ior: Option<f32>,
    /// Tables for light arriving on the front (the normal's side).
    pub front: Face,
    /// The back face.
    pub back: BackFace,
}

/// A validation error: which table, which entry (indices in `values` order) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct TableError {
    /// "wavelengths", "front.brdf", "back.btdf.theta", ...
    pub table: String,
    /// Indices of the offending entry, when one is at fault.
    pub entry: Option<Vec<usize>>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for TableError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}`", self.table)?;
        if let Some(e) = &self.entry {
            write!(f, " entry {e:?}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for TableError {}

fn err(table: impl Into<String>, entry: Option<Vec<usize>>, message: impl Into<String>) -> TableError {
    TableError { table: table.into(), entry, message: message.into() }
}

/// A validated tabulated BSDF with its sampling distributions (immutable, shared by threads).
pub struct TabulatedTable {
    spec: TabulatedSpec,
    /// Per face (front, back) and lobe (reflection, transmission): sampling distributions.
    dists: [[Option<LobeDistribution>; 2]; 2],
}

impl fmt::Debug for TabulatedTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "TabulatedTable({:?}: {} wavelengths, {} x {} incidences)",
            self.spec.name,
            self.spec.wavelengths.len(),
            self.spec.theta_i.len(),
            self.spec.phi_i.len()
        )
    }
}

impl PartialEq for TabulatedTable {
    fn eq(&self, other: &Self) -> bool {
        self.spec == other.spec
    }
}

/// Checks an axis: non-empty, finite, strictly increasing, within [lo, hi] (`hi_open`: < hi).
fn check_axis(name: &str, v: &[f32], lo: f32, hi: f32, hi_open: bool, unit: &str) -> Result<(), TableError> {
    let scale = if unit == "deg" { 180.0 / PI } else { 1.0 };
    if v.is_empty() {
        return Err(err(name, None, "must have at least one entry"));
    }
    if v.len() > MAX_AXIS_LEN {
        return Err(err(name, None, format!("has {} entries, more than the limit {MAX_AXIS_LEN}", v.len())));
    }
    for (i, &x) in v.iter().enumerate() {
        if !x.is_finite() || x < lo || x > hi || (hi_open && x >= hi) {
            let bound = if hi_open { ")" } else { "]" };
            return Err(err(
                name,
                Some(vec![i]),
                format!("{} {unit} is outside [{}, {}{bound}", x * scale, lo * scale, hi * scale),
            ));
        }
        if i > 0 && x <= v[i - 1] {
            return Err(err(
                name,
                Some(vec![i]),
                format!(
                    "{} {unit} does not increase (previous {}): the grid must be strictly increasing",
                    x * scale,
                    v[i - 1] * scale
                ),
            ));
        }
    }
    Ok(())
}

impl ScatterTable {
    /// Number of values the table must hold for `n_wl` wavelengths and `n_inc` incidences, or
    /// an error when it exceeds [`MAX_TABLE_ENTRIES`] (checked before anything is allocated).
    pub fn expected_len(
        name: &str,
        n_wl: usize,
        n_inc: usize,
        n_theta: usize,
        n_phi: usize,
    ) -> Result<usize, TableError> {
        let n = [n_wl, n_inc, n_theta, n_phi].iter().try_fold(1usize, |a, &b| a.checked_mul(b));
        match n {
            Some(n) if n <= MAX_TABLE_ENTRIES => Ok(n),
            _ => Err(err(
                name,
                None,
                format!(
                    "{n_wl} wavelengths x {n_inc} incidences x {n_theta} theta x {n_phi} phi entries exceed the \
                     limit of {MAX_TABLE_ENTRIES} values per table"
                ),
            )),
        }
    }

    /// Validates grid and values for a table named `name`.
    fn validate(&self, name: &str, dims: (usize, usize, usize)) -> Result<(), TableError> {
        let hi = if self.grid == ScatterGrid::Absolute { FRAC_PI_2 } else { PI };
        check_axis(&format!("{name}.theta"), &self.theta, 0.0, hi, false, "deg")?;
        check_axis(&format!("{name}.phi"), &self.phi, 0.0, TAU, true, "deg")?;
        if self.theta.len() < 2 || self.theta[0] != 0.0 {
            return Err(err(format!("{name}.theta"), None, "needs at least two angles, the first 0"));
        }
        if self.phi[0] != 0.0 {
            return Err(err(format!("{name}.phi"), Some(vec![0]), "the first azimuth must be 0"));
        }
        let (n_wl, n_pi, n_ti) = dims;
        let n = Self::expected_len(name, n_wl, n_pi * n_ti, self.theta.len(), self.phi.len())?;
        if self.values.len() != n {
            return Err(err(
                format!("{name}.values"),
                None,
                format!(
                    "holds {} values, the grid needs {n} ({n_wl} wavelengths x {n_pi} x {n_ti} incidences x {} theta x {} phi)",
                    self.values.len(),
                    self.theta.len(),
                    self.phi.len()
                ),
            ));
        }
        let shape = [n_wl, n_pi, n_ti, self.theta.len(), self.phi.len()];
        if let Some(i) = self.values.iter().position(|v| !v.is_finite() || *v < 0.0) {
            let mut idx = vec![0; 5];
            let mut r = i;
            for d in (0..5).rev() {
                idx[d] = r % shape[d];
                r /= shape[d];
            }
            return Err(err(
                format!("{name}.values"),
                Some(idx),
                format!("{} is not a finite, non-negative BSDF value (1/sr)", self.values[i]),
            ));
        }
        Ok(())
    }

    /// An isotropic table given over phi in [0, pi] (mirror symmetric about the incidence plane)
    /// expanded to the full periodic [0, 2 pi).
    fn expand_mirror(&mut self) {
        let n_p = self.phi.len();
        // Exactly 180 degrees, allowing for the f32 rounding of a degree value written as text.
        if n_p < 2 || (self.phi[n_p - 1] - PI).abs() > 1e-5 {
            return;
        }
        self.phi[n_p - 1] = PI;
        let mirrored: Vec<usize> = (1..n_p - 1).rev().collect();
        let mut phi = self.phi.clone();
        phi.extend(mirrored.iter().map(|&j| TAU - self.phi[j]));
        let rows = self.values.len() / n_p;
        let mut values = Vec::with_capacity(rows * phi.len());
        for r in 0..rows {
            let row = &self.values[r * n_p..(r + 1) * n_p];
            values.extend_from_slice(row);
            values.extend(mirrored.iter().map(|&j| row[j]));
        }
        self.phi = phi;
        self.values = values;
    }
}

impl TabulatedTable {
    /// Validates `spec` (grids finite and strictly increasing, values finite and >= 0, sizes
    /// within limits, directional albedo R + T <= 1 + [`ALBEDO_TOLERANCE`] at every wavelength and
    /// incidence) and builds the sampling distributions.
    pub fn new(spec: TabulatedSpec) -> Result<Self, TableError> {
        Self::build(spec, true)
    }

    /// Like [`new`](Self::new) without the albedo check (for reports on tables that fail it).
    pub fn new_without_energy_check(spec: TabulatedSpec) -> Result<Self, TableError> {
        Self::build(spec, false)
    }

    fn build(mut spec: TabulatedSpec, check_energy: bool) -> Result<Self, TableError> {
        check_axis("wavelengths", &spec.wavelengths, 1.0, 1e5, false, "nm")?;
        check_axis("incidence.theta", &spec.theta_i, 0.0, FRAC_PI_2, false, "deg")?;
        check_axis("incidence.phi", &spec.phi_i, 0.0, TAU, true, "deg")?;
        if spec.phi_i[0] != 0.0 {
            return Err(err("incidence.phi", Some(vec![0]), "the first azimuth must be 0"));
        }
        if let Some(ior) = spec.ior
            && !(ior.is_finite() && (1e-3..=1e3).contains(&ior))
        {
            return Err(err("ior", None, format!("{ior} must be finite and within [0.001, 1000]")));
        }
        let isotropic = spec.phi_i.len() == 1;
        let dims = (spec.wavelengths.len(), spec.phi_i.len(), spec.theta_i.len());
        let ior = spec.ior;
        let mut any = false;
        for (face_name, face) in Self::faces_mut(&mut spec) {
            for (lobe, t) in [("brdf", &mut face.brdf), ("btdf", &mut face.btdf)] {
                let Some(t) = t else { continue };
                any = true;
                let name = format!("{face_name}.{lobe}");
                t.validate(&name, dims)?;
                if lobe == "btdf" && t.grid == ScatterGrid::SpecularRelative && ior.is_none() {
                    return Err(err(
                        name,
                        None,
                        "a specular-relative BTDF needs the relative `ior` (its axis is the refraction direction)",
                    ));
                }
                if isotropic {
                    t.expand_mirror();
                }
            }
        }
        if !any {
            return Err(err("front", None, "the material has no BRDF or BTDF table"));
        }
        let mut table = TabulatedTable { spec, dists: Default::default() };
        for back in [false, true] {
            for transmit in [false, true] {
                if let Some(t) = table.lobe_table(back, transmit) {
                    let d = LobeDistribution::build(&table, t, back, transmit);
                    table.dists[back as usize][transmit as usize] = Some(d);
                }
            }
        }
        if check_energy {
            table.check_energy()?;
        }
        Ok(table)
    }

    fn faces_mut(spec: &mut TabulatedSpec) -> Vec<(&'static str, &mut Face)> {
        let mut v = vec![("front", &mut spec.front)];
        if let BackFace::Own(b) = &mut spec.back {
            v.push(("back", b));
        }
        v
    }

    /// The validated data.
    pub fn spec(&self) -> &TabulatedSpec {
        &self.spec
    }

    /// The tables of the face light arrives on (None: black).
    pub fn face(&self, back: bool) -> Option<&Face> {
        match (back, &self.spec.back) {
            (false, _) | (true, BackFace::Same) => Some(&self.spec.front),
            (true, BackFace::Black) => None,
            (true, BackFace::Own(f)) => Some(f),
        }
    }

    /// The reflection (`transmit = false`) or transmission table of a face.
    pub(crate) fn lobe_table(&self, back: bool, transmit: bool) -> Option<&ScatterTable> {
        let f = self.face(back)?;
        if transmit { f.btdf.as_ref() } else { f.brdf.as_ref() }
    }

    pub(crate) fn dist(&self, back: bool, transmit: bool) -> Option<&LobeDistribution> {
        self.dists[back as usize][transmit as usize].as_ref()
    }

    /// Relative IOR of the far side over the side light arrives on (1 without `ior`).
    pub(crate) fn eta(&self, back: bool) -> f32 {
        let n = self.spec.ior.unwrap_or(1.0);
        if back { 1.0 / n } else { n }
    }

    /// True when some face transmits.
    pub fn has_transmission(&self) -> bool {
        self.lobe_table(false, true).is_some() || self.lobe_table(true, true).is_some()
    }

    /// Number of incidence slices (phi_i x theta_i).
    pub(crate) fn n_slices(&self) -> usize {
        self.spec.phi_i.len() * self.spec.theta_i.len()
    }

    /// The slices around incidence (theta, phi) with their interpolation weights (up to 4).
    pub(crate) fn slices(&self, theta: f32, phi: f32) -> ([(usize, f32); 4], usize) {
        let (t0, t1, ft) = bracket(&self.spec.theta_i, theta);
        let (p0, p1, fp) =
            if self.spec.phi_i.len() == 1 { (0, 0, 0.0) } else { bracket_periodic(&self.spec.phi_i, phi) };
        let n_t = self.spec.theta_i.len();
        let mut out = [(0, 0.0); 4];
        let mut n = 0;
        for (p, wp) in [(p0, 1.0 - fp), (p1, fp)] {
            for (t, wt) in [(t0, 1.0 - ft), (t1, ft)] {
                let w = wp * wt;
                if w > 0.0 {
                    out[n] = (p * n_t + t, w);
                    n += 1;
                }
            }
        }
        (out, n)
    }

    /// Directional albedo (reflected, transmitted) of light arriving on a face at incidence
    /// slice (`phi_i` index, `theta_i` index) and wavelength index `l`: the integral of
    /// f |cos theta_o| over the outgoing directions of the interpolated table.
    pub fn albedo(&self, back: bool, l: usize, pi: usize, ti: usize) -> (f32, f32) {
        let slice = pi * self.spec.theta_i.len() + ti;
        let one = |transmit: bool| {
            self.lobe_table(back, transmit).map_or(0.0, |t| {
                distribution::cell_integrals(self, t, back, transmit, slice, &[(l, 1.0)]).iter().sum::<f64>() as f32
            })
        };
        (one(false), one(true))
    }

    /// The faces with their own data, as (`back`, name): the front, and the back when it has
    /// its own tables (a "same" back repeats the front, a "black" one scatters nothing).
    pub fn distinct_faces(&self) -> &'static [(bool, &'static str)] {
        if matches!(self.spec.back, BackFace::Own(_)) {
            &[(false, "front"), (true, "back")]
        } else {
            &[(false, "front")]
        }
    }

    fn check_energy(&self) -> Result<(), TableError> {
        for &(back, name) in self.distinct_faces() {
            for pi in 0..self.spec.phi_i.len() {
                for ti in 0..self.spec.theta_i.len() {
                    for l in 0..self.spec.wavelengths.len() {
                        let (r, t) = self.albedo(back, l, pi, ti);
                        if r + t > 1.0 + ALBEDO_TOLERANCE {
                            return Err(err(
                                name,
                                Some(vec![l, pi, ti]),
                                format!(
                                    "scatters more than it receives: albedo R + T = {r:.4} + {t:.4} = {:.4} > 1 at \
                                     {} nm, incidence theta {:.2} deg, phi {:.2} deg",
                                    r + t,
                                    self.spec.wavelengths[l],
                                    self.spec.theta_i[ti].to_degrees(),
                                    self.spec.phi_i[pi].to_degrees()
                                ),
                            ));
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// Linear interpolation bracket (i0, i1, t) of `x` in the increasing `v`, clamped to its ends.
#[inline]
pub(crate) fn bracket(v: &[f32], x: f32) -> (usize, usize, f32) {
    let n = v.len();
    if n == 1 || x <= v[0] || x.is_nan() {
        return (0, 0, 0.0);
    }
    if x >= v[n - 1] {
        return (n - 1, n - 1, 0.0);
    }
    let i = v.partition_point(|&a| a <= x) - 1;
    let t = (x - v[i]) / (v[i + 1] - v[i]);
    (i, i + 1, t.clamp(0.0, 1.0))
}

/// Bracket of angle `x` in [0, 2 pi) on the periodic grid `v` (v[0] = 0, last cell wraps to 2 pi).
#[inline]
pub(crate) fn bracket_periodic(v: &[f32], x: f32) -> (usize, usize, f32) {
    let n = v.len();
    if n == 1 || x.is_nan() {
        return (0, 0, 0.0);
    }
    let i = (v.partition_point(|&a| a <= x).max(1) - 1).min(n - 1);
    let (lo, hi, j) = if i + 1 < n { (v[i], v[i + 1], i + 1) } else { (v[i], TAU, 0) };
    (i, j, ((x - lo) / (hi - lo)).clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests;
