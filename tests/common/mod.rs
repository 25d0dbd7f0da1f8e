//! Helpers shared by the integration tests: running the `nffrt` binary, finding the
//! shared scenes, reading the `# expect:` headers of the hand-written test data.

// Each test crate includes this module and uses a different subset of it.
#![allow(dead_code)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// Runs the `nffrt` binary built for these tests, feeding `stdin` to it.
pub fn nffrt(args: &[&str], stdin: &[u8]) -> Output {
    run_nffrt(None, args, stdin)
}

/// Runs the `nffrt` binary in `dir` (for the default output names, which are
/// relative), with nothing on standard input.
pub fn nffrt_in(dir: &Path, args: &[&str]) -> Output {
    run_nffrt(Some(dir), args, b"")
}

/// Runs the `nffrt` binary with `vars` added to its environment, nothing on
/// standard input.
pub fn nffrt_env(args: &[&str], vars: &[(&str, &str)]) -> Output {
    run_nffrt_with(None, args, b"", vars)
}

fn run_nffrt(dir: Option<&Path>, args: &[&str], stdin: &[u8]) -> Output {
    run_nffrt_with(dir, args, stdin, &[])
}

fn run_nffrt_with(dir: Option<&Path>, args: &[&str], stdin: &[u8], vars: &[(&str, &str)]) -> Output {
    // Absent without the `cli` feature; the tests that run the binary require it.
    let Some(binary) = option_env!("CARGO_BIN_EXE_nffrt") else {
        panic!("the nffrt binary is built only with the `cli` feature");
    };
    let mut command = Command::new(binary);
    if let Some(dir) = dir {
        command.current_dir(dir);
    }
    let mut child = command
        .args(args)
        .envs(vars.iter().copied())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the nffrt binary starts");
    // The binary may exit (e.g. on a usage error) before reading stdin: ignore a broken pipe.
    let _ = child.stdin.take().expect("piped stdin").write_all(stdin);
    child.wait_with_output().expect("nffrt runs to completion")
}

/// A fresh, empty directory for one test: `CARGO_TARGET_TMPDIR/{test_file}_{name}_{pid}`.
pub fn scratch_dir(test_file: &str, name: &str) -> PathBuf {
    let dir =
        PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{test_file}_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `nffrt info --json PATH` and returns the output.
pub fn info_json(path: &Path) -> Output {
    nffrt(&["info", "--json", path.to_str().expect("UTF-8 test path")], b"")
}

/// Parses stdout of a successful `info --json` run, failing the test with stderr otherwise.
pub fn json_of(out: &Output, what: &str) -> serde_json::Value {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{what}: expected success, stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{what}: stdout is not JSON ({e})"))
}

/// An unsigned field of an `info --json` object.
pub fn field(json: &serde_json::Value, key: &str) -> u64 {
    json[key]
        .as_u64()
        .unwrap_or_else(|| panic!("no unsigned field {key:?} in {json}"))
}

/// The `warnings` array of an `info --json` object, each as `LINE:COL: message`.
pub fn warnings(json: &serde_json::Value) -> Vec<String> {
    json["warnings"]
        .as_array()
        .unwrap_or_else(|| panic!("no warnings array in {json}"))
        .iter()
        .map(|w| w.as_str().expect("warnings are strings").to_string())
        .collect()
}

/// `tests/data/<kind>`.
pub fn data_dir(kind: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(kind)
}

/// The `.nff` files directly in `dir`, sorted by name.
pub fn nff_files(dir: &Path) -> Vec<PathBuf> {
    // (`.nff` and `.p3f` files alike: the binary picks the format by the extension.)
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "nff" || x == "p3f"))
        .collect();
    files.sort();
    files
}

/// Every `.nff` under `../shared/scenes/{spd,p3d}`, or `None` (after [`skip::skip`]) when
/// the shared directory is absent, as it is outside the development machines.
pub fn shared_scenes() -> Option<Vec<PathBuf>> {
    let root = skip::shared("scenes")?;
    let mut all = Vec::new();
    for sub in ["spd", "p3d"] {
        let dir = root.join(sub);
        if dir.is_dir() {
            all.extend(nff_files(&dir));
        }
    }
    assert!(!all.is_empty(), "{} holds no .nff scene", root.display());
    Some(all)
}

/// The text after `# KEY:` on each leading comment line of a test file, in order.
/// Only the comment block at the top of the file is read, so a header cannot hide
/// further down. Bytes after the header need not be UTF-8.
pub fn header_values(bytes: &[u8], key: &str) -> Vec<String> {
    let prefix = format!("# {key}:");
    let mut values = Vec::new();
    for line in bytes.split(|&b| b == b'\n') {
        let Ok(line) = std::str::from_utf8(line) else {
            break;
        };
        let line = line.trim_end_matches('\r');
        if !line.starts_with('#') {
            break;
        }
        if let Some(rest) = line.strip_prefix(&prefix) {
            values.push(rest.trim().to_string());
        }
    }
    values
}

/// The file name of a path, for messages and for the `PATH:` in error lines.
pub fn name(path: &Path) -> String {
    path.file_name()
        .expect("a file name")
        .to_string_lossy()
        .into_owned()
}

pub mod compare;
pub mod skip;

/// The whitespace-separated tokens of a scene's text with `#` comments stripped: all
/// the independent entity counters of the tests need (they never parse a scene).
pub fn tokens_without_comments(text: &str) -> Vec<&str> {
    text.lines()
        .flat_map(|line| line.split('#').next().unwrap_or("").split_whitespace())
        .collect()
}

/// The `.p3f` files of the folders `dirs` of `../shared/scenes/p3f/`, sorted, or `None`
/// (after saying the test is skipped) without `../shared`.
pub fn shared_p3f_scenes(dirs: &[&str]) -> Option<Vec<PathBuf>> {
    let root = skip::shared("scenes/p3f")?;
    let mut all = Vec::new();
    for dir in dirs {
        let dir = root.join(dir);
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "p3f") {
                all.push(path);
            }
        }
    }
    all.sort();
    Some(all)
}

/// Runs the `nffrt` binary with nothing on standard input, asserting that it exits
/// with 0 (its standard error in the message otherwise).
pub fn nffrt_ok(args: &[&str]) {
    let out = nffrt(args, b"");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// An AFF animation of a white sphere of radius 0.2 (shown by the ambient light
/// alone: exactly 1 where it is met) on a black background, its block `x ball` keyed
/// along x: keys x = 0, 0, 2, 2 at times -1, 0, 1, 2 (the curve runs from the second
/// key to the third: on t in [0, 1] the centre is at x = t + 3t² - 2t³,
/// tests/aff_frames.rs works it out), four frames over t = 0..1. The camera at
/// z = 10 looks at the origin; its `side` x `side` pixel centres span x, y = ±2.5 on
/// the plane z = 0 (tan(angle / 2) = 0.25).
pub fn keyed_ball(side: u32) -> String {
    format!(
        "v from 0 0 10 at 0 0 0 up 0 1 0 angle 28.072486935852957 hither 1 resolution {side} {side}\n\
         b 0 0 0\nam 1 1 1\nfm 1 1 1  0 0 0  0 0 0  1 0 1\na 0 1 4\n\
         x ball {{ s 0 0 0 0.2 }}\n\
         k ball {{ transl 4  -1 0 0 0 0 0 0   0 0 0 0 0 0 0   1 2 0 0 0 0 0   2 2 0 0 0 0 0 }}\n"
    )
}

/// True if Open Image Denoise is found as `nffrt render --denoise` looks for it;
/// otherwise says the check is skipped (a failure under NFFRT_REQUIRE_OIDN=1).
pub fn denoiser_installed() -> bool {
    if nffrt::denoise::Denoiser::open(&[], 1).is_ok() {
        return true;
    }
    skip::skip_unless_required(
        "NFFRT_REQUIRE_OIDN",
        "Open Image Denoise is not installed (pip install pyoidn, or NFFRT_OIDN)",
    );
    false
}
