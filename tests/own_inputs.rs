//! Issue 30, item A: no command writes over one of its own inputs. `merge` into
//! one of its tiles, `render` of a scene file named like its picture (by default or
//! with `-o`, or its `--stats-json`), and `gen` into a file named like an image are
//! refused as usage errors, with every file left as it was.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{nffrt, nffrt_in};

const SHOWCASE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff");
const SMALL: [&str; 5] = ["--width", "40", "--height", "30", "-q"];

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("own_inputs", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Asserts a usage error (exit 2, one line, nothing on standard output) that
/// contains `needle`.
fn refused(out: &Output, needle: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(needle), "{err:?} lacks {needle:?}");
    assert!(out.stdout.is_empty());
}

/// The files of `dir` and their bytes, sorted by name.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (common::name(&p), std::fs::read(&p).unwrap()))
        .collect();
    files.sort();
    files
}

#[test]
fn merge_never_writes_into_one_of_its_tiles() {
    let dir = scratch("merge");
    for (region, tile) in [
        ("0,0,40,15", "dof.0-0-40-15.png"),
        ("0,15,40,30", "dof.0-15-40-30.png"),
    ] {
        let args = [
            &["render", SHOWCASE, "--region", region, "-o", tile][..],
            &SMALL[..],
        ]
        .concat();
        assert!(nffrt_in(&dir, &args).status.success());
    }
    let before = contents(&dir);
    let merge = |out: &str| {
        nffrt_in(
            &dir,
            &["merge", "dof.0-0-40-15.png", "dof.0-15-40-30.png", "-o", out],
        )
    };
    refused(
        &merge("dof.0-15-40-30.png"),
        "-o dof.0-15-40-30.png would overwrite the tile dof.0-15-40-30.png; name another output",
    );
    // The same file under another name (a hard link) is the same input.
    std::fs::hard_link(dir.join("dof.0-0-40-15.png"), dir.join("link.png")).unwrap();
    let mut before_link = before.clone();
    before_link.push(("link.png".into(), before[0].1.clone()));
    before_link.sort();
    refused(
        &merge("link.png"),
        "-o link.png would overwrite the tile dof.0-0-40-15.png (the same file)",
    );
    assert_eq!(contents(&dir), before_link, "a file changed");
    assert!(merge("full.png").status.success());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn render_never_writes_over_its_scene() {
    let dir = scratch("render");
    std::fs::copy(SHOWCASE, dir.join("a.png")).unwrap();
    std::fs::copy(SHOWCASE, dir.join("scene.nff")).unwrap();
    let before = contents(&dir);
    let render = |args: &[&str]| nffrt_in(&dir, &[&["render"][..], args, &SMALL[..]].concat());
    refused(
        &render(&["a.png"]),
        "the default output a.png would overwrite the scene file a.png; name another output",
    );
    refused(
        &render(&["a.png", "-o", "a.png"]),
        "-o a.png would overwrite the scene file a.png",
    );
    refused(
        &render(&["a.png", "-o", "./a.png"]),
        "-o ./a.png would overwrite the scene file a.png (the same file)",
    );
    refused(
        &render(&["scene.nff", "-o", "x.png", "--stats-json", "scene.nff"]),
        "--stats-json scene.nff would overwrite the scene file scene.nff",
    );
    refused(
        &render(&["scene.nff", "-o", "x.png", "--stats-json", "x.png"]),
        "-o x.png and --stats-json x.png name the same file; give each its own",
    );
    assert_eq!(contents(&dir), before, "a file changed");
    // Another name is fine, and a scene on standard input has no file to protect.
    assert!(render(&["a.png", "-o", "b.png"]).status.success());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn gen_refuses_an_image_name() {
    let dir = scratch("gen");
    std::fs::write(dir.join("k2.png"), b"the user's picture").unwrap();
    let before = contents(&dir);
    for name in ["k2.png", "k2.PPM", "k2.pfm", "k2.exr"] {
        let out = nffrt(&["gen", "tetra", "-o", s(&dir.join(name))], b"");
        refused(
            &out,
            "gen writes NFF scene text, not an image; name the output .nff",
        );
    }
    assert_eq!(contents(&dir), before, "a file changed");
    assert!(nffrt(&["gen", "tetra", "-o", s(&dir.join("k2.nff"))], b"")
        .status
        .success());
    std::fs::remove_dir_all(&dir).unwrap();
}
