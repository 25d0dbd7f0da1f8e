//! `nffrt` on AFF scenes: chosen by the `.aff` extension or `--format aff`, `info`
//! reports the animation in text and JSON, `render` renders frame 0, and a bad
//! include is refused at its file and line with the bad-scene exit code.

mod common;

use common::{json_of, nffrt, scratch_dir, skip::shared};

/// A scene with an animated triangle under a keyframed transform, and an include.
fn scene_dir(test: &str) -> std::path::PathBuf {
    let dir = scratch_dir("aff_cli", test);
    let main = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 16 12\n\
                l 0 0 5\nfm 0.1 0.1 0.1 0.8 0.2 0.2 0.3 0.3 0.3 10 0 1\n\
                a 0 2 5\nx turn { i 0 tri.aff }\n\
                k turn { rot 4 -1 0 0 1 0 0 0 0 0 0 0 1 0 0 0 0 1 0 0 1 90 0 0 0 2 0 0 1 90 0 0 0 }\n";
    std::fs::write(dir.join("main.aff"), main).unwrap();
    std::fs::write(dir.join("tri.aff"), "p 3 -1 -1 0 1 -1 0 0 1 0\n").unwrap();
    dir
}

#[test]
fn info_reports_the_animation() {
    let dir = scene_dir("info");
    let main = dir.join("main.aff");
    let json = json_of(
        &nffrt(&["info", "--json", main.to_str().unwrap()], b""),
        "info --json",
    );
    assert_eq!(json["dialect"], "aff");
    let aff = &json["aff"];
    assert_eq!(
        (aff["frames"].as_u64(), aff["time_span"][1].as_f64()),
        (Some(5), Some(2.0))
    );
    assert_eq!(
        (aff["animated_transforms"].as_u64(), aff["files"].as_u64()),
        (Some(1), Some(2))
    );
    assert_eq!(aff["objects"]["polygons"].as_u64(), Some(1));
    let out = nffrt(&["info", main.to_str().unwrap()], b"");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("animation   5 frames from time 0 to 2, 0.4 apart"),
        "{text}"
    );
    assert!(text.contains("format      aff"), "{text}");
}

#[test]
fn render_shows_frame_zero_and_stdin_takes_format_aff() {
    let dir = scene_dir("render");
    let out = nffrt(
        &[
            "render",
            dir.join("main.aff").to_str().unwrap(),
            "-o",
            dir.join("f0.png").to_str().unwrap(),
        ],
        b"",
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("f0.png").is_file());
    // Standard input needs --format aff (and includes nothing here).
    let text = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\nam 1 1 1\ns 0 0 0 1\n";
    let out = nffrt(&["info", "--json", "--format", "aff", "-"], text.as_bytes());
    assert_eq!(json_of(&out, "stdin")["dialect"], "aff");
    let out = nffrt(&["info", "-"], text.as_bytes());
    assert_eq!(out.status.code(), Some(3), "'am' is no NFF keyword");
}

#[test]
fn a_bad_include_is_refused_at_its_line() {
    let dir = scene_dir("bad_include");
    std::fs::write(dir.join("tri.aff"), "p 3 -1 -1 0 1 -1 0 0 1 0\ni 0 gone.aff\n").unwrap();
    let out = nffrt(&["info", dir.join("main.aff").to_str().unwrap()], b"");
    assert_eq!(out.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let want = format!("{}:2:5: cannot include gone.aff", dir.join("tri.aff").display());
    assert!(stderr.contains(&want), "{stderr}\nshould contain {want}");
}

#[test]
fn museum7_fails_saying_which_include() {
    let Some(path) = shared("scenes/bart/museum/aff/museum7.aff") else {
        return;
    };
    let png = scratch_dir("aff_cli", "museum7").join("never.png");
    let out = nffrt(
        &["render", path.to_str().unwrap(), "-o", png.to_str().unwrap()],
        b"",
    );
    assert_eq!(out.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let want = format!(
        "{}:33:5: cannot include animart7.aff: no such file or directory",
        path.display()
    );
    assert!(stderr.contains(&want), "{stderr}");
    assert!(!png.exists());
}
