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

/// `--isa`: an instruction set of the render kernels, or None for `auto`.
#[derive(Clone, Copy, Debug)]
pub struct IsaArg(pub Option<quasar::core::isa::Isa>);

/// Parses `--isa` (`auto`, `baseline`, `x86-64-v3`; one this CPU lacks is refused).
pub fn parse_isa(s: &str) -> Result<IsaArg, String> {
    quasar::core::isa::Isa::from_name(s).map(IsaArg)
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

/// Most worker threads per core `--threads` accepts: beyond a few per core threads only add
/// scheduling overhead (2,000 threads on 2 cores ran 300x slower) and each needs its own stack.
pub const MAX_THREADS_PER_CORE: usize = 4;

/// Parses `--threads`: 0 means all cores (the default); more than [`MAX_THREADS_PER_CORE`] per
/// core is refused with the limit.
pub fn parse_threads(s: &str) -> Result<usize, String> {
    let n: usize = s.trim().parse().map_err(|_| format!("expected a number of threads, got {s:?}"))?;
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    if n == 0 {
        return Ok(cores);
    }
    let max = MAX_THREADS_PER_CORE * cores;
    if n > max {
        return Err(format!(
            "{n} threads: at most {max} ({MAX_THREADS_PER_CORE} per core, {cores} cores here); 0 means all cores"
        ));
    }
    Ok(n)
}

/// Parses `--exposure`: `auto` or a finite number of stops.
pub fn parse_exposure(s: &str) -> Result<quasar::output::preview::Exposure, String> {
    use quasar::output::preview::Exposure;
    if s.trim() == "auto" {
        return Ok(Exposure::Auto);
    }
    match s.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(Exposure::Stops(v)),
        _ => Err(format!("expected `auto` or a finite number of stops, got {s:?}")),
    }
}

/// Parses a positive, finite number of seconds or a positive error target.
pub fn parse_positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("expected a positive number, got {s:?}")),
    }
}

/// A finite time code (`--time-code`).
pub fn parse_time_code(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("expected a finite time code, got {s:?}")),
    }
}

/// Parses `MIN:MAX` for `--false-colour-range` (finite, MIN < MAX).
pub fn parse_range(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s.split_once(':').ok_or("expected MIN:MAX, e.g. 10:1000")?;
    let (a, b): (f64, f64) =
        (a.trim().parse().map_err(|_| "MIN is not a number")?, b.trim().parse().map_err(|_| "MAX is not a number")?);
    if !(a.is_finite() && b.is_finite() && a < b) {
        return Err(format!("{s}: need finite MIN < MAX"));
    }
    Ok((a, b))
}

/// Parses `--method`: `auto` or a row of the method table; another name is a command-line
/// error (exit code 2, as every other bad argument) listing the names.
pub fn parse_method(s: &str) -> Result<String, String> {
    let names = quasar::integrator::method::method_names();
    if names.contains(&s) {
        Ok(s.to_string())
    } else {
        Err(format!("unknown method `{s}` (expected one of: {})", names.join(", ")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_counts() {
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        assert_eq!(parse_threads("0"), Ok(cores));
        assert_eq!(parse_threads("1"), Ok(1));
        assert_eq!(parse_threads(&(MAX_THREADS_PER_CORE * cores).to_string()), Ok(MAX_THREADS_PER_CORE * cores));
        let e = parse_threads("100000").unwrap_err();
        assert!(e.contains("at most") && e.contains("per core"), "{e}");
        assert!(parse_threads("-1").is_err() && parse_threads("two").is_err());
    }

    #[test]
    fn numbers() {
        use quasar::output::preview::Exposure;
        assert_eq!(parse_exposure("-1.5"), Ok(Exposure::Stops(-1.5)));
        assert_eq!(parse_exposure("auto"), Ok(Exposure::Auto));
        assert!(parse_exposure("nan").is_err() && parse_exposure("inf").is_err());
        assert!(parse_positive("0").is_err() && parse_positive("-3").is_err() && parse_positive("nan").is_err());
        assert_eq!(parse_positive("2.5"), Ok(2.5));
        assert_eq!(parse_range("10:1000"), Ok((10.0, 1000.0)));
        assert!(parse_range("5:5").is_err() && parse_range("1000").is_err() && parse_range("a:3").is_err());
    }
}
