//! Spectra in the TOML scene format: a bare number, `{constant}`, `{wavelengths, values}`,
//! `{blackbody}`, `{illuminant}`, `{rgb}` or `{file}` (CSV).

use std::path::Path;

use quasar_materials::spectrum::{Spectrum, SpectrumError, StandardIlluminant};
use toml::de::DeValue;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind, did_you_mean};
use crate::small_text::read_small_text;
use crate::toml_reader::{Doc, Span, Tbl, Val, float, float_list, string};

/// Largest number of entries in a spectrum table (inline or CSV).
pub const MAX_SPECTRUM_ENTRIES: usize = 100_000;

/// What a spectrum describes; decides what `{rgb = ...}` means and its bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SpectrumUse {
    /// A reflectance or transmittance in [0, 1]: `rgb` -> [`Spectrum::rgb_reflectance`].
    Reflectance,
    /// Emitted light: `rgb` -> [`Spectrum::rgb_illuminant`].
    Emission,
    /// A physical quantity such as eta or k: `rgb` is not meaningful.
    Quantity,
}

const FORMS: [&str; 7] = ["constant", "wavelengths", "values", "blackbody", "illuminant", "rgb", "file"];
const ILLUMINANTS: [&str; 2] = ["A", "D65"];

fn spectrum_error(doc: &Doc<'_>, span: &Span, what: &str, e: SpectrumError) -> ImportError {
    doc.invalid(span, format!("`{what}`: {e}"))
}

/// Reads a spectrum value named `what` (used in messages).
pub(crate) fn spectrum(doc: &Doc<'_>, v: &Val<'_>, what: &str, usage: SpectrumUse) -> Result<Spectrum, ImportError> {
    match v.get_ref() {
        DeValue::Integer(_) | DeValue::Float(_) => {
            let x = float(doc, v, what)?;
            Spectrum::constant(x).map_err(|e| spectrum_error(doc, &v.span(), what, e))
        }
        DeValue::Table(_) => table_spectrum(&Tbl::of(doc, v, what)?, usage),
        DeValue::String(s) => Err(doc.invalid(
            &v.span(),
            format!(
                "`{what}` must be a number or a table such as {{ illuminant = \"{s}\" }}, {{ constant = 1 }}, \
                 {{ rgb = [r, g, b] }}, {{ blackbody = 3000 }}, {{ wavelengths = [...], values = [...] }} or {{ file = \"x.csv\" }}"
            ),
        )),
        other => Err(doc.invalid(
            &v.span(),
            format!("`{what}` must be a number or a spectrum table, got {}", crate::toml_reader::type_name(other)),
        )),
    }
}

fn table_spectrum(t: &Tbl<'_>, usage: SpectrumUse) -> Result<Spectrum, ImportError> {
    let doc = t.doc;
    t.check_keys(&FORMS)?;
    let forms: Vec<&str> = ["constant", "wavelengths", "blackbody", "illuminant", "rgb", "file"]
        .into_iter()
        .filter(|k| t.has(k))
        .collect();
    if forms.len() != 1 {
        let msg = if forms.is_empty() {
            if t.has("values") {
                format!("`{}`: `values` needs `wavelengths`", t.path)
            } else {
                format!(
                    "`{}`: a spectrum table needs one of: constant, wavelengths + values, blackbody, illuminant, rgb, file",
                    t.path
                )
            }
        } else {
            format!("`{}`: give only one spectrum form, got {}", t.path, forms.join(" and "))
        };
        return Err(doc.invalid(&t.span, msg));
    }
    if forms[0] != "wavelengths" && t.has("values") {
        return Err(doc.invalid(&t.key_span("values"), format!("`{}`: `values` only goes with `wavelengths`", t.path)));
    }
    let v = t.get(forms[0]).unwrap_or_else(|| unreachable!());
    let what = t.key_path(forms[0]);
    let span = v.span();
    match forms[0] {
        "constant" => {
            let x = float(doc, v, &what)?;
            Spectrum::constant(x).map_err(|e| spectrum_error(doc, &span, &what, e))
        }
        "wavelengths" => {
            let vals = t.get("values").ok_or_else(|| t.missing("values"))?;
            let lambda = float_list(doc, v, &what, MAX_SPECTRUM_ENTRIES)?;
            let values = float_list(doc, vals, &t.key_path("values"), MAX_SPECTRUM_ENTRIES)?;
            Spectrum::piecewise_linear(lambda, values).map_err(|e| {
                // point at the offending entry when there is one
                let (arr, idx) = match &e {
                    SpectrumError::NotIncreasing { index, .. } => (v, Some(*index)),
                    SpectrumError::Negative { index, .. } | SpectrumError::NotFinite { index, .. } => {
                        (vals, Some(*index))
                    }
                    _ => (v, None),
                };
                let at = match (arr.get_ref(), idx) {
                    (DeValue::Array(a), Some(i)) if i < a.len() => a[i].span(),
                    _ => t.span.clone(),
                };
                spectrum_error(doc, &at, &t.path, e)
            })
        }
        "blackbody" => {
            let k = float(doc, v, &what)?;
            Spectrum::blackbody(k).map_err(|e| spectrum_error(doc, &span, &what, e))
        }
        "illuminant" => {
            let name = string(doc, v, &what)?;
            let ill = StandardIlluminant::from_name(name).ok_or_else(|| {
                doc.invalid(
                    &span,
                    format!(
                        "`{what}`: unknown illuminant \"{name}\"; known: {}{}",
                        ILLUMINANTS.join(", "),
                        did_you_mean(name, ILLUMINANTS)
                    ),
                )
            })?;
            Ok(Spectrum::illuminant(ill))
        }
        "rgb" => {
            let rgb = crate::toml_reader::floats::<3>(doc, v, &what)?;
            let r = match usage {
                SpectrumUse::Reflectance => Spectrum::rgb_reflectance(rgb),
                SpectrumUse::Emission => Spectrum::rgb_illuminant(rgb),
                SpectrumUse::Quantity => {
                    return Err(doc.invalid(
                        &span,
                        format!("`{what}`: an RGB colour is not meaningful here; give a number or a wavelength table"),
                    ));
                }
            };
            r.map_err(|e| spectrum_error(doc, &span, &what, e))
        }
        _ => {
            let name = string(doc, v, &what)?;
            let path = doc.resolve(name);
            csv_spectrum(&path).map_err(|e| match e.kind {
                ImportErrorKind::MissingFile | ImportErrorKind::Io => doc.error(
                    e.kind,
                    &span,
                    format!("`{what}`: cannot read spectrum file `{name}` ({}): {}", path.display(), e.message),
                ),
                _ => e.included_from(doc.place(&span)),
            })
        }
    }
}

/// Reads a spectrum CSV: one `wavelength_nm,value` pair per line (comma, semicolon, tab or
/// spaces between them), `#` starts a comment, blank lines are skipped, and the first data line
/// may be a non-numeric header. Errors name the CSV file and line.
pub fn csv_spectrum(path: &Path) -> Result<Spectrum, ImportError> {
    let text = read_small_text(path, "spectrum file")?;
    let err =
        |line: usize, msg: String| ImportError::new(ImportErrorKind::InvalidValue, ErrorPlace::line(path, line), msg);
    let mut lambda = Vec::new();
    let mut values = Vec::new();
    let mut lines = Vec::new();
    let mut seen_data = false;
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let fields: Vec<&str> =
            content.split(|c: char| c == ',' || c == ';' || c.is_whitespace()).filter(|s| !s.is_empty()).collect();
        let parsed: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        if !seen_data && parsed.iter().all(|p| p.is_none()) {
            seen_data = true; // a header line
            continue;
        }
        seen_data = true;
        if fields.len() != 2 {
            return Err(err(n, format!("expected `wavelength_nm,value`, got {} fields", fields.len())));
        }
        let mut xy = [0.0f32; 2];
        for k in 0..2 {
            match parsed[k] {
                Some(x) if x.is_finite() && x.abs() <= f32::MAX as f64 => xy[k] = x as f32,
                Some(_) => return Err(err(n, format!("`{}` is not a finite number", fields[k]))),
                None => return Err(err(n, format!("`{}` is not a number", fields[k]))),
            }
        }
        if lambda.len() >= MAX_SPECTRUM_ENTRIES {
            return Err(ImportError::new(
                ImportErrorKind::TooLarge,
                ErrorPlace::line(path, n),
                format!("more than {MAX_SPECTRUM_ENTRIES} entries"),
            ));
        }
        lambda.push(xy[0]);
        values.push(xy[1]);
        lines.push(n);
    }
    if lambda.is_empty() {
        return Err(ImportError::new(
            ImportErrorKind::InvalidValue,
            ErrorPlace::file(path),
            "no `wavelength_nm,value` lines",
        ));
    }
    Spectrum::piecewise_linear(lambda, values).map_err(|e| {
        let line = match &e {
            SpectrumError::NotIncreasing { index, .. }
            | SpectrumError::Negative { index, .. }
            | SpectrumError::NotFinite { index, .. } => lines.get(*index).copied(),
            _ => None,
        };
        let place = line.map_or_else(|| ErrorPlace::file(path), |l| ErrorPlace::line(path, l));
        ImportError::new(ImportErrorKind::InvalidValue, place, e.to_string())
    })
}
