//! Converter from the Zemax / Radiant Imaging tabular BSDF text format (`.bsdf`, the "BSDF Data
//! Interchange" format of ASTM E2387-style measurements) to a [`TabulatedSpec`].
//!
//! The format (from its public description): `#` comment lines; `Source`, `Symmetry`
//! (PlaneSymmetrical | Asymmetrical | Asymmetrical4D), `SpectralContent` (Monochrome | XYZ),
//! `ScatterType` (BRDF | BTDF); then `SampleRotation N`, `AngleOfIncidence N`, `ScatterAzimuth N`,
//! `ScatterRadial N`, each followed by its N angles in degrees; then a spectral block label
//! (`Monochrome`, or `TristimulusX/Y/Z`), `DataBegin`, and per sample rotation and angle of
//! incidence a line `TIS value` followed by one row of ScatterRadial values per azimuth;
//! `DataEnd`. The scatter angles are specular-relative: radial 0 is the specular (BRDF) or
//! straight-through (BTDF) direction, azimuth 0 points from it towards the normal — exactly the
//! `specular` grid of the TOML format, so values are copied, not resampled.
//!
//! Choices: the sample rotation becomes the incidence azimuth (anisotropic tables); a
//! PlaneSymmetrical file has azimuths 0..180 (mirror symmetric); monochrome data is spectrally
//! flat (one wavelength, 555 nm); of tristimulus data the Y block (luminance) is used, flat, with
//! a warning; BTDF data is straight-through (no refraction: `ior` 1); TIS lines are checked for
//! being finite but not used (the table's integral is recomputed on load).

use std::path::Path;

use quasar_materials::TabulatedSpec;
use quasar_materials::tabulated::{BackFace, Face, MAX_AXIS_LEN, ScatterGrid, ScatterTable};

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::small_text::read_small_text;

/// A converted file: the spec plus warnings (dropped information).
#[derive(Clone, Debug, PartialEq)]
pub struct Converted {
    /// The tabulated BSDF (not yet validated: pass it to `TabulatedTable::new`).
    pub spec: TabulatedSpec,
    /// Information the conversion dropped.
    pub warnings: Vec<String>,
    /// Header fields (`Source`, `Symmetry`, ...) for the provenance.
    pub header: Vec<(String, String)>,
}

/// Reads and converts the `.bsdf` file at `path`.
pub fn convert_zemax_bsdf(path: &Path) -> Result<Converted, ImportError> {
    let text = read_small_text(path, "Zemax BSDF file")?;
    parse_zemax_bsdf(&text, path)
}

/// Tokens with their 1-based line numbers, comments and blank lines skipped.
struct Tokens<'a> {
    items: Vec<(&'a str, usize)>,
    pos: usize,
    file: &'a Path,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str, file: &'a Path) -> Self {
        let mut items = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.starts_with('#') {
                continue;
            }
            items.extend(line.split_whitespace().map(|t| (t, i + 1)));
        }
        Self { items, pos: 0, file }
    }

    fn line(&self) -> usize {
        self.items.get(self.pos).or(self.items.last()).map_or(1, |t| t.1)
    }

    fn err(&self, kind: ImportErrorKind, msg: impl Into<String>) -> ImportError {
        ImportError::new(kind, ErrorPlace::line(self.file, self.line()), msg)
    }

    fn next(&mut self, what: &str) -> Result<&'a str, ImportError> {
        let t = self
            .items
            .get(self.pos)
            .ok_or_else(|| self.err(ImportErrorKind::Syntax, format!("file ends where {what} was expected")))?;
        self.pos += 1;
        Ok(t.0)
    }

    fn keyword(&mut self, key: &str) -> Result<(), ImportError> {
        let t = self.next(key)?;
        if !t.eq_ignore_ascii_case(key) {
            self.pos -= 1;
            return Err(self.err(ImportErrorKind::Syntax, format!("expected `{key}`, found `{t}`")));
        }
        Ok(())
    }

    fn number(&mut self, what: &str) -> Result<f64, ImportError> {
        let t = self.next(what)?;
        match t.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => {
                self.pos -= 1;
                Err(self.err(ImportErrorKind::InvalidValue, format!("{what}: `{t}` is not a finite number")))
            }
        }
    }

    fn count(&mut self, what: &str) -> Result<usize, ImportError> {
        let t = self.next(what)?;
        match t.parse::<usize>() {
            Ok(n) if (1..=MAX_AXIS_LEN).contains(&n) => Ok(n),
            _ => {
                self.pos -= 1;
                Err(self.err(
                    ImportErrorKind::TooLarge,
                    format!("{what}: count `{t}` must be an integer in 1..={MAX_AXIS_LEN}"),
                ))
            }
        }
    }

    /// `KEY N` followed by N angles (degrees).
    fn angles(&mut self, key: &str) -> Result<Vec<f64>, ImportError> {
        self.keyword(key)?;
        let n = self.count(key)?;
        if n > self.items.len() - self.pos {
            return Err(self
                .err(ImportErrorKind::Syntax, format!("{key} declares {n} angles, the file has fewer numbers left")));
        }
        (0..n).map(|i| self.number(&format!("{key} angle {i}"))).collect()
    }
}

/// Converts `.bsdf` text as if read from `path` (for messages).
pub fn parse_zemax_bsdf(text: &str, path: &Path) -> Result<Converted, ImportError> {
    let mut tk = Tokens::new(text, path);
    let mut header = Vec::new();
    for key in ["Source", "Symmetry", "SpectralContent", "ScatterType"] {
        tk.keyword(key)?;
        header.push((key.to_owned(), tk.next(key)?.to_owned()));
    }
    let value = |k: &str| header.iter().find(|(h, _)| h == k).map(|(_, v)| v.to_ascii_lowercase()).unwrap_or_default();
    let symmetry = value("Symmetry");
    if !["planesymmetrical", "asymmetrical", "asymmetrical4d"].contains(&symmetry.as_str()) {
        return Err(tk.err(
            ImportErrorKind::Unsupported,
            format!("unknown Symmetry `{symmetry}` (PlaneSymmetrical, Asymmetrical, Asymmetrical4D)"),
        ));
    }
    let spectral = value("SpectralContent");
    let blocks: &[&str] = match spectral.as_str() {
        "monochrome" => &["Monochrome"],
        "xyz" | "tristimulus" => &["TristimulusX", "TristimulusY", "TristimulusZ"],
        other => {
            return Err(tk.err(
                ImportErrorKind::Unsupported,
                format!("unsupported SpectralContent `{other}` (Monochrome or XYZ)"),
            ));
        }
    };
    let transmit = match value("ScatterType").as_str() {
        "brdf" => false,
        "btdf" => true,
        other => {
            return Err(tk.err(ImportErrorKind::InvalidValue, format!("ScatterType `{other}` must be BRDF or BTDF")));
        }
    };
    let rotations = tk.angles("SampleRotation")?;
    let aoi = tk.angles("AngleOfIncidence")?;
    let azimuth = tk.angles("ScatterAzimuth")?;
    let radial = tk.angles("ScatterRadial")?;
    let per_block = rotations.len() * aoi.len() * azimuth.len() * radial.len();
    let n = ScatterTable::expected_len("data", 1, rotations.len() * aoi.len(), radial.len(), azimuth.len())
        .map_err(|e| tk.err(ImportErrorKind::TooLarge, e.to_string()))?;
    debug_assert_eq!(n, per_block);
    let mut warnings = Vec::new();
    let mut kept: Option<Vec<f32>> = None;
    for (b, block) in blocks.iter().enumerate() {
        tk.keyword(block)?;
        tk.keyword("DataBegin")?;
        let keep = blocks.len() == 1 || b == 1;
        let mut values = if keep { vec![0.0f32; per_block] } else { Vec::new() };
        for r in 0..rotations.len() {
            for i in 0..aoi.len() {
                tk.keyword("TIS")?;
                tk.number("TIS")?;
                for a in 0..azimuth.len() {
                    for t in 0..radial.len() {
                        let x = tk.number(&format!(
                            "{block} value (rotation {}, incidence {}, azimuth {}, radial {})",
                            rotations[r], aoi[i], azimuth[a], radial[t]
                        ))?;
                        if x < 0.0 {
                            tk.pos -= 1;
                            return Err(tk.err(ImportErrorKind::InvalidValue, format!("negative BSDF value {x}")));
                        }
                        if keep {
                            // TOML order: [wavelength][phi_i][theta_i][theta][phi].
                            values[((r * aoi.len() + i) * radial.len() + t) * azimuth.len() + a] = x as f32;
                        }
                    }
                }
            }
        }
        tk.keyword("DataEnd")?;
        if keep {
            kept = Some(values);
        }
    }
    if blocks.len() > 1 {
        warnings.push(
            "tristimulus data: the Y (luminance) block is used as a spectrally flat BSDF; X and Z are dropped".into(),
        );
    }
    if tk.pos < tk.items.len() {
        warnings.push(format!("ignored text after DataEnd (line {})", tk.line()));
    }
    let deg = |v: &[f64]| v.iter().map(|x| (*x as f32).to_radians()).collect::<Vec<f32>>();
    let mut phi = deg(&azimuth);
    let mut values = kept.unwrap_or_default();
    // A full-circle azimuth list may repeat 0 as 360: drop the duplicate column.
    if phi.len() > 1 && (phi[phi.len() - 1] - std::f32::consts::TAU).abs() < 1e-5 {
        let n_p = phi.len();
        phi.pop();
        values = values.chunks(n_p).flat_map(|row| row[..n_p - 1].iter().copied()).collect();
    }
    if symmetry == "planesymmetrical" && rotations.len() > 1 {
        warnings.push("PlaneSymmetrical data with several sample rotations: read as anisotropic".into());
    }
    let table = ScatterTable { grid: ScatterGrid::SpecularRelative, theta: deg(&radial), phi, values };
    let face = if transmit { Face { brdf: None, btdf: Some(table) } } else { Face { brdf: Some(table), btdf: None } };
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("bsdf").to_owned();
    let spec = TabulatedSpec {
        name,
        wavelengths: vec![555.0],
        theta_i: deg(&aoi),
        phi_i: deg(&rotations),
        ior: transmit.then_some(1.0),
        front: face,
        back: BackFace::Same,
    };
    Ok(Converted { spec, warnings, header })
}
