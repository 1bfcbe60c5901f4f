//! The USD reader isolated in a child process (docs/reliability.md): before this process opens a
//! USD stage, a child of the same binary imports it (`quasar __import-usd FILE ...`), and only if
//! the child ended normally, with the stage imported or refused by an error, does this process
//! import it. An abort inside openusd 0.6's reader (an unchecked allocation size from a hostile
//! `.usdc`, a stack overflow on a malformed `.usda`) kills the child, and the import here fails
//! with an error naming the file. A child that has not finished after [`reader_time_limit`] (a
//! composition of a malformed stage that never ends: openusd 0.6's instancing resolution can
//! loop) is killed, and the import fails the same way. The cost is a second import of every USD
//! stage (measured in docs/reliability.md).

use std::ffi::OsString;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use quasar_importers::ImportOptions;

/// The hidden first argument that makes `quasar` the child.
pub const CHILD_ARG: &str = "__import-usd";

/// The child: imports the stage `args[0]` with the options that follow (`--units-scale F`,
/// `--time-code T`, `--allow-external-paths`); exit 0 when it imports, 1 when it is refused.
pub fn child(args: &[OsString]) -> ExitCode {
    let Some(path) = args.first().map(PathBuf::from) else { return ExitCode::from(2) };
    let mut opts = ImportOptions::default();
    let mut it = args[1..].iter().map(|a| a.to_string_lossy().into_owned());
    while let Some(a) = it.next() {
        match a.as_str() {
            "--units-scale" => opts.units_scale = it.next().and_then(|v| v.parse().ok()),
            "--time-code" => opts.time_code = it.next().and_then(|v| v.parse().ok()),
            "--allow-external-paths" => opts.allow_external_paths = true,
            _ => return ExitCode::from(2),
        }
    }
    match quasar_importers::import_usd(&path, &opts) {
        Ok(_) => ExitCode::SUCCESS,
        Err(_) => ExitCode::FAILURE,
    }
}

/// The guard installed by `main` ([`quasar_importers::set_usd_reader_guard`]): runs [`child`]
/// on `path` and refuses the stage when the child did not end with 0 or 1. When no child can be
/// started, the stage is imported here, unguarded.
pub fn guard(path: &Path, opts: &ImportOptions) -> Result<(), String> {
    let Ok(exe) = std::env::current_exe() else { return Ok(()) };
    let mut cmd = Command::new(exe);
    cmd.arg(CHILD_ARG).arg(path);
    if let Some(u) = opts.units_scale {
        cmd.arg("--units-scale").arg(u.to_string());
    }
    if let Some(t) = opts.time_code {
        cmd.arg("--time-code").arg(t.to_string());
    }
    if opts.allow_external_paths {
        cmd.arg("--allow-external-paths");
    }
    let Ok(mut child) = cmd.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::piped()).spawn() else {
        return Ok(());
    };
    // the child's stderr, drained beside the wait so that a chatty child cannot block on it
    let mut pipe = child.stderr.take();
    let drain = std::thread::spawn(move || {
        let mut said = String::new();
        if let Some(p) = pipe.as_mut() {
            let _ = p.take(1 << 16).read_to_string(&mut said);
        }
        said
    });
    let limit = reader_time_limit(path);
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if start.elapsed() < limit => std::thread::sleep(Duration::from_millis(10)),
            Ok(None) => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            Err(_) => return Ok(()),
        }
    };
    let said = drain.join().unwrap_or_default();
    let Some(status) = status else {
        return Err(format!(
            "the USD reader (openusd 0.6.0) did not finish this stage in {} s (a malformed or hostile stage whose composition does not end; the limit is {TIME_LIMIT_ENV} seconds); nothing was imported",
            limit.as_secs()
        ));
    };
    if matches!(status.code(), Some(0 | 1)) {
        return Ok(());
    }
    let first = said.lines().next().unwrap_or("").trim();
    let how = match status.code() {
        Some(c) => format!("exit code {c}"),
        None => signal_name(&status),
    };
    Err(format!(
        "the USD reader (openusd 0.6.0) aborted on this stage ({how}{}): a corrupt or hostile file; nothing was imported",
        if first.is_empty() { String::new() } else { format!(": {first}") }
    ))
}

/// The environment variable that sets the child's time limit in seconds.
pub const TIME_LIMIT_ENV: &str = "QUASAR_USD_READER_TIMEOUT_S";

/// How long the child may read `path`: `QUASAR_USD_READER_TIMEOUT_S` seconds when set, else 60 s
/// plus 10 s per MB of the file (openusd reads a 1,002,528-triangle, 40 MB `.usdc` in 0.07 s
/// and a 5,000-prim `.usda` in 0.5 s: the limit is two orders of magnitude above any stage
/// measured, and only ends a reader that does not terminate).
pub fn reader_time_limit(path: &Path) -> Duration {
    if let Some(s) = std::env::var(TIME_LIMIT_ENV).ok().and_then(|v| v.parse::<f64>().ok())
        && s.is_finite()
        && s > 0.0
    {
        return Duration::from_secs_f64(s);
    }
    let mb = std::fs::metadata(path).map_or(0.0, |m| m.len() as f64 / 1e6);
    Duration::from_secs_f64(60.0 + 10.0 * mb)
}

#[cfg(unix)]
fn signal_name(status: &std::process::ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match status.signal() {
        Some(6) => "SIGABRT".into(),
        Some(9) => "SIGKILL".into(),
        Some(11) => "SIGSEGV".into(),
        Some(s) => format!("signal {s}"),
        None => "no exit code".into(),
    }
}

#[cfg(not(unix))]
fn signal_name(_: &std::process::ExitStatus) -> String {
    "no exit code".into()
}
