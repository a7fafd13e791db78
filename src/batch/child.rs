//! One part in a child process of its own (`matrace trace`), with a time limit and, through
//! `prlimit`, a memory limit; how a child that failed is described.

use super::inputs::Input;
use super::options::BatchOptions;
use super::summary::{failed_record, record_from_report, PartRecord, PartStatus};
use std::ffi::OsString;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Bytes of a child's stderr kept for the error message (the end is kept).
const STDERR_KEEP: usize = 16 * 1024;

/// The child's command line: `[prlimit --as=BYTES] WORKER trace PART -o DIR --stem STEM …`.
fn part_command(
    input: &Input,
    opts: &BatchOptions,
    prlimit: Option<&Path>,
    child_threads: usize,
) -> Command {
    let mut args: Vec<OsString> = vec!["trace".into(), input.path.clone().into_os_string()];
    args.push("-o".into());
    args.push(input.out_dir(&opts.out_dir).into_os_string());
    args.push("--stem".into());
    args.push(input.stem().into());
    if let Some(t) = opts.part.accuracy {
        args.push("--accuracy".into());
        args.push(t.to_string().into());
    }
    if let Some(t) = opts.part.fit_tol {
        args.push("--fit-tol".into());
        args.push(t.to_string().into());
    }
    for (on, flag) in [
        (opts.part.verify, "--verify"),
        (!opts.part.mesh, "--no-mesh"),
        (!opts.part.picture, "--no-svg"),
        (opts.part.with_solid, "--with-solid"),
    ] {
        if on {
            args.push(flag.into());
        }
    }
    let mut cmd = match (prlimit, opts.memory_limit) {
        (Some(prlimit), Some(bytes)) => {
            let mut c = Command::new(prlimit);
            c.arg(format!("--as={bytes}")).arg(&opts.worker);
            c
        }
        _ => Command::new(&opts.worker),
    };
    cmd.args(args)
        .env("RAYON_NUM_THREADS", child_threads.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    cmd
}

/// Runs one part in a child process and makes its record.
pub(super) fn run_part(
    input: &Input,
    opts: &BatchOptions,
    prlimit: Option<&Path>,
    child_threads: usize,
) -> PartRecord {
    let started = Instant::now();
    let mut child = match part_command(input, opts, prlimit, child_threads).spawn() {
        Ok(c) => c,
        Err(e) => {
            return failed_record(
                input,
                PartStatus::Failed,
                format!(
                    "{}: cannot start {}: {e}",
                    input.path.display(),
                    opts.worker.display()
                ),
                0.0,
            )
        }
    };
    let pid = child.id();
    let stderr = child.stderr.take().map(|mut pipe| {
        std::thread::spawn(move || {
            let mut kept = Vec::new();
            let mut buf = [0u8; 8192];
            while let Ok(n) = pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                kept.extend_from_slice(&buf[..n]);
                if kept.len() > 2 * STDERR_KEEP {
                    kept.drain(..kept.len() - STDERR_KEEP);
                }
            }
            kept
        })
    });
    let waited = wait_with_timeout(&mut child, opts.timeout);
    let seconds = started.elapsed().as_secs_f64();
    let stderr = stderr
        .and_then(|h| h.join().ok())
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .unwrap_or_default();
    let record = match waited {
        Err(e) => failed_record(
            input,
            PartStatus::Failed,
            format!("{}: lost the child process: {e}", input.path.display()),
            seconds,
        ),
        Ok(None) => failed_record(
            input,
            PartStatus::Timeout,
            format!(
                "{}: killed after the time limit of {} s",
                input.path.display(),
                opts.timeout.map_or(0.0, |t| t.as_secs_f64())
            ),
            seconds,
        ),
        // 0: traced; 1: traced, verification above the accuracy (the report says so).
        Ok(Some(status)) if matches!(status.code(), Some(0 | 1)) => {
            let path = input
                .out_dir(&opts.out_dir)
                .join(format!("{}.mat.json", input.stem()));
            match std::fs::read(&path)
                .ok()
                .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
            {
                Some(report) => record_from_report(input, opts, &report, false),
                None => failed_record(
                    input,
                    PartStatus::Failed,
                    format!("{}: no readable report after the trace", path.display()),
                    seconds,
                ),
            }
        }
        Ok(Some(status)) => failed_record(
            input,
            PartStatus::Failed,
            child_failure(input, status, &stderr, opts.memory_limit.and(prlimit)),
            seconds,
        ),
    };
    if record.status != PartStatus::Ok {
        remove_temp_files(&input.out_dir(&opts.out_dir), &input.stem(), pid);
    }
    record
}

/// Waits for `child`; kills it at `timeout` and returns `None`.
fn wait_with_timeout(
    child: &mut std::process::Child,
    timeout: Option<Duration>,
) -> std::io::Result<Option<ExitStatus>> {
    let started = Instant::now();
    let mut nap = Duration::from_millis(1);
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok(Some(status));
        }
        if timeout.is_some_and(|t| started.elapsed() >= t) {
            let _ = child.kill();
            child.wait()?;
            return Ok(None);
        }
        let mut sleep = nap;
        if let Some(t) = timeout {
            sleep = sleep.min(t.saturating_sub(started.elapsed()));
        }
        std::thread::sleep(sleep.max(Duration::from_micros(100)));
        nap = (nap * 2).min(Duration::from_millis(50));
    }
}

/// The error message of a child that ended with `status` (not 0 or 1).
fn child_failure(
    input: &Input,
    status: ExitStatus,
    stderr: &str,
    memory_limited: Option<&Path>,
) -> String {
    // The messages, without a backtrace and the notes about one.
    let lines: Vec<&str> = stderr
        .lines()
        .map(str::trim_end)
        .take_while(|l| *l != "stack backtrace:")
        .filter(|l| !l.is_empty() && !l.starts_with("note: "))
        .collect();
    // `trace` reports an unusable part as one line that names the file (exit status 2).
    if status.code() == Some(2) {
        if let Some(l) = lines
            .iter()
            .rev()
            .find(|l| l.starts_with("matrace: error: "))
        {
            return l.trim_start_matches("matrace: error: ").to_string();
        }
    }
    let how = describe_exit(status);
    let oom = stderr.contains("memory allocation of");
    let mut msg = format!("{}: crashed ({how})", input.path.display());
    if oom {
        msg.push_str(if memory_limited.is_some() {
            ": out of memory (the per-part memory limit)"
        } else {
            ": out of memory"
        });
    }
    if !lines.is_empty() {
        msg.push_str(": ");
        msg.push_str(&lines.join(" | "));
    }
    msg
}

#[cfg(unix)]
fn describe_exit(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(c), _) => format!("exit status {c}"),
        (None, Some(s)) => format!("killed by signal {s}"),
        _ => status.to_string(),
    }
}

#[cfg(not(unix))]
fn describe_exit(status: ExitStatus) -> String {
    status.to_string()
}

/// Removes the temporary files `output::write_atomic` of process `pid` left for stem `stem`
/// (`.<stem>.<suffix>.<pid>.tmp`) when that process was killed or crashed mid-write.
fn remove_temp_files(dir: &Path, stem: &str, pid: u32) {
    let prefix = format!(".{stem}.");
    let suffix = format!(".{pid}.tmp");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with(&prefix) && name.ends_with(&suffix) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// An executable `name` on the `PATH`.
pub fn find_in_path(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    })
}

/// Physical memory in bytes (Linux `/proc/meminfo`), if known.
pub fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
