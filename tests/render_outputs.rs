//! Where `nffrt render` puts what it makes, and what its reports say: standard output
//! that carries an image or JSON holds nothing else, `-` means standard output for
//! `--stats-json` too, `--pixel` refuses the options it cannot honour, one of
//! `--width`/`--height` keeps the scene's framing, and the statistics name the
//! sampling and the region they count.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{nffrt, nffrt_in};
use nffrt::image::decode_png;

/// 640x480 (its `resolution` line).
const SHOWCASE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff");
const SMALL: [&str; 4] = ["--width", "40", "--height", "30"];

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("render_outputs", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn render(extra: &[&str]) -> Output {
    let mut args = vec!["render", SHOWCASE];
    args.extend_from_slice(extra);
    nffrt(&args, b"")
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Item 1: with `-o -`, standard output is the PNG and nothing after it; the
/// statistics go to standard error.
#[test]
fn stats_never_follow_the_image_on_standard_output() {
    let dir = scratch("stats_stdout");
    let file = dir.join("a.png");
    ok(render(&[&SMALL[..], &["-q", "-o", s(&file)]].concat()));
    let o = ok(render(&[&SMALL[..], &["-q", "-o", "-", "--stats"]].concat()));
    assert_eq!(
        o.stdout,
        std::fs::read(&file).unwrap(),
        "standard output is not the image alone"
    );
    let err = text(&o.stderr);
    assert!(err.contains("eye rays") && err.contains("total rays"), "{err}");
    // Without -o -, the statistics stay on standard output.
    let o = ok(render(&[&SMALL[..], &["-q", "-o", s(&file), "--stats"]].concat()));
    assert!(text(&o.stdout).contains("eye rays"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 4: `--stats-json -` writes the JSON to standard output (no file named `-`),
/// and is refused together with `-o -`.
#[test]
fn stats_json_dash_is_standard_output() {
    let dir = scratch("stats_json_dash");
    let args = [
        "render",
        SHOWCASE,
        "-q",
        "-o",
        "a.png",
        "--stats-json",
        "-",
        "--stats",
    ];
    let o = ok(nffrt_in(&dir, &[&args[..], &SMALL[..]].concat()));
    assert!(!dir.join("-").exists(), "a file named '-' was written");
    let json: serde_json::Value =
        serde_json::from_slice(&o.stdout).expect("standard output is the JSON alone");
    assert_eq!(json["eye_rays"], 40 * 30);
    // --stats text went to standard error, out of the JSON's way.
    assert!(text(&o.stderr).contains("eye rays"));
    let both = render(&[&SMALL[..], &["-o", "-", "--stats-json", "-"]].concat());
    assert_eq!(both.status.code(), Some(2));
    assert!(both.stdout.is_empty());
    assert!(text(&both.stderr).contains("--stats-json - and -o - both ask for standard output"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 5: `--pixel` writes no image and no statistics, so it refuses the options
/// that ask for them instead of ignoring them.
#[test]
fn pixel_refuses_output_and_stats_options() {
    let dir = scratch("pixel");
    let png = dir.join("p.png");
    let json = dir.join("p.json");
    for extra in [
        vec!["-o", s(&png)],
        vec!["--stats"],
        vec!["--stats-json", s(&json)],
    ] {
        let o = render(&[&["--pixel", "3,3"][..], &extra].concat());
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        let err = text(&o.stderr);
        assert!(err.contains("'--pixel <X,Y>' cannot be used with"), "{err}");
        assert!(o.stdout.is_empty(), "{extra:?}");
    }
    assert!(!png.exists() && !json.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 9: one of `--width`/`--height` keeps the scene's 4:3; both set the size
/// exactly. The framing is the scene's either way: `--width 320` gives the image of
/// `--width 320 --height 240`.
#[test]
fn one_side_keeps_the_aspect_ratio() {
    let dir = scratch("aspect");
    let size_of = |extra: &[&str]| {
        let out = dir.join("a.png");
        ok(render(&[extra, &["-q", "-o", s(&out)]].concat()));
        let bytes = std::fs::read(&out).unwrap();
        let png = decode_png(&bytes[..]).unwrap();
        ((png.width, png.height), bytes)
    };
    let (size, width_only) = size_of(&["--width", "32"]);
    assert_eq!(size, (32, 24));
    let (size, both) = size_of(&["--width", "32", "--height", "24"]);
    assert_eq!(size, (32, 24));
    assert_eq!(width_only, both);
    assert_eq!(size_of(&["--height", "24"]).0, (32, 24));
    assert_eq!(size_of(&["--width", "32", "--height", "32"]).0, (32, 32));
    // Rounded to the nearest pixel: 33 x 3/4 = 24.75.
    assert_eq!(size_of(&["--width", "33"]).0, (33, 25));
    let help = text(&nffrt(&["render", "--help"], b"").stdout);
    assert!(
        help.contains("Given alone, the height follows the scene's aspect ratio"),
        "{help}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 10: the statistics say the sampling, the samples per pixel and the region,
/// so that the ray counts can be checked against them: 5 x 5 pixels at 4 samples
/// are 100 eye rays.
#[test]
fn stats_name_the_sampling_and_the_region() {
    let dir = scratch("stats_settings");
    let out = dir.join("t.png");
    let json = dir.join("t.json");
    let o = ok(render(&[
        "--width",
        "9",
        "--height",
        "9",
        "--spp",
        "4",
        "--region",
        "0,0,5,5",
        "-q",
        "--stats",
        "-o",
        s(&out),
        "--stats-json",
        s(&json),
    ]));
    let stats = text(&o.stdout);
    for want in [
        "region             0,0,5,5",
        "pixels             25",
        "sampling           stratified",
        "samples per pixel  4",
        "eye rays           100 ",
    ] {
        assert!(stats.contains(want), "{want:?} in\n{stats}");
    }
    let j: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(j["region"], serde_json::json!([0, 0, 5, 5]));
    assert_eq!(j["pixels"], 25);
    assert_eq!(j["sampling"], "stratified");
    assert_eq!(j["samples_per_pixel"], 4);
    assert_eq!(j["eye_rays"], 100);
    assert_eq!((j["width"].as_u64(), j["height"].as_u64()), (Some(9), Some(9)));
    std::fs::remove_dir_all(&dir).unwrap();
}
