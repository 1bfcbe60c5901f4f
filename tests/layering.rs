//! The architecture as a test (docs/architecture.md): in every crate of the workspace the
//! modules' `use` graph has no cycle (at file granularity: a file is a node, every `use` or
//! qualified path into another file of the same crate is an edge); the renderer's top-level
//! folders only point down the layer order; no source file is longer than 500 lines.
//!
//! `cargo test --release --test layering -- --nocapture` prints each crate's module count, edge
//! count and the layer edges found.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The renderer's layers, lowest first: a module may use its own layer and those below.
const LAYERS: [&str; 6] = ["core", "film", "integrator", "output", "render", "tools"];

/// A module path: its segments below the crate root.
type ModulePath = Vec<String>;
/// Module -> the modules it uses.
type Graph = BTreeMap<ModulePath, BTreeSet<ModulePath>>;

/// Longest source file allowed, in lines.
const MAX_LINES: usize = 500;

/// One crate's modules: module path (segments below the crate root) -> file.
struct Crate {
    name: &'static str,
    modules: BTreeMap<Vec<String>, PathBuf>,
}

impl Crate {
    /// The modules of the crate rooted at `root` (`lib.rs` or `main.rs`), from the file layout:
    /// `a/mod.rs` and `a.rs` are module `a`, `a/b.rs` is `a::b`. `skip` lists top-level folders
    /// that belong to another crate (the binary's `cli/`).
    fn scan(name: &'static str, root: &Path, skip: &[&str], only: Option<&[&str]>) -> Self {
        let dir = root.parent().unwrap();
        let mut modules = BTreeMap::new();
        modules.insert(Vec::new(), root.to_path_buf());
        let mut stack = vec![dir.to_path_buf()];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let p = e.unwrap().path();
                let rel: Vec<String> = p
                    .strip_prefix(dir)
                    .unwrap()
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                if skip.contains(&rel[0].as_str()) || only.is_some_and(|o| !o.contains(&rel[0].as_str())) {
                    continue;
                }
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "rs") && p != root {
                    let mut m = rel.clone();
                    let last = m.pop().unwrap();
                    let stem = last.trim_end_matches(".rs");
                    if m.is_empty() && (stem == "lib" || stem == "main") {
                        continue;
                    }
                    if stem != "mod" {
                        m.push(stem.to_string());
                    }
                    modules.insert(m, p);
                }
            }
        }
        // modules declared `#[cfg(test)] mod name;` are unit tests, which may use anything
        let test_modules: Vec<Vec<String>> = modules
            .iter()
            .flat_map(|(m, file)| {
                let text = std::fs::read_to_string(file).unwrap();
                let tokens = tokenize(&strip_comments_and_strings(&text));
                let mut out = Vec::new();
                for (i, t) in tokens.iter().enumerate() {
                    let cfg_test = ["#", "[", "cfg", "(", "test", ")", "]"]
                        .iter()
                        .enumerate()
                        .all(|(k, s)| tokens.get(i + k).is_some_and(|x| x == s));
                    if t == "#"
                        && cfg_test
                        && tokens.get(i + 7).is_some_and(|x| x == "mod")
                        && tokens.get(i + 9).is_some_and(|x| x == ";")
                    {
                        let mut child = m.clone();
                        child.push(tokens[i + 8].clone());
                        out.push(child);
                    }
                }
                out
            })
            .collect();
        modules.retain(|m, _| !test_modules.iter().any(|t| m.starts_with(t)));
        Self { name, modules }
    }

    /// The module of `segments` (longest prefix that is a module of the crate).
    fn resolve(&self, segments: &[String]) -> Vec<String> {
        (0..=segments.len()).rev().map(|n| segments[..n].to_vec()).find(|m| self.modules.contains_key(m)).unwrap()
    }

    /// Edges module -> modules it uses (self-edges dropped). A path is resolved as rustc
    /// does: from the crate root (`crate::`), this module (`self::`), its ancestors (`super::`) or,
    /// when its first segment names a submodule, from this module.
    fn edges(&self) -> Graph {
        let mut out = BTreeMap::new();
        for (module, file) in &self.modules {
            let text = strip_tests(&strip_comments_and_strings(&std::fs::read_to_string(file).unwrap()));
            let mut targets = BTreeSet::new();
            for path in module_paths(&text) {
                let mut abs: Vec<String> = Vec::new();
                let mut rest = path.as_slice();
                match rest.first().map(String::as_str) {
                    Some("crate") => rest = &rest[1..],
                    Some("self") => {
                        abs = module.clone();
                        rest = &rest[1..];
                    }
                    Some("super") => {
                        abs = module.clone();
                        while rest.first().is_some_and(|s| s == "super") {
                            abs.pop();
                            rest = &rest[1..];
                        }
                    }
                    Some(first) => {
                        let mut child = module.clone();
                        child.push(first.to_string());
                        if !self.modules.contains_key(&child) {
                            continue; // another crate, a type or a variable
                        }
                        abs = module.clone();
                    }
                    None => continue,
                }
                abs.extend(rest.iter().cloned());
                let target = self.resolve(&abs);
                if &target != module {
                    targets.insert(target);
                }
            }
            out.insert(module.clone(), targets);
        }
        out
    }

    /// For every module with submodules, the graph of its direct submodules (each standing for
    /// its whole subtree): A -> B when a file under A uses one under B. Uses between a module
    /// and its own submodules (a `mod.rs` re-exporting them, a submodule using its parent's
    /// items) stay inside one node of the level above.
    fn sibling_graphs(&self) -> BTreeMap<ModulePath, Graph> {
        let mut out: BTreeMap<ModulePath, Graph> = BTreeMap::new();
        for m in self.modules.keys() {
            if let Some((_, parent)) = m.split_last() {
                out.entry(parent.to_vec()).or_default().entry(m.clone()).or_default();
            }
        }
        for (from, tos) in self.edges() {
            for to in tos {
                let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
                if common < from.len() && common < to.len() {
                    let parent = from[..common].to_vec();
                    let graph = out.entry(parent).or_default();
                    graph.entry(from[..=common].to_vec()).or_default().insert(to[..=common].to_vec());
                }
            }
        }
        out
    }
}

/// `text` without comments, string and char literals (their contents could look like paths).
fn strip_comments_and_strings(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if c == 'r'
            && (next == Some('#') || next == Some('"'))
            && !b.get(i.wrapping_sub(1)).is_some_and(|p| p.is_alphanumeric() || *p == '_')
        {
            // raw string r#"..."#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|h| b.get(j + 1 + h) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                i += if b[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' {
            // a char literal ('x', '\n', '\u{..}') or a lifetime ('a)
            if next == Some('\\') {
                let mut j = i + 2;
                while j < b.len() && b[j] != '\'' {
                    j += 1;
                }
                i = j + 1;
            } else if b.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                out.push(c);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// `text` without its `#[cfg(test)]` items (unit tests may use anything).
fn strip_tests(text: &str) -> String {
    let mut out = text.to_string();
    while let Some(at) = out.find("#[cfg(test)]") {
        let Some(open) = out[at..].find(['{', ';']).map(|o| at + o) else { break };
        let mut end = open + 1;
        if out.as_bytes()[open] == b'{' {
            let mut depth = 0;
            for (k, ch) in out[open..].char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            end = open + k + 1;
                            break;
                        }
                    }
                    _ => {}
                }
            }
        }
        out.replace_range(at..end, "");
    }
    out
}

/// Every path in `text` that could name a module of this crate: `use` trees expanded
/// (`use super::{a::B, c}` gives `super::a::B` and `super::c`) and qualified paths in code
/// (`a::b::f()`, not preceded by `::`).
fn module_paths(text: &str) -> Vec<Vec<String>> {
    let tokens = tokenize(text);
    let mut out = Vec::new();
    let mut i = 0;
    while i < tokens.len() {
        if tokens[i] == "use" {
            let end = (i..tokens.len()).find(|&j| tokens[j] == ";").unwrap_or(tokens.len());
            expand_use(&tokens[i + 1..end], &mut Vec::new(), &mut out);
            i = end;
        } else if is_ident(&tokens[i])
            && tokens.get(i + 1).is_some_and(|t| t == "::")
            && (i == 0 || tokens[i - 1] != "::")
        {
            let mut path = vec![tokens[i].clone()];
            let mut j = i + 1;
            while tokens.get(j).is_some_and(|t| t == "::") && tokens.get(j + 1).is_some_and(|t| is_ident(t)) {
                path.push(tokens[j + 1].clone());
                j += 2;
            }
            out.push(path);
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

fn is_ident(t: &str) -> bool {
    t.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
}

/// Identifiers, `::` and single punctuation characters.
fn tokenize(text: &str) -> Vec<String> {
    let c: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        if c[i].is_alphanumeric() || c[i] == '_' {
            let s = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(c[s..i].iter().collect());
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push("::".into());
            i += 2;
        } else {
            if !c[i].is_whitespace() {
                out.push(c[i].to_string());
            }
            i += 1;
        }
    }
    out
}

/// Expands one use tree (`a::b::{c, d::e as f, *}`) under `prefix` into `out`.
fn expand_use(tokens: &[String], prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    let depth0 = prefix.len();
    let mut i = 0;
    while i < tokens.len() {
        let t = tokens[i].as_str();
        match t {
            "::" => i += 1,
            "{" => {
                // split the group at top-level commas
                let mut depth = 0;
                let mut start = i + 1;
                let mut j = i;
                while j < tokens.len() {
                    match tokens[j].as_str() {
                        "{" => depth += 1,
                        "}" => {
                            depth -= 1;
                            if depth == 0 {
                                expand_use(&tokens[start..j], prefix, out);
                                break;
                            }
                        }
                        "," if depth == 1 => {
                            expand_use(&tokens[start..j], prefix, out);
                            start = j + 1;
                        }
                        _ => {}
                    }
                    j += 1;
                }
                prefix.truncate(depth0);
                return;
            }
            "as" | "*" => break,
            _ if is_ident(t) => {
                prefix.push(t.to_string());
                i += 1;
            }
            _ => i += 1,
        }
    }
    if prefix.len() > depth0 {
        out.push(prefix.clone());
    }
    prefix.truncate(depth0);
}

/// Strongly connected components of more than one node (Tarjan).
fn cycles(edges: &Graph) -> Vec<Vec<ModulePath>> {
    struct T<'a> {
        edges: &'a Graph,
        index: BTreeMap<&'a Vec<String>, usize>,
        low: BTreeMap<&'a Vec<String>, usize>,
        stack: Vec<&'a Vec<String>>,
        on: BTreeSet<&'a Vec<String>>,
        out: Vec<Vec<Vec<String>>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a Vec<String>) {
        let n = t.index.len();
        t.index.insert(v, n);
        t.low.insert(v, n);
        t.stack.push(v);
        t.on.insert(v);
        for w in &t.edges[v] {
            if !t.index.contains_key(w) {
                visit(t, w);
                let lw = t.low[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if t.on.contains(w) {
                let iw = t.index[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                t.out.push(comp);
            }
        }
    }
    let mut t = T {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in edges.keys() {
        if !t.index.contains_key(v) {
            visit(&mut t, v);
        }
    }
    t.out
}

fn crates() -> Vec<Crate> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    vec![
        Crate::scan("quasar (lib)", &root.join("src/lib.rs"), &["cli", "main.rs"], None),
        Crate::scan("quasar (bin)", &root.join("src/main.rs"), &[], Some(&["cli"])),
        Crate::scan("quasar-importers", &root.join("importers/src/lib.rs"), &[], None),
        Crate::scan("quasar-materials", &root.join("materials/src/lib.rs"), &[], None),
    ]
}

fn show(m: &[String]) -> String {
    if m.is_empty() { "crate".into() } else { m.join("::") }
}

#[test]
fn no_module_cycle_in_any_crate() {
    let mut problems = Vec::new();
    for c in crates() {
        let edges = c.edges();
        let n_edges: usize = edges.values().map(BTreeSet::len).sum();
        println!("{}: {} modules, {} use edges", c.name, c.modules.len(), n_edges);
        for (parent, graph) in c.sibling_graphs() {
            for comp in cycles(&graph) {
                let inner: Vec<String> = comp
                    .iter()
                    .flat_map(|a| {
                        graph[a].iter().filter(|b| comp.contains(b)).map(move |b| format!("{} -> {}", show(a), show(b)))
                    })
                    .collect();
                problems.push(format!(
                    "{}: cycle among the submodules of {}: {}",
                    c.name,
                    show(&parent),
                    inner.join("; ")
                ));
            }
        }
    }
    assert!(problems.is_empty(), "module cycles:\n{}", problems.join("\n"));
}

#[test]
fn layers_point_down() {
    let c = crates().remove(0);
    let graph = c.sibling_graphs().remove(&Vec::new()).unwrap();
    let rank = |m: &[String]| LAYERS.iter().position(|l| *l == m[0]);
    let mut problems = Vec::new();
    let mut seen = Vec::new();
    for (from, tos) in &graph {
        for to in tos {
            let (Some(a), Some(b)) = (rank(from), rank(to)) else {
                problems.push(format!(
                    "{} -> {}: a top-level module outside the layers {LAYERS:?}",
                    show(from),
                    show(to)
                ));
                continue;
            };
            seen.push(format!("{} -> {}", LAYERS[a], LAYERS[b]));
            if b > a {
                problems.push(format!("{} uses {}, a higher layer", LAYERS[a], LAYERS[b]));
            }
        }
    }
    println!("layer edges: {}", seen.join(", "));
    assert!(problems.is_empty(), "upward edges:\n{}", problems.join("\n"));
}

#[test]
fn no_source_file_over_the_limit() {
    let mut long = Vec::new();
    for c in crates() {
        for file in c.modules.values() {
            let n = std::fs::read_to_string(file).unwrap().lines().count();
            if n > MAX_LINES {
                long.push(format!("{} ({n} lines)", file.display()));
            }
        }
    }
    assert!(long.is_empty(), "files over {MAX_LINES} lines (one concept per file): {long:?}");
}

#[test]
fn the_path_scanner_sees_use_trees_and_qualified_paths() {
    let text = "use super::{a::B, c::{self, D as E}};\nuse crate::x::*;\nfn f() { crate::y::z(); let s = \"crate::no\"; } // crate::no\n";
    let paths = module_paths(&strip_comments_and_strings(text));
    let shown: Vec<String> = paths.iter().map(|p| p.join("::")).collect();
    assert_eq!(shown, ["super::a::B", "super::c::self", "super::c::D", "crate::x", "crate::y::z"]);
    let mut e = BTreeMap::new();
    let (a, b) = (vec!["a".to_string()], vec!["b".to_string()]);
    e.insert(a.clone(), BTreeSet::from([b.clone()]));
    e.insert(b.clone(), BTreeSet::from([a.clone()]));
    assert_eq!(cycles(&e).len(), 1);
    e.get_mut(&b).unwrap().clear();
    assert!(cycles(&e).is_empty());
}
