//! EULUMDAT photometric files (`.ldt`, Stockmar 1990/1998): one field per line; type C
//! photometry. The fields read: symmetry `Isym` (line 3: 0 none, 1 about the vertical axis,
//! 2 to the C0-C180 plane, 3 to the C90-C270 plane, 4 to both), the counts `Mc` and `Ng`
//! (lines 4 and 6), the luminaire name (9), the light output ratio LORL (23, %), the conversion
//! factor (24; 0 read as 1), the lamp sets (26: count `n`, then `n` lines each of lamp counts,
//! types, total luminous flux in lm, colour, colour rendering and watts, field by field), the
//! ten direct ratios (27), the `Mc` C angles, the `Ng` gamma angles and the intensities in cd
//! per 1000 lm of lamp flux for the planes the symmetry stores (C0..C180 for 2, C270..C90 for
//! 3, C0..C90 for 4, C0 for 1, all for 0). The candela in the web are those values times the
//! lamp flux / 1000 times the conversion factor. Decimal commas are read as points. Errors name
//! the file and line.

use std::path::{Path, PathBuf};

use super::{HorizontalSymmetry, PhotometricType, PhotometricWeb};
use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::small_text::read_legacy_text;

/// Most C planes or gamma angles.
pub const MAX_LDT_ANGLES: usize = 10_000;
/// Most lamp sets.
pub const MAX_LDT_LAMP_SETS: usize = 1_000;

/// A EULUMDAT file's web and the figures it states.
#[derive(Clone, Debug, PartialEq)]
pub struct LdtFile {
    /// The intensity distribution (cd).
    pub web: PhotometricWeb,
    /// Light output ratio of the luminaire (fraction, from line 23).
    pub light_output_ratio: f32,
    /// Downward flux fraction (fraction, line 22).
    pub downward_flux_fraction: f32,
}

struct Lines<'a> {
    path: &'a Path,
    lines: Vec<&'a str>,
    next: usize,
}

impl<'a> Lines<'a> {
    fn err(&self, kind: ImportErrorKind, line: usize, msg: impl Into<String>) -> ImportError {
        ImportError::new(kind, ErrorPlace::line(self.path, line), msg)
    }

    /// The next line (trimmed) and its number.
    fn text(&mut self, what: &str) -> Result<(&'a str, usize), ImportError> {
        let n = self.next + 1;
        let l: &'a str = self.lines.get(self.next).copied().ok_or_else(|| {
            self.err(
                ImportErrorKind::Syntax,
                self.lines.len().max(1),
                format!("the file ends before {what} (line {n})"),
            )
        })?;
        self.next += 1;
        Ok((l.trim(), n))
    }

    fn number(&mut self, what: &str) -> Result<(f64, usize), ImportError> {
        let (t, n) = self.text(what)?;
        let v: f64 = t.replace(',', ".").parse().map_err(|_| {
            ImportError::new(
                ImportErrorKind::Syntax,
                ErrorPlace::line(self.path, n),
                format!("{what}: `{t}` is not a number"),
            )
        })?;
        if !v.is_finite() {
            return Err(self.err(ImportErrorKind::InvalidValue, n, format!("{what}: `{t}` is not finite")));
        }
        Ok((v, n))
    }

    /// `n` angles, one per line, increasing within 0..=`max` degrees.
    fn angles(&mut self, n: usize, what: &str, max: f64) -> Result<Vec<f32>, ImportError> {
        let mut out: Vec<f32> = Vec::with_capacity(n);
        for i in 0..n {
            let (a, line) = self.number(&format!("{what} angle {}", i + 1))?;
            if !(0.0..=max).contains(&a) || out.last().is_some_and(|&p| a as f32 <= p) {
                let msg = format!("{what} angles must increase within 0..{max}, got {a}");
                return Err(self.err(ImportErrorKind::InvalidValue, line, msg));
            }
            out.push(a as f32);
        }
        Ok(out)
    }

    fn count(&mut self, what: &str, lo: usize, max: usize) -> Result<usize, ImportError> {
        let (v, n) = self.number(what)?;
        if v.fract() != 0.0 || v < lo as f64 || v > max as f64 {
            return Err(self.err(
                ImportErrorKind::InvalidValue,
                n,
                format!("{what} must be a whole number in {lo}..={max}, got {v}"),
            ));
        }
        Ok(v as usize)
    }
}

/// Reads the EULUMDAT file at `path`.
pub fn read_ldt(path: &Path) -> Result<LdtFile, ImportError> {
    let text = read_legacy_text(path, "EULUMDAT file")?;
    parse_ldt(&text, path)
}

/// Parses EULUMDAT text (`path` for messages).
pub fn parse_ldt(text: &str, path: &Path) -> Result<LdtFile, ImportError> {
    let mut l = Lines { path, lines: text.lines().map(|s| s.trim_start_matches('\u{feff}')).collect(), next: 0 };
    let (company, _) = l.text("the company identification")?;
    let company = company.to_string();
    l.count("the type indicator Ityp", 0, 3)?;
    let isym = l.count("the symmetry indicator Isym", 0, 4)?;
    let mc = l.count("the number of C planes Mc", 1, MAX_LDT_ANGLES)?;
    l.number("the C plane distance Dc")?;
    let ng = l.count("the number of intensities per plane Ng", 1, MAX_LDT_ANGLES)?;
    l.number("the intensity distance Dg")?;
    l.text("the measurement report number")?;
    let (name, _) = l.text("the luminaire name")?;
    let name = name.to_string();
    for what in ["the luminaire number", "the file name", "the date/user"] {
        l.text(what)?;
    }
    for what in ["the luminaire length", "the luminaire width", "the luminaire height", "the luminous area length"] {
        l.number(what)?;
    }
    for what in ["the luminous area width", "the C0 height", "the C90 height", "the C180 height", "the C270 height"] {
        l.number(what)?;
    }
    let (dff, _) = l.number("the downward flux fraction DFF")?;
    let (lor, lor_line) = l.number("the light output ratio LORL")?;
    let (cf, _) = l.number("the conversion factor")?;
    l.number("the tilt during measurement")?;
    let sets = l.count("the number of lamp sets n", 1, MAX_LDT_LAMP_SETS)?;
    for _ in 0..sets {
        l.text("a lamp count")?;
    }
    for _ in 0..sets {
        l.text("a lamp type")?;
    }
    let mut flux = 0.0f64;
    for _ in 0..sets {
        let (f, n) = l.number("a lamp set's luminous flux")?;
        if f < 0.0 {
            return Err(l.err(ImportErrorKind::InvalidValue, n, format!("lamp flux must be >= 0 lm, got {f}")));
        }
        flux += f;
    }
    for what in ["a colour appearance", "a colour rendering group", "a wattage"] {
        for _ in 0..sets {
            l.text(what)?;
        }
    }
    for _ in 0..10 {
        l.number("a direct ratio")?;
    }
    let c_angles = l.angles(mc, "C", 360.0)?;
    let vertical_deg = l.angles(ng, "gamma", 180.0)?;
    // the stored planes, as indices into c_angles
    let planes: Vec<usize> = match isym {
        0 => (0..mc).collect(),
        1 => vec![0],
        2 => (0..=mc / 2).collect(),
        3 => (3 * mc / 4..mc).chain(0..=mc / 4).collect(),
        _ => (0..=mc / 4).collect(),
    };
    if planes.iter().any(|&i| i >= mc) || (isym >= 2 && mc % 4 != 0 && isym != 2) || (isym == 2 && mc % 2 != 0) {
        return Err(l.err(
            ImportErrorKind::InvalidValue,
            4,
            format!("Mc = {mc} planes do not fit symmetry Isym = {isym}"),
        ));
    }
    let factor = (flux / 1000.0 * if cf > 0.0 { cf } else { 1.0 }) as f32;
    if !factor.is_finite() {
        return Err(l.err(
            ImportErrorKind::InvalidValue,
            24,
            "the lamp flux times the conversion factor is not finite",
        ));
    }
    let mut rows: Vec<(f32, Vec<f32>)> = Vec::with_capacity(planes.len());
    for &p in &planes {
        let mut row = Vec::with_capacity(ng);
        for g in &vertical_deg {
            let (v, n) = l.number(&format!("the intensity at C {} gamma {g}", c_angles[p]))?;
            if v < 0.0 {
                return Err(l.err(ImportErrorKind::InvalidValue, n, format!("intensities must be >= 0, got {v}")));
            }
            if v * f64::from(factor) > super::MAX_CANDELA {
                let msg = format!("{v} cd/klm (x {factor}) is more than {:e} cd", super::MAX_CANDELA);
                return Err(l.err(ImportErrorKind::InvalidValue, n, msg));
            }
            row.push((v * f64::from(factor)) as f32);
        }
        // Isym 3 stores C270..C90: mirrored about the C90-C270 plane they are C90..C270 (C -> 180 - C)
        let c = if isym == 3 { (180.0 - c_angles[p]).rem_euclid(360.0) } else { c_angles[p] };
        rows.push((c, row));
    }
    if isym == 3 {
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        // C0 mirrors to 180 and C90 to 90; C270 to 270
    }
    if isym == 0 && rows.last().is_some_and(|r| r.0 < 360.0) && rows[0].0 == 0.0 {
        let first = rows[0].1.clone();
        rows.push((360.0, first));
    }
    let symmetry = match isym {
        0 => HorizontalSymmetry::Full,
        1 => HorizontalSymmetry::Axial,
        2 => HorizontalSymmetry::Bilateral,
        3 => HorizontalSymmetry::BilateralC90,
        _ => HorizontalSymmetry::Quadrant,
    };
    let expected_range = match isym {
        2 => Some((0.0, 180.0)),
        3 => Some((90.0, 270.0)),
        4 => Some((0.0, 90.0)),
        _ => None,
    };
    if let Some((a, b)) = expected_range {
        let (first, last) = (rows[0].0, rows[rows.len() - 1].0);
        if (first - a).abs() > 1e-3 || (last - b).abs() > 1e-3 {
            return Err(l.err(
                ImportErrorKind::InvalidValue,
                4,
                format!("the stored C planes span {first}..{last}, not {a}..{b} as Isym = {isym} needs"),
            ));
        }
    }
    if l.lines[l.next..].iter().any(|s| !s.trim().is_empty()) {
        return Err(l.err(ImportErrorKind::Syntax, l.next + 1, "text after the last intensity"));
    }
    if !(0.0..=100.0).contains(&lor) {
        return Err(l.err(ImportErrorKind::InvalidValue, lor_line, format!("LORL must be in 0..100 %, got {lor}")));
    }
    let web = PhotometricWeb {
        file: PathBuf::from(path),
        kind: PhotometricType::C,
        symmetry,
        vertical_deg,
        horizontal_deg: rows.iter().map(|r| r.0).collect(),
        candela: rows.into_iter().flat_map(|r| r.1).collect(),
        lamp_lumens: Some(flux as f32).filter(|f| *f > 0.0 && f.is_finite()),
        luminaire_lumens: Some((flux * lor / 100.0) as f32).filter(|f| *f > 0.0 && f.is_finite()),
        multiplier: factor,
        label: [company, name].iter().filter(|s| !s.is_empty()).cloned().collect::<Vec<_>>().join(" "),
    };
    Ok(LdtFile { web, light_output_ratio: (lor / 100.0) as f32, downward_flux_fraction: (dff / 100.0) as f32 })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A EULUMDAT text of symmetry `isym` with `mc` planes every 360/mc degrees, gamma 0..180 every
    /// 45 degrees, one lamp set of 2000 lm, intensities `f(C, gamma)` in cd/klm.
    pub(crate) fn ldt(isym: usize, mc: usize, f: impl Fn(f32, f32) -> f32) -> String {
        let dc = 360.0 / mc as f32;
        let mut s = format!("Example\n1\n{isym}\n{mc}\n{dc}\n5\n45\nreport\nDownlight\nNo 1\nfile\ndate\n");
        s += "100\n0\n50\n90\n0\n0\n0\n0\n0\n100\n80\n1\n0\n1\n1\nLED\n2000\n3000K\n1B\n20\n";
        s += &"0.5\n".repeat(10);
        let cs: Vec<f32> = (0..mc).map(|i| i as f32 * dc).collect();
        for c in &cs {
            s += &format!("{c}\n");
        }
        for g in 0..5 {
            s += &format!("{}\n", g * 45);
        }
        let planes: Vec<usize> = match isym {
            0 => (0..mc).collect(),
            1 => vec![0],
            2 => (0..=mc / 2).collect(),
            3 => (3 * mc / 4..mc).chain(0..=mc / 4).collect(),
            _ => (0..=mc / 4).collect(),
        };
        for p in planes {
            for g in 0..5 {
                s += &format!("{}\n", f(cs[p], g as f32 * 45.0));
            }
        }
        s
    }

    /// Every symmetry unfolds to the distribution the full file gives, in candela (cd/klm x 2 klm).
    #[test]
    fn every_symmetry_reads_to_the_same_distribution() {
        // symmetric about both planes, so every Isym can store it
        let f = |c: f32, g: f32| (100.0 + 50.0 * (2.0 * c.to_radians()).cos()) * (1.0 + g / 90.0);
        let full = parse_ldt(&ldt(0, 24, f), Path::new("a.ldt")).unwrap().web;
        assert_eq!(full.lamp_lumens, Some(2000.0));
        assert_eq!(full.luminaire_lumens, Some(1600.0));
        assert_eq!(full.label, "Example Downlight");
        for isym in 2..=4 {
            let w = parse_ldt(&ldt(isym, 24, f), Path::new("a.ldt")).unwrap().web;
            for c in [0.0f32, 15.0, 100.0, 185.0, 260.0, 300.0, 350.0] {
                for g in [0.0f32, 30.0, 135.0] {
                    let (a, b) = (w.intensity_at(c, g), full.intensity_at(c, g));
                    assert!((a - b).abs() < 1e-3 * b, "Isym {isym} C{c} g{g}: {a} vs {b}");
                }
            }
        }
        assert!((full.intensity_at(0.0, 0.0) - 300.0).abs() < 1e-3, "150 cd/klm x 2 klm");
        let axial = parse_ldt(&ldt(1, 24, |_, g| 100.0 - g / 2.0), Path::new("a.ldt")).unwrap().web;
        assert!((axial.intensity_at(77.0, 90.0) - 110.0).abs() < 1e-3);
    }

    /// Isym 3 keeps the asymmetry across the C0-C180 plane (C90 differs from C270).
    #[test]
    fn symmetry_to_the_c90_plane_keeps_c90_and_c270_apart() {
        let f = |c: f32, _: f32| 100.0 + c.to_radians().sin() * 50.0;
        let w = parse_ldt(&ldt(3, 24, f), Path::new("a.ldt")).unwrap().web;
        assert!((w.intensity_at(90.0, 0.0) - 300.0).abs() < 1e-3);
        assert!((w.intensity_at(270.0, 0.0) - 100.0).abs() < 1e-3);
        assert!((w.intensity_at(60.0, 0.0) - w.intensity_at(120.0, 0.0)).abs() < 1e-3);
        assert!((w.intensity_at(0.0, 0.0) - 200.0).abs() < 1e-3);
    }

    #[test]
    fn malformed_files_name_the_line() {
        let good = ldt(1, 24, |_, _| 10.0);
        let lines: Vec<&str> = good.lines().collect();
        let with = |i: usize, v: &str| {
            let mut l = lines.clone();
            l[i] = v;
            l.join("\n")
        };
        let cases = [
            (with(2, "7"), "a.ldt:3", "Isym"),
            (with(36, "x"), "a.ldt:37", "not a number"),
            (with(lines.len() - 1, "-1"), &*format!("a.ldt:{}", lines.len()), "intensities must be >= 0"),
            (lines[..40].join("\n"), "a.ldt:40", "the file ends before"),
            (format!("{good}\n7\n"), &*format!("a.ldt:{}", lines.len() + 1), "after the last intensity"),
        ];
        for (text, place, msg) in cases {
            let e = parse_ldt(&text, Path::new("a.ldt")).unwrap_err().to_string();
            assert!(e.starts_with(place) && e.contains(msg), "{e}\nwanted {place}: {msg}");
        }
    }
}
