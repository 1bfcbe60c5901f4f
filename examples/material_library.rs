//! Regenerates the material library: `cargo run --release --example material_library`
//! writes every `materials/library/*.toml` from `quasar::tools::material_library` and checks that each
//! loads (validation, energy) before writing it.

use std::path::Path;

fn main() -> anyhow::Result<()> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("materials/library");
    std::fs::create_dir_all(&dir)?;
    for e in quasar::tools::material_library::library() {
        quasar::materials::TabulatedTable::new(e.spec.clone()).map_err(|err| anyhow::anyhow!("{}: {err}", e.file))?;
        let path = dir.join(e.file);
        let text = quasar::tools::material_library::entry_text(&e);
        std::fs::write(&path, &text)?;
        println!("wrote {} ({} bytes)", path.display(), text.len());
    }
    Ok(())
}
