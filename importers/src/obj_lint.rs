//! Line-oriented validation of OBJ and MTL files before they are handed to `tobj`.
//!
//! `tobj` reports errors without line numbers (and panics on a few malformed MTL lines), so every
//! statement that `tobj` interprets is checked here first: arity, number syntax, finiteness and
//! (for faces) index ranges, including negative (relative) indices. Each problem is reported as
//! `file:line: what is wrong`. The MTL check also produces a normalised copy of the file (same
//! line count) that `tobj` can parse without surprises.

use std::io::{BufRead, Read};
use std::path::Path;

use crate::error::{ErrorPlace, ImportError, ImportErrorKind};
use crate::obj_keywords::QUIET_KEYWORDS;
use crate::obj_text::{strip_comment, strip_eol};

/// Largest OBJ file accepted (bytes).
pub const MAX_OBJ_BYTES: u64 = 2 << 30;
/// Longest line accepted in an OBJ file (bytes).
pub const MAX_OBJ_LINE_BYTES: u64 = 64 << 20;
/// Largest number of triangles (after fan triangulation) accepted in one OBJ file.
pub const MAX_OBJ_TRIANGLES: u64 = 1 << 28;

/// A `usemtl` statement.
#[derive(Clone, Debug)]
pub(crate) struct UseMtl {
    /// 1-based line.
    pub line: usize,
    /// The material name as `tobj` extracts it from the line (its lookup key).
    pub tobj_key: String,
    /// The material name (everything after the keyword, trimmed).
    pub name: String,
}

/// A `mtllib` statement.
#[derive(Clone, Debug)]
pub(crate) struct MtlLib {
    /// 1-based line.
    pub line: usize,
    /// Everything after the keyword, trimmed: one file name (possibly with spaces) or several.
    pub names: String,
}

/// What the OBJ check learned about the file.
#[derive(Clone, Debug, Default)]
pub(crate) struct ObjSummary {
    /// Number of `v` statements.
    pub positions: u64,
    /// Number of triangles the faces give after fan triangulation.
    pub triangles: u64,
    /// `mtllib` statements in file order.
    pub mtllibs: Vec<MtlLib>,
    /// `usemtl` statements in file order.
    pub usemtls: Vec<UseMtl>,
    /// Statements that are ignored although they are not blank or comments, in file order:
    /// (line, keyword). Keywords of the OBJ specification that quasar does not render (free-form
    /// curves and surfaces, points, lines, display attributes) and keywords it does not know.
    pub ignored: Vec<(usize, String)>,
}

fn syntax(file: &Path, line: usize, msg: impl Into<String>) -> ImportError {
    ImportError::new(ImportErrorKind::Syntax, ErrorPlace::line(file, line), msg)
}

fn invalid(file: &Path, line: usize, msg: impl Into<String>) -> ImportError {
    ImportError::new(ImportErrorKind::InvalidValue, ErrorPlace::line(file, line), msg)
}

/// Parses a finite f32 as `tobj` would read it (Rust `FromStr`), with a message on failure.
fn finite(file: &Path, line: usize, what: &str, tok: &str) -> Result<f32, ImportError> {
    match tok.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(invalid(
            file,
            line,
            format!("{what}: `{tok}` is not a finite number (NaN, infinite, or beyond the f32 range)"),
        )),
        Err(_) => Err(syntax(file, line, format!("{what}: `{tok}` is not a number"))),
    }
}

/// The material name `tobj` extracts from a `usemtl` line: the text after the first space, trimmed.
fn tobj_rest_after_space(line: &str) -> &str {
    line.split_once(' ').map_or("", |(_, r)| r.trim())
}

/// Checks one face-vertex reference `v`, `v/vt`, `v//vn` or `v/vt/vn` against the element counts
/// defined so far.
fn check_ref(file: &Path, line: usize, tok: &str, counts: [u64; 3]) -> Result<(), ImportError> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    const STMT: [&str; 3] = ["v", "vt", "vn"];
    let parts: Vec<&str> = tok.split('/').collect();
    if parts.len() > 3 {
        return Err(syntax(file, line, format!("face vertex `{tok}` has more than three `/`-separated indices")));
    }
    if parts[0].is_empty() {
        return Err(syntax(file, line, format!("face vertex `{tok}` has no vertex index")));
    }
    for (k, p) in parts.iter().enumerate() {
        if p.is_empty() {
            continue;
        }
        let Ok(i) = p.parse::<i64>() else {
            return Err(syntax(file, line, format!("face vertex `{tok}`: `{p}` is not an integer index")));
        };
        let n = counts[k];
        let ok = if i > 0 {
            (i as u64) <= n
        } else if i < 0 {
            i.unsigned_abs() <= n
        } else {
            return Err(invalid(
                file,
                line,
                format!("face vertex `{tok}`: {} index 0 is invalid (OBJ indices start at 1)", WHAT[k]),
            ));
        };
        if !ok {
            return Err(invalid(
                file,
                line,
                format!(
                    "face vertex `{tok}`: {} index {i} is out of range ({n} `{}` statement{} before this line)",
                    WHAT[k],
                    STMT[k],
                    if n == 1 { "" } else { "s" }
                ),
            ));
        }
    }
    Ok(())
}

/// Checks every statement of an OBJ file that `tobj` interprets; see the module documentation.
pub(crate) fn lint_obj(file: &Path, reader: &mut impl BufRead) -> Result<ObjSummary, ImportError> {
    let mut sum = ObjSummary::default();
    let (mut normals, mut texcoords) = (0u64, 0u64);
    let mut buf = Vec::new();
    let mut lineno = 0usize;
    let mut total = 0u64;
    loop {
        buf.clear();
        let n = (&mut *reader)
            .take(MAX_OBJ_LINE_BYTES + 1)
            .read_until(b'\n', &mut buf)
            .map_err(|e| ImportError::io(file, "cannot read OBJ file", e))?;
        if n == 0 {
            break;
        }
        lineno += 1;
        total += n as u64;
        if n as u64 > MAX_OBJ_LINE_BYTES || total > MAX_OBJ_BYTES {
            return Err(ImportError::new(
                ImportErrorKind::TooLarge,
                ErrorPlace::line(file, lineno),
                format!("line longer than {MAX_OBJ_LINE_BYTES} bytes or file larger than {MAX_OBJ_BYTES} bytes"),
            ));
        }
        let Ok(line) = std::str::from_utf8(strip_eol(&buf)) else {
            return Err(syntax(file, lineno, "line is not valid UTF-8"));
        };
        let line = strip_comment(line);
        let mut words = line.split_whitespace();
        let Some(kw) = words.next() else { continue };
        let args: Vec<&str> = words.collect();
        match kw {
            "v" => {
                if !matches!(args.len(), 3 | 4 | 6) {
                    return Err(syntax(
                        file,
                        lineno,
                        format!("`v` expects 3 coordinates (optionally w, or r g b), got {} values", args.len()),
                    ));
                }
                let mut p = [0.0f32; 3];
                for (k, t) in args[..3].iter().enumerate() {
                    p[k] = finite(file, lineno, "vertex coordinate", t)?;
                }
                if args.len() == 4 {
                    let w = finite(file, lineno, "vertex weight w", args[3])?;
                    if w == 0.0 || p.iter().any(|c| !(c / w).is_finite()) {
                        return Err(invalid(
                            file,
                            lineno,
                            format!("vertex weight w = {w} gives non-finite coordinates"),
                        ));
                    }
                } else if args.len() == 6 {
                    for t in &args[3..] {
                        finite(file, lineno, "vertex colour", t)?;
                    }
                }
                sum.positions += 1;
            }
            "vt" => {
                if !matches!(args.len(), 1..=3) {
                    return Err(syntax(file, lineno, format!("`vt` expects 1 to 3 values, got {}", args.len())));
                }
                if args.len() < 2 {
                    // tobj requires u and v
                    return Err(syntax(file, lineno, "`vt` with only one value is not supported (give u v)"));
                }
                for t in &args {
                    finite(file, lineno, "texture coordinate", t)?;
                }
                texcoords += 1;
            }
            "vn" => {
                if args.len() != 3 {
                    return Err(syntax(file, lineno, format!("`vn` expects 3 values, got {}", args.len())));
                }
                for t in &args {
                    finite(file, lineno, "normal component", t)?;
                }
                normals += 1;
            }
            "f" | "l" => {
                let min = if kw == "f" { 3 } else { 2 };
                if args.len() < min {
                    return Err(syntax(
                        file,
                        lineno,
                        format!("`{kw}` needs at least {min} vertices, got {}", args.len()),
                    ));
                }
                for t in &args {
                    check_ref(file, lineno, t, [sum.positions, texcoords, normals])?;
                }
                if kw == "f" {
                    sum.triangles += args.len() as u64 - 2;
                    if sum.triangles > MAX_OBJ_TRIANGLES {
                        return Err(ImportError::new(
                            ImportErrorKind::TooLarge,
                            ErrorPlace::line(file, lineno),
                            format!("more than {MAX_OBJ_TRIANGLES} triangles"),
                        ));
                    }
                }
            }
            "mtllib" => {
                let names = line.trim_start()["mtllib".len()..].trim();
                if names.is_empty() {
                    return Err(syntax(file, lineno, "`mtllib` needs a file name"));
                }
                sum.mtllibs.push(MtlLib { line: lineno, names: names.to_owned() });
            }
            "usemtl" => {
                let name = line.trim_start()["usemtl".len()..].trim();
                let key = tobj_rest_after_space(line);
                if name.is_empty() {
                    return Err(syntax(file, lineno, "`usemtl` needs a material name"));
                }
                if key.is_empty() {
                    return Err(syntax(file, lineno, "`usemtl` and the material name must be separated by a space"));
                }
                sum.usemtls.push(UseMtl { line: lineno, tobj_key: key.to_owned(), name: name.to_owned() });
            }
            kw if QUIET_KEYWORDS.contains(&kw) => {}
            kw => sum.ignored.push((lineno, kw.to_owned())),
        }
    }
    Ok(sum)
}

/// A material of an MTL file as the check saw it.
#[derive(Clone, Debug, Default)]
pub(crate) struct MtlEntry {
    /// Name after `newmtl`.
    pub name: String,
    /// Line of the `newmtl` statement.
    pub line: usize,
    /// Line of the last occurrence of each statement (`Kd`, `Ns`, ...) in this material.
    pub key_lines: Vec<(&'static str, usize)>,
    /// `Tr` (transparency = 1 - d), which `tobj` does not interpret.
    pub tr: Option<f32>,
    /// `Tf` (transmission filter), which `tobj` does not interpret.
    pub tf: Option<[f32; 3]>,
}

impl MtlEntry {
    /// Line of statement `key` in this material, or the `newmtl` line.
    pub fn line_of(&self, key: &str) -> usize {
        self.key_lines.iter().rev().find(|(k, _)| *k == key).map_or(self.line, |(_, l)| *l)
    }
}

/// Result of checking an MTL file.
#[derive(Clone, Debug, Default)]
pub(crate) struct MtlLint {
    /// The file with colour shorthands expanded and texture statements blanked (same lines).
    pub normalized: String,
    /// The materials in file order.
    pub entries: Vec<MtlEntry>,
}

const MTL_KEYS: [&str; 10] = ["Ka", "Kd", "Ks", "Ke", "Tf", "Ns", "Ni", "d", "Tr", "illum"];

/// Checks an MTL file's text; see the module documentation.
pub(crate) fn lint_mtl(file: &Path, text: &str) -> Result<MtlLint, ImportError> {
    let mut out = MtlLint { normalized: String::with_capacity(text.len() + 64), entries: Vec::new() };
    for (i, raw) in text.split('\n').enumerate() {
        let lineno = i + 1;
        let line = strip_comment(raw.strip_suffix('\r').unwrap_or(raw));
        let trimmed = line.trim();
        let mut words = trimmed.split_whitespace();
        let kw = words.next().unwrap_or("");
        let args: Vec<&str> = words.collect();
        let mut emit = line.to_owned();
        let key = MTL_KEYS.iter().copied().find(|k| *k == kw);
        if let Some(key) = key {
            let Some(entry) = out.entries.last_mut() else {
                return Err(syntax(file, lineno, format!("`{kw}` before the first `newmtl`")));
            };
            entry.key_lines.push((key, lineno));
            match key {
                "Ka" | "Kd" | "Ks" | "Ke" | "Tf" => {
                    if let Some(form @ ("spectral" | "xyz")) = args.first().copied() {
                        return Err(ImportError::new(
                            ImportErrorKind::Unsupported,
                            ErrorPlace::line(file, lineno),
                            format!("`{kw} {form}` is not supported; give linear RGB values `{kw} r g b`"),
                        ));
                    }
                    if args.len() != 1 && args.len() != 3 {
                        return Err(syntax(
                            file,
                            lineno,
                            format!("`{kw}` expects r g b (or one grey value), got {} values", args.len()),
                        ));
                    }
                    let mut c = [0.0f32; 3];
                    for (k, t) in args.iter().enumerate() {
                        c[k] = finite(file, lineno, kw, t)?;
                    }
                    if args.len() == 1 {
                        c = [c[0]; 3];
                        emit = format!("{kw} {} {} {}", args[0], args[0], args[0]);
                    }
                    if key == "Tf" {
                        entry.tf = Some(c);
                    }
                }
                "Ns" | "Ni" | "d" | "Tr" => {
                    if args.first() == Some(&"-halo") {
                        return Err(ImportError::new(
                            ImportErrorKind::Unsupported,
                            ErrorPlace::line(file, lineno),
                            "`d -halo` is not supported",
                        ));
                    }
                    if args.len() != 1 {
                        return Err(syntax(file, lineno, format!("`{kw}` expects one number, got {}", args.len())));
                    }
                    let v = finite(file, lineno, kw, args[0])?;
                    if key == "Tr" {
                        entry.tr = Some(v);
                    }
                }
                _ => {
                    // illum: tobj reads a u8
                    if args.len() != 1 || args[0].parse::<u8>().is_err() {
                        return Err(syntax(
                            file,
                            lineno,
                            format!("`illum` expects one integer 0..=10, got `{}`", args.join(" ")),
                        ));
                    }
                }
            }
        } else if kw == "newmtl" {
            let name = trimmed["newmtl".len()..].trim();
            if name.is_empty() {
                return Err(syntax(file, lineno, "`newmtl` needs a material name"));
            }
            out.entries.push(MtlEntry { name: name.to_owned(), line: lineno, ..Default::default() });
        } else if kw.starts_with("map_") || matches!(kw, "bump" | "disp" | "decal" | "refl" | "norm") {
            // textures are not used; blank them so tobj's texture parsing cannot fail
            emit.clear();
        }
        out.normalized.push_str(&emit);
        out.normalized.push('\n');
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obj(s: &str) -> Result<ObjSummary, ImportError> {
        lint_obj(Path::new("m.obj"), &mut s.as_bytes())
    }

    fn obj_err(s: &str) -> String {
        obj(s).unwrap_err().to_string()
    }

    #[test]
    fn accepts_valid_statements() {
        let s = obj("# c\nv 0 0 0\nv 1 0 0 1\nv 0 1 0 1 0 0\nvt 0 0\nvn 0 0 1\r\nf 1/1/1 2/1/1 -1/-1/-1\nf 1//1 2//1 3//1\nl 1 2\nusemtl red\nmtllib a b.mtl\ns off\n")
            .unwrap();
        assert_eq!(s.positions, 3);
        assert_eq!(s.triangles, 2);
        assert_eq!(s.usemtls[0].name, "red");
        assert_eq!(s.mtllibs[0].names, "a b.mtl");
    }

    #[test]
    fn reports_file_and_line() {
        assert!(obj_err("v 0 0 0\nv 1 0\n").starts_with("m.obj:2: `v` expects 3"));
        assert!(obj_err("v 0 0 zero\n").contains("m.obj:1: vertex coordinate: `zero` is not a number"));
        assert!(obj_err("v 0 0 nan\n").contains("m.obj:1:"));
        assert!(obj_err("\n\nv 0 0 1e39\n").contains("m.obj:3:"));
        assert!(obj_err("v 0 0 0 0\n").contains("weight"));
        assert!(obj_err("v 0 0 0\nf 1 1\n").starts_with("m.obj:2:"));
        assert!(
            obj_err("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 4\n")
                .contains("m.obj:4: face vertex `4`: vertex index 4 is out of range (3 `v` statements")
        );
        assert!(obj_err("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 -4\n").contains("m.obj:4:"));
        assert!(obj_err("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 0\n").contains("index 0 is invalid"));
        assert!(
            obj_err("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1/1 2 3\n").contains("texture coordinate index 1 is out of range")
        );
        assert!(obj_err("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1//x 2 3\n").contains("not an integer"));
        assert!(obj_err("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1/1/1/1 2 3\n").contains("more than three"));
        assert!(obj_err("v 0 0 0\nf //1 1 1\n").contains("no vertex index"));
        assert!(obj_err("usemtl\n").contains("m.obj:1: `usemtl` needs"));
        assert!(obj_err("usemtl\tred\n").contains("separated by a space"));
        assert!(obj_err("mtllib  \n").contains("m.obj:1: `mtllib` needs"));
        assert!(obj_err("vn 0 0\n").contains("m.obj:1:"));
        assert!(obj_err("vt 0\n").contains("m.obj:1:"));
        let mut bad = b"v 0 0 0\n".to_vec();
        bad.extend_from_slice(b"v \xff 0 0\n");
        let e = lint_obj(Path::new("m.obj"), &mut bad.as_slice()).unwrap_err().to_string();
        assert!(e.contains("m.obj:2: line is not valid UTF-8"), "{e}");
    }

    #[test]
    fn mtl_lint_normalises_and_reports_lines() {
        let l = lint_mtl(Path::new("a.mtl"), "newmtl red\nKd 0.5\nmap_Kd\nTr 0.2\nTf 1 1 1\nillum 2\n").unwrap();
        assert_eq!(l.entries.len(), 1);
        assert_eq!(l.entries[0].tr, Some(0.2));
        assert_eq!(l.entries[0].tf, Some([1.0; 3]));
        assert_eq!(l.entries[0].line_of("Kd"), 2);
        assert_eq!(l.entries[0].line_of("Ks"), 1);
        assert_eq!(l.normalized.lines().nth(1), Some("Kd 0.5 0.5 0.5"));
        assert_eq!(l.normalized.lines().nth(2), Some(""));
        let e = |s: &str| lint_mtl(Path::new("a.mtl"), s).unwrap_err().to_string();
        assert!(e("Kd 1 1 1\n").starts_with("a.mtl:1: `Kd` before the first `newmtl`"));
        assert!(e("newmtl a\nKd 1 1\n").starts_with("a.mtl:2:"));
        assert!(e("newmtl a\n\nNs x\n").starts_with("a.mtl:3:"));
        assert!(e("newmtl a\nKd spectral x.rfl\n").starts_with("a.mtl:2:"));
        assert!(e("newmtl a\nillum 2.5\n").starts_with("a.mtl:2:"));
        assert!(e("newmtl a\nNi inf\n").starts_with("a.mtl:2:"));
        assert!(e("newmtl\n").starts_with("a.mtl:1:"));
    }
}
