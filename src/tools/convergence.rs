//! Error-vs-time curves (`quasar bench convergence`; figures in BENCHMARKS.md): each method renders
//! the same scene for a series of time budgets and its luminance is compared with a converged
//! reference (relMSE, as `quasar compare`). Output: CSV, a markdown table with the time each
//! method needs to reach a target error, and a log-log PNG plot.

use std::path::Path;

use anyhow::{Result, bail};
use quasar_importers::SceneDesc;

use crate::film::LUMINANCE;
use crate::integrator::entry::MethodEntry;
use crate::integrator::params::{MethodParams, ParamKind};
use crate::output::text::Align;
use crate::render::job::{JobOverrides, render_desc};
use crate::tools::compare::rel_mse;
use crate::tools::plot::{Canvas, PLOT_COLOURS};

/// One method configuration of a comparison, parsed from `name[:value]`.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodVariant {
    /// Label in tables and plots (the text it was parsed from).
    pub label: String,
    /// The method.
    pub method: &'static MethodEntry,
    /// Its parameters (the variant's `value` sets the method's variant parameter).
    pub params: MethodParams,
}

impl MethodVariant {
    /// Parses `name` or `name:value` (the method table's variant parameter of `name`:
    /// `vismap:DEPTH`, `quasi:CONE`, `adaptive+quasi:CONE`, `adaptive:paper`).
    pub fn parse(s: &str) -> Result<Self> {
        let (name, value) = s.split_once(':').map_or((s, None), |(m, o)| (m, Some(o)));
        let method = crate::integrator::method::find(name).ok_or_else(|| bad(s))?;
        let mut params = MethodParams::default();
        if let Some(v) = value {
            let spec = method.variant.ok_or_else(|| bad(s))?;
            match spec.kind {
                ParamKind::Int { .. } => params.set(spec.key, v.parse::<i128>().map_err(|_| bad(s))?),
                ParamKind::Real { .. } | ParamKind::Length => {
                    params.set(spec.key, v.parse::<f64>().map_err(|_| bad(s))?)
                }
                // `adaptive:paper` for the `adaptive_paper` flag
                ParamKind::Bool if spec.key.ends_with(v) => params.set(spec.key, true),
                ParamKind::Bool => return Err(bad(s)),
            }
        }
        Ok(Self { label: s.to_string(), method, params })
    }
}

fn bad(s: &str) -> anyhow::Error {
    let forms: Vec<String> = crate::integrator::method::METHODS
        .iter()
        .map(|m| match m.variant {
            Some(v) if v.kind == ParamKind::Bool => {
                format!("{}[:{}]", m.name, v.key.rsplit('_').next().unwrap_or(v.key))
            }
            Some(v) => format!("{}[:{}]", m.name, v.key.to_uppercase()),
            None => m.name.to_string(),
        })
        .collect();
    anyhow::anyhow!("bad method '{s}' (expected one of: {})", forms.join(", "))
}

/// Parses a comma-separated list of [`MethodVariant`]s.
pub fn parse_methods(list: &str) -> Result<Vec<MethodVariant>> {
    let v: Vec<_> =
        list.split(',').map(str::trim).filter(|s| !s.is_empty()).map(MethodVariant::parse).collect::<Result<_>>()?;
    if v.is_empty() {
        bail!("no methods given");
    }
    Ok(v)
}

/// The luminance of a `pt` render of `desc` with `spp` samples per pixel at `width` x `height`:
/// the reference of a convergence comparison.
pub fn pt_reference(
    desc: &SceneDesc,
    width: u32,
    height: u32,
    spp: u32,
    seed: u64,
    progress: bool,
) -> Result<Vec<f32>> {
    let ov = JobOverrides {
        width: Some(width),
        height: Some(height),
        spp: Some(spp),
        seed: Some(seed),
        method: Some("pt".into()),
        ..Default::default()
    };
    Ok(render_desc(desc, &ov, progress)?.image.channel(LUMINANCE).unwrap_or_default().to_vec())
}

/// One render of a curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePoint {
    /// Method label.
    pub label: String,
    /// Time budget (s).
    pub budget: f64,
    /// Seconds the render took.
    pub seconds: f64,
    /// Samples per pixel or iterations reached.
    pub samples: u32,
    /// relMSE of the luminance against the reference.
    pub rel_mse: f64,
}

/// Renders `desc` with every method for every budget (`base` supplies size, seed, threads) and
/// measures relMSE against `reference` (luminance, same size). Photon methods use
/// `photons_per_iteration` unless their variant sets it.
pub fn run(
    desc: &SceneDesc,
    base: &JobOverrides,
    methods: &[MethodVariant],
    budgets: &[f64],
    reference: &[f32],
    mut progress: impl FnMut(&CurvePoint),
) -> Result<Vec<CurvePoint>> {
    let mut points = Vec::new();
    for m in methods {
        for &budget in budgets {
            // the base's parameters (photons per iteration) where the method reads them
            let mut params = m.params.clone();
            for (k, v) in base.params.values() {
                if m.method.params.iter().any(|p| p.key == k) && !params.contains(k) {
                    params.set(k, v.clone());
                }
            }
            let ov = JobOverrides { time_s: Some(budget), method: Some(m.method.name.into()), params, ..base.clone() };
            let out = render_desc(desc, &ov, false)?;
            let y = out.image.channel(LUMINANCE).unwrap_or_default();
            if y.len() != reference.len() {
                bail!("the reference has {} pixels, the render {}", reference.len(), y.len());
            }
            let p = CurvePoint {
                label: m.label.clone(),
                budget,
                seconds: out.result.seconds,
                samples: out.result.spp,
                rel_mse: rel_mse(y, reference),
            };
            progress(&p);
            points.push(p);
        }
    }
    Ok(points)
}

/// Seconds to reach relMSE `target` on one method's curve (budget, error), interpolating
/// log-linearly between the budgets around it; None when no budget reaches it. A curve that is
/// already below the target at its first budget returns that budget (an upper bound).
pub fn time_to_reach(curve: &[(f64, f64)], target: f64) -> Option<f64> {
    if curve.first()?.1 <= target {
        return Some(curve[0].0);
    }
    curve.windows(2).find(|w| w[1].1 <= target).map(|w| {
        let ((t0, e0), (t1, e1)) = (w[0], w[1]);
        let f = (target.ln() - e0.ln()) / (e1.ln() - e0.ln());
        (t0.ln() + f * (t1.ln() - t0.ln())).exp()
    })
}

/// The points as CSV: `method,budget_s,seconds,samples,relmse`.
pub fn to_csv(points: &[CurvePoint]) -> String {
    let mut s = String::from("method,budget_s,seconds,samples,relmse\n");
    for p in points {
        s += &format!("{},{},{:.4},{},{:.6e}\n", p.label, p.budget, p.seconds, p.samples, p.rel_mse);
    }
    s
}

fn labels(points: &[CurvePoint]) -> Vec<&str> {
    let mut v: Vec<&str> = Vec::new();
    for p in points {
        if !v.contains(&p.label.as_str()) {
            v.push(&p.label);
        }
    }
    v
}

/// A markdown table: one row per method, relMSE (samples) per budget, and the time to `target`.
pub fn markdown_table(points: &[CurvePoint], target: f64) -> String {
    let budgets: Vec<f64> = {
        let mut b: Vec<f64> = points.iter().map(|p| p.budget).collect();
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    };
    let mut s = String::from("| method |");
    for b in &budgets {
        s += &format!(" {b} s |");
    }
    s += &format!(" time to relMSE {target} |\n|---|{}---|\n", "---|".repeat(budgets.len()));
    for label in labels(points) {
        let curve: Vec<&CurvePoint> = points.iter().filter(|p| p.label == label).collect();
        s += &format!("| {label} |");
        for c in &curve {
            s += &format!(" {:.4} ({}) |", c.rel_mse, c.samples);
        }
        let xy: Vec<(f64, f64)> = curve.iter().map(|c| (c.budget, c.rel_mse)).collect();
        let last = budgets.last().copied().unwrap_or(0.0);
        s += &match time_to_reach(&xy, target) {
            Some(t) if t <= xy[0].0 => format!(" <= {t:.2} s |\n"),
            Some(t) => format!(" {t:.2} s |\n"),
            None => format!(" > {last} s |\n"),
        };
    }
    s
}

/// Writes a 720x520 log-log plot of relMSE (vertical) against seconds (horizontal): axes with a
/// tick label and a grey line at every power of ten, axis titles, one polyline per method in
/// [`PLOT_COLOURS`] order with a marker per render, and a legend box naming the methods. The
/// same legend and the axis ranges are returned as text to print beside it.
pub fn write_plot(points: &[CurvePoint], path: &Path) -> Result<String> {
    const W: u32 = 720;
    const H: u32 = 520;
    // margins: left for the vertical tick labels, bottom for the horizontal ones and the title
    const L: f64 = 64.0;
    const R: f64 = 20.0;
    const T: f64 = 34.0;
    const B: f64 = 52.0;
    const PX: f32 = 14.0;
    let finite: Vec<&CurvePoint> = points.iter().filter(|p| p.rel_mse > 0.0 && p.seconds > 0.0).collect();
    if finite.is_empty() {
        bail!("nothing to plot");
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in &finite {
        x0 = x0.min(p.seconds.log10());
        x1 = x1.max(p.seconds.log10());
        y0 = y0.min(p.rel_mse.log10());
        y1 = y1.max(p.rel_mse.log10());
    }
    let (x0, x1, y0, y1) = (x0.floor(), x1.ceil().max(x0.floor() + 1.0), y0.floor(), y1.ceil().max(y0.floor() + 1.0));
    let (w, h) = (f64::from(W), f64::from(H));
    let to_px = |s: f64, e: f64| {
        let x = L + (s.log10() - x0) / (x1 - x0) * (w - L - R);
        let y = h - B - (e.log10() - y0) / (y1 - y0) * (h - T - B);
        (x, y)
    };
    let mut img = Canvas::new(W, H);
    let black = [0, 0, 0];
    for d in x0 as i32..=x1 as i32 {
        let (x, _) = to_px(10f64.powi(d), 10f64.powf(y0));
        img.line((x, T), (x, h - B), [200, 200, 200]);
        img.text(x, h - B + 0.9 * f64::from(PX), PX, &format!("1e{d}"), black, Align::Centre);
    }
    for d in y0 as i32..=y1 as i32 {
        let (_, y) = to_px(10f64.powf(x0), 10f64.powi(d));
        img.line((L, y), (w - R, y), [200, 200, 200]);
        img.text(L - 0.4 * f64::from(PX), y, PX, &format!("1e{d}"), black, Align::Right);
    }
    img.line((L, T), (L, h - B), black);
    img.line((L, h - B), (w - R, h - B), black);
    img.text((L + w - R) / 2.0, h - 0.6 * f64::from(PX), PX, "render time (s), log scale", black, Align::Centre);
    img.text(L, T / 2.0, PX, "relMSE of Y against the reference, log scale", black, Align::Left);
    let mut legend = format!(
        "plot: seconds 1e{x0}..1e{x1} (horizontal, log), relMSE 1e{y0}..1e{y1} (vertical, log); grid at powers of ten\n"
    );
    let mut entries = Vec::new();
    for (k, label) in labels(points).iter().enumerate() {
        let (name, colour) = PLOT_COLOURS[k % PLOT_COLOURS.len()];
        legend += &format!("  {name}: {label}\n");
        entries.push((label.to_string(), colour));
        let pts: Vec<(f64, f64)> =
            finite.iter().filter(|p| p.label == *label).map(|p| to_px(p.seconds, p.rel_mse)).collect();
        for w in pts.windows(2) {
            img.line(w[0], w[1], colour);
        }
        for &(x, y) in &pts {
            img.marker(x, y, colour);
        }
    }
    img.legend(w - R - 6.0, T + 6.0, PX, &entries);
    img.save(path)?;
    Ok(legend)
}

/// The settings of `quasar bench convergence`.
#[derive(Clone, Debug)]
pub struct BenchSettings {
    /// Comma-separated method variants ([`parse_methods`]).
    pub methods: String,
    /// The longest time budget (s).
    pub time: f64,
    /// Number of budgets: time / 2^(steps - 1), ..., time.
    pub steps: u32,
    /// Reference EXR (its size is the render size); None: a pt render of `reference_spp`.
    pub reference: Option<std::path::PathBuf>,
    /// Samples per pixel of the pt reference.
    pub reference_spp: u32,
    /// Image width without a reference file.
    pub width: u32,
    /// Image height without a reference file.
    pub height: u32,
    /// Photons per iteration of the bidirectional methods (None: 4 per pixel).
    pub photons_per_iteration: Option<u64>,
    /// The error whose reaching time is reported.
    pub target: f64,
    /// Seed of the renders.
    pub seed: u64,
    /// Write the curves as CSV here.
    pub csv: Option<std::path::PathBuf>,
    /// Write a log-log plot here (PNG).
    pub plot: Option<std::path::PathBuf>,
}

/// Runs the benchmark on `desc` and returns its report (the markdown table, and the plot's
/// legend when a plot is written); `log` receives a line per render.
pub fn bench(desc: &SceneDesc, s: &BenchSettings, mut log: impl FnMut(&str)) -> Result<String> {
    let methods = parse_methods(&s.methods)?;
    if !(s.time > 0.0 && s.time.is_finite()) || s.steps == 0 || s.steps > 20 {
        bail!("--time must be positive and --steps in 1..=20");
    }
    let (w, h, reference) = match &s.reference {
        Some(p) => {
            let img = crate::output::read_exr(p)?;
            let y = img
                .channel(LUMINANCE)
                .ok_or_else(|| anyhow::anyhow!("{}: no {LUMINANCE} channel", p.display()))?
                .to_vec();
            (img.width as u32, img.height as u32, y)
        }
        None => {
            let t = std::time::Instant::now();
            let y = pt_reference(desc, s.width, s.height, s.reference_spp, s.seed ^ 0x5eed, true)?;
            log(&format!(
                "reference: pt {}x{}, {} spp, {:.1} s",
                s.width,
                s.height,
                s.reference_spp,
                t.elapsed().as_secs_f64()
            ));
            (s.width, s.height, y)
        }
    };
    let budgets: Vec<f64> = (0..s.steps).rev().map(|k| s.time / 2f64.powi(k as i32)).collect();
    let mut base = JobOverrides { width: Some(w), height: Some(h), seed: Some(s.seed), ..Default::default() };
    base.params.set("photons_per_iteration", s.photons_per_iteration.unwrap_or(4 * w as u64 * h as u64));
    let points = run(desc, &base, &methods, &budgets, &reference, |p| {
        log(&format!("{} {} s: relMSE {:.5} ({} samples/iterations)", p.label, p.budget, p.rel_mse, p.samples));
    })?;
    let mut out = markdown_table(&points, s.target);
    if let Some(p) = &s.csv {
        crate::output::write_atomic_bytes(p, to_csv(&points).as_bytes())?;
    }
    if let Some(p) = &s.plot {
        out += &write_plot(&points, p)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_parse() {
        let v = parse_methods("pt, vismap:1,adaptive:paper,quasi:30,adaptive+quasi").unwrap();
        assert_eq!(v.len(), 5);
        use crate::integrator::params::ParamValue;
        assert_eq!(v[1].params.get("gather_depth"), Some(&ParamValue::Int(1)));
        assert_eq!(v[2].params.get("adaptive_paper"), Some(&ParamValue::Bool(true)));
        assert_eq!(v[3].params.get("cone_deg"), Some(&ParamValue::Float(30.0)));
        assert!(parse_methods("pt:3").is_err());
        assert!(parse_methods("bdpt").is_err());
        assert!(parse_methods("").is_err());
    }

    #[test]
    fn time_to_reach_interpolates_in_log_space() {
        let curve = [(1.0, 0.1), (4.0, 0.01)];
        let t = time_to_reach(&curve, 0.0316227766).unwrap();
        assert!((t - 2.0).abs() < 1e-6, "{t}");
        assert_eq!(time_to_reach(&curve, 0.5), Some(1.0));
        assert_eq!(time_to_reach(&curve, 0.001), None);
    }

    #[test]
    fn the_plot_has_tick_labels_axis_titles_and_a_legend() {
        let point = |label: &str, seconds: f64, rel_mse: f64| CurvePoint {
            label: label.into(),
            budget: seconds,
            seconds,
            samples: 1,
            rel_mse,
        };
        let points =
            [point("pt", 0.5, 0.02), point("pt", 1.0, 0.01), point("vismap", 0.5, 0.03), point("vismap", 1.0, 0.015)];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("curves.png");
        let text = write_plot(&points, &path).unwrap();
        assert!(text.contains("black: pt") && text.contains("red: vismap"), "{text}");
        let img = image::open(&path).unwrap().to_rgb8();
        let dark = |x0: u32, x1: u32, y0: u32, y1: u32| {
            (y0..y1)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .filter(|&(x, y)| img.get_pixel(x, y).0[0] < 100)
                .count()
        };
        let (w, h) = img.dimensions();
        assert!(dark(0, 60, 24, h - 44) > 30, "vertical tick labels in the left margin");
        assert!(dark(70, w - 30, h - 48, h) > 60, "horizontal tick labels and the axis title below the axis");
        // the legend box (top right) holds each curve's colour swatch and dark label text
        let legend: Vec<[u8; 3]> = (30..120)
            .flat_map(|y| (w - 200..w - 20).map(move |x| (x, y)))
            .map(|(x, y)| img.get_pixel(x, y).0)
            .collect();
        assert!(legend.contains(&[220, 30, 30]), "the vismap swatch");
        assert!(legend.iter().filter(|p| p[0] < 60 && p[1] < 60 && p[2] < 60).count() > 40, "legend text");
    }
}
