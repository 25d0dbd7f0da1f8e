//! Every malformed input is refused with one clear line: exit code 3, and
//! `nffrt: error: PATH:LINE:COL: message` naming the offending token and what was expected.
//!
//! The corpus lives in `tests/data/bad/`. Each file opens with a comment
//! `# expect: LINE:COL TEXT`, worked out by hand: where the error must point, and a piece of
//! text the message must contain (usually `expected ..., found "TOKEN"`). The parser skips
//! that comment like any other, so line 1 of every case is the header.

mod common;

use std::path::Path;

use common::{data_dir, header_values, name, nff_files, nffrt};

/// What a bad file's header promises.
#[derive(Debug)]
struct Expect {
    line: u32,
    column: u32,
    text: String,
}

fn expectation(path: &Path, bytes: &[u8]) -> Result<Expect, String> {
    let file = name(path);
    let values = header_values(bytes, "expect");
    let [value] = values.as_slice() else {
        return Err(format!(
            "{file}: needs exactly one '# expect: LINE:COL TEXT' header, has {}",
            values.len()
        ));
    };
    let (pos, text) = value.split_once(' ').unwrap_or((value, ""));
    let parsed = pos
        .split_once(':')
        .and_then(|(l, c)| Some((l.parse().ok()?, c.parse().ok()?)));
    let Some((line, column)) = parsed else {
        return Err(format!("{file}: bad position {pos:?} in the expect header"));
    };
    if text.is_empty() {
        return Err(format!("{file}: the expect header names no message text"));
    }
    Ok(Expect {
        line,
        column,
        text: text.to_string(),
    })
}

/// Runs one bad file through the library and the binary; describes every mismatch.
fn check(path: &Path) -> Result<(), String> {
    let file = name(path);
    let bytes = std::fs::read(path).map_err(|e| format!("{file}: {e}"))?;
    let want = expectation(path, &bytes)?;

    // The library: an error (not a panic) at the promised place.
    let format = nffrt::nff::Format::of_path(path);
    let err = match nffrt::nff::parse_format(&bytes, format, &Default::default()) {
        Ok(scene) => {
            return Err(format!(
                "{file}: the library accepted it ({} primitives)",
                scene.primitive_count()
            ))
        }
        Err(e) => e,
    };
    if (err.line, err.column) != (want.line, want.column) {
        return Err(format!(
            "{file}: library error at {}:{}, expected {}:{} ({err})",
            err.line, err.column, want.line, want.column
        ));
    }

    // The binary: exit code 3, nothing on stdout, one line on stderr.
    let shown = path.to_str().expect("UTF-8 test path");
    let out = nffrt(&["info", "--json", shown], b"");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let mut problems = Vec::new();
    if out.status.code() != Some(3) {
        problems.push(format!("exit code {:?}, expected 3", out.status.code()));
    }
    if !out.stdout.is_empty() {
        problems.push(format!(
            "stdout not empty: {:?}",
            String::from_utf8_lossy(&out.stdout)
        ));
    }
    if stderr.contains("panicked") {
        problems.push("panicked".to_string());
    }
    if stderr.lines().count() != 1 || !stderr.ends_with('\n') {
        problems.push("stderr is not exactly one line".to_string());
    }
    let prefix = format!("nffrt: error: {shown}:{}:{}: ", want.line, want.column);
    if !stderr.starts_with(&prefix) {
        problems.push(format!("stderr does not start with {prefix:?}"));
    }
    if !stderr.contains(&want.text) {
        problems.push(format!("message lacks {:?}", want.text));
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!("{file}: {}\n    stderr: {stderr:?}", problems.join("; ")))
    }
}

#[test]
fn every_malformed_input_is_refused_at_its_line_and_column() {
    let files = nff_files(&data_dir("bad"));
    assert!(
        files.len() >= 30,
        "the bad corpus shrank to {} files",
        files.len()
    );
    let failures: Vec<String> = files.iter().filter_map(|p| check(p).err()).collect();
    assert!(
        failures.is_empty(),
        "{} of {} bad inputs misreported:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

#[test]
fn standard_input_errors_are_reported_as_stdin() {
    let path = data_dir("bad").join("truncated_sphere.nff");
    let bytes = std::fs::read(&path).expect("corpus file");
    let out = nffrt(&["info", "-"], &bytes);
    assert_eq!(out.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        stderr,
        "nffrt: error: <stdin>:5:1: expected a number (sphere radius), found end of file\n"
    );
    assert!(out.stdout.is_empty());
}

/// Counts in the file must not size an allocation: under a 256 MiB address-space limit a
/// count of four billion vertices (48 GB if reserved up front) still ends in a plain error.
#[cfg(target_os = "linux")]
#[test]
fn huge_counts_are_refused_without_allocating() {
    use std::process::Command;

    let hostile = Path::new(env!("CARGO_TARGET_TMPDIR")).join("huge-count-with-data.nff");
    // A few megabytes of real vertices after the count: memory must track the data read.
    let mut src = String::from("f 1 1 1 1 0 1 0 1\npp 4000000000\n");
    src.push_str(&"0 0 0 0 0 1\n".repeat(200_000));
    std::fs::write(&hostile, src).expect("writing a temporary scene");
    let bad = data_dir("bad");
    let cases = [
        bad.join("polygon_count_4e9_no_data.nff"),
        bad.join("polygon_count_huge.nff"),
        bad.join("patch_count_above_u32.nff"),
        hostile.clone(),
    ];
    for path in &cases {
        let out = Command::new("sh")
            .arg("-c")
            .arg("ulimit -v 262144 && exec \"$0\" info \"$1\"")
            .arg(env!("CARGO_BIN_EXE_nffrt"))
            .arg(path)
            .output()
            .expect("sh runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{}: {stderr}", path.display());
        assert!(
            stderr.starts_with("nffrt: error: ") && stderr.lines().count() == 1,
            "{stderr}"
        );
    }
    std::fs::remove_file(&hostile).expect("removing the temporary scene");
}

#[test]
fn every_truncation_of_a_valid_scene_is_an_error_inside_the_file_or_a_scene() {
    let src = std::fs::read(data_dir("ok").join("every_keyword.nff")).expect("corpus file");
    let mut errors = 0;
    for cut in 0..=src.len() {
        let prefix = &src[..cut];
        match nffrt::nff::parse_bytes(prefix) {
            Ok(_) => {}
            Err(e) => {
                errors += 1;
                // A truncated file fails at its very end or on a token inside it.
                let last_line = prefix.split(|&b| b == b'\n').count() as u32;
                assert!(
                    e.line >= 1 && e.line <= last_line && e.column >= 1,
                    "cut at {cut}: {e}"
                );
            }
        }
    }
    assert!(
        errors > src.len() / 2,
        "most cuts land mid-entity, yet only {errors} failed"
    );
}

mod fuzz {
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Arbitrary bytes never panic, and an error points at a line that exists.
        #[test]
        fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
            if let Err(e) = nffrt::nff::parse_bytes(&bytes) {
                let lines = bytes.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
                prop_assert!(e.line >= 1 && e.line <= lines && e.column >= 1, "{}", e);
            }
        }

        /// NFF-looking token soup (keywords, numbers, junk) never panics either.
        #[test]
        fn keyword_soup_never_panics(tokens in proptest::collection::vec(
            prop_oneof![
                Just("v"), Just("from"), Just("at"), Just("up"), Just("angle"), Just("resolution"),
                Just("f"), Just("s"), Just("c"), Just("p"), Just("pp"), Just("pl"), Just("aabb"),
                Just("l"), Just("b"), Just("0"), Just("1"), Just("-1"), Just("3"), Just("4000000000"),
                Just("1e39"), Just("nan"), Just(".5"), Just("#"), Just("\n"), Just("x"),
            ],
            0..200,
        )) {
            let src = tokens.join(" ");
            if let Err(e) = nffrt::nff::parse(&src) {
                prop_assert!(e.line >= 1 && e.column >= 1, "{}", e);
                prop_assert!(!e.to_string().is_empty());
            }
        }
    }
}

// ---- I/O and usage errors of the command line ----------------------------------------

#[test]
fn missing_file_exits_4_with_one_line() {
    let out = nffrt(&["info", "/nonexistent/nffrt/scene.nff"], b"");
    assert_eq!(out.status.code(), Some(4));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "nffrt: error: /nonexistent/nffrt/scene.nff: cannot read scene: no such file or directory\n"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn directory_exits_4_with_one_line() {
    let dir = data_dir("bad");
    let out = nffrt(&["info", "--json", dir.to_str().expect("UTF-8 path")], b"");
    assert_eq!(out.status.code(), Some(4));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        stderr,
        format!(
            "nffrt: error: {}: is a directory, not a scene file\n",
            dir.display()
        )
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn usage_errors_exit_2() {
    for args in [
        &["info"][..],
        &["info", "--no-such-flag", "x.nff"],
        &["no-such-command"],
    ] {
        let out = nffrt(args, b"");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            !String::from_utf8_lossy(&out.stderr).contains("panicked"),
            "{args:?}"
        );
    }
}
