//! The OBJ statements quasar does not use: which are skipped silently (grouping, smoothing) and
//! the warnings about the others (free-form geometry, display attributes, unknown keywords), so
//! that a line like `hello world` is not accepted without a word.

use std::path::Path;

/// OBJ keywords that are read (by the check and `tobj`) or deliberately ignored without a word:
/// grouping, smoothing and merging groups, level of detail.
pub(crate) const QUIET_KEYWORDS: [&str; 6] = ["o", "g", "s", "mg", "lod", "vp"];

/// The warnings for the `ignored` statements (line, keyword) of an OBJ file: one per keyword, with its count and first
/// line (``file:line: statement `hello` ignored (not an OBJ keyword; 3 such statements, the
/// first here)``).
pub(crate) fn ignored_warnings(file: &Path, ignored: &[(usize, String)]) -> Vec<String> {
    let mut seen: Vec<(&str, usize, usize)> = Vec::new();
    for (line, kw) in ignored {
        match seen.iter_mut().find(|(k, _, _)| k == kw) {
            Some(e) => e.2 += 1,
            None => seen.push((kw, *line, 1)),
        }
    }
    seen.into_iter()
        .map(|(kw, line, n)| {
            let why = if SPEC_UNRENDERED.contains(&kw) {
                "free-form geometry, points, lines and display attributes are not rendered"
            } else {
                "not an OBJ keyword"
            };
            let count = if n == 1 { String::new() } else { format!("; {n} such statements, the first here") };
            format!("{}:{line}: statement `{kw}` ignored ({why}{count})", file.display())
        })
        .collect()
}

/// Keywords of the OBJ specification that quasar reads past: free-form geometry and its
/// attributes, points and lines, display and render attributes.
const SPEC_UNRENDERED: [&str; 25] = [
    "p",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "bevel",
    "c_interp",
    "d_interp",
    "usemap",
    "maplib",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "call",
];
