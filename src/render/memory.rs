//! The memory a render needs, estimated before anything large is allocated, so that an image too
//! large for the machine is refused with the figure instead of aborting on a failed allocation
//! (a 16384 x 16384 `pt` render needs about 100 GiB).
//!
//! The estimate is pixels x the method's `bytes_per_pixel` (its row of the method table: the peak
//! resident memory per pixel measured on the shipped scenes, with 25% headroom; BENCHMARKS.md
//! "Memory per pixel"). It is compared with the memory available to the process after the scene
//! is compiled (so the scene is already accounted for): `MemAvailable` of `/proc/meminfo`, or the
//! cgroup limit (`memory.max`) less its usage when that is smaller. Where neither can be read,
//! nothing is refused.

/// The memory, in bytes, that this process may still allocate (module documentation), or None
/// where it cannot be read.
pub fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        t.lines()
            .find_map(|l| l.strip_prefix("MemAvailable:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
            .map(|kb| kb * 1024)
    });
    let read = |p: &str| std::fs::read_to_string(p).ok().and_then(|t| t.trim().parse::<u64>().ok());
    let cgroup = match (read("/sys/fs/cgroup/memory.max"), read("/sys/fs/cgroup/memory.current")) {
        (Some(max), Some(cur)) => Some(max.saturating_sub(cur)),
        _ => None,
    };
    match (meminfo, cgroup) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Bytes as GiB with one decimal (`93.8 GiB`).
fn gib(bytes: u64) -> String {
    format!("{:.1} GiB", bytes as f64 / f64::from(1u32 << 30))
}

/// Refuses a render of `width` x `height` with `method` (its `bytes_per_pixel`) when it needs
/// more than `available` bytes; the error gives both figures.
pub fn check_memory(
    method: &str,
    bytes_per_pixel: u64,
    (width, height): (u32, u32),
    available: Option<u64>,
) -> Result<(), String> {
    let need = u64::from(width) * u64::from(height) * bytes_per_pixel;
    match available {
        Some(avail) if need > avail => Err(format!(
            "a {width}x{height} render with `{method}` needs about {} of memory ({bytes_per_pixel} bytes per pixel), more than the {} available: render a smaller image",
            gib(need),
            gib(avail)
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_larger_than_the_memory_are_refused_with_the_figures() {
        let e = check_memory("pt", 400, (16384, 16384), Some(24 << 30)).unwrap_err();
        assert!(e.contains("16384x16384") && e.contains("100.0 GiB") && e.contains("24.0 GiB"), "{e}");
        assert!(e.contains("400 bytes per pixel"), "{e}");
        assert!(check_memory("pt", 400, (1024, 1024), Some(24 << 30)).is_ok());
        assert!(check_memory("pt", 400, (16384, 16384), None).is_ok());
    }

    #[test]
    fn this_machine_reports_its_memory() {
        if cfg!(target_os = "linux") {
            let a = available_memory().expect("/proc/meminfo");
            assert!(a > 1 << 20, "{a}");
        }
    }
}
