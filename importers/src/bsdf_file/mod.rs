//! Tabulated-BSDF material files (`materials/library/*.toml`, schema in materials/README.md):
//! reading them into a validated [`TabulatedTable`], writing a [`TabulatedSpec`] back as TOML,
//! and converting Zemax/Radiant tabular `.bsdf` files ([`zemax`]).
//!
//! Errors name the file, line and column, the table (`front.brdf`) and the entry
//! (`values[wavelength][phi_i][theta_i][theta][phi]`). Grid sizes are checked against
//! [`MAX_TABLE_ENTRIES`] before the values are read, and files above
//! [`MAX_SMALL_FILE_BYTES`](crate::small_text::MAX_SMALL_FILE_BYTES) are refused before they are read.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use quasar_materials::tabulated::{BackFace, Face, MAX_AXIS_LEN, MAX_TABLE_ENTRIES, ScatterGrid, ScatterTable};
use quasar_materials::{TabulatedSpec, TabulatedTable};
use toml::de::DeValue;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::small_text::read_small_text;
use crate::toml_reader::{Doc, Span, Tbl, Val, float_list, number, parse_document};

mod write;
pub mod zemax;

pub use write::to_toml;

/// The value of the required top-level `format` key.
pub const FORMAT: &str = "quasar-bsdf";
/// The schema version this reader understands.
pub const VERSION: i128 = 1;

const TOP_KEYS: [&str; 11] = [
    "format",
    "version",
    "name",
    "description",
    "units",
    "provenance",
    "wavelengths_nm",
    "ior",
    "incidence",
    "front",
    "back",
];

/// Reads and validates the tabulated-BSDF file at `path`.
pub fn load_tabulated_bsdf(path: &Path) -> Result<Arc<TabulatedTable>, ImportError> {
    let text = read_small_text(path, "tabulated BSDF file")?;
    parse_tabulated_bsdf(&text, path)
}

/// Parses and validates tabulated-BSDF TOML text as if read from `path` (for messages).
pub fn parse_tabulated_bsdf(text: &str, path: &Path) -> Result<Arc<TabulatedTable>, ImportError> {
    parse_checked(text, path, true)
}

/// Reads a tabulated BSDF for inspection (`quasar bsdf`): a `.bsdf` file is converted first
/// ([`zemax`], its warnings returned), and the albedo check is left to the caller (so a report
/// can show where a table fails it). Every other check applies.
pub fn load_for_inspection(path: &Path) -> Result<(Arc<TabulatedTable>, Vec<String>), ImportError> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("bsdf")) {
        let c = zemax::convert_zemax_bsdf(path)?;
        let t = TabulatedTable::new_without_energy_check(c.spec)
            .map_err(|e| ImportError::new(ImportErrorKind::InvalidValue, ErrorPlace::file(path), e.to_string()))?;
        return Ok((Arc::new(t), c.warnings));
    }
    let text = read_small_text(path, "tabulated BSDF file")?;
    Ok((parse_checked(&text, path, false)?, Vec::new()))
}

fn parse_checked(text: &str, path: &Path, check_energy: bool) -> Result<Arc<TabulatedTable>, ImportError> {
    let (spec, spans) = parse_spec(text, path)?;
    let built = if check_energy { TabulatedTable::new(spec) } else { TabulatedTable::new_without_energy_check(spec) };
    let table = built.map_err(|e| {
        let key = e.table.split('.').take(2).collect::<Vec<_>>().join(".");
        let span = spans.get(&key).or_else(|| spans.get(e.table.split('.').next().unwrap_or(""))).cloned();
        let place = span.map_or_else(|| ErrorPlace::file(path), |s| ErrorPlace::at_offset(path, text, s.start));
        ImportError::new(ImportErrorKind::InvalidValue, place, e.to_string())
    })?;
    Ok(Arc::new(table))
}

/// Parses the text into an unvalidated spec plus the spans of its tables (for later errors).
pub fn parse_spec(text: &str, path: &Path) -> Result<(TabulatedSpec, HashMap<String, Span>), ImportError> {
    let root = parse_document(text, path)?;
    let doc = Doc::new(path, text);
    let top = Tbl::root(&doc, &root);
    top.check_keys(&TOP_KEYS)?;
    match top.opt_str("format")? {
        Some(FORMAT) => {}
        Some(other) => {
            return Err(doc.invalid(
                &top.get("format").unwrap().span(),
                format!("`format` must be \"{FORMAT}\", got \"{other}\""),
            ));
        }
        None => {
            return Err(doc.invalid(
                &top.span,
                format!("missing `format = \"{FORMAT}\"`: is this a tabulated BSDF file (see materials/README.md)?"),
            ));
        }
    }
    if let Some(v) = top.opt_int::<i64>("version", i128::MIN, i128::MAX)?
        && i128::from(v) != VERSION
    {
        return Err(doc.invalid(
            &top.key_span("version"),
            format!("unsupported version {v}; this quasar reads version {VERSION}"),
        ));
    }
    match top.opt_str("units")? {
        Some("1/sr") => {}
        Some(u) => {
            return Err(doc.invalid(
                &top.key_span("units"),
                format!("`units` must be \"1/sr\" (BSDF values per steradian), got \"{u}\""),
            ));
        }
        None => return Err(top.missing("units")),
    }
    if let Some(p) = top.opt_table("provenance")? {
        for (k, v) in p.entries() {
            crate::toml_reader::string(&doc, v, &p.key_path(k.get_ref()))?;
        }
    }
    top.opt_str("description")?;
    let name =
        top.opt_str("name")?.unwrap_or_else(|| path.file_stem().and_then(|s| s.to_str()).unwrap_or("bsdf")).to_owned();
    let wavelengths = float_list(&doc, top.req("wavelengths_nm")?, "wavelengths_nm", MAX_AXIS_LEN)?;
    let ior = top.opt_f32("ior")?;
    let inc = top.opt_table("incidence")?.ok_or_else(|| top.missing("incidence"))?;
    inc.check_keys(&["theta_deg", "phi_deg"])?;
    let theta_i = radians(float_list(&doc, inc.req("theta_deg")?, "incidence.theta_deg", MAX_AXIS_LEN)?);
    let phi_i = match inc.get("phi_deg") {
        Some(v) => radians(float_list(&doc, v, "incidence.phi_deg", MAX_AXIS_LEN)?),
        None => vec![0.0],
    };
    let mut spans = HashMap::new();
    let dims = (wavelengths.len(), phi_i.len() * theta_i.len());
    let front = top.opt_table("front")?.ok_or_else(|| top.missing("front"))?;
    spans.insert("front".to_owned(), front.span.clone());
    let front = face(&front, dims, &mut spans)?;
    let back = match top.get("back") {
        None => BackFace::Same,
        Some(v) => match v.get_ref() {
            DeValue::String(s) if s.as_ref() == "same" => BackFace::Same,
            DeValue::String(s) if s.as_ref() == "black" => BackFace::Black,
            DeValue::Table(_) => {
                let b = Tbl::of(&doc, v, "back")?;
                spans.insert("back".to_owned(), b.span.clone());
                BackFace::Own(face(&b, dims, &mut spans)?)
            }
            _ => return Err(doc.invalid(&v.span(), "`back` must be \"same\", \"black\" or a table with `brdf`/`btdf`")),
        },
    };
    Ok((TabulatedSpec { name, wavelengths, theta_i, phi_i, ior, front, back }, spans))
}

fn radians(v: Vec<f32>) -> Vec<f32> {
    v.into_iter().map(f32::to_radians).collect()
}

/// `[front]` / `[back]`: optional `brdf` and `btdf` tables.
fn face(t: &Tbl<'_>, dims: (usize, usize), spans: &mut HashMap<String, Span>) -> Result<Face, ImportError> {
    t.check_keys(&["brdf", "btdf"])?;
    let mut f = Face::default();
    for (key, slot) in [("brdf", &mut f.brdf), ("btdf", &mut f.btdf)] {
        if let Some(s) = t.opt_table(key)? {
            spans.insert(s.path.clone(), s.span.clone());
            *slot = Some(scatter_table(&s, dims)?);
        }
    }
    if f.brdf.is_none() && f.btdf.is_none() {
        return Err(t.doc.invalid(&t.span, format!("`{}` needs a `brdf` or a `btdf` table", t.path)));
    }
    Ok(f)
}

/// One `[front.brdf]`-style table.
fn scatter_table(t: &Tbl<'_>, (n_wl, n_inc): (usize, usize)) -> Result<ScatterTable, ImportError> {
    let doc = t.doc;
    t.check_keys(&["grid", "theta_deg", "phi_deg", "values"])?;
    let grid = match t.choice("grid", &["absolute", "specular"])? {
        Some(("absolute", _)) => ScatterGrid::Absolute,
        Some(_) => ScatterGrid::SpecularRelative,
        None => return Err(t.missing("grid")),
    };
    let theta = radians(float_list(doc, t.req("theta_deg")?, &t.key_path("theta_deg"), MAX_AXIS_LEN)?);
    let phi = match t.get("phi_deg") {
        Some(v) => radians(float_list(doc, v, &t.key_path("phi_deg"), MAX_AXIS_LEN)?),
        None => vec![0.0],
    };
    let values_v = t.req("values")?;
    let n = ScatterTable::expected_len(&t.path, n_wl, n_inc, theta.len(), phi.len())
        .map_err(|e| doc.error(ImportErrorKind::TooLarge, &t.key_span("values"), e.to_string()))?;
    let shape = [n_wl, n_inc, theta.len(), phi.len()];
    let mut values = Vec::with_capacity(n.min(MAX_TABLE_ENTRIES));
    flatten(doc, values_v, &t.key_path("values"), n, &shape, &mut values, 0)?;
    if values.len() != n {
        return Err(doc.invalid(
            &values_v.span(),
            format!(
                "`{}` holds {} values, the grid needs {n} (wavelengths x incidences x theta x phi = {} x {} x {} x {})",
                t.key_path("values"),
                values.len(),
                shape[0],
                shape[1],
                shape[2],
                shape[3]
            ),
        ));
    }
    Ok(ScatterTable { grid, theta, phi, values })
}

/// Appends the numbers of a (nested) array in row-major order; errors at the first entry that is
/// not a finite non-negative number, or once more than `limit` values are seen.
fn flatten(
    doc: &Doc<'_>,
    v: &Val<'_>,
    what: &str,
    limit: usize,
    shape: &[usize; 4],
    out: &mut Vec<f32>,
    depth: usize,
) -> Result<(), ImportError> {
    match v.get_ref() {
        DeValue::Array(a) => {
            if depth > 8 {
                return Err(doc.invalid(&v.span(), format!("`{what}` is nested more than 8 arrays deep")));
            }
            for x in a.iter() {
                flatten(doc, x, what, limit, shape, out, depth + 1)?;
            }
            Ok(())
        }
        DeValue::Integer(_) | DeValue::Float(_) => {
            if out.len() >= limit {
                return Err(doc.invalid(&v.span(), format!("`{what}` has more values than the grid's {limit}")));
            }
            let i = out.len();
            let entry = || {
                let (mut idx, mut r) = ([0usize; 4], i);
                for d in (0..4).rev() {
                    idx[d] = r % shape[d].max(1);
                    r /= shape[d].max(1);
                }
                format!(
                    "{what} entry {i} (wavelength {}, incidence {}, theta {}, phi {})",
                    idx[0], idx[1], idx[2], idx[3]
                )
            };
            let x = number(doc, v, what).map_err(|e| doc.invalid(&v.span(), format!("{}: {}", entry(), e.message)))?;
            if x < 0.0 || x as f32 > f32::MAX {
                return Err(
                    doc.invalid(&v.span(), format!("{}: {x} is not a finite non-negative BSDF value (1/sr)", entry()))
                );
            }
            out.push(x as f32);
            Ok(())
        }
        _ => Err(doc.invalid(
            &v.span(),
            format!("`{what}` must hold numbers (1/sr), got {}", crate::toml_reader::type_name(v.get_ref())),
        )),
    }
}
