//! Writes a [`TabulatedSpec`] as a tabulated-BSDF TOML file (the converter's output and the
//! material library's generator use it; [`super::parse_spec`] reads it back unchanged).

use std::fmt::Write;

use quasar_materials::TabulatedSpec;
use quasar_materials::tabulated::{BackFace, Face, ScatterGrid, ScatterTable};

/// Free-form provenance written to `[provenance]` (key, value).
pub type Provenance<'a> = &'a [(&'a str, &'a str)];

/// A list of numbers (`degrees`: radians written as degrees, see [`fmt_deg`]).
fn list(v: &[f32], degrees: bool) -> String {
    let items: Vec<String> = v.iter().map(|&x| if degrees { fmt_deg(x) } else { fmt_num(x) }).collect();
    format!("[{}]", items.join(", "))
}

/// Radians as the shortest degree text that reads back (f32 degrees -> `to_radians`) as exactly
/// the same radians, so a written table loads with the identical grid.
fn fmt_deg(x: f32) -> String {
    let d = x.to_degrees();
    let mut candidates = vec![((f64::from(x).to_degrees() * 1e5).round() / 1e5) as f32, d];
    let (mut lo, mut hi) = (d, d);
    for _ in 0..4 {
        lo = lo.next_down();
        hi = hi.next_up();
        candidates.extend([lo, hi]);
    }
    let exact = candidates.into_iter().filter(|c| c.to_radians() == x).min_by_key(|c| fmt_num(*c).len());
    fmt_num(exact.unwrap_or(d))
}

/// Shortest text that reads back as the same f32, always with a digit TOML accepts.
fn fmt_num(x: f32) -> String {
    let s = format!("{x}");
    if s.contains("inf") || s.contains("NaN") { "0".to_owned() } else { s }
}

fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn table(out: &mut String, header: &str, t: &ScatterTable, spec: &TabulatedSpec) {
    let grid = match t.grid {
        ScatterGrid::Absolute => "absolute",
        ScatterGrid::SpecularRelative => "specular",
    };
    let _ = writeln!(out, "\n[{header}]\ngrid = \"{grid}\"");
    let _ = writeln!(out, "theta_deg = {}", list(&t.theta, true));
    let _ = writeln!(out, "phi_deg = {}", list(&t.phi, true));
    let _ = writeln!(out, "# values[wavelength][incidence phi][incidence theta][theta][phi], one line per theta");
    out.push_str("values = [\n");
    let n_p = t.phi.len();
    let n_t = t.theta.len();
    for (r, row) in t.values.chunks(n_p).enumerate() {
        if r % n_t == 0 {
            let slice = r / n_t;
            let n_ti = spec.theta_i.len();
            let n_pi = spec.phi_i.len();
            let (l, pi, ti) = (slice / (n_ti * n_pi), (slice / n_ti) % n_pi, slice % n_ti);
            let _ = writeln!(
                out,
                "  # {} nm, incidence phi {} deg, theta {} deg",
                fmt_num(spec.wavelengths[l]),
                fmt_deg(spec.phi_i[pi]),
                fmt_deg(spec.theta_i[ti])
            );
        }
        let items: Vec<String> = row.iter().map(|&x| fmt_num(x)).collect();
        let _ = writeln!(out, "  {},", items.join(", "));
    }
    out.push_str("]\n");
}

fn face(out: &mut String, name: &str, f: &Face, spec: &TabulatedSpec) {
    if let Some(t) = &f.brdf {
        table(out, &format!("{name}.brdf"), t, spec);
    }
    if let Some(t) = &f.btdf {
        table(out, &format!("{name}.btdf"), t, spec);
    }
}

/// The TOML text of `spec` with a description and provenance entries.
pub fn to_toml(spec: &TabulatedSpec, description: &str, provenance: Provenance<'_>) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Tabulated spectral BSDF (schema: materials/README.md).");
    let _ = writeln!(out, "format = \"quasar-bsdf\"\nversion = 1");
    let _ = writeln!(out, "name = {}", quote(&spec.name));
    if !description.is_empty() {
        let _ = writeln!(out, "description = {}", quote(description));
    }
    let _ = writeln!(out, "units = \"1/sr\"");
    let _ = writeln!(out, "wavelengths_nm = {}", list(&spec.wavelengths, false));
    if let Some(ior) = spec.ior {
        let _ = writeln!(out, "ior = {}", fmt_num(ior));
    }
    match &spec.back {
        BackFace::Same => out.push_str("back = \"same\"\n"),
        BackFace::Black => out.push_str("back = \"black\"\n"),
        BackFace::Own(_) => {}
    }
    if !provenance.is_empty() {
        out.push_str("\n[provenance]\n");
        for (k, v) in provenance {
            let _ = writeln!(out, "{} = {}", quote(k), quote(v));
        }
    }
    let _ = writeln!(
        out,
        "\n[incidence]\ntheta_deg = {}\nphi_deg = {}",
        list(&spec.theta_i, true),
        list(&spec.phi_i, true)
    );
    face(&mut out, "front", &spec.front, spec);
    if let BackFace::Own(b) = &spec.back {
        face(&mut out, "back", b, spec);
    }
    out
}
