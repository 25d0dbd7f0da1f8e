//! Command output into a pipe whose reader has gone away. A report for people
//! (`nffrt info ... | head -1`) ends quietly with success: no panic, no error
//! message. Data that did not all arrive — an image (`-o -`), a scene (`gen`), the
//! JSON of `--stats-json -` — is an output error (exit 4) without the success line.

use std::process::{Command, Stdio};

fn example() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff").to_string()
}

#[test]
fn commands_survive_a_closed_standard_output() {
    for args in [
        vec!["info", "--bvh"],
        vec!["render", "--pixel", "320,240"],
        vec!["bench", "--repeat", "1"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_nffrt"))
            .args(&args)
            .arg(example())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Close the read end before the program has printed anything.
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
    }
}

/// Runs nffrt with standard output a pipe whose read end is closed before it starts,
/// so that its first write to it fails, whenever it comes: (exit code, stderr).
fn run_into_a_closed_pipe(args: &[&str]) -> (Option<i32>, String) {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_nffrt"))
        .args(args)
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn data_cut_short_is_an_output_error() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("closed_stdout_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("a.png");
    let scene = example();
    let small = ["--width", "40", "--height", "30"];
    for args in [
        [&["render", &scene, "-o", "-"][..], &small[..]].concat(),
        [
            &["render", &scene, "-o", png.to_str().unwrap(), "--stats-json", "-"][..],
            &small[..],
        ]
        .concat(),
        vec!["gen", "tetra"],
        vec!["gen", "balls", "-o", "-"],
    ] {
        let (code, stderr) = run_into_a_closed_pipe(&args);
        assert_eq!(code, Some(4), "{args:?}: {stderr}");
        assert_eq!(
            stderr, "nffrt: error: standard output: cannot write output: the reader closed the pipe\n",
            "{args:?}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
