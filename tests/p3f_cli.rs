//! P3F through the command line: the skybox a scene names is read from the scene's
//! folder and seen in the picture; a missing, incomplete or corrupt skybox is an I/O
//! error naming the path, with no picture written; `--format` reads P3F from
//! standard input.

mod common;

use std::path::Path;

use common::{nffrt, scratch_dir};
use nffrt::image::{decode_png, encode_png_rgb8};

const FACES: [&str; 6] = ["right", "left", "top", "bottom", "front", "back"];

/// Writes six 3x3 PNG faces into `dir/sky`: face k is grey 40k + 10 everywhere but
/// its centre texel, which is (200, 100 + k, 50).
fn write_skybox(dir: &Path) {
    let sky = dir.join("sky");
    std::fs::create_dir_all(&sky).unwrap();
    for (k, name) in FACES.iter().enumerate() {
        let grey = 40 * k as u8 + 10;
        let mut rgb = vec![grey; 27];
        rgb[12..15].copy_from_slice(&[200, 100 + k as u8, 50]);
        let file = std::fs::File::create(sky.join(format!("{name}.png"))).unwrap();
        encode_png_rgb8(3, 3, &rgb, &[], file).unwrap();
    }
}

/// A 3x3 picture looking along `dir` from the origin into the skybox `sky`.
fn scene(dir: &str) -> String {
    format!("bclr 1 0 1\nenv sky\ncamera eye 0 0 0 at {dir} up 0 0.6 0.8 angle 10 hither 1 resolution 3 3\n")
}

#[test]
fn each_axis_sees_the_centre_texel_of_its_face_in_the_picture() {
    let dir = scratch_dir("p3f_cli", "axes");
    write_skybox(&dir);
    // +X sees `left` (face 1), -X `right` (0), +Y `top` (2), -Y `bottom` (3), +Z
    // `front` (4), -Z `back` (5) (P3F-SPEC's naming).
    for (look, face) in [
        ("1 0 0", 1u8),
        ("-1 0 0", 0),
        ("0 1 0", 2),
        ("0 -1 0", 3),
        ("0 0 1", 4),
        ("0 0 -1", 5),
    ] {
        let out = dir.join("look.png");
        let run = render_look(&dir, look, &out);
        assert_eq!(
            run.status.code(),
            Some(0),
            "{look}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        let png = decode_png(std::fs::read(&out).unwrap().as_slice()).unwrap();
        // The centre pixel looks along the axis: the centre texel of the face.
        assert_eq!(&png.rgb[12..15], &[200, 100 + face, 50], "looking along {look}");
    }
}

/// `--stats-json` reports the CPU time the skybox's faces took to decode (they are
/// decoded during the render, so it is not in `load_s`), and nothing without a skybox.
#[test]
fn stats_report_the_skybox_decode() {
    let dir = scratch_dir("p3f_cli", "decode_stats");
    write_skybox(&dir);
    let stats = |text: &str| {
        let path = dir.join("look.p3f");
        std::fs::write(&path, text).unwrap();
        let out = dir.join("look.png");
        let run = nffrt(
            &[
                "render",
                path.to_str().unwrap(),
                "-q",
                "--stats-json",
                "-",
                "-o",
                out.to_str().unwrap(),
            ],
            b"",
        );
        assert_eq!(
            run.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&run.stdout).unwrap()
    };
    let with = stats(&scene("1 0 0"));
    let seconds = with["skybox_decode_s"].as_f64().unwrap();
    assert!(seconds > 0.0 && seconds < 10.0, "{with}");
    let without = stats(&scene("1 0 0").replace("env sky\n", ""));
    assert_eq!(without["skybox"], false);
    assert!(without.get("skybox_decode_s").is_none(), "{without}");
}

/// Writes `dir/look.p3f` looking along `look` and renders it to `out`.
fn render_look(dir: &Path, look: &str, out: &Path) -> std::process::Output {
    let path = dir.join("look.p3f");
    std::fs::write(&path, scene(look)).unwrap();
    nffrt(
        &[
            "render",
            path.to_str().unwrap(),
            "-q",
            "-o",
            out.to_str().unwrap(),
        ],
        b"",
    )
}

/// Runs `render` on `dir/look.p3f` and returns (exit code, stderr); checks no picture
/// was written.
fn render_broken(dir: &Path) -> (Option<i32>, String) {
    let out = dir.join("never.png");
    let run = render_look(dir, "1 0 0", &out);
    assert!(!out.exists(), "a picture was written");
    (
        run.status.code(),
        String::from_utf8_lossy(&run.stderr).into_owned(),
    )
}

#[test]
fn a_missing_incomplete_or_corrupt_skybox_is_an_io_error_naming_the_path() {
    let dir = scratch_dir("p3f_cli", "broken");
    // No folder at all.
    let (code, err) = render_broken(&dir);
    assert_eq!(code, Some(4), "{err}");
    assert!(
        err.contains("sky") && err.contains("no such skybox folder") && err.contains("look.p3f:2:5"),
        "{err}"
    );
    // A face missing.
    write_skybox(&dir);
    std::fs::remove_file(dir.join("sky/top.png")).unwrap();
    let (code, err) = render_broken(&dir);
    assert_eq!(code, Some(4), "{err}");
    assert!(err.contains("skybox face 'top' not found"), "{err}");
    // A face that is not an image.
    write_skybox(&dir);
    std::fs::write(dir.join("sky/front.png"), b"\x89PNG\r\n\x1a\n not really").unwrap();
    let (code, err) = render_broken(&dir);
    assert_eq!(code, Some(4), "{err}");
    assert!(
        err.contains("front.png") && err.contains("not a readable"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
}

/// A face whose header reads but whose pixels do not (a PNG cut after its header) is
/// found while rendering, since faces are decoded then: still an I/O error naming
/// the file, with no picture written, whether the picture looks at that face or not.
#[test]
fn a_face_cut_after_its_header_is_an_io_error_found_while_rendering() {
    let dir = scratch_dir("p3f_cli", "cut");
    for (look, cut) in [("1 0 0", "left"), ("1 0 0", "front"), ("0 0 1", "front")] {
        write_skybox(&dir);
        let path = dir.join(format!("sky/{cut}.png"));
        let bytes = std::fs::read(&path).unwrap();
        // The signature (8 bytes) and the IHDR chunk (25): the size, then nothing.
        std::fs::write(&path, &bytes[..33]).unwrap();
        let out = dir.join("never.png");
        let run = render_look(&dir, look, &out);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(4), "{look} {cut}: {err}");
        assert!(!out.exists(), "{look} {cut}: a picture was written");
        assert!(
            err.contains(&format!("{cut}.png"))
                && err.contains("not a readable")
                && err.contains("look.p3f:2:5"),
            "{look} {cut}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

#[test]
fn format_p3f_reads_standard_input_and_the_extension_is_the_default() {
    let src = b"spp 4\ncamera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 6\n\
                mat 1 1 1 1 1 1 1 0 10 0 1\ns 0 0 0 1\n";
    let run = nffrt(&["info", "--json", "--format", "p3f", "-"], src);
    assert_eq!(
        run.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(json["dialect"], "p3f-2025");
    assert_eq!(json["spp"], 4);
    // Read as NFF (the default for standard input), `spp` is no keyword.
    let run = nffrt(&["info", "-"], src);
    assert_eq!(run.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&run.stderr).contains("<stdin>:1:1: unknown keyword \"spp\""));
}

#[test]
fn info_reports_the_course_additions_in_text_and_json() {
    let path = common::data_dir("ok").join("p3f_course_additions.p3f");
    let path = path.to_str().unwrap();
    let text = nffrt(&["info", path], b"");
    let text = String::from_utf8_lossy(&text.stdout);
    for line in [
        "integrator  path (as the file asks)",
        "shutter     open from time 0.25 to 0.75",
        "materials   3 (2 emitting, 2 rough)",
        "  moving_spheres 2",
    ] {
        assert!(text.lines().any(|l| l == line), "{line:?} not in\n{text}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&nffrt(&["info", "--json", path], b"").stdout).unwrap();
    assert_eq!(json["integrator"], "path");
    assert_eq!(json["shutter"], serde_json::json!([0.25, 0.75]));
    // Without a shutter: open from 0 to 1, said so in the text once a sphere moves.
    let src = b"camera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40\nsm 0 0 0 1 0 0 0.5 0 1\n";
    let json: serde_json::Value =
        serde_json::from_slice(&nffrt(&["info", "--json", "--format", "p3f", "-"], src).stdout).unwrap();
    assert_eq!(json["shutter"], serde_json::json!([0.0, 1.0]));
    assert_eq!(json.get("integrator"), None);
    let text = nffrt(&["info", "--format", "p3f", "-"], src);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("shutter     open from time 0 to 1 (the default)"),
        "{text}"
    );
}
