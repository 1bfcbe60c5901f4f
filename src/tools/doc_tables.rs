//! The documentation's copies of the code's tables, generated from them (tests/docs_tables.rs
//! checks each generated section of the docs against these): the README's methods
//! ([`METHODS`] and `auto`), output channels ([`OUTPUTS`]) and header entries ([`HEADER`]), and docs/scene-format.md's `[render]` keys
//! (the importer's [`RENDER_KEYS`] and every method parameter of the method table).

use quasar_importers::toml_scene::RENDER_KEYS;

use crate::film::outputs::OUTPUTS;
use crate::integrator::method::{METHODS, all_params, users_of};
use crate::render::header::{HEADER, HeaderMerge};

/// The README's method table: one line per row of [`METHODS`] with its parameters' flags, and
/// `auto`'s choice with the pilot's constants.
pub fn methods_table() -> String {
    use crate::render::pilot::{BIDIR_MARGIN, PILOT_ITERATIONS, PILOT_SPP};
    let mut s = String::from("| `--method` | what it is | its parameters |\n|---|---|---|\n");
    for m in METHODS {
        let flags: Vec<String> = m.params.iter().map(|p| format!("`--{}`", p.flag)).collect();
        s += &format!("| `{}` | {} | {} |\n", m.name, m.summary, flags.join(", "));
    }
    s += &format!(
        "| `auto` (default) | scene analysis (`quasar info`): `pt` for scenes without narrow or specular surfaces; otherwise short pilots of `pt` ({PILOT_SPP} spp) and `quasi` ({PILOT_ITERATIONS} iterations), each scored by its relative error times the rays it traced, and the render continues the winner's pilot (`quasi` only if it is {BIDIR_MARGIN}x better) | those of the method it runs |\n"
    );
    s
}

/// The README's channel table: one line per row of [`OUTPUTS`].
pub fn outputs_table() -> String {
    let mut s = String::from("| channel | content |\n|---|---|\n");
    for g in OUTPUTS {
        s += &format!("| {} | {} |\n", g.pattern(), g.doc);
    }
    s
}

/// The README's table of header entries: one line per row of [`HEADER`].
pub fn header_table() -> String {
    let mut s = String::from("| key | `quasar merge` | content |\n|---|---|---|\n");
    for h in HEADER {
        let merge = match h.merge {
            HeaderMerge::Agree => "must agree",
            HeaderMerge::Sum => "summed",
            HeaderMerge::AnyTrue => "true if any is",
            HeaderMerge::Recomputed => "recomputed",
            HeaderMerge::Merged => "`merged`",
            HeaderMerge::Dropped => "replaced",
            HeaderMerge::First => "the first image's",
        };
        s += &format!("| `{}` | {merge} | {} |\n", h.key, h.doc);
    }
    s
}

/// docs/scene-format.md's `[render]` table: the importer's own keys, then every method
/// parameter with the methods that read it, its range and its default.
pub fn render_keys_table() -> String {
    let mut s = String::from("| key | value | default |\n|---|---|---|\n");
    for k in RENDER_KEYS {
        s += &format!("| `{}` | {} | {} |\n", k.key, k.value, k.default);
    }
    for p in all_params() {
        let users: Vec<String> = users_of(p.key).iter().map(|m| format!("`{m}`")).collect();
        s += &format!("| `{}` | {}: {}, {} | {} |\n", p.key, users.join(", "), p.doc, p.range(), p.default);
    }
    s
}
