//! Docs that restate a table of the code are generated from it: each generated section of a
//! document sits between `<!-- generated: NAME -->` and `<!-- end generated: NAME -->`, and must
//! equal what the table gives now. `QUASAR_BLESS=1 cargo test --release --test docs_tables`
//! rewrites the sections from the tables instead of failing.

use std::path::Path;

/// The generated sections: (document, section name, its text from the code's table).
fn sections() -> Vec<(&'static str, &'static str, String)> {
    vec![
        ("README.md", "methods", quasar::tools::doc_tables::methods_table()),
        ("README.md", "output channels", quasar::tools::doc_tables::outputs_table()),
        ("README.md", "header entries", quasar::tools::doc_tables::header_table()),
        ("docs/scene-format.md", "render keys", quasar::tools::doc_tables::render_keys_table()),
    ]
}

#[test]
fn generated_doc_sections_match_their_tables() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bless = std::env::var_os("QUASAR_BLESS").is_some();
    let mut stale = Vec::new();
    for (doc, name, table) in sections() {
        let path = root.join(doc);
        let text = std::fs::read_to_string(&path).unwrap();
        let (open, close) = (format!("<!-- generated: {name} -->\n"), format!("<!-- end generated: {name} -->"));
        let start = text.find(&open).unwrap_or_else(|| panic!("{doc} has no section '{open}'")) + open.len();
        let end = start + text[start..].find(&close).unwrap_or_else(|| panic!("{doc}: '{open}' is not closed"));
        if text[start..end] != table {
            if bless {
                std::fs::write(&path, format!("{}{table}{}", &text[..start], &text[end..])).unwrap();
            } else {
                stale.push(format!("{doc}: section '{name}'"));
            }
        }
    }
    assert!(
        stale.is_empty(),
        "generated sections differ from their tables (QUASAR_BLESS=1 cargo test --release --test docs_tables rewrites them): {stale:?}"
    );
}

/// `quasar render --help` lists the names `--aov` takes, which are the output table's.
#[test]
fn the_help_lists_the_aov_names_of_the_output_table() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_quasar")).args(["render", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&o.stdout).split_whitespace().collect::<Vec<_>>().join(" ");
    let names = quasar::film::outputs::aov_names().join(", ");
    assert!(help.contains(&format!("scene's `aovs`): {names} (Cryptomatte)")), "{help}");
}

/// The docs name the checkpoint format the code writes (they said `QSRCKPT4` for `QSRCKPT5`).
#[test]
fn the_docs_name_the_current_checkpoint_format() {
    let magic = std::str::from_utf8(quasar::render::checkpoint::MAGIC).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for doc in ["docs/architecture.md", "src/render/checkpoint.rs"] {
        let text = std::fs::read_to_string(root.join(doc)).unwrap();
        for (i, _) in text.match_indices("QSRCKPT") {
            assert_eq!(&text[i..i + 8], magic, "{doc} names another checkpoint format than {magic}");
        }
        assert!(text.contains(magic), "{doc} does not name {magic}");
    }
}
