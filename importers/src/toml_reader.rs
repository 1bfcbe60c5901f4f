//! Typed, span-aware access to a parsed TOML document: every value read here can be traced back
//! to its line and column, so type, range and semantic errors name the place in the file.

use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::error::{ErrorPlace, ImportError, ImportErrorKind, did_you_mean};

/// A TOML value with its byte span.
pub(crate) type Val<'a> = Spanned<DeValue<'a>>;
/// A byte range in the source text.
pub(crate) type Span = Range<usize>;

/// The document being read: file name (for messages), text (for line/column) and base directory
/// (for relative file references).
pub(crate) struct Doc<'a> {
    /// The scene file.
    pub file: &'a Path,
    /// Its text.
    pub src: &'a str,
    /// Directory that relative file names are resolved against.
    pub dir: PathBuf,
}

/// Parses TOML text read from `path`; a syntax error names its line and column.
pub(crate) fn parse_document<'a>(text: &'a str, path: &Path) -> Result<Spanned<DeTable<'a>>, ImportError> {
    DeTable::parse(text).map_err(|e| {
        let place = e.span().map_or_else(|| ErrorPlace::file(path), |s| ErrorPlace::at_offset(path, text, s.start));
        ImportError::new(ImportErrorKind::Syntax, place, format!("TOML syntax error: {}", e.message().trim_end()))
    })
}

impl<'a> Doc<'a> {
    /// The document of `src` read from `file`; relative names resolve against its directory.
    pub fn new(file: &'a Path, src: &'a str) -> Self {
        Self { file, src, dir: file.parent().map(Path::to_path_buf).unwrap_or_default() }
    }
}

impl Doc<'_> {
    /// The line/column place of a span's start.
    pub fn place(&self, span: &Span) -> ErrorPlace {
        ErrorPlace::at_offset(self.file, self.src, span.start)
    }

    /// The 1-based line of a span's start.
    pub fn line(&self, span: &Span) -> usize {
        self.place(span).line.unwrap_or(1)
    }

    /// An error of `kind` at `span`.
    pub fn error(&self, kind: ImportErrorKind, span: &Span, msg: impl Into<String>) -> ImportError {
        ImportError::new(kind, self.place(span), msg)
    }

    /// An [`ImportErrorKind::InvalidValue`] error at `span`.
    pub fn invalid(&self, span: &Span, msg: impl Into<String>) -> ImportError {
        self.error(ImportErrorKind::InvalidValue, span, msg)
    }

    /// Resolves a file name relative to the scene's directory.
    pub fn resolve(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }
}

/// "a string", "an integer", ... for type errors.
pub(crate) fn type_name(v: &DeValue<'_>) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a datetime",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

fn wrong_type(doc: &Doc<'_>, v: &Val<'_>, what: &str, expected: &str) -> ImportError {
    doc.invalid(&v.span(), format!("`{what}` must be {expected}, got {}", type_name(v.get_ref())))
}

/// A number (integer or float) as f64; NaN and infinities are errors.
pub(crate) fn number(doc: &Doc<'_>, v: &Val<'_>, what: &str) -> Result<f64, ImportError> {
    let x = match v.get_ref() {
        DeValue::Integer(i) => i128::from_str_radix(i.as_str(), i.radix()).ok().map(|i| i as f64),
        DeValue::Float(f) => f.as_str().parse::<f64>().ok(),
        _ => return Err(wrong_type(doc, v, what, "a number")),
    };
    match x {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(doc.invalid(&v.span(), format!("`{what}` must be a finite number"))),
    }
}

/// A number that fits f32 (finite, |x| <= f32::MAX).
pub(crate) fn float(doc: &Doc<'_>, v: &Val<'_>, what: &str) -> Result<f32, ImportError> {
    let x = number(doc, v, what)?;
    if x.abs() > f32::MAX as f64 {
        return Err(doc.invalid(&v.span(), format!("`{what}` = {x:e} is out of range (|x| must be <= {:e})", f32::MAX)));
    }
    Ok(x as f32)
}

/// An integer (no fraction, no float syntax) as i128.
pub(crate) fn integer(doc: &Doc<'_>, v: &Val<'_>, what: &str) -> Result<i128, ImportError> {
    match v.get_ref() {
        DeValue::Integer(i) => i128::from_str_radix(i.as_str(), i.radix())
            .map_err(|_| doc.invalid(&v.span(), format!("`{what}` is not a valid integer"))),
        _ => Err(wrong_type(doc, v, what, "an integer")),
    }
}

/// An integer within `range` (inclusive), converted to `T`.
pub(crate) fn int_in<T: TryFrom<i128>>(
    doc: &Doc<'_>,
    v: &Val<'_>,
    what: &str,
    lo: i128,
    hi: i128,
) -> Result<T, ImportError> {
    let i = integer(doc, v, what)?;
    if i < lo || i > hi {
        return Err(doc.invalid(&v.span(), format!("`{what}` must be in {lo}..={hi}, got {i}")));
    }
    T::try_from(i).map_err(|_| doc.invalid(&v.span(), format!("`{what}` is out of range")))
}

/// A string.
pub(crate) fn string<'a>(doc: &Doc<'_>, v: &'a Val<'_>, what: &str) -> Result<&'a str, ImportError> {
    match v.get_ref() {
        DeValue::String(s) => Ok(s.as_ref()),
        _ => Err(wrong_type(doc, v, what, "a string")),
    }
}

/// A boolean.
pub(crate) fn boolean(doc: &Doc<'_>, v: &Val<'_>, what: &str) -> Result<bool, ImportError> {
    match v.get_ref() {
        DeValue::Boolean(b) => Ok(*b),
        _ => Err(wrong_type(doc, v, what, "a boolean (true or false)")),
    }
}

/// An array of exactly `N` f32 numbers.
pub(crate) fn floats<const N: usize>(doc: &Doc<'_>, v: &Val<'_>, what: &str) -> Result<[f32; N], ImportError> {
    let a = match v.get_ref() {
        DeValue::Array(a) => a,
        _ => return Err(wrong_type(doc, v, what, &format!("an array of {N} numbers"))),
    };
    if a.len() != N {
        return Err(doc.invalid(&v.span(), format!("`{what}` must have {N} numbers, got {}", a.len())));
    }
    let mut out = [0.0; N];
    for (i, x) in a.iter().enumerate() {
        out[i] = float(doc, x, &format!("{what}[{i}]"))?;
    }
    Ok(out)
}

/// A list of f32 numbers of any length up to `max`.
pub(crate) fn float_list(doc: &Doc<'_>, v: &Val<'_>, what: &str, max: usize) -> Result<Vec<f32>, ImportError> {
    let a = match v.get_ref() {
        DeValue::Array(a) => a,
        _ => return Err(wrong_type(doc, v, what, "an array of numbers")),
    };
    if a.len() > max {
        return Err(doc.error(
            ImportErrorKind::TooLarge,
            &v.span(),
            format!("`{what}` has {} entries, more than the limit of {max}", a.len()),
        ));
    }
    a.iter().enumerate().map(|(i, x)| float(doc, x, &format!("{what}[{i}]"))).collect()
}

/// A table of a TOML document, with the path used in messages (`camera`, `shape[2]`, ...).
#[derive(Clone)]
pub(crate) struct Tbl<'a> {
    /// The document.
    pub doc: &'a Doc<'a>,
    /// The table's entries.
    pub t: &'a DeTable<'a>,
    /// Span of the table (its header, or the inline table).
    pub span: Span,
    /// Dotted path for messages.
    pub path: String,
}

impl<'a> Tbl<'a> {
    /// The top-level table of a parsed document.
    pub fn root(doc: &'a Doc<'a>, root: &'a Spanned<DeTable<'a>>) -> Self {
        Self { doc, t: root.get_ref(), span: root.span(), path: String::new() }
    }

    /// Views `v` as a table named `path`; other types are an error.
    pub fn of(doc: &'a Doc<'a>, v: &'a Val<'a>, path: impl Into<String>) -> Result<Self, ImportError> {
        let path = path.into();
        match v.get_ref() {
            DeValue::Table(t) => Ok(Self { doc, t, span: v.span(), path }),
            _ => Err(wrong_type(doc, v, &path, "a table")),
        }
    }

    /// `path.key` for messages.
    pub fn key_path(&self, key: &str) -> String {
        if self.path.is_empty() { key.to_owned() } else { format!("{}.{key}", self.path) }
    }

    /// Entries sorted by their position in the file.
    pub fn entries(&self) -> Vec<(&'a Spanned<std::borrow::Cow<'a, str>>, &'a Val<'a>)> {
        let mut e: Vec<_> = self.t.iter().collect();
        e.sort_by_key(|(k, _)| k.span().start);
        e
    }

    /// Errors on the first key (in file order) not in `allowed`, listing the allowed keys and
    /// suggesting the closest one.
    pub fn check_keys(&self, allowed: &[&str]) -> Result<(), ImportError> {
        for (k, _) in self.entries() {
            let key: &str = k.get_ref();
            if !allowed.contains(&key) {
                let within =
                    if self.path.is_empty() { "at the top level".to_owned() } else { format!("in `{}`", self.path) };
                return Err(self.doc.error(
                    ImportErrorKind::UnknownKey,
                    &k.span(),
                    format!(
                        "unknown key `{key}` {within}; expected one of: {}{}",
                        allowed.join(", "),
                        did_you_mean(key, allowed.iter().copied())
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The value of `key`, if present.
    pub fn get(&self, key: &str) -> Option<&'a Val<'a>> {
        self.t.get(key)
    }

    /// Whether `key` is present.
    pub fn has(&self, key: &str) -> bool {
        self.t.contains_key(key)
    }

    /// Span of `key` itself when present, else of the table.
    pub fn key_span(&self, key: &str) -> Span {
        self.t.get_key_value(key).map_or(self.span.clone(), |(k, _)| k.span())
    }

    /// The "missing key" error, at the table.
    pub fn missing(&self, key: &str) -> ImportError {
        let at = if self.path.is_empty() { String::new() } else { format!(" in `{}`", self.path) };
        self.doc.invalid(&self.span, format!("missing key `{key}`{at}"))
    }

    /// The value of a required key.
    pub fn req(&self, key: &str) -> Result<&'a Val<'a>, ImportError> {
        self.get(key).ok_or_else(|| self.missing(key))
    }

    /// An optional f32.
    pub fn opt_f32(&self, key: &str) -> Result<Option<f32>, ImportError> {
        self.get(key).map(|v| float(self.doc, v, &self.key_path(key))).transpose()
    }

    /// An optional f32 that must satisfy `ok` (described by `rule`, e.g. "> 0").
    pub fn opt_f32_where(&self, key: &str, rule: &str, ok: impl Fn(f32) -> bool) -> Result<Option<f32>, ImportError> {
        match self.get(key) {
            None => Ok(None),
            Some(v) => {
                let x = float(self.doc, v, &self.key_path(key))?;
                if !ok(x) {
                    return Err(self
                        .doc
                        .invalid(&v.span(), format!("`{}` must be {rule}, got {x}", self.key_path(key))));
                }
                Ok(Some(x))
            }
        }
    }

    /// An optional `[x, y, z]`.
    pub fn opt_vec3(&self, key: &str) -> Result<Option<Vec3>, ImportError> {
        self.get(key).map(|v| floats::<3>(self.doc, v, &self.key_path(key)).map(Vec3::from)).transpose()
    }

    /// An optional `[x, y]`.
    pub fn opt_vec2(&self, key: &str) -> Result<Option<Vec2>, ImportError> {
        self.get(key).map(|v| floats::<2>(self.doc, v, &self.key_path(key)).map(Vec2::from)).transpose()
    }

    /// An optional length triple in scene units, converted with `unit` (metres per unit); an
    /// overflow after conversion is an error.
    pub fn opt_point(&self, key: &str, unit: f32) -> Result<Option<Vec3>, ImportError> {
        match self.opt_vec3(key)? {
            None => Ok(None),
            Some(p) => {
                let q = p * unit;
                if !q.is_finite() {
                    let span = self.get(key).map_or(self.span.clone(), |v| v.span());
                    return Err(self.doc.invalid(
                        &span,
                        format!("`{}` overflows when converted to metres (x {unit})", self.key_path(key)),
                    ));
                }
                Ok(Some(q))
            }
        }
    }

    /// An optional direction: `[x, y, z]`, not zero.
    pub fn opt_dir(&self, key: &str) -> Result<Option<Vec3>, ImportError> {
        match self.opt_vec3(key)? {
            Some(d) if !(d.length_squared() > 0.0 && d.length_squared().is_finite()) => {
                let span = self.get(key).map_or(self.span.clone(), |v| v.span());
                let rule = "a non-zero vector of moderate length";
                Err(self.doc.invalid(&span, format!("`{}` must be {rule}, got {d}", self.key_path(key))))
            }
            d => Ok(d),
        }
    }

    /// An optional string.
    pub fn opt_str(&self, key: &str) -> Result<Option<&'a str>, ImportError> {
        self.get(key).map(|v| string(self.doc, v, &self.key_path(key))).transpose()
    }

    /// An optional boolean.
    pub fn opt_bool(&self, key: &str) -> Result<Option<bool>, ImportError> {
        self.get(key).map(|v| boolean(self.doc, v, &self.key_path(key))).transpose()
    }

    /// An optional integer within `lo..=hi`.
    pub fn opt_int<T: TryFrom<i128>>(&self, key: &str, lo: i128, hi: i128) -> Result<Option<T>, ImportError> {
        self.get(key).map(|v| int_in(self.doc, v, &self.key_path(key), lo, hi)).transpose()
    }

    /// An optional sub-table.
    pub fn opt_table(&self, key: &str) -> Result<Option<Tbl<'a>>, ImportError> {
        self.get(key).map(|v| Tbl::of(self.doc, v, self.key_path(key))).transpose()
    }

    /// A required string naming one of `choices` (case-sensitive), with a suggestion on error.
    pub fn choice(&self, key: &str, choices: &[&str]) -> Result<Option<(&'a str, Span)>, ImportError> {
        let Some(v) = self.get(key) else { return Ok(None) };
        let s = string(self.doc, v, &self.key_path(key))?;
        if !choices.contains(&s) {
            return Err(self.doc.invalid(
                &v.span(),
                format!(
                    "`{}` = \"{s}\" is not one of: {}{}",
                    self.key_path(key),
                    choices.join(", "),
                    did_you_mean(s, choices.iter().copied())
                ),
            ));
        }
        Ok(Some((s, v.span())))
    }

    /// Errors when more than one of `keys` is present ("give only one of ...").
    pub fn exclusive(&self, keys: &[&str]) -> Result<(), ImportError> {
        let mut present: Vec<&str> = keys.iter().copied().filter(|k| self.has(k)).collect();
        present.sort_by_key(|k| self.key_span(k).start);
        if present.len() > 1 {
            let last = present[present.len() - 1];
            return Err(self.doc.invalid(
                &self.key_span(last),
                format!(
                    "`{}`: give only one of {}",
                    self.path,
                    present.iter().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(", ")
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with<R>(src: &str, f: impl FnOnce(&Tbl<'_>) -> R) -> R {
        let root = DeTable::parse(src).unwrap();
        let doc = Doc { file: Path::new("t.toml"), src, dir: PathBuf::new() };
        let t = Tbl { doc: &doc, t: root.get_ref(), span: root.span(), path: "top".into() };
        f(&t)
    }

    #[test]
    fn numbers() {
        with("a = 0x10\nb = -3\nc = 1.5e3\nd = 1e39\ne = nan\nf = -inf\ng = 1_000\nh = \"1\"\n", |t| {
            assert_eq!(t.opt_f32("a").unwrap(), Some(16.0));
            assert_eq!(t.opt_f32("b").unwrap(), Some(-3.0));
            assert_eq!(t.opt_f32("c").unwrap(), Some(1500.0));
            assert_eq!(t.opt_f32("g").unwrap(), Some(1000.0));
            let e = t.opt_f32("d").unwrap_err().to_string();
            assert!(e.starts_with("t.toml:4:5: `top.d` = 1e39 is out of range"), "{e}");
            assert!(t.opt_f32("e").unwrap_err().to_string().contains("finite"));
            assert!(t.opt_f32("f").unwrap_err().to_string().contains("t.toml:6:5"));
            assert!(t.opt_f32("h").unwrap_err().to_string().contains("must be a number, got a string"));
            assert_eq!(t.opt_f32("missing").unwrap(), None);
            assert_eq!(t.opt_int::<u32>("a", 0, 100).unwrap(), Some(16));
            assert!(t.opt_int::<u32>("b", 0, 100).unwrap_err().to_string().contains("0..=100"));
            assert!(t.opt_int::<u32>("c", 0, 100).unwrap_err().to_string().contains("integer"));
        });
    }

    #[test]
    fn keys_and_tables() {
        with("pos = [1, 2, 3]\nsub = { x = 1 }\nflag = true\n", |t| {
            assert_eq!(t.opt_vec3("pos").unwrap(), Some(Vec3::new(1.0, 2.0, 3.0)));
            assert!(t.opt_vec2("pos").unwrap_err().to_string().contains("must have 2 numbers, got 3"));
            assert_eq!(t.opt_point("pos", 0.01).unwrap(), Some(Vec3::new(0.01, 0.02, 0.03)));
            assert!(t.opt_point("pos", f32::MAX).unwrap_err().to_string().contains("overflows"));
            assert_eq!(t.opt_bool("flag").unwrap(), Some(true));
            let sub = t.opt_table("sub").unwrap().unwrap();
            assert_eq!(sub.path, "top.sub");
            assert!(sub.check_keys(&["x"]).is_ok());
            let e = sub.check_keys(&["y", "xx"]).unwrap_err();
            assert_eq!(e.kind, ImportErrorKind::UnknownKey);
            assert!(
                e.to_string().starts_with("t.toml:2:9: unknown key `x` in `top.sub`; expected one of: y, xx"),
                "{e}"
            );
            assert!(t.missing("q").to_string().contains("missing key `q` in `top`"));
            assert!(t.exclusive(&["pos", "flag"]).unwrap_err().to_string().starts_with("t.toml:3:1"));
        });
    }
}
