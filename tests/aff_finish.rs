//! `nffrt render --frames` with `--denoise` and `--aov`: each frame finished as
//! `--frame N` alone finishes it, the same bytes (picture and AOV files); the AOVs
//! are the frame's own (a keyed sphere's depth where it is at that frame, computed
//! here); an AOV file that would replace a texture is refused before anything is
//! written.
//!
//! The denoising check skips, saying so, when Open Image Denoise is not installed
//! (`pip install pyoidn`, or `NFFRT_OIDN`); `NFFRT_REQUIRE_OIDN=1` makes that skip a
//! failure.

mod common;

use std::path::{Path, PathBuf};

use common::{denoiser_installed, nffrt, nffrt_ok, scratch_dir};
use nffrt::image::decode_pfm;

/// [`common::keyed_ball`] at 41 x 41 pixels: 0.125 a pixel, column 20 at x = 0; the
/// ball's centre at x = 0, 0.40625, 1, 1.59375 in frames 0 to 3.
fn ball_text() -> String {
    common::keyed_ball(41)
}

fn ball(test: &str) -> (PathBuf, PathBuf) {
    let dir = scratch_dir("aff_finish", test);
    let scene = dir.join("ball.aff");
    std::fs::write(&scene, ball_text()).unwrap();
    (dir, scene)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Renders frames 0..2 with `extra` into `f_%d.EXT`, and frame 2 alone into
/// `one.EXT`; asserts that each of `files` (suffixes after the stem, `.png`,
/// `.albedo.png`...) of frame 2 is the same bytes both ways.
fn frames_equal_frame(dir: &Path, scene: &Path, ext: &str, extra: &[&str], files: &[&str]) {
    let pattern = dir.join(format!("f_%d.{ext}"));
    let one = dir.join(format!("one.{ext}"));
    let base = ["render", s(scene), "-q", "--spp", "4"];
    nffrt_ok(&[&base[..], extra, &["--frames", "0..2", "-o", s(&pattern)]].concat());
    nffrt_ok(&[&base[..], extra, &["--frame", "2", "-o", s(&one)]].concat());
    for suffix in files {
        let a = std::fs::read(dir.join(format!("f_2{suffix}"))).unwrap();
        let b = std::fs::read(dir.join(format!("one{suffix}"))).unwrap();
        assert!(a == b, "{extra:?}: f_2{suffix} differs from one{suffix}");
    }
}

#[test]
fn aovs_of_each_frame_are_those_of_the_frame_alone() {
    let (dir, scene) = ball("aov");
    let png = [".png", ".albedo.png", ".normal.png", ".depth.png"];
    frames_equal_frame(&dir, &scene, "png", &["--aov", "albedo,normal,depth"], &png);
    frames_equal_frame(&dir, &scene, "exr", &["--aov", "depth,normal"], &[".exr"]);
    frames_equal_frame(&dir, &scene, "pfm", &["--aov", "depth"], &[".pfm", ".depth.pfm"]);
    // Each frame's depth is its own: the ball's nearest point is |C - eye| - 0.2
    // from the camera, seen about the pixel of its centre's x (column 20 + x /
    // 0.125); where frame 0's ball was, frame 2 sees nothing (infinity).
    let depth = |n: u32| decode_pfm(&std::fs::read(dir.join(format!("f_{n}.depth.pfm"))).unwrap()).unwrap();
    for (n, x) in [(0, 0.0f64), (1, 0.40625), (2, 1.0)] {
        let column = (20.0 + x / 0.125).round() as u32;
        let nearest = (100.0 + x * x).sqrt() - 0.2;
        let d = depth(n).get(column, 20).x as f64;
        // The pixel's samples meet the plane z = 0 within 0.12 of the centre (its
        // half diagonal, 0.088, and the rounding of the column, 0.031): at most
        // 0.2 - sqrt(0.2^2 - 0.12^2) = 0.04 behind the nearest point.
        assert!(
            d > nearest - 1e-3 && d < nearest + 0.04,
            "frame {n}: depth {d} at column {column}, nearest point {nearest}"
        );
    }
    assert!(
        depth(2).get(20, 20).x.is_infinite(),
        "frame 2 sees frame 0's ball"
    );
}

#[test]
fn each_frame_is_denoised_as_the_frame_alone() {
    if !denoiser_installed() {
        return;
    }
    let (dir, scene) = ball("denoise");
    frames_equal_frame(&dir, &scene, "pfm", &["--denoise"], &[".pfm"]);
    frames_equal_frame(
        &dir,
        &scene,
        "png",
        &["--denoise=fast", "--aov", "albedo"],
        &[".png", ".albedo.png"],
    );
    // The frames differ: each is its own frame's picture, denoised.
    let a = std::fs::read(dir.join("f_0.pfm")).unwrap();
    assert!(
        a != std::fs::read(dir.join("f_2.pfm")).unwrap(),
        "frames 0 and 2 alike"
    );
}

#[test]
fn an_aov_file_over_a_texture_is_refused_before_anything_is_written() {
    let (dir, _) = ball("refused");
    let textured = format!(
        "{}tt t_1.albedo.ppm 0 0 -5 0 0  1 0 -5 1 0  0 1 -5 0 1\n",
        ball_text()
    );
    std::fs::write(dir.join("tex.aff"), textured).unwrap();
    let texture = b"P6\n1 1\n255\n\x10\x20\x30";
    std::fs::write(dir.join("t_1.albedo.ppm"), texture).unwrap();
    let pattern = dir.join("t_%d.ppm");
    let run = nffrt(
        &[
            "render",
            s(&dir.join("tex.aff")),
            "--frames",
            "0..2",
            "--aov",
            "albedo",
            "-o",
            s(&pattern),
        ],
        b"",
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("would overwrite a texture"), "{stderr}");
    assert_eq!(std::fs::read(dir.join("t_1.albedo.ppm")).unwrap(), texture);
    assert!(
        !dir.join("t_0.ppm").exists(),
        "nothing is written before the refusal"
    );
}
