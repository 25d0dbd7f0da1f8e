//! Skipped checks, said the same way everywhere. A test that cannot run a check on
//! this machine calls [`skip`], which prints one line, `SKIPPED: <test>: <reason>`,
//! on standard error and appends it to the file `$NFFRT_SKIP_LOG` names, if any
//! (`scripts/test-all.sh` sets it, and sums the skips up by reason at the end).
//!
//! Most skips are for `../shared` (the SPD and course scenes, reference pictures and
//! specs kept beside the checkout, not in it): [`shared`] finds a file there or skips.
//! With `NFFRT_REQUIRE_SHARED=1` (`.ci/run` sets it) such a skip is a failure
//! instead, so that a check CI expects to run cannot pass by not running; other
//! skips CI must not take go through [`skip_unless_required`] with a variable of
//! their own (`NFFRT_REQUIRE_AVX2` for the AVX2 kernels' bit-equality tests).
//!
//! Included by `tests/common` and, for the unit tests, by `src/lib.rs`.

// Each includer uses a different subset of it.
#![allow(dead_code)]

use std::io::Write;
use std::path::PathBuf;

/// The reason every `../shared` skip gives (one line of the summary for all of them).
pub const SHARED_ABSENT: &str = "../shared is absent (the SPD and course scenes, reference pictures)";

/// Says that the running test skips a check, and why: `SKIPPED: <test>: <reason>`.
pub fn skip(reason: &str) {
    // libtest names each test's thread after the test (`module::name`).
    let thread = std::thread::current();
    let test = thread.name().unwrap_or("unknown");
    let line = format!("SKIPPED: {}::{test}: {reason}", env!("CARGO_CRATE_NAME"));
    eprintln!("{line}");
    if let Some(log) = std::env::var_os("NFFRT_SKIP_LOG") {
        // One write per line in append mode: lines of tests running at once do not mix.
        let appended = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&log)
            .and_then(|mut f| f.write_all(format!("{line}\n").as_bytes()));
        if let Err(e) = appended {
            panic!(
                "cannot append to NFFRT_SKIP_LOG {}: {e}",
                PathBuf::from(log).display()
            );
        }
    }
}

/// The shared folder: `$NFFRT_SHARED` if set (`NFFRT_SHARED=/nowhere` rehearses a
/// fresh clone), else `../shared` beside the checkout.
pub fn shared_root() -> PathBuf {
    match std::env::var_os("NFFRT_SHARED") {
        Some(dir) => PathBuf::from(dir),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"),
    }
}

/// `../shared/RELATIVE` if it exists; otherwise `None` after [`skip`] (with
/// [`SHARED_ABSENT`] when the whole folder is missing), or a panic when
/// `NFFRT_REQUIRE_SHARED=1`.
pub fn shared(relative: &str) -> Option<PathBuf> {
    let root = shared_root();
    let path = root.join(relative);
    if path.exists() {
        return Some(path);
    }
    if root.is_dir() {
        skip_unless_required(
            "NFFRT_REQUIRE_SHARED",
            &format!("{relative} is absent from ../shared"),
        );
    } else {
        skip_unless_required("NFFRT_REQUIRE_SHARED", SHARED_ABSENT);
    }
    None
}

/// [`skip`] for `reason`, or, when the environment variable `var` is `1` (`.ci/run`
/// sets the ones CI needs), a panic: a check CI expects to run must not pass by not
/// running.
pub fn skip_unless_required(var: &str, reason: &str) {
    if std::env::var(var).as_deref() == Ok("1") {
        panic!("{var}=1 but {reason}: this check must run");
    }
    skip(reason);
}
