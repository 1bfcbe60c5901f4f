//! `quasar bsdf`: a report on a tabulated BSDF — directional albedo per incidence and wavelength,
//! the non-uniformity coefficient kappa (docs/architecture.md §5) and the energy verdict — and a
//! polar plot of its lobes in the plane of incidence.

use std::f32::consts::PI;
use std::fmt::Write;
use std::path::Path;
use std::sync::Arc;

use anyhow::Result;
use glam::Vec3;
use quasar_materials::non_uniformity::kappa;
use quasar_materials::spectrum::SampledWavelengths;
use quasar_materials::tabulated::{ALBEDO_TOLERANCE, BackFace, ScatterGrid, ScatterTable};
use quasar_materials::{Material, TabulatedBsdf, TabulatedTable, TransportMode};

use crate::output::text::Align;
use crate::tools::plot::{Canvas, PLOT_COLOURS};

/// Largest number of wavelength columns printed (evenly chosen from the table's).
const MAX_COLUMNS: usize = 8;

/// The report's text and whether the table passes the energy check.
#[derive(Clone, Debug, PartialEq)]
pub struct BsdfReport {
    /// Human-readable report.
    pub text: String,
    /// Largest directional albedo R + T over faces, incidences and wavelengths.
    pub max_albedo: f32,
    /// max_albedo <= 1 + ALBEDO_TOLERANCE.
    pub energy_ok: bool,
}

fn columns(n: usize) -> Vec<usize> {
    if n <= MAX_COLUMNS {
        return (0..n).collect();
    }
    let mut v: Vec<usize> = (0..MAX_COLUMNS).map(|i| i * (n - 1) / (MAX_COLUMNS - 1)).collect();
    v.dedup();
    v
}

fn describe(t: &Option<ScatterTable>) -> String {
    match t {
        None => "-".into(),
        Some(t) => format!(
            "{} grid, {} theta (0..{:.3} deg) x {} phi",
            match t.grid {
                ScatterGrid::Absolute => "absolute",
                ScatterGrid::SpecularRelative => "specular-relative",
            },
            t.theta.len(),
            t.theta.last().copied().unwrap_or(0.0).to_degrees(),
            t.phi.len()
        ),
    }
}

/// The report of `table` (read from `file`).
pub fn report(table: &Arc<TabulatedTable>, file: &Path) -> BsdfReport {
    let spec = table.spec();
    let mut s = String::new();
    let _ = writeln!(s, "material: {} ({})", spec.name, file.display());
    let wl = &spec.wavelengths;
    let _ = writeln!(
        s,
        "wavelengths: {} ({}..{} nm, clamped outside); incidences: {} theta ({:.1}..{:.1} deg) x {} phi{}",
        wl.len(),
        wl[0],
        wl[wl.len() - 1],
        spec.theta_i.len(),
        spec.theta_i[0].to_degrees(),
        spec.theta_i[spec.theta_i.len() - 1].to_degrees(),
        spec.phi_i.len(),
        if spec.phi_i.len() == 1 { " (isotropic)" } else { " (anisotropic)" }
    );
    if let Some(ior) = spec.ior {
        let _ = writeln!(s, "ior: {ior}");
    }
    let _ = writeln!(s, "front: BRDF {}; BTDF {}", describe(&spec.front.brdf), describe(&spec.front.btdf));
    match &spec.back {
        BackFace::Same => s.push_str("back: same as front\n"),
        BackFace::Black => s.push_str("back: black (absorbs)\n"),
        BackFace::Own(f) => {
            let _ = writeln!(s, "back: BRDF {}; BTDF {}", describe(&f.brdf), describe(&f.btdf));
        }
    }
    let cols = columns(wl.len());
    let mut worst = (0.0f32, String::new());
    for &(back, name) in table.distinct_faces() {
        let _ = writeln!(
            s,
            "\ndirectional albedo, {name} face: R (reflected) + T (transmitted) per incidence and wavelength"
        );
        let mut head = format!("{:>16}", "incidence");
        for &l in &cols {
            let _ = write!(head, " {:>15}", format!("{} nm", wl[l]));
        }
        let _ = writeln!(s, "{head}");
        for pi in 0..spec.phi_i.len() {
            for ti in 0..spec.theta_i.len() {
                let mut row = if spec.phi_i.len() == 1 {
                    format!("{:>12.2} deg", spec.theta_i[ti].to_degrees())
                } else {
                    format!("{:>6.1}/{:>5.1} deg", spec.theta_i[ti].to_degrees(), spec.phi_i[pi].to_degrees())
                };
                for (l, &lambda) in wl.iter().enumerate() {
                    let (r, t) = table.albedo(back, l, pi, ti);
                    if r + t > worst.0 {
                        worst = (
                            r + t,
                            format!(
                                "{name} face, {lambda} nm, incidence {:.2} deg / {:.2} deg",
                                spec.theta_i[ti].to_degrees(),
                                spec.phi_i[pi].to_degrees()
                            ),
                        );
                    }
                    if cols.contains(&l) {
                        let _ = write!(row, " {:>15}", format!("{r:.3}+{t:.3}"));
                    }
                }
                let _ = writeln!(s, "{row}");
            }
        }
    }
    let material = Material::Tabulated(Arc::clone(table));
    s.push_str("\nkappa (non-uniformity: max f / mean f over the projected solid angle; 1 = Lambertian)\n");
    for deg in [0.0f32, 30.0, 45.0, 60.0, 80.0] {
        let t = deg.to_radians();
        let k = kappa(&material, Vec3::new(t.sin(), 0.0, t.cos()));
        let _ = writeln!(s, "{:>12.0} deg  {:>10.2}", deg, k);
    }
    let energy_ok = worst.0 <= 1.0 + ALBEDO_TOLERANCE;
    let verdict = if worst.0 <= 1.0 {
        "OK: conserves energy".to_owned()
    } else if energy_ok {
        format!("OK within the tolerance {ALBEDO_TOLERANCE} (measurement noise)")
    } else {
        "FAILS: scatters more light than it receives; the renderer refuses it".to_owned()
    };
    let _ = writeln!(s, "\nenergy: max albedo {:.4} ({}): {verdict}", worst.0, worst.1);
    BsdfReport { text: s, max_albedo: worst.0, energy_ok }
}

/// Writes a 720 x 720 polar plot of the front face's lobes in the plane of incidence for
/// incidence angles 0, 30, 60 and 80 degrees (light arriving from the upper left; reflection
/// above the horizontal surface line, transmission below; radius log10 f over four decades below
/// the largest value, one grey circle per decade labelled with its f), at the wavelength nearest
/// 555 nm, with a title, the two half-planes named and a legend box of the incidence angles.
/// Returns the same legend as text.
pub fn write_lobe_plot(table: &TabulatedTable, path: &Path) -> Result<String> {
    const SIZE: u32 = 720;
    const STEPS: usize = 14_400;
    let (cx, cy, rim) = (f64::from(SIZE) / 2.0, f64::from(SIZE) / 2.0, f64::from(SIZE) / 2.0 - 20.0);
    let wl = SampledWavelengths::from_parts([555.0; 4], [1.0; 4]);
    let b = TabulatedBsdf::new(table, &wl);
    let incidences = [0.0f32, 30.0, 60.0, 80.0];
    let curves: Vec<Vec<(f32, f32)>> = incidences
        .iter()
        .map(|&deg| {
            let t = deg.to_radians();
            let d_in = Vec3::new(-t.sin(), 0.0, t.cos());
            (0..STEPS)
                .map(|i| {
                    let a = -PI + 2.0 * PI * (i as f32 + 0.5) / STEPS as f32;
                    let d_out = Vec3::new(a.sin(), 0.0, a.cos());
                    (a, b.f(d_out, d_in, TransportMode::Radiance)[0])
                })
                .collect()
        })
        .collect();
    let fmax = curves.iter().flatten().map(|c| c.1).fold(0.0f32, f32::max);
    if fmax <= 0.0 {
        anyhow::bail!("the table is zero in the plane of incidence: nothing to plot");
    }
    let decades = 4.0f64;
    let lo = f64::from(fmax).log10() - decades;
    let mut c = Canvas::new(SIZE, SIZE);
    for d in 1..=decades as i32 {
        let r = rim * f64::from(d) / decades;
        let n = (r * 8.0) as usize + 8;
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            c.dot(cx + r * a.cos(), cy + r * a.sin(), [200, 200, 200]);
        }
    }
    c.line((cx - rim, cy), (cx + rim, cy), [0, 0, 0]);
    c.line((cx, cy - rim), (cx, cy + rim), [200, 200, 200]);
    const PX: f32 = 14.0;
    let black = [0, 0, 0];
    // each decade circle labelled with its f where it crosses the surface line, right of the centre
    for d in 0..=decades as i32 {
        let r = rim * f64::from(d) / decades;
        let label = format!("{:.2e}", 10f64.powf(lo + f64::from(d)));
        c.text(cx + r - 2.0, cy + 0.9 * f64::from(PX), PX, &label, [90, 90, 90], Align::Right);
    }
    c.text(
        6.0,
        12.0,
        PX,
        &format!("f (1/sr) at {:.0} nm, plane of incidence, log radius", wl.lambda(0)),
        black,
        Align::Left,
    );
    c.text(6.0, cy - 0.9 * f64::from(PX), PX, "reflection", black, Align::Left);
    c.text(6.0, cy + 0.9 * f64::from(PX), PX, "transmission", black, Align::Left);
    let entries: Vec<(String, [u8; 3])> = incidences
        .iter()
        .enumerate()
        .map(|(k, deg)| (format!("incidence {deg} deg"), PLOT_COLOURS[k % PLOT_COLOURS.len()].1))
        .collect();
    c.legend(f64::from(SIZE) - 6.0, 6.0, PX, &entries);
    let mut legend = format!(
        "lobe plot (front face, {} nm): plane of incidence, light from the upper left; the surface is the \
         horizontal line, reflection above, transmission below; radius log10 f from {:.3e} (centre) to {:.3e} \
         (rim) 1/sr, grey circles at decades\n",
        wl.lambda(0),
        10f64.powf(lo),
        fmax
    );
    for (k, (curve, deg)) in curves.iter().zip(incidences).enumerate() {
        let (name, colour) = PLOT_COLOURS[k % PLOT_COLOURS.len()];
        let _ = writeln!(legend, "  {name}: incidence {deg} deg");
        let t = f64::from(deg).to_radians();
        c.line(
            (cx - rim * t.sin(), cy - rim * t.cos()),
            (cx - 0.85 * rim * t.sin(), cy - 0.85 * rim * t.cos()),
            colour,
        );
        let px = |&(a, f): &(f32, f32)| {
            let r = if f > 0.0 { rim * ((f64::from(f).log10() - lo) / decades).clamp(0.0, 1.0) } else { 0.0 };
            (cx + r * f64::from(a).sin(), cy - r * f64::from(a).cos())
        };
        for w in curve.windows(2) {
            if w[0].1 > 0.0 || w[1].1 > 0.0 {
                c.line(px(&w[0]), px(&w[1]), colour);
            }
        }
    }
    c.save(path)?;
    Ok(legend)
}

/// Evaluates, samples and takes the pdf of `table` in a fixed set of directions on both faces
/// and in both transport modes; an error names the first non-finite or negative result (the
/// fuzz target and its regression test use this).
pub fn check_finite(table: &TabulatedTable) -> Result<(), String> {
    let wl = SampledWavelengths::from_parts([380.0, 500.0, 620.0, 800.0], [1.0; 4]);
    let b = TabulatedBsdf::new(table, &wl);
    let dirs = [
        Vec3::Z,
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(-0.3, 0.9, 0.3).normalize(),
        Vec3::new(0.1, 0.2, -0.97).normalize(),
        Vec3::new(1.0, 0.0, 1e-7).normalize(),
    ];
    for &wo in &dirs {
        for &wi in &dirs {
            for mode in [TransportMode::Radiance, TransportMode::Importance] {
                let f = b.f(wo, wi, mode);
                let p = b.pdf(wo, wi, mode);
                if !f.is_finite() || f.min_component() < 0.0 || !p.is_finite() || p < 0.0 {
                    return Err(format!("f {f:?} / pdf {p} at wo {wo}, wi {wi} ({mode:?})"));
                }
            }
        }
        for k in 0..8 {
            let u = glam::Vec2::new((k as f32 + 0.5) / 8.0, ((k * 5 % 8) as f32 + 0.5) / 8.0);
            if let Some(s) = b.sample_f(wo, k as f32 / 8.0, u, TransportMode::Radiance)
                && !(s.pdf > 0.0 && s.pdf.is_finite() && s.f.is_finite() && s.wi.is_finite())
            {
                return Err(format!("sample {s:?} from wo {wo}"));
            }
        }
    }
    Ok(())
}

/// `quasar bsdf convert`: converts the Zemax/Radiant tabular `.bsdf` file `input` into the TOML
/// format at `output` (written atomically) and returns the conversion's warnings.
pub fn convert_zemax(input: &Path, output: &Path) -> anyhow::Result<Vec<String>> {
    use quasar_importers::bsdf_file;
    let c = bsdf_file::zemax::convert_zemax_bsdf(input)?;
    quasar_materials::TabulatedTable::new(c.spec.clone())
        .map_err(|e| anyhow::anyhow!("{}: the converted table is invalid: {e}", input.display()))?;
    let source = input.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
    let mut prov: Vec<(&str, &str)> = vec![("converted_from", &source), ("converter", "quasar bsdf convert")];
    prov.extend(c.header.iter().map(|(k, v)| (k.as_str(), v.as_str())));
    let text = bsdf_file::to_toml(&c.spec, "converted from a Zemax tabular BSDF file", &prov);
    crate::output::write_atomic_bytes(output, text.as_bytes())?;
    Ok(c.warnings)
}
