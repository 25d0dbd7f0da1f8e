//! `nffrt diff` from the outside: exit codes 0, 1 (above `--tolerance`), 2 (sizes,
//! kinds, overwriting an input), 3 and 4; the table's order, the JSON's shape and
//! values, the maps written. The pictures are written here byte by byte, their
//! errors computed by hand. FLIP's own values are held to NVIDIA's in
//! python/tests/test_diff.py.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{nffrt, scratch_dir};

/// A binary PPM of `w` x `h` pixels, every one `rgb`.
fn ppm(dir: &Path, name: &str, w: u32, h: u32, rgb: [u8; 3]) -> PathBuf {
    let mut bytes = format!("P6\n{w} {h}\n255\n").into_bytes();
    for _ in 0..w * h {
        bytes.extend_from_slice(&rgb);
    }
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A little-endian colour PFM of `w` x `h` pixels, every one `rgb`.
fn pfm(dir: &Path, name: &str, w: u32, h: u32, rgb: [f32; 3]) -> PathBuf {
    let mut bytes = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    for _ in 0..w * h {
        for c in rgb {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn run(args: &[&Path], flags: &[&str]) -> Output {
    let mut all: Vec<&str> = vec!["diff"];
    all.extend(args.iter().map(|p| p.to_str().unwrap()));
    all.extend_from_slice(flags);
    nffrt(&all, b"")
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn fails_with(out: &Output, code: i32, needle: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(code), "stderr: {err}");
    assert!(
        err.starts_with("nffrt: error: ") && err.lines().count() == 1,
        "{err}"
    );
    assert!(err.contains(needle), "{err:?} lacks {needle:?}");
}

#[test]
fn exit_codes_follow_the_tolerance() {
    let dir = scratch_dir("diff_cli", "tolerance");
    let reference = ppm(&dir, "ref.ppm", 4, 4, [100, 100, 100]);
    // Every channel 51 levels off: MAE 51/255 = 0.2.
    let test = ppm(&dir, "test.ppm", 4, 4, [151, 151, 151]);
    let same = run(&[&reference, &reference], &["--tolerance", "0"]);
    assert_eq!(same.status.code(), Some(0), "{}", stderr(&same));
    assert!(stdout(&same).starts_with(&format!("{}: flip 0 against", reference.display())));
    let ok = run(&[&test, &reference], &["--metric", "mae", "--tolerance", "0.25"]);
    assert_eq!(ok.status.code(), Some(0), "{}", stderr(&ok));
    assert!(stdout(&ok).contains("mae 0.200000 against"), "{}", stdout(&ok));
    let far = run(&[&test, &reference], &["--metric", "mae", "--tolerance", "0.15"]);
    fails_with(&far, 1, "test.ppm: mae 0.200000 is above --tolerance 0.15");
    assert!(
        stdout(&far).contains("above --tolerance 0.15"),
        "{}",
        stdout(&far)
    );
    // PSNR: 10 log10(1 / 0.04) = 13.98 dB; closer pictures score higher.
    let psnr = run(&[&test, &reference], &["--metric", "psnr", "--tolerance", "20"]);
    fails_with(&psnr, 1, "psnr 13.9794 is below --tolerance 20");
    let psnr = run(&[&test, &reference], &["--metric", "psnr", "--tolerance", "10"]);
    assert_eq!(psnr.status.code(), Some(0), "{}", stderr(&psnr));
}

#[test]
fn several_pictures_make_a_table_from_the_closest() {
    let dir = scratch_dir("diff_cli", "table");
    let reference = ppm(&dir, "ref.ppm", 3, 2, [100, 100, 100]);
    let far = ppm(&dir, "far.ppm", 3, 2, [130, 130, 130]);
    let near = ppm(&dir, "near.ppm", 3, 2, [110, 110, 110]);
    let middle = ppm(&dir, "middle.ppm", 3, 2, [80, 80, 80]);
    let r = format!("--ref={}", reference.display());
    let out = run(
        &[&far, &near, &middle],
        &[&r, "--metric", "mae", "--tolerance", "0.1"],
    );
    fails_with(&out, 1, "1 of 3 pictures are above --tolerance 0.1 by mae: ");
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 4, "{text}");
    assert!(
        lines[0].starts_with("mae against") && lines[0].ends_with("(3x2), closest first:"),
        "{text}"
    );
    // 10, 20 and 30 levels off: 0.0392157, 0.0784314, 0.117647.
    assert!(
        lines[1].contains("0.0392157") && lines[1].ends_with("near.ppm"),
        "{text}"
    );
    assert!(
        lines[2].contains("0.0784314") && lines[2].ends_with("middle.ppm"),
        "{text}"
    );
    assert!(
        lines[3].contains("0.117647") && lines[3].ends_with("far.ppm  above --tolerance 0.1"),
        "{text}"
    );
    // PSNR ranks the other way up: the highest (closest) first.
    let out = run(&[&far, &near, &middle], &[&r, "--metric", "psnr"]);
    let text = stdout(&out);
    let order: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.rsplit('/').next().unwrap())
        .collect();
    assert_eq!(order, ["near.ppm", "middle.ppm", "far.ppm"], "{text}");
}

#[test]
fn json_gives_every_result_and_the_verdict() {
    let dir = scratch_dir("diff_cli", "json");
    let reference = ppm(&dir, "ref.ppm", 2, 2, [0, 0, 0]);
    let a = ppm(&dir, "a.ppm", 2, 2, [51, 0, 0]);
    let b = ppm(&dir, "b.ppm", 2, 2, [0, 0, 0]);
    let r = format!("--ref={}", reference.display());
    let out = run(
        &[&a, &b],
        &[&r, "--metric", "mse", "--json", "--tolerance", "0.01"],
    );
    assert_eq!(out.status.code(), Some(1));
    let j: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(j["metric"], "mse");
    assert_eq!(j["reference"], reference.display().to_string());
    assert_eq!((j["width"].as_u64(), j["height"].as_u64()), (Some(2), Some(2)));
    assert_eq!(j["tolerance"], 0.01);
    assert_eq!(j["passed"], false);
    assert_eq!(j["flip"], serde_json::Value::Null);
    assert_eq!(j["map"], serde_json::Value::Null);
    let results = j["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    assert_eq!(results[0]["test"], b.display().to_string());
    assert_eq!(results[0]["value"], 0.0);
    assert_eq!(results[0]["exceeds_tolerance"], false);
    // One channel of three 0.2 off: MSE 0.04 / 3.
    let v = results[1]["value"].as_f64().unwrap();
    assert!((v - 0.04 / 3.0).abs() < 1e-7, "{v}");
    assert_eq!(results[1]["exceeds_tolerance"], true);
    // FLIP says how it viewed the pictures; equal pictures' PSNR is infinite: null.
    let out = run(&[&a, &reference], &["--json"]);
    let j: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(j["flip"]["mode"], "ldr");
    assert!((j["flip"]["ppd"].as_f64().unwrap() - 67.0206).abs() < 1e-4);
    let out = run(&[&b, &reference], &["--json", "--metric", "psnr"]);
    let j: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(j["results"][0]["value"], serde_json::Value::Null);
    let hdr_ref = pfm(&dir, "ref.pfm", 2, 2, [0.5, 1.0, 2.0]);
    let hdr_test = pfm(&dir, "test.pfm", 2, 2, [0.5, 1.0, 2.5]);
    let out = run(&[&hdr_test, &hdr_ref], &["--json"]);
    let j: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(j["flip"]["mode"], "hdr");
    assert_eq!(j["flip"]["exposures"], 2);
}

#[test]
fn pictures_that_do_not_match_are_refused() {
    let dir = scratch_dir("diff_cli", "mismatch");
    let reference = ppm(&dir, "ref.ppm", 4, 4, [0, 0, 0]);
    let wide = ppm(&dir, "wide.ppm", 5, 4, [0, 0, 0]);
    let float = pfm(&dir, "f.pfm", 4, 4, [0.0; 3]);
    fails_with(
        &run(&[&wide, &reference], &[]),
        2,
        "the test picture is 5x4 and the reference 4x4: compare pictures of one size",
    );
    fails_with(
        &run(&[&float, &reference], &[]),
        2,
        "the test picture is a float picture and the reference an 8-bit picture",
    );
    // A black float reference leaves HDR-FLIP no exposure; other metrics work.
    fails_with(&run(&[&float, &float], &[]), 3, "black everywhere");
    assert_eq!(
        run(&[&float, &float], &["--metric", "mse"]).status.code(),
        Some(0)
    );
    fails_with(
        &run(&[&dir.join("none.png"), &reference], &[]),
        4,
        "none.png: cannot read picture: no such file",
    );
    let broken = dir.join("broken.png");
    std::fs::write(&broken, b"not a png").unwrap();
    fails_with(
        &run(&[&broken, &reference], &[]),
        3,
        "broken.png: not a usable picture",
    );
    fails_with(
        &run(&[&dir.join("a.gif"), &reference], &[]),
        2,
        "unknown image format",
    );
    fails_with(
        &run(&[&reference], &[]),
        2,
        "give TEST REF, or the reference with --ref",
    );
    fails_with(
        &run(&[&reference, &reference], &["--metric", "ssim"]),
        2,
        "invalid value 'ssim'",
    );
}

#[test]
fn maps_are_written_whole_and_never_over_an_input() {
    let dir = scratch_dir("diff_cli", "maps");
    let reference = ppm(&dir, "ref.ppm", 3, 2, [100, 100, 100]);
    let test = ppm(&dir, "test.ppm", 3, 2, [100, 100, 151]);
    let before = std::fs::read(&test).unwrap();
    for target in [&test, &reference] {
        let out = run(&[&test, &reference], &["-o", target.to_str().unwrap()]);
        fails_with(&out, 2, "would overwrite the");
    }
    assert_eq!(std::fs::read(&test).unwrap(), before);
    let r = format!("--ref={}", reference.display());
    let heat = dir.join("heat.png");
    fails_with(
        &run(&[&test, &test], &[&r, "-o", heat.to_str().unwrap()]),
        2,
        "the error map is of one picture",
    );
    assert!(!heat.exists());
    // Equal pictures: every pixel magma's first colour, (0.001462, 0.000466,
    // 0.013866) x 255 rounded = (0, 0, 4).
    let out = run(&[&reference, &reference], &["-o", heat.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).starts_with("wrote the flip map to"),
        "{}",
        stderr(&out)
    );
    let png = nffrt::image::decode_png(&std::fs::read(&heat).unwrap()[..]).unwrap();
    assert_eq!((png.width, png.height), (3, 2));
    assert_eq!(png.rgb, [0, 0, 4].repeat(6));
    // MAE per pixel, as values: one channel of three 0.2 off, 0.2 / 3.
    let map = dir.join("mae.pfm");
    let out = run(
        &[&test, &reference],
        &["--metric", "mae", "-o", map.to_str().unwrap(), "-q"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stderr(&out), "");
    let values = nffrt::image::decode_pfm(&std::fs::read(&map).unwrap()).unwrap();
    assert!(values
        .pixels
        .iter()
        .all(|p| (p.x - 0.2 / 3.0).abs() < 1e-7 && p.x == p.z));
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .contains(".nffrt-tmp-")
        })
        .collect();
    assert!(leftovers.is_empty());
}
