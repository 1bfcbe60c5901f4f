//! The USD reader isolated in a child process (docs/reliability.md): before this process opens a
//! USD stage, a child of the same binary imports it (`quasar __import-usd FILE ...`), and only if
//! the child ended normally, with the stage imported or refused by an error, does this process
//! import it. An abort inside openusd 0.6's binary reader (an unchecked allocation size from a
//! hostile `.usdc`) kills the child, and the import here fails with an error naming the file.
//! The cost is a second import of every USD stage (measured in docs/reliability.md).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

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
    let Ok(out) = cmd.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::piped()).output() else {
        return Ok(());
    };
    if matches!(out.status.code(), Some(0 | 1)) {
        return Ok(());
    }
    let said = String::from_utf8_lossy(&out.stderr);
    let first = said.lines().next().unwrap_or("").trim();
    let how = match out.status.code() {
        Some(c) => format!("exit code {c}"),
        None => signal_name(&out.status),
    };
    Err(format!(
        "the USD reader (openusd 0.6.0) aborted on this stage ({how}{}): a corrupt or hostile binary file; nothing was imported",
        if first.is_empty() { String::new() } else { format!(": {first}") }
    ))
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
