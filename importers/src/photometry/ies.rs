//! IES LM-63 photometric files (`.ies`): the 1986 layout (no first line), `IESNA91`,
//! `IESNA:LM-63-1995`, `IESNA:LM-63-2002` and `IES:LM-63-2019` headers; `TILT=NONE`,
//! `TILT=INCLUDE` and `TILT=<file>`; photometric types C, B and A. Keyword lines (`[MANUFAC]`,
//! `[LUMCAT]`, `[LUMINAIRE]`) give the label.
//!
//! After the `TILT` line the numbers (separated by spaces, commas or line ends) are:
//! lamps, lumens per lamp (-1: absolute photometry), candela multiplier, vertical and horizontal
//! angle counts, photometric type (1 C, 2 B, 3 A), units, the luminous opening's width, length
//! and height; ballast factor, the 1995 "ballast-lamp photometric factor" (2002: future use,
//! 2019: file generation type; applied only for files before 2002), input watts; the vertical
//! angles, the horizontal angles, and the candela values plane by plane. The candela in the web
//! are the file's values times multiplier, ballast factor (and the old ballast-lamp factor).
//! Errors name the file and line.

use std::path::{Path, PathBuf};

use super::{HorizontalSymmetry, PhotometricType, PhotometricWeb};
use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::small_text::read_legacy_text;

/// Most angles on either axis.
pub const MAX_IES_ANGLES: usize = 100_000;
/// Most candela values in one file.
pub const MAX_IES_VALUES: usize = 4 << 20;

/// The lamp output factor as a function of the luminaire's tilt from its photometric position
/// (`TILT=INCLUDE` or a tilt file): `factors[i]` at `angles_deg[i]`.
#[derive(Clone, Debug, PartialEq)]
pub struct TiltTable {
    /// Lamp-to-luminaire geometry code (1 vertical base-up/down, 2 horizontal along C90, 3 along C0).
    pub geometry: u32,
    /// Tilt angles (degrees, increasing).
    pub angles_deg: Vec<f32>,
    /// Output factor at each angle.
    pub factors: Vec<f32>,
}

impl TiltTable {
    /// The factor at `deg` (linear between the angles, the end values beyond them).
    pub fn factor(&self, deg: f32) -> f32 {
        let (a, f) = (&self.angles_deg, &self.factors);
        if a.is_empty() {
            return 1.0;
        }
        if deg <= a[0] {
            return f[0];
        }
        let i = a.partition_point(|&x| x <= deg);
        if i >= a.len() {
            return f[a.len() - 1];
        }
        let t = (deg - a[i - 1]) / (a[i] - a[i - 1]).max(f32::MIN_POSITIVE);
        f[i - 1] + t * (f[i] - f[i - 1])
    }
}

/// An IES file: the web and, when the file has one, its tilt table.
#[derive(Clone, Debug, PartialEq)]
pub struct IesFile {
    /// The intensity distribution (cd).
    pub web: PhotometricWeb,
    /// `TILT=INCLUDE` / tilt-file data.
    pub tilt: Option<TiltTable>,
    /// The standard the first line names (`LM-63-2002`, ...; `LM-63-1986` without one).
    pub standard: String,
    /// Input watts.
    pub input_watts: f32,
}

/// The numbers after the `TILT` line, each with its line.
struct Numbers<'a> {
    path: &'a Path,
    items: Vec<(f64, usize)>,
    next: usize,
    last_line: usize,
}

impl<'a> Numbers<'a> {
    fn new(path: &'a Path, lines: impl Iterator<Item = (usize, &'a str)>) -> Result<Self, ImportError> {
        let mut items = Vec::new();
        let mut last_line = 0;
        for (n, line) in lines {
            last_line = n;
            for tok in line.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty()) {
                let v: f64 = tok.parse().map_err(|_| {
                    ImportError::new(
                        ImportErrorKind::Syntax,
                        ErrorPlace::line(path, n),
                        format!("`{tok}` is not a number"),
                    )
                })?;
                if !v.is_finite() {
                    return Err(ImportError::new(
                        ImportErrorKind::InvalidValue,
                        ErrorPlace::line(path, n),
                        format!("`{tok}` is not finite"),
                    ));
                }
                if items.len() > MAX_IES_VALUES + 2 * MAX_IES_ANGLES + 64 {
                    return Err(ImportError::new(
                        ImportErrorKind::TooLarge,
                        ErrorPlace::line(path, n),
                        "more numbers than an IES file may hold",
                    ));
                }
                items.push((v, n));
            }
        }
        Ok(Self { path, items, next: 0, last_line })
    }

    fn err(&self, line: usize, msg: impl Into<String>) -> ImportError {
        ImportError::new(ImportErrorKind::InvalidValue, ErrorPlace::line(self.path, line), msg)
    }

    /// The next number and its line; `what` names it in the error at the end of the data.
    fn take(&mut self, what: &str) -> Result<(f64, usize), ImportError> {
        let v = self.items.get(self.next).copied().ok_or_else(|| {
            ImportError::new(
                ImportErrorKind::Syntax,
                ErrorPlace::line(self.path, self.last_line.max(1)),
                format!("the file ends before {what}"),
            )
        })?;
        self.next += 1;
        Ok(v)
    }

    fn count(&mut self, what: &str, max: usize) -> Result<usize, ImportError> {
        let (v, line) = self.take(what)?;
        if v.fract() != 0.0 || v < 1.0 || v > max as f64 {
            return Err(self.err(line, format!("{what} must be a whole number in 1..={max}, got {v}")));
        }
        Ok(v as usize)
    }

    /// `n` angles, increasing, within `range`.
    fn angles(&mut self, n: usize, what: &str, range: (f32, f32)) -> Result<Vec<f32>, ImportError> {
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let (v, line) = self.take(&format!("{what} angle {}", i + 1))?;
            let v = v as f32;
            if !(range.0..=range.1).contains(&v) {
                return Err(self.err(line, format!("{what} angle {v} is outside {}..{} degrees", range.0, range.1)));
            }
            if out.last().is_some_and(|&p| v <= p) {
                return Err(self.err(line, format!("{what} angles must increase: {v} follows {}", out[i - 1])));
            }
            out.push(v);
        }
        Ok(out)
    }
}

/// Reads the IES file at `path`.
pub fn read_ies(path: &Path) -> Result<IesFile, ImportError> {
    let text = read_legacy_text(path, "IES file")?;
    parse_ies(&text, path)
}

/// Parses IES text (`path` for messages and for a relative `TILT=<file>`).
pub fn parse_ies(text: &str, path: &Path) -> Result<IesFile, ImportError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim_start_matches('\u{feff}')));
    let mut standard = "LM-63-1986".to_string();
    let mut label = Vec::new();
    let mut tilt_line = None;
    for (n, line) in lines.by_ref() {
        let t = line.trim();
        if n == 1 && !t.starts_with('[') && !t.to_ascii_uppercase().starts_with("TILT=") {
            standard = match t.to_ascii_uppercase().as_str() {
                "IESNA91" => "LM-63-1991".into(),
                s if s.starts_with("IESNA:LM-63-") || s.starts_with("IES:LM-63-") => {
                    s.split_once(':').map_or(s, |(_, v)| v).to_string()
                }
                _ => {
                    // a 1986 file: free text up to the TILT line
                    label.push(t.to_string());
                    "LM-63-1986".into()
                }
            };
            continue;
        }
        if let Some(rest) = t.strip_prefix('[') {
            if let Some((key, value)) = rest.split_once(']')
                && matches!(key.to_ascii_uppercase().as_str(), "MANUFAC" | "LUMCAT" | "LUMINAIRE")
                && !value.trim().is_empty()
            {
                label.push(value.trim().to_string());
            }
            continue;
        }
        if t.to_ascii_uppercase().starts_with("TILT=") {
            tilt_line = Some((n, t.split_once('=').map_or("", |(_, v)| v).trim().to_string()));
            break;
        }
        // free text of an old file (1986), or a continuation line
    }
    let Some((tilt_n, tilt)) = tilt_line else {
        return Err(ImportError::new(ImportErrorKind::Syntax, ErrorPlace::file(path), "no `TILT=` line"));
    };
    let mut nums = Numbers::new(path, lines)?;
    let tilt = match tilt.to_ascii_uppercase().as_str() {
        "NONE" => None,
        "INCLUDE" => Some(tilt_table(&mut nums)?),
        _ => {
            let file = path.parent().unwrap_or(Path::new(".")).join(&tilt);
            let t = read_legacy_text(&file, "IES tilt file").map_err(|e| {
                ImportError::new(e.kind, ErrorPlace::line(path, tilt_n), format!("TILT={tilt}: {}", e.message))
            })?;
            let mut tn = Numbers::new(&file, t.lines().enumerate().map(|(i, l)| (i + 1, l)))?;
            Some(tilt_table(&mut tn)?)
        }
    };
    let lamps = nums.take("the number of lamps")?.0;
    let (lumens, _) = nums.take("the lumens per lamp")?;
    let (multiplier, mline) = nums.take("the candela multiplier")?;
    if multiplier < 0.0 {
        return Err(nums.err(mline, format!("the candela multiplier must be >= 0, got {multiplier}")));
    }
    let nv = nums.count("the number of vertical angles", MAX_IES_ANGLES)?;
    let nh = nums.count("the number of horizontal angles", MAX_IES_ANGLES)?;
    let (ty, tline) = nums.take("the photometric type")?;
    let kind = match ty as i64 {
        1 => PhotometricType::C,
        2 => PhotometricType::B,
        3 => PhotometricType::A,
        _ => return Err(nums.err(tline, format!("photometric type must be 1 (C), 2 (B) or 3 (A), got {ty}"))),
    };
    for what in ["the units type", "the luminous width", "the luminous length", "the luminous height"] {
        nums.take(what)?;
    }
    let (ballast, bline) = nums.take("the ballast factor")?;
    let (old_factor, oline) = nums.take("the ballast-lamp photometric factor / future use")?;
    let (watts, _) = nums.take("the input watts")?;
    let old = matches!(standard.as_str(), "LM-63-1986" | "LM-63-1991" | "LM-63-1995");
    if ballast < 0.0 || (old && old_factor < 0.0) {
        let line = if ballast < 0.0 { bline } else { oline };
        return Err(nums.err(line, "ballast factors must be >= 0"));
    }
    if nv * nh > MAX_IES_VALUES {
        return Err(nums.err(tline, format!("{nv} x {nh} candela values are more than {MAX_IES_VALUES}")));
    }
    let (vr, hr) = match kind {
        PhotometricType::C => ((0.0, 180.0), (0.0, 360.0)),
        _ => ((-90.0, 90.0), (-90.0, 90.0)),
    };
    let vertical_deg = nums.angles(nv, "vertical", vr)?;
    let mut horizontal_deg = nums.angles(nh, "horizontal", hr)?;
    let factor = (multiplier * ballast * if old { old_factor } else { 1.0 }) as f32;
    if !factor.is_finite() {
        return Err(nums.err(mline, "the candela multiplier times the ballast factors is not a finite number"));
    }
    let mut candela = Vec::with_capacity(nv * nh);
    for h in 0..nh {
        for v in 0..nv {
            let (c, line) = nums.take(&format!("candela value {} of horizontal angle {}", v + 1, h + 1))?;
            if c < 0.0 {
                return Err(nums.err(line, format!("candela values must be >= 0, got {c}")));
            }
            if c * f64::from(factor) > super::MAX_CANDELA {
                return Err(nums.err(line, format!("{c} cd (x {factor}) is more than {:e} cd", super::MAX_CANDELA)));
            }
            candela.push((c * f64::from(factor)) as f32);
        }
    }
    if let Some(&(_, line)) = nums.items.get(nums.next) {
        return Err(ImportError::new(
            ImportErrorKind::Syntax,
            ErrorPlace::line(path, line),
            format!("{} numbers after the last candela value", nums.items.len() - nums.next),
        ));
    }
    let (first, last) = (horizontal_deg[0], horizontal_deg[nh - 1]);
    let symmetry = match kind {
        _ if nh == 1 => HorizontalSymmetry::Axial,
        PhotometricType::C if first == 0.0 && last == 90.0 => HorizontalSymmetry::Quadrant,
        PhotometricType::C if first == 0.0 && last == 180.0 => HorizontalSymmetry::Bilateral,
        PhotometricType::C if first == 90.0 && last == 270.0 => HorizontalSymmetry::BilateralC90,
        PhotometricType::C if first == 0.0 => {
            if last < 360.0 {
                // the measured planes end short of 360: close the circle with the C0 plane
                let c0: Vec<f32> = candela[..nv].to_vec();
                candela.extend(c0);
                horizontal_deg.push(360.0);
            }
            HorizontalSymmetry::Full
        }
        PhotometricType::C => {
            return Err(nums.err(
                tline,
                format!("type C horizontal angles {first}..{last}: expected 0, 0..90, 0..180, 90..270 or 0..360"),
            ));
        }
        _ if first == 0.0 => HorizontalSymmetry::Bilateral,
        _ => HorizontalSymmetry::Full,
    };
    let lamp_lumens = Some((lumens * lamps.max(1.0)) as f32).filter(|l| *l > 0.0 && l.is_finite());
    let web = PhotometricWeb {
        file: PathBuf::from(path),
        kind,
        symmetry,
        vertical_deg,
        horizontal_deg,
        candela,
        lamp_lumens,
        luminaire_lumens: None,
        multiplier: factor,
        label: label.join(" "),
    };
    Ok(IesFile { web, tilt, standard, input_watts: watts as f32 })
}

/// The tilt data: geometry, count, angles, factors.
fn tilt_table(nums: &mut Numbers<'_>) -> Result<TiltTable, ImportError> {
    let (g, gline) = nums.take("the lamp-to-luminaire geometry")?;
    if !(1.0..=3.0).contains(&g) || g.fract() != 0.0 {
        return Err(nums.err(gline, format!("lamp-to-luminaire geometry must be 1, 2 or 3, got {g}")));
    }
    let n = nums.count("the number of tilt angles", MAX_IES_ANGLES)?;
    let angles_deg = nums.angles(n, "tilt", (0.0, 180.0))?;
    let mut factors = Vec::with_capacity(n);
    for i in 0..n {
        let (f, line) = nums.take(&format!("tilt factor {}", i + 1))?;
        if f < 0.0 {
            return Err(nums.err(line, format!("tilt factors must be >= 0, got {f}")));
        }
        factors.push(f as f32);
    }
    Ok(TiltTable { geometry: g as u32, angles_deg, factors })
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOWNLIGHT: &str = "IESNA:LM-63-2002
[TEST] 12345
[MANUFAC] Example Lighting
[LUMCAT] DL-1
TILT=NONE
1 1000 2.0 5 1 1 2 0.1 0.1 0
0.9 1.0 12
0 22.5 45 67.5 90
0
100 92.4 70.7 38.3 0
";

    #[test]
    fn a_2002_file_reads_with_its_multipliers() {
        let f = parse_ies(DOWNLIGHT, Path::new("dl.ies")).unwrap();
        assert_eq!(f.standard, "LM-63-2002");
        let w = &f.web;
        assert_eq!((w.kind, w.symmetry), (PhotometricType::C, HorizontalSymmetry::Axial));
        assert_eq!(w.label, "Example Lighting DL-1");
        assert_eq!(w.lamp_lumens, Some(1000.0));
        assert!((w.multiplier - 1.8).abs() < 1e-6);
        assert!((w.intensity_at(0.0, 0.0) - 180.0).abs() < 1e-3);
        assert!((w.intensity_at(123.0, 45.0) - 70.7 * 1.8).abs() < 1e-3);
        assert_eq!(w.intensity_at(0.0, 100.0), 0.0);
        assert_eq!(f.input_watts, 12.0);
    }

    /// A label with a Latin-1 byte (a degree sign, 0xB0, as manufacturers' tools write it) is
    /// read as Latin-1 (issue 51: "not valid UTF-8"); an EULUMDAT file likewise.
    #[test]
    fn latin1_labels_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let mut bytes = DOWNLIGHT.replace("[LUMCAT] DL-1", "[LUMCAT] DL-1 60").into_bytes();
        let at = bytes.windows(5).position(|w| w == b"DL-1 ").unwrap() + 7;
        bytes.insert(at, 0xB0);
        let p = dir.path().join("latin1.ies");
        std::fs::write(&p, &bytes).unwrap();
        let f = read_ies(&p).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.web.label, "Example Lighting DL-1 60\u{b0}");
        let mut ldt = crate::photometry::eulumdat::tests::ldt(1, 24, |_, _| 10.0).into_bytes();
        let at = ldt.windows(9).position(|w| w == b"Downlight").unwrap() + 9;
        ldt.splice(at..at, b" 60\xB0".iter().copied());
        let p = dir.path().join("latin1.ldt");
        std::fs::write(&p, &ldt).unwrap();
        let w = crate::photometry::eulumdat::read_ldt(&p).unwrap_or_else(|e| panic!("{e}")).web;
        assert!(w.label.contains("Downlight 60\u{b0}"), "{}", w.label);
    }

    /// The numbers may run across lines and be separated by commas; a 1995 file applies its
    /// ballast-lamp factor, a 2019 file does not (the field is the file generation type).
    #[test]
    fn headers_of_every_edition() {
        let body = "TILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1.0 0.5 10\n0,90\n0\n10\n20\n";
        let f95 = parse_ies(&format!("IESNA:LM-63-1995\n{body}"), Path::new("a.ies")).unwrap();
        assert!((f95.web.intensity_at(0.0, 0.0) - 5.0).abs() < 1e-6);
        assert_eq!(f95.web.lamp_lumens, None, "absolute photometry");
        let f19 = parse_ies(&format!("IES:LM-63-2019\n[TEST] x\n{body}"), Path::new("a.ies")).unwrap();
        assert_eq!(f19.standard, "LM-63-2019");
        assert!((f19.web.intensity_at(0.0, 90.0) - 20.0).abs() < 1e-6);
        let f86 = parse_ies(&format!("A 1986 FILE'S FREE TEXT\n{body}"), Path::new("a.ies")).unwrap();
        assert_eq!((f86.standard.as_str(), f86.web.label.as_str()), ("LM-63-1986", "A 1986 FILE'S FREE TEXT"));
        assert!((f86.web.intensity_at(0.0, 0.0) - 5.0).abs() < 1e-6, "the old ballast-lamp factor applies");
    }

    #[test]
    fn tilt_include_and_tilt_files() {
        let body = "1 1000 1 2 1 1 2 0 0 0\n1 1 10\n0 90\n0\n10 20\n";
        let inc = format!("IESNA:LM-63-2002\nTILT=INCLUDE\n1\n3\n0 45 90\n1 0.8 0.5\n{body}");
        let f = parse_ies(&inc, Path::new("t.ies")).unwrap();
        let t = f.tilt.unwrap();
        assert_eq!((t.geometry, t.angles_deg.len()), (1, 3));
        assert!((t.factor(22.5) - 0.9).abs() < 1e-6 && t.factor(120.0) == 0.5);
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("lamp.tlt"), "2\n2\n0 90\n1 0.5\n").unwrap();
        let p = dir.path().join("t.ies");
        std::fs::write(&p, format!("IESNA:LM-63-2002\nTILT=lamp.tlt\n{body}")).unwrap();
        let t = read_ies(&p).unwrap().tilt.unwrap();
        assert!((t.factor(45.0) - 0.75).abs() < 1e-6);
        std::fs::write(&p, format!("IESNA:LM-63-2002\nTILT=none.tlt\n{body}")).unwrap();
        let e = read_ies(&p).unwrap_err().to_string();
        assert!(e.contains("t.ies:2") && e.contains("none.tlt"), "{e}");
    }

    /// Malformed files are errors naming the file and the line.
    #[test]
    fn malformed_files_name_the_line() {
        let cases = [
            (DOWNLIGHT.replace("100 92.4", "100 -92.4"), "dl.ies:10", "candela values must be >= 0"),
            (DOWNLIGHT.replace("0 22.5 45", "0 45 22.5"), "dl.ies:8", "must increase"),
            (DOWNLIGHT.replace("38.3 0\n", "38.3\n"), "dl.ies:10", "ends before candela value 5"),
            (DOWNLIGHT.replace("1 1 2 0.1", "1 4 2 0.1"), "dl.ies:6", "photometric type"),
            (DOWNLIGHT.replace("TILT=NONE", "TILTED"), "dl.ies", "no `TILT=` line"),
            (DOWNLIGHT.replace("0.9 1.0 12", "0.9 x 12"), "dl.ies:7", "`x` is not a number"),
            (DOWNLIGHT.replace("38.3 0\n", "38.3 0 7\n"), "dl.ies:10", "after the last candela"),
            (DOWNLIGHT.replace(" 5 1 1 2", " 0 1 1 2"), "dl.ies:6", "number of vertical angles"),
            (DOWNLIGHT.replace("100 92.4", "1e300 92.4"), "dl.ies:10", "cd (x 1.8) is more than"),
        ];
        for (text, place, msg) in cases {
            let e = parse_ies(&text, Path::new("dl.ies")).unwrap_err().to_string();
            assert!(e.starts_with(place) && e.contains(msg), "{e}\nwanted {place}: {msg}");
        }
    }
}
