//! Value parsers of the command line.

/// Parses `--units`: a unit name of the TOML `units` key or a positive factor in metres.
pub fn parse_units(s: &str) -> Result<f32, String> {
    if let Some((_, m)) = quasar_importers::toml_scene::UNITS.iter().find(|(n, _)| *n == s) {
        return Ok(*m);
    }
    match s.parse::<f32>() {
        Ok(f) if f.is_finite() && f > 0.0 => Ok(f),
        _ => Err(format!("expected m, cm, mm, in, ft or a positive number of metres, got {s:?}")),
    }
}

/// Parses `--masking`.
pub fn parse_masking(s: &str) -> Result<quasar_materials::Masking, String> {
    quasar_materials::Masking::from_name(s)
        .ok_or_else(|| format!("expected one of {}, got {s:?}", quasar_materials::Masking::NAMES.join(", ")))
}

/// Parses `K/N` for `--shard`.
pub fn parse_shard(s: &str) -> Result<(u32, u32), String> {
    let (k, n) = s.split_once('/').ok_or("expected K/N, e.g. 0/4")?;
    let (k, n): (u32, u32) =
        (k.trim().parse().map_err(|_| "K is not a number")?, n.trim().parse().map_err(|_| "N is not a number")?);
    if n == 0 || k >= n {
        return Err(format!("{k}/{n}: need 0 <= K < N"));
    }
    Ok((k, n))
}

/// True when both paths name the same existing file.
pub fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
