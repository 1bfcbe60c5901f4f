//! Tabulated-BSDF files: the TOML reader (errors name file, line, table and entry; hostile
//! tables are refused before anything large is allocated), the writer (round trip), and the
//! Zemax tabular .bsdf converter on a file authored here from the format's public description.

use std::f32::consts::PI;
use std::path::Path;

use glam::Vec3;
use quasar_importers::ImportErrorKind;
use quasar_importers::bsdf_file::zemax::parse_zemax_bsdf;
use quasar_importers::bsdf_file::{parse_spec, parse_tabulated_bsdf, to_toml};
use quasar_materials::spectrum::SampledWavelengths;
use quasar_materials::tabulated::{BackFace, ScatterGrid};
use quasar_materials::{TabulatedBsdf, TabulatedTable, TransportMode};

/// A small valid Lambertian-like table: 2 wavelengths x 2 incidences x 3 theta x 1 phi.
const GOOD: &str = r#"format = "quasar-bsdf"
version = 1
name = "test"
units = "1/sr"
wavelengths_nm = [450, 650]

[provenance]
source = "written by the test"

[incidence]
theta_deg = [0, 60]

[front.brdf]
grid = "absolute"
theta_deg = [0, 45, 90]
values = [
  [[0.2, 0.2, 0.2], [0.2, 0.2, 0.2]],
  [[0.25, 0.25, 0.25], [0.25, 0.25, 0.25]],
]
"#;

fn path() -> &'static Path {
    Path::new("lib/test.toml")
}

fn err(text: &str) -> quasar_importers::ImportError {
    parse_tabulated_bsdf(text, path()).expect_err("must fail")
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap_or_else(|| panic!("{needle:?} not found")) + 1
}

#[test]
fn a_valid_table_loads_and_interpolates_in_wavelength() {
    let t = parse_tabulated_bsdf(GOOD, path()).unwrap();
    let wl = SampledWavelengths::from_parts([450.0, 550.0, 650.0, 800.0], [1.0; 4]);
    let b = TabulatedBsdf::new(&t, &wl);
    let f = b.f(Vec3::Z, Vec3::new(0.6, 0.0, 0.8), TransportMode::Radiance);
    assert!((f[0] - 0.2).abs() < 1e-6 && (f[1] - 0.225).abs() < 1e-6 && (f[2] - 0.25).abs() < 1e-6, "{f:?}");
    assert!((f[3] - 0.25).abs() < 1e-6, "clamped beyond the last wavelength: {f:?}");
    assert!(matches!(t.spec().back, BackFace::Same));
}

#[test]
fn hostile_values_name_the_file_line_and_entry() {
    // NaN (a TOML float literal) at wavelength 1, incidence 0, theta 1.
    let text = GOOD.replacen("[[0.25, 0.25, 0.25]", "[[0.25, nan, 0.25]", 1);
    let e = err(&text);
    let msg = e.to_string();
    assert!(msg.starts_with(&format!("lib/test.toml:{}:", line_of(&text, "0.25, nan"))), "{msg}");
    assert!(msg.contains("front.brdf.values entry 7 (wavelength 1, incidence 0, theta 1, phi 0)"), "{msg}");

    let text = GOOD.replacen("0.2, 0.2, 0.2]", "0.2, -0.5, 0.2]", 1);
    let msg = err(&text).to_string();
    assert!(msg.contains("non-negative") && msg.contains("entry 1 "), "{msg}");

    // Albedo 3: f = 0.95 / sr everywhere is an albedo of 0.95 pi.
    let text = GOOD.replace("0.2", "0.95");
    let e = err(&text);
    let msg = e.to_string();
    assert!(msg.contains("scatters more than it receives") && msg.contains("albedo"), "{msg}");
    assert!(msg.starts_with(&format!("lib/test.toml:{}:", line_of(&text, "[front.brdf]"))), "{msg}");

    // Unsorted angles.
    let text = GOOD.replace("theta_deg = [0, 45, 90]", "theta_deg = [0, 60, 45]");
    let msg = err(&text).to_string();
    assert!(msg.contains("front.brdf.theta") && msg.contains("[2]") && msg.contains("strictly increasing"), "{msg}");
    let text = GOOD.replace("theta_deg = [0, 60]", "theta_deg = [60, 0]");
    assert!(err(&text).to_string().contains("incidence.theta"));

    // Too few and too many values.
    let text = GOOD.replacen("[[0.2, 0.2, 0.2], [0.2, 0.2, 0.2]],", "[[0.2, 0.2, 0.2]],", 1);
    assert!(err(&text).to_string().contains("the grid needs 12"));
    let text = GOOD.replacen("[[0.2, 0.2, 0.2], [0.2, 0.2, 0.2]],", "[[0.2, 0.2, 0.2, 0.2], [0.2, 0.2, 0.2]],", 1);
    assert!(err(&text).to_string().contains("more values than the grid's 12"));
}

#[test]
fn a_billion_declared_entries_are_refused_before_allocation() {
    let axis = |n: usize, max: f32| {
        let v: Vec<String> = (0..n).map(|i| format!("{}", max * i as f32 / n as f32)).collect();
        format!("[{}]", v.join(", "))
    };
    // 1000 wavelengths x 1000 incidences x 1000 theta x 1 phi = 1e9 values, with one given.
    let text = format!(
        "format = \"quasar-bsdf\"\nunits = \"1/sr\"\nwavelengths_nm = {}\n[incidence]\ntheta_deg = {}\n\
         [front.brdf]\ngrid = \"specular\"\ntheta_deg = {}\nvalues = [0.1]\n",
        axis(1000, 1000.0).replace("[0,", "[300,"),
        axis(1000, 90.0),
        axis(1000, 180.0)
    );
    let e = err(&text);
    assert_eq!(e.kind, ImportErrorKind::TooLarge, "{e}");
    assert!(e.to_string().contains("exceed the limit"), "{e}");
    // An axis longer than the limit is refused while reading the list.
    let text = GOOD.replace("theta_deg = [0, 60]", &format!("theta_deg = {}", axis(70_000, 90.0)));
    assert_eq!(err(&text).kind, ImportErrorKind::TooLarge);
}

#[test]
fn file_level_mistakes_are_clear() {
    let msg = err(&GOOD.replace("format = \"quasar-bsdf\"\n", "")).to_string();
    assert!(msg.contains("missing `format = \"quasar-bsdf\"`"), "{msg}");
    let text = GOOD.replace("units = \"1/sr\"", "units = \"cd\"");
    let msg = err(&text).to_string();
    assert!(msg.contains(&format!(":{}:", line_of(&text, "units"))) && msg.contains("1/sr"), "{msg}");
    let text = GOOD.replace("grid = \"absolute\"", "grid = \"absolut\"");
    assert!(err(&text).to_string().contains("did you mean"), "suggestion expected");
    let text = GOOD.replace("[provenance]", "[provenance]\ncolour = 3");
    assert!(err(&text).to_string().contains("provenance.colour"));
    let text = GOOD.replace("[front.brdf]", "[front.brdf]\nior = 1.5");
    assert_eq!(err(&text).kind, ImportErrorKind::UnknownKey);
    let text = GOOD.replace("grid = \"absolute\"", "grid = \"specular\"").replace("[front.brdf]", "[front.btdf]");
    assert!(err(&text).to_string().contains("needs the relative `ior`"));
}

#[test]
fn written_tables_read_back_unchanged() {
    let (spec, _) = parse_spec(GOOD, path()).unwrap();
    let text = to_toml(&spec, "round trip", &[("source", "test")]);
    let (again, _) = parse_spec(&text, path()).unwrap();
    assert_eq!(spec.wavelengths, again.wavelengths);
    assert_eq!(spec.front, again.front);
    for (a, b) in spec.theta_i.iter().zip(&again.theta_i) {
        assert!((a - b).abs() < 1e-6);
    }
}

/// A Zemax tabular BSDF file written from the format's public description: plane symmetric,
/// monochrome BRDF, two angles of incidence, azimuths 0..180 in 45 degree steps, eight radial
/// angles; f(radial, azimuth) = A(aoi) exp(-(r / 5 deg)^2) (1 + 0.5 cos az) + 0.01.
fn zemax_text() -> (String, impl Fn(usize, f32, f32) -> f32) {
    let aoi = [0.0f32, 30.0];
    let az = [0.0f32, 45.0, 90.0, 135.0, 180.0];
    let radial = [0.0f32, 1.0, 2.0, 5.0, 10.0, 20.0, 45.0, 90.0];
    let f = |i: usize, r: f32, a: f32| {
        let amp = [2.0f32, 3.0][i];
        amp * (-(r / 5.0).powi(2)).exp() * (1.0 + 0.5 * a.to_radians().cos()) + 0.01
    };
    let list = |v: &[f32]| v.iter().map(|x| format!("{x}")).collect::<Vec<_>>().join("\t");
    let mut s =
        String::from("# Authored by quasar's tests\n#2026-11-25\nSource  Measured\nSymmetry  PlaneSymmetrical\n");
    s += "SpectralContent  Monochrome\nScatterType  BRDF\nSampleRotation  1\n0\n";
    s += &format!("AngleOfIncidence  {}\n{}\n", aoi.len(), list(&aoi));
    s += &format!("ScatterAzimuth {}\n{}\n", az.len(), list(&az));
    s += &format!("ScatterRadial {}\n{}\n\nMonochrome\nDataBegin\n", radial.len(), list(&radial));
    for i in 0..aoi.len() {
        s += "TIS 0.5\n";
        for &a in &az {
            let row: Vec<String> = radial.iter().map(|&r| format!("{:.6E}", f(i, r, a))).collect();
            s += &row.join("\t");
            s += "\n";
        }
    }
    s += "DataEnd\n";
    (s, f)
}

#[test]
fn zemax_bsdf_converts_to_the_specular_relative_grid() {
    let (text, f) = zemax_text();
    let c = parse_zemax_bsdf(&text, Path::new("vinyl.bsdf")).unwrap();
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    let t = c.spec.front.brdf.as_ref().unwrap();
    assert_eq!(t.grid, ScatterGrid::SpecularRelative);
    assert_eq!((t.theta.len(), t.phi.len()), (8, 5));
    // values[wavelength][rotation][aoi][radial][azimuth]: aoi 1, radial 2 deg, azimuth 45 deg.
    let v = t.values[(8 + 2) * 5 + 1];
    assert!((v - f(1, 2.0, 45.0)).abs() < 1e-5 * v, "{v}");
    // Through the TOML writer and reader into a renderable table.
    let toml = to_toml(&c.spec, "converted", &[("source", "vinyl.bsdf")]);
    let table = parse_tabulated_bsdf(&toml, Path::new("vinyl.toml")).unwrap();
    let wl = SampledWavelengths::from_parts([555.0; 4], [1.0; 4]);
    let b = TabulatedBsdf::new(&table, &wl);
    let ti = 30f32.to_radians();
    let light = Vec3::new(-ti.sin(), 0.0, ti.cos());
    let mirror = Vec3::new(ti.sin(), 0.0, ti.cos());
    let at = |d: Vec3| b.f(d, light, TransportMode::Radiance)[0];
    assert!((at(mirror) - f(1, 0.0, 0.0)).abs() < 1e-4 * f(1, 0.0, 0.0), "peak at the mirror direction");
    // Radial 5 deg towards the normal (azimuth 0) and away from it (azimuth 180).
    let (t5, tn, ta) = (5f32.to_radians(), ti - 5f32.to_radians(), ti + 5f32.to_radians());
    let toward = Vec3::new(tn.sin(), 0.0, tn.cos());
    let away = Vec3::new(ta.sin(), 0.0, ta.cos());
    assert!((at(toward) - f(1, 5.0, 0.0)).abs() < 1e-3 * at(toward), "{} vs {}", at(toward), f(1, 5.0, 0.0));
    assert!((at(away) - f(1, 5.0, 180.0)).abs() < 1e-3 * at(away), "{} vs {}", at(away), f(1, 5.0, 180.0));
    assert!(t5 > 0.0 && PI > 0.0);
    // Plane symmetry: azimuth 90 and 270 agree.
    let side = |sgn: f32| {
        let c = mirror * t5.cos() + Vec3::Y * (sgn * t5.sin());
        at(c.normalize())
    };
    assert!((side(1.0) - side(-1.0)).abs() < 1e-5 * side(1.0));
    let _ = TabulatedTable::new(c.spec).unwrap();
}

#[test]
fn hostile_zemax_files_give_clear_errors() {
    let (text, _) = zemax_text();
    let p = Path::new("x.bsdf");
    let e = parse_zemax_bsdf(&text.replace("ScatterRadial 8", "ScatterRadial 1000000000"), p).unwrap_err();
    assert_eq!(e.kind, ImportErrorKind::TooLarge, "{e}");
    let e = parse_zemax_bsdf(&text.replace("ScatterRadial 8", "ScatterRadial 60000"), p).unwrap_err();
    assert!(e.to_string().contains("fewer numbers left"), "{e}");
    let e = parse_zemax_bsdf(&text.replacen("TIS 0.5\n", "TIS 0.5\nnan\t", 1), p).unwrap_err();
    assert!(e.to_string().contains("not a finite number"), "{e}");
    let cut = &text[..text.len() / 2];
    let e = parse_zemax_bsdf(cut, p).unwrap_err();
    assert!(e.to_string().starts_with("x.bsdf:"), "{e}");
    let e = parse_zemax_bsdf(&text.replace("Monochrome\nDataBegin", "Spectral\nDataBegin"), p).unwrap_err();
    assert!(e.to_string().contains("expected `Monochrome`"), "{e}");
    let e = parse_zemax_bsdf(&text.replace("SpectralContent  Monochrome", "SpectralContent  Spectral"), p).unwrap_err();
    assert_eq!(e.kind, ImportErrorKind::Unsupported);
}
